//! The animator's operators (issue 17): their laws as property tests on
//! random Euler-joint motions, a blend on every shared BVH that must not spin
//! a limb, and the errors of bad input as the language reports them.

use crate::common;

use std::sync::Arc;

use mx::Interpreter;
use mx::mocap::bvh::Units;
use mx::motion::compose::{self, Weight};
use mx::motion::rotation::{euler_joints, from_euler};
use mx::motion::*;
use proptest::prelude::*;

/// A motion of a root (positions + ZXY rotation) and a left and right arm
/// (XYZ and ZYX rotations), sampled at 60 Hz over [t0, t0 + 2] from random
/// smooth curves; `big` puts the middle angles near gimbal lock.
fn clip(seed: &[f64], t0: f64, big: bool) -> Mu {
    let names = [
        "Hips.Xposition",
        "Hips.Yposition",
        "Hips.Zposition",
        "Hips.Zrotation",
        "Hips.Xrotation",
        "Hips.Yrotation",
        "LeftArm.Xrotation",
        "LeftArm.Yrotation",
        "LeftArm.Zrotation",
        "RightArm.Zrotation",
        "RightArm.Yrotation",
        "RightArm.Xrotation",
    ];
    let dt = 1.0 / 60.0;
    let mut m = Mu::new();
    for (k, n) in names.iter().enumerate() {
        let (a, f, p) = (
            seed[k % seed.len()],
            1.0 + k as f64 * 0.37,
            seed[(k + 3) % seed.len()],
        );
        let middle = k % 3 == 1 && k >= 3;
        let v: Vec<f64> = (0..=120)
            .map(|i| {
                let t = i as f64 * dt;
                let base = if middle && big { 1.45 } else { 0.0 };
                base + 0.4 * a * (f * t + p).sin()
            })
            .collect();
        let c = Curve::samples(t0, dt, v).unwrap();
        m.insert(*n, Dof::from(Interval::curve(c, t0, t0 + 2.0).unwrap()));
    }
    m
}

fn times(s: f64, e: f64, n: usize) -> Vec<f64> {
    (0..=n).map(|k| s + (e - s) * k as f64 / n as f64).collect()
}

fn max_diff(a: &Mu, b: &Mu, ts: &[f64]) -> f64 {
    let mut worst: f64 = 0.0;
    for n in a.names() {
        for &t in ts {
            let x = a.sample_value(n, t).unwrap().unwrap();
            let y = b.sample_value(n, t).unwrap().unwrap();
            worst = worst.max((x - y).abs());
        }
    }
    worst
}

/// The largest angle between the joint rotations of a and b at times ts.
fn max_angle(a: &Mu, b: &Mu, ts: &[f64]) -> f64 {
    let mut worst: f64 = 0.0;
    for j in euler_joints(a.names()) {
        for &t in ts {
            let e = |m: &Mu| -> [f64; 3] {
                std::array::from_fn(|c| m.sample_value(&j.dofs[c], t).unwrap().unwrap())
            };
            worst = worst.max(from_euler(j.axes, e(a)).angle_to(&from_euler(j.axes, e(b))));
        }
    }
    worst
}

fn seeds() -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec(-1.0f64..1.0, 6)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(16))]

    #[test]
    fn blend_at_zero_and_one_is_each_input(s1 in seeds(), s2 in seeds(), big in any::<bool>()) {
        let a = clip(&s1, 0.0, big);
        let b = clip(&s2, 0.5, big);
        // on the 60 Hz frames both define (at t = 2 a ends and b alone continues)
        let grid = times(0.5, 2.0 - 1.0 / 60.0, 89);
        let b0 = compose::blend(&a, &b, &Weight::Const(0.0)).unwrap();
        let b1 = compose::blend(&a, &b, &Weight::Const(1.0)).unwrap();
        prop_assert!(max_diff(&b0, &a, &grid) < 1e-9, "{}", max_diff(&b0, &a, &grid));
        prop_assert!(max_diff(&b1, &b, &grid) < 1e-9, "{}", max_diff(&b1, &b, &grid));
        // where only one is defined, that one
        let only_a = times(0.0, 0.45, 20);
        prop_assert!(max_diff(&b1, &a, &only_a) < 1e-12);
    }

    #[test]
    fn half_blend_is_the_rotation_halfway(s1 in seeds(), s2 in seeds(), big in any::<bool>()) {
        let a = clip(&s1, 0.0, big);
        let b = clip(&s2, 0.0, big);
        let m = compose::blend(&a, &b, &Weight::Const(0.5)).unwrap();
        let ts = times(0.0, 2.0, 120);
        for j in euler_joints(a.names()) {
            for &t in &ts {
                let e = |m: &Mu| -> [f64; 3] {
                    std::array::from_fn(|c| m.sample_value(&j.dofs[c], t).unwrap().unwrap())
                };
                let (qa, qb, qm) = (from_euler(j.axes, e(&a)), from_euler(j.axes, e(&b)), from_euler(j.axes, e(&m)));
                prop_assert!((qm.angle_to(&qa) - qm.angle_to(&qb)).abs() < 1e-9);
                prop_assert!((qm.angle_to(&qa) - 0.5 * qa.angle_to(&qb)).abs() < 1e-9);
            }
        }
    }

    #[test]
    fn mirror_and_reverse_are_involutions(s in seeds(), big in any::<bool>()) {
        let m = clip(&s, 0.25, big);
        let ts = times(0.25, 2.25, 333);
        let mm = compose::mirror(&compose::mirror(&m, 0).unwrap(), 0).unwrap();
        prop_assert!(max_diff(&mm, &m, &ts) < 1e-12);
        let rr = compose::reverse(&compose::reverse(&m).unwrap()).unwrap();
        prop_assert_eq!(rr.span(), m.span());
        prop_assert!(max_diff(&rr, &m, &ts) < 1e-12, "{}", max_diff(&rr, &m, &ts));
        // reverse plays backwards with velocities negated
        let r = compose::reverse(&m).unwrap();
        let a = m.sample("LeftArm.Yrotation", 0.7).unwrap().unwrap();
        let b = r.sample("LeftArm.Yrotation", 2.5 - 0.7).unwrap().unwrap();
        prop_assert!((a[0] - b[0]).abs() < 1e-12 && (a[1] + b[1]).abs() < 1e-9);
    }

    #[test]
    fn layer_of_a_zero_delta_is_the_base(s1 in seeds(), s2 in seeds(), w in 0.0f64..1.0) {
        let base = clip(&s1, 0.0, true);
        // a delta that holds its first frame: no change from the reference
        let d = clip(&s2, 0.0, false);
        let mut zero = Mu::new();
        for (n, dof) in &d.dofs {
            let v = dof.sample(n, 0.0).unwrap().unwrap()[0];
            zero.insert(n.clone(), Dof::from(Interval::constant(v, 0.0, 2.0).unwrap()));
        }
        let out = compose::layer(&base, &zero, w, None).unwrap();
        let ts = times(0.0, 2.0, 120);
        prop_assert!(max_diff(&out, &base, &ts) < 1e-9, "{}", max_diff(&out, &base, &ts));
    }

    #[test]
    fn warp_by_the_identity_is_the_motion(s in seeds()) {
        #[derive(Debug)]
        struct Id;
        impl TimeFunction for Id {
            fn eval(&self, t: f64) -> Result<f64, mx::motion::FnError> { Ok(t) }
        }
        let m = clip(&s, 0.0, true);
        let w = compose::warp(&m, Arc::new(Id)).unwrap();
        prop_assert_eq!(w.span(), m.span());
        let ts = times(0.0, 2.0, 157);
        prop_assert!(max_diff(&w, &m, &ts) < 1e-12);
    }

    #[test]
    fn crossfade_is_c1_at_both_ends_of_the_overlap(s1 in seeds(), s2 in seeds()) {
        let a = clip(&s1, 0.0, false);
        let b = clip(&s2, 0.0, false);
        let d = 0.5;
        let c = compose::crossfade(&a, &b, d, 1).unwrap();
        prop_assert_eq!(c.span(), Some((0.0, 3.5)));
        let h = 1e-6;
        for t in [1.5, 2.0] {
            for n in c.names() {
                let l = c.sample(n, t - h).unwrap().unwrap();
                let r = c.sample(n, t + h).unwrap().unwrap();
                prop_assert!((l[0] - r[0]).abs() < 1e-5, "{n} at {t}: {} vs {}", l[0], r[0]);
                prop_assert!((l[1] - r[1]).abs() < 2e-2 * (1.0 + l[1].abs()), "{n} velocity at {t}: {} vs {}", l[1], r[1]);
            }
        }
    }

    #[test]
    fn align_puts_bs_first_root_pose_on_as_last(s1 in seeds(), s2 in seeds()) {
        let a = clip(&s1, 0.0, false);
        let b = clip(&s2, 3.0, false);
        let out = compose::align(&a, &b, 1).unwrap();
        let v = |m: &Mu, n: &str, t: f64| m.sample_value(n, t).unwrap().unwrap();
        for n in ["Hips.Xposition", "Hips.Zposition"] {
            prop_assert!((v(&out, n, 3.0) - v(&a, n, 2.0)).abs() < 1e-9);
        }
        // height untouched
        prop_assert!((v(&out, "Hips.Yposition", 3.0) - v(&b, "Hips.Yposition", 3.0)).abs() < 1e-12);
        let q = |m: &Mu, t: f64| {
            from_euler([2, 0, 1], [v(m, "Hips.Zrotation", t), v(m, "Hips.Xrotation", t), v(m, "Hips.Yrotation", t)])
        };
        let yaw = |q: nalgebra::UnitQuaternion<f64>| 2.0 * q.vector()[1].atan2(q.scalar());
        let dy = (yaw(q(&out, 3.0)) - yaw(q(&a, 2.0))).rem_euclid(std::f64::consts::TAU);
        prop_assert!(dy.min(std::f64::consts::TAU - dy) < 1e-9, "heading off by {dy}");
        // the rest of b is moved rigidly: the arms are unchanged
        let ts = times(3.0, 5.0, 40);
        let arms = |m: &Mu| only(m, &["LeftArm.*", "RightArm.*"]).unwrap();
        prop_assert!(max_angle(&arms(&out), &arms(&b), &ts) < 1e-12);
    }
}

#[test]
fn mask_scales_motion_toward_the_first_frame() {
    let m = clip(&[0.3, -0.7, 0.9, 0.2, -0.4, 0.6], 0.0, true);
    let ts = times(0.0, 2.0, 120);
    let keep = compose::mask(&m, &["LeftArm.*"], 1.0).unwrap();
    assert!(max_diff(&keep, &m, &ts) < 1e-9);
    let held = compose::mask(&m, &["LeftArm.*"], 0.0).unwrap();
    let first = compose::mask(&m, &["LeftArm.*"], 0.0).unwrap();
    for &t in &ts {
        for n in [
            "LeftArm.Xrotation",
            "LeftArm.Yrotation",
            "LeftArm.Zrotation",
        ] {
            let a = held.sample_value(n, t).unwrap().unwrap();
            let b = m.sample_value(n, 0.0).unwrap().unwrap();
            assert!((a - b).abs() < 1e-9, "{n} at {t}");
        }
        let r = "RightArm.Xrotation";
        assert_eq!(
            first.sample_value(r, t).unwrap(),
            m.sample_value(r, t).unwrap()
        );
    }
}

#[test]
fn a_warp_slows_the_motion_down() {
    #[derive(Debug)]
    struct Half;
    impl TimeFunction for Half {
        fn eval(&self, t: f64) -> Result<f64, mx::motion::FnError> {
            Ok(t / 2.0)
        }
    }
    let m = clip(&[0.3, -0.7, 0.9, 0.2, -0.4, 0.6], 0.0, false);
    let w = compose::warp(&m, Arc::new(Half)).unwrap();
    let (s, e) = w.span().unwrap();
    assert!(s.abs() < 1e-9 && (e - 4.0).abs() < 1e-9);
    let a = m.sample_value("Hips.Xposition", 0.8).unwrap().unwrap();
    let b = w.sample_value("Hips.Xposition", 1.6).unwrap().unwrap();
    assert!((a - b).abs() < 1e-12);
}

#[test]
fn resample_and_linear_fill() {
    let m = clip(&[0.3, -0.7, 0.9, 0.2, -0.4, 0.6], 0.0, false);
    let r = compose::resample(&m, 240.0).unwrap();
    assert!(max_diff(&r, &m, &times(0.0, 2.0, 60)) < 1e-4);
    let hole = clip_in_place(0.5, 1.0, &m).unwrap();
    let f = fill_linear(&minus(&m, &hole)).unwrap();
    assert!(gaps(&f).is_empty());
    let n = "LeftArm.Yrotation";
    let (x0, x1) = (
        m.sample_value(n, 0.5).unwrap().unwrap(),
        m.sample_value(n, 1.0).unwrap().unwrap(),
    );
    let mid = f.sample_value(n, 0.75).unwrap().unwrap();
    assert!((mid - 0.5 * (x0 + x1)).abs() < 1e-12);
}

/// On every shared BVH: the clip blended at w = 0.5 with itself half a walk
/// cycle (0.5 s) later, its joint positions sampled at 4× the frame rate so
/// the curves between frames are seen. A limb that spins (Euler channels
/// interpolated across a branch change near gimbal lock) moves far within one
/// step (0.56 m on the Bandai dance before quaternions were sign-aligned
/// along time), so per step no joint of the blend may move more than the
/// faster of the two inputs plus 5 cm (measured: at most 3 cm, on the dance,
/// where the two poses' relative rotation turns fast). The stronger bound (within the inputs'
/// spread + 1 cm at every time) is measured and printed: slerping every
/// joint of a chain halfway does not meet it on every clip (see the report).
/// The issue asks that a blend of a walk with itself half a cycle later never
/// move a joint's world position more than the inputs' spread at that time
/// plus 1 cm. That bound is geometrically unreachable for any per-joint
/// interpolation, slerp included: two configurations can put a point in the
/// same place with different joint angles (a planar two-link arm with unit
/// links at (0°, +90°) and (90°, −90°) puts the hand at (1, 1) both ways;
/// the per-joint mean (45°, 0°) puts it at (1.41, 1.41), 0.59 m from both,
/// with a spread of 0). Measured on the shared clips (printed below), the
/// blend exceeds the spread by up to 0.68 m (Bandai dance, a hand whose two
/// inputs pass close together with different arm poses), 0.44 m (kick),
/// 0.18 m (CMU jump-turn), 5–8 cm on the walks; a still pose (bow, bye, wave)
/// stays within 1 mm.
///
/// What is measured (printed per clip) and asserted:
/// 1. measured, not yet asserted: each joint's blended rotation should be the
///    midpoint of an arc of the geodesic through the inputs' rotations
///    (ψa = ψb, ψa + ψb = φ on the short arc). Each input's quaternion is
///    sign-aligned along time so the blend is continuous; where two inputs
///    pass through opposite rotations (φ = π) continuity forces the blend
///    onto the long arc (ψa + ψb = 2π − φ) until they pass π again (the
///    alternative is a 180° jump). On the still clips the deviation is
///    ≤ 1.1e-3 rad (the blend is a C² spline through frame-step samples,
///    seen here at 4× finer times). On the long arc: 0.21 % of the Bandai
///    dance's joint samples (up to 2.01 rad past φ/2), 0.36 % of the kick's
///    (1.14 rad), 0.04 % of CMU 131's (3.10 rad). Around
///    UpperArm_L at t ≈ 21.1–21.2 s, where the inputs turn fast (more than
///    0.05 rad per quarter frame), the blend is up to 0.58 rad off the
///    midpoint even at slow samples nearby: not yet explained (open; see
///    the README's issue 17 notes);
/// 2. asserted, the chain bound from the blend's own joint angles: a
///    point's distance from input a's is at most the root's move plus Σ over
///    the bones above it of bone length × min(2, Σ ψa of the joints above
///    that bone) (a rotation by ψ moves a vector of length L by
///    ≤ 2L sin(ψ/2)), plus position channels' moves, plus 1 cm; the same
///    for b. It checks that the Euler channels written back are the
///    rotations mixed, in the joint's order, and composed down the chain;
/// 3. asserted, the per-step bound: a joint moves at most 5 cm more per
///    sample step than the faster input.
#[test]
fn blends_of_shared_clips_do_not_spin_limbs() {
    let files = common::shared_files("mocap", ".bvh");
    for path in &files {
        let clip = mx::mocap::to_motion::load(path, Units::Auto).unwrap();
        let (body, _) =
            mx::mocap::body_of::body_of(&clip.skeleton, 70.0, clip.units.metres_per_unit).unwrap();
        let a = clip.mu.clone();
        let (s, e) = a.span().unwrap();
        let shift = 0.5f64.min((e - s) / 4.0);
        let b = affine(shift, 1.0, &a).unwrap();
        let m = compose::blend(&a, &b, &Weight::Const(0.5)).unwrap();
        let win = |x: &Mu| clip_in_place(s + shift, e, x).unwrap();
        let rate = 4.0 / clip.frame_time;
        let pos = |x: &Mu| {
            mx::mocap::positions::positions(
                &win(x),
                &body,
                Some(rate),
                mx::mocap::positions::Missing::Error,
            )
            .unwrap()
        };
        let (pa, pb, pm) = (pos(&a), pos(&b), pos(&m));
        let joints = euler_joints(a.names());
        let rot = |x: &Mu, name: &str, t: f64| {
            joints.iter().find(|j| j.joint == name).map(|j| {
                let e: [f64; 3] =
                    std::array::from_fn(|c| x.sample_value(&j.dofs[c], t).unwrap().unwrap());
                from_euler(j.axes, e)
            })
        };
        // a joint's position channels (root and any others), as a vector
        let offset = |x: &Mu, name: &str, t: f64| {
            let mut v = nalgebra::Vector3::zeros();
            for (k, c) in ["Xposition", "Yposition", "Zposition"].iter().enumerate() {
                if let Some(Some(val)) = x
                    .get(&format!("{name}.{c}"))
                    .map(|d| d.sample_value("p", t).unwrap())
                {
                    v[k] = val;
                }
            }
            v
        };
        let (mut spread_excess, mut step_excess, mut chain_excess) =
            (f64::NEG_INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY);
        let mut worst_spread = (0.0, String::new());
        let mut worst_half = 0.0f64;
        let (mut samples, mut long_arc, mut worst_long, mut unresolved) =
            (0usize, 0usize, 0.0f64, 0usize);
        for k in 0..pm.times.len() {
            let t = pm.times[k];
            if t >= e - 1e-9 {
                break; // at a's end the b-only part starts, and touching intervals give it the time
            }
            // per point: half-angle sums down the chain, and the bound
            let n = pm.names.len();
            let mut psi = vec![[0.0f64; 2]; n]; // rotation of the point's joint: blend vs a, vs b
            #[allow(clippy::needless_range_loop)] // j indexes psi and the names together
            for j in 0..n {
                let name = &pm.names[j];
                if let (Some(ra), Some(rb), Some(rm)) =
                    (rot(&a, name, t), rot(&b, name, t), rot(&m, name, t))
                {
                    let phi = ra.angle_to(&rb);
                    psi[j] = [rm.angle_to(&ra), rm.angle_to(&rb)];
                    // on the geodesic through a and b, at its midpoint: the
                    // short arc (ψa + ψb = φ) or, after the inputs passed
                    // through opposite rotations, the long one (2π − φ)
                    let sum = psi[j][0] + psi[j][1];
                    let long = (sum - (2.0 * std::f64::consts::PI - phi)).abs() < (sum - phi).abs();
                    let off = (sum
                        - if long {
                            2.0 * std::f64::consts::PI - phi
                        } else {
                            phi
                        })
                    .abs();
                    // only where both inputs turn < 0.05 rad per quarter frame: a
                    // faster turn (a capture glitch through gimbal lock in the
                    // dance) is not resolved by the blend's frame-step samples
                    let dt4 = pm.times.get(1).map_or(0.0, |t1| t1 - pm.times[0]);
                    let speed = |x: &Mu| match (rot(x, name, t), rot(x, name, t + dt4)) {
                        (Some(p), Some(q)) => p.angle_to(&q),
                        _ => 0.0,
                    };
                    let resolved = speed(&a) < 0.05 && speed(&b) < 0.05;
                    let dev = if resolved {
                        off.max((psi[j][0] - psi[j][1]).abs())
                    } else {
                        0.0
                    };
                    unresolved += usize::from(!resolved);
                    worst_half = worst_half.max(dev);
                    samples += 1;
                    if long && sum - phi > 1e-3 {
                        long_arc += 1;
                        worst_long = worst_long.max(psi[j][0].max(psi[j][1]) - phi / 2.0);
                    }
                }
            }
            let mut bound = vec![[0.0f64; 2]; n];
            let mut turned = vec![[0.0f64; 2]; n]; // Σ ψ over the joints at and above
            for j in 0..n {
                let moved =
                    |x: &Mu| (offset(&m, &pm.names[j], t) - offset(x, &pm.names[j], t)).norm();
                let (dma, dmb) = (moved(&a), moved(&b));
                match pm.parents[j] {
                    None => {
                        bound[j] = [dma, dmb];
                        turned[j] = psi[j];
                    }
                    Some(p) => {
                        let len = (pa.points[k][j] - pa.points[k][p]).norm();
                        for side in 0..2 {
                            bound[j][side] =
                                bound[p][side] + len * turned[p][side].min(2.0) + [dma, dmb][side];
                            turned[j][side] = turned[p][side] + psi[j][side];
                        }
                    }
                }
            }
            #[allow(clippy::needless_range_loop)] // j indexes four parallel tables
            for j in 0..n {
                let (x, y, z) = (pa.points[k][j], pb.points[k][j], pm.points[k][j]);
                let spread = (x - y).norm();
                let excess = (z - x).norm().max((z - y).norm()) - spread;
                if excess > spread_excess {
                    spread_excess = excess;
                    worst_spread = (t, pm.names[j].clone());
                }
                chain_excess = chain_excess
                    .max(((z - x).norm() - bound[j][0]).max((z - y).norm() - bound[j][1]));
                if k > 0 {
                    let step = |p: &mx::mocap::positions::Positions| {
                        (p.points[k][j] - p.points[k - 1][j]).norm()
                    };
                    step_excess = step_excess.max(step(&pm) - step(&pa).max(step(&pb)));
                }
            }
        }
        eprintln!(
            "{}: beyond the inputs' spread {spread_excess:.4} m (worst: {} at t = {:.3} s), beyond the chain bound {chain_excess:.2e} m, \
             off the a–b geodesic midpoint {worst_half:.1e} rad, on the long arc {:.2} % of joint samples (up to {worst_long:.2} rad past φ/2), {unresolved} fast samples skipped, \
             per-step beyond the faster input {step_excess:.4} m",
            path.display(),
            worst_spread.1,
            worst_spread.0,
            100.0 * long_arc as f64 / samples.max(1) as f64
        );
        // (1) is measured and printed, not asserted: see the comment above
        assert!(
            chain_excess <= 0.01,
            "{}: a joint is {chain_excess} m past the chain bound",
            path.display()
        );
        assert!(
            step_excess <= 0.05,
            "{}: a joint of the blend jumped {step_excess} m more than the inputs in one step",
            path.display()
        );
    }
}

fn error_of(src: &str) -> String {
    let mut mx = Interpreter::new();
    match mx.eval_str(src) {
        Ok(v) => panic!("expected an error, got {v:?}"),
        Err(d) => d.render_plain(),
    }
}

#[test]
fn bad_input_gets_clear_errors() {
    let pre = "let a = mu({\"Hips.Xposition\": interval(fn(t) = t, 0, 2), \"LeftArm.Xrotation\": interval(0, 0, 2)})\n\
               let b = mu({q: interval(1, 0, 2)})\n";
    let e = error_of(&format!("{pre}blend(a, b, 0.5)"));
    assert!(e.contains("no DOF in common"), "{e}");
    let e = error_of(&format!("{pre}blend(a, a, 1.5)"));
    assert!(e.contains("[0, 1]") && e.contains("1.5"), "{e}");
    let e = error_of(&format!("{pre}blend(a, a, fn(t) = t)"));
    assert!(e.contains("[0, 1]") && e.contains("at t ="), "{e}");
    let e = error_of(&format!(
        "{pre}warp(a, fn(t) = if t < 1 {{ t }} else if t < 1.5 {{ 1 }} else {{ t - 0.5 }})"
    ));
    assert!(
        e.contains("strictly increasing") && e.contains("f(1"),
        "{e}"
    );
    let e = error_of(&format!("{pre}mirror(b)"));
    assert!(e.contains("no DOF name has a side"), "{e}");
    let e = error_of(&format!("{pre}layer(a, a, w: 2)"));
    assert!(e.contains("[0, 1]"), "{e}");
    let e = error_of(&format!("{pre}crossfade(a, a, 5)"));
    assert!(e.contains("overlap"), "{e}");
    // reverse still reverses lists
    let mut mx = Interpreter::new();
    let v = mx.eval_str("reverse([1, 2, 3])").unwrap();
    assert_eq!(format!("{v}"), "[3, 2, 1]");
}

/// The composing examples run from the repository root (as `mx run` would)
/// and their checks (`assert`) hold.
#[test]
fn composing_examples_run() {
    std::env::set_current_dir(env!("CARGO_MANIFEST_DIR")).unwrap();
    for ex in [
        "compose_mirror_loop.mx",
        "compose_crossfade.mx",
        "compose_layer_warp.mx",
    ] {
        let mut mx = Interpreter::new();
        let out = mx.capture_output();
        if let Err(e) = mx.eval_file(format!("examples/{ex}")) {
            panic!("{ex} failed: {}", e.render_plain());
        }
        let printed = String::from_utf8(out.lock().unwrap().clone()).unwrap();
        assert!(printed.contains("Mu ["), "{ex} printed {printed}");
    }
}

/// hold and loop extrapolation (issue 17 item 2): the motion unchanged inside
/// its span, the first/last pose held or whole periods repeated outside, and
/// the result an ordinary motion for the algebra.
#[test]
fn hold_and_loop_extend_a_motion_and_compose_with_the_algebra() {
    let m = clip(&[0.3, -0.7, 1.1, 0.4], 0.0, false); // defined on [0, 2]
    let inside = times(0.0, 2.0, 40);
    let held = extrapolate(&m, -1.0, 3.5, Extrapolation::Hold).unwrap();
    assert_eq!(held.span(), Some((-1.0, 3.5)));
    assert_eq!(max_diff(&held, &m, &inside), 0.0);
    for n in m.names() {
        let first = m.sample_value(n, 0.0).unwrap().unwrap();
        let last = m.sample_value(n, 2.0).unwrap().unwrap();
        for t in [-1.0, -0.3] {
            assert_eq!(held.sample_value(n, t).unwrap(), Some(first), "{n} at {t}");
        }
        for t in [2.2, 3.5] {
            assert_eq!(held.sample_value(n, t).unwrap(), Some(last), "{n} at {t}");
        }
    }
    let looped = extrapolate(&m, -3.0, 7.0, Extrapolation::Loop).unwrap();
    assert_eq!(looped.span(), Some((-3.0, 7.0)));
    // at a seam (t = 2 here) the next period's first pose is sampled
    assert_eq!(max_diff(&looped, &m, &inside[..inside.len() - 1]), 0.0);
    for n in m.names() {
        for t in [0.1, 0.77, 1.5] {
            let v = m.sample_value(n, t).unwrap().unwrap();
            for k in [-1.0, 1.0, 2.0] {
                let got = looped.sample_value(n, t + 2.0 * k).unwrap().unwrap();
                assert!(
                    (got - v).abs() < 1e-12,
                    "{n} at {t} + {k} periods: {got} vs {v}"
                );
            }
        }
    }
    // the algebra: what hold adds is exactly the outside, and a meet with it
    // is defined where both are
    let added = minus(&held, &m);
    assert_eq!(added.span(), Some((-1.0, 3.5)));
    let d = added.get("Hips.Xposition").unwrap();
    assert_eq!(d.intervals.len(), 2);
    assert!(
        (d.intervals[0].stop - 0.0).abs() < 1e-12 && (d.intervals[1].start - 2.0).abs() < 1e-12
    );
    let window = {
        let mut w = Mu::new();
        w.insert(
            "Hips.Xposition",
            Dof::from(Interval::constant(0.0, 2.5, 3.0).unwrap()),
        );
        w
    };
    let met = and(&held, &window);
    assert_eq!(
        met.get("Hips.Xposition").and_then(|d| d.span()),
        Some((2.5, 3.0))
    );
    // a cyclic motion loops seamlessly: value and velocity continuous at the seam
    let mut cyc = Mu::new();
    cyc.insert(
        "q",
        Dof::from(Interval::function(Arc::new(Sine), 0.0, 1.0).unwrap()),
    );
    let l = extrapolate(&cyc, 0.0, 3.0, Extrapolation::Loop).unwrap();
    let (a, b) = (
        l.sample("q", 1.0 - 1e-9).unwrap().unwrap(),
        l.sample("q", 1.0 + 1e-9).unwrap().unwrap(),
    );
    assert!(
        (a[0] - b[0]).abs() < 1e-6 && (a[1] - b[1]).abs() < 1e-6,
        "{a:?} {b:?}"
    );
    // errors
    assert!(extrapolate(&m, 3.0, 1.0, Extrapolation::Hold).is_err());
    assert!(extrapolate(&Mu::new(), 0.0, 1.0, Extrapolation::Loop).is_err());
    // a span no number of copies can cover is a clear error, not an overflow
    for (ts, tf) in [(-1e308, 1e308), (0.0, 1e12)] {
        let e = extrapolate(&m, ts, tf, Extrapolation::Loop).unwrap_err();
        assert!(e.to_string().contains("copies"), "{e}");
    }
}

/// sin(2πt): one period over [0, 1].
#[derive(Debug)]
struct Sine;
impl TimeFunction for Sine {
    fn eval(&self, t: f64) -> Result<f64, mx::motion::FnError> {
        Ok((2.0 * std::f64::consts::PI * t).sin())
    }
}

/// The chain forms in mx: `m.hold(ts, tf)`, `m.loop(ts, tf)`, beside the
/// older `hold(names, value, ts, tf)` and `loop(m, n)`.
#[test]
fn hold_and_loop_read_well_in_a_chain() {
    let mut mx = Interpreter::new();
    let v = mx
        .eval_str(
            "let a = mu({x: interval(fn(t) = t, 0, 1)})\n\
             let h = a.hold(-1, 3)\n\
             let l = a.loop(0, 3.5).only(\"x\")\n\
             [span(h)[0], span(h)[1], sample(h, -0.5).x, sample(h, 2).x, sample(l, 2.25).x, span(hold([\"p\"], 2, 0, 1))[1], span(loop(cyclify(a, 0, 1), 2))[1]]",
        )
        .unwrap_or_else(|d| panic!("{}", d.render_plain()));
    let got: Vec<f64> = v
        .as_list()
        .unwrap()
        .iter()
        .map(|x| x.as_number().unwrap())
        .collect();
    assert_eq!(&got[..6], &[-1.0, 3.0, 0.0, 1.0, 0.25, 1.0]);
    assert!(got[6] > 1.0);
    let e = error_of("let a = mu({x: interval(0, 0, 1)})\na.hold(2, 1)");
    assert!(e.contains("ts < tf"), "{e}");
    let e = error_of("let a = mu({x: interval(0, 0, 1)})\nextrapolate(a, 0, 2, \"bounce\")");
    assert!(e.contains("\"hold\" or \"loop\""), "{e}");
}
