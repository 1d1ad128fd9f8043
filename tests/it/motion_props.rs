//! Property tests of the motion algebra on random intervals.

use proptest::prelude::*;

use mx::motion::*;

const TOL: f64 = 1e-9;

/// A Hermite cubic with random end states: a non-constant function of time,
/// so time maps that go wrong show up in the values.
fn herm(seed: (f64, f64, f64, f64)) -> Curve {
    Curve::Hermite(HermiteCurve::new(0.0, seed.0, seed.1, 1.0, seed.2, seed.3).unwrap())
}

/// Intervals on a quarter-second grid (so touching and identical endpoints
/// are common) or, with `fine`, at arbitrary times.
fn arb_dof() -> impl Strategy<Value = Dof> {
    let iv = (
        0u32..40,
        1u32..16,
        -1.0f64..1.0,
        -1.0f64..1.0,
        -1.0f64..1.0,
        -1.0f64..1.0,
        0.0f64..0.2,
        any::<bool>(),
    );
    prop::collection::vec(iv, 0..6).prop_map(|ivs| {
        let list = ivs
            .into_iter()
            .map(|(s, l, a, b, c, d, jitter, fine)| {
                let (mut start, mut stop) = (s as f64 * 0.25, (s + l) as f64 * 0.25);
                if fine {
                    start += jitter;
                    stop += jitter * 0.5;
                }
                Interval::curve(herm((a, b, c, d)), start, stop).unwrap()
            })
            .collect();
        Dof::new(list).unwrap()
    })
}

fn arb_mu() -> impl Strategy<Value = Mu> {
    prop::collection::vec(arb_dof(), 1..4).prop_map(|ds| {
        ds.into_iter()
            .enumerate()
            .map(|(k, d)| (format!("d{k}"), d))
            .collect()
    })
}

/// How many functions of an interval of `a ∧ b` come from `a` (those of the
/// interval of `a` that contains it; `∧` puts a's functions first).
fn a_funcs(a: &Dof, piece: &Interval) -> usize {
    let mid = 0.5 * (piece.start + piece.stop);
    a.intervals
        .iter()
        .find(|i| i.start <= mid && mid <= i.stop)
        .map_or(0, |i| i.funcs.len())
}

/// Normal form: sorted, disjoint (touching allowed), non-empty intervals with functions.
fn check_normal(d: &Dof) -> Result<(), TestCaseError> {
    for i in &d.intervals {
        prop_assert!(
            i.start.is_finite() && i.stop.is_finite() && i.start < i.stop,
            "bad interval {i:?}"
        );
        prop_assert!(!i.funcs.is_empty());
    }
    for w in d.intervals.windows(2) {
        prop_assert!(
            w[0].stop <= w[1].start,
            "overlap {:?} {:?}",
            (w[0].start, w[0].stop),
            (w[1].start, w[1].stop)
        );
    }
    Ok(())
}

/// The set of times covered, as merged closed spans (touching spans merge).
fn coverage(d: &Dof) -> Vec<(f64, f64)> {
    merge(d.intervals.iter().map(|i| (i.start, i.stop)).collect())
}

fn merge(mut v: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    v.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out: Vec<(f64, f64)> = Vec::new();
    for (s, e) in v {
        match out.last_mut() {
            Some(last) if s <= last.1 + TOL => last.1 = last.1.max(e),
            _ => out.push((s, e)),
        }
    }
    out
}

fn intersect(a: &[(f64, f64)], b: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    for &(s1, e1) in a {
        for &(s2, e2) in b {
            let (s, e) = (s1.max(s2), e1.min(e2));
            if e - s > TOL {
                out.push((s, e));
            }
        }
    }
    merge(out)
}

fn same_cover(a: &[(f64, f64)], b: &[(f64, f64)]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(x, y)| (x.0 - y.0).abs() <= TOL && (x.1 - y.1).abs() <= TOL)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn plus_covers_the_union(a in arb_dof(), b in arb_dof()) {
        let s = a.plus(&b);
        check_normal(&s)?;
        let mut both = coverage(&a);
        both.extend(coverage(&b));
        prop_assert!(same_cover(&coverage(&s), &merge(both)), "{:?}", coverage(&s));
        // The conflicts of a + b are exactly where both were defined (plus old conflicts).
        let mut expect = intersect(&coverage(&a), &coverage(&b));
        expect.extend(a.conflicts());
        expect.extend(b.conflicts());
        prop_assert!(same_cover(&merge(s.conflicts()), &merge(expect)));
    }

    /// `−` is the paper's symmetric difference (its disjoint case keeps both
    /// operands, its partial-overlap case keeps g's part), so `(a − b) ∧ b`
    /// is empty exactly when b lies within a — the usual `walk − wave` use —
    /// and in general is b's part outside a. The overlap is always undefined.
    #[test]
    fn minus_undefines_the_overlap(a in arb_dof(), b in arb_dof()) {
        let d = a.minus(&b);
        check_normal(&d)?;
        prop_assert!(d.and(&a.and(&b)).is_empty());
        // b restricted to where a is defined: (a − (a − b))... built directly.
        let b_inside = b.and(&a).intervals.iter().map(|i| Interval { start: i.start, stop: i.stop, funcs: i.funcs[a_funcs(&a, i)..].to_vec() }).collect::<Vec<_>>();
        let b_inside = Dof { intervals: b_inside };
        prop_assert!(d.and(&b_inside).is_empty() || b_inside.is_empty());
        prop_assert!(a.minus(&b_inside).and(&b_inside).is_empty());
        // In general (a − b) ∧ b covers exactly the part of b outside a.
        let outside: Vec<(f64, f64)> = coverage(&b.minus(&a).and(&b));
        prop_assert!(same_cover(&coverage(&d.and(&b)), &outside));
    }

    #[test]
    fn and_is_commutative_in_coverage(a in arb_dof(), b in arb_dof()) {
        let ab = a.and(&b);
        let ba = b.and(&a);
        check_normal(&ab)?;
        prop_assert!(same_cover(&coverage(&ab), &coverage(&ba)));
        prop_assert!(same_cover(&coverage(&ab), &intersect(&coverage(&a), &coverage(&b))));
        // Every piece of a ∧ b carries functions of both.
        for i in &ab.intervals {
            prop_assert!(i.funcs.len() >= 2);
        }
    }

    #[test]
    fn plus_is_minus_then_and(a in arb_dof(), b in arb_dof()) {
        let lhs = coverage(&a.plus(&b));
        let rhs = coverage(&a.minus(&b).plus(&a.and(&b)));
        prop_assert!(same_cover(&lhs, &rhs));
    }

    #[test]
    fn affine_composes(m in arb_mu(), ts1 in -5.0f64..5.0, d1 in 0.1f64..4.0, ts2 in -5.0f64..5.0, d2 in 0.1f64..4.0) {
        let twice = affine(ts2, d2, &affine(ts1, d1, &m).unwrap()).unwrap();
        let once = affine(ts2 + d2 * ts1, d2 * d1, &m).unwrap();
        prop_assert_eq!(twice.span().is_some(), once.span().is_some());
        for (name, dof) in &m.dofs {
            let (a, b) = (twice.get(name).unwrap(), once.get(name).unwrap());
            check_normal(a)?;
            prop_assert_eq!(a.intervals.len(), dof.intervals.len());
            for (x, y) in a.intervals.iter().zip(&b.intervals) {
                prop_assert!((x.start - y.start).abs() < 1e-9 && (x.stop - y.stop).abs() < 1e-9);
                // Sample inside each interval (away from the ends so both agree on which interval).
                for s in [0.25, 0.5, 0.75] {
                    let t = x.start + s * (x.stop - x.start);
                    for (f, g) in x.funcs.iter().zip(&y.funcs) {
                        let (p, q) = (f.eval(t).unwrap(), g.eval(t).unwrap());
                        for k in 0..3 {
                            prop_assert!((p[k] - q[k]).abs() <= 1e-7 * (1.0 + q[k].abs()), "{p:?} vs {q:?}");
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn clip_then_concatenate_restores_samples(mut m in arb_mu(), split in 0.05f64..0.95, v in -1.0f64..1.0) {
        // A DOF spanning the whole motion fixes the span of every piece.
        let (t0, t1) = m.span().unwrap_or((0.0, 1.0));
        m.insert("base", Dof::from(Interval::curve(herm((v, 0.3, -v, 0.1)), t0, t1).unwrap()));
        let s = t0 + split * (t1 - t0);
        let joined = concatenate(&clip(t0, s, &m).unwrap(), &clip(s, t1, &m).unwrap());
        let moved = affine(-t0, 1.0, &m).unwrap();
        for name in m.names() {
            check_normal(joined.get(name).unwrap())?;
            for k in 0..=200 {
                let t = (t1 - t0) * k as f64 / 200.0;
                match (joined.sample(name, t), moved.sample(name, t)) {
                    (Ok(Some(a)), Ok(Some(b))) => {
                        for i in 0..3 {
                            prop_assert!((a[i] - b[i]).abs() <= 1e-9 * (1.0 + b[i].abs()), "{name} t={t}: {a:?} vs {b:?}");
                        }
                    }
                    (Ok(None), Ok(None)) | (Err(_), Err(_)) => {}
                    (a, b) => prop_assert!(false, "{name} at t={t}: {a:?} vs {b:?}"),
                }
            }
        }
    }

    #[test]
    fn grid_sampling_matches_point_sampling(a in arb_dof(), b in arb_dof(), rate in 1.0f64..40.0) {
        let m: Mu = [("x".to_string(), a.plus(&b))].into_iter().collect();
        match sample_grid(&m, rate, None) {
            Ok(g) => {
                for (k, &t) in g.times.iter().enumerate() {
                    prop_assert_eq!(g.values[0][k], m.sample_value("x", t).unwrap());
                }
            }
            Err(MotionError::Conflict { t, .. }) => prop_assert!(m.sample_value("x", t).is_err()),
            Err(e) => prop_assert!(false, "{e}"),
        }
    }

    /// `Dof::new` (with its sorted-and-disjoint fast path) is the fold of `+`.
    #[test]
    fn dof_new_is_the_sum_of_its_intervals(a in arb_dof(), b in arb_dof()) {
        let mut list: Vec<Interval> = a.intervals.iter().chain(&b.intervals).cloned().collect();
        list.reverse();
        let built = Dof::new(list.clone()).unwrap();
        check_normal(&built)?;
        let folded = list.into_iter().fold(Dof::empty(), |acc, i| acc.plus(&Dof::from(i)));
        prop_assert!(same_cover(&coverage(&built), &coverage(&folded)));
        prop_assert!(same_cover(&merge(built.conflicts()), &merge(folded.conflicts())));
    }
}
