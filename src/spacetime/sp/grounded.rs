//! Whether SP stands the body on the ground (issue 35), and the ground its
//! groups stand on (issue 42): [`SpGround`] makes each group's contact plan
//! from the motion being filled — its edges, `contact:`'s stances, the
//! laid example's own stances — re-makes it from a solve's result, and
//! gives the solve its forces and terms (`solve/group.rs` runs them).
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
use super::hold_contacts::contact_links;
use super::options::{SpOptions, Support};
use crate::ground::{FloorPlane, up_of};
use crate::model::{Model, RootCoords};
use crate::motion::JointSampler;
use crate::spacetime::contact::feet::land_toes_after_heels;
use crate::spacetime::contact::{
    Contact, Context, GapPlan, PlanPoint, Replan, Timing, example_plan, plan_given, with_edges,
};
use crate::spacetime::error::SpError;
use crate::spacetime::objective::{
    BaseTerm, Clearance, ContactForces, GapDof, GapLayout, GroundScale, Objective, Term,
    clearance_term, floor_term, stance_term,
};
use crate::spacetime::reference::LaidExample;
use crate::spacetime::solve::{GroundModel, GroundSettings, PlanSource};
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

/// The ground of SP's transitions ([`GroundModel`]) over the motion being
/// filled: its floor, its contact points, `contact:` and the settings.
pub(super) struct SpGround<'a> {
    body: &'a BodyDynamics<'a>,
    floor: FloorPlane,
    root: &'a RootCoords,
    /// The contact points `contact:` plans (links) and whether it named them.
    links: Vec<usize>,
    named: bool,
    contact: &'a Contact,
    /// The motion as it is before the transitions (the gaps undefined).
    sampler: JointSampler<'a>,
    settings: &'a GroundSettings,
}

impl<'a> SpGround<'a> {
    pub(super) fn new(
        body: &'a BodyDynamics<'a>,
        (floor, root): (FloorPlane, &'a RootCoords),
        contact: &'a Contact,
        sampler: JointSampler<'a>,
        settings: &'a GroundSettings,
    ) -> Result<Self, SpError> {
        let (links, named) = contact_links(body.model, contact)?;
        Ok(SpGround {
            body,
            floor,
            root,
            links,
            named,
            contact,
            sampler,
            settings,
        })
    }

    /// Every coordinate at t as `layout` at unknowns `x` moves the gap
    /// DOFs, the rest as recorded (NaN where undefined).
    fn configuration(&self, layout: &GapLayout, x: &[f64], t: f64) -> Result<Vec<f64>, SpError> {
        let mut q = self.sampler.positions(t).map_err(motion_err)?;
        for (d, g) in layout.dofs().iter().enumerate() {
            if t >= g.t0 && t <= g.t1 {
                q[g.coord] = layout.state(d, x, t)?[0];
            }
        }
        Ok(q)
    }

    /// The body's scale at the start of the plan's gap.
    fn scale(&self, plan: &GapPlan) -> Result<GroundScale, SpError> {
        let q0 = self.sampler.positions(plan.t0).map_err(motion_err)?;
        GroundScale::of(self.body, &q0)
    }
}

impl<'a> GroundModel<BodyDynamics<'a>> for SpGround<'a> {
    fn moves_contacts(&self, dofs: &[GapDof]) -> bool {
        let model = self.body.model;
        dofs.iter()
            .filter_map(|d| model.coordinate_link(d.coord))
            .any(|l| self.links.iter().any(|&c| model.is_ancestor(l, c)))
    }

    fn plan(
        &self,
        dofs: &[GapDof],
        layout: &GapLayout,
        x: &[f64],
        laid: Option<&LaidExample>,
    ) -> Result<GapPlan, SpError> {
        let model = self.body.model;
        let t0 = dofs.iter().map(|d| d.t0).fold(f64::INFINITY, f64::min);
        let t1 = dofs.iter().map(|d| d.t1).fold(f64::NEG_INFINITY, f64::max);
        let configuration = |t: f64| self.configuration(layout, x, t);
        let ctx = Context::new(
            model,
            &self.floor,
            &self.links,
            self.named,
            (t0, t1),
            &configuration,
        )?;
        if let Contact::Given(given) = self.contact {
            let points: Vec<(usize, f64)> = ctx.points().collect();
            return plan_given(model, given, &points, (t0, t1), &configuration);
        }
        let edges = ctx.plan();
        let laid = match self.settings.plan {
            PlanSource::Context => return Ok(feet_in_order(model, edges)),
            PlanSource::Steps => None,
            PlanSource::Auto | PlanSource::Example => laid,
        };
        let Some(laid) = laid else {
            if self.settings.plan == PlanSource::Example {
                return Ok(feet_in_order(model, edges));
            }
            let steps = ctx.steps(&configuration)?;
            return Ok(feet_in_order(model, with_edges(&edges, &steps)));
        };
        let points: Vec<PlanPoint> = ctx
            .points()
            .map(|(link, stand)| PlanPoint { link, stand })
            .collect();
        let shift = laid.example.shift;
        let recorded = |t: f64| self.sampler.positions(t + shift).map_err(motion_err);
        let timing = match laid
            .example
            .clip
            .as_ref()
            .and_then(|c| c.stances.as_deref())
        {
            Some(stored) => Timing::Stored(stored),
            None if laid.example.clip.is_none() => Timing::Recorded(&recorded),
            // a library example without stored labels: the laid poses' own
            None => Timing::Recorded(&configuration),
        };
        let inner = example_plan(
            model,
            &self.floor.up,
            &points,
            (t0, t1),
            &configuration,
            timing,
        )?;
        Ok(feet_in_order(model, with_edges(&edges, &inner)))
    }

    fn replan(
        &self,
        plan: &GapPlan,
        obj: &Objective<'_, BodyDynamics<'a>>,
        x: &[f64],
    ) -> Result<GapPlan, SpError> {
        let layout = obj.layout();
        let configuration = |t: f64| self.configuration(layout, x, t);
        Replan {
            model: self.body.model,
            up: self.floor.up,
            nodes: layout.nodes().0,
            forces: obj.forces(),
            weight: self.scale(plan)?.weight,
        }
        .of(plan, &configuration)
    }

    fn set_forces(
        &self,
        plan: &GapPlan,
        obj: &mut Objective<'_, BodyDynamics<'a>>,
        x: &[f64],
    ) -> Result<(), SpError> {
        let scale = self.scale(plan)?;
        let friction = self.settings.friction;
        let forces =
            ContactForces::new(self.body, plan, scale, friction, obj.layout())?.solve(obj, x)?;
        obj.set_forces(forces)
    }

    fn terms<'t>(
        &'t self,
        plan: &GapPlan,
        layout: &GapLayout,
        base: f64,
    ) -> Result<Vec<Box<dyn Term<BodyDynamics<'a>> + 't>>, SpError> {
        let (body, floor, s) = (self.body, self.floor, self.settings);
        let scale = self.scale(plan)?;
        let stands: Vec<f64> = plan.points.iter().map(|p| p.stand).collect();
        let mut terms: Vec<Box<dyn Term<BodyDynamics<'a>> + 't>> = vec![
            Box::new(stance_term(body, plan, layout, s.stance)?),
            Box::new(floor_term(body, plan, floor, layout, s.floor)?),
            Box::new(clearance_term(
                body,
                plan,
                &stands,
                floor,
                Clearance::of(&scale),
                layout,
                s.clearance,
            )?),
        ];
        if base > 0.0 {
            terms.push(Box::new(BaseTerm::new(body, scale, base)?));
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

    fn score(&self, plan: &mut GapPlan, layout: &GapLayout, x: &[f64]) -> Result<(), SpError> {
        let model = self.body.model;
        let mut poses = vec![];
        for p in &mut plan.points {
            for s in &mut p.stances {
                let n = ((s.t1 - s.t0) / SCORE_STEP).ceil().max(1.0) as usize;
                let mut worst: f64 = 0.0;
                for k in 0..=n {
                    let t = s.t0 + (s.t1 - s.t0) * k as f64 / n as f64;
                    let q = self.configuration(layout, x, t)?;
                    model
                        .forward_kinematics(&q, &mut poses)
                        .map_err(SpError::Kinematics)?;
                    worst = worst.max((poses[p.link].p - s.at(t)).norm());
                }
                s.solved = Some(worst);
            }
        }
        Ok(())
    }
}

/// The step (s) a stance's solved distance is measured at.
const SCORE_STEP: f64 = 1.0 / 120.0;

/// `plan` with each foot's points in a foot's order ([`land_toes_after_heels`]).
fn feet_in_order(model: &Model, mut plan: GapPlan) -> GapPlan {
    land_toes_after_heels(model, &mut plan);
    plan
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
