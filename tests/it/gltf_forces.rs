//! A glTF round trip keeps the contact forces (issue 44, item 4): every
//! shared clip saved with its `ground_forces` passes the Khronos validator
//! and gives them back number for number (f64 in `extras`), on the frames
//! the animation is read on; a z-up copy of every walk keeps them in its own
//! up; a save without forces is the file it was; malformed forces are an
//! error naming the file and the field; the language's and Python's forms.

use crate::common;
use crate::gltf::{quote, validate, validator};
use mx::ground::{self, ForceSeries, GroundForces, GroundOptions};
use mx::io::gltf::{self, Clip, Container, Which};
use mx::lang::host::Motion;
use mx::lang::interpreter::Interpreter;
use mx::mocap::bvh::Units;
use mx::model::Model;
use mx::motion::Mu;
use mx::report::heldout::rotated_up;
use mx::report::inbetween::Case;
use nalgebra::Vector3;
use std::path::Path;

/// Saves `m` on `body` with `g` as `out`, checks it with the validator when
/// there is one, and reads the forces back.
fn round_trip(name: &str, m: &Mu, body: &Model, g: &GroundForces, out: &Path) -> gltf::SavedForces {
    let clip = Clip { name, motion: m };
    gltf::save_with_forces(body, &[clip], &[Some(&g.series())], None, out).unwrap();
    if let Some(v) = validator() {
        let (errors, _, messages) = validate(&v, out);
        assert_eq!(errors, 0, "{name}: {messages}");
    }
    gltf::load_forces(out, Which::First).unwrap()
}

/// The forces read back are the written ones exactly, one per frame of the
/// animation as `load` reads it, on its grid from 0 s; and the motion
/// `load(…, forces: true)` makes of them gives each number at its frame.
fn assert_kept(name: &str, g: &GroundForces, back: &gltf::SavedForces, out: &Path) {
    let s = &back.series;
    let written = g.series();
    assert_eq!(back.animation, name);
    assert_eq!(s.points, written.points, "{name}");
    assert_eq!(s.forces, written.forces, "{name}: forces");
    assert_eq!(s.residual_force, written.residual_force, "{name}");
    assert_eq!(s.residual_moment, written.residual_moment, "{name}");
    assert_eq!(s.percent_bw, written.percent_bw, "{name}");
    let loaded = gltf::load(out, Which::First).unwrap().clip;
    assert_eq!(s.times.len(), loaded.frames, "{name}: one per frame");
    assert_eq!(s.frame_time, loaded.frame_time, "{name}: the loaded grid");
    for (k, (t, w)) in s.times.iter().zip(&written.times).enumerate() {
        assert_eq!(*t, k as f64 * loaded.frame_time);
        assert!(
            (t - (w - written.times[0])).abs() < 1e-9,
            "{name}: frame {k}"
        );
    }
    let mu = s.to_motion().unwrap();
    let again = ForceSeries::from_motion(&mu, &s.times, s.frame_time).unwrap();
    assert_eq!(&again, s, "{name}: the motion's samples");
}

#[test]
fn every_shared_clip_keeps_its_forces_through_a_glb() {
    let files = common::shared_files("mocap", ".bvh");
    let dir = tempfile::tempdir().unwrap();
    for f in &files {
        let name = f.file_stem().unwrap().to_string_lossy().to_string();
        let clip = mx::mocap::load(f, Units::Auto).unwrap();
        let (body, _) =
            mx::mocap::body_of(&clip.skeleton, 70.0, clip.units.metres_per_unit).unwrap();
        let g = ground::ground_forces(&clip.mu, &body, &GroundOptions::default(), 0.8).unwrap();
        let out = dir.path().join(format!("{name}.glb"));
        let back = round_trip(&name, &clip.mu, &body, &g, &out);
        assert_kept(&name, &g, &back, &out);
        assert_eq!(back.up, Some(g.up), "{name}");
        let plain = gltf::to_bytes(
            &body,
            &[Clip {
                name: &name,
                motion: &clip.mu,
            }],
            None,
            Container::Binary,
        )
        .unwrap();
        let with = std::fs::metadata(&out).unwrap().len() as f64;
        eprintln!(
            "{name}: {} frames × {} points kept exactly; file {:.0} kB, {:.2}× without forces",
            g.times.len(),
            g.points.len(),
            with / 1e3,
            with / plain.len() as f64
        );
    }
}

/// A z-up copy of every walk (`rotated_up`): its forces come back as
/// written, `up` is the body's (+z), the loaded body stands on −z gravity,
/// and the forces hold it up along z: over the walk the contact forces and
/// the residual average the body's weight along up, and nothing along y.
#[test]
fn a_z_up_walk_keeps_its_forces_in_its_own_up() {
    let walks: Vec<_> = common::shared_files("inbetween", ".bvh")
        .into_iter()
        .filter(|p| {
            p.file_stem()
                .is_some_and(|s| s.to_string_lossy().contains("walk"))
        })
        .collect();
    let dir = tempfile::tempdir().unwrap();
    for path in &walks {
        let up = rotated_up(&Case::load(path).unwrap()).unwrap();
        let g =
            ground::ground_forces(&up.capture, &up.body, &GroundOptions::default(), 0.8).unwrap();
        assert_eq!(g.up, Vector3::z(), "{}", up.name);
        let out = dir.path().join(format!("{}.glb", up.name));
        let back = round_trip(&up.name, &up.capture, &up.body, &g, &out);
        assert_kept(&up.name, &g, &back, &out);
        assert_eq!(back.up, Some(Vector3::z()), "{}", up.name);
        let loaded = gltf::load(&out, Which::First).unwrap().clip;
        let (body, _) = mx::mocap::body_of_motion(&loaded.skeleton, &loaded.mu, 70.0, 1.0).unwrap();
        assert_eq!(
            ground::up_of(&body.default_gravity),
            back.up,
            "{}: the loaded body's up",
            up.name
        );
        let s = &back.series;
        let mean: Vector3<f64> = (0..s.times.len())
            .map(|k| s.forces[k].iter().sum::<Vector3<f64>>() + s.residual_force[k])
            .sum::<Vector3<f64>>()
            / s.times.len() as f64;
        eprintln!(
            "{}: mean external force {:.1} N for a weight of {:.1} N",
            up.name, mean, g.weight
        );
        // a walk starts and ends at about the same vertical speed: the mean
        // vertical force is its weight (within 10 %), the mean horizontal
        // one far less
        assert!((mean.z / g.weight - 1.0).abs() < 0.1, "{}: {mean}", up.name);
        assert!(mean.y.abs() < 0.1 * g.weight, "{}: {mean}", up.name);
    }
}

/// The language's forms: `forces: true` and `forces: ground_forces(m, b)`
/// write the same file, `load(…, forces: true)` gives ground_forces(m, b)
/// back; without `forces:` (or with `forces: false`) the file is the one
/// the plain writer makes, with no forces in it.
#[test]
fn the_language_saves_and_loads_the_forces() {
    let walk = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/data/walk.bvh");
    let dir = tempfile::tempdir().unwrap();
    let out = |n: &str| quote(&dir.path().join(n));
    let mut i = Interpreter::new();
    let src = format!(
        r#"
let m = load({walk})
let b = body_of(m)
save(m, {plain}, names: ["walk"], body: b)
save(m, {off}, names: ["walk"], body: b, forces: false)
save(m, {on}, names: ["walk"], body: b, forces: true)
save(m, {given}, names: ["walk"], body: b, forces: ground_forces(m, b))
save([m, clip(0s, 1s, m)], {two}, body: b, names: ["walk", "first second"], forces: [true, false])
save(m, {fast}, body: b, rate: 60, forces: true)
[ground_forces(m, b), load({on}, forces: true), load({two}, animation: "walk", forces: true), frames(load({fast})), frames(load({fast}, forces: true))]
"#,
        walk = quote(&walk),
        plain = out("plain.glb"),
        off = out("off.glb"),
        on = out("on.glb"),
        given = out("given.glb"),
        two = out("two.glb"),
        fast = out("fast.glb"),
    );
    let v = i
        .eval_str(&src)
        .unwrap_or_else(|d| panic!("{}", d.render_plain()));
    let items = v.as_list().unwrap();
    let mu = |k: usize| match items[k].as_object::<Motion>() {
        Some(Motion::Mu(m)) => m.clone(),
        _ => panic!("item {k} is not a motion"),
    };
    let (computed, loaded, first) = (mu(0), mu(1), mu(2));
    let names: Vec<&str> = computed.names().collect();
    assert_eq!(loaded.names().collect::<Vec<_>>(), names);
    assert_eq!(first.names().collect::<Vec<_>>(), names);
    let dt = mx::motion::sample_period(&computed).unwrap();
    let frames = (computed.span().unwrap().1 / dt).round() as usize + 1;
    for n in &names {
        for k in 0..frames {
            let t = k as f64 * dt;
            let want = computed.sample_value(n, t).unwrap().unwrap();
            assert_eq!(loaded.sample_value(n, t).unwrap(), Some(want), "{n} at {t}");
            assert_eq!(first.sample_value(n, t).unwrap(), Some(want), "{n} at {t}");
        }
    }
    let f60 = items[3].as_number();
    assert!(f60.is_some());
    assert_eq!(
        items[4].as_number(),
        f60,
        "60 Hz forces on the 60 Hz frames"
    );
    let read = |n: &str| std::fs::read(dir.path().join(n)).unwrap();
    assert_eq!(
        read("on.glb"),
        read("given.glb"),
        "forces: true is ground_forces(m, b)"
    );
    assert_eq!(read("plain.glb"), read("off.glb"));
    assert!(!String::from_utf8_lossy(&read("plain.glb")).contains("\"forces\""));
    assert!(String::from_utf8_lossy(&read("on.glb")).contains("\"forces\""));
    let clip = mx::mocap::load(&walk, Units::Auto).unwrap();
    let (body, _) = mx::mocap::body_of(&clip.skeleton, 70.0, clip.units.metres_per_unit).unwrap();
    let bytes = gltf::to_bytes(
        &body,
        &[Clip {
            name: "walk",
            motion: &clip.mu,
        }],
        None,
        Container::Binary,
    )
    .unwrap();
    assert_eq!(
        read("plain.glb"),
        bytes,
        "a save without forces is the plain writer's"
    );
    // 60 Hz: the forces computed on the animation's 60 Hz frames
    let fast = gltf::load_forces(&dir.path().join("fast.glb"), Which::First).unwrap();
    let fast_clip = gltf::load(&dir.path().join("fast.glb"), Which::First)
        .unwrap()
        .clip;
    assert_eq!(fast.series.times.len(), fast_clip.frames);
    assert_eq!(Some(fast_clip.frames as f64), f60);
    // the second animation carries none; forces on another grid are refused
    for (bad, says) in [
        (
            format!("load({}, animation: 1, forces: true)", out("two.glb")),
            "carries no contact forces",
        ),
        (
            format!(
                "save(m, {}, body: b, rate: 60, forces: ground_forces(m, b))",
                out("x.glb")
            ),
            "compute them at the rate saved",
        ),
        (
            format!("save(m, {}, body: b, forces: m)", out("x.glb")),
            "no contact force",
        ),
        (
            format!("save(m, {}, body: b, forces: 3)", out("x.glb")),
            "forces",
        ),
        (
            format!("save([m, m], {}, body: b, forces: [true])", out("x.glb")),
            "one per motion",
        ),
        (format!("load({}, forces: 1)", out("on.glb")), "forces"),
    ] {
        let e = i.eval_str(&bad).unwrap_err().error().message.clone();
        assert!(e.contains(says), "{bad}: {e}");
    }
    assert!(!dir.path().join("x.glb").exists());
}

/// Malformed forces extras: `load(…, forces: true)` names the file and the
/// field; a plain `load` reads the motion as before.
#[test]
fn malformed_forces_are_an_error_naming_the_file_and_field() {
    let walk = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/data/walk.bvh");
    let clip = mx::mocap::load(&walk, Units::Auto).unwrap();
    let (body, _) = mx::mocap::body_of(&clip.skeleton, 70.0, clip.units.metres_per_unit).unwrap();
    let g = ground::ground_forces(&clip.mu, &body, &GroundOptions::default(), 0.8).unwrap();
    let bytes = gltf::to_bytes_with_forces(
        &body,
        &[Clip {
            name: "walk",
            motion: &clip.mu,
        }],
        &[Some(&g.series())],
        None,
        Container::Embedded,
    )
    .unwrap();
    let doc: serde_json::Value = serde_json::from_slice(&bytes).unwrap();
    let dir = tempfile::tempdir().unwrap();
    type Edit = fn(&mut serde_json::Value);
    let cases: [(&str, Edit, &str); 9] = [
        (
            "absent",
            |f| *f = serde_json::Value::Null,
            "carries no contact forces",
        ),
        ("number", |f| *f = 5.into(), "forces.points: missing"),
        (
            "points",
            |f| f["points"] = "LeftFoot".into(),
            "forces.points: not an array",
        ),
        (
            "one_point",
            |f| f["forces"][3] = serde_json::json!([[0, 1, 0]]),
            "forces.forces[3]: 1 items",
        ),
        (
            "text",
            |f| f["forces"][2][1][1] = "up".into(),
            "forces.forces[2][1][1]: not a finite number",
        ),
        (
            "short",
            |f| {
                f["times"].as_array_mut().unwrap().pop();
            },
            "forces.times: 60 items",
        ),
        ("late", |f| f["times"][5] = 1.0.into(), "forces.times[5]"),
        (
            "residual",
            |f| {
                f["residual"]
                    .as_object_mut()
                    .unwrap()
                    .remove("moment")
                    .map(|_| ())
                    .unwrap()
            },
            "forces.residual.moment: missing",
        ),
        (
            "percent",
            |f| f["residual"]["percent_bw"][0] = serde_json::Value::Null,
            "forces.residual.percent_bw[0]",
        ),
    ];
    let mut i = Interpreter::new();
    for (name, edit, says) in cases {
        let mut d = doc.clone();
        edit(&mut d["animations"][0]["extras"]["mx"]["forces"]);
        let path = dir.path().join(format!("{name}.gltf"));
        std::fs::write(&path, serde_json::to_vec(&d).unwrap()).unwrap();
        let e = gltf::load_forces(&path, Which::First)
            .unwrap_err()
            .to_string();
        assert!(e.contains(says), "{name}: {e}");
        assert!(e.contains(&format!("{name}.gltf")), "{name}: the file: {e}");
        assert!(e.contains("animations[0].extras.mx.forces"), "{name}: {e}");
        let e = i
            .eval_str(&format!("load({}, forces: true)", quote(&path)))
            .unwrap_err()
            .error()
            .message
            .clone();
        assert!(e.contains(says), "{name}: {e}");
        // the motion itself still loads
        let frames = i
            .eval_str(&format!("frames(load({}))", quote(&path)))
            .unwrap_or_else(|d| panic!("{name}: {}", d.render_plain()));
        assert_eq!(frames.as_number(), Some(61.0), "{name}");
    }
}
