//! What a transition needs from the dynamics: torques and the gradient of a
//! weighted sum of their squares. A small trait so the solver can be tested on
//! a hand-checked model and run on the real multibody engine alike.

use super::error::SpError;
use crate::dynamics::{JointState, StateGradient};

/// A body whose joint torques τ(q, q̇, q̈) the objective ∫Σwᵢτᵢ² dt penalises.
pub trait TorqueModel: Sync {
    /// Scratch memory of one evaluation thread (reused between calls, never shared).
    type Workspace: Send;

    /// Number of coordinates (length of q, q̇, q̈, τ).
    fn nq(&self) -> usize;

    fn workspace(&self) -> Self::Workspace;

    /// The name of coordinate i, for messages.
    fn coordinate_name(&self, i: usize) -> String {
        format!("coordinate {i}")
    }

    /// τ into `tau`.
    fn torques(
        &self,
        ws: &mut Self::Workspace,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        tau: &mut [f64],
    ) -> Result<(), SpError>;

    /// Σ wᵢτᵢ² at `x`, with its gradient with respect to q, q̇, q̈ written (not
    /// added) into `grad`.
    fn torque_sq_grad(
        &self,
        ws: &mut Self::Workspace,
        x: &JointState,
        w: &[f64],
        grad: StateGradient,
    ) -> Result<f64, SpError>;

    /// ∂τ/∂q_c, ∂τ/∂q̇_c, ∂τ/∂q̈_c for the coordinates c of `coords` (each
    /// nq × coords.len()), used to build the solver's preconditioner. The
    /// default takes central differences of [`TorqueModel::torques`]
    /// (6 passes per coordinate; exact for q̈, where τ is linear) — precise
    /// enough for a preconditioner, which only shapes the steps.
    fn torque_jacobians(
        &self,
        ws: &mut Self::Workspace,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        coords: &[usize],
    ) -> Result<[nalgebra::DMatrix<f64>; 3], SpError> {
        let n = self.nq();
        let mut out = [
            nalgebra::DMatrix::zeros(n, coords.len()),
            nalgebra::DMatrix::zeros(n, coords.len()),
            nalgebra::DMatrix::zeros(n, coords.len()),
        ];
        let mut x = [q.to_vec(), v.to_vec(), a.to_vec()];
        let (mut tp, mut tm) = (vec![0.0; n], vec![0.0; n]);
        for (j, &c) in coords.iter().enumerate() {
            for (k, m) in out.iter_mut().enumerate() {
                let x0 = x[k][c];
                let h = 1e-6 * (1.0 + x0.abs());
                x[k][c] = x0 + h;
                self.torques(ws, &x[0], &x[1], &x[2], &mut tp)?;
                x[k][c] = x0 - h;
                self.torques(ws, &x[0], &x[1], &x[2], &mut tm)?;
                x[k][c] = x0;
                for i in 0..n {
                    m[(i, j)] = (tp[i] - tm[i]) / (2.0 * h);
                }
            }
        }
        Ok(out)
    }
}

/// The multibody engine as a [`TorqueModel`]: RNEA for τ, its adjoint for the
/// gradient of Σwτ² (O(n) per sample).
#[derive(Clone, Debug)]
pub struct BodyDynamics<'m> {
    pub model: &'m crate::model::Model,
    pub gravity: nalgebra::Vector3<f64>,
}

impl<'m> BodyDynamics<'m> {
    /// The body under its model's default gravity.
    pub fn new(model: &'m crate::model::Model) -> Self {
        BodyDynamics {
            model,
            gravity: model.default_gravity,
        }
    }
}

fn dyn_err(e: crate::dynamics::DynamicsError) -> SpError {
    SpError::Dynamics(e)
}

impl TorqueModel for BodyDynamics<'_> {
    type Workspace = crate::dynamics::Workspace;

    fn nq(&self) -> usize {
        self.model.nq()
    }

    fn workspace(&self) -> Self::Workspace {
        crate::dynamics::Workspace::new(self.model)
    }

    fn coordinate_name(&self, i: usize) -> String {
        self.model
            .coordinate_names()
            .get(i)
            .cloned()
            .unwrap_or_else(|| format!("coordinate {i}"))
    }

    fn torques(
        &self,
        ws: &mut Self::Workspace,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        tau: &mut [f64],
    ) -> Result<(), SpError> {
        crate::dynamics::inverse_dynamics(self.model, ws, q, v, a, &self.gravity, tau)
            .map_err(dyn_err)
    }

    fn torque_sq_grad(
        &self,
        ws: &mut Self::Workspace,
        x: &JointState,
        w: &[f64],
        grad: StateGradient,
    ) -> Result<f64, SpError> {
        crate::dynamics::torque_sq_gradient(self.model, ws, x, &self.gravity, w, grad)
            .map_err(dyn_err)
    }

    /// Exact: the analytic RNEA derivatives and the mass matrix (CRBA).
    fn torque_jacobians(
        &self,
        ws: &mut Self::Workspace,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        coords: &[usize],
    ) -> Result<[nalgebra::DMatrix<f64>; 3], SpError> {
        let n = self.model.nq();
        let mut dq = nalgebra::DMatrix::zeros(n, n);
        let mut dv = nalgebra::DMatrix::zeros(n, n);
        let mut m = nalgebra::DMatrix::zeros(n, n);
        crate::dynamics::rnea_derivatives(
            self.model,
            ws,
            &JointState::new(q, v, a),
            &self.gravity,
            &mut dq,
            &mut dv,
        )
        .map_err(dyn_err)?;
        crate::dynamics::mass_matrix(self.model, ws, q, &mut m).map_err(dyn_err)?;
        Ok([
            dq.select_columns(coords),
            dv.select_columns(coords),
            m.select_columns(coords),
        ])
    }
}
