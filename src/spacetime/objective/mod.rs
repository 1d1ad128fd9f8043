//! The spacetime objective of one group of overlapping gaps:
//! e(x) = ∫ Σᵢ wᵢ τᵢ(q, q̇, q̈)² dt over the group's span by composite
//! Gauss–Legendre quadrature, where the gap DOFs follow their transition
//! curves (free coefficients x) and every other coordinate is an input.
//!
//! The gradient is exact: the model's adjoint gives ∂(Σwτ²)/∂(q, q̇, q̈) per
//! node, and each gap coordinate's q, q̇, q̈ is linear in its free coefficients
//! (the basis rows of the [`GapLayout`]), so ∂e/∂x = Σ_nodes w_k (g_q·B + g_q̇·B' + g_q̈·B'').
//!
//! The objective is a list of terms (`term.rs`: [`Term`]) summed node by
//! node here: the torque term (`torque_term.rs`), SP's kinematic prior
//! (`prior.rs`), then any added with [`Objective::with_term`]. The layout
//! (`layout.rs`) is shared with the support IK; the state at the nodes is
//! `sampled.rs`; the Gauss–Newton preconditioner, which asks every term for
//! its part, is `gauss_newton.rs`. The terms at one node share one forward
//! kinematics, one inverse dynamics and one reverse sweep (`node_state.rs`).

use super::error::{SpError, invalid};
use super::torque::TorqueModel;
use super::transition::{Continuity, EndState, TransitionCurve};

mod base;
mod clearance;
mod example;
mod floor;
mod forces;
mod gauss_newton;
pub mod layout;
mod node_seeds;
mod node_state;
mod points;
mod prior;
mod sampled;
mod stance;
pub mod term;
#[cfg(test)]
mod term_tests;
#[cfg(test)]
mod tests;
mod torque_term;

pub use base::BaseTerm;
pub use clearance::{Clearance, clearance_term};
pub use example::{ExampleTerm, position_weight};
pub use floor::floor_term;
pub use forces::{ContactForces, GroundScale};
pub use layout::{GapLayout, MIN_POINTS_PER_PIECE, NodeRows, composite_nodes};
pub use points::{PointRow, PointTerm};
use prior::KinematicPrior;
use sampled::Sampled;
pub use stance::stance_term;
pub use term::{
    GaussNewtonNode, Node, NodeForces, NodeGrad, NodeSum, Term, TermScratch, scratch_of,
};
use torque_term::TorqueTerm;

/// One DOF's gap: model coordinate `coord` is undefined on (t0, t1) and has
/// the given states at the ends.
#[derive(Clone, Debug, PartialEq)]
pub struct GapDof {
    pub coord: usize,
    pub t0: f64,
    pub t1: f64,
    pub start: EndState,
    pub end: EndState,
}

/// Settings shared by every gap of a solve.
#[derive(Clone, Debug)]
pub struct TransitionSettings {
    /// Free B-spline coefficients per DOF (`coefficients:`).
    pub coefficients: usize,
    /// Gauss points per quadrature segment (`samples:`).
    pub samples: usize,
    pub continuity: Continuity,
}

impl Default for TransitionSettings {
    fn default() -> Self {
        // Rose's Fig. 8 value (5 coefficients), which the benchmark
        // (benches/spacetime.rs) shows converging fastest; more coefficients
        // lower the energy further mainly by letting hands and feet oscillate.
        TransitionSettings {
            coefficients: 5,
            samples: 20,
            continuity: Continuity::C1,
        }
    }
}

/// Fills q, q̇, q̈ of every coordinate that is not a gap at time t; a
/// coordinate undefined at t is left NaN (an error unless it is a gap DOF of
/// the transition being solved).
pub type Inputs<'a> =
    dyn Fn(f64, &mut [f64], &mut [f64], &mut [f64]) -> Result<(), SpError> + Sync + 'a;

/// The objective of one group of gaps over one [`GapLayout`]: the torque
/// term, SP's kinematic prior, then the terms added with
/// [`Objective::with_term`], summed node by node in that order.
pub struct Objective<'a, M: TorqueModel> {
    layout: GapLayout,
    /// The state at every node (the inputs sampled once).
    sampled: Sampled,
    torque: TorqueTerm<'a, M>,
    /// Per gap DOF, the weights (c_v, c_a) of the kinematic prior
    /// ∫ c_v (q̇ − ṙ)² + c_a (q̈ − r̈)² dt added to the torque term
    /// ([`Objective::with_prior`], [`Objective::rescale_prior`]) and the
    /// example's [ṙ, r̈] it follows ([`Objective::with_example`]).
    prior: KinematicPrior,
    /// The terms after the built-in two.
    more: Vec<Box<dyn Term<M> + 'a>>,
    /// The contact forces held at each node (empty: none at any).
    forces: Vec<NodeForces>,
    /// Their point forces alone, per node, for [`Objective::forces`].
    point_forces: Vec<Vec<crate::dynamics::PointForce>>,
}

/// Scratch vectors of one node evaluation (one thread's).
pub struct NodeScratch<W> {
    pub ws: W,
    q: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    /// The integrand's gradient with respect to the node's state, which
    /// every term adds to.
    gq: Vec<f64>,
    gv: Vec<f64>,
    ga: Vec<f64>,
    /// Each term's own scratch, in the order of [`Objective::terms`].
    terms: Vec<TermScratch>,
    /// The body's passes at the node, shared by the terms, and the seeds
    /// of its reverse sweep (`node_state.rs`).
    shared: node_seeds::Shared,
    seeds: node_seeds::Seeds,
}

/// Scratch memory of one solve: one [`NodeScratch`] and one partial gradient
/// per chunk of quadrature nodes. The chunks are evaluated in parallel (the
/// nodes are independent inverse-dynamics problems); a fixed chunking keeps
/// the sums, hence the solver's path, the same from run to run.
pub struct Scratch<W> {
    parts: Vec<(NodeScratch<W>, Vec<f64>)>,
}

impl<W> Scratch<W> {
    /// The first chunk's node scratch (for serial work: preconditioner, tests).
    pub fn node(&mut self) -> &mut NodeScratch<W> {
        &mut self.parts[0].0
    }
}

/// Fewest nodes worth a thread of their own: below this, the fork–join costs
/// more than the inverse dynamics it spreads.
const MIN_NODES_PER_CHUNK: usize = 8;

/// Checks the gaps and the torque weights against a body of `n` coordinates.
fn check<M: TorqueModel>(model: &M, dofs: &[GapDof], weights: &[f64]) -> Result<(), SpError> {
    let n = model.nq();
    if dofs.is_empty() {
        return Err(invalid("a transition needs at least one gap DOF"));
    }
    if weights.len() != n {
        return Err(invalid(format!(
            "torque weights have {} entries but the body has {n} coordinates",
            weights.len()
        )));
    }
    if weights.iter().any(|w| !w.is_finite() || *w < 0.0) {
        return Err(invalid("torque weights must be finite and non-negative"));
    }
    for (i, d) in dofs.iter().enumerate() {
        if d.coord >= n {
            return Err(invalid(format!(
                "gap coordinate {} is outside the body's {n} coordinates",
                d.coord
            )));
        }
        if dofs[..i].iter().any(|e| e.coord == d.coord) {
            return Err(invalid(format!(
                "coordinate {} has two overlapping gaps in one transition",
                d.coord
            )));
        }
        let s = [d.start.q, d.start.v, d.start.a, d.end.q, d.end.v, d.end.a];
        if s.iter().any(|x| !x.is_finite()) {
            return Err(invalid(format!(
                "the motion around the gap of coordinate {} on [{}, {}] is not finite",
                d.coord, d.t0, d.t1
            )));
        }
    }
    Ok(())
}

impl<'a, M: TorqueModel> Objective<'a, M> {
    /// Set up the objective: checks the gaps, lays the quadrature nodes
    /// (see [`composite_nodes`]), samples the inputs once, and tabulates the basis rows.
    pub fn new(
        model: &'a M,
        dofs: Vec<GapDof>,
        settings: &TransitionSettings,
        weights: Vec<f64>,
        inputs: &Inputs<'_>,
    ) -> Result<Self, SpError> {
        check(model, &dofs, &weights)?;
        Self::build(model, GapLayout::new(dofs, settings)?, weights, inputs)
    }

    /// The objective over a layout built beforehand (and possibly shared
    /// with the support IK): checks its gaps, samples the inputs once.
    pub fn on_layout(
        model: &'a M,
        layout: GapLayout,
        weights: Vec<f64>,
        inputs: &Inputs<'_>,
    ) -> Result<Self, SpError> {
        check(model, &layout.dofs, &weights)?;
        Self::build(model, layout, weights, inputs)
    }

    fn build(
        model: &'a M,
        layout: GapLayout,
        weights: Vec<f64>,
        inputs: &Inputs<'_>,
    ) -> Result<Self, SpError> {
        let sampled = Sampled::new(model, &layout, inputs)?;
        let prior = KinematicPrior::none(&layout);
        Ok(Objective {
            layout,
            sampled,
            torque: TorqueTerm { model, weights },
            prior,
            more: vec![],
            forces: vec![],
            point_forces: vec![],
        })
    }

    /// The contact forces held fixed at each node (`per_node[k]` at node k,
    /// with the point their moments are taken about; empty: none anywhere):
    /// the torque term becomes Σwᵢτᵢ² with τ = ID − Σ J_cᵀ f_c,
    /// differentiated with the forces held fixed, and every term reads them
    /// at its node ([`Node::forces`], and in [`Node::tau`]: the base term
    /// balances the root with the same forces). Replaces those set before.
    pub fn set_forces(&mut self, per_node: Vec<NodeForces>) -> Result<(), SpError> {
        if !per_node.is_empty() && per_node.len() != self.n_nodes() {
            return Err(invalid(format!(
                "forces are given at {} nodes but the objective has {}",
                per_node.len(),
                self.n_nodes()
            )));
        }
        self.point_forces = per_node.iter().map(|f| f.forces.clone()).collect();
        self.forces = per_node;
        Ok(())
    }

    /// The contact forces held at each node (empty: none), as
    /// [`Objective::set_forces`] gave them.
    pub fn forces(&self) -> &[Vec<crate::dynamics::PointForce>] {
        &self.point_forces
    }

    /// Sets the weight of the added term named `term` ([`Term::name`]; the
    /// first of that name), e.g. the base term's continuation, without
    /// rebuilding the objective; an error if none has that name or it has
    /// no weight.
    pub fn set_weight(&mut self, term: &str, w: f64) -> Result<(), SpError> {
        match self.more.iter_mut().find(|t| t.name() == term) {
            Some(t) => t.set_weight(w),
            None => Err(invalid(format!("the objective has no `{term}` term"))),
        }
    }

    /// q, q̇, q̈ of every coordinate at node k for unknowns x (the state every
    /// term reads there), e.g. to compute the forces of [`Objective::set_forces`].
    pub fn node_state(&self, x: &[f64], k: usize) -> [Vec<f64>; 3] {
        let n = self.torque.model.nq();
        let [mut q, mut v, mut a] = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
        self.sampled
            .load_into(&self.layout, k, x, [&mut q, &mut v, &mut a]);
        [q, v, a]
    }

    /// Adds a term after those it has (see [`Term`]).
    pub fn with_term(mut self, term: Box<dyn Term<M> + 'a>) -> Self {
        self.more.push(term);
        self
    }

    /// Every term in the order they are summed: torque, prior, then those
    /// of [`Objective::with_term`].
    pub fn terms(&self) -> impl Iterator<Item = &(dyn Term<M> + 'a)> + '_ {
        [&self.torque as &dyn Term<M>, &self.prior as &dyn Term<M>]
            .into_iter()
            .chain(self.more.iter().map(|t| t.as_ref()))
    }

    /// Adds the kinematic prior Σ_d ∫ c_v,d q̇_d² + c_a,d q̈_d² dt over the gap
    /// DOFs, `per_coord[c] = [c_v, c_a]` for model coordinate c (empty: none).
    /// See `sp::prior_weights` for what the weights are and why.
    pub fn with_prior(mut self, per_coord: &[[f64; 2]]) -> Result<Self, SpError> {
        self.prior
            .set(&self.layout.dofs, self.torque.model.nq(), per_coord)?;
        Ok(self)
    }

    /// Scales the prior's weights, as given to [`Objective::with_prior`], by
    /// `scale` in place: the objective equals, bit for bit, one built with
    /// the weights times `scale` (the continuation's steps, `solve/continuation.rs`, need
    /// not rebuild the objective, its inputs sampled again). The example
    /// followed, if any, stays.
    pub fn rescale_prior(&mut self, scale: f64) -> Result<(), SpError> {
        self.prior.rescale(scale)
    }

    /// Makes the prior of the gap DOFs of model coordinates `follow` follow an
    /// example: `trust` (0–1) times the velocities and accelerations of the
    /// motion of `inputs` `shift` seconds away (see [`super::reference`]).
    /// They must be defined there at every node; `false` (and the objective
    /// unchanged) if not.
    pub fn with_example(
        &mut self,
        inputs: &Inputs,
        shift: f64,
        follow: &[usize],
        trust: f64,
    ) -> Result<bool, SpError> {
        let nq = self.torque.model.nq();
        self.prior
            .follow(&self.layout, nq, inputs, (shift, follow, trust))
    }

    /// The layout the objective is built on.
    pub fn layout(&self) -> &GapLayout {
        &self.layout
    }

    /// Number of unknowns (gap DOFs × free coefficients, laid out DOF-major,
    /// then the layout's extras).
    pub fn n_vars(&self) -> usize {
        self.layout.n_vars()
    }

    pub fn n_free(&self) -> usize {
        self.layout.n_free
    }

    pub fn n_nodes(&self) -> usize {
        self.layout.nodes.len()
    }

    pub fn dofs(&self) -> &[GapDof] {
        &self.layout.dofs
    }

    pub fn curves(&self) -> &[TransitionCurve] {
        &self.layout.curves
    }

    pub fn scratch(&self) -> Scratch<M::Workspace> {
        let chunks =
            (self.n_nodes() / MIN_NODES_PER_CHUNK).clamp(1, rayon::current_num_threads().max(1));
        Scratch {
            parts: (0..chunks)
                .map(|_| (self.node_scratch(), vec![0.0; self.n_vars()]))
                .collect(),
        }
    }

    fn node_scratch(&self) -> NodeScratch<M::Workspace> {
        let model = self.torque.model;
        let n = model.nq();
        NodeScratch {
            ws: model.workspace(),
            q: vec![0.0; n],
            v: vec![0.0; n],
            a: vec![0.0; n],
            gq: vec![0.0; n],
            gv: vec![0.0; n],
            ga: vec![0.0; n],
            terms: self.terms().map(|t| t.scratch()).collect(),
            shared: node_seeds::Shared::new(n),
            seeds: node_seeds::Seeds::new(n),
        }
    }

    /// The starting point: every gap DOF's free coefficients fitted to the
    /// Hermite curve (cubic for C¹ — exactly representable — quintic for C²).
    pub fn hermite_start(&self) -> Vec<f64> {
        self.layout.hermite_start()
    }

    /// e(x), and ∂e/∂x into `grad` when given.
    pub fn eval(
        &self,
        s: &mut Scratch<M::Workspace>,
        x: &[f64],
        grad: Option<&mut [f64]>,
    ) -> Result<f64, SpError> {
        debug_assert_eq!(x.len(), self.n_vars());
        let want_grad = grad.is_some();
        let nn = self.n_nodes();
        let chunks = s.parts.len();
        let e = if chunks == 1 {
            let (ns, g) = &mut s.parts[0];
            self.eval_nodes(0..nn, ns, x, want_grad.then_some(g.as_mut_slice()))?
        } else {
            use rayon::prelude::*;
            let partial: Result<Vec<f64>, SpError> = s
                .parts
                .par_iter_mut()
                .enumerate()
                .map(|(i, (ns, g))| {
                    let range = i * nn / chunks..(i + 1) * nn / chunks;
                    self.eval_nodes(range, ns, x, want_grad.then_some(g.as_mut_slice()))
                })
                .collect();
            partial?.iter().sum()
        };
        if let Some(out) = grad {
            out.copy_from_slice(&s.parts[0].1);
            for (_, g) in &s.parts[1..] {
                for (o, v) in out.iter_mut().zip(g) {
                    *o += v;
                }
            }
        }
        if !e.is_finite() {
            return Err(SpError::Numerical(
                "the torque objective is not finite (the body or the motion gives NaN/∞ torques)"
                    .into(),
            ));
        }
        Ok(e)
    }

    /// The part of e (and of ∂e/∂x, into `grad`, overwritten) from the nodes
    /// in `range`: at each node every term in turn (in that order: the sums
    /// are the solver's path), then the state gradient chained through the
    /// basis rows of every DOF whose gap holds the node.
    fn eval_nodes(
        &self,
        range: std::ops::Range<usize>,
        s: &mut NodeScratch<M::Workspace>,
        x: &[f64],
        mut grad: Option<&mut [f64]>,
    ) -> Result<f64, SpError> {
        if let Some(g) = grad.as_deref_mut() {
            g.fill(0.0);
        }
        let layout = &self.layout;
        let mut e = 0.0;
        for k in range {
            self.sampled.load(layout, k, x, s);
            let wk = layout.qweights[k];
            self.node_terms(k, s, x, grad.as_deref_mut(), &mut e)?;
            let Some(g) = grad.as_deref_mut() else {
                continue;
            };
            self.chain_seeds(k, s)?;
            let NodeScratch { gq, gv, ga, .. } = &*s;
            for (d, (dof, act)) in layout.dofs.iter().zip(&layout.active).enumerate() {
                if let Some(r) = &act[k] {
                    let c = dof.coord;
                    let (a0, a1, a2) = (wk * gq[c], wk * gv[c], wk * ga[c]);
                    let gd = &mut g[d * layout.n_free..(d + 1) * layout.n_free];
                    for j in r.live.clone() {
                        gd[j] += a0 * r.rows[0][j] + a1 * r.rows[1][j] + a2 * r.rows[2][j];
                    }
                }
            }
        }
        Ok(e)
    }

    /// Every term at node k (loaded into `s`), in order, into `e` and, when
    /// `grad` is given, into the node's state gradient (zeroed here), the
    /// extras' part of `grad` and the node's seeds.
    fn node_terms(
        &self,
        k: usize,
        s: &mut NodeScratch<M::Workspace>,
        x: &[f64],
        mut grad: Option<&mut [f64]>,
        e: &mut f64,
    ) -> Result<(), SpError> {
        let layout = &self.layout;
        let (n0, wk) = (layout.n_coefficients(), layout.qweights[k]);
        let NodeScratch {
            ws,
            q,
            v,
            a,
            gq,
            gv,
            ga,
            terms,
            shared,
            seeds,
        } = s;
        if grad.is_some() {
            for g in [&mut *gq, &mut *gv, &mut *ga] {
                g.fill(0.0);
            }
            seeds.clear();
        }
        for (term, scratch) in self.terms().zip(terms.iter_mut()) {
            let mut node = Node {
                model: self.torque.model,
                layout,
                k,
                q,
                v,
                a,
                forces: self.forces.get(k),
                extras: &x[n0..],
                ws: &mut *ws,
                scratch,
                shared: &mut *shared,
            };
            let mut sum = NodeSum {
                wk,
                e: &mut *e,
                grad: grad.as_deref_mut().map(|g| NodeGrad {
                    q: &mut gq[..],
                    v: &mut gv[..],
                    a: &mut ga[..],
                    wk,
                    extras: &mut g[n0..],
                    seeds: &mut *seeds,
                }),
            };
            term.node(&mut node, &mut sum)?;
        }
        Ok(())
    }

    /// Full coefficient vectors of every gap DOF for free coefficients x.
    pub fn coefficients(&self, x: &[f64]) -> Vec<Vec<f64>> {
        self.layout.coefficients(x)
    }
}
