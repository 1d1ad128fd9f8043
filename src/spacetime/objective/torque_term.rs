//! The torque term ∫ Σᵢ wᵢ τᵢ² dt of one objective: the body, the
//! per-coordinate weights, and every coordinate that is not a gap (the
//! inputs) sampled once at the quadrature nodes.

use super::super::error::SpError;
use super::super::torque::TorqueModel;
use super::layout::GapLayout;
use super::{Inputs, NodeScratch};
use crate::dynamics::{JointState, StateGradient};
use nalgebra::DMatrix;

pub(super) struct TorqueTerm<'a, M: TorqueModel> {
    pub(super) model: &'a M,
    pub(super) weights: Vec<f64>,
    /// q, q̇, q̈ of every coordinate at every node (gap DOFs overwritten from x).
    base: Vec<[Vec<f64>; 3]>,
}

impl<'a, M: TorqueModel> TorqueTerm<'a, M> {
    /// Samples `inputs` at the layout's nodes; a coordinate undefined at a
    /// node outside its own gap is an error naming it and the gaps.
    pub(super) fn new(
        model: &'a M,
        weights: Vec<f64>,
        layout: &GapLayout,
        inputs: &Inputs<'_>,
    ) -> Result<Self, SpError> {
        let n = model.nq();
        let mut base = Vec::with_capacity(layout.nodes.len());
        for &t in &layout.nodes {
            let (mut q, mut v, mut a) = (vec![f64::NAN; n], vec![f64::NAN; n], vec![f64::NAN; n]);
            inputs(t, &mut q, &mut v, &mut a)?;
            for c in 0..n {
                if layout.in_gap(c, t) {
                    continue;
                }
                if !(q[c].is_finite() && v[c].is_finite() && a[c].is_finite()) {
                    return Err(undefined(model, layout, c, t));
                }
            }
            base.push([q, v, a]);
        }
        Ok(TorqueTerm {
            model,
            weights,
            base,
        })
    }

    /// Sets the q, q̇, q̈ of node k from x into the scratch vectors.
    pub(super) fn load_node(
        &self,
        layout: &GapLayout,
        k: usize,
        x: &[f64],
        s: &mut NodeScratch<M::Workspace>,
    ) {
        let [bq, bv, ba] = &self.base[k];
        s.q.copy_from_slice(bq);
        s.v.copy_from_slice(bv);
        s.a.copy_from_slice(ba);
        for (d, (dof, act)) in layout.dofs.iter().zip(&layout.active).enumerate() {
            if let Some(r) = &act[k] {
                let xd = layout.of_dof(d, x);
                s.q[dof.coord] = r.value(0, xd);
                s.v[dof.coord] = r.value(1, xd);
                s.a[dof.coord] = r.value(2, xd);
            }
        }
    }

    /// Σ wᵢ τᵢ² at the state loaded in `s`, its gradient with respect to
    /// (q, q̇, q̈) into the scratch's gradient vectors.
    pub(super) fn node_cost(&self, s: &mut NodeScratch<M::Workspace>) -> Result<f64, SpError> {
        self.model.torque_sq_grad(
            &mut s.ws,
            &JointState::new(&s.q, &s.v, &s.a),
            &self.weights,
            StateGradient {
                q: &mut s.gq,
                v: &mut s.gv,
                a: &mut s.ga,
            },
        )
    }

    /// At the state loaded in `s`, G_αβ = D_αᵀ (w_k W) D_β for α ≤ β, with
    /// D_α = ∂τ/∂(q, q̇, q̈)_α restricted to the columns `coords`.
    pub(super) fn gauss_newton_blocks(
        &self,
        s: &mut NodeScratch<M::Workspace>,
        coords: &[usize],
        wk: f64,
    ) -> Result<[[Option<DMatrix<f64>>; 3]; 3], SpError> {
        let dm = self
            .model
            .torque_jacobians(&mut s.ws, &s.q, &s.v, &s.a, coords)?;
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
        Ok(g)
    }
}

/// Coordinate c is undefined at t outside any gap of its own.
fn undefined<M: TorqueModel>(model: &M, layout: &GapLayout, c: usize, t: f64) -> SpError {
    let gaps: Vec<String> = layout
        .dofs
        .iter()
        .map(|d| format!("{} on [{}, {}]", model.coordinate_name(d.coord), d.t0, d.t1))
        .collect();
    SpError::Undefined {
        dof: model.coordinate_name(c).to_string(),
        t,
        need: crate::spacetime::Need::Transition(gaps.join(", ")),
    }
}
