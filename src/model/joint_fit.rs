//! Designing spline curve joints from sampled motion (paper §6.2–6.3).
//!
//! Fitting (eq. 32–36): control frames move with body velocities ǔ_j; the
//! joint's velocity at a sample is approximated by eq. (34),
//!   u(q) ≈ Σ_i B_{f+i}(q) Ad⁻¹_{E_{i+1}⋯E_p} ǔ_{f+i},  E_i = exp(ẑ_{f+i} B̃_{f+i}(q)),
//! which stacks into the banded system M ǔ = u_d with u_d^k = log(G(q^k)⁻¹ G_d^k).
//! Each iteration solves it in the least-squares sense (normal equations,
//! block-banded, assembled per sample) and moves Ǧ_j ← Ǧ_j exp(ǔ_j). A
//! backtracking step keeps the objective decreasing.
//!
//! Smoothing (eq. 37–42): the joint Hessian h(q^k) = ∇S is driven towards
//! zero by also solving N ǔ ≈ −c h with weight w:
//!   ((1−w) MᵀM + w NᵀN) ǔ = (1−w) Mᵀ u_d − c w Nᵀ h.
//! N = ∂h/∂ǔ is computed by central differences of the exact Hessian in the
//! frame velocities (the paper notes numerical differentiation "is simple and
//! effective"; we differentiate h directly rather than the N'_j of eq. 39–41).
//!
//! Knots: clamped cubic on the samples' q range, interior knots either uniform
//! in q or "natural" — at equal steps of the accumulated twist length
//! Σ‖log(G_k⁻¹G_{k+1})‖ of the samples (§6.1 with the erratum: no square),
//! mapped back to q, so busy parts of the motion get more knots.

use super::joints::JointSamples;
use super::joints::SplineCurveJoint;
use super::joints::error::{JointSpecError, jerr};
use crate::lie::{Se3, Twist, exp_se3, log_se3, rotation_angle};
use crate::model::joint::{Derivatives, Joint, JointKinematics};
use crate::spline::BSplineBasis;
use nalgebra::{DMatrix, DVector, Matrix6};
use std::f64::consts::PI;

/// Where the interior knots go.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KnotPlacement {
    Uniform,
    Natural,
}

#[derive(Debug, Clone)]
pub struct FitOptions {
    /// Number of control frames (≥ 4).
    pub frames: usize,
    /// Smoothing weight w in [0, 1): 0 fits only the data.
    pub smooth: f64,
    /// c of ḣ_d = −c h (0 < c ≤ 1).
    pub smooth_rate: f64,
    pub knots: KnotPlacement,
    pub max_iterations: usize,
    /// Stop when the objective decreases by less than this fraction in an iteration.
    pub tolerance: f64,
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions {
            frames: 8,
            smooth: 0.0,
            smooth_rate: 1.0,
            knots: KnotPlacement::Uniform,
            max_iterations: 100,
            tolerance: 1e-12,
        }
    }
}

#[derive(Debug, Clone)]
pub struct FitReport {
    pub joint: SplineCurveJoint,
    pub iterations: usize,
    /// Σ‖log(G⁻¹G_d)‖² at the end.
    pub data_residual: f64,
    /// Σ‖∇S(q^k)‖² at the samples at the end.
    pub hessian_sum: f64,
}

/// Fits a cubic spline curve joint to the samples.
pub fn fit_spline_joint(
    samples: &JointSamples,
    opt: &FitOptions,
) -> Result<FitReport, JointSpecError> {
    let n = opt.frames;
    if n < 4 {
        return jerr(format!(
            "a cubic spline joint needs at least 4 control frames, got {n}"
        ));
    }
    if !(opt.smooth.is_finite() && (0.0..1.0).contains(&opt.smooth)) {
        return jerr(format!(
            "smoothing weight must be in [0, 1), got {}",
            opt.smooth
        ));
    }
    if !(opt.smooth_rate > 0.0 && opt.smooth_rate <= 1.0) {
        return jerr(format!(
            "smoothing rate c must be in (0, 1], got {}",
            opt.smooth_rate
        ));
    }
    for (k, w) in samples.transforms.windows(2).enumerate() {
        if rotation_angle(&w[0].inv_compose(&w[1]).r) > PI - 1e-6 {
            return jerr(format!(
                "samples {k} and {} are π or more apart in rotation: the motion between them is ambiguous; sample more densely",
                k + 1
            ));
        }
    }
    if samples.len() < n {
        return jerr(format!(
            "{} samples cannot determine {n} control frames: use fewer frames",
            samples.len()
        ));
    }
    let basis = fit_basis(samples, n, opt.knots)?;
    // initial frames: the sampled motion at the Greville abscissae
    let k = basis.knots();
    let frames: Vec<Se3> = (0..n)
        .map(|j| interpolate(samples, (k[j + 1] + k[j + 2] + k[j + 3]) / 3.0))
        .collect();
    let mut joint = SplineCurveJoint::new(frames, basis)?;
    let w = opt.smooth;
    let mut e = objective(&joint, samples, w);
    let mut iterations = 0;
    for _ in 0..opt.max_iterations {
        iterations += 1;
        let step = solve_step(&joint, samples, opt)?;
        // backtracking: accept the largest of 1, ½, ¼, … that lowers the objective
        let mut t = 1.0;
        let mut accepted = None;
        for _ in 0..12 {
            let frames: Vec<Se3> = joint
                .frames()
                .iter()
                .enumerate()
                .map(|(j, g)| g.compose(&exp_se3(&(step[j] * t))))
                .collect();
            let mut cand = joint.clone();
            if cand.set_frames(frames).is_ok() {
                let ec = objective(&cand, samples, w);
                if ec < e {
                    accepted = Some((cand, ec));
                    break;
                }
            }
            t *= 0.5;
        }
        let Some((cand, ec)) = accepted else { break };
        let rel = (e - ec) / e.max(f64::MIN_POSITIVE);
        joint = cand;
        e = ec;
        if rel < opt.tolerance {
            break;
        }
    }
    joint.check_jacobian(1e-9)?;
    Ok(FitReport {
        data_residual: data_residual(&joint, samples),
        hessian_sum: hessian_sum(&joint, samples),
        joint,
        iterations,
    })
}

/// Clamped cubic basis with `n` coefficients on the samples' q range.
fn fit_basis(
    s: &JointSamples,
    n: usize,
    placement: KnotPlacement,
) -> Result<BSplineBasis, JointSpecError> {
    let (a, b) = s.range();
    let map = |e: crate::spline::SplineError| JointSpecError(format!("knots: {e}"));
    match placement {
        KnotPlacement::Uniform => BSplineBasis::clamped_uniform(3, n, a, b).map_err(map),
        KnotPlacement::Natural => {
            // cumulative twist length along the samples, then q at equal fractions of it
            let mut d = vec![0.0];
            for w in s.transforms.windows(2) {
                let last = *d.last().unwrap_or(&0.0);
                d.push(last + log_se3(&w[0].inv_compose(&w[1])).norm());
            }
            let total = *d.last().unwrap_or(&0.0);
            if total <= 0.0 {
                return jerr("the samples do not move: nothing to fit");
            }
            let spans = n - 3;
            let mut knots = vec![a; 4];
            for i in 1..spans {
                let target = total * i as f64 / spans as f64;
                let k = d.partition_point(|&x| x < target).clamp(1, d.len() - 1);
                let f = (target - d[k - 1]) / (d[k] - d[k - 1]).max(f64::MIN_POSITIVE);
                knots.push(s.q[k - 1] + f * (s.q[k] - s.q[k - 1]));
            }
            knots.extend([b; 4]);
            BSplineBasis::new(3, knots).map_err(map)
        }
    }
}

/// The sampled motion at t, by geodesic interpolation between neighbours.
fn interpolate(s: &JointSamples, t: f64) -> Se3 {
    let k = s.q.partition_point(|&x| x <= t).clamp(1, s.q.len() - 1);
    let (q0, q1) = (s.q[k - 1], s.q[k]);
    let f = ((t - q0) / (q1 - q0)).clamp(0.0, 1.0);
    let g0 = s.transforms[k - 1];
    g0.compose(&exp_se3(&(log_se3(&g0.inv_compose(&s.transforms[k])) * f)))
}

fn residuals(joint: &SplineCurveJoint, s: &JointSamples) -> Vec<Twist> {
    let mut k = JointKinematics::default();
    s.q.iter()
        .zip(&s.transforms)
        .map(|(q, gd)| {
            joint.kinematics(&[*q], Derivatives::Transform, &mut k);
            log_se3(&k.transform.inv_compose(gd))
        })
        .collect()
}

fn hessians(joint: &SplineCurveJoint, s: &JointSamples) -> Vec<Twist> {
    let mut k = JointKinematics::default();
    s.q.iter()
        .map(|q| {
            joint.kinematics(&[*q], Derivatives::Hessian, &mut k);
            k.ds[0][0]
        })
        .collect()
}

fn data_residual(joint: &SplineCurveJoint, s: &JointSamples) -> f64 {
    residuals(joint, s).iter().map(|r| r.norm_squared()).sum()
}

fn hessian_sum(joint: &SplineCurveJoint, s: &JointSamples) -> f64 {
    hessians(joint, s).iter().map(|h| h.norm_squared()).sum()
}

fn objective(joint: &SplineCurveJoint, s: &JointSamples, w: f64) -> f64 {
    let d = data_residual(joint, s);
    if w > 0.0 {
        (1.0 - w) * d + w * hessian_sum(joint, s)
    } else {
        d
    }
}

/// One step ǔ (one twist per control frame).
fn solve_step(
    joint: &SplineCurveJoint,
    s: &JointSamples,
    opt: &FitOptions,
) -> Result<Vec<Twist>, JointSpecError> {
    let (chol, rhs, _) = normal_equations(joint, s, opt)?;
    let n = joint.basis().n_coeffs();
    let x = chol.solve(&rhs);
    Ok((0..n)
        .map(|j| Twist::from_iterator(x.rows(6 * j, 6).iter().copied()))
        .collect())
}

type Factor = nalgebra::linalg::Cholesky<f64, nalgebra::Dyn>;

/// The factored system ((1−w) MᵀM + w NᵀN) ǔ = rhs of one step, and its
/// data part (1−w) MᵀM (for the trace of the influence matrix).
fn normal_equations(
    joint: &SplineCurveJoint,
    s: &JointSamples,
    opt: &FitOptions,
) -> Result<(Factor, DVector<f64>, DMatrix<f64>), JointSpecError> {
    let basis = joint.basis();
    let p = basis.degree();
    let n = basis.n_coeffs();
    let dim = 6 * n;
    let mut a = DMatrix::<f64>::zeros(dim, dim);
    let mut rhs = DVector::<f64>::zeros(dim);
    let w = opt.smooth;
    let ud = residuals(joint, s);
    let frames = joint.frames();
    let twists: Vec<Twist> = frames
        .windows(2)
        .map(|f| log_se3(&f[0].inv_compose(&f[1])))
        .collect();
    let mut b = [[0.0; 6]; 3];
    for (k, &q) in s.q.iter().enumerate() {
        let first = basis.eval_nonzero(q, 0, &mut b);
        // E_i = exp(ẑ_{f+i} B̃_{f+i}), i = 1..p
        let mut e = [Se3::identity(); 6];
        let mut acc = 0.0;
        for i in (1..=p).rev() {
            acc += b[0][i];
            e[i] = exp_se3(&(twists[first + i - 1] * acc));
        }
        // blocks C_i = B_{f+i} Ad⁻¹_{E_{i+1}⋯E_p}
        let mut blocks = [Matrix6::<f64>::zeros(); 6];
        let mut tail = Se3::identity();
        for i in (0..=p).rev() {
            blocks[i] = tail.inverse().ad_matrix() * b[0][i];
            if i >= 1 {
                tail = e[i].compose(&tail);
            }
        }
        for i in 0..=p {
            let ci = blocks[i].transpose() * (1.0 - w);
            let r = ci * ud[k];
            let mut rv = rhs.rows_mut(6 * (first + i), 6);
            rv += r;
            for (j, bj) in blocks.iter().enumerate().take(p + 1) {
                let m = ci * bj;
                let mut v = a.view_mut((6 * (first + i), 6 * (first + j)), (6, 6));
                v += m;
            }
        }
    }
    let data_part = a.clone();
    if w > 0.0 {
        add_smoothing(joint, s, opt, &mut a, &mut rhs)?;
    }
    // a tiny Levenberg term keeps frames without nearby samples well posed
    let scale = (0..dim)
        .map(|i| a[(i, i)])
        .fold(0.0f64, f64::max)
        .max(1e-300);
    for i in 0..dim {
        a[(i, i)] += 1e-12 * scale;
    }
    let chol = nalgebra::linalg::Cholesky::new(a).ok_or_else(|| {
        JointSpecError(
            "fitting system is singular: use fewer control frames or more samples".into(),
        )
    })?;
    Ok((chol, rhs, data_part))
}

/// The smoothing weights `smooth: "auto"` first scores: none, and the useful
/// range 1e-6…1e-2, one per decade (heavier weights trade translation
/// accuracy for rotation smoothness, which the twist residual, dominated by
/// its radians, would let cross-validation accept).
pub const AUTO_WEIGHTS: [f64; 6] = [0.0, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2];

/// Golden-section steps that refine the best decade of [`AUTO_WEIGHTS`] in
/// log w: four steps narrow two decades to a third of one, finer than the
/// GCV curve's flat minimum distinguishes.
const REFINE_STEPS: usize = 4;

/// Generalised cross-validation of a fit (Craven & Wahba 1979) on the
/// problem linearised at the fitted joint: V = m·RSS / (m − tr H)², with m
/// the residual components (6 per sample), RSS = Σ‖log(G⁻¹G_d)‖² and
/// H = (1−w) M ((1−w) MᵀM + w NᵀN)⁻¹ Mᵀ the influence matrix, whose trace
/// is the fit's effective number of parameters.
pub fn gcv_score(
    joint: &SplineCurveJoint,
    samples: &JointSamples,
    opt: &FitOptions,
) -> Result<f64, JointSpecError> {
    let (chol, _, data_part) = normal_equations(joint, samples, opt)?;
    let trace = chol.solve(&data_part).trace();
    let m = 6.0 * samples.len() as f64;
    let rss = data_residual(joint, samples);
    let dof = m - trace;
    if dof <= 0.0 {
        return Ok(f64::INFINITY);
    }
    Ok(m * rss / (dof * dof))
}

/// What [`fit_spline_joint_auto`] returns.
#[derive(Debug, Clone)]
pub struct AutoFit {
    /// The fit at the chosen weight.
    pub fit: FitReport,
    /// The chosen smoothing weight w.
    pub weight: f64,
    /// Every (weight, GCV score) tried, in the order tried.
    pub scores: Vec<(f64, f64)>,
}

/// Chooses the smoothing weight from the data (`smooth: "auto"`, the
/// language's default), as spline smoothers do (Woltring's GCVSPL, which
/// OpenSim's GCVSpline wraps): the weight of least generalised
/// cross-validation score. The score is taken at every weight of
/// [`AUTO_WEIGHTS`]; when the best is positive, a golden-section search in
/// log w between its neighbours (the decade below 1e-6 stands for 0) refines it.
pub fn fit_spline_joint_auto(
    samples: &JointSamples,
    opt: &FitOptions,
) -> Result<AutoFit, JointSpecError> {
    let mut scores = Vec::new();
    let mut best: Option<(FitReport, f64, f64)> = None;
    let mut score = |w: f64, best: &mut Option<(FitReport, f64, f64)>| {
        let o = FitOptions {
            smooth: w,
            ..opt.clone()
        };
        let r = fit_spline_joint(samples, &o)?;
        let v = gcv_score(&r.joint, samples, &o)?;
        scores.push((w, v));
        if best.as_ref().is_none_or(|b| v < b.2) {
            *best = Some((r, w, v));
        }
        Ok::<f64, JointSpecError>(v)
    };
    for w in AUTO_WEIGHTS {
        score(w, &mut best)?;
    }
    let w0 = best.as_ref().map_or(0.0, |b| b.1);
    if w0 > 0.0 {
        let k = AUTO_WEIGHTS.iter().position(|&w| w == w0).unwrap_or(0);
        let lo = if k >= 2 {
            AUTO_WEIGHTS[k - 1]
        } else {
            w0 / 10.0
        };
        let hi = AUTO_WEIGHTS.get(k + 1).copied().unwrap_or(w0);
        // golden section on x = log10 w over [lo, hi], w0 (already scored) inside
        let phi = (5f64.sqrt() - 1.0) / 2.0;
        let (mut a, mut b) = (lo.log10(), hi.log10());
        let mut c = b - phi * (b - a);
        let mut d = a + phi * (b - a);
        let mut fc = score(10f64.powf(c), &mut best)?;
        let mut fd = score(10f64.powf(d), &mut best)?;
        for _ in 2..REFINE_STEPS {
            if fc < fd {
                (b, d, fd) = (d, c, fc);
                c = b - phi * (b - a);
                fc = score(10f64.powf(c), &mut best)?;
            } else {
                (a, c, fc) = (c, d, fd);
                d = a + phi * (b - a);
                fd = score(10f64.powf(d), &mut best)?;
            }
        }
    }
    let (fit, weight, _) =
        best.ok_or_else(|| JointSpecError("no smoothing weight to try".into()))?;
    Ok(AutoFit {
        fit,
        weight,
        scores,
    })
}

/// Adds w NᵀN and −c w Nᵀh, N = ∂h/∂ǔ by central differences.
fn add_smoothing(
    joint: &SplineCurveJoint,
    s: &JointSamples,
    opt: &FitOptions,
    a: &mut DMatrix<f64>,
    rhs: &mut DVector<f64>,
) -> Result<(), JointSpecError> {
    let n = joint.frames().len();
    let p = joint.basis().degree();
    let h0 = hessians(joint, s);
    let eps = 1e-6;
    let w = opt.smooth;
    // which samples each frame influences: first ∈ [j − p, j]
    let mut firsts = Vec::with_capacity(s.len());
    let mut b = [[0.0; 6]; 3];
    for &q in &s.q {
        firsts.push(joint.basis().eval_nonzero(q, 0, &mut b));
    }
    // columns of N, per sample: ncol[k][(j,d)]
    let mut cols: Vec<Vec<(usize, Twist)>> = vec![Vec::new(); s.len()];
    let mut kin = JointKinematics::default();
    for j in 0..n {
        for d in 0..6 {
            let mut dir = Twist::zeros();
            dir[d] = eps;
            let mut jp = joint.clone();
            let mut jm = joint.clone();
            let mut fp = joint.frames().to_vec();
            let mut fm = joint.frames().to_vec();
            fp[j] = fp[j].compose(&exp_se3(&dir));
            fm[j] = fm[j].compose(&exp_se3(&(-dir)));
            jp.set_frames(fp)?;
            jm.set_frames(fm)?;
            for (k, &q) in s.q.iter().enumerate() {
                if firsts[k] + p < j || firsts[k] > j {
                    continue;
                }
                jp.kinematics(&[q], Derivatives::Hessian, &mut kin);
                let hp = kin.ds[0][0];
                jm.kinematics(&[q], Derivatives::Hessian, &mut kin);
                let hm = kin.ds[0][0];
                cols[k].push((6 * j + d, (hp - hm) / (2.0 * eps)));
            }
        }
    }
    for (k, ck) in cols.iter().enumerate() {
        for (ci, vi) in ck {
            rhs[*ci] -= w * opt.smooth_rate * vi.dot(&h0[k]);
            for (cj, vj) in ck {
                a[(*ci, *cj)] += w * vi.dot(vj);
            }
        }
    }
    Ok(())
}

/// ∫‖∇S(q)‖² dq over the joint's domain (composite Simpson, `n` even intervals).
pub fn hessian_energy(joint: &dyn Joint, a: f64, b: f64, n: usize) -> f64 {
    let n = (n.max(2) + 1) & !1;
    let h = (b - a) / n as f64;
    let mut k = JointKinematics::default();
    let mut sum = 0.0;
    for i in 0..=n {
        joint.kinematics(&[a + h * i as f64], Derivatives::Hessian, &mut k);
        let wgt = if i == 0 || i == n {
            1.0
        } else if i % 2 == 1 {
            4.0
        } else {
            2.0
        };
        sum += wgt * k.ds[0][0].norm_squared();
    }
    sum * h / 3.0
}
