//! What every group of gaps of one motion shares: the body, the transition's
//! settings, the torque weights, the prior, the motion outside the gaps, the
//! solver's options and the coordinates' names.

use super::ground_model::{GroundModel, GroundSettings};
use super::options::SolveOptions;
use crate::spacetime::error::SpError;
use crate::spacetime::objective::{GapDof, Inputs, Objective, TransitionSettings};
use crate::spacetime::reference::{Example, ExampleChoice};
use crate::spacetime::torque::TorqueModel;

/// Finds the example a group of gaps follows ([`crate::spacetime::reference::find`]).
pub type FindExample<'a> = dyn Fn(&[GapDof]) -> Result<Option<Example>, SpError> + Sync + 'a;

/// Chooses and lays the example a group of gaps follows, saying why none
/// when none ([`crate::spacetime::reference::choose`]).
pub type LayExample<'a> = dyn Fn(&[GapDof]) -> Result<ExampleChoice, SpError> + Sync + 'a;

/// SP's kinematic prior (see `sp::prior_weights`) and what it is held to.
pub struct PriorTerm<'a> {
    /// Per model coordinate, [c_v, c_a].
    pub weights: Vec<[f64; 2]>,
    /// ∫Στ² over [t0, t1] of the whole motion filled by Hermite curves (every
    /// gap DOF, support limbs included): what a transition must undercut.
    pub baseline: &'a (dyn Fn(f64, f64) -> Result<f64, SpError> + Sync),
    /// The stretch of the motion a group's prior follows, if any
    /// ([`crate::spacetime::reference::find`]).
    pub example: &'a FindExample<'a>,
    /// When set, the example is laid in the world and anchors the
    /// transition's poses (`objective::ExampleTerm`) in one solve
    /// (`continuation.rs`); `example` is then not asked.
    pub laid: Option<&'a LayExample<'a>>,
}

impl PriorTerm<'_> {
    /// The weights times `scale` (a step of the continuation).
    pub fn scaled(&self, scale: f64) -> Vec<[f64; 2]> {
        self.weights
            .iter()
            .map(|[v, a]| [v * scale, a * scale])
            .collect()
    }

    /// Whether any weight is on (a prior of zeros is no prior).
    pub fn is_on(&self) -> bool {
        self.weights.iter().flatten().any(|w| *w > 0.0)
    }
}

/// What every group of one motion shares: the body, the transition's
/// settings, the per-coordinate torque weights, the prior, the motion outside
/// the gaps and the solver's options.
pub struct Problem<'a, M: TorqueModel> {
    pub model: &'a M,
    pub settings: &'a TransitionSettings,
    pub weights: &'a [f64],
    pub prior: Option<&'a PriorTerm<'a>>,
    pub inputs: &'a Inputs<'a>,
    pub opts: &'a SolveOptions,
    /// The model's coordinate names, for the reports (empty: unnamed).
    pub names: &'a [String],
    /// The ground the body stands on and the grounded solve's settings
    /// (`group.rs`); `None`: Rose's objective with the prior, anchored on a
    /// laid example or lowered along its continuation.
    pub ground: Option<(&'a dyn GroundModel<M>, &'a GroundSettings)>,
}

impl<M: TorqueModel> Problem<'_, M> {
    /// ∫Σwτ² over the gaps of `dofs` under `settings` (no prior).
    pub fn objective(
        &self,
        dofs: Vec<GapDof>,
        settings: &TransitionSettings,
    ) -> Result<Objective<'_, M>, SpError> {
        Objective::new(
            self.model,
            dofs,
            settings,
            self.weights.to_vec(),
            self.inputs,
        )
    }

    /// The prior, if it has any weight on.
    pub fn active_prior(&self) -> Option<&PriorTerm<'_>> {
        self.prior.filter(|p| p.is_on())
    }
}
