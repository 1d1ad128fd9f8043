//! The floor term: w max(0, floor − h_c(q(t)))² for every contact point of
//! the plan at every node, h = up · p (one one-sided row per point,
//! `points.rs`).

use super::super::error::{SpError, invalid};
use super::super::torque::BodyDynamics;
use super::layout::GapLayout;
use super::points::{PointRow, PointTerm};
use crate::ground::FloorPlane;
use crate::spacetime::contact::GapPlan;

/// The floor term of every point of `plan` over `floor` at `layout`'s nodes,
/// weight `weight` (m⁻² s⁻¹).
pub fn floor_term<'a>(
    body: &'a BodyDynamics<'a>,
    plan: &GapPlan,
    floor: FloorPlane,
    layout: &GapLayout,
    weight: f64,
) -> Result<PointTerm<'a>, SpError> {
    check_links(body, plan)?;
    let rows: Vec<PointRow> = plan
        .points
        .iter()
        .map(|p| PointRow {
            link: p.link,
            dir: -floor.up,
            target: -floor.height,
            one_sided: true,
        })
        .collect();
    let n = layout.nodes().0.len();
    PointTerm::new("floor", body, layout, weight, vec![rows; n])
}

/// `Err` naming the first point of `plan` on a link the body lacks.
pub(super) fn check_links(body: &BodyDynamics, plan: &GapPlan) -> Result<(), SpError> {
    let n = body.model.num_links();
    match plan.points.iter().find(|p| p.link >= n) {
        Some(p) => Err(invalid(format!(
            "the contact plan's point `{}` is on link {}, but the body has {n} links",
            p.name, p.link
        ))),
        None => Ok(()),
    }
}
