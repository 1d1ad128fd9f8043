//! Dynamics in coupled coordinates (`model::Coupling`, URDF `<mimic>`
//! joints): with q_full = G q + b,
//!   τ = Gᵀ τ_full(G q + b, G v, G a),   M = Gᵀ M_full G,
//! and forward dynamics solves M q̈ = τ − Gᵀ h_full (h at zero acceleration)
//! by Cholesky: O(n³), like driven coordinates, for the small mechanisms
//! (grippers, hands) that have followers. Pinocchio 4.1 computes τ and M the
//! same way and has no ABA for mimic joints.

use crate::dynamics::state::{Forces, JointState};
use crate::dynamics::workspace::Workspace;
use crate::dynamics::{
    DynamicsError, inverse_dynamics, inverse_dynamics_ext, mass_matrix, nonlinear_effects,
};
use crate::model::{Coupling, Model};
use nalgebra::{DMatrix, DVector, Vector3};

fn check(c: &Coupling, model: &Model, what: &[(&str, &[f64])]) -> Result<(), DynamicsError> {
    if c.full_nq() != model.nq() {
        return Err(DynamicsError::Input(format!(
            "the coupling is of a model with {} coordinates, not {}",
            c.full_nq(),
            model.nq()
        )));
    }
    for (name, v) in what {
        if v.len() != c.nq() {
            return Err(DynamicsError::Input(format!(
                "`{name}` has {} numbers but the body has {} independent coordinates",
                v.len(),
                c.nq()
            )));
        }
    }
    Ok(())
}

fn expanded(c: &Coupling, x: &[f64], positions: bool) -> Vec<f64> {
    let mut out = vec![0.0; c.full_nq()];
    if positions {
        c.expand_q(x, &mut out);
    } else {
        c.expand_v(x, &mut out);
    }
    out
}

/// τ on the independent coordinates: Gᵀ τ_full(G q + b, G v, G a).
pub fn coupled_inverse_dynamics(
    model: &Model,
    c: &Coupling,
    ws: &mut Workspace,
    x: &JointState,
    gravity: &Vector3<f64>,
    tau: &mut [f64],
) -> Result<(), DynamicsError> {
    let (q, v, a) = (x.q, x.v, x.a);
    check(c, model, &[("q", q), ("v", v), ("a", a), ("tau", tau)])?;
    let mut full = vec![0.0; model.nq()];
    inverse_dynamics(
        model,
        ws,
        &expanded(c, q, true),
        &expanded(c, v, false),
        &expanded(c, a, false),
        gravity,
        &mut full,
    )?;
    c.reduce(&full, tau);
    Ok(())
}

/// The mass matrix of the independent coordinates: Gᵀ M_full G.
pub fn coupled_mass_matrix(
    model: &Model,
    c: &Coupling,
    ws: &mut Workspace,
    q: &[f64],
) -> Result<DMatrix<f64>, DynamicsError> {
    check(c, model, &[("q", q)])?;
    let n = model.nq();
    let mut full = DMatrix::zeros(n, n);
    mass_matrix(model, ws, &expanded(c, q, true), &mut full)?;
    let mut g = DMatrix::zeros(n, c.nq());
    for (k, &(i, m, _)) in c.map().iter().enumerate() {
        g[(k, i)] = m;
    }
    Ok(g.transpose() * full * g)
}

/// q̈ of the independent coordinates under `forces` (τ on the independent
/// coordinates): M q̈ = τ − Gᵀ h_full, with h_full the full model's inverse
/// dynamics at zero acceleration (external wrenches included).
pub fn coupled_forward_dynamics(
    model: &Model,
    c: &Coupling,
    ws: &mut Workspace,
    q: &[f64],
    v: &[f64],
    forces: &Forces,
    qdd: &mut [f64],
) -> Result<(), DynamicsError> {
    let tau = forces.tau;
    check(c, model, &[("q", q), ("v", v), ("tau", tau), ("qdd", qdd)])?;
    let m = coupled_mass_matrix(model, c, ws, q)?;
    let mut h_full = vec![0.0; model.nq()];
    let (q_full, v_full) = (expanded(c, q, true), expanded(c, v, false));
    match forces.fext {
        None => nonlinear_effects(model, ws, &q_full, &v_full, forces.gravity, &mut h_full)?,
        Some(fext) => {
            let zero = vec![0.0; model.nq()];
            let at_rest = JointState::new(&q_full, &v_full, &zero);
            inverse_dynamics_ext(model, ws, &at_rest, forces.gravity, fext, &mut h_full)?
        }
    }
    let mut h = vec![0.0; c.nq()];
    c.reduce(&h_full, &mut h);
    let rhs = DVector::from_iterator(c.nq(), tau.iter().zip(&h).map(|(t, h)| t - h));
    let chol = m.cholesky().ok_or_else(|| {
        DynamicsError::Singular(
            "the mass matrix of the independent coordinates is not positive definite \
             (a coordinate that moves no mass?)"
                .into(),
        )
    })?;
    qdd.copy_from_slice(chol.solve(&rhs).as_slice());
    Ok(())
}
