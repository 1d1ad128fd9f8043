//! glTF 2.0 (`.glb`, `.gltf`) in and out: a body's joints as a skinned node
//! hierarchy and motions as its animations ([`write`]); a skinned skeleton
//! animation read back as a BVH-like clip ([`read`]); the per-frame contact
//! forces an animation may carry in its `extras` ([`forces`]).

pub mod forces;
pub mod read;
pub mod write;

pub use forces::{SavedForces, load_forces};
pub use read::{Loaded, Which, load};
pub use write::{Clip, Container, save, save_with_forces, to_bytes, to_bytes_with_forces};

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
    /// The contact forces an animation's `extras.mx.forces` carries are
    /// missing or not what mx writes: `field` is the JSON path under the
    /// file's root (`animations[0].extras.mx.forces.times`).
    #[error("{path}: {field}: {message}")]
    Forces {
        path: String,
        field: String,
        message: String,
    },
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
