//! Spacetime transitions: what accuracy costs in time.
//!
//! 1. A 44-DOF transition of the Fig. 8 kind — the human of
//!    `$MX_SHARED/data/reference/human44.urdf` walking (a calm synthetic
//!    walk-like motion: root forward at 1.2 m/s, joints swinging at ~1 Hz),
//!    a 0.6 s gap on all DOFs but the root — solved for coefficients per DOF
//!    (3, 5, 8, 12, 20) × quadrature samples (10, 20, 40, 80): final energy
//!    (re-measured with a fine 200-point rule, so rows compare the true
//!    integral, not each rule's own estimate), gap to the best energy of the
//!    table, iterations, wall time (best of 3).
//! 2. divan: one objective-and-gradient evaluation against one inverse-dynamics
//!    pass over the same quadrature nodes.
//!
//! Run: `cargo bench --bench spacetime`.

use mx::dynamics::{Workspace, inverse_dynamics};
use mx::model::Model;
use mx::spacetime::objective::Inputs;
use mx::spacetime::{
    BodyDynamics, Continuity, EndState, GapDof, Objective, SolveOptions, SpError,
    TransitionSettings, solve_group,
};
use std::path::PathBuf;
use std::sync::OnceLock;
use std::time::Instant;

fn shared() -> PathBuf {
    std::env::var_os("MX_SHARED")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            PathBuf::from(env!("CARGO_MANIFEST_DIR"))
                .join("..")
                .join("shared")
        })
}

fn model() -> &'static Model {
    static M: OnceLock<Model> = OnceLock::new();
    M.get_or_init(|| {
        Model::from_urdf_file(shared().join("data/reference/human44.urdf"))
            .expect("human44.urdf (set MX_SHARED to the folder holding data/)")
    })
}

fn value(c: usize, t: f64) -> [f64; 3] {
    // [q, q̇, q̈] of the synthetic walk (same as tests/spacetime_motion.rs)
    let s = |amp: f64, w: f64, ph: f64, base: f64| {
        [
            base + amp * (w * t + ph).sin(),
            amp * w * (w * t + ph).cos(),
            -amp * w * w * (w * t + ph).sin(),
        ]
    };
    match c {
        0 => [1.2 * t, 1.2, 0.0],
        1 => s(0.02, 2.0, 0.0, 0.0),
        2 => s(0.02, 12.0, std::f64::consts::FRAC_PI_2, 0.95),
        3..=5 => s(0.05, 3.0, c as f64, 0.0),
        _ => s(0.25, 6.0, 0.7 * c as f64, 0.05 * (1.3 * c as f64).cos()),
    }
}

fn inputs(t: f64, q: &mut [f64], v: &mut [f64], a: &mut [f64]) -> Result<(), SpError> {
    for i in 0..q.len() {
        let s = value(i, t);
        q[i] = s[0];
        v[i] = s[1];
        a[i] = s[2];
    }
    Ok(())
}

const T0: f64 = 1.0;
const T1: f64 = 1.6;

fn gaps() -> Vec<GapDof> {
    (6..44)
        .map(|c| {
            let (s, e) = (value(c, T0), value(c, T1));
            GapDof {
                coord: c,
                t0: T0,
                t1: T1,
                start: EndState {
                    q: s[0],
                    v: s[1],
                    a: s[2],
                },
                end: EndState {
                    q: e[0],
                    v: e[1],
                    a: e[2],
                },
            }
        })
        .collect()
}

fn weights() -> Vec<f64> {
    let mut w = vec![1.0; 44];
    w[..6].fill(0.0);
    w
}

fn objective(coefficients: usize, samples: usize) -> Objective<'static, BodyDynamics<'static>> {
    static BODY: OnceLock<BodyDynamics<'static>> = OnceLock::new();
    let body = BODY.get_or_init(|| BodyDynamics::new(model()));
    let settings = TransitionSettings {
        coefficients,
        samples,
        continuity: Continuity::C1,
    };
    let inputs: &Inputs = &inputs;
    Objective::new(body, gaps(), &settings, weights(), inputs).expect("objective")
}

fn table() {
    let coefs = [3, 5, 8, 12, 20];
    let samples = [10, 20, 40, 80];
    let default = TransitionSettings::default();
    let mut rows = vec![];
    for &n in &coefs {
        for &k in &samples {
            let obj = objective(n, k);
            let mut best_t = f64::INFINITY;
            let mut sol = None;
            for _ in 0..3 {
                let t = Instant::now();
                let s = solve_group(&obj, &SolveOptions::default()).expect("solve");
                best_t = best_t.min(t.elapsed().as_secs_f64());
                sol = Some(s);
            }
            let sol = sol.expect("ran");
            // the true integral of the solution: the same curves under a 200-point rule
            let fine = objective(n, 200);
            let e_true = fine.eval(&mut fine.scratch(), &sol.x, None).expect("eval");
            rows.push((
                n,
                k,
                obj.n_nodes(),
                e_true,
                sol.report.iterations,
                sol.report.stop.clone(),
                best_t,
            ));
        }
    }
    let best = rows.iter().map(|r| r.3).fold(f64::INFINITY, f64::min);
    println!(
        "44-DOF human, 0.6 s gap, 38 DOFs (all but the root), ∫Στ² dt; energy re-measured with 200 Gauss points"
    );
    println!(
        "{:>6} {:>7} {:>6} {:>14} {:>10} {:>6} {:>10}  stop",
        "coefs", "samples", "nodes", "energy", "gap", "iters", "time ms"
    );
    for (n, k, nodes, e, it, stop, t) in &rows {
        let mark = if *n == default.coefficients && *k == default.samples {
            " ← default"
        } else {
            ""
        };
        println!(
            "{n:>6} {k:>7} {nodes:>6} {e:>14.6} {:>9.3}% {it:>6} {:>10.1}  {stop}{mark}",
            100.0 * (e - best) / best,
            t * 1e3
        );
    }
}

fn main() {
    table();
    divan::main();
}

/// One objective-and-gradient evaluation (adjoint through every node) at default settings.
#[divan::bench]
fn objective_and_gradient(bencher: divan::Bencher) {
    let obj = objective(
        TransitionSettings::default().coefficients,
        TransitionSettings::default().samples,
    );
    let x = obj.hermite_start();
    let mut s = obj.scratch();
    let mut g = vec![0.0; x.len()];
    bencher.bench_local(|| {
        obj.eval(&mut s, divan::black_box(&x), Some(&mut g))
            .expect("eval")
    });
}

/// One inverse-dynamics pass over the same nodes (the floor of the above).
#[divan::bench]
fn inverse_dynamics_over_the_nodes(bencher: divan::Bencher) {
    let obj = objective(
        TransitionSettings::default().coefficients,
        TransitionSettings::default().samples,
    );
    let nodes = obj.n_nodes();
    let m = model();
    let mut ws = Workspace::new(m);
    let states: Vec<[Vec<f64>; 3]> = (0..nodes)
        .map(|k| {
            let t = T0 + (T1 - T0) * (k as f64 + 0.5) / nodes as f64;
            let (mut q, mut v, mut a) = (vec![0.0; 44], vec![0.0; 44], vec![0.0; 44]);
            inputs(t, &mut q, &mut v, &mut a).expect("inputs");
            [q, v, a]
        })
        .collect();
    let mut tau = vec![0.0; 44];
    let g = m.default_gravity;
    bencher.bench_local(|| {
        for [q, v, a] in &states {
            inverse_dynamics(m, &mut ws, q, v, a, &g, &mut tau).expect("rnea");
        }
    });
}

/// The preconditioner (built once per solve).
#[divan::bench]
fn preconditioner(bencher: divan::Bencher) {
    let obj = objective(
        TransitionSettings::default().coefficients,
        TransitionSettings::default().samples,
    );
    let mut s = obj.scratch();
    bencher.bench_local(|| obj.preconditioner(&mut s).expect("precond"));
}
