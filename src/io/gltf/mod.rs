//! glTF 2.0 (`.glb`, `.gltf`) in and out: a body's joints as a skinned node
//! hierarchy and motions as its animations ([`write`]); a skinned skeleton
//! animation read back as a BVH-like clip ([`read`]).

pub mod read;
pub mod write;

pub use read::{Loaded, Which, load};
pub use write::{Clip, Container, save, to_bytes};

use super::FileError;
use crate::mocap::MocapError;
use crate::motion::MotionError;

/// Why a glTF file could not be written or read.
#[derive(Debug, thiserror::Error)]
pub enum GltfError {
    /// The document or the request is not what it must be.
    #[error("{0}")]
    Invalid(String),
    #[error(transparent)]
    File(#[from] FileError),
    #[error(transparent)]
    Mocap(#[from] MocapError),
}

impl GltfError {
    pub(crate) fn invalid(message: impl Into<String>) -> GltfError {
        GltfError::Invalid(message.into())
    }
}

impl From<MotionError> for GltfError {
    fn from(e: MotionError) -> Self {
        GltfError::Mocap(MocapError::Motion(e))
    }
}
