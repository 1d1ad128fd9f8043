//! Forces the world applies at points of the body (a foot on the floor):
//! a world-frame force, and optionally a moment, at a point fixed on a link.
//! Inverse dynamics with them is τ = ID(q, q̇, q̈) − Σ_c J_c(q)ᵀ [m_c; f_c]
//! (`rnea::inverse_dynamics_at_points`), J_c the point's world Jacobian;
//! the adjoint (`adjoint::torque_sq_gradient_at_points`) differentiates Σwτ²
//! with the forces held fixed in the world.
//!
//! The RNEA takes external wrenches in link frames; a world force at a link
//! point is one there, F_i = [r × Rᵢᵀf + Rᵢᵀm; Rᵢᵀf], Rᵢ the link's world
//! rotation. F_i turns with the link, so beside what the adjoint already
//! gives for a wrench fixed on the link, q moves it: with ω the link-frame
//! angular part of ∂Tᵢ/∂q_k, ∂F_i/∂q_k = [r × (f_i × ω) + m_i × ω; f_i × ω],
//! and since ∂(Σwτ²)/∂F_i = −F̄_i = −[α; β] (the adjoint twist),
//! ∂(Σwτ²)/∂q_k gains ω · u_i, u_i = −((α × r) × f_i + α × m_i + β × f_i).
//! Summed over the links below k as U_k = u_k + Σ_children R_c U_c, that is
//! s_k,angular · U_k for each column of joint k.

use crate::dynamics::DynamicsError;
use crate::dynamics::workspace::Workspace;
use crate::lie::{Se3, Wrench};
use crate::model::Model;
use nalgebra::Vector3;

/// A world-frame force (N), and moment (N·m), applied at a point fixed on a
/// link, given in that link's frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointForce {
    pub link: usize,
    pub point: Vector3<f64>,
    pub force: Vector3<f64>,
    /// Zero for a pure force.
    pub moment: Vector3<f64>,
}

impl PointForce {
    /// Force `force` at `point` of `link`, no moment.
    pub fn at(link: usize, point: Vector3<f64>, force: Vector3<f64>) -> Self {
        PointForce {
            link,
            point,
            force,
            moment: Vector3::zeros(),
        }
    }

    /// The same force with a world-frame moment besides.
    pub fn with_moment(self, moment: Vector3<f64>) -> Self {
        PointForce { moment, ..self }
    }
}

/// Each force on a link of `model`, finite.
pub(crate) fn check_points(model: &Model, forces: &[PointForce]) -> Result<(), DynamicsError> {
    for (i, f) in forces.iter().enumerate() {
        if f.link >= model.num_links() {
            return Err(DynamicsError::Input(format!(
                "point force {i} acts on link {}, but the model has {} links",
                f.link,
                model.num_links()
            )));
        }
        let all = f.point.iter().chain(&f.force).chain(&f.moment);
        if !all.into_iter().all(|x| x.is_finite()) {
            return Err(DynamicsError::Input(format!(
                "point force {i} (on link `{}`) must be finite",
                model.link(f.link).name
            )));
        }
    }
    Ok(())
}

/// The forces as link-frame wrenches into `ws.pf`, after a velocity pass
/// (which set the links' poses in their parents, `ws.xt`); leaves the links'
/// world poses in `ws.world`.
pub(crate) fn point_wrenches(model: &Model, ws: &mut Workspace, forces: &[PointForce]) {
    world_poses(model, ws);
    link_wrenches(model, ws, forces);
}

/// The forces as link-frame wrenches into `ws.pf`, the world poses already
/// in `ws.world`.
pub(crate) fn link_wrenches(model: &Model, ws: &mut Workspace, forces: &[PointForce]) {
    debug_assert_eq!(ws.pf.len(), model.num_links());
    ws.pf.iter_mut().for_each(|w| *w = Wrench::zeros());
    for pf in forces {
        ws.pf[pf.link] += link_wrench(&ws.world[pf.link], pf);
    }
}

/// World pose of every link from the poses in their parents.
pub(crate) fn world_poses(model: &Model, ws: &mut Workspace) {
    for (i, l) in model.links().iter().enumerate() {
        ws.world[i] = match l.parent {
            Some(p) => ws.world[p].compose(&ws.xt[i]),
            None => ws.xt[i],
        };
    }
}

/// `pf` as a wrench in its link's frame (moment about the link's origin),
/// the link at world pose `pose`.
fn link_wrench(pose: &Se3, pf: &PointForce) -> Wrench {
    let rt = pose.r.transpose();
    let (f, m) = (rt * pf.force, rt * pf.moment);
    let mu = pf.point.cross(&f) + m;
    Wrench::new(mu.x, mu.y, mu.z, f.x, f.y, f.z)
}

/// Adds to `gq` the part of ∂(Σwτ²)/∂q that comes from the forces turning
/// with their links (see the module docs), after the adjoint sweep left the
/// adjoint twists F̄ in `ws.df` and the world poses of [`point_wrenches`]
/// are still in `ws.world`.
pub(crate) fn add_turning_gradient(
    model: &Model,
    ws: &mut Workspace,
    forces: &[PointForce],
    gq: &mut [f64],
) {
    ws.pu.iter_mut().for_each(|u| *u = Vector3::zeros());
    for pf in forces {
        let i = pf.link;
        let rt = ws.world[i].r.transpose();
        let (f, m) = (rt * pf.force, rt * pf.moment);
        let fb = &ws.df[i];
        let (alpha, beta) = (
            fb.fixed_rows::<3>(0).into_owned(),
            fb.fixed_rows::<3>(3).into_owned(),
        );
        ws.pu[i] -= alpha.cross(&pf.point).cross(&f) + alpha.cross(&m) + beta.cross(&f);
    }
    for i in (0..model.num_links()).rev() {
        let l = model.link(i);
        let u = ws.pu[i];
        for k in 0..l.dof {
            gq[l.q_index + k] += ws.kin[i].s[k].fixed_rows::<3>(0).dot(&u);
        }
        if let Some(p) = l.parent {
            let up = ws.xt[i].r * u;
            ws.pu[p] += up;
        }
    }
}
