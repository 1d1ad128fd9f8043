//! A gap's plan re-estimated from what a solve made (issue 42, after
//! contact-invariant optimisation: a contact is kept where the point is
//! near the surface and still and the physics wants force there).
//!
//! Per planned stance, from the solved motion and the forces the solve held:
//! - **kept** while the solved point stands by the planning rule over at
//!   least half of it, or the friction-cone problem gave it at least
//!   [`MIN_FORCE_SHARE`] of the body's weight on average; otherwise it goes
//!   (a stance the motion neither stands on nor pushes from);
//! - **its ends move** toward where the solved point's own stance begins
//!   and ends — half-way (the prior toward the source's timing), at most
//!   [`MAX_SHIFT`], never into a neighbour's swing of [`MIN_PHASE`], never
//!   off a gap edge the motion is recorded at; moves under [`HYSTERESIS`]
//!   are not made, so a plan cannot flicker between solves;
//! - **its anchor moves** to the solved point's mean position over its
//!   stance (put on its standing height), unless it is anchored at a gap
//!   edge (where the motion is recorded) or moves less than [`ANCHOR_TOL`].
//!
//! A stance that changed says so ([`Source::Replanned`]); one `contact:`
//! states ([`Source::Given`]) is never re-planned. Re-planning the
//! capture's own fill with the capture's own plan returns that plan.

use super::capture::Tracks;
use super::context::{CONTEXT, STEP};
use super::example::on_height;
use super::merge::MIN_PHASE;
use super::plan::{GapPlan, PointPlan, Source, Stance};
use crate::dynamics::PointForce;
use crate::ground::runs_of;
use crate::model::Model;
use crate::spacetime::error::SpError;
use nalgebra::Vector3;

/// Least mean normal force, as a share of the body's weight, that keeps a
/// stance the solved point does not stand on: 5 %, about a resting foot's
/// share in a double stance's shift of weight.
pub const MIN_FORCE_SHARE: f64 = 0.05;
/// Farthest (s) a stance end moves in one re-plan: 0.1 s, the plan
/// accuracy the benchmark counts as right.
pub const MAX_SHIFT: f64 = 0.1;
/// How far toward the solved timing an end moves (the rest stays with the
/// source's timing).
pub const TOWARD_SOLVED: f64 = 0.5;
/// Smallest end move (s) made: one planning sample.
pub const HYSTERESIS: f64 = STEP;
/// Smallest anchor move (m) made: the planning rule's contact height.
pub const ANCHOR_TOL: f64 = crate::ground::CONTACT_HEIGHT;

/// What a re-plan reads of the solve besides its motion.
pub struct Replan<'a> {
    pub model: &'a Model,
    pub up: Vector3<f64>,
    /// The quadrature nodes' times and, per node, the forces the solve held
    /// there (empty: none).
    pub nodes: &'a [f64],
    pub forces: &'a [Vec<PointForce>],
    /// The body's weight (N).
    pub weight: f64,
}

impl Replan<'_> {
    /// `plan` re-estimated from the motion `configuration` gives (the
    /// solved gap with the recorded motion around it).
    pub fn of(
        &self,
        plan: &GapPlan,
        configuration: &dyn Fn(f64) -> Result<Vec<f64>, SpError>,
    ) -> Result<GapPlan, SpError> {
        let (t0, t1) = (plan.t0, plan.t1);
        let links: Vec<usize> = plan.points.iter().map(|p| p.link).collect();
        let span = (t0 - CONTEXT, t1 + CONTEXT);
        let tracks = Tracks::sample(self.model, &self.up, &links, span, (t0, t1), configuration)?;
        let points = plan
            .points
            .iter()
            .enumerate()
            .map(|(j, p)| PointPlan {
                stances: self.point(&tracks, j, p, (t0, t1)),
                ..p.clone()
            })
            .collect();
        Ok(GapPlan { t0, t1, points })
    }

    /// Point j's stances re-estimated.
    fn point(&self, tracks: &Tracks, j: usize, p: &PointPlan, gap: (f64, f64)) -> Vec<Stance> {
        let flags = tracks.flags(j, p.stand, &self.up);
        let runs = runs_of(&flags);
        let ts = &tracks.times;
        let mut out: Vec<Stance> = vec![];
        for (i, s) in p.stances.iter().enumerate() {
            if s.source == Source::Given {
                // a stance `contact:` states is the user's: never re-planned
                out.push(s.clone());
                continue;
            }
            let inside = |k: &usize| ts[*k] >= s.t0 && ts[*k] <= s.t1;
            let (all, standing) = (0..ts.len())
                .filter(inside)
                .fold((0, 0), |(a, b), k| (a + 1, b + usize::from(flags[k])));
            let stands = all > 0 && 2 * standing >= all;
            if !stands && self.mean_force(p.link, s) < MIN_FORCE_SHARE * self.weight {
                continue;
            }
            // the solved point's own stance over this one: the longest overlap
            let best = runs
                .iter()
                .map(|&(a, b)| (a, b, ts[b].min(s.t1) - ts[a].max(s.t0)))
                .filter(|r| r.2 >= 0.0)
                .max_by(|x, y| x.2.total_cmp(&y.2));
            let prev_end = out.last().map_or(f64::NEG_INFINITY, |o| o.t1 + MIN_PHASE);
            let next_start = p
                .stances
                .get(i + 1)
                .map_or(f64::INFINITY, |o| o.t0 - MIN_PHASE);
            let mut r = s.clone();
            if let Some((a, b, _)) = best {
                let at_start = s.t0 <= gap.0;
                let at_end = s.t1 >= gap.1;
                if !at_start {
                    r.t0 = moved(s.t0, ts[a]).max(prev_end).max(gap.0);
                }
                if !at_end {
                    r.t1 = moved(s.t1, ts[b]).min(next_start).min(gap.1);
                }
                if r.t1 - r.t0 < MIN_PHASE.min(s.t1 - s.t0) {
                    r.t0 = s.t0;
                    r.t1 = s.t1;
                }
                if !at_start && !at_end && s.p0 == s.p1 {
                    let mean = tracks.mean(j, a, b);
                    let anchored = on_height(Stance::planted(r.t0, r.t1, mean), &self.up, p.stand);
                    if (anchored.p0 - s.p0).norm() >= ANCHOR_TOL {
                        r.p0 = anchored.p0;
                        r.p1 = anchored.p0;
                    }
                }
            }
            if r.t0 != s.t0 || r.t1 != s.t1 || r.p0 != s.p0 {
                r.source = Source::Replanned;
            }
            out.push(r);
        }
        out
    }

    /// The mean normal force (N, along up) the solve held at `link` over
    /// the nodes of stance `s` (0 without forces there).
    fn mean_force(&self, link: usize, s: &Stance) -> f64 {
        let (mut sum, mut count) = (0.0, 0usize);
        for (t, forces) in self.nodes.iter().zip(self.forces) {
            if !s.covers(*t) {
                continue;
            }
            count += 1;
            sum += forces
                .iter()
                .filter(|f| f.link == link)
                .map(|f| self.up.dot(&f.force))
                .sum::<f64>();
        }
        if count == 0 { 0.0 } else { sum / count as f64 }
    }
}

/// An end at `planned` moved toward `solved` (see the module docs).
fn moved(planned: f64, solved: f64) -> f64 {
    let d = (TOWARD_SOLVED * (solved - planned)).clamp(-MAX_SHIFT, MAX_SHIFT);
    if d.abs() < HYSTERESIS {
        planned
    } else {
        planned + d
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_end_moves_half_way_at_most_a_tenth_and_not_for_a_sample() {
        assert_eq!(moved(1.0, 1.0 + 0.5 * HYSTERESIS), 1.0);
        assert!((moved(1.0, 1.1) - 1.05).abs() < 1e-12);
        assert!((moved(1.0, 0.5) - 0.9).abs() < 1e-12);
    }
}
