//! The state of the body at every quadrature node: every coordinate that is
//! not a gap (the inputs) sampled once when the objective is built, the gap
//! DOFs set from x at each evaluation. Every term reads the same state.

use super::super::error::SpError;
use super::super::torque::TorqueModel;
use super::layout::GapLayout;
use super::{Inputs, NodeScratch};

pub(super) struct Sampled {
    /// q, q̇, q̈ of every coordinate at every node (gap DOFs overwritten from x).
    base: Vec<[Vec<f64>; 3]>,
}

impl Sampled {
    /// Samples `inputs` at the layout's nodes; a coordinate undefined at a
    /// node outside its own gap is an error naming it and the gaps.
    pub(super) fn new<M: TorqueModel>(
        model: &M,
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
        Ok(Sampled { base })
    }

    /// Sets the q, q̇, q̈ of node k from x into the scratch vectors.
    pub(super) fn load<W>(&self, layout: &GapLayout, k: usize, x: &[f64], s: &mut NodeScratch<W>) {
        self.load_into(layout, k, x, [&mut s.q, &mut s.v, &mut s.a]);
    }

    /// Sets the q, q̇, q̈ of node k from x into `out`.
    pub(super) fn load_into(
        &self,
        layout: &GapLayout,
        k: usize,
        x: &[f64],
        [q, v, a]: [&mut [f64]; 3],
    ) {
        let [bq, bv, ba] = &self.base[k];
        q.copy_from_slice(bq);
        v.copy_from_slice(bv);
        a.copy_from_slice(ba);
        for (d, (dof, act)) in layout.dofs.iter().zip(&layout.active).enumerate() {
            if let Some(r) = &act[k] {
                let xd = layout.of_dof(d, x);
                q[dof.coord] = r.value(0, xd);
                v[dof.coord] = r.value(1, xd);
                a[dof.coord] = r.value(2, xd);
            }
        }
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
