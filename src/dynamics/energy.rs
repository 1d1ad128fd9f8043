//! Kinetic and potential energy.

use crate::dynamics::DynamicsError;
use crate::dynamics::workspace::{Workspace, velocity_pass};
use crate::model::Model;
use nalgebra::Vector3;

/// `½ q̇ᵀ M(q) q̇ = ½ Σ V_iᵀ G_i V_i`.
pub fn kinetic_energy(
    model: &Model,
    ws: &mut Workspace,
    q: &[f64],
    v: &[f64],
) -> Result<f64, DynamicsError> {
    ws.check(model)?;
    model.check_vec("q", q, model.nq())?;
    model.check_vec("v", v, model.nq())?;
    velocity_pass(model, ws, q, v, false);
    Ok(model
        .links()
        .iter()
        .enumerate()
        .map(|(i, l)| 0.5 * ws.v[i].dot(&l.inertia.mul_twist(&ws.v[i])))
        .sum())
}

/// `−Σ m_i g · c_i` with `c_i` the world position of each centre of mass
/// (zero at the world origin).
pub fn potential_energy(
    model: &Model,
    ws: &mut Workspace,
    q: &[f64],
    gravity: &Vector3<f64>,
) -> Result<f64, DynamicsError> {
    ws.check(model)?;
    let mut world = std::mem::take(&mut ws.world);
    let r = model.forward_kinematics(q, &mut world);
    let e = r.map(|_| {
        model
            .links()
            .iter()
            .enumerate()
            .map(|(i, l)| -gravity.dot(&(world[i].r * l.inertia.h + world[i].p * l.inertia.mass)))
            .sum()
    });
    ws.world = world;
    Ok(e?)
}
