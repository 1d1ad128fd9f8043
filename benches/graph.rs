//! Transition-library throughput (`mx::graph::build`): pairs and transitions
//! per second at 1 and 2 threads on the first N shared in-betweening clips
//! (sorted by name), the time split between the point search and SP, and the
//! node-hours a library of 100, 1,000 and 10,000 clips would take at the
//! measured rate (pairs grow as n(n−1); a clip's search cost with its length², taken
//! here at the measured clips' mean length).
//!
//! Run: `cargo bench --bench graph`. Environment:
//! - `MX_GRAPH_BENCH_CLIPS=N`: clips of the subset (default 8; 50 is the whole folder);
//! - `MX_GRAPH_BENCH_THREADS=1,2`: thread counts to time;
//! - `MX_GRAPH_BENCH_K`, `MX_GRAPH_BENCH_THRESHOLD`: the library settings (default: `mx graph build`'s).

mod common;
use common::shared;

use mx::graph::{BuildOptions, Settings, Shard, build};
use std::path::PathBuf;

fn env_or<T: std::str::FromStr>(name: &str, default: T) -> T {
    std::env::var(name)
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

fn main() {
    let all_dir = shared().join("data").join("inbetween");
    let mut paths: Vec<PathBuf> = std::fs::read_dir(&all_dir)
        .unwrap_or_else(|e| panic!("{}: {e}", all_dir.display()))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "bvh"))
        .collect();
    paths.sort();
    let n: usize = env_or("MX_GRAPH_BENCH_CLIPS", 8);
    paths.truncate(n);
    let clips = tempfile::tempdir().unwrap();
    let mut frames = 0usize;
    for p in &paths {
        std::os::unix::fs::symlink(p, clips.path().join(p.file_name().unwrap())).unwrap();
        frames += mx::mocap::bvh::read_file(p).unwrap().frame_count();
    }
    let mean_frames = frames as f64 / paths.len() as f64;
    let settings = Settings {
        k: env_or("MX_GRAPH_BENCH_K", Settings::default().k),
        threshold: env_or("MX_GRAPH_BENCH_THRESHOLD", Settings::default().threshold),
        ..Settings::default()
    };
    let threads: Vec<usize> = std::env::var("MX_GRAPH_BENCH_THREADS")
        .unwrap_or_else(|_| "1,2".into())
        .split(',')
        .filter_map(|s| s.trim().parse().ok())
        .collect();
    println!(
        "{} clips ({mean_frames:.0} frames on average), {} ordered pairs, settings {settings:?}",
        paths.len(),
        paths.len() * (paths.len() - 1)
    );
    println!(
        "| threads | pairs | transitions | wall (s) | pairs/s | transitions/s | search (s) | SP (s) | SP share |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    let mut best_rate = 0.0f64;
    let mut per_pair_search = 0.0;
    let mut per_pair_sp = 0.0;
    for &t in &threads {
        let out = tempfile::tempdir().unwrap();
        let o = BuildOptions {
            clips: clips.path().to_path_buf(),
            out: out.path().to_path_buf(),
            settings: settings.clone(),
            shard: Shard::WHOLE,
            threads: Some(t),
            log: None,
            progress: false,
        };
        let s = build(&o).unwrap();
        let rate = s.pairs as f64 / s.wall_seconds;
        println!(
            "| {t} | {} | {} | {:.1} | {:.2} | {:.2} | {:.1} | {:.1} | {:.0} % |",
            s.pairs,
            s.transitions,
            s.wall_seconds,
            rate,
            s.transitions as f64 / s.wall_seconds,
            s.search_seconds,
            s.sp_seconds,
            100.0 * s.sp_seconds / (s.search_seconds + s.sp_seconds).max(1e-12)
        );
        if rate > best_rate {
            best_rate = rate;
            per_pair_search = s.search_seconds / s.pairs as f64;
            per_pair_sp = s.sp_seconds / s.pairs as f64;
        }
    }
    // projection at the best measured rate on this machine (one node)
    println!();
    println!(
        "projection at {best_rate:.2} pairs/s per node ({:.3} s search + {:.3} s SP per pair, thread-seconds):",
        per_pair_search, per_pair_sp
    );
    println!("| clips | ordered pairs | node-hours |");
    println!("| --- | --- | --- |");
    for clips in [100usize, 1_000, 10_000] {
        let pairs = clips * (clips - 1);
        println!(
            "| {clips} | {pairs} | {:.1} |",
            pairs as f64 / best_rate / 3600.0
        );
    }
}
