//! The motion algebra on real motion capture (every BVH file in
//! `data/mocap`): clips become motions of sampled curves, and the paper's
//! wave-into-walk expression, CSV and JSON work on them.

use crate::common;

use std::path::Path;
use std::sync::Arc;

use mx::io::csv::to_csv_string;
use mx::io::motion_json::{from_json_str, to_json_string};
use mx::mocap::bvh::{BvhFile, read_file};
use mx::motion::*;

/// A clip as a motion: one sampled-curve DOF per channel, `Joint.channel`
/// names, angles unwrapped (in degrees, as in the file — the algebra does not care).
fn clip_mu(path: &Path) -> (BvhFile, Mu) {
    let mut bvh = read_file(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    bvh.unwrap_rotations();
    let n = bvh.frame_count();
    let dt = bvh.frame_time;
    let end = (n - 1) as f64 * dt;
    let mu = bvh
        .skeleton
        .channel_names()
        .into_iter()
        .enumerate()
        .map(|(c, name)| {
            let curve = Curve::samples(0.0, dt, bvh.column(c)).unwrap();
            (name, Dof::from(Interval::curve(curve, 0.0, end).unwrap()))
        })
        .collect();
    (bvh, mu)
}

#[test]
fn every_clip_samples_back_its_frames_and_round_trips() {
    let files = common::shared_files("mocap", ".bvh");
    for path in &files {
        let (bvh, mu) = clip_mu(path);
        let n = bvh.frame_count();
        let names: Vec<String> = mu.names().map(str::to_string).collect();
        assert_eq!(mu.span(), Some((0.0, (n - 1) as f64 * bvh.frame_time)));
        // The interpolant passes through every frame, bit for bit.
        let mut worst: f64 = 0.0;
        for (c, name) in names.iter().enumerate().step_by(7) {
            let col = bvh.column(c);
            for f in (0..n).step_by(5) {
                let v = mu
                    .sample_value(name, f as f64 * bvh.frame_time)
                    .unwrap()
                    .unwrap();
                worst = worst.max((v - col[f]).abs() / (1.0 + col[f].abs()));
            }
        }
        assert!(
            worst == 0.0,
            "{}: interpolation misses a frame by {worst:e}",
            path.display()
        );
        // Exact JSON round trip of real data.
        let none = |_: &str| -> Result<Arc<dyn TimeFunction>, mx::io::ContentError> {
            Err("no functions".into())
        };
        let back = from_json_str(&to_json_string(&mu).unwrap(), &none).unwrap();
        assert!(
            back == mu,
            "{}: JSON round trip changed the motion",
            path.display()
        );
    }
}

#[test]
fn wave_pasted_into_walk_leaves_two_transition_gaps_per_arm_dof() {
    let Some(dir) = common::shared_dir() else {
        return;
    };
    let mocap = dir.join("data").join("mocap");
    let (_, walk) = clip_mu(&mocap.join("bandai2_walk_normal_001.bvh"));
    let (_, wave) = clip_mu(&mocap.join("bandai2_wave-right-hand_normal_001.bvh"));
    let arm = only(
        &wave,
        &[
            "Shoulder_R.*rotation",
            "*Arm_R.*rotation",
            "Hand_R.*rotation",
        ],
    )
    .unwrap();
    let (w0, w1) = walk.span().unwrap();
    let (_, a1) = arm.span().unwrap();
    // Fit the wave inside the walk: scale it to a third of the walk, with
    // 0.3 s of transition on each side (Rose Figure 6).
    let d = (w1 - w0) / 3.0 / a1;
    let at = w0 + (w1 - w0) / 3.0;
    let hole = affine(at - 0.3, (a1 * d + 0.6) / a1, &arm).unwrap();
    let inner = affine(at, d, &arm).unwrap();
    let m = plus(&inner, &minus(&walk, &hole));

    assert!(conflicts(&m).is_empty());
    let g = gaps(&m);
    assert_eq!(g.len(), 2 * arm.len());
    for gap in &g {
        assert!(
            arm.get(&gap.dof).is_some(),
            "gap in a non-arm DOF {}",
            gap.dof
        );
        assert!((gap.stop - gap.start - 0.3).abs() < 1e-9, "{gap:?}");
    }
    // Inside the pasted part, the arm follows the (time-scaled) wave.
    let name = arm.names().next().unwrap();
    let t = at + 0.5 * a1 * d;
    let got = m.sample(name, t).unwrap().unwrap();
    let want = arm.sample(name, 0.5 * a1).unwrap().unwrap();
    assert!((got[0] - want[0]).abs() < 1e-9);
    assert!((got[1] - want[1] / d).abs() < 1e-9 * (1.0 + want[1].abs()));
    // The CSV at 30 Hz: full rows, arm cells empty only in the gaps.
    let text = to_csv_string(&m, 30.0, None).unwrap();
    let rows: Vec<&str> = text.lines().collect();
    assert_eq!(rows.len() - 1, (w1 * 30.0 + 1e-9).floor() as usize + 1);
    let header: Vec<&str> = rows[0].split(',').collect();
    assert_eq!(header.len(), walk.len() + 1);
    let empty_cells: usize = rows[1..]
        .iter()
        .map(|r| r.split(',').filter(|c| c.is_empty()).count())
        .sum();
    // 0.3 s gaps at 30 Hz hold 8 or 9 grid times each (open ends are defined).
    assert!(
        empty_cells >= 8 * g.len() && empty_cells <= 10 * g.len(),
        "{empty_cells}"
    );
}
