//! OpenSim's `GCVSpline` with `error_variance` 0: the natural spline of
//! order 2m (m the `half_order`, degree 2m − 1) that interpolates the points.
//! OpenSim computes it with Woltring's GCVSPL; any interpolating natural
//! spline is the same function, so mx builds it its own, well-conditioned
//! way: a clamped B-spline of degree 2m − 1 with the points as knots, solved
//! for the n interpolation conditions and the natural end conditions
//! s⁽ʲ⁾(x₁) = s⁽ʲ⁾(xₙ) = 0, j = m … 2m − 2. Outside [x₁, xₙ] a natural spline
//! is the polynomial of degree m − 1 that continues it (its Taylor polynomial
//! at the end), as GCVSPL's evaluation gives.
//!
//! A smoothing GCVSpline (`error_variance` > 0) depends on GCVSPL's choice of
//! the smoothing parameter and is not read (the reader says so).

use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

use crate::spline::bspline::{BSplineBasis, BSplineCurve, SplineError};

/// An interpolating natural spline of order 2·half_order (OpenSim `GCVSpline`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GcvSpline {
    half_order: usize,
    curve: BSplineCurve,
    /// (x, [s, s′, s″, s‴]) at the first and the last point.
    ends: [(f64, [f64; 4]); 2],
}

fn fit_err(m: impl Into<String>) -> SplineError {
    SplineError::Fit(m.into())
}

/// b − Σ aᵢ xᵢ, accumulated in double-double (Ogita, Rump & Oishi's Dot2).
fn residual_dd(b: f64, a: impl Iterator<Item = f64>, x: impl Iterator<Item = f64>) -> f64 {
    let (mut hi, mut lo) = (b, 0.0f64);
    for (ai, xi) in a.zip(x) {
        let p = -ai * xi;
        let pe = (-ai).mul_add(xi, -p); // exact: −ai·xi = p + pe
        let s = hi + p;
        let z = s - hi;
        let se = (hi - (s - z)) + (p - z); // exact: hi + p = s + se
        hi = s;
        lo += pe + se;
    }
    hi + lo
}

impl GcvSpline {
    /// Through (x[i], y[i]), x strictly increasing, at least 2·half_order
    /// points (GCVSPL's minimum); half_order 1 (linear), 2 (cubic) or 3
    /// (quintic, OpenSim's default).
    pub fn new(half_order: usize, x: Vec<f64>, y: Vec<f64>) -> Result<Self, SplineError> {
        let m = half_order;
        if !(1..=3).contains(&m) {
            return Err(fit_err(format!(
                "GCVSpline half_order {m} is not supported: mx reads 1, 2 and 3 (degree 1, 3, 5)"
            )));
        }
        let n = x.len();
        if y.len() != n {
            return Err(fit_err(format!(
                "GCVSpline has {n} x values but {} y values",
                y.len()
            )));
        }
        if n < 2 * m {
            return Err(fit_err(format!(
                "GCVSpline of half_order {m} needs at least {} points, it has {n}",
                2 * m
            )));
        }
        if x.iter().chain(&y).any(|v| !v.is_finite()) {
            return Err(fit_err("GCVSpline points must be finite"));
        }
        if let Some(i) = (1..n).find(|&i| x[i] <= x[i - 1]) {
            return Err(fit_err(format!(
                "GCVSpline x values must be strictly increasing: x[{i}] = {} follows {}",
                x[i],
                x[i - 1]
            )));
        }
        let p = 2 * m - 1;
        let mut knots = vec![x[0]; p + 1];
        knots.extend_from_slice(&x[1..n - 1]);
        knots.extend(std::iter::repeat_n(x[n - 1], p + 1));
        let basis = BSplineBasis::new(p, knots)?;
        let nc = basis.n_coeffs();
        debug_assert_eq!(nc, n + 2 * m - 2);
        // rows: interpolation, then the natural end conditions
        let mut a = DMatrix::zeros(nc, nc);
        let mut rhs = DVector::zeros(nc);
        let mut row = 0;
        let mut put = |t: f64, d: usize, value: f64, a: &mut DMatrix<f64>, row: &mut usize| {
            let mut b = [[0.0; 6]; 6];
            let first = basis.eval_nonzero(t, d, &mut b);
            for (i, bi) in b[d].iter().take(p + 1).enumerate() {
                a[(*row, basis.index(first, i))] = *bi;
            }
            rhs[*row] = value;
            *row += 1;
        };
        for (xi, yi) in x.iter().zip(&y) {
            put(*xi, 0, *yi, &mut a, &mut row);
        }
        for d in m..=2 * m - 2 {
            put(x[0], d, 0.0, &mut a, &mut row);
            put(x[n - 1], d, 0.0, &mut a, &mut row);
        }
        // The end conditions' rows grow as 1/h^d near close points: equilibrate
        // the rows by powers of two (exactly), solve with full pivoting, and
        // refine twice with residuals summed in double-double, which recovers
        // the digits the system's conditioning costs.
        for r in 0..nc {
            let s = a.row(r).amax().log2().round().exp2();
            a.row_mut(r).unscale_mut(s);
            rhs[r] /= s;
        }
        let lu = a.clone().full_piv_lu();
        let singular = || fit_err("GCVSpline: the interpolation system is singular");
        let mut coeffs = lu.solve(&rhs).ok_or_else(singular)?;
        for _ in 0..2 {
            let residual = DVector::from_fn(nc, |r, _| {
                residual_dd(rhs[r], a.row(r).iter().copied(), coeffs.iter().copied())
            });
            coeffs += lu.solve(&residual).ok_or_else(singular)?;
        }
        let curve = BSplineCurve::new(basis, coeffs.as_slice().to_vec())?;
        let ends = [(x[0], curve.eval3(x[0])), (x[n - 1], curve.eval3(x[n - 1]))];
        Ok(GcvSpline {
            half_order: m,
            curve,
            ends,
        })
    }

    pub fn half_order(&self) -> usize {
        self.half_order
    }

    /// Value and first three derivatives at t.
    pub fn eval3(&self, t: f64) -> [f64; 4] {
        let [(x0, s0), (x1, s1)] = self.ends;
        // t = xₙ counts as outside, as in GCVSPL (its derivatives are the
        // right-hand ones, which matters for the linear spline only)
        let (e, s) = if t < x0 {
            (x0, s0)
        } else if t >= x1 {
            (x1, s1)
        } else {
            return self.curve.eval3(t);
        };
        // the Taylor polynomial of degree m − 1 at the end, and its derivatives
        let h = t - e;
        let mut out = [0.0; 4];
        for (d, o) in out.iter_mut().enumerate() {
            let mut term = 1.0;
            for (k, sj) in s.iter().enumerate().take(self.half_order).skip(d) {
                *o += sj * term;
                term *= h / (k - d + 1) as f64;
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolates_and_is_natural_at_the_ends() {
        let x: Vec<f64> = (0..8).map(|i| (i as f64 * 0.37).sin() + i as f64).collect();
        let y: Vec<f64> = x.iter().map(|v| (1.3 * v).cos()).collect();
        for m in 1..=3 {
            let s = GcvSpline::new(m, x.clone(), y.clone()).unwrap();
            for (xi, yi) in x.iter().zip(&y) {
                assert!((s.eval3(*xi)[0] - yi).abs() < 1e-13);
            }
            // degree m − 1 outside: the m-th derivative vanishes there
            if m <= 3 {
                assert_eq!(s.eval3(x[0] - 1.0)[m.min(3)], 0.0);
            }
            // C^(2m−2) across the end: the value continues
            let e = x[7];
            assert!((s.eval3(e + 1e-9)[0] - s.eval3(e)[0]).abs() < 1e-8);
        }
        assert!(GcvSpline::new(3, x[..5].to_vec(), y[..5].to_vec()).is_err());
        assert!(GcvSpline::new(4, x.clone(), y.clone()).is_err());
    }
}
