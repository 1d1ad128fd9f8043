//! Least-squares fitting of scalar B-spline curves to samples.
//!
//! The normal equations BᵀB c = Bᵀy are banded (bandwidth = degree; cyclic for
//! a periodic basis). They are small (tens to hundreds of coefficients), so a
//! dense Cholesky factorisation is used; a rank-deficient system (a knot span
//! without enough samples) is reported as an error rather than solved badly.

use super::bspline::{BSplineBasis, BSplineCurve, SplineError};
use nalgebra::{DMatrix, DVector};

/// Least-squares fit Σ (c·B(tₖ) − yₖ)² → min over the coefficients of `basis`.
/// Works for clamped, general and periodic bases (the periodic fit is the
/// cyclic fit used for cyclification).
pub fn fit_least_squares(
    basis: &BSplineBasis,
    ts: &[f64],
    ys: &[f64],
) -> Result<BSplineCurve, SplineError> {
    fit_weighted(basis, ts, ys, None, 0.0)
}

/// Weighted, optionally smoothed least squares:
/// Σ wₖ (c·B(tₖ) − yₖ)² + λ ∫ (c·B''(t))² dt → min.
/// `weights` (if given) must be non-negative; λ ≥ 0 penalises curvature and
/// also makes the system well posed where data is missing.
pub fn fit_weighted(
    basis: &BSplineBasis,
    ts: &[f64],
    ys: &[f64],
    weights: Option<&[f64]>,
    lambda: f64,
) -> Result<BSplineCurve, SplineError> {
    if ts.len() != ys.len() {
        return Err(SplineError::Fit(format!(
            "fit needs as many times as values: {} times, {} values",
            ts.len(),
            ys.len()
        )));
    }
    if let Some(w) = weights {
        if w.len() != ts.len() {
            return Err(SplineError::Fit(format!(
                "{} weights for {} samples",
                w.len(),
                ts.len()
            )));
        }
        if w.iter().any(|x| !x.is_finite() || *x < 0.0) {
            return Err(SplineError::Fit(
                "weights must be finite and non-negative".into(),
            ));
        }
    }
    if !(lambda.is_finite() && lambda >= 0.0) {
        return Err(SplineError::Fit(format!(
            "smoothing weight {lambda} must be finite and ≥ 0"
        )));
    }
    if let Some(k) = ts.iter().chain(ys).position(|x| !x.is_finite()) {
        return Err(SplineError::Fit(format!(
            "sample {} is not finite",
            k % ts.len().max(1)
        )));
    }
    let n = basis.n_coeffs();
    let p = basis.degree();
    let mut a = DMatrix::<f64>::zeros(n, n);
    let mut rhs = DVector::<f64>::zeros(n);
    let mut b = [[0.0; 6]; 3];
    for (k, (&t, &y)) in ts.iter().zip(ys).enumerate() {
        let w = weights.map_or(1.0, |w| w[k]);
        let first = basis.eval_nonzero(t, 0, &mut b);
        for i in 0..=p {
            let ii = basis.index(first, i);
            rhs[ii] += w * b[0][i] * y;
            for j in 0..=p {
                a[(ii, basis.index(first, j))] += w * b[0][i] * b[0][j];
            }
        }
    }
    if lambda > 0.0 && p >= 2 {
        add_curvature_penalty(basis, lambda, &mut a);
    }
    let scale = (0..n).map(|i| a[(i, i)]).fold(0.0f64, f64::max);
    if scale == 0.0 {
        return Err(SplineError::Fit("no samples to fit".into()));
    }
    let chol = nalgebra::linalg::Cholesky::new(a.clone()).ok_or_else(rank_error)?;
    let l = chol.l();
    let min_piv = (0..n)
        .map(|i| l[(i, i)] * l[(i, i)])
        .fold(f64::INFINITY, f64::min);
    if min_piv < 1e-12 * scale {
        return Err(rank_error());
    }
    let c = chol.solve(&rhs);
    BSplineCurve::new(basis.clone(), c.iter().copied().collect())
}

fn rank_error() -> SplineError {
    SplineError::Fit(
        "the fit is under-determined: some knot span has too few samples; use fewer coefficients, more samples, or a smoothing weight"
            .into(),
    )
}

/// Adds λ ∫ B''ᵢ B''ⱼ dt, integrated exactly per span by Gauss–Legendre with
/// enough points for the polynomial degree 2(p−2) ≤ 6 (4 points are exact to degree 7).
fn add_curvature_penalty(basis: &BSplineBasis, lambda: f64, a: &mut DMatrix<f64>) {
    const X: [f64; 4] = [
        -0.861_136_311_594_052_6,
        -0.339_981_043_584_856_3,
        0.339_981_043_584_856_3,
        0.861_136_311_594_052_6,
    ];
    const W: [f64; 4] = [
        0.347_854_845_137_453_9,
        0.652_145_154_862_546_1,
        0.652_145_154_862_546_1,
        0.347_854_845_137_453_9,
    ];
    let p = basis.degree();
    let k = basis.knots();
    let n_ext = k.len() - p - 1;
    let mut b = [[0.0; 6]; 3];
    for s in p..n_ext {
        let (u0, u1) = (k[s], k[s + 1]);
        if u1 <= u0 {
            continue;
        }
        let h = 0.5 * (u1 - u0);
        for (x, w) in X.iter().zip(W) {
            let t = u0 + h * (1.0 + x);
            let first = basis.eval_nonzero(t, 2, &mut b);
            for i in 0..=p {
                for j in 0..=p {
                    a[(basis.index(first, i), basis.index(first, j))] +=
                        lambda * w * h * b[2][i] * b[2][j];
                }
            }
        }
    }
}
