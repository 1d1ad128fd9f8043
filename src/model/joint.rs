//! The one trait every joint implements, and the fixed-size buffer it fills.
//!
//! A joint maps its coordinates `q ∈ ℝⁿ` (n ≤ 6) to the transform `G(q)` of the
//! child joint frame in the parent joint frame (`x_parent = G(q) x_child`).
//! Its body-frame Jacobian is `S(q) = (G⁻¹ ∂G/∂q)^∨` (6×n, eq. 13 of the
//! spline-joint paper) and its Hessian `∇S(q)` holds `∂s_j/∂q_k`.

use crate::lie::{Se3, Twist};
use std::fmt::Debug;

/// The largest number of coordinates a joint may have.
pub const MAX_JOINT_DOF: usize = 6;

/// How much of [`JointKinematics`] a call must fill: each level includes the ones before.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Derivatives {
    /// Only `transform`.
    Transform,
    /// `transform` and the Jacobian `s`.
    Jacobian,
    /// `transform`, `s` and the Hessian `ds`.
    Hessian,
}

/// What a joint computes at one configuration. Fixed-size so that evaluating a
/// joint never allocates; only the first `dof()` columns are meaningful.
#[derive(Clone, Debug)]
pub struct JointKinematics {
    /// `G(q)`.
    pub transform: Se3,
    /// `s[j]` is column j of `S(q)`.
    pub s: [Twist; MAX_JOINT_DOF],
    /// `ds[j][k] = ∂s_j/∂q_k` (symmetric in j, k for a product-of-exponentials joint
    /// only up to a bracket term; do not assume symmetry).
    pub ds: [[Twist; MAX_JOINT_DOF]; MAX_JOINT_DOF],
}

impl Default for JointKinematics {
    fn default() -> Self {
        JointKinematics {
            transform: Se3::identity(),
            s: [Twist::zeros(); MAX_JOINT_DOF],
            ds: [[Twist::zeros(); MAX_JOINT_DOF]; MAX_JOINT_DOF],
        }
    }
}

/// A closed interval of admissible values of one coordinate (±∞ when unlimited).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limit {
    pub lower: f64,
    pub upper: f64,
}

impl Limit {
    pub const NONE: Limit = Limit {
        lower: f64::NEG_INFINITY,
        upper: f64::INFINITY,
    };
}

/// A joint type. Implementations live one per file in `model::joints`.
pub trait Joint: Send + Sync + Debug {
    /// A short name of the joint type, e.g. `"revolute"`.
    fn kind(&self) -> &'static str;

    /// Number of coordinates n (0 ≤ n ≤ [`MAX_JOINT_DOF`]).
    fn dof(&self) -> usize;

    /// Names of the coordinates, used to name a body's coordinates
    /// (`"<joint>.<suffix>"`; a 1-DOF joint may return `[""]` to use the joint name alone).
    fn coordinate_suffixes(&self) -> Vec<String> {
        match self.dof() {
            0 => vec![],
            1 => vec![String::new()],
            n => (0..n).map(|i| format!("q{i}")).collect(),
        }
    }

    /// Fills `out` up to the level `want` at configuration `q` (`q.len() == dof()`).
    fn kinematics(&self, q: &[f64], want: Derivatives, out: &mut JointKinematics);

    /// Admissible ranges of the coordinates.
    fn limits(&self) -> Vec<Limit> {
        vec![Limit::NONE; self.dof()]
    }

    /// True when `S` does not depend on `q` (so `ds` is zero): lets the dynamics
    /// skip the Hessian terms. Only return true when it really holds.
    fn constant_jacobian(&self) -> bool {
        false
    }
}
