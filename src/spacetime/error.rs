//! Errors of the spacetime layer: each says what was wrong and what to do.

use crate::cancel::Cancelled;
use crate::motion::cyclify::CyclifyError;

#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SpError {
    /// Bad parameters or data given by the user.
    #[error("{0}")]
    Invalid(String),
    /// An option of `SP(…)` out of its range, or naming what the body lacks:
    /// `option` is its name as the language spells it (`coefficients`,
    /// `support`), so a diagnostic can point at the argument.
    #[error("{message}")]
    InvalidOption {
        option: &'static str,
        message: String,
    },
    /// The motion is multiply defined where a transition needs one value.
    #[error("{0}")]
    Conflict(String),
    /// The model or the motion could not be evaluated.
    #[error("{0}")]
    Evaluation(String),
    #[error("spacetime solve cancelled")]
    Cancelled,
}

impl From<Cancelled> for SpError {
    fn from(_: Cancelled) -> Self {
        SpError::Cancelled
    }
}

/// Cyclification lives with the motion operations; the language reports its
/// errors as it reports SP's.
impl From<CyclifyError> for SpError {
    fn from(e: CyclifyError) -> Self {
        match e {
            CyclifyError::Invalid(m) => SpError::Invalid(m),
            CyclifyError::Evaluation(m) => SpError::Evaluation(m),
        }
    }
}

impl SpError {
    /// The option at fault, when the error is about one.
    pub fn option(&self) -> Option<&'static str> {
        match self {
            SpError::InvalidOption { option, .. } => Some(option),
            _ => None,
        }
    }
}

pub(crate) fn invalid(msg: impl Into<String>) -> SpError {
    SpError::Invalid(msg.into())
}

/// An [`SpError::InvalidOption`] of `option`.
pub(crate) fn invalid_option(option: &'static str, message: impl Into<String>) -> SpError {
    SpError::InvalidOption {
        option,
        message: message.into(),
    }
}
