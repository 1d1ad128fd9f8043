//! Whether SP stands the body on the ground (issue 35): the rule the
//! pipeline's grounded stages ask ([`super::root_fill`] leaving the cut
//! root open, [`super::transitions`] solving with the ground's terms and
//! forces, [`crate::spacetime::solve::grounded`]).
//!
//! The body stands when all of these hold, and otherwise SP is Rose's
//! (today's numbers, bit for bit):
//! - `contact:` is not `"none"` (the opt-out), and `support:` is not a
//!   list of frames (which asks for Rose's support IK);
//! - gravity acts (something is up: [`crate::ground::up_of`]);
//! - the body has contact points: the ones `contact:` names, or `ground`'s
//!   default ones (its ankle/toe/foot/heel joints). An arm, a pendulum or
//!   Rose's Fig. 10 arm have none, so SP on them never changes.

use super::checks::motion_err;
use super::filling::Filling;
use super::hold_contacts::contact_links;
use super::options::{SpOptions, Support};
use crate::ground::{FloorPlane, up_of};
use crate::model::{Model, RootCoords};
use crate::motion::time_tol;
use crate::spacetime::contact::{Contact, ContactPlan, GapPlan};
use crate::spacetime::error::{SpError, invalid};
use crate::spacetime::objective::{
    BaseTerm, Clearance, ContactForces, GapLayout, GroundScale, Objective, Term, clearance_term,
    floor_term, stance_term,
};
use crate::spacetime::solve::GroundModel;
use crate::spacetime::torque::BodyDynamics;
use nalgebra::Vector3;

/// Whether SP with `opts` stands `model` on the ground under `gravity`
/// (see the module docs). Errors only for a `contact:` naming a link the
/// body lacks.
pub fn stands(model: &Model, gravity: &Vector3<f64>, opts: &SpOptions) -> Result<bool, SpError> {
    let rose_support = !matches!(opts.support, Support::Auto { .. });
    if opts.contact == Contact::None || rose_support || up_of(gravity).is_none() {
        return Ok(false);
    }
    let (links, _) = contact_links(model, &opts.contact)?;
    Ok(!links.is_empty())
}

/// The friction coefficient of the feet's cones (the in-betweening
/// report's, shoe on floor).
pub const GROUND_FRICTION: f64 = 0.8;

/// The spike's weights relative to ∫Στ² weight 1 (m⁻² s⁻¹ on the points'
/// errors): stance 1e10 brought the worst stance error from 3–5 cm to 1–2 cm;
/// floor and clearance 1e9.
pub const STANCE_WEIGHT: f64 = 1e10;
pub const FLOOR_WEIGHT: f64 = 1e9;
pub const CLEARANCE_WEIGHT: f64 = 1e9;

/// How far around a gap a contact point's standing height is looked for (s).
const STAND_CONTEXT: f64 = 0.3;

/// One group's ground: its plan, the scales its base term and forces share
/// and each point's standing height.
struct GroupGround {
    plan: GapPlan,
    scale: GroundScale,
    stands: Vec<f64>,
}

/// The ground of SP's transitions ([`GroundModel`]): per group of gaps, the
/// contact plan `hold_contacts` made, the forces chosen in the cones at the
/// points planted at each node, and the ground's terms.
pub(super) struct SpGround<'a> {
    body: &'a BodyDynamics<'a>,
    floor: FloorPlane,
    root: &'a RootCoords,
    groups: Vec<GroupGround>,
}

impl<'a> SpGround<'a> {
    /// The ground of every gap plan of `plan` on `f`'s motion (the root's
    /// gaps open, everything else defined around the gaps).
    pub(super) fn new(
        f: &Filling<'_>,
        body: &'a BodyDynamics<'a>,
        root: &'a RootCoords,
        plan: &ContactPlan,
    ) -> Result<Self, SpError> {
        let sampler = f.sampler();
        let configuration = |t: f64| sampler.positions(t).map_err(motion_err);
        let up = plan.floor.up;
        let mut poses = vec![];
        let mut groups = vec![];
        for gap in &plan.gaps {
            let q0 = configuration(gap.t0)?;
            let scale = GroundScale::of(body, &q0)?;
            // each point's lowest height in the recorded frames around the gap
            let mut stands = vec![f64::INFINITY; gap.points.len()];
            let step = 1.0 / 60.0;
            let n = (STAND_CONTEXT / step).round() as usize;
            let times = (0..=n).flat_map(|k| {
                let d = k as f64 * step;
                [gap.t0 - d, gap.t1 + d]
            });
            for t in times {
                let q = configuration(t)?;
                if q.iter().any(|x| !x.is_finite()) {
                    continue;
                }
                body.model
                    .forward_kinematics(&q, &mut poses)
                    .map_err(|e| invalid(e.to_string()))?;
                for (h, p) in stands.iter_mut().zip(&gap.points) {
                    *h = h.min(poses[p.link].p.dot(&up));
                }
            }
            // a point never seen around the gap stands on the floor
            for h in &mut stands {
                if !h.is_finite() {
                    *h = plan.floor.height;
                }
            }
            groups.push(GroupGround {
                plan: gap.clone(),
                scale,
                stands,
            });
        }
        Ok(SpGround {
            body,
            floor: plan.floor,
            root,
            groups,
        })
    }

    /// The group whose span is `layout`'s.
    fn group(&self, layout: &GapLayout) -> Result<&GroupGround, SpError> {
        let dofs = layout.dofs();
        let t0 = dofs.iter().map(|d| d.t0).fold(f64::INFINITY, f64::min);
        let t1 = dofs.iter().map(|d| d.t1).fold(f64::NEG_INFINITY, f64::max);
        self.groups
            .iter()
            .find(|g| {
                (g.plan.t0 - t0).abs() <= time_tol(t0) && (g.plan.t1 - t1).abs() <= time_tol(t1)
            })
            .ok_or_else(|| {
                SpError::Numerical(format!("no contact plan for the gaps over [{t0}, {t1}] s"))
            })
    }
}

impl<'a> GroundModel<BodyDynamics<'a>> for SpGround<'a> {
    fn set_forces(
        &self,
        obj: &mut Objective<'_, BodyDynamics<'a>>,
        x: &[f64],
    ) -> Result<(), SpError> {
        let g = self.group(obj.layout())?;
        let forces =
            ContactForces::new(self.body, &g.plan, g.scale, GROUND_FRICTION, obj.layout())?
                .solve(obj, x)?;
        obj.set_forces(forces)
    }

    fn terms<'t>(
        &'t self,
        layout: &GapLayout,
        base: f64,
    ) -> Result<Vec<Box<dyn Term<BodyDynamics<'a>> + 't>>, SpError> {
        let g = self.group(layout)?;
        let (body, floor, plan) = (self.body, self.floor, &g.plan);
        let mut terms: Vec<Box<dyn Term<BodyDynamics<'a>> + 't>> = vec![
            Box::new(stance_term(body, plan, layout, STANCE_WEIGHT)?),
            Box::new(floor_term(body, plan, floor, layout, FLOOR_WEIGHT)?),
            Box::new(clearance_term(
                body,
                plan,
                &g.stands,
                floor,
                Clearance::of(&g.scale),
                layout,
                CLEARANCE_WEIGHT,
            )?),
        ];
        if base > 0.0 {
            terms.push(Box::new(BaseTerm::new(body, g.scale, base)?));
        }
        Ok(terms)
    }

    fn free_root(&self, layout: &GapLayout) -> bool {
        self.root.is_floating()
            && layout
                .dofs()
                .iter()
                .any(|d| self.root.all.contains(&d.coord))
    }
}

#[cfg(test)]
mod tests {
    use super::super::fixture::{Y_UP, body};
    use super::*;
    use crate::lie::Se3;
    use crate::model::Inertia;
    use crate::model::joints::Revolute;
    use std::sync::Arc;

    fn with(contact: Contact) -> SpOptions {
        SpOptions {
            contact,
            ..Default::default()
        }
    }

    #[test]
    fn a_body_with_feet_stands_under_gravity_unless_asked_not_to() {
        let b = body();
        assert!(stands(&b, &Y_UP, &with(Contact::Auto)).unwrap());
        assert!(stands(&b, &Y_UP, &with(Contact::Named(vec!["foot".into()]))).unwrap());
        assert!(!stands(&b, &Y_UP, &with(Contact::None)).unwrap());
        assert!(!stands(&b, &Vector3::zeros(), &with(Contact::Auto)).unwrap());
        let named = with(Contact::Named(vec!["hoof".into()]));
        assert!(stands(&b, &Y_UP, &named).is_err());
    }

    #[test]
    fn a_body_without_feet_never_stands() {
        let mut arm = Model::new("arm");
        let mass = Inertia::point(2.0, Vector3::new(0.0, -0.3, 0.0)).unwrap();
        let hinge = Arc::new(Revolute::new(Vector3::z()).unwrap());
        let upper = arm
            .add_link(
                "upper_arm",
                None,
                "shoulder",
                hinge.clone(),
                Se3::identity(),
                mass,
            )
            .unwrap();
        let below = Se3::from_translation(Vector3::new(0.0, -0.3, 0.0));
        arm.add_link("forearm", Some(upper), "elbow", hinge, below, mass)
            .unwrap();
        assert!(!stands(&arm, &Y_UP, &with(Contact::Auto)).unwrap());
    }
}
