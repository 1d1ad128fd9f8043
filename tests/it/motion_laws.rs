//! The laws of the animator's operators on captured clips (issue 28): a
//! blend of a clip with itself is the clip, `blend(a, b, 0) = a`,
//! `blend(a, b, 1) = b`, a crossfade is a before its overlap and the aligned
//! b after it, `layer(b, d, 0) = b`, `mask(m, …, 1) = m`, and mirror and
//! reverse are their own inverses: each to 1e-9 on every DOF of every shared
//! BVH, at the frames and between them (a resampled result would pass at the
//! frames only).

use crate::common;

use mx::mocap::bvh::Units;
use mx::motion::compose::{self, Weight};
use mx::motion::*;

const TOL: f64 = 1e-9;

/// Times over [s, e]: every frame step split in three, so most fall between frames.
fn times(s: f64, e: f64, frame: f64) -> Vec<f64> {
    let n = ((e - s) / (frame / 3.0)).ceil() as usize;
    (0..=n).map(|k| s + (e - s) * k as f64 / n as f64).collect()
}

/// The largest |a − b| over `a`'s DOFs at `ts`, relative to max(1, |b|),
/// with the DOF and time where it is.
fn worst(a: &Mu, b: &Mu, ts: &[f64]) -> (f64, String, f64) {
    let mut w = (0.0, String::new(), 0.0);
    for n in a.names() {
        for &t in ts {
            let x = a.sample_value(n, t).unwrap().unwrap();
            let y = b.sample_value(n, t).unwrap().unwrap();
            let d = (x - y).abs() / y.abs().max(1.0);
            if d > w.0 {
                w = (d, n.to_string(), t);
            }
        }
    }
    w
}

fn assert_same(what: &str, a: &Mu, b: &Mu, ts: &[f64]) {
    assert_eq!(
        a.names().collect::<Vec<_>>(),
        b.names().collect::<Vec<_>>(),
        "{what}: DOF names"
    );
    let (d, dof, t) = worst(a, b, ts);
    assert!(d <= TOL, "{what}: {dof} differs by {d:e} at t = {t}");
}

/// Each shared clip: its motion, frame step, and two windows of it, 2 s
/// each (shorter for short clips), both moved to start at 0.
fn clips() -> Vec<(String, Mu, f64, Mu, Mu)> {
    common::shared_files("mocap", ".bvh")
        .iter()
        .map(|path| {
            let name = path.file_name().unwrap().to_string_lossy().to_string();
            let c = mx::mocap::to_motion::load(path, Units::Auto).unwrap();
            let (s, e) = c.mu.span().unwrap();
            let len = 2.0f64.min((e - s) / 3.0);
            let a = clip(s + len, s + 2.0 * len, &c.mu).unwrap();
            let b = clip(s + 1.5 * len, s + 2.5 * len, &c.mu).unwrap();
            (name, c.mu, c.frame_time, a, b)
        })
        .collect()
}

#[test]
fn blending_a_clip_with_itself_changes_nothing() {
    for (name, _, frame, a, _) in clips() {
        let (s, e) = a.span().unwrap();
        let ts = times(s, e, frame);
        for w in [0.25, 0.5, 0.9] {
            let m = compose::blend(&a, &a, &Weight::Const(w)).unwrap();
            assert_same(&format!("{name}: blend(c, c, {w})"), &m, &a, &ts);
        }
    }
}

#[test]
fn blend_at_zero_is_a_and_at_one_is_b() {
    for (name, _, frame, a, b) in clips() {
        let (s, e) = a.span().unwrap();
        let ts = times(s, e, frame);
        let m0 = compose::blend(&a, &b, &Weight::Const(0.0)).unwrap();
        assert_same(&format!("{name}: blend(a, b, 0)"), &m0, &a, &ts);
        let m1 = compose::blend(&a, &b, &Weight::Const(1.0)).unwrap();
        assert_same(&format!("{name}: blend(a, b, 1)"), &m1, &b, &ts);
    }
}

#[test]
fn a_crossfade_is_a_before_its_overlap_and_aligned_b_after_it() {
    for (name, _, frame, a, b) in clips() {
        let (a0, a1) = a.span().unwrap();
        let (b0, b1) = b.span().unwrap();
        let d = (a1 - a0) / 4.0;
        let up = 1; // BVH: y up
        let m = compose::crossfade(&a, &b, d, up).unwrap();
        let before = clip_in_place(a0, a1 - d, &a).unwrap();
        let ts = times(a0, a1 - d, frame);
        assert_same(&format!("{name}: crossfade before"), &before, &m, &ts);
        let shifted = affine(a1 - d - b0, 1.0, &b).unwrap();
        let aligned = compose::align_at(&a, a1 - d, &shifted, up).unwrap();
        let end = a1 - d + (b1 - b0);
        let after = clip_in_place(a1, end, &aligned).unwrap();
        let ts = times(a1, end, frame);
        assert_same(&format!("{name}: crossfade after"), &after, &m, &ts);
    }
}

#[test]
fn layer_at_zero_and_mask_at_one_change_nothing() {
    for (name, _, frame, a, b) in clips() {
        let (s, e) = a.span().unwrap();
        let ts = times(s, e, frame);
        let l = compose::layer(&a, &b, 0.0, None).unwrap();
        assert_same(&format!("{name}: layer(a, d, 0)"), &l, &a, &ts);
        let m = compose::mask(&a, &["*"], 1.0).unwrap();
        assert_same(&format!("{name}: mask(a, *, 1)"), &m, &a, &ts);
    }
}

#[test]
fn mirror_and_reverse_are_their_own_inverses() {
    for (name, whole, frame, a, _) in clips() {
        for m in [&whole, &a] {
            let (s, e) = m.span().unwrap();
            let ts = times(s, e, frame);
            for axis in 0..3 {
                let mm = compose::mirror(&compose::mirror(m, axis).unwrap(), axis).unwrap();
                assert_same(&format!("{name}: mirror∘mirror ({axis})"), &mm, m, &ts);
            }
            let rr = compose::reverse(&compose::reverse(m).unwrap()).unwrap();
            assert_same(&format!("{name}: reverse∘reverse"), &rr, m, &ts);
        }
    }
}
