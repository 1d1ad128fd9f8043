//! Dynamics benchmark: prints tables.
//!
//! 1. Per call on every URDF of `$MX_SHARED/data/reference` (human44, Panda,
//!    UR5), on the URDFs `MX_BENCH_URDFS` names (colon-separated: models the
//!    project never tuned on) and on generated trees (`mx::report::trees`:
//!    chains, humanoid-like and random trees of 6–60 coordinates with mixed
//!    joints, written as URDF to a temporary folder): RNEA, ABA, CRBA, ∂τ (RNEA
//!    derivatives) and the adjoint gradient of Σwτ², median µs over random
//!    states, and the mass matrix by each of its two passes (world and link
//!    frames) with the one the workspace picks; when Pinocchio's timer is built
//!    (`$MX_SHARED/tools/pinocchio/build.sh /tmp/pinocchio-bench`, or
//!    `$MX_PINOCCHIO_BENCH`), it is run on the same URDF in the same session,
//!    alternated with ours `MX_BENCH_RUNS` times (default 5), and the median
//!    ratios are printed (the table says so when it is absent); beside them
//!    mx's instructions per call under callgrind (when valgrind is installed),
//!    which show whether a change saved work on this noisy shared machine (but
//!    not a stall: #37's CRBA doubled its time at ±10 % instructions). A summary
//!    closes the table: per model the ratios with instructions in brackets,
//!    their mean, and whether the goals (each ≤ 1, CRBA ≤ 0.8, mean ≤ 0.6) hold.
//! 2. The cost of each scene effect (same scene with and without it).
//! 3. Integrator work–precision: error at t = 1 s against a tight reference vs time.
//!
//! Run: `cargo bench --bench dynamics` (`-- per_call` prints table 1 only).

mod common;
use common::shared;

use mx::cancel::CancelToken;
use mx::dynamics::{
    ExternalForce, Integrator, LimitPenalty, Scene, SceneWorkspace, Spring, State, simulate,
};
use mx::lie::Se3;
use mx::model::joints::Revolute;
use mx::model::{Inertia, Model};
use nalgebra::{Matrix3, Vector3};
use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

struct Rng(u64);
impl Rng {
    fn f(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
    }
}

use mx::report::perf::{ALGORITHMS, TIMED, median_us};

/// Runs of mx's timing and Pinocchio's timer, alternated, per model: ratios are
/// quoted as the median over the runs (`MX_BENCH_RUNS`, default 5).
fn runs() -> usize {
    std::env::var("MX_BENCH_RUNS")
        .ok()
        .and_then(|x| x.parse().ok())
        .filter(|n| *n > 0)
        .unwrap_or(5)
}

fn median(mut x: Vec<f64>) -> f64 {
    x.sort_by(|a, b| a.total_cmp(b));
    let n = x.len();
    if n % 2 == 1 {
        x[n / 2]
    } else {
        0.5 * (x[n / 2 - 1] + x[n / 2])
    }
}

/// Instructions per call of `algorithm` on `urdf`, counted by callgrind: this
/// binary runs [`mx::report::perf::drive`] for 20 and for 220 calls, and the
/// difference of the two totals over 200 leaves out loading and set-up. Exact
/// and repeatable where times on this shared machine are not; `None` without valgrind.
fn instructions_per_call(urdf: &Path, algorithm: &str) -> Option<f64> {
    let exe = std::env::current_exe().ok()?;
    let count = |n: usize| -> Option<f64> {
        let out = std::env::temp_dir().join(format!(
            "mx-dynamics-callgrind-{}-{algorithm}-{n}.out",
            std::process::id()
        ));
        let status = std::process::Command::new("valgrind")
            .arg("--tool=callgrind")
            .arg(format!("--callgrind-out-file={}", out.display()))
            .arg(&exe)
            .arg("instructions-driver")
            .arg(urdf)
            .arg(algorithm)
            .arg(n.to_string())
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .status()
            .ok()?;
        let text = std::fs::read_to_string(&out).ok();
        let _ = std::fs::remove_file(&out);
        if !status.success() {
            return None;
        }
        text?
            .lines()
            .find_map(|l| l.strip_prefix("summary:").or(l.strip_prefix("totals:")))
            .and_then(|x| x.trim().parse::<f64>().ok())
    };
    let (a, b) = (20, 220);
    Some((count(b)? - count(a)?) / (b - a) as f64)
}

/// The `instructions-driver URDF ALGORITHM N` mode of this binary, run under callgrind.
fn instructions_driver(args: &[String]) {
    let [urdf, algorithm, n] = args else {
        eprintln!("usage: instructions-driver URDF ALGORITHM N");
        std::process::exit(2);
    };
    // (a message is all this binary prints)
    let result = Model::from_urdf_file(Path::new(urdf))
        .map_err(|e| e.to_string())
        .and_then(|m| {
            let n = n
                .parse()
                .map_err(|_| format!("N must be a count, got `{n}`"))?;
            mx::report::perf::drive(&m, algorithm, n).map_err(|e| e.to_string())
        });
    if let Err(e) = result {
        eprintln!("{e}");
        std::process::exit(1);
    }
}

/// What one model's table found: the median ratios mx / Pinocchio of
/// [`ALGORITHMS`] (empty without Pinocchio's timer), mx's instructions per call
/// of the [`TIMED`] algorithms, and the two CRBA passes' times.
struct Found {
    name: String,
    nq: usize,
    ratios: Vec<f64>,
    instructions: Vec<Option<f64>>,
    /// the median of the runs' world/link time ratios, and of the picked
    /// pass's time over the faster pass's
    passes: (f64, f64),
    /// the pass the workspace picks
    picks: &'static str,
}

/// One model's table: mx's time, Pinocchio's (its C++ timer, same URDF, same
/// session, alternated with ours `runs()` times), the ratio and mx's
/// instructions per call; then the mass matrix by each of mx's two passes.
/// Times are medians over the runs of each run's median per call (ours: 2000
/// states; Pinocchio's: the best of its 5 rounds of 10000), ratios the median
/// of the runs' ratios with their range.
fn per_call(name: &str, urdf: &Path) -> Option<Found> {
    let model = match Model::from_urdf_file(urdf) {
        Ok(m) => m,
        Err(e) => {
            println!("{name}: cannot load ({e})");
            return None;
        }
    };
    const N: usize = 2000;
    let runs = runs();
    let all: Vec<usize> = (0..TIMED.len()).collect();
    let mut ours: Vec<Vec<f64>> = Vec::new();
    let mut theirs: Vec<[f64; 4]> = Vec::new();
    for _ in 0..runs {
        match mx::report::perf::per_call_of(&model, N, &all) {
            Ok(t) => ours.push(t),
            Err(e) => {
                println!("{name}: {e}");
                return None;
            }
        }
        if let Some(p) = mx::report::perf::pinocchio(urdf) {
            theirs.push(p);
        }
    }
    let instructions: Vec<Option<f64>> = TIMED
        .iter()
        .map(|a| instructions_per_call(urdf, a))
        .collect();
    let kilo = |x: Option<f64>| x.map_or("-".to_string(), |x| format!("{:.1}k", x / 1e3));
    println!(
        "\n{name} (nq = {}): median over {runs} alternated runs of the median µs per call",
        model.nq()
    );
    println!(
        "{:<24}{:>10}{:>14}{:>8}{:>14}{:>15}",
        "algorithm", "mx µs", "pinocchio µs", "ratio", "ratio range", "mx instr/call"
    );
    let pin = !theirs.is_empty() && theirs.len() == ours.len();
    let mut ratios = Vec::new();
    for (k, alg) in ALGORITHMS.iter().enumerate() {
        let t = median(ours.iter().map(|r| r[k]).collect());
        let ins = kilo(instructions[k]);
        if pin {
            let p = median(theirs.iter().map(|r| r[k]).collect());
            let each: Vec<f64> = ours.iter().zip(&theirs).map(|(a, b)| a[k] / b[k]).collect();
            let (lo, hi) = each
                .iter()
                .fold((f64::INFINITY, 0.0f64), |(l, h), x| (l.min(*x), h.max(*x)));
            let r = median(each);
            ratios.push(r);
            println!(
                "{alg:<24}{t:>10.3}{p:>14.3}{r:>8.2}{:>14}{ins:>15}",
                format!("{lo:.2}–{hi:.2}")
            );
        } else {
            println!(
                "{alg:<24}{t:>10.3}{:>14}{:>8}{:>14}{ins:>15}",
                "-", "-", "-"
            );
        }
    }
    let med = |k: usize| median(ours.iter().map(|r| r[k]).collect());
    let (adj, rnea) = (med(4), med(0));
    println!(
        "{:<24}{adj:>10.3}   ({:.2}× one RNEA){:>29}",
        "adjoint Σwτ² gradient",
        adj / rnea,
        kilo(instructions[4])
    );
    let picks = match mx::dynamics::crba_frame_for(&model) {
        mx::dynamics::CrbaFrame::Link => "link",
        mx::dynamics::CrbaFrame::World => "world",
    };
    let world_over_link = median(ours.iter().map(|r| r[5] / r[6]).collect());
    for (k, pass) in [(5, "crba, world-frame pass"), (6, "crba, link-frame pass")] {
        println!("{pass:<24}{:>10.3}{:>36}", med(k), kilo(instructions[k]));
    }
    // what the workspace's choice costs against the faster pass of each run
    let picked = if picks == "link" { 6 } else { 5 };
    let lost = median(ours.iter().map(|r| r[picked] / r[5].min(r[6])).collect());
    println!(
        "{:<24}{world_over_link:>10.2}   (the workspace picks the {picks}-frame pass: {lost:.2}× the faster one)",
        "world / link time"
    );
    if !pin {
        println!(
            "(Pinocchio's timer is absent at {}: build it with \
             `$MX_SHARED/tools/pinocchio/build.sh /tmp/pinocchio-bench` or point \
             MX_PINOCCHIO_BENCH at it)",
            mx::report::perf::pinocchio_exe().display()
        );
    }
    Some(Found {
        name: name.to_string(),
        nq: model.nq(),
        ratios,
        instructions,
        passes: (world_over_link, lost),
        picks,
    })
}

/// The summary of every model: each cell the ratio mx / Pinocchio with mx's
/// instructions per call in brackets, the mean of the four ratios, and whether
/// the goals hold (every ratio ≤ 1, CRBA ≤ 0.8, the mean ≤ 0.6).
fn summary(found: &[Found]) {
    println!(
        "\nSummary: time ratio mx / Pinocchio (mx instructions per call); goals: each ≤ 1.0, CRBA ≤ 0.8, mean ≤ 0.6"
    );
    println!(
        "{:<26}{:>4}{:>16}{:>16}{:>16}{:>16}{:>7}  {:<6}{:>11}{:>11}  goals",
        "model", "nq", "RNEA", "ABA", "CRBA", "∂τ", "mean", "pass", "world/link", "vs faster"
    );
    for f in found {
        let cell = |k: usize| {
            let ins = f.instructions[k].map_or(String::new(), |x| format!(" ({:.1}k)", x / 1e3));
            match f.ratios.get(k) {
                Some(r) => format!("{r:.2}{ins}"),
                None => format!("-{ins}"),
            }
        };
        let (mean, goals) = if f.ratios.len() == 4 {
            let mean = f.ratios.iter().sum::<f64>() / 4.0;
            let ok = f.ratios.iter().all(|r| *r <= 1.0) && f.ratios[2] <= 0.8 && mean <= 0.6;
            (format!("{mean:.2}"), if ok { "met" } else { "MISSED" })
        } else {
            ("-".into(), "-")
        };
        println!(
            "{:<26}{:>4}{:>16}{:>16}{:>16}{:>16}{mean:>7}  {:<6}{:>11.2}{:>11.2}  {goals}",
            f.name,
            f.nq,
            cell(0),
            cell(1),
            cell(2),
            cell(3),
            f.picks,
            f.passes.0,
            f.passes.1
        );
    }
}

/// The models of table 1: every URDF of the reference data, the files
/// `MX_BENCH_URDFS` names (colon-separated: models this project never tuned
/// on), and the generated trees of [`mx::report::trees::family`], written as
/// URDF to a temporary folder so Pinocchio reads the same files.
fn models(dir: &Path) -> Vec<(String, PathBuf)> {
    let stem = |p: &Path| {
        p.file_stem()
            .map_or_else(String::new, |s| s.to_string_lossy().into())
    };
    let mut urdfs: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|d| {
            d.filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|x| x == "urdf"))
                .collect()
        })
        .unwrap_or_default();
    urdfs.sort();
    if urdfs.is_empty() {
        println!("\nno URDF in {} (set MX_SHARED)", dir.display());
    }
    if let Some(extra) = std::env::var_os("MX_BENCH_URDFS") {
        urdfs.extend(std::env::split_paths(&extra));
    }
    let mut out: Vec<(String, PathBuf)> = urdfs.iter().map(|p| (stem(p), p.clone())).collect();
    let tmp = std::env::temp_dir().join(format!("mx-bench-trees-{}", std::process::id()));
    if std::fs::create_dir_all(&tmp).is_ok() {
        for t in mx::report::trees::family() {
            let path = tmp.join(format!("{}.urdf", t.name));
            match std::fs::write(&path, &t.urdf) {
                Ok(()) => out.push((t.name, path)),
                Err(e) => println!("{}: cannot write {} ({e})", t.name, path.display()),
            }
        }
    }
    out
}

fn chain(n: usize) -> Arc<Model> {
    let mut m = Model::new("chain");
    for i in 0..n {
        let inertia = Inertia::from_com(
            1.0,
            Vector3::new(0.0, -0.25, 0.0),
            Matrix3::identity() * 0.01,
        )
        .unwrap();
        let axis = if i % 2 == 0 {
            Vector3::z()
        } else {
            Vector3::x()
        };
        m.add_link(
            &format!("l{i}"),
            if i == 0 { None } else { Some(i - 1) },
            &format!("j{i}"),
            Arc::new(Revolute::new(axis).unwrap().with_limit(mx::model::Limit {
                lower: -1.0,
                upper: 1.0,
            })),
            Se3::from_translation(Vector3::new(0.0, if i == 0 { 0.0 } else { -0.5 }, 0.0)),
            inertia,
        )
        .unwrap();
    }
    Arc::new(m)
}

fn effects() {
    let model = chain(20);
    let n = model.nq();
    let base = Scene::new(model.clone());
    let g = Vector3::new(0.0, -9.80665, 0.0);
    let spring = Spring {
        link_a: Some(3),
        point_a: Vector3::new(0.1, 0.0, 0.0),
        link_b: Some(12),
        point_b: Vector3::new(0.0, 0.1, 0.0),
        stiffness: 100.0,
        damping: 2.0,
        rest_length: 0.5,
    };
    let force = ExternalForce {
        link: 19,
        point: Vector3::new(0.0, -0.5, 0.0),
        force: Vector3::new(1.0, 0.0, 0.0),
    };
    let scenes: Vec<(&str, Scene)> = vec![
        ("no effects", base.clone()),
        ("gravity", base.clone().with_gravity(g).unwrap()),
        ("joint damping", base.clone().with_damping(&[0.1]).unwrap()),
        (
            "1 spring",
            base.clone().with_spring(spring.clone()).unwrap(),
        ),
        (
            "1 external force",
            base.clone().with_force(force.clone()).unwrap(),
        ),
        (
            "joint limits",
            base.clone()
                .with_limits(LimitPenalty {
                    stiffness: 1e3,
                    damping: 10.0,
                })
                .unwrap(),
        ),
        (
            "all of them",
            base.clone()
                .with_gravity(g)
                .unwrap()
                .with_damping(&[0.1])
                .unwrap()
                .with_spring(spring)
                .unwrap()
                .with_force(force)
                .unwrap()
                .with_limits(LimitPenalty {
                    stiffness: 1e3,
                    damping: 10.0,
                })
                .unwrap(),
        ),
    ];
    let mut rng = Rng(99);
    let states: Vec<(Vec<f64>, Vec<f64>)> = (0..2000)
        .map(|_| {
            (
                (0..n).map(|_| rng.f(-1.2, 1.2)).collect(),
                (0..n).map(|_| rng.f(-2.0, 2.0)).collect(),
            )
        })
        .collect();
    println!(
        "\nScene effects: q̈ of a 20-link chain, median µs per call (best of 5 interleaved rounds)"
    );
    println!("{:<20}{:>10}{:>12}", "scene", "µs", "vs none");
    let mut best = vec![f64::INFINITY; scenes.len()];
    for _round in 0..5 {
        for (k, (_, s)) in scenes.iter().enumerate() {
            let mut sw = SceneWorkspace::new(s);
            let mut qdd = vec![0.0; n];
            let t = median_us(states.len(), |i| {
                s.accelerations(&mut sw, &states[i].0, &states[i].1, &[], &mut qdd)
                    .unwrap();
                black_box(&qdd);
            });
            best[k] = best[k].min(t);
        }
    }
    for (k, (name, _)) in scenes.iter().enumerate() {
        println!("{name:<20}{:>10.3}{:>11.2}×", best[k], best[k] / best[0]);
    }
}

/// The OpenSim knee pendulum (run `shank_foot_femur_flexed_50deg`): scene, initial state, reference q.
fn knee_pendulum() -> Option<(Scene, State, Vec<f64>)> {
    mx::report::integrators::knee_pendulum(&shared()).ok()
}

fn work_precision() {
    let Some((scene, init, q_ref)) = knee_pendulum() else {
        println!("\nwork-precision: OpenSim knee pendulum data not found");
        return;
    };
    let tok = CancelToken::new();
    // One knee spline-joint step (one forward-dynamics evaluation) for reference.
    let mut sw = SceneWorkspace::new(&scene);
    let mut qdd = [0.0];
    let step = median_us(5000, |i| {
        let q = [-(i as f64) * 1e-4];
        scene
            .accelerations(&mut sw, &q, &[0.3], &[], &mut qdd)
            .unwrap();
        black_box(&qdd);
    });
    println!(
        "\nKnee spline joint (OpenSim gait2392): forward dynamics {step:.3} µs per evaluation (paper: 6 ms per step)"
    );
    println!("\nIntegrators on the OpenSim knee pendulum (shank+foot, femur flexed 50°, 1 s):");
    println!("max |q − q_OpenSim(accuracy 1e-12)| over the 1 ms grid vs run time");
    println!(
        "{:<34}{:>12}{:>12}{:>10}",
        "integrator", "max |Δq|", "ms", "evals"
    );
    let mut cases: Vec<(String, Integrator, f64)> = Vec::new();
    for dt in [1e-2, 1e-3, 1e-4] {
        cases.push((format!("euler dt={dt:e}"), Integrator::Euler, dt));
        cases.push((
            format!("semi_implicit_euler dt={dt:e}"),
            Integrator::SemiImplicitEuler,
            dt,
        ));
        cases.push((format!("rk4 dt={dt:e}"), Integrator::Rk4, dt));
    }
    for tol in [1e-4, 1e-6, 1e-8, 1e-10, 1e-12] {
        cases.push((
            format!("dopri5 tol={tol:e}"),
            Integrator::DormandPrince {
                rtol: tol,
                atol: tol,
            },
            // Output every 10 ms so the grid does not cap the adaptive step.
            1e-2,
        ));
    }
    for (name, m, dt) in cases {
        // Best of 3 runs: the machine is shared.
        let mut ms = f64::INFINITY;
        let mut r = simulate(&scene, 1.0, dt, m, &init, &tok, &mut |_| {});
        for _ in 0..3 {
            let s = Instant::now();
            r = simulate(&scene, 1.0, dt, m, &init, &tok, &mut |_| {});
            ms = ms.min(s.elapsed().as_secs_f64() * 1e3);
        }
        match r {
            Ok(tr) => {
                // Compare on the common grid (every 1 ms for dt ≤ 1 ms, else every dt).
                let stride_ref = ((dt / 1e-3).round() as usize).max(1);
                let stride_sim = ((1e-3 / dt).round() as usize).max(1);
                let e = (0..)
                    .map(|k| (k * stride_sim, k * stride_ref))
                    .take_while(|(a, b)| *a < tr.q.len() && *b < q_ref.len())
                    .map(|(a, b)| (tr.q[a][0] - q_ref[b]).abs())
                    .fold(0.0, f64::max);
                println!("{name:<34}{e:>12.2e}{ms:>12.3}{:>10}", tr.evaluations);
            }
            Err(e) => println!("{name:<34}{:>12}{ms:>12.3}   ({e})", "failed"),
        }
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if let Some(k) = args.iter().position(|a| a == "instructions-driver") {
        instructions_driver(&args[k + 1..]);
        return;
    }
    // `cargo test --benches` runs this with --bench absent; keep it quick then.
    let quick = !args.iter().any(|a| a == "--bench");
    let dir = shared().join("data/reference");
    if quick {
        println!("dynamics bench: run with `cargo bench --bench dynamics` for the tables");
        return;
    }
    // Every URDF of the reference data (human44, Panda, UR5, and any added
    // later), the ones MX_BENCH_URDFS names, and the generated trees.
    let mut found = Vec::new();
    for (name, urdf) in models(&dir) {
        found.extend(per_call(&name, &urdf));
    }
    let ratios: Vec<f64> = found
        .iter()
        .flat_map(|f| f.ratios.iter().copied())
        .collect();
    if !ratios.is_empty() {
        println!(
            "\nmean ratio over {} cells (models × algorithms): {:.2}",
            ratios.len(),
            ratios.iter().sum::<f64>() / ratios.len() as f64
        );
    }
    summary(&found);
    // Table 1 alone is what one checks against Pinocchio after a change.
    if args.iter().any(|a| a == "per_call") {
        return;
    }
    effects();
    work_precision();
}
