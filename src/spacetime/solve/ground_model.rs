//! What a grounded solve is given (issue 35): the ground over one group's
//! objective ([`GroundModel`]) and the continuation it runs
//! ([`GroundSchedule`]). A leaf of `solve`, so the problem every group shares
//! can name it without importing the solve that uses it (`grounded.rs`).

use crate::spacetime::error::SpError;
use crate::spacetime::objective::{GapLayout, Objective, Term};
use crate::spacetime::torque::TorqueModel;

/// The ground as a solve sees it, over one group's objective: the contact
/// forces it chooses for the unknowns so far, and the terms that hold the
/// body on the ground. SP's stage builds it from the contact plan
/// (`grounded-terms`' `ContactForces`, `BaseTerm`, stance/floor/clearance).
pub trait GroundModel<M: TorqueModel>: Sync {
    /// Chooses the contact forces at every node of `obj` for unknowns `x`
    /// (the best ones inside the friction cones at the points planted there)
    /// and hands them to `obj` (`Objective::set_forces`: the torque term and
    /// every ground term read them).
    fn set_forces(&self, obj: &mut Objective<'_, M>, x: &[f64]) -> Result<(), SpError>;

    /// The ground's terms over `layout`, the base term at weight `base`
    /// (left out where it is 0).
    fn terms<'t>(
        &'t self,
        layout: &GapLayout,
        base: f64,
    ) -> Result<Vec<Box<dyn Term<M> + 't>>, SpError>;

    /// Whether the base term acts on this layout: the root is one of its
    /// unknowns. With the root given (a gap that leaves it recorded, or
    /// Rose's kinematic root) the base's equations cannot be met by moving
    /// the root, only by bending the limbs, which the spike measured to
    /// hurt (L2P 1.0–1.3× Hermite, a dash blowing up to 692 % BW).
    fn free_root(&self, layout: &GapLayout) -> bool;
}

/// The grounded solve's continuation.
#[derive(Clone, Debug, PartialEq)]
pub struct GroundSchedule {
    /// The base term's weights, one solve each, forces re-solved before each.
    pub base: Vec<f64>,
    /// Solves after the last base weight, each after a force re-solve.
    pub resolves: usize,
    /// The prior's weights are scaled by this (the spike: 1e-5 with the
    /// self example; at 1e-6 L2P doubled, at 1e-4 skate grew).
    pub prior_scale: f64,
}

/// The spike's base weights (relative to ∫Στ² weight 1, on
/// ∫(F/mg)² + ∫(μ/(mgL))²): 1e5 → 1e6 → 1e7. At 1e8 L2P rose from 0.68× to
/// 0.83× Hermite for a residual 1.7 % BW lower; at 1e9 it passed Hermite.
pub const BASE_SCHEDULE: [f64; 3] = [1e5, 1e6, 1e7];

/// Force re-solves after the schedule's last step (the spike's one).
pub const FORCE_RESOLVES: usize = 1;

/// The prior's scale in a grounded solve (see [`GroundSchedule::prior_scale`]).
pub const GROUNDED_PRIOR_SCALE: f64 = 1e-5;

impl Default for GroundSchedule {
    fn default() -> Self {
        GroundSchedule {
            base: BASE_SCHEDULE.to_vec(),
            resolves: FORCE_RESOLVES,
            prior_scale: GROUNDED_PRIOR_SCALE,
        }
    }
}

impl GroundSchedule {
    /// The base weight of every solve: the schedule, then its last weight
    /// once per re-solve; with the root given, the base is off and the
    /// continuation collapses to one solve and the re-solves.
    pub(super) fn weights(&self, free_root: bool) -> Vec<f64> {
        let last = self.base.last().copied().unwrap_or(0.0);
        if !free_root || self.base.is_empty() {
            return vec![0.0; 1 + self.resolves];
        }
        let mut w = self.base.clone();
        w.extend(std::iter::repeat_n(last, self.resolves));
        w
    }
}
