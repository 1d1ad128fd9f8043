//! The spline-joint mechanisms of `examples/mech_*.mx` run and behave
//! physically, and bodies written in mx (`body`/`link`) are checked and
//! equal to the same body loaded from URDF.

use mx::Interpreter;
use mx::lang::value::Value;

/// Runs an example (from the repository root, as `mx run` would) and returns
/// the interpreter holding its variables.
fn run(example: &str) -> Interpreter {
    let root = env!("CARGO_MANIFEST_DIR");
    std::env::set_current_dir(root).unwrap();
    let mut mx = Interpreter::new();
    let out = mx.capture_output();
    if let Err(e) = mx.eval_file(format!("examples/{example}")) {
        panic!("{example} failed: {e:?}");
    }
    let printed = String::from_utf8(out.lock().unwrap().clone()).unwrap();
    assert!(!printed.trim().is_empty(), "{example} printed nothing");
    eprintln!("{example}: {printed}");
    mx
}

fn num(mx: &Interpreter, name: &str) -> f64 {
    match mx.get(name) {
        Some(Value::Number(x)) => x,
        other => panic!("`{name}` is not a number: {other:?}"),
    }
}

fn nums(mx: &Interpreter, name: &str) -> Vec<f64> {
    match mx.get(name) {
        Some(Value::List(l)) => l.iter().map(|v| v.as_number().unwrap()).collect(),
        other => panic!("`{name}` is not a list: {other:?}"),
    }
}

fn csv_is_finite(path: &str) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut rows = 0;
    for line in text.lines().skip(1) {
        for x in line.split(',') {
            let x: f64 = x.trim().parse().unwrap();
            assert!(x.is_finite(), "{path}: {line}");
        }
        rows += 1;
    }
    assert!(rows > 10, "{path} has {rows} rows");
}

#[test]
fn elliptic_joint_conserves_energy_and_swings_symmetrically() {
    let mx = run("mech_elliptic.mx");
    assert!(num(&mx, "drift") < 1e-6, "drift {}", num(&mx, "drift"));
    let qs = nums(&mx, "qs");
    let (lo, hi) = qs
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
    // The ellipse is symmetric about its minor axis: the swing reaches −70° and +70°.
    assert!(
        (hi - 70f64.to_radians()).abs() < 1e-3 && (lo + hi).abs() < 2e-3,
        "{lo} {hi}"
    );
    csv_is_finite("examples/out/mech_elliptic.csv");
}

#[test]
fn knee_pendulum_conserves_energy_and_slides() {
    let mx = run("mech_knee_pendulum.mx");
    assert!(num(&mx, "drift") < 1e-6, "drift {}", num(&mx, "drift"));
    let qs = nums(&mx, "qs");
    let hi = qs.iter().cloned().fold(f64::MIN, f64::max);
    assert!(hi > 0.0, "the shank never swung through straight: max {hi}");
    // gait2392: the tibia origin is 395.8 mm below the femur straight and 410 mm or so at 60°.
    let slide = num(&mx, "slide");
    assert!(slide < -0.005 && slide > -0.03, "slide {slide}");
    csv_is_finite("examples/out/mech_knee_pendulum.csv");
}

#[test]
fn beads_stay_on_their_wires_with_100ms_explicit_euler() {
    let mx = run("mech_beads.mx");
    let speed = num(&mx, "max_speed");
    assert!(
        speed.is_finite() && speed < 10.0,
        "beads sped up to {speed} rad/s"
    );
    let reach = num(&mx, "max_reach");
    assert!(reach > 0.3 && reach <= 0.8, "farthest bead {reach} m");
    assert!(num(&mx, "wire_error") < 1e-9);
    csv_is_finite("examples/out/mech_beads.csv");
}

#[test]
fn airplanes_coast_on_the_globe() {
    let mx = run("mech_globe.mx");
    assert!(num(&mx, "drift") < 1e-4, "drift {}", num(&mx, "drift"));
    let rs = nums(&mx, "rs");
    assert!(rs.iter().all(|r| *r > 0.95 && *r < 1.001), "{rs:?}");
    csv_is_finite("examples/out/mech_globe.csv");
}

#[test]
fn letter_chain_falls_conserving_energy() {
    let mx = run("mech_letters.mx");
    assert!(num(&mx, "drift") < 1e-5, "drift {}", num(&mx, "drift"));
    assert!(num(&mx, "lowest").is_finite());
    csv_is_finite("examples/out/mech_letters.csv");
}

#[test]
fn springs_settle_the_scapula_on_its_surface() {
    let mx = run("mech_scapula.mx");
    let speed = num(&mx, "speed");
    assert!(speed < 1e-2, "still moving at {speed} rad/s after 4 s");
    let out = mx.get("end").unwrap();
    let r = out.as_record().unwrap();
    let (u, v) = (
        r["scapula.u"].as_number().unwrap(),
        r["scapula.v"].as_number().unwrap(),
    );
    assert!(
        (0.15..=1.45).contains(&u) && (-0.55..=0.75).contains(&v),
        "({u}, {v})"
    );
    csv_is_finite("examples/out/mech_scapula.csv");
}

#[test]
fn deforming_surface_runs_on_its_clock() {
    let mx = run("mech_deforming.mx");
    assert!(num(&mx, "clock_error") < 1e-9);
    for k in ["us", "vs"] {
        assert!(
            nums(&mx, k).iter().all(|x| x.abs() < 1.05),
            "{k} left the patch"
        );
    }
    // A still surface driven by its clock does no work.
    assert!(num(&mx, "drift") < 1e-5, "drift {}", num(&mx, "drift"));
    csv_is_finite("examples/out/mech_deforming.csv");
}

#[test]
fn spline_surface_at_its_range_end_is_held_by_limits() {
    // A 1-D spline surface (a straight rail) with the ball thrown off its end:
    // without limits it leaves the range; with them it comes back inside.
    let mut mx = Interpreter::new();
    mx.eval_str(
        r#"
        let rail = spline_surface(map(linspace(0, 1, 5), fn(x) = frame([x, 0, 0])), u: [0, 1])
        let b = body([link("ball", joint: rail, mass: 1)])
        fn run(sc) {
            let m = simulate(sc, 2, dt: 1ms, init: {q: {"ball.u": 0.9}, v: {"ball.u": 1}})
            map(linspace(0, 2, 401), fn(t) = sample(m, t)["ball.u"])
        }
        let free = run(scene(b))
        let held = run(scene(b, limits: {stiffness: 1e4, damping: 200}))
        "#,
    )
    .unwrap();
    let free = nums(&mx, "free");
    assert!(
        free.iter().cloned().fold(f64::MIN, f64::max) > 1.5,
        "{free:?}"
    );
    let held = nums(&mx, "held");
    assert!(
        held.iter().all(|u| (-0.05..=1.05).contains(u)),
        "left the range: {held:?}"
    );
}

#[test]
fn body_from_links_equals_the_urdf_body() {
    let root = env!("CARGO_MANIFEST_DIR");
    let mut mx = Interpreter::new();
    mx.eval_str(&format!(
        r#"
        let urdf = load("{root}/examples/data/double_pendulum.urdf")
        let mine = body([
            link("lower", parent: "upper", joint: revolute([0, 1, 0]), joint_name: "elbow",
                 offset: [0, 0, -1], mass: 1, com: [0, 0, -0.4], inertia: [0.054, 0.054, 0.001]),
            link("upper", joint: revolute([0, 1, 0]), joint_name: "shoulder",
                 mass: 2, com: [0, 0, -0.5], inertia: [[0.17, 0, 0], [0, 0.17, 0], [0, 0, 0.002]]),
        ])
        let a = inverse_dynamics(urdf, [0.6, -0.4], [0.3, 1.1], [-2, 0.5])
        let b = inverse_dynamics(mine, [0.6, -0.4], [0.3, 1.1], [-2, 0.5])
        let names = coordinates(mine)
        "#
    ))
    .unwrap();
    let (a, b) = (nums(&mx, "a"), nums(&mx, "b"));
    for (x, y) in a.iter().zip(&b) {
        assert!((x - y).abs() < 1e-12, "{a:?} vs {b:?}");
    }
    let names = mx.get("names").unwrap();
    assert_eq!(names.repr(), r#"["shoulder", "elbow"]"#);
}

#[test]
fn bad_bodies_are_clear_errors() {
    let cases = [
        (
            r#"body([link("a", parent: "b", joint: revolute([0, 0, 1]), mass: 1)])"#,
            "names parent link `b`, which is not defined",
        ),
        (
            r#"body([link("a", parent: "b", joint: revolute([0, 0, 1]), mass: 1),
                     link("b", parent: "a", joint: revolute([0, 0, 1]), mass: 1)])"#,
            "cycle",
        ),
        (
            r#"body([link("a", joint: revolute([0, 0, 1]), mass: 1),
                     link("a", joint: revolute([0, 0, 1]), mass: 1)])"#,
            "unique",
        ),
        (
            r#"link("a", joint: revolute([0, 0, 1]), mass: 0)"#,
            "> 0 kg",
        ),
        (
            r#"link("a", joint: revolute([0, 0, 1]), mass: -2)"#,
            "> 0 kg",
        ),
        (
            r#"link("a", joint: revolute([0, 0, 1]), mass: 1, inertia: [1, 1, -1])"#,
            "positive definite",
        ),
        (
            r#"link("a", joint: revolute([0, 0, 1]), mass: 1, inertia: [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]])"#,
            "symmetric",
        ),
        (
            r#"link("a", joint: revolute([0, 0, 1]), mass: 1, inertia: [1, 1, 3])"#,
            "no rigid body",
        ),
        (r#"body([])"#, "at least one link"),
        (r#"body([1])"#, "not a link"),
        (
            r#"spline_surface([[frame([0, 0, 0]), frame([1, 0, 0])], [frame([0, 1, 0])]])"#,
            "regular grid",
        ),
        (
            r#"scene(body([link("a", joint: revolute([0, 0, 1]), mass: 1)]), driven: {b: 1})"#,
            "no coordinate `b`",
        ),
    ];
    for (src, want) in cases {
        let mut mx = Interpreter::new();
        let e = mx.eval_str(src).expect_err(src);
        let text = format!("{e:?}");
        assert!(text.contains(want), "{src}\n→ {text}");
    }
}
