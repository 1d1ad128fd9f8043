//! The clamped uniform cubic B-spline basis of one transition curve, with
//! first and second derivatives.
//!
//! Kept small and private to `spacetime`: a transition has at most a few dozen
//! coefficients and its basis is evaluated once per quadrature node when the
//! problem is set up, so a dense Cox–de Boor evaluation is plenty. (The general
//! basis of the `spline` module serves curves and fitting elsewhere.)

/// Degree of the transition curves (Rose §3.1: cubic B-splines).
pub const DEGREE: usize = 3;

/// Clamped uniform cubic basis on [t0, t1] with `m` coefficients (m ≥ 4):
/// knots t0 (×4), interior uniform, t1 (×4).
#[derive(Clone, Debug)]
pub struct ClampedCubic {
    pub t0: f64,
    pub t1: f64,
    knots: Vec<f64>,
    m: usize,
}

impl ClampedCubic {
    /// `m ≥ 4` coefficients over `t0 < t1` (checked by the caller, which gives the user-facing error).
    pub fn new(t0: f64, t1: f64, m: usize) -> Self {
        debug_assert!(m >= 4 && t1 > t0);
        let spans = m - DEGREE;
        let h = (t1 - t0) / spans as f64;
        let mut knots = Vec::with_capacity(m + DEGREE + 1);
        knots.extend([t0; DEGREE]);
        for i in 0..=spans {
            // the last knot exactly t1 (no rounding drift)
            knots.push(if i == spans { t1 } else { t0 + h * i as f64 });
        }
        knots.extend([t1; DEGREE]);
        ClampedCubic { t0, t1, knots, m }
    }

    pub fn len(&self) -> usize {
        self.m
    }

    /// The distinct knots t0 < … < t1 (ends of the polynomial pieces).
    pub fn breakpoints(&self) -> Vec<f64> {
        let mut b = self.knots[DEGREE..self.knots.len() - DEGREE].to_vec();
        b.dedup();
        b
    }

    pub fn is_empty(&self) -> bool {
        self.m == 0
    }

    /// Values (`out[0]`), first (`out[1]`) and second (`out[2]`) derivatives of
    /// all `m` basis functions at `t` (clamped into [t0, t1]; at t1 the last span
    /// is used so the right end is evaluated from the left, as a closed interval).
    pub fn eval(&self, t: f64) -> [Vec<f64>; 3] {
        let t = t.clamp(self.t0, self.t1);
        let u = &self.knots;
        let nk = u.len();
        // degree-0 basis on half-open spans; at t1 take the last non-empty span.
        let mut n: Vec<Vec<f64>> = vec![vec![0.0; nk - 1]];
        let span = if t >= self.t1 {
            (0..nk - 1).rev().find(|&i| u[i] < u[i + 1]).unwrap_or(0)
        } else {
            (0..nk - 1)
                .find(|&i| u[i] <= t && t < u[i + 1])
                .unwrap_or(0)
        };
        n[0][span] = 1.0;
        for p in 1..=DEGREE {
            let mut row = vec![0.0; nk - 1 - p];
            for (i, r) in row.iter_mut().enumerate() {
                let a = ratio(t - u[i], u[i + p] - u[i]);
                let b = ratio(u[i + p + 1] - t, u[i + p + 1] - u[i + 1]);
                *r = a * n[p - 1][i] + b * n[p - 1][i + 1];
            }
            n.push(row);
        }
        // k-th derivative of N_{i,p}: p·(D^{k-1}N_{i,p-1}/(u_{i+p}-u_i) − D^{k-1}N_{i+1,p-1}/(u_{i+p+1}-u_{i+1})).
        let deriv = |k: usize| -> Vec<f64> {
            // d[p] holds D^{j}N_{·,p} for the current j, built from lower degrees.
            let mut d: Vec<f64> = n[DEGREE - k].clone();
            for j in 1..=k {
                let p = DEGREE - k + j;
                let mut next = vec![0.0; nk - 1 - p];
                for (i, r) in next.iter_mut().enumerate() {
                    *r = p as f64
                        * (ratio(d[i], u[i + p] - u[i]) - ratio(d[i + 1], u[i + p + 1] - u[i + 1]));
                }
                d = next;
            }
            d
        };
        let v = n[DEGREE][..self.m].to_vec();
        let d1 = deriv(1)[..self.m].to_vec();
        let d2 = deriv(2)[..self.m].to_vec();
        [v, d1, d2]
    }
}

/// a / b with 0/0 = 0 (the convention of repeated knots).
fn ratio(a: f64, b: f64) -> f64 {
    if b == 0.0 { 0.0 } else { a / b }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn partition_of_unity_and_derivatives_match_differences() {
        for m in [4, 5, 8, 13] {
            let b = ClampedCubic::new(0.2, 1.1, m);
            for i in 0..=50 {
                let t = 0.2 + 0.9 * i as f64 / 50.0;
                let [v, d1, d2] = b.eval(t);
                assert!((v.iter().sum::<f64>() - 1.0).abs() < 1e-13);
                assert!(d1.iter().sum::<f64>().abs() < 1e-10);
                assert!(d2.iter().sum::<f64>().abs() < 1e-8);
                let h = 1e-6;
                if t - h > 0.2 && t + h < 1.1 {
                    let [vp, d1p, _] = b.eval(t + h);
                    let [vm, d1m, _] = b.eval(t - h);
                    for j in 0..m {
                        let fd1 = (vp[j] - vm[j]) / (2.0 * h);
                        let fd2 = (d1p[j] - d1m[j]) / (2.0 * h);
                        // skip points next to a knot where d2 jumps
                        assert!((fd1 - d1[j]).abs() < 1e-6, "m={m} t={t} j={j}");
                        let knotty = (0..=m).any(|k| {
                            let s = 0.2 + 0.9 * k as f64 / (m - 3) as f64;
                            (t - s).abs() < 2.0 * h
                        });
                        if !knotty {
                            assert!(
                                (fd2 - d2[j]).abs() < 1e-4 * (1.0 + d2[j].abs()),
                                "m={m} t={t} j={j}"
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn clamped_ends_touch_only_the_end_coefficients() {
        let b = ClampedCubic::new(0.0, 1.0, 7);
        let [v, d1, d2] = b.eval(0.0);
        assert_eq!(v[0], 1.0);
        assert!(v[1..].iter().all(|x| *x == 0.0));
        assert!(d1[2..].iter().all(|x| *x == 0.0));
        assert!(d2[3..].iter().all(|x| *x == 0.0));
        let [v, d1, d2] = b.eval(1.0);
        assert_eq!(v[6], 1.0);
        assert!(v[..6].iter().all(|x| *x == 0.0));
        assert!(d1[..5].iter().all(|x| *x == 0.0));
        assert!(d2[..4].iter().all(|x| *x == 0.0));
        // a cubic with 4 coefficients is the Bézier curve: q'(0) = 3(c1 − c0)/T
        let b = ClampedCubic::new(0.0, 2.0, 4);
        let [_, d1, _] = b.eval(0.0);
        assert!((d1[0] + 1.5).abs() < 1e-14 && (d1[1] - 1.5).abs() < 1e-14);
    }
}
