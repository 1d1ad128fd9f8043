//! SO(3): exponential, logarithm (through a unit quaternion) and the
//! derivative of the exponential.

use super::series::{one_minus_cos_over_t2, sinc, t_minus_sin_over_t3};
use super::skew;
use nalgebra::{Matrix3, Vector3};

/// exp([ω]) by Rodrigues' formula: I + A[ω] + B[ω]², A = sin θ/θ, B = (1−cos θ)/θ².
pub fn exp_so3(w: &Vector3<f64>) -> Matrix3<f64> {
    let theta = w.norm();
    let a = sinc(theta);
    let b = one_minus_cos_over_t2(theta);
    let k = skew(w);
    Matrix3::identity() + k * a + k * k * b
}

/// A unit quaternion `(w, x, y, z)` from a rotation matrix, by the largest
/// pivot (Shepperd): the square root is taken of the largest of the four
/// candidates 1 + trace, 1 + 2R_ii − trace, so it is never near zero and every
/// component keeps full relative accuracy, including near θ = π.
/// The sign is chosen so that w ≥ 0 (rotation angle in [0, π]).
pub fn quat_from_matrix(r: &Matrix3<f64>) -> [f64; 4] {
    let tr = r[(0, 0)] + r[(1, 1)] + r[(2, 2)];
    let cands = [tr, r[(0, 0)], r[(1, 1)], r[(2, 2)]];
    let mut i = 0;
    for k in 1..4 {
        if cands[k] > cands[i] {
            i = k;
        }
    }
    let q = match i {
        0 => {
            let s = 2.0 * (1.0 + tr).sqrt(); // s = 4w
            [
                0.25 * s,
                (r[(2, 1)] - r[(1, 2)]) / s,
                (r[(0, 2)] - r[(2, 0)]) / s,
                (r[(1, 0)] - r[(0, 1)]) / s,
            ]
        }
        1 => {
            let s = 2.0 * (1.0 + r[(0, 0)] - r[(1, 1)] - r[(2, 2)]).sqrt(); // 4x
            [
                (r[(2, 1)] - r[(1, 2)]) / s,
                0.25 * s,
                (r[(0, 1)] + r[(1, 0)]) / s,
                (r[(0, 2)] + r[(2, 0)]) / s,
            ]
        }
        2 => {
            let s = 2.0 * (1.0 - r[(0, 0)] + r[(1, 1)] - r[(2, 2)]).sqrt(); // 4y
            [
                (r[(0, 2)] - r[(2, 0)]) / s,
                (r[(0, 1)] + r[(1, 0)]) / s,
                0.25 * s,
                (r[(1, 2)] + r[(2, 1)]) / s,
            ]
        }
        _ => {
            let s = 2.0 * (1.0 - r[(0, 0)] - r[(1, 1)] + r[(2, 2)]).sqrt(); // 4z
            [
                (r[(1, 0)] - r[(0, 1)]) / s,
                (r[(0, 2)] + r[(2, 0)]) / s,
                (r[(1, 2)] + r[(2, 1)]) / s,
                0.25 * s,
            ]
        }
    };
    let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
    let sg = if q[0] < 0.0 { -1.0 / n } else { 1.0 / n };
    [q[0] * sg, q[1] * sg, q[2] * sg, q[3] * sg]
}

/// log(R) as a rotation vector ω with |ω| ∈ [0, π].
///
/// Via the quaternion (w, v): θ = 2 atan2(|v|, w), ω = θ v/|v|. `atan2` is
/// well conditioned everywhere, so there is no cancellation near 0 (where
/// θ/|v| → 2/w) nor near π (where w → 0 and the largest pivot keeps v exact).
/// At exactly θ = π both ±ω are logarithms; the one returned has the sign of
/// the largest component of v positive (the pivot choice), a deterministic rule.
pub fn log_so3(r: &Matrix3<f64>) -> Vector3<f64> {
    let q = quat_from_matrix(r);
    let v = Vector3::new(q[1], q[2], q[3]);
    let s = v.norm();
    if s == 0.0 {
        return Vector3::zeros();
    }
    let theta = 2.0 * s.atan2(q[0]);
    v * (theta / s)
}

/// The right Jacobian of SO(3): `exp(ω + δ) ≈ exp(ω) exp(J_r(ω) δ)`,
/// J_r = I − B[ω] + C[ω]², with C = (θ − sin θ)/θ³.
pub fn right_jacobian_so3(w: &Vector3<f64>) -> Matrix3<f64> {
    let theta = w.norm();
    let k = skew(w);
    Matrix3::identity() - k * one_minus_cos_over_t2(theta) + k * k * t_minus_sin_over_t3(theta)
}

/// The left Jacobian of SO(3): `exp(ω + δ) ≈ exp(J_l(ω) δ) exp(ω)`; J_l(ω) = J_r(−ω).
/// It is also the matrix V in exp of SE(3): p = J_l(ω) v.
pub fn left_jacobian_so3(w: &Vector3<f64>) -> Matrix3<f64> {
    right_jacobian_so3(&(-w))
}

/// The inverse of the left Jacobian: I − ½[ω] + D[ω]², D = (1 − (θ/2)cot(θ/2))/θ².
/// Singular at θ = 2π only; callers pass |ω| ≤ π (from [`log_so3`]).
pub fn left_jacobian_inv_so3(w: &Vector3<f64>) -> Matrix3<f64> {
    let theta = w.norm();
    let k = skew(w);
    Matrix3::identity() - k * 0.5 + k * k * super::series::log_v_coeff(theta)
}

/// The angle of a rotation matrix, accurate near 0 and π.
pub fn rotation_angle(r: &Matrix3<f64>) -> f64 {
    log_so3(r).norm()
}
