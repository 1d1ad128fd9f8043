//! The motion algebra: the paper's three cases of ∧, − and + (Rose 1996 §4,
//! errata applied), time operations, sampling and hard cases.

use std::sync::Arc;

use mx::motion::*;

fn c(v: f64, a: f64, b: f64) -> Interval {
    Interval::constant(v, a, b).unwrap()
}

fn mu1(name: &str, ivs: Vec<Interval>) -> Mu {
    let mut m = Mu::new();
    m.insert(name, Dof::new(ivs).unwrap());
    m
}

/// (start, stop, values of the functions at the interval's midpoint).
fn shape(d: &Dof) -> Vec<(f64, f64, Vec<f64>)> {
    d.intervals
        .iter()
        .map(|i| {
            let mid = 0.5 * (i.start + i.stop);
            (
                i.start,
                i.stop,
                i.funcs.iter().map(|f| f.value(mid).unwrap()).collect(),
            )
        })
        .collect()
}

// I1 = (f, t1, t2) = (1, 0, 2); I2 = (g, t3, t4) with t3 > t1.

#[test]
fn and_case1_disjoint_is_empty() {
    // t2 ≤ t3 (errata: the text says t1 ≤ t2).
    let d = Dof::from(c(1.0, 0.0, 2.0)).and(&Dof::from(c(2.0, 3.0, 4.0)));
    assert!(d.is_empty());
    let touching = Dof::from(c(1.0, 0.0, 2.0)).and(&Dof::from(c(2.0, 2.0, 4.0)));
    assert!(touching.is_empty(), "touching endpoints do not overlap");
}

#[test]
fn and_case2_partial_overlap() {
    // t3 < t2 < t4 → (f, g, t3, t2)
    let d = Dof::from(c(1.0, 0.0, 2.0)).and(&Dof::from(c(2.0, 1.0, 4.0)));
    assert_eq!(shape(&d), vec![(1.0, 2.0, vec![1.0, 2.0])]);
}

#[test]
fn and_case3_contained() {
    // t4 < t2 → (f, g, t3, t4)
    let d = Dof::from(c(1.0, 0.0, 4.0)).and(&Dof::from(c(2.0, 1.0, 3.0)));
    assert_eq!(shape(&d), vec![(1.0, 3.0, vec![1.0, 2.0])]);
}

#[test]
fn minus_case1_disjoint_keeps_both() {
    // t2 ≤ t3 → (f, t1, t2)(g, t3, t4)  (errata)
    let d = Dof::from(c(1.0, 0.0, 2.0)).minus(&Dof::from(c(2.0, 3.0, 4.0)));
    assert_eq!(
        shape(&d),
        vec![(0.0, 2.0, vec![1.0]), (3.0, 4.0, vec![2.0])]
    );
}

#[test]
fn minus_case2_partial_overlap() {
    // → (f, t1, t3)(g, t2, t4)
    let d = Dof::from(c(1.0, 0.0, 2.0)).minus(&Dof::from(c(2.0, 1.0, 4.0)));
    assert_eq!(
        shape(&d),
        vec![(0.0, 1.0, vec![1.0]), (2.0, 4.0, vec![2.0])]
    );
}

#[test]
fn minus_case3_contained_undefines_the_middle() {
    // → (f, t1, t3)(f, t4, t2)
    let d = Dof::from(c(1.0, 0.0, 4.0)).minus(&Dof::from(c(2.0, 1.0, 3.0)));
    assert_eq!(
        shape(&d),
        vec![(0.0, 1.0, vec![1.0]), (3.0, 4.0, vec![1.0])]
    );
}

#[test]
fn plus_case1_disjoint() {
    let d = Dof::from(c(1.0, 0.0, 2.0)).plus(&Dof::from(c(2.0, 3.0, 4.0)));
    assert_eq!(
        shape(&d),
        vec![(0.0, 2.0, vec![1.0]), (3.0, 4.0, vec![2.0])]
    );
    assert!(d.conflicts().is_empty());
    assert_eq!(d.gaps(), vec![(2.0, 3.0)]);
}

#[test]
fn plus_case2_partial_overlap_is_a_conflict() {
    let d = Dof::from(c(1.0, 0.0, 2.0)).plus(&Dof::from(c(2.0, 1.0, 4.0)));
    assert_eq!(
        shape(&d),
        vec![
            (0.0, 1.0, vec![1.0]),
            (1.0, 2.0, vec![1.0, 2.0]),
            (2.0, 4.0, vec![2.0])
        ]
    );
    assert_eq!(d.conflicts(), vec![(1.0, 2.0)]);
}

#[test]
fn plus_case3_contained() {
    let d = Dof::from(c(1.0, 0.0, 4.0)).plus(&Dof::from(c(2.0, 1.0, 3.0)));
    assert_eq!(
        shape(&d),
        vec![
            (0.0, 1.0, vec![1.0]),
            (1.0, 3.0, vec![1.0, 2.0]),
            (3.0, 4.0, vec![1.0])
        ]
    );
}

#[test]
fn operand_order_does_not_matter_for_coverage() {
    // The paper assumes t3 > t1 without loss of generality; check the mirror.
    let a = Dof::from(c(1.0, 1.0, 4.0));
    let b = Dof::from(c(2.0, 0.0, 2.0));
    assert_eq!(shape(&a.and(&b)), vec![(1.0, 2.0, vec![1.0, 2.0])]);
    assert_eq!(
        shape(&a.minus(&b)),
        vec![(0.0, 1.0, vec![2.0]), (2.0, 4.0, vec![1.0])]
    );
}

#[test]
fn touching_endpoints_are_not_a_conflict() {
    let m = mu1("x", vec![c(1.0, 0.0, 1.0)]);
    let n = mu1("x", vec![c(2.0, 1.0, 2.0)]);
    let s = plus(&m, &n);
    assert!(conflicts(&s).is_empty());
    assert!(gaps(&s).is_empty());
    // The instant 1 belongs to the interval that starts there.
    assert_eq!(s.sample_value("x", 1.0).unwrap(), Some(2.0));
    assert_eq!(s.sample_value("x", 0.5).unwrap(), Some(1.0));
    assert_eq!(s.sample_value("x", 2.0).unwrap(), Some(2.0));
    assert_eq!(s.sample_value("x", 2.5).unwrap(), None);
}

#[test]
fn walk_minus_wave_plus_wave_leaves_two_gaps() {
    // The paper's Figure 6 pattern: SP(affine2(wave) + (walk − affine1(wave))).
    let walk = mu1("arm", vec![c(1.0, 0.0, 10.0)]);
    let wave = mu1("arm", vec![c(5.0, 0.0, 2.0)]);
    let hole = affine(3.5, 1.5, &wave).unwrap(); // [3.5, 6.5]
    let inner = affine(4.0, 1.0, &wave).unwrap(); // [4, 6]
    let m = plus(&inner, &minus(&walk, &hole));
    let g = gaps(&m);
    assert_eq!(g.len(), 2);
    assert_eq!((g[0].start, g[0].stop), (3.5, 4.0));
    assert_eq!((g[1].start, g[1].stop), (6.0, 6.5));
    assert!(conflicts(&m).is_empty());
    // wave order first (first definition is in `inner`).
    assert_eq!(m.sample_value("arm", 5.0).unwrap(), Some(5.0));
}

#[test]
fn sampling_a_conflict_names_dof_and_span() {
    let m = plus(
        &mu1("Hips.Xposition", vec![c(1.0, 0.0, 2.0)]),
        &mu1("Hips.Xposition", vec![c(2.0, 1.0, 3.0)]),
    );
    let e = m.sample("Hips.Xposition", 1.5).unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.contains("Hips.Xposition") && msg.contains("[1, 2]"),
        "{msg}"
    );
    // Either side of the conflict samples fine, also at its touching ends.
    assert_eq!(m.sample_value("Hips.Xposition", 1.0).unwrap(), Some(1.0));
    assert_eq!(m.sample_value("Hips.Xposition", 2.0).unwrap(), Some(2.0));
}

#[test]
fn affine_scales_time_and_derivatives() {
    let f = Curve::Hermite(HermiteCurve::new(0.0, 0.0, 1.0, 1.0, 2.0, 0.5).unwrap());
    let m = mu1("x", vec![Interval::curve(f.clone(), 0.0, 1.0).unwrap()]);
    let a = affine(2.0, 3.0, &m).unwrap();
    assert_eq!(a.span(), Some((2.0, 5.0)));
    let [v0, d0, dd0] = f.eval(0.25).unwrap();
    let [v, d, dd] = a.sample("x", 2.0 + 3.0 * 0.25).unwrap().unwrap();
    assert!((v - v0).abs() < 1e-14);
    assert!((d - d0 / 3.0).abs() < 1e-14);
    assert!((dd - dd0 / 9.0).abs() < 1e-14);
}

#[test]
fn affine_rejects_bad_scales() {
    let m = mu1("x", vec![c(1.0, 0.0, 1.0)]);
    for d in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let e = affine(0.0, d, &m).unwrap_err();
        assert!(matches!(e, MotionError::BadScale { .. }), "{d}: {e}");
    }
    assert!(affine(f64::NAN, 1.0, &m).is_err());
}

#[test]
fn clip_outside_span_message() {
    let walk = mu1("x", vec![c(1.0, 0.0, 2.4)]);
    let e = clip(2.0, 3.5, &walk).unwrap_err().with_name("walk");
    assert_eq!(
        e.to_string(),
        "clip [2.0, 3.5] lies outside walk's span [0, 2.4]"
    );
    assert!(clip(1.0, 1.0, &walk).is_err());
    assert!(clip(1.5, 1.0, &walk).is_err());
    assert!(clip(f64::NAN, 1.0, &walk).is_err());
    assert!(matches!(
        clip(0.0, 1.0, &Mu::new()),
        Err(MotionError::EmptyMotion { .. })
    ));
}

#[test]
fn clip_moves_to_zero_and_in_place_keeps_times() {
    let f: Arc<dyn TimeFunction> = Arc::new(Lin);
    let m = mu1("x", vec![Interval::function(f, 0.0, 10.0).unwrap()]);
    let a = clip(2.0, 5.0, &m).unwrap();
    assert_eq!(a.span(), Some((0.0, 3.0)));
    assert_eq!(a.sample_value("x", 1.0).unwrap(), Some(3.0));
    let b = clip_in_place(2.0, 5.0, &m).unwrap();
    assert_eq!(b.span(), Some((2.0, 5.0)));
    assert_eq!(b.sample_value("x", 3.0).unwrap(), Some(3.0));
}

#[test]
fn concatenate_follows_on() {
    let a = mu1("x", vec![c(1.0, 0.0, 2.0)]);
    let b = mu1("x", vec![c(2.0, 5.0, 6.0)]);
    let m = concatenate(&a, &b);
    assert_eq!(m.span(), Some((0.0, 3.0)));
    assert!(conflicts(&m).is_empty());
    assert_eq!(m.sample_value("x", 2.5).unwrap(), Some(2.0));
}

#[test]
fn zero_length_and_non_finite_intervals_are_errors() {
    assert!(matches!(
        Interval::constant(1.0, 1.0, 1.0),
        Err(MotionError::EmptyInterval { .. })
    ));
    assert!(matches!(
        Interval::constant(1.0, 2.0, 1.0),
        Err(MotionError::EmptyInterval { .. })
    ));
    assert!(matches!(
        Interval::constant(1.0, f64::NAN, 1.0),
        Err(MotionError::NonFinite { .. })
    ));
    assert!(matches!(
        Interval::constant(1.0, 0.0, f64::INFINITY),
        Err(MotionError::NonFinite { .. })
    ));
    assert!(matches!(
        Interval::constant(f64::NAN, 0.0, 1.0),
        Err(MotionError::NonFinite { .. })
    ));
}

#[test]
fn only_by_name_and_glob() {
    let mut m = Mu::new();
    for n in [
        "Hips.Xposition",
        "RightArm.Zrotation",
        "RightArm.Xrotation",
        "LeftArm.Zrotation",
    ] {
        m.insert(n, Dof::from(c(0.0, 0.0, 1.0)));
    }
    let r = only(&m, &["RightArm*"]).unwrap();
    assert_eq!(
        r.names().collect::<Vec<_>>(),
        vec!["RightArm.Zrotation", "RightArm.Xrotation"]
    );
    let r = only(&m, &["Hips.Xposition", "*Arm.Z*"]).unwrap();
    assert_eq!(
        r.names().collect::<Vec<_>>(),
        vec!["Hips.Xposition", "RightArm.Zrotation", "LeftArm.Zrotation"]
    );
    let e = only(&m, &["Head*"]).unwrap_err();
    assert!(e.to_string().contains("Head*"));
}

#[test]
fn unknown_dof_suggests() {
    let m = mu1("Hips.Xposition", vec![c(0.0, 0.0, 1.0)]);
    // A DOF the motion does not name is undefined everywhere…
    assert_eq!(m.sample("Hips.Xpositon", 0.5).unwrap(), None);
    // …and looking it up by name reports the likely typo.
    let e = m.dof("Hips.Xpositon").unwrap_err();
    assert!(
        e.to_string().contains("did you mean 'Hips.Xposition'"),
        "{e}"
    );
}

#[derive(Debug)]
struct Lin;
impl TimeFunction for Lin {
    fn eval(&self, t: f64) -> Result<f64, mx::motion::FnError> {
        Ok(t)
    }
}

#[test]
fn extreme_affine_maps_are_errors_not_infinities() {
    let m = mu1("x", vec![c(1.0, 0.0, 1.0)]);
    // Overflow to infinity.
    let e = affine(0.0, 1e308, &mu1("x", vec![c(1.0, 1.0, 10.0)])).unwrap_err();
    assert!(matches!(e, MotionError::AffineDegenerate { .. }), "{e}");
    // Shrinks an interval below the time resolution.
    let e = affine(0.0, 1e-12, &m).unwrap_err();
    assert!(e.to_string().contains("d nearer 1"), "{e}");
    // Bad scale even with no DOF to map.
    assert!(affine(0.0, 0.0, &Mu::new()).is_err());
    // Large but representable maps are fine, and exact on dyadic numbers.
    let big = affine(1e6, 1024.0, &m).unwrap();
    assert_eq!(big.span(), Some((1e6, 1e6 + 1024.0)));
    assert_eq!(big.sample_value("x", 1e6 + 512.0).unwrap(), Some(1.0));
}

#[test]
fn non_finite_sample_times_are_errors() {
    let m = mu1("x", vec![c(1.0, 0.0, 1.0)]);
    for t in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert!(matches!(m.sample("x", t), Err(MotionError::BadTime { .. })));
        assert!(matches!(
            m.sample_value("x", t),
            Err(MotionError::BadTime { .. })
        ));
    }
}

#[test]
fn rounding_after_affine_leaves_no_slivers() {
    // 0.1 + 0.2 ≠ 0.3 in floating point: the pieces still touch, no gap appears.
    let a = mu1("x", vec![c(1.0, 0.0, 0.1 + 0.2)]);
    let b = mu1("x", vec![c(2.0, 0.3, 1.0)]);
    let s = plus(&a, &b);
    assert!(gaps(&s).is_empty() && conflicts(&s).is_empty());
    assert_eq!(s.get("x").unwrap().intervals.len(), 2);
    // Scale by 1/3 then by 3: the same span up to rounding, and ops still see one interval.
    let round = affine(0.0, 3.0, &affine(0.0, 1.0 / 3.0, &b).unwrap()).unwrap();
    let d = minus(&round, &b);
    assert!(d.get("x").unwrap().is_empty(), "{d:?}");
}

#[test]
fn long_chains_of_operations_stay_in_normal_form() {
    // 200 pasted pieces, each undefining a hole first: O(n) pieces, no conflicts.
    let mut m = mu1("x", vec![c(0.0, 0.0, 1000.0)]);
    let piece = mu1("x", vec![c(1.0, 0.0, 1.0)]);
    for k in 0..200 {
        let at = 2.0 + 4.9 * k as f64;
        m = plus(
            &affine(at, 1.0, &piece).unwrap(),
            &minus(&m, &affine(at - 0.5, 2.0, &piece).unwrap()),
        );
    }
    let d = m.get("x").unwrap();
    assert_eq!(d.intervals.len(), 401);
    assert_eq!(gaps(&m).len(), 400);
    assert!(conflicts(&m).is_empty());
    for w in d.intervals.windows(2) {
        assert!(w[0].stop <= w[1].start);
    }
}

#[test]
fn hand_built_interval_without_functions_is_an_error_not_a_panic() {
    let mut m = Mu::new();
    m.insert(
        "x",
        Dof {
            intervals: vec![Interval {
                start: 0.0,
                stop: 1.0,
                funcs: vec![],
            }],
        },
    );
    assert!(matches!(m.sample("x", 0.5), Err(MotionError::NoFunction)));
    assert!(matches!(
        m.sample_value("x", 0.5),
        Err(MotionError::NoFunction)
    ));
    assert!(
        Dof::new(vec![Interval {
            start: 0.0,
            stop: 1.0,
            funcs: vec![]
        }])
        .is_err()
    );
}
