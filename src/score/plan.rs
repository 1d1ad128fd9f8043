//! How well a contact plan foresaw the reference's own contacts over a gap.
//!
//! The reference's contacts are read by the rule SP plans with
//! ([`capture_plan`]: a point stands while within 2 cm of its own lowest
//! height and slower than a share of the body's speed), so a plan is judged
//! against what the same rule reads off the capture: an ankle joint, which
//! never comes within 2 cm of the floor, stands on it as its toe does.
//!
//! Two numbers, per gap, pooled over gaps by their counts:
//! - **edges**: stance starts and ends strictly inside the gap (a stance cut
//!   by the gap's own edge has no event there). A planned edge matches a
//!   reference edge of the same point and kind (start or end) within
//!   [`EDGE_TOLERANCE`], one to one, nearest pairs first; the share is
//!   2·matched / (planned + reference edges): 1 when every edge is matched
//!   both ways, lowered alike by a missed stance and an invented one.
//! - **frames**: per contact point and frame of the gap, whether the plan
//!   has it standing exactly when the reference does; the share that agree.
//!
//! A point only one of the two plans lists is free (never standing) in the other.

use super::error::{ScoreError, Which};
use crate::ground::FloorPlane;
use crate::ground::{GroundOptions, contact_points, contacts_of_tracks, tracks};
use crate::model::Model;
use crate::motion::Mu;
use crate::spacetime::SpError;
use crate::spacetime::contact::{GapPlan, GivenStance, Stance, capture_plan};
use nalgebra::Vector3;

/// A planned stance edge counts as on time within this of the reference's (s).
pub const EDGE_TOLERANCE: f64 = 0.1;

/// A plan against the reference's contacts over gaps: counts, so gaps pool.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PlanAccuracy {
    /// Edge pairs within [`EDGE_TOLERANCE`], the plan's edges and the reference's.
    pub edges_matched: usize,
    pub edges_planned: usize,
    pub edges_reference: usize,
    /// (point, frame) pairs where plan and reference agree, and all of them.
    pub frames_agreeing: usize,
    pub frames: usize,
}

impl PlanAccuracy {
    /// 2·matched / (planned + reference edges); `None` when neither has an edge.
    pub fn edges(&self) -> Option<f64> {
        let n = self.edges_planned + self.edges_reference;
        (n > 0).then(|| 2.0 * self.edges_matched as f64 / n as f64)
    }

    /// The share of (point, frame) pairs that agree; `None` without frames.
    pub fn agreement(&self) -> Option<f64> {
        (self.frames > 0).then(|| self.frames_agreeing as f64 / self.frames as f64)
    }

    /// Pools another gap's counts into these.
    pub fn add(&mut self, o: &PlanAccuracy) {
        self.edges_matched += o.edges_matched;
        self.edges_planned += o.edges_planned;
        self.edges_reference += o.edges_reference;
        self.frames_agreeing += o.frames_agreeing;
        self.frames += o.frames;
    }
}

/// `link`'s stances in `g` (none when `g` does not list the point).
fn stances_of(g: &GapPlan, link: usize) -> &[Stance] {
    g.points
        .iter()
        .find(|p| p.link == link)
        .map_or(&[][..], |p| &p.stances)
}

/// The starts (`start`) or ends of `stances` strictly inside (t0, t1).
fn edges(stances: &[Stance], (t0, t1): (f64, f64), start: bool) -> Vec<f64> {
    let inside = |t: f64| {
        let eps = 1e-9 * t.abs().max(1.0);
        t > t0 + eps && t < t1 - eps
    };
    stances
        .iter()
        .map(|s| if start { s.t0 } else { s.t1 })
        .filter(|&t| inside(t))
        .collect()
}

/// Pairs of `a` and `b` within `tol`, one to one, nearest pairs first.
fn matched(a: &[f64], b: &[f64], tol: f64) -> usize {
    let mut pairs: Vec<(f64, usize, usize)> = vec![];
    for (i, x) in a.iter().enumerate() {
        for (j, y) in b.iter().enumerate() {
            let d = (x - y).abs();
            if d <= tol {
                pairs.push((d, i, j));
            }
        }
    }
    pairs.sort_by(|p, q| p.0.total_cmp(&q.0).then(p.1.cmp(&q.1)).then(p.2.cmp(&q.2)));
    let (mut used_a, mut used_b) = (vec![false; a.len()], vec![false; b.len()]);
    let mut n = 0;
    for (_, i, j) in pairs {
        if !used_a[i] && !used_b[j] {
            (used_a[i], used_b[j]) = (true, true);
            n += 1;
        }
    }
    n
}

/// `plan` against `reference` (the reference's own plan of the same gap,
/// whose span [t0, t1] is the gap's) at the gap's frames `times`.
pub fn plan_accuracy(plan: &GapPlan, reference: &GapPlan, times: &[f64]) -> PlanAccuracy {
    let span = (reference.t0, reference.t1);
    let mut links: Vec<usize> = reference.points.iter().map(|p| p.link).collect();
    for p in &plan.points {
        if !links.contains(&p.link) {
            links.push(p.link);
        }
    }
    let mut out = PlanAccuracy::default();
    for link in links {
        let (planned, actual) = (stances_of(plan, link), stances_of(reference, link));
        for start in [true, false] {
            let (a, b) = (edges(planned, span, start), edges(actual, span, start));
            out.edges_matched += matched(&a, &b, EDGE_TOLERANCE);
            out.edges_planned += a.len();
            out.edges_reference += b.len();
        }
        for &t in times {
            let standing = |s: &[Stance]| s.iter().any(|s| s.covers(t));
            out.frames_agreeing += usize::from(standing(planned) == standing(actual));
            out.frames += 1;
        }
    }
    out
}

/// The reference's own plan of the gap [t0, t1] ([`capture_plan`]) for
/// `points` (links) and the body's contact points, "up" along `up`.
pub fn reference_plan(
    reference: &Mu,
    body: &Model,
    up: Vector3<f64>,
    (t0, t1): (f64, f64),
    points: &[usize],
) -> Result<GapPlan, ScoreError> {
    let mut links: Vec<usize> = contact_points(body, None)
        .map_err(ScoreError::ground(Which::Reference))?
        .iter()
        .map(|p| p.link)
        .collect();
    for &l in points {
        if !links.contains(&l) {
            links.push(l);
        }
    }
    let names = body.coordinate_names();
    let configuration = |t: f64| -> Result<Vec<f64>, SpError> {
        names
            .iter()
            .map(|n| Ok(reference.sample(n, t)?.map_or(f64::NAN, |s| s[0])))
            .collect()
    };
    let floor = FloorPlane { up, height: 0.0 };
    capture_plan(body, &floor, &links, (t0, t1), &configuration).map_err(ScoreError::Plan)
}

/// The reference's own contacts as `contact:` takes them:
/// `ground::contacts(reference, body)` at its defaults (its contact points
/// within 2 cm of its floor and slower than 0.3 m/s, at its frame rate),
/// each stance at the point's mean position over it — what
/// `SP(m, body: b, contact: contacts(c, b))` is given with each `at:` from
/// the capture.
pub fn given_contacts(reference: &Mu, body: &Model) -> Result<Vec<GivenStance>, ScoreError> {
    let err = ScoreError::ground(Which::Reference);
    let opts = GroundOptions::default();
    let points = contact_points(body, None).map_err(&err)?;
    let tr = tracks(reference, body, &points, &opts).map_err(&err)?;
    let c = contacts_of_tracks(&tr, &opts).map_err(&err)?;
    let mut out = vec![];
    for (j, p) in c.points.iter().enumerate() {
        for iv in &p.intervals {
            let n = (iv.last - iv.first + 1) as f64;
            let at = (iv.first..=iv.last)
                .map(|k| tr.positions[k][j])
                .sum::<Vector3<f64>>()
                / n;
            out.push(GivenStance {
                point: p.name.clone(),
                from: iv.start,
                to: iv.stop,
                at: Some(at),
            });
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spacetime::contact::PointPlan;

    fn plan(points: Vec<(usize, Vec<(f64, f64)>)>) -> GapPlan {
        GapPlan {
            t0: 1.0,
            t1: 2.0,
            points: points
                .into_iter()
                .map(|(link, s)| PointPlan {
                    name: format!("p{link}"),
                    link,
                    stand: 0.0,
                    stances: s
                        .into_iter()
                        .map(|(a, b)| Stance::planted(a, b, Vector3::zeros()))
                        .collect(),
                })
                .collect(),
        }
    }

    fn frames() -> Vec<f64> {
        (1..10).map(|k| 1.0 + 0.1 * k as f64).collect()
    }

    #[test]
    fn a_plan_equal_to_the_reference_scores_one() {
        let r = plan(vec![(3, vec![(1.0, 1.35)]), (5, vec![(1.62, 2.0)])]);
        let a = plan_accuracy(&r, &r, &frames());
        assert_eq!((a.edges(), a.agreement()), (Some(1.0), Some(1.0)));
        // the gap's own edges are no events: one end and one start
        assert_eq!((a.edges_planned, a.edges_reference), (2, 2));
    }

    #[test]
    fn late_missing_and_invented_stances_count_against_the_plan() {
        let r = plan(vec![(3, vec![(1.0, 1.35)]), (5, vec![(1.62, 2.0)])]);
        // point 3 lifts 0.03 s late (on time), point 5 lands 0.3 s late (not)
        let p = plan(vec![(3, vec![(1.0, 1.38)]), (5, vec![(1.92, 2.0)])]);
        let a = plan_accuracy(&p, &r, &frames());
        assert_eq!(a.edges_matched, 1);
        assert_eq!(a.edges(), Some(0.5));
        // frames 1.7, 1.8, 1.9: point 5 stands in the reference only
        assert_eq!((a.frames_agreeing, a.frames), (15, 18));
        // a plan that lists no point: nothing stands, no edge matches
        let none = plan(vec![]);
        let a = plan_accuracy(&none, &r, &frames());
        assert_eq!(
            (a.edges_matched, a.edges_planned, a.edges_reference),
            (0, 0, 2)
        );
        assert_eq!(a.edges(), Some(0.0));
        // an invented stance of a point the reference never stands on
        let extra = plan(vec![
            (3, vec![(1.0, 1.35)]),
            (5, vec![(1.62, 2.0)]),
            (7, vec![(1.2, 1.5)]),
        ]);
        let a = plan_accuracy(&extra, &r, &frames());
        assert_eq!(a.edges(), Some(4.0 / 6.0));
        // pooled over gaps by counts
        let mut pooled = PlanAccuracy::default();
        pooled.add(&plan_accuracy(&r, &r, &frames()));
        pooled.add(&a);
        assert_eq!(pooled.edges(), Some(8.0 / 10.0));
        // no edge on either side: no share to give
        let whole = plan(vec![(3, vec![(1.0, 2.0)])]);
        assert_eq!(plan_accuracy(&whole, &whole, &frames()).edges(), None);
    }

    #[test]
    fn edges_pair_one_to_one_nearest_first() {
        assert_eq!(matched(&[1.0, 1.05], &[1.04], 0.1), 1);
        assert_eq!(matched(&[1.0, 1.3], &[1.04, 1.25], 0.1), 2);
        assert_eq!(matched(&[1.0], &[1.2], 0.1), 0);
    }
}
