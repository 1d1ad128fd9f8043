//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;

/// The folder holding `data/` (reference data from peers and motion capture):
/// `$MX_SHARED`, else `../shared` from the repository root.
///
/// Returns `None` when it is missing on a developer machine (the caller prints
/// why and returns), and panics when it is missing in CI (`CI=true`), so a
/// missing folder never passes silently there.
pub fn shared_dir() -> Option<PathBuf> {
    let dir = match std::env::var_os("MX_SHARED") {
        Some(d) => PathBuf::from(d),
        None => PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("..")
            .join("shared"),
    };
    if dir.join("data").is_dir() {
        return Some(dir);
    }
    let msg = format!(
        "shared data folder not found at {} (set MX_SHARED)",
        dir.display()
    );
    if std::env::var("CI").is_ok_and(|v| v == "true" || v == "1") {
        panic!("{msg}: required in CI");
    }
    eprintln!("SKIPPED: {msg}");
    None
}

/// Every file in `$MX_SHARED/data/<sub>` whose name ends with `suffix`, sorted.
/// The folder is the input: a file dropped there becomes a case.
pub fn shared_files(sub: &str, suffix: &str) -> Vec<PathBuf> {
    let Some(dir) = shared_dir() else {
        return vec![];
    };
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir.join("data").join(sub))
        .unwrap_or_else(|e| panic!("cannot read data/{sub}: {e}"))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.ends_with(suffix))
        })
        .collect();
    files.sort();
    assert!(
        !files.is_empty() || shared_dir().is_none(),
        "no *{suffix} files in data/{sub}"
    );
    files
}

/// `max|x − ref| / max(1, max|ref|)`: the relative error the reference
/// comparisons (Pinocchio, mimic joints) report.
pub fn rel_err(x: &[f64], r: &[f64]) -> f64 {
    let scale = r.iter().fold(1.0f64, |m, v| m.max(v.abs()));
    x.iter()
        .zip(r)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max)
        / scale
}

/// A JSON array of numbers (reference files); panics with what was expected.
pub fn json_f64s(v: &serde_json::Value) -> Vec<f64> {
    v.as_array()
        .expect("array")
        .iter()
        .map(|x| x.as_f64().expect("number"))
        .collect()
}

/// Largest position and velocity jumps where one interval of a DOF ends and
/// the next starts, over all DOFs: how continuously a fill joins the motion.
pub fn jumps(m: &mx::motion::Mu) -> (f64, f64) {
    let (mut jq, mut jv) = (0.0f64, 0.0f64);
    for d in m.dofs.values() {
        for w in d.intervals.windows(2) {
            if (w[1].start - w[0].stop).abs() < 1e-12 {
                let a = w[0].funcs[0].eval(w[0].stop).unwrap();
                let b = w[1].funcs[0].eval(w[1].start).unwrap();
                jq = jq.max((a[0] - b[0]).abs());
                jv = jv.max((a[1] - b[1]).abs());
            }
        }
    }
    (jq, jv)
}

/// Whether the tests run in CI (`CI=true` or `1`), where missing tools fail.
pub fn in_ci() -> bool {
    std::env::var("CI").is_ok_and(|v| v == "true" || v == "1")
}

/// A Python that imports `bpy` (Blender 5 as a module): `MX_BPY_PYTHON`, else
/// `target/bpyenv/bin/python` (`scripts/test` installs bpy 5.0.1 there, apart
/// from the package's venv: bpy pins numpy 1.26, pandas 3 needs numpy 2).
/// `None` with a note on a developer machine without it; a panic in CI.
pub fn blender_python() -> Option<PathBuf> {
    let py = std::env::var_os("MX_BPY_PYTHON")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("target/bpyenv/bin/python"));
    let ok = Command::new(&py)
        .args(["-c", "import bpy"])
        .output()
        .is_ok_and(|o| o.status.success());
    if ok {
        return Some(py);
    }
    let msg = format!(
        "no Python with bpy at {} (scripts/test installs it)",
        py.display()
    );
    assert!(!in_ci(), "{msg}: required in CI");
    eprintln!("SKIPPED: {msg}");
    None
}
