//! Motion algebra benchmark: build a composite expression over a 60-DOF,
//! 60 s motion sampled at 120 Hz, then sample it at 120 Hz (7,201 rows ×
//! 60 DOFs) as `save(m, "x.csv", rate: 120)` does. Target: well under 100 ms.
//!
//! The animator's operators (issue 17): blend, crossfade and mirror of a
//! 60-DOF skeleton-like motion (a root with positions and 19 joints of Euler
//! channels, 60 s at 120 Hz), each timed against sampling its input alone at
//! 120 Hz (the ratio is the number to quote); and IK per frame on the
//! project's human(walk) (the 44-DOF anatomical model) with two foot
//! targets: µs per frame and iterations.
//!
//! Run: `cargo bench --bench motion`.

use std::hint::black_box;
use std::time::Instant;

use mx::motion::*;

const DOFS: usize = 60;
const SECONDS: f64 = 60.0;
const RATE: f64 = 120.0;

/// A mocap-like clip: every DOF a smooth, different curve sampled at 120 Hz.
fn clip_like(dofs: usize, seconds: f64, phase: f64) -> Mu {
    let n = (seconds * RATE) as usize + 1;
    (0..dofs)
        .map(|d| {
            let w = 0.5 + d as f64 * 0.05;
            let values = (0..n)
                .map(|k| (w * k as f64 / RATE + phase).sin() * (1.0 + 0.01 * d as f64))
                .collect();
            let c = Curve::samples(0.0, 1.0 / RATE, values).expect("valid samples");
            (
                format!("Joint{d}.rot"),
                Dof::from(Interval::curve(c, 0.0, seconds).expect("valid interval")),
            )
        })
        .collect()
}

/// The paper's Figure 6 pattern, repeated: waves pasted into a walk with
/// transition gaps around them, then a clip and a concatenation.
fn composite(walk: &Mu, wave: &Mu) -> Mu {
    let mut m = walk.clone();
    for k in 0..6 {
        let at = 2.0 + 9.0 * k as f64;
        let hole = affine(at - 0.4, 1.2, wave).expect("affine");
        let inner = affine(at, 1.0, wave).expect("affine");
        m = plus(&inner, &minus(&m, &hole));
    }
    let head = clip(0.0, 30.0, &m).expect("clip");
    let tail = clip(30.0, SECONDS, &m).expect("clip");
    concatenate(&head, &tail)
}

fn sample_all(m: &Mu) -> usize {
    let g = sample_grid(m, RATE, None).expect("no conflicts");
    g.values
        .iter()
        .map(|c| c.iter().filter(|v| v.is_some()).count())
        .sum()
}

fn main() {
    // One explicit measurement, printed, before divan's statistics.
    let walk = clip_like(DOFS, SECONDS, 0.0);
    let wave = only(&clip_like(DOFS, 4.0, 1.0), &["Joint1*", "Joint2*"]).expect("glob");
    let t = Instant::now();
    let m = composite(&walk, &wave);
    let built = t.elapsed();
    let defined = sample_all(&m);
    let total = t.elapsed();
    println!(
        "composite over {DOFS} DOFs × {SECONDS} s: build {:.3} ms, build + sample at {RATE} Hz ({defined} values, {} gaps) {:.3} ms",
        built.as_secs_f64() * 1e3,
        gaps(&m).len(),
        total.as_secs_f64() * 1e3
    );
    operators();
    ik_per_frame();
    divan::main();
}

/// 60 DOFs like a clip's: Hips with positions and ZXY rotations, nine
/// left and nine right joints of three rotation channels each.
fn skeleton_like(seconds: f64, phase: f64) -> Mu {
    let n = (seconds * RATE) as usize + 1;
    let mut names: Vec<String> = [
        "Xposition",
        "Yposition",
        "Zposition",
        "Zrotation",
        "Xrotation",
        "Yrotation",
    ]
    .iter()
    .map(|c| format!("Hips.{c}"))
    .collect();
    for side in ["Left", "Right"] {
        for j in 0..9 {
            for c in ["Zrotation", "Xrotation", "Yrotation"] {
                names.push(format!("{side}Joint{j}.{c}"));
            }
        }
    }
    names
        .into_iter()
        .enumerate()
        .map(|(d, name)| {
            let w = 0.5 + d as f64 * 0.05;
            let amp = if name.contains("position") { 0.3 } else { 40.0 };
            let drift = if name == "Hips.Zposition" { 1.2 } else { 0.0 };
            let values = (0..n)
                .map(|k| {
                    let t = k as f64 / RATE;
                    amp * (w * t + phase).sin() + drift * t
                })
                .collect();
            let c = Curve::samples(0.0, 1.0 / RATE, values).expect("valid samples");
            (
                name,
                Dof::from(Interval::curve(c, 0.0, seconds).expect("valid interval")),
            )
        })
        .collect()
}

/// Seconds of the best of `runs` calls of `f`.
fn best_of(runs: usize, mut f: impl FnMut() -> usize) -> f64 {
    (0..runs)
        .map(|_| {
            let t = Instant::now();
            black_box(f());
            t.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

/// Each operator (building its result, then sampling that at 120 Hz) against
/// sampling the input alone at 120 Hz, in one run.
fn operators() {
    use mx::motion::compose::{Weight, blend, crossfade, mirror};
    let a = skeleton_like(SECONDS, 0.0);
    let b = skeleton_like(SECONDS, 1.3);
    let base = best_of(5, || sample_all(&a));
    type Op<'a> = (&'static str, Box<dyn Fn() -> usize + 'a>);
    let rows: [Op<'_>; 3] = [
        (
            "blend(a, b, 0.5)",
            Box::new(|| sample_all(&blend(&a, &b, &Weight::Const(0.5)).expect("blend"))),
        ),
        (
            "crossfade(a, b, 1 s)",
            Box::new(|| sample_all(&crossfade(&a, &b, 1.0, 1).expect("crossfade"))),
        ),
        (
            "mirror(a)",
            Box::new(|| sample_all(&mirror(&a, 0).expect("mirror"))),
        ),
    ];
    println!(
        "\noperators on 60 DOFs × {SECONDS} s at {RATE} Hz; sampling the input alone {:.1} ms",
        base * 1e3
    );
    for (what, f) in rows {
        let t = best_of(3, f);
        println!(
            "  {what:<22} {:>8.1} ms  {:>6.1}× sampling the input",
            t * 1e3,
            t / base
        );
    }
}

/// IK on human(walk): both feet put where the walk has them 0.3 s later
/// (reachable, ~30 cm from each frame's own pose), every coordinate free.
fn ik_per_frame() {
    use mx::ik::{IkOptions, Target, ik};
    let (model, walk) = mx::spacetime::fig8::example_walk().expect("example walk");
    let later = affine(-0.3, 1.0, &walk).expect("affine");
    let (s, e) = later.span().expect("span");
    let e = e.min(walk.span().expect("span").1);
    let ts: Vec<f64> = grid_times((s.max(0.0), e), 60.0).expect("grid");
    let p = mx::mocap::positions_at(&later, &model, ts.clone(), mx::mocap::Missing::Error)
        .expect("positions");
    let target = |link: &str| {
        let j = p.names.iter().position(|n| n == link).expect("foot link");
        let axis = |k: usize| {
            let v: Vec<f64> = p.points.iter().map(|f| f[j][k]).collect();
            let c = Curve::samples(ts[0], ts[1] - ts[0], v).expect("samples");
            Dof::from(Interval::curve(c, ts[0], *ts.last().expect("frames")).expect("interval"))
        };
        Target {
            link: link.into(),
            position: [axis(0), axis(1), axis(2)],
            orientation: None,
            weight: 1.0,
        }
    };
    let targets = [target("foot_L"), target("foot_R")];
    let opts = IkOptions {
        rate: Some(60.0),
        ..Default::default()
    };
    let t = Instant::now();
    let (_, r) = ik(&model, &walk, &targets, &opts).expect("ik");
    let secs = t.elapsed().as_secs_f64();
    println!(
        "\nIK on human(walk) ({} coordinates), two foot targets, {} frames: {:.1} µs per frame, iterations mean {:.2} max {}, largest residual {:.2e} m, {} frames not within {:.0e} m",
        model.nq(),
        r.frames,
        secs * 1e6 / r.frames as f64,
        r.mean_iterations,
        r.max_iterations,
        r.targets.iter().map(|t| t.max_residual).fold(0.0, f64::max),
        r.unconverged_frames,
        r.tolerance
    );
}

#[divan::bench]
fn build_composite(bencher: divan::Bencher) {
    let walk = clip_like(DOFS, SECONDS, 0.0);
    let wave = only(&clip_like(DOFS, 4.0, 1.0), &["Joint1*", "Joint2*"]).expect("glob");
    bencher.bench(|| composite(black_box(&walk), black_box(&wave)));
}

#[divan::bench]
fn build_and_sample_at_120hz(bencher: divan::Bencher) {
    let walk = clip_like(DOFS, SECONDS, 0.0);
    let wave = only(&clip_like(DOFS, 4.0, 1.0), &["Joint1*", "Joint2*"]).expect("glob");
    bencher.bench(|| sample_all(&composite(black_box(&walk), black_box(&wave))));
}

#[divan::bench]
fn csv_text_at_120hz(bencher: divan::Bencher) {
    let walk = clip_like(DOFS, SECONDS, 0.0);
    let wave = only(&clip_like(DOFS, 4.0, 1.0), &["Joint1*", "Joint2*"]).expect("glob");
    let m = composite(&walk, &wave);
    bencher.bench(|| {
        mx::io::csv::to_csv_string(black_box(&m), RATE, None)
            .expect("csv")
            .len()
    });
}
