//! glTF in and out: every shared clip saved as .glb passes the Khronos
//! validator with 0 errors and loads back with every joint within 1e-6 m of
//! the original at every frame; the language's forms as the issue writes them.

use crate::common;

use mx::io::gltf::{self, Clip, Which};
use mx::lang::interpreter::Interpreter;
use mx::mocap::{Missing, bvh::Units, positions};
use std::path::{Path, PathBuf};
use std::process::Command;

pub(crate) fn quote(p: &Path) -> String {
    format!("{:?}", p.to_string_lossy())
}

/// The npm `gltf-validator` package's `node_modules` folder (`scripts/test`
/// installs it into `target/gltf-validator`; `MX_GLTF_VALIDATOR` moves it).
/// `None` (with a note) on a developer machine without it or without node;
/// a panic in CI, where it must be there.
pub(crate) fn validator() -> Option<PathBuf> {
    let dir = std::env::var_os("MX_GLTF_VALIDATOR")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            Path::new(env!("CARGO_MANIFEST_DIR")).join("target/gltf-validator/node_modules")
        });
    let node = Command::new("node")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if node && dir.join("gltf-validator").is_dir() {
        return Some(dir);
    }
    let msg = format!(
        "the glTF validator is not at {} (or node is missing); scripts/test installs it",
        dir.display()
    );
    assert!(!common::in_ci(), "{msg}: required in CI");
    eprintln!("SKIPPED: {msg}");
    None
}

/// The validator's report on `file`: (errors, warnings, the messages).
pub(crate) fn validate(modules: &Path, file: &Path) -> (u64, u64, String) {
    const SCRIPT: &str = r#"
const fs = require("fs");
const v = require("gltf-validator");
const f = process.argv[1];
v.validateBytes(new Uint8Array(fs.readFileSync(f)), { uri: f, maxIssues: 50 })
  .then(r => console.log(JSON.stringify(r.issues)))
  .catch(e => { console.error(String(e)); process.exit(2); });
"#;
    let out = Command::new("node")
        .env("NODE_PATH", modules)
        .arg("-e")
        .arg(SCRIPT)
        .arg(file)
        .output()
        .expect("node runs");
    assert!(
        out.status.success(),
        "validator failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let issues: serde_json::Value = serde_json::from_slice(&out.stdout).expect("validator JSON");
    let messages = issues["messages"]
        .as_array()
        .map(|m| {
            m.iter()
                .map(|x| format!("{} {} {}", x["code"], x["pointer"], x["message"]))
                .collect::<Vec<_>>()
                .join("\n")
        })
        .unwrap_or_default();
    (
        issues["numErrors"].as_u64().unwrap(),
        issues["numWarnings"].as_u64().unwrap(),
        messages,
    )
}

/// Largest distance (m) between the joints of `a` and the joints of the same
/// name in `b`, over all frames; every joint of `a` must be in `b`.
fn max_joint_distance(a: &mx::mocap::Positions, b: &mx::mocap::Positions) -> f64 {
    assert_eq!(a.times.len(), b.times.len(), "frame counts differ");
    let mut worst = 0.0f64;
    for (j, name) in a.names.iter().enumerate() {
        let k = b
            .names
            .iter()
            .position(|n| n == name)
            .unwrap_or_else(|| panic!("joint {name} lost"));
        for (fa, fb) in a.points.iter().zip(&b.points) {
            worst = worst.max((fa[j] - fb[k]).norm());
        }
    }
    worst
}

#[test]
fn shared_clips_as_glb_validate_and_load_back_within_a_micron() {
    let files = common::shared_files("mocap", ".bvh");
    let checker = validator();
    let dir = tempfile::tempdir().unwrap();
    for f in &files {
        let name = f.file_stem().unwrap().to_string_lossy().to_string();
        let clip = mx::mocap::load(f, Units::Auto).unwrap();
        let (body, _) =
            mx::mocap::body_of(&clip.skeleton, 70.0, clip.units.metres_per_unit).unwrap();
        let out = dir.path().join(format!("{name}.glb"));
        gltf::save(
            &body,
            &[Clip {
                name: &name,
                motion: &clip.mu,
            }],
            None,
            &out,
        )
        .unwrap();
        if let Some(m) = &checker {
            let (errors, warnings, messages) = validate(m, &out);
            assert_eq!(errors, 0, "{name}: {messages}");
            eprintln!("{name}: validator 0 errors, {warnings} warnings");
        }
        let back = gltf::load(&out, Which::First).unwrap();
        assert_eq!(back.animation, name);
        assert_eq!(back.clip.frames, clip.frames, "{name}");
        assert!(
            (back.clip.frame_time - clip.frame_time).abs() < 1e-9 * clip.frame_time.max(1.0) + 1e-7,
            "{name}"
        );
        let (body2, _) = mx::mocap::body_of(&back.clip.skeleton, 70.0, 1.0).unwrap();
        let p1 = positions(&clip.mu, &body, None, Missing::Error).unwrap();
        let p2 = positions(&back.clip.mu, &body2, None, Missing::Error).unwrap();
        let d = max_joint_distance(&p1, &p2);
        eprintln!(
            "{name}: {} frames, {} joints, max joint distance {d:.2e} m",
            p1.times.len(),
            p1.names.len()
        );
        assert!(
            d <= 1e-6,
            "{name}: joints {d} m apart after a .glb round trip"
        );
    }
}

#[test]
fn the_issue_forms_and_several_animations() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/data");
    let dir = tempfile::tempdir().unwrap();
    let out = |n: &str| quote(&dir.path().join(n));
    let mut i = Interpreter::new();
    let src = format!(
        r#"
let m = load({walk})
let b = body_of(m)
save(m, {glb}, body: b)
save(m, {gltf}, body: b)
save([m, clip(0s, 1s, m)], {two}, body: b, names: ["walk", "first second"])
let g = load({glb})
let t = load({gltf})
let s = load({two}, animation: "first second")
let s1 = load({two}, animation: 1)
[frames(m), frame_time(m), frames(g), frame_time(g), frames(t), frames(s), frames(s1), len(dofs(g))]
"#,
        walk = quote(&data.join("walk.bvh")),
        glb = out("walk.glb"),
        gltf = out("walk.gltf"),
        two = out("two.glb"),
    );
    let v = i
        .eval_str(&src)
        .unwrap_or_else(|d| panic!("{}", d.render_plain()));
    let n: Vec<f64> = v
        .as_list()
        .unwrap()
        .iter()
        .map(|x| x.as_number().unwrap())
        .collect();
    assert_eq!(n[0], 61.0, "walk.bvh has 61 frames");
    assert!((n[1] - 1.0 / 30.0).abs() < 1e-15);
    assert_eq!(n[2], 61.0);
    assert!(
        (n[3] - 1.0 / 30.0).abs() < 1e-15,
        "30 fps recovered from f32 key times: {}",
        n[3]
    );
    assert_eq!(n[4], 61.0, ".gltf (embedded buffer) reads as .glb does");
    assert_eq!(n[5], 31.0, "the second animation: 1 s at 30 fps");
    assert_eq!(n[6], 31.0);
    assert!(n[7] >= 3.0 * 10.0);
    // .gltf is one self-contained JSON file.
    let text = std::fs::read_to_string(dir.path().join("walk.gltf")).unwrap();
    assert!(text.contains("data:application/octet-stream;base64,"));
    if let Some(m) = validator() {
        for f in ["walk.glb", "walk.gltf", "two.glb"] {
            let (errors, _, messages) = validate(&m, &dir.path().join(f));
            assert_eq!(errors, 0, "{f}: {messages}");
        }
    }
}

#[test]
fn bad_glb_input_is_an_error_not_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    let mut i = Interpreter::new();
    let cases: [(&str, &[u8], &str); 4] = [
        ("empty.glb", b"", "not a valid glTF"),
        ("header.glb", b"glTF\x02\0\0\0\x0c\0\0\0", "not a valid glTF"),
        ("static.gltf", br#"{"asset":{"version":"2.0"},"nodes":[{"name":"a"}],"scenes":[{"nodes":[0]}]}"#, "no animation"),
        (
            "noskin.gltf",
            br#"{"asset":{"version":"2.0"},"nodes":[{"name":"a"}],"buffers":[{"byteLength":8,"uri":"data:application/octet-stream;base64,AAAAAAAAgD8="}],
                "bufferViews":[{"buffer":0,"byteLength":8}],
                "accessors":[{"bufferView":0,"componentType":5126,"count":2,"type":"SCALAR","min":[0],"max":[1]}],
                "animations":[{"samplers":[{"input":0,"output":0}],"channels":[{"sampler":0,"target":{"node":0,"path":"weights"}}]}]}"#,
            "",
        ),
    ];
    for (name, bytes, expect) in cases {
        let p = dir.path().join(name);
        std::fs::write(&p, bytes).unwrap();
        let e = i
            .eval_str(&format!("load({})", quote(&p)))
            .unwrap_err()
            .render_plain();
        assert!(e.contains(expect), "{name}: {e}");
    }
    // Saving needs a body when no loaded clip names the motion's DOFs.
    let e = i
        .eval_str(r#"save(mu({"a.Xrotation": interval(fn(t) = t, 0s, 1s)}), "x.glb")"#)
        .unwrap_err()
        .render_plain();
    assert!(e.contains("skeleton") || e.contains("body"), "{e}");
    assert!(!dir.path().join("x.glb").exists());
}

#[test]
fn blenders_own_importer_puts_every_joint_within_a_millimetre() {
    let files = common::shared_files("mocap", ".bvh");
    let Some(py) = common::blender_python() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let mut args = Vec::new();
    for f in &files {
        let name = f.file_stem().unwrap().to_string_lossy().to_string();
        let clip = mx::mocap::load(f, Units::Auto).unwrap();
        let (body, _) =
            mx::mocap::body_of(&clip.skeleton, 70.0, clip.units.metres_per_unit).unwrap();
        let glb = dir.path().join(format!("{name}.glb"));
        gltf::save(
            &body,
            &[Clip {
                name: &name,
                motion: &clip.mu,
            }],
            None,
            &glb,
        )
        .unwrap();
        let p = positions(&clip.mu, &body, None, Missing::Error).unwrap();
        let json = serde_json::json!({
            "times": p.times,
            "names": p.names,
            "points": p.points.iter().map(|fr| fr.iter().map(|v| [v.x, v.y, v.z]).collect::<Vec<_>>()).collect::<Vec<_>>(),
        });
        let pos = dir.path().join(format!("{name}.json"));
        std::fs::write(&pos, json.to_string()).unwrap();
        args.push(glb);
        args.push(pos);
    }
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/it/blender/gltf_joints.py");
    let out = Command::new(&py)
        .arg(&script)
        .args(&args)
        .output()
        .expect("runs Blender's Python");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let results: Vec<&str> = stdout
        .lines()
        .filter(|l| l.starts_with("RESULT "))
        .collect();
    assert_eq!(results.len(), files.len(), "{stdout}");
    for line in results {
        let w: Vec<&str> = line.split_whitespace().collect();
        let (worst, missing): (f64, usize) = (w[2].parse().unwrap(), w[3].parse().unwrap());
        eprintln!("Blender import of {}: worst joint {worst:.2e} m", w[1]);
        assert_eq!(missing, 0, "{line}: bones missing");
        assert!(worst <= 1e-3, "{line}: a joint is more than 1 mm off");
    }
}

/// The body and the clock travel with the motion: `body_of(load(glb))` is the
/// saved body (its masses and inertias in the nodes' `extras`), so the torque
/// energy of the loaded motion on it is the original's within 0.1 %; and the
/// frames come back on the file's grid, so the original's last frame time is
/// a time of the loaded motion (f32 key times read as is put it 2e-7 s early).
#[test]
fn glb_keeps_the_body_and_the_frame_grid() {
    let files = common::shared_files("mocap", ".bvh");
    let dir = tempfile::tempdir().unwrap();
    for f in &files {
        let name = f.file_stem().unwrap().to_string_lossy().to_string();
        let out = dir.path().join(format!("{name}.glb"));
        let mut i = Interpreter::new();
        let src = format!(
            "let m = load({f})\n\
             let b = body_of(m, mass: 80)\n\
             save(m, {out}, body: b)\n\
             let g = load({out})\n\
             let t = (frames(m) - 1) * frame_time(m)\n\
             let undefined = sum(map(values(sample(g, t)), fn(v) = if v == nil {{ 1 }} else {{ 0 }}))\n\
             [torque_energy(m, b), torque_energy(g, body_of(g)), frame_time(m), frame_time(g), undefined, len(dofs(m)), len(dofs(g))]",
            f = quote(f),
            out = quote(&out),
        );
        let v = i
            .eval_str(&src)
            .unwrap_or_else(|d| panic!("{name}: {}", d.render_plain()));
        let n: Vec<f64> = v
            .as_list()
            .unwrap()
            .iter()
            .map(|x| x.as_number().unwrap())
            .collect();
        let rel = (n[1] - n[0]) / n[0];
        eprintln!(
            "{name}: torque energy {:.6e} → {:.6e} ({rel:+.2e}), frame time {} → {}, DOFs {} → {}",
            n[0], n[1], n[2], n[3], n[5], n[6]
        );
        assert!(
            rel.abs() < 1e-3,
            "{name}: torque energy {rel:+.2e} relative"
        );
        assert_eq!(n[3], n[2], "{name}: frame time off the file's grid");
        assert_eq!(n[4], 0.0, "{name}: DOFs undefined at the last frame time");
    }
}
