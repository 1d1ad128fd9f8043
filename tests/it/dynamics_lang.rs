//! The dynamics built-ins as written in mx, against the Pinocchio references.

use crate::common;

use mx::{Interpreter, Value};
use serde_json::Value as J;

fn list(v: &Value) -> Vec<f64> {
    match v {
        Value::List(l) => l.iter().map(|x| x.as_number().expect("number")).collect(),
        other => panic!("expected a list, got {other:?}"),
    }
}

fn fmt(v: &J) -> String {
    let xs: Vec<String> = v
        .as_array()
        .unwrap()
        .iter()
        .map(|x| format!("{:?}", x.as_f64().unwrap()))
        .collect();
    format!("[{}]", xs.join(", "))
}

#[test]
fn inverse_forward_mass_matrix_and_coordinates_match_pinocchio() {
    for path in common::shared_files("reference", ".json") {
        let json: J = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        let urdf = path.with_file_name(json["urdf_file"].as_str().unwrap());
        let s = &json["samples"][0];
        let mut mx = Interpreter::new();
        mx.eval_str(&format!(
            "let body = load({:?})",
            urdf.display().to_string()
        ))
        .unwrap();
        let names = mx.eval_str("coordinates(body)").unwrap();
        let Value::List(names) = names else { panic!() };
        let expect: Vec<&str> = json["joints"]
            .as_array()
            .unwrap()
            .iter()
            .map(|j| j["name"].as_str().unwrap())
            .collect();
        let got: Vec<&str> = names.iter().map(|v| v.as_str().unwrap()).collect();
        assert_eq!(got, expect);
        let (q, v, a) = (fmt(&s["q"]), fmt(&s["v"]), fmt(&s["a"]));
        let tau = list(
            &mx.eval_str(&format!("inverse_dynamics(body, {q}, {v}, {a})"))
                .unwrap(),
        );
        let tref: Vec<f64> = s["tau"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        let scale = tref.iter().fold(1.0f64, |m, x| m.max(x.abs()));
        let e = tau
            .iter()
            .zip(&tref)
            .map(|(x, r)| (x - r).abs())
            .fold(0.0, f64::max)
            / scale;
        assert!(e < 1e-10, "{}: tau err {e:e}", path.display());
        let qdd = list(
            &mx.eval_str(&format!(
                "forward_dynamics(body, {q}, {v}, {})",
                fmt(&s["tau"])
            ))
            .unwrap(),
        );
        let aref: Vec<f64> = s["ddq_aba"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        let scale = aref.iter().fold(1.0f64, |m, x| m.max(x.abs()));
        let e = qdd
            .iter()
            .zip(&aref)
            .map(|(x, r)| (x - r).abs())
            .fold(0.0, f64::max)
            / scale;
        assert!(e < 1e-8, "{}: ddq err {e:e}", path.display());
        let m = mx.eval_str(&format!("mass_matrix(body, {q})")).unwrap();
        let Value::List(rows) = m else { panic!() };
        let m00 = list(&rows[0])[0];
        let r00 = s["M"][0][0].as_f64().unwrap();
        assert!((m00 - r00).abs() < 1e-10 * r00.abs().max(1.0));
        // A scene prints what it declares.
        let sc = mx
            .eval_str("scene(body, gravity: [0, 0, -9.81], damping: 0.1)")
            .unwrap();
        assert!(format!("{sc:?}").contains("Scene") || matches!(sc, Value::Object(_)));
    }
}

#[test]
fn bad_calls_are_clear_errors() {
    let Some(dir) = common::shared_dir() else {
        return;
    };
    let urdf = dir.join("data/reference/ur5_robot.urdf");
    let mut mx = Interpreter::new();
    mx.eval_str(&format!(
        "let body = load({:?})",
        urdf.display().to_string()
    ))
    .unwrap();
    let e = mx
        .eval_str("inverse_dynamics(body, [0, 0], [0, 0, 0, 0, 0, 0], [0, 0, 0, 0, 0, 0])")
        .unwrap_err();
    let msg = e.render_plain();
    assert!(msg.contains("6 coordinates"), "{msg}");
    let e = mx
        .eval_str("inverse_dynamics(3, [0], [0], [0])")
        .unwrap_err();
    assert!(e.render_plain().contains("body"), "{}", e.render_plain());
    let e = mx
        .eval_str("scene(body, springs: [{a: \"nope\", b: \"world\", k: 1}])")
        .unwrap_err();
    assert!(
        e.render_plain().contains("no link named `nope`"),
        "{}",
        e.render_plain()
    );
}

const PENDULUM: &str = r#"<robot name="pendulum">
  <link name="base"/>
  <link name="rod"><inertial><origin xyz="0 0 -0.5"/><mass value="2"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.001"/></inertial></link>
  <link name="rod2"><inertial><origin xyz="0 0 -0.4"/><mass value="1"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.001"/></inertial></link>
  <joint name="hinge" type="continuous"><parent link="base"/><child link="rod"/><axis xyz="0 1 0"/></joint>
  <joint name="elbow" type="revolute"><parent link="rod"/><child link="rod2"/><origin xyz="0 0 -1"/>
    <axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="10" velocity="10"/></joint>
</robot>"#;

#[test]
fn simulate_returns_a_motion_that_conserves_energy() {
    let dir = tempfile::tempdir().unwrap();
    let urdf = dir.path().join("pendulum.urdf");
    std::fs::write(&urdf, PENDULUM).unwrap();
    let mut mx = Interpreter::new();
    mx.eval_str(&format!(
        "let body = load({:?})",
        urdf.display().to_string()
    ))
    .unwrap();
    mx.eval_str(
        "let m = simulate(scene(body, gravity: [0, 0, -9.81]), 2, dt: 0.01, integrator: \"dopri5\", tol: 1e-11, \
         init: {q: {hinge: 1.0, elbow: -0.5}}, velocities: true)",
    )
    .unwrap();
    let end = mx.eval_str("sample(m, 2)").unwrap();
    let Value::Record(r) = end else {
        panic!("{end:?}")
    };
    let get = |k: &str| {
        r.get(k)
            .and_then(|v| v.as_number())
            .unwrap_or_else(|| panic!("{k} missing"))
    };
    let (q, v) = (
        [get("hinge"), get("elbow")],
        [get("hinge.v"), get("elbow.v")],
    );
    // Energy at the end equals the energy at rest at the start.
    let model = mx::model::Model::from_urdf_file(&urdf).unwrap();
    let scene = mx::dynamics::Scene::new(std::sync::Arc::new(model))
        .with_gravity(nalgebra::Vector3::new(0.0, 0.0, -9.81))
        .unwrap();
    let mut sw = mx::dynamics::SceneWorkspace::new(&scene);
    let e0 = scene.energy(&mut sw, &[1.0, -0.5], &[0.0, 0.0]).unwrap();
    let e1 = scene.energy(&mut sw, &q, &v).unwrap();
    assert!(v[0].abs() > 0.1, "the pendulum moves");
    assert!((e1 - e0).abs() < 1e-7 * e0.abs(), "energy {e0} → {e1}");
    // Bad integrator names and unknown coordinates are reported.
    let e = mx
        .eval_str("simulate(scene(body), 1, integrator: \"leapfrog\")")
        .unwrap_err();
    assert!(
        e.render_plain().contains("unknown integrator"),
        "{}",
        e.render_plain()
    );
    let e = mx
        .eval_str("simulate(scene(body), 1, init: {knee: 1})")
        .unwrap_err();
    assert!(
        e.render_plain().contains("no coordinate `knee`"),
        "{}",
        e.render_plain()
    );
}

#[test]
fn a_scene_summary_counts_springs_in_the_singular_and_plural() {
    // The repository's own double pendulum (no shared data needed).
    let mut mx = Interpreter::new();
    let buf = mx.capture_output();
    let spring = "{a: \"world\", pa: [0.5, 0, -1.5], b: \"lower\", pb: [0, 0, -0.8], k: 40}";
    let src = format!(
        "let body = load(\"examples/data/double_pendulum.urdf\")\n\
         print(scene(body, springs: [{spring}]))\n\
         print(scene(body, springs: [{spring}, {spring}]))"
    );
    if let Err(d) = mx.eval_str(&src) {
        panic!("{}", d.render_plain());
    }
    let out = String::from_utf8(buf.lock().unwrap().clone()).unwrap();
    let lines: Vec<&str> = out.lines().collect();
    assert!(lines[0].contains("(1 spring)"), "{out}");
    assert!(lines[1].contains("(2 springs)"), "{out}");
}
