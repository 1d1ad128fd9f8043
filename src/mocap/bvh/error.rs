//! Errors of the BVH reader and writer. Every parse error carries the 1-based
//! line number where the problem was found and says what was expected.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum BvhError {
    #[error("BVH line {line}: {message}")]
    Parse { line: usize, message: String },
    #[error("cannot read or write {path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("BVH: {0}")]
    Invalid(String),
}

impl BvhError {
    pub(crate) fn at(line: usize, message: impl Into<String>) -> BvhError {
        BvhError::Parse {
            line,
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
}
