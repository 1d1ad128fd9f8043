//! Opens the HTML viewer in headless Chromium: the page must report that it
//! drew the figure (non-background stage pixels, counted in the page) and no
//! script error may reach the console; a screenshot must be written.

mod common;

use mx::io::viewer::{ViewerData, html};
use mx::mocap::bvh;
use std::path::{Path, PathBuf};
use std::process::Command;

fn chromium() -> PathBuf {
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

/// Runs Chromium on `page`; returns (dumped DOM, stderr) and checks the screenshot.
fn open(page: &Path) -> (String, String) {
    let dir = page.parent().unwrap();
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
        "--window-size=1000,800",
        "--virtual-time-budget=2000",
    ];
    let url = format!("file://{}", page.display());
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

fn check(page_text: &str, min_pixels: usize) {
    let dir = tempfile::tempdir().unwrap();
    let page = dir.path().join("view.html");
    std::fs::write(&page, page_text).unwrap();
    let (dom, stderr) = open(&page);
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
        positions,
        up: 1,
        curves: vec![],
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
        positions,
        up: 1,
        curves: vec![],
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
