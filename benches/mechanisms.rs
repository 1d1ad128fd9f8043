//! Mechanisms benchmark: prints a table of the time per simulation step of
//! the spline-joint mechanisms of `examples/mech_*.mx`, beside the paper's
//! (Lee & Terzopoulos 2008, 2.6 GHz Core 2, "unoptimized": 6 ms per step for
//! the 1-DOF knee, 49 ms for the 8-DOF letter chain), and what a driven
//! coordinate costs (the beads' spinning frame). The cost of the other scene
//! effects (gravity, damping, springs, forces, limits) is measured on a
//! 20-link chain by `benches/dynamics.rs`; it is not repeated here.
//!
//! Each scene is the one its example builds (the script runs once), timed at
//! a state of its own simulation (t = 1 s).
//!
//! Run: `cargo bench --bench mechanisms`.

use mx::Interpreter;
use mx::dynamics::{Scene, SceneWorkspace};
use mx::lang::builtins::dynamics::SceneValue;
use mx::lang::value::Value;
use std::hint::black_box;
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
    for (file, paper) in cases {
        match example(file) {
            Ok((scene, q, v)) => {
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
