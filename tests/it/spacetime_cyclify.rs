//! Cyclification (Rose §3.3) of the real walks in `$MX_SHARED/data/mocap`,
//! looped 10 times: the seam jumps in q, q̇, q̈ must be ≤ 1e-9, 1e-6, 1e-3.

use crate::common;

use mx::mocap::bvh::Units;
use mx::motion::Mu;
use mx::motion::cyclify::floor_drift;
use mx::motion::cyclify::{CyclifyOptions, cyclify, loop_motion};

/// Largest (|Δq|, |Δq̇|, |Δq̈|) where consecutive intervals touch, minus each DOF's
/// own per-cycle advance in q (a drifting root continues, it does not jump).
fn seam_jumps(m: &Mu) -> (f64, f64, f64) {
    let mut j = (0.0f64, 0.0f64, 0.0f64);
    for d in m.dofs.values() {
        for w in d.intervals.windows(2) {
            let a = w[0].funcs[0].eval(w[0].stop).unwrap();
            let b = w[1].funcs[0].eval(w[1].start).unwrap();
            j.0 = j.0.max((a[0] - b[0]).abs() / (1.0 + a[0].abs()));
            j.1 = j.1.max((a[1] - b[1]).abs());
            j.2 = j.2.max((a[2] - b[2]).abs());
        }
    }
    j
}

#[test]
fn cyclified_walks_loop_with_c2_seams() {
    let files: Vec<_> = common::shared_files("mocap", ".bvh")
        .into_iter()
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.contains("_walk_"))
        })
        .collect();
    if common::shared_dir().is_some() {
        assert!(!files.is_empty(), "no walk clips in data/mocap");
    }
    for path in files {
        let clip = mx::mocap::load(&path, Units::Auto).unwrap();
        // every horizontal position channel (y is up in BVH) keeps its advance per cycle
        let drift = floor_drift(&clip.mu);
        let opts = CyclifyOptions {
            drift,
            ..Default::default()
        };
        // about one walk cycle (two steps) starting at 1 s
        let (cyc, report) = cyclify(&clip.mu, 1.0, 2.1, &opts).unwrap();
        let looped = loop_motion(&cyc, 10).unwrap();
        let (jq, jv, ja) = seam_jumps(&looped);
        println!(
            "{}: cycle [{:.4}, {:.4}] s, ‖Δ[q,q̇,q̈]‖ {:.3} at the marks → {:.3}, largest spread jump {} {:.4}, {} coefficients; seams of 10 loops: q {jq:.1e} (relative), q̇ {jv:.1e}, q̈ {ja:.1e}",
            path.file_name().unwrap().to_string_lossy(),
            report.t1,
            report.t2,
            report.distance_at_marks,
            report.distance,
            report.max_jump.0,
            report.max_jump.1,
            report.coefficients
        );
        assert!(report.distance <= report.distance_at_marks);
        assert!(jq <= 1e-9 && jv <= 1e-6 && ja <= 1e-3, "{jq} {jv} {ja}");
        // the root keeps walking: 10 cycles cover 10 advances
        let (s, e) = looped.span().unwrap();
        let (root_x, adv) = report
            .drift
            .iter()
            .filter(|(n, _)| n.ends_with("Xposition"))
            .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
            .cloned()
            .unwrap();
        println!("  {root_x} advances {adv:.4} m per cycle");
        let x0 = looped.sample(&root_x, s).unwrap().unwrap()[0];
        let x1 = looped.sample(&root_x, e).unwrap().unwrap()[0];
        assert!((x1 - x0 - 10.0 * adv).abs() < 1e-6 * (1.0 + adv.abs()));
        // looping the raw clip is refused with a clear message
        assert!(
            loop_motion(&clip.mu, 2)
                .unwrap_err()
                .to_string()
                .contains("cyclify")
        );
    }
}

#[test]
fn bad_marks_are_clear_errors() {
    let Some(dir) = common::shared_dir() else {
        return;
    };
    let clip = mx::mocap::load(
        &dir.join("data/mocap/bandai1_walk_normal_001.bvh"),
        Units::Auto,
    )
    .unwrap();
    let o = CyclifyOptions::default();
    assert!(cyclify(&clip.mu, 2.0, 1.0, &o).is_err());
    assert!(cyclify(&clip.mu, 100.0, 101.0, &o).is_err());
    assert!(cyclify(&clip.mu, 1.0, 1.0, &o).is_err());
    assert!(loop_motion(&clip.mu, 0).is_err());
}
