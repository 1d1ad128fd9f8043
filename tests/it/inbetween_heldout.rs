//! The in-betweening bench's held-out runs (`mx::report::heldout`): clips of
//! other folders read at the protocol's 30 fps whatever rate they were
//! captured at, time warps and mirrors made from them, the clip filter of
//! the fast modes, and results that do not depend on the thread count.

use crate::common;

use mx::report::heldout::{self, ClipFilter};
use mx::report::inbetween::{self, Case, Method, PROTOCOL_RATE, Protocol, RootMode};

fn mocap_files() -> Vec<std::path::PathBuf> {
    common::shared_files("mocap", ".bvh")
}

fn value(c: &Case, dof: &str, t: f64) -> f64 {
    c.capture.sample(dof, t).unwrap().unwrap()[0]
}

/// Every clip of `data/mocap` (Bandai at 30 fps, CMU at 120 Hz, another
/// skeleton) reads at 30 fps: frame k is the clip's own pose at k/30 s, the
/// span is kept, and its foot joints are found by name on either skeleton.
#[test]
fn every_held_out_clip_reads_at_the_protocols_rate() {
    let files = mocap_files();
    let mut resampled = 0;
    for path in &files {
        let own = Case::load(path).unwrap();
        let at = Case::load_at(path, Some(PROTOCOL_RATE)).unwrap();
        // a clip within 0.1 % of the rate keeps its own frames (a BVH's
        // 0.033333 s), any other is resampled to exactly 1/30 s
        let dt = at.frame_time;
        assert!(
            (dt - 1.0 / PROTOCOL_RATE).abs() <= 1e-3 / PROTOCOL_RATE,
            "{}",
            own.name
        );
        let span = (own.frames - 1) as f64 * own.frame_time;
        let last = (at.frames - 1) as f64 * dt;
        assert!(
            last <= span + 1e-9 && span - last < dt,
            "{}: {last} of {span} s",
            own.name
        );
        if (own.frame_time - dt).abs() > 1e-12 {
            resampled += 1;
        }
        for (dof, _) in own.capture.dofs.iter().take(12) {
            for k in [0, at.frames / 2, at.frames - 1] {
                let t = k as f64 * dt;
                let (a, b) = (value(&at, dof, t), value(&own, dof, t));
                assert!(
                    (a - b).abs() < 1e-9,
                    "{} {dof} frame {k}: {a} vs {b}",
                    own.name
                );
            }
        }
        let feet = mx::ground::contact_points(&at.body, None).unwrap();
        assert!(feet.len() >= 2, "{}: {} foot joints", own.name, feet.len());
        assert!(at.floor.is_finite(), "{}", own.name);
    }
    println!("{resampled} of {} clips resampled to 30 fps", files.len());
}

/// A time warp plays the clip `speed` times as fast (frame k is the
/// original at k·speed frames), keeps the source file's name for the
/// leave-one-out library, and a mirror of a mirror is the clip again.
#[test]
fn warps_and_mirrors_are_the_clip_replayed_and_reflected() {
    let Some(path) = mocap_files().into_iter().next() else {
        return;
    };
    let case = Case::load_at(&path, Some(PROTOCOL_RATE)).unwrap();
    let dt = case.frame_time;
    for speed in [0.8, 1.25] {
        let w = heldout::warped(&case, speed).unwrap();
        assert_eq!(w.source, case.name);
        assert!(w.name.contains(&case.name) && w.name != case.name);
        assert!((w.frame_time - dt).abs() < 1e-15);
        let expect = ((case.frames - 1) as f64 / speed + 1e-6).floor() as usize + 1;
        assert_eq!(w.frames, expect, "speed {speed}");
        for (dof, _) in case.capture.dofs.iter().take(8) {
            for k in [1, w.frames / 3, w.frames - 1] {
                let (a, b) = (
                    value(&w, dof, k as f64 * dt),
                    value(&case, dof, k as f64 * dt * speed),
                );
                assert!(
                    (a - b).abs() < 1e-9,
                    "{dof} speed {speed} frame {k}: {a} vs {b}"
                );
            }
        }
    }
    let m = heldout::mirrored(&case).unwrap();
    assert_eq!(
        (m.source.as_str(), m.frames),
        (case.name.as_str(), case.frames)
    );
    let back = heldout::mirrored(&m).unwrap();
    let mut moved = 0.0f64;
    for (dof, _) in &case.capture.dofs {
        for k in [0, case.frames / 2, case.frames - 1] {
            let t = k as f64 * dt;
            assert!(
                (value(&back, dof, t) - value(&case, dof, t)).abs() < 1e-6,
                "{dof} at {t}"
            );
            moved = moved.max((value(&m, dof, t) - value(&case, dof, t)).abs());
        }
    }
    assert!(moved > 1e-3, "the mirror changed nothing");
    // both sides have twins on every skeleton of the folder
    assert!(heldout::lateral_axis(&case.skeleton).is_some());
}

/// The fast modes' clip filter: globs on the file name (any may match), a
/// bad glob is an error naming it, locomotion alone keeps walk/run/dash/turn.
#[test]
fn the_clip_filter_keeps_globs_and_locomotion() {
    let f = ClipFilter::parse("walk*, *_run_*", false).unwrap();
    assert!(f.keeps("walk_fast") && f.keeps("bandai1_run_normal_001"));
    assert!(!f.keeps("bandai1_bow_normal_001"));
    assert!(ClipFilter::parse("", false).unwrap().keeps("anything"));
    let loco = ClipFilter::parse("", true).unwrap();
    assert!(loco.keeps("bandai2_walk-turn-left_normal_001") && loco.keeps("x_dash_y"));
    assert!(!loco.keeps("bandai1_bow_normal_001"));
    let e = ClipFilter::parse("walk*,[a-", false).unwrap_err();
    assert!(e.to_string().contains("[a-"), "{e}");
    let Some(dir) = common::shared_dir().map(|d| d.join("data").join("mocap")) else {
        return;
    };
    let all = heldout::clip_paths(std::slice::from_ref(&dir), &ClipFilter::default()).unwrap();
    assert_eq!(all.len(), mocap_files().len());
    let walks = heldout::clip_paths(
        std::slice::from_ref(&dir),
        &ClipFilter::parse("*walk*", false).unwrap(),
    )
    .unwrap();
    assert!(walks.len() < all.len());
    assert!(walks.iter().all(|p| p.to_string_lossy().contains("walk")));
    assert!(heldout::clip_paths(&[dir.join("no such folder")], &ClipFilter::default()).is_err());
}

/// Rows with the same SP options share one solve; a library row never does.
#[test]
fn identical_sp_options_are_solved_once() {
    use mx::spacetime::{RootFill, SpOptions};
    let pinned = SpOptions {
        root: RootFill::Pinned,
        ..Default::default()
    };
    let methods = [
        Method::Hermite,
        Method::Sp("a".into(), Box::default()),
        Method::Sp("b".into(), Box::default()),
        Method::Sp("c".into(), Box::new(pinned)),
    ];
    // the root given cuts no root channel: `root:` is moot there
    assert_eq!(
        inbetween::same_options(&methods, RootMode::Given),
        [None, None, Some(1), Some(1)]
    );
    assert_eq!(
        inbetween::same_options(&methods, RootMode::Filled),
        [None, None, Some(1), None]
    );
}

/// The windows run in parallel; every number but the time is the same on
/// one thread as on several, in the same order.
#[test]
fn results_do_not_depend_on_the_thread_count() {
    let files = mocap_files();
    let cases: Vec<Case> = files
        .iter()
        .take(2)
        .map(|p| Case::load_at(p, Some(PROTOCOL_RATE)).unwrap())
        .collect();
    if cases.is_empty() {
        return;
    }
    let p = Protocol {
        gaps: vec![15],
        windows_per_clip: Some(1),
        ..Protocol::default()
    };
    let methods = [
        Method::Hermite,
        Method::Sp(inbetween::SP_DEFAULTS.into(), Box::default()),
        Method::Sp(
            inbetween::TODAYS_SP.into(),
            Box::new(inbetween::todays_sp()),
        ),
    ];
    let on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| inbetween::run(&cases, &p, &methods, |_| {}).unwrap())
    };
    let (one, two) = (on(1), on(2));
    assert_eq!(one.len(), two.len());
    // the same rows in the same order; the numbers to rounding (SP's node
    // sums are split across threads, so their last bits may differ)
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-8 * a.abs().max(b.abs()) + 1e-12;
    for (a, b) in one.iter().zip(&two) {
        let key = |r: &inbetween::WindowResult| {
            (
                r.clip.clone(),
                r.start,
                r.gap,
                r.root,
                r.method.clone(),
                r.worst_joint.clone(),
            )
        };
        assert_eq!(key(a), key(b));
        for (x, y) in [
            (a.l2p, b.l2p),
            (a.worst, b.worst),
            (a.l2q, b.l2q),
            (a.npss, b.npss),
            (a.skate, b.skate),
            (a.bone, b.bone),
            (a.energy, b.energy),
            (a.penetration, b.penetration),
            (a.residual, b.residual),
            (a.residual_worst, b.residual_worst),
        ] {
            assert!(close(x, y) || (x.is_nan() && y.is_nan()), "{a:?}\n{b:?}");
        }
    }
}
