//! Foot contact inside a gap (issue 25): which contact frames stand on the
//! floor when, and where, planned from the motion around the gap.
//!
//! A contact frame is a joint point whose lowest height over the context is
//! within [`GROUND_BAND`] of the floor (ankles and toes of a walk; a hand
//! only if it reaches the floor). It is *in stance* at a sample when it is
//! within [`CONTACT_HEIGHT`] of its own lowest height in the context (an
//! ankle never comes within 2 cm of the floor, its toe does) and moves
//! horizontally slower than [`CONTACT_SPEED`].
//!
//! Per frame, at the gap's ends:
//! - in stance at both ends, in the same place (a [`super::support`] box):
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
//! The floor is the lowest height any contact frame reaches in the recorded
//! part of the motion, or `floor:`. Planting is done by the support IK
//! ([`super::support::SupportObjective::planned`]), which also keeps every
//! contact frame at or above the floor.

use super::error::{SpError, invalid};
use super::support::{Floor, Plant};
use crate::model::Model;
use nalgebra::Vector3;

/// `SP(…, contact: …)`.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum Contact {
    /// Contact frames found near the floor, schedules planned per gap.
    Auto,
    /// `contact: ["Toes_L", …]`: these frames, schedules planned per gap.
    Named(Vec<String>),
    /// No contact planning: Rose's support alone (`support:`), as before.
    #[default]
    None,
}

/// Height (m) above its own lowest point within which a frame may be in stance.
pub const CONTACT_HEIGHT: f64 = 0.02;
/// Horizontal speed (m/s) under which a low frame is in stance: a planted
/// toe of a Bandai walk moves ~0.1 m/s (capture noise, rolling), a swinging
/// one passes its lowest point at over 1 m/s.
pub const CONTACT_SPEED: f64 = 0.3;
/// A contact frame's lowest point lies within this (m) of the floor.
pub const GROUND_BAND: f64 = 0.15;
/// Seconds of context looked at on each side of a gap.
pub const CONTEXT: f64 = 1.5;
/// Context sampling step (s).
const STEP: f64 = 1.0 / 60.0;
/// Stance and swing durations (s) used when the context shows no complete
/// one (a typical walk: 0.6 s stance, 0.4 s swing).
const DEFAULT_STANCE: f64 = 0.6;
const DEFAULT_SWING: f64 = 0.4;
/// Two stances within this (m) of each other are one plant.
const SAME_PLACE: f64 = 0.02;

/// One contact frame's schedule in one gap.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactPhase {
    /// The frame's name.
    pub frame: String,
    /// Planted intervals and where.
    pub plants: Vec<Plant>,
}

/// One side of a gap: sample times, and per frame its positions at them.
type Side = (Vec<f64>, Vec<Vec<Vector3<f64>>>);

/// The contact frames of a motion around one gap and their samples.
pub struct Context<'a> {
    model: &'a Model,
    up: Vector3<f64>,
    frames: Vec<usize>,
    /// The samples before and after the gap.
    before: Side,
    after: Side,
    /// Per frame, its lowest height over both sides.
    lowest: Vec<f64>,
}

/// The floor of a motion's recorded part: the lowest height any of `frames`
/// reaches at `configurations` (fully defined poses).
pub fn floor_of(
    model: &Model,
    frames: &[usize],
    up: &Vector3<f64>,
    configurations: &[Vec<f64>],
) -> Result<Option<f64>, SpError> {
    let mut poses = vec![];
    let mut lowest: Option<f64> = None;
    for q in configurations {
        fk(model, q, &mut poses)?;
        for &f in frames {
            let h = up.dot(&poses[f].p);
            lowest = Some(lowest.map_or(h, |l| l.min(h)));
        }
    }
    Ok(lowest)
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
        up: Vector3<f64>,
        candidates: &[usize],
        named: bool,
        floor: f64,
        (t0, t1): (f64, f64),
        configuration: &dyn Fn(f64) -> Result<Vec<f64>, SpError>,
    ) -> Result<Self, SpError> {
        let n = (CONTEXT / STEP).round() as usize;
        let mut poses = vec![];
        let mut side = |times: Vec<f64>| -> Result<Side, SpError> {
            let mut ts = vec![];
            let mut ps = vec![vec![]; candidates.len()];
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
            }
            Ok((ts, ps))
        };
        // before the gap from t0 backwards, after it from t1 forwards
        let (mut tb, mut pb) = side((0..=n).map(|k| t0 - k as f64 * STEP).collect())?;
        tb.reverse();
        pb.iter_mut().for_each(|p| p.reverse());
        let (ta, pa) = side((0..=n).map(|k| t1 + k as f64 * STEP).collect())?;
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
            if named || low - floor <= GROUND_BAND {
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
            before: (tb, pick(pb)),
            after: (ta, pick(pa)),
            lowest,
        })
    }

    /// The contact frames kept.
    pub fn frames(&self) -> &[usize] {
        &self.frames
    }

    /// Stance flags of frame k on one side's samples.
    fn stance(&self, k: usize, (ts, ps): &Side) -> Vec<bool> {
        let p = &ps[k];
        (0..ts.len())
            .map(|i| {
                let low = self.up.dot(&p[i]) - self.lowest[k] <= CONTACT_HEIGHT;
                // horizontal speed by the nearest difference on this side
                let (a, b) = if i + 1 < ts.len() {
                    (i, i + 1)
                } else if i > 0 {
                    (i - 1, i)
                } else {
                    return low;
                };
                let d = p[b] - p[a];
                let horizontal = d - self.up * self.up.dot(&d);
                low && horizontal.norm() / (ts[b] - ts[a]) <= CONTACT_SPEED
            })
            .collect()
    }

    /// The contact schedule of every frame over the gap [t0, t1].
    pub fn plan(&self) -> Vec<Vec<Plant>> {
        let (t0, t1) = (
            *self.before.0.last().unwrap_or(&0.0),
            *self.after.0.first().unwrap_or(&0.0),
        );
        let gap = t1 - t0;
        (0..self.frames.len())
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
                let plant = |a: f64, b: f64, p: Vector3<f64>, q: Vector3<f64>| Plant {
                    t0: a,
                    t1: b,
                    p0: p,
                    p1: q,
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
                out
            })
            .collect()
    }

    /// Names of the frames with their schedules.
    pub fn phases(&self, plants: &[Vec<Plant>]) -> Vec<ContactPhase> {
        self.frames
            .iter()
            .zip(plants)
            .map(|(&f, p)| ContactPhase {
                frame: self.model.link(f).name.clone(),
                plants: p.clone(),
            })
            .collect()
    }
}

/// Mean durations (s) of the complete stance and swing runs (bounded by the
/// other state on both sides) in the two sides' stance flags.
fn durations(before: &[bool], after: &[bool]) -> (f64, f64) {
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

/// The floor for the IK, from a height and gravity.
pub fn floor(gravity: &Vector3<f64>, height: f64) -> Result<Floor, SpError> {
    if gravity.norm() == 0.0 {
        return Err(invalid("contact needs gravity to know which way is up"));
    }
    if !height.is_finite() {
        return Err(crate::spacetime::error::invalid_option(
            "floor",
            format!("`floor:` must be a finite height in metres, found {height}"),
        ));
    }
    Ok(Floor {
        up: -gravity / gravity.norm(),
        height,
    })
}
