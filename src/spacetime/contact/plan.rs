//! The contact plan: a typed value on SP's [`Filling`](crate::spacetime::sp::Filling)
//! that says, per gap and per contact point, when the point stands and
//! where, and on which floor. The support IK holds the planned stances and
//! keeps every contact point at or above the floor; `sp_report(m).contacts`
//! lists it.
//!
//! Every way of making one fills the same value, and each stance says which
//! made it ([`Source`]): [`super::context::Context`] plans each gap from the
//! stances around it; a user's `contact: [...]` (or a capture's own contacts)
//! gives stances directly (`given.rs`).

use crate::ground::FloorPlane;
use nalgebra::Vector3;

/// Which of the plan's sources made a stance.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Source {
    /// Planned from the stances around the gap.
    #[default]
    Context,
    /// The example SP follows: its own contacts, laid into the world.
    Example,
    /// A step planner (cadence and step length of the context's steps).
    Steps,
    /// Stated by `contact: [...]` (a user's records, or a capture's contacts).
    Given,
    /// Re-estimated from a solve's result (its ends and anchor moved to
    /// where the solved point stood).
    Replanned,
}

impl Source {
    /// The name the report and the language use.
    pub fn name(self) -> &'static str {
        match self {
            Source::Context => "context",
            Source::Example => "example",
            Source::Steps => "steps",
            Source::Given => "given",
            Source::Replanned => "re-planned",
        }
    }
}

/// Where a held point must be over part of a gap: on the straight path from
/// `p0` at `t0` to `p1` at `t1`. A planted foot stands still (`p0 == p1`,
/// its anchor); Rose's support path may move between two planted ends.
#[derive(Clone, Debug, PartialEq)]
pub struct Stance {
    pub t0: f64,
    pub t1: f64,
    pub p0: Vector3<f64>,
    pub p1: Vector3<f64>,
    /// What made it.
    pub source: Source,
    /// After the solve: the solved point's largest distance (m) from where
    /// the stance holds it (`at`) over the stance; `None` before.
    pub solved: Option<f64>,
}

impl Stance {
    /// Planted at `anchor` over [t0, t1], by the context.
    pub fn planted(t0: f64, t1: f64, anchor: Vector3<f64>) -> Stance {
        Stance {
            t0,
            t1,
            p0: anchor,
            p1: anchor,
            source: Source::Context,
            solved: None,
        }
    }

    /// The same stance, made by `source`.
    pub fn by(self, source: Source) -> Stance {
        Stance { source, ..self }
    }

    /// Whether `t` is inside the stance, ends included.
    pub fn covers(&self, t: f64) -> bool {
        t >= self.t0 && t <= self.t1
    }

    /// Where the point must be at `t` (clamped into the stance).
    pub fn at(&self, t: f64) -> Vector3<f64> {
        let s = ((t - self.t0) / (self.t1 - self.t0)).clamp(0.0, 1.0);
        self.p0 * (1.0 - s) + self.p1 * s
    }
}

/// One contact point's stances in one gap.
#[derive(Clone, Debug, PartialEq)]
pub struct PointPlan {
    /// The link's name.
    pub name: String,
    /// Link index in the body.
    pub link: usize,
    /// The height (m along up, the floor's axis) the point stands at when
    /// planted: its own lowest height around the gap. An ankle joint stands
    /// ~8 cm above the floor its toe stands on; a clearance term keeps a
    /// swinging point above this, anchors lie on it.
    pub stand: f64,
    /// Its stances in the gap, in time order, not overlapping; empty: free
    /// (only kept above the floor).
    pub stances: Vec<Stance>,
}

impl PointPlan {
    /// The intervals of [t0, t1] where the point is free (swinging): the
    /// complement of its stances, in time order; empty intervals dropped.
    pub fn swings(&self, t0: f64, t1: f64) -> Vec<(f64, f64)> {
        let mut out = vec![];
        let mut from = t0;
        for s in &self.stances {
            if s.t0 > from {
                out.push((from, s.t0.min(t1)));
            }
            from = from.max(s.t1);
        }
        if t1 > from {
            out.push((from, t1));
        }
        out.retain(|(a, b)| b > a);
        out
    }
}

/// The plan of one gap (a group of overlapping gaps: their common span).
#[derive(Clone, Debug, PartialEq)]
pub struct GapPlan {
    pub t0: f64,
    pub t1: f64,
    /// Every contact point that can stand around the gap, planted or not.
    pub points: Vec<PointPlan>,
}

impl GapPlan {
    /// Where the point on `link` must be at `t`: its stance's anchor (or path
    /// point), `None` when it is free then or not in the plan.
    pub fn anchor(&self, link: usize, t: f64) -> Option<Vector3<f64>> {
        self.points
            .iter()
            .find(|p| p.link == link)?
            .stances
            .iter()
            .find(|s| s.covers(t))
            .map(|s| s.at(t))
    }
}

/// The contact plan of a whole motion.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactPlan {
    /// The floor every point stands on and stays above: `ground`'s floor of
    /// the motion's recorded part unless `floor:` states it.
    pub floor: FloorPlane,
    /// One entry per group of overlapping gaps, in time order.
    pub gaps: Vec<GapPlan>,
}

impl ContactPlan {
    /// An empty plan on `floor`.
    pub fn new(floor: FloorPlane) -> ContactPlan {
        ContactPlan {
            floor,
            gaps: vec![],
        }
    }

    /// The gap whose span holds `t`.
    pub fn gap_at(&self, t: f64) -> Option<&GapPlan> {
        self.gaps.iter().find(|g| t >= g.t0 && t <= g.t1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_plan_answers_where_a_point_stands_when() {
        let floor = FloorPlane {
            up: Vector3::y(),
            height: 0.04,
        };
        let mut plan = ContactPlan::new(floor);
        let a = Vector3::new(1.0, 0.05, 0.0);
        plan.gaps.push(GapPlan {
            t0: 1.0,
            t1: 2.0,
            points: vec![
                PointPlan {
                    name: "Toes_L".into(),
                    link: 7,
                    stand: 0.05,
                    stances: vec![Stance::planted(1.0, 1.4, a)],
                },
                PointPlan {
                    name: "Toes_R".into(),
                    link: 9,
                    stand: 0.05,
                    stances: vec![],
                },
            ],
        });
        let g = plan.gap_at(1.5).unwrap();
        assert_eq!(g.anchor(7, 1.2), Some(a));
        assert_eq!(g.anchor(7, 1.6), None, "lifted off");
        assert_eq!(g.anchor(9, 1.2), None, "free");
        assert_eq!(g.anchor(3, 1.2), None, "not a contact point");
        assert!(plan.gap_at(2.5).is_none());
        // the free intervals: the stances' complement inside the gap
        assert_eq!(g.points[0].swings(1.0, 2.0), vec![(1.4, 2.0)]);
        assert_eq!(g.points[1].swings(1.0, 2.0), vec![(1.0, 2.0)]);
        let mid = PointPlan {
            stances: vec![Stance::planted(1.2, 1.5, a), Stance::planted(1.5, 2.0, a)],
            ..g.points[0].clone()
        };
        assert_eq!(mid.swings(1.0, 2.0), vec![(1.0, 1.2)]);
        // a path between two ends
        let s = Stance {
            t0: 0.0,
            t1: 2.0,
            p0: Vector3::zeros(),
            p1: Vector3::x(),
            source: Source::Given,
            solved: None,
        };
        assert_eq!(s.at(1.0), Vector3::new(0.5, 0.0, 0.0));
        assert_eq!(s.at(5.0), Vector3::x());
    }
}
