//! Spacetime transitions: what accuracy costs in time.
//!
//! 1. The Fig. 8 case (`mx::spacetime::fig8`): a 0.6 s gap on all 38 joint
//!    DOFs of a 44-DOF human (the root is an input), on two bodies and motions —
//!    `$MX_SHARED/data/reference/human44.urdf` driven by a calm synthetic
//!    walk-like motion (root forward at 1.2 m/s, joints swinging at ~1 Hz),
//!    and the project's own `human(walk)` with the procedural walk fitted to it.
//!    For coefficients per DOF (3, 5, 8, 12, 20) × quadrature samples
//!    (10, 20, 40, 80): final energy (re-measured with a fine 200-point rule,
//!    so rows compare the true integral, not each rule's own estimate), gap to
//!    the best energy of the table, iterations, wall time (best of 3, set-up
//!    of the objective included), the default marked.
//! 2. divan: one objective-and-gradient evaluation against one inverse-dynamics
//!    pass over the same quadrature nodes, and the preconditioner.
//!
//! Run: `cargo bench --bench spacetime`.

use mx::dynamics::{Workspace, inverse_dynamics};
use mx::model::Model;
use mx::motion::{Curve, Dof, Interval, Mu};
use mx::spacetime::fig8::{self, Case};
use mx::spacetime::{SolveOptions, TransitionSettings, solve_group};
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

const T0: f64 = 1.0;
const T1: f64 = 1.6;
const RATE: f64 = 240.0;

/// The synthetic walk as a motion: every coordinate sampled at 240 Hz on [0, 2.6] s.
fn calm_walk(model: &Model) -> Mu {
    let mut m = Mu::new();
    let n = (2.6 * RATE) as usize;
    for (c, name) in model.coordinate_names().iter().enumerate() {
        let vals = (0..=n).map(|k| value(c, k as f64 / RATE)[0]).collect();
        let iv = Interval::curve(
            Curve::samples(0.0, 1.0 / RATE, vals).expect("samples"),
            0.0,
            2.6,
        )
        .expect("interval");
        m.insert(name.clone(), Dof::from(iv));
    }
    m
}

fn human44_case() -> &'static Case<'static> {
    static C: OnceLock<Case<'static>> = OnceLock::new();
    C.get_or_init(|| fig8::case(model(), calm_walk(model()), T0, T1).expect("case"))
}

fn example_case() -> &'static Case<'static> {
    static M: OnceLock<Model> = OnceLock::new();
    static C: OnceLock<Case<'static>> = OnceLock::new();
    C.get_or_init(|| {
        let (model, mu) = fig8::example_walk().expect("example walk");
        let model = M.get_or_init(|| model);
        let (t0, t1) = fig8::EXAMPLE_GAP;
        fig8::case(model, mu, t0, t1).expect("case")
    })
}

fn settings(coefficients: usize, samples: usize) -> TransitionSettings {
    TransitionSettings {
        coefficients,
        samples,
        ..Default::default()
    }
}

fn table(title: &str, case: &Case) {
    let coefs = [3, 5, 8, 12, 20];
    let samples = [10, 20, 40, 80];
    let default = TransitionSettings::default();
    let mut rows = vec![];
    for &n in &coefs {
        for &k in &samples {
            let mut best_t = f64::INFINITY;
            let mut sol = None;
            let mut nodes = 0;
            for _ in 0..3 {
                let t = Instant::now();
                let obj = case.objective(&settings(n, k)).expect("objective");
                let s = solve_group(&obj, &SolveOptions::default()).expect("solve");
                best_t = best_t.min(t.elapsed().as_secs_f64());
                nodes = obj.n_nodes();
                sol = Some(s);
            }
            let sol = sol.expect("ran");
            // the true integral of the solution: the same curves under a 200-point rule
            let fine = case.objective(&settings(n, 200)).expect("objective");
            let e_true = fine.eval(&mut fine.scratch(), &sol.x, None).expect("eval");
            rows.push((
                n,
                k,
                nodes,
                e_true,
                sol.report.iterations,
                sol.report.stop.clone(),
                best_t,
            ));
        }
    }
    let best = rows.iter().map(|r| r.3).fold(f64::INFINITY, f64::min);
    println!(
        "{title}: {} joint DOFs, ∫Στ² dt re-measured with 200 Gauss points",
        case.gaps.len()
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
    println!();
}

/// The solver's own knobs at the default transition settings: L-BFGS memory
/// and restarts from a re-linearised preconditioner → energy against time.
fn solver_table(title: &str, case: &Case) {
    let obj = case
        .objective(&TransitionSettings::default())
        .expect("objective");
    let fine = case
        .objective(&settings(TransitionSettings::default().coefficients, 200))
        .expect("objective");
    println!(
        "{title}: solver knobs at the default settings (energy re-measured with 200 Gauss points)"
    );
    println!(
        "{:>7} {:>10} {:>14} {:>6} {:>10}  stop",
        "memory", "relinearise", "energy", "iters", "time ms"
    );
    for (memory, every) in [(10, u64::MAX), (30, u64::MAX), (30, 50), (30, 15)] {
        let opts = SolveOptions {
            lbfgs_memory: memory,
            relinearise_every: every,
            ..Default::default()
        };
        let t = Instant::now();
        let sol = solve_group(&obj, &opts).expect("solve");
        let ms = t.elapsed().as_secs_f64() * 1e3;
        let e = fine.eval(&mut fine.scratch(), &sol.x, None).expect("eval");
        let every = if every == u64::MAX {
            "never".to_string()
        } else {
            every.to_string()
        };
        let mark = if memory == SolveOptions::default().lbfgs_memory
            && SolveOptions::default().relinearise_every == u64::MAX
            && every == "never"
        {
            " ← default"
        } else {
            ""
        };
        println!(
            "{memory:>7} {every:>10} {e:>14.6} {:>6} {ms:>10.1}  {}{mark}",
            sol.report.iterations, sol.report.stop
        );
    }
    println!();
}

fn main() {
    solver_table("Fig. 8 case on human(walk)", example_case());
    table(
        "Fig. 8 case on human44.urdf, calm synthetic walk, gap [1.0, 1.6] s",
        human44_case(),
    );
    table(
        "Fig. 8 case on human(walk) with the project's procedural walk, gap [0.6, 1.2] s",
        example_case(),
    );
    divan::main();
}

/// One objective-and-gradient evaluation (adjoint through every node) at default settings.
#[divan::bench]
fn objective_and_gradient(bencher: divan::Bencher) {
    let obj = human44_case()
        .objective(&TransitionSettings::default())
        .expect("objective");
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
    let case = human44_case();
    let obj = case
        .objective(&TransitionSettings::default())
        .expect("objective");
    let nodes = obj.n_nodes();
    let m = model();
    let mut ws = Workspace::new(m);
    let states: Vec<[Vec<f64>; 3]> = (0..nodes)
        .map(|k| {
            let t = T0 + (T1 - T0) * (k as f64 + 0.5) / nodes as f64;
            let (mut q, mut v, mut a) = (vec![0.0; 44], vec![0.0; 44], vec![0.0; 44]);
            case.inputs(t, &mut q, &mut v, &mut a).expect("inputs");
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
    let obj = human44_case()
        .objective(&TransitionSettings::default())
        .expect("objective");
    let mut s = obj.scratch();
    bencher.bench_local(|| obj.preconditioner(&mut s).expect("precond"));
}
