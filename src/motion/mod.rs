//! The motion algebra of Rose et al. 1996 §4: intervals of functions of time,
//! DOFs (lists of intervals), motion units (named DOFs), the set operations
//! ∧ − + and the time operations affine, clip, clip-in-place, concatenate;
//! the animator's operators beyond Rose (blend, crossfade, align, layer,
//! mask, mirror, reverse, warp, resample) in [`compose`]; DOF names
//! (`Joint.Xrotation`, sides for mirroring) parsed in [`channel`]; hold and loop
//! extrapolation in [`extrapolate`].
//!
//! This module knows nothing of the language: the interpreter wraps mx
//! functions of time as [`TimeFunction`]s and calls the operations here.
//!
//! Conventions (see each module for details):
//! - Intervals are closed, `start < stop`; a DOF's intervals are sorted and
//!   disjoint, possibly touching. Touching endpoints are not an overlap:
//!   `[0,1] + [1,2]` is not a conflict.
//! - Times closer than [`time_tol`] are the same time in set operations and
//!   containment, so floating-point rounding never creates sliver gaps.

pub mod channel;
pub mod compose;
pub mod curve;
pub mod cyclify;
mod display;
pub mod dof;
pub mod error;
pub mod extrapolate;
pub mod fill;
pub mod func;
pub mod interval;
pub mod joint_sampler;
pub mod mu;
pub mod ops;
pub mod rotation;
pub mod sample;

pub use compose::Weight;
pub use curve::{Curve, HermiteCurve, SampledCurve, TimeFunction};
pub use dof::Dof;
pub use error::{FnError, MotionError};
pub use extrapolate::{Extrapolation, extrapolate};
pub use fill::{fill_hermite, fill_linear, fill_slerp};
pub use func::Func;
pub use interval::Interval;
pub use joint_sampler::JointSampler;
pub use mu::Mu;
pub use ops::{
    DofSpan, affine, and, clip, clip_in_place, concatenate, conflicts, gaps, minus, only, plus,
    span,
};
pub use sample::{Grid, Located, frames, grid_times, sample_grid, sample_period};

/// Two times closer than this are treated as equal: 1e-9 s, relative beyond
/// one second. Far below any frame period (mocap runs at ≤ 1 kHz) and far
/// above the rounding error of a few affine maps.
#[inline]
pub fn time_tol(t: f64) -> f64 {
    1e-9 * t.abs().max(1.0)
}
