//! Inverse kinematics over time: links put on target positions (and,
//! optionally, orientations) frame by frame, by damped least squares on the
//! analytic Jacobian of forward kinematics.
//!
//! `frame.rs` solves one configuration (Levenberg–Marquardt with adaptive
//! damping, joint limits as bounds); `over_time.rs` samples a motion and its
//! targets on one clock, warm-starts each frame from the previous solution
//! and reports the residual per target.
//!
//! Layering: uses `lie`, `model`, `motion`; used by `lang` (and
//! `report`, the benches). Knows nothing of the language.

pub mod frame;
pub mod over_time;

pub use frame::{FrameResult, Goal, Settings, Solver};
pub use over_time::{IkOptions, IkReport, Target, TargetReport, ik};

/// Why IK could not run: bad input, with a message naming what and where.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IkError {
    /// `argument`: what is at fault, as the language names `ik`'s parameters
    /// (`targets`, `m`, `tolerance`, …), when one input is.
    #[error("ik: {message}")]
    Invalid {
        argument: Option<&'static str>,
        message: String,
    },
    #[error(transparent)]
    Motion(#[from] crate::motion::MotionError),
    #[error(transparent)]
    Model(#[from] crate::model::ModelError),
}

/// An [`IkError::Invalid`] about the input `argument`.
pub(crate) fn invalid(argument: &'static str, msg: impl Into<String>) -> IkError {
    IkError::Invalid {
        argument: Some(argument),
        message: msg.into(),
    }
}

impl IkError {
    /// The input at fault, when one is.
    pub fn argument(&self) -> Option<&'static str> {
        match self {
            IkError::Invalid { argument, .. } => *argument,
            _ => None,
        }
    }
}
