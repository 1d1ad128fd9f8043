//! One solve: a quasi-Newton run (BFGS or L-BFGS, see the module docs of
//! [`super`]) in rounds that re-linearise the preconditioner at the best
//! point, under the stall rule.

use super::eval::{Evaluator, Lend};
use super::options::SolveOptions;
use super::report::{GapReport, GroupSolution, RunStats, StopReason};
use super::stall::{Stall, StallAware, stop_reason};
use crate::spacetime::error::SpError;
use crate::spacetime::objective::Objective;
use crate::spacetime::torque::TorqueModel;
use argmin::core::{Error, Executor, IterState, Solver, State};
use argmin::solver::linesearch::MoreThuenteLineSearch;
use argmin::solver::quasinewton::{BFGS, LBFGS};
use std::cell::{Cell, RefCell};
use std::time::Instant;

fn norm(g: &[f64]) -> f64 {
    g.iter().map(|v| v * v).sum::<f64>().sqrt()
}

/// The argmin state of a round: parameters and gradients as vectors, `H` the
/// inverse Hessian BFGS keeps (`()` for L-BFGS).
type RoundState<H> = IterState<Vec<f64>, Vec<f64>, (), H, (), f64>;

/// One round of a quasi-Newton `solver` (BFGS or L-BFGS: they differ only in
/// the solver and in BFGS's starting inverse Hessian, which `init` sets with the
/// start point and the round's budget) under the stall rule: the iterations it
/// ran and why it stopped.
fn run_round<'p, 'o, 'a, M, S, H>(
    problem: &'p Evaluator<'o, 'a, M>,
    solver: S,
    stall: Stall<'_>,
    init: impl FnOnce(RoundState<H>) -> RoundState<H>,
) -> Result<(u64, StopReason), Error>
where
    M: TorqueModel,
    S: Solver<Lend<'p, 'o, 'a, M>, RoundState<H>>,
    RoundState<H>: State<Float = f64>,
{
    let stalled = stall.stalled;
    let solver = StallAware {
        inner: solver,
        rule: stall,
    };
    Executor::new(Lend(problem), solver)
        .configure(init)
        .run()
        .map(|r| {
            (
                r.state().get_iter(),
                stop_reason(r.state().get_termination_status(), stalled.get()),
            )
        })
}

/// Minimise the objective from the Hermite start.
pub fn solve_group<M: TorqueModel>(
    obj: &Objective<'_, M>,
    opts: &SolveOptions,
) -> Result<GroupSolution, SpError> {
    solve_group_from(obj, obj.hermite_start(), opts)
}

/// [`solve_group`] from the free coefficients `x0` (a warm start) instead of
/// the Hermite curves; the preconditioner is linearised there. The report's
/// names are empty (see [`super::solve_all`] for named ones).
pub fn solve_group_from<M: TorqueModel>(
    obj: &Objective<'_, M>,
    x0: Vec<f64>,
    opts: &SolveOptions,
) -> Result<GroupSolution, SpError> {
    let (x, stats) = run(obj, x0, opts)?;
    let report = GapReport::of_run(obj.dofs(), &[], stats);
    GroupSolution::of(obj, x, report, None)
}

/// Minimise `obj` from `x0`: the best point seen and what the run did.
pub(super) fn run<M: TorqueModel>(
    obj: &Objective<'_, M>,
    x0: Vec<f64>,
    opts: &SolveOptions,
) -> Result<(Vec<f64>, RunStats), SpError> {
    let started = Instant::now();
    opts.cancel.check()?;
    let mut scratch = obj.scratch();
    let t = obj.gauss_newton_at(&mut scratch, &x0)?;
    let problem = Evaluator::new(obj, t, scratch, opts.cancel.clone(), opts.progress.clone());
    // the objective's own errors travel through argmin whole; anything else is the solver's
    let eval_err = |e: Error| {
        e.downcast::<SpError>()
            .unwrap_or_else(|e| SpError::Numerical(e.to_string()))
    };
    let y0 = problem.to_y(&x0);
    let (e0, g0x) = problem.eval_x(&x0).map_err(eval_err)?;
    let (_, g0) = problem.eval(&y0).map_err(eval_err)?;
    let g0n = norm(&g0);
    let n = x0.len();
    let (method, iterations, stop) = if n == 0 {
        ("none", 0, StopReason::NothingToOptimise)
    } else if g0n == 0.0 {
        ("none", 0, StopReason::StationaryStart)
    } else {
        rounds(&problem, &x0, y0, (e0, g0n), opts)?
    };
    let (best, evaluations) = problem.finish();
    let (x, energy, grad_norm) = match best {
        Some(b) => (b.x, b.e, norm(&b.g)),
        None => (x0, e0, norm(&g0x)),
    };
    let stats = RunStats {
        method,
        n_vars: n,
        iterations,
        evaluations,
        initial_energy: e0,
        energy,
        grad_norm,
        stop,
        seconds: started.elapsed().as_secs_f64(),
    };
    Ok((x, stats))
}

/// The quasi-Newton run in rounds of `relinearise_every` iterations: after
/// a round cut short by its budget, the preconditioner is rebuilt at the best
/// point and the next round starts there. Returns the method, the iterations
/// and why it stopped; a line search that cannot progress is a (flagged)
/// stop, cancellation an error.
fn rounds<M: TorqueModel>(
    problem: &Evaluator<'_, '_, M>,
    x0: &[f64],
    mut y_start: Vec<f64>,
    (e0, g0n): (f64, f64),
    opts: &SolveOptions,
) -> Result<(&'static str, u64, StopReason), SpError> {
    let n = x0.len();
    let tol_grad = (opts.grad_rtol * g0n).max(f64::MIN_POSITIVE);
    let tol_cost = (opts.cost_rtol * e0.abs()).max(f64::MIN_POSITIVE);
    let round = opts.relinearise_every.max(1);
    if opts.max_iters == 0 {
        return Ok(("none", 0, StopReason::NothingToOptimise));
    }
    let method = if n <= opts.bfgs_max_vars {
        "BFGS"
    } else {
        "L-BFGS"
    };
    let mut run: Result<(u64, StopReason), Error> = Ok((0, StopReason::NothingToOptimise));
    let stalled = Cell::new(None);
    let history = RefCell::new(vec![(0, e0)]);
    let mut total = 0;
    while total < opts.max_iters {
        let budget = round.min(opts.max_iters - total);
        let stall = Stall {
            start: total,
            window: opts.stall_window.max(1),
            tolerance: opts.tolerance,
            history: &history,
            stalled: &stalled,
            progress: &opts.progress,
            max_iters: opts.max_iters,
        };
        let tolerances = (tol_grad, tol_cost);
        run = one_round(problem, y_start.clone(), budget, stall, tolerances, opts)?;
        let it = run.as_ref().map(|r| r.0).unwrap_or(budget);
        total += it.max(1);
        // only a run cut short by its round's budget continues; convergence,
        // a stuck line search or cancellation end the solve
        let limited = matches!(&run, Ok((_, StopReason::IterationLimit)));
        if !limited || total >= opts.max_iters {
            break;
        }
        let bx = problem.best_x().unwrap_or_else(|| x0.to_vec());
        // re-linearise the preconditioner at the best point and restart there
        problem.relinearise_at(&bx)?;
        y_start = problem.to_y(&bx);
    }
    match run {
        Ok((_, s)) => Ok((method, total, s)),
        Err(_) if opts.cancel.is_cancelled() => Err(SpError::Cancelled),
        // A line search that cannot progress means we are at the precision
        // limit of the objective: keep the best point seen (0 iterations
        // reported, as the run's count is lost with its error).
        Err(e) => Ok((method, 0, StopReason::LineSearch(e.to_string()))),
    }
}

/// One round from `y` with at most `budget` iterations: dense BFGS for few
/// unknowns, L-BFGS for many.
fn one_round<M: TorqueModel>(
    problem: &Evaluator<'_, '_, M>,
    y: Vec<f64>,
    budget: u64,
    stall: Stall<'_>,
    (tol_grad, tol_cost): (f64, f64),
    opts: &SolveOptions,
) -> Result<Result<(u64, StopReason), Error>, SpError> {
    let n = y.len();
    let linesearch = MoreThuenteLineSearch::new();
    let invalid = |e: Error| SpError::Invalid(e.to_string());
    if n <= opts.bfgs_max_vars {
        // In the preconditioned variables the Hessian is about 2·I.
        let s = 0.5;
        let h0: Vec<Vec<f64>> = (0..n)
            .map(|i| (0..n).map(|j| if i == j { s } else { 0.0 }).collect())
            .collect();
        let solver = BFGS::new(linesearch)
            .with_tolerance_grad(tol_grad)
            .and_then(|s| s.with_tolerance_cost(tol_cost))
            .map_err(invalid)?;
        Ok(run_round(problem, solver, stall, |st| {
            st.param(y).inv_hessian(h0).max_iters(budget)
        }))
    } else {
        let solver = LBFGS::new(linesearch, opts.lbfgs_memory.max(1))
            .with_tolerance_grad(tol_grad)
            .and_then(|s| s.with_tolerance_cost(tol_cost))
            .map_err(invalid)?;
        Ok(run_round(problem, solver, stall, |st| {
            st.param(y).max_iters(budget)
        }))
    }
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
