//! The joint-space mass matrix by the composite-rigid-body algorithm:
//! `M_ij = S_iᵀ I^c_j S_j` (i an ancestor of j) with `I^c_j` the inertia of the
//! subtree of link j, all in the world frame.

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
    let out = m.as_mut_slice();
    out.fill(0.0);
    // Everything in the world frame (as Pinocchio does): composite inertias then
    // add up without transforms, and each entry above the diagonal block is a
    // plain dot product `J_aᵀ (I^c_i J_i)` instead of a transform per ancestor.
    for (i, l) in model.links().iter().enumerate() {
        // The frame the joint moves in: the parent's placement times the fixed offset.
        let before = match l.parent {
            Some(p) => ws.world[p].compose(&l.offset),
            None => l.offset,
        };
        let world = match l.joint.joint_axis() {
            // Revolute/prismatic: a constant motion subspace, placed directly.
            Some(axis) => {
                let world = axis.place(&before, q[l.q_index]);
                ws.jw[l.q_index] = axis.twist_in(&world);
                world
            }
            None => {
                l.joint.kinematics(
                    &q[l.q_index..l.q_index + l.dof],
                    Derivatives::Jacobian,
                    &mut ws.kin[i],
                );
                let world = before.compose(&ws.kin[i].transform);
                for j in 0..l.dof {
                    ws.jw[l.q_index + j] = world.ad_twist(&ws.kin[i].s[j]);
                }
                world
            }
        };
        ws.world[i] = world;
        ws.ic[i] = l.inertia.transformed(&world);
    }
    for i in (0..model.num_links()).rev() {
        let l = model.link(i);
        let ic = ws.ic[i];
        for j in 0..l.dof {
            let col = l.q_index + j;
            let f = ic.mul_twist(&ws.jw[col]);
            for k in 0..l.dof {
                out[col * n + l.q_index + k] = ws.jw[l.q_index + k].dot(&f);
            }
            let mut c = i;
            while let Some(p) = model.link(c).parent {
                let lp = model.link(p);
                for row in lp.q_index..lp.q_index + lp.dof {
                    let x = ws.jw[row].dot(&f);
                    out[col * n + row] = x;
                    out[row * n + col] = x;
                }
                c = p;
            }
        }
        if let Some(p) = l.parent {
            ws.ic[p] += ic;
        }
    }
    Ok(())
}
