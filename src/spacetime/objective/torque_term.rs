//! The torque term Σᵢ wᵢ τᵢ(q, q̇, q̈)² of one objective (Rose's energy): the
//! body, the per-coordinate weights and, per node, the world forces at link
//! points acting besides the joints (contact forces, held fixed while x
//! moves; none by default), so τ = ID − Σ J_cᵀ f_c. Its gradient is the
//! model's adjoint; its Gauss–Newton rows are the torque Jacobians, one row
//! per coordinate. With a free root, the root's rows are the base residual
//! W_base − J_baseᵀ f, weighted as any coordinate's.

use super::super::error::SpError;
use super::super::torque::TorqueModel;
use super::term::{GaussNewtonNode, Node, NodeSum, Term, TermScratch, scratch_of};
use crate::dynamics::{JointState, PointForce, StateGradient};

pub(super) struct TorqueTerm<'a, M: TorqueModel> {
    pub(super) model: &'a M,
    pub(super) weights: Vec<f64>,
    /// The forces at each node; empty: none at any.
    pub(super) forces: Vec<Vec<PointForce>>,
}

impl<M: TorqueModel> TorqueTerm<'_, M> {
    /// The forces acting at node k.
    fn forces_at(&self, k: usize) -> &[PointForce] {
        self.forces.get(k).map_or(&[], |f| f.as_slice())
    }
}

/// The adjoint writes its gradient; the term adds it to the node's.
struct Gradient {
    q: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
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
        let (q, v, a) = (node.q, node.v, node.a);
        let g = scratch_of::<Gradient>(node.scratch)?;
        let f = self.model.torque_sq_grad(
            node.ws,
            &JointState::new(q, v, a),
            self.forces_at(node.k),
            &self.weights,
            StateGradient {
                q: &mut g.q,
                v: &mut g.v,
                a: &mut g.a,
            },
        )?;
        sum.add(f);
        if let Some(out) = sum.gradient() {
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
            self.forces_at(node.k),
            gn.coords(),
        )?;
        gn.add_rows(&d, &self.weights, None);
        Ok(())
    }
}
