//! The base term: the root's six equations with the contact forces,
//! w_b ‖S (W_root − Σ W_c)‖² per node — the wrench the motion needs beyond
//! what the held contact forces supply, as force/(m g) and moment about the
//! node's reference point /(m g L) ([`super::forces`]).
//!
//! Frames: `dynamics::root_wrench` after inverse dynamics with the forces
//! acting is the spatial wrench the world applies through the root joints
//! (moment about the world origin, world axes) — not the root coordinates'
//! generalised forces, whose rotational part is in Euler coordinates and
//! changes with the root's orientation. Its moment is moved to the
//! reference c: μ_c = μ_O − c × F. The reference is held fixed with the
//! forces, so the residual is exactly the cone problem's, and its gradient
//! (the envelope theorem) that of the best forces.
//!
//! The residual comes from the node's shared inverse dynamics
//! ([`Node::root_wrench`], the same RNEA the torque term reads); its
//! gradient is the seed ∂f/∂w_root of the node's one reverse sweep
//! ([`super::term::NodeGrad::seed_root`]), and its exact Gauss–Newton rows
//! six reverse sweeps seeded on the root's wrench ([`Node::reverse`]); no
//! finite differences.

use super::super::error::{SpError, invalid};
use super::super::torque::BodyDynamics;
use super::forces::GroundScale;
use super::term::{GaussNewtonNode, Node, NodeForces, NodeSum, Term, check_weight};
use crate::dynamics::{InverseDynamicsPass, JointState};
use crate::ground::up_direction;
use crate::lie::{Twist, Wrench};
use crate::model::RootCoords;
use nalgebra::{DMatrix, Vector3};

/// The base term (see the module doc).
pub struct BaseTerm<'a> {
    body: &'a BodyDynamics<'a>,
    scale: GroundScale,
    weight: f64,
}

impl<'a> BaseTerm<'a> {
    /// The base term of `body` (whose root must be free: six coordinates
    /// down to its first link with mass), scales `scale`, weight `weight`
    /// (≥ 0, on (F/mg)² + (μ/mgL)² per second).
    pub fn new(
        body: &'a BodyDynamics<'a>,
        scale: GroundScale,
        weight: f64,
    ) -> Result<Self, SpError> {
        check_weight("base", weight)?;
        let up = up_direction(&body.gravity)?;
        if !RootCoords::detect(body.model, Some(&up)).is_floating() {
            return Err(invalid(format!(
                "the base term balances the root's six equations, but the root of `{}` is not free",
                body.model.name
            )));
        }
        let positive = |x: f64| x.is_finite() && x > 0.0;
        if !(positive(scale.weight) && positive(scale.length)) {
            return Err(invalid(format!(
                "the base term's scales must be positive and finite, got {scale:?}"
            )));
        }
        Ok(BaseTerm {
            body,
            scale,
            weight,
        })
    }

    /// The six scaled residuals for state `x` with the forces `nf` held
    /// ([force/(mg); moment about the reference/(mgL)]), unweighted.
    pub fn residual(
        &self,
        ws: &mut crate::dynamics::Workspace,
        x: JointState,
        nf: &NodeForces,
    ) -> Result<[f64; 6], SpError> {
        let pass =
            InverseDynamicsPass::new(self.body.model, ws, x, &self.body.gravity, &nf.forces)?;
        Ok(self.scaled(&pass.root_wrench(), &nf.reference))
    }

    /// [F/(mg); (μ_O − c × F)/(mgL)].
    fn scaled(&self, w: &Wrench, c: &Vector3<f64>) -> [f64; 6] {
        let f = Vector3::new(w[3], w[4], w[5]);
        let mu = Vector3::new(w[0], w[1], w[2]) - c.cross(&f);
        let (sf, sm) = (
            1.0 / self.scale.weight,
            1.0 / (self.scale.weight * self.scale.length),
        );
        [
            f.x * sf,
            f.y * sf,
            f.z * sf,
            mu.x * sm,
            mu.y * sm,
            mu.z * sm,
        ]
    }

    /// ∂r/∂w_root for r = [`BaseTerm::scaled`] contracted with `rbar`, as a
    /// seed pairing with the wrench [moment; force]: ∂/∂μ_O = S_m r̄_m,
    /// ∂/∂F = S_f r̄_f + c × (S_m r̄_m) (from −c × F).
    fn seed(&self, rbar: &[f64; 6], c: &Vector3<f64>) -> Twist {
        let (sf, sm) = (
            1.0 / self.scale.weight,
            1.0 / (self.scale.weight * self.scale.length),
        );
        let m = Vector3::new(rbar[3], rbar[4], rbar[5]) * sm;
        let f = Vector3::new(rbar[0], rbar[1], rbar[2]) * sf + c.cross(&m);
        Twist::new(m.x, m.y, m.z, f.x, f.y, f.z)
    }
}

/// The forces held at the node; an error if none were set.
fn forces_at<'n>(node: &Node<'n, BodyDynamics<'_>>) -> Result<&'n NodeForces, SpError> {
    node.forces.ok_or_else(|| {
        invalid(
            "the base term needs the contact forces at every node: set them \
             (`ContactForces::solve`, then `Objective::set_forces`) before evaluating",
        )
    })
}

impl<'a> Term<BodyDynamics<'a>> for BaseTerm<'a> {
    fn name(&self) -> &str {
        "base"
    }

    fn set_weight(&mut self, w: f64) -> Result<(), SpError> {
        check_weight("base", w)?;
        self.weight = w;
        Ok(())
    }

    fn node(
        &self,
        node: &mut Node<'_, BodyDynamics<'a>>,
        sum: &mut NodeSum<'_>,
    ) -> Result<(), SpError> {
        if self.weight == 0.0 {
            return Ok(());
        }
        let c = forces_at(node)?.reference;
        let r = self.scaled(&node.root_wrench()?, &c);
        sum.add(self.weight * r.iter().map(|x| x * x).sum::<f64>());
        if let Some(g) = sum.gradient() {
            g.seed_root(&self.seed(&r.map(|x| 2.0 * self.weight * x), &c));
        }
        Ok(())
    }

    /// Six rows, one reverse sweep each: D_α[i, :] = ∂r_i/∂(q, q̇, q̈)_α over
    /// the gap coordinates, weight w_b.
    fn gauss_newton(
        &self,
        node: &mut Node<'_, BodyDynamics<'a>>,
        gn: &mut GaussNewtonNode<'_>,
    ) -> Result<(), SpError> {
        if self.weight == 0.0 {
            return Ok(());
        }
        let c = forces_at(node)?.reference;
        let coords = gn.coords();
        let mut d: [DMatrix<f64>; 3] = std::array::from_fn(|_| DMatrix::zeros(6, coords.len()));
        for i in 0..6 {
            let mut e = [0.0; 6];
            e[i] = 1.0;
            let g = node.reverse(None, Some(&self.seed(&e, &c)))?;
            for (m, g) in d.iter_mut().zip(g) {
                for (j, &c) in coords.iter().enumerate() {
                    m[(i, j)] = g[c];
                }
            }
        }
        gn.add_rows(&d, &[self.weight; 6], None);
        Ok(())
    }
}
