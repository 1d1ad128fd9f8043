//! One group's grounded solve (issue 35): the body stands on the ground.
//! The objective is ∫Στ² net of the contact forces, the ground's terms (the
//! base's six equations where the root is an unknown, stance, floor,
//! clearance: [`GroundModel::terms`]) and the prior at a fixed low scale.
//! The contact forces are not unknowns: at the start of every solve they
//! are the best ones given the motion so far, node by node
//! ([`GroundModel::set_forces`]), and held fixed while the solver moves the
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
use super::ground_model::{GroundModel, GroundSchedule};
use super::problem::Problem;
use super::report::{GapReport, GroupSolution, Outcome, RunStats, Work};
use super::run::run;
use crate::spacetime::error::SpError;
use crate::spacetime::objective::{GapDof, Objective};
use crate::spacetime::torque::TorqueModel;

/// ∫Στ² net of the contact forces at `x` (forces chosen there): what the
/// report calls the group's energy in a grounded solve.
fn net_energy<M: TorqueModel>(
    torque_only: &mut Objective<'_, M>,
    ground: &dyn GroundModel<M>,
    x: &[f64],
) -> Result<f64, SpError> {
    ground.set_forces(torque_only, x)?;
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
        let mut obj = match prior {
            Some(p) => step_objective(problem, p, &dofs, schedule.prior_scale, &mut example)?,
            None => problem.objective(dofs.clone(), problem.settings)?,
        };
        for term in ground.terms(obj.layout(), base)? {
            obj = obj.with_term(term);
        }
        // forces chosen at this solve's start, held through it (envelope)
        ground.set_forces(&mut obj, &x)?;
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
        // the grounded solve follows the example through the prior only; the
        // laid example's choice (and its reasons) is the anchored solve's
        tried: Vec::new(),
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
    use crate::spacetime::objective::{GapLayout, Term};
    use crate::spacetime::objective::{Node, NodeSum, TransitionSettings};
    use crate::spacetime::planar2::TwoLinkArm;
    use crate::spacetime::solve::{SolveOptions, solve_all};
    use crate::spacetime::transition::EndState;
    use std::sync::Mutex;

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

    /// w (q₁ − target)²: a stand-in for the base term, its weight the
    /// schedule's.
    struct Toward {
        target: f64,
        weight: f64,
    }

    impl Term<TwoLinkArm> for Toward {
        fn name(&self) -> &str {
            "toward"
        }

        fn node(
            &self,
            node: &mut Node<'_, TwoLinkArm>,
            sum: &mut NodeSum<'_>,
        ) -> Result<(), SpError> {
            let r = node.q[1] - self.target;
            sum.add(self.weight * r * r);
            if let Some(g) = sum.gradient() {
                g.q[1] += 2.0 * self.weight * r;
            }
            Ok(())
        }
    }

    /// A ground that plants nothing (no forces) and pulls the elbow toward
    /// `target` with the base weight, recording every call.
    struct Recording {
        target: f64,
        free: bool,
        bases: Mutex<Vec<f64>>,
        force_calls: Mutex<usize>,
    }

    impl GroundModel<TwoLinkArm> for Recording {
        fn set_forces(
            &self,
            obj: &mut Objective<'_, TwoLinkArm>,
            _: &[f64],
        ) -> Result<(), SpError> {
            *self.force_calls.lock().unwrap() += 1;
            obj.set_forces(vec![])
        }

        fn terms<'t>(
            &'t self,
            _: &GapLayout,
            base: f64,
        ) -> Result<Vec<Box<dyn Term<TwoLinkArm> + 't>>, SpError> {
            self.bases.lock().unwrap().push(base);
            Ok(if base > 0.0 {
                vec![Box::new(Toward {
                    target: self.target,
                    weight: base,
                })]
            } else {
                vec![]
            })
        }

        fn free_root(&self, _: &GapLayout) -> bool {
            self.free
        }
    }

    fn solve_on(ground: &Recording, schedule: &GroundSchedule) -> GroupSolution {
        let arm = TwoLinkArm::default();
        let inputs = |t: f64, q: &mut [f64], v: &mut [f64], a: &mut [f64]| {
            (q[0], v[0], a[0]) = (t, 1.0, 0.0);
            (q[1], v[1], a[1]) = (0.3, 0.0, 0.0);
            Ok(())
        };
        let (s, o) = (TransitionSettings::default(), SolveOptions::default());
        let problem = Problem {
            model: &arm,
            settings: &s,
            weights: &[1.0, 1.0],
            prior: None,
            inputs: &inputs,
            opts: &o,
            names: &[],
            ground: Some((ground, schedule)),
        };
        let gap = GapDof {
            coord: 1,
            t0: 0.0,
            t1: 0.6,
            start: EndState {
                q: 0.3,
                v: 0.0,
                a: 0.0,
            },
            end: EndState {
                q: 0.3,
                v: 0.0,
                a: 0.0,
            },
        };
        solve_all(&problem, vec![gap]).unwrap().remove(0)
    }

    #[test]
    fn each_solve_sees_its_base_weight_and_forces_chosen_at_its_start() {
        let schedule = GroundSchedule {
            base: vec![1e-2, 1e-1, 1.0],
            resolves: 1,
            prior_scale: 1.0,
        };
        let ground = Recording {
            target: 1.0,
            free: true,
            bases: Mutex::new(vec![]),
            force_calls: Mutex::new(0),
        };
        let g = solve_on(&ground, &schedule);
        assert_eq!(*ground.bases.lock().unwrap(), vec![1e-2, 1e-1, 1.0, 1.0]);
        assert_eq!(g.report.solves, 4);
        // forces chosen before each of the 4 solves, and twice for the
        // report's energies (Hermite start and solution)
        assert_eq!(*ground.force_calls.lock().unwrap(), 6);
        // the ground's term moved the elbow off Hermite's (constant 0.3) toward 1
        let mid = g.x.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        assert!(mid > 0.3, "coefficients {:?}", g.x);
        assert!(g.report.energy.is_finite());
    }

    #[test]
    fn with_the_root_given_the_base_is_off() {
        let ground = Recording {
            target: 1.0,
            free: false,
            bases: Mutex::new(vec![]),
            force_calls: Mutex::new(0),
        };
        let g = solve_on(&ground, &GroundSchedule::default());
        assert_eq!(*ground.bases.lock().unwrap(), vec![0.0, 0.0]);
        // nothing pulls: the torque-optimal elbow, not the target
        assert!(g.x.iter().all(|&c| c < 1.0), "coefficients {:?}", g.x);
    }
}
