//! OpenSim's `SimmSpline`: the Forsythe–Malcolm–Moler cubic interpolating
//! spline (`spline`/`seval` of "Computer Methods for Mathematical
//! Computations", 1977), extended linearly outside its knots.
//!
//! It is NOT a natural spline: the end conditions make the third derivative
//! of the first (last) cubic equal to that of the cubic through the first
//! (last) four points. n = 2 gives a line, n = 3 one parabola.

use super::bspline::SplineError;
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "SimmRepr", into = "SimmRepr")]
pub struct SimmSpline {
    /// OpenSim's `NaturalCubicSpline` (s'' = 0 at both ends) instead of FMM's end conditions.
    natural: bool,
    x: Vec<f64>,
    y: Vec<f64>,
    b: Vec<f64>,
    c: Vec<f64>,
    d: Vec<f64>,
}

#[derive(Serialize, Deserialize)]
struct SimmRepr {
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    natural: bool,
    x: Vec<f64>,
    y: Vec<f64>,
}

impl TryFrom<SimmRepr> for SimmSpline {
    type Error = SplineError;
    fn try_from(r: SimmRepr) -> Result<Self, SplineError> {
        if r.natural {
            SimmSpline::natural(r.x, r.y)
        } else {
            SimmSpline::new(r.x, r.y)
        }
    }
}
impl From<SimmSpline> for SimmRepr {
    fn from(s: SimmSpline) -> Self {
        SimmRepr {
            natural: s.natural,
            x: s.x,
            y: s.y,
        }
    }
}

impl SimmSpline {
    /// Interpolant through (x[i], y[i]); x strictly increasing, at least 2 points.
    pub fn new(x: Vec<f64>, y: Vec<f64>) -> Result<Self, SplineError> {
        check_points("SimmSpline", &x, &y)?;
        let n = x.len();
        let mut b = vec![0.0; n];
        let mut c = vec![0.0; n];
        let mut d = vec![0.0; n];
        if n == 2 {
            b[0] = (y[1] - y[0]) / (x[1] - x[0]);
            b[1] = b[0];
            return Ok(SimmSpline {
                natural: false,
                x,
                y,
                b,
                c,
                d,
            });
        }
        let nm1 = n - 1;
        // Tridiagonal system for σ_i = s''(x_i)/6 (stored in c), diagonal b, off-diagonal d.
        d[0] = x[1] - x[0];
        c[1] = (y[1] - y[0]) / d[0];
        for i in 1..nm1 {
            d[i] = x[i + 1] - x[i];
            b[i] = 2.0 * (d[i - 1] + d[i]);
            c[i + 1] = (y[i + 1] - y[i]) / d[i];
            c[i] = c[i + 1] - c[i];
        }
        // End conditions: third derivatives match the third divided differences.
        b[0] = -d[0];
        b[nm1] = -d[n - 2];
        c[0] = 0.0;
        c[nm1] = 0.0;
        if n > 3 {
            c[0] = c[2] / (x[3] - x[1]) - c[1] / (x[2] - x[0]);
            c[nm1] = c[n - 2] / (x[nm1] - x[n - 3]) - c[n - 3] / (x[n - 2] - x[n - 4]);
            c[0] = c[0] * d[0] * d[0] / (x[3] - x[0]);
            c[nm1] = -c[nm1] * d[n - 2] * d[n - 2] / (x[nm1] - x[n - 4]);
        }
        for i in 1..n {
            let t = d[i - 1] / b[i - 1];
            b[i] -= t * d[i - 1];
            c[i] -= t * c[i - 1];
        }
        c[nm1] /= b[nm1];
        for i in (0..nm1).rev() {
            c[i] = (c[i] - d[i] * c[i + 1]) / b[i];
        }
        b[nm1] = (y[nm1] - y[n - 2]) / d[n - 2] + d[n - 2] * (c[n - 2] + 2.0 * c[nm1]);
        for i in 0..nm1 {
            b[i] = (y[i + 1] - y[i]) / d[i] - d[i] * (c[i + 1] + 2.0 * c[i]);
            d[i] = (c[i + 1] - c[i]) / d[i];
            c[i] *= 3.0;
        }
        c[nm1] *= 3.0;
        d[nm1] = d[n - 2];
        Ok(SimmSpline {
            natural: false,
            x,
            y,
            b,
            c,
            d,
        })
    }

    /// OpenSim's `NaturalCubicSpline`: the C² cubic interpolant with s'' = 0 at
    /// both ends (n = 2 gives a line), extended linearly outside the knots.
    pub fn natural(x: Vec<f64>, y: Vec<f64>) -> Result<Self, SplineError> {
        check_points("NaturalCubicSpline", &x, &y)?;
        let n = x.len();
        let h: Vec<f64> = (0..n - 1).map(|i| x[i + 1] - x[i]).collect();
        // Second derivatives m (m[0] = m[n-1] = 0) by the Thomas algorithm.
        let mut m = vec![0.0; n];
        if n > 2 {
            let k = n - 2;
            let mut diag = vec![0.0; k];
            let mut rhs = vec![0.0; k];
            for j in 0..k {
                let i = j + 1;
                diag[j] = 2.0 * (h[i - 1] + h[i]);
                rhs[j] = 6.0 * ((y[i + 1] - y[i]) / h[i] - (y[i] - y[i - 1]) / h[i - 1]);
            }
            for j in 1..k {
                let w = h[j] / diag[j - 1];
                diag[j] -= w * h[j];
                rhs[j] -= w * rhs[j - 1];
            }
            m[k] = rhs[k - 1] / diag[k - 1];
            for j in (0..k - 1).rev() {
                m[j + 1] = (rhs[j] - h[j + 1] * m[j + 2]) / diag[j];
            }
        }
        let mut b = vec![0.0; n];
        let mut c = vec![0.0; n];
        let mut d = vec![0.0; n];
        for i in 0..n - 1 {
            b[i] = (y[i + 1] - y[i]) / h[i] - h[i] * (2.0 * m[i] + m[i + 1]) / 6.0;
            c[i] = m[i] / 2.0;
            d[i] = (m[i + 1] - m[i]) / (6.0 * h[i]);
        }
        let l = n - 2;
        b[n - 1] = b[l] + h[l] * (2.0 * c[l] + 3.0 * h[l] * d[l]);
        d[n - 1] = d[l];
        Ok(SimmSpline {
            natural: true,
            x,
            y,
            b,
            c,
            d,
        })
    }

    /// True for a `NaturalCubicSpline`.
    pub fn is_natural(&self) -> bool {
        self.natural
    }

    pub fn x(&self) -> &[f64] {
        &self.x
    }
    pub fn y(&self) -> &[f64] {
        &self.y
    }

    /// Value, first and second derivative. Outside [x₀, x_{n−1}] the spline
    /// continues as the tangent line at the end (s'' = 0 there), as OpenSim does.
    pub fn eval(&self, t: f64) -> [f64; 3] {
        let [f, d1, d2, _] = self.eval3(t);
        [f, d1, d2]
    }

    /// Value and first three derivatives. The third is constant on each
    /// interval (taken from the interval `eval` uses at a knot) and zero outside.
    pub fn eval3(&self, t: f64) -> [f64; 4] {
        let n = self.x.len();
        if t < self.x[0] {
            return [self.y[0] + self.b[0] * (t - self.x[0]), self.b[0], 0.0, 0.0];
        }
        if t > self.x[n - 1] {
            return [
                self.y[n - 1] + self.b[n - 1] * (t - self.x[n - 1]),
                self.b[n - 1],
                0.0,
                0.0,
            ];
        }
        // interval i with x[i] ≤ t (the last interval includes its right end)
        let i = match self.x.partition_point(|&xi| xi <= t) {
            0 => 0,
            k => (k - 1).min(n - 2),
        };
        let dx = t - self.x[i];
        let (b, c, d) = (self.b[i], self.c[i], self.d[i]);
        [
            self.y[i] + dx * (b + dx * (c + dx * d)),
            b + dx * (2.0 * c + 3.0 * dx * d),
            2.0 * c + 6.0 * dx * d,
            6.0 * d,
        ]
    }
}

fn check_points(what: &str, x: &[f64], y: &[f64]) -> Result<(), SplineError> {
    let n = x.len();
    if n != y.len() {
        return Err(SplineError::Fit(format!(
            "{what} has {} x values but {} y values",
            n,
            y.len()
        )));
    }
    if n < 2 {
        return Err(SplineError::Fit(format!("{what} needs at least 2 points")));
    }
    if x.iter().chain(y).any(|v| !v.is_finite()) {
        return Err(SplineError::Fit(format!("{what} points must be finite")));
    }
    if let Some(i) = (1..n).find(|&i| x[i] <= x[i - 1]) {
        return Err(SplineError::Fit(format!(
            "{what} x values must be strictly increasing: x[{}] = {} follows {}",
            i,
            x[i],
            x[i - 1]
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reproduces_cubics_exactly_and_lines_and_parabolas() {
        // The FMM end condition makes the spline exact for cubic data.
        let x: Vec<f64> = vec![-1.0, -0.3, 0.2, 0.9, 1.4, 2.0];
        let f = |t: f64| 0.5 - t + 0.3 * t * t - 0.7 * t * t * t;
        let s = SimmSpline::new(x.clone(), x.iter().map(|&t| f(t)).collect()).unwrap();
        for k in 0..=30 {
            let t = -1.0 + 3.0 * k as f64 / 30.0;
            let v = s.eval(t);
            assert!((v[0] - f(t)).abs() < 1e-13, "{t}");
            assert!((v[1] - (-1.0 + 0.6 * t - 2.1 * t * t)).abs() < 1e-12);
            assert!((v[2] - (0.6 - 4.2 * t)).abs() < 1e-11);
        }
        let l = SimmSpline::new(vec![0.0, 2.0], vec![1.0, 5.0]).unwrap();
        assert_eq!(l.eval(1.0), [3.0, 2.0, 0.0]);
        let p = SimmSpline::new(vec![0.0, 1.0, 3.0], vec![0.0, 1.0, 9.0]).unwrap();
        assert!((p.eval(2.0)[0] - 4.0).abs() < 1e-14);
        // linear extension outside
        let v = s.eval(3.0);
        let e = s.eval(2.0);
        assert!((v[0] - (e[0] + e[1])).abs() < 1e-13 && v[2] == 0.0);
    }

    #[test]
    fn natural_spline_has_zero_end_curvature_and_interpolates() {
        let x = vec![-1.0, -0.2, 0.5, 1.1, 2.0];
        let y = vec![0.3, -0.4, 0.9, 0.2, 1.5];
        let s = SimmSpline::natural(x.clone(), y.clone()).unwrap();
        for (xi, yi) in x.iter().zip(&y) {
            assert!((s.eval(*xi)[0] - yi).abs() < 1e-14);
        }
        assert!(s.eval(-1.0)[2].abs() < 1e-12 && s.eval(2.0)[2].abs() < 1e-12);
        // C² at interior knots
        for xi in &x[1..4] {
            let (l, r) = (s.eval(xi - 1e-9), s.eval(xi + 1e-9));
            assert!((l[1] - r[1]).abs() < 1e-7 && (l[2] - r[2]).abs() < 1e-6);
        }
        // linear continuation with the end slope
        let e = s.eval(2.0);
        assert!((s.eval(3.0)[0] - (e[0] + e[1])).abs() < 1e-13);
        let back: SimmSpline = serde_json::from_str(&serde_json::to_string(&s).unwrap()).unwrap();
        assert_eq!(back, s);
        assert!(SimmSpline::natural(vec![0.0, 1.0, 0.5], vec![0.0; 3]).is_err());
    }

    #[test]
    fn rejects_bad_points() {
        assert!(SimmSpline::new(vec![0.0], vec![1.0]).is_err());
        assert!(SimmSpline::new(vec![0.0, 0.0, 1.0], vec![1.0, 2.0, 3.0]).is_err());
        assert!(SimmSpline::new(vec![0.0, 1.0], vec![1.0]).is_err());
    }
}
