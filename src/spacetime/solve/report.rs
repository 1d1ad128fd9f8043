//! What a solve returns: the statistics of one quasi-Newton run
//! ([`RunStats`]), why it stopped ([`StopReason`]), and the report of a
//! group of gaps ([`GapReport`]), built once from the runs of its
//! continuation.

use crate::motion::Curve;
use crate::spacetime::contact::GapPlan;
use crate::spacetime::error::SpError;
use crate::spacetime::objective::{GapDof, Objective};
use crate::spacetime::reference::{Example, Tried};
use crate::spacetime::torque::TorqueModel;
use crate::spacetime::transition::TransitionCurve;

/// What one quasi-Newton solve (one step of the continuation) did.
#[derive(Clone, Debug, PartialEq)]
pub struct RunStats {
    pub method: &'static str,
    pub n_vars: usize,
    pub iterations: u64,
    pub evaluations: u64,
    /// The objective at the start point.
    pub initial_energy: f64,
    /// The objective at the best point seen.
    pub energy: f64,
    pub grad_norm: f64,
    pub stop: StopReason,
    pub seconds: f64,
}

/// The work of several runs, added up (a continuation's steps, and the
/// bisection's evaluations).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Work {
    pub iterations: u64,
    pub evaluations: u64,
    pub seconds: f64,
    pub solves: u32,
}

impl Work {
    /// Adds one run.
    pub fn add(&mut self, s: &RunStats) {
        self.iterations += s.iterations;
        self.evaluations += s.evaluations;
        self.seconds += s.seconds;
        self.solves += 1;
    }

    /// Adds the work of another continuation.
    pub fn absorb(&mut self, o: &Work) {
        self.iterations += o.iterations;
        self.evaluations += o.evaluations;
        self.seconds += o.seconds;
        self.solves += o.solves;
    }
}

/// The coordinates and span of a group's gap DOFs.
fn span_of(d: &[GapDof]) -> (Vec<usize>, f64, f64) {
    (
        d.iter().map(|d| d.coord).collect(),
        d.iter().map(|d| d.t0).fold(f64::INFINITY, f64::min),
        d.iter().map(|d| d.t1).fold(f64::NEG_INFINITY, f64::max),
    )
}

/// The group's ∫Στ² (not the objective's value when a prior is on) and what
/// the continuation did to reach it.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// ∫Στ² of the Hermite start.
    pub initial_energy: f64,
    /// ∫Στ² of the result.
    pub energy: f64,
    pub prior_scale: f64,
    pub example: Option<Example>,
    /// Each example source asked, with its match cost or why it had none
    /// (empty when none was asked, or before issue 36's anchor).
    pub tried: Vec<Tried>,
}

impl GapReport {
    /// The report of a single run on the gap DOFs `dofs` (an objective's,
    /// in its order): its energies are the objective's.
    pub fn of_run(dofs: &[GapDof], names: &[String], s: RunStats) -> Self {
        let work = Work {
            iterations: s.iterations,
            evaluations: s.evaluations,
            seconds: s.seconds,
            solves: 1,
        };
        let outcome = Outcome {
            initial_energy: s.initial_energy,
            energy: s.energy,
            prior_scale: 1.0,
            example: None,
            tried: vec![],
        };
        GapReport::new(dofs, names, s, work, outcome)
    }

    /// The report of a group: the last run's method, gradient and stop, the
    /// work of every run, and the energies the continuation measured.
    pub fn new(
        dofs: &[GapDof],
        names: &[String],
        last: RunStats,
        work: Work,
        outcome: Outcome,
    ) -> Self {
        let (coords, t0, t1) = span_of(dofs);
        GapReport {
            names: coords
                .iter()
                .filter_map(|&c| names.get(c).cloned())
                .collect(),
            coords,
            t0,
            t1,
            n_vars: last.n_vars,
            method: last.method,
            iterations: work.iterations,
            evaluations: work.evaluations,
            initial_energy: outcome.initial_energy,
            energy: outcome.energy,
            grad_norm: last.grad_norm,
            stop: last.stop,
            seconds: work.seconds,
            prior_scale: outcome.prior_scale,
            solves: work.solves,
            example: outcome.example,
            tried: outcome.tried,
        }
    }
}

/// What happened while solving one group of gaps.
#[derive(Clone, Debug, PartialEq)]
pub struct GapReport {
    /// Model coordinates of the gap DOFs.
    pub coords: Vec<usize>,
    /// Their names (empty where the caller gave none).
    pub names: Vec<String>,
    pub t0: f64,
    pub t1: f64,
    pub n_vars: usize,
    pub method: &'static str,
    pub iterations: u64,
    pub evaluations: u64,
    /// Energy of the starting (Hermite) curves.
    pub initial_energy: f64,
    pub energy: f64,
    pub grad_norm: f64,
    pub stop: StopReason,
    pub seconds: f64,
    /// The factor the kinematic prior's weights were scaled by in the last
    /// solve (1: as asked; smaller when SP had to lower it so the transition
    /// costs less torque than the Hermite curves; see `groups::solve_all`;
    /// that last step is then taken only part of the way from the step
    /// before).
    pub prior_scale: f64,
    /// Solves run (one, or more while the prior was being lowered).
    pub solves: u32,
    /// The stretch of the motion the prior followed (`None`: the plain prior;
    /// see [`crate::spacetime::reference`]).
    pub example: Option<Example>,
    /// Each example source asked (`"self"`, the library), with its match
    /// cost ρ or why it had none: why no example is followed, when none is.
    pub tried: Vec<Tried>,
}

impl GapReport {
    /// Why the group follows no example (`None` when it follows one, or
    /// when no source was asked).
    pub fn why_no_example(&self) -> Option<String> {
        crate::spacetime::reference::why_none(&self.tried, self.example.is_some())
    }

    /// Whether the solve ended by one of its stopping rules (not by the
    /// iteration limit or a failed step): a result, not a flagged stop.
    pub fn converged(&self) -> bool {
        self.stop.converged()
    }
}

/// Why a solve ended. Printed as a sentence (`sp_report`'s `stop`).
#[derive(Clone, Debug, PartialEq)]
pub enum StopReason {
    /// No free coefficient: the gap's curves are fixed by their end states.
    NothingToOptimise,
    /// The gradient at the Hermite start is exactly zero.
    StationaryStart,
    /// argmin's gradient or cost tolerance was met.
    Converged,
    /// The stall rule: the last `iterations` lowered the energy by less than
    /// `tolerance` (relative).
    Stalled { iterations: u64, tolerance: f64 },
    /// The iteration budget ran out first: a flagged stop.
    IterationLimit,
    /// The line search could not progress (the objective's precision limit):
    /// the best point seen is kept, but the stop is flagged.
    LineSearch(String),
    /// Any other reason argmin gave.
    Other(String),
}

impl StopReason {
    /// A result, not a flagged stop.
    pub fn converged(&self) -> bool {
        !matches!(self, StopReason::IterationLimit | StopReason::LineSearch(_))
    }
}

impl std::fmt::Display for StopReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            StopReason::NothingToOptimise => write!(f, "nothing to optimise (coefficients: 0)"),
            StopReason::StationaryStart => {
                write!(f, "converged (the Hermite start is stationary)")
            }
            StopReason::Converged => write!(f, "converged"),
            StopReason::Stalled {
                iterations,
                tolerance,
            } => write!(
                f,
                "converged (the last {iterations} iterations lowered the energy by less than {tolerance})"
            ),
            StopReason::IterationLimit => write!(f, "iteration limit reached"),
            StopReason::LineSearch(e) => write!(f, "stopped: {e}"),
            StopReason::Other(s) => write!(f, "{s}"),
        }
    }
}

/// The solved free coefficients and full coefficient vectors of each gap
/// DOF, the curves to write and, when the body stood, the plan it stood on.
#[derive(Clone, Debug)]
pub struct GroupSolution {
    pub x: Vec<f64>,
    /// The spline space of each gap DOF (same order as `coefficients`).
    pub curves: Vec<TransitionCurve>,
    /// The splines' full coefficients: a DOF that corrects a laid example
    /// has the correction's (see `written`).
    pub coefficients: Vec<Vec<f64>>,
    /// Each gap DOF's curve as the motion stores it: the spline, or the laid
    /// example plus the spline (same order as `coefficients`).
    pub written: Vec<Curve>,
    pub report: GapReport,
    /// The contact plan the group stood on, re-planned and scored
    /// (`Stance::solved`); `None` when the body did not stand.
    pub plan: Option<GapPlan>,
}

impl GroupSolution {
    /// The solution of `obj` at unknowns `x`, with its report and plan.
    pub fn of<M: TorqueModel>(
        obj: &Objective<'_, M>,
        x: Vec<f64>,
        report: GapReport,
        plan: Option<GapPlan>,
    ) -> Result<Self, SpError> {
        let layout = obj.layout();
        let written = (0..layout.dofs().len())
            .map(|d| layout.curve(d, &x))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(GroupSolution {
            coefficients: obj.coefficients(&x),
            curves: obj.curves().to_vec(),
            written,
            x,
            report,
            plan,
        })
    }

    /// The same solution, its report listing the example sources `tried`.
    pub fn with_tried(mut self, tried: Vec<Tried>) -> Self {
        self.report.tried = tried;
        self
    }
}
