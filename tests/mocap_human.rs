//! human(clip): 44 DOFs (6 root + 38 joint), limb lengths from the clip;
//! fit(clip, model): per-frame least squares on joint positions, with the
//! fit error measured and bounded.

mod common;

use mx::mocap::bvh::{self, Units};
use mx::mocap::human::{fit, human};
use mx::mocap::{Missing, positions};
use std::path::Path;
use std::time::Instant;

fn fit_file(path: &Path, frames: Option<usize>) -> (f64, f64, usize) {
    let mut f = bvh::read_file(path).unwrap();
    if let Some(n) = frames {
        let nch = f.skeleton.channel_count();
        f.values.truncate(n.min(f.frame_count()) * nch);
    }
    let s = bvh::detect_units(&f.skeleton).metres_per_unit;
    let h = human(&f.skeleton, s, 70.0).unwrap();
    assert_eq!(h.model.nq(), 44);
    assert!((h.model.total_mass() - 70.0).abs() < 1e-9);
    let root = h
        .model
        .coordinate_names()
        .iter()
        .filter(|n| n.starts_with("root."))
        .count();
    assert_eq!(root, 6);
    let t = Instant::now();
    let (mu, rep) = fit(&f, s, &h, None).unwrap();
    let secs = t.elapsed().as_secs_f64();
    assert_eq!(mu.len(), 44);
    // The fitted motion drives the model: its pelvis follows the clip's hips.
    let p = positions(&mu, &h.model, None, Missing::Error).unwrap();
    let pelvis = p.names.iter().position(|n| n == "pelvis").unwrap();
    let want = bvh::fk::world_positions(&f, f.frame_count() - 1, s);
    let hips = f.skeleton.find("Hips").unwrap();
    let last = p.points.len() - 1;
    assert!((p.points[last][pelvis] - want[hips]).norm() < 0.05);
    eprintln!(
        "{}: {} frames, {} landmarks, RMS {:.4} m, max {:.4} m, {:.2} s",
        path.file_name().unwrap().to_string_lossy(),
        f.frame_count(),
        rep.landmarks,
        rep.rms,
        rep.max,
        secs
    );
    (rep.rms, rep.max, f.frame_count())
}

#[test]
fn fits_the_example_walk_closely() {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/data/walk.bvh");
    let (rms, max, _) = fit_file(&p, None);
    assert!(rms < 0.03 && max < 0.08, "rms {rms} max {max}");
}

#[test]
fn fits_shared_bandai_and_cmu_clips() {
    let Some(d) = common::shared_dir() else {
        return;
    };
    for (name, bound) in [
        ("bandai1_walk_normal_001.bvh", 0.05),
        ("cmu_131_01_start_walk_stop.bvh", 0.05),
        ("bandai2_wave-right-hand_normal_001.bvh", 0.05),
    ] {
        let (rms, max, _) = fit_file(&d.join("data/mocap").join(name), Some(120));
        assert!(rms < bound, "{name}: rms {rms} m (max {max})");
    }
}

#[test]
fn non_humanoid_skeleton_is_a_clear_error() {
    let one = "HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nCHANNELS 1 Zrotation\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\n45\n";
    let f = bvh::parse(one).unwrap();
    let e = human(&f.skeleton, 0.01, 70.0).unwrap_err().to_string();
    assert!(e.contains("humanoid"), "{e}");
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/data/walk.bvh");
    let f = bvh::read_file(&p).unwrap();
    assert!(human(&f.skeleton, 0.01, -3.0).is_err());
    let _ = Units::Auto;
}
