//! The scalar coefficient functions of the SO(3)/SE(3) exponential and its
//! derivatives, each accurate to a few ulps for every angle.
//!
//! Each function that cancels catastrophically near θ = 0 switches to its own
//! Taylor series below its own threshold: the threshold is chosen where the
//! closed form has lost at most ~1 digit and the truncated series is exact to
//! below 1e-17 (relative). There is no global epsilon on purpose: a single
//! cut-off would be too small for one series and too large for another.

/// sin θ / θ. No cancellation: `sin` is accurate, only θ = 0 needs a rule.
#[inline]
pub fn sinc(theta: f64) -> f64 {
    // Below 1e-4 the series 1 − θ²/6 + θ⁴/120 is exact to θ⁶/5040 < 1e-27.
    if theta.abs() < 1e-4 {
        let t2 = theta * theta;
        1.0 - t2 / 6.0 * (1.0 - t2 / 20.0)
    } else {
        theta.sin() / theta
    }
}

/// (1 − cos θ)/θ², computed as ½ (sin(θ/2)/(θ/2))², which never cancels.
#[inline]
pub fn one_minus_cos_over_t2(theta: f64) -> f64 {
    let s = sinc(0.5 * theta);
    0.5 * s * s
}

/// (θ − sin θ)/θ³. The closed form loses ~ log10(6/θ²) digits; below θ = 1
/// the series (10 terms, remainder θ²⁰/23! < 4e-23) is used instead.
#[inline]
pub fn t_minus_sin_over_t3(theta: f64) -> f64 {
    let t2 = theta * theta;
    if theta.abs() < 1.0 {
        // Σ_{n≥0} (−1)ⁿ θ²ⁿ / (2n+3)!, by Horner from the top.
        let mut acc = 0.0;
        for n in (0..10).rev() {
            acc = 1.0 / fact(2 * n + 3) - t2 * acc;
        }
        acc
    } else {
        (theta - theta.sin()) / (t2 * theta)
    }
}

/// (1 − (θ/2) cot(θ/2)) / θ², the coefficient of W² in the inverse of the SE(3)
/// left Jacobian V⁻¹ = I − ½W + D W². Series below θ = 1 (remainder < 1e-19).
#[inline]
pub fn log_v_coeff(theta: f64) -> f64 {
    let t2 = theta * theta;
    if theta.abs() < 1.0 {
        // x cot x = 1 − Σ c_n x^{2n}, x = θ/2, c_n = 2^{2n}|B_{2n}|/(2n)!; D = Σ c_n x^{2n−2} / 4.
        const C: [f64; 9] = [
            1.0 / 3.0,
            1.0 / 45.0,
            2.0 / 945.0,
            1.0 / 4725.0,
            2.0 / 93555.0,
            1382.0 / 638512875.0,
            4.0 / 18243225.0,
            3617.0 / 162820783125.0,
            87734.0 / 38979295480125.0,
        ];
        let x2 = 0.25 * t2;
        let mut acc = 0.0;
        for c in C.iter().rev() {
            acc = c + x2 * acc;
        }
        0.25 * acc
    } else {
        let half = 0.5 * theta;
        (1.0 - half * half.cos() / half.sin()) / t2
    }
}

fn fact(n: usize) -> f64 {
    (1..=n).fold(1.0, |a, k| a * k as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    // Reference values by direct summation in an extended (double-double style)
    // fashion would be overkill: at θ = 1 both branches must agree, and small θ
    // must give the leading terms.
    #[test]
    fn branches_agree_at_their_thresholds() {
        for &t in &[1.0 - 1e-12, 1.0, 1.0 + 1e-12] {
            let a = t_minus_sin_over_t3(t);
            let b = (t - t.sin()) / (t * t * t);
            assert!((a - b).abs() < 1e-15, "{a} {b}");
            let c = log_v_coeff(t);
            let d = (1.0 - 0.5 * t * (0.5 * t).cos() / (0.5 * t).sin()) / (t * t);
            assert!((c - d).abs() < 1e-15, "{c} {d}");
        }
        assert!((sinc(1e-4) - (1e-4f64).sin() / 1e-4).abs() < 1e-16);
    }

    #[test]
    fn small_angle_limits() {
        assert_eq!(sinc(0.0), 1.0);
        assert!((one_minus_cos_over_t2(0.0) - 0.5).abs() < 1e-16);
        assert!((t_minus_sin_over_t3(0.0) - 1.0 / 6.0).abs() < 1e-16);
        assert!((log_v_coeff(0.0) - 1.0 / 12.0).abs() < 1e-16);
        // second-order terms
        let t = 1e-3;
        let e = t_minus_sin_over_t3(t) - (1.0 / 6.0 - t * t / 120.0 + t.powi(4) / 5040.0);
        assert!(e.abs() < 1e-16, "{e}");
        assert!((log_v_coeff(t) - (1.0 / 12.0 + t * t / 720.0)).abs() < 1e-16);
        // at π the W² coefficient of V⁻¹ is 1/π²
        let p = std::f64::consts::PI;
        assert!((log_v_coeff(p) - 1.0 / (p * p)).abs() < 1e-15);
    }
}
