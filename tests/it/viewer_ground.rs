//! The viewer's ground layers in headless Chromium, each found on the page
//! where the engine says it is: the floor (the first motion's; a motion
//! below it drawn below), footprints at `sp_report(m).contacts`' anchors in
//! their source's colour, force arrows along `ground_forces`, the residual
//! at the centre of mass, the contact strip frame by frame against
//! `contacts(m, b)`; the address keeping layers, camera, zoom and follow;
//! the page's size and its playback rate with every layer on.

use crate::common::shared_files;
use crate::viewer_chromium::{check_page, field, open_page, page_data, view_walk, walk_path};
use mx::ground::{self, Floor, GroundOptions};
use mx::io::viewer::ground::{GroundRequest, Layer, ground_layer};
use mx::io::viewer::{html, overlay};
use mx::mocap::{self, bvh::Units};
use mx::motion::{Curve, Dof, Interval, Mu};
use serde_json::{Value as Json, json};
use std::path::Path;

/// Appends `body` (JavaScript that fills the array `out`) after the page's
/// own script, opens the page at `fragment` and returns `out`.
fn drive(page: &Path, fragment: &str, body: &str, virtual_time: bool) -> Json {
    drive_wide(page, fragment, body, virtual_time, 1000)
}

/// As [`drive`] in a window `width` px wide.
fn drive_wide(page: &Path, fragment: &str, body: &str, virtual_time: bool, width: u32) -> Json {
    let text = std::fs::read_to_string(page).unwrap();
    let driver = format!(
        "<script>\n(function () {{\n  const out = [];\n  const v = window.mxViewer;\n{body}\n  \
         const pre = document.createElement(\"pre\"); pre.id = \"mx-test\"; pre.textContent = JSON.stringify(out);\n  \
         document.body.appendChild(pre);\n}})();\n</script>\n</body>"
    );
    let driven = page.with_file_name("driven.html");
    std::fs::write(&driven, text.replacen("</body>", &driver, 1)).unwrap();
    let (dom, stderr) = open_page(&driven, fragment, virtual_time, width);
    let report = dom
        .split("<pre id=\"mx-test\">")
        .nth(1)
        .and_then(|t| t.split("</pre>").next())
        .unwrap_or_else(|| panic!("the driver did not run:\n{stderr}"))
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&amp;", "&");
    serde_json::from_str(&report).unwrap()
}

/// JavaScript: the RGB of the stage at `[x, y]` (page pixels).
const PIXEL: &str = "const pixel = (x, y) => Array.from(document.getElementById(\"stage\").getContext(\"2d\").getImageData(Math.round(x), Math.round(y), 1, 1).data).slice(0, 3);";

fn rgb(hex: &str) -> [f64; 3] {
    let c = |k: usize| u8::from_str_radix(&hex[k..k + 2], 16).unwrap() as f64;
    [c(1), c(3), c(5)]
}

fn near(px: &Json, hex: &str, tol: f64) -> bool {
    let want = rgb(hex);
    (0..3)
        .map(|k| (px[k].as_f64().unwrap() - want[k]).abs())
        .sum::<f64>()
        < tol
}

fn walk() -> (Mu, mx::model::Model) {
    let clip = mocap::load(Path::new(&walk_path()), Units::Auto).unwrap();
    let (body, _) = mocap::body_of(&clip.skeleton, 70.0, clip.units.metres_per_unit).unwrap();
    (clip.mu, body)
}

/// `m` with `dof` moved by `by` (m) at every time.
fn shifted(m: &Mu, dof: &str, by: f64) -> Mu {
    let mut out = m.clone();
    let (t0, t1) = m.span().unwrap();
    let n = 200;
    let vals: Vec<f64> = (0..=n)
        .map(|k| {
            let t = t0 + (t1 - t0) * k as f64 / n as f64;
            m.sample(dof, t).unwrap().unwrap()[0] + by
        })
        .collect();
    let c = Curve::samples(t0, (t1 - t0) / n as f64, vals).unwrap();
    out.insert(
        dof.to_string(),
        Dof::new(vec![Interval::curve(c, t0, t1).unwrap()]).unwrap(),
    );
    out
}

/// A page of `motions` on the walk's body with the ground `layers`.
fn page_of(dir: &Path, motions: &[(&str, &Mu)], layers: &[Layer]) -> std::path::PathBuf {
    let (_, body) = walk();
    let mut data = overlay(&body, motions, "ground", &[]).unwrap();
    let request = GroundRequest {
        layers: layers.to_vec(),
        ..GroundRequest::default()
    };
    let plans = vec![None; motions.len()];
    data.ground = ground_layer(&body, motions, &data, &plans, &request).unwrap();
    let page = dir.join("ground.html");
    std::fs::write(&page, html(&data).unwrap()).unwrap();
    page
}

/// The floor is the first motion's, whatever the others do: a copy sunk
/// 3 cm shows 3 cm below it (ringed and named), and the floor's plane is
/// drawn where the page projects the floor (and not when the layer is off).
#[test]
fn the_floor_is_the_first_motions_and_what_sinks_shows_below_it() {
    let dir = tempfile::tempdir().unwrap();
    let (w, body) = walk();
    let sunk = shifted(&w, "Hips.Yposition", -0.03);
    let page = page_of(
        dir.path(),
        &[("capture", &w), ("sunk", &sunk)],
        &Layer::DEFAULT,
    );
    let floor = ground::contacts(&w, &body, &GroundOptions::default())
        .unwrap()
        .floor;
    let data = page_data(&page);
    assert_eq!(data["ground"]["floor"].as_f64().unwrap(), floor);
    // at the frame where the capture's lowest contact point is on the floor, the sunk copy's is 3 cm below
    let joints: Vec<usize> = data["ground"]["joint"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|j| j.as_u64())
        .map(|j| j as usize)
        .collect();
    let lowest = |k: usize| {
        joints
            .iter()
            .map(|&j| data["tracks"][0]["positions"][k][j][1].as_f64().unwrap())
            .fold(f64::INFINITY, f64::min)
    };
    let frames = data["times"].as_array().unwrap().len();
    let k = (0..frames)
        .min_by(|&a, &b| lowest(a).total_cmp(&lowest(b)))
        .unwrap();
    assert!(
        (lowest(k) - floor).abs() < 1e-9,
        "the page's floor is the capture's lowest contact point"
    );
    let t = data["times"][k].as_f64().unwrap();
    let title = check_page(&page, &format!("#view=side&t={t}"), 500);
    let below: f64 = field(&title, "below").parse().unwrap();
    assert!((below - 3.0).abs() < 0.06, "{title}");
    // a floor point beside the figure (a square's middle, off the grid lines): the
    // floor's shade with the layer, the background without
    let probe = format!(
        "{PIXEL}\n  v.go(0); const r = DATA.tracks[0].positions[0][0];\n  \
         const gx = Math.round(r[0] / 0.5) * 0.5 + 0.75, gz = Math.round(r[2] / 0.5) * 0.5 + 0.25;\n  \
         const p = v.project([gx, {floor}, gz]);\n  out.push(pixel(p[0], p[1]));"
    );
    let on = drive(&page, "#t=0", &probe, true);
    let off = drive(&page, "#ground=plan,contacts&t=0", &probe, true);
    assert!(near(&on[0], "#e9ecf0", 18.0), "floor pixel {on}");
    assert!(
        near(&off[0], "#fdfdfd", 6.0),
        "no floor: background, got {off}"
    );
    // the sunk copy is below the floor alone: lifted, nothing is below
    let lifted = shifted(&w, "Hips.Yposition", 0.05);
    let page = page_of(
        dir.path(),
        &[("capture", &w), ("lifted", &lifted)],
        &Layer::DEFAULT,
    );
    let title = check_page(&page, "#t=1", 500);
    assert_eq!(field(&title, "below"), "0.0", "{title}");
}

/// A language value (numbers, strings, lists, records) as JSON.
fn to_json(v: &mx::lang::value::Value) -> Json {
    use mx::lang::value::Value;
    match v {
        Value::Number(x) => json!(x),
        Value::Str(s) => json!(&**s),
        Value::Bool(b) => json!(b),
        Value::List(items) => Json::Array(items.iter().map(to_json).collect()),
        Value::Record(r) => Json::Object(r.iter().map(|(k, v)| (k.clone(), to_json(v))).collect()),
        _ => Json::Null,
    }
}

/// The record fields of `sp_report(m).contacts` as (point, from, to, at, source).
fn stances(plan: &mx::lang::value::Value) -> Vec<(String, f64, f64, [f64; 3], String)> {
    to_json(plan)
        .as_array()
        .unwrap()
        .iter()
        .map(|s| {
            let at: Vec<f64> = s["at"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect();
            (
                s["point"].as_str().unwrap().to_string(),
                s["from"].as_f64().unwrap(),
                s["to"].as_f64().unwrap(),
                [at[0], at[1], at[2]],
                s["source"].as_str().unwrap().to_string(),
            )
        })
        .collect()
}

/// SP's contact plan: the page embeds `sp_report(m).contacts` as it is, and
/// each footprint is drawn in its source's colour on the floor under its
/// anchor while its stance holds; the strip marks the plan.
#[test]
fn footprints_stand_at_the_plans_anchors_in_their_sources_colour() {
    // Bandai's walks: toe and ankle points, stances around a 0.5 s gap
    for clip in shared_files("mocap", ".bvh").into_iter().filter(|p| {
        p.to_string_lossy().contains("bandai") && p.to_string_lossy().contains("_walk_")
    }) {
        footprints_of(&clip);
    }
}

fn footprints_of(clip: &Path) {
    let dir = tempfile::tempdir().unwrap();
    let page = dir.path().join("plan.html");
    let mut mx = mx::Interpreter::new();
    let script = format!(
        "let w = load({:?})\nlet cut = w - clip_in_place(1s, 1.5s, w - w.only(\"joint_Root.*\"))\n\
         let f = SP(cut, body: body_of(w), coefficients: 3, samples: 8, contact: \"auto\")\n\
         let plan = sp_report(f).contacts\nview([cut, f], body_of(w), {:?}, labels: [\"capture\", \"SP\"])\n",
        clip.display().to_string(),
        page.display().to_string()
    );
    mx.eval_str(&script).unwrap();
    let plan = stances(&mx.get("plan").unwrap());
    assert!(!plan.is_empty(), "SP planned no stance");
    let data = page_data(&page);
    let g = &data["ground"];
    let points: Vec<&str> = g["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p.as_str().unwrap())
        .collect();
    let embedded = g["tracks"][1]["stances"].as_array().unwrap();
    assert_eq!(embedded.len(), plan.len());
    for (e, (point, from, to, at, source)) in embedded.iter().zip(&plan) {
        assert_eq!(
            points[e["point"].as_u64().unwrap() as usize],
            point.as_str()
        );
        assert_eq!(
            (e["t0"].as_f64().unwrap(), e["t1"].as_f64().unwrap()),
            (*from, *to)
        );
        let eat: Vec<f64> = e["at"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        assert_eq!(eat, at.to_vec());
        assert_eq!(e["source"].as_str().unwrap(), source.as_str());
    }
    // the capture (no plan) shows its own contacts
    assert!(g["tracks"][0]["stances"].as_array().unwrap().is_empty());
    let floor = g["floor"].as_f64().unwrap();
    let frame_time = data["frame_time"].as_f64().unwrap();
    let t0 = data["times"][0].as_f64().unwrap();
    let probes: Vec<Json> = plan
        .iter()
        .map(|(point, from, to, at, source)| {
            let mid = ((from + to) / 2.0 - t0) / frame_time;
            json!({"point": point, "frame": mid.round(), "at": at, "source": source})
        })
        .collect();
    let body = format!(
        "{PIXEL}\n  const probes = {};\n  const floor = {floor};\n  \
         for (const s of probes) {{\n    v.go(s.frame);\n    \
         const lit = v.drawn().prints.filter(p => p.track === 1 && p.point === s.point && p.source === s.source).length;\n    \
         const ring = [];\n    for (let k = 0; k < 8; k++) {{\n      const a = k / 8 * 2 * Math.PI;\n      \
         const q = v.project([s.at[0] + 0.045 * Math.cos(a), floor, s.at[2] + 0.045 * Math.sin(a)]);\n      \
         ring.push(pixel(q[0], q[1]));\n    }}\n    out.push({{ lit: lit, ring: ring, colour: v.colours.sources[s.source] }});\n  }}",
        Json::Array(probes)
    );
    let found = drive(&page, "#view=top&t=1", &body, true);
    for (f, (point, from, to, at, source)) in found.as_array().unwrap().iter().zip(&plan) {
        assert!(
            f["lit"].as_u64().unwrap() >= 1,
            "{point} [{from}, {to}] not lit: {f}"
        );
        // a footprint another source's overlaps (an ankle's and a toe's a few
        // cm apart) shows both colours on its ring: its colour is not probed
        let overlapped = plan.iter().any(|(_, _, _, b, s)| {
            s != source && ((at[0] - b[0]).powi(2) + (at[2] - b[2]).powi(2)).sqrt() < 0.12
        });
        if overlapped {
            continue;
        }
        let colour = f["colour"].as_str().unwrap();
        let hits = f["ring"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|px| near(px, colour, 90.0))
            .count();
        // the capture's own footprint at the same stance (#1f77b4, drawn for
        // the first motion) covers part of the ring where the two motions
        // stand at one place: the ring is the stance's colour and the capture's
        let capture = f["ring"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|px| near(px, "#1f77b4", 90.0))
            .count();
        assert!(
            hits >= 1 && hits + capture >= 5,
            "{point} {source} [{from}, {to}]: {hits}/8 of {colour} ({capture} the capture's) in {f}"
        );
    }
}

/// The force arrows are `ground_forces`' values to the precision embedded
/// (1 mN), drawn from each contact point along its force (body weight = half
/// the figure's height); a lifted body gets no arrows and its weight as a
/// red residual arrow at its centre of mass.
#[test]
fn force_and_residual_arrows_are_the_engines() {
    let dir = tempfile::tempdir().unwrap();
    let (w, body) = walk();
    let layers = [Layer::Floor, Layer::Forces, Layer::Residual];
    let page = page_of(dir.path(), &[("walk", &w)], &layers);
    let data = page_data(&page);
    let g = &data["ground"];
    let floor = g["floor"].as_f64().unwrap();
    let points: Vec<String> = g["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p.as_str().unwrap().to_string())
        .collect();
    let o = GroundOptions {
        floor: Floor::At(floor),
        points: Some(points.clone()),
        ..GroundOptions::default()
    };
    let engine = ground::ground_forces(&w, &body, &o, 0.8).unwrap();
    let frames = g["tracks"][0]["forces"]["frames"].as_array().unwrap();
    assert_eq!(frames.len(), engine.times.len());
    let mut strongest = (0, 0, 0.0);
    for (k, row) in frames.iter().enumerate() {
        let row: Vec<f64> = row
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        for (j, f) in engine.forces[k].iter().enumerate() {
            for c in 0..3 {
                assert!(
                    (row[3 * j + c] - f[c]).abs() <= 5e-4 + 1e-9,
                    "frame {k} point {j}"
                );
            }
            if f.norm() > strongest.2 {
                strongest = (k, j, f.norm());
            }
        }
        assert!((row[3 * points.len() + 9] - engine.percent_bw(k)).abs() <= 5e-4 + 1e-9);
    }
    let (k, j, _) = strongest;
    let from = engine.positions[k][j];
    let to = from + engine.forces[k][j] / engine.weight * 0.5 * page_height(&data);
    let body_js = format!(
        "{PIXEL}\n  v.go({k});\n  const a = v.project({:?}), b = v.project({:?});\n  \
         out.push(pixel((a[0] + b[0]) / 2, (a[1] + b[1]) / 2));\n  out.push(v.drawn().stats.arrows);",
        [from.x, from.y, from.z],
        [to.x, to.y, to.z]
    );
    let found = drive(&page, "#view=side", &body_js, true);
    assert!(near(&found[0], "#00a000", 30.0), "arrow pixel {found}");
    assert!(found[1].as_u64().unwrap() >= 1);
    // lifted 10 cm above the walk's floor: no arrows, the residual at the centre of mass
    let lifted = shifted(&w, "Hips.Yposition", 0.10);
    let mut data = overlay(&body, &[("lifted", &lifted)], "lifted", &[]).unwrap();
    let request = GroundRequest {
        layers: layers.to_vec(),
        floor: Some(floor),
        ..GroundRequest::default()
    };
    data.ground = ground_layer(&body, &[("lifted", &lifted)], &data, &[None], &request).unwrap();
    let page = dir.path().join("lifted.html");
    std::fs::write(&page, html(&data).unwrap()).unwrap();
    let o = GroundOptions {
        floor: Floor::At(floor),
        ..GroundOptions::default()
    };
    let e = ground::ground_forces(&lifted, &body, &o, 0.8).unwrap();
    let k = e.times.len() / 2;
    let com = e.com[k];
    let tip = com + e.residual_force[k] / e.weight * 0.5 * page_height(&page_data(&page));
    let body_js = format!(
        "{PIXEL}\n  v.go({k});\n  const a = v.project({:?}), b = v.project({:?});\n  \
         out.push(pixel(a[0] + (b[0] - a[0]) * 0.4, a[1] + (b[1] - a[1]) * 0.4));\n  out.push(v.drawn().stats);",
        [com.x, com.y, com.z],
        [tip.x, tip.y, tip.z]
    );
    let found = drive(&page, "#view=front", &body_js, true);
    assert!(near(&found[0], "#ff0000", 30.0), "residual pixel {found}");
    assert_eq!(found[1]["arrows"], 0);
    assert_eq!(found[1]["residual"], 1);
    // no contact: the residual is everything the motion needs
    assert!((e.residual_force[k] - e.needed[k]).norm() < 1e-9 * e.weight);
}

/// The figure's height the page scales arrows by: the first pose's highest
/// point over the floor.
fn page_height(data: &Json) -> f64 {
    let floor = data["ground"]["floor"].as_f64().unwrap();
    let up = data["up"].as_u64().unwrap() as usize;
    data["tracks"][0]["positions"][0]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p[up].as_f64().unwrap() - floor)
        .fold(0.0, f64::max)
}

/// On the capture of a walk (the example's and every shared clip of a walk),
/// frame by frame: the strip's bar for each point, the point's lit footprint
/// and `contacts(m, b)` all say the same. The window is wide enough for 3 px
/// a frame, so the strip's pixels resolve every frame.
#[test]
fn the_contact_strip_and_the_footprints_agree_with_contacts_frame_by_frame() {
    let mut clips = vec![Path::new(&walk_path()).to_path_buf()];
    clips.extend(
        shared_files("mocap", ".bvh")
            .into_iter()
            .filter(|p| p.to_string_lossy().contains("walk")),
    );
    let dir = tempfile::tempdir().unwrap();
    for path in &clips {
        let clip = mocap::load(path, Units::Auto).unwrap();
        let (body, _) = mocap::body_of(&clip.skeleton, 70.0, clip.units.metres_per_unit).unwrap();
        let c = ground::contacts(&clip.mu, &body, &GroundOptions::default()).unwrap();
        let page = dir.path().join("capture.html");
        let mut mx = mx::Interpreter::new();
        mx.eval_str(&format!(
            "view(load({:?}), body_of(load({:?})), {:?})",
            path.display().to_string(),
            path.display().to_string(),
            page.display().to_string()
        ))
        .unwrap();
        let data = page_data(&page);
        let times = data["times"].as_array().unwrap();
        assert_eq!(times.len(), c.times.len(), "{path:?}");
        let body_js = "  for (let k = 0; k < DATA.times.length; k++) {\n    \
             const rows = v.stripAt(k).filter(r => r.kind === \"contact\");\n    \
             const lit = v.drawn().prints.map(p => p.point);\n    \
             out.push(DATA.ground.points.map(function (name, j) {\n      \
             const px = rows.find(r => r.point === name).rgb;\n      \
             const bar = px[0] < 140 ? \"1\" : \"0\";\n      \
             return bar + (lit.includes(name) ? \"1\" : \"0\");\n    }).join(\",\"));\n  }";
        let width = (3 * times.len() + 400).max(1000) as u32;
        let found = drive_wide(&page, "", body_js, true, width);
        let found = found.as_array().unwrap();
        let names: Vec<&str> = data["ground"]["points"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| p.as_str().unwrap())
            .collect();
        for (k, row) in found.iter().enumerate() {
            let cells: Vec<&str> = row.as_str().unwrap().split(',').collect();
            for (j, name) in names.iter().enumerate() {
                let p = c.points.iter().find(|p| p.name == *name).unwrap();
                let want = if p.in_contact[k] { "11" } else { "00" };
                assert_eq!(
                    cells[j], want,
                    "{path:?} frame {k} {name}: strip+footprint {} vs contacts {}",
                    cells[j], p.in_contact[k]
                );
            }
        }
    }
}

/// The keys and the address: g/p/c/f/r toggle layers, h holds the camera,
/// the wheel zooms, and the address carries each (only where not the
/// default) and opens the page with them.
#[test]
fn layers_camera_zoom_and_follow_live_in_the_address() {
    let dir = tempfile::tempdir().unwrap();
    let page = dir.path().join("walk.html");
    view_walk(
        "view(w, body_of(w), PAGE, ground: [\"plan\", \"forces\", \"residual\", \"floor\", \"contacts\"])",
        &page,
    );
    let body = "  const key = k => document.dispatchEvent(new KeyboardEvent(\"keydown\", { key: k }));\n  \
        key(\"f\"); out.push(location.hash);\n  key(\"f\"); key(\"p\"); out.push(location.hash);\n  \
        key(\"h\"); out.push(location.hash);\n  \
        document.getElementById(\"stage\").dispatchEvent(new WheelEvent(\"wheel\", { deltaY: -300, cancelable: true }));\n  \
        out.push(v.state().zoom);";
    let got = drive(&page, "#t=0.5", body, true);
    assert_eq!(got[0], "#ground=floor,plan,contacts,residual&t=0.5");
    assert_eq!(got[1], "#ground=floor,contacts,forces,residual&t=0.5");
    assert_eq!(
        got[2],
        "#follow=off&ground=floor,contacts,forces,residual&t=0.5"
    );
    assert!(got[3].as_f64().unwrap() > 1.2);
    // opened at such an address, the page shows it
    let title = check_page(
        &page,
        "#cam=1.2,0.4&zoom=1.5&follow=off&ground=forces,plan&t=1",
        300,
    );
    assert_eq!(field(&title, "ground"), "[plan|forces]", "{title}");
    assert_eq!(field(&title, "follow"), "off");
    assert_eq!(field(&title, "zoom"), "1.5");
    assert_eq!(field(&title, "view"), "orbit");
    assert!(
        field(&title, "hash")
            .starts_with("#cam=1.200,0.400&zoom=1.5&follow=off&ground=plan,forces&t=1"),
        "{title}"
    );
    // `ground: false`: no layer, the old grid at the lowest point
    view_walk("view(w, body_of(w), PAGE, ground: false)", &page);
    assert!(page_data(&page).get("ground").is_none());
    let title = check_page(&page, "#t=1", 300);
    assert_eq!(field(&title, "ground"), "[]");
}

/// One self-contained file of at most twice the size without the ground
/// (every layer on, forces included), on every clip.
#[test]
fn the_page_with_every_layer_is_at_most_twice_the_size_without() {
    let mut clips = vec![Path::new(&walk_path()).to_path_buf()];
    clips.extend(shared_files("mocap", ".bvh"));
    let dir = tempfile::tempdir().unwrap();
    let (plain, full) = (dir.path().join("plain.html"), dir.path().join("full.html"));
    for path in &clips {
        let mut mx = mx::Interpreter::new();
        mx.eval_str(&format!(
            "{{ let m = load({p:?}); let b = body_of(m); view(m, b, {:?}, ground: false); \
               view(m, b, {:?}, ground: [\"floor\", \"plan\", \"contacts\", \"forces\", \"residual\"]) }}",
            plain.display().to_string(),
            full.display().to_string(),
            p = path.display().to_string()
        ))
        .unwrap();
        let (a, b) = (
            std::fs::metadata(&plain).unwrap().len(),
            std::fs::metadata(&full).unwrap().len(),
        );
        println!(
            "{:50} {a:>9} → {b:>9} bytes ({:.2}×)",
            path.file_name().unwrap().to_string_lossy(),
            b as f64 / a as f64
        );
        assert!(
            b <= 2 * a,
            "{path:?}: {b} bytes with the ground, {a} without"
        );
        let text = std::fs::read_to_string(&full).unwrap();
        assert!(
            !text.contains("http://")
                && !text.contains("https://")
                && !text.contains("<script src")
        );
    }
}

/// Playback at 60 frames per second: a 10 s clip filled by SP, every layer
/// on, draws a frame (stage, curves, strip, legend) in under 1/60 s on the
/// real clock.
#[test]
fn a_10_s_clip_with_every_layer_plays_at_60_fps() {
    let dir = tempfile::tempdir().unwrap();
    let page = dir.path().join("long.html");
    view_walk(
        "let long = concatenate(w, concatenate(w, concatenate(w, concatenate(w, w))))\n\
         let cut = long - clip_in_place(4.8s, 5.2s, long)\n\
         let f = SP(cut, body: body_of(w), coefficients: 3, samples: 8, contact: \"auto\")\n\
         view(f, body_of(w), PAGE, ground: [\"floor\", \"plan\", \"contacts\", \"forces\", \"residual\"])",
        &page,
    );
    let data = page_data(&page);
    let span = data["times"].as_array().unwrap();
    let seconds = span.last().unwrap().as_f64().unwrap() - span[0].as_f64().unwrap();
    assert!(seconds >= 9.9, "{seconds} s");
    let got = drive(
        &page,
        "",
        "  v.bench(30);\n  out.push(v.bench(DATA.times.length));\n  out.push(v.state().layers.length);",
        false,
    );
    let ms = got[0].as_f64().unwrap();
    println!(
        "{} frames, {ms:.2} ms a frame with every layer on",
        span.len()
    );
    assert_eq!(got[1], 5);
    assert!(ms > 0.0 && ms < 1000.0 / 60.0, "{ms} ms a frame");
}
