//! B-spline bases (arbitrary non-decreasing knots, clamped uniform, periodic
//! uniform) and scalar B-spline curves.
//!
//! Basis functions are evaluated with the Cox–de Boor triangle and their
//! derivatives by the algorithm of Piegl & Tiller (The NURBS Book, A2.3), for
//! degree ≤ 5 and derivative order ≤ 2, into a fixed-size buffer (no allocation).
//!
//! Outside its domain a (non-periodic) basis is evaluated by the polynomial of
//! the first or last non-empty span: curves extrapolate smoothly. A periodic
//! basis wraps t into its period.
// Index loops mirror the equations (several arrays per index); iterators would obscure them.
#![allow(clippy::needless_range_loop)]

use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Highest supported degree (the evaluation buffer holds degree + 1 = 6 functions).
pub const MAX_DEGREE: usize = 5;

#[derive(Debug, Clone, PartialEq, Error)]
pub enum SplineError {
    #[error("B-spline degree {0} is not supported: use a degree from 0 to 5")]
    Degree(usize),
    #[error(
        "knot vector has {have} knots but degree {degree} needs at least {need} (2·(degree+1))"
    )]
    TooFewKnots {
        have: usize,
        need: usize,
        degree: usize,
    },
    #[error("knot {index} ({value}) is not finite: knots must be finite numbers")]
    NonFiniteKnot { index: usize, value: f64 },
    #[error(
        "knots must be non-decreasing, but knot {index} ({value}) is less than the one before ({prev})"
    )]
    Decreasing { index: usize, value: f64, prev: f64 },
    #[error(
        "knot {value} is repeated {mult} times; with degree {degree} a knot may appear at most {max} times"
    )]
    Multiplicity {
        value: f64,
        mult: usize,
        degree: usize,
        max: usize,
    },
    #[error("the spline domain [{0}, {1}] is empty: the knots at the domain ends coincide")]
    EmptyDomain(f64, f64),
    #[error("{what}: need at least {need} coefficients for degree {degree}, got {have}")]
    TooFewCoeffs {
        what: &'static str,
        need: usize,
        have: usize,
        degree: usize,
    },
    #[error("interval [{0}, {1}] must be finite with t0 < t1")]
    BadInterval(f64, f64),
    #[error("{0}")]
    Fit(String),
}

/// A B-spline basis: degree and knot vector, or a periodic uniform basis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "BasisRepr", into = "BasisRepr")]
pub struct BSplineBasis {
    degree: usize,
    /// For a periodic basis: the extended uniform knot vector of the
    /// `n_coeffs + degree` wrapped functions.
    knots: Vec<f64>,
    /// Number of free coefficients (for a periodic basis, the period count).
    n_coeffs: usize,
    periodic: bool,
}

/// The serialized form: what a user would write (validated on read).
#[derive(Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
enum BasisRepr {
    Knots {
        degree: usize,
        knots: Vec<f64>,
    },
    Periodic {
        degree: usize,
        n_coeffs: usize,
        t0: f64,
        t1: f64,
    },
}

impl TryFrom<BasisRepr> for BSplineBasis {
    type Error = SplineError;
    fn try_from(r: BasisRepr) -> Result<Self, SplineError> {
        match r {
            BasisRepr::Knots { degree, knots } => BSplineBasis::new(degree, knots),
            BasisRepr::Periodic {
                degree,
                n_coeffs,
                t0,
                t1,
            } => BSplineBasis::periodic_uniform(degree, n_coeffs, t0, t1),
        }
    }
}

impl From<BSplineBasis> for BasisRepr {
    fn from(b: BSplineBasis) -> Self {
        if b.periodic {
            let (t0, t1) = b.domain();
            BasisRepr::Periodic {
                degree: b.degree,
                n_coeffs: b.n_coeffs,
                t0,
                t1,
            }
        } else {
            BasisRepr::Knots {
                degree: b.degree,
                knots: b.knots,
            }
        }
    }
}

impl BSplineBasis {
    /// A basis of degree `degree` on `knots` (non-decreasing; a knot may repeat
    /// up to degree + 1 times, which lowers continuity there). The number of
    /// coefficients is `knots.len() − degree − 1`; the domain is
    /// `[knots[degree], knots[n_coeffs]]`.
    pub fn new(degree: usize, knots: Vec<f64>) -> Result<Self, SplineError> {
        if degree > MAX_DEGREE {
            return Err(SplineError::Degree(degree));
        }
        let need = 2 * (degree + 1);
        if knots.len() < need {
            return Err(SplineError::TooFewKnots {
                have: knots.len(),
                need,
                degree,
            });
        }
        for (i, &k) in knots.iter().enumerate() {
            if !k.is_finite() {
                return Err(SplineError::NonFiniteKnot { index: i, value: k });
            }
            if i > 0 && k < knots[i - 1] {
                return Err(SplineError::Decreasing {
                    index: i,
                    value: k,
                    prev: knots[i - 1],
                });
            }
        }
        let mut i = 0;
        while i < knots.len() {
            let mut j = i;
            while j + 1 < knots.len() && knots[j + 1] == knots[i] {
                j += 1;
            }
            if j - i + 1 > degree + 1 {
                return Err(SplineError::Multiplicity {
                    value: knots[i],
                    mult: j - i + 1,
                    degree,
                    max: degree + 1,
                });
            }
            i = j + 1;
        }
        let n = knots.len() - degree - 1;
        let b = BSplineBasis {
            degree,
            knots,
            n_coeffs: n,
            periodic: false,
        };
        let (a, z) = b.domain();
        if a >= z {
            return Err(SplineError::EmptyDomain(a, z));
        }
        Ok(b)
    }

    /// A clamped basis on [t0, t1]: end knots repeated degree + 1 times, the
    /// `n_coeffs − degree − 1` interior knots uniformly spaced. The curve
    /// interpolates its first and last coefficients.
    pub fn clamped_uniform(
        degree: usize,
        n_coeffs: usize,
        t0: f64,
        t1: f64,
    ) -> Result<Self, SplineError> {
        check_interval(t0, t1)?;
        if degree > MAX_DEGREE {
            return Err(SplineError::Degree(degree));
        }
        if n_coeffs < degree + 1 {
            return Err(SplineError::TooFewCoeffs {
                what: "clamped basis",
                need: degree + 1,
                have: n_coeffs,
                degree,
            });
        }
        let spans = n_coeffs - degree;
        let mut knots = vec![t0; degree + 1];
        for k in 1..spans {
            knots.push(t0 + (t1 - t0) * k as f64 / spans as f64);
        }
        knots.extend(std::iter::repeat_n(t1, degree + 1));
        BSplineBasis::new(degree, knots)
    }

    /// A periodic (cyclic) uniform basis of period t1 − t0 with `n_coeffs`
    /// coefficients: the curve and all its derivatives join at t1 and t0.
    /// `eval_nonzero` reports function indices modulo `n_coeffs`.
    pub fn periodic_uniform(
        degree: usize,
        n_coeffs: usize,
        t0: f64,
        t1: f64,
    ) -> Result<Self, SplineError> {
        check_interval(t0, t1)?;
        if degree > MAX_DEGREE {
            return Err(SplineError::Degree(degree));
        }
        if n_coeffs < degree + 1 {
            return Err(SplineError::TooFewCoeffs {
                what: "periodic basis",
                need: degree + 1,
                have: n_coeffs,
                degree,
            });
        }
        let h = (t1 - t0) / n_coeffs as f64;
        // n_coeffs + degree wrapped functions need n_coeffs + 2·degree + 1 knots.
        let knots = (0..n_coeffs + 2 * degree + 1)
            .map(|k| t0 + (k as f64 - degree as f64) * h)
            .collect();
        Ok(BSplineBasis {
            degree,
            knots,
            n_coeffs,
            periodic: true,
        })
    }

    pub fn degree(&self) -> usize {
        self.degree
    }
    pub fn n_coeffs(&self) -> usize {
        self.n_coeffs
    }
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }
    pub fn is_periodic(&self) -> bool {
        self.periodic
    }
    /// The parameter interval on which the basis is a partition of unity
    /// (for a periodic basis, one period).
    pub fn domain(&self) -> (f64, f64) {
        let n_ext = self.knots.len() - self.degree - 1;
        (self.knots[self.degree], self.knots[n_ext])
    }

    /// The span index s with knots[s] ≤ t < knots[s+1], restricted to the
    /// domain's non-empty spans (so t outside the domain uses an end span).
    fn span(&self, t: f64) -> usize {
        let p = self.degree;
        let n_ext = self.knots.len() - p - 1;
        let k = &self.knots;
        // last span with k[s] < k[s+1] inside [p, n_ext-1]
        let mut hi = n_ext - 1;
        while hi > p && k[hi] == k[hi + 1] {
            hi -= 1;
        }
        let mut lo = p;
        while lo < hi && k[lo] == k[lo + 1] {
            lo += 1;
        }
        if t >= k[hi] {
            return hi;
        }
        if t < k[lo + 1] {
            return lo;
        }
        // binary search for k[s] ≤ t < k[s+1]
        let (mut a, mut b) = (lo, hi);
        while b - a > 1 {
            let m = (a + b) / 2;
            if t < k[m] {
                b = m;
            } else {
                a = m;
            }
        }
        a
    }

    /// Wraps t into [t0, t1) for a periodic basis; identity otherwise.
    pub fn wrap(&self, t: f64) -> f64 {
        if !self.periodic {
            return t;
        }
        let (a, b) = self.domain();
        let w = (t - a).rem_euclid(b - a) + a;
        if w >= b { a } else { w }
    }

    /// Non-zero basis functions at t and their derivatives up to order
    /// `nderiv` (< R, the rows of `out`: 3 for the Hessian, 4 when the third
    /// derivative is wanted): `out[d][i]` is the d-th derivative of basis function
    /// `first + i`, i in 0..=degree. Returns `first`. For a periodic basis the
    /// function index is `(first + i) % n_coeffs`. Orders above `nderiv` are
    /// left untouched.
    pub fn eval_nonzero<const R: usize>(
        &self,
        t: f64,
        nderiv: usize,
        out: &mut [[f64; 6]; R],
    ) -> usize {
        let p = self.degree;
        let top = nderiv.min(R.saturating_sub(1));
        // derivatives above the degree vanish
        for row in out.iter_mut().take(top + 1).skip(p + 1) {
            row[..=p].fill(0.0);
        }
        let nd = top.min(p);
        let t = self.wrap(t);
        let s = self.span(t);
        let k = &self.knots;
        // ndu[j][r]: basis functions (upper triangle incl. diagonal) and knot differences (lower).
        let mut ndu = [[0.0f64; 6]; 6];
        let mut left = [0.0f64; 6];
        let mut right = [0.0f64; 6];
        ndu[0][0] = 1.0;
        for j in 1..=p {
            left[j] = t - k[s + 1 - j];
            right[j] = k[s + j] - t;
            let mut saved = 0.0;
            for r in 0..j {
                ndu[j][r] = right[r + 1] + left[j - r];
                let temp = ndu[r][j - 1] / ndu[j][r];
                ndu[r][j] = saved + right[r + 1] * temp;
                saved = left[j - r] * temp;
            }
            ndu[j][j] = saved;
        }
        for j in 0..=p {
            out[0][j] = ndu[j][p];
        }
        if nd > 0 {
            let mut a = [[0.0f64; 6]; 2];
            for r in 0..=p {
                let (mut s1, mut s2) = (0usize, 1usize);
                a[0][0] = 1.0;
                for kk in 1..=nd {
                    let mut d = 0.0;
                    let rk = r as isize - kk as isize;
                    let pk = p as isize - kk as isize;
                    if r >= kk {
                        a[s2][0] = a[s1][0] / ndu[(pk + 1) as usize][rk as usize];
                        d = a[s2][0] * ndu[rk as usize][pk as usize];
                    }
                    let j1 = if rk >= -1 { 1 } else { (-rk) as usize };
                    let j2 = if (r as isize) - 1 <= pk {
                        kk - 1
                    } else {
                        p - r
                    };
                    for j in j1..=j2 {
                        let idx = (rk + j as isize) as usize;
                        a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[(pk + 1) as usize][idx];
                        d += a[s2][j] * ndu[idx][pk as usize];
                    }
                    if r as isize <= pk {
                        a[s2][kk] = -a[s1][kk - 1] / ndu[(pk + 1) as usize][r];
                        d += a[s2][kk] * ndu[r][pk as usize];
                    }
                    out[kk][r] = d;
                    std::mem::swap(&mut s1, &mut s2);
                }
            }
            let mut f = p as f64;
            for kk in 1..=nd {
                for j in 0..=p {
                    out[kk][j] *= f;
                }
                f *= (p - kk) as f64;
            }
        }
        let first = s - p;
        if self.periodic {
            first % self.n_coeffs
        } else {
            first
        }
    }

    /// Coefficient index of the i-th non-zero function when `first` was returned.
    #[inline]
    pub fn index(&self, first: usize, i: usize) -> usize {
        if self.periodic {
            (first + i) % self.n_coeffs
        } else {
            first + i
        }
    }
}

fn check_interval(t0: f64, t1: f64) -> Result<(), SplineError> {
    if !(t0.is_finite() && t1.is_finite() && t0 < t1) {
        return Err(SplineError::BadInterval(t0, t1));
    }
    Ok(())
}

/// A scalar B-spline curve Σ cᵢ Bᵢ(t).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BSplineCurve {
    pub basis: BSplineBasis,
    pub coeffs: Vec<f64>,
}

impl BSplineCurve {
    /// A curve; `coeffs.len()` must equal `basis.n_coeffs()`.
    pub fn new(basis: BSplineBasis, coeffs: Vec<f64>) -> Result<Self, SplineError> {
        if coeffs.len() != basis.n_coeffs() {
            return Err(SplineError::Fit(format!(
                "curve needs {} coefficients for its basis, got {}",
                basis.n_coeffs(),
                coeffs.len()
            )));
        }
        Ok(BSplineCurve { basis, coeffs })
    }

    /// Value, first and second derivative at t.
    pub fn eval(&self, t: f64) -> [f64; 3] {
        let [f, d1, d2, _] = self.eval3(t);
        [f, d1, d2]
    }

    /// Value and first three derivatives at t (the third for the joints'
    /// third-derivative kinematics).
    pub fn eval3(&self, t: f64) -> [f64; 4] {
        let mut b = [[0.0; 6]; 4];
        let p = self.basis.degree();
        let first = self.basis.eval_nonzero(t, 3, &mut b);
        let mut r = [0.0; 4];
        for i in 0..=p {
            let c = self
                .coeffs
                .get(self.basis.index(first, i))
                .copied()
                .unwrap_or(0.0);
            for (d, rd) in r.iter_mut().enumerate() {
                *rd += c * b[d][i];
            }
        }
        // Orders above the degree were left untouched by eval_nonzero: zero them.
        for rd in r.iter_mut().skip(p + 1) {
            *rd = 0.0;
        }
        r
    }
}
