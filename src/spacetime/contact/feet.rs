//! One foot's contact points keep a foot's order: it lands heel first and
//! leaves toe last. Each point's stances are planned on their own (the
//! gap's edges from each point's stance lengths, merged with the example's
//! or the step planner's), and a toe's stances are the longer (it stays down
//! through the push-off), so a toe could land long before its own ankle.

use super::plan::GapPlan;
use crate::model::Model;

/// A foot lands heel first and leaves toe last: a point below another
/// on one leg (a toe below its ankle) touches down inside the gap no
/// earlier than the point above it, and lifts off no earlier either (a
/// dash's toe was planted at the gap's end 0.3 s before its ankle, at the
/// spot the foot had not reached yet).
pub fn land_toes_after_heels(model: &Model, plan: &mut GapPlan) {
    let (t0, t1) = (plan.t0, plan.t1);
    let points = &mut plan.points;
    for below in 0..points.len() {
        for above in 0..points.len() {
            let (a, b) = (points[above].link, points[below].link);
            if a == b || !model.is_ancestor(a, b) {
                continue;
            }
            // the landing into the stance that reaches the gap's end
            let heel_lands = points[above]
                .stances
                .iter()
                .find(|s| s.t1 >= t1 && s.t0 > t0)
                .map(|s| s.t0);
            if let (Some(land), Some(toe)) = (
                heel_lands,
                points[below]
                    .stances
                    .iter_mut()
                    .find(|s| s.t1 >= t1 && s.t0 > t0),
            ) {
                toe.t0 = toe.t0.max(land).min(toe.t1);
            }
            // the lift-off from the stance the gap starts in
            let heel_lifts = points[above]
                .stances
                .iter()
                .find(|s| s.t0 <= t0 && s.t1 < t1)
                .map(|s| s.t1);
            if let (Some(lift), Some(toe)) = (
                heel_lifts,
                points[below]
                    .stances
                    .iter_mut()
                    .find(|s| s.t0 <= t0 && s.t1 < t1),
            ) {
                toe.t1 = toe.t1.max(lift);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lie::Se3;
    use crate::model::Inertia;
    use crate::model::joints::Revolute;
    use crate::spacetime::contact::plan::{PointPlan, Stance};
    use nalgebra::Vector3;
    use std::sync::Arc;

    /// shin → ankle → toe, and another leg's ankle beside.
    fn legs() -> (Model, [usize; 3]) {
        let mut m = Model::new("legs");
        let hinge = || Arc::new(Revolute::new(Vector3::x()).unwrap());
        let (id, i) = (Se3::identity(), Inertia::default());
        let shin = m.add_link("shin", None, "knee", hinge(), id, i).unwrap();
        let ankle = m
            .add_link("ankle", Some(shin), "a", hinge(), id, i)
            .unwrap();
        let toe = m.add_link("toe", Some(ankle), "t", hinge(), id, i).unwrap();
        let other = m.add_link("other", None, "o", hinge(), id, i).unwrap();
        (m, [ankle, toe, other])
    }

    fn point(name: &str, link: usize, spans: &[(f64, f64)]) -> PointPlan {
        PointPlan {
            name: name.into(),
            link,
            stand: 0.0,
            stances: spans
                .iter()
                .map(|&(a, b)| Stance::planted(a, b, Vector3::zeros()))
                .collect(),
        }
    }

    #[test]
    fn a_toe_lands_with_its_ankle_and_leaves_after_it() {
        let (m, [ankle, toe, other]) = legs();
        let mut plan = GapPlan {
            t0: 1.0,
            t1: 2.0,
            points: vec![
                point("ankle", ankle, &[(1.0, 1.3), (1.8, 2.0)]),
                point("toe", toe, &[(1.0, 1.2), (1.5, 2.0)]),
                point("other", other, &[(1.0, 1.1), (1.4, 2.0)]),
            ],
        };
        land_toes_after_heels(&m, &mut plan);
        let spans = |k: usize| -> Vec<(f64, f64)> {
            plan.points[k]
                .stances
                .iter()
                .map(|s| (s.t0, s.t1))
                .collect()
        };
        // the toe lifts no earlier than its ankle and lands no earlier
        assert_eq!(spans(1), [(1.0, 1.3), (1.8, 2.0)]);
        // the ankle and another leg's point are not moved
        assert_eq!(spans(0), [(1.0, 1.3), (1.8, 2.0)]);
        assert_eq!(spans(2), [(1.0, 1.1), (1.4, 2.0)]);
    }
}
