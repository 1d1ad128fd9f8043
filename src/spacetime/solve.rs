//! Minimise one group's objective with argmin: BFGS for small problems, where
//! the dense inverse-Hessian update is cheap and converges in fewer steps;
//! L-BFGS beyond, where (nm)² per step would dominate (Rose §3.2.3).
//! The solver works in variables whitened by a Gauss–Newton preconditioner;
//! the body's pose (hence its mass matrix and gravity torques) moves away
//! from the Hermite start as the solve proceeds, so the solve runs in rounds
//! of `relinearise_every` iterations: after each, the preconditioner is
//! rebuilt at the best point so far and the quasi-Newton run restarts there.
//! The solve ends when the last 25 iterations (`stall_window`, checked after
//! every iteration, across rounds) lowered the energy by less than
//! `tolerance` (relative): the objective is non-convex and its gradient never
//! gets small in relative terms before the energy has stopped moving, so
//! energy progress is the honest stopping rule. Measured on the 44-DOF Fig. 8 case
//! (`cargo bench --bench spacetime`): see the solver table there.
//! Evaluation shares one pass for cost and gradient (the adjoint gives both),
//! remembers the best point seen, and polls a `CancelToken`.
//!
//! Measured alternatives that did not pay on the 44-DOF Fig. 8 case (5
//! coefficients, 190 unknowns; the default needs 150 iterations, 175
//! evaluations and 6 preconditioner builds to land 0.3 % above the converged
//! optimum):
//! - Gauss–Newton or Levenberg–Marquardt steps: the residual is large (τ does
//!   not vanish at the optimum) and the ignored Σ τ ∂²τ curvature is of the
//!   same size as JᵀJ, so LM keeps λ ≈ 0.1 and after 60 steps (46 Jacobian
//!   builds) stands where L-BFGS is after 40 iterations.
//! - Dense BFGS (argmin) on all 190 unknowns: 2–3 evaluations per iteration
//!   and 500–900 evaluations in all.
//! - An L-BFGS whose correction pairs survive re-linearisation (H₀ = the new
//!   Gauss–Newton inverse): 218–260 evaluations, no better.
//! - Re-linearising every 5–15 iterations: 145–176 evaluations (as many) for
//!   1.5–3 times the preconditioner builds; every 35–75: 225–276.
//! - Leaving the ∂τ/∂q̇ blocks out of the preconditioner: twice the iterations.
//! - A coarse first solve on 2–4 Gauss points per piece: the coarse problem
//!   needs as many iterations as the fine one.

use super::error::SpError;
use super::objective::{Objective, Scratch};
use super::precond::Precond;
use super::torque::TorqueModel;
use crate::cancel::CancelToken;
use argmin::core::{
    CostFunction, Executor, Gradient, IterState, KV, Problem as ArgminProblem, Solver, State,
    TerminationReason, TerminationStatus,
};
use argmin::solver::linesearch::MoreThuenteLineSearch;
use argmin::solver::quasinewton::{BFGS, LBFGS};
use std::cell::{Cell, RefCell};
use std::time::Instant;

/// Solver settings (not the transition's shape: see `TransitionSettings`).
#[derive(Clone, Debug)]
pub struct SolveOptions {
    pub max_iters: u64,
    /// Stop when ‖∇e‖ falls below this fraction of its value at the start.
    pub grad_rtol: f64,
    /// Stop when the last `stall_window` iterations lowered the energy by
    /// less than this fraction of it (`tolerance:` in mx).
    pub tolerance: f64,
    /// Iterations over which `tolerance` is measured (checked after every one).
    pub stall_window: u64,
    /// Stop when an iteration lowers e by less than this fraction of the starting e.
    pub cost_rtol: f64,
    /// Use dense BFGS up to this many unknowns, L-BFGS above.
    pub bfgs_max_vars: usize,
    /// Correction pairs L-BFGS keeps.
    pub lbfgs_memory: usize,
    /// Iterations per round: the preconditioner is rebuilt at the best point
    /// and L-BFGS restarts after each (see the module docs).
    pub relinearise_every: u64,
    pub cancel: CancelToken,
    /// Told of every objective evaluation (a progress bar's heartbeat).
    pub progress: super::progress::Progress,
}

impl Default for SolveOptions {
    fn default() -> Self {
        SolveOptions {
            max_iters: 300,
            grad_rtol: 1e-6,
            tolerance: 1e-3,
            stall_window: 25,
            cost_rtol: 1e-12,
            bfgs_max_vars: 40,
            lbfgs_memory: 30,
            relinearise_every: 25,
            cancel: CancelToken::new(),
            progress: Default::default(),
        }
    }
}

/// What happened while solving one group of gaps.
#[derive(Clone, Debug, PartialEq)]
pub struct GapReport {
    /// Model coordinates of the gap DOFs.
    pub coords: Vec<usize>,
    /// Their names (filled in by the caller that knows them).
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
    /// see [`super::reference`]).
    pub example: Option<super::reference::Example>,
}

impl GapReport {
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

/// The solved free coefficients and full coefficient vectors of each gap DOF.
#[derive(Clone, Debug)]
pub struct GroupSolution {
    pub x: Vec<f64>,
    /// The spline space of each gap DOF (same order as `coefficients`).
    pub curves: Vec<super::transition::TransitionCurve>,
    pub coefficients: Vec<Vec<f64>>,
    pub report: GapReport,
}

/// The last point evaluated: (y, e, ∂e/∂y).
type LastEval = Option<(Vec<f64>, f64, Vec<f64>)>;

struct Best {
    x: Vec<f64>,
    e: f64,
    g: Vec<f64>,
}

struct Problem<'o, 'a, M: TorqueModel> {
    obj: &'o Objective<'a, M>,
    /// x = T(y); the solver works in y (re-linearised between rounds).
    t: RefCell<Precond>,
    scratch: RefCell<Scratch<M::Workspace>>,
    /// The last evaluated point: argmin asks for cost and gradient separately at the same x.
    last: RefCell<LastEval>,
    best: RefCell<Option<Best>>,
    evals: RefCell<u64>,
    cancel: CancelToken,
    progress: super::progress::Progress,
}

impl<M: TorqueModel> Problem<'_, '_, M> {
    fn to_x(&self, y: &[f64]) -> Vec<f64> {
        self.t.borrow().apply(y)
    }

    fn to_y(&self, x: &[f64]) -> Vec<f64> {
        self.t.borrow().solve(x)
    }

    /// e and ∂e/∂y = Tᵀ ∂e/∂x at y.
    fn eval(&self, y: &[f64]) -> Result<(f64, Vec<f64>), argmin::core::Error> {
        if let Some((ly, le, lg)) = self.last.borrow().as_ref()
            && ly.as_slice() == y
        {
            return Ok((*le, lg.clone()));
        }
        let x = self.to_x(y);
        let (e, gx) = self.eval_x(&x)?;
        let gy = self.t.borrow().apply_t(&gx);
        *self.last.borrow_mut() = Some((y.to_vec(), e, gy.clone()));
        Ok((e, gy))
    }

    fn eval_x(&self, x: &[f64]) -> Result<(f64, Vec<f64>), argmin::core::Error> {
        if self.cancel.is_cancelled() {
            return Err(argmin::core::Error::msg("cancelled"));
        }
        let mut g = vec![0.0; x.len()];
        let e = self
            .obj
            .eval(&mut self.scratch.borrow_mut(), x, Some(&mut g))
            .map_err(|e| argmin::core::Error::msg(e.to_string()))?;
        *self.evals.borrow_mut() += 1;
        self.progress
            .report(super::progress::ProgressEvent::Evaluation);
        let mut best = self.best.borrow_mut();
        if best.as_ref().is_none_or(|b| e < b.e) {
            *best = Some(Best {
                x: x.to_vec(),
                e,
                g: g.clone(),
            });
        }
        Ok((e, g))
    }
}

/// argmin owns its problem; lend it ours so the best point survives the run.
struct Lend<'p, 'o, 'a, M: TorqueModel>(&'p Problem<'o, 'a, M>);

impl<M: TorqueModel> CostFunction for Lend<'_, '_, '_, M> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, x: &Vec<f64>) -> Result<f64, argmin::core::Error> {
        Ok(self.0.eval(x)?.0)
    }
}

impl<M: TorqueModel> Gradient for Lend<'_, '_, '_, M> {
    type Param = Vec<f64>;
    type Gradient = Vec<f64>;
    fn gradient(&self, x: &Vec<f64>) -> Result<Vec<f64>, argmin::core::Error> {
        Ok(self.0.eval(x)?.1)
    }
}

fn norm(g: &[f64]) -> f64 {
    g.iter().map(|v| v * v).sum::<f64>().sqrt()
}

/// Why a round ended: the stall rule if it fired, else argmin's status.
fn stop_reason(status: &TerminationStatus, stalled: Option<(u64, f64)>) -> StopReason {
    if let Some((iterations, tolerance)) = stalled {
        return StopReason::Stalled {
            iterations,
            tolerance,
        };
    }
    match status {
        TerminationStatus::Terminated(TerminationReason::SolverConverged) => StopReason::Converged,
        TerminationStatus::Terminated(TerminationReason::MaxItersReached) => {
            StopReason::IterationLimit
        }
        TerminationStatus::Terminated(r) => StopReason::Other(r.text().to_string()),
        TerminationStatus::NotTerminated => StopReason::Other("not terminated".into()),
    }
}

/// A solver run with one more stopping rule: after every iteration, stop
/// when the best energy fell by less than `tolerance` (relative) over the
/// last `window` iterations, counted across rounds (`history` outlives one
/// run), so the solve ends where progress stalls, not at the end of a round.
struct StallAware<'h, S> {
    inner: S,
    /// Iterations done in earlier rounds.
    start: u64,
    window: u64,
    tolerance: f64,
    /// (iteration, best energy) after every iteration so far.
    history: &'h RefCell<Vec<(u64, f64)>>,
    /// Set when this rule ends the run, so the report can say so (argmin's
    /// own reason is only text).
    stalled: &'h Cell<Option<(u64, f64)>>,
}

impl<O, I, S> Solver<O, I> for StallAware<'_, S>
where
    I: State<Float = f64>,
    S: Solver<O, I>,
{
    fn name(&self) -> &str {
        self.inner.name()
    }

    fn init(
        &mut self,
        problem: &mut ArgminProblem<O>,
        state: I,
    ) -> Result<(I, Option<KV>), argmin::core::Error> {
        self.inner.init(problem, state)
    }

    fn next_iter(
        &mut self,
        problem: &mut ArgminProblem<O>,
        state: I,
    ) -> Result<(I, Option<KV>), argmin::core::Error> {
        self.inner.next_iter(problem, state)
    }

    fn terminate(&mut self, state: &I) -> TerminationStatus {
        let status = self.inner.terminate(state);
        if status.terminated() {
            return status;
        }
        let now = self.start + state.get_iter();
        let e = state.get_best_cost();
        if !e.is_finite() {
            // before the run's first evaluation
            return TerminationStatus::NotTerminated;
        }
        let mut history = self.history.borrow_mut();
        history.push((now, e));
        let then = history
            .iter()
            .rev()
            .find(|(t, _)| *t + self.window <= now)
            .copied();
        match then {
            Some((t, e_then)) if e_then - e < self.tolerance * e.abs() => {
                self.stalled.set(Some((now - t, self.tolerance)));
                TerminationStatus::Terminated(TerminationReason::SolverExit("stalled".into()))
            }
            _ => TerminationStatus::NotTerminated,
        }
    }
}

/// The stall rule of one round (see [`StallAware`]).
struct Stall<'h> {
    start: u64,
    window: u64,
    tolerance: f64,
    history: &'h RefCell<Vec<(u64, f64)>>,
    /// Set when the stall rule ends the round: (iterations looked back, tolerance).
    stalled: &'h Cell<Option<(u64, f64)>>,
}

/// One round of a quasi-Newton `solver` (BFGS or L-BFGS: they differ only in
/// the solver and in BFGS's starting inverse Hessian, which `init` sets with the
/// start point and the round's budget) under the stall rule: the iterations it
/// ran and why it stopped.
fn run_round<'p, 'o, 'a, M, S, H>(
    problem: &'p Problem<'o, 'a, M>,
    solver: S,
    stall: Stall<'_>,
    init: impl FnOnce(RoundState<H>) -> RoundState<H>,
) -> Result<(u64, StopReason), argmin::core::Error>
where
    M: TorqueModel,
    S: Solver<Lend<'p, 'o, 'a, M>, RoundState<H>>,
    RoundState<H>: State<Float = f64>,
{
    let solver = StallAware {
        inner: solver,
        start: stall.start,
        window: stall.window,
        tolerance: stall.tolerance,
        history: stall.history,
        stalled: stall.stalled,
    };
    Executor::new(Lend(problem), solver)
        .configure(init)
        .run()
        .map(|r| {
            (
                r.state().get_iter(),
                stop_reason(r.state().get_termination_status(), stall.stalled.get()),
            )
        })
}

/// The argmin state of a round: parameters and gradients as vectors, `H` the
/// inverse Hessian BFGS keeps (`()` for L-BFGS).
type RoundState<H> = IterState<Vec<f64>, Vec<f64>, (), H, (), f64>;

/// Minimise the objective from the Hermite start.
pub fn solve_group<M: TorqueModel>(
    obj: &Objective<'_, M>,
    opts: &SolveOptions,
) -> Result<GroupSolution, SpError> {
    solve_group_from(obj, obj.hermite_start(), opts)
}

/// [`solve_group`] from the free coefficients `x0` (a warm start) instead of
/// the Hermite curves; the preconditioner is linearised there.
pub fn solve_group_from<M: TorqueModel>(
    obj: &Objective<'_, M>,
    x0: Vec<f64>,
    opts: &SolveOptions,
) -> Result<GroupSolution, SpError> {
    let started = Instant::now();
    opts.cancel.check()?;
    let mut scratch = obj.scratch();
    let t = obj.gauss_newton_at(&mut scratch, &x0)?;
    let problem = Problem {
        obj,
        t: RefCell::new(t),
        scratch: RefCell::new(scratch),
        last: RefCell::new(None),
        best: RefCell::new(None),
        evals: RefCell::new(0),
        cancel: opts.cancel.clone(),
        progress: opts.progress.clone(),
    };
    let y0 = problem.to_y(&x0);
    let (e0, g0x) = problem
        .eval_x(&x0)
        .map_err(|e| SpError::Evaluation(e.to_string()))?;
    let (_, g0) = problem
        .eval(&y0)
        .map_err(|e| SpError::Evaluation(e.to_string()))?;
    let g0n = norm(&g0);
    let n = x0.len();
    let mut iterations = 0;
    let mut method = "none";
    let mut stop = StopReason::NothingToOptimise;
    if n > 0 && g0n == 0.0 {
        stop = StopReason::StationaryStart;
    } else if n > 0 {
        let tol_grad = (opts.grad_rtol * g0n).max(f64::MIN_POSITIVE);
        let tol_cost = (opts.cost_rtol * e0.abs()).max(f64::MIN_POSITIVE);
        let mem = opts.lbfgs_memory.max(1);
        let round = opts.relinearise_every.max(1);
        let mut y_start = y0.clone();
        let mut run: Result<(u64, StopReason), argmin::core::Error> =
            Ok((0, StopReason::NothingToOptimise));
        let stalled = Cell::new(None);
        let history = RefCell::new(vec![(0, e0)]);
        let mut total = 0;
        while total < opts.max_iters {
            let budget = round.min(opts.max_iters - total);
            let linesearch = MoreThuenteLineSearch::new();
            let stall = Stall {
                start: total,
                window: opts.stall_window.max(1),
                tolerance: opts.tolerance,
                history: &history,
                stalled: &stalled,
            };
            let y = y_start.clone();
            run = if n <= opts.bfgs_max_vars {
                method = "BFGS";
                // In the preconditioned variables the Hessian is about 2·I.
                let s = 0.5;
                let h0: Vec<Vec<f64>> = (0..n)
                    .map(|i| (0..n).map(|j| if i == j { s } else { 0.0 }).collect())
                    .collect();
                let solver = BFGS::new(linesearch)
                    .with_tolerance_grad(tol_grad)
                    .and_then(|s| s.with_tolerance_cost(tol_cost))
                    .map_err(|e| SpError::Invalid(e.to_string()))?;
                run_round(&problem, solver, stall, |st| {
                    st.param(y).inv_hessian(h0).max_iters(budget)
                })
            } else {
                method = "L-BFGS";
                let solver = LBFGS::new(linesearch, mem)
                    .with_tolerance_grad(tol_grad)
                    .and_then(|s| s.with_tolerance_cost(tol_cost))
                    .map_err(|e| SpError::Invalid(e.to_string()))?;
                run_round(&problem, solver, stall, |st| st.param(y).max_iters(budget))
            };
            let it = run.as_ref().map(|r| r.0).unwrap_or(budget);
            total += it.max(1);
            // only a run cut short by its round's budget continues; convergence,
            // a stuck line search or cancellation end the solve
            let limited = matches!(&run, Ok((_, StopReason::IterationLimit)));
            if !limited || total >= opts.max_iters {
                break;
            }
            let bx = problem
                .best
                .borrow()
                .as_ref()
                .map_or_else(|| x0.clone(), |b| b.x.clone());
            // re-linearise the preconditioner at the best point and restart there
            let t = obj.gauss_newton_at(&mut problem.scratch.borrow_mut(), &bx)?;
            *problem.t.borrow_mut() = t;
            *problem.last.borrow_mut() = None;
            y_start = problem.to_y(&bx);
        }
        let run = run.map(|(_, s)| (total, s));
        match run {
            Ok((it, s)) => {
                iterations = it;
                stop = s;
            }
            Err(e) => {
                if opts.cancel.is_cancelled() {
                    return Err(SpError::Cancelled);
                }
                // A line search that cannot progress means we are at the
                // precision limit of the objective: keep the best point seen.
                stop = StopReason::LineSearch(e.to_string());
            }
        }
    }
    let best = problem.best.into_inner();
    let (x, energy, grad_norm) = match best {
        Some(b) => (b.x, b.e, norm(&b.g)),
        None => (x0, e0, norm(&g0x)),
    };
    let coefficients = obj.coefficients(&x);
    let report = GapReport {
        coords: obj.dofs().iter().map(|d| d.coord).collect(),
        names: vec![],
        t0: obj
            .dofs()
            .iter()
            .map(|d| d.t0)
            .fold(f64::INFINITY, f64::min),
        t1: obj
            .dofs()
            .iter()
            .map(|d| d.t1)
            .fold(f64::NEG_INFINITY, f64::max),
        n_vars: n,
        method,
        iterations,
        evaluations: *problem.evals.borrow(),
        initial_energy: e0,
        energy,
        grad_norm,
        stop,
        seconds: started.elapsed().as_secs_f64(),
        prior_scale: 1.0,
        example: None,
        solves: 1,
    };
    Ok(GroupSolution {
        x,
        curves: obj.curves().to_vec(),
        coefficients,
        report,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spacetime::objective::{GapDof, TransitionSettings};
    use crate::spacetime::planar2::TwoLinkArm;
    use crate::spacetime::transition::{Continuity, EndState};

    fn st(q: f64, v: f64) -> EndState {
        EndState { q, v, a: 0.0 }
    }

    fn arm_problem<'a>(
        arm: &'a TwoLinkArm,
        settings: &TransitionSettings,
        t1: f64,
    ) -> Objective<'a, TwoLinkArm> {
        let dofs = vec![
            GapDof {
                coord: 0,
                t0: 0.0,
                t1,
                start: st(-0.3, 0.5),
                end: st(1.1, 0.0),
            },
            GapDof {
                coord: 1,
                t0: 0.0,
                t1,
                start: st(0.2, 0.0),
                end: st(0.2, 0.0),
            },
        ];
        let inputs = |_: f64, _: &mut [f64], _: &mut [f64], _: &mut [f64]| Ok(());
        Objective::new(arm, dofs, settings, vec![1.0, 1.0], &inputs).unwrap()
    }

    #[test]
    fn lowers_the_energy_below_hermite_and_reaches_a_stationary_point() {
        let arm = TwoLinkArm::default();
        for (n, method) in [(6, "BFGS"), (30, "L-BFGS")] {
            let settings = TransitionSettings {
                coefficients: n,
                samples: 30,
                continuity: Continuity::C1,
            };
            let obj = arm_problem(&arm, &settings, 0.8);
            let sol = solve_group(&obj, &SolveOptions::default()).unwrap();
            let r = &sol.report;
            eprintln!("{r:?}");
            assert_eq!(r.method, method);
            assert!(r.energy < 0.9 * r.initial_energy, "{r:?}");
            assert!(r.grad_norm < 1e-3 * obj_grad0(&obj), "{r:?}");
            // the interior joint moves although its ends are equal (the Fig. 10 effect)
            let c = &sol.coefficients[1];
            let mid = obj.curves()[1].eval(c, 0.4)[0];
            assert!((mid - 0.2).abs() > 1e-3, "elbow stayed at {mid}");
            // and the ends still match exactly
            let e = obj.curves()[0].eval(&sol.coefficients[0], 0.8);
            assert!((e[0] - 1.1).abs() <= 1e-12 && e[1].abs() <= 1e-9);
        }
    }

    fn obj_grad0(obj: &Objective<'_, TwoLinkArm>) -> f64 {
        let x = obj.hermite_start();
        let mut g = vec![0.0; x.len()];
        obj.eval(&mut obj.scratch(), &x, Some(&mut g)).unwrap();
        norm(&g)
    }

    #[test]
    fn more_coefficients_never_do_worse() {
        // The spline spaces are nested when the span count doubles (3 → 6 spans).
        let arm = TwoLinkArm::default();
        let s = |n| TransitionSettings {
            coefficients: n,
            samples: 40,
            continuity: Continuity::C1,
        };
        let e_small =
            solve_group(&arm_problem(&arm, &s(2), 0.8), &SolveOptions::default()).unwrap();
        let e_big = solve_group(&arm_problem(&arm, &s(5), 0.8), &SolveOptions::default()).unwrap();
        assert!(e_big.report.energy <= e_small.report.energy * (1.0 + 1e-9));
    }

    /// Many coefficients, densely sampled: a problem that takes dozens of iterations.
    const FINE: TransitionSettings = TransitionSettings {
        coefficients: 30,
        samples: 90,
        continuity: Continuity::C1,
    };

    #[test]
    fn relinearising_restarts_still_descend_to_a_stationary_point() {
        let arm = TwoLinkArm::default();
        let obj = arm_problem(&arm, &FINE, 0.8);
        let plain = solve_group(&obj, &SolveOptions::default()).unwrap().report;
        let opts = SolveOptions {
            relinearise_every: 5,
            lbfgs_memory: 30,
            ..Default::default()
        };
        let r = solve_group(&obj, &opts).unwrap().report;
        assert!(r.iterations > 5, "{r:?}");
        assert!(r.energy < 0.9 * r.initial_energy, "{r:?}");
        assert!(
            r.energy <= plain.energy * (1.0 + 1e-3),
            "{r:?} vs {plain:?}"
        );
    }

    #[test]
    fn stalled_progress_ends_the_solve_inside_a_round() {
        let arm = TwoLinkArm::default();
        let obj = arm_problem(&arm, &FINE, 0.8);
        let opts = SolveOptions {
            relinearise_every: 1000,
            stall_window: 5,
            tolerance: 1e-2,
            ..Default::default()
        };
        let r = solve_group(&obj, &opts).unwrap().report;
        assert!(
            matches!(r.stop, StopReason::Stalled { iterations: 5, .. }),
            "{r:?}"
        );
        assert!(r.iterations >= 5 && r.iterations < 1000, "{r:?}");
        assert!(r.energy < 0.9 * r.initial_energy, "{r:?}");
        // a tighter tolerance runs longer and gets no worse
        let tight = solve_group(
            &obj,
            &SolveOptions {
                tolerance: 1e-6,
                ..opts
            },
        )
        .unwrap()
        .report;
        assert!(tight.iterations > r.iterations, "{tight:?} vs {r:?}");
        assert!(tight.energy <= r.energy, "{tight:?} vs {r:?}");
    }

    #[test]
    fn cancelled_token_stops_with_an_error() {
        let arm = TwoLinkArm::default();
        let obj = arm_problem(&arm, &TransitionSettings::default(), 0.8);
        let opts = SolveOptions::default();
        opts.cancel.cancel();
        assert_eq!(solve_group(&obj, &opts).unwrap_err(), SpError::Cancelled);
    }

    #[test]
    fn a_five_second_gap_is_solved_finitely() {
        let arm = TwoLinkArm::default();
        let obj = arm_problem(
            &arm,
            &TransitionSettings {
                coefficients: 10,
                samples: 40,
                continuity: Continuity::C2,
            },
            5.0,
        );
        let sol = solve_group(&obj, &SolveOptions::default()).unwrap();
        assert!(sol.report.energy.is_finite() && sol.report.energy <= sol.report.initial_energy);
        assert!(sol.coefficients.iter().flatten().all(|c| c.is_finite()));
    }

    #[test]
    fn zero_free_coefficients_is_the_hermite_curve() {
        let arm = TwoLinkArm::default();
        let obj = arm_problem(
            &arm,
            &TransitionSettings {
                coefficients: 0,
                samples: 10,
                continuity: Continuity::C1,
            },
            0.8,
        );
        let sol = solve_group(&obj, &SolveOptions::default()).unwrap();
        assert_eq!(sol.report.iterations, 0);
        assert_eq!(sol.report.energy, sol.report.initial_energy);
    }
}
