//! The parameterisation of one transition DOF: a clamped cubic B-spline over
//! the gap [t0, t1] whose boundary coefficients are fixed by the end states,
//! so position and velocity (and acceleration with C² continuity) match the
//! neighbouring motion exactly whatever the free interior coefficients are.
//! The optimiser only ever sees the free coefficients.

use super::basis::ClampedCubic;
use super::error::{SpError, invalid};
use nalgebra::{DMatrix, DVector};

/// Position, velocity and acceleration of one DOF at one end of a gap.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EndState {
    pub q: f64,
    pub v: f64,
    pub a: f64,
}

/// Which derivatives a transition matches at its ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Continuity {
    /// Position and velocity (the paper's C¹ transitions).
    #[default]
    C1,
    /// Position, velocity and acceleration.
    C2,
}

impl Continuity {
    /// `continuity: 1` or `continuity: 2`.
    pub fn from_order(n: i64) -> Result<Self, SpError> {
        match n {
            1 => Ok(Continuity::C1),
            2 => Ok(Continuity::C2),
            _ => Err(invalid(format!(
                "continuity: {n} is not supported; use 1 (position and velocity) or 2 (also acceleration)"
            ))),
        }
    }

    /// Coefficients fixed at each end.
    pub fn fixed_per_end(self) -> usize {
        match self {
            Continuity::C1 => 2,
            Continuity::C2 => 3,
        }
    }

    pub fn order(self) -> usize {
        self.fixed_per_end() - 1
    }
}

/// The spline space of one gap: shared by every DOF of the gap.
#[derive(Clone, Debug)]
pub struct TransitionCurve {
    basis: ClampedCubic,
    continuity: Continuity,
    n_free: usize,
}

impl TransitionCurve {
    /// A curve on [t0, t1] with `n_free` free coefficients.
    pub fn new(t0: f64, t1: f64, n_free: usize, continuity: Continuity) -> Result<Self, SpError> {
        if !(t0.is_finite() && t1.is_finite()) {
            return Err(invalid(format!(
                "transition span [{t0}, {t1}] is not finite"
            )));
        }
        if t1 <= t0 {
            return Err(invalid(format!(
                "transition span [{t0}, {t1}] has no length; a zero-length gap needs no transition"
            )));
        }
        if n_free > 200 {
            return Err(invalid(format!(
                "coefficients: {n_free} is too many for one transition; use 3–30 (the paper uses 5–10)"
            )));
        }
        let m = n_free + 2 * continuity.fixed_per_end();
        Ok(TransitionCurve {
            basis: ClampedCubic::new(t0, t1, m)
                .map_err(|e| invalid(format!("transition basis: {e}")))?,
            continuity,
            n_free,
        })
    }

    pub fn t0(&self) -> f64 {
        self.basis.t0
    }
    pub fn t1(&self) -> f64 {
        self.basis.t1
    }
    pub fn n_free(&self) -> usize {
        self.n_free
    }
    pub fn n_coeffs(&self) -> usize {
        self.basis.len()
    }
    pub fn continuity(&self) -> Continuity {
        self.continuity
    }

    /// Ends of the curve's polynomial pieces.
    pub fn breakpoints(&self) -> Vec<f64> {
        self.basis.breakpoints()
    }

    /// Index of the first free coefficient in the full coefficient vector.
    pub fn first_free(&self) -> usize {
        self.continuity.fixed_per_end()
    }

    /// All basis values and derivatives at t: `[values, d/dt, d²/dt²]`, each of length `n_coeffs()`.
    pub fn basis_at(&self, t: f64) -> [Vec<f64>; 3] {
        self.basis.eval(t)
    }

    /// The full coefficient vector: boundary coefficients solved from the end
    /// states (a triangular system at each clamped end), free ones from `free`.
    pub fn coefficients(&self, start: &EndState, end: &EndState, free: &[f64]) -> Vec<f64> {
        debug_assert_eq!(free.len(), self.n_free);
        let m = self.n_coeffs();
        let k = self.continuity.fixed_per_end();
        let mut c = vec![0.0; m];
        c[k..k + self.n_free].copy_from_slice(free);
        let left = self.basis.eval(self.t0());
        let s = [start.q, start.v, start.a];
        for d in 0..k {
            // Σ_{j≤d} B_j^{(d)}(t0) c_j = s[d]; B_d^{(d)}(t0) ≠ 0 for a clamped basis.
            let rest: f64 = (0..d).map(|j| left[d][j] * c[j]).sum();
            c[d] = (s[d] - rest) / left[d][d];
        }
        let right = self.basis.eval(self.t1());
        let e = [end.q, end.v, end.a];
        for d in 0..k {
            let i = m - 1 - d;
            let rest: f64 = (i + 1..m).map(|j| right[d][j] * c[j]).sum();
            c[i] = (e[d] - rest) / right[d][i];
        }
        c
    }

    /// The curve with full coefficients `c` as a spline of the `spline` module
    /// (what is stored in the motion).
    pub fn to_curve(&self, c: Vec<f64>) -> Result<crate::spline::BSplineCurve, SpError> {
        self.basis.curve(c).map_err(SpError::Curve)
    }

    /// [q, q̇, q̈] of the curve with full coefficients `c` at t.
    pub fn eval(&self, c: &[f64], t: f64) -> [f64; 3] {
        let b = self.basis.eval(t);
        let mut out = [0.0; 3];
        for (o, row) in out.iter_mut().zip(&b) {
            *o = row.iter().zip(c).map(|(x, y)| x * y).sum();
        }
        out
    }

    /// Free coefficients whose curve best fits `target` in least squares
    /// (boundary coefficients held from the end states). Used for the starting
    /// point: fitting the Hermite curve makes the first iterate that curve
    /// (exactly, for C¹, since cubics lie in the spline space).
    pub fn fit_free(
        &self,
        start: &EndState,
        end: &EndState,
        target: impl Fn(f64) -> f64,
    ) -> Vec<f64> {
        let n = self.n_free;
        if n == 0 {
            return vec![];
        }
        let fixed = self.coefficients(start, end, &vec![0.0; n]);
        let k = self.first_free();
        let samples = 8 * self.n_coeffs();
        let mut a = DMatrix::zeros(samples, n);
        let mut y = DVector::zeros(samples);
        for s in 0..samples {
            let t = self.t0() + (self.t1() - self.t0()) * (s as f64 + 0.5) / samples as f64;
            let b = self.basis.eval(t);
            let off: f64 = b[0].iter().zip(&fixed).map(|(x, c)| x * c).sum();
            y[s] = target(t) - off;
            for j in 0..n {
                a[(s, j)] = b[0][k + j];
            }
        }
        // The free columns are linearly independent B-splines: SVD is robust
        // even when a tiny span makes them badly scaled.
        match a.svd(true, true).solve(&y, 1e-14) {
            Ok(x) => x.iter().copied().collect(),
            Err(_) => vec![0.0; n],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spacetime::hermite;

    fn st(q: f64, v: f64, a: f64) -> EndState {
        EndState { q, v, a }
    }

    #[test]
    fn ends_match_exactly_for_any_free_coefficients() {
        let (a, b) = (st(0.4, -2.0, 3.0), st(-1.3, 0.7, -9.0));
        for cont in [Continuity::C1, Continuity::C2] {
            for n in [0, 1, 3, 8, 20] {
                let c = TransitionCurve::new(2.0, 2.6, n, cont).unwrap();
                let free: Vec<f64> = (0..n).map(|i| (i as f64 * 1.7).sin() * 5.0).collect();
                let coef = c.coefficients(&a, &b, &free);
                let s = c.eval(&coef, 2.0);
                let e = c.eval(&coef, 2.6);
                assert!((s[0] - a.q).abs() <= 1e-12 && (e[0] - b.q).abs() <= 1e-12);
                assert!((s[1] - a.v).abs() <= 1e-10 && (e[1] - b.v).abs() <= 1e-10);
                if cont == Continuity::C2 {
                    assert!(
                        (s[2] - a.a).abs() <= 1e-8 && (e[2] - b.a).abs() <= 1e-8,
                        "{n}"
                    );
                }
            }
        }
    }

    #[test]
    fn the_cubic_hermite_curve_is_in_the_space() {
        let (a, b) = (st(0.4, -2.0, 0.0), st(3.5, 0.7, 0.0));
        let c = TransitionCurve::new(0.0, 0.6, 5, Continuity::C1).unwrap();
        let free = c.fit_free(&a, &b, |t| hermite::cubic(0.0, 0.6, &a, &b, t)[0]);
        let coef = c.coefficients(&a, &b, &free);
        for i in 0..=30 {
            let t = 0.6 * i as f64 / 30.0;
            let h = hermite::cubic(0.0, 0.6, &a, &b, t);
            let s = c.eval(&coef, t);
            assert!(
                (h[0] - s[0]).abs() < 1e-10 && (h[1] - s[1]).abs() < 1e-8,
                "t={t}"
            );
        }
    }

    #[test]
    fn bad_spans_and_orders_are_clear_errors() {
        assert!(TransitionCurve::new(1.0, 1.0, 5, Continuity::C1).is_err());
        assert!(TransitionCurve::new(1.0, 0.5, 5, Continuity::C1).is_err());
        assert!(TransitionCurve::new(0.0, f64::NAN, 5, Continuity::C1).is_err());
        assert!(Continuity::from_order(3).is_err());
        let e = TransitionCurve::new(1.0, 1.0, 5, Continuity::C1).unwrap_err();
        assert!(e.to_string().contains("zero-length"));
    }

    #[test]
    fn tiny_and_long_spans_stay_finite_and_exact() {
        let (a, b) = (st(0.0, 1.0, 0.0), st(1.0, 1.0, 0.0));
        for (t0, t1) in [(0.0, 1e-6), (0.0, 5.0), (100.0, 100.001)] {
            let c = TransitionCurve::new(t0, t1, 5, Continuity::C2).unwrap();
            let coef = c.coefficients(&a, &b, &[0.3, 0.5, 0.5, 0.6, 0.9]);
            assert!(coef.iter().all(|x| x.is_finite()));
            let e = c.eval(&coef, t1);
            assert!(
                (e[0] - 1.0).abs() < 1e-9 && (e[1] - 1.0).abs() < 1e-6 * (1.0 + 1.0 / (t1 - t0))
            );
        }
    }
}
