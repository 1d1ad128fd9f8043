//! Motion cyclification (Rose §3.3) and looping.
//!
//! The user marks the approximate start and end of a cycle. In two windows
//! centred on the marks, each a fifth of the period long, we find the pair of
//! times (t₁, t₂) minimising ‖[q, q̇, q̈](t₁) − [q, q̇, q̈](t₂)‖ over all DOFs;
//! the remaining jump Δ = q(t₂) − q(t₁) of each DOF is spread linearly over
//! the cycle, and a least-squares cubic B-spline is fitted with the three
//! cyclic constraints q, q̇, q̈(t₂) = q, q̇, q̈(t₁) (+ Δ for drifting DOFs),
//! so the loop is C² by construction.
//!
//! Drifting DOFs (the root's horizontal position in a walk) keep their
//! advance per cycle: only their velocity and acceleration are made cyclic,
//! and `loop_motion` continues them by that advance on every repetition.

use super::{Curve, Dof, Func, Interval, MotionError, Mu, sample_period, time_tol};
use crate::spline::{BSplineBasis, BSplineCurve};
use nalgebra::{DMatrix, DVector, Dyn, LU};

/// Why a motion could not be cyclified or looped.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CyclifyError {
    /// Bad marks, options or motion given by the user.
    #[error("{0}")]
    Invalid(String),
    /// The motion could not be sampled or fitted.
    #[error("{0}")]
    Evaluation(String),
}

fn invalid(msg: impl Into<String>) -> CyclifyError {
    CyclifyError::Invalid(msg.into())
}

/// Options of `cyclify`.
#[derive(Clone, Debug)]
pub struct CyclifyOptions {
    /// DOFs that advance by a fixed amount per cycle (e.g. `Hips.Xposition`).
    pub drift: Vec<String>,
    /// Knot spacing of the fitted spline (s): detail finer than this is smoothed.
    pub knot_spacing: f64,
    /// Grid step of the search for (t₁, t₂) (s); `None`: the clip's frame time, else 1/120 s.
    pub search_step: Option<f64>,
}

impl Default for CyclifyOptions {
    fn default() -> Self {
        CyclifyOptions {
            drift: vec![],
            knot_spacing: 1.0 / 30.0,
            search_step: None,
        }
    }
}

/// The DOFs of a y-up clip that advance in the floor plane: every
/// `*Xposition` and `*Zposition` (a walk's root keeps its advance per cycle).
pub fn floor_drift(m: &Mu) -> Vec<String> {
    m.names()
        .filter(|n| n.ends_with("Xposition") || n.ends_with("Zposition"))
        .map(str::to_string)
        .collect()
}

/// What cyclify chose.
#[derive(Clone, Debug, PartialEq)]
pub struct CyclifyReport {
    pub t1: f64,
    pub t2: f64,
    /// ‖a − b‖ at the marks and at the chosen pair.
    pub distance_at_marks: f64,
    pub distance: f64,
    /// Largest |Δq| spread over the cycle, and its DOF.
    pub max_jump: (String, f64),
    /// Per drifting DOF: its advance per cycle.
    pub drift: Vec<(String, f64)>,
    pub coefficients: usize,
}

fn motion_err(e: MotionError) -> CyclifyError {
    CyclifyError::Evaluation(e.to_string())
}

fn state(m: &Mu, name: &str, t: f64) -> Result<[f64; 3], CyclifyError> {
    m.sample(name, t).map_err(motion_err)?.ok_or_else(|| {
        invalid(format!(
            "cyclify: DOF '{name}' is undefined at t = {t:.4}; the cycle and its search windows must lie where every DOF is defined"
        ))
    })
}

/// `cyclify(m, t_start, t_end)`: one C² cycle of `m` on [t₁, t₂] ≈ [t_start, t_end].
pub fn cyclify(
    m: &Mu,
    t_start: f64,
    t_end: f64,
    opts: &CyclifyOptions,
) -> Result<(Mu, CyclifyReport), CyclifyError> {
    let span = check_cyclify(m, t_start, t_end, opts)?;
    let names: Vec<String> = m.dofs.keys().cloned().collect();
    let drift: Vec<bool> = names.iter().map(|n| opts.drift.contains(n)).collect();
    let cycle = find_cycle(m, &names, &drift, (t_start, t_end), span, opts)?;
    let (t1, t2) = (cycle.t1, cycle.t2);
    let fit = CyclicFit::new(t1, t2, opts.knot_spacing, cycle.step)?;
    let mut out = Mu::new();
    let mut max_jump = (String::new(), 0.0f64);
    let mut drifts = vec![];
    for (name, &drifts_on) in names.iter().zip(&drift) {
        let delta = state(m, name, t2)?[0] - state(m, name, t1)?[0];
        if drifts_on {
            drifts.push((name.clone(), delta));
        } else if delta.abs() > max_jump.1.abs() {
            max_jump = (name.clone(), delta);
        }
        let curve = fit.fit_dof(m, name, delta, drifts_on)?;
        let iv = Interval::curve(Curve::Spline(curve), t1, t2).map_err(motion_err)?;
        out.insert(name.clone(), Dof::from(iv));
    }
    Ok((
        out,
        CyclifyReport {
            t1,
            t2,
            distance_at_marks: cycle.distance_at_marks,
            distance: cycle.distance,
            max_jump,
            drift: drifts,
            coefficients: fit.n_coef,
        },
    ))
}

/// The arguments of [`cyclify`] checked; the motion's span.
fn check_cyclify(
    m: &Mu,
    t_start: f64,
    t_end: f64,
    opts: &CyclifyOptions,
) -> Result<(f64, f64), CyclifyError> {
    if !(t_start.is_finite() && t_end.is_finite()) || t_end <= t_start {
        return Err(invalid(format!(
            "cyclify({t_start}, {t_end}): the cycle must have t_start < t_end (mark the approximate start and end of one cycle)"
        )));
    }
    if m.is_empty() {
        return Err(invalid("cyclify of an empty motion"));
    }
    for d in &opts.drift {
        if m.get(d).is_none() {
            return Err(invalid(format!(
                "cyclify: drift DOF '{d}' is not in the motion"
            )));
        }
    }
    if !(opts.knot_spacing.is_finite() && opts.knot_spacing > 0.0) {
        return Err(invalid(
            "cyclify: knot spacing must be a positive number of seconds",
        ));
    }
    m.span()
        .ok_or_else(|| invalid("cyclify of an empty motion"))
}

/// The cycle found near the marks.
struct Cycle {
    t1: f64,
    t2: f64,
    /// ‖a − b‖ at the chosen pair and at the marks.
    distance: f64,
    distance_at_marks: f64,
    /// The search grid's step, also the fit's sampling step.
    step: f64,
}

/// In windows of a fifth of the period centred on the marks, the pair of times
/// (t₁, t₂), at least half a period apart, where the states [q, q̇, q̈] of all
/// DOFs are closest (a drifting DOF's position is left out).
fn find_cycle(
    m: &Mu,
    names: &[String],
    drift: &[bool],
    (t_start, t_end): (f64, f64),
    (s0, s1): (f64, f64),
    opts: &CyclifyOptions,
) -> Result<Cycle, CyclifyError> {
    let period = t_end - t_start;
    let half = period / 10.0;
    let win = |c: f64| ((c - half).max(s0), (c + half).min(s1));
    let (ws, wf) = (win(t_start), win(t_end));
    if ws.1 < ws.0 || wf.1 < wf.0 {
        return Err(invalid(format!(
            "cyclify({t_start}, {t_end}): the marks must lie inside the motion's span [{s0}, {s1}]"
        )));
    }
    let step = opts
        .search_step
        .or_else(|| sample_period(m))
        .unwrap_or(1.0 / 120.0)
        .max(period / 2000.0);
    let grid = |(a, b): (f64, f64)| -> Vec<f64> {
        let n = ((b - a) / step).floor() as usize;
        let mut v: Vec<f64> = (0..=n).map(|k| a + k as f64 * step).collect();
        if v.is_empty() {
            v.push(a);
        }
        v
    };
    let states = |ts: &[f64]| -> Result<Vec<Vec<[f64; 3]>>, CyclifyError> {
        ts.iter()
            .map(|&t| names.iter().map(|n| state(m, n, t)).collect())
            .collect()
    };
    let (gs, gf) = (grid(ws), grid(wf));
    let (ss, sf) = (states(&gs)?, states(&gf)?);
    let dist = |a: &[[f64; 3]], b: &[[f64; 3]]| -> f64 {
        let mut s = 0.0;
        for (i, (x, y)) in a.iter().zip(b).enumerate() {
            // a drifting DOF's position is not expected to repeat
            let from = if drift[i] { 1 } else { 0 };
            for k in from..3 {
                s += (x[k] - y[k]).powi(2);
            }
        }
        s.sqrt()
    };
    let mut best = (f64::INFINITY, 0, 0);
    for (i, a) in ss.iter().enumerate() {
        for (j, b) in sf.iter().enumerate() {
            if gf[j] - gs[i] < 0.5 * period {
                continue;
            }
            let d = dist(a, b);
            if d < best.0 {
                best = (d, i, j);
            }
        }
    }
    if !best.0.is_finite() {
        return Err(invalid(
            "cyclify: no pair of times found in the search windows",
        ));
    }
    let marks = dist(&states(&[t_start])?[0], &states(&[t_end])?[0]);
    Ok(Cycle {
        t1: gs[best.1],
        t2: gf[best.2],
        distance: best.0,
        distance_at_marks: marks,
        step,
    })
}

/// The least-squares fit of a clamped uniform cubic B-spline on [t₁, t₂] with
/// the three cyclic constraints q, q̇, q̈(t₂) − q, q̇, q̈(t₁) = (advance, 0, 0):
/// one KKT system, factorised once and shared by every DOF.
struct CyclicFit {
    t1: f64,
    p: f64,
    n_coef: usize,
    basis: BSplineBasis,
    /// sample times and the design matrix of the fit there
    ts: Vec<f64>,
    a: DMatrix<f64>,
    kkt: LU<f64, Dyn, Dyn>,
}

impl CyclicFit {
    fn new(t1: f64, t2: f64, knot_spacing: f64, step: f64) -> Result<Self, CyclifyError> {
        let p = t2 - t1;
        let n_coef = ((p / knot_spacing).round() as usize + 3).max(7);
        let basis = BSplineBasis::clamped_uniform(3, n_coef, t1, t2)
            .map_err(|e| invalid(format!("cyclify basis: {e}")))?;
        let n_samples = (4 * n_coef).max(((p / step).round() as usize) + 1);
        let ts: Vec<f64> = (0..n_samples)
            .map(|k| t1 + p * k as f64 / (n_samples - 1) as f64)
            .collect();
        let mut a = DMatrix::<f64>::zeros(n_samples, n_coef);
        let mut nz = [[0.0; 6]; 3];
        for (r, &t) in ts.iter().enumerate() {
            let first = basis.eval_nonzero(t, 0, &mut nz);
            for i in 0..4 {
                a[(r, basis.index(first, i))] += nz[0][i];
            }
        }
        // constraint rows: B^(d)(t2) − B^(d)(t1), d = 0, 1, 2
        let mut c = DMatrix::<f64>::zeros(3, n_coef);
        for (t, sign) in [(t2, 1.0), (t1, -1.0)] {
            let first = basis.eval_nonzero(t, 2, &mut nz);
            for d in 0..3 {
                for i in 0..4 {
                    c[(d, basis.index(first, i))] += sign * nz[d][i];
                }
            }
        }
        let ata = a.transpose() * &a;
        let mut kkt = DMatrix::<f64>::zeros(n_coef + 3, n_coef + 3);
        kkt.view_mut((0, 0), (n_coef, n_coef)).copy_from(&ata);
        kkt.view_mut((n_coef, 0), (3, n_coef)).copy_from(&c);
        kkt.view_mut((0, n_coef), (n_coef, 3))
            .copy_from(&c.transpose());
        Ok(CyclicFit {
            t1,
            p,
            n_coef,
            basis,
            ts,
            a,
            kkt: kkt.lu(),
        })
    }

    /// The cyclic curve of DOF `name`, whose values at t₂ and t₁ differ by
    /// `delta`: a drifting DOF keeps that advance, any other has it spread
    /// linearly over the cycle (so its loop closes).
    fn fit_dof(
        &self,
        m: &Mu,
        name: &str,
        delta: f64,
        drifts: bool,
    ) -> Result<BSplineCurve, CyclifyError> {
        let (n_coef, t1, p) = (self.n_coef, self.t1, self.p);
        let mut y = DVector::<f64>::zeros(self.ts.len());
        for (r, &t) in self.ts.iter().enumerate() {
            let q = m
                .sample_value(name, t)
                .map_err(motion_err)?
                .ok_or_else(|| {
                    invalid(format!(
                        "cyclify: DOF '{name}' is undefined at t = {t:.4} inside the cycle"
                    ))
                })?;
            // spread the jump linearly unless the DOF drifts
            y[r] = if drifts { q } else { q - delta * (t - t1) / p };
        }
        let advance = if drifts { delta } else { 0.0 };
        let mut rhs = DVector::<f64>::zeros(n_coef + 3);
        rhs.rows_mut(0, n_coef)
            .copy_from(&(self.a.transpose() * &y));
        rhs[n_coef] = advance;
        let sol = self.kkt.solve(&rhs).ok_or_else(|| {
            CyclifyError::Evaluation(
                "cyclify: the constrained fit is singular (cycle too short?)".into(),
            )
        })?;
        let coeffs: Vec<f64> = sol.rows(0, n_coef).iter().copied().collect();
        if coeffs.iter().any(|v| !v.is_finite()) {
            return Err(CyclifyError::Evaluation(format!(
                "cyclify: the fit of '{name}' is not finite"
            )));
        }
        BSplineCurve::new(self.basis.clone(), coeffs)
            .map_err(|e| CyclifyError::Evaluation(e.to_string()))
    }
}

/// `loop(m, n)`: a cyclified motion (one interval per DOF) repeated n times.
/// A DOF whose cycle ends higher than it starts (a drifting root) continues
/// from where the previous repetition ended.
pub fn loop_motion(m: &Mu, n: usize) -> Result<Mu, CyclifyError> {
    if n == 0 {
        return Err(invalid("loop(m, 0): repeat at least once"));
    }
    if n > 100_000 {
        return Err(invalid(format!("loop(m, {n}): too many repetitions")));
    }
    let mut out = Mu::new();
    for (name, dof) in &m.dofs {
        let [iv] = dof.intervals.as_slice() else {
            return Err(invalid(format!(
                "loop: DOF '{name}' has {} intervals; loop a cyclified motion (cyclify(m, ts, te)), which has one per DOF",
                dof.intervals.len()
            )));
        };
        let [f] = iv.funcs.as_slice() else {
            return Err(invalid(format!(
                "loop: DOF '{name}' is multiply defined (a conflict)"
            )));
        };
        let p = iv.stop - iv.start;
        let start = f.eval(iv.start).map_err(motion_err)?;
        let end = f.eval(iv.stop).map_err(motion_err)?;
        let advance = end[0] - start[0];
        let tol = 1e-6 * (1.0 + start[1].abs() + start[2].abs());
        if (end[1] - start[1]).abs() > tol || (end[2] - start[2]).abs() > 1e3 * tol {
            return Err(invalid(format!(
                "loop: DOF '{name}' is not cyclic (velocity {:.4} → {:.4}); cyclify it first",
                start[1], end[1]
            )));
        }
        let mut d = Dof::empty();
        for k in 0..n {
            let shifted = f.affine(k as f64 * p, 1.0);
            let g = Func {
                offset: shifted.offset + k as f64 * advance,
                ..shifted
            };
            let piece = Interval::new(g, iv.start + k as f64 * p, iv.stop + k as f64 * p)
                .map_err(motion_err)?;
            d = d.plus(&Dof::from(piece));
        }
        if d.intervals.len() != n && p > time_tol(p) {
            return Err(CyclifyError::Evaluation(format!(
                "loop: DOF '{name}' did not repeat cleanly"
            )));
        }
        out.insert(name.clone(), d);
    }
    Ok(out)
}
