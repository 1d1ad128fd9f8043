//! What the terms share at one quadrature node: the body's kinematic and
//! inverse-dynamics passes at the node's state ([`crate::dynamics::StateCache`],
//! computed on the first term's request and reused by the next term at the
//! same node), and the seeds of the node's one reverse sweep.
//!
//! A term reads link poses ([`Node::poses`]), a link origin's Jacobian
//! ([`Node::point_jacobian`]), τ with the node's held contact forces
//! ([`Node::tau`]) and the root's wrench ([`Node::root_wrench`]). Its
//! gradient through τ and the root's wrench goes in as seeds
//! ([`NodeGrad::seed_tau`], [`NodeGrad::seed_root`]); after every term the
//! objective chains all of them to q, q̇, q̈ with one reverse sweep
//! ([`Objective::chain_seeds`]), so the torque and base terms cost one RNEA
//! and one sweep together. A term that needs a sweep of its own (the base
//! term's Gauss–Newton rows, one per residual) runs it with [`Node::reverse`].

use super::super::error::SpError;
use super::super::torque::{BodyDynamics, TorqueModel};
use super::node_seeds::Shared;
use super::term::{Node, NodeGrad};
use super::{NodeScratch, Objective};
use crate::dynamics::{JointState, Loaded, PointForce, StateCache, StateGradient};
use crate::lie::{Se3, Twist, Wrench};
use nalgebra::Vector3;

impl NodeGrad<'_> {
    /// ∂f/∂τ at this node, one entry per coordinate, to add to: τ's
    /// gradient is chained to q, q̇, q̈ by the node's reverse sweep after
    /// every term (with the node's held forces fixed; see [`Node::tau`]).
    pub fn seed_tau(&mut self) -> &mut [f64] {
        self.seeds.on_tau = true;
        &mut self.seeds.tau
    }

    /// Adds ∂f/∂w_root, paired with the root's wrench [moment; force]
    /// component by component (see [`Node::root_wrench`]).
    pub fn seed_root(&mut self, g: &Twist) {
        self.seeds.on_root = true;
        self.seeds.root += g;
    }
}

/// `Err` for a term that reads the body's passes on a model without one.
fn no_body(what: &str) -> SpError {
    SpError::Invalid(format!(
        "an objective term reads the body's {what}, but the model is not a multibody body"
    ))
}

/// The cache, built for `body` at its first use.
fn cache_for<'c>(cache: &'c mut Option<StateCache>, body: &BodyDynamics) -> &'c mut StateCache {
    cache.get_or_insert_with(|| StateCache::new(body.model))
}

/// The state at a node with the forces held there.
fn loaded<'x>(body: &'x BodyDynamics, x: JointState<'x>, forces: &'x [PointForce]) -> Loaded<'x> {
    Loaded {
        x,
        gravity: &body.gravity,
        forces,
    }
}

impl<'s, M: TorqueModel> Node<'s, M> {
    /// The body and the node's state with its held forces.
    fn passes(&self, what: &str) -> Result<(&'s BodyDynamics<'s>, Loaded<'s>), SpError> {
        let model: &'s M = self.model;
        let body = model.multibody().ok_or_else(|| no_body(what))?;
        let forces: &'s [PointForce] = self.forces.map_or(&[], |f| &f.forces);
        let x = JointState::new(self.q, self.v, self.a);
        Ok((body, loaded(body, x, forces)))
    }

    /// The links' world poses at the node.
    pub fn poses(&mut self) -> Result<&[Se3], SpError> {
        let (body, s) = self.passes("link poses")?;
        let cache = cache_for(&mut self.shared.cache, body);
        Ok(cache.poses(body.model, &s.x)?)
    }

    /// (c, ∂p/∂q_c) for every coordinate c that moves the origin p of
    /// `link` at the node (see [`StateCache::point_jacobian`]).
    pub fn point_jacobian(&mut self, link: usize) -> Result<&[(usize, Vector3<f64>)], SpError> {
        let (body, s) = self.passes("point Jacobians")?;
        let cache = cache_for(&mut self.shared.cache, body);
        Ok(cache.point_jacobian(body.model, &s.x, link)?)
    }

    /// τ at the node with its held contact forces acting,
    /// τ = ID − Σ J_cᵀ f_c (none held: plain inverse dynamics).
    pub fn tau(&mut self) -> Result<&[f64], SpError> {
        let (body, s) = self.passes("inverse dynamics")?;
        let cache = cache_for(&mut self.shared.cache, body);
        Ok(cache.tau(body.model, &s)?)
    }

    /// The wrench the world applies through the root joints at the node,
    /// with its held forces acting (moment about the world origin, force;
    /// world axes; [`crate::dynamics::root_wrench`]).
    pub fn root_wrench(&mut self) -> Result<Wrench, SpError> {
        let (body, s) = self.passes("inverse dynamics")?;
        let cache = cache_for(&mut self.shared.cache, body);
        Ok(cache.root_wrench(body.model, &s)?)
    }

    /// The gradient with respect to the node's q, q̇, q̈ of
    /// `tau_bar · τ + root_bar · w_root` (none: a zero seed), the held forces
    /// fixed: one reverse sweep of its own, valid until the next call.
    pub fn reverse(
        &mut self,
        tau_bar: Option<&[f64]>,
        root_bar: Option<&Twist>,
    ) -> Result<[&[f64]; 3], SpError> {
        let (body, s) = self.passes("inverse dynamics")?;
        let Shared { cache, grad } = &mut *self.shared;
        let [q, v, a] = grad;
        let out = StateGradient { q, v, a };
        cache_for(cache, body).reverse(body.model, &s, tau_bar, root_bar, out)?;
        let [q, v, a] = &self.shared.grad;
        Ok([q, v, a])
    }
}

impl<M: TorqueModel> Objective<'_, M> {
    /// After every term at node k: the seeds they gave chained to the
    /// state gradient by one reverse sweep, added to it.
    pub(super) fn chain_seeds(
        &self,
        k: usize,
        s: &mut NodeScratch<M::Workspace>,
    ) -> Result<(), SpError> {
        let NodeScratch {
            q,
            v,
            a,
            gq,
            gv,
            ga,
            shared,
            seeds,
            ..
        } = s;
        if !(seeds.on_tau || seeds.on_root) {
            return Ok(());
        }
        let body = (self.torque.model)
            .multibody()
            .ok_or_else(|| no_body("inverse dynamics"))?;
        let forces: &[PointForce] = self.forces.get(k).map_or(&[], |f| &f.forces);
        let at = loaded(body, JointState::new(q, v, a), forces);
        let Shared { cache, grad } = shared;
        let [sq, sv, sa] = grad;
        let out = StateGradient {
            q: sq,
            v: sv,
            a: sa,
        };
        let tau_bar = seeds.on_tau.then_some(seeds.tau.as_slice());
        let root_bar = seeds.on_root.then_some(&seeds.root);
        cache_for(cache, body).reverse(body.model, &at, tau_bar, root_bar, out)?;
        for (out, g) in [(gq, &*sq), (gv, &*sv), (ga, &*sa)] {
            for (o, x) in out.iter_mut().zip(g) {
                *o += x;
            }
        }
        Ok(())
    }
}
