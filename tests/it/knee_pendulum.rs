//! OpenSim's gait2392 knee pendulum (`$MX_SHARED/data/opensim/*_pendulum.json`):
//! the shank hangs from a fixed femur on the function-based knee joint; our
//! simulation must follow OpenSim's accuracy-1e-12 run within 1e-6 rad over 1 s.

use crate::common;

use mx::cancel::CancelToken;
use mx::dynamics::{Integrator, Scene, SceneWorkspace, State, simulate};
use mx::lie::Se3;
use mx::model::joints::FunctionJoint;
use mx::model::{Inertia, Model};
use nalgebra::{Matrix3, Matrix4, Rotation3, Vector3};
use serde_json::Value;
use std::sync::Arc;

fn v3(v: &Value) -> Vector3<f64> {
    Vector3::from_iterator(v.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()))
}

fn m3(v: &Value) -> Matrix3<f64> {
    let rows: Vec<f64> = v
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|r| r.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()))
        .collect();
    Matrix3::from_row_slice(&rows)
}

fn m4(v: &Value) -> Matrix4<f64> {
    let rows: Vec<f64> = v
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|r| r.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()))
        .collect();
    Matrix4::from_row_slice(&rows)
}

fn series(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

#[test]
fn knee_pendulum_follows_opensim() {
    let files = common::shared_files("opensim", "_pendulum.json");
    for path in &files {
        let run_file: Value =
            serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        // The joint lives in the samples file beside it (same SpatialTransform and offsets).
        let samples_path = path.with_file_name(
            path.file_name()
                .unwrap()
                .to_string_lossy()
                .replace("_pendulum.json", "_samples.json"),
        );
        let samples: Value =
            serde_json::from_str(&std::fs::read_to_string(&samples_path).unwrap()).unwrap();
        let joint =
            FunctionJoint::from_opensim_samples_json(&samples).unwrap_or_else(|e| panic!("{e:?}"));
        let joint = Arc::new(joint);
        for run in run_file["runs"].as_array().unwrap() {
            let name = run["name"].as_str().unwrap();
            let mut inertia = Inertia::zero();
            for b in run["setup"]["bodies"].as_array().unwrap() {
                let local = Inertia::from_com(
                    b["mass"].as_f64().unwrap(),
                    v3(&b["com_in_body"]),
                    m3(&b["inertia_about_com_in_body"]),
                )
                .unwrap();
                inertia += local.transformed(&Se3::from_matrix(&m4(&b["T_tibia_body"])));
            }
            let flex = run["femur_flexion_rad"].as_f64().unwrap();
            let mut model = Model::new(name);
            model
                .add_link(
                    "tibia_r",
                    None,
                    "knee_r",
                    joint.clone(),
                    Se3::from_rotation(
                        Rotation3::from_axis_angle(&Vector3::z_axis(), flex).into_inner(),
                    ),
                    inertia,
                )
                .unwrap();
            let scene = Scene::new(Arc::new(model))
                .with_gravity(Vector3::new(0.0, -9.80665, 0.0))
                .unwrap();
            let init = State {
                q: vec![run["q0"].as_f64().unwrap()],
                v: vec![run["u0"].as_f64().unwrap()],
            };
            // Energy at t = 0 in Simbody's convention (−m g·p_com, femur origin = 0).
            let mut sw = SceneWorkspace::new(&scene);
            let e0 = scene.energy(&mut sw, &init.q, &init.v).unwrap();
            let e0_ref = run["energy_initial_J"]["potential"].as_f64().unwrap();
            assert!(
                (e0 - e0_ref).abs() < 1e-9,
                "{name}: initial energy {e0} vs {e0_ref}"
            );
            let t_ref = series(&run["t"]);
            let q_ref = series(&run["q_accuracy_1e-12"]);
            let u_ref = series(&run["u_accuracy_1e-12"]);
            let dt = t_ref[1] - t_ref[0];
            let dur = t_ref[t_ref.len() - 1];
            let tr = simulate(
                &scene,
                dur,
                dt,
                Integrator::DormandPrince {
                    rtol: 1e-12,
                    atol: 1e-12,
                },
                &init,
                &CancelToken::new(),
                &mut |_| {},
            )
            .unwrap();
            assert_eq!(tr.t.len(), t_ref.len());
            let eq =
                tr.q.iter()
                    .zip(&q_ref)
                    .map(|(q, r)| (q[0] - r).abs())
                    .fold(0.0, f64::max);
            let eu =
                tr.v.iter()
                    .zip(&u_ref)
                    .map(|(v, r)| (v[0] - r).abs())
                    .fold(0.0, f64::max);
            eprintln!(
                "{name}: max |q − q_ref| = {eq:.2e} rad, max |u − u_ref| = {eu:.2e} rad/s ({} steps)",
                tr.steps
            );
            assert!(eq < 1e-6, "{name}: knee angle off by {eq:e} rad");
        }
    }
}

/// The knee spline joint at the ends of its coordinate range (and just past
/// them, where SimmSpline extends linearly): forward dynamics is finite and
/// agrees with M q̈ = τ − nle, and the analytic ∂τ agrees with finite differences.
#[test]
fn knee_dynamics_at_the_range_ends() {
    let Some(dir) = common::shared_dir() else {
        return;
    };
    let path = dir.join("data/opensim/knee_r_gait2392_samples.json");
    let samples: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let joint = Arc::new(FunctionJoint::from_opensim_samples_json(&samples).unwrap());
    let mut model = Model::new("knee");
    let inertia = Inertia::from_com(
        3.7075,
        Vector3::new(0.0, -0.1867, 0.0),
        Matrix3::from_diagonal(&Vector3::new(0.0504, 0.0051, 0.0511)),
    )
    .unwrap();
    model
        .add_link("tibia_r", None, "knee_r", joint, Se3::identity(), inertia)
        .unwrap();
    let g = Vector3::new(0.0, -9.80665, 0.0);
    let mut ws = mx::dynamics::Workspace::new(&model);
    for q in [
        -2.0943951,
        -2.0943951 + 1e-9,
        0.17453293,
        0.17453293 + 1e-3,
        -1.0,
    ] {
        for v in [0.0, 3.0, -7.0] {
            let mut qdd = [0.0];
            mx::dynamics::forward_dynamics(&model, &mut ws, &[q], &[v], &[0.5], &g, &mut qdd)
                .unwrap();
            let mut m = nalgebra::DMatrix::zeros(1, 1);
            mx::dynamics::mass_matrix(&model, &mut ws, &[q], &mut m).unwrap();
            let mut nle = [0.0];
            mx::dynamics::nonlinear_effects(&model, &mut ws, &[q], &[v], &g, &mut nle).unwrap();
            let expect = (0.5 - nle[0]) / m[(0, 0)];
            assert!(
                qdd[0].is_finite() && (qdd[0] - expect).abs() < 1e-10 * expect.abs().max(1.0),
                "q={q} v={v}: {} vs {expect}",
                qdd[0]
            );
            let (mut dq, mut dv) = (
                nalgebra::DMatrix::zeros(1, 1),
                nalgebra::DMatrix::zeros(1, 1),
            );
            mx::dynamics::rnea_derivatives(
                &model,
                &mut ws,
                &mx::dynamics::JointState::new(&[q], &[v], &[1.5]),
                &g,
                &mut dq,
                &mut dv,
            )
            .unwrap();
            let h = 1e-6;
            let tau = |ws: &mut mx::dynamics::Workspace, q: f64, v: f64| {
                let mut t = [0.0];
                mx::dynamics::inverse_dynamics(&model, ws, &[q], &[v], &[1.5], &g, &mut t).unwrap();
                t[0]
            };
            // τ jumps at the ends of the knots (the spline's s'' does) when v ≠ 0:
            // differentiate from inside the range there (one-sided, second order).
            let fdq = if q == -2.0943951 || q == 0.17453293 {
                let s = if q < 0.0 { h } else { -h };
                (-3.0 * tau(&mut ws, q, v) + 4.0 * tau(&mut ws, q + s, v)
                    - tau(&mut ws, q + 2.0 * s, v))
                    / (2.0 * s)
            } else {
                (tau(&mut ws, q + h, v) - tau(&mut ws, q - h, v)) / (2.0 * h)
            };
            let fdv = (tau(&mut ws, q, v + h) - tau(&mut ws, q, v - h)) / (2.0 * h);
            assert!(
                (dv[(0, 0)] - fdv).abs() < 1e-6 * (1.0 + fdv.abs()),
                "q={q}: ∂τ/∂v {} vs {fdv}",
                dv[(0, 0)]
            );
            assert!(
                (dq[(0, 0)] - fdq).abs() < 1e-5 * (1.0 + fdq.abs()),
                "q={q} v={v}: ∂τ/∂q {} vs {fdq}",
                dq[(0, 0)]
            );
        }
    }
}
