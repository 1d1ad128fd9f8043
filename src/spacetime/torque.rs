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
}
