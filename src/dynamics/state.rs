//! The arguments the algorithms share, bundled so each signature says what it
//! reads and writes: where the body is and how it moves ([`JointState`]), what
//! drives it in forward dynamics ([`Forces`]), and where a gradient with respect
//! to the state goes ([`StateGradient`]). Each slice has one entry per coordinate.

use crate::lie::Wrench;
use nalgebra::Vector3;

/// The body at one instant: coordinates `q`, velocities `v` (q̇) and
/// accelerations `a` (q̈).
#[derive(Clone, Copy, Debug)]
pub struct JointState<'a> {
    pub q: &'a [f64],
    pub v: &'a [f64],
    pub a: &'a [f64],
}

impl<'a> JointState<'a> {
    pub fn new(q: &'a [f64], v: &'a [f64], a: &'a [f64]) -> Self {
        JointState { q, v, a }
    }
}

/// What drives forward dynamics: joint forces `tau`, `gravity` (a world-frame
/// vector; models carry theirs as `Model::default_gravity`) and optionally one
/// external wrench per link (`fext[i]` on link i, in its frame, moment about
/// its origin, `[μ; η]`).
#[derive(Clone, Copy, Debug)]
pub struct Forces<'a> {
    pub tau: &'a [f64],
    pub gravity: &'a Vector3<f64>,
    pub fext: Option<&'a [Wrench]>,
}

impl<'a> Forces<'a> {
    /// Joint forces and gravity, no external wrench.
    pub fn new(tau: &'a [f64], gravity: &'a Vector3<f64>) -> Self {
        Forces {
            tau,
            gravity,
            fext: None,
        }
    }

    /// The same forces with external wrenches on the links.
    pub fn with_wrenches(self, fext: &'a [Wrench]) -> Self {
        Forces {
            fext: Some(fext),
            ..self
        }
    }
}

/// Where the gradient of a scalar function of (q, q̇, q̈) is written: its
/// partial derivatives with respect to `q`, `v` and `a`.
#[derive(Debug)]
pub struct StateGradient<'a> {
    pub q: &'a mut [f64],
    pub v: &'a mut [f64],
    pub a: &'a mut [f64],
}
