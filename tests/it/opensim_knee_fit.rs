//! Fitting spline curve joints to the OpenSim knee samples (paper §6.2) and
//! smoothing noisy samples (§6.3). Every `*_samples.json` is a case.

use crate::common;

use mx::lie::{Se3, Twist, exp_se3};
use mx::model::Joint;
use mx::model::joint_fit::*;
use mx::model::joints::*;
use mx::report::fit;
use std::time::Instant;

#[test]
fn fitted_curve_joint_reaches_0_1_mm_and_0_05_deg_with_at_most_16_frames() {
    for path in common::shared_files("opensim", "_samples.json") {
        let samples = JointSamples::load(&path).unwrap();
        println!("{}", path.display());
        println!(
            "{:>7} {:>9} | {:>9} {:>9} {:>9} {:>9} | {:>5} {:>9}",
            "frames", "knots", "max mm", "rms mm", "max °", "rms °", "iters", "fit ms"
        );
        let mut best: Option<(usize, JointError)> = None;
        for frames in [4, 6, 8, 12, 16] {
            for knots in [KnotPlacement::Uniform, KnotPlacement::Natural] {
                let t0 = Instant::now();
                let r = fit_spline_joint(
                    &samples,
                    &FitOptions {
                        frames,
                        knots,
                        ..Default::default()
                    },
                )
                .unwrap();
                let ms = t0.elapsed().as_secs_f64() * 1e3;
                let e = joint_error(&r.joint, &samples).unwrap();
                println!(
                    "{frames:>7} {:>9} | {:>9.5} {:>9.5} {:>9.5} {:>9.5} | {:>5} {ms:>9.1}",
                    format!("{knots:?}"),
                    e.max_mm,
                    e.rms_mm,
                    e.max_deg,
                    e.rms_deg,
                    r.iterations
                );
                if e.max_mm <= 0.1 && e.max_deg <= 0.05 && best.is_none() {
                    best = Some((frames, e));
                }
            }
        }
        let (frames, e) = best.expect("no fit within 0.1 mm and 0.05° with ≤ 16 control frames");
        println!(
            "first fit within 0.1 mm / 0.05°: {frames} control frames ({:.4} mm, {:.4}°)",
            e.max_mm, e.max_deg
        );
    }
}

#[test]
fn smoothing_lowers_hessian_energy_monotonically() {
    for path in common::shared_files("opensim", "_samples.json") {
        let clean = JointSamples::load(&path).unwrap();
        // the report's noisy data: 1 mm per translation axis and 0.5° per
        // rotation axis (σ), fixed seed
        let noisy = clean.with_noise(fit::NOISE_M, fit::NOISE_DEG.to_radians(), fit::NOISE_SEED);
        let (a, b) = clean.range();
        println!(
            "{}: 16 frames on noisy samples (1 mm, 0.5°)",
            path.display()
        );
        println!(
            "{:>6} | {:>12} | {:>9} {:>9} {:>9} {:>9} (error to clean data)",
            "w", "∫‖∇S‖² dq", "max mm", "rms mm", "max °", "rms °"
        );
        let mut rows = Vec::new();
        for w in [0.0, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2] {
            let r = fit_spline_joint(
                &noisy,
                &FitOptions {
                    frames: 16,
                    smooth: w,
                    ..Default::default()
                },
            )
            .unwrap();
            let energy = hessian_energy(&r.joint, a, b, 2000);
            let e = joint_error(&r.joint, &clean).unwrap();
            println!(
                "{w:>6} | {energy:>12.5e} | {:>9.4} {:>9.4} {:>9.4} {:>9.4}",
                e.max_mm, e.rms_mm, e.max_deg, e.rms_deg
            );
            rows.push((w, energy));
        }
        // The weight trades data fit for ∫‖∇S‖², so the energy falls with w.
        // Which weight is *best* depends on the data (the knee, the noise): no
        // fixed weight is asserted to be good; `smooth: "auto"` chooses one
        // (the test below).
        for pair in rows.windows(2) {
            assert!(
                pair[1].1 < pair[0].1,
                "w = {}: ∫‖∇S‖² {:e} did not drop below {:e}",
                pair[1].0,
                pair[1].1,
                pair[0].1
            );
        }
    }
}

#[test]
fn fitting_rejects_bad_requests() {
    let q: Vec<f64> = (0..20).map(|i| i as f64 * 0.1).collect();
    let t: Vec<Se3> = q
        .iter()
        .map(|&x| exp_se3(&Twist::new(0., 0., x, 0.01 * x, 0., 0.)))
        .collect();
    let s = JointSamples::new(q.clone(), t).unwrap();
    assert!(
        fit_spline_joint(
            &s,
            &FitOptions {
                frames: 3,
                ..Default::default()
            }
        )
        .is_err()
    );
    assert!(
        fit_spline_joint(
            &s,
            &FitOptions {
                frames: 30,
                ..Default::default()
            }
        )
        .is_err()
    );
    assert!(
        fit_spline_joint(
            &s,
            &FitOptions {
                smooth: 1.0,
                ..Default::default()
            }
        )
        .is_err()
    );
    // a screw motion is reproduced essentially exactly
    let r = fit_spline_joint(
        &s,
        &FitOptions {
            frames: 5,
            ..Default::default()
        },
    )
    .unwrap();
    let e = joint_error(&r.joint, &s).unwrap();
    assert!(e.max_mm < 1e-6 && e.max_deg < 1e-6, "{e:?}");
    // samples a half-turn apart are ambiguous
    let t2: Vec<Se3> = q
        .iter()
        .map(|&x| {
            exp_se3(&Twist::new(
                0.,
                0.,
                x * 10.0 * std::f64::consts::PI,
                0.,
                0.,
                0.,
            ))
        })
        .collect();
    let s2 = JointSamples::new(q.clone(), t2).unwrap();
    assert!(
        fit_spline_joint(&s2, &FitOptions::default())
            .unwrap_err()
            .to_string()
            .contains("π")
    );
    // repeated q
    assert!(JointSamples::new(vec![0.0, 0.0], vec![Se3::identity(); 2]).is_err());
}

/// Samples of the repository's own knee (`examples/data/knee_r.osim`) at 121
/// angles over its range: the second knee beside the shared gait2392 one.
fn example_knee_samples() -> JointSamples {
    let osim = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/data/knee_r.osim");
    let joint = FunctionJoint::from_osim_file(&osim, "knee_r").unwrap();
    let lim = joint.limits()[0];
    let mut k = mx::model::JointKinematics::default();
    let (q, g): (Vec<f64>, Vec<Se3>) = (0..=120)
        .map(|i| {
            let q = lim.lower + (lim.upper - lim.lower) * i as f64 / 120.0;
            joint.kinematics(&[q], mx::model::Derivatives::Transform, &mut k);
            (q, k.transform)
        })
        .unzip();
    JointSamples::new(q, g).unwrap()
}

/// A knee nobody tuned on: a random smooth 1-DOF motion of knee size. The
/// coordinate turns the child about a random axis over a random range of
/// 80–140°; two smaller rotations about random axes (up to ±4° each) and the
/// translation (a random offset up to 0.45 m, varying by up to ±8 mm per axis)
/// are sums of slow sines of q. Sampled at 61–181 evenly spaced q.
fn generated_knee(seed: u64) -> JointSamples {
    let mut s = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    let mut r = |lo: f64, hi: f64| {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        lo + (hi - lo) * ((s >> 11) as f64 / (1u64 << 53) as f64)
    };
    let unit = |r: &mut dyn FnMut(f64, f64) -> f64| {
        let v = nalgebra::Vector3::new(r(-1.0, 1.0), r(-1.0, 1.0), r(-1.0, 1.0) + 0.1);
        v / v.norm()
    };
    let axes = [unit(&mut r), unit(&mut r), unit(&mut r)];
    // a smooth function of q: Σ amplitude·sin(ω q + φ) over three terms, ω ≤ 2/rad
    type Wave = [(f64, f64, f64); 3];
    let wave = |amp: f64, r: &mut dyn FnMut(f64, f64) -> f64| -> Wave {
        [0, 1, 2].map(|_| (r(-amp, amp) / 3.0, r(0.3, 2.0), r(0.0, 6.3)))
    };
    let eval = |w: &Wave, q: f64| {
        w.iter()
            .map(|(a, om, ph)| a * (om * q + ph).sin())
            .sum::<f64>()
    };
    let small = 4f64.to_radians();
    let rot = [wave(small, &mut r), wave(small, &mut r)];
    let trans = [wave(8e-3, &mut r), wave(8e-3, &mut r), wave(8e-3, &mut r)];
    let offset = nalgebra::Vector3::new(r(-0.05, 0.05), r(-0.45, -0.3), r(-0.05, 0.05));
    let lo = r(-2.2, 0.0);
    let span = r(80f64, 140.0).to_radians();
    let n = r(61.0, 182.0) as usize;
    let (q, g): (Vec<f64>, Vec<Se3>) = (0..n)
        .map(|k| {
            let q = lo + span * k as f64 / (n - 1) as f64;
            let turn = |axis: &nalgebra::Vector3<f64>, angle: f64| {
                exp_se3(&Twist::new(
                    axis.x * angle,
                    axis.y * angle,
                    axis.z * angle,
                    0.,
                    0.,
                    0.,
                ))
            };
            let mut g = turn(&axes[0], q)
                .compose(&turn(&axes[1], eval(&rot[0], q)))
                .compose(&turn(&axes[2], eval(&rot[1], q)));
            g.p = offset
                + nalgebra::Vector3::new(
                    eval(&trans[0], q),
                    eval(&trans[1], q),
                    eval(&trans[2], q),
                );
            (q, g)
        })
        .unzip();
    JointSamples::new(q, g).unwrap()
}

/// How many generated knees the test below adds to the data folder's.
const GENERATED_KNEES: u64 = 6;

#[test]
fn gcv_weight_brings_every_knee_closer_to_clean_data_than_no_smoothing() {
    let mut knees: Vec<(String, JointSamples)> = common::shared_files("opensim", "_samples.json")
        .into_iter()
        .map(|p| (p.display().to_string(), JointSamples::load(&p).unwrap()))
        .collect();
    knees.push(("examples/data/knee_r.osim".into(), example_knee_samples()));
    knees.extend((1..=GENERATED_KNEES).map(|k| (format!("generated knee {k}"), generated_knee(k))));
    for (name, clean) in knees {
        for seed in [fit::NOISE_SEED, 7] {
            let noisy = clean.with_noise(fit::NOISE_M, fit::NOISE_DEG.to_radians(), seed);
            let opt = FitOptions {
                frames: 16,
                ..Default::default()
            };
            let auto = fit_spline_joint_auto(&noisy, &opt).unwrap();
            let none = fit_spline_joint(&noisy, &opt).unwrap();
            let (ea, e0) = (
                joint_error(&auto.fit.joint, &clean).unwrap(),
                joint_error(&none.joint, &clean).unwrap(),
            );
            println!(
                "{name} (seed {seed}): GCV chose w = {:.3e} of {} tried; error to clean data rms {:.4} mm {:.4}°, max {:.4} mm {:.4}° (w = 0: rms {:.4} mm {:.4}°, max {:.4} mm {:.4}°)",
                auto.weight,
                auto.scores.len(),
                ea.rms_mm,
                ea.rms_deg,
                ea.max_mm,
                ea.max_deg,
                e0.rms_mm,
                e0.rms_deg,
                e0.max_mm,
                e0.max_deg
            );
            assert!(auto.scores.iter().all(|(_, v)| v.is_finite() && *v > 0.0));
            // the chosen weight is the least score of all tried
            let least = auto
                .scores
                .iter()
                .fold(f64::INFINITY, |m, (_, v)| m.min(*v));
            assert!(auto.scores.contains(&(auto.weight, least)));
            // Closer to the clean data than no smoothing, in position and in angle.
            assert!(
                ea.rms_mm < e0.rms_mm && ea.rms_deg < e0.rms_deg,
                "{name} (seed {seed}): auto w = {} {ea:?} vs w = 0 {e0:?}",
                auto.weight
            );
        }
    }
}

#[test]
fn smooth_auto_in_the_language() {
    for path in common::shared_files("opensim", "_samples.json") {
        let p = path.display().to_string();
        let mut mx = mx::Interpreter::new();
        mx.eval_str(&format!("let s = load_samples({p:?})"))
            .unwrap();
        // "auto" is the default, and the joint reports the weight it chose
        let auto = mx
            .eval_str("fit_spline_joint(s, frames: 8, smooth: \"auto\").smooth")
            .unwrap();
        let default = mx
            .eval_str("fit_spline_joint(s, frames: 8).smooth")
            .unwrap();
        assert_eq!(auto.to_string(), default.to_string());
        let samples = JointSamples::load(&path).unwrap();
        let engine = fit_spline_joint_auto(
            &samples,
            &FitOptions {
                frames: 8,
                ..Default::default()
            },
        )
        .unwrap();
        assert_eq!(
            auto.to_string(),
            mx::Value::Number(engine.weight).to_string()
        );
        // a number still sets the weight
        let set = mx
            .eval_str("fit_spline_joint(s, frames: 8, smooth: 0.001).smooth")
            .unwrap();
        assert_eq!(set.to_string(), "0.001");
        let v = mx
            .eval_str("joint_error(fit_spline_joint(s, frames: 8), s).rms_mm < 1")
            .unwrap();
        assert_eq!(v.to_string(), "true");
        let e = mx
            .eval_str("fit_spline_joint(s, smooth: \"often\")")
            .unwrap_err();
        assert!(format!("{e:?}").contains("\\\"auto\\\""), "{e:?}");
    }
}
