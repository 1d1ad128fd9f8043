//! Spacetime transitions through the language: the examples of `examples/`
//! (run in a temporary folder holding the project's clips; their output and
//! their motions are checked), the same composites on Bandai motion capture
//! from `$MX_SHARED/data/mocap`, SP's diagnostics, and the hard cases.

use crate::common;

use std::path::{Path, PathBuf};

use mx::lang::builtins::motion::Motion;
use mx::motion::Mu;
use mx::{Interpreter, Value};

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn mu(v: &Value) -> Mu {
    match v.as_object::<Motion>() {
        Some(Motion::Mu(m)) => m.clone(),
        _ => panic!("not a motion: {}", v.repr()),
    }
}

/// An interpreter confined to a fresh folder holding copies of `examples/data`
/// as `data/` (where the examples, run from their own folder, find it).
fn sandbox() -> (
    Interpreter,
    std::sync::Arc<std::sync::Mutex<Vec<u8>>>,
    tempfile::TempDir,
) {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("data");
    std::fs::create_dir_all(&data).unwrap();
    for e in std::fs::read_dir(repo().join("examples/data")).unwrap() {
        let p = e.unwrap().path();
        std::fs::copy(&p, data.join(p.file_name().unwrap())).unwrap();
    }
    let mut mx = Interpreter::new();
    let out = mx.capture_output();
    mx.set_file_root(Some(dir.path().to_path_buf()));
    (mx, out, dir)
}

/// Runs `examples/<name>` and returns the interpreter (to read its variables), stdout and the folder.
fn run_example(name: &str) -> (Interpreter, String, tempfile::TempDir) {
    let (mut mx, out, dir) = sandbox();
    if let Err(d) = mx.eval_file(repo().join("examples").join(name)) {
        panic!("{name} failed:\n{}", d.render_plain());
    }
    let text = String::from_utf8(out.lock().unwrap().clone()).unwrap();
    print!("{text}");
    (mx, text, dir)
}

/// Largest position, velocity and acceleration jumps where one interval ends and the next starts.
fn jumps(m: &Mu) -> [f64; 3] {
    let mut j = [0.0f64; 3];
    for d in m.dofs.values() {
        for w in d.intervals.windows(2) {
            if (w[1].start - w[0].stop).abs() < 1e-12 {
                let a = w[0].funcs[0].eval(w[0].stop).unwrap();
                let b = w[1].funcs[0].eval(w[1].start).unwrap();
                for k in 0..3 {
                    j[k] = j[k].max((a[k] - b[k]).abs());
                }
            }
        }
    }
    j
}

/// (SP, Hermite, against SP's own start) from the line `torque energy: SP x
/// … Hermite y` (a Hermite fill) or `torque energy over the gap: SP x its
/// Hermite start y` (SP's report: the same root handling on both sides).
fn energies(out: &str) -> (f64, f64, bool) {
    let line = out
        .lines()
        .find(|l| l.starts_with("torque energy: SP") || l.starts_with("torque energy over the gap"))
        .unwrap_or_else(|| panic!("no energy line in\n{out}"));
    let w: Vec<&str> = line.split_whitespace().collect();
    let after = |label: &str| -> f64 {
        let i = w.iter().position(|x| *x == label).unwrap();
        w[i + 1].parse().unwrap()
    };
    if line.contains("its Hermite start") {
        (after("SP"), after("start"), true)
    } else {
        (after("SP"), after("Hermite"), false)
    }
}

/// The checks every transition example shares: no gap left, continuity at
/// every transition end, SP below Hermite, the output file written.
fn check_transitions(mx: &Interpreter, out: &str, dir: &Path, file: &str) {
    let filled = mu(&mx.get("filled").expect("the example binds `filled`"));
    assert!(mx::motion::gaps(&filled).is_empty(), "gaps left");
    let [jq, jv, _] = jumps(&filled);
    println!("transition ends: |Δq| {jq:.1e}, |Δq̇| {jv:.1e}");
    assert!(jq <= 1e-9 && jv <= 1e-6, "jumps {jq} {jv}");
    let (sp, hermite, own_start) = energies(out);
    if own_start {
        // SP's continuation ends at its smallest prior: against its own
        // start it is within a percent (0.04–0.55 % above on these clips,
        // issue 28), not the 10–30× a baseline with the root left behind showed
        assert!(
            sp <= 1.01 * hermite,
            "SP {sp} vs its Hermite start {hermite}"
        );
    } else {
        assert!(sp < hermite, "SP {sp} must be below Hermite {hermite}");
    }
    let len = std::fs::metadata(dir.join("out").join(file))
        .map(|m| m.len())
        .unwrap_or(0);
    assert!(len > 1000, "{file} missing or empty");
}

#[test]
fn fig6_wave_example() {
    let (mx, out, dir) = run_example("fig6_wave.mx");
    assert!(out.contains("gaps: 12 conflicts: 0"), "{out}");
    check_transitions(&mx, &out, dir.path(), "fig6_wave.bvh");
    assert!(out.contains("gap 1 [0.2500, 0.6000] s"), "{out}");
}

#[test]
fn walk_to_run_example() {
    let (mx, out, dir) = run_example("walk_to_run.mx");
    check_transitions(&mx, &out, dir.path(), "walk_to_run.bvh");
    assert!(out.contains("root over [1.2000, 1.6000] s"), "{out}");
}

#[test]
fn kick_to_walk_example() {
    let (mx, out, dir) = run_example("kick_to_walk.mx");
    check_transitions(&mx, &out, dir.path(), "kick_to_walk.bvh");
}

#[test]
fn fig10_arm_example_moves_shoulder_and_wrist_only_with_sp() {
    let (mx, out, dir) = run_example("fig10_arm.mx");
    check_transitions(&mx, &out, dir.path(), "fig10_arm_sp.bvh");
    let moved = |joint: &str| -> (f64, f64, f64) {
        let line = out
            .lines()
            .find(|l| l.starts_with(&format!("{joint} moves:")))
            .unwrap();
        let w: Vec<&str> = line.split_whitespace().collect();
        (
            w[3].parse().unwrap(),
            w[6].parse().unwrap(),
            w[9].parse().unwrap(),
        )
    };
    for joint in ["shoulder", "wrist"] {
        let (sp, interp, rose) = moved(joint);
        assert!(
            interp < 1e-9,
            "interpolation keeps the {joint} still: {interp}"
        );
        assert!(rose > 0.1, "Rose's objective moves the {joint}: {rose} deg");
        // the default's prior holds what torque barely constrains (the hand
        // turning about its long axis went 293° under Rose's objective)
        assert!(
            sp < 30.0,
            "SP's default keeps the {joint} near its ends: {sp} deg"
        );
    }
    let (sp, interp, _) = moved("forearm");
    assert!(
        sp > 80.0 && interp > 80.0,
        "the forearm turns 90°: {sp} {interp}"
    );
}

#[test]
fn cyclic_walk_example_loops_with_c2_seams() {
    let (mx, out, dir) = run_example("cyclic_walk.mx");
    check_transitions(&mx, &out, dir.path(), "cyclic_walk_sp.bvh");
    let looped = mu(&mx.get("looped").unwrap());
    let cycle = mu(&mx.get("cycle").unwrap());
    let [jq, jv, ja] = jumps(&looped);
    println!("loop seams: |Δq| {jq:.1e}, |Δq̇| {jv:.1e}, |Δq̈| {ja:.1e}");
    assert!(jq <= 1e-9 && jv <= 1e-6 && ja <= 1e-3, "{jq} {jv} {ja}");
    for d in looped.dofs.values() {
        assert_eq!(d.intervals.len(), 10);
    }
    // the walk keeps going forward: ten cycles advance ten times one cycle's advance
    let z = |m: &Mu, t: f64| m.sample("Hips.Zposition", t).unwrap().unwrap()[0];
    let (c0, c1) = cycle.span().unwrap();
    let (l0, l1) = looped.span().unwrap();
    let per_cycle = z(&cycle, c1) - z(&cycle, c0);
    assert!(per_cycle > 0.5, "{per_cycle}");
    assert!(((z(&looped, l1) - z(&looped, l0)) - 10.0 * per_cycle).abs() < 1e-9);
    let csv = std::fs::read_to_string(dir.path().join("out/cyclic_walk.csv")).unwrap();
    assert!(csv.lines().count() > 250);
}

#[test]
fn the_binary_runs_an_example_and_shows_no_progress_bar_off_a_terminal() {
    // the example and its data copied to `ex/`, run from the folder above:
    // the script's paths (data/…, out/…) are taken from its own folder
    let dir = tempfile::tempdir().unwrap();
    let ex = dir.path().join("ex");
    std::fs::create_dir_all(ex.join("data")).unwrap();
    for name in ["walk.bvh", "wave.bvh"] {
        std::fs::copy(
            repo().join("examples/data").join(name),
            ex.join("data").join(name),
        )
        .unwrap();
    }
    std::fs::copy(
        repo().join("examples/fig6_wave.mx"),
        ex.join("fig6_wave.mx"),
    )
    .unwrap();
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_mx"))
        .args(["run", "ex/fig6_wave.mx"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.trim().is_empty(),
        "stderr is not a terminal: no bar, got {err}"
    );
    assert!(ex.join("out/fig6_wave.bvh").exists());
    assert!(!dir.path().join("out").exists());
}

// ---- Bandai motion capture ($MX_SHARED/data/mocap) --------------------------

fn bandai(name_part: &str) -> Option<PathBuf> {
    let files = common::shared_files("mocap", ".bvh");
    if files.is_empty() {
        return None;
    }
    Some(
        files
            .into_iter()
            .find(|p| {
                let n = p.file_name().unwrap().to_string_lossy();
                n.starts_with("bandai") && n.contains(name_part)
            })
            .unwrap_or_else(|| panic!("no bandai clip named *{name_part}*")),
    )
}

/// Runs `src` with `$a`, `$b` replaced by the paths of the Bandai clips
/// named `a` and `b`: the interpreter and what the script printed (None
/// without the shared data, outside CI).
fn run_bandai(a: &str, b: &str, src: &str) -> Option<(Interpreter, String)> {
    let (pa, pb) = (bandai(a)?, bandai(b)?);
    let mut mx = Interpreter::new();
    let out = mx.capture_output();
    let src = src
        .replace("$a", &pa.to_string_lossy())
        .replace("$b", &pb.to_string_lossy());
    if let Err(d) = mx.eval_str(&src) {
        panic!("{}", d.render_plain());
    }
    let text = String::from_utf8(out.lock().unwrap().clone()).unwrap();
    print!("{text}");
    Some((mx, text))
}

/// Runs `src` (see [`run_bandai`]); checks the transitions of `filled`.
fn bandai_composite(a: &str, b: &str, src: &str) {
    let Some((mx, text)) = run_bandai(a, b, src) else {
        return;
    };
    let filled = mu(&mx.get("filled").unwrap());
    assert!(mx::motion::gaps(&filled).is_empty());
    let [jq, jv, _] = jumps(&filled);
    assert!(jq <= 1e-9 && jv <= 1e-6, "jumps {jq} {jv}");
    let (sp, hermite, _) = energies(&text);
    assert!(sp < hermite, "SP {sp} vs Hermite {hermite}");
}

/// The Bandai skeleton has 6 channels on every joint (132 coordinates); the
/// position channels of all joints but the hips are constant bone offsets, so
/// the composites cut and fill the rotations and the hips, and keep the
/// constant channels defined throughout (taken from the first clip).
const BANDAI_PRELUDE: &str = r#"
let a = load("$a")
let b = load("$b")
let body = body_of(a)
let moving = fn(m) = m.only("*rotation", "Hips.*")
let fixed = a - moving(a)
fn with_fixed(m) = m + clip_in_place(span(m)[0], span(m)[1], fixed)
"#;

#[test]
fn bandai_fig6_wave() {
    bandai_composite(
        "walk_normal",
        "wave-right-hand",
        &format!(
            "{BANDAI_PRELUDE}
let arm = clip(1s, 2s, b.only(\"UpperArm_R.?rotation\", \"LowerArm_R.?rotation\"))
let gapped = affine(1.3s, 1, arm) + (a - affine(1s, 1.6, arm))
let filled = SP(gapped, body: body, coefficients: 5, samples: 16)
print(\"torque energy: SP\", torque_energy(filled, body), \"Hermite\", torque_energy(fill(gapped, \"hermite\"), body))
"
        ),
    );
}

#[test]
fn bandai_walk_to_run() {
    bandai_composite(
        "1_walk_normal",
        "1_run_normal",
        &format!(
            "{BANDAI_PRELUDE}
let gapped = with_fixed(gap_between(clip(0s, 1s, moving(a)), clip(0s, 0.6s, moving(b)), 0.4s))
let filled = SP(gapped, body: body, coefficients: 3, samples: 8, contact: \"none\")
print(\"torque energy: SP\", torque_energy(filled, body), \"Hermite\", torque_energy(fill(gapped, \"hermite\"), body))
"
        ),
    );
}

#[test]
fn bandai_kick_to_walk() {
    bandai_composite(
        "kick_normal",
        "1_walk_normal",
        &format!(
            "{BANDAI_PRELUDE}
let gapped = with_fixed(gap_between(clip(0s, 1s, moving(a)), clip(0s, 0.6s, moving(b)), 0.4s))
let filled = SP(gapped, body: body, coefficients: 3, samples: 8, contact: \"none\")
print(\"torque energy: SP\", torque_energy(filled, body), \"Hermite\", torque_energy(fill(gapped, \"hermite\"), body))
"
        ),
    );
}

// ---- diagnostics and hard cases through the language ---------------------

const WALK: &str = "let walk = load(\"data/walk.bvh\")\nlet body = body_of(walk)\n";

/// The rendered diagnostic of a script that must fail (run in the sandbox).
fn diagnose(src: &str) -> String {
    let (mut mx, _, _dir) = sandbox();
    match mx.eval_named("bad.mx", &format!("{WALK}{src}")) {
        Ok(v) => panic!("expected an error from {src:?}, got {}", v.repr()),
        Err(d) => format!("[{}]\n{}", d.error().kind.code(), d.render_plain()),
    }
}

macro_rules! diag {
    ($name:ident, $src:expr) => {
        #[test]
        fn $name() {
            insta::assert_snapshot!(stringify!($name), diagnose($src));
        }
    };
}

diag!(
    sp_conflict,
    "let m = walk + clip_in_place(0.5s, 0.8s, walk.only(\"RightLeg.Xrotation\"))\nSP(m, body: body)"
);
diag!(
    sp_too_few_coefficients,
    "SP(walk, body: body, coefficients: 2, continuity: 2)"
);
diag!(sp_zero_samples, "SP(walk, body: body, samples: 0)");
diag!(sp_bad_continuity, "SP(walk, body: body, continuity: 3)");
diag!(
    sp_unknown_support,
    "SP(walk, body: body, support: [\"LeftFut\"])"
);
diag!(sp_without_body, "SP(walk)");
diag!(fill_unknown_method, "fill(walk, \"cubic\")");
diag!(sp_report_of_other_motion, "sp_report(walk)");
diag!(
    torque_energy_of_gapped_motion,
    "torque_energy(walk - clip_in_place(0.5s, 0.8s, walk.only(\"RightLeg.*\")), body)"
);

/// Evaluates `src` after loading the walk; returns the interpreter.
fn eval(src: &str) -> Interpreter {
    let (mut mx, _, _dir) = sandbox();
    if let Err(d) = mx.eval_named("case.mx", &format!("{WALK}{src}")) {
        panic!("{}", d.render_plain());
    }
    mx
}

fn number(mx: &Interpreter, name: &str) -> f64 {
    mx.get(name).and_then(|v| v.as_number()).unwrap()
}

#[test]
fn zero_length_gap_leaves_the_motion_as_it_is() {
    let mx = eval(
        "let m = gap_between(clip(0s, 1s, walk), clip(1s, 2s, walk), 0s)\n\
         let filled = SP(m, body: body)\n\
         let same = filled == m\n\
         let text = sp_report(filled).text",
    );
    assert_eq!(mx.get("same").and_then(|v| v.as_bool()), Some(true));
    let text = mx.get("text").unwrap();
    assert!(
        text.as_str().unwrap().contains("no interior gaps"),
        "{}",
        text.repr()
    );
}

#[test]
fn gaps_at_the_start_and_end_stay_undefined_and_are_reported() {
    let mx = eval(
        "let legs = walk.only(\"RightLeg.*\")\n\
         let m = walk - clip_in_place(0s, 0.3s, legs) - clip_in_place(1.8s, 2s, legs)\n\
         let filled = SP(m, body: body)\n\
         let r = sp_report(filled)\n\
         let n_undefined = len(r.undefined)\n\
         let n_groups = len(r.groups)\n\
         let first = r.undefined[0]\n\
         let starts = span(get(filled, \"RightLeg.Xrotation\"))[0]",
    );
    assert_eq!(number(&mx, "n_undefined"), 6.0);
    assert_eq!(number(&mx, "n_groups"), 0.0);
    let first = mx.get("first").unwrap().repr();
    assert!(first.contains("RightLeg"), "{first}");
    assert!(
        (number(&mx, "starts") - 0.3).abs() < 1e-9,
        "the start stays undefined"
    );
}

#[test]
fn identical_end_states_give_a_finite_continuous_transition() {
    // The walk's right hand never moves: both ends of its gap are the same state.
    let mx = eval(
        "let m = walk - clip_in_place(0.6s, 1.2s, walk.only(\"RightHand.*\", \"RightForeArm.*\"))\n\
         let filled = SP(m, body: body)\n\
         let r = sp_report(filled).groups[0]\n\
         let e0 = r.initial_energy\n\
         let e = r.energy",
    );
    let filled = mu(&mx.get("filled").unwrap());
    let [jq, jv, _] = jumps(&filled);
    assert!(jq <= 1e-9 && jv <= 1e-6);
    let (e0, e) = (number(&mx, "e0"), number(&mx, "e"));
    // not costlier than the Hermite start, to the solver's precision
    assert!(e.is_finite() && e <= e0 * (1.0 + 1e-5), "{e} vs {e0}");
}

#[test]
fn a_five_second_gap() {
    let mx = eval(
        "let long = loop(cyclify(walk, 0.5s, 1.5s), 8)\n\
         let t0 = span(long)[0]\n\
         let m = long - clip_in_place(t0 + 1.5s, t0 + 6.5s, long.only(\"RightForeArm.*\", \"LeftForeArm.*\"))\n\
         let g = gaps(m)[0]\n\
         let length = g.stop - g.start\n\
         let filled = SP(m, body: body, coefficients: 10)\n\
         let e0 = sp_report(filled).groups[0].initial_energy\n\
         let e = sp_report(filled).groups[0].energy",
    );
    assert!((number(&mx, "length") - 5.0).abs() < 1e-9);
    let filled = mu(&mx.get("filled").unwrap());
    let [jq, jv, _] = jumps(&filled);
    assert!(jq <= 1e-9 && jv <= 1e-6, "{jq} {jv}");
    assert!(number(&mx, "e") <= number(&mx, "e0"));
}

#[test]
fn ends_more_than_pi_apart_are_not_wrapped() {
    // The forearm turns by 4 rad across the gap: the transition goes the long
    // way (the angle is a joint coordinate, not modular) and ends exactly at 4.
    let mx = eval(
        "let name = \"RightForeArm.Zrotation\"\n\
         let turn = mu({\"RightForeArm.Zrotation\": dof(interval(0, 0s, 0.6s), interval(4, 1.4s, 2s))})\n\
         let m = (walk - walk.only(name)) + turn\n\
         let filled = SP(m, body: body)\n\
         let mid = sample(get(filled, name), 1s)\n\
         let end = sample(get(filled, name), 1.4s)",
    );
    let mid = number(&mx, "mid");
    assert!(mid > 0.5 && mid < 3.5, "{mid}");
    assert!((number(&mx, "end") - 4.0).abs() <= 1e-9);
    let filled = mu(&mx.get("filled").unwrap());
    let [jq, jv, _] = jumps(&filled);
    assert!(jq <= 1e-9 && jv <= 1e-6, "{jq} {jv}");
}

#[test]
fn a_cancelled_sp_returns_an_error_not_a_motion() {
    let (mut mx, _, _dir) = sandbox();
    mx.eval_str(WALK).unwrap();
    // A solve far longer than the 0.2 s after which the token is cancelled (as Ctrl-C does).
    let token = mx.cancel_token();
    let canceller = std::thread::spawn(move || {
        std::thread::sleep(std::time::Duration::from_millis(200));
        token.cancel();
    });
    let started = std::time::Instant::now();
    let err = mx
        .eval_str("let filled = SP(gap_between(walk, walk, 0.5s), body: body, coefficients: 40, samples: 200)")
        .unwrap_err();
    canceller.join().unwrap();
    assert_eq!(
        err.kind(),
        mx::lang::ErrorKind::Cancelled,
        "{}",
        err.render_plain()
    );
    assert!(
        mx.get("filled").is_none(),
        "no motion, not even a partial one"
    );
    println!("cancelled after {:.2} s", started.elapsed().as_secs_f64());
}

#[test]
fn the_report_reads_like_a_record_and_prints_as_text() {
    let mx = eval(
        "let m = walk - clip_in_place(0.6s, 1.2s, walk.only(\"RightForeArm.*\"))\n\
         let filled = SP(m, body: body, coefficients: 4, samples: 12, continuity: 2, support: [])\n\
         let g = sp_report(filled).groups[0]\n\
         let shown = str(sp_report(filled))",
    );
    let g = mx.get("g").unwrap().repr();
    for field in [
        "dofs: [\"RightForeArm.Zrotation\"",
        "t0: 0.6",
        "t1: 1.2",
        "iterations:",
        "initial_energy:",
        "energy:",
        "grad_norm:",
        "stop:",
    ] {
        assert!(g.contains(field), "{field} missing in {g}");
    }
    let shown = mx.get("shown").unwrap();
    assert!(
        shown
            .as_str()
            .unwrap()
            .starts_with("gap 1 [0.6000, 1.2000] s, 3 DOFs"),
        "{}",
        shown.repr()
    );
}

/// Rose §3.2.1 on Bandai: the all-zero `joint_Root` is a placeholder, so the
/// kinematic root is `Hips`: its x–z are filled from interpolated velocities
/// (named in the report), its path is C¹ through the gap, and the run after
/// the gap is translated to continue from where that path ends.
#[test]
fn bandai_natural_cut_keeps_the_frames_after_the_hole_where_they_were_recorded() {
    // every DOF cut, root included, inside one recording (issue 25's headline case)
    let src = "
let w = load(\"$a\")
let cut = w - clip_in_place(1s, 1.5s, w)
let filled = SP(cut, body: body_of(w), coefficients: 3, samples: 8, contact: \"none\")
print(sp_report(filled))
";
    let Some((mx, text)) = run_bandai("1_walk_normal", "1_walk_normal", src) else {
        return;
    };
    assert!(
        text.lines()
            .any(|l| l.starts_with("root over") && l.contains("pinned") && l.contains("auto")),
        "{text}"
    );
    assert!(!text.contains("translated by"), "{text}");
    let w = mu(&mx.get("w").unwrap());
    let filled = mu(&mx.get("filled").unwrap());
    assert!(mx::motion::gaps(&filled).is_empty());
    let [jq, jv, _] = jumps(&filled);
    assert!(jq <= 1e-9 && jv <= 1e-6, "jumps {jq} {jv}");
    let (_, end) = w.span().unwrap();
    let mut t = 1.5;
    while t <= end {
        for name in w.dofs.keys() {
            let a = w.sample(name, t).unwrap().unwrap()[0];
            let b = filled.sample(name, t).unwrap().unwrap()[0];
            assert!((a - b).abs() <= 1e-9, "{name} at {t}: {b} vs recorded {a}");
        }
        t += 0.25;
    }
}

#[test]
fn bandai_walk_to_run_root_is_the_hips() {
    let src = format!(
        "{BANDAI_PRELUDE}
let gapped = with_fixed(gap_between(clip(0s, 1s, moving(a)), clip(0s, 0.6s, moving(b)), 0.4s))
let filled = SP(gapped, body: body, coefficients: 3, samples: 8)
print(sp_report(filled))
"
    );
    let Some((mx, text)) = run_bandai("1_walk_normal", "1_run_normal", &src) else {
        return;
    };
    let root_line = text
        .lines()
        .find(|l| l.starts_with("root over"))
        .expect("a root line in the report");
    assert!(
        root_line.contains("Hips.Xposition") && root_line.contains("Hips.Zposition"),
        "{root_line}"
    );
    assert!(!root_line.contains("joint_Root"), "{root_line}");
    let gapped = mu(&mx.get("gapped").unwrap());
    let filled = mu(&mx.get("filled").unwrap());
    let gaps = gapped.get("Hips.Xposition").unwrap().gaps();
    assert_eq!(gaps.len(), 1, "{gaps:?}");
    let (t0, t1) = gaps[0];
    let at = |m: &Mu, n: &str, t: f64| m.sample(n, t).unwrap().unwrap();
    for n in ["Hips.Xposition", "Hips.Zposition"] {
        // C¹ at both ends of the transition (the jumps check of the composite
        // tests covers interval joins; here against the neighbouring samples)
        let h = 1e-6;
        for t in [t0, t1] {
            let [q0, v0, _] = at(&filled, n, t - h);
            let [q1, v1, _] = at(&filled, n, t + h);
            assert!(
                (q1 - q0).abs() < 1e-4 && (v1 - v0).abs() < 1e-2,
                "{n} at {t}"
            );
        }
        // the path is the integral of a linearly interpolated velocity
        let [p1, v1, _] = at(&filled, n, t0);
        let [p2, v2, _] = at(&filled, n, t1);
        let end = p1 + (t1 - t0) * (v1 + v2) / 2.0;
        assert!(
            (p2 - end).abs() < 1e-9,
            "{n}: ends at {p2}, path ends at {end}"
        );
        // after the gap the run is the recorded one translated by the shift
        let shift = p2 - at(&gapped, n, t1)[0];
        for t in [t1, t1 + 0.2, t1 + 0.5] {
            let moved = at(&filled, n, t)[0] - at(&gapped, n, t)[0];
            assert!(
                (moved - shift).abs() < 1e-9,
                "{n} at {t}: {moved} vs {shift}"
            );
        }
        assert!(
            root_line.contains(&format!("{n} {shift:+.4}")),
            "{root_line}"
        );
    }
    // the placeholder stays where it was
    for c in ["joint_Root.Xposition", "joint_Root.Zposition"] {
        assert_eq!(at(&filled, c, (t0 + t1) / 2.0)[0], 0.0);
    }
}

/// `contact:` as the issues write it: `"auto"` is the default (the same
/// transition to the bit: the body stands, its plan in
/// `sp_report(m).contacts`, the hole filled and continuous), `"none"` is
/// Rose's (the feet not planned), and the option's misuses are errors that
/// point at it.
#[test]
fn sp_contact_option_in_the_language() {
    let src = "
let w = load(\"$a\")
let cut = w - clip_in_place(1s, 1.5s, w)
let plain = SP(cut, body: body_of(w), coefficients: 3, samples: 8)
let none = SP(cut, body: body_of(w), coefficients: 3, samples: 8, contact: \"none\")
let planned = SP(cut, body: body_of(w), coefficients: 3, samples: 8, contact: \"auto\", floor: \"auto\")
let plan = sp_report(planned).contacts
let rose = sp_report(none).contacts
";
    let Some((mut mx, _)) = run_bandai("1_walk_normal", "1_walk_normal", src) else {
        return;
    };
    let (plain, planned) = (
        mu(&mx.get("plain").unwrap()),
        mu(&mx.get("planned").unwrap()),
    );
    let (_, end) = plain.span().unwrap();
    for k in 0..=40 {
        let t = end * k as f64 / 40.0;
        for name in plain.dofs.keys() {
            assert_eq!(
                plain.sample(name, t).unwrap(),
                planned.sample(name, t).unwrap(),
                "{name} at {t}"
            );
        }
    }
    assert_eq!(
        mx.get("rose").unwrap().repr(),
        "[]",
        "contact: \"none\" plans nothing"
    );
    assert!(mx::motion::gaps(&planned).is_empty());
    let [jq, jv, _] = jumps(&planned);
    assert!(jq <= 1e-9 && jv <= 1e-6, "jumps {jq} {jv}");
    let plan = mx.get("plan").unwrap();
    assert!(plan.repr().contains("Toes_"), "{}", plan.repr());
    for (bad, says) in [
        ("SP(cut, body: body_of(w), contact: \"feet\")", "contact"),
        (
            "SP(cut, body: body_of(w), contact: [\"Toes_X\"])",
            "no frame named `Toes_X`",
        ),
        (
            "SP(cut, body: body_of(w), contact: \"auto\", support: [])",
            "replaces `support:`",
        ),
        (
            "SP(cut, body: body_of(w), contact: \"auto\", floor: \"low\")",
            "`floor:`",
        ),
    ] {
        let e = mx.eval_str(bad).unwrap_err().render_plain();
        assert!(e.contains(says), "{bad}: {e}");
    }
}
