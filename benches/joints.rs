//! Joint evaluation cost (transform + Jacobian + Hessian) per joint type, and
//! spline-joint fitting: fit time and accuracy against the number of control
//! frames (the accuracy-vs-time knob of curve-joint design).
//!
//! Run: `cargo bench --bench joints`. The fitting table uses the OpenSim knee
//! samples from `$MX_SHARED/data/opensim` (default `../shared`).

use divan::{Bencher, black_box};
use mx::lie::{Se3, Twist, exp_se3};
use mx::model::joint::{Derivatives, Joint, JointKinematics};
use mx::model::joint_fit::{FitOptions, fit_spline_joint};
use mx::model::joints::*;
use mx::spline::{BSplineBasis, SimmSpline, TensorSpline};
use nalgebra::Vector3;
use std::path::PathBuf;
use std::time::Instant;

fn main() {
    print_fit_table();
    divan::main();
}

fn curve() -> SplineCurveJoint {
    let frames: Vec<Se3> = (0..8)
        .map(|i| {
            exp_se3(&Twist::new(
                0.1,
                0.2,
                0.3 * i as f64,
                0.01 * i as f64,
                0.02,
                0.0,
            ))
        })
        .collect();
    SplineCurveJoint::from_knots(frames, &[0., 0.3, 0.7, 1.0, 1.4, 1.9, 2.2, 3.0])
        .expect("valid frames")
}

fn ndof() -> SplineJoint {
    let b = BSplineBasis::clamped_uniform(3, 6, -1.0, 1.0).expect("basis");
    let phis = (0..6)
        .map(|k| {
            TensorSpline::new(
                vec![b.clone(), b.clone()],
                (0..36).map(|i| ((i * 7 + k) % 11) as f64 * 0.05).collect(),
            )
            .expect("spline")
        })
        .collect();
    SplineJoint::new(Se3::identity(), SplineJoint::standard_twists(), phis).expect("joint")
}

fn knee() -> FunctionJoint {
    let sp = |ys: &[f64]| {
        ScalarFunction::SimmSpline(
            SimmSpline::new(vec![-2.0, -1.2, -0.5, 0.0, 0.4], ys.to_vec()).expect("spline"),
        )
    };
    let ax = |v: [f64; 3], f| TransformAxis {
        axis: Vector3::new(v[0], v[1], v[2]),
        coordinate: Some(0),
        function: f,
    };
    let c = |v: [f64; 3]| TransformAxis {
        axis: Vector3::new(v[0], v[1], v[2]),
        coordinate: None,
        function: ScalarFunction::Constant { value: 0.0 },
    };
    FunctionJoint::new(
        "knee",
        vec!["q".into()],
        [
            ax(
                [0., 0., 1.],
                ScalarFunction::Linear {
                    slope: 1.0,
                    intercept: 0.0,
                },
            ),
            c([0., 1., 0.]),
            c([1., 0., 0.]),
        ],
        [
            ax([1., 0., 0.], sp(&[-0.003, 0.004, 0.002, -0.0045, -0.005])),
            ax([0., 1., 0.], sp(&[-0.42, -0.405, -0.398, -0.396, -0.395])),
            c([0., 0., 1.]),
        ],
        Se3::identity(),
        Se3::identity(),
    )
    .expect("joint")
}

fn joints() -> Vec<(&'static str, Box<dyn Joint>, Vec<f64>)> {
    vec![
        (
            "revolute",
            Box::new(Revolute::new(Vector3::z()).expect("axis")),
            vec![0.3],
        ),
        (
            "prismatic",
            Box::new(Prismatic::new(Vector3::x()).expect("axis")),
            vec![0.3],
        ),
        (
            "helical",
            Box::new(Helical::new(Vector3::z(), 0.01).expect("axis")),
            vec![0.3],
        ),
        (
            "cylindrical",
            Box::new(Cylindrical::new(Vector3::z()).expect("axis")),
            vec![0.3, 0.1],
        ),
        (
            "universal",
            Box::new(Universal::new(Vector3::x(), Vector3::y()).expect("axes")),
            vec![0.3, -0.2],
        ),
        (
            "spherical",
            Box::new(Spherical::default()),
            vec![0.3, -0.2, 0.5],
        ),
        ("planar", Box::new(Planar::xy()), vec![0.3, -0.2, 0.5]),
        (
            "root6",
            Box::new(Root6::new(EulerOrder::ZXY)),
            vec![0.1, 0.9, -0.2, 0.3, -0.2, 0.5],
        ),
        (
            "elliptic",
            Box::new(Elliptic::new(2.0, 1.0).expect("axes")),
            vec![0.7],
        ),
        ("spline_curve", Box::new(curve()), vec![1.2]),
        ("spline_2dof", Box::new(ndof()), vec![0.3, -0.4]),
        ("function_based", Box::new(knee()), vec![-0.7]),
    ]
}

const NAMES: &[&str] = &[
    "revolute",
    "prismatic",
    "helical",
    "cylindrical",
    "universal",
    "spherical",
    "planar",
    "root6",
    "elliptic",
    "spline_curve",
    "spline_2dof",
    "function_based",
];

/// Nanoseconds per transform + Jacobian + Hessian.
#[divan::bench(args = NAMES)]
fn kinematics_hessian(b: Bencher, name: &str) {
    let all = joints();
    let (_, j, q) = all.into_iter().find(|(n, _, _)| *n == name).expect("joint");
    let mut out = JointKinematics::default();
    b.bench_local(|| {
        j.kinematics(black_box(&q), Derivatives::Hessian, &mut out);
        black_box(&out);
    });
}

/// Transform only, for comparison.
#[divan::bench(args = NAMES)]
fn transform_only(b: Bencher, name: &str) {
    let all = joints();
    let (_, j, q) = all.into_iter().find(|(n, _, _)| *n == name).expect("joint");
    let mut out = JointKinematics::default();
    b.bench_local(|| {
        j.kinematics(black_box(&q), Derivatives::Transform, &mut out);
        black_box(&out);
    });
}

fn knee_samples() -> Option<JointSamples> {
    let dir = std::env::var_os("MX_SHARED")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared"));
    JointSamples::load(dir.join("data/opensim/knee_r_gait2392_samples.json")).ok()
}

const FRAMES: &[usize] = &[4, 6, 8, 12, 16, 24];

/// Fit time against the number of control frames (knee samples).
#[divan::bench(args = FRAMES, sample_count = 10)]
fn fit_knee(b: Bencher, frames: usize) {
    let Some(s) = knee_samples() else { return };
    b.bench_local(|| {
        fit_spline_joint(
            black_box(&s),
            &FitOptions {
                frames,
                ..Default::default()
            },
        )
        .expect("fit")
    });
}

/// Error-vs-time table of the fitting knob (control frames), printed once.
fn print_fit_table() {
    let Some(s) = knee_samples() else {
        eprintln!("knee samples not found (set MX_SHARED): skipping the fit table");
        return;
    };
    println!(
        "spline curve joint fit to the OpenSim knee ({} samples)",
        s.len()
    );
    println!(
        "{:>7} {:>9} {:>9} {:>9} {:>9} {:>6} {:>9}",
        "frames", "max mm", "rms mm", "max °", "rms °", "iters", "time ms"
    );
    for &frames in FRAMES {
        for smooth in [0.0, 1e-4] {
            let t0 = Instant::now();
            let Ok(r) = fit_spline_joint(
                &s,
                &FitOptions {
                    frames,
                    smooth,
                    ..Default::default()
                },
            ) else {
                continue;
            };
            let ms = t0.elapsed().as_secs_f64() * 1e3;
            let Ok(e) = joint_error(&r.joint, &s) else {
                continue;
            };
            println!(
                "{:>7} {:>9.5} {:>9.5} {:>9.5} {:>9.5} {:>6} {:>9.1}{}",
                frames,
                e.max_mm,
                e.rms_mm,
                e.max_deg,
                e.rms_deg,
                r.iterations,
                ms,
                if smooth > 0.0 {
                    "  (smooth w=1e-4)"
                } else {
                    ""
                }
            );
        }
    }
}
