//! Stage 4, the transitions (Rose §3.2.3): the gap DOFs no earlier stage
//! filled, solved as spacetime transitions (overlapping gaps together,
//! disjoint ones in parallel, see [`crate::spacetime::solve`]) under ∫Στ²
//! and the kinematic prior, and their curves written back.

use super::checks::motion_err;
use super::energy::{joint_weights, torque_energy};
use super::filling::Filling;
use super::grounded::SpGround;
use super::offsets::is_translation;
use super::options::SpOptions;
use super::prior_weights::prior_weights;
use crate::ground::FloorPlane;
use crate::motion::Mu;
use crate::spacetime::error::SpError;
use crate::spacetime::objective::{GapDof, Inputs};
use crate::spacetime::reference::{self, Example, ExampleChoice};
use crate::spacetime::solve::GroundModel;
use crate::spacetime::solve::{GroupSolution, LayExample, PriorTerm, Problem, solve_all};
use crate::spacetime::torque::BodyDynamics;

/// Solves `gaps` and writes their curves into the motion, one report entry
/// per group. `hermite_all` is the motion with every gap filled by Hermite
/// curves: the effort each transition must undercut.
pub(super) fn solve_transitions(
    f: &mut Filling<'_>,
    opts: &SpOptions,
    hermite_all: &Mu,
    gaps: Vec<GapDof>,
    standing: Option<FloorPlane>,
) -> Result<(), SpError> {
    let (model, gravity, names) = (f.model, f.gravity, f.names);
    let weights = joint_weights(model, &f.root);
    let baseline = |t0: f64, t1: f64| -> Result<f64, SpError> {
        let piece = crate::motion::clip_in_place(t0, t1, hermite_all).map_err(motion_err)?;
        torque_energy(&piece, model, Some(gravity))
    };
    let rotation = |c: usize| !is_translation(model, c);
    let solutions = {
        let motion = &f.motion;
        let example = |group: &[GapDof]| -> Result<Option<Example>, SpError> {
            reference::choose_for(
                model,
                motion,
                names,
                &rotation,
                group,
                opts.prior.example,
                opts.library.as_ref(),
            )
        };
        let joints = reference::Joints::of_model(model, names);
        let up = crate::ground::up_of(&gravity);
        let lay = reference::Lay {
            model,
            names,
            up,
            root: &f.root,
            motion,
            rotation: &rotation,
            joints: &joints,
        };
        let laid = |group: &[GapDof]| -> Result<ExampleChoice, SpError> {
            reference::choose(&lay, group, opts.prior.example, opts.library.as_ref())
        };
        let prior = PriorTerm {
            weights: prior_weights(model, motion, &gaps, &opts.prior)?,
            baseline: &baseline,
            example: &example,
            laid: opts.prior.anchor.then_some(&laid as &LayExample),
        };
        let body = BodyDynamics { model, gravity };
        let root = f.root.clone();
        let settings = &opts.ground;
        let ground = match standing {
            Some(floor) => Some(SpGround::new(
                &body,
                (floor, &root),
                &opts.contact,
                f.sampler(),
                settings,
            )?),
            None => None,
        };
        // the objective's inputs: every body coordinate at t, NaN where undefined
        let sampler = f.sampler();
        let inputs_fn = |t: f64, q: &mut [f64], v: &mut [f64], a: &mut [f64]| {
            sampler.state(t, q, v, a).map_err(motion_err).map(|_| ())
        };
        let inputs: &Inputs = &inputs_fn;
        let problem = Problem {
            model: &body,
            settings: &opts.settings,
            weights: &weights,
            prior: Some(&prior),
            inputs,
            opts: &opts.solve,
            names,
            ground: ground
                .as_ref()
                .map(|g| (g as &dyn GroundModel<BodyDynamics<'_>>, settings)),
        };
        solve_all(&problem, gaps)?
    };
    for sol in solutions {
        write_back(f, sol)?;
    }
    if standing.is_some() {
        f.report.ground = Some(opts.ground.clone());
    }
    Ok(())
}

/// Writes one group's curves into the motion (the objective's order is the
/// report's order), adds its report and, when it stood, its plan.
fn write_back(f: &mut Filling<'_>, sol: GroupSolution) -> Result<(), SpError> {
    let GroupSolution {
        report,
        written,
        curves,
        plan,
        ..
    } = sol;
    let names = f.names;
    for ((&c, curve), gap) in report.coords.iter().zip(written).zip(&curves) {
        f.write(&names[c], curve, gap.t0(), gap.t1())?;
    }
    f.report.groups.push(report);
    if let (Some(plan), Some(contacts)) = (plan, f.contacts.as_mut()) {
        f.report.unplanned.extend(super::report::unplanned(&plan));
        contacts.gaps.push(plan);
    }
    Ok(())
}
