//! Files in and out: motion CSV and JSON (and, from other modules, BVH,
//! URDF, plots). Every write is atomic (see [`atomic`]).

pub mod atomic;
pub mod csv;
pub mod gltf;
pub mod motion_json;
pub mod plot;
pub mod storage;
pub mod viewer;

use std::path::{Path, PathBuf};

use crate::motion::MotionError;

/// Why reading or writing a file failed; messages name the file.
#[derive(Debug, thiserror::Error)]
pub enum FileError {
    #[error("cannot write {}: {source}", path.display())]
    Write {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("cannot read {}: {source}", path.display())]
    Read {
        path: PathBuf,
        source: std::io::Error,
    },
    /// The file was read but its content is not what it should be.
    #[error("{}: {content}", path.display())]
    Format {
        path: PathBuf,
        content: ContentError,
    },
    #[error(transparent)]
    Motion(#[from] MotionError),
}

impl FileError {
    /// The content of the file at `path` is wrong as `content` says.
    pub(crate) fn content(path: &Path, content: ContentError) -> FileError {
        FileError::Format {
            path: path.to_path_buf(),
            content,
        }
    }
}

/// What is wrong in a file's text, found before its path is known (the
/// readers of CSV, motion JSON and Storage text): the 1-based line at fault,
/// when one is, and the message.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{}{message}", line.map(|l| format!("line {l}: ")).unwrap_or_default())]
pub struct ContentError {
    pub line: Option<usize>,
    pub message: String,
}

impl ContentError {
    pub fn new(message: impl Into<String>) -> ContentError {
        ContentError {
            line: None,
            message: message.into(),
        }
    }

    /// An error on line `line` (1-based).
    pub fn at(line: usize, message: impl Into<String>) -> ContentError {
        ContentError {
            line: Some(line),
            message: message.into(),
        }
    }
}

impl From<String> for ContentError {
    fn from(message: String) -> Self {
        ContentError::new(message)
    }
}

impl From<&str> for ContentError {
    fn from(message: &str) -> Self {
        ContentError::new(message)
    }
}
