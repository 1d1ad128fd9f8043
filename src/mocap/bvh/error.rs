//! Errors and warnings of the BVH reader and writer. Every parse error carries
//! the 1-based line number where the problem was found (and the column, when
//! one word is to blame) and says what was expected. A warning names the line
//! and what the reader did about a loose but readable file.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum BvhError {
    #[error("BVH line {line}{}: {message}", column.map(|c| format!(", column {c}")).unwrap_or_default())]
    Parse {
        line: usize,
        column: Option<usize>,
        message: String,
    },
    #[error("cannot read or write {path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("BVH: {0}")]
    Invalid(String),
    /// A stated scale that is no length (`unit:`).
    #[error(
        "unit scale must be a positive number of metres per file unit, got {0} (use 0.01 for centimetres)"
    )]
    Unit(f64),
}

impl BvhError {
    pub(crate) fn at(line: usize, message: impl Into<String>) -> BvhError {
        BvhError::Parse {
            line,
            column: None,
            message: message.into(),
        }
    }

    /// A parse error blamed on the word at `column` (1-based, in characters).
    pub(crate) fn at_col(line: usize, column: usize, message: impl Into<String>) -> BvhError {
        BvhError::Parse {
            line,
            column: Some(column),
            message: message.into(),
        }
    }

    /// The line number of a parse error.
    pub fn line(&self) -> Option<usize> {
        match self {
            BvhError::Parse { line, .. } => Some(*line),
            _ => None,
        }
    }

    /// The column of a parse error blamed on one word.
    pub fn column(&self) -> Option<usize> {
        match self {
            BvhError::Parse { column, .. } => *column,
            _ => None,
        }
    }
}

/// Something the reader tolerated in a loose file, and what it did: one per
/// kind of looseness (the first line it was seen on), never one per row.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BvhWarning {
    pub line: usize,
    pub message: String,
}

impl std::fmt::Display for BvhWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "line {}: {}", self.line, self.message)
    }
}
