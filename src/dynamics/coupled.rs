//! Dynamics in coupled coordinates (`model::Coupling`: URDF `<mimic>`
//! joints, OpenSim CoordinateCouplerConstraints): with q_full = F(q),
//! G = ∂F/∂q and c = q̈_full at q̈ = 0 (f″ q̇², zero for linear followers),
//!   τ = Gᵀ τ_full(F(q), G v, G a + c),   M = Gᵀ M_full G,
//! and forward dynamics solves M q̈ = τ − Gᵀ τ_full(F(q), G v, c) by
//! Cholesky: O(n³), like driven coordinates, for the small mechanisms
//! (grippers, hands, knees) that have followers. Pinocchio 4.1 computes τ and
//! M the same way and has no ABA for mimic joints; Simbody's forward dynamics
//! with the coupler constraint enforced gives the same q̈ (tests/it/opensim_model.rs).

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

/// The model's (q, v, a) at independent (q, v, a).
fn expanded(c: &Coupling, q: &[f64], v: &[f64], a: &[f64]) -> [Vec<f64>; 3] {
    let n = c.full_nq();
    let (mut qf, mut vf, mut af) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    c.expand_q(q, &mut qf);
    c.expand_v(q, v, &mut vf);
    c.expand_a(q, v, a, &mut af);
    [qf, vf, af]
}

/// τ on the independent coordinates: Gᵀ τ_full(F(q), G v, G a + c).
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
    let [qf, vf, af] = expanded(c, q, v, a);
    inverse_dynamics(model, ws, &qf, &vf, &af, gravity, &mut full)?;
    c.reduce(q, &full, tau);
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
    let mut qf = vec![0.0; n];
    c.expand_q(q, &mut qf);
    mass_matrix(model, ws, &qf, &mut full)?;
    let g = c.jacobian(q);
    Ok(g.transpose() * full * g)
}

/// q̈ of the independent coordinates under `forces` (τ on the independent
/// coordinates): M q̈ = τ − Gᵀ h_full, with h_full the full model's inverse
/// dynamics at the acceleration c that q̈ = 0 leaves (external wrenches included).
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
    let zero = vec![0.0; c.nq()];
    let [q_full, v_full, bias] = expanded(c, q, v, &zero);
    match forces.fext {
        None if c.is_linear() => {
            nonlinear_effects(model, ws, &q_full, &v_full, forces.gravity, &mut h_full)?
        }
        None => inverse_dynamics(
            model,
            ws,
            &q_full,
            &v_full,
            &bias,
            forces.gravity,
            &mut h_full,
        )?,
        Some(fext) => {
            let at_rest = JointState::new(&q_full, &v_full, &bias);
            inverse_dynamics_ext(model, ws, &at_rest, forces.gravity, fext, &mut h_full)?
        }
    }
    let mut h = vec![0.0; c.nq()];
    c.reduce(q, &h_full, &mut h);
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
