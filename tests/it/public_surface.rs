//! The public forms of issues #2, #4 and #5, exactly as a user writes them,
//! run through the real binary (`mx run file.mx` in a temporary folder) on
//! data this test writes itself (a URDF arm with prismatic, fixed and
//! continuous joints; a slider; a CRLF BVH with odd channel orders) plus the
//! shared Pinocchio reference data. Outputs are checked exactly where the
//! language promises exact text, and against closed forms elsewhere.

use crate::common;

use std::path::Path;
use std::process::Command;

struct Run {
    stdout: String,
    stderr: String,
    ok: bool,
}

fn run(dir: &Path, script: &str) -> Run {
    std::fs::write(dir.join("main.mx"), script).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_mx"))
        .args(["run", "main.mx"])
        .current_dir(dir)
        .output()
        .expect("runs mx");
    Run {
        stdout: String::from_utf8_lossy(&o.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&o.stderr).into_owned(),
        ok: o.status.success(),
    }
}

/// Runs `script` and returns stdout, failing the test with stderr otherwise.
fn ok(dir: &Path, script: &str) -> String {
    let r = run(dir, script);
    assert!(r.ok, "script failed:\n{script}\n--- stderr:\n{}", r.stderr);
    r.stdout
}

/// One printed line of numbers (`[1, 2.5]`) or nested lists, as JSON.
fn nums(line: &str) -> Vec<f64> {
    let v: serde_json::Value = serde_json::from_str(line).unwrap_or_else(|e| panic!("{line}: {e}"));
    fn flat(v: &serde_json::Value, out: &mut Vec<f64>) {
        match v {
            serde_json::Value::Array(a) => a.iter().for_each(|x| flat(x, out)),
            x => out.push(x.as_f64().expect("a number")),
        }
    }
    let mut out = Vec::new();
    flat(&v, &mut out);
    out
}

// ---- issue #2: motions -------------------------------------------------------

#[test]
fn motion_forms_and_print_formats() {
    let dir = tempfile::tempdir().unwrap();
    let out = ok(
        dir.path(),
        r#"let a = interval(1, 0, 1)
let b = interval(fn(t) = 2 * t, 0.5s, 2s)
print(a, b)
let d = dof(a, interval(3, 3, 4))
print(d)
let m = mu({x: d, y: b})
print(m)
print(0.1, 1e-12, [1, 2], {a: 1, b: 2}, -0.0, 1e-300, 123456789012, "text", ["q"], {"Hips.Xposition": 0.5})
print(span(m), gaps(m), conflicts(m), dofs(m))
print(m & mu({x: interval(5, 0.5, 3.5)}))
print(m ∧ m, m - m, m − m, m + m)
print(2s, 250ms, 90deg, 1.2rad)
print(m.only("x"), m.dofs(), m.span(), only(m, "?"))
print(affine(1, 2, m), clip(0.5, 1.5, m), clip_in_place(0.5, 1.5, m), concatenate(m, m))
print(sample(m, 0.75), sample(affine(1, 2, m), 2.5))
"#,
    );
    assert_eq!(
        out,
        "Interval [0, 1] (1 function) Interval [0.5, 2] (1 function)\n\
         Dof [0, 4] (2 intervals, 1 gap, 0 conflicts)\n\
         Mu [0, 4] (2 DOFs: x, y; 3 intervals, 1 gap, 0 conflicts)\n\
         0.1 1e-12 [1, 2] {a: 1, b: 2} -0 1e-300 123456789012 text [\"q\"] {\"Hips.Xposition\": 0.5}\n\
         [0, 4] [{dof: \"x\", start: 1, stop: 3}] [] [\"x\", \"y\"]\n\
         Mu [0.5, 3.5] (1 DOF: x; 2 intervals, 1 gap, 2 conflicts)\n\
         Mu [0, 4] (2 DOFs: x, y; 3 intervals, 1 gap, 3 conflicts) \
         Mu nothing defined (2 DOFs: x, y; 0 intervals, 0 gaps, 0 conflicts) \
         Mu nothing defined (2 DOFs: x, y; 0 intervals, 0 gaps, 0 conflicts) \
         Mu [0, 4] (2 DOFs: x, y; 3 intervals, 1 gap, 3 conflicts)\n\
         2 0.25 1.5707963267948966 1.2\n\
         Mu [0, 4] (1 DOF: x; 2 intervals, 1 gap, 0 conflicts) [\"x\", \"y\"] [0, 4] \
         Mu [0, 4] (2 DOFs: x, y; 3 intervals, 1 gap, 0 conflicts)\n\
         Mu [1, 9] (2 DOFs: x, y; 3 intervals, 1 gap, 0 conflicts) \
         Mu [0, 1] (2 DOFs: x, y; 2 intervals, 0 gaps, 0 conflicts) \
         Mu [0.5, 1.5] (2 DOFs: x, y; 2 intervals, 0 gaps, 0 conflicts) \
         Mu [0, 8] (2 DOFs: x, y; 6 intervals, 3 gaps, 0 conflicts)\n\
         {x: 1, y: 1.5} {x: 1, y: 1.5}\n"
    );
}

#[test]
fn csv_rows_are_whole_multiples_of_the_period_with_float_edges() {
    let dir = tempfile::tempdir().unwrap();
    ok(
        dir.path(),
        r#"save(mu({x: interval(1, 0, 1)}), "third.csv", rate: 3)
save(mu({x: interval(fn(t) = t, 0.1, 0.7)}), "tenth.csv", rate: 10)
let m = mu({b: interval(2, 0.5, 1), a: dof(interval(1, 0, 0.5), interval(3, 1.5, 2))})
save(m, "cells.csv", rate: 2)
save(mu({x: interval(1e-300, 0, 1), y: interval(-2.44e-17, 0, 1), z: interval(123456789012, 0, 1)}), "tiny.csv", rate: 1)
"#,
    );
    let read = |f: &str| std::fs::read_to_string(dir.path().join(f)).unwrap();
    assert_eq!(
        read("third.csv"),
        "t,x\n0,1\n0.3333333333333333,1\n0.6666666666666666,1\n1,1\n"
    );
    // 0.7 · 10 is 7.000000000000001 in floating point: the row at 0.7 is still there.
    assert_eq!(
        read("tenth.csv"),
        "t,x\n0.1,0.1\n0.2,0.2\n0.3,0.3\n0.4,0.4\n0.5,0.5\n0.6,0.6\n0.7,0.7\n"
    );
    // Header in first-definition order; undefined = empty cell.
    assert_eq!(
        read("cells.csv"),
        "t,b,a\n0,,1\n0.5,2,1\n1,2,\n1.5,,3\n2,,3\n"
    );
    // Tiny and huge numbers in shortest round-trip form, exponent when long.
    assert_eq!(
        read("tiny.csv"),
        "t,x,y,z\n0,1e-300,-2.44e-17,123456789012\n1,1e-300,-2.44e-17,123456789012\n"
    );
}

#[test]
fn csv_save_then_load_gives_the_same_samples() {
    let dir = tempfile::tempdir().unwrap();
    let out = ok(
        dir.path(),
        r#"let m = mu({a: interval(1e-300, 0, 1), b: interval(1e-12, 0, 1), c: interval(0.1, 0, 1), d: interval(123456789012, 0, 1), e: interval(fn(t) = t * t - 0.5, 0.5, 1)})
save(m, "r.csv", rate: 4)
let back = load("r.csv")
print(back)
print(map(range(5), fn(k) = sample(back, k / 4)) == map(range(5), fn(k) = sample(m, k / 4)))
print(sample(back, 0.25))
"#,
    );
    assert_eq!(
        out,
        "Mu [0, 1] (5 DOFs: a, b, c, d, …; 5 intervals, 0 gaps, 0 conflicts)\ntrue\n\
         {a: 1e-300, b: 1e-12, c: 0.1, d: 123456789012, e: nil}\n"
    );
}

#[test]
fn csv_undefined_vs_not_a_number() {
    let dir = tempfile::tempdir().unwrap();
    // A motion never holds NaN: a function that returns one fails when sampled,
    // naming the time, instead of writing a value CSV could not tell from data.
    let r = run(
        dir.path(),
        "save(mu({x: interval(fn(t) = if t < 0.5 { 1 } else { pow(-1, 0.5) }, 0, 1)}), \"n.csv\", rate: 4)",
    );
    assert!(!r.ok);
    assert!(r.stderr.contains("t = 0.5"), "{}", r.stderr);
    assert!(!dir.path().join("n.csv").exists());
    // Reading: an empty cell is undefined; `nan` is refused with its line.
    std::fs::write(dir.path().join("bad.csv"), "t,x\n0,1\n0.5,nan\n1,2\n").unwrap();
    let r = run(dir.path(), "load(\"bad.csv\")");
    assert!(!r.ok);
    assert!(
        r.stderr.contains("line 3") && r.stderr.contains("nan"),
        "{}",
        r.stderr
    );
    std::fs::write(
        dir.path().join("gap.csv"),
        "t,x\n0,1\n0.5,2\n1,\n1.5,3\n2,4\n",
    )
    .unwrap();
    let out = ok(
        dir.path(),
        "let g = load(\"gap.csv\")\nprint(gaps(g), sample(g, 1))",
    );
    assert_eq!(out, "[{dof: \"x\", start: 0.5, stop: 1.5}] {x: nil}\n");
}

#[test]
fn sampling_a_conflict_names_dof_and_span_and_keeps_the_old_file() {
    let dir = tempfile::tempdir().unwrap();
    let keep = dir.path().join("keep.csv");
    std::fs::write(&keep, "old content").unwrap();
    let r = run(
        dir.path(),
        r#"let m = mu({x: interval(1, 0, 1), y: interval(2, 0, 2)}) + mu({y: interval(3, 0.5, 1.5)})
save(m, "keep.csv", rate: 10)"#,
    );
    assert!(!r.ok);
    assert!(
        r.stderr.contains("DOF 'y'") && r.stderr.contains("[0.5, 1.5]"),
        "{}",
        r.stderr
    );
    assert!(r.stdout.is_empty());
    assert_eq!(std::fs::read_to_string(&keep).unwrap(), "old content");
    for bad in [
        "save(mu({x: interval(1, 0, 1)}), \"keep.csv\", rate: 0)",
        "save(mu({x: interval(1, 0, 1)}), \"keep.csv\")",
        "save(mu({x: interval(fn(t) = t, 0, 1)}), \"keep.bvh\")",
    ] {
        std::fs::write(dir.path().join("keep.bvh"), "old content").unwrap();
        let r = run(dir.path(), bad);
        assert!(!r.ok, "{bad}");
        assert_eq!(std::fs::read_to_string(&keep).unwrap(), "old content");
        assert_eq!(
            std::fs::read_to_string(dir.path().join("keep.bvh")).unwrap(),
            "old content"
        );
    }
    // No temporary files are left behind.
    let names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect();
    assert!(names.is_empty(), "{names:?}");
}

#[test]
fn json_round_trip_is_exact_including_mx_functions() {
    let dir = tempfile::tempdir().unwrap();
    let out = ok(
        dir.path(),
        r#"let w = [0.1, 0.2, 1e-300]
let r = {amp: 0.30000000000000004}
fn g(t, k = 2) = r.amp * k * t + w[2]
fn f(t) = 0.1 * sin(2 * pi * t) + square(t)
let s = samples([0, 1e-17, 0.3, 0.5, 1], 4, t0: 0.1)
let m = mu({a: interval(g, 0, 1), b: affine(0.25, 1.5, mu({b: interval(fn(t) = t * t, 0, 1)})).get("b"), c: s, d: interval(0.1 + 0.2, -1, 1e-9), e: dof(interval(f, 0, 1), interval(-0.0, 2, 3))})
save(m, "m.json")
let n = load("m.json")
save(n, "n.json")
let ts = linspace(-1, 3, 41)
print(n == m, dofs(n) == dofs(m), gaps(n) == gaps(m))
print(map(ts, fn(t) = sample(n, t)) == map(ts, fn(t) = sample(m, t)))
print(map(ts, fn(t) = sample(n, t, deriv: 1)) == map(ts, fn(t) = sample(m, t, deriv: 1)))
"#,
    );
    assert_eq!(out, "true true true\ntrue\ntrue\n");
    let a = std::fs::read_to_string(dir.path().join("m.json")).unwrap();
    let b = std::fs::read_to_string(dir.path().join("n.json")).unwrap();
    assert_eq!(a, b, "save(load(x)) writes the same file");
}

#[test]
fn only_print_writes_to_stdout() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("old.csv"), "x").unwrap();
    let r = run(
        dir.path(),
        r#"let m = mu({x: interval(1, 0, 1)})
save(m, "a.csv", rate: 2)
save(m, "a.json")
let n = load("a.json")
eprint("note")
span(n)
m
"#,
    );
    assert!(r.ok, "{}", r.stderr);
    assert_eq!(r.stdout, "");
    assert_eq!(r.stderr, "note\n");
}

// ---- issue #4: bodies and dynamics ----------------------------------------------

/// A planar arm in the x–z plane (rotations about y): revolute shoulder,
/// prismatic slide along the arm, a fixed clamp (merged into the slider) and
/// a continuous wrist. Joint origins and centres of mass lie on the arm's
/// axis, so M(q) and g(q) have closed forms (below).
const ARM_URDF: &str = r#"<?xml version="1.0"?>
<robot name="rpr_arm">
  <link name="base"/>
  <link name="upper">
    <inertial><origin xyz="0.5 0 0"/><mass value="2"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.2" iyz="0" izz="0.2"/></inertial>
  </link>
  <link name="slider">
    <inertial><origin xyz="0.1 0 0"/><mass value="1"/>
      <inertia ixx="0.005" ixy="0" ixz="0" iyy="0.05" iyz="0" izz="0.05"/></inertial>
  </link>
  <link name="clamp">
    <inertial><origin xyz="0 0 0"/><mass value="0.5"/>
      <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>
  </link>
  <link name="hand">
    <inertial><origin xyz="0.2 0 0"/><mass value="0.5"/>
      <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
  </link>
  <joint name="shoulder" type="revolute">
    <parent link="base"/><child link="upper"/><origin xyz="0 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-3" upper="3" effort="100" velocity="10"/>
  </joint>
  <joint name="slide" type="prismatic">
    <parent link="upper"/><child link="slider"/><origin xyz="1 0 0"/><axis xyz="1 0 0"/>
    <limit lower="-0.5" upper="0.5" effort="100" velocity="1"/>
  </joint>
  <joint name="clamp_mount" type="fixed">
    <parent link="slider"/><child link="clamp"/><origin xyz="0.2 0 0"/>
  </joint>
  <joint name="wrist" type="continuous">
    <parent link="slider"/><child link="hand"/><origin xyz="0.3 0 0"/><axis xyz="0 1 0"/>
  </joint>
</robot>
"#;

/// M(q) and g(q) of `ARM_URDF` from the bodies' planar Jacobians:
/// M = Σ m Jvᵀ Jv + I_yy Jωᵀ Jω, g = Σ m · 9.81 · ∂z/∂q (z up).
fn arm_closed_form(q: [f64; 3]) -> ([[f64; 3]; 3], [f64; 3]) {
    let u = |t: f64| [t.cos(), -t.sin()]; // the arm's direction (x, z) after a rotation t about y
    let du = |t: f64| [-t.sin(), -t.cos()];
    let sc = |k: f64, a: [f64; 2]| [k * a[0], k * a[1]];
    let add = |a: [f64; 2], b: [f64; 2]| [a[0] + b[0], a[1] + b[1]];
    let (q1, q2, q3) = (q[0], q[1], q[2]);
    let z = [0.0, 0.0];
    // (mass, I_yy, ∂(x, z)/∂q per coordinate, ∂angle/∂q)
    type PlanarBody = (f64, f64, [[f64; 2]; 3], [f64; 3]);
    let bodies: [PlanarBody; 4] = [
        (2.0, 0.2, [sc(0.5, du(q1)), z, z], [1.0, 0.0, 0.0]),
        (1.0, 0.05, [sc(1.1 + q2, du(q1)), u(q1), z], [1.0, 0.0, 0.0]),
        (
            0.5,
            0.001,
            [sc(1.2 + q2, du(q1)), u(q1), z],
            [1.0, 0.0, 0.0],
        ),
        (
            0.5,
            0.01,
            [
                add(sc(1.3 + q2, du(q1)), sc(0.2, du(q1 + q3))),
                u(q1),
                sc(0.2, du(q1 + q3)),
            ],
            [1.0, 0.0, 1.0],
        ),
    ];
    let mut m = [[0.0; 3]; 3];
    let mut g = [0.0; 3];
    for (mass, iyy, jv, jw) in bodies {
        for i in 0..3 {
            g[i] += mass * 9.81 * jv[i][1];
            for j in 0..3 {
                m[i][j] += mass * (jv[i][0] * jv[j][0] + jv[i][1] * jv[j][1]) + iyy * jw[i] * jw[j];
            }
        }
    }
    (m, g)
}

#[test]
fn urdf_dynamics_take_and_return_lists_in_coordinate_order() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("arm.urdf"), ARM_URDF).unwrap();
    let out = ok(
        dir.path(),
        r#"let arm = load("arm.urdf")
print(coordinates(arm))
let q = [0.3, 0.1, -0.7]
print(inverse_dynamics(arm, q, [0, 0, 0], [0, 0, 0]))
print(mass_matrix(arm, q))
let v = [0.5, -0.2, 1]
let tau = inverse_dynamics(arm, q, v, [1, 2, 3])
print(forward_dynamics(arm, q, v, tau))
print(inverse_dynamics(arm, q, [0, 0, 0], [0, 0, 0], gravity: [0, 0, 0]))
"#,
    );
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines[0], r#"["shoulder", "slide", "wrist"]"#);
    let (m, g) = arm_closed_form([0.3, 0.1, -0.7]);
    let close = |a: &[f64], b: &[f64], tol: f64| {
        assert_eq!(a.len(), b.len());
        for (x, y) in a.iter().zip(b) {
            assert!((x - y).abs() <= tol, "{a:?} vs {b:?}");
        }
    };
    close(&nums(lines[1]), &g, 1e-12);
    close(&nums(lines[2]), &m.concat(), 1e-12);
    close(&nums(lines[3]), &[1.0, 2.0, 3.0], 1e-10);
    assert_eq!(nums(lines[4]), vec![0.0; 3]);
    // Wrong lengths and non-bodies are errors that say what is expected.
    let r = run(
        dir.path(),
        "inverse_dynamics(load(\"arm.urdf\"), [0, 0], [0, 0, 0], [0, 0, 0])",
    );
    assert!(!r.ok);
    assert!(
        r.stderr
            .contains("has 2 numbers but the body has 3 coordinates")
            && r.stderr.contains("shoulder, slide, wrist"),
        "{}",
        r.stderr
    );
}

#[test]
fn urdf_dynamics_match_pinocchio_reference() {
    let files = common::shared_files("reference", ".json");
    for json in files {
        let text = std::fs::read_to_string(&json).unwrap();
        let r: serde_json::Value = serde_json::from_str(&text).unwrap();
        let urdf = json.with_file_name(r["urdf_file"].as_str().unwrap());
        let names: Vec<&str> = r["joints"]
            .as_array()
            .unwrap()
            .iter()
            .map(|j| j["name"].as_str().unwrap())
            .collect();
        let samples = &r["samples"].as_array().unwrap()[..4];
        let list = |v: &serde_json::Value| serde_json::to_string(v).unwrap();
        let mut script = format!(
            "let b = load({:?})\nprint(coordinates(b))\n",
            urdf.to_str().unwrap()
        );
        for s in samples {
            script += &format!(
                "print(inverse_dynamics(b, {q}, {v}, {a}))\nprint(mass_matrix(b, {q}))\nprint(forward_dynamics(b, {q}, {v}, {tau}))\n",
                q = list(&s["q"]),
                v = list(&s["v"]),
                a = list(&s["a"]),
                tau = list(&s["tau"]),
            );
        }
        let dir = tempfile::tempdir().unwrap();
        let out = ok(dir.path(), &script);
        let lines: Vec<&str> = out.lines().collect();
        let got: Vec<String> = serde_json::from_str(lines[0]).unwrap();
        assert_eq!(
            got,
            names,
            "{}: coordinates in Pinocchio's order",
            json.display()
        );
        let err = |x: &[f64], r: &[f64]| {
            let scale = r.iter().fold(1.0f64, |m, v| m.max(v.abs()));
            x.iter()
                .zip(r)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
                / scale
        };
        for (k, s) in samples.iter().enumerate() {
            let reference = |key: &str| nums(&list(&s[key]));
            let tau = nums(lines[1 + 3 * k]);
            let m = nums(lines[2 + 3 * k]);
            let ddq = nums(lines[3 + 3 * k]);
            let what = format!("{} sample {k}", json.display());
            assert!(err(&tau, &reference("tau")) <= 1e-10, "{what}: tau");
            assert!(err(&m, &reference("M")) <= 1e-10, "{what}: M");
            assert!(err(&ddq, &reference("a")) <= 1e-8, "{what}: ddq");
        }
    }
}

#[test]
fn scene_and_simulate_match_the_damped_oscillator() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("slider.urdf"),
        r#"<?xml version="1.0"?>
<robot name="slider">
  <link name="ground"/>
  <link name="cart">
    <inertial><origin xyz="0 0 0"/><mass value="2"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
  </link>
  <joint name="lift" type="prismatic">
    <parent link="ground"/><child link="cart"/><origin xyz="0 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-5" upper="5" effort="100" velocity="10"/>
  </joint>
</robot>
"#,
    )
    .unwrap();
    let out = ok(
        dir.path(),
        r#"let cart = load("slider.urdf")
let sc = scene(cart, gravity: [0, -9.80665, 0], damping: 0.8, springs: [{a: "world", pa: [0, 1, 0], b: "cart", pb: [0, 0, 0], k: 50, rest: 1}])
let m = simulate(sc, 2, dt: 0.001, integrator: "rk4", init: {q: {lift: 0.3}, v: {lift: -0.5}}, velocities: true)
print(dofs(m), span(m))
let s1 = sample(m, 1)
let s2 = sample(m, 2)
print([s1.lift, s1["lift.v"], s2.lift, s2["lift.v"]])
print(dofs(simulate(sc, 0.5, dt: 0.01, integrator: "dopri5")))
"#,
    );
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines[0], r#"["lift", "lift.v"] [0, 2]"#);
    assert_eq!(lines[2], r#"["lift"]"#);
    // m ÿ + c ẏ + k y = −m g: the spring (rest 1, anchored 1 m above) pulls with −k y.
    let (m, k, c, g) = (2.0f64, 50.0f64, 0.8f64, 9.80665f64);
    let yeq = -m * g / k;
    let w = (k / m).sqrt();
    let zeta = c / (2.0 * (k * m).sqrt());
    let wd = w * (1.0 - zeta * zeta).sqrt();
    let (a, b) = (0.3 - yeq, (-0.5 + zeta * w * (0.3 - yeq)) / wd);
    let y = |t: f64| yeq + (-zeta * w * t).exp() * (a * (wd * t).cos() + b * (wd * t).sin());
    let v = |t: f64| {
        let e = (-zeta * w * t).exp();
        e * (-zeta * w * (a * (wd * t).cos() + b * (wd * t).sin())
            + wd * (-a * (wd * t).sin() + b * (wd * t).cos()))
    };
    let got = nums(lines[1]);
    let want = [y(1.0), v(1.0), y(2.0), v(2.0)];
    for (x, e) in got.iter().zip(want) {
        assert!((x - e).abs() < 1e-8, "{got:?} vs {want:?}");
    }
}

// ---- issue #5: motion capture ---------------------------------------------------

const FRAMES: usize = 5;
const FRAME_TIME: f64 = 0.0333333;

/// A 21-joint humanoid BVH in centimetres with CRLF line endings, a root
/// whose six channels come in an unusual order, and 3-channel joints each
/// with its own rotation order. Returns the text and the channel names in
/// file order.
fn odd_bvh() -> (String, Vec<String>) {
    let mut joints: Vec<(&str, Option<&str>, [f64; 3], &str)> = vec![
        (
            "Hips",
            None,
            [0.0, 90.0, 0.0],
            "Xposition Zposition Yposition Yrotation Xrotation Zrotation",
        ),
        (
            "Spine",
            Some("Hips"),
            [0.0, 10.0, 0.0],
            "Xrotation Yrotation Zrotation",
        ),
        (
            "Chest",
            Some("Spine"),
            [0.0, 15.0, 0.0],
            "Zrotation Yrotation Xrotation",
        ),
        (
            "Neck",
            Some("Chest"),
            [0.0, 20.0, 0.0],
            "Yrotation Zrotation Xrotation",
        ),
        (
            "Head",
            Some("Neck"),
            [0.0, 10.0, 0.0],
            "Xrotation Zrotation Yrotation",
        ),
    ];
    let names: Vec<[String; 8]> = ["Left", "Right"]
        .iter()
        .map(|s| {
            [
                "Shoulder", "Arm", "ForeArm", "Hand", "UpLeg", "Leg", "Foot", "Toe",
            ]
            .map(|part| format!("{s}{part}"))
        })
        .collect();
    let leak = |s: &String| -> &'static str { Box::leak(s.clone().into_boxed_str()) };
    for (side, n) in names.iter().enumerate() {
        let s = if side == 0 { 1.0 } else { -1.0 };
        joints.extend([
            (
                leak(&n[0]),
                Some("Chest"),
                [s * 3.0, 18.0, 0.0],
                "Zrotation Xrotation Yrotation",
            ),
            (
                leak(&n[1]),
                Some(leak(&n[0])),
                [s * 15.0, 0.0, 0.0],
                "Yrotation Xrotation Zrotation",
            ),
            (
                leak(&n[2]),
                Some(leak(&n[1])),
                [s * 28.0, 0.0, 0.0],
                "Xrotation Yrotation Zrotation",
            ),
            (
                leak(&n[3]),
                Some(leak(&n[2])),
                [s * 25.0, 0.0, 0.0],
                "Zrotation Yrotation Xrotation",
            ),
            (
                leak(&n[4]),
                Some("Hips"),
                [s * 9.0, -5.0, 0.0],
                "Zrotation Xrotation Yrotation",
            ),
            (
                leak(&n[5]),
                Some(leak(&n[4])),
                [0.0, -42.0, 0.0],
                "Xrotation Zrotation Yrotation",
            ),
            (
                leak(&n[6]),
                Some(leak(&n[5])),
                [0.0, -40.0, 0.0],
                "Yrotation Xrotation Zrotation",
            ),
            (
                leak(&n[7]),
                Some(leak(&n[6])),
                [0.0, -4.0, 12.0],
                "Xrotation Yrotation Zrotation",
            ),
        ]);
    }
    let end_site = |n: &str| match n {
        "Head" => Some([0.0, 12.0, 0.0]),
        "LeftHand" => Some([8.0, 0.0, 0.0]),
        "RightHand" => Some([-8.0, 0.0, 0.0]),
        "LeftToe" | "RightToe" => Some([0.0, 0.0, 5.0]),
        _ => None,
    };
    let mut lines = vec!["HIERARCHY".to_string()];
    let mut order: Vec<usize> = Vec::new();
    fn write(
        i: usize,
        depth: usize,
        joints: &[(&str, Option<&str>, [f64; 3], &str)],
        end_site: &dyn Fn(&str) -> Option<[f64; 3]>,
        lines: &mut Vec<String>,
        order: &mut Vec<usize>,
    ) {
        let (name, parent, o, ch) = joints[i];
        let ind = "\t".repeat(depth);
        let kw = if parent.is_none() { "ROOT" } else { "JOINT" };
        lines.push(format!("{ind}{kw} {name}"));
        lines.push(format!("{ind}{{"));
        lines.push(format!("{ind}\tOFFSET {:.2} {:.2} {:.2}", o[0], o[1], o[2]));
        lines.push(format!("{ind}\tCHANNELS {} {ch}", ch.split(' ').count()));
        order.push(i);
        for (c, j) in joints.iter().enumerate() {
            if j.1 == Some(name) {
                write(c, depth + 1, joints, end_site, lines, order);
            }
        }
        if let Some(e) = end_site(name) {
            lines.push(format!("{ind}\tEnd Site"));
            lines.push(format!("{ind}\t{{"));
            lines.push(format!("{ind}\t\tOFFSET {} {} {}", e[0], e[1], e[2]));
            lines.push(format!("{ind}\t}}"));
        }
        lines.push(format!("{ind}}}"));
    }
    write(0, 0, &joints, &end_site, &mut lines, &mut order);
    lines.push("MOTION".into());
    lines.push(format!("Frames: {FRAMES}"));
    lines.push(format!("Frame Time: {FRAME_TIME}"));
    let mut channels = Vec::new();
    for &i in &order {
        for ch in joints[i].3.split(' ') {
            channels.push(format!("{}.{ch}", joints[i].0));
        }
    }
    for f in 0..FRAMES {
        let mut row = Vec::new();
        for &i in &order {
            let (name, ..) = joints[i];
            for (c, ch) in joints[i].3.split(' ').enumerate() {
                let v = if ch.ends_with("position") {
                    (10 * f + c) as f64
                } else {
                    ((5 * f + 3 * c + name.len()) % 40) as f64 - 20.0
                };
                row.push(format!("{v:.4}"));
            }
        }
        lines.push(row.join(" "));
    }
    (lines.join("\r\n") + "\r\n", channels)
}

#[test]
fn bvh_load_save_and_bodies_from_a_clip() {
    let dir = tempfile::tempdir().unwrap();
    let (text, channels) = odd_bvh();
    std::fs::write(dir.path().join("odd.bvh"), &text).unwrap();
    let out = ok(
        dir.path(),
        r#"let clip = load("odd.bvh")
print(dofs(clip))
print(span(clip))
let s = sample(clip, 0.0333333)
print([s["Hips.Xposition"], s["Hips.Zposition"], s["Hips.Yposition"], s["Hips.Yrotation"], s["Chest.Xrotation"]])
save(clip, "rt.bvh")
let back = load("rt.bvh")
print(dofs(back) == dofs(clip))
let ts = map(range(5), fn(k) = k * 0.0333333)
print(max(map(ts, fn(t) = max(map(dofs(clip), fn(n) = abs(sample(clip, t)[n] - sample(back, t)[n]))))))
let b = body_of(clip, mass: 70)
print(coordinates(b) == dofs(clip))
let h = human(clip)
print(len(coordinates(h)))
let f = fit(clip, h)
print(len(dofs(f)), span(f))
let p = positions(clip, b)
let p0 = sample(p, 0)
print(len(dofs(p)), [p0["Hips.x"], p0["Hips.y"], p0["Hips.z"]])
"#,
    );
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 9, "{out}");
    let dofs: Vec<String> = serde_json::from_str(lines[0]).unwrap();
    assert_eq!(dofs, channels, "DOFs named Joint.channel in file order");
    assert_eq!(lines[1], "[0, 0.1333332]");
    // Frame 1: positions 10, 11, 12 cm → metres; rotations (written in
    // degrees by `odd_bvh`: Hips.Yrotation −2°, Chest.Xrotation −4°) in radians.
    let deg = std::f64::consts::PI / 180.0;
    let want = [0.10, 0.11, 0.12, -2.0 * deg, -4.0 * deg];
    let got = nums(lines[2]);
    for (g, w) in got.iter().zip(want) {
        assert!((g - w).abs() < 1e-12, "{got:?} vs {want:?}");
    }
    assert_eq!(lines[3], "true");
    assert!(nums(lines[4])[0] <= 1e-6, "round trip error {}", lines[4]);
    assert_eq!(lines[5], "true");
    assert_eq!(lines[6], "44");
    assert_eq!(lines[7], "44 [0, 0.1333332]");
    // 21 joints and 5 end sites, three coordinates each; the root at its channels.
    let p = nums(&lines[8][lines[8].find('[').unwrap()..]);
    assert!(lines[8].starts_with("78 "), "{}", lines[8]);
    for (g, w) in p.iter().zip([0.0, 0.02, 0.01]) {
        assert!((g - w).abs() < 1e-12, "{p:?}");
    }
    let saved = std::fs::read_to_string(dir.path().join("rt.bvh")).unwrap();
    assert!(
        saved.contains("CHANNELS 6 Xposition Zposition Yposition Yrotation Xrotation Zrotation")
    );
}

#[test]
fn fit_reports_on_stderr_not_stdout() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("odd.bvh"), odd_bvh().0).unwrap();
    let r = run(
        dir.path(),
        "let clip = load(\"odd.bvh\")\nlet f = fit(clip, human(clip))\n",
    );
    assert!(r.ok, "{}", r.stderr);
    assert_eq!(r.stdout, "");
    assert!(r.stderr.contains("fit: 5 frames"), "{}", r.stderr);
}
