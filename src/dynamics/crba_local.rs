//! The mass matrix in link frames (the CRBA as Pinocchio runs it by default):
//! composite inertias are carried to the parent through the link's own
//! placement `X_i = offset_i · G_i(q_i)` as 10 numbers (mass, first moment,
//! symmetric rotational inertia) rather than 6×6 matrices, each column's
//! composite momentum `F = I^c S` is read off the composite (a one-axis joint's:
//! a column of it) and carried up the same way, and an entry `S_rᵀ F_c` is one
//! component of a momentum (`S` has one nonzero on a coordinate axis). No world
//! placement of any link is formed. Links that turn about a coordinate axis
//! behind a translating offset are carried by an [`AxisTurn`].

use crate::dynamics::axis_turn::AxisTurn;
use crate::dynamics::workspace::Workspace;
use crate::lie::{Se3, Twist, Wrench};
use crate::model::joint::Derivatives;
use crate::model::{Inertia, Model};
use nalgebra::Vector3;

/// The placement of a link in its parent frame, in the cheapest form its joint
/// and offset allow.
enum Placement {
    Turn(AxisTurn),
    General(Se3),
}

impl Placement {
    /// Carries every wrench of `fs` from the link frame to the parent's.
    #[inline(always)]
    fn wrenches_to_parent(&self, fs: &mut [Wrench]) {
        match self {
            Placement::Turn(t) => t.ad_wrenches(fs),
            Placement::General(x) => {
                for f in fs {
                    *f = x.ad_wrench(f);
                }
            }
        }
    }

    #[inline(always)]
    fn inertia_to_parent(&self, y: &Inertia) -> Inertia {
        match self {
            Placement::Turn(t) => t.inertia_to_parent(y),
            Placement::General(x) => y.transformed(x),
        }
    }
}

/// Fills `out` (column-major, n × n, zeroed by the caller) on a depth-first
/// model (the caller checks): link i's rows meet the contiguous coordinate
/// range of its subtree.
pub(super) fn mass_matrix_local(model: &Model, ws: &mut Workspace, q: &[f64], out: &mut [f64]) {
    let n = model.nq();
    for (i, l) in model.links().iter().enumerate() {
        ws.ic[i] = l.inertia;
    }
    for i in (0..model.num_links()).rev() {
        let l = model.link(i);
        let qi = l.q_index;
        // Some on every link: the caller checked the model is depth-first.
        let Some(subtree) = model.subtree_coordinates(i) else {
            continue;
        };
        let y = ws.ic[i];
        // Own columns: F = I^c S, and the entries S_rᵀ F_c of this joint's rows
        // r against every column c ≥ r of its subtree.
        let placement = if let Some((turn, sign)) = AxisTurn::of(l, q[qi]) {
            // F = I^c (σ e_k; 0) = σ (column k of i_o; e_k × h).
            let k = turn.axis();
            let h = &y.h;
            let ek_h = match k {
                0 => Vector3::new(0.0, -h.z, h.y),
                1 => Vector3::new(h.z, 0.0, -h.x),
                _ => Vector3::new(-h.y, h.x, 0.0),
            };
            let col = y.i_o.column(k);
            ws.ag[qi] = Wrench::new(col[0], col[1], col[2], ek_h.x, ek_h.y, ek_h.z) * sign;
            for c in subtree.clone() {
                let x = sign * ws.ag[c][k];
                out[c * n + qi] = x;
                out[qi * n + c] = x;
            }
            Placement::Turn(turn)
        } else if let Some(axis) = &l.axis {
            let sj = axis.twist();
            ws.ag[qi] = y.mul_twist(&sj);
            for c in subtree.clone() {
                let x = sj.dot(&ws.ag[c]);
                out[c * n + qi] = x;
                out[qi * n + c] = x;
            }
            Placement::General(axis.place(&l.offset, q[qi]))
        } else {
            l.joint
                .kinematics(&q[qi..qi + l.dof], Derivatives::Jacobian, &mut ws.kin[i]);
            let kin = &ws.kin[i];
            for j in 0..l.dof {
                ws.ag[qi + j] = y.mul_twist(&kin.s[j]);
            }
            for j in 0..l.dof {
                let sj: &Twist = &kin.s[j];
                for c in qi + j..subtree.end {
                    let x = sj.dot(&ws.ag[c]);
                    out[c * n + qi + j] = x;
                    out[(qi + j) * n + c] = x;
                }
            }
            Placement::General(l.offset.compose(&kin.transform))
        };
        if let Some(p) = l.parent {
            // Massless leaves (URDF frames, the links between one anatomical
            // joint's axes) add nothing.
            if !y.is_zero() {
                let yp = placement.inertia_to_parent(&y);
                ws.ic[p] += yp;
            }
            placement.wrenches_to_parent(&mut ws.ag[subtree]);
        }
    }
}
