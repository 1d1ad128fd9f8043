//! How world forces at link points change the torques as the body moves:
//! ∂(−Σ_c J_c(q)ᵀ [m_c; f_c])/∂q, the forces held fixed in the world while
//! their points move with q (`external.rs`), exactly, from one kinematic
//! pass — the spacetime preconditioner's torque Jacobian with contact
//! forces took it by central differences, two inverse dynamics per column.

use crate::dynamics::DynamicsError;
use crate::dynamics::external::{PointForce, check_points};
use crate::dynamics::workspace::{Workspace, world_velocity_pass};
use crate::lie::{Wrench, ad};
use crate::model::Model;
use nalgebra::{DMatrix, Vector3};

/// ∂(−Σ_c J_c(q)ᵀ [m_c; f_c])/∂q over the columns `coords` (an nq ×
/// `coords.len()` matrix written into `out`), the forces held fixed in the
/// world while their points move with q: the part of ∂τ/∂q that the forces
/// add to inverse dynamics' own ([`crate::dynamics::inverse_dynamics_at_points`]).
/// Exact, from one kinematic pass.
///
/// With ξ_j the world column of coordinate j (twist at the world origin)
/// and W_c = [p_c × f_c + m_c; f_c] the force's wrench about the origin, the
/// force's torque on j is −ξ_j · W_c for every j that moves its link. Then
/// ∂(ξ_j · W_c)/∂q_k = (∂ξ_j/∂q_k) · W_c + ξ_j · ∂W_c/∂q_k with
/// ∂ξ_j/∂q_k = ad_{ξ_k} ξ_j for k of the same or an ancestor joint (plus
/// Ad_T ∂S_j/∂q_k within a joint whose Jacobian depends on q), and
/// ∂W_c/∂q_k = [(∂p_c/∂q_k) × f_c; 0], ∂p_c/∂q_k = v_k + ω_k × p_c.
pub fn point_forces_jacobian(
    model: &Model,
    ws: &mut Workspace,
    q: &[f64],
    forces: &[PointForce],
    coords: &[usize],
    out: &mut DMatrix<f64>,
) -> Result<(), DynamicsError> {
    let n = model.nq();
    model
        .check_vec("q", q, n)
        .map_err(|e| DynamicsError::Input(e.to_string()))?;
    ws.check(model)?;
    check_points(model, forces)?;
    if out.shape() != (n, coords.len()) || coords.iter().any(|&c| c >= n) {
        return Err(DynamicsError::Input(format!(
            "the forces' Jacobian is {n} × {} over coordinates below {n}, given {:?} over {coords:?}",
            coords.len(),
            out.shape()
        )));
    }
    out.fill(0.0);
    // the world columns and poses at q (at rest: only the placement is read)
    let mut rest = std::mem::take(&mut ws.tau);
    rest.fill(0.0);
    world_velocity_pass(model, ws, q, &rest);
    ws.tau = rest;
    let mut col_of = vec![None; n];
    for (j, &c) in coords.iter().enumerate() {
        col_of[c] = Some(j);
    }
    // the coordinates moving a link, leaf to root, with their links
    let mut chain: Vec<(usize, usize, usize)> = vec![];
    for pf in forces {
        let p = ws.world[pf.link].act_point(&pf.point);
        let mu = p.cross(&pf.force) + pf.moment;
        let f = pf.force;
        let w = Wrench::new(mu.x, mu.y, mu.z, f.x, f.y, f.z);
        chain.clear();
        let mut l = Some(pf.link);
        while let Some(i) = l {
            let lk = model.link(i);
            chain.extend((0..lk.dof).map(|m| (lk.q_index + m, i, m)));
            l = lk.parent;
        }
        for (pj, &(cj, lj, mj)) in chain.iter().enumerate() {
            let xj = ws.jw[cj];
            let wj = Vector3::new(xj[0], xj[1], xj[2]);
            for (pk, &(ck, lk, mk)) in chain.iter().enumerate() {
                let Some(col) = col_of[ck] else { continue };
                let xk = ws.jw[ck];
                let (wk, vk) = (
                    Vector3::new(xk[0], xk[1], xk[2]),
                    Vector3::new(xk[3], xk[4], xk[5]),
                );
                // the point moves: ξ_j · [(∂p/∂q_k) × f; 0]
                let mut d = wj.dot(&(vk + wk.cross(&p)).cross(&pf.force));
                // the column turns: k of the same joint, or of an ancestor
                // (later in the chain, leaf to root)
                if lk == lj || pk > pj {
                    let mut dx = ad(&xk, &xj);
                    let link = model.link(lj);
                    if lk == lj && !link.constant_jacobian {
                        dx += ws.world[lj].ad_twist(&ws.kin[lj].ds[mj][mk]);
                    }
                    d += dx.dot(&w);
                }
                out[(cj, col)] -= d;
            }
        }
    }
    Ok(())
}
