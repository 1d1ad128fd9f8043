//! Joint evaluation cost (transform + Jacobian + Hessian) per joint type, and
//! spline-joint fitting: fit time and accuracy against the number of control
//! frames (the accuracy-vs-time knob of curve-joint design).
//!
//! Run: `cargo bench --bench joints`. The fitting table and the knee-model
//! comparison (`print_knee_table`) use the OpenSim knee samples from
//! `$MX_SHARED/data/opensim` (default `../shared`).

use divan::{Bencher, black_box};
use mx::dynamics::{Workspace, inverse_dynamics};
use mx::lie::{Se3, Twist, exp_se3};
use mx::model::joint::{Derivatives, Joint, JointKinematics};
use mx::model::joint_fit::{FitOptions, fit_spline_joint};
use mx::model::joints::*;
use mx::model::{Inertia, Model};
use mx::spline::{BSplineBasis, SimmSpline, TensorSpline};
use nalgebra::{Matrix3, Vector3};
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

fn main() {
    print_fit_table();
    print_knee_table();
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

fn knee_samples_path() -> PathBuf {
    let dir = std::env::var_os("MX_SHARED")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared"));
    dir.join("data/opensim/knee_r_gait2392_samples.json")
}

fn knee_samples() -> Option<JointSamples> {
    JointSamples::load(knee_samples_path()).ok()
}

/// gait2392's shank (tibia_r) on a knee: one link, the femur fixed.
fn shank_on(joint: Arc<dyn Joint>, offset: Se3) -> Model {
    let inertia = Inertia::from_com(
        3.7075,
        Vector3::new(0.0, -0.1867, 0.0),
        Matrix3::from_diagonal(&Vector3::new(0.0504, 0.0051, 0.0511)),
    )
    .expect("inertia");
    let mut m = Model::new("shank");
    m.add_link("tibia_r", None, "knee_r", joint, offset, inertia)
        .expect("link");
    m
}

/// The spline-joint paper's Fig. 1 claim, measured: one knee motion (a
/// 1 s flexion swing, q = −1 − 0.8 sin 2πt rad, inside the samples' range)
/// and its knee torque under the model's own CustomJoint (the tibia slides on
/// two SimmSplines), a pin at the swing's middle pose, and a spline curve
/// joint fitted to the CustomJoint's samples (12 control frames, the first
/// within 0.1 mm in the fit table above), with the
/// cost of inverse dynamics per state under each, in one run.
fn print_knee_table() {
    let path = knee_samples_path();
    let (Some(s), Ok(text)) = (knee_samples(), std::fs::read_to_string(&path)) else {
        eprintln!("knee samples not found (set MX_SHARED): skipping the knee-model table");
        return;
    };
    let v: serde_json::Value = serde_json::from_str(&text).expect("samples JSON");
    let custom = FunctionJoint::from_opensim_samples_json(&v).expect("CustomJoint");
    let fitted = fit_spline_joint(
        &s,
        &FitOptions {
            frames: 12,
            ..Default::default()
        },
    )
    .expect("fit")
    .joint;
    let fit_err = joint_error(&fitted, &s).expect("error");
    let mid = -1.0;
    let mut k = JointKinematics::default();
    custom.kinematics(&[mid], Derivatives::Transform, &mut k);
    let rz = Se3::new(
        *nalgebra::Rotation3::from_axis_angle(&Vector3::z_axis(), -mid).matrix(),
        Vector3::zeros(),
    );
    let pin_offset = k.transform * rz; // the pin at q = mid is the CustomJoint's pose there
    let models = [
        (
            "CustomJoint (model's own)",
            shank_on(Arc::new(custom), Se3::identity()),
        ),
        (
            "pin at the middle pose",
            shank_on(
                Arc::new(Revolute::new(Vector3::z()).expect("axis")),
                pin_offset,
            ),
        ),
        (
            "spline curve joint, 12 frames",
            shank_on(Arc::new(fitted), Se3::identity()),
        ),
    ];
    let g = Vector3::new(0.0, -9.80665, 0.0);
    let n = 1001;
    let w = 2.0 * std::f64::consts::PI;
    let states: Vec<[f64; 3]> = (0..n)
        .map(|i| {
            let t = i as f64 / (n - 1) as f64;
            [
                mid - 0.8 * (w * t).sin(),
                -0.8 * w * (w * t).cos(),
                0.8 * w * w * (w * t).sin(),
            ]
        })
        .collect();
    let torques = |m: &Model| -> Vec<f64> {
        let mut ws = Workspace::new(m);
        let mut tau = [0.0];
        states
            .iter()
            .map(|x| {
                inverse_dynamics(m, &mut ws, &x[..1], &x[1..2], &x[2..], &g, &mut tau).expect("ID");
                tau[0]
            })
            .collect()
    };
    // ns per inverse-dynamics call over one pass of the motion
    let pass = |m: &Model| -> f64 {
        let mut ws = Workspace::new(m);
        let mut tau = [0.0];
        let t0 = Instant::now();
        for x in &states {
            inverse_dynamics(
                m,
                &mut ws,
                black_box(&x[..1]),
                &x[1..2],
                &x[2..],
                &g,
                &mut tau,
            )
            .expect("ID");
            black_box(tau[0]);
        }
        t0.elapsed().as_secs_f64() * 1e9 / n as f64
    };
    // the three knees alternated, 7 rounds, the best pass of each: ratios from one run
    let mut costs = [f64::INFINITY; 3];
    for _ in 0..7 {
        for (c, (_, m)) in costs.iter_mut().zip(&models) {
            *c = c.min(pass(m));
        }
    }
    let reference = torques(&models[0].1);
    let rms = |v: &[f64]| (v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64).sqrt();
    let ref_rms = rms(&reference);
    println!(
        "knee models on gait2392's shank, one flexion swing (q = -1 - 0.8 sin 2πt rad, {n} states); \
         the curve joint is {:.3} mm / {:.4}° from the CustomJoint's samples",
        fit_err.max_mm, fit_err.max_deg
    );
    println!(
        "{:<30} {:>9} {:>9} {:>12} {:>12} {:>9} {:>7}",
        "knee", "rms τ N·m", "max τ N·m", "max |Δτ| N·m", "rms Δτ / rms", "ns / ID", "× cost"
    );
    for ((name, m), ns) in models.iter().zip(costs) {
        let tau = torques(m);
        let diff: Vec<f64> = tau.iter().zip(&reference).map(|(a, b)| a - b).collect();
        println!(
            "{:<30} {:>9.4} {:>9.4} {:>12.2e} {:>12.2e} {:>9.0} {:>7.2}",
            name,
            rms(&tau),
            tau.iter().fold(0.0f64, |a, x| a.max(x.abs())),
            diff.iter().fold(0.0f64, |a, x| a.max(x.abs())),
            rms(&diff) / ref_rms,
            ns,
            ns / costs[0]
        );
    }
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
