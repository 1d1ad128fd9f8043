//! Errors of the mocap layer (reading, converting, fitting).

use super::bvh::BvhError;
use crate::model::ModelError;
use crate::motion::MotionError;

#[derive(Debug, thiserror::Error)]
pub enum MocapError {
    #[error(transparent)]
    Bvh(#[from] BvhError),
    #[error(transparent)]
    Motion(#[from] MotionError),
    #[error(transparent)]
    Model(#[from] ModelError),
    #[error("{0}")]
    Invalid(String),
}

impl MocapError {
    pub(crate) fn invalid(m: impl Into<String>) -> MocapError {
        MocapError::Invalid(m.into())
    }
}
