//! Scalar curves of time: each gives its value and first and second time
//! derivatives, because the dynamics needs q, q̇ and q̈.

use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::error::{FnError, MotionError, finite};
use super::time_tol;

/// A scalar function of time supplied from outside the motion library — the
/// interpreter implements it for mx functions of time.
pub trait TimeFunction: Send + Sync + std::fmt::Debug {
    /// The value at time `t`, or why it cannot be computed.
    fn eval(&self, t: f64) -> Result<f64, FnError>;
    /// Self-contained mx source of the function, so a motion holding it can
    /// be written to JSON and compiled again on load. `None`: not saveable.
    fn source(&self) -> Option<String> {
        None
    }
}

/// One scalar curve of (local) time.
#[derive(Clone, Debug)]
pub enum Curve {
    /// The same value at every time.
    Constant(f64),
    /// Uniformly sampled data, interpolated by a C² cubic spline.
    Samples(SampledCurve),
    /// A function of time from outside (an mx function); derivatives by
    /// fourth-order central differences.
    Function(Arc<dyn TimeFunction>),
    /// The cubic that joins two end states (time, value, velocity).
    Hermite(HermiteCurve),
    /// A B-spline (spacetime transitions, cyclified motions): exact derivatives.
    Spline(crate::spline::BSplineCurve),
    /// The sum of two curves (an SP transition that corrects a laid example:
    /// the example plus the solved spline), exact as its parts are.
    Sum(Arc<Curve>, Arc<Curve>),
}

impl Curve {
    /// A constant curve; `Err` when `v` is not finite.
    pub fn constant(v: f64) -> Result<Curve, MotionError> {
        Ok(Curve::Constant(finite("constant value", v)?))
    }

    /// Samples `values[k]` at times `t0 + k·dt`.
    pub fn samples(t0: f64, dt: f64, values: Vec<f64>) -> Result<Curve, MotionError> {
        Ok(Curve::Samples(SampledCurve::new(t0, dt, values)?))
    }

    /// A B-spline curve, checked: one coefficient per basis function, all finite.
    pub fn spline(c: crate::spline::BSplineCurve) -> Result<Curve, MotionError> {
        let need = c.basis.n_coeffs();
        if c.coeffs.len() != need {
            return Err(MotionError::BadSamples(format!(
                "B-spline needs {need} coefficients for its basis, got {}",
                c.coeffs.len()
            )));
        }
        if let Some(k) = c.coeffs.iter().position(|v| !v.is_finite()) {
            return Err(MotionError::BadSamples(format!(
                "B-spline coefficient {k} is {}, not a finite number",
                c.coeffs[k]
            )));
        }
        Ok(Curve::Spline(c))
    }

    /// Value, first and second derivative at `t`.
    pub fn eval(&self, t: f64) -> Result<[f64; 3], MotionError> {
        match self {
            Curve::Constant(v) => Ok([*v, 0.0, 0.0]),
            Curve::Samples(s) => s.eval(t),
            Curve::Function(f) => eval_function(f.as_ref(), t),
            Curve::Hermite(h) => Ok(h.eval(t)),
            Curve::Spline(c) => Ok(c.eval(t)),
            Curve::Sum(a, b) => {
                let (a, b) = (a.eval(t)?, b.eval(t)?);
                Ok([a[0] + b[0], a[1] + b[1], a[2] + b[2]])
            }
        }
    }

    /// Value only (cheaper for functions: one evaluation instead of five).
    pub fn value(&self, t: f64) -> Result<f64, MotionError> {
        match self {
            Curve::Constant(v) => Ok(*v),
            Curve::Samples(s) => s.value(t),
            Curve::Function(f) => call(f.as_ref(), t),
            Curve::Hermite(h) => Ok(h.eval(t)[0]),
            Curve::Spline(c) => Ok(c.eval(t)[0]),
            Curve::Sum(a, b) => Ok(a.value(t)? + b.value(t)?),
        }
    }

    /// Structural equality: functions compare by identity or, failing that,
    /// by their mx source (what a JSON round trip preserves).
    pub fn same_as(&self, other: &Curve) -> bool {
        match (self, other) {
            (Curve::Constant(a), Curve::Constant(b)) => a.to_bits() == b.to_bits(),
            (Curve::Samples(a), Curve::Samples(b)) => a == b,
            (Curve::Hermite(a), Curve::Hermite(b)) => a == b,
            (Curve::Spline(a), Curve::Spline(b)) => a == b,
            (Curve::Sum(a, b), Curve::Sum(c, d)) => a.same_as(c) && b.same_as(d),
            (Curve::Function(a), Curve::Function(b)) => {
                Arc::ptr_eq(a, b) || (a.source().is_some() && a.source() == b.source())
            }
            _ => false,
        }
    }
}

impl PartialEq for Curve {
    fn eq(&self, other: &Self) -> bool {
        self.same_as(other)
    }
}

fn call(f: &dyn TimeFunction, t: f64) -> Result<f64, MotionError> {
    match f.eval(t) {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(v) => Err(MotionError::Function {
            t,
            message: format!("returned {v}, not a finite number"),
            dof: None,
        }),
        Err(e) => Err(MotionError::Function {
            t,
            message: e.to_string(),
            dof: None,
        }),
    }
}

/// Fourth-order central differences with an absolute step of 1 ms: motion
/// features have the same time scale at t = 1000 s as at t = 0, so the step
/// must not grow with |t| (it does only past 10⁷ s, to stay ≫ one ulp of t).
/// Truncation (∝ h⁴) and rounding (∝ ε|t|/h for f′, ε|t|/h² for f″) then
/// give about 1e-11 relative for f′ and 1e-9 for f″ on smooth functions.
fn eval_function(f: &dyn TimeFunction, t: f64) -> Result<[f64; 3], MotionError> {
    let v = call(f, t)?;
    let h0 = (1e-10 * t.abs()).max(1e-3);
    // Make h exactly representable relative to t so t ± h are the points used.
    let h = (t + h0) - t;
    let fp1 = call(f, t + h)?;
    let fm1 = call(f, t - h)?;
    let fp2 = call(f, t + 2.0 * h)?;
    let fm2 = call(f, t - 2.0 * h)?;
    let d1 = (-fp2 + 8.0 * fp1 - 8.0 * fm1 + fm2) / (12.0 * h);
    let d2 = (-fp2 + 16.0 * fp1 - 30.0 * v + 16.0 * fm1 - fm2) / (12.0 * h * h);
    Ok([v, d1, d2])
}

/// Uniform samples interpolated by a not-a-knot cubic spline (C², and no
/// artificial zero acceleration at the ends as a natural spline would force —
/// SP transitions match q̈ at clip ends).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "SampledRaw", into = "SampledRaw")]
pub struct SampledCurve {
    t0: f64,
    dt: f64,
    values: Vec<f64>,
    /// Second derivatives at the knots (derived from the values, not stored in files).
    m: Vec<f64>,
}

#[derive(Serialize, Deserialize)]
struct SampledRaw {
    t0: f64,
    dt: f64,
    values: Vec<f64>,
}

impl TryFrom<SampledRaw> for SampledCurve {
    type Error = MotionError;
    fn try_from(r: SampledRaw) -> Result<Self, MotionError> {
        SampledCurve::new(r.t0, r.dt, r.values)
    }
}

impl From<SampledCurve> for SampledRaw {
    fn from(s: SampledCurve) -> Self {
        SampledRaw {
            t0: s.t0,
            dt: s.dt,
            values: s.values,
        }
    }
}

impl SampledCurve {
    pub fn new(t0: f64, dt: f64, values: Vec<f64>) -> Result<SampledCurve, MotionError> {
        finite("sample start time", t0)?;
        if !(dt.is_finite() && dt > 0.0) {
            return Err(MotionError::BadSamples(format!(
                "sample step must be a positive finite number of seconds, got {dt}"
            )));
        }
        if values.is_empty() {
            return Err(MotionError::BadSamples(
                "no samples (need at least one value)".into(),
            ));
        }
        if let Some(k) = values.iter().position(|v| !v.is_finite()) {
            return Err(MotionError::BadSamples(format!(
                "sample {k} (t = {}) is {}, not a finite number",
                t0 + k as f64 * dt,
                values[k]
            )));
        }
        let m = not_a_knot_second_derivatives(&values, dt);
        Ok(SampledCurve { t0, dt, values, m })
    }

    pub fn t0(&self) -> f64 {
        self.t0
    }
    pub fn dt(&self) -> f64 {
        self.dt
    }
    pub fn values(&self) -> &[f64] {
        &self.values
    }
    /// Time of the last sample.
    pub fn t_end(&self) -> f64 {
        self.t0 + (self.values.len() - 1) as f64 * self.dt
    }

    /// Segment index, offset into it, and the knot index when `t` is a
    /// sample time (within 1e-9 of a step: rounding of k/R vs t0 + k·dt), or
    /// an error outside the data.
    fn locate(&self, t: f64) -> Result<(usize, f64, Option<usize>), MotionError> {
        let end = self.t_end();
        if !t.is_finite() || t < self.t0 - time_tol(self.t0) || t > end + time_tol(end) {
            return Err(MotionError::OutsideSamples {
                t,
                start: self.t0,
                stop: end,
            });
        }
        let n = self.values.len();
        if n == 1 {
            return Ok((0, 0.0, Some(0)));
        }
        let mut x = ((t - self.t0) / self.dt).clamp(0.0, (n - 1) as f64);
        let knot = if (x - x.round()).abs() < 1e-9 {
            x = x.round();
            Some(x as usize)
        } else {
            None
        };
        let i = (x.floor() as usize).min(n - 2);
        Ok((i, (x - i as f64) * self.dt, knot))
    }

    /// Value only. At a sample time it is that sample, exactly, so saving a
    /// clip at its own frame rate reproduces the data bit for bit.
    pub fn value(&self, t: f64) -> Result<f64, MotionError> {
        let (i, s, knot) = self.locate(t)?;
        if let Some(k) = knot {
            return Ok(self.values[k]);
        }
        let [b, c, d] = self.power(i);
        Ok(self.values[i] + s * (b + s * (c + s * d)))
    }

    pub fn eval(&self, t: f64) -> Result<[f64; 3], MotionError> {
        let (i, s, knot) = self.locate(t)?;
        if self.values.len() == 1 {
            return Ok([self.values[0], 0.0, 0.0]);
        }
        let [b, c, d] = self.power(i);
        let v = match knot {
            Some(k) => self.values[k],
            None => self.values[i] + s * (b + s * (c + s * d)),
        };
        Ok([v, b + s * (2.0 * c + 3.0 * d * s), 2.0 * c + 6.0 * d * s])
    }

    /// Segment i as y[i] + b·s + c·s² + d·s³ (s = t − t[i]): exact at s = 0.
    fn power(&self, i: usize) -> [f64; 3] {
        let h = self.dt;
        let (y0, y1, m0, m1) = (self.values[i], self.values[i + 1], self.m[i], self.m[i + 1]);
        [
            (y1 - y0) / h - h * (2.0 * m0 + m1) / 6.0,
            0.5 * m0,
            (m1 - m0) / (6.0 * h),
        ]
    }
}

/// Knot second derivatives M of the not-a-knot cubic spline on a uniform grid.
/// Interior rows: M[i−1] + 4M[i] + M[i+1] = 6(y[i+1] − 2y[i] + y[i−1])/h².
/// Not-a-knot (M[0] = 2M[1] − M[2], likewise at the end) turns the first and
/// last rows into 6M[1] = r[1] and 6M[n−2] = r[n−2]; a diagonally dominant
/// tridiagonal system solved by the Thomas algorithm.
fn not_a_knot_second_derivatives(y: &[f64], h: f64) -> Vec<f64> {
    let n = y.len();
    let mut m = vec![0.0; n];
    if n < 3 {
        return m; // constant or straight line
    }
    let r = |i: usize| 6.0 * (y[i + 1] - 2.0 * y[i] + y[i - 1]) / (h * h);
    if n == 3 {
        // One parabola through three points.
        m.fill(r(1) / 6.0);
        return m;
    }
    // Unknowns M[1..n-1] (k = i − 1), k = 0..n−3, solved in place in m (the
    // right-hand side goes in, the solution comes out): the off-diagonals are
    // 1 but for the not-a-knot rows, so only the diagonal needs a scratch
    // vector (one allocation per curve; a clip builds one curve per channel).
    let k = n - 2;
    let sub = |j: usize| if j == k - 1 { 0.0 } else { 1.0 }; // coefficient of unknown j−1 in row j
    let sup = |j: usize| if j == 0 { 0.0 } else { 1.0 }; // coefficient of unknown j+1 in row j
    let mut diag = vec![4.0; k];
    diag[0] = 6.0;
    diag[k - 1] = 6.0;
    for (i, mi) in m.iter_mut().enumerate().take(n - 1).skip(1) {
        *mi = r(i);
    }
    let rhs = &mut m[1..n - 1];
    for j in 1..k {
        let w = sub(j) / diag[j - 1];
        diag[j] -= w * sup(j - 1);
        rhs[j] -= w * rhs[j - 1];
    }
    rhs[k - 1] /= diag[k - 1];
    for j in (0..k - 1).rev() {
        rhs[j] = (rhs[j] - sup(j) * rhs[j + 1]) / diag[j];
    }
    m[0] = 2.0 * m[1] - m[2];
    m[n - 1] = 2.0 * m[n - 2] - m[n - 3];
    m
}

/// The cubic joining (t0, q0, v0) to (t1, q1, v1): the simplest C¹ bridge
/// across a gap (e.g. a quick `fill` before a full spacetime transition).
/// Evaluated outside [t0, t1] it continues the same polynomial.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HermiteCurve {
    pub t0: f64,
    pub t1: f64,
    pub q0: f64,
    pub v0: f64,
    pub q1: f64,
    pub v1: f64,
}

impl HermiteCurve {
    pub fn new(
        t0: f64,
        q0: f64,
        v0: f64,
        t1: f64,
        q1: f64,
        v1: f64,
    ) -> Result<HermiteCurve, MotionError> {
        for (what, v) in [
            ("Hermite start time", t0),
            ("Hermite stop time", t1),
            ("Hermite start value", q0),
            ("Hermite start velocity", v0),
            ("Hermite end value", q1),
            ("Hermite end velocity", v1),
        ] {
            finite(what, v)?;
        }
        if t1 - t0 <= time_tol(t0) {
            return Err(MotionError::EmptyInterval {
                start: t0,
                stop: t1,
            });
        }
        Ok(HermiteCurve {
            t0,
            t1,
            q0,
            v0,
            q1,
            v1,
        })
    }

    pub fn eval(&self, t: f64) -> [f64; 3] {
        let h = self.t1 - self.t0;
        let s = (t - self.t0) / h;
        let (s2, s3) = (s * s, s * s * s);
        // Hermite basis and its derivatives with respect to s.
        let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
        let h10 = s3 - 2.0 * s2 + s;
        let h01 = -2.0 * s3 + 3.0 * s2;
        let h11 = s3 - s2;
        let d00 = 6.0 * s2 - 6.0 * s;
        let d10 = 3.0 * s2 - 4.0 * s + 1.0;
        let d01 = -6.0 * s2 + 6.0 * s;
        let d11 = 3.0 * s2 - 2.0 * s;
        let e00 = 12.0 * s - 6.0;
        let e10 = 6.0 * s - 4.0;
        let e01 = -12.0 * s + 6.0;
        let e11 = 6.0 * s - 2.0;
        let (q0, q1, m0, m1) = (self.q0, self.q1, self.v0 * h, self.v1 * h);
        let v = h00 * q0 + h10 * m0 + h01 * q1 + h11 * m1;
        let d = (d00 * q0 + d10 * m0 + d01 * q1 + d11 * m1) / h;
        let dd = (e00 * q0 + e10 * m0 + e01 * q1 + e11 * m1) / (h * h);
        [v, d, dd]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol * (1.0 + b.abs())
    }

    #[test]
    fn not_a_knot_spline_reproduces_cubics_exactly() {
        // A cubic is its own not-a-knot interpolant: value, q̇ and q̈ exact.
        let p = |t: f64| {
            [
                0.3 - 1.2 * t + 0.7 * t * t - 0.25 * t * t * t,
                -1.2 + 1.4 * t - 0.75 * t * t,
                1.4 - 1.5 * t,
            ]
        };
        let (t0, dt) = (-0.5, 0.1);
        let values = (0..31).map(|k| p(t0 + k as f64 * dt)[0]).collect();
        let c = Curve::samples(t0, dt, values).unwrap();
        for k in 0..=300 {
            let t = t0 + 3.0 * k as f64 / 300.0;
            let got = c.eval(t).unwrap();
            assert_eq!(c.value(t).unwrap(), got[0]);
            let want = p(t);
            for i in 0..3 {
                assert!(
                    close(got[i], want[i], 1e-10),
                    "t={t} i={i}: {got:?} vs {want:?}"
                );
            }
        }
    }

    #[test]
    fn sampled_sine_has_accurate_derivatives() {
        let dt = 1.0 / 120.0;
        let values = (0..=240).map(|k| (k as f64 * dt * 3.0).sin()).collect();
        let c = Curve::samples(0.0, dt, values).unwrap();
        let mut err = [0.0f64; 3];
        for k in 0..=997 {
            let t = 2.0 * k as f64 / 997.0;
            let got = c.eval(t).unwrap();
            let want = [
                (3.0 * t).sin(),
                3.0 * (3.0 * t).cos(),
                -9.0 * (3.0 * t).sin(),
            ];
            for i in 0..3 {
                err[i] = err[i].max((got[i] - want[i]).abs());
            }
        }
        // O(h⁴), O(h³), O(h²) with h = 1/120 (ends included).
        assert!(err[0] < 1e-7 && err[1] < 1e-5 && err[2] < 2e-2, "{err:?}");
    }

    #[test]
    fn sample_times_give_the_samples_exactly() {
        let values: Vec<f64> = (0..50).map(|k| (k as f64 * 0.37).sin() * 1e3).collect();
        let c = Curve::samples(0.2, 1.0 / 30.0, values.clone()).unwrap();
        for (k, v) in values.iter().enumerate() {
            // Both ways of writing the time: t0 + k·dt and (6 + k)/30.
            assert_eq!(c.value(0.2 + k as f64 / 30.0).unwrap(), *v);
            assert_eq!(c.value((6 + k) as f64 / 30.0).unwrap(), *v);
            assert_eq!(c.eval((6 + k) as f64 / 30.0).unwrap()[0], *v);
        }
    }

    #[test]
    fn few_samples_and_bad_samples() {
        assert_eq!(
            Curve::samples(1.0, 0.5, vec![2.0])
                .unwrap()
                .eval(1.0)
                .unwrap(),
            [2.0, 0.0, 0.0]
        );
        let lin = Curve::samples(0.0, 1.0, vec![0.0, 2.0]).unwrap();
        assert_eq!(lin.eval(0.5).unwrap(), [1.0, 2.0, 0.0]);
        let par = Curve::samples(0.0, 1.0, vec![0.0, 1.0, 4.0]).unwrap(); // t²
        let v = par.eval(1.5).unwrap();
        assert!(
            close(v[0], 2.25, 1e-14) && close(v[1], 3.0, 1e-14) && close(v[2], 2.0, 1e-14),
            "{v:?}"
        );
        let four = Curve::samples(0.0, 1.0, vec![0.0, 1.0, 8.0, 27.0]).unwrap(); // t³
        let v = four.eval(2.5).unwrap();
        assert!(
            close(v[0], 15.625, 1e-12) && close(v[1], 18.75, 1e-12) && close(v[2], 15.0, 1e-12),
            "{v:?}"
        );

        assert!(matches!(
            Curve::samples(0.0, 1.0, vec![]),
            Err(MotionError::BadSamples(_))
        ));
        assert!(matches!(
            Curve::samples(0.0, 0.0, vec![1.0]),
            Err(MotionError::BadSamples(_))
        ));
        assert!(matches!(
            Curve::samples(0.0, -1.0, vec![1.0]),
            Err(MotionError::BadSamples(_))
        ));
        assert!(matches!(
            Curve::samples(0.0, f64::NAN, vec![1.0]),
            Err(MotionError::BadSamples(_))
        ));
        assert!(matches!(
            Curve::samples(f64::INFINITY, 1.0, vec![1.0]),
            Err(MotionError::NonFinite { .. })
        ));
        let e = Curve::samples(0.0, 1.0, vec![1.0, f64::NAN]).unwrap_err();
        assert!(e.to_string().contains("sample 1"), "{e}");
        assert!(matches!(
            Curve::constant(f64::NAN),
            Err(MotionError::NonFinite { .. })
        ));
    }

    #[test]
    fn samples_outside_their_range_are_an_error_but_rounding_is_not() {
        let c = Curve::samples(0.0, 0.1, vec![0.0, 1.0, 2.0, 3.0]).unwrap();
        assert!(matches!(
            c.eval(-0.01),
            Err(MotionError::OutsideSamples { .. })
        ));
        assert!(matches!(
            c.eval(0.31),
            Err(MotionError::OutsideSamples { .. })
        ));
        assert!(matches!(
            c.eval(f64::NAN),
            Err(MotionError::OutsideSamples { .. })
        ));
        // 0.1·3 = 0.30000000000000004: a rounding error past the end is the end.
        assert!(close(c.eval(0.1 * 3.0).unwrap()[0], 3.0, 1e-12));
        assert!(close(c.eval(-1e-15).unwrap()[0], 0.0, 1e-12));
    }

    #[derive(Debug)]
    struct Sin(f64);
    impl TimeFunction for Sin {
        fn eval(&self, t: f64) -> Result<f64, FnError> {
            Ok((self.0 * t).sin())
        }
    }

    #[test]
    fn function_derivatives_by_central_differences() {
        for &w in &[1.0, 5.0] {
            let c = Curve::Function(Arc::new(Sin(w)));
            for &t in &[0.0, 0.3, 1.0, 17.5, 1000.0] {
                let [v, d, dd] = c.eval(t).unwrap();
                let (s, co) = ((w * t).sin(), (w * t).cos());
                assert_eq!(v, s);
                // Relative to the derivative's scale w, w².
                assert!((d - w * co).abs() < 1e-10 * w, "w={w} t={t}: {d}");
                assert!((dd + w * w * s).abs() < 1e-8 * w * w, "w={w} t={t}: {dd}");
            }
        }
    }

    #[derive(Debug)]
    struct Bad;
    impl TimeFunction for Bad {
        fn eval(&self, t: f64) -> Result<f64, FnError> {
            if t > 1.0 {
                Err("boom".into())
            } else {
                Ok(f64::NAN)
            }
        }
    }

    #[test]
    fn failing_functions_are_errors() {
        let c = Curve::Function(Arc::new(Bad));
        let e = c.value(0.5).unwrap_err().to_string();
        assert!(e.contains("NaN") && e.contains("0.5"), "{e}");
        let e = c.value(2.0).unwrap_err().to_string();
        assert!(e.contains("boom"), "{e}");
    }

    #[test]
    fn hermite_meets_its_end_states() {
        let h = HermiteCurve::new(1.0, 0.5, -2.0, 3.0, 1.5, 4.0).unwrap();
        let a = h.eval(1.0);
        let b = h.eval(3.0);
        assert!(close(a[0], 0.5, 1e-15) && close(a[1], -2.0, 1e-15));
        assert!(close(b[0], 1.5, 1e-15) && close(b[1], 4.0, 1e-14));
        // Second derivative against a difference of first derivatives.
        let e = 1e-6;
        let fd = (h.eval(2.0 + e)[1] - h.eval(2.0 - e)[1]) / (2.0 * e);
        assert!(close(h.eval(2.0)[2], fd, 1e-8));
        assert!(HermiteCurve::new(1.0, 0.0, 0.0, 1.0, 0.0, 0.0).is_err());
        assert!(HermiteCurve::new(0.0, f64::NAN, 0.0, 1.0, 0.0, 0.0).is_err());
    }
}
