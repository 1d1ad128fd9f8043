//! Cyclification and looping live with the motion operations
//! ([`crate::motion::cyclify`]: they use only motions and splines); this keeps
//! their spacetime paths, with the spacetime layer's errors.

use super::error::SpError;
use crate::motion::Mu;
use crate::motion::cyclify::CyclifyError;
pub use crate::motion::cyclify::{CyclifyOptions, CyclifyReport, floor_drift};

impl From<CyclifyError> for SpError {
    fn from(e: CyclifyError) -> Self {
        match e {
            CyclifyError::Invalid(m) => SpError::Invalid(m),
            CyclifyError::Evaluation(m) => SpError::Evaluation(m),
        }
    }
}

/// [`crate::motion::cyclify::cyclify`], with a [`SpError`].
pub fn cyclify(
    m: &Mu,
    t_start: f64,
    t_end: f64,
    opts: &CyclifyOptions,
) -> Result<(Mu, CyclifyReport), SpError> {
    Ok(crate::motion::cyclify::cyclify(m, t_start, t_end, opts)?)
}

/// [`crate::motion::cyclify::loop_motion`], with a [`SpError`].
pub fn loop_motion(m: &Mu, n: usize) -> Result<Mu, SpError> {
    Ok(crate::motion::cyclify::loop_motion(m, n)?)
}
