//! Minimise one group's objective by quasi-Newton steps in Gauss–Newton
//! whitened variables y (x = T(y), see [`Precond`]): there the Hessian of e is
//! close to 2·I, so the very first step −∇e/2 is the Gauss–Newton step and the
//! quasi-Newton updates only have to learn the small part of the curvature the
//! Gauss–Newton model misses (the τ·∂²τ terms). Dense BFGS up to
//! `bfgs_max_vars` unknowns, L-BFGS beyond, where (nm)² per step would dominate
//! (Rose §3.2.3). Each evaluation gives cost and gradient in one adjoint pass;
//! the line search is a backtracking Armijo search from the unit step (the
//! natural step length in the whitened variables). The best point seen is
//! kept, and a `CancelToken` is polled at every evaluation.

use super::error::SpError;
use super::objective::{Objective, Scratch};
use super::precond::Precond;
use super::torque::TorqueModel;
use crate::cancel::CancelToken;
use nalgebra::{DMatrix, DVector};
use std::collections::VecDeque;
use std::time::Instant;

/// Solver settings (not the transition's shape: see `TransitionSettings`).
#[derive(Clone, Debug)]
pub struct SolveOptions {
    pub max_iters: u64,
    /// Stop when ‖∇e‖ (in the whitened variables) falls below this fraction of its value at the start.
    pub grad_rtol: f64,
    /// Stop when an iteration lowers e by less than this fraction of e.
    pub cost_rtol: f64,
    /// Use dense BFGS up to this many unknowns, L-BFGS above.
    pub bfgs_max_vars: usize,
    pub cancel: CancelToken,
    /// Stop when the decrease of e still to come, as the Gauss–Newton model
    /// predicts it (‖∂e/∂y‖²/4 in the whitened variables), is below this
    /// fraction of e: the energy is then that close to its minimum.
    pub decrease_rtol: f64,
}

impl Default for SolveOptions {
    fn default() -> Self {
        // Measured on the 44-DOF Fig. 8 gap (benches/spacetime.rs): these
        // stop within 1e-6 of the converged energy in a dozen iterations;
        // tighter ones only polish digits no table reads.
        SolveOptions {
            max_iters: 300,
            grad_rtol: 1e-6,
            cost_rtol: 1e-12,
            bfgs_max_vars: 1000,
            cancel: CancelToken::new(),
            decrease_rtol: 1e-7,
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
    pub stop: String,
    pub seconds: f64,
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

/// The objective in the whitened variables y, counting evaluations.
struct Whitened<'o, 'a, M: TorqueModel> {
    obj: &'o Objective<'a, M>,
    t: Precond,
    scratch: Scratch<M::Workspace>,
    evals: u64,
    cancel: CancelToken,
}

impl<M: TorqueModel> Whitened<'_, '_, M> {
    /// e and ∂e/∂y = Tᵀ ∂e/∂x at y.
    fn eval(&mut self, y: &DVector<f64>) -> Result<(f64, DVector<f64>), SpError> {
        self.cancel.check()?;
        let x = self.t.apply(y.as_slice());
        let mut g = vec![0.0; x.len()];
        let e = self.obj.eval(&mut self.scratch, &x, Some(&mut g))?;
        self.evals += 1;
        Ok((e, DVector::from_vec(self.t.apply_t(&g))))
    }
}

/// The inverse-Hessian model of the quasi-Newton iteration (in y, where the
/// Gauss–Newton Hessian is 2·I, hence the starting inverse I/2).
enum Curvature {
    Dense(DMatrix<f64>),
    /// The last (s, Δg, 1/sᵀΔg) pairs, oldest first.
    Limited(VecDeque<(DVector<f64>, DVector<f64>, f64)>),
}

/// Pairs kept by L-BFGS.
const LBFGS_MEMORY: usize = 20;

impl Curvature {
    fn new(n: usize, dense: bool) -> Self {
        if dense {
            Curvature::Dense(DMatrix::identity(n, n) * 0.5)
        } else {
            Curvature::Limited(VecDeque::new())
        }
    }

    /// The quasi-Newton direction −H⁻¹g.
    fn direction(&self, g: &DVector<f64>) -> DVector<f64> {
        match self {
            Curvature::Dense(h) => -(h * g),
            Curvature::Limited(pairs) => {
                // two-loop recursion with the initial inverse I/2
                let mut q = g.clone();
                let mut alphas = Vec::with_capacity(pairs.len());
                for (s, y, rho) in pairs.iter().rev() {
                    let a = rho * s.dot(&q);
                    q.axpy(-a, y, 1.0);
                    alphas.push(a);
                }
                q *= 0.5;
                for ((s, y, rho), a) in pairs.iter().zip(alphas.iter().rev()) {
                    let b = rho * y.dot(&q);
                    q.axpy(a - b, s, 1.0);
                }
                -q
            }
        }
    }

    /// BFGS update with step s and gradient change y; skipped when sᵀy is not
    /// safely positive (the curvature condition fails, e.g. after a short backtracked step).
    fn update(&mut self, s: DVector<f64>, y: DVector<f64>) {
        let sy = s.dot(&y);
        if sy.is_nan() || sy <= 1e-12 * s.norm() * y.norm() {
            return;
        }
        match self {
            Curvature::Dense(h) => {
                let hy = &*h * &y;
                let yhy = y.dot(&hy);
                let c = (sy + yhy) / (sy * sy);
                // H ← H + c s sᵀ − (Hy sᵀ + s (Hy)ᵀ)/sᵀy
                h.ger(c, &s, &s, 1.0);
                h.ger(-1.0 / sy, &hy, &s, 1.0);
                h.ger(-1.0 / sy, &s, &hy, 1.0);
            }
            Curvature::Limited(pairs) => {
                if pairs.len() == LBFGS_MEMORY {
                    pairs.pop_front();
                }
                pairs.push_back((s, y, 1.0 / sy));
            }
        }
    }
}

/// Armijo's sufficient-decrease constant.
const ARMIJO: f64 = 1e-4;
/// Backtracking steps before the line search gives up.
const MAX_BACKTRACKS: usize = 30;

/// Curvature constant of the (weak) Wolfe condition.
const WOLFE: f64 = 0.9;
/// Step growth while extrapolating.
const GROW: f64 = 4.0;

/// A point along d from y with sufficient decrease (Armijo) and, when it can
/// be had by extrapolating, the Wolfe curvature condition. Why extrapolate:
/// ∫Στ² is not convex (a limb held out against gravity has torque² falling
/// either way), so along directions of negative curvature the Gauss–Newton
/// unit step is far too short and a backtracking-only search would crawl.
#[allow(clippy::type_complexity)]
fn line_search<M: TorqueModel>(
    f: &mut Whitened<'_, '_, M>,
    y: &DVector<f64>,
    e: f64,
    d: &DVector<f64>,
    slope: f64,
) -> Result<Option<(DVector<f64>, f64, DVector<f64>)>, SpError> {
    let mut alpha = 1.0;
    let mut best: Option<(DVector<f64>, f64, DVector<f64>)> = None;
    for _ in 0..MAX_BACKTRACKS {
        let yt = y + d * alpha;
        let (et, gt) = f.eval(&yt)?;
        let armijo = et.is_finite() && et <= e + ARMIJO * alpha * slope;
        if armijo {
            let better = best.as_ref().is_none_or(|b| et < b.1);
            let curved = gt.dot(d) >= WOLFE * slope;
            if better {
                best = Some((yt, et, gt));
            }
            if curved || !better {
                return Ok(best);
            }
            alpha *= GROW; // still falling steeply: go further
            continue;
        }
        if best.is_some() {
            // overshot while extrapolating: keep the last good point
            return Ok(best);
        }
        // minimiser of the quadratic through e, slope and et, kept in [α/10, α/2]
        let denom = 2.0 * (et - e - slope * alpha);
        let next = if et.is_finite() && denom > 0.0 {
            -slope * alpha * alpha / denom
        } else {
            0.1 * alpha
        };
        alpha = next.clamp(0.1 * alpha, 0.5 * alpha);
    }
    Ok(best)
}

/// Minimise the objective from the Hermite start.
pub fn solve_group<M: TorqueModel>(
    obj: &Objective<'_, M>,
    opts: &SolveOptions,
) -> Result<GroupSolution, SpError> {
    let started = Instant::now();
    opts.cancel.check()?;
    let x0 = obj.hermite_start();
    let n = x0.len();
    let mut scratch = obj.scratch();
    let t = if n > 0 {
        obj.preconditioner(&mut scratch)?
    } else {
        Precond::Identity
    };
    let mut f = Whitened {
        obj,
        t,
        scratch,
        evals: 0,
        cancel: opts.cancel.clone(),
    };
    let mut y = DVector::from_vec(f.t.solve(&x0));
    let (e0, g0) = f.eval(&y)?;
    let g0n = g0.norm();
    let (mut e, mut g) = (e0, g0);
    let mut iterations = 0;
    let dense = n <= opts.bfgs_max_vars;
    let method = match (n, dense) {
        (0, _) => "none",
        (_, true) => "BFGS",
        (_, false) => "L-BFGS",
    };
    let mut stop = if n == 0 {
        String::from("nothing to optimise (coefficients: 0)")
    } else {
        String::from("iteration limit reached")
    };
    let mut curvature = Curvature::new(n, dense);
    loop {
        if n == 0 {
            break;
        }
        let gn = g.norm();
        if gn == 0.0 {
            stop = if iterations == 0 {
                "converged (the Hermite start is stationary)".into()
            } else {
                "converged (zero gradient)".into()
            };
            break;
        }
        if gn <= opts.grad_rtol * g0n {
            stop = "converged (gradient)".into();
            break;
        }
        if 0.25 * gn * gn <= opts.decrease_rtol * e.abs() {
            stop = "converged (predicted decrease)".into();
            break;
        }
        if iterations >= opts.max_iters {
            break;
        }
        let mut d = curvature.direction(&g);
        let mut slope = g.dot(&d);
        if slope.is_nan() || slope >= 0.0 {
            // the model lost positive definiteness (rounding): restart from the Gauss–Newton model
            curvature = Curvature::new(n, dense);
            d = curvature.direction(&g);
            slope = g.dot(&d);
        }
        let Some((yt, et, gt)) = line_search(&mut f, &y, e, &d, slope)? else {
            // no decrease along a descent direction: the objective's rounding floor
            stop = "converged (no further decrease representable)".into();
            break;
        };
        iterations += 1;
        let decrease = e - et;
        curvature.update(&yt - &y, &gt - &g);
        y = yt;
        e = et;
        g = gt;
        if decrease <= opts.cost_rtol * e.abs() {
            stop = "converged (cost change)".into();
            break;
        }
    }
    let x = f.t.apply(y.as_slice());
    // ‖∂e/∂x‖ for the report (the solver's own test is in y)
    let mut gx = vec![0.0; n];
    let energy = if n > 0 {
        obj.eval(&mut f.scratch, &x, Some(&mut gx))?
    } else {
        e
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
        evaluations: f.evals,
        initial_energy: e0,
        energy,
        grad_norm: gx.iter().map(|v| v * v).sum::<f64>().sqrt(),
        stop,
        seconds: started.elapsed().as_secs_f64(),
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
            // stop on the gradient only: this test asks for a stationary point
            let opts = SolveOptions {
                bfgs_max_vars: 40,
                decrease_rtol: 0.0,
                ..Default::default()
            };
            let sol = solve_group(&obj, &opts).unwrap();
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
        g.iter().map(|v| v * v).sum::<f64>().sqrt()
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
