//! Why a section of `mx report` could not be computed: a lower layer's
//! error kept whole, or a check of the report's own (a case that reads its
//! data, a measurement that came out non-finite), in words that say which.

use crate::dynamics::DynamicsError;
use crate::ground::GroundError;
use crate::ik::IkError;
use crate::io::plot::PlotError;
use crate::io::{ContentError, FileError};
use crate::mocap::MocapError;
use crate::mocap::bvh::BvhError;
use crate::model::joints::JointSpecError;
use crate::model::{InertiaError, ModelError};
use crate::motion::MotionError;
use crate::motion::cyclify::CyclifyError;
use crate::spacetime::SpError;
use crate::spline::SplineError;

#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    #[error(transparent)]
    Sp(#[from] SpError),
    #[error(transparent)]
    Dynamics(#[from] DynamicsError),
    #[error(transparent)]
    Model(#[from] ModelError),
    #[error(transparent)]
    Inertia(#[from] InertiaError),
    #[error(transparent)]
    Joint(#[from] JointSpecError),
    #[error(transparent)]
    Motion(#[from] MotionError),
    #[error(transparent)]
    Cyclify(#[from] CyclifyError),
    #[error(transparent)]
    Mocap(#[from] MocapError),
    #[error(transparent)]
    Bvh(#[from] BvhError),
    #[error(transparent)]
    Ik(#[from] IkError),
    #[error(transparent)]
    File(#[from] FileError),
    #[error(transparent)]
    Content(#[from] ContentError),
    #[error(transparent)]
    Ground(#[from] GroundError),
    #[error(transparent)]
    Spline(#[from] SplineError),
    #[error(transparent)]
    Plot(#[from] PlotError),
    #[error(transparent)]
    Io(#[from] std::io::Error),
    /// A check of the report's own failed; the sentence says which.
    #[error("{0}")]
    Check(String),
}

impl From<String> for ReportError {
    fn from(message: String) -> Self {
        ReportError::Check(message)
    }
}

impl From<&str> for ReportError {
    fn from(message: &str) -> Self {
        ReportError::Check(message.to_string())
    }
}
