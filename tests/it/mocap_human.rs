//! human(clip): 44 DOFs (6 root + 38 joint), limb lengths from the clip;
//! fit(clip, model): per-frame least squares on joint positions and segment
//! orientations, with both errors measured and bounded on every shared clip.

use crate::common;

use mx::mocap::bvh::{self, Units};
use mx::mocap::human::{FitOptions, FitReport, fit, human};
use mx::mocap::{Missing, positions};
use std::path::Path;
use std::time::Instant;

fn fit_file(path: &Path, frames: Option<usize>, options: FitOptions) -> FitReport {
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
    let (mu, rep) = fit(&f, s, &h, options, None).unwrap();
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
        "{:<45} {:>5} frames, w {:.2} m/rad: {rep}, {:.2} s",
        path.file_name().unwrap().to_string_lossy(),
        f.frame_count(),
        rep.angle_weight,
        secs
    );
    rep
}

#[test]
fn fits_the_example_walk_closely() {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/data/walk.bvh");
    let r = fit_file(&p, None, FitOptions::default());
    assert!(r.rms < 0.03 && r.max < 0.08, "{r}");
    assert!(r.angle_rms < 10f64.to_radians(), "{r}");
}

/// Every clip in `$MX_SHARED/data/mocap` (the folder is the input), fitted
/// whole, on positions only and on positions and orientations. Matching
/// orientations must cut their error sharply and cost little in positions.
#[test]
fn fits_every_shared_clip_on_positions_and_angles() {
    for p in common::shared_files("mocap", ".bvh") {
        let name = p.file_name().unwrap().to_string_lossy().to_string();
        let before = fit_file(&p, None, FitOptions { angle_weight: 0.0 });
        let after = fit_file(&p, None, FitOptions::default());
        assert!(after.rms < 0.035 && after.max < 0.20, "{name}: {after}");
        assert!(after.angle_rms < 25f64.to_radians(), "{name}: {after}");
        assert!(
            after.angle_rms < 0.6 * before.angle_rms,
            "{name}: orientations {:.1}° → {:.1}°",
            before.angle_rms.to_degrees(),
            after.angle_rms.to_degrees()
        );
        assert!(after.rms < before.rms + 0.01, "{name}: {before} → {after}");
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
