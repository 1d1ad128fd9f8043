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
    #[error("ik: {0}")]
    Invalid(String),
    #[error(transparent)]
    Motion(#[from] crate::motion::MotionError),
    #[error(transparent)]
    Model(#[from] crate::model::ModelError),
}

pub(crate) fn invalid(msg: impl Into<String>) -> IkError {
    IkError::Invalid(msg.into())
}
