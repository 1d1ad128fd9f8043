//! Mechanisms benchmark: prints a table of the time per simulation step of
//! the spline-joint mechanisms of `examples/mech_*.mx`, beside the paper's
//! (Lee & Terzopoulos 2008, 2.6 GHz Core 2, "unoptimized": 6 ms per step for
//! the 1-DOF knee, 49 ms for the 8-DOF letter chain), and what a driven
//! coordinate costs (the beads' spinning frame), and what the analytic third
//! derivative of the spline joints saves in ∂τ (RNEA derivatives) and the
//! adjoint gradient against differencing their Hessian. The cost of the other scene
//! effects (gravity, damping, springs, forces, limits) is measured on a
//! 20-link chain by `benches/dynamics.rs`; it is not repeated here.
//!
//! Each scene is the one its example builds (the script runs once), timed at
//! a state of its own simulation (t = 1 s).
//!
//! Run: `cargo bench --bench mechanisms`.

use mx::Interpreter;
use mx::dynamics::{
    JointState, Scene, SceneWorkspace, StateGradient, Workspace, rnea_derivatives,
    torque_sq_gradient,
};
use mx::lang::builtins::dynamics::SceneValue;
use mx::lang::value::Value;
use mx::lie::Twist;
use mx::model::Model;
use mx::model::joint::{Derivatives, Joint, JointKinematics, Limit, MAX_JOINT_DOF};
use nalgebra::{DMatrix, Vector3};
use std::hint::black_box;
use std::sync::Arc;
use std::time::Instant;

/// The scene `sc` of an example and its simulated state at t = 1 s.
fn example(file: &str) -> Result<(Scene, Vec<f64>, Vec<f64>), String> {
    let mut mx = Interpreter::new();
    let _quiet = mx.capture_output();
    mx.eval_file(format!("examples/{file}"))
        .map_err(|e| format!("{e:?}"))?;
    let scene = match mx.get("sc") {
        Some(v) => v
            .as_object::<SceneValue>()
            .ok_or("`sc` is not a scene")?
            .scene
            .clone(),
        None => return Err("the example defines no `sc`".into()),
    };
    let list = |src: &str, mx: &mut Interpreter| -> Result<Vec<f64>, String> {
        match mx.eval_str(src).map_err(|e| format!("{e:?}"))? {
            Value::List(l) => Ok(l.iter().filter_map(Value::as_number).collect()),
            other => Err(format!("not a list: {other:?}")),
        }
    };
    mx.eval_str("let __r = sample(sim, 1)")
        .map_err(|e| format!("{e:?}"))?;
    let q = list("map(coordinates(sc), fn(n) = __r[n])", &mut mx)?;
    let v = list("map(coordinates(sc), fn(n) = __r[n + \".v\"])", &mut mx)?;
    Ok((scene, q, v))
}

/// Median µs of one q̈ evaluation (best of 5 rounds of `n` calls).
fn per_call(scene: &Scene, q: &[f64], v: &[f64]) -> f64 {
    let mut sw = SceneWorkspace::new(scene);
    let mut qdd = vec![0.0; q.len()];
    let mut rounds = Vec::new();
    for _ in 0..5 {
        let n = 2000;
        let t = Instant::now();
        for _ in 0..n {
            scene
                .accelerations(&mut sw, black_box(q), black_box(v), &[], &mut qdd)
                .unwrap();
            black_box(&qdd);
        }
        rounds.push(t.elapsed().as_secs_f64() * 1e6 / n as f64);
    }
    rounds.sort_by(f64::total_cmp);
    rounds[0]
}

/// A joint that hides its analytic `∂(Ṡ q̇)/∂q`, so the dynamics falls back
/// to differencing its Hessian (what every spline joint did before).
#[derive(Debug)]
struct HessianOnly(Arc<dyn Joint>);

impl Joint for HessianOnly {
    fn kind(&self) -> &'static str {
        self.0.kind()
    }
    fn dof(&self) -> usize {
        self.0.dof()
    }
    fn kinematics(&self, q: &[f64], want: Derivatives, out: &mut JointKinematics) {
        self.0.kinematics(q, want, out)
    }
    fn limits(&self) -> Vec<Limit> {
        self.0.limits()
    }
    fn constant_jacobian(&self) -> bool {
        self.0.constant_jacobian()
    }
    fn sdot_v_dq(&self, _q: &[f64], _v: &[f64], _out: &mut [Twist; MAX_JOINT_DOF]) -> bool {
        false
    }
}

/// The same model with every joint wrapped in [`HessianOnly`].
fn hessian_only(model: &Model) -> Model {
    let mut m = Model::new(&model.name);
    for l in model.links() {
        let joint: Arc<dyn Joint> = Arc::new(HessianOnly(l.joint.clone()));
        m.add_link(&l.name, l.parent, &l.joint_name, joint, l.offset, l.inertia)
            .expect("a copy of a valid model");
    }
    m
}

/// Median-of-rounds µs of `rnea_derivatives` and of the adjoint gradient.
fn derivative_costs(model: &Model, q: &[f64], v: &[f64], g: &Vector3<f64>) -> (f64, f64) {
    let n = q.len();
    let mut ws = Workspace::new(model);
    let a = vec![0.3; n];
    let w = vec![1.0; n];
    let (mut dq, mut dv) = (DMatrix::zeros(n, n), DMatrix::zeros(n, n));
    let (mut gq, mut gv, mut ga) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let best = |f: &mut dyn FnMut()| {
        let mut rounds = Vec::new();
        for _ in 0..5 {
            let t = Instant::now();
            for _ in 0..500 {
                f();
            }
            rounds.push(t.elapsed().as_secs_f64() * 1e6 / 500.0);
        }
        rounds.sort_by(f64::total_cmp);
        rounds[0]
    };
    let der = best(&mut || {
        rnea_derivatives(
            model,
            &mut ws,
            &JointState::new(q, v, &a),
            g,
            &mut dq,
            &mut dv,
        )
        .unwrap();
        black_box(&dq);
    });
    let mut ws = Workspace::new(model);
    let adj = best(&mut || {
        torque_sq_gradient(
            model,
            &mut ws,
            &JointState::new(q, v, &a),
            g,
            &w,
            StateGradient {
                q: &mut gq,
                v: &mut gv,
                a: &mut ga,
            },
        )
        .unwrap();
        black_box(&gq);
    });
    (der, adj)
}

fn main() {
    if std::env::args().any(|a| a == "--test") || std::env::var_os("MX_BENCH_SKIP").is_some() {
        println!("mechanisms bench: run with `cargo bench --bench mechanisms` for the tables");
        return;
    }
    std::env::set_current_dir(env!("CARGO_MANIFEST_DIR")).unwrap();
    println!("Time per simulation step of the spline-joint mechanisms (µs; best of 5 rounds)");
    println!("explicit Euler = 1 q̈ evaluation per step, RK4 = 4");
    println!(
        "{:<26}{:>5}{:>14}{:>12}{:>16}",
        "example", "dof", "Euler step", "RK4 step", "paper (Euler)"
    );
    let cases = [
        ("mech_knee_pendulum.mx", Some(6000.0)),
        ("mech_letters.mx", Some(49000.0)),
        ("mech_elliptic.mx", None),
        ("mech_beads.mx", None),
        ("mech_globe.mx", None),
        ("mech_scapula.mx", None),
        ("mech_deforming.mx", None),
    ];
    let mut beads = None;
    let mut derivs = Vec::new();
    for (file, paper) in cases {
        match example(file) {
            Ok((scene, q, v)) => {
                derivs.push((file, scene.clone(), q.clone(), v.clone()));
                let t = per_call(&scene, &q, &v);
                let p = paper.map_or("-".to_string(), |p: f64| format!("{p:.0}"));
                println!("{file:<26}{:>5}{t:>14.2}{:>12.2}{p:>16}", q.len(), 4.0 * t);
                if file == "mech_beads.mx" {
                    beads = Some((scene, q, v));
                }
            }
            Err(e) => println!("{file:<26} failed: {e}"),
        }
    }
    println!(
        "\n∂τ/∂q, ∂τ/∂q̇ (RNEA derivatives) and the adjoint Σwτ² gradient, µs per call (best of 5):"
    );
    println!("analytic ∂(Ṡq̇)/∂q of the spline joints vs differences of their Hessian");
    println!(
        "{:<26}{:>12}{:>12}{:>8}{:>12}{:>12}{:>8}",
        "example", "∂τ", "∂τ (diff)", "ratio", "adjoint", "adj (diff)", "ratio"
    );
    for (file, scene, q, v) in derivs {
        let g = scene.gravity.unwrap_or_else(Vector3::zeros);
        let (der, adj) = derivative_costs(&scene.model, &q, &v, &g);
        let (der_fd, adj_fd) = derivative_costs(&hessian_only(&scene.model), &q, &v, &g);
        println!(
            "{file:<26}{der:>12.2}{der_fd:>12.2}{:>8.2}{adj:>12.2}{adj_fd:>12.2}{:>8.2}",
            der / der_fd,
            adj / adj_fd
        );
    }
    if let Some((scene, q, v)) = beads {
        let mut free = scene.clone();
        free.driven.clear();
        let (with, without) = (per_call(&scene, &q, &v), per_call(&free, &q, &v));
        println!("\nA driven coordinate (the beads' spinning frame), µs per q̈:");
        println!("{:<26}{:>10.2}", "wire free (ABA, O(n))", without);
        println!(
            "{:<26}{:>10.2}   ({:.2}×: mass matrix + Cholesky of the free block)",
            "wire driven",
            with,
            with / without
        );
    }
}
