//! The objective's Gauss–Newton Hessian: the change of variables the solver
//! works in ([`Precond`]), assembled from every term's part
//! ([`super::Term::gauss_newton`]).

use super::super::error::SpError;
use super::super::precond::Precond;
use super::super::torque::TorqueModel;
use super::layout::NodeRows;
use super::term::{GaussNewtonNode, Node};
use super::{NodeScratch, Objective, Scratch};
use nalgebra::DMatrix;

impl<M: TorqueModel> Objective<'_, M> {
    /// The change of variables the solver works in (see [`Precond`]): the
    /// Gauss–Newton Hessian of e at the Hermite start.
    pub fn preconditioner(&self, s: &mut Scratch<M::Workspace>) -> Result<Precond, SpError> {
        let x0 = self.hermite_start();
        self.gauss_newton_at(s, &x0)
    }

    /// The Gauss–Newton preconditioner linearised at x: H/2 = Σ_k w_k J_kᵀ W J_k
    /// over every term's residual rows at every node (for the torque term
    /// J_k[:, (d, j)] = Σ_α D_α[:, d] r_{α,d,k}[j], D_α = ∂τ/∂(q, q̇, q̈) of the
    /// gap coordinates; see [`GaussNewtonNode::add_rows`]), plus the exact
    /// Hessian of quadratic terms (the prior).
    /// Linearising at every node, not at a few, matters: the body's pose and
    /// hence M(q) and the gravity Jacobian change over the gap, and with three
    /// linearisation points L-BFGS needed ~25 % more iterations for the same
    /// energy on the Fig. 8 case. Chunks of nodes run in parallel.
    pub fn gauss_newton_at(
        &self,
        s: &mut Scratch<M::Workspace>,
        x0: &[f64],
    ) -> Result<Precond, SpError> {
        if self.n_vars() == 0 {
            return Ok(Precond::Identity);
        }
        Ok(Precond::from_half_hessian(self.half_gauss_newton(s, x0)?))
    }

    /// H/2 of [`Objective::gauss_newton_at`], whole (both triangles).
    pub fn half_gauss_newton(
        &self,
        s: &mut Scratch<M::Workspace>,
        x0: &[f64],
    ) -> Result<DMatrix<f64>, SpError> {
        let nv = self.n_vars();
        let nn = self.layout.nodes.len();
        let chunks = s.parts.len();
        let partial = |i: usize, ns: &mut NodeScratch<M::Workspace>| {
            let mut h = DMatrix::<f64>::zeros(nv, nv);
            for k in i * nn / chunks..(i + 1) * nn / chunks {
                self.add_gauss_newton_node(k, x0, ns, &mut h)?;
            }
            Ok::<_, SpError>(h)
        };
        let mut h = if chunks == 1 {
            partial(0, s.node())?
        } else {
            use rayon::prelude::*;
            let parts: Result<Vec<DMatrix<f64>>, SpError> = s
                .parts
                .par_iter_mut()
                .enumerate()
                .map(|(i, (ns, _))| partial(i, ns))
                .collect();
            let mut parts = parts?.into_iter();
            let mut h = parts.next().unwrap_or_else(|| DMatrix::zeros(nv, nv));
            for p in parts {
                h += p;
            }
            h
        };
        // only the upper triangle was accumulated
        h.fill_lower_triangle_with_upper_triangle();
        Ok(h)
    }

    /// Adds node k's part w_k J_kᵀ W J_k (upper triangle) to `h`: every
    /// term's, last term first (the order the preconditioner had when the
    /// prior and torque were its only parts, so that its rounding, hence the
    /// solver's path, stays as it was).
    fn add_gauss_newton_node(
        &self,
        k: usize,
        x0: &[f64],
        s: &mut NodeScratch<M::Workspace>,
        h: &mut DMatrix<f64>,
    ) -> Result<(), SpError> {
        let layout = &self.layout;
        // the gap DOFs alive at this node, with their rows
        let alive: Vec<(usize, &NodeRows)> = layout
            .active
            .iter()
            .enumerate()
            .filter_map(|(d, a)| a[k].as_ref().map(|r| (d, r)))
            .collect();
        if alive.is_empty() && layout.n_extras() == 0 {
            return Ok(());
        }
        let coords: Vec<usize> = alive.iter().map(|(d, _)| layout.dofs[*d].coord).collect();
        self.sampled.load(layout, k, x0, s);
        let NodeScratch {
            ws,
            q,
            v,
            a,
            terms,
            shared,
            ..
        } = s;
        let mut gn = GaussNewtonNode {
            layout,
            wk: layout.qweights[k],
            alive: &alive,
            coords: &coords,
            h,
        };
        let terms: Vec<_> = self.terms().zip(terms.iter_mut()).collect();
        for (term, scratch) in terms.into_iter().rev() {
            let mut node = Node {
                model: self.torque.model,
                layout,
                k,
                q,
                v,
                a,
                forces: self.forces.get(k),
                extras: layout.extras(x0),
                ws: &mut *ws,
                scratch,
                shared: &mut *shared,
            };
            term.gauss_newton(&mut node, &mut gn)?;
        }
        Ok(())
    }
}
