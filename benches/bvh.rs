//! BVH load time of every shared clip (ms and frames/s): read + parse +
//! unwrap, and (`load` column) the whole conversion to a motion unit once
//! it exists. Prints a table, then the time `fit` takes to convert the
//! 1,901-frame dance to the 44-DOF model (positions only, and positions and
//! orientations), then divan times loading the dance (target: well under 50 ms).

use mx::mocap::bvh;
use std::path::{Path, PathBuf};
use std::time::Instant;

fn shared_mocap() -> Vec<PathBuf> {
    let dir = std::env::var_os("MX_SHARED")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared"))
        .join("data/mocap");
    let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    v.retain(|p| p.extension().is_some_and(|e| e == "bvh"));
    v.sort();
    if v.is_empty() {
        eprintln!("no shared clips at {} (set MX_SHARED)", dir.display());
    }
    v
}

fn load(path: &Path) -> bvh::BvhFile {
    let mut f = bvh::read_file(path).expect("shared clip loads");
    f.unwrap_rotations();
    f
}

/// `load("x.bvh")` as the language does it: parse, unwrap, build the MU.
fn load_mu(path: &Path) -> mx::mocap::Clip {
    mx::mocap::to_motion::load(path, bvh::Units::Auto).expect("shared clip loads")
}

fn main() {
    println!(
        "{:<45} {:>7} {:>10} {:>12} {:>10}",
        "clip", "frames", "parse ms", "frames/s", "MU ms"
    );
    for p in shared_mocap() {
        let runs = 5;
        let start = Instant::now();
        let mut frames = 0;
        for _ in 0..runs {
            frames = divan::black_box(load(&p)).frame_count();
        }
        let s = start.elapsed().as_secs_f64() / runs as f64;
        let start = Instant::now();
        for _ in 0..runs {
            divan::black_box(load_mu(&p));
        }
        let mu = start.elapsed().as_secs_f64() / runs as f64;
        println!(
            "{:<45} {:>7} {:>10.2} {:>12.0} {:>10.2}",
            p.file_name().unwrap_or_default().to_string_lossy(),
            frames,
            s * 1e3,
            frames as f64 / s,
            mu * 1e3
        );
    }
    fit_dance();
    divan::main();
}

/// One fit of the dance each way: seconds and ms per frame.
fn fit_dance() {
    use mx::mocap::human::{FitOptions, fit, human};
    let Some(p) = shared_mocap()
        .into_iter()
        .find(|p| p.to_string_lossy().contains("dance-short"))
    else {
        return;
    };
    let f = bvh::read_file(&p).expect("shared clip loads");
    let s = bvh::detect_units(&f.skeleton).metres_per_unit;
    let h = human(&f.skeleton, s, 70.0).expect("humanoid");
    println!(
        "\n{:<28} {:>7} {:>8} {:>9} {:>8} {:>8}",
        "fit of the dance", "frames", "s", "ms/frame", "RMS cm", "RMS deg"
    );
    for (what, w) in [("positions only", 0.0), ("positions + orientations", 0.1)] {
        let start = Instant::now();
        let (_, rep) = fit(&f, s, &h, FitOptions { angle_weight: w }, None).expect("fit");
        let secs = start.elapsed().as_secs_f64();
        println!(
            "{:<28} {:>7} {:>8.2} {:>9.2} {:>8.2} {:>8.1}",
            what,
            f.frame_count(),
            secs,
            secs * 1e3 / f.frame_count() as f64,
            rep.rms * 100.0,
            rep.angle_rms.to_degrees()
        );
    }
}

#[divan::bench(sample_count = 20)]
fn load_dance(b: divan::Bencher) {
    let Some(p) = shared_mocap()
        .into_iter()
        .find(|p| p.to_string_lossy().contains("dance-short"))
    else {
        return;
    };
    b.bench(|| load(&p));
}

#[divan::bench(sample_count = 20)]
fn load_dance_as_mu(b: divan::Bencher) {
    let Some(p) = shared_mocap()
        .into_iter()
        .find(|p| p.to_string_lossy().contains("dance-short"))
    else {
        return;
    };
    b.bench(|| load_mu(&p));
}
