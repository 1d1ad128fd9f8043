//! The torque term Σᵢ wᵢ τᵢ(q, q̇, q̈)² of one objective (Rose's energy): the
//! body and the per-coordinate weights; τ = ID − Σ J_cᵀ f_c with the contact
//! forces held at the node ([`Node::forces`]; none by default). On the
//! multibody body, τ is the node's shared inverse dynamics ([`Node::tau`])
//! and the gradient the seed 2wτ of the node's one reverse sweep
//! ([`NodeGrad::seed_tau`]); on another model, the model's own adjoint
//! ([`TorqueModel::torque_sq_grad`]). Its Gauss–Newton rows are the torque
//! Jacobians, one row per coordinate. With a free root, the root's rows are
//! the base residual W_base − J_baseᵀ f, weighted as any coordinate's.

use super::super::error::SpError;
use super::super::torque::TorqueModel;
use super::term::{GaussNewtonNode, Node, NodeGrad, NodeSum, Term, TermScratch, scratch_of};
use crate::dynamics::{JointState, PointForce, StateGradient};

pub(super) struct TorqueTerm<'a, M: TorqueModel> {
    pub(super) model: &'a M,
    pub(super) weights: Vec<f64>,
}

/// The forces held at the node.
fn forces_at<'n, M: TorqueModel>(node: &Node<'n, M>) -> &'n [PointForce] {
    node.forces.map_or(&[], |f| &f.forces)
}

/// A model's adjoint writes its gradient; the term adds it to the node's.
struct Gradient {
    q: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
}

impl<M: TorqueModel> TorqueTerm<'_, M> {
    /// Σwτ² and its gradient by the model's own adjoint (a model that is
    /// not the multibody body).
    fn by_model(&self, node: &mut Node<'_, M>, sum: &mut NodeSum<'_>) -> Result<(), SpError> {
        let (q, v, a, forces) = (node.q, node.v, node.a, forces_at(node));
        let g = scratch_of::<Gradient>(node.scratch)?;
        let f = self.model.torque_sq_grad(
            node.ws,
            &JointState::new(q, v, a),
            forces,
            &self.weights,
            StateGradient {
                q: &mut g.q,
                v: &mut g.v,
                a: &mut g.a,
            },
        )?;
        sum.add(f);
        if let Some(out) = sum.gradient() {
            add_state_gradient(out, g);
        }
        Ok(())
    }
}

fn add_state_gradient(out: &mut NodeGrad, g: &Gradient) {
    for (o, x) in [
        (&mut *out.q, &g.q),
        (&mut *out.v, &g.v),
        (&mut *out.a, &g.a),
    ] {
        for (o, x) in o.iter_mut().zip(x) {
            *o += x;
        }
    }
}

impl<M: TorqueModel> Term<M> for TorqueTerm<'_, M> {
    fn name(&self) -> &str {
        "torque"
    }

    fn scratch(&self) -> TermScratch {
        let n = self.model.nq();
        Box::new(Gradient {
            q: vec![0.0; n],
            v: vec![0.0; n],
            a: vec![0.0; n],
        })
    }

    fn node(&self, node: &mut Node<'_, M>, sum: &mut NodeSum<'_>) -> Result<(), SpError> {
        if self.model.multibody().is_none() {
            return self.by_model(node, sum);
        }
        let tau = node.tau()?;
        let w = &self.weights;
        let mut f = 0.0;
        for i in 0..tau.len() {
            f += w[i] * tau[i] * tau[i];
        }
        sum.add(f);
        if let Some(g) = sum.gradient() {
            for (s, (t, w)) in g.seed_tau().iter_mut().zip(tau.iter().zip(w)) {
                *s += t * (2.0 * w);
            }
        }
        Ok(())
    }

    /// Rows τᵢ with weights wᵢ: D_α = ∂τ/∂(q, q̇, q̈)_α of the gap coordinates.
    fn gauss_newton(
        &self,
        node: &mut Node<'_, M>,
        gn: &mut GaussNewtonNode<'_>,
    ) -> Result<(), SpError> {
        let d = self.model.torque_jacobians(
            node.ws,
            &JointState::new(node.q, node.v, node.a),
            forces_at(node),
            gn.coords(),
        )?;
        gn.add_rows(&d, &self.weights, None);
        Ok(())
    }
}
