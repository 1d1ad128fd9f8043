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
    #[error(transparent)]
    Inertia(#[from] crate::model::InertiaError),
    #[error("{0}")]
    Invalid(String),
    /// An option out of its range: `option` as the language spells it
    /// (`mass`, `angle_weight`), so a diagnostic can point at the argument.
    #[error("{message}")]
    InvalidOption {
        option: &'static str,
        message: String,
    },
}

impl MocapError {
    pub(crate) fn invalid(m: impl Into<String>) -> MocapError {
        MocapError::Invalid(m.into())
    }

    pub(crate) fn invalid_option(option: &'static str, m: impl Into<String>) -> MocapError {
        MocapError::InvalidOption {
            option,
            message: m.into(),
        }
    }

    /// The option at fault, when the error is about one.
    pub fn option(&self) -> Option<&'static str> {
        match self {
            MocapError::InvalidOption { option, .. } => Some(option),
            MocapError::Bvh(BvhError::Unit(_)) => Some("unit"),
            MocapError::Motion(m) => m.option(),
            _ => None,
        }
    }
}
