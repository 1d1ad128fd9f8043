//! The interface of one objective term. The objective is
//! e(x) = Σ_k w_k Σ_terms f_term(node k), a list of terms summed node by node
//! over one [`GapLayout`]'s quadrature nodes: each term gives its integrand
//! at a node ([`Term::node`]), with its gradient with respect to the node's
//! state (q, q̇, q̈ of every coordinate) and to the layout's extra unknowns,
//! and, if it has one, its Gauss–Newton part ([`Term::gauss_newton`]) for
//! the solver's preconditioner. The objective does the rest: it sets the
//! node's state from x, applies the quadrature weight, and chains the state
//! gradient through the basis rows of the gap DOFs.
//!
//! A term is one file under `objective/` implementing [`Term`]; it is added
//! with [`super::Objective::with_term`] (torque and the kinematic prior are
//! built in: `torque_term.rs`, `prior.rs`). What the body's passes give at
//! the node — link poses, point Jacobians, τ and the root's wrench with the
//! held contact forces — a term reads from the [`Node`], which computes each
//! once per node for all terms (`node_state.rs`).

use super::super::error::{SpError, invalid};
use super::super::torque::TorqueModel;
use super::layout::{GapLayout, NodeRows};
use super::node_seeds::{Seeds, Shared};
use crate::dynamics::PointForce;
use nalgebra::{DMatrix, Vector3};

/// A term's own scratch memory, one per evaluation thread
/// ([`Term::scratch`]; read back with [`scratch_of`]).
pub type TermScratch = Box<dyn std::any::Any + Send>;

/// The scratch a term's [`Term::scratch`] built, as its type `T`
/// (`scratch_of::<T>(node.scratch)`, which leaves the node's other fields free to borrow).
pub fn scratch_of<T: 'static>(s: &mut TermScratch) -> Result<&mut T, SpError> {
    s.downcast_mut::<T>().ok_or_else(|| {
        SpError::Numerical("an objective term was given another term's scratch".into())
    })
}

/// One term of the objective.
pub trait Term<M: TorqueModel>: Send + Sync {
    /// What the term is, for messages.
    fn name(&self) -> &str;

    /// Scratch memory for one evaluation thread, built once per solve
    /// (none by default).
    fn scratch(&self) -> TermScratch {
        Box::new(())
    }

    /// Adds the integrand at `node` with [`NodeSum::add`] and, when
    /// [`NodeSum::gradient`] is `Some`, its partial derivatives with respect
    /// to the node's state and the extras (added, never written: the terms
    /// share them).
    fn node(&self, node: &mut Node<'_, M>, sum: &mut NodeSum<'_>) -> Result<(), SpError>;

    /// Adds the term's Gauss–Newton part at `node` (the Hessian of a sum of
    /// squares without its second-derivative part; the exact Hessian of a
    /// quadratic term) to the preconditioner: [`GaussNewtonNode::add_rows`]
    /// for residual rows, [`GaussNewtonNode::add`] entry by entry. None by
    /// default (the term does not shape the solver's steps).
    fn gauss_newton(
        &self,
        _node: &mut Node<'_, M>,
        _gn: &mut GaussNewtonNode<'_>,
    ) -> Result<(), SpError> {
        Ok(())
    }

    /// Sets the term's weight (a continuation's step) without rebuilding
    /// the objective; by default an error naming the term, which has none.
    fn set_weight(&mut self, _w: f64) -> Result<(), SpError> {
        Err(SpError::Invalid(format!(
            "the objective's `{}` term has no weight to set",
            self.name()
        )))
    }
}

/// What a term sees at one quadrature node: the layout, the node's index,
/// the state of every coordinate there (gap DOFs from x, the rest from the
/// inputs), the contact forces held there, the extra unknowns of x, the
/// model and its workspace, and the term's own scratch; and, computed once
/// for every term, the body's passes at the node (`node_state.rs`:
/// [`Node::poses`], [`Node::point_jacobian`], [`Node::tau`],
/// [`Node::root_wrench`], [`Node::reverse`]).
pub struct Node<'s, M: TorqueModel> {
    pub model: &'s M,
    pub layout: &'s GapLayout,
    /// The node's index (its time is `layout.nodes().0[k]`).
    pub k: usize,
    pub q: &'s [f64],
    pub v: &'s [f64],
    pub a: &'s [f64],
    /// The contact forces held at the node and their reference point
    /// ([`super::Objective::set_forces`]; none set: `None`).
    pub forces: Option<&'s NodeForces>,
    /// The extra unknowns (see [`GapLayout::with_extras`]).
    pub extras: &'s [f64],
    pub ws: &'s mut M::Workspace,
    /// The term's own scratch (see [`scratch_of`]).
    pub scratch: &'s mut TermScratch,
    pub(super) shared: &'s mut Shared,
}

/// Where a term adds its integrand at one node: the objective's running sum,
/// weighted by the node's quadrature weight here so every term's
/// contribution is rounded the same way.
pub struct NodeSum<'s> {
    pub(super) wk: f64,
    pub(super) e: &'s mut f64,
    pub(super) grad: Option<NodeGrad<'s>>,
}

impl<'s> NodeSum<'s> {
    /// Adds `f` (the term's integrand, or a part of it) at this node.
    pub fn add(&mut self, f: f64) {
        *self.e += self.wk * f;
    }

    /// Where the gradient goes, when the caller wants one.
    pub fn gradient(&mut self) -> Option<&mut NodeGrad<'s>> {
        self.grad.as_mut()
    }
}

/// The gradient of the integrand at one node: with respect to the state
/// (unweighted; the objective chains it through the basis rows and the
/// quadrature weight), to the extras, and through τ and the root's wrench
/// ([`NodeGrad::seed_tau`], [`NodeGrad::seed_root`]: one reverse sweep
/// chains them after every term).
pub struct NodeGrad<'s> {
    /// ∂f/∂q, ∂f/∂q̇, ∂f/∂q̈ of every coordinate (add to them).
    pub q: &'s mut [f64],
    pub v: &'s mut [f64],
    pub a: &'s mut [f64],
    pub(super) wk: f64,
    pub(super) extras: &'s mut [f64],
    pub(super) seeds: &'s mut Seeds,
}

impl NodeGrad<'_> {
    /// Adds ∂f/∂(extra i) = `g` at this node.
    pub fn add_extra(&mut self, i: usize, g: f64) {
        self.extras[i] += self.wk * g;
    }
}

/// One node's share of the preconditioner's half Gauss–Newton Hessian
/// H/2 = Σ_k w_k J_kᵀ W J_k over the unknowns `[coefficients | extras]`
/// (upper triangle only).
pub struct GaussNewtonNode<'s> {
    pub(super) layout: &'s GapLayout,
    pub(super) wk: f64,
    /// The gap DOFs alive at the node, with their basis rows.
    pub(super) alive: &'s [(usize, &'s NodeRows)],
    /// Their model coordinates.
    pub(super) coords: &'s [usize],
    pub(super) h: &'s mut DMatrix<f64>,
}

impl<'s> GaussNewtonNode<'s> {
    /// The node's quadrature weight.
    pub fn wk(&self) -> f64 {
        self.wk
    }

    /// The gap DOFs alive at the node (index into the layout's DOFs, rows).
    pub fn alive(&self) -> &'s [(usize, &'s NodeRows)] {
        self.alive
    }

    /// The model coordinates of [`GaussNewtonNode::alive`], in its order:
    /// the columns [`GaussNewtonNode::add_rows`] expects.
    pub fn coords(&self) -> &'s [usize] {
        self.coords
    }

    /// Adds `v` to entry (i, j), i ≤ j, of H/2 (indices into x; a term with
    /// an exact Hessian of its own adds it this way, weighted by [`Self::wk`]).
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        debug_assert!(i <= j, "only the upper triangle is accumulated");
        self.h[(i, j)] += v;
    }

    /// Adds the rows of residuals r (m of them) with weights `weights` (W,
    /// times the node's weight here): `d[α]` = ∂r/∂(q, q̇, q̈)_α over the
    /// columns [`GaussNewtonNode::coords`] (each m × coords), and `extras` =
    /// ∂r/∂(extras) (m × n_extras), if r depends on them.
    ///
    /// With J[:, (d, j)] = Σ_α D_α[:, d] r_{α,d}[j], assembled as
    /// Σ_αβ G_αβ[d, e] r_{α,d} r_{β,e}ᵀ with G_αβ = D_αᵀ w_k W D_β, over the
    /// (at most four) basis functions alive at the node, so a node costs
    /// O(nd²·m) rather than O(m·(nd·nf)²).
    pub fn add_rows(
        &mut self,
        d: &[DMatrix<f64>; 3],
        weights: &[f64],
        extras: Option<&DMatrix<f64>>,
    ) {
        let wk = self.wk;
        let wd: Vec<DMatrix<f64>> = d
            .iter()
            .map(|m| {
                let mut m = m.clone();
                for (i, mut row) in m.row_iter_mut().enumerate() {
                    row *= wk * weights[i];
                }
                m
            })
            .collect();
        // G_αβ = D_αᵀ (w_k W) D_β for α ≤ β; G_βα = G_αβᵀ
        let mut g: [[Option<DMatrix<f64>>; 3]; 3] = Default::default();
        let zero: [bool; 3] = std::array::from_fn(|a| d[a].iter().all(|x| *x == 0.0));
        for a in 0..3 {
            for b in a..3 {
                if !(zero[a] || zero[b]) {
                    g[a][b] = Some(d[a].transpose() * &wd[b]);
                }
            }
        }
        let gab = |a: usize, b: usize, i: usize, j: usize| match (&g[a][b], &g[b][a]) {
            (Some(m), _) => m[(i, j)],
            (None, Some(m)) => m[(j, i)],
            _ => 0.0,
        };
        let nf = self.layout.n_free;
        // only the DOFs the rows depend on (a point's rows: its chain's)
        let moves: Vec<bool> = (0..self.alive.len())
            .map(|i| d.iter().any(|m| m.column(i).iter().any(|x| *x != 0.0)))
            .collect();
        for (i, (di, rd)) in self.alive.iter().enumerate() {
            if !moves[i] {
                continue;
            }
            for (j, (ei, re)) in self.alive.iter().enumerate().skip(i) {
                if !moves[j] {
                    continue;
                }
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
                        self.h[(row, col)] +=
                            cr[0] * re.rows[0][l] + cr[1] * re.rows[1][l] + cr[2] * re.rows[2][l];
                    }
                }
            }
        }
        if let Some(e) = extras {
            self.add_extras_rows(d, weights, e);
        }
    }

    /// The blocks of [`GaussNewtonNode::add_rows`] that involve the extras:
    /// coefficients × extras, Σ_α r_{α,d} (D_αᵀ w_k W E)[d, :], and
    /// extras × extras, Eᵀ w_k W E.
    fn add_extras_rows(&mut self, d: &[DMatrix<f64>; 3], weights: &[f64], e: &DMatrix<f64>) {
        let (nf, n0) = (self.layout.n_free, self.layout.n_coefficients());
        let mut we = e.clone();
        for (i, mut row) in we.row_iter_mut().enumerate() {
            row *= self.wk * weights[i];
        }
        let de: Vec<DMatrix<f64>> = d.iter().map(|m| m.transpose() * &we).collect();
        for (i, (di, rd)) in self.alive.iter().enumerate() {
            for p in rd.live.clone() {
                for c in 0..e.ncols() {
                    let v: f64 = (0..3).map(|a| rd.rows[a][p] * de[a][(i, c)]).sum();
                    self.h[(di * nf + p, n0 + c)] += v;
                }
            }
        }
        let ee = e.transpose() * &we;
        for i in 0..e.ncols() {
            for j in i..e.ncols() {
                self.h[(n0 + i, n0 + j)] += ee[(i, j)];
            }
        }
    }
}

/// The forces held fixed at one node, and the point their moment balance
/// is taken about (the centre of mass where they were chosen).
#[derive(Clone, Debug, PartialEq)]
pub struct NodeForces {
    pub forces: Vec<PointForce>,
    pub reference: Vector3<f64>,
}

/// `Err` naming the term unless `w` is a finite weight ≥ 0.
pub(super) fn check_weight(term: &str, w: f64) -> Result<(), SpError> {
    if w.is_finite() && w >= 0.0 {
        Ok(())
    } else {
        Err(invalid(format!(
            "the {term} term's weight must be finite and ≥ 0, got {w}"
        )))
    }
}
