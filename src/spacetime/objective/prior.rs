//! SP's kinematic prior over the gap DOFs of one objective:
//! Σ_d ∫ c_v,d (q̇_d − ṙ_d)² + c_a,d (q̈_d − r̈_d)² dt, r an example's motion
//! (zero without one). It is quadratic in the free coefficients, so its
//! Gauss–Newton block is its exact Hessian. The weights are kept as given
//! and as scaled, so the continuation (`groups.rs`) can lower the prior in
//! place instead of rebuilding the objective.

use super::super::error::{SpError, invalid};
use super::super::torque::TorqueModel;
use super::layout::GapLayout;
use super::term::{GaussNewtonNode, Node, NodeSum, Term};
use super::{GapDof, Inputs};

/// The prior's weights and the motion it follows.
#[derive(Clone, Debug)]
pub(super) struct KinematicPrior {
    /// Per gap DOF, (c_v, c_a) as given ([`KinematicPrior::set`]).
    given: Vec<[f64; 2]>,
    /// Per gap DOF, the weights in use: `given` times the last scale.
    weights: Vec<[f64; 2]>,
    /// Per gap DOF and node, the example's [ṙ, r̈] the prior follows; zero
    /// without one.
    example: Vec<Vec<[f64; 2]>>,
}

impl KinematicPrior {
    /// No prior: every weight zero.
    pub(super) fn none(layout: &GapLayout) -> Self {
        let n = layout.dofs.len();
        KinematicPrior {
            given: vec![[0.0; 2]; n],
            weights: vec![[0.0; 2]; n],
            example: vec![vec![[0.0; 2]; layout.nodes.len()]; n],
        }
    }

    /// The weights `per_coord[c] = [c_v, c_a]` of model coordinate c (of a
    /// body with `nq` coordinates) on the gap DOFs; empty leaves them as they are.
    pub(super) fn set(
        &mut self,
        dofs: &[GapDof],
        nq: usize,
        per_coord: &[[f64; 2]],
    ) -> Result<(), SpError> {
        if per_coord.is_empty() {
            return Ok(());
        }
        if per_coord.len() != nq {
            return Err(invalid(format!(
                "prior weights have {} entries but the body has {nq} coordinates",
                per_coord.len(),
            )));
        }
        if per_coord
            .iter()
            .flatten()
            .any(|w| !w.is_finite() || *w < 0.0)
        {
            return Err(invalid("prior weights must be finite and non-negative"));
        }
        self.given = dofs.iter().map(|d| per_coord[d.coord]).collect();
        self.weights = self.given.clone();
        Ok(())
    }

    /// The weights as given times `scale`: the same products a prior built
    /// from scaled weights holds, so the two agree bit for bit.
    pub(super) fn rescale(&mut self, scale: f64) -> Result<(), SpError> {
        if !(scale.is_finite() && scale >= 0.0) {
            return Err(invalid(format!(
                "prior scale {scale} must be finite and non-negative"
            )));
        }
        let scaled: Vec<[f64; 2]> = self
            .given
            .iter()
            .map(|[v, a]| [v * scale, a * scale])
            .collect();
        if scaled.iter().flatten().any(|w| !w.is_finite()) {
            return Err(invalid(format!(
                "prior scale {scale} makes the prior's weights overflow"
            )));
        }
        self.weights = scaled;
        Ok(())
    }

    /// Follows `trust` times the q̇, q̈ of `inputs` `shift` seconds away on
    /// the gap DOFs of coordinates `follow`; `false` (and the prior
    /// unchanged) where they are undefined at a node of their gap.
    pub(super) fn follow(
        &mut self,
        layout: &GapLayout,
        nq: usize,
        inputs: &Inputs,
        (shift, follow, trust): (f64, &[usize], f64),
    ) -> Result<bool, SpError> {
        let (mut q, mut v, mut a) = (vec![0.0; nq], vec![0.0; nq], vec![0.0; nq]);
        let mut example = vec![vec![[0.0; 2]; layout.nodes.len()]; layout.dofs.len()];
        for (k, &t) in layout.nodes.iter().enumerate() {
            v.fill(f64::NAN);
            a.fill(f64::NAN);
            inputs(t + shift, &mut q, &mut v, &mut a)?;
            for (d, dof) in layout.dofs.iter().enumerate() {
                if layout.active[d][k].is_none() || !follow.contains(&dof.coord) {
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

    /// The integrand c_v (q̇ − ṙ)² + c_a (q̈ − r̈)² of DOF d at node k.
    pub(super) fn cost(&self, d: usize, k: usize, v: f64, a: f64) -> f64 {
        let [cv, ca] = self.weights[d];
        let [rv, ra] = self.example[d][k];
        let (dv, da) = (v - rv, a - ra);
        cv * dv * dv + ca * da * da
    }

    /// The integrand's derivatives with respect to q̇ and q̈ of DOF d at node k.
    pub(super) fn slopes(&self, d: usize, k: usize, v: f64, a: f64) -> [f64; 2] {
        let [cv, ca] = self.weights[d];
        let [rv, ra] = self.example[d][k];
        [2.0 * cv * (v - rv), 2.0 * ca * (a - ra)]
    }
}

impl<M: TorqueModel> Term<M> for KinematicPrior {
    fn name(&self) -> &str {
        "prior"
    }

    /// Σ_d over the DOFs whose gap holds the node; a DOF's integrand is
    /// added on its own (the sums are the solver's path).
    fn node(&self, node: &mut Node<'_, M>, sum: &mut NodeSum<'_>) -> Result<(), SpError> {
        let (layout, k) = (node.layout, node.k);
        let alive = || {
            layout
                .dofs
                .iter()
                .zip(&layout.active)
                .enumerate()
                .filter(move |(_, (_, act))| act[k].is_some())
                .map(|(d, (dof, _))| (d, dof.coord))
        };
        for (d, c) in alive() {
            sum.add(self.cost(d, k, node.v[c], node.a[c]));
        }
        if let Some(g) = sum.gradient() {
            for (d, c) in alive() {
                let [sv, sa] = self.slopes(d, k, node.v[c], node.a[c]);
                g.v[c] += sv;
                g.a[c] += sa;
            }
        }
        Ok(())
    }

    /// Its exact half-Hessian at the node, w_k (c_v r₁r₁ᵀ + c_a r₂r₂ᵀ),
    /// block-diagonal per DOF.
    fn gauss_newton(
        &self,
        _node: &mut Node<'_, M>,
        gn: &mut GaussNewtonNode<'_>,
    ) -> Result<(), SpError> {
        let (wk, nf) = (gn.wk(), gn.layout.n_free);
        for &(di, rd) in gn.alive() {
            let [cv, ca] = self.weights[di];
            if cv == 0.0 && ca == 0.0 {
                continue;
            }
            for p in rd.live.clone() {
                for l in rd.live.clone().filter(|&l| l >= p) {
                    gn.add(
                        di * nf + p,
                        di * nf + l,
                        wk * (cv * rd.rows[1][p] * rd.rows[1][l]
                            + ca * rd.rows[2][p] * rd.rows[2][l]),
                    );
                }
            }
        }
        Ok(())
    }
}
