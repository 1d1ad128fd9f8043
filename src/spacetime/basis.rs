//! The clamped uniform cubic B-spline basis of one transition curve, as dense
//! rows (all coefficients) of values and first and second derivatives: the
//! objective tabulates these rows once per quadrature node. Evaluation is the
//! `spline` module's [`BSplineBasis`]; the transition result is a
//! [`BSplineCurve`] on the same basis.

use crate::spline::{BSplineBasis, BSplineCurve, SplineError};

/// Degree of the transition curves (Rose §3.1: cubic B-splines).
pub const DEGREE: usize = 3;

/// Clamped uniform cubic basis on [t0, t1] with `m ≥ 4` coefficients.
#[derive(Clone, Debug)]
pub struct ClampedCubic {
    pub t0: f64,
    pub t1: f64,
    basis: BSplineBasis,
}

impl ClampedCubic {
    pub fn new(t0: f64, t1: f64, m: usize) -> Result<Self, SplineError> {
        Ok(ClampedCubic {
            t0,
            t1,
            basis: BSplineBasis::clamped_uniform(DEGREE, m, t0, t1)?,
        })
    }

    pub fn len(&self) -> usize {
        self.basis.n_coeffs()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The distinct knots t0 < … < t1 (ends of the polynomial pieces).
    pub fn breakpoints(&self) -> Vec<f64> {
        let k = self.basis.knots();
        let mut b = k[DEGREE..k.len() - DEGREE].to_vec();
        b.dedup();
        b
    }

    /// The curve with coefficients `c` on this basis.
    pub fn curve(&self, c: Vec<f64>) -> Result<BSplineCurve, SplineError> {
        BSplineCurve::new(self.basis.clone(), c)
    }

    /// Values (`out[0]`), first (`out[1]`) and second (`out[2]`) derivatives of
    /// all basis functions at `t` (clamped into [t0, t1]; the right end is
    /// evaluated from the left, as a closed interval).
    pub fn eval(&self, t: f64) -> [Vec<f64>; 3] {
        let t = t.clamp(self.t0, self.t1);
        let m = self.len();
        let mut nz = [[0.0; 6]; 3];
        let first = self.basis.eval_nonzero(t, 2, &mut nz);
        let mut out = [vec![0.0; m], vec![0.0; m], vec![0.0; m]];
        #[allow(clippy::needless_range_loop)] // i indexes nz's rows and maps to j
        for i in 0..=DEGREE {
            let j = self.basis.index(first, i);
            if j < m {
                for (o, row) in out.iter_mut().zip(&nz) {
                    o[j] = row[i];
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn partition_of_unity_and_derivatives_match_differences() {
        for m in [4, 5, 8, 13] {
            let b = ClampedCubic::new(0.2, 1.1, m).unwrap();
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
        let b = ClampedCubic::new(0.0, 1.0, 7).unwrap();
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
        let b = ClampedCubic::new(0.0, 2.0, 4).unwrap();
        let [_, d1, _] = b.eval(0.0);
        assert!((d1[0] + 1.5).abs() < 1e-14 && (d1[1] - 1.5).abs() < 1e-14);
    }
}
