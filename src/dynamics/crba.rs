//! The joint-space mass matrix by the composite-rigid-body algorithm:
//! `M_ij = S_iᵀ Ad*(I^c_i S_j)` with `I^c_i` the inertia of the subtree of link i.

use crate::dynamics::DynamicsError;
use crate::dynamics::workspace::Workspace;
use crate::model::Model;
use crate::model::joint::Derivatives;
use nalgebra::DMatrix;

/// Fills `m` (nq × nq, symmetric) with the mass matrix `M(q)`.
pub fn mass_matrix(
    model: &Model,
    ws: &mut Workspace,
    q: &[f64],
    m: &mut DMatrix<f64>,
) -> Result<(), DynamicsError> {
    ws.check(model)?;
    model.check_vec("q", q, model.nq())?;
    let n = model.nq();
    if m.nrows() != n || m.ncols() != n {
        return Err(DynamicsError::Input(format!(
            "the mass-matrix output is {}×{}; it must be {n}×{n}",
            m.nrows(),
            m.ncols()
        )));
    }
    // Entries between coordinates of different branches are never written below.
    m.fill(0.0);
    for (i, l) in model.links().iter().enumerate() {
        l.joint.kinematics(
            &q[l.q_index..l.q_index + l.dof],
            Derivatives::Jacobian,
            &mut ws.kin[i],
        );
        ws.xt[i] = l.offset.compose(&ws.kin[i].transform);
        ws.ic[i] = l.inertia;
    }
    for i in (0..model.num_links()).rev() {
        let l = model.link(i);
        let ic = ws.ic[i];
        for j in 0..l.dof {
            let col = l.q_index + j;
            let mut f = ic.mul_twist(&ws.kin[i].s[j]);
            for k in 0..l.dof {
                m[(l.q_index + k, col)] = ws.kin[i].s[k].dot(&f);
            }
            // Walk up to the root, filling the column above the diagonal block.
            let mut c = i;
            while let Some(p) = model.link(c).parent {
                f = ws.xt[c].ad_wrench(&f);
                let lp = model.link(p);
                for k in 0..lp.dof {
                    let x = ws.kin[p].s[k].dot(&f);
                    m[(lp.q_index + k, col)] = x;
                    m[(col, lp.q_index + k)] = x;
                }
                c = p;
            }
        }
        if let Some(p) = l.parent {
            let moved = ic.transformed(&ws.xt[i]);
            ws.ic[p] += moved;
        }
    }
    Ok(())
}
