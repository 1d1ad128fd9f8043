//! The clip library at scale (`mx::library`): libraries of 10², 10³ (and,
//! with `MX_LIBRARY_SIZES=100,1000,10000`, 10⁴) clips made in memory from
//! the shared clips (`data/mocap` and `data/inbetween`) by time-warping,
//! mirroring and renaming, so it runs anywhere the shared data is. Per size:
//! index build time and memory, query time per gap (tree and brute force),
//! and SP time per gap with the library against `example: "self"`.
//!
//! Run: `cargo bench --bench library`. Environment:
//! - `MX_LIBRARY_SIZES=100,1000`: the library sizes (clips);
//! - `MX_LIBRARY_SP=N`: SP windows timed per size (default 4; 0: none).

mod common;
use common::shared;

use mx::library::{self, ClipInput, Library, Settings};
use mx::mocap::bvh::{BvhFile, Channel};
use mx::report::inbetween::{Case, RootMode};
use mx::spacetime::reference::LibrarySource;
use mx::spacetime::{Prior, SpOptions, sp};
use std::sync::Arc;
use std::time::Instant;

/// `file` played `w` times as fast (linear between frames; angles were
/// unwrapped by the reader's caller, so linear is safe between close frames).
fn warped(file: &BvhFile, w: f64) -> BvhFile {
    let nch = file.skeleton.channel_count();
    let n = file.frame_count();
    let m = (((n - 1) as f64) / w).floor() as usize + 1;
    let mut values = Vec::with_capacity(m * nch);
    for k in 0..m {
        let x = (k as f64 * w).min((n - 1) as f64);
        let (i, f) = (x.floor() as usize, x.fract());
        let j = (i + 1).min(n - 1);
        for c in 0..nch {
            let (a, b) = (file.values[i * nch + c], file.values[j * nch + c]);
            values.push(a + f * (b - a));
        }
    }
    BvhFile {
        skeleton: file.skeleton.clone(),
        frame_time: file.frame_time,
        values,
    }
}

/// `file` mirrored left for right: paired joints swap their channels, and
/// the reflection x → −x negates y and z rotations and x positions.
fn mirrored(file: &BvhFile) -> BvhFile {
    let sk = &file.skeleton;
    let nch = sk.channel_count();
    let starts = sk.channel_starts();
    let twin = |name: &str| -> Option<String> {
        for (a, b) in [
            ("Left", "Right"),
            ("_L", "_R"),
            ("Right", "Left"),
            ("_R", "_L"),
        ] {
            if name.contains(a) {
                return Some(name.replacen(a, b, 1));
            }
        }
        None
    };
    let mut out = file.clone();
    for (i, j) in sk.joints.iter().enumerate() {
        let from = twin(&j.name).and_then(|n| sk.find(&n)).unwrap_or(i);
        if sk.joints[from].channels != j.channels {
            continue;
        }
        for (k, ch) in j.channels.iter().enumerate() {
            let sign = match ch {
                Channel::Yrotation | Channel::Zrotation | Channel::Xposition => -1.0,
                _ => 1.0,
            };
            for f in 0..file.frame_count() {
                out.values[f * nch + starts[i] + k] =
                    sign * file.values[f * nch + starts[from] + k];
            }
        }
    }
    out
}

fn base_clips() -> Vec<ClipInput> {
    let mut all = vec![];
    for sub in ["mocap", "inbetween"] {
        let (clips, skipped) = library::clips_in_folder(&shared().join("data").join(sub))
            .unwrap_or_else(|e| panic!("{e}"));
        assert!(skipped.is_empty(), "{skipped:?}");
        all.extend(clips);
    }
    all
}

/// `n` clips: the base clips, then warped and mirrored copies, renamed.
fn library_of(base: &[ClipInput], n: usize) -> Vec<ClipInput> {
    const WARPS: [f64; 8] = [1.0, 0.85, 1.15, 0.92, 1.08, 0.8, 1.2, 0.96];
    (0..n)
        .map(|i| {
            let b = &base[i % base.len()];
            let round = i / base.len();
            let w = WARPS[round % WARPS.len()];
            let mut file = if w == 1.0 {
                b.file.clone()
            } else {
                warped(&b.file, w)
            };
            if (round / WARPS.len()) % 2 == 1 {
                file = mirrored(&file);
            }
            ClipInput {
                name: format!("{}#{round}", b.name),
                file,
                metres_per_unit: b.metres_per_unit,
                source: None,
            }
        })
        .collect()
}

fn main() {
    let sizes: Vec<usize> = std::env::var("MX_LIBRARY_SIZES")
        .ok()
        .map(|s| s.split(',').filter_map(|x| x.trim().parse().ok()).collect())
        .unwrap_or(vec![100, 1000]);
    let sp_windows: usize = std::env::var("MX_LIBRARY_SP")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(4);
    let base = base_clips();
    let inbetween = shared().join("data").join("inbetween");
    let cases = Case::load_dir(&inbetween).unwrap_or_else(|e| panic!("{e}"));
    println!(
        "{} base clips; gaps of 30 frames with 10 frames of context in {} in-betweening clips",
        base.len(),
        cases.len()
    );
    println!(
        "| clips | frames | build s | memory MB | query ms (tree) | query ms (brute) | SP s/gap self | SP s/gap library |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- | --- |");
    for &n in &sizes {
        let clips = library_of(&base, n);
        let t = Instant::now();
        let lib = Arc::new(Library::build(clips, vec![], Settings::default()).unwrap());
        let build = t.elapsed().as_secs_f64();
        // one gap per in-betweening clip, from its own motion
        let mut queries = vec![];
        for case in &cases {
            let b = base.iter().find(|b| b.name == case.name).unwrap();
            // a middle window: at frame 0 the context starts 3e-7 s before the clip
            let w = case.windows(&Default::default(), 30);
            let Some(&start) = w.get(w.len() / 2) else {
                continue;
            };
            let t0 = (start + 10) as f64 * case.frame_time;
            let t1 = t0 + 30.0 * case.frame_time;
            if let Ok(q) = lib.query(&case.capture, &b.file.skeleton, b.metres_per_unit, t0, t1) {
                queries.push(q);
            }
        }
        let t = Instant::now();
        for q in &queries {
            std::hint::black_box(lib.match_gap(q, 5));
        }
        let tree_ms = t.elapsed().as_secs_f64() * 1e3 / queries.len() as f64;
        let brute_n = queries.len().min(10);
        let t = Instant::now();
        for q in &queries[..brute_n] {
            std::hint::black_box(lib.match_brute(q, 5));
        }
        let brute_ms = t.elapsed().as_secs_f64() * 1e3 / brute_n as f64;
        // SP on the first windows, self example against the library
        let (mut t_self, mut t_lib) = (0.0, 0.0);
        for case in cases.iter().take(sp_windows) {
            let b = base.iter().find(|b| b.name == case.name).unwrap();
            let w = case.windows(&Default::default(), 30);
            let start = w[w.len() / 2];
            let m = case.cut(start, 10, 30, RootMode::Given).unwrap();
            let t = Instant::now();
            sp(&m, &case.body, &SpOptions::default()).unwrap();
            t_self += t.elapsed().as_secs_f64();
            let opts = SpOptions {
                library: Some(LibrarySource {
                    library: lib.clone(),
                    skeleton: Arc::new(b.file.skeleton.clone()),
                    metres_per_unit: b.metres_per_unit,
                }),
                prior: Prior {
                    example: false,
                    ..Prior::default()
                },
                ..Default::default()
            };
            let t = Instant::now();
            sp(&m, &case.body, &opts).unwrap();
            t_lib += t.elapsed().as_secs_f64();
        }
        let per = sp_windows.max(1) as f64;
        println!(
            "| {n} | {} | {build:.2} | {:.0} | {tree_ms:.2} | {brute_ms:.1} | {:.3} | {:.3} |",
            lib.frames(),
            lib.memory_bytes() as f64 / 1e6,
            t_self / per,
            t_lib / per
        );
    }
}
