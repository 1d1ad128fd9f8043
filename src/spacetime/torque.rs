//! What a transition needs from the dynamics: torques and the gradient of a
//! weighted sum of their squares. A small trait so the solver can be tested on
//! a hand-checked model and run on the real multibody engine alike.
//!
//! Every method takes the world forces at link points acting besides the
//! joints (`ext`, contact forces; empty for none): τ = ID(q, q̇, q̈) − Σ J_cᵀ f_c,
//! the forces held fixed in the world when differentiating. With a free root
//! the root's rows of τ are then the wrench the contacts leave unbalanced.

use super::error::SpError;
use crate::dynamics::{JointState, PointForce, StateGradient};

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

    /// The multibody body this model is, if it is one: the objective's
    /// terms then share its kinematic and inverse-dynamics passes at each
    /// node (`objective::Node::tau` and the like) instead of each asking
    /// the model. None by default (a hand-checked model: the objective
    /// uses [`TorqueModel::torque_sq_grad`]).
    fn multibody(&self) -> Option<&BodyDynamics<'_>> {
        None
    }

    /// τ into `tau`, with the forces `ext` acting.
    fn torques(
        &self,
        ws: &mut Self::Workspace,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        ext: &[PointForce],
        tau: &mut [f64],
    ) -> Result<(), SpError>;

    /// Σ wᵢτᵢ² at `x` with the forces `ext` acting, with its gradient with
    /// respect to q, q̇, q̈ (the forces held fixed) written (not added) into `grad`.
    fn torque_sq_grad(
        &self,
        ws: &mut Self::Workspace,
        x: &JointState,
        ext: &[PointForce],
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
        x: &JointState,
        ext: &[PointForce],
        coords: &[usize],
    ) -> Result<[nalgebra::DMatrix<f64>; 3], SpError> {
        let (q, v, a) = (x.q, x.v, x.a);
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
                self.torques(ws, &x[0], &x[1], &x[2], ext, &mut tp)?;
                x[k][c] = x0 - h;
                self.torques(ws, &x[0], &x[1], &x[2], ext, &mut tm)?;
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

    fn multibody(&self) -> Option<&BodyDynamics<'_>> {
        Some(self)
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
        ext: &[PointForce],
        tau: &mut [f64],
    ) -> Result<(), SpError> {
        let x = JointState::new(q, v, a);
        crate::dynamics::inverse_dynamics_at_points(self.model, ws, &x, &self.gravity, ext, tau)
            .map_err(dyn_err)
    }

    fn torque_sq_grad(
        &self,
        ws: &mut Self::Workspace,
        x: &JointState,
        ext: &[PointForce],
        w: &[f64],
        grad: StateGradient,
    ) -> Result<f64, SpError> {
        crate::dynamics::torque_sq_gradient_at_points(
            self.model,
            ws,
            x,
            &self.gravity,
            w,
            ext,
            grad,
        )
        .map_err(dyn_err)
    }

    /// The analytic RNEA derivatives and the mass matrix (CRBA), exact; with
    /// forces, ∂(−Σ J_cᵀ f_c)/∂q beside them, exact too
    /// ([`crate::dynamics::point_forces_jacobian`]).
    fn torque_jacobians(
        &self,
        ws: &mut Self::Workspace,
        x: &JointState,
        ext: &[PointForce],
        coords: &[usize],
    ) -> Result<[nalgebra::DMatrix<f64>; 3], SpError> {
        let (q, v, a) = (x.q, x.v, x.a);
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
        let mut dq = dq.select_columns(coords);
        if !ext.is_empty() {
            let mut df = nalgebra::DMatrix::zeros(n, coords.len());
            crate::dynamics::point_forces_jacobian(self.model, ws, q, ext, coords, &mut df)
                .map_err(dyn_err)?;
            dq += df;
        }
        Ok([dq, dv.select_columns(coords), m.select_columns(coords)])
    }
}
