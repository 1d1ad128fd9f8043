//! A motion's own contacts inside a span as a gap's plan: what a capture did
//! where SP is asked to fill. It is the known answer a planned gap is
//! measured against, and a plan a user can give SP (`contact:` with a
//! capture's contacts): the same planning stance rule as the context's
//! ([`plan_stances`]), applied to the motion's own samples through the span.

use super::context::{CONTEXT, STEP, body_link};
use super::plan::{GapPlan, PointPlan, Source, Stance};
use crate::ground::{FloorPlane, plan_stances};
use crate::model::Model;
use crate::spacetime::error::SpError;
use nalgebra::Vector3;

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
    let body = body_link(model, &up);
    let n = ((t1 - t0 + 2.0 * CONTEXT) / STEP).round() as usize;
    let mut poses = vec![];
    let (mut ts, mut ps, mut bs) = (vec![], vec![vec![]; points.len()], vec![]);
    for k in 0..=n {
        let t = t0 - CONTEXT + k as f64 * STEP;
        let q = configuration(t)?;
        let defined = q.iter().all(|v| v.is_finite());
        if !defined && (t0..=t1).contains(&t) {
            return Err(SpError::Incomplete(format!(
                "contact: a motion's own contacts need the motion at {t:.4} s inside [{t0}, {t1}]"
            )));
        }
        if !defined {
            continue;
        }
        model
            .forward_kinematics(&q, &mut poses)
            .map_err(SpError::Kinematics)?;
        ts.push(t);
        for (j, &f) in points.iter().enumerate() {
            ps[j].push(poses[f].p);
        }
        bs.push(body.map_or_else(Vector3::zeros, |b| poses[b].p));
    }
    let points = points
        .iter()
        .zip(&ps)
        .map(|(&link, p)| {
            let stand = p.iter().map(|x| up.dot(x)).fold(f64::INFINITY, f64::min);
            let flags = plan_stances(p, &bs, STEP, stand, &up);
            let stances = runs(&flags)
                .into_iter()
                .filter(|&(a, b)| ts[b] >= t0 && ts[a] <= t1)
                .map(|(a, b)| {
                    let anchor = p[a..=b].iter().sum::<Vector3<f64>>() / (b - a + 1) as f64;
                    Stance::planted(ts[a].max(t0), ts[b].min(t1), anchor).by(Source::Given)
                })
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

/// The runs of `true` in `flags`: (first, last) sample, inclusive.
pub(super) fn runs(flags: &[bool]) -> Vec<(usize, usize)> {
    let mut out = vec![];
    let mut k = 0;
    while k < flags.len() {
        if flags[k] {
            let first = k;
            while k + 1 < flags.len() && flags[k + 1] {
                k += 1;
            }
            out.push((first, k));
        }
        k += 1;
    }
    out
}
