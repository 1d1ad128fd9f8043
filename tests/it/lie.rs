//! exp/log round trips, Ad/ad consistency and dexp over a sweep of angles that
//! includes 0, 1e-12 … 1e-3, π − 1e-9 and π.

use mx::lie::*;
use nalgebra::{Matrix3, Vector3};
use std::f64::consts::PI;

fn angles() -> Vec<f64> {
    let mut a = vec![0.0];
    for e in -12..=-3 {
        a.push(10f64.powi(e));
        a.push(3.0 * 10f64.powi(e));
    }
    a.extend([0.1, 0.5, 1.0 - 1e-12, 1.0, 1.0 + 1e-12, 2.0, 3.0]);
    a.extend([PI - 1e-3, PI - 1e-6, PI - 1e-9, PI - 1e-12, PI]);
    a
}

fn axes() -> Vec<Vector3<f64>> {
    // fixed pseudo-random unit axes (a simple LCG keeps the test deterministic)
    let mut s: u64 = 0x1234_5678;
    let mut next = || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((s >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    };
    let mut v = vec![
        Vector3::x(),
        Vector3::y(),
        Vector3::z(),
        Vector3::new(1.0, 1.0, 1.0).normalize(),
    ];
    for _ in 0..8 {
        v.push(Vector3::new(next(), next(), next()).normalize());
    }
    v
}

fn mat_err(a: &Matrix3<f64>, b: &Matrix3<f64>) -> f64 {
    (a - b).abs().max()
}

#[test]
fn so3_and_se3_round_trips_are_exact_to_1e_12() {
    let mut worst_rot = 0.0f64;
    let mut worst_log = 0.0f64;
    let mut worst_se3 = 0.0f64;
    for th in angles() {
        for ax in axes() {
            let w = ax * th;
            let r = exp_so3(&w);
            // R stays orthonormal
            worst_rot = worst_rot.max(mat_err(&(r.transpose() * r), &Matrix3::identity()));
            let w2 = log_so3(&r);
            // exp(log R) = R at every angle; log(exp ω) = ω below π (at π, ±ω both valid).
            worst_rot = worst_rot.max(mat_err(&exp_so3(&w2), &r));
            let e = if th < PI - 1e-6 {
                (w2 - w).norm()
            } else {
                (w2 - w).norm().min((w2 + w).norm())
            };
            worst_log = worst_log.max(e);
            assert!((w2.norm() - th).abs() <= 1e-12, "angle {th}: {}", w2.norm());

            let x = Twist::new(w.x, w.y, w.z, 0.3, -1.2, 0.7);
            let t = exp_se3(&x);
            let y = log_se3(&t);
            let t2 = exp_se3(&y);
            worst_se3 = worst_se3.max(mat_err(&t2.r, &t.r)).max((t2.p - t.p).norm());
            if th < PI - 1e-6 {
                worst_se3 = worst_se3.max((y - x).norm());
            }
        }
    }
    println!(
        "worst SO(3) exp(log R) error {worst_rot:.3e}, log(exp ω) error {worst_log:.3e}, SE(3) round trip {worst_se3:.3e}"
    );
    assert!(worst_rot <= 1e-12 && worst_log <= 1e-12 && worst_se3 <= 1e-12);
}

#[test]
fn small_angles_keep_full_relative_accuracy() {
    // log(exp(ω)) for tiny ω must be ω to relative precision, not absolute.
    for e in -12..=-3 {
        let th = 10f64.powi(e);
        let w = Vector3::new(0.6, -0.8, 0.0) * th;
        let w2 = log_so3(&exp_so3(&w));
        assert!(
            (w2 - w).norm() <= 1e-14 * th,
            "θ={th}: {}",
            (w2 - w).norm() / th
        );
        let x = Twist::new(w.x, w.y, w.z, 1.0, 2.0, 3.0);
        let y = log_se3(&exp_se3(&x));
        assert!((y - x).norm() <= 1e-14, "θ={th}");
    }
}

#[test]
fn adjoint_is_consistent_with_exp_and_bracket() {
    let mut worst = 0.0f64;
    for th in angles() {
        for ax in axes() {
            let x = Twist::new(ax.x * th, ax.y * th, ax.z * th, 0.2, 0.5, -0.4);
            let t = exp_se3(&Twist::new(0.3, -0.2, 0.9, 1.0, 0.0, -2.0));
            // exp(Ad_T x) = T exp(x) T⁻¹
            let lhs = exp_se3(&t.ad_twist(&x));
            let rhs = t.compose(&exp_se3(&x)).compose(&t.inverse());
            worst = worst
                .max(mat_err(&lhs.r, &rhs.r))
                .max((lhs.p - rhs.p).norm());
            // Ad_{exp x} x = x (a twist is invariant under its own flow)
            worst = worst.max((exp_se3(&x).ad_twist(&x) - x).norm());
            // ad matrix agrees with the bracket
            let y = Twist::new(0.1, 0.2, 0.3, -0.4, 0.5, -0.6);
            worst = worst.max((ad_bracket_matrix(&x) * y - ad(&x, &y)).norm());
        }
    }
    println!("worst Ad/ad consistency error {worst:.3e}");
    assert!(worst <= 1e-12);
}

#[test]
fn right_jacobian_matches_finite_differences() {
    for th in [0.0, 1e-8, 1e-4, 0.3, 1.5, 3.0] {
        let w = Vector3::new(0.48, 0.6, 0.64) * th;
        let jr = right_jacobian_so3(&w);
        let h = 1e-6;
        for k in 0..3 {
            let mut d = Vector3::zeros();
            d[k] = h;
            let fd = (log_so3(&(exp_so3(&w).transpose() * exp_so3(&(w + d))))
                - log_so3(&(exp_so3(&w).transpose() * exp_so3(&(w - d)))))
                / (2.0 * h);
            assert!((fd - jr.column(k)).norm() < 1e-8, "θ={th}");
        }
        let jl = left_jacobian_so3(&w);
        assert!(mat_err(&(jl * left_jacobian_inv_so3(&w)), &Matrix3::identity()) < 1e-13);
    }
}

#[test]
fn rotation_angle_is_accurate_near_pi() {
    for d in [1e-3, 1e-6, 1e-9] {
        let r = exp_so3(&(Vector3::new(0.0, 0.0, 1.0) * (PI - d)));
        assert!((rotation_angle(&r) - (PI - d)).abs() < 1e-13);
    }
    // exactly π about an arbitrary axis: angle π, and the axis up to sign.
    let a = Vector3::new(1.0, 2.0, -2.0) / 3.0;
    let w = log_so3(&exp_so3(&(a * PI)));
    assert!((w.norm() - PI).abs() < 1e-14);
    assert!((w / PI - a).norm().min((w / PI + a).norm()) < 1e-14);
}
