//! The one trait every joint implements, and the fixed-size buffer it fills.
//!
//! A joint maps its coordinates `q ∈ ℝⁿ` (n ≤ 6) to the transform `G(q)` of the
//! child joint frame in the parent joint frame (`x_parent = G(q) x_child`).
//! Its body-frame Jacobian is `S(q) = (G⁻¹ ∂G/∂q)^∨` (6×n, eq. 13 of the
//! spline-joint paper) and its Hessian `∇S(q)` holds `∂s_j/∂q_k`.

use crate::lie::{Se3, Twist};
use nalgebra::{Matrix3, Unit, Vector3};
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

    /// `out[m] = ∂(Ṡ(q) q̇)/∂q_m` for m < `dof()`, where `Ṡ q̇ = Σ_ij ∂s_i/∂q_j q̇_i q̇_j`
    /// (body frame, q̇ = `v` held fixed): the joint map's third derivative
    /// contracted twice with the velocity, the one term of the dynamics'
    /// ∂τ/∂q and adjoint gradient the Hessian does not give. At a coordinate's
    /// range end it is the value from inside the range (as the Hessian is).
    ///
    /// Returns false when the joint does not provide it (the default, for joints
    /// defined outside this library); the dynamics then differences the Hessian.
    /// Never called for joints with a [`Joint::constant_jacobian`].
    fn sdot_v_dq(&self, q: &[f64], v: &[f64], out: &mut [Twist; MAX_JOINT_DOF]) -> bool {
        let _ = (q, v, out);
        false
    }

    /// `Some` for a 1-DOF joint that rotates about or slides along one fixed axis:
    /// its motion subspace is then constant and known, so the algorithms that
    /// work in the world frame (CRBA) place the link and its Jacobian column
    /// without the generic [`Joint::kinematics`] call.
    fn joint_axis(&self) -> Option<JointAxis> {
        None
    }
}

/// Whether a [`JointAxis`] rotates or translates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AxisMotion {
    Rotation,
    Translation,
}

/// The constant motion subspace of a revolute or prismatic joint, with fast
/// paths when the axis is a coordinate axis (URDF models are mostly built of
/// those): placing a link then touches two rotation columns instead of
/// multiplying two 3×3 matrices.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointAxis {
    pub motion: AxisMotion,
    axis: Unit<Vector3<f64>>,
    /// `Some((k, σ))` when the axis is exactly `σ e_k`.
    principal: Option<(usize, f64)>,
}

impl JointAxis {
    pub fn new(motion: AxisMotion, axis: Unit<Vector3<f64>>) -> Self {
        let principal = (0..3).find_map(|k| {
            let others_zero = (0..3).all(|j| j == k || axis[j] == 0.0);
            (others_zero && axis[k].abs() == 1.0).then_some((k, axis[k]))
        });
        JointAxis {
            motion,
            axis,
            principal,
        }
    }

    pub fn axis(&self) -> Vector3<f64> {
        self.axis.into_inner()
    }

    /// `Some((k, σ))` when the axis is exactly `σ e_k`: the motion subspace
    /// then has one nonzero, and link-frame algorithms read a component
    /// where they would take a dot product.
    pub fn principal(&self) -> Option<(usize, f64)> {
        self.principal
    }

    /// The joint's Jacobian column `s` (body frame, constant).
    pub fn twist(&self) -> Twist {
        let a = &self.axis;
        match self.motion {
            AxisMotion::Rotation => Twist::new(a.x, a.y, a.z, 0.0, 0.0, 0.0),
            AxisMotion::Translation => Twist::new(0.0, 0.0, 0.0, a.x, a.y, a.z),
        }
    }

    /// `G(q)`.
    pub fn transform(&self, q: f64) -> Se3 {
        match (self.motion, self.principal) {
            (AxisMotion::Rotation, None) => {
                Se3::from_rotation(nalgebra::Rotation3::from_axis_angle(&self.axis, q).into_inner())
            }
            (AxisMotion::Translation, None) => Se3::from_translation(self.axis.into_inner() * q),
            _ => self.place(&Se3::identity(), q),
        }
    }

    /// `t ∘ G(q)` without forming `G(q)` as a matrix.
    #[inline]
    pub fn place(&self, t: &Se3, q: f64) -> Se3 {
        match (self.motion, self.principal) {
            (AxisMotion::Rotation, Some((k, sign))) => {
                let (s, c) = (sign * q).sin_cos();
                let r = match k {
                    0 => rotate_columns::<0>(&t.r, s, c),
                    1 => rotate_columns::<1>(&t.r, s, c),
                    _ => rotate_columns::<2>(&t.r, s, c),
                };
                Se3 { r, p: t.p }
            }
            (AxisMotion::Rotation, None) => {
                let g = nalgebra::Rotation3::from_axis_angle(&self.axis, q).into_inner();
                Se3 { r: t.r * g, p: t.p }
            }
            (AxisMotion::Translation, Some((k, sign))) => Se3 {
                r: t.r,
                p: t.p + t.r.column(k) * (sign * q),
            },
            (AxisMotion::Translation, None) => Se3 {
                r: t.r,
                p: t.p + t.r * (self.axis.into_inner() * q),
            },
        }
    }

    /// `Ad_T s`: the Jacobian column in the frame `t` (typically the world placement
    /// of the child frame, as returned by [`JointAxis::place`]).
    #[inline]
    pub fn twist_in(&self, t: &Se3) -> Twist {
        let d = self.direction_in(&t.r);
        match self.motion {
            AxisMotion::Rotation => {
                let v = t.p.cross(&d);
                Twist::new(d.x, d.y, d.z, v.x, v.y, v.z)
            }
            AxisMotion::Translation => Twist::new(0.0, 0.0, 0.0, d.x, d.y, d.z),
        }
    }

    /// `R a`: the axis in the frame of rotation `r` (for a coordinate axis, a
    /// signed column of `r`). A link-aligned frame's Jacobian column is this
    /// direction in its angular (rotation) or linear (translation) half.
    #[inline]
    pub fn direction_in(&self, r: &Matrix3<f64>) -> Vector3<f64> {
        match self.principal {
            Some((k, sign)) => r.column(k) * sign,
            None => r * self.axis.into_inner(),
        }
    }
}

/// `r · Rot(e_K, θ)` given `sin θ`, `cos θ`: rotating about e_K mixes only the
/// two other columns of `r`. Built element by element from scalars (with K known
/// at compile time) so the placement stays in registers instead of being
/// patched column by column through memory.
#[inline(always)]
fn rotate_columns<const K: usize>(r: &Matrix3<f64>, s: f64, c: f64) -> Matrix3<f64> {
    let (a, b) = ((K + 1) % 3, (K + 2) % 3);
    Matrix3::from_fn(|i, j| {
        if j == K {
            r[(i, K)]
        } else if j == a {
            r[(i, a)] * c + r[(i, b)] * s
        } else {
            r[(i, b)] * c - r[(i, a)] * s
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The fast paths must agree with the generic `t ∘ G(q)` and `Ad_T s`,
    /// for coordinate axes of either sign and for a general axis.
    #[test]
    fn axis_fast_paths_match_generic_products() {
        let t = Se3 {
            r: nalgebra::Rotation3::from_euler_angles(0.3, -1.1, 2.0).into_inner(),
            p: Vector3::new(0.4, -0.2, 1.5),
        };
        let axes = [
            Vector3::x(),
            -Vector3::y(),
            Vector3::z(),
            -Vector3::z(),
            Vector3::new(0.3, -0.5, 0.8),
        ];
        for motion in [AxisMotion::Rotation, AxisMotion::Translation] {
            for a in axes {
                let axis = JointAxis::new(motion, Unit::new_normalize(a));
                assert_eq!(
                    axis.principal.is_some(),
                    a.iter().filter(|x| **x != 0.0).count() == 1
                );
                for q in [-2.5, 0.0, 0.7] {
                    let g = axis.transform(q);
                    let want = t.compose(&g);
                    let got = axis.place(&t, q);
                    assert!((got.r - want.r).norm() < 1e-14, "{motion:?} {a:?} {q}");
                    assert!((got.p - want.p).norm() < 1e-14, "{motion:?} {a:?} {q}");
                    let s = (axis.twist_in(&got) - got.ad_twist(&axis.twist())).norm();
                    assert!(s < 1e-14, "{motion:?} {a:?} {q}");
                    // G(q) itself: rotation by q about a, or translation q a.
                    let moved = g.r * Vector3::new(1.0, 2.0, 3.0) + g.p;
                    let expect = match motion {
                        AxisMotion::Rotation => {
                            nalgebra::Rotation3::from_axis_angle(&axis.axis, q)
                                * Vector3::new(1.0, 2.0, 3.0)
                        }
                        AxisMotion::Translation => Vector3::new(1.0, 2.0, 3.0) + axis.axis() * q,
                    };
                    assert!((moved - expect).norm() < 1e-14, "{motion:?} {a:?} {q}");
                }
            }
        }
    }
}
