//! What a transition needs from the dynamics: torques and the gradient of a
//! weighted sum of their squares. A small trait so the solver can be tested on
//! a hand-checked model and run on the real multibody engine alike.

use super::error::SpError;

/// A body whose joint torques τ(q, q̇, q̈) the objective ∫Σwᵢτᵢ² dt penalises.
pub trait TorqueModel: Sync {
    /// Scratch memory of one evaluation thread (reused between calls, never shared).
    type Workspace: Send;

    /// Number of coordinates (length of q, q̇, q̈, τ).
    fn nq(&self) -> usize;

    fn workspace(&self) -> Self::Workspace;

    /// τ into `tau`.
    fn torques(
        &self,
        ws: &mut Self::Workspace,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        tau: &mut [f64],
    ) -> Result<(), SpError>;

    /// Σ wᵢτᵢ², with its gradient with respect to q, q̇, q̈ written (not added) into
    /// `gq`, `gv`, `ga`.
    #[allow(clippy::too_many_arguments)]
    fn torque_sq_grad(
        &self,
        ws: &mut Self::Workspace,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        w: &[f64],
        gq: &mut [f64],
        gv: &mut [f64],
        ga: &mut [f64],
    ) -> Result<f64, SpError>;

    /// Σᵢ wᵢ M_{i,c}² for each coordinate c of `coords` (M the mass matrix at q):
    /// how strongly an acceleration of c shows in the objective. Used to scale
    /// the unknowns. The default costs one inverse-dynamics pass per coordinate
    /// (M e_c = τ(q, 0, e_c) − τ(q, 0, 0)).
    fn acceleration_weights(
        &self,
        ws: &mut Self::Workspace,
        q: &[f64],
        w: &[f64],
        coords: &[usize],
    ) -> Result<Vec<f64>, SpError> {
        let n = self.nq();
        let zero = vec![0.0; n];
        let mut t0 = vec![0.0; n];
        let mut t1 = vec![0.0; n];
        self.torques(ws, q, &zero, &zero, &mut t0)?;
        let mut a = zero.clone();
        let mut out = Vec::with_capacity(coords.len());
        for &c in coords {
            a[c] = 1.0;
            self.torques(ws, q, &zero, &a, &mut t1)?;
            a[c] = 0.0;
            out.push((0..n).map(|i| w[i] * (t1[i] - t0[i]).powi(2)).sum());
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
    SpError::Evaluation(format!("dynamics: {e}"))
}

impl TorqueModel for BodyDynamics<'_> {
    type Workspace = crate::dynamics::Workspace;

    fn nq(&self) -> usize {
        self.model.nq()
    }

    fn workspace(&self) -> Self::Workspace {
        crate::dynamics::Workspace::new(self.model)
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
        q: &[f64],
        v: &[f64],
        a: &[f64],
        w: &[f64],
        gq: &mut [f64],
        gv: &mut [f64],
        ga: &mut [f64],
    ) -> Result<f64, SpError> {
        crate::dynamics::torque_sq_gradient(self.model, ws, q, v, a, &self.gravity, w, gq, gv, ga)
            .map_err(dyn_err)
    }
}
