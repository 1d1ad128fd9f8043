//! The contact forces of a grounded objective: per quadrature node, the
//! forces at the points the plan plants then that best supply the wrench the
//! motion needs, each inside its friction cone ([`crate::ground::cone`]).
//!
//! The forces are held fixed while the solver moves x and re-solved between
//! solves ([`ContactForces::solve`], then [`super::Objective::set_forces`]).
//! The cone problem minimises ‖F − Σf‖²/(mg)² + ‖μ − Σ r×f‖²/(mgL)² about
//! the centre of mass c, the same norm as the base term's
//! ([`super::base::BaseTerm`]) with its moment taken about the same c
//! ([`NodeForces::reference`]): at the cone problem's optimum the base
//! term's gradient with the forces held fixed is the gradient of the
//! optimum itself (envelope theorem), so nothing is lost by holding them.

use super::super::error::{SpError, invalid};
use super::super::torque::BodyDynamics;
use super::Objective;
use super::layout::GapLayout;
use super::term::NodeForces;
use crate::dynamics::{JointState, Loaded, PointForce, StateCache};
use crate::ground::cone::best_contact_forces;
use crate::ground::residual::{centre_of_mass, length_scale};
use crate::ground::up_direction;
use crate::lie::{Se3, Wrench};
use crate::spacetime::contact::GapPlan;
use nalgebra::Vector3;

/// The scales the base term and the cone problem share: the body's weight
/// m|g| (N) and its length L (m: the largest extent of its joint points, as
/// `ground_residual` takes it), so a moment of L·1 N weighs as 1 N.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GroundScale {
    pub weight: f64,
    pub length: f64,
}

impl GroundScale {
    /// The scales of `body` at configuration `q` (take it once per group of
    /// gaps, e.g. at the first node of the start, and give the same value to
    /// the base term and the forces).
    pub fn of(body: &BodyDynamics, q: &[f64]) -> Result<GroundScale, SpError> {
        let weight = body.model.total_mass() * body.gravity.norm();
        if !(weight.is_finite() && weight > 0.0) {
            return Err(invalid(format!(
                "the ground terms weigh forces by the body's weight, but `{}` weighs {weight} N",
                body.model.name
            )));
        }
        let mut poses: Vec<Se3> = vec![];
        body.model
            .forward_kinematics(q, &mut poses)
            .map_err(SpError::Kinematics)?;
        Ok(GroundScale {
            weight,
            length: length_scale(&poses, body.model),
        })
    }
}

/// The per-node cone problems of one objective: which links the plan plants
/// at each node.
pub struct ContactForces<'a> {
    body: &'a BodyDynamics<'a>,
    up: Vector3<f64>,
    scale: GroundScale,
    friction: f64,
    /// Per node, the links planted there.
    planted: Vec<Vec<usize>>,
}

impl<'a> ContactForces<'a> {
    /// The cone problems at `layout`'s nodes for the points `plan` plants
    /// there, with friction coefficient `friction` (≥ 0).
    pub fn new(
        body: &'a BodyDynamics<'a>,
        plan: &GapPlan,
        scale: GroundScale,
        friction: f64,
        layout: &GapLayout,
    ) -> Result<Self, SpError> {
        if !(friction.is_finite() && friction >= 0.0) {
            return Err(invalid(format!(
                "friction must be a finite coefficient ≥ 0, got {friction}"
            )));
        }
        let up = up_direction(&body.gravity)?;
        let planted = planted_links(body, plan, layout)?;
        Ok(ContactForces {
            body,
            up,
            scale,
            friction,
            planted,
        })
    }

    /// The best forces at every node of `obj` for unknowns `x` (nodes in
    /// parallel): inverse dynamics without forces gives the wrench the
    /// motion needs, moved to the centre of mass c; the cone problem spreads
    /// it over the planted points. With no point planted a node has no
    /// forces (and c still as its reference).
    pub fn solve(
        &self,
        obj: &Objective<'_, BodyDynamics<'_>>,
        x: &[f64],
    ) -> Result<Vec<NodeForces>, SpError> {
        use rayon::prelude::*;
        if obj.n_nodes() != self.planted.len() {
            return Err(invalid(format!(
                "the contact forces were laid on {} nodes but the objective has {}",
                self.planted.len(),
                obj.n_nodes()
            )));
        }
        (0..self.planted.len())
            .into_par_iter()
            .map_init(
                || StateCache::new(self.body.model),
                |cache, k| {
                    let [q, v, a] = obj.node_state(x, k);
                    self.at_node(cache, k, JointState::new(&q, &v, &a))
                },
            )
            .collect()
    }

    /// The forces at node k in state `x`: one inverse dynamics, whose
    /// velocity pass also places the links for the centre of mass and the
    /// planted points (a separate forward kinematics cost as much again).
    fn at_node(
        &self,
        cache: &mut StateCache,
        k: usize,
        x: JointState,
    ) -> Result<NodeForces, SpError> {
        let model = self.body.model;
        let s = Loaded {
            x,
            gravity: &self.body.gravity,
            forces: &[],
        };
        let w0 = cache.root_wrench(model, &s)?;
        let poses = cache.poses(model, &x)?;
        let c = centre_of_mass(poses, model);
        let f = Vector3::new(w0[3], w0[4], w0[5]);
        let mu = Vector3::new(w0[0], w0[1], w0[2]) - c.cross(&f);
        let w = Wrench::new(mu.x, mu.y, mu.z, f.x, f.y, f.z);
        let links = &self.planted[k];
        let arms: Vec<Vector3<f64>> = links.iter().map(|&l| poses[l].p - c).collect();
        let s = best_contact_forces(&w, &arms, &self.up, self.friction, self.scale.length)?;
        let forces = links
            .iter()
            .zip(s.forces)
            .map(|(&l, f)| PointForce::at(l, Vector3::zeros(), f))
            .collect();
        Ok(NodeForces {
            forces,
            reference: c,
        })
    }
}

/// Per node of `layout`, the links `plan` plants at the node's time;
/// an error if the plan names a link the body lacks.
fn planted_links(
    body: &BodyDynamics,
    plan: &GapPlan,
    layout: &GapLayout,
) -> Result<Vec<Vec<usize>>, SpError> {
    super::floor::check_links(body, plan)?;
    Ok(layout
        .nodes()
        .0
        .iter()
        .map(|&t| {
            plan.points
                .iter()
                .filter(|p| p.stances.iter().any(|s| s.covers(t)))
                .map(|p| p.link)
                .collect()
        })
        .collect())
}
