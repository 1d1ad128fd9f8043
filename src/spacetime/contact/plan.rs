//! The contact plan: a typed value on SP's [`Filling`](crate::spacetime::sp::Filling)
//! that says, per gap and per contact point, when the point stands and
//! where, and on which floor. The support IK holds the planned stances and
//! keeps every contact point at or above the floor; `sp_report(m).contacts`
//! lists it.
//!
//! The plan does not say how it was made, so every way of making one fills
//! the same value: today [`super::context::Context`] plans each gap from the
//! stances around it; an example's own contacts laid into the world, a step
//! planner, or a user's `contact: [...]` give a plan of the same shape.

use crate::ground::FloorPlane;
use nalgebra::Vector3;

/// Where a held point must be over part of a gap: on the straight path from
/// `p0` at `t0` to `p1` at `t1`. A planted foot stands still (`p0 == p1`,
/// its anchor); Rose's support path may move between two planted ends.
#[derive(Clone, Debug, PartialEq)]
pub struct Stance {
    pub t0: f64,
    pub t1: f64,
    pub p0: Vector3<f64>,
    pub p1: Vector3<f64>,
}

impl Stance {
    /// Planted at `anchor` over [t0, t1].
    pub fn planted(t0: f64, t1: f64, anchor: Vector3<f64>) -> Stance {
        Stance {
            t0,
            t1,
            p0: anchor,
            p1: anchor,
        }
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
    /// Its stances in the gap, in time order; empty: free (only kept above the floor).
    pub stances: Vec<Stance>,
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
                    stances: vec![Stance::planted(1.0, 1.4, a)],
                },
                PointPlan {
                    name: "Toes_R".into(),
                    link: 9,
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
        // a path between two ends
        let s = Stance {
            t0: 0.0,
            t1: 2.0,
            p0: Vector3::zeros(),
            p1: Vector3::x(),
        };
        assert_eq!(s.at(1.0), Vector3::new(0.5, 0.0, 0.0));
        assert_eq!(s.at(5.0), Vector3::x());
    }
}
