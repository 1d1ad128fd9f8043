//! The mocap built-ins as written in the issue: load, save, body_of,
//! positions, plot, view, and BVH errors as diagnostics.

use crate::common;

use mx::lang::interpreter::Interpreter;
use std::path::Path;

fn quote(p: &Path) -> String {
    format!("{:?}", p.to_string_lossy())
}

#[test]
fn load_save_body_positions_plot_view_on_example_data() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/data");
    let dir = tempfile::tempdir().unwrap();
    let out = |n: &str| quote(&dir.path().join(n));
    let mut i = Interpreter::new();
    let src = format!(
        r#"
let walk = load({walk})
let v = sample(walk, 0.5)
save(walk, {again})
let again = load({again})
let body = body_of(walk, mass: 70)
let p = positions(walk, body)
plot(only(walk, "RightArm.*"), {svg})
view(walk, body, {html})
[sample(again, 0.5), v, body.mass, sample(p, 1.0)]
"#,
        walk = quote(&data.join("walk.bvh")),
        again = out("again.bvh"),
        svg = out("arm.svg"),
        html = out("walk.html"),
    );
    let v = i
        .eval_str(&src)
        .unwrap_or_else(|d| panic!("{}", d.render_plain()));
    let list = v.as_list().unwrap();
    let again = list[0].as_record().unwrap();
    let first = list[1].as_record().unwrap();
    // DOF names exactly as in the file; radians; load → save → load within 1e-6.
    let rz = first["RightForeArm.Yrotation"].as_number().unwrap();
    assert!((rz - 15f64.to_radians()).abs() < 0.2, "{rz}");
    for (k, a) in first {
        let b = again[k].as_number().unwrap();
        assert!((a.as_number().unwrap() - b).abs() < 1e-6, "{k}");
    }
    assert!(first.contains_key("Hips.Xposition"));
    assert!((list[2].as_number().unwrap() - 70.0).abs() < 1e-9);
    // Hips at 1 s: walked 1.2 m forward (z), hip height ≈ 0.9 m.
    let p = list[3].as_record().unwrap();
    assert!((p["Hips.z"].as_number().unwrap() - 1.2).abs() < 1e-9);
    assert!((p["Hips.y"].as_number().unwrap() - 0.9).abs() < 0.05);
    assert!(
        std::fs::read_to_string(dir.path().join("arm.svg"))
            .unwrap()
            .contains("<svg")
    );
    assert!(
        std::fs::read_to_string(dir.path().join("walk.html"))
            .unwrap()
            .contains("mx-viewer")
    );
}

#[test]
fn shared_clip_dofs_are_named_as_in_the_file() {
    let Some(d) = common::shared_dir() else {
        return;
    };
    let mut i = Interpreter::new();
    let src = format!(
        "let m = load({})\nsample(m, 1.0)",
        quote(&d.join("data/mocap/cmu_131_01_start_walk_stop.bvh"))
    );
    let v = i
        .eval_str(&src)
        .unwrap_or_else(|d| panic!("{}", d.render_plain()));
    let r = v.as_record().unwrap();
    assert!(r.contains_key("RightElbow.Zrotation") && r.contains_key("Hips.Xposition"));
    // CMU units: hips about a metre high.
    let y = r["Hips.Yposition"].as_number().unwrap();
    assert!(y > 0.8 && y < 1.1, "{y}");
}

#[test]
fn malformed_bvh_is_a_diagnostic_with_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.bvh");
    std::fs::write(&bad, "HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nCHANNELS 1 Zrotation\n}\nMOTION\nFrames: 2\nFrame Time: 0.1\n1\nx\n").unwrap();
    let mut i = Interpreter::new();
    let d = i.eval_str(&format!("load({})", quote(&bad))).unwrap_err();
    let text = d.render_plain();
    assert!(
        text.contains("line 11, column 1") && text.contains("`x` is not a number"),
        "{text}"
    );
}

#[test]
fn human_and_fit_in_mx() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/data");
    let mut i = Interpreter::new();
    let out = i.capture_output();
    let src = format!(
        "let wave = load({})\nlet h = human(wave)\nlet m = fit(wave, h)\n[len(h.coordinates), sample(m, 1.0)]",
        quote(&data.join("wave.bvh"))
    );
    let v = i
        .eval_str(&src)
        .unwrap_or_else(|d| panic!("{}", d.render_plain()));
    let l = v.as_list().unwrap();
    assert_eq!(l[0].as_number(), Some(44.0));
    assert!(l[1].as_record().unwrap().contains_key("elbow_R.Yrotation"));
    let printed = String::from_utf8(out.lock().unwrap().clone()).unwrap();
    // fit notes its error on stderr: stdout carries only what the script prints
    assert!(!printed.contains("RMS error"), "{printed}");
}
