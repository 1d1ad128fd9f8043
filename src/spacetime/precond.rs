//! The change of variables x = L⁻ᵀ y under which the solver sees a Hessian
//! close to 2·I, so quasi-Newton steps are well scaled from the first one.
//!
//! Why: the transition objective is a sum of squares, e = Σ_k w_k τ_kᵀ W τ_k,
//! and its Hessian is badly conditioned in the raw B-spline coefficients —
//! ∫B''ᵀB'' grows like (pieces)⁴, masses range from a pelvis to a toe, and
//! gravity couples a wrist angle to the lumbar torque. Its Gauss–Newton part
//! H = 2 Σ_k w_k J_kᵀ W J_k (J_k = ∂τ/∂x at node k) captures all three; we
//! build it once at the start (see `Objective::preconditioner`) and factor
//! H/2 = L Lᵀ.

use nalgebra::{DMatrix, DVector};

#[derive(Clone, Debug)]
pub enum Precond {
    /// x = y (nothing to scale, e.g. no free coefficients).
    Identity,
    /// x = L⁻ᵀ y with L lower triangular.
    Dense(DMatrix<f64>),
}

impl Precond {
    /// From a symmetric positive semidefinite approximation `h2` of half the
    /// Hessian, with a relative floor on its spectrum so a DOF that moves no
    /// mass never gives an infinite scale.
    pub fn from_half_hessian(mut h2: DMatrix<f64>) -> Self {
        let n = h2.nrows();
        if n == 0 {
            return Precond::Identity;
        }
        let scale = (0..n).map(|i| h2[(i, i)].abs()).fold(0.0, f64::max);
        if !(scale.is_finite() && scale > 0.0) {
            return Precond::Identity;
        }
        for i in 0..n {
            h2[(i, i)] += 1e-9 * scale;
        }
        match h2.cholesky() {
            Some(ch) => Precond::Dense(ch.l()),
            None => Precond::Identity,
        }
    }

    /// x = T(y).
    pub fn apply(&self, y: &[f64]) -> Vec<f64> {
        match self {
            Precond::Identity => y.to_vec(),
            Precond::Dense(l) => {
                let mut v = DVector::from_column_slice(y);
                // Lᵀ x = y
                if !l.tr_solve_lower_triangular_mut(&mut v) {
                    return y.to_vec();
                }
                v.as_slice().to_vec()
            }
        }
    }

    /// ∂e/∂y = L⁻¹ ∂e/∂x (the transpose map).
    pub fn apply_t(&self, g: &[f64]) -> Vec<f64> {
        match self {
            Precond::Identity => g.to_vec(),
            Precond::Dense(l) => {
                let mut v = DVector::from_column_slice(g);
                if !l.solve_lower_triangular_mut(&mut v) {
                    return g.to_vec();
                }
                v.as_slice().to_vec()
            }
        }
    }

    /// y with T(y) = x: y = Lᵀ x.
    pub fn solve(&self, x: &[f64]) -> Vec<f64> {
        match self {
            Precond::Identity => x.to_vec(),
            Precond::Dense(l) => (l.transpose() * DVector::from_column_slice(x))
                .as_slice()
                .to_vec(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spd(n: usize, seed: f64) -> DMatrix<f64> {
        let m = DMatrix::from_fn(n, n, |i, j| ((i * 7 + j * 3) as f64 * seed).sin());
        &m * m.transpose() + DMatrix::identity(n, n) * 0.1
    }

    #[test]
    fn round_trip_transpose_and_whitening() {
        let h = spd(6, 0.7);
        let p = Precond::from_half_hessian(h.clone());
        let y: Vec<f64> = (0..6).map(|i| (i as f64 * 0.37).cos()).collect();
        let g: Vec<f64> = (0..6).map(|i| (i as f64 * 1.1).sin()).collect();
        let x = p.apply(&y);
        let back = p.solve(&x);
        assert!(y.iter().zip(&back).all(|(a, b)| (a - b).abs() < 1e-9));
        let lhs: f64 = g.iter().zip(&x).map(|(a, b)| a * b).sum();
        let rhs: f64 = p.apply_t(&g).iter().zip(&y).map(|(a, b)| a * b).sum();
        assert!((lhs - rhs).abs() < 1e-10 * lhs.abs().max(1.0));
        // xᵀ H x = |y|² (up to the 1e-9 floor)
        let xv = DVector::from_column_slice(&x);
        let q = (xv.transpose() * &h * &xv)[(0, 0)];
        let yy: f64 = y.iter().map(|v| v * v).sum();
        assert!((q - yy).abs() < 1e-6 * yy);
    }

    #[test]
    fn singular_or_empty_inputs_stay_finite() {
        let p = Precond::from_half_hessian(DMatrix::zeros(3, 3));
        assert!(p.apply(&[1.0; 3]).iter().all(|v| v.is_finite()));
        let mut h = DMatrix::zeros(2, 2);
        h[(0, 0)] = 1.0; // rank deficient: floored
        let p = Precond::from_half_hessian(h);
        assert!(p.apply(&[1.0; 2]).iter().all(|v| v.is_finite()));
        assert!(matches!(
            Precond::from_half_hessian(DMatrix::zeros(0, 0)),
            Precond::Identity
        ));
    }
}
