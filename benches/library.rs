//! The clip library at scale (`mx::library`): libraries of 10², 10³ and 10⁴
//! clips made from the shared clips (`data/mocap` and `data/inbetween`) by
//! a seeded rule (`generated`: time warps, mirrors, skeletons scaled
//! 0.85–1.15×, smooth noise; no two alike), written as `.bvh` files under
//! `target/library-bench/` (made once, never committed), so it runs
//! anywhere the shared data is. Each size is built from its files as `mx
//! library build` does (read, indexed and let go file by file), saved as an
//! `.mxlib`, and loaded. Per size, each phase in a child process of its own
//! so its peak resident memory is its own:
//! - build: time and peak memory (the goal: ≤ 2 min and ≤ 2 GB at 10⁴), and
//!   the `.mxlib`'s size beside its clips' `.bvh` files' (the goal: ≤ 1×);
//! - use: the `.mxlib`'s load time (the tree built at the first query),
//!   query time per gap (tree; brute force on a few; goal ≤ 5 ms), peak
//!   memory, and SP's time per gap following the library against the same
//!   windows following the library of the base clips, run alternately in
//!   the same process (the goal: a ratio ≤ 1.5).
//!
//! Run: `cargo bench --bench library`. Environment:
//! - `MX_LIBRARY_SIZES=100,1000,10000` (default): the library sizes (clips);
//! - `MX_LIBRARY_SP=N`: SP windows timed per size (default 4; 0: none);
//! - `MX_LIBRARY_DIR=PATH`: where the clips and libraries go;
//! - `MX_LIBRARY_REPEATS=1`: the generated clips are exact copies of the
//!   shared ones (the "10⁴ files of repeats"; the goal: a ratio ≤ 2),
//!   in a folder of their own.

mod common;
use common::shared;

use mx::library::{self, ClipInput, Library, Settings, file};
use mx::mocap::bvh::{self, BvhFile, Channel};
use mx::report::inbetween::{Case, RootMode};
use mx::spacetime::reference::LibrarySource;
use mx::spacetime::{Prior, SpOptions, sp};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Arc;
use std::time::Instant;

/// `file` played `w` times as fast (linear between frames, its rotation
/// channels unwrapped first so no interpolation crosses a ±180° wrap).
fn warped(file: &BvhFile, w: f64) -> BvhFile {
    let nch = file.skeleton.channel_count();
    let n = file.frame_count();
    let mut src = file.values.clone();
    let kinds: Vec<Channel> = file
        .skeleton
        .joints
        .iter()
        .flat_map(|j| j.channels.iter().copied())
        .collect();
    for (c, kind) in kinds.iter().enumerate() {
        if kind.is_rotation() {
            bvh::unwrap_degrees_in(src.iter_mut().skip(c).step_by(nch));
        }
    }
    let m = (((n - 1) as f64) / w).floor() as usize + 1;
    let mut values = Vec::with_capacity(m * nch);
    for k in 0..m {
        let x = (k as f64 * w).min((n - 1) as f64);
        let (i, f) = (x.floor() as usize, x.fract());
        let j = (i + 1).min(n - 1);
        for c in 0..nch {
            let (a, b) = (src[i * nch + c], src[j * nch + c]);
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

/// A small seeded generator (splitmix64): the same clip index gives the
/// same variant on every machine.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// `file` retargeted to its skeleton scaled by `s`: every bone offset and
/// end site, and the root's position channels, times `s` (the same joint
/// angles on a taller or shorter actor, whose feet then stay planted).
fn scaled(file: &BvhFile, s: f64) -> BvhFile {
    let mut out = file.clone();
    for j in &mut out.skeleton.joints {
        j.offset *= s;
        j.end_sites.iter_mut().for_each(|e| *e *= s);
    }
    let nch = file.skeleton.channel_count();
    let starts = file.skeleton.channel_starts();
    for (i, j) in file.skeleton.joints.iter().enumerate() {
        for (k, ch) in j.channels.iter().enumerate() {
            if !ch.is_rotation() {
                let c = starts[i] + k;
                out.values
                    .iter_mut()
                    .skip(c)
                    .step_by(nch)
                    .for_each(|v| *v *= s);
            }
        }
    }
    out
}

/// `file` with smooth noise on every rotation channel: per channel a
/// sinusoid of amplitude up to `degrees`, period 0.5–2 s and a phase drawn
/// from `rng` (a capture's slow marker drift, not frame-to-frame jitter,
/// which would only make the velocities noisy).
fn noised(file: &BvhFile, degrees: f64, rng: &mut Rng) -> BvhFile {
    let mut out = file.clone();
    let nch = file.skeleton.channel_count();
    let kinds: Vec<Channel> = file
        .skeleton
        .joints
        .iter()
        .flat_map(|j| j.channels.iter().copied())
        .collect();
    for (c, kind) in kinds.iter().enumerate() {
        if !kind.is_rotation() {
            continue;
        }
        let a = degrees * rng.next();
        let omega = std::f64::consts::TAU / (0.5 + 1.5 * rng.next());
        let phase = std::f64::consts::TAU * rng.next();
        for (f, v) in out.values.iter_mut().skip(c).step_by(nch).enumerate() {
            *v += a * (omega * f as f64 * file.frame_time + phase).sin();
        }
    }
    out
}

/// Clip `i` of the generated set: base clip `i mod B` in round `i / B`.
/// Round 0 is the shared clips as captured; in round r ≥ 1 each is played
/// at a warp of its own (0.8–1.2, the golden-ratio sequence in r), mirrored
/// in odd rounds, retargeted to its skeleton scaled by 0.85–1.15 (the √2
/// sequence in r) and given smooth noise of up to 0.5° seeded by `i`: no
/// two alike, by a rule that reads nothing of the clips. Named so that the
/// first `n` files in name order are rounds 0, 1, … (every base clip in each).
fn generated(base: &[ClipInput], i: usize) -> (String, BvhFile) {
    let b = &base[i % base.len()];
    let round = i / base.len();
    let name = format!("r{round:04}_{}", b.name);
    if repeats() || round == 0 {
        return (name, b.file.clone());
    }
    let r = round as f64;
    let w = 0.8 + 0.4 * (r * 0.618_033_988_75).fract();
    let s = 0.85 + 0.3 * (r * std::f64::consts::SQRT_2).fract();
    let mut file = warped(&b.file, w);
    if round % 2 == 1 {
        file = mirrored(&file);
    }
    let mut rng = Rng(i as u64 ^ 0x6d78_6c69_6273_6361);
    let mut file = noised(&scaled(&file, s), 0.5, &mut rng);
    file.values.iter_mut().for_each(|v| *v = six_digits(*v));
    (name, file)
}

/// `v` to six significant digits, as capture exporters write them (`%g`):
/// a generated file is then as large as a captured one, not padded with the
/// seventeen digits of a computed double.
fn six_digits(v: f64) -> f64 {
    if v == 0.0 || !v.is_finite() {
        return v;
    }
    let e = v.abs().log10().floor() as i32;
    // an integer over or times an exact power of ten: the nearest double
    // to the six-digit decimal, which prints back as those six digits
    if e <= 5 {
        let f = 10f64.powi(5 - e);
        (v * f).round() / f
    } else {
        let f = 10f64.powi(e - 5);
        (v / f).round() * f
    }
}

/// The generator's rule, in the stamp of the files it wrote.
const GENERATOR: &str = "warp-mirror-scale-noise-2";

/// Whether the generated clips are exact repeats (`MX_LIBRARY_REPEATS=1`).
fn repeats() -> bool {
    std::env::var("MX_LIBRARY_REPEATS").is_ok_and(|v| v == "1")
}

fn bench_dir() -> PathBuf {
    let dir = std::env::var_os("MX_LIBRARY_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            PathBuf::from(env!("CARGO_MANIFEST_DIR"))
                .join("target")
                .join("library-bench")
        });
    if repeats() { dir.join("repeats") } else { dir }
}

/// The first `n` generated clips' files (written once; a stamp marks the
/// count written).
fn clip_files(base: &[ClipInput], n: usize) -> Vec<PathBuf> {
    let dir = bench_dir().join("clips");
    // the stamp names the generator, so files of an older rule are rewritten
    let stamp = dir.join(".written");
    let have: usize = std::fs::read_to_string(&stamp)
        .ok()
        .and_then(|s| s.trim().strip_prefix(GENERATOR)?.trim().parse().ok())
        .unwrap_or(0);
    if have < n {
        std::fs::create_dir_all(&dir).unwrap();
        eprintln!("writing {} generated clips to {}", n - have, dir.display());
        use rayon::prelude::*;
        (have..n).into_par_iter().for_each(|i| {
            let (name, file) = generated(base, i);
            let text = bvh::to_string(&file).unwrap();
            std::fs::write(dir.join(format!("{name}.bvh")), text).unwrap();
        });
        std::fs::write(&stamp, format!("{GENERATOR} {n}")).unwrap();
    }
    let mut all = library::bvh_files(&dir).unwrap();
    all.truncate(n);
    all
}

/// This process's peak resident memory (MB), from /proc.
fn peak_mb() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM:"))
                .and_then(|l| l.split_whitespace().nth(1)?.parse::<f64>().ok())
        })
        .map_or(f64::NAN, |kb| kb / 1024.0)
}

/// Runs this bench again as a child for one phase; its `key=value` line.
fn child(phase: &str) -> std::collections::HashMap<String, String> {
    let o = Command::new(std::env::current_exe().unwrap())
        .env("MX_LIBRARY_CHILD", phase)
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "{phase}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    let out = String::from_utf8_lossy(&o.stdout);
    let line = out
        .lines()
        .find(|l| l.starts_with("RESULT"))
        .unwrap_or_else(|| panic!("{phase}: no result in {out}"));
    line.split_whitespace()
        .skip(1)
        .filter_map(|kv| kv.split_once('='))
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect()
}

/// Child: builds the library of the first `n` clips and saves it.
fn build_phase(n: usize, out: &Path) {
    let base = base_clips();
    let files = clip_files(&base, n);
    drop(base);
    let bvh_bytes: u64 = files
        .iter()
        .map(|f| std::fs::metadata(f).map_or(0, |m| m.len()))
        .sum();
    let t = Instant::now();
    let lib = Library::build_files(&files, Settings::default()).unwrap();
    let build = t.elapsed().as_secs_f64();
    let t = Instant::now();
    file::save(&lib, out).unwrap();
    let save = t.elapsed().as_secs_f64();
    println!(
        "RESULT build_s={build:.2} save_s={save:.2} frames={} bvh_mb={:.1} memory_mb={:.0} peak_mb={:.0}",
        lib.frames(),
        bvh_bytes as f64 / 1e6,
        lib.memory_bytes() as f64 / 1e6,
        peak_mb()
    );
}

/// Child: loads `lib` (and the base library), times queries and SP.
fn use_phase(lib_path: &Path, base_path: &Path, sp_windows: usize) {
    let t = Instant::now();
    let lib = Arc::new(file::load(lib_path, None).unwrap());
    let load = t.elapsed().as_secs_f64();
    let base_lib = Arc::new(file::load(base_path, None).unwrap());
    let cases = Case::load_dir(&shared().join("data").join("inbetween")).unwrap();
    // one 30-frame gap with 10 frames of context in the middle of each in-betweening clip
    let mut queries = vec![];
    for case in &cases {
        let w = case.windows(&Default::default(), 30);
        let Some(&start) = w.get(w.len() / 2) else {
            continue;
        };
        let t0 = (start + 10) as f64 * case.frame_time;
        let t1 = t0 + 30.0 * case.frame_time;
        if let Ok(q) = lib.query(&case.capture, &case.skeleton, case.metres_per_unit, t0, t1) {
            queries.push(q);
        }
    }
    let t = Instant::now();
    std::hint::black_box(lib.match_gap(&queries[0], 5));
    let first = t.elapsed().as_secs_f64();
    let t = Instant::now();
    for q in &queries {
        std::hint::black_box(lib.match_gap(q, 5));
    }
    let tree_ms = t.elapsed().as_secs_f64() * 1e3 / queries.len() as f64;
    let brute_n = queries.len().min(3);
    let t = Instant::now();
    for q in &queries[..brute_n] {
        std::hint::black_box(lib.match_brute(q, 5));
    }
    let brute_ms = t.elapsed().as_secs_f64() * 1e3 / brute_n as f64;
    // SP on the same windows, following the base library and this one in turn
    let (mut t_base, mut t_lib) = (0.0, 0.0);
    let opts = |l: &Arc<Library>, case: &Case| SpOptions {
        library: Some(LibrarySource {
            library: l.clone(),
            skeleton: case.skeleton.clone(),
            metres_per_unit: case.metres_per_unit,
        }),
        prior: Prior {
            example: false,
            ..Prior::default()
        },
        ..Default::default()
    };
    for case in cases.iter().take(sp_windows) {
        let w = case.windows(&Default::default(), 30);
        let start = w[w.len() / 2];
        let m = case.cut(start, 10, 30, RootMode::Given).unwrap();
        let t = Instant::now();
        sp(&m, &case.body, &opts(&base_lib, case)).unwrap();
        t_base += t.elapsed().as_secs_f64();
        let t = Instant::now();
        sp(&m, &case.body, &opts(&lib, case)).unwrap();
        t_lib += t.elapsed().as_secs_f64();
    }
    let per = sp_windows.max(1) as f64;
    println!(
        "RESULT load_s={load:.2} tree_s={first:.2} query_ms={tree_ms:.2} brute_ms={brute_ms:.1} sp_base_s={:.3} sp_lib_s={:.3} peak_mb={:.0}",
        t_base / per,
        t_lib / per,
        peak_mb()
    );
}

fn main() {
    let sizes: Vec<usize> = std::env::var("MX_LIBRARY_SIZES")
        .ok()
        .map(|s| s.split(',').filter_map(|x| x.trim().parse().ok()).collect())
        .unwrap_or(vec![100, 1000, 10000]);
    let sp_windows: usize = std::env::var("MX_LIBRARY_SP")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(4);
    let dir = bench_dir();
    let lib_path = |n: usize| dir.join(format!("lib-{n}.mxlib"));
    if let Ok(phase) = std::env::var("MX_LIBRARY_CHILD") {
        let (what, n) = phase.split_once(':').unwrap();
        let n: usize = n.parse().unwrap();
        match what {
            "build" => build_phase(n, &lib_path(n)),
            _ => use_phase(&lib_path(n), &dir.join("lib-base.mxlib"), sp_windows),
        }
        return;
    }
    let base = base_clips();
    let nb = base.len();
    std::fs::create_dir_all(&dir).unwrap();
    clip_files(&base, sizes.iter().copied().max().unwrap_or(0).max(nb));
    drop(base);
    // the base library: the shared clips themselves (round 0)
    let b = child(&format!("build:{nb}"));
    std::fs::rename(lib_path(nb), dir.join("lib-base.mxlib")).unwrap();
    let base_mb = std::fs::metadata(dir.join("lib-base.mxlib")).map_or(0, |m| m.len()) as f64 / 1e6;
    println!(
        "base library: {nb} clips (the shared ones), built in {} s, .mxlib {base_mb:.2} MB for {} MB of .bvh; SP windows: {sp_windows} (30-frame gaps, root given)",
        b["build_s"], b["bvh_mb"]
    );
    println!(
        "| clips | frames | build s | save s | build peak MB | index MB | .bvh MB | .mxlib MB | ÷ .bvh | load s | tree s | query ms (tree) | query ms (brute) | use peak MB | SP s/gap base | SP s/gap this | ratio |"
    );
    println!(
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    );
    for &n in &sizes {
        let b = child(&format!("build:{n}"));
        let u = child(&format!("use:{n}"));
        let size = std::fs::metadata(lib_path(n)).map_or(0, |m| m.len());
        let f = |m: &std::collections::HashMap<String, String>, k: &str| -> f64 {
            m[k].parse().unwrap_or(f64::NAN)
        };
        println!(
            "| {n} | {} | {} | {} | {} | {} | {} | {:.1} | {:.2} | {} | {} | {} | {} | {} | {} | {} | {:.2} |",
            b["frames"],
            b["build_s"],
            b["save_s"],
            b["peak_mb"],
            b["memory_mb"],
            b["bvh_mb"],
            size as f64 / 1e6,
            size as f64 / 1e6 / f(&b, "bvh_mb"),
            u["load_s"],
            u["tree_s"],
            u["query_ms"],
            u["brute_ms"],
            u["peak_mb"],
            u["sp_base_s"],
            u["sp_lib_s"],
            f(&u, "sp_lib_s") / f(&u, "sp_base_s")
        );
    }
}
