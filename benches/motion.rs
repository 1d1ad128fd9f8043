//! Motion algebra benchmark: build a composite expression over a 60-DOF,
//! 60 s motion sampled at 120 Hz, then sample it at 120 Hz (7,201 rows ×
//! 60 DOFs) as `save(m, "x.csv", rate: 120)` does. Target: well under 100 ms.
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
    divan::main();
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
