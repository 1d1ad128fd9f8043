//! The mx add-on (blender/mx_transitions/) in real Blender: bpy 5 from PyPI, headless. The
//! extension zip `scripts/blender-addon` builds is installed through
//! Blender's extension system into a throwaway user folder; two shared BVH
//! clips are imported with Blender's own importer and the fill operator joins
//! them (tests/it/blender/addon_fill.py does the Blender side and prints
//! `CHECK name value` lines, asserted here).

use crate::common;

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The extension zip: `MX_BLENDER_ADDON_ZIP`, else what `scripts/blender-addon`
/// writes. `None` with a note on a developer machine without it; a panic in CI.
fn addon_zip() -> Option<PathBuf> {
    let zip = std::env::var_os("MX_BLENDER_ADDON_ZIP")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            Path::new(env!("CARGO_MANIFEST_DIR")).join("target/blender/mx_transitions-0.1.0.zip")
        });
    if zip.is_file() {
        return Some(zip);
    }
    let msg = format!(
        "no add-on zip at {} (scripts/blender-addon builds it)",
        zip.display()
    );
    assert!(!common::in_ci(), "{msg}: required in CI");
    eprintln!("SKIPPED: {msg}");
    None
}

/// `blender/` (a local extension repository holding `mx_transitions/`) once
/// `scripts/blender-addon` has put the wheel in it; as `addon_zip` otherwise.
fn local_repository() -> Option<PathBuf> {
    let repo = Path::new(env!("CARGO_MANIFEST_DIR")).join("blender");
    let wheels = std::fs::read_dir(repo.join("mx_transitions/wheels"))
        .map(|d| {
            d.filter_map(|e| e.ok())
                .any(|e| e.path().extension().is_some_and(|x| x == "whl"))
        })
        .unwrap_or(false);
    if wheels {
        return Some(repo);
    }
    let msg = "no wheel in blender/mx_transitions/wheels (scripts/blender-addon puts it there)";
    assert!(!common::in_ci(), "{msg}: required in CI");
    eprintln!("SKIPPED: {msg}");
    None
}

/// Runs the driver in `mode` with Blender's user folders in a temporary
/// directory; returns the CHECK values and the whole stdout.
fn drive(mode: &str) -> Option<(HashMap<String, f64>, String)> {
    let dir = common::shared_dir()?;
    let py = common::blender_python()?;
    let zip = if mode == "local" {
        local_repository()?
    } else {
        addon_zip()?
    };
    let home = tempfile::tempdir().unwrap();
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/it/blender/addon_fill.py");
    let out = Command::new(&py)
        .arg(&script)
        .arg(&zip)
        .arg(dir.join("data/mocap"))
        .arg(mode)
        // Blender installs extensions under its user folders: keep them out of $HOME.
        .env("BLENDER_USER_RESOURCES", home.path())
        .env("BLENDER_USER_CONFIG", home.path().join("config"))
        .env("BLENDER_USER_SCRIPTS", home.path().join("scripts"))
        .env("BLENDER_USER_EXTENSIONS", home.path().join("extensions"))
        .output()
        .expect("runs Blender's Python");
    let stdout = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let checks = stdout
        .lines()
        .filter_map(|l| l.strip_prefix("CHECK "))
        .map(|l| {
            let (k, v) = l.split_once(' ').unwrap();
            (k.to_string(), v.parse::<f64>().unwrap())
        })
        .collect();
    Some((checks, stdout))
}

#[test]
fn the_fill_operator_joins_two_clips_as_the_python_api_does() {
    check_fill("check");
}

/// The same with the clips imported as quaternion bones (the BVH importer's
/// rotate_mode "QUATERNION", as glTF rigs come).
#[test]
fn the_fill_operator_works_on_quaternion_bones() {
    check_fill("check_quaternion");
}

fn check_fill(mode: &str) {
    let Some((c, stdout)) = drive(mode) else {
        return;
    };
    eprintln!("{stdout}");
    let get = |k: &str| {
        *c.get(k)
            .unwrap_or_else(|| panic!("no CHECK {k}:\n{stdout}"))
    };
    // Blender's armature mapped to mx is the file's clip (F-curves are float32).
    assert!(
        get("rig_vs_file_max") < 1e-4,
        "rig mapping off by {}",
        get("rig_vs_file_max")
    );
    // The new action spans the walk, the 30-frame gap and the run.
    assert_eq!(get("frame_start"), 0.0);
    assert_eq!(get("frame_end"), 0.0);
    assert_eq!(get("curves_missing"), 0.0);
    // Outside the gap: the two actions' keys, bit for bit, but the location
    // of the bone carrying the root's path after the gap (root "auto" shifts
    // a walk onto a run), moved as a whole.
    assert_eq!(get("outside_first_max"), 0.0);
    assert_eq!(get("outside_second_max"), 0.0);
    assert!(get("shifted_curves") <= 3.0);
    assert!(get("shift_not_constant") < 1e-5);
    // The keys hold SP's result (float32, as F-curves store values; up to 10 m here).
    assert!(get("keys_vs_result_max") < 1e-4);
    // Continuous joins (mx's DOFs from the keys): the step across each join and
    // its change are like those beside it; a jump or a kink would be many times them.
    assert!(get("join_step_ratio") < 2.0, "value jump at a join");
    assert!(
        get("join_velocity_change_ratio") < 3.0,
        "velocity jump at a join"
    );
    // The operator's transition is exactly mx.sp's from Python on the same
    // clips (as Blender holds them) and options.
    assert!(get("result_vs_python_api_max") <= 1e-9);
    // On the files themselves (mx.load, body_of) it differs only by the body:
    // Blender's importer lengthens zero-length leaf bones (head, hands, toes),
    // so the armature's body is not the file's; the values alone agree to
    // float32 (rig_vs_file_max above): with the armature's body, the files'
    // values give the operator's transition within 1e-4 rad/m (2e-5 measured).
    let same_body = get("vs_files_same_body_max");
    assert!(
        same_body < 1e-4,
        "operator vs files with the same body: {same_body}"
    );
    // Between two NLA strips placed as the actions were: the same transition.
    assert!(get("nla_vs_actions_max") <= 1e-9);
    // Misuse (a missing action, no gap, no strips) is a clear report.
    for source in ["ACTIONS", "GAP", "NLA"] {
        assert_eq!(
            get(&format!("misuse_{source}_reported")),
            1.0,
            "{source}: {stdout}"
        );
    }
    // Undo (bl_options UNDO) takes the new action back off.
    assert_eq!(get("undo_fill_added_actions"), 1.0);
    assert_eq!(get("undo_left_actions"), 0.0);
    assert_eq!(get("undo_active_is_walk"), 1.0);
    // Export with mx and import back, per format: every frame, the same motion
    // (float32 keys both ways; .bvh's decimals; glTF's quaternions).
    for ext in ["json", "bvh", "glb", "gltf"] {
        assert_eq!(get(&format!("roundtrip_frames_{ext}")), 0.0, "{ext}");
        let d = get(&format!("roundtrip_{ext}_max"));
        assert!(d < 1e-3, "{ext}: {d}");
    }
}

/// Standing on the ground (contact AUTO): the plan shows as one empty per
/// stance, named by point and source, at the plan's anchor within 1 mm, the
/// foot bone there while the stance holds (within the report's own `error`
/// and 1 cm); a fill without contact leaves none.
#[test]
fn the_fill_operator_shows_the_contact_plan_as_empties_on_the_floor() {
    let Some((c, stdout)) = drive("plan") else {
        return;
    };
    eprintln!("{stdout}");
    let get = |k: &str| {
        *c.get(k)
            .unwrap_or_else(|| panic!("no CHECK {k}:\n{stdout}"))
    };
    assert!(get("plan_stances") > 0.0, "SP planned no stance");
    assert_eq!(get("plan_empties"), get("plan_stances"));
    assert_eq!(get("plan_named"), get("plan_stances"));
    assert!(get("plan_anchor_max") < 1e-3, "{}", get("plan_anchor_max"));
    assert!(
        get("plan_bone_beyond_error_max") < 0.01,
        "{}",
        get("plan_bone_beyond_error_max")
    );
    assert_eq!(get("plan_after_none"), 0.0);
}

/// The operator on a 1 s gap of three walks (two 30 Hz Bandai clips, a
/// 120 Hz CMU clip) against `mx.sp` from Python on the same problem, warm,
/// interleaved, best of five. The issue's goal is 1.5×; on this shared 2-core
/// machine SP's own time varies twofold from run to run, so the assertion is
/// loose: under 4× or under 0.25 s more than SP, which a per-key Python loop
/// in the glue (seconds on the CMU clip's 92k keys) would break; the ratios
/// are printed (README quotes them).
#[test]
fn the_fill_operator_costs_about_what_sp_costs() {
    let Some((c, stdout)) = drive("timing") else {
        return;
    };
    for line in stdout.lines().filter(|l| l.starts_with("TIME ")) {
        eprintln!("{line}");
    }
    let ratios: Vec<(&String, &f64)> = c.iter().filter(|(k, _)| k.starts_with("ratio_")).collect();
    assert_eq!(ratios.len(), 3, "{stdout}");
    for (k, r) in ratios {
        let glue = c[&k.replace("ratio_", "glue_")];
        assert!(
            *r < 4.0 || glue < 0.25,
            "{k}: the operator takes {r:.2}× mx.sp's time, {glue:.3} s more"
        );
    }
}

#[test]
fn the_blender_folder_works_as_a_local_extension_repository() {
    let Some((c, stdout)) = drive("local") else {
        return;
    };
    assert_eq!(c.get("local_operator_registered"), Some(&1.0), "{stdout}");
    assert_eq!(c.get("local_mx_imports"), Some(&1.0), "{stdout}");
}

/// The README's Blender section, followed word for word (issue 38): its
/// ```sh block (the one command that builds the add-on) run from the
/// repository root, then its ```python block run in bpy 5.0.1 from a folder
/// that looks like the repository root (the repository's `examples` and
/// `target` linked in, `out/` its own): install the zip, import two clips
/// with Blender's importer, fill the gap, export. The exported file must be
/// the walk, the gap and the run.
#[test]
fn the_readme_blender_steps_run_as_written() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let section = readme
        .split("\n## Blender\n")
        .nth(1)
        .expect("README.md has a `## Blender` section")
        .split("\n## ")
        .next()
        .unwrap();
    let found = crate::doc_blocks::blocks(section);
    let of = |lang: &str| -> Vec<String> {
        found
            .iter()
            .filter(|(b, _)| b.info.first().is_some_and(|l| l == lang))
            .map(|(b, _)| b.text.clone())
            .collect()
    };
    let (sh, py) = (of("sh"), of("python"));
    assert_eq!(sh.len(), 1, "one command builds the add-on: {sh:?}");
    assert_eq!(py.len(), 1, "one Python block: {py:?}");
    let Some(python) = common::blender_python() else {
        return;
    };
    // The build, as the README says it (a no-op rebuild after scripts/test's).
    let built = Command::new("bash")
        .args(["-euo", "pipefail", "-c", &sh[0]])
        .current_dir(root)
        .output()
        .expect("runs bash");
    assert!(
        built.status.success(),
        "the README's build command failed:\n{}",
        String::from_utf8_lossy(&built.stderr)
    );
    let work = tempfile::tempdir().unwrap();
    for name in ["examples", "target"] {
        std::os::unix::fs::symlink(root.join(name), work.path().join(name)).unwrap();
    }
    std::fs::create_dir(work.path().join("out")).unwrap();
    let script = work.path().join("readme_blender.py");
    std::fs::write(&script, &py[0]).unwrap();
    let home = work.path().join("home");
    let out = Command::new(&python)
        .arg(&script)
        .current_dir(work.path())
        .env("BLENDER_USER_RESOURCES", &home)
        .env("BLENDER_USER_CONFIG", home.join("config"))
        .env("BLENDER_USER_SCRIPTS", home.join("scripts"))
        .env("BLENDER_USER_EXTENSIONS", home.join("extensions"))
        .output()
        .expect("runs Blender's Python");
    let log = format!(
        "{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        out.status.success(),
        "the README's Python block failed:\n{log}"
    );
    // What it exported is the walk, the README's gap and the run, in mx.
    let glb = work.path().join("out/walk_to_run.glb");
    assert!(glb.is_file(), "no {}:\n{log}", glb.display());
    let gap: f64 = py[0]
        .split("gap=")
        .nth(1)
        .and_then(|s| s.split(|c: char| !c.is_ascii_digit()).next())
        .and_then(|s| s.parse().ok())
        .expect("the block names its gap in frames");
    let mut mx = mx::Interpreter::new();
    let data = root.join("examples/data");
    let src = format!(
        "let w = load({w:?})\nlet r = load({r:?})\nlet m = load({g:?})\n\
         [frames(m), frames(w) + frames(r) + {gap} - 1, len(gaps(m)), len(dofs(m))]",
        w = data.join("walk.bvh").display().to_string(),
        r = data.join("run.bvh").display().to_string(),
        g = glb.display().to_string(),
    );
    let v = mx
        .eval_str(&src)
        .unwrap_or_else(|d| panic!("{}", d.render_plain()));
    let n: Vec<f64> = match v {
        mx::Value::List(xs) => xs.iter().map(|x| x.as_number().unwrap()).collect(),
        other => panic!("{}", other.repr()),
    };
    assert_eq!(n[0], n[1], "frames: exported vs walk + gap + run ({log})");
    assert_eq!(n[2], 0.0, "the export has gaps");
    assert!(n[3] > 0.0);
}
