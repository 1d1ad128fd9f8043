//! The objective's Gauss–Newton Hessian: the change of variables the solver
//! works in ([`Precond`]).

use super::super::error::SpError;
use super::super::precond::Precond;
use super::super::torque::TorqueModel;
use super::layout::NodeRows;
use super::{NodeScratch, Objective, Scratch};
use nalgebra::DMatrix;

impl<M: TorqueModel> Objective<'_, M> {
    /// The change of variables the solver works in (see [`Precond`]): the
    /// Gauss–Newton Hessian of e at the Hermite start.
    pub fn preconditioner(&self, s: &mut Scratch<M::Workspace>) -> Result<Precond, SpError> {
        let x0 = self.hermite_start();
        self.gauss_newton_at(s, &x0)
    }

    /// The Gauss–Newton preconditioner linearised at x: with the torque
    /// Jacobians D_α = ∂τ/∂(q, q̇, q̈) of the gap coordinates at every node,
    /// H/2 = Σ_k w_k J_kᵀ W J_k, J_k[:, (d, j)] = Σ_α D_α[:, d] r_{α,d,k}[j].
    /// Assembled as Σ_αβ G_αβ[d, e] · w_k r_{α,d,k} r_{β,e,k}ᵀ with
    /// G_αβ = D_αᵀ W D_β, over the (at most four) basis functions alive at
    /// the node, so a node costs O(nd²·nq) rather than O(nq·(nd·nf)²).
    /// Linearising at every node, not at a few, matters: the body's pose and
    /// hence M(q) and the gravity Jacobian change over the gap, and with three
    /// linearisation points L-BFGS needed ~25 % more iterations for the same
    /// energy on the Fig. 8 case. Chunks of nodes run in parallel.
    pub fn gauss_newton_at(
        &self,
        s: &mut Scratch<M::Workspace>,
        x0: &[f64],
    ) -> Result<Precond, SpError> {
        let nv = self.n_vars();
        if nv == 0 {
            return Ok(Precond::Identity);
        }
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
        Ok(Precond::from_half_hessian(h))
    }

    /// Adds node k's term w_k J_kᵀ W J_k (upper triangle) to `h`.
    fn add_gauss_newton_node(
        &self,
        k: usize,
        x0: &[f64],
        s: &mut NodeScratch<M::Workspace>,
        h: &mut DMatrix<f64>,
    ) -> Result<(), SpError> {
        let layout = &self.layout;
        let nf = layout.n_free;
        // the gap DOFs alive at this node, with their rows
        let alive: Vec<(usize, &NodeRows)> = layout
            .active
            .iter()
            .enumerate()
            .filter_map(|(d, a)| a[k].as_ref().map(|r| (d, r)))
            .collect();
        if alive.is_empty() {
            return Ok(());
        }
        let coords: Vec<usize> = alive.iter().map(|(d, _)| layout.dofs[*d].coord).collect();
        self.torque.load_node(layout, k, x0, s);
        let wk = layout.qweights[k];
        // G_αβ = D_αᵀ (w_k W) D_β; G_βα = G_αβᵀ
        let g = self.torque.gauss_newton_blocks(s, &coords, wk)?;
        let gab = |a: usize, b: usize, i: usize, j: usize| match (&g[a][b], &g[b][a]) {
            (Some(m), _) => m[(i, j)],
            (None, Some(m)) => m[(j, i)],
            _ => 0.0,
        };
        self.prior.add_gauss_newton(&alive, wk, nf, h);
        for (i, (di, rd)) in alive.iter().enumerate() {
            for (j, (ei, re)) in alive.iter().enumerate().skip(i) {
                let c: [[f64; 3]; 3] =
                    std::array::from_fn(|a| std::array::from_fn(|b| gab(a, b, i, j)));
                for p in rd.live.clone() {
                    let row = di * nf + p;
                    // [Σ_a c_ab r_a[p]]_b
                    let cr: [f64; 3] = std::array::from_fn(|b| {
                        (0..3).map(|a| c[a][b] * rd.rows[a][p]).sum::<f64>()
                    });
                    for l in re.live.clone() {
                        let col = ei * nf + l;
                        if col < row {
                            continue;
                        }
                        h[(row, col)] +=
                            cr[0] * re.rows[0][l] + cr[1] * re.rows[1][l] + cr[2] * re.rows[2][l];
                    }
                }
            }
        }
        Ok(())
    }
}
