//! The motion's own example for a gap: the stretch of the same motion, a
//! shift Δ away, whose frames around it look most like the frames around the
//! gap. A walk or a run repeats itself; what the person did in the gap is
//! then best told by what they did one cycle earlier or later, which no end
//! state carries (two interpolated ends cannot make a step).
//!
//! SP's prior follows the example's velocities and accelerations instead of
//! zero ([`super::sp::Prior`]): it is minimised by the example plus the
//! smooth correction that meets the gap's end states. A motion that does not
//! repeat (a bow, a wave) has no stretch that matches well, and then the
//! prior stays the plain one.

use super::error::SpError;
use super::objective::GapDof;
use crate::motion::Mu;
use std::f64::consts::PI;

/// Grid step (s) the motion is compared on: a capture's usual frame time.
const STEP: f64 = 1.0 / 30.0;

/// Context (s) compared on each side of the gap: the in-betweening protocol's
/// ten frames at 30 Hz (`$MX_SHARED/data/inbetween/README.md`).
const CONTEXT: f64 = 0.3;

/// How far (s) from the gap an example is looked for: a long recording is
/// searched only this near the gap (the cost is linear in the span).
const SEARCH_SPAN: f64 = 30.0;

/// Longest gap (s) an example is looked for: a cycle copied from the same
/// motion tells nothing over longer, and the search's grid grows with it.
const MAX_GAP: f64 = 10.0;

/// Fewest context samples worth comparing (both sides together).
const MIN_CONTEXT_SAMPLES: usize = 4;

/// Largest mismatch ρ (see [`Example::mismatch`]) of an accepted example.
/// Measured by `cargo bench --bench inbetween` (50 shared clips, one window
/// each, root given): with ρ ≤ 0.5 instead, SP came 0.81 × Hermite at
/// 30-frame gaps against 0.76 here (before [`Example::trust`]); in a first
/// look, with the example alone corrected to its ends, windows with ρ between
/// 1 and 3 came farther from the capture than Hermite in 7 of 9 (a turning
/// walk whose cycles differ).
pub const MAX_MISMATCH: f64 = 1.0;

/// Largest difference (rad) between a DOF and its example at either end of
/// the gap for the DOF to follow it: the prior's motion is the example plus
/// a smooth ramp between the two end differences, so it stays this close to
/// poses the person took. A joint with a channel farther off keeps the plain
/// prior on all its channels (channel by channel, a kick's spine turned
/// 1.6 rad away from any pose of the clip: one Euler channel followed and its
/// siblings did not). With 0.15 a walk's toe ended 67 cm off where one leg
/// joint followed and the next did not; with no limit a punch's upper arm
/// turned 0.62 rad from its sides (`tests/it/inbetween.rs` allows 0.48).
pub const MAX_END_DIFFERENCE: f64 = 0.25;

/// A rotation coordinate that turns by more than this between two grid
/// samples is taken to wrap (±π in the data), and such a stretch is no example.
const MAX_TURN_PER_STEP: f64 = PI / 2.0;

/// The stretch of the motion a group of gaps follows.
#[derive(Clone, Debug, PartialEq)]
pub struct Example {
    /// Δ (s): the gap at t follows the motion at t + Δ.
    pub shift: f64,
    /// ρ: over the context on both sides of the gap, the squared difference
    /// between the motion and the motion Δ away, over the context's own
    /// squared spread about its mean (rotation coordinates, angles wrapped).
    /// 0 is a perfect repeat; 1 is no better than the context's mean pose.
    pub mismatch: f64,
    /// The model coordinates that follow it: those within
    /// [`MAX_END_DIFFERENCE`] of it at both ends of the gap.
    pub follow: Vec<usize>,
    /// The group's gap coordinates (followers or not).
    pub of: usize,
}

impl Example {
    /// How much of the example the prior follows: 1 − ρ, all of a perfect
    /// repeat and less of a looser match, so that a context that matched
    /// by chance (a step the person did not take in the gap) weighs little.
    pub fn trust(&self) -> f64 {
        (1.0 - self.mismatch).clamp(0.0, 1.0)
    }
}

/// The best example for `gaps` (one group: they share the span the example
/// must cover), or `None` when no stretch of `m` is defined around a shifted
/// copy of the gap, or none matches within [`MAX_MISMATCH`].
///
/// `names[c]` is the DOF of model coordinate c; `rotation(c)` says whether it
/// is an angle (only angles are compared: translations are in the motion's
/// own units and mostly bone offsets).
pub fn find(
    m: &Mu,
    names: &[String],
    rotation: &dyn Fn(usize) -> bool,
    gaps: &[GapDof],
) -> Result<Option<Example>, SpError> {
    let (Some(t0), Some(t1)) = (
        gaps.iter().map(|g| g.t0).reduce(f64::min),
        gaps.iter().map(|g| g.t1).reduce(f64::max),
    ) else {
        return Ok(None);
    };
    // a zero-length gap (or a degenerate span) has no stretch to copy, nor
    // has one longer than any cycle
    if !(t1 - t0 > 1e-9 && t1 - t0 <= MAX_GAP) {
        return Ok(None);
    }
    let Some((start, stop)) = m.span() else {
        return Ok(None);
    };
    let (start, stop) = (start.max(t0 - SEARCH_SPAN), stop.min(t1 + SEARCH_SPAN));
    // the grid: t0 + k h, with the gap's end on it
    let n = ((t1 - t0) / STEP).round().max(1.0) as i64;
    let h = (t1 - t0) / n as f64;
    let k_lo = ((start - t0) / h).ceil() as i64;
    let k_hi = ((stop - t0) / h).floor() as i64;
    if k_hi - k_lo < 2 * n {
        return Ok(None);
    }
    let mut coords: Vec<usize> = gaps.iter().map(|g| g.coord).collect();
    coords.sort_unstable();
    coords.dedup();
    let angles: Vec<bool> = coords.iter().map(|&c| rotation(c)).collect();
    if !angles.iter().any(|&a| a) {
        return Ok(None);
    }
    // every gap coordinate on the grid, NaN where undefined
    let len = (k_hi - k_lo + 1) as usize;
    let mut x = vec![vec![f64::NAN; len]; coords.len()];
    for (row, &c) in x.iter_mut().zip(&coords) {
        for (j, v) in row.iter_mut().enumerate() {
            let t = (t0 + (k_lo + j as i64) as f64 * h).clamp(start, stop);
            if let Some(s) = m
                .sample(&names[c], t)
                .map_err(|e| SpError::Evaluation(e.to_string()))?
            {
                *v = s[0];
            }
        }
    }
    let at = |k: i64| (k - k_lo) as usize;
    // whether every gap coordinate is defined at each grid point (once: the
    // shift search asks it for every point of every candidate window)
    let everywhere: Vec<bool> = (0..len)
        .map(|j| x.iter().all(|row| row[j].is_finite()))
        .collect();
    let defined = |k: i64| k >= k_lo && k <= k_hi && everywhere[at(k)];
    // the context: up to CONTEXT before t0 and after t1, where defined
    let reach = (CONTEXT / h).round() as i64;
    let before: Vec<i64> = (0..=reach)
        .map(|j| -j)
        .take_while(|&k| defined(k))
        .collect();
    let after: Vec<i64> = (0..=reach)
        .map(|j| n + j)
        .take_while(|&k| defined(k))
        .collect();
    let context: Vec<i64> = before.iter().chain(&after).copied().collect();
    if context.len() < MIN_CONTEXT_SAMPLES {
        return Ok(None);
    }
    let lo = before.last().copied().unwrap_or(0);
    let hi = after.last().copied().unwrap_or(n);
    let wrap = |d: f64| (d + PI).rem_euclid(2.0 * PI) - PI;
    // the context's spread about its mean pose
    let mut spread = 0.0;
    for (row, _) in x.iter().zip(&angles).filter(|(_, a)| **a) {
        let first = row[at(context[0])];
        let rel: Vec<f64> = context.iter().map(|&k| wrap(row[at(k)] - first)).collect();
        let mean = rel.iter().sum::<f64>() / rel.len() as f64;
        spread += rel.iter().map(|r| (r - mean) * (r - mean)).sum::<f64>();
    }
    if spread <= 0.0 {
        return Ok(None);
    }
    let mut best: Option<(i64, f64)> = None;
    for s in (k_lo - lo)..=(k_hi - hi) {
        // the shifted window must lie wholly in defined, unwrapped data
        if s == 0 || !(lo..=hi).all(|k| defined(k + s)) {
            continue;
        }
        let wraps = x.iter().zip(&angles).filter(|(_, a)| **a).any(|(row, _)| {
            (lo..hi).any(|k| (row[at(k + s + 1)] - row[at(k + s)]).abs() > MAX_TURN_PER_STEP)
        });
        if wraps {
            continue;
        }
        let mut e = 0.0;
        for (row, _) in x.iter().zip(&angles).filter(|(_, a)| **a) {
            for &k in &context {
                let d = wrap(row[at(k + s)] - row[at(k)]);
                e += d * d;
            }
        }
        let rho = e / spread;
        if best.is_none_or(|(_, b)| rho < b) {
            best = Some((s, rho));
        }
    }
    let Some((s, rho)) = best.filter(|(_, rho)| *rho <= MAX_MISMATCH) else {
        return Ok(None);
    };
    // A joint's channels follow together or not at all: one Euler channel
    // following and its siblings not is a rotation neither side has.
    let joint = |c: usize| {
        names[c]
            .rsplit_once('.')
            .map_or(names[c].as_str(), |(j, _)| j)
    };
    let close: Vec<bool> = x
        .iter()
        .map(|row| {
            [0, n]
                .iter()
                .all(|&k| wrap(row[at(k + s)] - row[at(k)]).abs() <= MAX_END_DIFFERENCE)
        })
        .collect();
    let follow: Vec<usize> = coords
        .iter()
        .filter(|&&c| {
            coords
                .iter()
                .zip(&close)
                .all(|(&o, &ok)| ok || joint(o) != joint(c))
        })
        .copied()
        .collect();
    if follow.is_empty() {
        return Ok(None);
    }
    Ok(Some(Example {
        shift: s as f64 * h,
        mismatch: rho,
        follow,
        of: coords.len(),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::{Curve, Dof, Interval};
    use crate::spacetime::EndState;

    /// A motion of `f` sampled at 30 Hz over [0, 6] s with a gap (2, 3).
    fn with_gap(names: &[&str], f: &dyn Fn(usize, f64) -> f64) -> (Mu, Vec<GapDof>) {
        let dt = 1.0 / 30.0;
        let mut m = Mu::new();
        let mut gaps = vec![];
        for (c, name) in names.iter().enumerate() {
            let piece = |a: usize, b: usize| {
                let v: Vec<f64> = (a..=b).map(|k| f(c, k as f64 * dt)).collect();
                let curve = Curve::samples(a as f64 * dt, dt, v).unwrap();
                Interval::curve(curve, a as f64 * dt, b as f64 * dt).unwrap()
            };
            m.insert(
                name.to_string(),
                Dof::new(vec![piece(0, 60), piece(90, 180)]).unwrap(),
            );
            let end = |t: f64| EndState {
                q: f(c, t),
                v: 0.0,
                a: 0.0,
            };
            gaps.push(GapDof {
                coord: c,
                t0: 2.0,
                t1: 3.0,
                start: end(2.0),
                end: end(3.0),
            });
        }
        (m, gaps)
    }

    #[test]
    fn a_periodic_motion_follows_itself_a_whole_number_of_periods_away() {
        let period = 1.2;
        let f = |c: usize, t: f64| (2.0 * PI * t / period + c as f64).sin() * 0.8;
        let names = ["a", "b"];
        let (m, gaps) = with_gap(&names, &f);
        let names: Vec<String> = names.iter().map(|s| s.to_string()).collect();
        let ex = find(&m, &names, &|_| true, &gaps)
            .unwrap()
            .expect("an example");
        let periods = ex.shift / period;
        assert!((periods - periods.round()).abs() < 0.03, "{ex:?}");
        assert!(ex.mismatch < 1e-3, "{ex:?}");
        assert_eq!((ex.follow, ex.of), (vec![0, 1], 2));
    }

    #[test]
    fn a_dof_far_from_its_example_at_an_end_keeps_the_plain_prior() {
        // a, c, d repeat every second; b drifts 0.15 rad/s, so every copy of
        // it far enough away to clear the gap (2 s or more) is 0.3 rad off
        let f = |c: usize, t: f64| {
            (2.0 * PI * t + c as f64).sin() * 0.8 + if c == 1 { 0.15 * t } else { 0.0 }
        };
        let names = ["a", "b", "c", "d"];
        let (m, gaps) = with_gap(&names, &f);
        let names: Vec<String> = names.iter().map(|s| s.to_string()).collect();
        let ex = find(&m, &names, &|_| true, &gaps)
            .unwrap()
            .expect("an example");
        assert!((ex.shift - ex.shift.round()).abs() < 0.05, "{ex:?}");
        assert_eq!((ex.follow, ex.of), (vec![0, 2, 3], 4));
    }

    #[test]
    fn a_zero_length_or_huge_gap_has_no_example() {
        let f = |_: usize, t: f64| (2.0 * PI * t).sin();
        let names = ["a"];
        let (m, mut gaps) = with_gap(&names, &f);
        gaps[0].t1 = gaps[0].t0;
        let names: Vec<String> = names.iter().map(|s| s.to_string()).collect();
        assert_eq!(find(&m, &names, &|_| true, &gaps).unwrap(), None);
        // nor one longer than any cycle (whose grid would be huge)
        gaps[0].t1 = gaps[0].t0 + 1e7;
        assert_eq!(find(&m, &names, &|_| true, &gaps).unwrap(), None);
        assert_eq!(find(&m, &names, &|_| true, &[]).unwrap(), None);
    }

    #[test]
    fn a_motion_that_never_repeats_has_no_example() {
        // a slow turn: every other stretch is a different pose
        let f = |c: usize, t: f64| 0.3 * t + 0.1 * c as f64;
        let names = ["a"];
        let (m, gaps) = with_gap(&names, &f);
        let names: Vec<String> = names.iter().map(|s| s.to_string()).collect();
        assert_eq!(find(&m, &names, &|_| true, &gaps).unwrap(), None);
        // nor a motion without angles, nor one too short to hold a copy
        assert_eq!(find(&m, &names, &|_| false, &gaps).unwrap(), None);
    }

    #[test]
    fn a_stretch_through_a_wrapped_angle_is_no_example() {
        // periodic, but every copy outside the gap crosses a ±π wrap
        let period = 1.0;
        let f = |_: usize, t: f64| {
            let u = (2.0 * PI * t / period).sin() * 0.5;
            if (t - 2.5).abs() > 0.6 && (t / period).fract() > 0.45 && (t / period).fract() < 0.55 {
                u + 2.0 * PI
            } else {
                u
            }
        };
        let names = ["a"];
        let (m, gaps) = with_gap(&names, &f);
        let names: Vec<String> = names.iter().map(|s| s.to_string()).collect();
        if let Some(ex) = find(&m, &names, &|_| true, &gaps).unwrap() {
            // any example left must avoid every wrap
            let k = (ex.shift * 30.0).round() as i64;
            for j in -9..=39 {
                let t = 2.0 + (j + k) as f64 / 30.0;
                let y = m.sample("a", t).unwrap().unwrap()[0];
                assert!(y.abs() < 1.0, "{ex:?} crosses a wrap at {t}");
            }
        }
    }
}
