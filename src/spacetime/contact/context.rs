//! A gap's contact plan from the motion around it: which contact points
//! stand on the floor when, and where.
//!
//! The contact points are `ground`'s (a body's ankle and toe joints, or the
//! links `contact: [...]` names); one whose lowest height over the context is
//! within [`GROUND_BAND`] of the floor is kept (unless named). It is *in
//! stance* at a sample by `ground`'s planning rule ([`plan_stances`]): within
//! 2 cm of its own lowest height in the context (an ankle never comes within
//! 2 cm of the floor, its toe does) and moving horizontally slower than a
//! fraction of the body's speed (so a run's stances are whole, not 1–3
//! frames).
//!
//! Per point, at the gap's ends:
//! - in stance at both ends, in the same place (within 2 cm):
//!   planted over the whole gap on the path between the two (Rose's support);
//! - in stance at both ends in different places: one step, planted at the
//!   start until lift-off and at the end from touch-down. Lift-off comes when
//!   the stance has lasted as long as the context's stances, touch-down so
//!   that the end stance lasts as long; a swing shorter than half the
//!   context's swing is widened to it around its middle;
//! - in stance at one end only: planted there until lift-off (after
//!   touch-down);
//! - in the air at both ends: free.
//!
//! The floor is `ground`'s floor of the motion's recorded part
//! ([`crate::ground::recorded_floor`]), or `floor:`. Planting is done by the
//! hold IK ([`crate::spacetime::hold::HoldObjective::planned`]), which also
//! keeps every contact point at or above the floor.

use super::plan::{GapPlan, PointPlan, Source, Stance};
use crate::ground::{FloorPlane, GROUND_BAND, plan_stances};
use crate::lie::Se3;
use crate::model::{Model, RootCoords};
use crate::spacetime::error::SpError;
use nalgebra::Vector3;

/// Seconds of context looked at on each side of a gap.
pub const CONTEXT: f64 = 1.5;
/// Context sampling step (s).
pub(super) const STEP: f64 = 1.0 / 60.0;
/// Stance and swing durations (s) used when the context shows no complete
/// one (a typical walk: 0.6 s stance, 0.4 s swing).
const DEFAULT_STANCE: f64 = 0.6;
const DEFAULT_SWING: f64 = 0.4;
/// Two stances within this (m) of each other are one plant.
const SAME_PLACE: f64 = 0.02;

/// One side of a gap: sample times, per frame its positions at them, and
/// the body's (its root link's) poses.
pub(super) type Side = (Vec<f64>, Vec<Vec<Vector3<f64>>>, Vec<Se3>);

/// The link whose horizontal speed is the body's: the last link of its root
/// chain (a BVH skeleton's hips). `None` for a body without a root chain.
pub(super) fn body_link(model: &Model, up: &Vector3<f64>) -> Option<usize> {
    let root = RootCoords::detect(model, Some(up));
    model.coordinate_link(*root.all.last()?)
}

/// The contact points of a motion around one gap and their samples.
pub struct Context<'a> {
    pub(super) model: &'a Model,
    pub(super) up: Vector3<f64>,
    /// The contact points kept (link indices).
    pub(super) frames: Vec<usize>,
    /// The samples before and after the gap.
    pub(super) before: Side,
    pub(super) after: Side,
    /// Per point, its lowest height over both sides.
    pub(super) lowest: Vec<f64>,
    /// The gap [t0, t1].
    pub(super) span: (f64, f64),
}

fn fk(model: &Model, q: &[f64], poses: &mut Vec<crate::lie::Se3>) -> Result<(), SpError> {
    model
        .forward_kinematics(q, poses)
        .map_err(SpError::Kinematics)
}

impl<'a> Context<'a> {
    /// Samples `candidates` over [`CONTEXT`] s before `t0` and after `t1`
    /// (where `configuration` is fully defined) and keeps, unless `named`,
    /// those whose lowest point is within [`GROUND_BAND`] of `floor`.
    pub fn new(
        model: &'a Model,
        floor: &FloorPlane,
        candidates: &[usize],
        named: bool,
        (t0, t1): (f64, f64),
        configuration: &dyn Fn(f64) -> Result<Vec<f64>, SpError>,
    ) -> Result<Self, SpError> {
        let up = floor.up;
        let n = (CONTEXT / STEP).round() as usize;
        let body = body_link(model, &up);
        let mut poses = vec![];
        let mut side = |times: Vec<f64>| -> Result<Side, SpError> {
            let mut ts = vec![];
            let mut ps = vec![vec![]; candidates.len()];
            let mut bs = vec![];
            for t in times {
                let q = configuration(t)?;
                if !q.iter().all(|v| v.is_finite()) {
                    break; // the motion stops being defined: the context ends here
                }
                fk(model, &q, &mut poses)?;
                ts.push(t);
                for (j, &f) in candidates.iter().enumerate() {
                    ps[j].push(poses[f].p);
                }
                bs.push(body.map_or_else(Se3::default, |b| poses[b].clone()));
            }
            Ok((ts, ps, bs))
        };
        // before the gap from t0 backwards, after it from t1 forwards
        let (mut tb, mut pb, mut bb) = side((0..=n).map(|k| t0 - k as f64 * STEP).collect())?;
        tb.reverse();
        bb.reverse();
        pb.iter_mut().for_each(|p| p.reverse());
        let (ta, pa, ba) = side((0..=n).map(|k| t1 + k as f64 * STEP).collect())?;
        if tb.is_empty() || ta.is_empty() {
            return Err(SpError::Incomplete(format!(
                "contact: the body is not fully defined at the gap ends [{t0}, {t1}]"
            )));
        }
        let mut keep = vec![];
        let mut lowest = vec![];
        for (j, &f) in candidates.iter().enumerate() {
            let low = pb[j]
                .iter()
                .chain(&pa[j])
                .map(|p| up.dot(p))
                .fold(f64::INFINITY, f64::min);
            if named || low - floor.height <= GROUND_BAND {
                keep.push((j, f));
                lowest.push(low);
            }
        }
        let pick = |ps: Vec<Vec<Vector3<f64>>>| -> Vec<Vec<Vector3<f64>>> {
            keep.iter().map(|&(j, _)| ps[j].clone()).collect()
        };
        Ok(Context {
            model,
            up,
            frames: keep.iter().map(|&(_, f)| f).collect(),
            before: (tb, pick(pb), bb),
            after: (ta, pick(pa), ba),
            lowest,
            span: (t0, t1),
        })
    }

    /// Stance flags of point k on one side's samples.
    pub(super) fn stance(&self, k: usize, (_, ps, body): &Side) -> Vec<bool> {
        let body: Vec<Vector3<f64>> = body.iter().map(|b| b.p).collect();
        plan_stances(&ps[k], &body, STEP, self.lowest[k], &self.up)
    }

    /// The kept points' links and the heights they stand at.
    pub fn points(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.frames.iter().copied().zip(self.lowest.iter().copied())
    }

    /// The gap's plan: every kept point's stances over [t0, t1].
    pub fn plan(&self) -> GapPlan {
        let (t0, t1) = (
            *self.before.0.last().unwrap_or(&0.0),
            *self.after.0.first().unwrap_or(&0.0),
        );
        let gap = t1 - t0;
        let points = (0..self.frames.len())
            .map(|k| {
                let sb = self.stance(k, &self.before);
                let sa = self.stance(k, &self.after);
                let (stance, swing) = durations(&sb, &sa);
                let st0 = *sb.last().unwrap_or(&false);
                let st1 = *sa.first().unwrap_or(&false);
                // how long the stance has lasted at t0, and lasts after t1
                let a0 = sb
                    .iter()
                    .rev()
                    .take_while(|&&s| s)
                    .count()
                    .saturating_sub(1) as f64
                    * STEP;
                let b1 = sa.iter().take_while(|&&s| s).count().saturating_sub(1) as f64 * STEP;
                let p0 = *self.before.1[k].last().expect("context is not empty");
                let p1 = self.after.1[k][0];
                let plant = |a: f64, b: f64, p: Vector3<f64>, q: Vector3<f64>| Stance {
                    t0: a,
                    t1: b,
                    p0: p,
                    p1: q,
                    source: Source::Context,
                    solved: None,
                };
                let lift = (t0 + (stance - a0).max(0.0)).min(t1);
                let touch = (t1 - (stance - b1).max(0.0)).max(t0);
                let mut out = vec![];
                match (st0, st1) {
                    (true, true) if (p1 - p0).amax() <= SAME_PLACE => {
                        out.push(plant(t0, t1, p0, p1))
                    }
                    (true, true) => {
                        let (mut lift, mut touch) = (lift, touch);
                        let want = swing.min(0.8 * gap);
                        if touch - lift < 0.5 * want {
                            let mid = 0.5 * (lift + touch);
                            lift = (mid - 0.5 * want).max(t0);
                            touch = (mid + 0.5 * want).min(t1);
                        }
                        if lift > t0 {
                            out.push(plant(t0, lift, p0, p0));
                        }
                        if touch < t1 {
                            out.push(plant(touch, t1, p1, p1));
                        }
                    }
                    (true, false) if lift > t0 => out.push(plant(t0, lift, p0, p0)),
                    (false, true) if touch < t1 => out.push(plant(touch, t1, p1, p1)),
                    _ => {}
                }
                let link = self.frames[k];
                PointPlan {
                    name: self.model.link(link).name.clone(),
                    link,
                    stand: self.lowest[k],
                    stances: out,
                }
            })
            .collect();
        GapPlan {
            t0: self.span.0,
            t1: self.span.1,
            points,
        }
    }
}

/// Mean durations (s) of the complete stance and swing runs (bounded by the
/// other state on both sides) in the two sides' stance flags.
pub(super) fn durations(before: &[bool], after: &[bool]) -> (f64, f64) {
    let mut stance = vec![];
    let mut swing = vec![];
    for flags in [before, after] {
        let mut i = 0;
        // runs: (state, start, end exclusive)
        let mut runs = vec![];
        while i < flags.len() {
            let j = (i..flags.len())
                .find(|&j| flags[j] != flags[i])
                .unwrap_or(flags.len());
            runs.push((flags[i], i, j));
            i = j;
        }
        // the first and last runs are cut by the window or the gap
        if runs.len() > 2 {
            for &(s, a, b) in &runs[1..runs.len() - 1] {
                let d = (b - a) as f64 * STEP;
                if s { stance.push(d) } else { swing.push(d) }
            }
        }
    }
    let mean = |v: &[f64], d: f64| {
        if v.is_empty() {
            d
        } else {
            v.iter().sum::<f64>() / v.len() as f64
        }
    };
    (mean(&stance, DEFAULT_STANCE), mean(&swing, DEFAULT_SWING))
}
