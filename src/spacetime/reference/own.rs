//! The example from the motion itself: the shift Δ whose stretch's context
//! (the frames either side of the gap) matches the gap's own context best.

use super::pose::{Pose, PoseMetric};
use super::{
    CONTEXT, Example, Joints, MAX_END_DIFFERENCE, MAX_MISMATCH, MAX_TURN_PER_STEP,
    MIN_CONTEXT_SAMPLES, NoExample, SEARCH_SPAN, STEP, gap_coords, gap_span, span_seconds,
};
use crate::motion::Mu;
use crate::spacetime::error::SpError;
use crate::spacetime::objective::GapDof;

/// The best example for `gaps` (one group: they share the span the example
/// must cover), or `None` when no stretch of `m` is defined around a shifted
/// copy of the gap, or none matches within [`MAX_MISMATCH`]; joints by the
/// name convention ([`Joints::by_name`]).
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
    find_with(m, names, rotation, &Joints::by_name(names), gaps)
}

/// [`find`] with the coordinates' joints given: a joint's coordinates follow
/// the example together or not at all.
pub fn find_with(
    m: &Mu,
    names: &[String],
    rotation: &dyn Fn(usize) -> bool,
    joints: &Joints,
    gaps: &[GapDof],
) -> Result<Option<Example>, SpError> {
    Ok(search(m, names, rotation, joints, gaps)?.ok())
}

/// [`find_with`], saying why there is none.
pub(super) fn search(
    m: &Mu,
    names: &[String],
    rotation: &dyn Fn(usize) -> bool,
    joints: &Joints,
    gaps: &[GapDof],
) -> Result<Result<Example, NoExample>, SpError> {
    let grid = match Grid::sample(m, names, rotation, joints, gaps)? {
        Ok(g) => g,
        Err(why) => return Ok(Err(why)),
    };
    let Some(context) = grid.context() else {
        return Ok(Err(NoExample::NoContext));
    };
    // the context's spread about its mean pose
    let poses: Vec<Pose> = context.ks.iter().map(|&k| grid.pose(k).clone()).collect();
    let total = grid.metric.spread(&poses);
    if total <= 0.0 {
        return Ok(Err(NoExample::NoContext));
    }
    let Some((s, rho)) = grid.best_shift(&context, total) else {
        return Ok(Err(NoExample::NoStretch));
    };
    // (a NaN ρ is refused too)
    if rho.is_nan() || rho > MAX_MISMATCH {
        return Ok(Err(NoExample::NoMatch {
            best: rho,
            threshold: MAX_MISMATCH,
        }));
    }
    // which channels are close to the example at both gap ends (angles, a
    // joint's as one rotation: translations, the root's among them, are
    // compared once the example is laid in the world, `lay.rs`)
    let ends: Vec<Vec<f64>> = [0, grid.n]
        .iter()
        .map(|&k| grid.metric.angles(grid.pose(k + s), grid.pose(k)))
        .collect();
    let close: Vec<bool> = (0..grid.coords.len())
        .map(|i| grid.metric.close(i, &ends, MAX_END_DIFFERENCE))
        .collect();
    let follow = joints.whole(&grid.coords, &close);
    if follow.is_empty() {
        return Ok(Err(NoExample::FarAtEnds {
            start: f64::NAN,
            end: f64::NAN,
            angle: f64::NAN,
        }));
    }
    Ok(Ok(Example {
        shift: s as f64 * grid.h,
        mismatch: rho,
        follow,
        of: grid.coords.len(),
        clip: None,
        fit: None,
    }))
}

/// The gap coordinates sampled on the grid t0 + k h (the gap's ends on it),
/// as far as the search reaches.
struct Grid {
    /// Grid steps across the gap.
    n: i64,
    h: f64,
    k_lo: i64,
    k_hi: i64,
    coords: Vec<usize>,
    angles: Vec<bool>,
    /// Per gap coordinate, its value at every grid point, NaN where undefined.
    x: Vec<Vec<f64>>,
    /// Whether every gap coordinate is defined at each grid point (once: the
    /// shift search asks it for every point of every candidate window).
    everywhere: Vec<bool>,
    /// How poses are compared ([`PoseMetric`]), and the pose at each grid
    /// point (meaningful where `everywhere`).
    metric: PoseMetric,
    poses: Vec<Pose>,
}

/// The context: grid points up to [`CONTEXT`] before t0 and after t1
/// where the motion is defined, and the window they span.
struct Context {
    ks: Vec<i64>,
    lo: i64,
    hi: i64,
}

impl Grid {
    /// Why not when the span is no example's, the motion cannot hold a
    /// shifted copy of it, or no gap coordinate is an angle.
    fn sample(
        m: &Mu,
        names: &[String],
        rotation: &dyn Fn(usize) -> bool,
        joints: &Joints,
        gaps: &[GapDof],
    ) -> Result<Result<Grid, NoExample>, SpError> {
        let Some((t0, t1)) = gap_span(gaps) else {
            return Ok(Err(NoExample::Span {
                seconds: span_seconds(gaps),
            }));
        };
        let Some((start, stop)) = m.span() else {
            return Ok(Err(NoExample::NoStretch));
        };
        let (start, stop) = (start.max(t0 - SEARCH_SPAN), stop.min(t1 + SEARCH_SPAN));
        let n = ((t1 - t0) / STEP).round().max(1.0) as i64;
        let h = (t1 - t0) / n as f64;
        let k_lo = ((start - t0) / h).ceil() as i64;
        let k_hi = ((stop - t0) / h).floor() as i64;
        if k_hi - k_lo < 2 * n {
            return Ok(Err(NoExample::NoStretch));
        }
        let coords = gap_coords(gaps);
        let angles: Vec<bool> = coords.iter().map(|&c| rotation(c)).collect();
        if !angles.iter().any(|&a| a) {
            return Ok(Err(NoExample::NoAngles));
        }
        let len = (k_hi - k_lo + 1) as usize;
        let mut x = vec![vec![f64::NAN; len]; coords.len()];
        for (row, &c) in x.iter_mut().zip(&coords) {
            for (j, v) in row.iter_mut().enumerate() {
                let t = (t0 + (k_lo + j as i64) as f64 * h).clamp(start, stop);
                if let Some(s) = m.sample(&names[c], t).map_err(SpError::Motion)? {
                    *v = s[0];
                }
            }
        }
        let everywhere = (0..len)
            .map(|j| x.iter().all(|row| row[j].is_finite()))
            .collect();
        let metric = PoseMetric::new(names, &coords, rotation, joints);
        let poses = (0..len).map(|j| metric.pose(|i| x[i][j])).collect();
        Ok(Ok(Grid {
            n,
            h,
            k_lo,
            k_hi,
            coords,
            angles,
            x,
            everywhere,
            metric,
            poses,
        }))
    }

    fn at(&self, k: i64) -> usize {
        (k - self.k_lo) as usize
    }

    fn pose(&self, k: i64) -> &Pose {
        &self.poses[self.at(k)]
    }

    fn defined(&self, k: i64) -> bool {
        k >= self.k_lo && k <= self.k_hi && self.everywhere[self.at(k)]
    }

    /// The rows of the angle coordinates whose wraps in the data would be
    /// jumps in the laid example.
    fn wrapping_rows(&self) -> impl Iterator<Item = &Vec<f64>> {
        self.x
            .iter()
            .enumerate()
            .filter(|(i, _)| self.angles[*i] && !self.metric.unwrapped_when_laid(*i))
            .map(|(_, row)| row)
    }

    /// The context, `None` with fewer than [`MIN_CONTEXT_SAMPLES`] points.
    fn context(&self) -> Option<Context> {
        let reach = (CONTEXT / self.h).round() as i64;
        let before: Vec<i64> = (0..=reach)
            .map(|j| -j)
            .take_while(|&k| self.defined(k))
            .collect();
        let after: Vec<i64> = (0..=reach)
            .map(|j| self.n + j)
            .take_while(|&k| self.defined(k))
            .collect();
        let ks: Vec<i64> = before.iter().chain(&after).copied().collect();
        if ks.len() < MIN_CONTEXT_SAMPLES {
            return None;
        }
        let lo = before.last().copied().unwrap_or(0);
        let hi = after.last().copied().unwrap_or(self.n);
        Some(Context { ks, lo, hi })
    }

    /// The shift s (grid steps) of least ρ whose window lies wholly in
    /// defined, unwrapped data, and its ρ (`spread`: the context's own).
    fn best_shift(&self, context: &Context, spread: f64) -> Option<(i64, f64)> {
        let (lo, hi) = (context.lo, context.hi);
        let mut best: Option<(i64, f64)> = None;
        for s in (self.k_lo - lo)..=(self.k_hi - hi) {
            if s == 0 || !(lo..=hi).all(|k| self.defined(k + s)) {
                continue;
            }
            // (a three-channel joint's channels are laid as rotations, so
            // their wraps in the data are none in the laid curve)
            let wraps = self.wrapping_rows().any(|row| {
                (lo..hi).any(|k| {
                    (row[self.at(k + s + 1)] - row[self.at(k + s)]).abs() > MAX_TURN_PER_STEP
                })
            });
            if wraps {
                continue;
            }
            let e: f64 = context
                .ks
                .iter()
                .map(|&k| self.metric.distance2(self.pose(k + s), self.pose(k)))
                .sum();
            let rho = e / spread;
            if best.is_none_or(|(_, b)| rho < b) {
                best = Some((s, rho));
            }
        }
        best
    }
}
