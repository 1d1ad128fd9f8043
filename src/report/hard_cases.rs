//! The registry of numerically delicate cases. Each case runs real library
//! code and reports what the engine returned, the worst error measured, the
//! bound it must stay under and whether it passed. `tests/it/hard_cases.rs`
//! asserts every case passes and the report prints the same table, so the two
//! cannot drift apart. A case that expects a clear error measures 0 when the
//! error arrives with the expected words, 1 otherwise (bound 0.5).

use crate::cancel::CancelToken;
use crate::dynamics::{
    DynamicsError, Integrator, Scene, State, Workspace, forward_dynamics, inverse_dynamics,
    simulate,
};
use crate::lie::{Se3, Twist, exp_se3, exp_so3, log_se3, rotation_angle};
use crate::model::joint_fit::{FitOptions, fit_spline_joint};
use crate::model::joints::{EulerOrder, JointSamples, Revolute, Spherical};
use crate::model::{Inertia, Model};
use crate::motion::{Dof, Interval, Mu};
use crate::report::error::{ReportError, ZERO_AXIS};
use crate::spacetime::planar2::TwoLinkArm;
use crate::spacetime::{
    Continuity, EndState, GapDof, Objective, SolveOptions, TransitionCurve, TransitionSettings,
    solve_group,
};
use crate::spline::BSplineBasis;

pub use super::hard_case::HardCase;
use super::hard_case::case;
use nalgebra::{Matrix3, Vector3};
use std::f64::consts::PI;
use std::sync::Arc;

/// A case whose correct outcome is an error containing every word in `want`.
fn expect_err<T>(
    name: &'static str,
    area: &'static str,
    r: Result<T, ReportError>,
    want: &[&str],
) -> HardCase {
    match r {
        Ok(_) => case(name, area, "accepted (expected an error)".into(), 1.0, 0.5),
        Err(e) => {
            let msg = e.to_string();
            let ok = want
                .iter()
                .all(|w| msg.to_lowercase().contains(&w.to_lowercase()));
            case(
                name,
                area,
                format!("error: {}", first_line(&msg)),
                if ok { 0.0 } else { 1.0 },
                0.5,
            )
        }
    }
}

fn first_line(s: &str) -> String {
    let l = s.lines().next().unwrap_or("");
    if l.chars().count() > 110 {
        format!("{}…", l.chars().take(110).collect::<String>())
    } else {
        l.to_string()
    }
}

/// Every case, in the order the report prints them.
pub fn all() -> Vec<HardCase> {
    vec![
        se3_log_near_zero(),
        se3_log_near_pi(),
        coincident_knots(),
        frames_near_pi_apart(),
        vanishing_jacobian(),
        tiny_mass(),
        huge_mass(),
        massless_tip(),
        long_chain(),
        euler_100ms(),
        super::hard_mechanisms::beads_euler_100ms(),
        super::hard_mechanisms::spline_surface_range_end(),
        zero_length_gap(),
        five_second_gap(),
        identical_end_states(),
        wrapped_euler_angles(),
        conflicting_dofs(),
        malformed_bvh(),
        malformed_urdf(),
    ]
}

pub fn se3_log_near_zero() -> HardCase {
    let mut worst = 0.0f64;
    for s in [1e-15, 1e-12, 1e-9, 1e-6, 1e-4] {
        let x = Twist::new(0.3, -0.5, 0.8, 1.0, 2.0, -0.7) * s;
        let y = log_se3(&exp_se3(&x));
        worst = worst.max((y - x).norm() / x.norm());
    }
    case(
        "SE(3) log near 0 (|ξ| = 1e-15 … 1e-4)",
        "lie",
        "log(exp ξ) relative to |ξ|".into(),
        worst,
        1e-12,
    )
}

pub fn se3_log_near_pi() -> HardCase {
    let mut worst = 0.0f64;
    let axis = Vector3::new(1.0, 2.0, -2.0) / 3.0;
    for d in [1e-3, 1e-6, 1e-9, 0.0] {
        let w = axis * (PI - d);
        let t = Se3::new(exp_so3(&w), Vector3::new(0.4, -1.0, 0.2));
        let back = exp_se3(&log_se3(&t));
        worst = worst
            .max((back.r - t.r).norm())
            .max((back.p - t.p).norm())
            .max((rotation_angle(&t.r) - (PI - d)).abs());
    }
    case(
        "SE(3) log near π (π − 1e-3 … π exactly)",
        "lie",
        "exp(log T) and the rotation angle".into(),
        worst,
        1e-9,
    )
}

pub fn coincident_knots() -> HardCase {
    let r = (|| -> Result<f64, ReportError> {
        let b = BSplineBasis::new(
            3,
            vec![0.0, 0.0, 0.0, 0.0, 0.5, 0.5, 0.5, 1.0, 1.0, 1.0, 1.0],
        )?;
        let mut worst = 0.0f64;
        let mut out = [[0.0; 6]; 3];
        for k in 0..=200 {
            let t = k as f64 / 200.0;
            b.eval_nonzero(t, 2, &mut out);
            let sum: f64 = out[0][..=3].iter().sum();
            let d1: f64 = out[1][..=3].iter().sum();
            if out.iter().flatten().any(|x| !x.is_finite()) {
                return Ok(f64::INFINITY);
            }
            worst = worst.max((sum - 1.0).abs()).max(d1.abs());
        }
        Ok(worst)
    })();
    match r {
        Ok(w) => case(
            "coincident knots (triple interior knot)",
            "spline",
            "finite basis; Σ Bᵢ − 1 and Σ Bᵢ′ on 201 points".into(),
            w,
            1e-12,
        ),
        Err(e) => case(
            "coincident knots (triple interior knot)",
            "spline",
            e.to_string(),
            1.0,
            0.0,
        ),
    }
}

pub fn frames_near_pi_apart() -> HardCase {
    let q: Vec<f64> = (0..20).map(|i| i as f64 * 0.1).collect();
    let t: Vec<Se3> = q
        .iter()
        .map(|&x| exp_se3(&Twist::new(0.0, 0.0, x * 10.0 * PI, 0.0, 0.0, 0.0)))
        .collect();
    let r = JointSamples::new(q, t)
        .map_err(ReportError::from)
        .and_then(|s| fit_spline_joint(&s, &FitOptions::default()).map_err(ReportError::from));
    expect_err("control frames a half-turn apart", "joints", r, &["π"])
}

pub fn vanishing_jacobian() -> HardCase {
    let s = Spherical::default();
    let a = s.singularity_measure(&[0.3, PI / 2.0, 0.2]);
    let b = match EulerOrder::parse("zxz") {
        Ok(o) => Spherical::new(o).singularity_measure(&[0.3, 0.0, 0.2]),
        Err(_) => f64::INFINITY,
    };
    let regular = s.singularity_measure(&[0.3, 0.0, 0.2]);
    case(
        "vanishing joint Jacobian (gimbal lock)",
        "joints",
        format!(
            "singularity measure {a:.1e} (xyz at 90°), {b:.1e} (zxz at 0), {regular:.3} regular"
        ),
        a.max(b).max((regular - 1.0).abs()),
        1e-12,
    )
}

/// Revolute chain, alternating axes, link masses cycling through `masses`
/// (the chain of `tests/it/dynamics.rs`).
pub fn chain(n: usize, masses: &[f64]) -> Result<Model, ReportError> {
    if masses.is_empty() {
        return Err(ReportError::BadModel {
            model: "chain",
            why: "needs at least one link mass",
        });
    }
    let mut m = Model::new("chain");
    for i in 0..n {
        let axis = if i % 2 == 0 {
            Vector3::z()
        } else {
            Vector3::y()
        };
        let mass = masses[i % masses.len()];
        let inertia = Inertia::from_com(
            mass,
            Vector3::new(0.05, 0.0, 0.0),
            Matrix3::from_diagonal(&Vector3::new(1e-4, 4e-4, 4e-4)) * mass,
        )?;
        let off = Se3::from_translation(Vector3::new(if i == 0 { 0.0 } else { 0.1 }, 0.0, 0.0));
        m.add_link(
            &format!("l{i}"),
            if i == 0 { None } else { Some(i - 1) },
            &format!("j{i}"),
            Arc::new(Revolute::new(axis).ok_or(ZERO_AXIS)?),
            off,
            inertia,
        )?;
    }
    Ok(m)
}

/// |RNEA(q, q̇, ABA(q, q̇, τ)) − τ| / max(|τ|, 1): a residual that does not
/// depend on the conditioning of the mass matrix.
pub fn aba_residual(m: &Model, seed: u64) -> Result<f64, ReportError> {
    let mut s = seed.max(1);
    let mut r = |lo: f64, hi: f64| {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        lo + (hi - lo) * ((s >> 11) as f64 / (1u64 << 53) as f64)
    };
    let n = m.nq();
    let q: Vec<f64> = (0..n).map(|_| r(-0.5, 0.5)).collect();
    let v: Vec<f64> = (0..n).map(|_| r(-1.0, 1.0)).collect();
    let tau: Vec<f64> = (0..n).map(|_| r(-1.0, 1.0)).collect();
    let g = Vector3::new(0.0, 0.0, -9.81);
    let mut ws = Workspace::new(m);
    let mut qdd = vec![0.0; n];
    forward_dynamics(m, &mut ws, &q, &v, &tau, &g, &mut qdd)?;
    if qdd.iter().any(|x| !x.is_finite()) {
        return Ok(f64::INFINITY);
    }
    let mut t2 = vec![0.0; n];
    inverse_dynamics(m, &mut ws, &q, &v, &qdd, &g, &mut t2)?;
    let scale = tau.iter().fold(1.0f64, |a, b| a.max(b.abs()));
    Ok(t2
        .iter()
        .zip(&tau)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max)
        / scale)
}

fn residual_case(name: &'static str, n: usize, masses: &[f64], seed: u64) -> HardCase {
    match chain(n, masses).and_then(|m| aba_residual(&m, seed)) {
        Ok(e) => case(
            name,
            "dynamics",
            format!("finite q̈; |RNEA(ABA(τ)) − τ|/|τ| = {e:.1e}"),
            e,
            1e-8,
        ),
        Err(e) => case(name, "dynamics", format!("error: {e}"), 1.0, 0.0),
    }
}

pub fn tiny_mass() -> HardCase {
    residual_case("tiny mass (1e-9 kg beside 100 kg)", 4, &[100.0, 1e-9], 2)
}

pub fn huge_mass() -> HardCase {
    residual_case("huge mass (1e6 kg beside 1 kg)", 6, &[1e6, 1.0], 3)
}

pub fn long_chain() -> HardCase {
    residual_case("500-link chain", 500, &[1.0, 0.5], 1)
}

pub fn massless_tip() -> HardCase {
    let r = chain(3, &[1.0, 1.0, 0.0]).and_then(|m| {
        let mut ws = Workspace::new(&m);
        let mut qdd = vec![0.0; 3];
        forward_dynamics(
            &m,
            &mut ws,
            &[0.1; 3],
            &[0.0; 3],
            &[0.0; 3],
            &Vector3::zeros(),
            &mut qdd,
        )
        .map_err(ReportError::from)
    });
    expect_err("massless tip link", "dynamics", r, &["j2"])
}

pub fn euler_100ms() -> HardCase {
    let name = "explicit Euler at 100 ms steps (3-link pendulum, 20 s)";
    let r = (|| -> Result<HardCase, ReportError> {
        let mut m = Model::new("pendulum");
        for i in 0..3 {
            let inertia = Inertia::from_com(
                1.0,
                Vector3::new(0.0, -0.25, 0.0),
                Matrix3::from_diagonal(&Vector3::new(0.02, 0.001, 0.02)),
            )?;
            m.add_link(
                &format!("rod{i}"),
                if i == 0 { None } else { Some(i - 1) },
                &format!("j{i}"),
                Arc::new(Revolute::new(Vector3::z()).ok_or(ZERO_AXIS)?),
                Se3::from_translation(Vector3::new(0.0, if i == 0 { 0.0 } else { -0.5 }, 0.0)),
                inertia,
            )?;
        }
        let scene = Scene::new(Arc::new(m)).with_gravity(Vector3::new(0.0, -9.81, 0.0))?;
        let init = State {
            q: vec![1.2, -0.5, 0.8],
            v: vec![0.0; 3],
        };
        Ok(
            match simulate(
                &scene,
                20.0,
                0.1,
                Integrator::Euler,
                &init,
                &CancelToken::new(),
                &mut |_| {},
            ) {
                Ok(tr) => {
                    let finite = tr.q.iter().chain(&tr.v).flatten().all(|x| x.is_finite());
                    case(
                        name,
                        "dynamics",
                        format!("{} finite samples", tr.q.len()),
                        if finite { 0.0 } else { 1.0 },
                        0.5,
                    )
                }
                Err(DynamicsError::Singular(msg)) => {
                    let ok = msg.contains("smaller dt");
                    case(
                        name,
                        "dynamics",
                        format!("error: {}", first_line(&msg)),
                        if ok { 0.0 } else { 1.0 },
                        0.5,
                    )
                }
                Err(e) => case(name, "dynamics", format!("unexpected error: {e}"), 1.0, 0.5),
            },
        )
    })();
    r.unwrap_or_else(|e| case(name, "dynamics", format!("setup failed: {e}"), 1.0, 0.5))
}

pub fn zero_length_gap() -> HardCase {
    let a = TransitionCurve::new(1.0, 1.0, 4, Continuity::C1).map_err(ReportError::from);
    let b = Interval::constant(0.0, 2.0, 2.0).map_err(ReportError::from);
    let mut c = expect_err("zero-length gap", "spacetime", a, &[]);
    let d = expect_err("zero-length interval", "motion", b, &[]);
    c.returned = format!("transition: {}; interval: {}", c.returned, d.returned);
    c.worst_error = c.worst_error.max(d.worst_error);
    c.passed = c.passed && d.passed;
    c
}

fn st(q: f64, v: f64) -> EndState {
    EndState { q, v, a: 0.0 }
}

/// The two-link arm's gap of `solve.rs`' tests: returns (energy, Hermite energy, worst end jump).
pub fn arm_gap(
    t1: f64,
    settings: &TransitionSettings,
    start: [EndState; 2],
    end: [EndState; 2],
) -> Result<(f64, f64, f64), ReportError> {
    let arm = TwoLinkArm::default();
    let dofs: Vec<GapDof> = (0..2)
        .map(|c| GapDof {
            coord: c,
            t0: 0.0,
            t1,
            start: start[c],
            end: end[c],
        })
        .collect();
    let inputs = |_: f64, _: &mut [f64], _: &mut [f64], _: &mut [f64]| Ok(());
    let obj = Objective::new(&arm, dofs, settings, vec![1.0, 1.0], &inputs)?;
    let sol = solve_group(&obj, &SolveOptions::default())?;
    if sol.coefficients.iter().flatten().any(|c| !c.is_finite()) {
        return Ok((f64::INFINITY, sol.report.initial_energy, f64::INFINITY));
    }
    let mut jump = 0.0f64;
    for (i, dof) in obj.dofs().iter().enumerate() {
        for (t, w) in [(dof.t0, dof.start), (dof.t1, dof.end)] {
            let g = obj.curves()[i].eval(&sol.coefficients[i], t);
            jump = jump.max((g[0] - w.q).abs()).max((g[1] - w.v).abs());
        }
    }
    Ok((sol.report.energy, sol.report.initial_energy, jump))
}

/// An [`arm_gap`] result as a case: the worst of the end jump and how far the
/// energy rose above the Hermite start must stay ≤ 1e-9.
fn arm_gap_case(name: &'static str, r: Result<(f64, f64, f64), ReportError>) -> HardCase {
    match r {
        Ok((e, h, j)) => {
            let w = j.max(((e - h) / h.abs().max(1e-300)).max(0.0));
            case(
                name,
                "spacetime",
                format!("energy {e:.4} (Hermite {h:.4}), end jump {j:.1e}"),
                w,
                1e-9,
            )
        }
        Err(e) => case(name, "spacetime", format!("error: {e}"), 1.0, 0.0),
    }
}

pub fn five_second_gap() -> HardCase {
    let name = "5 s gap (two-link arm, C², 10 coefficients)";
    let s = TransitionSettings {
        coefficients: 10,
        samples: 40,
        continuity: Continuity::C2,
    };
    arm_gap_case(
        name,
        arm_gap(
            5.0,
            &s,
            [st(-0.3, 0.5), st(0.2, 0.0)],
            [st(1.1, 0.0), st(0.2, 0.0)],
        ),
    )
}

pub fn identical_end_states() -> HardCase {
    let name = "identical end states (0.8 s gap)";
    let same = [st(0.4, 0.0), st(-0.2, 0.0)];
    arm_gap_case(
        name,
        arm_gap(0.8, &TransitionSettings::default(), same, same),
    )
}

pub fn wrapped_euler_angles() -> HardCase {
    let name = "wrapped Euler angles (170° → −170°)";
    let vals = [150.0, 170.0, -179.0, -170.0, -150.0, 179.5, -179.5];
    let mut text = String::from(
        "HIERARCHY\nROOT Hips\n{\n\tOFFSET 0 0 0\n\tCHANNELS 3 Zrotation Xrotation Yrotation\n\tEnd Site\n\t{\n\t\tOFFSET 0 10 0\n\t}\n}\nMOTION\n",
    );
    text += &format!("Frames: {}\nFrame Time: 0.033333\n", vals.len());
    for v in vals {
        text += &format!("{v} 0 0\n");
    }
    let r = (|| -> Result<(usize, f64), ReportError> {
        let f = crate::mocap::bvh::parse(&text)?;
        let clip = crate::mocap::from_bvh(&f, crate::mocap::bvh::Units::MetresPerUnit(0.01))?;
        let name = f.skeleton.channel_names()[0].clone();
        let dof = clip.mu.dof(&name)?;
        let mut prev: Option<f64> = None;
        let mut worst = 0.0f64;
        for k in 0..vals.len() {
            let y =
                dof.sample(&name, k as f64 * clip.frame_time)?
                    .ok_or(ReportError::Undefined {
                        dof: name.clone(),
                        t: k as f64 * clip.frame_time,
                    })?[0]
                    .to_degrees();
            if let Some(p) = prev {
                worst = worst.max((y - p).abs());
            }
            prev = Some(y);
        }
        Ok((clip.wraps_removed, worst))
    })();
    match r {
        // the largest true step between frames is 30.5° (−150° → 179.5°); a wrap left in shows ~330°
        Ok((n, w)) => case(
            name,
            "mocap",
            format!("{n} wraps removed; largest frame step {w:.1}°"),
            (w - 30.5).abs(),
            1e-9,
        ),
        Err(e) => case(name, "mocap", format!("error: {e}"), 1.0, 0.0),
    }
}

pub fn conflicting_dofs() -> HardCase {
    let r = (|| -> Result<Option<[f64; 3]>, ReportError> {
        let d = Dof::new(vec![Interval::constant(1.0, 0.0, 2.0)?])?
            .plus(&Dof::new(vec![Interval::constant(2.0, 1.0, 3.0)?])?);
        let mut m = Mu::new();
        m.insert("Hips.Xposition", d);
        m.sample("Hips.Xposition", 1.5).map_err(ReportError::from)
    })();
    expect_err(
        "conflicting DOFs (sampled inside the overlap)",
        "motion",
        r,
        &["Hips.Xposition"],
    )
}

pub fn malformed_bvh() -> HardCase {
    let good = "HIERARCHY\nROOT Hips\n{\n\tOFFSET 0 0 0\n\tCHANNELS 3 Xposition Yposition Zposition\n\tEnd Site\n\t{\n\t\tOFFSET 0 1 0\n\t}\n}\nMOTION\nFrames: 1\nFrame Time: 0.04\n1 2 3\n";
    let bad = [
        String::new(),
        good.replace("HIERARCHY", "HIERARCHX"),
        good.replace("CHANNELS 3", "CHANNELS 4"),
        // A short row that is not the last (a cut-short last row is dropped with a warning).
        good.replace("1 2 3\n", "1 2\n1 2 3\n"),
        good.replace("1 2 3", "1 nan 3"),
        good.replace("Frame Time: 0.04", "Frame Time: -1"),
    ];
    let mut rejected = 0;
    let mut msgs = Vec::new();
    for t in &bad {
        if let Err(e) = crate::mocap::bvh::parse(t) {
            rejected += 1;
            if msgs.is_empty() {
                msgs.push(first_line(&e.to_string()));
            }
        }
    }
    let missed = (bad.len() - rejected) as f64;
    case(
        "malformed BVH files (6 kinds)",
        "mocap",
        format!(
            "{rejected}/{} rejected, e.g. “{}”",
            bad.len(),
            msgs.join("")
        ),
        missed,
        0.0,
    )
}

pub fn malformed_urdf() -> HardCase {
    let dir = std::env::temp_dir().join(format!("mx-hard-case-{}", std::process::id()));
    let r = (|| -> Result<(), ReportError> {
        let write = |path: &std::path::Path| {
            let path = path.to_path_buf();
            move |source| ReportError::Write { path, source }
        };
        std::fs::create_dir_all(&dir).map_err(write(&dir))?;
        let p = dir.join("broken.urdf");
        std::fs::write(
            &p,
            "<robot name=\"r\"><link name=\"a\"><inertial><mass value=\"oops\"/></inertial></link>",
        )
        .map_err(write(&p))?;
        Model::from_urdf_file(&p)
            .map(|_| ())
            .map_err(ReportError::from)
    })();
    let _ = std::fs::remove_dir_all(&dir);
    expect_err("malformed URDF", "model", r, &[])
}
