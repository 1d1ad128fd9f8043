//! The stance term: w ‖p_c(q(t)) − anchor_c(t)‖² while the plan holds
//! point c (each of its stances; a planted point's anchor is fixed, a
//! support path's moves), three two-sided rows per held point
//! (`points.rs`).

use super::super::error::SpError;
use super::super::torque::BodyDynamics;
use super::layout::GapLayout;
use super::points::{PointRow, PointTerm};
use crate::spacetime::contact::GapPlan;
use nalgebra::Vector3;

/// The stance term of `plan` at `layout`'s nodes, weight `weight` (m⁻² s⁻¹).
pub fn stance_term<'a>(
    body: &'a BodyDynamics<'a>,
    plan: &GapPlan,
    layout: &GapLayout,
    weight: f64,
) -> Result<PointTerm<'a>, SpError> {
    super::floor::check_links(body, plan)?;
    let rows = layout
        .nodes()
        .0
        .iter()
        .map(|&t| {
            plan.points
                .iter()
                .filter_map(|p| Some((p.link, plan.anchor(p.link, t)?)))
                .flat_map(|(link, anchor)| {
                    (0..3).map(move |i| PointRow {
                        link,
                        dir: Vector3::ith(i, 1.0),
                        target: anchor[i],
                        one_sided: false,
                    })
                })
                .collect()
        })
        .collect();
    PointTerm::new("stance", body, layout, weight, rows)
}
