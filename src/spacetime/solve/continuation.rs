//! One group's continuation without a laid example (see [`unanchored`]):
//! the prior lowered step by step until the transition costs less torque
//! than the Hermite curves, the crossing step taken only as far as it must
//! go; and the effort check every solve that reports ∫Στ² shares.

use super::problem::{PriorTerm, Problem};
use super::report::{GapReport, GroupSolution, Outcome, RunStats, Work};
use super::run::run;
use crate::motion::Curve;
use crate::spacetime::error::SpError;
use crate::spacetime::objective::{GapDof, GapLayout, Objective, Scratch, TransitionSettings};
use crate::spacetime::progress::ProgressEvent;
use crate::spacetime::reference::{Example, Tried};
use crate::spacetime::torque::TorqueModel;
use crate::spacetime::transition::TransitionCurve;
use std::sync::Arc;

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

/// One group without a laid example to anchor on: minimise ∫Στ² + prior;
/// while the result costs more torque than the Hermite curves (∫Στ² alone
/// under a finer rule, by [`EFFORT_MARGIN`]), weaken the prior by the next
/// step of [`PRIOR_SCHEDULE`] and solve again from there, down to the
/// schedule's last step. The step that first undercuts Hermite is taken only
/// as far as it must go ([`nearest_cheaper`]). So SP returns the transition
/// nearest the prior's motion along this continuation that costs less effort
/// than interpolation, or the last step's. The report's energies are ∫Στ²
/// alone. Without `Prior::anchor` the prior follows the motion's own repeat
/// ([`super::super::reference::find`]); if even the last step cannot
/// undercut Hermite with it, the plain prior's continuation decides instead.
/// `tried`: the example sources the owner asked and why none was laid
/// (`None`: it asked none).
pub(super) fn unanchored<M: TorqueModel>(
    problem: &Problem<'_, M>,
    dofs: Vec<GapDof>,
    tried: Option<Vec<Tried>>,
) -> Result<GroupSolution, SpError> {
    let Some(prior) = problem.active_prior() else {
        step(problem, 0, 1);
        let obj = problem.objective(dofs, problem.settings)?;
        let (x, stats) = run(&obj, obj.hermite_start(), problem.opts)?;
        let report = GapReport::of_run(obj.dofs(), problem.names, stats);
        return GroupSolution::of(&obj, x, report, None);
    };
    if let Some(tried) = tried {
        // the owner asked for a laid example and none could be laid
        let plain = continuation(problem, prior, &dofs, None)?;
        return plain.tried(tried).solution(problem.names, Work::default());
    }
    let example = (prior.example)(&dofs)?;
    let had_example = example.is_some();
    let first = continuation(problem, prior, &dofs, example)?;
    if !had_example || first.undercut {
        return first.solution(problem.names, Work::default());
    }
    // The example could not be made cheaper than Hermite (a short gap whose
    // example moves faster than its ends): the plain prior, which always
    // starts at Hermite's effort, then decides; the work of both is reported.
    let plain = continuation(problem, prior, &dofs, None)?;
    plain.solution(problem.names, first.work)
}

/// Tells the progress callback that solve `k` (from 0) of at most `of` starts.
pub(super) fn step<M: TorqueModel>(problem: &Problem<'_, M>, k: usize, of: usize) {
    problem.opts.progress.report(ProgressEvent::Step {
        step: k + 1,
        steps: of,
    });
}

/// The result of one run down [`PRIOR_SCHEDULE`].
struct Continued {
    x: Vec<f64>,
    /// The objective's gap DOFs, spline spaces, full coefficients and curves at `x`.
    dofs: Vec<GapDof>,
    curves: Vec<TransitionCurve>,
    coefficients: Vec<Vec<f64>>,
    written: Vec<Curve>,
    /// The last step's run.
    last: RunStats,
    /// Every step's work.
    work: Work,
    outcome: Outcome,
    /// Whether it costs less ∫Στ² than Hermite by [`EFFORT_MARGIN`].
    undercut: bool,
}

impl Continued {
    /// The example sources asked, for the report.
    fn tried(mut self, tried: Vec<Tried>) -> Self {
        self.outcome.tried = tried;
        self
    }

    /// The group's solution, its report adding the work `before` it.
    fn solution(self, names: &[String], before: Work) -> Result<GroupSolution, SpError> {
        let mut work = self.work;
        work.absorb(&before);
        Ok(GroupSolution {
            report: GapReport::new(&self.dofs, names, self.last, work, self.outcome),
            x: self.x,
            curves: self.curves,
            coefficients: self.coefficients,
            written: self.written,
            plan: None,
        })
    }
}

/// ∫Στ² alone under the effort check's finer rule ([`CHECK_SAMPLES`]), and
/// the Hermite curves' that a transition must undercut.
pub(super) struct EffortCheck<'p, M: TorqueModel> {
    torque_only: Objective<'p, M>,
    scratch: Scratch<M::Workspace>,
    /// The Hermite start's free coefficients.
    pub(super) hermite: Vec<f64>,
    /// The most ∫Στ² a transition may cost: [`EFFORT_MARGIN`] below the
    /// whole motion filled by Hermite curves.
    target: f64,
}

impl<'p, M: TorqueModel> EffortCheck<'p, M> {
    /// The check of transitions of `dofs`, each a correction to its base
    /// curve where `bases` has one (none given: no bases).
    pub(super) fn new(
        problem: &'p Problem<'_, M>,
        prior: &PriorTerm<'_>,
        dofs: &[GapDof],
        bases: Option<Vec<Option<Arc<Curve>>>>,
    ) -> Result<Self, SpError> {
        let settings = problem.settings;
        let fine = TransitionSettings {
            samples: settings.samples * CHECK_SAMPLES,
            ..settings.clone()
        };
        let layout = match bases {
            Some(b) => GapLayout::with_bases(dofs.to_vec(), &fine, b)?,
            None => GapLayout::new(dofs.to_vec(), &fine)?,
        };
        let torque_only = Objective::on_layout(
            problem.model,
            layout,
            problem.weights.to_vec(),
            problem.inputs,
        )?;
        let scratch = torque_only.scratch();
        let hermite = torque_only.hermite_start();
        let t0 = dofs.iter().map(|d| d.t0).fold(f64::INFINITY, f64::min);
        let t1 = dofs.iter().map(|d| d.t1).fold(f64::NEG_INFINITY, f64::max);
        let hermite_energy = (prior.baseline)(t0, t1)?;
        Ok(EffortCheck {
            torque_only,
            scratch,
            hermite,
            target: (1.0 - EFFORT_MARGIN) * hermite_energy,
        })
    }

    /// ∫Στ² of the transition of unknowns `x`.
    pub(super) fn energy(&mut self, x: &[f64]) -> Result<f64, SpError> {
        self.torque_only.eval(&mut self.scratch, x, None)
    }
}

/// The continuation's objective: ∫Στ² and the prior scaled by `scale`
/// (the steps after rescale it in place), following `example` where it can (`example` is dropped when the
/// objective cannot follow it).
pub(super) fn step_objective<'p, M: TorqueModel>(
    problem: &'p Problem<'_, M>,
    prior: &PriorTerm<'_>,
    dofs: &[GapDof],
    scale: f64,
    example: &mut Option<Example>,
) -> Result<Objective<'p, M>, SpError> {
    let mut obj = problem
        .objective(dofs.to_vec(), problem.settings)?
        .with_prior(&prior.scaled(scale))?;
    let follows = match example.as_ref().map(|ex| (ex, &ex.clip)) {
        None => true,
        Some((ex, None)) => obj.with_example(problem.inputs, ex.shift, &ex.follow, ex.trust())?,
        // a library stretch: its own motion, already on the gap's clock
        Some((ex, Some(clip))) => obj.with_example(&clip.inputs(), 0.0, &ex.follow, ex.trust())?,
    };
    if !follows {
        *example = None;
    }
    Ok(obj)
}

/// [`unanchored`]'s continuation with the prior following `example`
/// (or the plain prior).
fn continuation<M: TorqueModel>(
    problem: &Problem<'_, M>,
    prior: &PriorTerm<'_>,
    dofs: &[GapDof],
    mut example: Option<Example>,
) -> Result<Continued, SpError> {
    let mut check = EffortCheck::new(problem, prior, dofs, None)?;
    let mut x = check.hermite.clone();
    let mut work = Work::default();
    // built once: each step rescales the prior in place (bit for bit the
    // objective built at that scale; `Objective::rescale_prior`)
    let mut obj = step_objective(problem, prior, dofs, PRIOR_SCHEDULE[0], &mut example)?;
    let mut k = 0;
    loop {
        let scale = PRIOR_SCHEDULE[k];
        step(problem, k, PRIOR_SCHEDULE.len());
        obj.rescale_prior(scale)?;
        let above = x;
        let (mut x_k, last) = run(&obj, above.clone(), problem.opts)?;
        let mut energy = check.energy(&x_k)?;
        work.add(&last);
        let undercut = energy <= check.target;
        if undercut || k + 1 == PRIOR_SCHEDULE.len() {
            if k > 0 && undercut {
                let target = check.target;
                let (x_c, e, n) =
                    nearest_cheaper(&above, &x_k, energy, target, |x| check.energy(x))?;
                x_k = x_c;
                energy = e;
                work.evaluations += n as u64;
            }
            let hermite = check.hermite.clone();
            let outcome = Outcome {
                // under the same rule as `energy`, with any support limbs as held
                initial_energy: check.energy(&hermite)?,
                energy,
                prior_scale: scale,
                example,
                tried: vec![],
            };
            let layout = obj.layout();
            let written = (0..layout.dofs().len())
                .map(|d| layout.curve(d, &x_k))
                .collect::<Result<Vec<_>, _>>()?;
            return Ok(Continued {
                written,
                coefficients: obj.coefficients(&x_k),
                curves: obj.curves().to_vec(),
                dofs: obj.dofs().to_vec(),
                x: x_k,
                last,
                work,
                outcome,
                undercut,
            });
        }
        x = x_k;
        k += 1;
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
}
