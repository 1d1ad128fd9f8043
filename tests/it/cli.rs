//! The real binary: exit codes, stdout carrying only `print` output,
//! diagnostics on stderr, `run`/`check`/`eval`, and every example script.

use std::path::Path;
use std::process::{Command, Output};

fn mx(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_mx"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("runs mx")
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

#[test]
fn eval_prints_the_value_and_errors_exit_1() {
    let dir = tempfile::tempdir().unwrap();
    let o = mx(&["eval", "1 + 2 * 3"], dir.path());
    assert!(o.status.success());
    assert_eq!(text(&o.stdout), "7\n");
    let o = mx(&["eval", "[0.1, 1e-12, {a: 1}]"], dir.path());
    assert_eq!(text(&o.stdout), "[0.1, 1e-12, {a: 1}]\n");
    let o = mx(&["eval", "let walk = 1\nwakl"], dir.path());
    assert_eq!(o.status.code(), Some(1));
    assert!(
        o.stdout.is_empty(),
        "stdout must stay clean: {}",
        text(&o.stdout)
    );
    let err = text(&o.stderr);
    assert!(
        err.contains("unknown name `wakl`") && err.contains("did you mean `walk`?"),
        "{err}"
    );
}

#[test]
fn run_writes_only_print_output_to_stdout() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("a.mx"), "print(\"a\", 0.1)\nlet m = mu({x: interval(1, 0, 1)})\nsave(m, \"o/m.csv\", rate: 2)\neprint(\"progress\")\nprint(m)\n").unwrap();
    let o = mx(&["run", "a.mx"], dir.path());
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert_eq!(
        text(&o.stdout),
        "a 0.1\nMu [0, 1] (1 DOF: x; 1 interval, 0 gaps, 0 conflicts)\n"
    );
    assert_eq!(text(&o.stderr), "progress\n");
    assert_eq!(
        std::fs::read_to_string(dir.path().join("o/m.csv")).unwrap(),
        "t,x\n0,1\n0.5,1\n1,1\n"
    );
}

#[test]
fn runtime_error_exits_1_with_file_and_span() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("bad.mx"),
        "print(1)\nlet walk = mu({x: interval(1, 0, 2.4)})\nclip(2.0, 3.5, walk)\n",
    )
    .unwrap();
    let o = mx(&["run", "bad.mx"], dir.path());
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(text(&o.stdout), "1\n");
    let err = text(&o.stderr);
    assert!(err.contains("bad.mx:3:1"), "{err}");
    assert!(
        err.contains("clip [2.0, 3.5] lies outside walk's span [0, 2.4]"),
        "{err}"
    );
}

#[test]
fn check_parses_and_resolves_without_running() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("ok.mx"), "print(\"ran\")\n1 / 0\n").unwrap();
    let o = mx(&["check", "ok.mx"], dir.path());
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(o.stdout.is_empty(), "check must not run the script");
    std::fs::write(dir.path().join("bad.mx"), "fn f(t) = t + k\n").unwrap();
    let o = mx(&["check", "bad.mx"], dir.path());
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o.stderr).contains("unknown name `k`"));
    let o = mx(&["run", "missing.mx"], dir.path());
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o.stderr).contains("cannot read missing.mx"));
    // every statement's error, not only the first; a broken `let` still
    // binds its name, so `a` below is not reported again
    std::fs::write(
        dir.path().join("many.mx"),
        "let a = wakl + 1
print(a, runn)
fn g(x) = x * jmp
let ok = a
",
    )
    .unwrap();
    let o = mx(&["check", "many.mx"], dir.path());
    assert_eq!(o.status.code(), Some(1));
    let err = text(&o.stderr);
    assert!(err.contains("3 errors in many.mx"), "{err}");
    for name in ["wakl", "runn", "jmp"] {
        assert!(err.contains(&format!("unknown name `{name}`")), "{err}");
    }
    assert!(!err.contains("unknown name `a`"), "{err}");
}

/// `mx check` reads on past syntax errors (to the next statement) and
/// resolves the names of every statement that parses: each independent
/// error is reported once, in source order, at its line and column.
#[test]
fn check_reports_every_syntax_error_and_unknown_name_in_order() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("typos.mx"),
        "let walk = 1
print(walk 2)
let = 3
let a = wakl + runn
let b = [1, 2
print(a, b, jmp)
fn f(x) = x +* 1
print(f(a), walk)
",
    )
    .unwrap();
    let o = mx(&["check", "typos.mx"], dir.path());
    assert_eq!(o.status.code(), Some(1));
    assert!(o.stdout.is_empty(), "check must not run the script");
    let err = text(&o.stderr);
    assert!(err.contains("7 errors in typos.mx"), "{err}");
    // (line:col, what is reported there), in the order they must appear
    let expected = [
        ("2:12", "expected"),
        ("3:5", "expected a name"),
        ("4:9", "unknown name `wakl`"),
        ("4:16", "unknown name `runn`"),
        ("5:9", "this `[` is never closed"),
        ("6:13", "unknown name `jmp`"),
        ("7:14", "expected"),
    ];
    let mut from = 0;
    for (at, what) in expected {
        let loc = format!("typos.mx:{at}");
        let k = err[from..]
            .find(&loc)
            .unwrap_or_else(|| panic!("{loc} ({what}) missing or out of order:\n{err}"))
            + from;
        // the message is printed above its location
        let message_start = err[..k].rfind("× ").unwrap_or(0);
        assert!(
            err[message_start..k].contains(what),
            "{loc}: no `{what}`:\n{err}"
        );
        from = k + loc.len();
    }
    // names bound by a broken statement (`b`, `f`) are not reported again
    for name in ["`b`", "`f`", "`a`"] {
        assert!(!err.contains(&format!("unknown name {name}")), "{err}");
    }
}

#[test]
fn the_tour_runs_and_its_outputs_are_right() {
    // The tour and its data copied to a temporary folder and run there as a
    // newcomer would (`cd examples && mx run tour.mx`): a script's paths are
    // taken from its own folder, so it reads data/ and writes out/ beside it.
    let dir = tempfile::tempdir().unwrap();
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    std::fs::create_dir(dir.path().join("data")).unwrap();
    for e in std::fs::read_dir(examples.join("data")).unwrap() {
        let p = e.unwrap().path();
        std::fs::copy(&p, dir.path().join("data").join(p.file_name().unwrap())).unwrap();
    }
    std::fs::copy(examples.join("tour.mx"), dir.path().join("tour.mx")).unwrap();
    let o = mx(&["run", "tour.mx"], dir.path());
    assert!(o.status.success(), "{}", text(&o.stderr));
    let out = text(&o.stdout);
    for expected in [
        "numbers: 7 0.1 1e-12 0.25 1.5707963267948966",
        "recursion: 3628800",
        "walk - wave: Mu [0, 2.4]",
        "gaps: [{dof: \"Hips.Zrotation\", start: 0.8, stop: 1.8}]",
        "walk + wave conflicts: [{dof: \"Hips.Zrotation\", start: 0.8, stop: 1.8}]",
        "mixed: Mu [0, 2.4] (3 DOFs: Hips.Xposition, Hips.Yposition, Hips.Zrotation; 5 intervals, 0 gaps, 0 conflicts) conflicts: 0",
        "clip: [0, 1] clip_in_place: [0.5, 1.5]",
        "sample at 0.25 s: {\"Hips.Xposition\": 0.3, \"Hips.Yposition\": 0.9, \"Hips.Zrotation\": 0.1}",
        "json round trip exact: true",
        "waving walk: Mu [0, 2] (60 DOFs",
        "18 gaps, 0 conflicts) gaps: 18 conflicts: 0",
        "body: Body body_of (65 links, 60 coordinates, 70.0 kg)",
        "torque to hold the T-pose, first six: 0 686.4655 0",
    ] {
        assert!(out.contains(expected), "missing {expected:?} in\n{out}");
    }
    let csv = std::fs::read_to_string(dir.path().join("out/tour.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("t,Hips.Xposition,Hips.Yposition,Hips.Zrotation")
    );
    assert_eq!(csv.lines().count(), 1 + 25, "rows at k/10 over [0, 2.4]");
    assert!(dir.path().join("out/tour.json").exists());
    for picture in ["out/tour_forearm.svg", "out/tour_walk.html"] {
        let len = std::fs::metadata(dir.path().join(picture))
            .map(|m| m.len())
            .unwrap_or(0);
        assert!(len > 1000, "{picture} missing or empty");
    }
}

#[test]
fn every_example_script_runs() {
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut n = 0;
    for entry in std::fs::read_dir(&examples).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) != Some("mx") {
            continue;
        }
        // From the repository root, as the README runs them: a script's
        // paths are its folder's (it reads examples/data and writes the
        // git-ignored examples/out/).
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let o = mx(&["run", path.to_str().unwrap()], root);
        assert!(
            o.status.success(),
            "{} failed:\n{}",
            path.display(),
            text(&o.stderr)
        );
        assert!(!o.stdout.is_empty(), "{} printed nothing", path.display());
        n += 1;
    }
    assert!(n >= 1);
}

#[test]
fn step_budget_flag_stops_runaway_scripts() {
    let dir = tempfile::tempdir().unwrap();
    let o = mx(
        &[
            "--steps",
            "10000",
            "eval",
            "fold(range(100000), 0, fn(a, x) = a + x)",
        ],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o.stderr).contains("budget of 10000 steps"));
}

#[test]
fn repl_plot_draws_a_motion_in_the_terminal_and_refuses_other_values() {
    use std::io::Write;
    use std::process::{Command, Stdio};
    let dir = tempfile::tempdir().unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_mx"))
        .current_dir(dir.path())
        .env("HOME", dir.path())
        .env("XDG_DATA_HOME", dir.path())
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(b":plot mu({x: interval(fn(t) = sin(3*t), 0s, 2s), y: interval(0.5, 0s, 1s)})\n:plot 3\n:quit\n")
        .unwrap();
    let o = child.wait_with_output().unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        out.contains("a = x") && out.contains("b = y"),
        "no legend in\n{out}\n{err}"
    );
    assert!(out.contains("2.000 s"), "no time axis in\n{out}");
    assert!(err.contains(":plot needs a motion"), "{err}");
}

/// `mx … | head -c 20`: the reader goes away while mx still writes. mx must
/// end as Unix tools do — quietly, status 0 or killed by SIGPIPE (141 in a
/// shell) — not panic with "failed printing to stdout" and a backtrace.
#[test]
fn a_closed_stdout_ends_mx_quietly() {
    use std::io::Read;
    let dir = tempfile::tempdir().unwrap();
    // `print` line by line (mx run) and one large value (mx eval): both far
    // beyond a pipe's buffer, so mx is still writing when the reader closes
    std::fs::write(
        dir.path().join("many.mx"),
        "map(range(200000), fn(i) = print(\"line\", i))\n",
    )
    .unwrap();
    for args in [
        &["eval", "range(300000)"][..],
        &["run", "many.mx"][..],
        &["help", "--markdown"][..],
    ] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_mx"))
            .args(args)
            .current_dir(dir.path())
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .expect("runs mx");
        let mut head = [0u8; 20];
        child.stdout.take().unwrap().read_exact(&mut head).unwrap();
        // the read end is dropped here, like `head -c 20` exiting
        let out = child.wait_with_output().unwrap();
        let err = text(&out.stderr);
        assert!(
            err.is_empty(),
            "mx {args:?} wrote to stderr after stdout closed: {err}"
        );
        #[cfg(unix)]
        {
            use std::os::unix::process::ExitStatusExt;
            assert!(
                out.status.code() == Some(0) || out.status.signal() == Some(libc::SIGPIPE),
                "mx {args:?} ended with {:?}",
                out.status
            );
        }
    }
}
