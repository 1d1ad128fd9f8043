//! Stage 1, the root (Rose §3.2.1): its horizontal translations from the
//! interpolated velocities (the motion after the gap shifted to continue
//! them) or pinned where both sides look like one recording; its vertical
//! and rotations by Hermite curves. Grounded SP (see [`super::grounded`])
//! leaves the root's gaps inside one recording open instead: its six
//! coordinates are then unknowns of the transition like any gap DOF, both
//! ends fixed, and the ground's forces decide where the body goes.

use super::filling::{Filling, hermite_curve};
use super::options::{RootFill, root_tolerance};
use super::report::{FreeRoot, PinnedRoot, RootShift, Undefined};
use crate::model::RootCoords;
use crate::motion::{Dof, Func};
use crate::spacetime::error::SpError;
use crate::spacetime::root_path::RootTransition;
use crate::spacetime::transition::EndState;

/// Shift every interval of `dof` that starts at or after `t` by `delta` in value.
fn shift_after(dof: &mut Dof, t: f64, delta: f64) {
    for iv in dof.intervals.iter_mut() {
        if iv.start >= t - crate::motion::time_tol(t) {
            for f in iv.funcs.iter_mut() {
                *f = Func {
                    offset: f.offset + delta,
                    ..f.clone()
                };
            }
        }
    }
}

/// Fill the root's gaps (§3.2.1): horizontal translations from interpolated
/// velocities (shifting what follows), the vertical and rotations by Hermite.
/// With `free` (grounded SP) and `root: "auto"`, a gap that `"auto"` takes
/// for one recording is left open (all of the root's moving coordinates over
/// it), listed in the report's `free_root`: the transitions solve it. Two
/// recordings joined are still shifted (the frames after the gap are then
/// not where they were recorded, so nothing pins the root's end), and
/// `root: "shift"` / `"pinned"` ask for Rose's kinematic root.
pub(super) fn fill_root(f: &mut Filling<'_>, how: RootFill, free: bool) -> Result<(), SpError> {
    let root = f.root.clone();
    let root = &root;
    let pinned = pinned_gaps(f, root, how)?;
    let same = |t0: f64, t1: f64, a: f64, b: f64| {
        (a - t0).abs() <= crate::motion::time_tol(t0)
            && (b - t1).abs() <= crate::motion::time_tol(t1)
    };
    let is_pinned = |t0: f64, t1: f64| pinned.iter().any(|p| same(t0, t1, p.t0, p.t1));
    // spans a horizontal coordinate is cut over (those not pinned are shifted)
    let horizontal_spans: Vec<(f64, f64)> = root
        .horizontal
        .iter()
        .filter_map(|&c| f.motion.get(&f.names[c]))
        .flat_map(|d| d.gaps())
        .collect();
    let open = |t0: f64, t1: f64| {
        free && how == RootFill::Auto
            && (is_pinned(t0, t1) || !horizontal_spans.iter().any(|&(a, b)| same(t0, t1, a, b)))
    };
    let names = f.names;
    for &c in &root.all {
        let name = &names[c];
        let Some(dof) = f.motion.get(name) else {
            continue;
        };
        let gaps = dof.gaps();
        for (t0, t1) in gaps {
            // a constant placeholder above the root is bridged, never solved
            if open(t0, t1) && !root.fixed.contains(&c) {
                match f
                    .report
                    .free_root
                    .iter_mut()
                    .find(|r| same(t0, t1, r.t0, r.t1))
                {
                    Some(r) => r.dofs.push(name.clone()),
                    None => f.report.free_root.push(FreeRoot {
                        t0,
                        t1,
                        dofs: vec![name.clone()],
                    }),
                }
                continue;
            }
            let a = f.end_state(name, t0)?;
            let b = f.end_state(name, t1)?;
            let curve = if root.horizontal.contains(&c) && !is_pinned(t0, t1) {
                shift_root(f, name, (t0, t1), a, b)?
            } else {
                f.report.hermite.push(Undefined {
                    dof: name.clone(),
                    start: t0,
                    stop: t1,
                });
                hermite_curve(t0, t1, &a, &b)?
            };
            f.write(name, curve, t0, t1)?;
        }
    }
    // a pinned gap left open is the transitions', not a pin
    let free_spans = &f.report.free_root;
    let kept: Vec<PinnedRoot> = pinned
        .into_iter()
        .filter(|p| !free_spans.iter().any(|r| same(p.t0, p.t1, r.t0, r.t1)))
        .collect();
    f.report.pinned.extend(kept);
    Ok(())
}

/// Rose's path for one horizontal root coordinate over [t0, t1]: shifts the
/// motion after the gap to where the interpolated velocities end, records
/// the shift, and returns the gap's curve.
fn shift_root(
    f: &mut Filling<'_>,
    name: &str,
    (t0, t1): (f64, f64),
    a: EndState,
    b: EndState,
) -> Result<crate::motion::Curve, SpError> {
    // one horizontal component of p(t); y of RootTransition is unused here
    let rt = RootTransition::new(t0, t1, [a.q, 0.0], [a.v, 0.0], [b.v, 0.0], a, b)?;
    let shift = rt.end_xz()[0] - b.q;
    shift_after(f.dof_mut(name)?, t1, shift);
    // p(t) is the Hermite cubic with end value p(t2) and the same velocities
    let end = EndState {
        q: b.q + shift,
        ..b
    };
    match f.report.root.iter_mut().find(|r| r.t0 == t0 && r.t1 == t1) {
        Some(r) => r.shift.push((name.to_string(), shift)),
        None => f.report.root.push(RootShift {
            t0,
            t1,
            shift: vec![(name.to_string(), shift)],
        }),
    }
    hermite_curve(t0, t1, &a, &end)
}

/// The gaps of the root's horizontal coordinates that keep the motion after
/// them in place: all of them for [`RootFill::Pinned`], none for
/// [`RootFill::Shift`], and for [`RootFill::Auto`] those whose recorded x–z
/// displacement is within [`root_tolerance`] of T (v₀ + v₁)/2. Horizontal
/// coordinates gapped over the same span are judged together (their vector).
fn pinned_gaps(
    f: &Filling<'_>,
    root: &RootCoords,
    how: RootFill,
) -> Result<Vec<PinnedRoot>, SpError> {
    let names = f.names;
    // per gap span: (squared mismatch, squared predicted displacement)
    let mut spans: Vec<(f64, f64, f64, f64)> = vec![];
    for &c in &root.horizontal {
        let Some(dof) = f.motion.get(&names[c]) else {
            continue;
        };
        for (t0, t1) in dof.gaps() {
            let a = f.end_state(&names[c], t0)?;
            let b = f.end_state(&names[c], t1)?;
            let predicted = (t1 - t0) * (a.v + b.v) / 2.0;
            let off = (b.q - a.q) - predicted;
            let same = |s: &&mut (f64, f64, f64, f64)| {
                (s.0 - t0).abs() <= crate::motion::time_tol(t0)
                    && (s.1 - t1).abs() <= crate::motion::time_tol(t1)
            };
            match spans.iter_mut().find(same) {
                Some(s) => {
                    s.2 += off * off;
                    s.3 += predicted * predicted;
                }
                None => spans.push((t0, t1, off * off, predicted * predicted)),
            }
        }
    }
    Ok(spans
        .into_iter()
        .filter_map(|(t0, t1, off2, pred2)| {
            let (mismatch, tolerance) = (off2.sqrt(), root_tolerance(pred2.sqrt()));
            let p = |auto| PinnedRoot {
                t0,
                t1,
                auto,
                mismatch,
                tolerance,
            };
            match how {
                RootFill::Shift => None,
                RootFill::Pinned => Some(p(false)),
                RootFill::Auto => (mismatch <= tolerance).then(|| p(true)),
            }
        })
        .collect())
}
#[cfg(test)]
mod tests {
    use super::super::fixture::{Y_UP, body, motion};
    use super::*;

    /// The root's x, y and rz gapped on (0.8, 1.2), the motion after the gap
    /// moved `dx` along x (recorded elsewhere in the room).
    fn gapped(dx: f64) -> (crate::model::Model, crate::motion::Mu) {
        let model = body();
        let mut m = motion(&model, &[0, 1, 2], (0.8, 1.2));
        let x = m.dofs.get_mut("x").unwrap();
        shift_after(x, 1.2, dx);
        (model, m)
    }

    fn fill(dx: f64, how: RootFill) -> Filling<'static> {
        fill_free(dx, how, false)
    }

    fn fill_free(dx: f64, how: RootFill, free: bool) -> Filling<'static> {
        let (model, m) = gapped(dx);
        let model: &'static crate::model::Model = Box::leak(Box::new(model));
        let m: &'static crate::motion::Mu = Box::leak(Box::new(m));
        let mut f = Filling::new(m, model, Y_UP);
        fill_root(&mut f, how, free).unwrap();
        f
    }

    #[test]
    fn grounded_sp_leaves_one_recordings_root_open_for_the_solve() {
        let f = fill_free(0.0, RootFill::Auto, true);
        assert_eq!(f.report.free_root.len(), 1, "{:?}", f.report);
        assert_eq!(f.report.free_root[0].dofs, ["x", "y", "rz"]);
        assert!(f.report.pinned.is_empty() && f.report.root.is_empty());
        assert!(f.report.hermite.is_empty());
        // the root's coordinates are gap DOFs, the frames after the gap as recorded
        let mut open: Vec<usize> = f.gaps().unwrap().iter().map(|d| d.coord).collect();
        open.sort_unstable();
        assert_eq!(open, [0, 1, 2]);
        let x = f.motion.sample_value("x", 1.5).unwrap().unwrap();
        assert!((x - 1.1 * 1.5).abs() < 1e-9, "{x}");
    }

    #[test]
    fn grounded_sp_still_joins_two_recordings_and_keeps_a_kinematic_root_asked_for() {
        // two recordings: shifted as before (nothing pins the end)
        let joined = fill_free(3.0, RootFill::Auto, true);
        assert!(joined.report.free_root.is_empty());
        assert_eq!(joined.report.root.len(), 1);
        // root: "shift" / "pinned": Rose's kinematic root, as without the ground
        for how in [RootFill::Shift, RootFill::Pinned] {
            let f = fill_free(0.0, how, true);
            let before = fill(0.0, how);
            assert!(f.report.free_root.is_empty());
            assert_eq!(f.report, before.report);
            assert!(f.gaps().unwrap().is_empty());
        }
    }

    #[test]
    fn one_recording_is_pinned_and_keeps_the_motion_after_the_gap() {
        let f = fill(0.0, RootFill::Auto);
        assert_eq!(f.report.pinned.len(), 1, "{:?}", f.report);
        assert!(f.report.pinned[0].auto && f.report.root.is_empty());
        let x = f.motion.sample_value("x", 1.5).unwrap().unwrap();
        assert!((x - 1.1 * 1.5).abs() < 1e-9, "{x}");
        // y and rz by Hermite; every root gap filled
        assert_eq!(f.report.hermite.len(), 3);
        assert!(f.gaps().unwrap().is_empty());
    }

    #[test]
    fn two_recordings_are_joined_by_shifting_the_one_after() {
        let f = fill(3.0, RootFill::Auto);
        assert!(f.report.pinned.is_empty());
        let r = &f.report.root;
        assert_eq!(r.len(), 1);
        let (name, shift) = &r[0].shift[0];
        assert_eq!(name, "x");
        // the walk continues at its own speed: the 3 m jump is taken back
        assert!((shift + 3.0).abs() < 0.01, "{shift}");
        let x = f.motion.sample_value("x", 1.5).unwrap().unwrap();
        assert!((x - 1.1 * 1.5).abs() < 0.01, "{x}");
        // asked for, a pin keeps even the jump
        let p = fill(3.0, RootFill::Pinned);
        assert!(!p.report.pinned[0].auto);
        let x = p.motion.sample_value("x", 1.5).unwrap().unwrap();
        assert!((x - (1.1 * 1.5 + 3.0)).abs() < 1e-9, "{x}");
    }
}
