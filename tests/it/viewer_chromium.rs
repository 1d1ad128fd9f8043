//! Opens the HTML viewer in headless Chromium: the page must report that it
//! drew the figure (non-background stage pixels, counted in the page) and no
//! script error may reach the console; a screenshot must be written. Also: a
//! clip that starts at 2.5 s opened at a time in its middle, a motion with a
//! gap, an overlay of three motions, and Bandai's still `joint_Root` left out.

use crate::common;

use mx::io::viewer::{Track, ViewerData, html};
use mx::mocap::bvh;
use std::path::{Path, PathBuf};
use std::process::Command;

pub(crate) fn chromium() -> PathBuf {
    for c in [
        "/usr/bin/chromium",
        "/usr/bin/chromium-browser",
        "/usr/bin/google-chrome",
    ] {
        if Path::new(c).exists() {
            return PathBuf::from(c);
        }
    }
    panic!(
        "headless Chromium is required for the viewer test: apt-get install -y chromium (.ci/run does this)"
    );
}

/// Runs Chromium on `page` (with a URL fragment such as `#t=3.5`, or "");
/// returns (dumped DOM, stderr) and checks the screenshot.
pub(crate) fn open_at(page: &Path, fragment: &str) -> (String, String) {
    open_page(page, fragment, true, 1000)
}

/// As [`open_at`]; `virtual_time` false runs the page on the real clock (a
/// timing measured in the page is then real), scripts running only at load;
/// the window `width` px wide.
pub(crate) fn open_page(
    page: &Path,
    fragment: &str,
    virtual_time: bool,
    width: u32,
) -> (String, String) {
    let dir = page.parent().unwrap();
    let size = format!("--window-size={width},800");
    let profile = dir.join("profile");
    let shot = dir.join("shot.png");
    let base = [
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--enable-logging=stderr",
        size.as_str(),
        if virtual_time {
            "--virtual-time-budget=2000"
        } else {
            "--disable-extensions"
        },
    ];
    let url = format!("file://{}{fragment}", page.display());
    let dom = Command::new(chromium())
        .args(base)
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg("--dump-dom")
        .arg(&url)
        .output()
        .expect("run chromium");
    let shot_run = Command::new(chromium())
        .args(base)
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("--screenshot={}", shot.display()))
        .arg(&url)
        .output()
        .expect("run chromium");
    let png = std::fs::read(&shot).expect("screenshot written");
    assert!(
        png.starts_with(b"\x89PNG") && png.len() > 5000,
        "screenshot is a real image"
    );
    let stderr = String::from_utf8_lossy(&dom.stderr).to_string()
        + &String::from_utf8_lossy(&shot_run.stderr);
    (String::from_utf8_lossy(&dom.stdout).to_string(), stderr)
}

fn check(page_text: &str, min_pixels: usize) -> String {
    let dir = tempfile::tempdir().unwrap();
    let page = dir.path().join("view.html");
    std::fs::write(&page, page_text).unwrap();
    check_page(&page, "", min_pixels)
}

/// Opens a written page (at `fragment`), checks it drew at least
/// `min_pixels` without a script error, and returns its self-check title.
pub(crate) fn check_page(page: &Path, fragment: &str, min_pixels: usize) -> String {
    let (dom, stderr) = open_at(page, fragment);
    let title = dom
        .split("<title>")
        .nth(1)
        .and_then(|t| t.split("</title>").next())
        .unwrap_or_else(|| panic!("no title in DOM:\n{dom}\nstderr:\n{stderr}"));
    assert!(
        title.starts_with("mx-viewer-ok"),
        "page reported: {title}\nstderr:\n{stderr}"
    );
    let drawn: usize = title
        .rsplit("drawn=")
        .next()
        .unwrap()
        .trim()
        .parse()
        .unwrap();
    assert!(drawn >= min_pixels, "only {drawn} figure pixels drawn");
    for l in stderr.lines() {
        let console_error =
            l.contains("CONSOLE") && (l.contains("Uncaught") || l.contains("Error"));
        assert!(!console_error, "console error: {l}");
    }
    eprintln!("{title}");
    // the DOM dump escapes `&` (the address in `hash=`)
    title.replace("&amp;", "&")
}

/// The value of `key=` in the page's self-check title.
pub(crate) fn field<'a>(title: &'a str, key: &str) -> &'a str {
    title
        .split_whitespace()
        .find_map(|w| w.strip_prefix(&format!("{key}=")))
        .unwrap_or_else(|| panic!("no {key}= in {title}"))
}

#[test]
fn synthetic_figure_is_drawn() {
    // A 3-bone arm swinging; needs no shared data.
    let frames = 30;
    let positions = (0..frames)
        .map(|f| {
            let a = f as f64 * 0.1;
            vec![
                [0.0, 1.0, 0.0],
                [0.0, 1.5, 0.0],
                [0.5 * a.cos(), 1.5 + 0.5 * a.sin(), 0.0],
                [0.0, 0.0, 0.0],
            ]
        })
        .collect();
    let data = ViewerData {
        title: "synthetic".into(),
        joint_names: vec![
            "Hips".into(),
            "Chest".into(),
            "RightHand".into(),
            "LeftFoot".into(),
        ],
        parents: vec![None, Some(0), Some(1), Some(0)],
        frame_time: 1.0 / 30.0,
        times: (0..frames).map(|f| f as f64 / 30.0).collect(),
        tracks: vec![Track {
            label: "synthetic".into(),
            positions,
            undefined: vec![],
            filled: vec![],
        }],
        up: 1,
        curves: vec![],
        ground: None,
    };
    check(&html(&data).unwrap(), 300);
}

#[test]
fn shared_clip_is_drawn() {
    let Some(dir) = common::shared_dir() else {
        return;
    };
    let f = bvh::read_file(&dir.join("data/mocap/bandai2_wave-right-hand_normal_001.bvh")).unwrap();
    let s = bvh::detect_units(&f.skeleton).metres_per_unit;
    let positions = (0..f.frame_count())
        .map(|i| {
            bvh::fk::world_positions(&f, i, s)
                .iter()
                .map(|p| [p.x, p.y, p.z])
                .collect()
        })
        .collect();
    let data = ViewerData {
        title: "wave".into(),
        joint_names: f.skeleton.joints.iter().map(|j| j.name.clone()).collect(),
        parents: f.skeleton.joints.iter().map(|j| j.parent).collect(),
        frame_time: f.frame_time,
        times: (0..f.frame_count())
            .map(|i| i as f64 * f.frame_time)
            .collect(),
        tracks: vec![Track {
            label: "wave".into(),
            positions,
            undefined: vec![],
            filled: vec![],
        }],
        up: 1,
        curves: vec![],
        ground: None,
    };
    let page = html(&data).unwrap();
    if let Ok(out) = std::env::var("MX_VIEWER_OUT") {
        std::fs::write(out, &page).unwrap();
    }
    check(&page, 1000);
}

#[test]
fn example_walk_on_its_body_is_drawn() {
    use mx::mocap::{body_of::body_of, to_motion};
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/data/walk.bvh");
    let clip = to_motion::load(&path, bvh::Units::Auto).unwrap();
    let (body, _) = body_of(&clip.skeleton, 70.0, clip.units.metres_per_unit).unwrap();
    let data = mx::io::viewer::from_motion(&clip.mu, &body, "walk", &[]).unwrap();
    assert_eq!(data.curves.len(), 6);
    assert_eq!(data.up, 1, "y-up body");
    check(&html(&data).unwrap(), 500);
}

pub(crate) fn walk_path() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples/data/walk.bvh")
        .display()
        .to_string()
}

/// Runs `script` with `w` bound to the example walk and `PAGE` replaced by
/// the quoted path of `page` (the script writes it with `view`).
pub(crate) fn view_walk(script: &str, page: &Path) {
    let mut mx = mx::Interpreter::new();
    let script = script.replace("PAGE", &format!("{:?}", page.display().to_string()));
    mx.eval_str(&format!("{{ let w = load({:?}); {script} }}", walk_path()))
        .unwrap();
}

#[test]
fn clip_starting_at_2_5_s_is_shown_in_the_middle_at_its_own_time() {
    let dir = tempfile::tempdir().unwrap();
    let page = dir.path().join("clip.html");
    view_walk(
        "let s = concatenate(w, concatenate(w, w)); view(clip_in_place(2.5, 4.5, s), body_of(w), PAGE)",
        &page,
    );
    let title = check_page(&page, "#t=3.5", 500);
    assert_eq!(field(&title, "t0"), "2.500", "{title}");
    assert_eq!(field(&title, "t1"), "4.500", "{title}");
    assert_eq!(field(&title, "time"), "3.500", "{title}");
    assert_eq!(field(&title, "frame"), "30", "{title}");
    // The clock's frame number is the clip's: 3.5 s at 30 fps.
    assert_eq!(field(&title, "clip_frame"), "105", "{title}");
    assert_eq!(field(&title, "undefined"), "[]", "{title}");
    // Past the 60 frames of the clip the page still draws (it used to vanish).
    let end = check_page(&page, "#t=4.5", 500);
    assert_eq!(field(&end, "time"), "4.500", "{end}");
    // The pose of a frame is the one sampled at the time it shows.
    use mx::mocap::{Missing, body_of::body_of, positions_at, to_motion};
    let clip = to_motion::load(Path::new(&walk_path()), bvh::Units::Auto).unwrap();
    let (body, _) = body_of(&clip.skeleton, 70.0, clip.units.metres_per_unit).unwrap();
    let shifted = mx::motion::ops::affine(2.5, 1.0, &clip.mu).unwrap();
    let data = mx::io::viewer::from_motion(&shifted, &body, "shifted", &[]).unwrap();
    let k = data
        .times
        .iter()
        .position(|t| (t - 3.5).abs() < 1e-9)
        .unwrap();
    let want = positions_at(&clip.mu, &body, vec![1.0], Missing::Error).unwrap();
    for (a, b) in data.tracks[0].positions[k].iter().zip(&want.points[0]) {
        assert!((a[0] - b.x).abs() + (a[1] - b.y).abs() + (a[2] - b.z).abs() < 1e-9);
    }
    assert_eq!(data.times[0], 2.5);
}

#[test]
fn gaps_hold_the_last_pose_marked_undefined() {
    let dir = tempfile::tempdir().unwrap();
    let page = dir.path().join("gap.html");
    view_walk(
        "let cut = clip(0.8s, 1.2s, w); view(w - shift(cut, 0.8s), body_of(w), PAGE, labels: [\"walk with a gap\"])",
        &page,
    );
    let inside = check_page(&page, "#t=1.0", 0);
    assert_eq!(field(&inside, "undefined"), "[walk", "{inside}");
    let outside = check_page(&page, "#t=0.5", 500);
    assert_eq!(field(&outside, "undefined"), "[]", "{outside}");
    let text = std::fs::read_to_string(&page).unwrap();
    let json = text
        .split("const DATA = ")
        .nth(1)
        .unwrap()
        .split(";\n")
        .next()
        .unwrap();
    let data: serde_json::Value = serde_json::from_str(json).unwrap();
    let undefined: Vec<bool> = data["tracks"][0]["undefined"]
        .as_array()
        .unwrap()
        .iter()
        .map(|b| b.as_bool().unwrap())
        .collect();
    let held = undefined.iter().filter(|u| **u).count();
    assert!((10..=13).contains(&held), "{held} frames held");
    // The held frames repeat the last defined pose.
    let k = undefined.iter().position(|u| *u).unwrap();
    assert_eq!(
        data["tracks"][0]["positions"][k],
        data["tracks"][0]["positions"][k - 1]
    );
    // Curves have a gap there: each curve is two pieces.
    for c in data["curves"].as_array().unwrap() {
        assert_eq!(c["pieces"].as_array().unwrap().len(), 2, "{}", c["name"]);
    }
}

#[test]
fn three_motions_overlay_in_distinct_colours_with_a_legend_and_one_clock() {
    let dir = tempfile::tempdir().unwrap();
    let page = dir.path().join("compare.html");
    view_walk(
        "let gap = w - shift(clip(0.7s, 1.3s, w), 0.7s); \
         view([w, shift(w, 0.4s), fill(gap, \"hermite\")], body_of(w), PAGE, \
              labels: [\"capture\", \"later\", \"hermite\"])",
        &page,
    );
    let title = check_page(&page, "#t=1.0", 800);
    assert_eq!(field(&title, "tracks"), "3", "{title}");
    // One clock over the union of the spans: 0 s to 2.4 s.
    assert_eq!(field(&title, "t0"), "0.000", "{title}");
    assert_eq!(field(&title, "t1"), "2.400", "{title}");
    let colours: Vec<usize> = field(&title, "colours")
        .split(',')
        .map(|c| c.parse().unwrap())
        .collect();
    assert_eq!(colours.len(), 3);
    assert!(
        colours.iter().all(|&c| c > 50),
        "each motion visible in its colour: {title}"
    );
    let text = std::fs::read_to_string(&page).unwrap();
    for label in ["capture", "later", "hermite"] {
        assert!(text.contains(&format!("\"label\":\"{label}\"")), "{label}");
    }
    // Before 0.4 s `later` is undefined: it shows its first pose, marked.
    let early = check_page(&page, "#t=0.2", 500);
    assert_eq!(field(&early, "undefined"), "[later]", "{early}");
    // The Rust entry point the in-betweening benchmark uses writes the same kind of page.
    use mx::mocap::{body_of::body_of, to_motion};
    let clip = to_motion::load(Path::new(&walk_path()), bvh::Units::Auto).unwrap();
    let (body, _) = body_of(&clip.skeleton, 70.0, clip.units.metres_per_unit).unwrap();
    let later = mx::motion::ops::affine(0.4, 1.0, &clip.mu).unwrap();
    let p2 = dir.path().join("bench.html");
    mx::io::viewer::write_overlay(
        &p2,
        &body,
        &[("capture", &clip.mu), ("later", &later)],
        "bench",
    )
    .unwrap();
    let t2 = check_page(&p2, "#t=1.0", 500);
    assert_eq!(field(&t2, "tracks"), "2", "{t2}");
}

#[test]
fn bandai_still_massless_root_is_not_drawn_as_a_bone() {
    let Some(dir) = common::shared_dir() else {
        return;
    };
    use mx::mocap::{body_of::body_of, to_motion};
    let path = dir.join("data/mocap/bandai2_wave-right-hand_normal_001.bvh");
    let clip = to_motion::load(&path, bvh::Units::Auto).unwrap();
    assert!(clip.skeleton.find("joint_Root").is_some());
    let (body, _) = body_of(&clip.skeleton, 70.0, clip.units.metres_per_unit).unwrap();
    let data = mx::io::viewer::from_motion(&clip.mu, &body, "wave", &[]).unwrap();
    assert!(
        !data.joint_names.iter().any(|n| n == "joint_Root"),
        "{:?}",
        data.joint_names
    );
    let hips = data.joint_names.iter().position(|n| n == "Hips").unwrap();
    assert_eq!(data.parents[hips], None, "Hips is the root drawn");
    assert!(
        data.parents
            .iter()
            .flatten()
            .all(|&p| p < data.joint_names.len())
    );
    check(&html(&data).unwrap(), 1000);
}

/// The JSON the page embeds.
pub(crate) fn page_data(page: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(page).unwrap();
    let json = text
        .split("const DATA = ")
        .nth(1)
        .unwrap()
        .split(";\n")
        .next()
        .unwrap();
    serde_json::from_str(json).unwrap()
}

/// `(w, h)` of the figure's extent on the stage in the self-check title.
fn extent(title: &str) -> (f64, f64) {
    let (w, h) = field(title, "extent").split_once('x').unwrap();
    (w.parse().unwrap(), h.parse().unwrap())
}

#[test]
fn camera_presets_and_time_come_from_the_url_and_go_back_into_it() {
    let dir = tempfile::tempdir().unwrap();
    let page = dir.path().join("walk.html");
    view_walk("view(w, body_of(w), PAGE)", &page);
    let side = check_page(&page, "#view=side&t=1.5", 500);
    assert_eq!(field(&side, "view"), "side", "{side}");
    assert_eq!(field(&side, "time"), "1.500", "{side}");
    assert_eq!(field(&side, "hash"), "#view=side&t=1.5", "{side}");
    // Either order is read; the page writes the address back in one form.
    let top = check_page(&page, "#t=1.5&view=top", 500);
    assert_eq!(field(&top, "view"), "top", "{top}");
    assert_eq!(field(&top, "hash"), "#view=top&t=1.5", "{top}");
    let front = check_page(&page, "#view=front&t=1.5", 500);
    assert_eq!(field(&front, "view"), "front", "{front}");
    // The presets look from different sides: from above a standing figure
    // is short on screen, from the front and side it is tall.
    let (fw, fh) = extent(&front);
    let (sw, sh) = extent(&side);
    let (_, th) = extent(&top);
    assert!(th < 0.6 * fh && th < 0.6 * sh, "{front}\n{side}\n{top}");
    assert!(
        (fw - sw).abs() > 5.0,
        "front and side differ: {front}\n{side}"
    );
    // No fragment: the default orbit, and the address gains the time.
    let plain = check_page(&page, "", 500);
    assert_eq!(field(&plain, "view"), "orbit", "{plain}");
    assert_eq!(field(&plain, "hash"), "#t=0", "{plain}");
    // An unknown view is ignored, not an error.
    let odd = check_page(&page, "#view=diagonal&t=2", 500);
    assert_eq!(field(&odd, "view"), "orbit", "{odd}");
    assert_eq!(field(&odd, "hash"), "#t=2", "{odd}");
}

/// Keys 1/2/3, the buttons, the slider and a mouse orbit, driven by a
/// script the test appends to the page (after the viewer's own): each
/// changes the view or the time and the address follows at once.
#[test]
fn keys_buttons_and_the_slider_update_the_view_and_the_address() {
    let dir = tempfile::tempdir().unwrap();
    let page = dir.path().join("walk.html");
    view_walk("view(w, body_of(w), PAGE)", &page);
    let driver = r#"<script>
(async function () {
  const out = [];
  // the address is written at once for keys and buttons, within 100 ms
  // for the slider: wait (virtual time) before reading it
  const settle = () => new Promise(r => setTimeout(r, 150));
  const note = async what => {
    await settle();
    const s = window.mxViewer.state();
    out.push(what + " " + s.view + " " + s.hash + " " + s.yaw.toFixed(3) + " " + s.pitch.toFixed(3));
  };
  document.dispatchEvent(new KeyboardEvent("keydown", { key: "2" }));
  await note("key2");
  document.getElementById("view-top").click();
  await note("top-button");
  document.dispatchEvent(new KeyboardEvent("keydown", { key: "1" }));
  await note("key1");
  const slider = document.getElementById("slider");
  for (const v of ["10", "20", "30"]) { slider.value = v; slider.dispatchEvent(new Event("input")); }
  await note("slider");
  const stage = document.getElementById("stage");
  stage.dispatchEvent(new MouseEvent("mousedown", { clientX: 100, clientY: 100, bubbles: true }));
  window.dispatchEvent(new MouseEvent("mousemove", { clientX: 140, clientY: 100 }));
  window.dispatchEvent(new MouseEvent("mouseup", {}));
  await note("orbit");
  const pre = document.createElement("pre");
  pre.id = "mx-test";
  pre.textContent = out.join(";");
  document.body.appendChild(pre);
})();
</script>
</body>"#;
    let text = std::fs::read_to_string(&page).unwrap();
    std::fs::write(&page, text.replacen("</body>", driver, 1)).unwrap();
    let (dom, stderr) = open_at(&page, "#t=0.5");
    let report = dom
        .split("<pre id=\"mx-test\">")
        .nth(1)
        .and_then(|t| t.split("</pre>").next())
        .unwrap_or_else(|| panic!("the driver did not run:\n{stderr}"))
        .replace("&amp;", "&");
    let steps: Vec<Vec<&str>> = report.split(';').map(|s| s.split(' ').collect()).collect();
    let half_pi = format!("{:.3}", std::f64::consts::FRAC_PI_2);
    let expect = [
        ("key2", "side", "#view=side&t=0.5"),
        ("top-button", "top", "#view=top&t=0.5"),
        ("key1", "front", "#view=front&t=0.5"),
        ("slider", "front", "#view=front&t=1"),
    ];
    for (step, (what, view, hash)) in steps.iter().zip(expect) {
        assert_eq!(step[..3], [what, view, hash], "{report}");
    }
    assert_eq!(steps[0][3], half_pi, "side looks along x: {report}");
    assert_eq!(steps[1][4], half_pi, "top looks down: {report}");
    // Orbiting leaves the preset: the address keeps the camera instead.
    assert_eq!(steps[4][..2], ["orbit", ""], "{report}");
    let cam = format!("#cam={},{}&t=1", steps[4][3], steps[4][4]);
    assert_eq!(steps[4][2], cam, "{report}");
}

#[test]
fn curves_are_chosen_by_dof_joint_or_glob_and_their_labels_never_overlap() {
    let dir = tempfile::tempdir().unwrap();
    let page = dir.path().join("chosen.html");
    view_walk(
        "view(w, body_of(w), PAGE, curves: [\"RightLeg.Xrotation\", \"Left?pLeg.Xrot*\", \"Hips\", \"RightLeg\"])",
        &page,
    );
    let data = page_data(&page);
    let names: Vec<&str> = data["curves"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["name"].as_str().unwrap())
        .collect();
    // In the patterns' order: a DOF, a glob, a joint's six DOFs, then the
    // rest of a joint whose first DOF was already asked for.
    assert_eq!(names.len(), 10, "{names:?}");
    assert_eq!(names[..2], ["RightLeg.Xrotation", "LeftUpLeg.Xrotation"]);
    let mut hips = names[2..8].to_vec();
    hips.sort();
    assert_eq!(
        hips,
        [
            "Hips.Xposition",
            "Hips.Xrotation",
            "Hips.Yposition",
            "Hips.Yrotation",
            "Hips.Zposition",
            "Hips.Zrotation"
        ]
    );
    let mut rest = names[8..].to_vec();
    rest.sort();
    assert_eq!(rest, ["RightLeg.Yrotation", "RightLeg.Zrotation"]);
    let title = check_page(&page, "", 500);
    assert_eq!(field(&title, "labels"), "10", "{title}");
    assert_eq!(field(&title, "more"), "0", "{title}");
    let gap: f64 = field(&title, "label_gap").parse().unwrap();
    assert!(gap >= 13.0, "{title}");
    // Every DOF: more curves than names fit; the rest are counted.
    let all = dir.path().join("all.html");
    view_walk("view(w, body_of(w), PAGE, curves: [\"*\"])", &all);
    let n = page_data(&all)["curves"].as_array().unwrap().len();
    let title = check_page(&all, "", 500);
    let shown: usize = field(&title, "labels").parse().unwrap();
    let more: usize = field(&title, "more").parse().unwrap();
    assert!(more > 0 && shown + more == n, "{n} curves: {title}");
    let gap: f64 = field(&title, "label_gap").parse().unwrap();
    assert!(gap >= 13.0, "{title}");
    // A pattern that matches nothing is an error at the option, with a suggestion.
    let mut mx = mx::Interpreter::new();
    let err = mx
        .eval_str(&format!(
            "{{ let w = load({:?}); view(w, body_of(w), {:?}, curves: [\"LeftLegg\"]) }}",
            walk_path(),
            dir.path().join("x.html").display().to_string()
        ))
        .unwrap_err()
        .render_plain();
    assert!(
        err.contains("no DOF or joint matches `LeftLegg`")
            && err.contains("did you mean `LeftLeg`?"),
        "{err}"
    );
}

#[test]
fn the_gap_sp_filled_is_shaded_and_named_in_the_legend() {
    let dir = tempfile::tempdir().unwrap();
    let page = dir.path().join("filled.html");
    view_walk(
        "let gapped = w - clip_in_place(0.8s, 1.2s, w.only(\"RightLeg.Xrotation\")); \
         view(SP(gapped, body: body_of(w), coefficients: 3, samples: 8), body_of(w), PAGE, curves: [\"RightLeg\"])",
        &page,
    );
    let data = page_data(&page);
    let filled = data["tracks"][0]["filled"].as_array().unwrap();
    assert_eq!(filled.len(), 1, "{filled:?}");
    let (a, b) = (
        filled[0][0].as_f64().unwrap(),
        filled[0][1].as_f64().unwrap(),
    );
    assert!(
        (a - 0.8).abs() < 0.05 && (b - 1.2).abs() < 0.05,
        "{filled:?}"
    );
    let inside = check_page(&page, "#t=1.0", 500);
    assert_eq!(field(&inside, "filled"), "[filled]", "{inside}");
    // The 0.4 s of 2 s over the plot's height: about 30,000 pixels.
    let shade: usize = field(&inside, "shade").parse().unwrap();
    assert!(shade > 10_000, "the span is shaded: {inside}");
    let outside = check_page(&page, "#t=0.3", 500);
    assert_eq!(field(&outside, "filled"), "[]", "{outside}");
    // A motion SP did not make has no shading.
    let plain = dir.path().join("plain.html");
    view_walk("view(w, body_of(w), PAGE)", &plain);
    // (a few anti-aliased pixels of a green curve match the shade)
    let title = check_page(&plain, "#t=1.0", 500);
    let plain_shade: usize = field(&title, "shade").parse().unwrap();
    assert!(plain_shade < 500, "{title}");
    assert_eq!(field(&title, "filled"), "[]", "{title}");
}

/// On a CMU clip the default curves skip fingers, thumbs and toes (their
/// Euler angles wrap and swing ±π there) and are the body's big movers.
#[test]
fn default_curves_on_cmu_leave_out_fingers_thumbs_and_toes() {
    let Some(dir) = common::shared_dir() else {
        return;
    };
    use mx::mocap::{body_of::body_of, to_motion};
    let path = dir.join("data/mocap/cmu_131_01_start_walk_stop.bvh");
    let clip = to_motion::load(&path, bvh::Units::Auto).unwrap();
    let (body, _) = body_of(&clip.skeleton, 70.0, clip.units.metres_per_unit).unwrap();
    let data = mx::io::viewer::from_motion(&clip.mu, &body, "cmu", &[]).unwrap();
    assert_eq!(data.curves.len(), 6);
    for c in &data.curves {
        assert!(!mx::io::viewer::curves::is_extremity(&c.name), "{}", c.name);
        // unwrapped: no step between samples of more than π
        for piece in &c.pieces {
            for w in piece.windows(2) {
                assert!(
                    (w[1][1] - w[0][1]).abs() < std::f64::consts::PI,
                    "{} jumps at {}",
                    c.name,
                    w[0][0]
                );
            }
        }
    }
    check(&html(&data).unwrap(), 1000);
}

/// The README's first session views into `out/` before anything saved
/// there: `view` (and `plot`) create the folders they write into, as `save` does.
#[test]
fn view_and_plot_create_the_folders_they_write_into() {
    let dir = tempfile::tempdir().unwrap();
    let page = dir.path().join("out/deeper/walk.html");
    view_walk("view(w, body_of(w), PAGE)", &page);
    assert!(page.exists());
    let svg = dir.path().join("plots/hips.svg");
    view_walk("plot(w.only(\"Hips.Xposition\"), PAGE)", &svg);
    assert!(svg.exists());
}

/// Python's notebook view embeds the page as an iframe's `srcdoc`: it
/// draws there, and has no address of its own to rewrite.
#[test]
fn the_page_embedded_as_srcdoc_draws_and_keeps_no_address() {
    let dir = tempfile::tempdir().unwrap();
    let page = dir.path().join("walk.html");
    view_walk("view(w, body_of(w), PAGE)", &page);
    let inner = std::fs::read_to_string(&page)
        .unwrap()
        .replace('&', "&amp;")
        .replace('"', "&quot;");
    let outer = dir.path().join("notebook.html");
    std::fs::write(
        &outer,
        format!(
            "<!DOCTYPE html><html><head><title>notebook</title></head><body>\
             <iframe id=\"f\" srcdoc=\"{inner}\" style=\"width:1000px;height:560px\"></iframe>\
             <script>document.getElementById(\"f\").addEventListener(\"load\", function () {{\
               const d = this.contentDocument;\
               const pre = document.createElement(\"pre\"); pre.id = \"mx-test\";\
               pre.textContent = d.title + \" inner=\" + this.contentWindow.location.href + \" outer=\" + location.hash;\
               document.body.appendChild(pre);\
             }});</script></body></html>"
        ),
    )
    .unwrap();
    let (dom, stderr) = open_at(&outer, "");
    let report = dom
        .split("<pre id=\"mx-test\">")
        .nth(1)
        .and_then(|t| t.split("</pre>").next())
        .unwrap_or_else(|| panic!("no report:\n{dom}\n{stderr}"));
    assert!(report.starts_with("mx-viewer-ok"), "{report}");
    assert!(report.contains("inner=about:srcdoc outer="), "{report}");
    assert!(report.ends_with("outer="), "{report}");
}
