use super::*;
use crate::spacetime::planar2::TwoLinkArm;

fn st(q: f64, v: f64) -> EndState {
    EndState { q, v, a: 0.0 }
}

/// Two gaps overlapping in time on the two joints of the arm.
fn problem<'a>(arm: &'a TwoLinkArm, settings: &TransitionSettings) -> Objective<'a, TwoLinkArm> {
    Objective::new(arm, gaps(), settings, vec![1.0, 1.5], &known_motion).unwrap()
}

/// The gaps of [`problem`].
pub(super) fn gaps() -> Vec<GapDof> {
    vec![
        GapDof {
            coord: 0,
            t0: 0.2,
            t1: 0.9,
            start: st(0.1, 1.0),
            end: st(1.2, -0.5),
        },
        GapDof {
            coord: 1,
            t0: 0.5,
            t1: 1.3,
            start: st(-0.4, 0.0),
            end: st(0.9, 2.0),
        },
    ]
}

/// Outside a gap each joint of [`problem`] follows this smooth known motion.
pub(super) fn known_motion(
    t: f64,
    q: &mut [f64],
    v: &mut [f64],
    a: &mut [f64],
) -> Result<(), SpError> {
    q[0] = (2.0 * t).sin();
    v[0] = 2.0 * (2.0 * t).cos();
    a[0] = -4.0 * (2.0 * t).sin();
    q[1] = t * t;
    v[1] = 2.0 * t;
    a[1] = 2.0;
    Ok(())
}

/// The gradient of `obj` at x, checked against central differences of e
/// in every unknown (relative to its largest entry).
pub(super) fn assert_gradient<M: TorqueModel>(obj: &Objective<'_, M>, x: &[f64]) -> Vec<f64> {
    let mut s = obj.scratch();
    let mut g = vec![0.0; x.len()];
    obj.eval(&mut s, x, Some(&mut g)).unwrap();
    let scale = g.iter().map(|v| v.abs()).fold(0.0, f64::max);
    for i in 0..x.len() {
        let h = 1e-6;
        let (mut xp, mut xm) = (x.to_vec(), x.to_vec());
        xp[i] += h;
        xm[i] -= h;
        let fd = (obj.eval(&mut s, &xp, None).unwrap() - obj.eval(&mut s, &xm, None).unwrap())
            / (2.0 * h);
        assert!(
            (fd - g[i]).abs() <= 1e-6 * scale,
            "i={i}: fd {fd} vs {}",
            g[i]
        );
    }
    g
}

#[test]
fn gradient_matches_central_differences() {
    let arm = TwoLinkArm::default();
    // with and without SP's kinematic prior ∫ c_v q̇² + c_a q̈²
    for (cont, prior) in [
        (Continuity::C1, vec![]),
        (Continuity::C2, vec![]),
        (Continuity::C1, vec![[0.3, 0.7], [2.0, 0.05]]),
        (Continuity::C2, vec![[0.3, 0.7], [2.0, 0.05]]),
    ] {
        let settings = TransitionSettings {
            coefficients: 6,
            samples: 12,
            continuity: cont,
        };
        let obj = problem(&arm, &settings).with_prior(&prior).unwrap();
        let x: Vec<f64> = (0..obj.n_vars()).map(|i| 0.3 * (i as f64).cos()).collect();
        assert_gradient(&obj, &x);
    }
}

#[test]
fn objective_is_the_integral_of_the_weighted_squared_torque() {
    // Compare with a fine trapezoid integral of the same curves.
    let arm = TwoLinkArm::default();
    let settings = TransitionSettings {
        coefficients: 5,
        samples: 30,
        continuity: Continuity::C1,
    };
    let obj = problem(&arm, &settings);
    let x = obj.hermite_start();
    let e = obj.eval(&mut obj.scratch(), &x, None).unwrap();
    let coefs = obj.coefficients(&x);
    let n = 20000;
    let (a, b) = (0.2, 1.3);
    let mut sum = 0.0;
    for i in 0..=n {
        let t = a + (b - a) * i as f64 / n as f64;
        let mut q = [(2.0 * t).sin(), t * t];
        let mut v = [2.0 * (2.0 * t).cos(), 2.0 * t];
        let mut acc = [-4.0 * (2.0 * t).sin(), 2.0];
        for (d, dof) in obj.dofs().iter().enumerate() {
            if t >= dof.t0 && t <= dof.t1 {
                let s = obj.curves()[d].eval(&coefs[d], t);
                q[dof.coord] = s[0];
                v[dof.coord] = s[1];
                acc[dof.coord] = s[2];
            }
        }
        let mut tau = [0.0; 2];
        arm.torques(&mut (), &q, &v, &acc, &[], &mut tau).unwrap();
        let f = tau[0] * tau[0] + 1.5 * tau[1] * tau[1];
        let w = if i == 0 || i == n { 0.5 } else { 1.0 };
        sum += w * f * (b - a) / n as f64;
    }
    assert!((e - sum).abs() < 1e-5 * sum, "{e} vs {sum}");
}

/// With an example, the prior integrates c_v (q̇ − ṙ)² + c_a (q̈ − r̈)² with
/// r the inputs `shift` away, and its gradient still matches differences.
#[test]
fn an_example_moves_the_priors_target_to_its_own_derivatives() {
    let arm = TwoLinkArm::default();
    let settings = TransitionSettings {
        coefficients: 5,
        samples: 30,
        continuity: Continuity::C1,
    };
    let prior = [[0.4, 1.5], [0.7, 0.2]];
    let shift = 0.3;
    let inputs = known_motion;
    let plain = problem(&arm, &settings);
    let mut with = problem(&arm, &settings).with_prior(&prior).unwrap();
    assert!(with.with_example(&inputs, shift, &[0, 1], 1.0).unwrap());
    let mut s = with.scratch();
    let x: Vec<f64> = (0..with.n_vars()).map(|i| 0.2 * (i as f64).sin()).collect();
    let part = with.eval(&mut s, &x, None).unwrap() - plain.eval(&mut s, &x, None).unwrap();
    let coefs = with.coefficients(&x);
    let (n, mut sum) = (20000, 0.0);
    for (d, dof) in with.dofs().iter().enumerate() {
        let [cv, ca] = prior[dof.coord];
        for i in 0..=n {
            let t = dof.t0 + (dof.t1 - dof.t0) * i as f64 / n as f64;
            let c = with.curves()[d].eval(&coefs[d], t);
            let (mut q, mut v, mut a) = ([0.0; 2], [0.0; 2], [0.0; 2]);
            inputs(t + shift, &mut q, &mut v, &mut a).unwrap();
            let f = cv * (c[1] - v[dof.coord]).powi(2) + ca * (c[2] - a[dof.coord]).powi(2);
            let w = if i == 0 || i == n { 0.5 } else { 1.0 };
            sum += w * f * (dof.t1 - dof.t0) / n as f64;
        }
    }
    assert!((part - sum).abs() < 1e-6 * sum, "{part} vs {sum}");
    assert_gradient(&with, &x);
    // an example undefined at some node is refused, the objective unchanged
    let undefined = |t: f64, q: &mut [f64], v: &mut [f64], a: &mut [f64]| {
        if t < 1.0 { inputs(t, q, v, a) } else { Ok(()) }
    };
    let mut other = problem(&arm, &settings).with_prior(&prior).unwrap();
    assert!(!other.with_example(&undefined, shift, &[0, 1], 1.0).unwrap());
    let e0 = other.eval(&mut s, &x, None).unwrap();
    let e1 = problem(&arm, &settings)
        .with_prior(&prior)
        .unwrap()
        .eval(&mut s, &x, None)
        .unwrap();
    assert_eq!(e0, e1);
}

#[test]
fn the_prior_adds_its_integral_and_its_gauss_newton_block() {
    let arm = TwoLinkArm::default();
    let settings = TransitionSettings {
        coefficients: 5,
        samples: 30,
        continuity: Continuity::C1,
    };
    let plain = problem(&arm, &settings);
    let prior = [[0.4, 1.5], [0.0, 0.0]];
    let with = problem(&arm, &settings).with_prior(&prior).unwrap();
    let x: Vec<f64> = (0..plain.n_vars())
        .map(|i| 0.2 * (i as f64).sin())
        .collect();
    let e0 = plain.eval(&mut plain.scratch(), &x, None).unwrap();
    let e1 = with.eval(&mut with.scratch(), &x, None).unwrap();
    // the prior on coordinate 0 alone, by a fine trapezoid rule over its gap
    let d = &plain.dofs()[0];
    let c = plain.coefficients(&x);
    let n = 20000;
    let mut sum = 0.0;
    for i in 0..=n {
        let t = d.t0 + (d.t1 - d.t0) * i as f64 / n as f64;
        let s = plain.curves()[0].eval(&c[0], t);
        let w = if i == 0 || i == n { 0.5 } else { 1.0 };
        sum += w * (0.4 * s[1] * s[1] + 1.5 * s[2] * s[2]) * (d.t1 - d.t0) / n as f64;
    }
    assert!((e1 - e0 - sum).abs() < 1e-6 * sum, "{} vs {sum}", e1 - e0);
    // the prior is quadratic in x: its Gauss–Newton block is its exact Hessian
    assert!(problem(&arm, &settings).with_prior(&[[1.0, 1.0]]).is_err());
    assert!(
        problem(&arm, &settings)
            .with_prior(&[[-1.0, 0.0], [0.0, 0.0]])
            .is_err()
    );
}

#[test]
fn bad_inputs_are_clear_errors() {
    let arm = TwoLinkArm::default();
    let s = TransitionSettings::default();
    let inputs = |_: f64, _: &mut [f64], _: &mut [f64], _: &mut [f64]| Ok(());
    let gap = GapDof {
        coord: 5,
        t0: 0.0,
        t1: 1.0,
        start: st(0.0, 0.0),
        end: st(1.0, 0.0),
    };
    assert!(Objective::new(&arm, vec![gap.clone()], &s, vec![1.0; 2], &inputs).is_err());
    let gap0 = GapDof {
        coord: 0,
        ..gap.clone()
    };
    assert!(Objective::new(&arm, vec![gap0.clone()], &s, vec![1.0; 3], &inputs).is_err());
    assert!(
        Objective::new(
            &arm,
            vec![gap0.clone(), gap0.clone()],
            &s,
            vec![1.0; 2],
            &inputs
        )
        .is_err()
    );
    let nan = GapDof {
        start: st(f64::NAN, 0.0),
        ..gap0.clone()
    };
    assert!(Objective::new(&arm, vec![nan], &s, vec![1.0; 2], &inputs).is_err());
    let s0 = TransitionSettings {
        samples: 0,
        ..s.clone()
    };
    assert!(Objective::new(&arm, vec![gap0], &s0, vec![1.0; 2], &inputs).is_err());
}

/// The continuation lowers the prior in place: an objective built with the
/// prior at scale 1 and rescaled to s gives, bit for bit, the cost and the
/// gradient of one built with the weights times s, with or without an
/// example, and after any earlier rescaling.
#[test]
fn rescaling_the_prior_in_place_equals_building_it_scaled() {
    let arm = TwoLinkArm::default();
    let settings = TransitionSettings {
        coefficients: 6,
        samples: 24,
        continuity: Continuity::C1,
    };
    let prior = [[0.4, 1.5], [0.7, 0.2]];
    let x: Vec<f64> = (0..12).map(|i| 0.25 * (i as f64 + 0.3).sin()).collect();
    let eval = |obj: &Objective<'_, TwoLinkArm>| {
        let mut g = vec![0.0; obj.n_vars()];
        let e = obj.eval(&mut obj.scratch(), &x, Some(&mut g)).unwrap();
        (e, g)
    };
    for example in [false, true] {
        let follow = |obj: &mut Objective<'_, TwoLinkArm>| {
            if example {
                assert!(obj.with_example(&known_motion, 0.3, &[0, 1], 0.8).unwrap());
            }
        };
        let mut moved = problem(&arm, &settings).with_prior(&prior).unwrap();
        follow(&mut moved);
        for scale in [1.0, 1e-1, 1e-2, 1e-3, 1e-4, 0.37, 0.0] {
            let scaled: Vec<[f64; 2]> = prior.iter().map(|[v, a]| [v * scale, a * scale]).collect();
            let mut built = problem(&arm, &settings).with_prior(&scaled).unwrap();
            follow(&mut built);
            moved.rescale_prior(scale).unwrap();
            let (e0, g0) = eval(&built);
            let (e1, g1) = eval(&moved);
            assert_eq!(e0.to_bits(), e1.to_bits(), "scale {scale}: {e0} vs {e1}");
            let bits = |g: &[f64]| g.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&g0), bits(&g1), "scale {scale}");
        }
        // the prior does move the cost: the test is not vacuous
        moved.rescale_prior(1.0).unwrap();
        let e1 = eval(&moved).0;
        moved.rescale_prior(0.0).unwrap();
        assert!(eval(&moved).0 < e1);
    }
    let mut obj = problem(&arm, &settings).with_prior(&prior).unwrap();
    for bad in [-1.0, f64::NAN, f64::INFINITY, f64::MAX] {
        assert!(obj.rescale_prior(bad).is_err(), "{bad}");
    }
}

/// An objective on a layout built beforehand is the objective `new` builds.
#[test]
fn an_objective_on_a_shared_layout_equals_a_new_one() {
    let arm = TwoLinkArm::default();
    let settings = TransitionSettings::default();
    let built = problem(&arm, &settings);
    let layout = GapLayout::new(built.dofs().to_vec(), &settings).unwrap();
    assert_eq!(layout.n_vars(), built.n_vars());
    let on = Objective::on_layout(&arm, layout, vec![1.0, 1.5], &known_motion).unwrap();
    let x = built.hermite_start();
    assert_eq!(x, on.hermite_start());
    let e0 = built.eval(&mut built.scratch(), &x, None).unwrap();
    let e1 = on.eval(&mut on.scratch(), &x, None).unwrap();
    assert_eq!(e0.to_bits(), e1.to_bits());
    // the layout's gaps are checked against the body
    let far = GapDof {
        coord: 7,
        ..built.dofs()[0].clone()
    };
    let layout = GapLayout::new(vec![far], &settings).unwrap();
    assert!(Objective::on_layout(&arm, layout, vec![1.0, 1.5], &known_motion).is_err());
}

/// A transition that corrects a base curve (`GapLayout::with_bases`) meets
/// the gap's end states whatever its unknowns (q, q̇; q̈ too with C²), is the
/// base itself at zero correction when the base meets them, and its nodes'
/// rows give the same state as the curve it writes.
#[test]
fn a_correction_to_a_base_meets_the_end_states_and_is_the_base_at_zero() {
    use crate::motion::Curve;
    use std::sync::Arc;
    // the base: samples of a smooth curve through the end states' region
    let f = |t: f64| 0.3 * (3.0 * t).sin() + 0.1 * t;
    let (h, from) = (1.0 / 240.0, -0.2);
    let base = Arc::new(
        Curve::samples(from, h, (0..600).map(|k| f(from + k as f64 * h)).collect()).unwrap(),
    );
    for continuity in [Continuity::C1, Continuity::C2] {
        let settings = TransitionSettings {
            continuity,
            ..Default::default()
        };
        let at = |t: f64| {
            let [q, v, a] = base.eval(t).unwrap();
            EndState { q, v, a }
        };
        // ends off the base by a little (a correction to make) and on it
        for off in [0.0, 0.05] {
            let mut start = at(0.2);
            start.q += off;
            start.v -= off;
            let gap = GapDof {
                coord: 0,
                t0: 0.2,
                t1: 0.9,
                start,
                end: at(0.9),
            };
            let layout =
                GapLayout::with_bases(vec![gap.clone()], &settings, vec![Some(base.clone())])
                    .unwrap();
            let n = layout.n_vars();
            for x in [vec![0.0; n], (0..n).map(|i| 0.1 * i as f64 - 0.2).collect()] {
                let c = layout.curve(0, &x).unwrap();
                let [q0, v0, a0] = c.eval(0.2).unwrap();
                let [q1, v1, _] = c.eval(0.9).unwrap();
                assert!((q0 - start.q).abs() < 1e-9 && (v0 - start.v).abs() < 1e-9);
                assert!((q1 - gap.end.q).abs() < 1e-9 && (v1 - gap.end.v).abs() < 1e-9);
                if continuity == Continuity::C2 {
                    assert!((a0 - start.a).abs() < 1e-6, "{a0} vs {}", start.a);
                }
                for (k, &t) in layout.nodes().0.iter().enumerate() {
                    let r = layout.rows(0, k).unwrap();
                    let s = c.eval(t).unwrap();
                    for o in 0..3 {
                        assert!(
                            (r.value(o, &x) - s[o]).abs() < 1e-9,
                            "{continuity:?} order {o} at {t}"
                        );
                    }
                    let st = layout.state(0, &x, t).unwrap();
                    assert!((st[0] - s[0]).abs() < 1e-12);
                }
            }
            if off == 0.0 {
                let c = layout.curve(0, &layout.base_start()).unwrap();
                for t in [0.3, 0.55, 0.8] {
                    assert!(
                        (c.value(t).unwrap() - f(t)).abs() < 1e-6,
                        "{continuity:?} at {t}"
                    );
                }
            }
        }
    }
}
