//! Inverse kinematics (issue 17 item 3): reachable targets met, unreachable
//! ones reported, the analytic Jacobian against central differences (spline
//! curve and function-based joints included), the knee example's tibia on
//! its curve, and bad input as the language reports it.

use std::path::Path;
use std::sync::Arc;

use mx::Interpreter;
use mx::ik::{Goal, IkOptions, Settings, Solver, Target, ik};
use mx::lie::Se3;
use mx::mocap::bvh::Units;
use mx::model::joints::spherical::Spherical;
use mx::model::joints::{FunctionJoint, Revolute, SplineCurveJoint};
use mx::model::{Derivatives, Inertia, Joint, JointKinematics, Model};
use mx::motion::{Curve, Dof, Interval, Mu};
use nalgebra::{Rotation3, Vector3};

fn repo(p: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

/// The repository's walk and the body built from it.
fn walk() -> (Mu, Model) {
    let clip = mx::mocap::to_motion::load(&repo("examples/data/walk.bvh"), Units::Auto).unwrap();
    let (body, _) = mx::mocap::body_of(&clip.skeleton, 70.0, clip.units.metres_per_unit).unwrap();
    (clip.mu, body)
}

/// A link's world position over `m` at times `ts`, as a target.
fn target_of(body: &Model, m: &Mu, link: &str, ts: &[f64], shift: Vector3<f64>) -> Target {
    let p = mx::mocap::positions_at(m, body, ts.to_vec(), mx::mocap::Missing::Error).unwrap();
    let j = p.names.iter().position(|n| n == link).unwrap();
    let dt = ts[1] - ts[0];
    let axis = |k: usize| {
        let v: Vec<f64> = p.points.iter().map(|f| f[j][k] + shift[k]).collect();
        Dof::from(
            Interval::curve(
                Curve::samples(ts[0], dt, v).unwrap(),
                ts[0],
                *ts.last().unwrap(),
            )
            .unwrap(),
        )
    };
    Target {
        link: link.into(),
        position: [axis(0), axis(1), axis(2)],
        orientation: None,
        weight: 1.0,
    }
}

fn grid(t0: f64, t1: f64, n: usize) -> Vec<f64> {
    (0..=n)
        .map(|k| t0 + (t1 - t0) * k as f64 / n as f64)
        .collect()
}

/// Where a link is at t in a motion.
fn link_at(body: &Model, m: &Mu, link: &str, t: f64) -> Vector3<f64> {
    let p = mx::mocap::positions_at(m, body, vec![t], mx::mocap::Missing::Error).unwrap();
    p.points[0][p.names.iter().position(|n| n == link).unwrap()]
}

#[test]
fn reachable_foot_targets_are_met_within_a_micrometre_in_at_most_20_iterations() {
    let (m, body) = walk();
    // Both feet where the walk puts them 0.3 s later: reachable (the same
    // body reaches them), and far from the frame's own pose (≈ 30 cm).
    let later = mx::motion::affine(-0.3, 1.0, &m).unwrap();
    let ts = grid(0.0, 1.6, 48);
    let targets = vec![
        target_of(&body, &later, "LeftFoot", &ts, Vector3::zeros()),
        target_of(&body, &later, "RightFoot", &ts, Vector3::zeros()),
    ];
    let opts = IkOptions {
        rate: Some(30.0),
        ..Default::default()
    };
    let (out, report) = ik(&body, &m, &targets, &opts).unwrap();
    assert_eq!(report.frames, 49);
    assert_eq!(report.unconverged_frames, 0, "{report:?}");
    assert!(
        report.max_iterations <= 20,
        "{} iterations",
        report.max_iterations
    );
    for t in &report.targets {
        assert!(t.max_residual <= 1e-6, "{}: {:e} m", t.link, t.max_residual);
    }
    // the report is the truth: forward kinematics of the result meets the targets
    for &t in &ts[..10] {
        for tg in &targets {
            let want =
                Vector3::from_fn(|k, _| tg.position[k].sample_value("x", t).unwrap().unwrap());
            let got = link_at(&body, &out, &tg.link, t);
            assert!(
                (got - want).norm() <= 1.1e-6,
                "{} at {t}: {:e}",
                tg.link,
                (got - want).norm()
            );
        }
    }
    println!(
        "reachable: {} frames, iterations mean {:.2} max {}",
        report.frames, report.mean_iterations, report.max_iterations
    );
}

/// A link's world pose over `m` at times `ts`, as a target with an
/// orientation (the frame's rotation vector, DOFs rx, ry, rz).
fn pose_target_of(body: &Model, m: &Mu, link: &str, ts: &[f64]) -> Target {
    let names = body.coordinate_names();
    let l = body.link_index(link).unwrap();
    let (mut cols, mut poses) = (vec![vec![]; 6], vec![]);
    for &t in ts {
        let q: Vec<f64> = names
            .iter()
            .map(|n| m.get(n).unwrap().sample_value(n, t).unwrap().unwrap())
            .collect();
        body.forward_kinematics(&q, &mut poses).unwrap();
        let w = mx::lie::log_so3(&poses[l].r);
        for k in 0..3 {
            cols[k].push(poses[l].p[k]);
            cols[3 + k].push(w[k]);
        }
    }
    let dt = ts[1] - ts[0];
    let dof = |v: Vec<f64>| {
        Dof::from(
            Interval::curve(
                Curve::samples(ts[0], dt, v).unwrap(),
                ts[0],
                *ts.last().unwrap(),
            )
            .unwrap(),
        )
    };
    let mut c = cols.into_iter().map(dof);
    let mut three = || [c.next().unwrap(), c.next().unwrap(), c.next().unwrap()];
    let position = three();
    Target {
        link: link.into(),
        position,
        orientation: Some(three()),
        weight: 1.0,
    }
}

/// Orientation targets over time: both feet's whole pose 0.3 s later (the
/// same body reaches it), met to a micrometre and a microradian.
#[test]
fn reachable_pose_targets_with_orientation_are_met() {
    let (m, body) = walk();
    let later = mx::motion::affine(-0.3, 1.0, &m).unwrap();
    let ts = grid(0.0, 1.6, 48);
    let targets = vec![
        pose_target_of(&body, &later, "LeftFoot", &ts),
        pose_target_of(&body, &later, "RightFoot", &ts),
    ];
    let opts = IkOptions {
        rate: Some(30.0),
        ..Default::default()
    };
    let (out, report) = ik(&body, &m, &targets, &opts).unwrap();
    assert_eq!(report.unconverged_frames, 0, "{report:?}");
    assert!(
        report.max_iterations <= 20,
        "{} iterations",
        report.max_iterations
    );
    for t in &report.targets {
        assert!(t.max_residual <= 1e-6, "{}: {:e} m", t.link, t.max_residual);
        assert!(
            t.max_orientation_residual <= 1e-6 && t.max_orientation_residual >= 0.0,
            "{}: {:e} rad",
            t.link,
            t.max_orientation_residual
        );
    }
    // the result's own frames have the target orientation
    let (names, l) = (
        body.coordinate_names(),
        body.link_index("LeftFoot").unwrap(),
    );
    let mut poses = vec![];
    for &t in &ts[..10] {
        let q: Vec<f64> = names
            .iter()
            .map(|n| out.get(n).unwrap().sample_value(n, t).unwrap().unwrap())
            .collect();
        body.forward_kinematics(&q, &mut poses).unwrap();
        let want = Vector3::from_fn(|k, _| {
            targets[0].orientation.as_ref().unwrap()[k]
                .sample_value("r", t)
                .unwrap()
                .unwrap()
        });
        let e = mx::lie::log_so3(&(mx::lie::exp_so3(&want).transpose() * poses[l].r)).norm();
        assert!(e <= 1.1e-6, "LeftFoot at {t}: {e:e} rad");
    }
    println!(
        "pose targets: {} frames, iterations mean {:.2} max {}",
        report.frames, report.mean_iterations, report.max_iterations
    );
}

#[test]
fn an_unreachable_target_gets_as_close_as_it_can_and_reports_by_how_much() {
    let (m, body) = walk();
    let ts = grid(0.0, 1.0, 30);
    // the left foot asked to be 3 m above where it is: the leg cannot follow
    // when only the left leg may move
    let targets = vec![target_of(
        &body,
        &m,
        "LeftFoot",
        &ts,
        Vector3::new(0.0, 3.0, 0.0),
    )];
    let opts = IkOptions {
        only: Some(vec!["LeftUpLeg.*".into(), "LeftLeg.*".into()]),
        ..Default::default()
    };
    let (out, report) = ik(&body, &m, &targets, &opts).unwrap();
    let r = &report.targets[0];
    assert_eq!(r.unreachable_frames, report.frames);
    assert_eq!(report.unconverged_frames, report.frames);
    // the nearest point: the leg straight up toward the target, so the
    // residual is the distance from the hip less the leg's length
    let hip = link_at(&body, &m, "LeftUpLeg", 0.5);
    let foot = link_at(&body, &out, "LeftFoot", 0.5);
    let goal = Vector3::from_fn(|k, _| {
        targets[0].position[k]
            .sample_value("x", 0.5)
            .unwrap()
            .unwrap()
    });
    let leg = (link_at(&body, &m, "LeftLeg", 0.5) - hip).norm()
        + (link_at(&body, &m, "LeftFoot", 0.5) - link_at(&body, &m, "LeftLeg", 0.5)).norm();
    let want = (goal - hip).norm() - leg;
    let got = (foot - goal).norm();
    assert!(
        (got - want).abs() < 1e-3 * want,
        "residual {got} m, nearest possible {want} m"
    );
    assert!(r.max_residual >= got - 1e-9 && r.max_residual < 3.0);
    assert!(r.mean_residual > 1.0 && r.mean_residual <= r.max_residual);
    println!("unreachable: residual {got:.4} m at t = 0.5 (geometric bound {want:.4} m)");
}

/// A chain of every kind of joint: spherical hip, a spline curve joint, the
/// repository's OpenSim knee (function-based: rotation and two SimmSpline
/// translations of the knee angle), a revolute ankle.
fn chain() -> Model {
    let mut m = Model::new("chain");
    let link = Inertia::point(1.0, Vector3::new(0.0, -0.1, 0.0)).unwrap();
    let hip = m
        .add_link(
            "thigh",
            None,
            "hip",
            Arc::new(Spherical::default()),
            Se3::identity(),
            link,
        )
        .unwrap();
    let frames: Vec<Se3> = (0..6)
        .map(|k| {
            let a = k as f64 * 0.25;
            Se3::new(
                Rotation3::from_euler_angles(0.3 * a, -0.2 * a, 0.5 * a).into_inner(),
                Vector3::new(0.05 * a, -0.1 - 0.06 * a, 0.02 * a * a),
            )
        })
        .collect();
    let knots = mx::model::joints::curve::natural_parameters(&frames, 0.0);
    let curve = SplineCurveJoint::from_knots(frames, &knots).unwrap();
    let c = m
        .add_link(
            "spline",
            Some(hip),
            "curve",
            Arc::new(curve),
            Se3::from_translation(Vector3::new(0.0, -0.3, 0.0)),
            link,
        )
        .unwrap();
    let knee = FunctionJoint::from_osim_file(repo("examples/data/knee_r.osim"), "knee_r").unwrap();
    let k = m
        .add_link(
            "tibia",
            Some(c),
            "knee",
            Arc::new(knee),
            Se3::from_translation(Vector3::new(0.0, -0.1, 0.0)),
            link,
        )
        .unwrap();
    m.add_link(
        "foot",
        Some(k),
        "ankle",
        Arc::new(Revolute::new(Vector3::new(0.0, 0.0, 1.0)).unwrap()),
        Se3::from_translation(Vector3::new(0.0, -0.4, 0.0)),
        link,
    )
    .unwrap();
    m
}

#[test]
fn analytic_jacobian_matches_central_differences_with_spline_and_function_joints() {
    let model = chain();
    let links = [
        model.link_index("spline").unwrap(),
        model.link_index("tibia").unwrap(),
        model.link_index("foot").unwrap(),
    ];
    let mut solver = Solver::new(&model, &links, &vec![true; model.nq()]).unwrap();
    assert_eq!(solver.free().len(), model.nq());
    let r0 = Rotation3::from_euler_angles(0.1, 0.2, -0.3).into_inner();
    let goals: Vec<Goal> = links
        .iter()
        .enumerate()
        .map(|(i, &l)| Goal {
            link: l,
            position: Vector3::new(0.1 * i as f64, -0.5, 0.2),
            // orientation goals on two links: the log-map rows too
            orientation: (i != 1).then_some(r0),
            weight: 1.0 + i as f64,
        })
        .collect();
    let s = Settings::default();
    let mut worst: f64 = 0.0;
    for q in [
        vec![0.2, -0.3, 0.4, 0.6, -0.8, 0.3],
        vec![-0.5, 0.1, 0.9, 0.2, -1.5, -0.4],
        vec![0.0, 0.0, 0.0, 1.1, -0.2, 1.0],
    ] {
        let (_, jac) = solver.jacobian(&q, &goals, &s).unwrap();
        let h = 1e-6;
        for c in 0..q.len() {
            let (mut qp, mut qm) = (q.clone(), q.clone());
            qp[c] += h;
            qm[c] -= h;
            let (rp, _) = solver.jacobian(&qp, &goals, &s).unwrap();
            let (rm, _) = solver.jacobian(&qm, &goals, &s).unwrap();
            let fd = (rp - rm) / (2.0 * h);
            worst = worst.max((fd - jac.column(c)).amax());
        }
    }
    println!("largest Jacobian difference {worst:e}");
    assert!(worst < 1e-7, "analytic vs central differences: {worst:e}");
}

#[test]
fn one_frame_reaches_a_reachable_pose_with_orientation_through_every_joint_kind() {
    let model = chain();
    let foot = model.link_index("foot").unwrap();
    let q_true = [0.3, -0.2, 0.25, 0.7, -1.0, 0.4];
    let mut poses = vec![];
    model.forward_kinematics(&q_true, &mut poses).unwrap();
    let goal = Goal {
        link: foot,
        position: poses[foot].p,
        orientation: Some(poses[foot].r),
        weight: 1.0,
    };
    let mut solver = Solver::new(&model, &[foot], &vec![true; model.nq()]).unwrap();
    let mut q = vec![0.2, -0.1, 0.2, 0.6, -0.9, 0.3];
    let r = solver.solve(&mut q, &[goal], &Settings::default()).unwrap();
    assert!(r.converged, "{r:?}");
    assert!(r.iterations <= 20, "{r:?}");
    assert!(r.position_error[0] <= 1e-6 && r.orientation_error[0] <= 1e-6);
}

/// The knee example: a femur swung at the hip, the tibia carried by the
/// OpenSim knee (the tibia slides along the femur as the knee bends), the
/// foot driven toward targets over time.
#[test]
fn the_knee_example_keeps_the_spline_knee_on_its_curve() {
    let mut i = Interpreter::new();
    i.eval_file(repo("examples/ik_knee.mx"))
        .unwrap_or_else(|d| panic!("{}", d.render_plain()));
    let res = i
        .eval_str("[ik_report(solved).max, ik_report(solved).frames, knee_range[0], knee_range[1]]")
        .unwrap();
    let v: Vec<f64> = res
        .as_list()
        .unwrap()
        .iter()
        .map(|x| x.as_number().unwrap())
        .collect();
    assert!(v[0] <= 1e-6, "foot residual {} m", v[0]);
    // every frame's tibia pose in the femur frame is the knee's own G(θ):
    // rebuild it from the knee angle and compare with forward kinematics of
    // the result (positions of tibia relative to femur)
    let knee = FunctionJoint::from_osim_file(repo("examples/data/knee_r.osim"), "knee_r").unwrap();
    let lim = knee.limits()[0];
    let n = v[1] as usize;
    let mut jk = JointKinematics::default();
    let mut off_curve: f64 = 0.0;
    for k in 0..n {
        let q = i
            .eval_str(&format!("let t = span(solved)[0] + {k} / 30; [sample(solved, t).hip, sample(solved, t).knee_angle_r, point(leg, \"tibia\", [sample(solved, t).hip, sample(solved, t).knee_angle_r])]"))
            .unwrap();
        let l = q.as_list().unwrap();
        let (hip, theta) = (l[0].as_number().unwrap(), l[1].as_number().unwrap());
        assert!(
            theta >= lim.lower - 1e-12 && theta <= lim.upper + 1e-12,
            "knee angle {theta} outside its range"
        );
        let p: Vec<f64> = l[2]
            .as_list()
            .unwrap()
            .iter()
            .map(|x| x.as_number().unwrap())
            .collect();
        knee.kinematics(&[theta], Derivatives::Transform, &mut jk);
        // femur: rotation `hip` about z at the origin; the knee 0.4 m below
        let femur =
            Se3::from_rotation(Rotation3::from_axis_angle(&Vector3::z_axis(), hip).into_inner());
        let knee_frame = femur.compose(&Se3::from_translation(Vector3::new(0.0, -0.4, 0.0)));
        let want = knee_frame.compose(&jk.transform).p;
        off_curve = off_curve.max((Vector3::new(p[0], p[1], p[2]) - want).norm());
    }
    assert!(
        off_curve < 1e-12,
        "tibia off the knee's curve by {off_curve:e} m"
    );
}

fn error_of(src: &str) -> String {
    let mut i = Interpreter::new();
    std::env::set_current_dir(env!("CARGO_MANIFEST_DIR")).unwrap();
    match i.eval_str(src) {
        Ok(v) => panic!("expected an error from {src}, got {v:?}"),
        Err(d) => d.render_plain(),
    }
}

#[test]
fn bad_input_gets_clear_errors() {
    let pre = "let walk = load(\"examples/data/walk.bvh\")\nlet body = body_of(walk)\nlet p = positions(walk, body)\n";
    let e = error_of(&format!(
        "{pre}ik(body, walk, {{LeftHoof: p.only(\"LeftFoot.x\", \"LeftFoot.y\", \"LeftFoot.z\")}})"
    ));
    assert!(
        e.contains("no link named 'LeftHoof'") && e.contains("LeftFoot"),
        "{e}"
    );
    let e = error_of(&format!(
        "{pre}ik(body, walk, {{LeftFoot: mu({{x: interval(0, 0, 1), y: interval(0, 0, 1)}})}})"
    ));
    assert!(e.contains("no DOF `z`"), "{e}");
    let e = error_of(&format!(
        "{pre}ik(body, walk, {{LeftFoot: mu({{x: interval(0, 0, 1), y: interval(fn(t) = if t > 0.5 {{ 1e308 * 10 }} else {{ 0 }}, 0, 1), z: interval(0, 0, 1)}})}})"
    ));
    // the motion layer already refuses a non-finite value, naming the DOF and time
    assert!(e.contains("LeftFoot.y") && e.contains("inf"), "{e}");
    let e = error_of(&format!(
        "{pre}ik(body, walk, p.only(\"LeftFoot.*\"), only: \"Nope*\")"
    ));
    assert!(e.contains("Nope"), "{e}");
    let e = error_of(&format!(
        "{pre}ik(body, walk, p.only(\"LeftFoot.*\"), weights: {{LeftFoot: -1}})"
    ));
    assert!(e.contains("weight"), "{e}");
    let e = error_of(&format!("{pre}ik_report(walk)"));
    assert!(e.contains("not returned by ik"), "{e}");
    let e = error_of(&format!(
        "{pre}ik(body, walk, {{LeftFoot: mu({{x: interval(0, 5, 6), y: interval(0, 5, 6), z: interval(0, 5, 6)}})}})"
    ));
    assert!(e.contains("never defined at the same time"), "{e}");
    let e = error_of(&format!(
        "{pre}ik(body, walk, {{LeftFoot: mu({{x: interval(0, 0, 1), y: interval(0, 0, 1), z: interval(0, 0, 1), rx: interval(0, 0, 1)}})}})"
    ));
    assert!(e.contains("part of an orientation"), "{e}");
}

/// Joint limits are bounds: a foot target that needs the knee past its
/// range (OpenSim's knee_r: −120° … 10°) leaves the knee at the limit, and
/// the residual says how far the foot stayed.
#[test]
fn joint_limits_are_respected_and_the_shortfall_reported() {
    let mut m = Model::new("leg");
    let mass = Inertia::point(1.0, Vector3::new(0.0, -0.2, 0.0)).unwrap();
    let hip = m
        .add_link(
            "femur",
            None,
            "hip",
            Arc::new(Revolute::new(Vector3::new(0.0, 0.0, 1.0)).unwrap()),
            Se3::identity(),
            mass,
        )
        .unwrap();
    let knee = FunctionJoint::from_osim_file(repo("examples/data/knee_r.osim"), "knee_r").unwrap();
    let lim = knee.limits()[0];
    let tibia = m
        .add_link(
            "tibia",
            Some(hip),
            "knee",
            Arc::new(knee),
            Se3::from_translation(Vector3::new(0.0, -0.4, 0.0)),
            mass,
        )
        .unwrap();
    let foot = m
        .add_link(
            "foot",
            Some(tibia),
            "ankle",
            Arc::new(mx::model::joints::Fixed::new(Se3::identity())),
            Se3::from_translation(Vector3::new(0.0, -0.43, 0.0)),
            mass,
        )
        .unwrap();
    // the foot pulled up against the thigh: the knee would have to fold past −120°
    let goal = Goal {
        link: foot,
        position: Vector3::new(0.0, -0.3, 0.0),
        orientation: None,
        weight: 1.0,
    };
    let mut solver = Solver::new(&m, &[foot], &[true, true]).unwrap();
    let mut q = vec![0.0, -0.5];
    let r = solver
        .solve(&mut q, std::slice::from_ref(&goal), &Settings::default())
        .unwrap();
    assert!(!r.converged);
    assert!(
        q[1] >= lim.lower && q[1] <= lim.upper,
        "knee {} outside [{}, {}]",
        q[1],
        lim.lower,
        lim.upper
    );
    assert!(
        (q[1] - lim.lower).abs() < 1e-9,
        "the knee should rest on its limit, at {}",
        q[1]
    );
    // the reported residual is the true distance, and no admissible knee angle does better
    let mut poses = vec![];
    m.forward_kinematics(&q, &mut poses).unwrap();
    assert!(((poses[foot].p - goal.position).norm() - r.position_error[0]).abs() < 1e-12);
    let best = (0..=2000)
        .flat_map(|i| (0..=200).map(move |k| (i, k)))
        .map(|(i, k)| {
            let h = -std::f64::consts::PI + 2.0 * std::f64::consts::PI * i as f64 / 2000.0;
            let kn = lim.lower + (lim.upper - lim.lower) * k as f64 / 200.0;
            let mut p = vec![];
            m.forward_kinematics(&[h, kn], &mut p).unwrap();
            (p[foot].p - goal.position).norm()
        })
        .fold(f64::INFINITY, f64::min);
    assert!(
        r.position_error[0] <= best + 1e-6,
        "residual {} m, a grid search finds {best} m",
        r.position_error[0]
    );
    println!(
        "limit: knee at {:.4} rad (limit {:.4}), residual {:.4} m, grid best {best:.4} m",
        q[1], lim.lower, r.position_error[0]
    );
}
