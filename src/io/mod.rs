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
    #[error("{}: {message}", path.display())]
    Format { path: PathBuf, message: String },
    #[error(transparent)]
    Motion(#[from] MotionError),
}

impl FileError {
    pub(crate) fn format(path: &Path, message: impl Into<String>) -> FileError {
        FileError::Format {
            path: path.to_path_buf(),
            message: message.into(),
        }
    }
}
