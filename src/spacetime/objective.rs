//! The spacetime objective of one group of overlapping gaps:
//! e(x) = ∫ Σᵢ wᵢ τᵢ(q, q̇, q̈)² dt over the group's span by composite
//! Gauss–Legendre quadrature, where the gap DOFs follow their transition
//! curves (free coefficients x) and every other coordinate is an input.
//!
//! The gradient is exact: the model's adjoint gives ∂(Σwτ²)/∂(q, q̇, q̈) per
//! node, and each gap coordinate's q, q̇, q̈ is linear in its free coefficients
//! (the basis rows stored here), so ∂e/∂x = Σ_nodes w_k (g_q·B + g_q̇·B' + g_q̈·B'').

use super::error::{SpError, invalid};
use super::precond::Precond;
use super::quadrature::GaussLegendre;
use super::torque::TorqueModel;
use super::transition::{Continuity, EndState, TransitionCurve};
use crate::dynamics::{JointState, StateGradient};
use nalgebra::DMatrix;

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

/// Fewest Gauss points on one polynomial piece of a transition. With fewer,
/// the optimiser hides torque between nodes (aliasing): on the Fig. 8 case
/// on human44.urdf (5 coefficients, 6 pieces) a solve with 4 points per
/// piece reads 840 by its own rule but 1520 under a 200-point rule; on the
/// project's walk (8 coefficients) 3 points per piece read 212.4 against
/// 220.8. With 6 per piece the two agree within 0.1 % on both cases
/// (measured by hand; the spacetime benchmark shows the nodes per row).
pub const MIN_POINTS_PER_PIECE: usize = 6;

/// Quadrature nodes and weights for the curves of one group: Gauss rules on
/// every piece between consecutive knots of any curve (so neither a gap end,
/// where a curve meets its data with a jump in q̈, nor a knot, where q̈ kinks,
/// lies inside a rule), `samples` points in all, shared in proportion to the
/// length of each piece but at least [`MIN_POINTS_PER_PIECE`] per piece.
pub fn composite_nodes(
    curves: &[TransitionCurve],
    samples: usize,
) -> Result<(Vec<f64>, Vec<f64>), SpError> {
    if samples == 0 {
        return Err(invalid(
            "samples: 0 gives no quadrature points; use samples: 1 or more (default 20)",
        ));
    }
    let mut breaks: Vec<f64> = curves.iter().flat_map(|c| c.breakpoints()).collect();
    breaks.sort_by(f64::total_cmp);
    // merge knots closer than a relative 1e-12 (rounding of equal knots of different curves)
    let span = breaks.last().copied().unwrap_or(0.0) - breaks.first().copied().unwrap_or(0.0);
    breaks.dedup_by(|a, b| (*a - *b).abs() <= 1e-12 * span.max(1e-300));
    let mut nodes = vec![];
    let mut weights = vec![];
    let mut rules: Vec<Option<GaussLegendre>> = vec![];
    for w in breaks.windows(2) {
        let k = ((samples as f64 * (w[1] - w[0]) / span).ceil() as usize).max(MIN_POINTS_PER_PIECE);
        if rules.len() <= k {
            rules.resize(k + 1, None);
        }
        if rules[k].is_none() {
            rules[k] = Some(GaussLegendre::new(k).map_err(|e| invalid(e.to_string()))?);
        }
        if let Some(rule) = &rules[k] {
            let (t, qw) = rule.on(w[0], w[1]);
            nodes.extend(t);
            weights.extend(qw);
        }
    }
    Ok((nodes, weights))
}

/// The gap coordinate's curve at one node: q = offset + rows·x (per derivative order).
#[derive(Clone, Debug)]
struct NodeRows {
    offset: [f64; 3],
    rows: [Vec<f64>; 3],
    /// The free coefficients whose basis functions are alive here (at most four).
    live: std::ops::Range<usize>,
}

/// Fills q, q̇, q̈ of every coordinate that is not a gap at time t; a
/// coordinate undefined at t is left NaN (an error unless it is a gap DOF of
/// the transition being solved).
pub type Inputs<'a> =
    dyn Fn(f64, &mut [f64], &mut [f64], &mut [f64]) -> Result<(), SpError> + Sync + 'a;

/// The objective of one group of gaps.
pub struct Objective<'a, M: TorqueModel> {
    pub(crate) model: &'a M,
    pub(crate) dofs: Vec<GapDof>,
    pub(crate) curves: Vec<TransitionCurve>,
    weights: Vec<f64>,
    pub(crate) nodes: Vec<f64>,
    qweights: Vec<f64>,
    base: Vec<[Vec<f64>; 3]>,
    /// `active[d][k]`: gap DOF d's rows at node k, `None` outside its gap.
    active: Vec<Vec<Option<NodeRows>>>,
    n_free: usize,
    /// Per gap DOF, the weights (c_v, c_a) of the kinematic prior
    /// ∫ c_v (q̇ − ṙ)² + c_a (q̈ − r̈)² dt added to the torque term
    /// ([`Objective::with_prior`]).
    prior: Vec<[f64; 2]>,
    /// Per gap DOF and node, the example's [ṙ, r̈] the prior follows
    /// ([`Objective::with_example`]); zero without one.
    example: Vec<Vec<[f64; 2]>>,
}

/// Scratch vectors of one node evaluation (one thread's).
pub struct NodeScratch<W> {
    pub ws: W,
    q: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
    gq: Vec<f64>,
    gv: Vec<f64>,
    ga: Vec<f64>,
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
        let curves = dofs
            .iter()
            .map(|d| TransitionCurve::new(d.t0, d.t1, settings.coefficients, settings.continuity))
            .collect::<Result<Vec<_>, _>>()?;

        let (nodes, qweights) = composite_nodes(&curves, settings.samples)?;
        let mut base = Vec::with_capacity(nodes.len());
        for &t in &nodes {
            let (mut q, mut v, mut a) = (vec![f64::NAN; n], vec![f64::NAN; n], vec![f64::NAN; n]);
            inputs(t, &mut q, &mut v, &mut a)?;
            for c in 0..n {
                let in_gap = dofs.iter().any(|d| d.coord == c && t >= d.t0 && t <= d.t1);
                if in_gap {
                    continue;
                }
                if !(q[c].is_finite() && v[c].is_finite() && a[c].is_finite()) {
                    let gaps: Vec<String> = dofs
                        .iter()
                        .map(|d| {
                            format!("{} on [{}, {}]", model.coordinate_name(d.coord), d.t0, d.t1)
                        })
                        .collect();
                    return Err(SpError::Evaluation(format!(
                        "{} is undefined at t = {t} but the transition of {} needs the whole body there; \
                         define it (e.g. extend its motion, or fill its own gap first)",
                        model.coordinate_name(c),
                        gaps.join(", ")
                    )));
                }
            }
            base.push([q, v, a]);
        }

        let n_free = settings.coefficients;
        let mut active = Vec::with_capacity(dofs.len());
        for (d, c) in dofs.iter().zip(&curves) {
            let fixed = c.coefficients(&d.start, &d.end, &vec![0.0; n_free]);
            let k0 = c.first_free();
            let per_node = nodes
                .iter()
                .map(|&t| {
                    if t < d.t0 || t > d.t1 {
                        return None;
                    }
                    let b = c.basis_at(t);
                    let mut offset = [0.0; 3];
                    for (o, row) in offset.iter_mut().zip(&b) {
                        *o = row.iter().zip(&fixed).map(|(x, y)| x * y).sum();
                    }
                    let rows = [
                        b[0][k0..k0 + n_free].to_vec(),
                        b[1][k0..k0 + n_free].to_vec(),
                        b[2][k0..k0 + n_free].to_vec(),
                    ];
                    let alive = |j: &usize| rows.iter().any(|r| r[*j] != 0.0);
                    let lo = (0..n_free).find(alive).unwrap_or(0);
                    let hi = (0..n_free).rev().find(alive).map_or(lo, |j| j + 1);
                    Some(NodeRows {
                        offset,
                        rows,
                        live: lo..hi,
                    })
                })
                .collect();
            active.push(per_node);
        }
        let example = vec![vec![[0.0; 2]; nodes.len()]; active.len()];
        Ok(Objective {
            model,
            dofs,
            curves,
            weights,
            nodes,
            qweights,
            base,
            prior: vec![[0.0; 2]; active.len()],
            example,
            active,
            n_free,
        })
    }

    /// Adds the kinematic prior Σ_d ∫ c_v,d q̇_d² + c_a,d q̈_d² dt over the gap
    /// DOFs, `per_coord[c] = [c_v, c_a]` for model coordinate c (empty: none).
    /// See `sp::prior_weights` for what the weights are and why.
    pub fn with_prior(mut self, per_coord: &[[f64; 2]]) -> Result<Self, SpError> {
        if per_coord.is_empty() {
            return Ok(self);
        }
        if per_coord.len() != self.model.nq() {
            return Err(invalid(format!(
                "prior weights have {} entries but the body has {} coordinates",
                per_coord.len(),
                self.model.nq()
            )));
        }
        if per_coord
            .iter()
            .flatten()
            .any(|w| !w.is_finite() || *w < 0.0)
        {
            return Err(invalid("prior weights must be finite and non-negative"));
        }
        self.prior = self.dofs.iter().map(|d| per_coord[d.coord]).collect();
        Ok(self)
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
        let n = self.model.nq();
        let (mut q, mut v, mut a) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        let mut example = vec![vec![[0.0; 2]; self.nodes.len()]; self.dofs.len()];
        for (k, &t) in self.nodes.iter().enumerate() {
            v.fill(f64::NAN);
            a.fill(f64::NAN);
            inputs(t + shift, &mut q, &mut v, &mut a)?;
            for (d, dof) in self.dofs.iter().enumerate() {
                if self.active[d][k].is_none() || !follow.contains(&dof.coord) {
                    continue;
                }
                let (dv, da) = (v[dof.coord], a[dof.coord]);
                if !(dv.is_finite() && da.is_finite()) {
                    return Ok(false);
                }
                example[d][k] = [trust * dv, trust * da];
            }
        }
        self.example = example;
        Ok(true)
    }

    /// Number of unknowns (gap DOFs × free coefficients), laid out DOF-major.
    pub fn n_vars(&self) -> usize {
        self.dofs.len() * self.n_free
    }

    pub fn n_free(&self) -> usize {
        self.n_free
    }

    pub fn n_nodes(&self) -> usize {
        self.nodes.len()
    }

    pub fn dofs(&self) -> &[GapDof] {
        &self.dofs
    }

    pub fn curves(&self) -> &[TransitionCurve] {
        &self.curves
    }

    pub fn scratch(&self) -> Scratch<M::Workspace> {
        let chunks =
            (self.nodes.len() / MIN_NODES_PER_CHUNK).clamp(1, rayon::current_num_threads().max(1));
        Scratch {
            parts: (0..chunks)
                .map(|_| (self.node_scratch(), vec![0.0; self.n_vars()]))
                .collect(),
        }
    }

    fn node_scratch(&self) -> NodeScratch<M::Workspace> {
        let n = self.model.nq();
        NodeScratch {
            ws: self.model.workspace(),
            q: vec![0.0; n],
            v: vec![0.0; n],
            a: vec![0.0; n],
            gq: vec![0.0; n],
            gv: vec![0.0; n],
            ga: vec![0.0; n],
        }
    }

    /// The starting point: every gap DOF's free coefficients fitted to the
    /// Hermite curve (cubic for C¹ — exactly representable — quintic for C²).
    pub fn hermite_start(&self) -> Vec<f64> {
        hermite_free_coefficients(&self.dofs, &self.curves)
    }

    /// Set the q, q̇, q̈ of node k from x into the scratch vectors.
    fn load_node(&self, k: usize, x: &[f64], s: &mut NodeScratch<M::Workspace>) {
        let [bq, bv, ba] = &self.base[k];
        s.q.copy_from_slice(bq);
        s.v.copy_from_slice(bv);
        s.a.copy_from_slice(ba);
        for (d, (dof, act)) in self.dofs.iter().zip(&self.active).enumerate() {
            if let Some(r) = &act[k] {
                let xd = &x[d * self.n_free..(d + 1) * self.n_free];
                let dot = |row: &[f64]| row.iter().zip(xd).map(|(a, b)| a * b).sum::<f64>();
                s.q[dof.coord] = r.offset[0] + dot(&r.rows[0]);
                s.v[dof.coord] = r.offset[1] + dot(&r.rows[1]);
                s.a[dof.coord] = r.offset[2] + dot(&r.rows[2]);
            }
        }
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
        let nn = self.nodes.len();
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
            return Err(SpError::Evaluation(
                "the torque objective is not finite (the body or the motion gives NaN/∞ torques)"
                    .into(),
            ));
        }
        Ok(e)
    }

    /// The part of e (and of ∂e/∂x, into `grad`, overwritten) from the nodes in `range`.
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
        let mut e = 0.0;
        for k in range {
            self.load_node(k, x, s);
            let f = self.model.torque_sq_grad(
                &mut s.ws,
                &JointState::new(&s.q, &s.v, &s.a),
                &self.weights,
                StateGradient {
                    q: &mut s.gq,
                    v: &mut s.gv,
                    a: &mut s.ga,
                },
            )?;
            let wk = self.qweights[k];
            e += wk * f;
            for (d, (dof, act)) in self.dofs.iter().zip(&self.active).enumerate() {
                if act[k].is_some() {
                    let [cv, ca] = self.prior[d];
                    let [rv, ra] = self.example[d][k];
                    let c = dof.coord;
                    let (dv, da) = (s.v[c] - rv, s.a[c] - ra);
                    e += wk * (cv * dv * dv + ca * da * da);
                }
            }
            if let Some(g) = grad.as_deref_mut() {
                for (d, (dof, act)) in self.dofs.iter().zip(&self.active).enumerate() {
                    if let Some(r) = &act[k] {
                        let c = dof.coord;
                        let [cv, ca] = self.prior[d];
                        let [rv, ra] = self.example[d][k];
                        let (a0, a1, a2) = (
                            wk * s.gq[c],
                            wk * (s.gv[c] + 2.0 * cv * (s.v[c] - rv)),
                            wk * (s.ga[c] + 2.0 * ca * (s.a[c] - ra)),
                        );
                        let gd = &mut g[d * self.n_free..(d + 1) * self.n_free];
                        for j in r.live.clone() {
                            gd[j] += a0 * r.rows[0][j] + a1 * r.rows[1][j] + a2 * r.rows[2][j];
                        }
                    }
                }
            }
        }
        Ok(e)
    }

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
        let nn = self.nodes.len();
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
        let nf = self.n_free;
        // the gap DOFs alive at this node, with their rows
        let alive: Vec<(usize, &NodeRows)> = self
            .active
            .iter()
            .enumerate()
            .filter_map(|(d, a)| a[k].as_ref().map(|r| (d, r)))
            .collect();
        if alive.is_empty() {
            return Ok(());
        }
        let coords: Vec<usize> = alive.iter().map(|(d, _)| self.dofs[*d].coord).collect();
        self.load_node(k, x0, s);
        let dm = self
            .model
            .torque_jacobians(&mut s.ws, &s.q, &s.v, &s.a, &coords)?;
        let wk = self.qweights[k];
        // G_αβ = D_αᵀ (w_k W) D_β; G_βα = G_αβᵀ
        let wd: Vec<DMatrix<f64>> = dm
            .iter()
            .map(|m| {
                let mut m = m.clone();
                for (i, mut row) in m.row_iter_mut().enumerate() {
                    row *= wk * self.weights[i];
                }
                m
            })
            .collect();
        let mut g: [[Option<DMatrix<f64>>; 3]; 3] = Default::default();
        for a in 0..3 {
            for b in a..3 {
                g[a][b] = Some(dm[a].transpose() * &wd[b]);
            }
        }
        let gab = |a: usize, b: usize, i: usize, j: usize| match (&g[a][b], &g[b][a]) {
            (Some(m), _) => m[(i, j)],
            (None, Some(m)) => m[(j, i)],
            _ => 0.0,
        };
        // the prior's half-Hessian w_k (c_v r₁r₁ᵀ + c_a r₂r₂ᵀ), block-diagonal per DOF
        for (di, rd) in &alive {
            let [cv, ca] = self.prior[*di];
            if cv == 0.0 && ca == 0.0 {
                continue;
            }
            for p in rd.live.clone() {
                for l in rd.live.clone().filter(|&l| l >= p) {
                    h[(di * nf + p, di * nf + l)] += wk
                        * (cv * rd.rows[1][p] * rd.rows[1][l] + ca * rd.rows[2][p] * rd.rows[2][l]);
                }
            }
        }
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

    /// Full coefficient vectors of every gap DOF for free coefficients x.
    pub fn coefficients(&self, x: &[f64]) -> Vec<Vec<f64>> {
        full_coefficients(&self.dofs, &self.curves, self.n_free, x)
    }
}

/// The free coefficients of every gap DOF fitted to its Hermite curve (cubic
/// for C¹ — exactly representable — quintic for C²), DOF after DOF: the
/// starting point of the torque objective and of the support IK.
pub(crate) fn hermite_free_coefficients(dofs: &[GapDof], curves: &[TransitionCurve]) -> Vec<f64> {
    let mut x = vec![];
    for (d, c) in dofs.iter().zip(curves) {
        let f = |t: f64| match c.continuity() {
            Continuity::C1 => super::hermite::cubic(d.t0, d.t1, &d.start, &d.end, t)[0],
            Continuity::C2 => super::hermite::quintic(d.t0, d.t1, &d.start, &d.end, t)[0],
        };
        x.extend(c.fit_free(&d.start, &d.end, f));
    }
    x
}

/// Full coefficient vectors of gap DOFs whose free coefficients are laid out
/// DOF after DOF, `n_free` each, in `x` (the torque objective's and the
/// support IK's layout).
pub(crate) fn full_coefficients(
    dofs: &[GapDof],
    curves: &[TransitionCurve],
    n_free: usize,
    x: &[f64],
) -> Vec<Vec<f64>> {
    dofs.iter()
        .zip(curves)
        .enumerate()
        .map(|(d, (dof, c))| c.coefficients(&dof.start, &dof.end, &x[d * n_free..(d + 1) * n_free]))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spacetime::planar2::TwoLinkArm;

    fn st(q: f64, v: f64) -> EndState {
        EndState { q, v, a: 0.0 }
    }

    /// Two gaps overlapping in time on the two joints of the arm.
    fn problem<'a>(
        arm: &'a TwoLinkArm,
        settings: &TransitionSettings,
    ) -> Objective<'a, TwoLinkArm> {
        let dofs = vec![
            GapDof {
                coord: 0,
                t0: 0.2,
                t1: 0.9,
                start: st(0.1, 1.0),
                end: st(1.2, -0.5),
            },
            GapDof {
                coord: 1,
                t0: 0.5,
                t1: 1.3,
                start: st(-0.4, 0.0),
                end: st(0.9, 2.0),
            },
        ];
        Objective::new(arm, dofs, settings, vec![1.0, 1.5], &known_motion).unwrap()
    }

    /// Outside a gap each joint of [`problem`] follows this smooth known motion.
    fn known_motion(t: f64, q: &mut [f64], v: &mut [f64], a: &mut [f64]) -> Result<(), SpError> {
        q[0] = (2.0 * t).sin();
        v[0] = 2.0 * (2.0 * t).cos();
        a[0] = -4.0 * (2.0 * t).sin();
        q[1] = t * t;
        v[1] = 2.0 * t;
        a[1] = 2.0;
        Ok(())
    }

    #[test]
    fn gradient_matches_central_differences() {
        let arm = TwoLinkArm::default();
        // with and without SP's kinematic prior ∫ c_v q̇² + c_a q̈²
        for (cont, prior) in [
            (Continuity::C1, vec![]),
            (Continuity::C2, vec![]),
            (Continuity::C1, vec![[0.3, 0.7], [2.0, 0.05]]),
            (Continuity::C2, vec![[0.3, 0.7], [2.0, 0.05]]),
        ] {
            let settings = TransitionSettings {
                coefficients: 6,
                samples: 12,
                continuity: cont,
            };
            let obj = problem(&arm, &settings).with_prior(&prior).unwrap();
            let mut s = obj.scratch();
            let x: Vec<f64> = (0..obj.n_vars()).map(|i| 0.3 * (i as f64).cos()).collect();
            let mut g = vec![0.0; x.len()];
            obj.eval(&mut s, &x, Some(&mut g)).unwrap();
            for i in 0..x.len() {
                let h = 1e-6;
                let (mut xp, mut xm) = (x.clone(), x.clone());
                xp[i] += h;
                xm[i] -= h;
                let fd = (obj.eval(&mut s, &xp, None).unwrap()
                    - obj.eval(&mut s, &xm, None).unwrap())
                    / (2.0 * h);
                let scale = g.iter().map(|v: &f64| v.abs()).fold(0.0, f64::max);
                assert!(
                    (fd - g[i]).abs() <= 1e-6 * scale,
                    "{cont:?} i={i}: fd {fd} vs {}",
                    g[i]
                );
            }
        }
    }

    #[test]
    fn objective_is_the_integral_of_the_weighted_squared_torque() {
        // Compare with a fine trapezoid integral of the same curves.
        let arm = TwoLinkArm::default();
        let settings = TransitionSettings {
            coefficients: 5,
            samples: 30,
            continuity: Continuity::C1,
        };
        let obj = problem(&arm, &settings);
        let x = obj.hermite_start();
        let e = obj.eval(&mut obj.scratch(), &x, None).unwrap();
        let coefs = obj.coefficients(&x);
        let n = 20000;
        let (a, b) = (0.2, 1.3);
        let mut sum = 0.0;
        for i in 0..=n {
            let t = a + (b - a) * i as f64 / n as f64;
            let mut q = [(2.0 * t).sin(), t * t];
            let mut v = [2.0 * (2.0 * t).cos(), 2.0 * t];
            let mut acc = [-4.0 * (2.0 * t).sin(), 2.0];
            for (d, dof) in obj.dofs().iter().enumerate() {
                if t >= dof.t0 && t <= dof.t1 {
                    let s = obj.curves()[d].eval(&coefs[d], t);
                    q[dof.coord] = s[0];
                    v[dof.coord] = s[1];
                    acc[dof.coord] = s[2];
                }
            }
            let mut tau = [0.0; 2];
            arm.torques(&mut (), &q, &v, &acc, &mut tau).unwrap();
            let f = tau[0] * tau[0] + 1.5 * tau[1] * tau[1];
            let w = if i == 0 || i == n { 0.5 } else { 1.0 };
            sum += w * f * (b - a) / n as f64;
        }
        assert!((e - sum).abs() < 1e-5 * sum, "{e} vs {sum}");
    }

    /// With an example, the prior integrates c_v (q̇ − ṙ)² + c_a (q̈ − r̈)² with
    /// r the inputs `shift` away, and its gradient still matches differences.
    #[test]
    fn an_example_moves_the_priors_target_to_its_own_derivatives() {
        let arm = TwoLinkArm::default();
        let settings = TransitionSettings {
            coefficients: 5,
            samples: 30,
            continuity: Continuity::C1,
        };
        let prior = [[0.4, 1.5], [0.7, 0.2]];
        let shift = 0.3;
        let inputs = known_motion;
        let plain = problem(&arm, &settings);
        let mut with = problem(&arm, &settings).with_prior(&prior).unwrap();
        assert!(with.with_example(&inputs, shift, &[0, 1], 1.0).unwrap());
        let mut s = with.scratch();
        let x: Vec<f64> = (0..with.n_vars()).map(|i| 0.2 * (i as f64).sin()).collect();
        let part = with.eval(&mut s, &x, None).unwrap() - plain.eval(&mut s, &x, None).unwrap();
        let coefs = with.coefficients(&x);
        let (n, mut sum) = (20000, 0.0);
        for (d, dof) in with.dofs().iter().enumerate() {
            let [cv, ca] = prior[dof.coord];
            for i in 0..=n {
                let t = dof.t0 + (dof.t1 - dof.t0) * i as f64 / n as f64;
                let c = with.curves()[d].eval(&coefs[d], t);
                let (mut q, mut v, mut a) = ([0.0; 2], [0.0; 2], [0.0; 2]);
                inputs(t + shift, &mut q, &mut v, &mut a).unwrap();
                let f = cv * (c[1] - v[dof.coord]).powi(2) + ca * (c[2] - a[dof.coord]).powi(2);
                let w = if i == 0 || i == n { 0.5 } else { 1.0 };
                sum += w * f * (dof.t1 - dof.t0) / n as f64;
            }
        }
        assert!((part - sum).abs() < 1e-6 * sum, "{part} vs {sum}");
        let mut g = vec![0.0; x.len()];
        with.eval(&mut s, &x, Some(&mut g)).unwrap();
        let scale = g.iter().map(|v: &f64| v.abs()).fold(0.0, f64::max);
        for i in 0..x.len() {
            let h = 1e-6;
            let (mut xp, mut xm) = (x.clone(), x.clone());
            xp[i] += h;
            xm[i] -= h;
            let fd = (with.eval(&mut s, &xp, None).unwrap()
                - with.eval(&mut s, &xm, None).unwrap())
                / (2.0 * h);
            assert!(
                (fd - g[i]).abs() <= 1e-6 * scale,
                "i={i}: fd {fd} vs {}",
                g[i]
            );
        }
        // an example undefined at some node is refused, the objective unchanged
        let undefined = |t: f64, q: &mut [f64], v: &mut [f64], a: &mut [f64]| {
            if t < 1.0 { inputs(t, q, v, a) } else { Ok(()) }
        };
        let mut other = problem(&arm, &settings).with_prior(&prior).unwrap();
        assert!(!other.with_example(&undefined, shift, &[0, 1], 1.0).unwrap());
        let e0 = other.eval(&mut s, &x, None).unwrap();
        let e1 = problem(&arm, &settings)
            .with_prior(&prior)
            .unwrap()
            .eval(&mut s, &x, None)
            .unwrap();
        assert_eq!(e0, e1);
    }

    #[test]
    fn the_prior_adds_its_integral_and_its_gauss_newton_block() {
        let arm = TwoLinkArm::default();
        let settings = TransitionSettings {
            coefficients: 5,
            samples: 30,
            continuity: Continuity::C1,
        };
        let plain = problem(&arm, &settings);
        let prior = [[0.4, 1.5], [0.0, 0.0]];
        let with = problem(&arm, &settings).with_prior(&prior).unwrap();
        let x: Vec<f64> = (0..plain.n_vars())
            .map(|i| 0.2 * (i as f64).sin())
            .collect();
        let e0 = plain.eval(&mut plain.scratch(), &x, None).unwrap();
        let e1 = with.eval(&mut with.scratch(), &x, None).unwrap();
        // the prior on coordinate 0 alone, by a fine trapezoid rule over its gap
        let d = &plain.dofs()[0];
        let c = plain.coefficients(&x);
        let n = 20000;
        let mut sum = 0.0;
        for i in 0..=n {
            let t = d.t0 + (d.t1 - d.t0) * i as f64 / n as f64;
            let s = plain.curves()[0].eval(&c[0], t);
            let w = if i == 0 || i == n { 0.5 } else { 1.0 };
            sum += w * (0.4 * s[1] * s[1] + 1.5 * s[2] * s[2]) * (d.t1 - d.t0) / n as f64;
        }
        assert!((e1 - e0 - sum).abs() < 1e-6 * sum, "{} vs {sum}", e1 - e0);
        // the prior is quadratic in x: its Gauss–Newton block is its exact Hessian
        assert!(problem(&arm, &settings).with_prior(&[[1.0, 1.0]]).is_err());
        assert!(
            problem(&arm, &settings)
                .with_prior(&[[-1.0, 0.0], [0.0, 0.0]])
                .is_err()
        );
    }

    #[test]
    fn bad_inputs_are_clear_errors() {
        let arm = TwoLinkArm::default();
        let s = TransitionSettings::default();
        let inputs = |_: f64, _: &mut [f64], _: &mut [f64], _: &mut [f64]| Ok(());
        let gap = GapDof {
            coord: 5,
            t0: 0.0,
            t1: 1.0,
            start: st(0.0, 0.0),
            end: st(1.0, 0.0),
        };
        assert!(Objective::new(&arm, vec![gap.clone()], &s, vec![1.0; 2], &inputs).is_err());
        let gap0 = GapDof {
            coord: 0,
            ..gap.clone()
        };
        assert!(Objective::new(&arm, vec![gap0.clone()], &s, vec![1.0; 3], &inputs).is_err());
        assert!(
            Objective::new(
                &arm,
                vec![gap0.clone(), gap0.clone()],
                &s,
                vec![1.0; 2],
                &inputs
            )
            .is_err()
        );
        let nan = GapDof {
            start: st(f64::NAN, 0.0),
            ..gap0.clone()
        };
        assert!(Objective::new(&arm, vec![nan], &s, vec![1.0; 2], &inputs).is_err());
        let s0 = TransitionSettings {
            samples: 0,
            ..s.clone()
        };
        assert!(Objective::new(&arm, vec![gap0], &s0, vec![1.0; 2], &inputs).is_err());
    }
}
