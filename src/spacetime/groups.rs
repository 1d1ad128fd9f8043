//! Split the gaps of a motion into independent transition problems: gaps of
//! different DOFs that overlap in time are coupled through the dynamics and
//! are solved together; disjoint groups are independent and run in parallel.

use super::error::SpError;
use super::objective::{GapDof, Inputs, Objective, TransitionSettings};
use super::progress::ProgressEvent;
use super::reference::Example;
use super::solve::{GroupSolution, SolveOptions, solve_group, solve_group_from};
use super::torque::TorqueModel;
use rayon::prelude::*;

/// Groups of gaps whose open spans overlap (transitively), ordered by start time.
/// Gaps that only touch at a point are independent.
pub fn group_overlapping(mut gaps: Vec<GapDof>) -> Vec<Vec<GapDof>> {
    gaps.sort_by(|a, b| a.t0.total_cmp(&b.t0).then(a.coord.cmp(&b.coord)));
    let mut groups: Vec<(f64, Vec<GapDof>)> = vec![];
    for g in gaps {
        match groups.last_mut() {
            Some((end, members)) if g.t0 < *end => {
                *end = end.max(g.t1);
                members.push(g);
            }
            _ => groups.push((g.t1, vec![g])),
        }
    }
    groups.into_iter().map(|(_, m)| m).collect()
}

/// Finds the example a group of gaps follows ([`super::reference::find`]).
pub type FindExample<'a> = dyn Fn(&[GapDof]) -> Result<Option<Example>, SpError> + Sync + 'a;

/// SP's kinematic prior (see `sp::prior_weights`) and what it is held to.
pub struct PriorTerm<'a> {
    /// Per model coordinate, [c_v, c_a].
    pub weights: Vec<[f64; 2]>,
    /// ∫Στ² over [t0, t1] of the whole motion filled by Hermite curves (every
    /// gap DOF, support limbs included): what a transition must undercut.
    pub baseline: &'a (dyn Fn(f64, f64) -> Result<f64, SpError> + Sync),
    /// The stretch of the motion a group's prior follows, if any
    /// ([`super::reference::find`]).
    pub example: &'a FindExample<'a>,
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
}

impl<M: TorqueModel> Problem<'_, M> {
    fn objective(
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
}

/// Solve every group (in parallel); results in the order of [`group_overlapping`].
pub fn solve_all<M: TorqueModel>(
    problem: &Problem<'_, M>,
    gaps: Vec<GapDof>,
) -> Result<Vec<GroupSolution>, SpError> {
    let groups = group_overlapping(gaps);
    let progress = &problem.opts.progress;
    progress.report(ProgressEvent::Groups(groups.len()));
    groups
        .into_par_iter()
        .map(|dofs| {
            let solution = solve_with_prior(problem, dofs);
            progress.report(ProgressEvent::GroupDone);
            solution
        })
        .collect()
}

/// The scales of the prior's weights tried in turn, until the transition
/// undercuts Hermite's ∫Στ²: as asked, then tenfold lower, down to 1e-4.
/// Between 1 and 1e-2 the solution barely moves (the prior decides it; on the
/// shared clips, one window per clip, root given, ∫Στ² changed by < 0.1 %);
/// 1e-3 is where the torque term starts to pay. Each step lower costs
/// closeness to the capture (the schedule run to 1e-4 wherever needed: SP
/// cheaper than Hermite in 49/50/48 windows at 15/30/45 frames, but L2P
/// ×Hermite 0.96/0.92/0.71 against 0.97/0.87/0.66 for the old schedule that
/// stopped at 1e-2 and was cheaper in only 41/33/33), which
/// [`nearest_cheaper`] recovers: the step that first
/// undercuts Hermite is taken only as far as it must go (with it: cheaper in
/// 50/50/50/49 windows at 5/15/30/45 frames, L2P ×Hermite 0.96/0.96/0.88/
/// 0.67). Below 1e-4 the
/// torque term takes over and pulls limbs toward low-gravity poses far from
/// what a person does (Rose's objective alone left SP 3–5 % farther from the
/// capture than Hermite at 5 and 15 frames, with a bow's neck and feet
/// 0.5 rad outside anything either side does). A window that stays above
/// Hermite's ∫Στ² is reported as such (`GapReport::energy` against
/// `initial_energy`).
/// (Dropping only the velocity term first, which leaves ∫(s q̈)² whose
/// minimiser is the Hermite curve, came 10 % less close to the capture at
/// 45-frame gaps.)
const PRIOR_SCHEDULE: [f64; 5] = [1.0, 1e-1, 1e-2, 1e-3, 1e-4];

/// How much less torque than the Hermite curves a transition with a prior
/// must cost (a fraction of Hermite's ∫Στ², measured by [`CHECK_SAMPLES`]).
/// 1 %, not less: [`nearest_cheaper`] lands just under the target, and
/// `torque_energy` of the written motion (its own quadrature, on the curves
/// as sampled) differs from this check by up to 0.6 %; with 0.2 %, 13 of 200
/// windows came out above Hermite by that measure, with 1 % one.
const EFFORT_MARGIN: f64 = 0.01;

/// The effort check integrates ∫Στ² with this many times the solve's Gauss
/// points: a solve that lowers the prior far enough to chase torque can
/// hide torque between its own nodes (aliasing), and the check must not be
/// fooled by that.
const CHECK_SAMPLES: usize = 4;

/// Bisection steps of [`nearest_cheaper`]: the fraction of the last step is
/// found to 2⁻⁸ of its length.
const BISECTION_STEPS: usize = 8;

/// One group: minimise ∫Στ² + prior; while the result costs more torque than
/// the Hermite curves (∫Στ² alone under a finer rule, by [`EFFORT_MARGIN`]),
/// weaken the prior by the next step of [`PRIOR_SCHEDULE`] and solve again
/// from there, down to the schedule's last step. The step that first
/// undercuts Hermite is taken only as far as it must go
/// ([`nearest_cheaper`]). So SP returns the transition nearest the prior's
/// motion along this continuation that costs less effort than
/// interpolation, or the last step's. The report's energies are ∫Στ² alone.
/// With an example (the motion's own repeat, [`super::reference`]) the prior
/// follows it; if even the last step cannot undercut Hermite with it, the
/// plain prior's continuation decides instead.
fn solve_with_prior<M: TorqueModel>(
    problem: &Problem<'_, M>,
    dofs: Vec<GapDof>,
) -> Result<GroupSolution, SpError> {
    let prior = problem
        .prior
        .filter(|p| p.weights.iter().flatten().any(|w| *w > 0.0));
    let Some(prior) = prior else {
        return solve_group(&problem.objective(dofs, problem.settings)?, problem.opts);
    };
    let example = (prior.example)(&dofs)?;
    let had_example = example.is_some();
    let first = continuation(problem, prior, &dofs, example)?;
    if !had_example || first.undercut {
        return Ok(first.solution);
    }
    // The example could not be made cheaper than Hermite (a short gap whose
    // example moves faster than its ends): the plain prior, which always
    // starts at Hermite's effort, then decides; the work of both is reported.
    let mut plain = continuation(problem, prior, &dofs, None)?;
    let (r, f) = (&mut plain.solution.report, &first.solution.report);
    r.iterations += f.iterations;
    r.evaluations += f.evaluations;
    r.seconds += f.seconds;
    r.solves += f.solves;
    Ok(plain.solution)
}

/// The result of one run down [`PRIOR_SCHEDULE`].
struct Continued {
    solution: GroupSolution,
    /// Whether it costs less ∫Στ² than Hermite by [`EFFORT_MARGIN`].
    undercut: bool,
}

/// [`solve_with_prior`]'s continuation with the prior following `example`
/// (or the plain prior).
fn continuation<M: TorqueModel>(
    problem: &Problem<'_, M>,
    prior: &PriorTerm<'_>,
    dofs: &[GapDof],
    mut example: Option<Example>,
) -> Result<Continued, SpError> {
    let (settings, opts) = (problem.settings, problem.opts);
    let fine = TransitionSettings {
        samples: settings.samples * CHECK_SAMPLES,
        ..settings.clone()
    };
    let torque_only = problem.objective(dofs.to_vec(), &fine)?;
    let mut scratch = torque_only.scratch();
    let hermite = torque_only.hermite_start();
    let t0 = dofs.iter().map(|d| d.t0).fold(f64::INFINITY, f64::min);
    let t1 = dofs.iter().map(|d| d.t1).fold(f64::NEG_INFINITY, f64::max);
    let hermite_energy = (prior.baseline)(t0, t1)?;
    let mut step = 0;
    let mut x = hermite.clone();
    let (mut iterations, mut evaluations, mut seconds, mut solves) = (0, 0, 0.0, 0);
    loop {
        let scale = PRIOR_SCHEDULE[step];
        let scaled: Vec<[f64; 2]> = prior
            .weights
            .iter()
            .map(|[v, a]| [v * scale, a * scale])
            .collect();
        let mut obj = problem
            .objective(dofs.to_vec(), settings)?
            .with_prior(&scaled)?;
        let follows = match example.as_ref().map(|ex| (ex, &ex.clip)) {
            None => true,
            Some((ex, None)) => {
                obj.with_example(problem.inputs, ex.shift, &ex.follow, ex.trust())?
            }
            // a library stretch: its own motion, already on the gap's clock
            Some((ex, Some(clip))) => {
                obj.with_example(&clip.inputs(), 0.0, &ex.follow, ex.trust())?
            }
        };
        if !follows {
            example = None;
        }
        let above = x.clone();
        let mut sol = solve_group_from(&obj, x, opts)?;
        let mut energy = torque_only.eval(&mut scratch, &sol.x, None)?;
        iterations += sol.report.iterations;
        evaluations += sol.report.evaluations;
        seconds += sol.report.seconds;
        solves += 1;
        let target = (1.0 - EFFORT_MARGIN) * hermite_energy;
        let undercut = energy <= target;
        if undercut || step + 1 == PRIOR_SCHEDULE.len() {
            if step > 0 && undercut {
                let (x, e, n) = nearest_cheaper(&above, &sol.x, energy, target, |x| {
                    torque_only.eval(&mut scratch, x, None)
                })?;
                sol.coefficients = obj.coefficients(&x);
                sol.x = x;
                energy = e;
                evaluations += n as u64;
            }
            let r = &mut sol.report;
            r.iterations = iterations;
            r.evaluations = evaluations;
            r.seconds = seconds;
            r.solves = solves;
            r.prior_scale = scale;
            r.energy = energy;
            r.example = example.clone();
            // under the same rule as `energy`, with any support limbs as held
            r.initial_energy = torque_only.eval(&mut scratch, &hermite, None)?;
            return Ok(Continued {
                solution: sol,
                undercut,
            });
        }
        x = sol.x;
        step += 1;
    }
}

/// The point of the segment from `above` (the previous step's transition,
/// whose ∫Στ² exceeds `target`) to `below` (this step's, `e_below` ≤
/// `target`) nearest `above` that still costs at most `target`, by
/// bisection on the fraction (∫Στ² is smooth along the segment; both ends
/// are transitions with the same fixed end states, so every point is one).
/// Returns it, its ∫Στ² and the evaluations spent.
fn nearest_cheaper(
    above: &[f64],
    below: &[f64],
    e_below: f64,
    target: f64,
    mut energy: impl FnMut(&[f64]) -> Result<f64, SpError>,
) -> Result<(Vec<f64>, f64, usize), SpError> {
    let at = |s: f64| -> Vec<f64> {
        above
            .iter()
            .zip(below)
            .map(|(a, b)| a + s * (b - a))
            .collect()
    };
    let (mut lo, mut hi, mut best) = (0.0, 1.0, (below.to_vec(), e_below));
    for _ in 0..BISECTION_STEPS {
        let mid = 0.5 * (lo + hi);
        let x = at(mid);
        let e = energy(&x)?;
        if e <= target {
            hi = mid;
            best = (x, e);
        } else {
            lo = mid;
        }
    }
    Ok((best.0, best.1, BISECTION_STEPS))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spacetime::planar2::TwoLinkArm;
    use crate::spacetime::transition::EndState;

    fn gap(coord: usize, t0: f64, t1: f64) -> GapDof {
        GapDof {
            coord,
            t0,
            t1,
            start: EndState::default(),
            end: EndState {
                q: 1.0,
                v: 0.0,
                a: 0.0,
            },
        }
    }

    #[test]
    fn overlapping_gaps_group_and_touching_ones_do_not() {
        let g = group_overlapping(vec![
            gap(1, 2.0, 3.0),
            gap(0, 0.0, 1.0),
            gap(1, 0.5, 1.5),
            gap(0, 1.5, 2.0),
        ]);
        let spans: Vec<Vec<(usize, f64)>> = g
            .iter()
            .map(|m| m.iter().map(|d| (d.coord, d.t0)).collect())
            .collect();
        assert_eq!(
            spans,
            vec![vec![(0, 0.0), (1, 0.5)], vec![(0, 1.5)], vec![(1, 2.0)]]
        );
    }

    #[test]
    fn disjoint_groups_solve_independently_and_equal_solo_solves() {
        let arm = TwoLinkArm::default();
        let inputs = |t: f64, q: &mut [f64], v: &mut [f64], a: &mut [f64]| {
            q[0] = t;
            v[0] = 1.0;
            a[0] = 0.0;
            q[1] = 0.3;
            v[1] = 0.0;
            a[1] = 0.0;
            Ok(())
        };
        let s = TransitionSettings::default();
        let o = SolveOptions::default();
        let problem = Problem {
            model: &arm,
            settings: &s,
            weights: &[1.0, 1.0],
            prior: None,
            inputs: &inputs,
            opts: &o,
        };
        let all = solve_all(&problem, vec![gap(1, 0.0, 0.5), gap(1, 2.0, 2.7)]).unwrap();
        assert_eq!(all.len(), 2);
        let solo = solve_all(&problem, vec![gap(1, 2.0, 2.7)]).unwrap();
        assert_eq!(all[1].report.energy, solo[0].report.energy);
        assert!(
            all.iter()
                .all(|g| g.report.energy <= g.report.initial_energy)
        );
    }

    #[test]
    fn nearest_cheaper_stops_where_the_segment_crosses_the_target() {
        // e(x) = x₀² + x₁² along (2, 0) → (0, 0): crosses e = 1 at x₀ = 1
        let e = |x: &[f64]| Ok(x[0] * x[0] + x[1] * x[1]);
        let (x, ex, n) = nearest_cheaper(&[2.0, 0.0], &[0.0, 0.0], 0.0, 1.0, e).unwrap();
        assert!(ex <= 1.0, "{ex}");
        assert!((x[0] - 1.0).abs() <= 2.0 / 256.0 + 1e-12, "{x:?}");
        assert_eq!(n, BISECTION_STEPS);
        // a segment cheap from its first bisection point on keeps the nearest found
        let (x, _, _) = nearest_cheaper(&[1.5, 0.0], &[0.0, 0.0], 0.0, 4.0, e).unwrap();
        assert!(x[0] >= 1.5 * (1.0 - 2.0 / 256.0), "{x:?}");
    }

    #[test]
    fn input_errors_propagate() {
        let arm = TwoLinkArm::default();
        let inputs = |t: f64, _: &mut [f64], _: &mut [f64], _: &mut [f64]| {
            Err(SpError::Evaluation(format!("undefined at {t}")))
        };
        let problem = Problem {
            model: &arm,
            settings: &TransitionSettings::default(),
            weights: &[1.0; 2],
            prior: None,
            inputs: &inputs,
            opts: &SolveOptions::default(),
        };
        let r = solve_all(&problem, vec![gap(1, 0.0, 0.5)]);
        assert!(matches!(r, Err(SpError::Evaluation(_))));
    }
}
