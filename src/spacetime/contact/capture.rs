//! A motion's own contacts inside a span as a gap's plan: what a capture did
//! where SP is asked to fill, or what the example SP follows does there
//! (`example.rs`), or what a solve made (`replan.rs`). The same planning
//! stance rule as the context's ([`plan_stances`]), applied to the motion's
//! own samples through the span and around it.
//!
//! It is the known answer a planned gap is measured against, and a plan a
//! user can give SP (`contact:` with a capture's contacts).

use super::context::{CONTEXT, STEP, body_link};
use super::plan::{GapPlan, PointPlan, Source, Stance};
use crate::ground::{FloorPlane, plan_stances, runs_of};
use crate::model::Model;
use crate::spacetime::error::SpError;
use nalgebra::Vector3;

/// Contact points' and the body's world positions on the planning grid
/// ([`STEP`]) over a stretch of a motion, where it is defined.
pub struct Tracks {
    pub times: Vec<f64>,
    /// Per point, its positions at `times`.
    pub points: Vec<Vec<Vector3<f64>>>,
    /// The body's (its root chain's last link's) positions at `times`.
    pub body: Vec<Vector3<f64>>,
}

impl Tracks {
    /// The positions of `links` over [a, b] as `configuration` moves them
    /// (samples where it is undefined are skipped, but it must be defined
    /// over `need`: an error names the first time it is not).
    pub fn sample(
        model: &Model,
        up: &Vector3<f64>,
        links: &[usize],
        (a, b): (f64, f64),
        need: (f64, f64),
        configuration: &dyn Fn(f64) -> Result<Vec<f64>, SpError>,
    ) -> Result<Tracks, SpError> {
        let body = body_link(model, up);
        let n = ((b - a) / STEP).round().max(0.0) as usize;
        let mut poses = vec![];
        let mut out = Tracks {
            times: vec![],
            points: vec![vec![]; links.len()],
            body: vec![],
        };
        for k in 0..=n {
            let t = a + k as f64 * STEP;
            let q = configuration(t)?;
            if !q.iter().all(|v| v.is_finite()) {
                if (need.0..=need.1).contains(&t) {
                    return Err(SpError::Incomplete(format!(
                        "contact: the motion's own contacts need it at {t:.4} s inside [{}, {}]",
                        need.0, need.1
                    )));
                }
                continue;
            }
            model
                .forward_kinematics(&q, &mut poses)
                .map_err(SpError::Kinematics)?;
            out.times.push(t);
            for (j, &f) in links.iter().enumerate() {
                out.points[j].push(poses[f].p);
            }
            out.body
                .push(body.map_or_else(Vector3::zeros, |l| poses[l].p));
        }
        Ok(out)
    }

    /// Point j's lowest height along `up`.
    pub fn lowest(&self, j: usize, up: &Vector3<f64>) -> f64 {
        self.points[j]
            .iter()
            .map(|x| up.dot(x))
            .fold(f64::INFINITY, f64::min)
    }

    /// Point j's stance flags by the planning rule, standing at `stand`.
    pub fn flags(&self, j: usize, stand: f64, up: &Vector3<f64>) -> Vec<bool> {
        plan_stances(&self.points[j], &self.body, STEP, stand, up)
    }

    /// Point j's mean position over samples [a, b] (inclusive).
    pub fn mean(&self, j: usize, a: usize, b: usize) -> Vector3<f64> {
        self.points[j][a..=b].iter().sum::<Vector3<f64>>() / (b - a + 1) as f64
    }

    /// The stances of point j from its stance flags, cut to [t0, t1]: each
    /// run of flags that meets the span, anchored at the point's mean
    /// position over the whole run (also outside the span).
    pub fn stances(&self, j: usize, flags: &[bool], (t0, t1): (f64, f64)) -> Vec<Stance> {
        let ts = &self.times;
        runs_of(flags)
            .into_iter()
            .filter(|&(a, b)| ts[b] >= t0 && ts[a] <= t1)
            .map(|(a, b)| Stance::planted(ts[a].max(t0), ts[b].min(t1), self.mean(j, a, b)))
            .collect()
    }
}

/// The stances of `points` (links) inside [t0, t1] as `configuration` (the
/// whole motion, defined through the span) moves them: each point stands at
/// its lowest height over the span and [`CONTEXT`] s around it, a stance's
/// anchor is the point's mean position over the whole stance (also outside
/// the span). Source: [`Source::Given`].
pub fn capture_plan(
    model: &Model,
    floor: &FloorPlane,
    points: &[usize],
    (t0, t1): (f64, f64),
    configuration: &dyn Fn(f64) -> Result<Vec<f64>, SpError>,
) -> Result<GapPlan, SpError> {
    let up = floor.up;
    let span = (t0 - CONTEXT, t1 + CONTEXT);
    let tracks = Tracks::sample(model, &up, points, span, (t0, t1), configuration)?;
    let points = points
        .iter()
        .enumerate()
        .map(|(j, &link)| {
            let stand = tracks.lowest(j, &up);
            let flags = tracks.flags(j, stand, &up);
            let stances = tracks
                .stances(j, &flags, (t0, t1))
                .into_iter()
                .map(|s| s.by(Source::Given))
                .collect();
            PointPlan {
                name: model.link(link).name.clone(),
                link,
                stand,
                stances,
            }
        })
        .collect();
    Ok(GapPlan { t0, t1, points })
}
