//! What a grounded solve is given (issues 35 and 42): the ground over one
//! group's objective ([`GroundModel`]: its contact plan, made and re-made,
//! the forces and the terms that hold the body on the ground) and the one
//! value of its settings ([`GroundSettings`]: the schedule, the weights, the
//! friction and the clearance). A leaf of `solve`, so the problem every
//! group shares can name it without importing the solve that uses it
//! (`group.rs`).

use crate::spacetime::contact::GapPlan;
use crate::spacetime::error::SpError;
use crate::spacetime::objective::{GapDof, GapLayout, Objective, Term};
use crate::spacetime::reference::LaidExample;
use crate::spacetime::torque::TorqueModel;

/// The ground as a group's solve sees it. SP's stage implements it over
/// the motion being filled (`sp/grounded.rs`); the solve (`group.rs`) asks
/// for a plan, builds the terms on it, chooses the forces, solves, re-plans
/// from the result and solves again.
pub trait GroundModel<M: TorqueModel>: Sync {
    /// The group's contact plan for the motion `layout` and unknowns `x`
    /// describe at the solve's start (the laid example, or Hermite's
    /// curves): the gap's edges, the stances `contact:` gives, and inside
    /// the gap the example's own stances (`laid`) or the step planner's.
    fn plan(
        &self,
        dofs: &[GapDof],
        layout: &GapLayout,
        x: &[f64],
        laid: Option<&LaidExample>,
    ) -> Result<GapPlan, SpError>;

    /// `plan` re-estimated from the motion a solve made (`layout` at `x`,
    /// with the forces `obj` holds): see `contact/replan.rs`.
    fn replan(&self, plan: &GapPlan, obj: &Objective<'_, M>, x: &[f64])
    -> Result<GapPlan, SpError>;

    /// Chooses the contact forces at every node of `obj` for unknowns `x`
    /// (the best ones inside the friction cones at the points `plan` plants
    /// there) and hands them to `obj` (`Objective::set_forces`: the torque
    /// term and every ground term read them).
    fn set_forces(
        &self,
        plan: &GapPlan,
        obj: &mut Objective<'_, M>,
        x: &[f64],
    ) -> Result<(), SpError>;

    /// The ground's terms on `plan` over `layout`, the base term at weight
    /// `base` (left out where it is 0).
    fn terms<'t>(
        &'t self,
        plan: &GapPlan,
        layout: &GapLayout,
        base: f64,
    ) -> Result<Vec<Box<dyn Term<M> + 't>>, SpError>;

    /// Whether the base term acts on this layout: the root is one of its
    /// unknowns. With the root given (a gap that leaves it recorded, or
    /// Rose's kinematic root) the base's equations cannot be met by moving
    /// the root, only by bending the limbs, which the spike measured to
    /// hurt (L2P 1.0–1.3× Hermite, a dash blowing up to 692 % BW).
    fn free_root(&self, layout: &GapLayout) -> bool;

    /// Sets each stance's `solved`: the largest distance of the solved
    /// point (`layout` at `x`) from where the stance holds it.
    fn score(&self, plan: &mut GapPlan, layout: &GapLayout, x: &[f64]) -> Result<(), SpError>;
}

/// Everything a grounded solve is set by, in one value: `:help SP` lists it
/// and `sp_report` prints it.
#[derive(Clone, Debug, PartialEq)]
pub struct GroundSettings {
    /// The base term's weights, one solve each, forces re-solved before each
    /// (relative to ∫Στ² weight 1, on ∫(F/mg)² + ∫(μ/(mgL))²).
    pub base: Vec<f64>,
    /// Re-plans after the base schedule, each followed by one solve at the
    /// last base weight (`replan:`).
    pub replans: usize,
    /// The prior's weights are scaled by this.
    pub prior_scale: f64,
    /// The example term's weight (`objective::position_weight`) is scaled
    /// by this (0: off; the prior alone follows the example).
    pub example: f64,
    /// Stance, floor and clearance weights (m⁻² s⁻¹ on the points' errors).
    pub stance: f64,
    pub floor: f64,
    pub clearance: f64,
    /// The feet's friction coefficient (the cones of the forces).
    pub friction: f64,
    /// Where the stances inside a gap come from.
    pub plan: PlanSource,
}

/// Where a gap's stances inside it come from (its edges and `contact:`'s
/// stances always take precedence).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PlanSource {
    /// The example's own stances where one is laid, else the step planner's.
    #[default]
    Auto,
    /// The edges alone (issue 35's plan: a stance wholly inside a gap is
    /// never planned).
    Context,
    /// The example's own stances (none without an example).
    Example,
    /// The step planner's, example or not.
    Steps,
}

impl PlanSource {
    /// The name the bench and the report use.
    pub fn name(self) -> &'static str {
        match self {
            PlanSource::Auto => "auto",
            PlanSource::Context => "context",
            PlanSource::Example => "example",
            PlanSource::Steps => "steps",
        }
    }
}

/// The spike's base weights: 1e5 → 1e6 → 1e7. At 1e8 L2P rose from 0.68×
/// to 0.83× Hermite for a residual 1.7 % BW lower; at 1e9 it passed Hermite.
pub const BASE_SCHEDULE: [f64; 3] = [1e5, 1e6, 1e7];

/// Re-plans by default (see `contact/replan.rs` for what one does and the
/// bench for what it buys).
pub const REPLANS: usize = 1;

/// The prior's scale in a grounded solve (the spike: 1e-5 with the self
/// example; at 1e-6 L2P doubled, at 1e-4 skate grew).
pub const GROUNDED_PRIOR_SCALE: f64 = 1e-5;

/// The example term's scale in a grounded solve: as the prior's, so the two
/// keep the proportion the anchored solve gives them.
pub const GROUNDED_EXAMPLE_SCALE: f64 = GROUNDED_PRIOR_SCALE;

/// The spike's weights relative to ∫Στ² weight 1 (m⁻² s⁻¹ on the points'
/// errors): stance 1e10 brought the worst stance error from 3–5 cm to
/// 1–2 cm; floor and clearance 1e9.
pub const STANCE_WEIGHT: f64 = 1e10;
pub const FLOOR_WEIGHT: f64 = 1e9;
pub const CLEARANCE_WEIGHT: f64 = 1e9;

/// The friction coefficient of the feet's cones (the in-betweening
/// report's, shoe on floor).
pub const GROUND_FRICTION: f64 = 0.8;

impl Default for GroundSettings {
    fn default() -> Self {
        GroundSettings {
            base: BASE_SCHEDULE.to_vec(),
            replans: REPLANS,
            prior_scale: GROUNDED_PRIOR_SCALE,
            example: GROUNDED_EXAMPLE_SCALE,
            stance: STANCE_WEIGHT,
            floor: FLOOR_WEIGHT,
            clearance: CLEARANCE_WEIGHT,
            friction: GROUND_FRICTION,
            plan: PlanSource::Auto,
        }
    }
}

/// One solve of a grounded schedule.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GroundStep {
    /// The base term's weight (0: off).
    pub base: f64,
    /// Whether the plan is re-made from the result so far before it.
    pub replan: bool,
}

impl GroundSettings {
    /// Every solve in order: the base schedule, then one solve at its last
    /// weight after each re-plan; with the root given, the base is off and
    /// the schedule is one solve and the re-plans.
    pub fn steps(&self, free_root: bool) -> Vec<GroundStep> {
        let base = |w: f64| if free_root { w } else { 0.0 };
        let mut out: Vec<GroundStep> = if free_root && !self.base.is_empty() {
            self.base
                .iter()
                .map(|&w| GroundStep {
                    base: w,
                    replan: false,
                })
                .collect()
        } else {
            vec![GroundStep {
                base: 0.0,
                replan: false,
            }]
        };
        let last = self.base.last().copied().unwrap_or(0.0);
        out.extend((0..self.replans).map(|_| GroundStep {
            base: base(last),
            replan: true,
        }));
        out
    }

    /// The settings as text, for `sp_report`.
    pub fn describe(&self) -> String {
        let base: Vec<String> = self.base.iter().map(|w| format!("{w:e}")).collect();
        format!(
            "plan {} · base {} · re-plans {} · prior ×{:e} · example ×{:e} · stance {:e} · floor {:e} · clearance {:e} · friction {}",
            self.plan.name(),
            base.join(" → "),
            self.replans,
            self.prior_scale,
            self.example,
            self.stance,
            self.floor,
            self.clearance,
            self.friction
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_schedule_raises_the_base_then_re_plans_and_drops_it_for_a_given_root() {
        let s = GroundSettings::default();
        let bases = |free| s.steps(free).iter().map(|s| s.base).collect::<Vec<_>>();
        assert_eq!(bases(true), vec![1e5, 1e6, 1e7, 1e7]);
        assert_eq!(bases(false), vec![0.0, 0.0]);
        let replans = s.steps(true).iter().filter(|s| s.replan).count();
        assert_eq!(replans, REPLANS);
        let none = GroundSettings {
            base: vec![],
            replans: 0,
            ..GroundSettings::default()
        };
        assert_eq!(none.steps(true).len(), 1);
        assert_eq!(none.steps(true)[0].base, 0.0);
    }
}
