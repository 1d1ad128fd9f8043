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

    /// Whether filling `dofs` can move a contact point (or the root): a
    /// group that fills only an arm stands as recorded, the ground's terms
    /// are constant on it, and it is solved without them (a scene pays for
    /// the effects it can change).
    fn moves_contacts(&self, _dofs: &[GapDof]) -> bool {
        true
    }

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
    /// The prior's and the example term's scales where the root is given
    /// (recorded, or Rose's kinematic root): no base term balances the body
    /// there, so the prior and the example hold what the feet do not.
    pub root_given: (f64, f64),
    /// Stance, floor and clearance weights (m⁻² s⁻¹ on the points' errors).
    pub stance: f64,
    pub floor: f64,
    pub clearance: f64,
    /// The feet's friction coefficient (the cones of the forces).
    pub friction: f64,
    /// Where the stances inside a gap come from.
    pub plan: PlanSource,
    /// Whether a group whose root is given (recorded, or Rose's kinematic
    /// root) stands. Not by default: the feet can meet the plan only by
    /// bending the limbs, and on dashes and runs a knee folded 1.3–2.3 rad
    /// away from every pose of the gap's sides where the capture stays
    /// within 0.1 (tests/it/inbetween.rs); `contact:` stated sets it (the
    /// in-betweening bench's root-given rows for what it buys).
    pub stand_root_given: bool,
    /// The stall rule's window (iterations) of a grounded solve (the
    /// solver's own `stall_window` where `None`).
    pub stall_window: Option<u64>,
    /// Whether a close example is followed more than a loose one: the
    /// example and prior scales rise geometrically from theirs at the
    /// acceptance threshold of the mismatch ρ to 1 at ρ = 0 (a perfect
    /// continuation, reproduced): scale^(ρ / ρ_max).
    pub by_mismatch: bool,
}

impl GroundSettings {
    /// The scale `scale` for an example of mismatch `rho` (see
    /// [`GroundSettings::by_mismatch`]); `scale` itself when off or without
    /// an example.
    pub fn scaled_by(&self, scale: f64, rho: Option<f64>) -> f64 {
        match (self.by_mismatch, rho) {
            (true, Some(rho)) if scale > 0.0 => {
                let r = (rho / crate::spacetime::reference::MAX_MISMATCH).clamp(0.0, 1.0);
                scale.powf(r)
            }
            _ => scale,
        }
    }
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

/// The base term's weights, one solve each. The spike raised it 1e5 → 1e6 →
/// 1e7 from Hermite's curves; from the laid example (or the plan's steps)
/// one solve at 1e7 and the re-plan's reach the same (28 locomotion
/// windows, gap 30, natural cut: L2P 0.740× Hermite against 0.742×, the
/// residual +4.2 % BW against +4.1) in 168 evaluations against 207. At 1e8
/// L2P rose from 0.68× to 0.83× Hermite for a residual 1.7 % BW lower
/// (the spike); at 1e9 it passed Hermite.
pub const BASE_SCHEDULE: [f64; 1] = [1e7];

/// Re-plans by default (see `contact/replan.rs` for what one does and the
/// bench for what it buys).
pub const REPLANS: usize = 1;

/// The prior's scale in a grounded solve (the spike: 1e-5 with the self
/// example; at 1e-6 L2P doubled, at 1e-4 skate grew).
pub const GROUNDED_PRIOR_SCALE: f64 = 1e-5;

/// The example term's scale in a grounded solve: as the prior's, so the two
/// keep the proportion the anchored solve gives them.
pub const GROUNDED_EXAMPLE_SCALE: f64 = GROUNDED_PRIOR_SCALE;

/// The prior's and the example term's scale where the root is given. On 28
/// locomotion windows (gap 30) 1e-3 came 0.65× Hermite's L2P against 1.00×
/// at the free root's 1e-5, for the same residual; but with the root held,
/// ground terms on positions leave a limb's twist to the prior, and at 1e-3
/// a bow's knees folded 1.7 rad with the feet planted. On one window of
/// each of the 50 shared clips (gap 30): 1e-3 / 1e-2 / 1e-1 gave L2P 0.654
/// / 0.645 / 0.642× Hermite, L2Q 1.04 / 0.91 / 0.84 (Hermite 1.08, today's
/// SP 0.82), skate 2.4 / 2.8 / 3.9× the capture's, residual +7.8 / +10.3 /
/// +13.3 % BW: 1e-1 keeps the joints' rotations (L2Q, NPSS) for some skate.
pub const ROOT_GIVEN_SCALE: f64 = 1e-1;

/// Weights relative to ∫Στ² weight 1 (m⁻² s⁻¹ on the points' errors). The
/// spike's stance 1e10 brought the worst stance error from 3–5 cm to 1–2 cm.
/// Its floor and clearance 1e9 were too soft against the base term's 1e7
/// once the example is followed: on 28 locomotion windows (gap 30, natural
/// cut) floor 1e12 and clearance 1e10 took the worst depth from 3.0 to
/// 1.15 cm and skate from 2.0× to 1.4× the capture's, for L2P 0.754×
/// Hermite against 0.740× and residual +6.7 % BW against +4.2 (stance
/// 3e10 on top: +3.8 % BW, but skate 1.65× and L2P 0.78×; the bench's
/// ground rows).
pub const STANCE_WEIGHT: f64 = 1e10;
pub const FLOOR_WEIGHT: f64 = 1e12;
pub const CLEARANCE_WEIGHT: f64 = 1e10;

/// The stall rule's window of a grounded solve: 10 iterations reached the
/// same L2P, skate and residual as the solver's 25 in 116 evaluations
/// against 168 (28 locomotion windows, gap 30).
pub const GROUNDED_STALL_WINDOW: u64 = 10;

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
            root_given: (ROOT_GIVEN_SCALE, ROOT_GIVEN_SCALE),
            stance: STANCE_WEIGHT,
            floor: FLOOR_WEIGHT,
            clearance: CLEARANCE_WEIGHT,
            friction: GROUND_FRICTION,
            plan: PlanSource::Auto,
            stand_root_given: false,
            stall_window: Some(GROUNDED_STALL_WINDOW),
            by_mismatch: false,
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
            "plan {} · base {} · re-plans {} · prior ×{:e} · example ×{:e} (root given: ×{:e}, ×{:e}) · stance {:e} · floor {:e} · clearance {:e} · friction {} · stall window {} · root given: {}",
            self.plan.name(),
            base.join(" → "),
            self.replans,
            self.prior_scale,
            self.example,
            self.root_given.0,
            self.root_given.1,
            self.stance,
            self.floor,
            self.clearance,
            self.friction,
            self.stall_window
                .map_or("the solver's".to_string(), |w| w.to_string()),
            if self.stand_root_given {
                "stands"
            } else {
                "kinematic"
            },
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
        assert_eq!(bases(true), vec![1e7, 1e7]);
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
