//! The OpenSim knee as an exact function-based joint: every `*_samples.json`
//! in data/opensim must be reproduced (transform and q-derivative) to 1e-9,
//! whether the joint is built from the JSON or from the `.osim` XML.
// Index loops mirror the equations (several arrays per index); iterators would obscure them.
#![allow(clippy::needless_range_loop)]

use crate::common;

use mx::model::joint::{Derivatives, Joint, JointKinematics};
use mx::model::joints::FunctionJoint;
use nalgebra::Vector3;
use serde_json::Value;

fn mat4(v: &Value) -> [[f64; 4]; 4] {
    let mut m = [[0.0; 4]; 4];
    for i in 0..4 {
        for j in 0..4 {
            m[i][j] = v[i][j].as_f64().expect("number");
        }
    }
    m
}

fn v3(v: &Value) -> Vector3<f64> {
    Vector3::new(
        v[0].as_f64().unwrap(),
        v[1].as_f64().unwrap(),
        v[2].as_f64().unwrap(),
    )
}

/// Max errors (transform, ω, v) of `joint` over the samples.
fn compare(joint: &FunctionJoint, doc: &Value) -> (f64, f64, f64) {
    let mut k = JointKinematics::default();
    let (mut et, mut ew, mut ev) = (0.0f64, 0.0f64, 0.0f64);
    for s in doc["samples"].as_array().expect("samples") {
        let q = [s["q"].as_f64().unwrap()];
        joint.kinematics(&q, Derivatives::Jacobian, &mut k);
        let m = k.transform.to_matrix();
        let r = mat4(&s["T_parent_child"]);
        for i in 0..4 {
            for j in 0..4 {
                et = et.max((m[(i, j)] - r[i][j]).abs());
            }
        }
        let s0 = k.s[0];
        let w = k.transform.r * Vector3::new(s0[0], s0[1], s0[2]);
        let v = k.transform.r * Vector3::new(s0[3], s0[4], s0[5]);
        ew = ew.max((w - v3(&s["dq_omega_parent"])).norm());
        ev = ev.max((v - v3(&s["dq_v_parent"])).norm());
        if let Some(vals) = s.get("transform_axis_values").and_then(Value::as_array) {
            let ours = joint.axis_values(&q);
            for (a, b) in ours.iter().zip(vals) {
                et = et.max((a - b.as_f64().unwrap()).abs());
            }
        }
    }
    (et, ew, ev)
}

#[test]
fn function_joint_reproduces_opensim_samples_to_1e_9() {
    for path in common::shared_files("opensim", "_samples.json") {
        let doc: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        let joint =
            FunctionJoint::from_opensim_samples_json(&doc["joint"]).expect("joint from JSON");
        let (et, ew, ev) = compare(&joint, &doc);
        println!(
            "{}: from JSON: max |ΔT| {et:.2e}, |Δω| {ew:.2e}, |Δv| {ev:.2e}",
            path.display()
        );
        assert!(et <= 1e-9 && ew <= 1e-9 && ev <= 1e-9);
        // the whole document is accepted too
        assert!(FunctionJoint::from_opensim_samples_json(&doc).is_ok());

        // … and from the model XML by joint name, when the file names its model.
        if let Some(model) = doc.get("model_file").and_then(Value::as_str) {
            let osim = path.parent().unwrap().join(model);
            if osim.is_file() {
                let name = doc["joint"]["name"].as_str().unwrap();
                let jx = FunctionJoint::from_osim_file(&osim, name).expect("joint from .osim");
                let (et, ew, ev) = compare(&jx, &doc);
                println!(
                    "{}: from .osim: max |ΔT| {et:.2e}, |Δω| {ew:.2e}, |Δv| {ev:.2e}",
                    path.display()
                );
                assert!(et <= 1e-9 && ew <= 1e-9 && ev <= 1e-9);
                assert_eq!(jx.limits(), joint.limits());
            }
        }
    }
}

#[test]
fn pendulum_joint_object_gets_a_clear_error_and_the_osim_fallback_works() {
    for path in common::shared_files("opensim", "_pendulum.json") {
        let doc: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        let e = FunctionJoint::from_opensim_samples_json(&doc["joint"]).unwrap_err();
        assert!(e.to_string().contains("samples"), "{e}");
        let osim = path
            .parent()
            .unwrap()
            .join(doc["model_file"].as_str().unwrap());
        let j =
            FunctionJoint::from_osim_file(osim, doc["joint"]["name"].as_str().unwrap()).unwrap();
        assert_eq!(j.dof(), 1);
    }
}

#[test]
fn function_joint_hessian_matches_finite_differences() {
    for path in common::shared_files("opensim", "_samples.json") {
        let doc: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        let joint = FunctionJoint::from_opensim_samples_json(&doc["joint"]).unwrap();
        let lim = joint.limits()[0];
        let h = 1e-6;
        let (mut k0, mut kp, mut km) = (
            JointKinematics::default(),
            JointKinematics::default(),
            JointKinematics::default(),
        );
        let mut worst = 0.0f64;
        for i in 0..=50 {
            let q = lim.lower + (lim.upper - lim.lower) * i as f64 / 50.0;
            joint.kinematics(&[q], Derivatives::Hessian, &mut k0);
            // Past the ends of a function's knot range the joint continues C¹
            // only, so at the ends difference on the inside: second-order
            // one-sided differences (−3f(q) + 4f(q ± h) − f(q ± 2h)) / (±2h);
            // central differences inside.
            let side = match i {
                0 => 1.0,
                50 => -1.0,
                _ => 0.0,
            };
            let at = |dq: f64, k: &mut JointKinematics| {
                joint.kinematics(&[q + dq], Derivatives::Jacobian, k);
                (k.transform.to_matrix(), k.s[0])
            };
            let (dg, ds_fd) = if side == 0.0 {
                let (gp, sp) = at(h, &mut kp);
                let (gm, sm) = at(-h, &mut km);
                ((gp - gm) / (2.0 * h), (sp - sm) / (2.0 * h))
            } else {
                let (g1, s1) = at(side * h, &mut kp);
                let (g2, s2) = at(side * 2.0 * h, &mut km);
                let g0 = k0.transform.to_matrix();
                let s0 = k0.s[0];
                (
                    (g1 * 4.0 - g0 * 3.0 - g2) / (side * 2.0 * h),
                    (s1 * 4.0 - s0 * 3.0 - s2) / (side * 2.0 * h),
                )
            };
            // S = (G⁻¹ dG/dq)^∨ by differences of G
            let x = k0.transform.to_matrix().try_inverse().unwrap() * dg;
            let s_fd = [
                x[(2, 1)],
                x[(0, 2)],
                x[(1, 0)],
                x[(0, 3)],
                x[(1, 3)],
                x[(2, 3)],
            ];
            for c in 0..6 {
                worst = worst.max((s_fd[c] - k0.s[0][c]).abs() / (1.0 + k0.s[0].norm()));
            }
            // SimmSpline knots are C² only: differences across a knot are fine at this step.
            worst = worst.max((ds_fd - k0.ds[0][0]).norm() / (1.0 + k0.ds[0][0].norm()));
        }
        println!(
            "{}: worst Jacobian/Hessian FD relative error {worst:.2e}",
            path.display()
        );
        assert!(worst < 1e-7);
    }
}
