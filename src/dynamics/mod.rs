//! Multibody dynamics on a [`Model`](crate::model::Model): inverse dynamics
//! (RNEA, Lie-group form of the spline-joint paper eq. 7–16), forward dynamics
//! (the O(n) articulated-body algorithm, paper appendix A), the mass matrix
//! (composite rigid bodies), energies, analytic derivatives of inverse
//! dynamics, and the adjoint gradient of a weighted sum of squared torques.
//!
//! Every algorithm works for any joint of the library: it uses the joint's
//! `S(q)` and, unless `constant_jacobian()`, its Hessian `∂S/∂q`.
//! Buffers live in a [`Workspace`] built once per model: calls allocate nothing.
//!
//! Gravity is an argument (a world-frame vector); models loaded from URDF carry
//! `default_gravity = [0, 0, −9.81]` (Pinocchio's), and `τ = M q̈ + C q̇ + g(q)`
//! with `g(q)` the torque that *holds* the body against gravity.

mod aba;
mod adjoint;
mod axis_turn;
mod coupled;
mod crba;
mod crba_frame;
mod crba_local;
mod derivatives;
mod driven;
mod energy;
mod external;
mod external_jacobian;
mod integrate;
mod rnea;
mod scene;
mod state;
mod state_cache;
mod variation;
mod workspace;

pub use aba::{forward_dynamics, forward_dynamics_ext};
pub use adjoint::{InverseDynamicsPass, torque_sq_gradient, torque_sq_gradient_at_points};
pub use coupled::{coupled_forward_dynamics, coupled_inverse_dynamics, coupled_mass_matrix};
pub use crba::{mass_matrix, mass_matrix_in};
pub use crba_frame::{CrbaFrame, crba_frame_for};
pub use derivatives::rnea_derivatives;
pub use driven::{Driven, driven_accelerations};
pub use energy::{kinetic_energy, potential_energy};
pub use external::PointForce;
pub use external_jacobian::point_forces_jacobian;
pub use integrate::{Integrator, State, Trajectory, simulate};
pub use rnea::{
    inverse_dynamics, inverse_dynamics_at_points, inverse_dynamics_ext, nonlinear_effects,
    root_wrench,
};
pub use scene::{ExternalForce, LimitPenalty, Scene, SceneWorkspace, Spring};
pub use state::{Forces, JointState, StateGradient};
pub use state_cache::{Loaded, StateCache};
pub use workspace::Workspace;

use crate::model::ModelError;

/// Why a dynamics computation failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DynamicsError {
    /// Bad input: wrong lengths, non-finite numbers, a workspace of another model.
    #[error("{0}")]
    Input(String),
    /// The dynamics is singular at this state (e.g. a massless link at the tip).
    #[error("{0}")]
    Singular(String),
    /// The computation was cancelled.
    #[error("cancelled")]
    Cancelled,
    /// The model rejected the input (its checks of lengths and finiteness):
    /// kept whole, so callers see which model error it was.
    #[error(transparent)]
    Model(#[from] ModelError),
}

impl From<crate::cancel::Cancelled> for DynamicsError {
    fn from(_: crate::cancel::Cancelled) -> Self {
        DynamicsError::Cancelled
    }
}

#[cfg(test)]
mod error_tests {
    use super::*;

    #[test]
    fn model_errors_are_kept_whole_with_their_text() {
        let e: DynamicsError = ModelError::Invalid("q has 2 entries".into()).into();
        assert_eq!(
            e,
            DynamicsError::Model(ModelError::Invalid("q has 2 entries".into()))
        );
        assert_eq!(e.to_string(), "q has 2 entries");
    }
}
