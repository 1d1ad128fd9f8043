//! The clearance term: a swinging contact point clears the height it stands
//! at by a margin, w max(0, stand_c + h_clear·ramp(t) − h_c(q(t)))², one
//! one-sided row per point not held at the node (`points.rs`).
//!
//! Without it a swinging foot may graze the floor all through its swing:
//! the floor term only keeps it above, and skate counts a foot point within
//! [`CONTACT_HEIGHT`] of the floor as on it (the spike found the term
//! essential). The margin ramps from 0 at each stance boundary and at the
//! gap's ends, where the point lifts off or touches down, so it never asks
//! a planted point to jump.
//!
//! The numbers hold on any body: the margin is a fraction of the body's
//! length L ([`GroundScale`]; 2 % is 3.4 cm on a 1.7 m person, the spike's
//! 3 cm on Bandai), and the ramp is the time to rise by it at ground's
//! stance speed ([`CONTACT_SPEED`]: a point slower than that counts as
//! standing), 0.11 s on that person.

use super::super::error::{SpError, invalid};
use super::super::torque::BodyDynamics;
use super::forces::GroundScale;
use super::layout::GapLayout;
use super::points::{PointRow, PointTerm};
use crate::ground::{CONTACT_HEIGHT, CONTACT_SPEED, FloorPlane};
use crate::spacetime::contact::GapPlan;

/// The margin as a fraction of the body's length.
const MARGIN_OF_LENGTH: f64 = 0.02;

/// How far a swinging point clears its standing height, and how fast the
/// margin ramps in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Clearance {
    /// Margin above the standing height (m).
    pub margin: f64,
    /// Time from a stance boundary to the full margin (s).
    pub ramp: f64,
}

impl Clearance {
    /// The margin of a body of scale `scale` (see the module doc); never
    /// under ground's contact height, so a cleared point is off the floor
    /// by skate's own rule.
    pub fn of(scale: &GroundScale) -> Clearance {
        let margin = (MARGIN_OF_LENGTH * scale.length).max(CONTACT_HEIGHT);
        Clearance {
            margin,
            ramp: margin / CONTACT_SPEED,
        }
    }

    /// The margin at time t, `d` seconds from the nearest boundary.
    fn at(&self, d: f64) -> f64 {
        self.margin * (d / self.ramp).clamp(0.0, 1.0)
    }
}

/// The clearance term of `plan` at `layout`'s nodes: point j of the plan
/// stands at height `stands[j]` (m along `floor.up`, its lowest height
/// around the gap); weight `weight` (m⁻² s⁻¹).
pub fn clearance_term<'a>(
    body: &'a BodyDynamics<'a>,
    plan: &GapPlan,
    stands: &[f64],
    floor: FloorPlane,
    clearance: Clearance,
    layout: &GapLayout,
    weight: f64,
) -> Result<PointTerm<'a>, SpError> {
    super::floor::check_links(body, plan)?;
    if stands.len() != plan.points.len() || stands.iter().any(|h| !h.is_finite()) {
        return Err(invalid(format!(
            "the clearance term needs a finite standing height for each of the plan's {} points, got {:?}",
            plan.points.len(),
            stands
        )));
    }
    if !(clearance.margin.is_finite() && clearance.margin >= 0.0 && clearance.ramp > 0.0) {
        return Err(invalid(format!(
            "the clearance's margin must be ≥ 0 m and its ramp > 0 s, got {clearance:?}"
        )));
    }
    let rows = layout
        .nodes()
        .0
        .iter()
        .map(|&t| {
            plan.points
                .iter()
                .zip(stands)
                .filter(|(p, _)| !p.stances.iter().any(|s| s.covers(t)))
                .map(|(p, &stand)| {
                    let d = p
                        .stances
                        .iter()
                        .map(|s| (t - s.t1).abs().min((s.t0 - t).abs()))
                        .fold((t - plan.t0).min(plan.t1 - t), f64::min);
                    PointRow {
                        link: p.link,
                        dir: -floor.up,
                        target: -(stand + clearance.at(d)),
                        one_sided: true,
                    }
                })
                .collect()
        })
        .collect();
    PointTerm::new("clearance", body, layout, weight, rows)
}
