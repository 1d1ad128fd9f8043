//! One gap's plan from several sources, in their order of precedence
//! (issue 42): a user's `contact: [...]` over everything; then the gap's
//! edges (the motion is recorded there, so a foot planted at an edge is
//! planted there, where it was); then the example's or the step planner's
//! stances inside the gap.
//!
//! At an edge where the context has the point planted, the stance keeps
//! the context's anchor (the recorded position) and takes its lift-off (or
//! touch-down) from the inner source when that has the point planted there
//! too: the example's gait phase tells the timing better than the
//! context's mean stance length. Where the context has the point in the
//! air at an edge, an inner stance over that edge starts (ends) a short
//! swing later (earlier), or goes when too little is left.

use super::plan::{GapPlan, PointPlan, Stance};

/// The least swing (s) between an edge the context has the point in the
/// air at and a stance the inner source plans next to it, and the least
/// stance worth planting: 0.1 s, three frames at 30 Hz, under the shortest
/// stance of a sprint (~0.1 s).
pub const MIN_PHASE: f64 = 0.1;

/// The plan of one gap from its edges (`edges`: the context's plan) and an
/// inner source's (`inner`, the same points); points are matched by link.
pub fn with_edges(edges: &GapPlan, inner: &GapPlan) -> GapPlan {
    let (t0, t1) = (edges.t0, edges.t1);
    let points = edges
        .points
        .iter()
        .map(|e| {
            let inner = inner
                .points
                .iter()
                .find(|p| p.link == e.link)
                .map_or(&[][..], |p| p.stances.as_slice());
            PointPlan {
                stances: merged(&e.stances, inner, (t0, t1)),
                ..e.clone()
            }
        })
        .collect();
    GapPlan { t0, t1, points }
}

/// One point's stances: `edges` (the context's) at the gap's edges, `inner`
/// inside (see the module doc).
fn merged(edges: &[Stance], inner: &[Stance], (t0, t1): (f64, f64)) -> Vec<Stance> {
    let tol = 1e-9 * (1.0 + t1.abs());
    let at_start = edges.iter().find(|s| s.t0 <= t0 + tol);
    let at_end = edges.iter().rev().find(|s| s.t1 >= t1 - tol);
    // planted over the whole gap in one place: the edges decide alone
    if let Some(s) = at_start
        && s.t1 >= t1 - tol
    {
        return vec![s.clone()];
    }
    let mut inner: Vec<Stance> = inner.to_vec();
    // the start edge
    let first_inner = inner.first().filter(|s| s.t0 <= t0 + tol).cloned();
    let mut out = vec![];
    match (at_start, first_inner) {
        (Some(e), Some(i)) => {
            inner.remove(0);
            out.push(Stance {
                t1: i.t1,
                ..e.clone()
            });
        }
        (Some(e), None) => {
            let next = inner.first().map_or(t1, |s| s.t0 - MIN_PHASE);
            out.push(Stance {
                t1: e.t1.min(next),
                ..e.clone()
            });
        }
        (None, Some(i)) => {
            inner[0].t0 = i.t0.max(t0 + MIN_PHASE);
        }
        (None, None) => {}
    }
    // the end edge
    let last_inner = inner.last().filter(|s| s.t1 >= t1 - tol).cloned();
    let mut tail = None;
    match (at_end, last_inner) {
        (Some(e), Some(i)) => {
            inner.pop();
            tail = Some(Stance {
                t0: i.t0,
                ..e.clone()
            });
        }
        (Some(e), None) => {
            let prev = inner.last().map_or(t0, |s| s.t1 + MIN_PHASE);
            tail = Some(Stance {
                t0: e.t0.max(prev),
                ..e.clone()
            });
        }
        (None, Some(i)) => {
            let n = inner.len();
            inner[n - 1].t1 = i.t1.min(t1 - MIN_PHASE);
        }
        (None, None) => {}
    }
    out.extend(inner);
    out.extend(tail);
    // the shortened ones that are too short to plant go; what remains is in
    // time order and, where two touch, the later starts after the earlier
    out.retain(|s| s.t1 - s.t0 >= MIN_PHASE || touches_edge(s, t0, t1, tol));
    out.sort_by(|a, b| a.t0.total_cmp(&b.t0));
    for k in 1..out.len() {
        if out[k].t0 < out[k - 1].t1 {
            out[k].t0 = out[k - 1].t1;
        }
    }
    out.retain(|s| s.t1 > s.t0);
    out
}

/// Whether a stance holds the point at one of the gap's edges (kept
/// however short: the point is planted there).
fn touches_edge(s: &Stance, t0: f64, t1: f64, tol: f64) -> bool {
    s.t0 <= t0 + tol || s.t1 >= t1 - tol
}

#[cfg(test)]
mod tests {
    use super::super::plan::Source;
    use super::*;
    use nalgebra::Vector3;

    fn at(x: f64) -> Vector3<f64> {
        Vector3::new(x, 0.0, 0.0)
    }

    fn plan(stances: Vec<Stance>) -> GapPlan {
        GapPlan {
            t0: 1.0,
            t1: 2.0,
            points: vec![PointPlan {
                name: "toe".into(),
                link: 3,
                stand: 0.0,
                stances,
            }],
        }
    }

    fn inner(t0: f64, t1: f64, x: f64) -> Stance {
        Stance::planted(t0, t1, at(x)).by(Source::Example)
    }

    #[test]
    fn an_edge_stance_keeps_its_anchor_and_takes_the_inner_lift_off() {
        let edges = plan(vec![
            Stance::planted(1.0, 1.5, at(0.0)),
            Stance::planted(1.8, 2.0, at(9.0)),
        ]);
        let ex = plan(vec![
            inner(1.0, 1.3, 0.1),
            inner(1.45, 1.7, 5.0),
            inner(1.9, 2.0, 8.8),
        ]);
        let got = &with_edges(&edges, &ex).points[0].stances;
        assert_eq!(got.len(), 3, "{got:?}");
        assert_eq!((got[0].t0, got[0].t1, got[0].p0), (1.0, 1.3, at(0.0)));
        assert_eq!(got[0].source, Source::Context);
        // the stance wholly inside the gap: the example's own
        assert_eq!((got[1].t0, got[1].t1, got[1].p0), (1.45, 1.7, at(5.0)));
        assert_eq!(got[1].source, Source::Example);
        assert_eq!((got[2].t0, got[2].t1, got[2].p0), (1.9, 2.0, at(9.0)));
    }

    #[test]
    fn a_point_in_the_air_at_an_edge_is_not_planted_there() {
        let edges = plan(vec![]);
        let ex = plan(vec![inner(1.0, 1.4, 0.0), inner(1.95, 2.0, 1.0)]);
        let got = &with_edges(&edges, &ex).points[0].stances;
        // the first starts a swing later; the last is too short once cut: gone
        assert_eq!(got.len(), 1, "{got:?}");
        assert!((got[0].t0 - 1.1).abs() < 1e-12 && got[0].t1 == 1.4);
    }

    #[test]
    fn planted_through_the_gap_in_one_place_stays_so() {
        let edges = plan(vec![Stance::planted(1.0, 2.0, at(0.0))]);
        let ex = plan(vec![inner(1.0, 1.2, 0.0), inner(1.5, 2.0, 0.3)]);
        let got = &with_edges(&edges, &ex).points[0].stances;
        assert_eq!(got, &edges.points[0].stances);
    }

    #[test]
    fn an_edge_stance_without_an_inner_one_ends_a_swing_before_the_next() {
        let edges = plan(vec![Stance::planted(1.0, 1.6, at(0.0))]);
        let ex = plan(vec![inner(1.5, 1.8, 2.0)]);
        let got = &with_edges(&edges, &ex).points[0].stances;
        assert_eq!(got.len(), 2, "{got:?}");
        assert!((got[0].t1 - 1.4).abs() < 1e-12);
        assert_eq!((got[1].t0, got[1].t1), (1.5, 1.8));
    }
}
