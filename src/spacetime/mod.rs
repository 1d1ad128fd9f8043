//! Spacetime transitions (Rose et al. 1996, §3): fill the interior gaps of a
//! motion with cubic B-spline curves that minimise ∫Σwτ² dt, keep support
//! limbs planted by IK, and move the root kinematically (cyclification is `motion::cyclify`).
//!
//! Layering: this module uses `spline`, `model`, `dynamics`, `motion`, and
//! `ground` for floor, "up", contact points, stance and the moving root; it
//! knows nothing of the language.

pub mod basis;
pub mod error;
pub mod hermite;
pub mod quadrature;
pub mod transition;

pub use error::{Need, SpError};
pub use transition::{Continuity, EndState, TransitionCurve};
/// A hand-checked two-link arm: a fixture of the unit tests and the report.
#[cfg(any(test, feature = "report"))]
pub mod planar2;
pub mod torque;
pub use torque::{BodyDynamics, TorqueModel};
pub mod objective;
pub use objective::{GapDof, Objective, TransitionSettings};
pub mod solve;
pub use solve::{
    GapReport, GroupSolution, Problem, SolveOptions, StopReason, group_overlapping, solve_all,
    solve_group, solve_group_from,
};
pub mod root_path;
pub use root_path::RootTransition;
/// The Fig. 8 case shared by the report and `benches/spacetime.rs`.
#[cfg(feature = "report")]
pub mod fig8;
pub mod precond;
pub mod progress;
pub mod reference;
pub use progress::{Progress, ProgressEvent, Tally};
pub mod contact;
pub mod hold;
pub mod sp;
pub use contact::{Contact, ContactPlan, GapPlan, PointPlan, Source, Stance};
pub use hold::HeldFrame;
pub use sp::{
    Filling, PinnedRoot, Prior, RootFill, SpOptions, SpReport, Support, fill_hermite, sp,
    torque_energy,
};
