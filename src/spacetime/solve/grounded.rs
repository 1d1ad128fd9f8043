//! One group's grounded solve (issue 35): the body stands on the ground.
//! The objective is ∫Στ² net of the contact forces, the ground's terms (the
//! base's six equations where the root is an unknown, stance, floor,
//! clearance: [`GroundModel::terms`]) and the prior at a fixed low scale.
//! The contact forces are not unknowns: at the start of every solve they
//! are the best ones given the motion so far, node by node
//! ([`GroundModel::forces`]), and held fixed while the solver moves the
//! curves. By the envelope theorem the gradient of min_f ‖W(q) − A(q)ᵀf‖²
//! is the gradient with f at its optimum, so each solve sees the exact
//! gradient at its start, and re-solving the forces between solves lets
//! them follow the motion.
//!
//! The base term's weight rises along a continuation ([`GroundSchedule`]):
//! stiff from the start, it pins the body to the Hermite start's momentum;
//! raised step by step, the limbs first find a motion the feet can carry
//! and the root then follows it (the spike, `grounded_spike/RESULTS.md`:
//! 1e5 → 1e6 → 1e7, one solve each, then one more force re-solve). Unlike
//! the plain continuation ([`super::continuation`]), the prior is not
//! lowered until the transition costs less torque than Hermite: the ground
//! terms, not the effort check, decide how far the motion moves from the
//! prior's.

use super::continuation::{step, step_objective};
use super::problem::Problem;
use super::report::{GapReport, GroupSolution, Outcome, RunStats, Work};
use super::run::run;
use crate::dynamics::{JointState, PointForce};
use crate::spacetime::error::SpError;
use crate::spacetime::objective::{GapDof, GapLayout, Objective, Term};
use crate::spacetime::torque::TorqueModel;
use rayon::prelude::*;

/// The ground as a solve sees it: the contact forces at a node and the
/// terms that hold the body on the ground, over one group's layout. SP's
/// stage builds it from the contact plan (`sp::grounded`).
pub trait GroundModel<M: TorqueModel>: Sync {
    /// The contact forces at node `k` of `layout` in the state `s`: the best
    /// ones inside the friction cones at the points planted then (none where
    /// no point is planted).
    fn forces(
        &self,
        layout: &GapLayout,
        k: usize,
        s: &JointState<'_>,
    ) -> Result<Vec<PointForce>, SpError>;

    /// The ground's terms over `layout` with the contact forces `forces`
    /// (per node, as [`GroundModel::forces`] gave them) and the base term at
    /// weight `base` (left out where it is 0).
    fn terms<'t>(
        &'t self,
        layout: &GapLayout,
        base: f64,
        forces: &[Vec<PointForce>],
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
    fn weights(&self, free_root: bool) -> Vec<f64> {
        let last = self.base.last().copied().unwrap_or(0.0);
        if !free_root || self.base.is_empty() {
            return vec![0.0; 1 + self.resolves];
        }
        let mut w = self.base.clone();
        w.extend(std::iter::repeat_n(last, self.resolves));
        w
    }
}

/// The contact forces at every node of `probe`'s layout for unknowns `x`
/// (nodes in parallel: one small cone problem each).
fn forces_at<M: TorqueModel>(
    probe: &Objective<'_, M>,
    ground: &dyn GroundModel<M>,
    x: &[f64],
) -> Result<Vec<Vec<PointForce>>, SpError> {
    let layout = probe.layout();
    (0..probe.n_nodes())
        .into_par_iter()
        .map(|k| {
            let [q, v, a] = probe.node_state(x, k);
            ground.forces(layout, k, &JointState::new(&q, &v, &a))
        })
        .collect()
}

/// ∫Στ² net of the contact forces at `x` (forces chosen there): what the
/// report calls the group's energy in a grounded solve.
fn net_energy<M: TorqueModel>(
    torque_only: &mut Objective<'_, M>,
    ground: &dyn GroundModel<M>,
    x: &[f64],
) -> Result<f64, SpError> {
    let forces = forces_at(torque_only, ground, x)?;
    torque_only.set_forces(forces)?;
    let mut s = torque_only.scratch();
    torque_only.eval(&mut s, x, None)
}

/// One group of gaps solved standing on the ground (see the module docs),
/// from the Hermite start.
pub(super) fn solve_grounded<M: TorqueModel>(
    problem: &Problem<'_, M>,
    ground: &dyn GroundModel<M>,
    schedule: &GroundSchedule,
    dofs: Vec<GapDof>,
) -> Result<GroupSolution, SpError> {
    let mut torque_only = problem.objective(dofs.clone(), problem.settings)?;
    let free_root = ground.free_root(torque_only.layout());
    let weights = schedule.weights(free_root);
    let prior = problem.active_prior();
    let mut example = match prior {
        Some(p) => (p.example)(&dofs)?,
        None => None,
    };
    let hermite = torque_only.hermite_start();
    let mut x = hermite.clone();
    let mut work = Work::default();
    let mut last: Option<RunStats> = None;
    for (i, &base) in weights.iter().enumerate() {
        step(problem, i, weights.len());
        let forces = forces_at(&torque_only, ground, &x)?;
        let mut obj = match prior {
            Some(p) => step_objective(problem, p, &dofs, schedule.prior_scale, &mut example)?,
            None => problem.objective(dofs.clone(), problem.settings)?,
        };
        for term in ground.terms(obj.layout(), base, &forces)? {
            obj = obj.with_term(term);
        }
        obj.set_forces(forces)?;
        let (x1, stats) = run(&obj, x, problem.opts)?;
        x = x1;
        work.add(&stats);
        last = Some(stats);
    }
    let last = last.ok_or_else(|| SpError::Numerical("a grounded solve ran no step".into()))?;
    let outcome = Outcome {
        initial_energy: net_energy(&mut torque_only, ground, &hermite)?,
        energy: net_energy(&mut torque_only, ground, &x)?,
        prior_scale: schedule.prior_scale,
        example,
    };
    Ok(GroupSolution {
        report: GapReport::new(&dofs, problem.names, last, work, outcome),
        coefficients: torque_only.coefficients(&x),
        curves: torque_only.curves().to_vec(),
        x,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_schedule_raises_the_base_then_re_solves_and_drops_it_for_a_given_root() {
        let s = GroundSchedule::default();
        assert_eq!(s.weights(true), vec![1e5, 1e6, 1e7, 1e7]);
        assert_eq!(s.weights(false), vec![0.0, 0.0]);
        let none = GroundSchedule {
            base: vec![],
            resolves: 0,
            prior_scale: 1.0,
        };
        assert_eq!(none.weights(true), vec![0.0]);
    }
}
