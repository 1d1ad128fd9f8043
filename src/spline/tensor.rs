//! Tensor-product B-spline functions ℝⁿ → ℝ (n ≤ 6), with gradient and Hessian.

use super::bspline::{BSplineBasis, SplineError};
use serde::{Deserialize, Serialize};

/// φ(q) = Σ c_{i0…i(n−1)} B⁰_{i0}(q0)·…·Bⁿ⁻¹_{i(n−1)}(q(n−1)); coefficients in
/// row-major order (the last coordinate varies fastest).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TensorSpline {
    bases: Vec<BSplineBasis>,
    coeffs: Vec<f64>,
}

/// Value, gradient and Hessian of a tensor spline at a point.
#[derive(Debug, Clone, Copy, Default)]
pub struct TensorEval {
    pub value: f64,
    pub grad: [f64; 6],
    pub hess: [[f64; 6]; 6],
}

impl TensorSpline {
    pub fn new(bases: Vec<BSplineBasis>, coeffs: Vec<f64>) -> Result<Self, SplineError> {
        if bases.is_empty() || bases.len() > 6 {
            return Err(SplineError::Fit(format!(
                "a tensor spline needs 1 to 6 bases, got {}",
                bases.len()
            )));
        }
        let need: usize = bases.iter().map(|b| b.n_coeffs()).product();
        if coeffs.len() != need {
            return Err(SplineError::Fit(format!(
                "tensor spline needs {need} coefficients ({}), got {}",
                bases
                    .iter()
                    .map(|b| b.n_coeffs().to_string())
                    .collect::<Vec<_>>()
                    .join("×"),
                coeffs.len()
            )));
        }
        if coeffs.iter().any(|c| !c.is_finite()) {
            return Err(SplineError::Fit(
                "tensor spline coefficients must be finite".into(),
            ));
        }
        Ok(TensorSpline { bases, coeffs })
    }

    /// A constant function of n coordinates (one cubic piece per coordinate on [lo, hi]).
    pub fn constant(value: f64, ranges: &[(f64, f64)]) -> Result<Self, SplineError> {
        let bases = ranges
            .iter()
            .map(|&(a, b)| BSplineBasis::clamped_uniform(3, 4, a, b))
            .collect::<Result<Vec<_>, _>>()?;
        let n: usize = bases.iter().map(|b| b.n_coeffs()).product();
        TensorSpline::new(bases, vec![value; n])
    }

    pub fn dim(&self) -> usize {
        self.bases.len()
    }
    pub fn bases(&self) -> &[BSplineBasis] {
        &self.bases
    }
    pub fn coeffs(&self) -> &[f64] {
        &self.coeffs
    }

    pub fn eval(&self, q: &[f64]) -> TensorEval {
        let n = self.bases.len();
        let mut r = TensorEval::default();
        self.for_each_term::<3>(q, 2, |c, b, idx| {
            let mut v = c;
            for d in 0..n {
                v *= b[d][0][idx[d]];
            }
            r.value += v;
            for k in 0..n {
                let mut g = c * b[k][1][idx[k]];
                for d in (0..n).filter(|&d| d != k) {
                    g *= b[d][0][idx[d]];
                }
                r.grad[k] += g;
                for l in 0..n {
                    let mut h = c;
                    for d in 0..n {
                        let order = (d == k) as usize + (d == l) as usize;
                        h *= b[d][order][idx[d]];
                    }
                    r.hess[k][l] += h;
                }
            }
        });
        r
    }

    /// `Σ_kl v_k v_l ∂³φ/∂q_k∂q_l∂q_m` for each m: the third derivative
    /// contracted twice with a velocity (what a joint's `∂(Ṡ q̇)/∂q` needs).
    pub fn third_vv(&self, q: &[f64], v: &[f64]) -> [f64; 6] {
        let n = self.bases.len();
        let mut r = [0.0; 6];
        self.for_each_term::<4>(q, 3, |c, b, idx| {
            for (m, rm) in r.iter_mut().enumerate().take(n) {
                for k in 0..n {
                    for l in 0..n {
                        let mut t = c * v[k] * v[l];
                        for d in 0..n {
                            let order = (d == k) as usize + (d == l) as usize + (d == m) as usize;
                            t *= b[d][order][idx[d]];
                        }
                        *rm += t;
                    }
                }
            }
        });
        r
    }

    /// Calls `f(c, b, idx)` for every non-zero coefficient `c` of the
    /// (degree+1)ⁿ whose basis functions are non-zero at `q`; `b[d][order][idx[d]]`
    /// is the derivative of that order of coordinate d's basis function.
    fn for_each_term<const R: usize>(
        &self,
        q: &[f64],
        nderiv: usize,
        mut f: impl FnMut(f64, &[[[f64; 6]; R]; 6], &[usize; 6]),
    ) {
        let n = self.bases.len();
        let mut b = [[[0.0; 6]; R]; 6];
        let mut first = [0usize; 6];
        let mut cnt = [0usize; 6];
        for d in 0..n {
            first[d] = self.bases[d].eval_nonzero(q[d], nderiv, &mut b[d]);
            cnt[d] = self.bases[d].degree() + 1;
        }
        let mut idx = [0usize; 6];
        loop {
            // flat coefficient index
            let mut flat = 0;
            for d in 0..n {
                flat = flat * self.bases[d].n_coeffs() + self.bases[d].index(first[d], idx[d]);
            }
            let c = self.coeffs[flat];
            if c != 0.0 {
                f(c, &b, &idx);
            }
            // next multi-index
            let mut d = n;
            loop {
                if d == 0 {
                    return;
                }
                d -= 1;
                idx[d] += 1;
                if idx[d] < cnt[d] {
                    break;
                }
                idx[d] = 0;
            }
        }
    }
}
