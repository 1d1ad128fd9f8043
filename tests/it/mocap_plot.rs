//! Plots of loaded motion: curves, and gaps marked where a wave was cut out.

use mx::io::plot;
use mx::mocap::{bvh::Units, to_motion};
use mx::motion::{Dof, Interval, Mu};
use std::path::Path;

#[test]
fn plot_of_a_motion_with_a_gap_marks_it() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/data/walk.bvh");
    let clip = to_motion::load(&path, Units::Auto).unwrap();
    let hole: Mu = [(
        "RightArm.Zrotation".to_string(),
        Dof::new(vec![Interval::constant(0.0, 0.5, 1.0).unwrap()]).unwrap(),
    )]
    .into_iter()
    .collect();
    let cut = mx::motion::minus(&clip.mu, &hole);
    let s = plot::series_of(&cut, &["RightArm.Zrotation", "LeftUpLeg.Xrotation"], 30.0).unwrap();
    assert_eq!(s[0].pieces.len(), 2);
    assert_eq!(s[0].gaps.len(), 1);
    assert!((s[0].gaps[0].0 - 0.5).abs() < 1e-9 && (s[0].gaps[0].1 - 1.0).abs() < 1e-9);
    assert!(s[1].gaps.is_empty());
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("walk.svg");
    plot::plot_motion(
        &cut,
        &["RightArm.Zrotation", "LeftUpLeg.Xrotation"],
        30.0,
        &out,
    )
    .unwrap();
    let svg = std::fs::read_to_string(&out).unwrap();
    assert!(svg.contains("RightArm.Zrotation") && svg.contains("#E1E1E1"));
    // Every DOF by default; an unknown DOF is a clear error.
    plot::plot_motion(&clip.mu, &[], 30.0, &out).unwrap();
    let e = plot::plot_motion(&clip.mu, &["RightArm.Zrot"], 30.0, &out)
        .unwrap_err()
        .to_string();
    assert!(e.contains("RightArm.Zrot"), "{e}");
    let t = plot::terminal(&s, 60, 10);
    assert!(t.contains('░'));
}
