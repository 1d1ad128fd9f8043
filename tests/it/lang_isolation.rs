//! Two interpreters in one process share nothing mutable: a clip's skeleton
//! and SP's report travel with the motion value they belong to, and what an
//! interpreter remembers of the clips it loaded is its own — also when two
//! interpreters run at the same time on two threads.

use std::path::{Path, PathBuf};
use std::sync::{Arc, Barrier};

use mx::Interpreter;

fn data(name: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("examples/data")
        .join(name)
        .display()
        .to_string()
}

fn quiet() -> Interpreter {
    let mut mx = Interpreter::new();
    mx.capture_output();
    mx
}

fn run(mx: &mut Interpreter, src: &str) {
    if let Err(d) = mx.eval_str(src) {
        panic!("{src}\n{}", d.render_plain());
    }
}

fn fails(mx: &mut Interpreter, src: &str) -> String {
    match mx.eval_str(src) {
        Ok(v) => panic!("{src} gave {}", v.repr()),
        Err(d) => d.render_plain(),
    }
}

/// A motion with some of the walk's DOF names and no provenance: only a
/// clip the interpreter loaded can give it a skeleton.
const LOOSE: &str =
    "mu({\"Hips.Xposition\": interval(0, 0, 1), \"Spine.Zrotation\": interval(0, 0, 1)})";

#[test]
fn a_clip_loaded_in_one_interpreter_is_unknown_to_another() {
    let mut a = quiet();
    let mut b = quiet();
    run(&mut a, &format!("let walk = load({:?})", data("walk.bvh")));
    run(&mut a, &format!("let body = body_of({LOOSE})"));
    let e = fails(&mut b, &format!("body_of({LOOSE})"));
    assert!(e.contains("no loaded clip's skeleton"), "{e}");
    // A value brings its own clip along: b can use a's walk, not its derivatives.
    b.set("walk", a.get("walk").unwrap());
    run(&mut b, "let body = body_of(walk)");
    let e = fails(&mut b, "body_of(clip(0s, 1s, walk))");
    assert!(e.contains("no loaded clip's skeleton"), "{e}");
}

#[test]
fn sp_report_travels_with_its_value_not_with_the_interpreter() {
    let mut a = quiet();
    run(
        &mut a,
        &format!(
            "let walk = load({:?})\n\
             let body = body_of(walk)\n\
             let filled = SP(walk, body: body)\n\
             let text = sp_report(filled).text",
            data("walk.bvh")
        ),
    );
    let mut b = quiet();
    let dir = tempfile::tempdir().unwrap();
    b.set("filled", a.get("filled").unwrap());
    run(&mut b, "let text = sp_report(filled).text");
    assert_eq!(a.get("text").unwrap().repr(), b.get("text").unwrap().repr());
    let e = fails(&mut b, "sp_report(clip(0s, 1s, filled))");
    assert!(e.contains("was not returned by SP"), "{e}");
    // SP's result keeps the clip of its input: b, which loaded nothing, writes it as BVH.
    let out = dir.path().join("filled.bvh");
    run(
        &mut b,
        &format!("save(filled, {:?})", out.display().to_string()),
    );
    assert!(out.exists());
}

/// `walk.bvh` with every bone twice as long.
fn tall_walk(dir: &Path) -> String {
    let text = std::fs::read_to_string(data("walk.bvh")).unwrap();
    let doubled: Vec<String> = text
        .lines()
        .map(|l| match l.trim_start().strip_prefix("OFFSET") {
            Some(rest) => {
                let indent = &l[..l.len() - l.trim_start().len()];
                let xs: Vec<String> = rest
                    .split_whitespace()
                    .map(|x| (2.0 * x.parse::<f64>().unwrap()).to_string())
                    .collect();
                format!("{indent}OFFSET {}", xs.join(" "))
            }
            None => l.to_string(),
        })
        .collect();
    let path = dir.join("tall.bvh");
    std::fs::write(&path, doubled.join("\n") + "\n").unwrap();
    path.display().to_string()
}

/// The height of the head in the rest pose of the body made for a piece of
/// `clip` (a new motion, so its skeleton comes from the clips loaded).
const HEAD: &str = "let part = clip(0s, 0.5s, clip_)\n\
                    let b = body_of(part)\n\
                    point(b, \"Head\", map(range(b.nq), fn(i) = 0))[1]";

fn head_heights(path: String, start: Arc<Barrier>) -> Vec<f64> {
    let mut mx = quiet();
    run(&mut mx, &format!("let clip_ = load({path:?}, unit: 0.01)"));
    // Both threads have loaded their clip before either asks for a skeleton.
    start.wait();
    (0..20)
        .map(|_| {
            mx.eval_str(HEAD)
                .map_err(|d| d.render_plain())
                .unwrap()
                .as_number()
                .unwrap()
        })
        .collect()
}

#[test]
fn interpreters_on_two_threads_keep_their_own_clips() {
    let dir = tempfile::tempdir().unwrap();
    let tall = tall_walk(dir.path());
    let start = Arc::new(Barrier::new(2));
    let (s1, s2) = (start.clone(), start);
    let walk = std::thread::spawn(move || head_heights(data("walk.bvh"), s1));
    let tall = std::thread::spawn(move || head_heights(tall, s2));
    let (walk, tall) = (walk.join().unwrap(), tall.join().unwrap());
    assert!(walk[0] > 0.1, "the head is above the hips: {}", walk[0]);
    for (w, t) in walk.iter().zip(&tall) {
        assert_eq!(*w, walk[0], "walk's interpreter always finds the walk");
        assert!(
            (t - 2.0 * w).abs() < 1e-9,
            "the tall clip's interpreter finds its own skeleton: {t} vs 2 × {w}"
        );
    }
}
