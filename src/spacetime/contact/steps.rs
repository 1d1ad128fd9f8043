//! A gap's stances without an example (issue 42): a step planner that
//! carries each contact point's gait phase across the gap.
//!
//! From the context, per point: its cycle — the mean length of its complete
//! stances S and swings W (those bounded on both sides; where a point has
//! none, the mean of the points that do, else a walk's 0.6 s / 0.4 s) —
//! and its phase at each edge: how long it has been standing or swinging at
//! the gap's start, and how long it goes on at the gap's end. Phase runs
//! from 0 to 1 over a cycle, standing while it is below σ = S / (S + W).
//! Across the gap it advances linearly from the start's phase to the end's,
//! by the whole number of cycles that makes the cycle nearest the context's:
//! the feet keep their cadence and alternate as they did, and the plan
//! agrees with both edges by construction. Where no point completes a
//! stance or a swing in the context and no foot travels across the gap
//! (slower than 0.2 m/s on average) there is no cadence (a bow, a
//! wave): each point holds the stance it has at an edge instead of stepping.
//!
//! A stance inside the gap is anchored along the body's path (the start of
//! the solve: the root's interpolated path): at its middle, the body's
//! horizontal position plus the point's own offset from the body while it
//! stands in the context, in the body's heading frame (forward and to the
//! side of the way its root link faces, so a walk backwards keeps its feet
//! on their sides), put on the point's standing height. Stances at the edges take the context's anchors
//! when the plans are merged (`merge.rs`).

use super::context::{Context, STEP, body_link};
use super::example::on_height;
use super::plan::{GapPlan, PointPlan, Source, Stance};
use crate::ground::{horizontal, runs_of};
use crate::lie::Se3;
use crate::spacetime::error::SpError;
use nalgebra::Vector3;

/// Stance and swing (s) when no point's context shows a complete one: a
/// walk's (the context plan's defaults).
const DEFAULT_STANCE: f64 = 0.6;
const DEFAULT_SWING: f64 = 0.4;
/// How long (s) a held foot takes to leave the floor, or to come down on
/// it, at an edge where it is in the air: half a walk's swing.
const LIFT: f64 = 0.5 * DEFAULT_SWING;
/// Below this mean horizontal speed (m/s) across the gap no foot travels:
/// without a cadence in the context, the feet hold (see [`held_runs`]).
const MOVING: f64 = 0.2;

/// A point's gait phase at the gap's two edges and its cycle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Phase {
    /// Cycle length (s) and the standing share of it.
    pub cycle: f64,
    pub sigma: f64,
    /// Phase at t0 and at t1 (unwrapped: `end` ≥ `start`).
    pub start: f64,
    pub end: f64,
}

impl Phase {
    /// Whether the point stands at phase φ.
    pub fn stands(&self, phi: f64) -> bool {
        phi.rem_euclid(1.0) < self.sigma
    }

    /// The phase at time t of [t0, t1].
    pub fn at(&self, t: f64, (t0, t1): (f64, f64)) -> f64 {
        let s = if t1 > t0 { (t - t0) / (t1 - t0) } else { 0.0 };
        self.start + s * (self.end - self.start)
    }

    /// The phase of a point whose cycle is `stance` + `swing` s, standing
    /// (or not) at t0 for `since` s so far and at t1 for `until` s more,
    /// over a gap of `gap` s.
    pub fn across(
        (stance, swing): (f64, f64),
        (st0, since): (bool, f64),
        (st1, until): (bool, f64),
        gap: f64,
    ) -> Phase {
        let cycle = stance + swing;
        let sigma = stance / cycle;
        let inside = |x: f64, lo: f64, hi: f64| x.clamp(lo, hi - 1e-9 * cycle.max(1.0));
        let start = if st0 {
            inside(since / cycle, 0.0, sigma)
        } else {
            inside(sigma + since / cycle, sigma, 1.0)
        };
        let end = if st1 {
            inside(sigma - until / cycle, 0.0, sigma)
        } else {
            inside(1.0 - until / cycle, sigma, 1.0)
        };
        // whole cycles so that the gap's cycle is nearest the context's
        let mut n = (gap / cycle - (end - start)).round();
        if end + n < start {
            n = (start - end).ceil();
        }
        Phase {
            cycle,
            sigma,
            start,
            end: end + n,
        }
    }
}

/// The complete stance and swing lengths (s) of one point's flags on one side.
fn complete_runs(flags: &[bool], stances: &mut Vec<f64>, swings: &mut Vec<f64>) {
    let on = runs_of(flags);
    let off = runs_of(&flags.iter().map(|f| !f).collect::<Vec<_>>());
    let last = flags.len().saturating_sub(1);
    for (runs, out) in [(on, stances), (off, swings)] {
        for (a, b) in runs {
            if a > 0 && b < last {
                out.push((b - a + 1) as f64 * STEP);
            }
        }
    }
}

fn mean(v: &[f64]) -> Option<f64> {
    (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
}

/// How long (s) the state at the end of `flags` has lasted, and at the
/// start of `flags` lasts.
fn trailing(flags: &[bool]) -> (bool, f64) {
    let Some(&last) = flags.last() else {
        return (false, 0.0);
    };
    let n = flags.iter().rev().take_while(|&&f| f == last).count();
    (last, n.saturating_sub(1) as f64 * STEP)
}

fn leading(flags: &[bool]) -> (bool, f64) {
    let Some(&first) = flags.first() else {
        return (false, 0.0);
    };
    let n = flags.iter().take_while(|&&f| f == first).count();
    (first, n.saturating_sub(1) as f64 * STEP)
}

impl Context<'_> {
    /// The step planner's plan of the gap (see the module docs);
    /// `configuration` is the motion at the solve's start (the body's path
    /// through the gap is read from it).
    pub fn steps(
        &self,
        configuration: &dyn Fn(f64) -> Result<Vec<f64>, SpError>,
    ) -> Result<GapPlan, SpError> {
        let body = body_link(self.model, &self.up);
        let body_path = |t: f64| -> Result<Se3, SpError> {
            let q = configuration(t)?;
            let mut poses = vec![];
            self.model
                .forward_kinematics(&q, &mut poses)
                .map_err(SpError::Kinematics)?;
            Ok(body.map_or_else(Se3::default, |b| poses[b].clone()))
        };
        let body_path = &body_path;
        let (t0, t1) = self.span;
        let flags: Vec<(Vec<bool>, Vec<bool>)> = (0..self.frames.len())
            .map(|k| (self.stance(k, &self.before), self.stance(k, &self.after)))
            .collect();
        let cycle = |k: usize| {
            let (mut st, mut sw) = (vec![], vec![]);
            complete_runs(&flags[k].0, &mut st, &mut sw);
            complete_runs(&flags[k].1, &mut st, &mut sw);
            (mean(&st), mean(&sw))
        };
        let own: Vec<(Option<f64>, Option<f64>)> = (0..self.frames.len()).map(cycle).collect();
        let all_st: Vec<f64> = own.iter().filter_map(|c| c.0).collect();
        let all_sw: Vec<f64> = own.iter().filter_map(|c| c.1).collect();
        // no point completes a stance or a swing in the context and no
        // point travels across the gap (the hips may: a bow moves them
        // back): there is no cadence to carry (a bow, a wave, a stand), and
        // a walk's would invent steps the person never took
        let gait = own.iter().any(|c| c.0.is_some() || c.1.is_some())
            || self.travel() >= MOVING * (t1 - t0);
        let fallback = (
            mean(&all_st).unwrap_or(DEFAULT_STANCE),
            mean(&all_sw).unwrap_or(DEFAULT_SWING),
        );
        let mut points = vec![];
        for (k, &link) in self.frames.iter().enumerate() {
            let durations = (
                own[k].0.unwrap_or(fallback.0),
                own[k].1.unwrap_or(fallback.1),
            );
            let (before, after) = (trailing(&flags[k].0), leading(&flags[k].1));
            let runs = if gait {
                phase_runs(&Phase::across(durations, before, after, t1 - t0), (t0, t1))
            } else {
                held_runs((before.0, after.0), (t0, t1))
            };
            let offset = self.offset(k, &flags[k]);
            let mut stances = vec![];
            for (a, b) in runs {
                let mid = 0.5 * (a + b);
                let anchor = self.anchor_at(mid, offset, body_path)?;
                let s = Stance::planted(a, b, anchor).by(Source::Steps);
                stances.push(on_height(s, &self.up, self.lowest[k]));
            }
            points.push(PointPlan {
                name: self.model.link(link).name.clone(),
                link,
                stand: self.lowest[k],
                stances,
            });
        }
        Ok(GapPlan { t0, t1, points })
    }

    /// The farthest any point is, along the floor, at the gap's end from
    /// where it was at its start (m).
    fn travel(&self) -> f64 {
        (0..self.frames.len())
            .filter_map(|k| {
                let (a, b) = (self.before.1[k].last()?, self.after.1[k].first()?);
                Some(horizontal(&(b - a), &self.up).norm())
            })
            .fold(0.0, f64::max)
    }

    /// Point k's mean offset from the body while it stands in the context,
    /// in the body's heading frame ([`Heading`]): forward and to the side
    /// of the way the body faces, so a walk backwards or sideways, or a bow
    /// whose hips move back, keeps each foot on its own side.
    fn offset(&self, k: usize, (before, after): &(Vec<bool>, Vec<bool>)) -> Offset {
        let heading = Heading::of(self.before.2.iter().chain(&self.after.2), &self.up);
        let mut along = vec![];
        for (side, flags) in [(&self.before, before), (&self.after, after)] {
            let any_stance = flags.iter().any(|&f| f);
            for (i, &f) in flags.iter().enumerate() {
                if any_stance && !f {
                    continue;
                }
                let d = horizontal(&(side.1[k][i] - side.2[i].p), &self.up);
                let (fwd, lat) = heading.axes(&side.2[i], &self.up);
                along.push((d.dot(&fwd), d.dot(&lat)));
            }
        }
        let n = along.len().max(1) as f64;
        let (f, l) = along
            .iter()
            .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / n, b + y / n));
        Offset { heading, f, l }
    }

    /// Where a point with `offset` stands at time t of the gap.
    fn anchor_at(
        &self,
        t: f64,
        offset: Offset,
        body_path: &dyn Fn(f64) -> Result<Se3, SpError>,
    ) -> Result<Vector3<f64>, SpError> {
        let here = body_path(t)?;
        let at = horizontal(&here.p, &self.up) + self.up * self.up.dot(&here.p);
        let (fwd, lat) = offset.heading.axes(&here, &self.up);
        Ok(at + fwd * offset.f + lat * offset.l)
    }
}

/// A point's offset from the body while it stands (see [`Context::offset`]).
#[derive(Clone, Copy, Debug)]
struct Offset {
    heading: Heading,
    f: f64,
    l: f64,
}

/// The body's heading: the axis of its root link that stays nearest the
/// floor's plane over the context (a pelvis's left–right axis, which
/// pitching in a bow and turning in a walk both keep horizontal), projected
/// onto the floor.
#[derive(Clone, Copy, Debug)]
struct Heading {
    axis: usize,
}

impl Heading {
    fn of<'p>(poses: impl Iterator<Item = &'p Se3>, up: &Vector3<f64>) -> Heading {
        let mut tilt = [0.0; 3];
        for pose in poses {
            for (k, t) in tilt.iter_mut().enumerate() {
                *t += (pose.r.column(k).dot(up)).abs();
            }
        }
        let axis = (0..3)
            .min_by(|&a, &b| tilt[a].total_cmp(&tilt[b]))
            .unwrap_or(0);
        Heading { axis }
    }

    /// The floor-plane axes (along the heading axis, and up × it) of a pose.
    fn axes(&self, pose: &Se3, up: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
        let a = horizontal(&pose.r.column(self.axis).into_owned(), up);
        let a = if a.norm() > 1e-9 {
            a.normalize()
        } else {
            // the axis stands upright: any floor direction (never chosen on
            // a body whose axes are not all vertical)
            up.cross(&Vector3::new(up.z, up.x, up.y)).normalize()
        };
        (a, up.cross(&a))
    }
}

/// Without a cadence, a point holds the stance it has at an edge: across
/// the gap where it stands at both, else from (or to) its edge until
/// [`LIFT`] s before the other edge, where it is in the air; no stance
/// where it stands at neither.
fn held_runs((at_t0, at_t1): (bool, bool), (t0, t1): (f64, f64)) -> Vec<(f64, f64)> {
    let lift = LIFT.min(0.25 * (t1 - t0));
    match (at_t0, at_t1) {
        (true, true) => vec![(t0, t1)],
        (true, false) => vec![(t0, t1 - lift)],
        (false, true) => vec![(t0 + lift, t1)],
        (false, false) => vec![],
    }
}

/// The stance intervals of [t0, t1] under `phase`, on the planning grid,
/// the gap's ends included.
fn phase_runs(phase: &Phase, (t0, t1): (f64, f64)) -> Vec<(f64, f64)> {
    let n = ((t1 - t0) / STEP).ceil().max(1.0) as usize;
    let times: Vec<f64> = (0..=n)
        .map(|i| t0 + (t1 - t0) * i as f64 / n as f64)
        .collect();
    let flags: Vec<bool> = times
        .iter()
        .map(|&t| phase.stands(phase.at(t, (t0, t1))))
        .collect();
    runs_of(&flags)
        .into_iter()
        .map(|(a, b)| (times[a], times[b]))
        .filter(|(a, b)| b > a)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_phase_meets_both_edges_and_keeps_the_cadence() {
        // a walk: 0.6 s stance, 0.4 s swing; standing 0.2 s at t0, swinging
        // for 0.1 s more at t1, over a 1 s gap
        let p = Phase::across((0.6, 0.4), (true, 0.2), (false, 0.1), 1.0);
        assert!((p.cycle - 1.0).abs() < 1e-12 && (p.sigma - 0.6).abs() < 1e-12);
        assert!((p.start - 0.2).abs() < 1e-12);
        // 0.9 + 0 cycles: 0.7 cycles over the gap, the nearest to 1 s / 1 s
        assert!((p.end - 0.9).abs() < 1e-12, "{p:?}");
        let runs = phase_runs(&p, (0.0, 1.0));
        assert_eq!(runs.len(), 1, "{runs:?}");
        assert_eq!(runs[0].0, 0.0);
        // lift-off where the phase passes σ: (0.6 − 0.2) / 0.7 of the gap
        assert!((runs[0].1 - 0.4 / 0.7).abs() <= STEP, "{runs:?}");
    }

    #[test]
    fn a_foot_in_the_air_at_both_edges_steps_once_inside_a_long_gap() {
        // swinging 0.1 s at t0, 0.3 s of swing left at t1, 1 s cycle, 1.1 s gap
        let p = Phase::across((0.6, 0.4), (false, 0.1), (false, 0.3), 1.1);
        let runs = phase_runs(&p, (0.0, 1.1));
        assert_eq!(runs.len(), 1, "{p:?} {runs:?}");
        let (a, b) = runs[0];
        assert!(a > 0.1 && b < 1.1 && b - a > 0.4, "{runs:?}");
    }

    #[test]
    fn without_a_cadence_a_foot_holds_its_edge_stance_and_takes_no_step() {
        assert_eq!(held_runs((true, true), (1.0, 2.0)), vec![(1.0, 2.0)]);
        let lifts = held_runs((true, false), (1.0, 2.0));
        assert_eq!(lifts.len(), 1);
        assert!((lifts[0].0 - 1.0).abs() < 1e-12 && (lifts[0].1 - (2.0 - LIFT)).abs() < 1e-12);
        let lands = held_runs((false, true), (1.0, 1.2));
        assert!(
            (lands[0].0 - 1.05).abs() < 1e-12 && lands[0].1 == 1.2,
            "{lands:?}"
        );
        assert!(held_runs((false, false), (1.0, 2.0)).is_empty());
    }

    #[test]
    fn runs_of_the_context_give_complete_stances_and_swings_only() {
        let f = [true, true, false, false, false, true, true, true, false];
        let (mut st, mut sw) = (vec![], vec![]);
        complete_runs(&f, &mut st, &mut sw);
        assert_eq!(st.len(), 1);
        assert!((st[0] - 3.0 * STEP).abs() < 1e-12);
        assert_eq!(sw.len(), 1);
        assert!((sw[0] - 3.0 * STEP).abs() < 1e-12);
        assert_eq!(trailing(&f), (false, 0.0));
        assert!(leading(&f).0);
    }
}
