//! The joint forms of issue 3 §5 in mx, as written there.

use crate::common;

use mx::lang::{Interpreter, Value};

fn eval(i: &mut Interpreter, src: &str) -> Value {
    match i.eval_str(src) {
        Ok(v) => v,
        Err(d) => panic!("{src}\n{}", d.render_plain()),
    }
}

fn num(v: &Value) -> f64 {
    v.as_number().expect("a number")
}

fn matrix(v: &Value) -> Vec<Vec<f64>> {
    v.as_list()
        .expect("rows")
        .iter()
        .map(|r| r.as_list().expect("row").iter().map(num).collect())
        .collect()
}

#[test]
fn constructors_and_transform() {
    let mut i = Interpreter::new();
    let m = matrix(&eval(&mut i, "transform(revolute([0,0,1]), pi / 2)"));
    assert_eq!(m.len(), 4);
    assert!(
        (m[0][0]).abs() < 1e-15 && (m[0][1] + 1.0).abs() < 1e-15 && (m[1][0] - 1.0).abs() < 1e-15
    );
    assert_eq!(m[3], vec![0.0, 0.0, 0.0, 1.0]);
    let m = matrix(&eval(&mut i, "transform(prismatic([1,0,0]), 0.25)"));
    assert!((m[0][3] - 0.25).abs() < 1e-15);
    let m = matrix(&eval(&mut i, "transform(elliptic(2, 1), pi / 2)"));
    assert!((m[0][3] - 2.0).abs() < 1e-15 && m[1][3].abs() < 1e-15);
    for src in [
        "helical([0,0,1], 0.01)",
        "cylindrical([0,1,0])",
        "universal([1,0,0], [0,1,0])",
        "spherical()",
        "spherical(order: \"zxz\")",
        "planar()",
        "fixed()",
        "root6()",
    ] {
        let j = eval(&mut i, &format!("let j = {src}\nj"));
        let dof = num(&eval(&mut i, "j.dof")) as usize;
        let q = format!("[{}]", vec!["0.3"; dof].join(", "));
        let m = matrix(&eval(&mut i, &format!("transform(j, {q})")));
        assert_eq!(m.len(), 4, "{src}");
        let s = eval(&mut i, &format!("jacobian(j, {q})"));
        assert_eq!(s.as_list().unwrap().len(), dof, "{src}: {j:?}");
    }
}

#[test]
fn spline_joint_from_frames_and_knots() {
    let mut i = Interpreter::new();
    let src = r#"
let frames = [transform(revolute([0,0,1]), 0), transform(revolute([0,0,1]), 0.5),
              transform(revolute([0,0,1]), 1.0), transform(revolute([0,0,1]), 1.5),
              transform(revolute([0,0,1]), 2.0)]
let j = spline_joint(frames, [0, 0.5, 1, 1.5, 2])
transform(j, 2)
"#;
    let m = matrix(&eval(&mut i, src));
    // the clamped curve ends on the last frame: rotation by 2 rad about z
    assert!((m[0][0] - 2f64.cos()).abs() < 1e-12 && (m[1][0] - 2f64.sin()).abs() < 1e-12);
    // without knots: natural parameterization (steps = twist norms 0.5), so the
    // domain is [0, 2] and the curve ends on the last frame
    let d = eval(&mut i, "spline_joint(frames).domain");
    let d: Vec<f64> = d.as_list().unwrap().iter().map(num).collect();
    assert!(
        (d[0] - 0.0).abs() < 1e-15 && (d[1] - 2.0).abs() < 1e-12,
        "{d:?}"
    );
    let m = matrix(&eval(&mut i, "transform(spline_joint(frames), 2)"));
    assert!((m[0][0] - 2f64.cos()).abs() < 1e-12);
    // rotation about z only, for every q: the curve stays in the frames' one-parameter subgroup
    let m = matrix(&eval(&mut i, "transform(spline_joint(frames), 1.25)"));
    assert!((m[2][2] - 1.0).abs() < 1e-12 && m[0][3].abs() < 1e-12);
    // frames π apart are refused with a message
    let e = i
        .eval_str("spline_joint([transform(revolute([0,0,1]), 0), transform(revolute([0,0,1]), pi), transform(revolute([0,0,1]), 0), transform(revolute([0,0,1]), pi)], [0,1,2,3])")
        .unwrap_err();
    assert!(
        e.render_plain().contains("intermediate frame"),
        "{}",
        e.render_plain()
    );
}

#[test]
fn bad_input_is_a_diagnostic() {
    let mut i = Interpreter::new();
    for src in [
        "revolute([0,0,0])",
        "revolute([0,0])",
        "transform(revolute([0,0,1]), [1, 2])",
        "transform(3, 1)",
        "elliptic(-1, 2)",
        "spherical(order: \"abc\")",
        "universal([1,0,0], [2,0,0])",
        "fixed([[1,0,0,0],[0,2,0,0],[0,0,1,0],[0,0,0,1]])",
    ] {
        assert!(i.eval_str(src).is_err(), "{src} should fail");
    }
}

#[test]
fn knee_forms_as_written_in_the_issue() {
    for path in common::shared_files("opensim", "_samples.json") {
        let mut i = Interpreter::new();
        let p = path.display().to_string().replace('\\', "/");
        eval(&mut i, &format!("let samples = load_samples(\"{p}\")"));
        eval(&mut i, "let j = fit_spline_joint(samples, frames: 12)");
        let e = eval(&mut i, "joint_error(j, samples)");
        let r = e.as_record().expect("record");
        let (mm, deg) = (num(&r["max_mm"]), num(&r["max_deg"]));
        println!(
            "{}: 12 frames: max {mm:.4} mm, {deg:.5}°, rms {:.4} mm",
            path.display(),
            num(&r["rms_mm"])
        );
        assert!(mm <= 0.1 && deg <= 0.05);
        for k in ["rms_mm", "rms_deg"] {
            assert!(num(&r[k]).is_finite());
        }
        // smoothing is optional and named
        eval(
            &mut i,
            "let js = fit_spline_joint(samples, frames: 8, smooth: 0.001)",
        );
        let m = matrix(&eval(&mut i, "transform(js, -1)"));
        assert_eq!(m.len(), 4);
        // the exact OpenSim joint from the samples file
        eval(&mut i, &format!("let k = opensim_joint(\"{p}\")"));
        let e = eval(&mut i, "joint_error(k, samples)");
        assert!(num(&e.as_record().unwrap()["max_mm"]) < 1e-9);
        assert!(i.eval_str("fit_spline_joint(samples, frames: 2)").is_err());
        assert!(
            i.eval_str("fit_spline_joint(samples, frames: 8, smooth: 1.5)")
                .is_err()
        );
    }
}
