//! OpenSim files from the language: `load("x.osim")`, `.mot`/`.sto` in and
//! out, and clear errors (never a panic) on bad input.

use crate::common;

use std::path::{Path, PathBuf};

use mx::{Interpreter, Value};
use serde_json::Value as J;

fn data() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/opensim")
}

fn q(p: &Path) -> String {
    format!("{:?}", p.display().to_string())
}

fn gait2392() -> Option<PathBuf> {
    common::shared_files("opensim", ".osim")
        .into_iter()
        .find(|p| {
            p.file_name()
                .is_some_and(|n| n == "gait2392_thelen2003muscle.osim")
        })
}

fn num(v: Value) -> f64 {
    v.as_number().expect("a number")
}

#[test]
fn gait2392_loads_as_a_body_with_its_report() {
    let Some(model) = gait2392() else { return };
    let mut mx = Interpreter::new();
    mx.eval_str(&format!("let b = load({})", q(&model)))
        .unwrap();
    let s = mx.eval_str("str(b)").unwrap();
    let s = s.as_str().unwrap().to_string();
    assert!(
        s.contains("23 coordinates") && s.contains("92 muscles"),
        "{s}"
    );
    let r = mx.eval_str("b.report").unwrap();
    let r = r.as_str().unwrap().to_string();
    assert!(
        r.contains("92 muscles ignored (92 Thelen2003Muscle)"),
        "{r}"
    );
    assert!(r.contains("gravity [0, -9.80665, 0]"), "{r}");
    assert_eq!(num(mx.eval_str("len(coordinates(b))").unwrap()), 23.0);
    assert_eq!(
        mx.eval_str("coordinates(b)[9]").unwrap().as_str(),
        Some("knee_angle_r")
    );
    // pelvis_ty's default (0.95) comes through
    assert_eq!(num(mx.eval_str("b.defaults[4]").unwrap()), 0.95);
    // inverse dynamics runs with the model's own gravity (y down)
    let tau = mx
        .eval_str("inverse_dynamics(b, b.defaults, map(b.defaults, fn(x) = 0), map(b.defaults, fn(x) = 0))[4]")
        .unwrap();
    let m = num(mx.eval_str("b.mass").unwrap());
    assert!(
        (num(tau) - m * 9.80665).abs() < 1e-9 * m * 10.0,
        "pelvis_ty holds the weight"
    );
}

#[test]
fn a_mot_written_by_opensim_loads_to_its_values() {
    let Some(model) = gait2392() else { return };
    let mot = data().join("mot/opensim_written.mot");
    let r: J = serde_json::from_str(
        &std::fs::read_to_string(data().join("mot/opensim_written.json")).unwrap(),
    )
    .unwrap();
    let labels: Vec<&str> = r["labels"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l.as_str().unwrap())
        .collect();
    let mut mx = Interpreter::new();
    mx.eval_str(&format!("let b = load({})", q(&model)))
        .unwrap();
    mx.eval_str(&format!("let m = load({}, body: b)", q(&mot)))
        .unwrap();
    mx.eval_str(&format!("let n = load({})", q(&mot))).unwrap();
    let mut worst: f64 = 0.0;
    for (k, t) in r["time"].as_array().unwrap().iter().enumerate() {
        let t = t.as_f64().unwrap();
        for (c, l) in labels.iter().enumerate() {
            let want_file = r["values"][k][c].as_f64().unwrap();
            let want = if l.ends_with("_tx") {
                want_file
            } else {
                want_file.to_radians()
            };
            for var in ["m", "n"] {
                let got = num(mx
                    .eval_str(&format!("sample({var}, {t:?})[{l:?}]"))
                    .unwrap());
                worst = worst.max((got - want).abs() / want.abs().max(1.0));
            }
        }
    }
    assert!(worst <= 1e-12, "values off by {worst:e}");
    // mx writes it back: same numbers in the file (degrees), OpenSim's layout
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("again.mot");
    mx.eval_str(&format!("save(m, {}, body: b)", q(&out)))
        .unwrap();
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(
        text.contains("inDegrees=yes\nendheader\ntime\tknee_angle_r\tpelvis_tx\thip_flexion_r\n"),
        "{text}"
    );
    let st = mx::io::storage::parse_storage(&text).unwrap();
    for (k, row) in r["values"].as_array().unwrap().iter().enumerate() {
        for (c, v) in row.as_array().unwrap().iter().enumerate() {
            let v = v.as_f64().unwrap();
            assert!((st.columns[c][k] - v).abs() <= 1e-12 * v.abs().max(1.0));
        }
    }
    // and loading mx's file gives the motion again
    mx.eval_str(&format!("let m2 = load({}, body: b)", q(&out)))
        .unwrap();
    let d = num(mx
        .eval_str("abs(sample(m2, 0.05)[\"hip_flexion_r\"] - sample(m, 0.05)[\"hip_flexion_r\"])")
        .unwrap());
    assert!(d < 1e-12, "{d}");
}

fn err_of(src: &str) -> String {
    let mut mx = Interpreter::new();
    match mx.eval_str(src) {
        Ok(v) => panic!("expected an error from `{src}`, got {v:?}"),
        Err(e) => e.to_string(),
    }
}

const MINI: &str = r#"<?xml version="1.0" encoding="UTF-8" ?>
<OpenSimDocument Version="40000">
  <Model name="mini">
    <gravity>0 -9.80665 0</gravity>
    <BodySet name="bodyset"><objects>
      <Body name="thigh"><mass>2</mass><mass_center>0 -0.2 0</mass_center><inertia>0.1 0.01 0.1 0 0 0</inertia></Body>
      <Body name="shank"><mass>1</mass><mass_center>0 -0.2 0</mass_center><inertia>0.05 0.005 0.05 0 0 0</inertia></Body>
    </objects></BodySet>
    <JointSet name="jointset"><objects>
      <PinJoint name="hip">
        <socket_parent_frame>/ground</socket_parent_frame>
        <socket_child_frame>/bodyset/thigh</socket_child_frame>
        <coordinates><Coordinate name="hip_flexion"><range>-1 1</range></Coordinate></coordinates>
      </PinJoint>
      <CustomJoint name="knee">
        <socket_parent_frame>knee_parent</socket_parent_frame>
        <socket_child_frame>/bodyset/SHANK</socket_child_frame>
        <coordinates><Coordinate name="KNEE_COORD"><range>-2 0.2</range></Coordinate></coordinates>
        <frames>
          <PhysicalOffsetFrame name="knee_parent"><socket_parent>/bodyset/thigh</socket_parent><translation>0 -0.4 0</translation><orientation>0 0 0</orientation></PhysicalOffsetFrame>
        </frames>
        <SpatialTransform>
          <TransformAxis name="rotation1"><coordinates>KNEE_COORD</coordinates><axis>0 0 1</axis><LinearFunction name="function"><coefficients>1 0</coefficients></LinearFunction></TransformAxis>
          <TransformAxis name="rotation2"><coordinates></coordinates><axis>1 0 0</axis></TransformAxis>
          <TransformAxis name="rotation3"><coordinates></coordinates><axis>0 1 0</axis></TransformAxis>
          <TransformAxis name="translation1"><coordinates>KNEE_COORD</coordinates><axis>1 0 0</axis><SimmSpline name="function"><x>SPLINE_X</x><y>0 0.001 0.002 0.003</y></SimmSpline></TransformAxis>
          <TransformAxis name="translation2"><coordinates></coordinates><axis>0 1 0</axis></TransformAxis>
          <TransformAxis name="translation3"><coordinates></coordinates><axis>0 0 1</axis></TransformAxis>
        </SpatialTransform>
      </CustomJoint>
    </objects></JointSet>
    CONSTRAINTS
    <ForceSet name="forceset"><objects><Thelen2003Muscle name="m1"/><CoordinateLimitForce name="lim"/></objects></ForceSet>
  </Model>
</OpenSimDocument>
"#;

fn mini(edit: &[(&str, &str)]) -> String {
    let mut s = MINI
        .replace("SHANK", "shank")
        .replace("KNEE_COORD", "knee_angle")
        .replace("SPLINE_X", "-2 -1 0 0.5")
        .replace("CONSTRAINTS", "");
    for (a, b) in edit {
        assert!(s.contains(a), "{a}");
        s = s.replace(a, b);
    }
    s
}

fn load_err(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    err_of(&format!("load({})", q(&p)))
}

#[test]
fn a_small_model_loads_and_couplers_are_enforced_and_listed() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("mini.osim");
    let coupler = r#"<ConstraintSet name="constraintset"><objects><CoordinateCouplerConstraint name="cc">
      <independent_coordinate_names>knee_angle</independent_coordinate_names>
      <dependent_coordinate_name>hip_flexion</dependent_coordinate_name>
      <coupled_coordinates_function><LinearFunction><coefficients>0.5 0</coefficients></LinearFunction></coupled_coordinates_function>
    </CoordinateCouplerConstraint></objects></ConstraintSet>"#;
    std::fs::write(
        &p,
        mini(&[]).replace("<ForceSet", &format!("{coupler}<ForceSet")),
    )
    .unwrap();
    let mut mx = Interpreter::new();
    mx.eval_str(&format!("let b = load({})", q(&p))).unwrap();
    let r = mx
        .eval_str("b.report")
        .unwrap()
        .as_str()
        .unwrap()
        .to_string();
    assert!(
        r.contains("coupled coordinate: hip_flexion = f(knee_angle)"),
        "{r}"
    );
    assert!(
        r.contains("1 muscles ignored") && r.contains("1 forces ignored (1 CoordinateLimitForce)"),
        "{r}"
    );
    // enforced by default: hip_flexion follows knee_angle; `couplers: false` keeps it
    assert!(r.contains("(cc), enforced"), "{r}");
    assert_eq!(
        mx.eval_str("coordinates(b)").unwrap().repr(),
        r#"["knee_angle"]"#
    );
    mx.eval_str(&format!("let f = load({}, couplers: false)", q(&p)))
        .unwrap();
    assert_eq!(
        mx.eval_str("coordinates(f)").unwrap().repr(),
        r#"["hip_flexion", "knee_angle"]"#
    );
}

#[test]
fn bad_models_are_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let e = load_err(d, "a.osim", "<OpenSimDocument Version=\"40000\"><Model>");
    assert!(e.contains("invalid XML"), "{e}");
    let e = load_err(d, "b.osim", &mini(&[("/bodyset/shank", "/bodyset/tibia")]));
    assert!(
        e.contains("joint 'knee'") && e.contains("'/bodyset/tibia'") && e.contains("line 15"),
        "{e}"
    );
    let e = load_err(
        d,
        "c.osim",
        &mini(&[(
            "<Coordinate name=\"knee_angle\">",
            "<Coordinate name=\"hip_flexion\">",
        )]),
    );
    assert!(
        e.contains("'hip_flexion'") && e.contains("used twice"),
        "{e}"
    );
    let e = load_err(d, "d.osim", &mini(&[("-2 -1 0 0.5", "-2 0 -1 0.5")]));
    assert!(
        e.contains("SimmSpline") && e.contains("strictly increasing") && e.contains("line 26"),
        "{e}"
    );
    // a fourth rotation axis, or one named twice, would be dropped silently
    for (i, name) in ["rotation4", "rotation1"].iter().enumerate() {
        let e = load_err(
            d,
            &format!("axis{i}.osim"),
            &mini(&[(
                "<TransformAxis name=\"rotation2\">",
                &format!("<TransformAxis name=\"{name}\">"),
            )]),
        );
        assert!(
            e.contains(name) && (e.contains("rotation1..3") || e.contains("two axes")),
            "{e}"
        );
    }
    let e = load_err(d, "e.osim", &mini(&[("PinJoint", "ScrewJoint")]));
    assert!(e.contains("ScrewJoint") && e.contains("line 10"), "{e}");
    let e = load_err(
        d,
        "g.osim",
        &mini(&[(
            "<ForceSet",
            "<ConstraintSet><objects><WeldConstraint name=\"w\"/></objects></ConstraintSet><ForceSet",
        )]),
    );
    assert!(
        e.contains("WeldConstraint") && e.contains("changes the kinematics"),
        "{e}"
    );
    let e = load_err(
        d,
        "h.osim",
        &mini(&[(
            "<SimmSpline name=\"function\"><x>-2 -1 0 0.5</x><y>0 0.001 0.002 0.003</y></SimmSpline>",
            "<GCVSpline name=\"function\"/>",
        )]),
    );
    assert!(e.contains("GCVSpline"), "{e}");
    let e = load_err(
        d,
        "i.osim",
        &mini(&[(
            "<coordinates>knee_angle</coordinates><axis>1 0 0</axis>",
            "<coordinates>knee_angle hip_flexion</coordinates><axis>1 0 0</axis>",
        )]),
    );
    assert!(e.contains("function of 2 coordinates"), "{e}");
    let e = load_err(d, "j.osim", "<robot name=\"r\"/>");
    assert!(e.contains("OpenSimDocument"), "{e}");
}

#[test]
fn bad_motion_files_are_clear_errors() {
    let Some(model) = gait2392() else { return };
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let p = d.join("a.mot");
    std::fs::write(&p, "version=1\ninDegrees=yes\nendheader\ntime\tknee_angle_r\tnot_a_coordinate\n0\t1\t2\n0.1\t2\t3\n").unwrap();
    let e = err_of(&format!("load({}, body: load({}))", q(&p), q(&model)));
    assert!(
        e.contains("`not_a_coordinate`") && e.contains("name no coordinate"),
        "{e}"
    );
    let p = d.join("b.mot");
    std::fs::write(
        &p,
        "version=1\ninDegrees=yes\ntime\tknee_angle_r\n0\t1\n0.1\t2\n",
    )
    .unwrap();
    let e = err_of(&format!("load({})", q(&p)));
    assert!(e.contains("endheader"), "{e}");
    let p = d.join("c.sto");
    std::fs::write(&p, "endheader\ntime\tknee_angle_r\n0\t1\n0.1\t2\n0.35\t3\n").unwrap();
    let e = err_of(&format!("load({})", q(&p)));
    assert!(e.contains("uniform grid"), "{e}");
}
