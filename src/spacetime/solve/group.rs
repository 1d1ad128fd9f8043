//! One group of gaps from start to finish (issue 42): the one owner of a
//! group's solve. In order:
//! 1. choose and lay the example (the motion's own repeat or a library
//!    stretch, [`crate::spacetime::reference`]);
//! 2. plan the contacts (when the body stands: [`GroundModel::plan`], from
//!    the gap's edges, `contact:` and the laid example's own stances);
//! 3. build the terms: torque, the prior (following the laid example), the
//!    example term, and the ground's (base, stance, floor, clearance);
//! 4. solve, the base term raised along [`GroundSettings::base`];
//! 5. re-plan from the result ([`GroundModel::replan`]);
//! 6. solve again.
//!
//! With an example the unknowns are a correction to it
//! ([`GapLayout::with_bases`]): the solve starts on the laid example, and
//! an example that needs no correction is reproduced by construction,
//! whatever the number of coefficients. Without a ground, steps 2, 5 and 6
//! are skipped (the anchored solve); with neither a ground nor an example,
//! the prior's continuation decides (`continuation.rs`).

use super::continuation::{EffortCheck, step, unanchored};
use super::ground_model::{GroundModel, GroundSettings};
use super::problem::{PriorTerm, Problem};
use super::report::{GapReport, GroupSolution, Outcome, RunStats, Work};
use super::run::run;
use crate::motion::Curve;
use crate::spacetime::contact::GapPlan;
use crate::spacetime::error::SpError;
use crate::spacetime::objective::{
    ExampleTerm, GapDof, GapLayout, Inputs, Objective, position_weight,
};
use crate::spacetime::reference::{ExampleChoice, LaidExample};
use crate::spacetime::torque::TorqueModel;
use std::sync::Arc;

/// One group of gaps solved (see the module docs).
pub(super) fn solve_group<M: TorqueModel>(
    problem: &Problem<'_, M>,
    dofs: Vec<GapDof>,
) -> Result<GroupSolution, SpError> {
    let prior = problem.active_prior();
    let choice = match prior.and_then(|p| p.laid) {
        Some(lay) => lay(&dofs)?,
        None => ExampleChoice::default(),
    };
    if let Some((ground, settings)) = problem.ground
        && ground.moves_contacts(&dofs)
        && (settings.stand_root_given
            || ground.free_root(&Following::of(&choice).layout(problem, &dofs)?))
    {
        return grounded(problem, ground, settings, dofs, choice);
    }
    if let (Some(p), Some(laid)) = (prior, &choice.laid)
        && let Some(done) = anchored(problem, p, &dofs, laid)?
    {
        return Ok(done.with_tried(choice.tried));
    }
    let asked = prior.is_some_and(|p| p.laid.is_some());
    unanchored(problem, dofs, asked.then_some(choice.tried))
}

/// What the owner builds an objective from: the group's layout on the laid
/// example (if any) and the example's inputs and weights.
struct Following<'l> {
    laid: Option<&'l LaidExample>,
}

impl<'l> Following<'l> {
    fn of(choice: &'l ExampleChoice) -> Self {
        Following {
            laid: choice.laid.as_ref(),
        }
    }

    /// Per gap DOF, its laid curve (if it follows).
    fn bases(&self, dofs: &[GapDof]) -> Vec<Option<Arc<Curve>>> {
        dofs.iter()
            .map(|d| self.laid.and_then(|l| l.curve(d.coord).cloned()))
            .collect()
    }

    /// The layout of `dofs`, each following DOF a correction to its laid curve.
    fn layout<M: TorqueModel>(
        &self,
        problem: &Problem<'_, M>,
        dofs: &[GapDof],
    ) -> Result<GapLayout, SpError> {
        GapLayout::with_bases(dofs.to_vec(), problem.settings, self.bases(dofs))
    }

    /// ∫Στ² and the prior at `prior_scale` over `layout`, the prior
    /// following the laid example, and the example term at `example_scale`
    /// of its weight (none without an example, or at scale 0).
    fn objective<'p, M: TorqueModel>(
        &self,
        problem: &'p Problem<'_, M>,
        prior: Option<&PriorTerm<'_>>,
        layout: GapLayout,
        (prior_scale, example_scale): (f64, f64),
    ) -> Result<Objective<'p, M>, SpError> {
        let mut obj = Objective::on_layout(
            problem.model,
            layout,
            problem.weights.to_vec(),
            problem.inputs,
        )?;
        let Some(prior) = prior else {
            return Ok(obj);
        };
        obj = obj.with_prior(&prior.scaled(prior_scale))?;
        let Some(laid) = self.laid else {
            return Ok(obj);
        };
        let inputs_fn = laid.inputs();
        let example: &Inputs = &inputs_fn;
        let follow: Vec<usize> = laid.coords().collect();
        let trust = laid.example.trust();
        if !obj.with_example(example, 0.0, &follow, trust)? {
            return Err(SpError::Numerical(
                "the laid example is undefined at a node of its own gap".into(),
            ));
        }
        if example_scale > 0.0 {
            let mut per_coord = vec![0.0; prior.weights.len()];
            for g in obj.dofs().iter().filter(|g| follow.contains(&g.coord)) {
                let c_a = prior.weights.get(g.coord).map_or(0.0, |w| w[1]);
                per_coord[g.coord] = example_scale * position_weight(c_a, g.t1 - g.t0, trust);
            }
            let term = ExampleTerm::new(obj.layout(), per_coord.len(), example, &per_coord)?;
            obj = obj.with_term(Box::new(term));
        }
        Ok(obj)
    }
}

/// With an example laid in the world (issues 36 and 42) and no ground: one
/// solve of ∫Στ², the prior at its full weight following the laid example's
/// q̇, q̈, and the example term pulling the poses to it, from the laid
/// example itself (the unknowns correct it). No effort check and no
/// lowering: a person's motion usually costs more ∫Στ² than Hermite's
/// curves, and lowering the prior until it does not traded the example away
/// for that; ∫Στ² is only the regulariser that breaks ties. `None` when the
/// prior cannot follow it (its derivatives undefined at a node).
fn anchored<M: TorqueModel>(
    problem: &Problem<'_, M>,
    prior: &PriorTerm<'_>,
    dofs: &[GapDof],
    laid: &LaidExample,
) -> Result<Option<GroupSolution>, SpError> {
    let following = Following { laid: Some(laid) };
    let mut plain = EffortCheck::new(problem, prior, dofs, None)?;
    let mut based = EffortCheck::new(problem, prior, dofs, Some(following.bases(dofs)))?;
    let layout = following.layout(problem, dofs)?;
    let obj = match following.objective(problem, Some(prior), layout, (1.0, 1.0)) {
        Ok(obj) => obj,
        Err(SpError::Numerical(_)) => return Ok(None),
        Err(e) => return Err(e),
    };
    step(problem, 0, 1);
    let (x, last) = run(&obj, obj.layout().base_start(), problem.opts)?;
    let mut work = Work::default();
    work.add(&last);
    let outcome = Outcome {
        initial_energy: plain.energy(&plain.hermite.clone())?,
        energy: based.energy(&x)?,
        prior_scale: 1.0,
        example: Some(laid.example.clone()),
        tried: vec![],
    };
    let report = GapReport::new(obj.dofs(), problem.names, last, work, outcome);
    GroupSolution::of(&obj, x, report, None).map(Some)
}

/// ∫Στ² net of the contact forces at `x` (forces chosen there on `plan`):
/// what the report calls the group's energy in a grounded solve.
fn net_energy<M: TorqueModel>(
    torque_only: &mut Objective<'_, M>,
    ground: &dyn GroundModel<M>,
    plan: &GapPlan,
    x: &[f64],
) -> Result<f64, SpError> {
    ground.set_forces(plan, torque_only, x)?;
    let mut s = torque_only.scratch();
    torque_only.eval(&mut s, x, None)
}

/// The body stands on the ground (issues 35 and 42): the plan from the
/// edges and the laid example, the ground's terms on it, the base term
/// raised step by step with the forces re-chosen before each solve and held
/// through it (envelope theorem), then re-planned from the result and
/// solved again.
fn grounded<M: TorqueModel>(
    problem: &Problem<'_, M>,
    ground: &dyn GroundModel<M>,
    settings: &GroundSettings,
    dofs: Vec<GapDof>,
    choice: ExampleChoice,
) -> Result<GroupSolution, SpError> {
    let prior = problem.active_prior();
    let following = Following::of(&choice);
    let layout = following.layout(problem, &dofs)?;
    let hermite = layout.hermite_start();
    let mut x = layout.base_start();
    let mut plan = ground.plan(&dofs, &layout, &x, following.laid)?;
    let free_root = ground.free_root(&layout);
    let rho = choice.laid.as_ref().map(|l| l.example.mismatch);
    let scales = match free_root {
        true => (settings.prior_scale, settings.example),
        false => settings.root_given,
    };
    let scales = (
        settings.scaled_by(scales.0, rho),
        settings.scaled_by(scales.1, rho),
    );
    let steps = settings.steps(free_root);
    let mut opts = problem.opts.clone();
    if let Some(w) = settings.stall_window {
        opts.stall_window = w;
    }
    let mut work = Work::default();
    let mut last: Option<(RunStats, Objective<'_, M>)> = None;
    for (i, s) in steps.iter().enumerate() {
        step(problem, i, steps.len());
        if s.replan
            && let Some((_, obj)) = &last
        {
            plan = ground.replan(&plan, obj, &x)?;
        }
        let mut obj = following.objective(problem, prior, layout.clone(), scales)?;
        for term in ground.terms(&plan, obj.layout(), s.base)? {
            obj = obj.with_term(term);
        }
        ground.set_forces(&plan, &mut obj, &x)?;
        let (x1, stats) = run(&obj, x, &opts)?;
        x = x1;
        work.add(&stats);
        last = Some((stats, obj));
    }
    let (last, obj) =
        last.ok_or_else(|| SpError::Numerical("a grounded solve ran no step".into()))?;
    ground.score(&mut plan, obj.layout(), &x)?;
    let mut torque_only = Objective::on_layout(
        problem.model,
        layout,
        problem.weights.to_vec(),
        problem.inputs,
    )?;
    let outcome = Outcome {
        initial_energy: net_energy(&mut torque_only, ground, &plan, &hermite)?,
        energy: net_energy(&mut torque_only, ground, &plan, &x)?,
        prior_scale: scales.0,
        example: choice.laid.as_ref().map(|l| l.example.clone()),
        tried: choice.tried,
    };
    let report = GapReport::new(&dofs, problem.names, last, work, outcome);
    GroupSolution::of(&obj, x, report, Some(plan))
}
#[cfg(test)]
mod tests {
    use super::*;
    use crate::spacetime::contact::GapPlan;
    use crate::spacetime::objective::{GapLayout, Objective, Term};
    use crate::spacetime::objective::{Node, NodeSum, TransitionSettings};
    use crate::spacetime::planar2::TwoLinkArm;
    use crate::spacetime::reference::LaidExample;
    use crate::spacetime::solve::GroundModel;
    use crate::spacetime::solve::{SolveOptions, solve_all};
    use crate::spacetime::transition::EndState;
    use std::sync::Mutex;

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
        replans: Mutex<usize>,
    }

    impl GroundModel<TwoLinkArm> for Recording {
        fn plan(
            &self,
            dofs: &[GapDof],
            _: &GapLayout,
            _: &[f64],
            _: Option<&LaidExample>,
        ) -> Result<GapPlan, SpError> {
            Ok(GapPlan {
                t0: dofs[0].t0,
                t1: dofs[0].t1,
                points: vec![],
            })
        }

        fn replan(
            &self,
            plan: &GapPlan,
            _: &Objective<'_, TwoLinkArm>,
            _: &[f64],
        ) -> Result<GapPlan, SpError> {
            *self.replans.lock().unwrap() += 1;
            Ok(plan.clone())
        }

        fn set_forces(
            &self,
            _: &GapPlan,
            obj: &mut Objective<'_, TwoLinkArm>,
            _: &[f64],
        ) -> Result<(), SpError> {
            *self.force_calls.lock().unwrap() += 1;
            obj.set_forces(vec![])
        }

        fn score(&self, _: &mut GapPlan, _: &GapLayout, _: &[f64]) -> Result<(), SpError> {
            Ok(())
        }

        fn terms<'t>(
            &'t self,
            _: &GapPlan,
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

    fn solve_on(ground: &Recording, schedule: &GroundSettings) -> GroupSolution {
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
        let schedule = GroundSettings {
            base: vec![1e-2, 1e-1, 1.0],
            replans: 1,
            prior_scale: 1.0,
            ..GroundSettings::default()
        };
        let ground = Recording {
            target: 1.0,
            free: true,
            bases: Mutex::new(vec![]),
            force_calls: Mutex::new(0),
            replans: Mutex::new(0),
        };
        let g = solve_on(&ground, &schedule);
        assert_eq!(*ground.bases.lock().unwrap(), vec![1e-2, 1e-1, 1.0, 1.0]);
        assert_eq!(g.report.solves, 4);
        // re-planned once, before the last solve
        assert_eq!(*ground.replans.lock().unwrap(), 1);
        // forces chosen before each of the 4 solves, and twice for the
        // report's energies (Hermite start and solution)
        assert_eq!(*ground.force_calls.lock().unwrap(), 6);
        assert!(g.plan.is_some());
        // the ground's term moved the elbow off Hermite's (constant 0.3) toward 1
        let mid = g.x.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        assert!(mid > 0.3, "coefficients {:?}", g.x);
        assert!(g.report.energy.is_finite());
    }

    #[test]
    fn with_the_root_given_the_base_is_off() {
        let ground = || Recording {
            target: 1.0,
            free: false,
            bases: Mutex::new(vec![]),
            force_calls: Mutex::new(0),
            replans: Mutex::new(0),
        };
        // by default a given root does not stand: no ground solve at all
        let kinematic = ground();
        solve_on(&kinematic, &GroundSettings::default());
        assert!(kinematic.bases.lock().unwrap().is_empty());
        assert_eq!(*kinematic.force_calls.lock().unwrap(), 0);
        let ground = ground();
        let standing = GroundSettings {
            stand_root_given: true,
            ..GroundSettings::default()
        };
        let g = solve_on(&ground, &standing);
        assert_eq!(*ground.bases.lock().unwrap(), vec![0.0, 0.0]);
        // nothing pulls: the torque-optimal elbow, not the target
        assert!(g.x.iter().all(|&c| c < 1.0), "coefficients {:?}", g.x);
    }
}
