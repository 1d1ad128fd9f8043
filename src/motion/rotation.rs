//! Joint rotations written as three Euler channels (`Joint.Zrotation`,
//! `Joint.Xrotation`, `Joint.Yrotation`, in the order the motion lists them,
//! which is the BVH channel order: R = R_a(α)·R_b(β)·R_c(γ)), as unit
//! quaternions and back.
//!
//! Operators that mix poses (slerp in-betweening, blends) work on the
//! rotation, never on raw Euler angles: near gimbal lock (Bandai joints sit
//! near a middle angle of ±90°) a small rotation can be a large change of
//! two channels, and interpolating them channel by channel spins the limb.
//! Going back, [`to_euler_near`] picks, of the two Euler triples of a
//! rotation and their 2π wraps, the one nearest a reference, so curves stay
//! continuous and equal to the capture's unwrapped channels at the ends.

use nalgebra::{Matrix3, Rotation3, Unit, UnitQuaternion, Vector3};
use std::f64::consts::{PI, TAU};

// The channel naming rules live in `super::channel`; these names stay for
// the callers that have always found them here.
pub use super::channel::{EulerJoint, euler_joints, rotation_axis};

fn axis_vector(axis: usize) -> Unit<Vector3<f64>> {
    match axis {
        0 => Vector3::x_axis(),
        1 => Vector3::y_axis(),
        _ => Vector3::z_axis(),
    }
}

/// R_a(α)·R_b(β)·R_c(γ) as a unit quaternion.
pub fn from_euler(axes: [usize; 3], angles: [f64; 3]) -> UnitQuaternion<f64> {
    axes.iter()
        .zip(angles)
        .map(|(&a, t)| UnitQuaternion::from_axis_angle(&axis_vector(a), t))
        .fold(UnitQuaternion::identity(), |acc, r| acc * r)
}

/// One Euler triple of `r` in the order `axes` (β in [−π/2, π/2]): the
/// principal angles a BVH exporter writes.
pub fn euler_of(axes: [usize; 3], r: &Matrix3<f64>) -> [f64; 3] {
    let [i, j, k] = axes;
    // +1 when (i, j, k) is a cyclic permutation of (x, y, z)
    let s = if (j + 3 - i) % 3 == 1 { 1.0 } else { -1.0 };
    // atan2, not asin: near gimbal lock asin(1 − ε) loses half the digits
    let cb = r[(i, i)].hypot(r[(i, j)]);
    let beta = (s * r[(i, k)]).atan2(cb);
    let alpha = (-s * r[(j, k)]).atan2(r[(k, k)]);
    // γ from what is left once α and β are taken out, so the three compose to
    // r to rounding even near gimbal lock (where α alone is ill-conditioned)
    let ab = Rotation3::from_axis_angle(&axis_vector(i), alpha)
        * Rotation3::from_axis_angle(&axis_vector(j), beta);
    let rest = ab.matrix().transpose() * r;
    let (p, q) = ((k + 1) % 3, (k + 2) % 3);
    let gamma = rest[(q, p)].atan2(rest[(p, p)]);
    [alpha, beta, gamma]
}

/// `x` plus the multiple of 2π that brings it nearest `near`.
fn wrap_near(x: f64, near: f64) -> f64 {
    x + TAU * ((near - x) / TAU).round()
}

/// The Euler angles of `q` (order `axes`) nearest `near`: of the two triples
/// (α, β, γ) and (α + π, π − β, γ + π), each wrapped by whole turns towards
/// `near`, the one at the smaller distance.
pub fn to_euler_near(axes: [usize; 3], q: &UnitQuaternion<f64>, near: [f64; 3]) -> [f64; 3] {
    let r: Rotation3<f64> = q.to_rotation_matrix();
    let [a, b, c] = euler_of(axes, r.matrix());
    let candidates = [[a, b, c], [a + PI, PI - b, c + PI]];
    let mut best = [0.0; 3];
    let mut best_d = f64::INFINITY;
    for cand in candidates {
        let w: [f64; 3] = std::array::from_fn(|i| wrap_near(cand[i], near[i]));
        let d: f64 = (0..3).map(|i| (w[i] - near[i]).powi(2)).sum();
        if d < best_d {
            best_d = d;
            best = w;
        }
    }
    best
}

/// `a` turned by the shorter way to `b`: `b` or `−b`, whichever is nearer `a`
/// as a 4-vector (the sign alignment of quaternion curves).
pub fn align_sign(a: &UnitQuaternion<f64>, b: &UnitQuaternion<f64>) -> UnitQuaternion<f64> {
    if a.coords.dot(&b.coords) < 0.0 {
        UnitQuaternion::new_unchecked(-b.into_inner())
    } else {
        *b
    }
}

/// Spherical linear interpolation along the shorter arc, s ∈ [0, 1].
pub fn slerp(a: &UnitQuaternion<f64>, b: &UnitQuaternion<f64>, s: f64) -> UnitQuaternion<f64> {
    let b = align_sign(a, b);
    // a·exp(s·log(a⁻¹b)): exact at s = 0 and 1, stable for nearly equal ends
    let d = a.inverse() * b;
    let w = d.scaled_axis();
    a * UnitQuaternion::from_scaled_axis(w * s)
}

/// `q^s` along the arc `q` itself describes, sign included: the raw
/// quaternion (w, v) is the rotation by 2·atan2(|v|, w) ∈ [0, 2π], so a
/// sign-aligned curve of `q` gives a curve of `q^s` continuous in time.
pub fn pow_signed(q: &UnitQuaternion<f64>, s: f64) -> UnitQuaternion<f64> {
    let v = q.vector();
    let n = v.norm();
    if n < 1e-300 {
        return if q.scalar() >= 0.0 {
            UnitQuaternion::identity()
        } else {
            // −1: a full turn about an undetermined axis; s of it about x
            UnitQuaternion::from_axis_angle(&Vector3::x_axis(), s * TAU)
        };
    }
    let theta = 2.0 * n.atan2(q.scalar());
    UnitQuaternion::from_scaled_axis(v * (theta * s / n))
}

/// Interpolation from `a` to `b` along the arc their signs give (the longer
/// one when a·b < 0): for mixing curves whose quaternions are each
/// sign-aligned along time, so the mix does not flip where the shorter arc
/// switches sides.
pub fn slerp_signed(
    a: &UnitQuaternion<f64>,
    b: &UnitQuaternion<f64>,
    s: f64,
) -> UnitQuaternion<f64> {
    a * pow_signed(&(a.inverse() * b), s)
}

#[cfg(test)]
mod tests {
    use super::*;

    const ORDERS: [[usize; 3]; 6] = [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ];

    #[test]
    fn euler_round_trip_in_every_order_and_near_gimbal_lock() {
        let mut seed = 7u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for axes in ORDERS {
            for k in 0..200 {
                let mut e = [
                    (rnd() - 0.5) * 6.0,
                    (rnd() - 0.5) * 3.0,
                    (rnd() - 0.5) * 6.0,
                ];
                if k % 4 == 0 {
                    // within 1e-7 rad of gimbal lock
                    e[1] = (PI / 2.0 - 1e-7) * if k % 8 == 0 { 1.0 } else { -1.0 };
                }
                let q = from_euler(axes, e);
                let back = to_euler_near(axes, &q, e);
                let q2 = from_euler(axes, back);
                assert!(q.angle_to(&q2) < 1e-12, "{axes:?} {e:?} → {back:?}");
                if k % 4 != 0 {
                    for i in 0..3 {
                        assert!((back[i] - e[i]).abs() < 1e-9, "{axes:?} {e:?} → {back:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn the_other_branch_and_wraps_are_found() {
        let axes = [2, 0, 1];
        let e = [0.3 + 4.0 * PI, PI - 0.2, -1.0 - 2.0 * PI];
        let q = from_euler(axes, e);
        let back = to_euler_near(axes, &q, e);
        for i in 0..3 {
            assert!((back[i] - e[i]).abs() < 1e-12);
        }
    }

    #[test]
    fn euler_joints_follow_the_motion_order() {
        let names = [
            "Hips.Xposition",
            "Hips.Zrotation",
            "Hips.Xrotation",
            "Hips.Yrotation",
            "Knee.Xrotation",
            "Arm.Yrotation",
            "Arm.Yrotation2",
        ];
        let j = euler_joints(names);
        assert_eq!(j.len(), 1);
        assert_eq!(j[0].joint, "Hips");
        assert_eq!(j[0].axes, [2, 0, 1]);
    }

    #[test]
    fn slerp_takes_the_short_way_and_keeps_its_ends() {
        let a = from_euler([0, 1, 2], [0.1, 0.2, 0.3]);
        let b = from_euler([0, 1, 2], [2.0, -0.4, 1.0]);
        let nb = UnitQuaternion::new_unchecked(-b.into_inner());
        assert!(slerp(&a, &nb, 0.0).angle_to(&a) < 1e-15);
        assert!(slerp(&a, &nb, 1.0).angle_to(&b) < 1e-14);
        let mid = slerp(&a, &b, 0.5);
        assert!((mid.angle_to(&a) - mid.angle_to(&b)).abs() < 1e-14);
        assert!((mid.angle_to(&a) - 0.5 * a.angle_to(&b)).abs() < 1e-14);
    }
}
