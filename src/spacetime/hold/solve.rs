//! The support IK's solve: Gauss–Newton with Levenberg–Marquardt damping
//! from the Hermite start (R is a sum of squares over few unknowns, so it
//! converges in a handful of iterations).

use super::super::error::SpError;
use super::HoldObjective;
use crate::cancel::CancelToken;
use nalgebra::{DMatrix, DVector};

/// Levenberg–Marquardt iterations at most (it converges in a handful).
const MAX_ITERS: usize = 50;
/// Stop when the largest residual is below this (m): far below what shows.
const RESIDUAL_TOL: f64 = 1e-6;

/// The Gauss–Newton system at one point: H = Σ w JᵀJ + μ², g = Σ w Jᵀr +
/// μ²(x − x_H), R, and the largest residual over the nodes.
struct System {
    h: DMatrix<f64>,
    g: DVector<f64>,
    e: f64,
    worst: f64,
}

impl HoldObjective<'_> {
    /// Minimise R by Levenberg–Marquardt from the Hermite start; returns x.
    pub fn solve(&self, cancel: &CancelToken) -> Result<Vec<f64>, SpError> {
        let n = self.n_vars();
        let mut x = self.hermite_start();
        if n == 0 {
            return Ok(x);
        }
        let mut lambda = 1e-6;
        let mut jac = DMatrix::zeros(3 * self.frames.len(), self.layout.dofs.len());
        for _ in 0..MAX_ITERS {
            cancel.check()?;
            let System { h, g, e, worst } = self.system(&x, &mut jac)?;
            if worst <= RESIDUAL_TOL {
                break;
            }
            // damped step, raising the damping until R decreases
            let scale = (0..n).map(|i| h[(i, i)]).fold(0.0, f64::max).max(1e-300);
            let mut improved = false;
            for _ in 0..20 {
                let mut a = h.clone();
                for i in 0..n {
                    a[(i, i)] += lambda * (h[(i, i)] + 1e-9 * scale);
                }
                let Some(ch) = a.cholesky() else {
                    lambda *= 10.0;
                    continue;
                };
                let step = ch.solve(&(-&g));
                let xt: Vec<f64> = x.iter().zip(step.iter()).map(|(a, b)| a + b).collect();
                let et = self.eval(&xt, None)?;
                if et < e {
                    x = xt;
                    lambda = (lambda * 0.1).max(1e-12);
                    improved = true;
                    // converged when the step no longer changes R noticeably
                    if e - et <= 1e-12 * e {
                        return Ok(x);
                    }
                    break;
                }
                lambda *= 10.0;
            }
            if !improved {
                break;
            }
        }
        Ok(x)
    }

    /// The Gauss–Newton system Σ w JᵀJ δ = −Σ w Jᵀ r over the coefficients
    /// at x (`jac`: scratch for the per-node Jacobian).
    fn system(&self, x: &[f64], jac: &mut DMatrix<f64>) -> Result<System, SpError> {
        let n = self.n_vars();
        let n_free = self.layout.n_free;
        let mut h = DMatrix::<f64>::zeros(n, n);
        let mut g = DVector::<f64>::zeros(n);
        let mut e = 0.0;
        let mut worst = 0.0f64;
        for k in 0..self.layout.nodes.len() {
            let r = self.node(k, x, Some(jac))?;
            let w = self.layout.qweights[k];
            e += w * r.iter().map(|v| v.norm_squared()).sum::<f64>();
            worst = r.iter().fold(worst, |m, v| m.max(v.norm()));
            let rv = DVector::from_iterator(3 * r.len(), r.iter().flat_map(|v| v.iter().copied()));
            // columns of the coefficient Jacobian: J_q[:, d] · basis row
            let mut cols: Vec<(usize, DVector<f64>)> = vec![];
            for d in 0..self.layout.dofs.len() {
                let Some(rows) = self.layout.rows(d, k) else {
                    continue;
                };
                for (j, b) in rows.rows[0].iter().enumerate() {
                    if *b != 0.0 {
                        cols.push((d * n_free + j, jac.column(d) * *b));
                    }
                }
            }
            for (i, ci) in &cols {
                g[*i] += w * ci.dot(&rv);
                for (j, cj) in &cols {
                    h[(*i, *j)] += w * ci.dot(cj);
                }
            }
        }
        for i in 0..n {
            e += self.stiffness * (x[i] - self.start[i]).powi(2);
            g[i] += self.stiffness * (x[i] - self.start[i]);
            h[(i, i)] += self.stiffness;
        }
        Ok(System { h, g, e, worst })
    }
}
