//! A gap's stances from the example SP follows (issue 42): the example is a
//! stretch whose context matches the gap's at both edges, so its gait phase
//! already matches there, and its own contacts are the best guess at when
//! and where the feet stand inside the gap — including stances wholly
//! inside it, which the edges alone never plan.
//!
//! The stances are read off the *laid* example (its poses in the world,
//! root aligned to both end states: [`crate::spacetime::reference::Lay`])
//! by `ground`'s planning rule, the same one that reads a capture's own
//! contacts ([`super::capture`]); a library example may bring the labels
//! its library stored at build time instead
//! ([`ExampleStances`], which `reference::ClipStretch` carries). Each stance is
//! anchored where the laid point is on average over it, put on the height
//! the point stands at around the gap (the floor for a toe, a few
//! centimetres above for an ankle).

use super::capture::Tracks;
use super::context::CONTEXT;
use super::plan::{GapPlan, PointPlan, Source, Stance};
use crate::ground::runs_of;
use crate::model::Model;
use crate::spacetime::error::SpError;
use nalgebra::Vector3;

/// One contact point's stances in a library example, on the gap's clock
/// (issues 42 and 43: the library example's contacts are the gap's plan).
#[derive(Clone, Debug, PartialEq)]
pub struct ExampleStances {
    /// The contact point: its joint's (link's) name, as the body names it.
    pub point: String,
    /// Stance intervals [t0, t1] (s, gap clock), in time order, over the
    /// gap and the context either side.
    pub spans: Vec<(f64, f64)>,
}

/// The points an example plan is made for: link and the height it stands at.
pub struct PlanPoint {
    pub link: usize,
    pub stand: f64,
}

/// Where an example's stance timing is read.
pub enum Timing<'a> {
    /// The library's stored spans, on the gap's clock, by point name.
    Stored(&'a [ExampleStances]),
    /// The example as recorded, on the gap's clock (the motion `shift`
    /// away): the planning rule on its own samples.
    Recorded(&'a dyn Fn(f64) -> Result<Vec<f64>, SpError>),
}

/// The stances of `points` inside [t0, t1] of an example: their timing from
/// `timing`, their anchors from the laid example that `configuration`
/// gives (the motion, with the laid example in the gap): the laid point's
/// mean over each stance, at the point's standing height. Source:
/// [`Source::Example`].
pub fn example_plan(
    model: &Model,
    up: &Vector3<f64>,
    points: &[PlanPoint],
    (t0, t1): (f64, f64),
    configuration: &dyn Fn(f64) -> Result<Vec<f64>, SpError>,
    timing: Timing,
) -> Result<GapPlan, SpError> {
    let links: Vec<usize> = points.iter().map(|p| p.link).collect();
    let span = (t0 - CONTEXT, t1 + CONTEXT);
    let tracks = Tracks::sample(model, up, &links, span, (t0, t1), configuration)?;
    let recorded = match timing {
        Timing::Recorded(c) => Some(Tracks::sample(model, up, &links, span, (t0, t1), c)?),
        Timing::Stored(_) => None,
    };
    let points = points
        .iter()
        .enumerate()
        .map(|(j, p)| {
            let name = model.link(p.link).name.clone();
            let spans: Vec<(f64, f64)> = match (&timing, &recorded) {
                (Timing::Stored(s), _) => s
                    .iter()
                    .find(|e| e.point == name)
                    .map_or(vec![], |e| e.spans.clone()),
                (_, Some(r)) => {
                    // the recorded example's own lowest: the rule reads it as recorded
                    let flags = r.flags(j, r.lowest(j, up), up);
                    runs_of(&flags)
                        .into_iter()
                        .map(|(a, b)| (r.times[a], r.times[b]))
                        .collect()
                }
                _ => vec![],
            };
            let flags = flags_of_spans(&tracks.times, &spans);
            let stances = tracks
                .stances(j, &flags, (t0, t1))
                .into_iter()
                .filter(|s| s.t1 > s.t0)
                .map(|s| on_height(s, up, p.stand).by(Source::Example))
                .collect();
            PointPlan {
                name,
                link: p.link,
                stand: p.stand,
                stances,
            }
        })
        .collect();
    Ok(GapPlan { t0, t1, points })
}

/// Per sample time, whether it lies in one of `spans`.
fn flags_of_spans(times: &[f64], spans: &[(f64, f64)]) -> Vec<bool> {
    times
        .iter()
        .map(|&t| spans.iter().any(|&(a, b)| t >= a && t <= b))
        .collect()
}

/// The stance with its anchors moved along `up` to height `stand`.
pub fn on_height(s: Stance, up: &Vector3<f64>, stand: f64) -> Stance {
    let put = |p: Vector3<f64>| p + up * (stand - up.dot(&p));
    Stance {
        p0: put(s.p0),
        p1: put(s.p1),
        ..s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spans_become_flags_and_anchors_go_onto_the_standing_height() {
        let f = flags_of_spans(&[0.0, 0.1, 0.2, 0.3], &[(0.05, 0.2)]);
        assert_eq!(f, vec![false, true, true, false]);
        let up = Vector3::new(0.0, 0.0, 1.0);
        let s = Stance::planted(1.0, 2.0, Vector3::new(0.3, -0.2, 0.07));
        let on = on_height(s, &up, 0.01);
        assert!(
            (on.p0 - Vector3::new(0.3, -0.2, 0.01)).norm() < 1e-15,
            "{on:?}"
        );
        assert_eq!(on.p1, on.p0);
        assert_eq!((on.t0, on.t1), (1.0, 2.0));
    }
}
