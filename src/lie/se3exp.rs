//! SE(3) exponential and logarithm of twists `[ω; v]`, and the adjoint matrix
//! `ad` used in the derivative of the exponential.

use super::so3::{exp_so3, left_jacobian_inv_so3, left_jacobian_so3, log_so3};
use super::{Se3, Twist, skew};
use nalgebra::{Matrix6, Vector3};

/// exp of a twist: R = exp([ω]), p = J_l(ω) v (a screw motion).
pub fn exp_se3(x: &Twist) -> Se3 {
    let w = Vector3::new(x[0], x[1], x[2]);
    let v = Vector3::new(x[3], x[4], x[5]);
    // Pure translations and pure rotations (most joint factors) skip the
    // work they do not need; the results are identical to the general case.
    if w == Vector3::zeros() {
        return Se3::from_translation(v);
    }
    if v == Vector3::zeros() {
        return Se3::from_rotation(exp_so3(&w));
    }
    Se3::new(exp_so3(&w), left_jacobian_so3(&w) * v)
}

/// log of a rigid transform: ω = log R (|ω| ≤ π), v = J_l(ω)⁻¹ p.
pub fn log_se3(t: &Se3) -> Twist {
    let w = log_so3(&t.r);
    let v = left_jacobian_inv_so3(&w) * t.p;
    Twist::new(w.x, w.y, w.z, v.x, v.y, v.z)
}

/// The 6×6 matrix of `ad_x` (Lie bracket with x): [[ω],0; [v],[ω]].
pub fn ad_bracket_matrix(x: &Twist) -> Matrix6<f64> {
    let w = skew(&Vector3::new(x[0], x[1], x[2]));
    let v = skew(&Vector3::new(x[3], x[4], x[5]));
    let mut m = Matrix6::zeros();
    m.fixed_view_mut::<3, 3>(0, 0).copy_from(&w);
    m.fixed_view_mut::<3, 3>(3, 3).copy_from(&w);
    m.fixed_view_mut::<3, 3>(3, 0).copy_from(&v);
    m
}

impl Se3 {
    /// `exp(x)` for a twist x.
    pub fn exp(x: &Twist) -> Se3 {
        exp_se3(x)
    }
    /// `log(self)` as a twist.
    pub fn log(&self) -> Twist {
        log_se3(self)
    }
}
