//! B-spline bases and curves: partition of unity, derivatives against a naive
//! Cox–de Boor recursion and finite differences, coincident knots, periodic
//! continuity, least-squares fits, errors and serde.
// Index loops mirror the equations (several arrays per index); iterators would obscure them.
#![allow(clippy::needless_range_loop)]

use mx::spline::*;

/// Naive recursive Cox–de Boor for reference (half-open spans; right end of the domain handled by caller).
fn cox(k: &[f64], i: usize, p: usize, t: f64) -> f64 {
    if p == 0 {
        return if k[i] <= t && t < k[i + 1] { 1.0 } else { 0.0 };
    }
    let mut r = 0.0;
    if k[i + p] > k[i] {
        r += (t - k[i]) / (k[i + p] - k[i]) * cox(k, i, p - 1, t);
    }
    if k[i + p + 1] > k[i + 1] {
        r += (k[i + p + 1] - t) / (k[i + p + 1] - k[i + 1]) * cox(k, i + 1, p - 1, t);
    }
    r
}

fn bases() -> Vec<BSplineBasis> {
    vec![
        BSplineBasis::clamped_uniform(3, 8, 0.0, 2.0).unwrap(),
        BSplineBasis::clamped_uniform(5, 9, -1.0, 1.0).unwrap(),
        BSplineBasis::clamped_uniform(1, 4, 0.0, 1.0).unwrap(),
        // non-uniform with a double and a triple knot
        BSplineBasis::new(
            3,
            vec![
                0., 0., 0., 0., 0.3, 0.3, 0.7, 1.1, 1.1, 1.1, 2.0, 2.0, 2.0, 2.0,
            ],
        )
        .unwrap(),
        BSplineBasis::periodic_uniform(3, 7, 0.0, 1.0).unwrap(),
        BSplineBasis::new(2, vec![0., 1., 2., 3., 4., 5., 6.]).unwrap(),
    ]
}

#[test]
fn partition_of_unity_and_match_with_cox_de_boor() {
    for b in bases() {
        let (a, z) = b.domain();
        let mut out = [[0.0; 6]; 3];
        for k in 0..=200 {
            let t = a + (z - a) * k as f64 / 200.0;
            let first = b.eval_nonzero(t, 2, &mut out);
            let p = b.degree();
            let s0: f64 = out[0][..=p].iter().sum();
            let s1: f64 = out[1][..=p].iter().sum();
            let s2: f64 = out[2][..=p].iter().sum();
            assert!((s0 - 1.0).abs() < 1e-14, "{b:?} t={t}: Σ={s0}");
            assert!(s1.abs() < 1e-10 && s2.abs() < 1e-8, "t={t}: {s1} {s2}");
            if !b.is_periodic() && t < z {
                for i in 0..=p {
                    let r = cox(b.knots(), first + i, p, t);
                    assert!(
                        (out[0][i] - r).abs() < 1e-14,
                        "t={t} i={i}: {} vs {r}",
                        out[0][i]
                    );
                }
            }
        }
    }
}

#[test]
fn curve_derivatives_match_finite_differences_including_at_knots() {
    for b in bases() {
        let n = b.n_coeffs();
        let coeffs: Vec<f64> = (0..n)
            .map(|i| ((i * 7 % 5) as f64 - 2.0) * 0.7 + i as f64 * 0.1)
            .collect();
        let c = BSplineCurve::new(b.clone(), coeffs).unwrap();
        let (a, z) = b.domain();
        let mut ts: Vec<f64> = (1..40).map(|k| a + (z - a) * k as f64 / 40.0).collect();
        ts.extend(b.knots().iter().copied().filter(|&k| k > a && k < z));
        let h = 1e-5;
        for t in ts {
            let v = c.eval(t);
            let mult = b.knots().iter().filter(|&&k| (k - t).abs() < 1e-12).count();
            let h1 = if mult > 0 { 1e-8 } else { h };
            let fd1 = (c.eval(t + h1)[0] - c.eval(t - h1)[0]) / (2.0 * h1);
            // f' is continuous at a knot of multiplicity ≤ p − 1 only
            assert!(
                mult + 1 > b.degree() || (fd1 - v[1]).abs() < 1e-6 * (1.0 + v[1].abs()),
                "{b:?} {t}: {fd1} vs {}",
                v[1]
            );
            // at a knot of multiplicity ≥ p−1 the second derivative may jump: only check where C².
            if b.degree() >= 3 && mult <= b.degree() - 2 {
                // across a knot the third derivative jumps, so the central difference
                // of f' has an O(h) error there: use a smaller step at knots.
                let h2 = if mult > 0 { 1e-8 } else { h };
                let fd2 = (c.eval(t + h2)[1] - c.eval(t - h2)[1]) / (2.0 * h2);
                assert!(
                    (fd2 - v[2]).abs() < 1e-5 * (1.0 + v[2].abs()),
                    "{t}: {fd2} vs {}",
                    v[2]
                );
            }
        }
    }
}

#[test]
fn clamped_curve_interpolates_end_coefficients_and_periodic_curve_closes() {
    let b = BSplineBasis::clamped_uniform(3, 6, 1.0, 3.0).unwrap();
    let c = BSplineCurve::new(b, vec![2.0, -1.0, 0.5, 4.0, 1.0, -3.0]).unwrap();
    assert!((c.eval(1.0)[0] - 2.0).abs() < 1e-15);
    assert!((c.eval(3.0)[0] + 3.0).abs() < 1e-14);

    let b = BSplineBasis::periodic_uniform(3, 5, 0.0, 2.0).unwrap();
    let c = BSplineCurve::new(b, vec![1.0, 3.0, -2.0, 0.5, 2.0]).unwrap();
    let (x0, x1) = (c.eval(0.0), c.eval(2.0 - 1e-12));
    for d in 0..3 {
        assert!(
            (x0[d] - x1[d]).abs() < 1e-9,
            "derivative {d}: {} vs {}",
            x0[d],
            x1[d]
        );
    }
    // wraps: t and t + period give the same value
    assert!((c.eval(0.37)[0] - c.eval(4.37)[0]).abs() < 1e-13);
    assert!((c.eval(0.37)[0] - c.eval(-1.63)[0]).abs() < 1e-13);
}

#[test]
fn least_squares_reproduces_polynomials_and_fits_periodic_data() {
    let b = BSplineBasis::clamped_uniform(3, 7, 0.0, 1.0).unwrap();
    let ts: Vec<f64> = (0..50).map(|k| k as f64 / 49.0).collect();
    let ys: Vec<f64> = ts
        .iter()
        .map(|t| 1.0 - 2.0 * t + 3.0 * t * t - 0.5 * t * t * t)
        .collect();
    let c = fit_least_squares(&b, &ts, &ys).unwrap();
    for t in [0.0, 0.13, 0.5, 0.77, 1.0] {
        let e = c.eval(t)[0] - (1.0 - 2.0 * t + 3.0 * t * t - 0.5 * t * t * t);
        assert!(e.abs() < 1e-12, "{t}: {e}");
    }
    let pb = BSplineBasis::periodic_uniform(3, 16, 0.0, 1.0).unwrap();
    let ts: Vec<f64> = (0..100).map(|k| k as f64 / 100.0).collect();
    let ys: Vec<f64> = ts
        .iter()
        .map(|t| (2.0 * std::f64::consts::PI * t).sin())
        .collect();
    let c = fit_least_squares(&pb, &ts, &ys).unwrap();
    let worst = (0..1000)
        .map(|k| {
            let t = k as f64 / 1000.0;
            (c.eval(t)[0] - (2.0 * std::f64::consts::PI * t).sin()).abs()
        })
        .fold(0.0, f64::max);
    println!("periodic cubic fit of sin with 16 coefficients: max error {worst:.2e}");
    assert!(worst < 1e-3);
    // smoothing lowers curvature but stays close
    let smooth = fit_weighted(&pb, &ts, &ys, None, 1e-6).unwrap();
    assert!((smooth.eval(0.25)[0] - 1.0).abs() < 1e-2);
}

#[test]
fn bad_input_gives_clear_errors() {
    assert!(matches!(
        BSplineBasis::new(3, vec![0., 1., 0.5, 2., 3., 4., 5., 6.]),
        Err(SplineError::Decreasing { .. })
    ));
    assert!(matches!(
        BSplineBasis::new(3, vec![0., 0., 1.]),
        Err(SplineError::TooFewKnots { .. })
    ));
    assert!(matches!(
        BSplineBasis::new(6, vec![0.; 20]),
        Err(SplineError::Degree(6))
    ));
    assert!(matches!(
        BSplineBasis::new(1, vec![0., 1., 1., 1., 2.]),
        Err(SplineError::Multiplicity { .. })
    ));
    assert!(BSplineBasis::new(1, vec![0., 0., 0., 0.]).is_err());
    assert!(BSplineBasis::new(1, vec![0., f64::NAN, 1., 2.]).is_err());
    assert!(BSplineBasis::clamped_uniform(3, 2, 0.0, 1.0).is_err());
    assert!(BSplineBasis::periodic_uniform(3, 8, 1.0, 1.0).is_err());
    // a fit with an empty span is rejected, not solved badly
    let b = BSplineBasis::clamped_uniform(3, 10, 0.0, 1.0).unwrap();
    let e = fit_least_squares(&b, &[0.0, 0.1, 0.9, 1.0], &[1.0, 2.0, 3.0, 4.0]).unwrap_err();
    assert!(e.to_string().contains("under-determined"), "{e}");
    // … unless smoothing makes it well posed
    assert!(fit_weighted(&b, &[0.0, 0.1, 0.9, 1.0], &[1.0, 2.0, 3.0, 4.0], None, 1e-3).is_ok());
    assert!(fit_least_squares(&b, &[0.0], &[1.0, 2.0]).is_err());
    assert!(BSplineCurve::new(b, vec![1.0]).is_err());
}

#[test]
fn serde_round_trip_and_validation() {
    for b in bases() {
        let c = BSplineCurve::new(
            b.clone(),
            (0..b.n_coeffs()).map(|i| i as f64 * 0.3).collect(),
        )
        .unwrap();
        let s = serde_json::to_string(&c).unwrap();
        let c2: BSplineCurve = serde_json::from_str(&s).unwrap();
        assert_eq!(c, c2);
    }
    let bad = r#"{"kind":"knots","degree":3,"knots":[0,1,0]}"#;
    assert!(serde_json::from_str::<BSplineBasis>(bad).is_err());
}
