//! Drives the real binary's REPL through a pseudo-terminal: typing, tab
//! completion, multi-line input, an error, Ctrl-C cancelling a long
//! evaluation, and :quit.

use std::process::Command;
use std::time::Duration;

use expectrl::{ControlCode, Eof, Session};

#[test]
fn repl_in_a_terminal() {
    let data = tempfile::tempdir().unwrap();
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_mx"));
    cmd.env("XDG_DATA_HOME", data.path())
        .env("HOME", data.path())
        .env("NO_COLOR", "1")
        .env("TERM", "xterm");
    let mut p = Session::spawn(cmd).expect("spawn mx in a pty");
    p.set_expect_timeout(Some(Duration::from_secs(20)));
    p.expect("mx> ").unwrap();

    p.send_line("let abcdef = 41").unwrap();
    p.expect("mx> ").unwrap();
    // Tab completes a name defined in this session.
    p.send("abcd").unwrap();
    p.send("\t").unwrap();
    p.send_line(" + 1").unwrap();
    p.expect("42").unwrap();

    // Multi-line: the list stays open across lines.
    p.send_line("[1,").unwrap();
    p.send_line("2]").unwrap();
    p.expect("[1, 2]").unwrap();

    // An error is reported and the REPL goes on.
    p.send_line("wakl + 1").unwrap();
    p.expect("unknown name `wakl`").unwrap();

    // :help from the doc strings.
    p.send_line(":help sin").unwrap();
    p.expect("Sine (radians).").unwrap();

    // Ctrl-C cancels a long evaluation and returns to the prompt.
    p.send_line("map(range(2000), fn(i) = fold(range(100000), 0, fn(a, x) = a + x))")
        .unwrap();
    std::thread::sleep(Duration::from_millis(700));
    p.send(ControlCode::EndOfText).unwrap();
    match p.expect("cancelled") {
        Ok(_) => {}
        Err(e) => {
            let mut buf = vec![0u8; 4096];
            let n = std::io::Read::read(&mut p, &mut buf).unwrap_or(0);
            panic!(
                "no `cancelled`: {e}; output: {:?}",
                String::from_utf8_lossy(&buf[..n])
            );
        }
    }
    p.send_line("abcdef * 2").unwrap();
    p.expect("82").unwrap();

    p.send_line(":quit").unwrap();
    p.expect(Eof).unwrap();
    assert!(
        data.path().join("mx/history.txt").exists(),
        "history is saved in the data dir"
    );
}

#[test]
fn sp_in_the_repl_info_progress_bar_and_ctrl_c() {
    let data = tempfile::tempdir().unwrap();
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_mx"));
    cmd.env("XDG_DATA_HOME", data.path())
        .env("HOME", data.path())
        .env("NO_COLOR", "1")
        .env("TERM", "xterm");
    let mut p = Session::spawn(cmd).expect("spawn mx in a pty");
    p.set_expect_timeout(Some(Duration::from_secs(60)));
    p.expect("mx> ").unwrap();
    // Each input prints a word the echo does not contain, so the next input is
    // typed only once the previous one has finished (rustyline drops type-ahead).
    let walk = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/walk.bvh");
    p.send_line(format!(
        "let walk = load(\"{walk}\"); let body = body_of(walk); print(\"loaded\" + \"!\")"
    ))
    .unwrap();
    p.expect("loaded!").unwrap();
    p.send_line("let m = walk - clip_in_place(0.6s, 1.2s, walk.only(\"RightForeArm.*\")); print(\"cut\" + \"!\")")
        .unwrap();
    p.expect("cut!").unwrap();
    p.send_line(
        "let filled = SP(m, body: body, coefficients: 3, samples: 8); print(\"solved\" + \"!\")",
    )
    .unwrap();
    p.expect("solved!").unwrap();
    // :info shows SP's report beside the value.
    p.send_line(":info filled").unwrap();
    p.expect("SP report:").unwrap();
    p.expect("gap 1 [0.6000, 1.2000] s, 3 DOFs").unwrap();

    // A long SP shows its bar after 0.5 s (where it is within the group:
    // solve, iteration, evaluations); Ctrl-C cancels it and binds nothing.
    p.send_line(
        "let big = SP(gap_between(walk, walk, 0.5s), body: body, coefficients: 40, samples: 200)",
    )
    .unwrap();
    p.expect("objective evaluations").unwrap();
    p.send(ControlCode::EndOfText).unwrap();
    p.expect("cancelled").unwrap();
    p.send_line("big").unwrap();
    p.expect("unknown name `big`").unwrap();
    p.send_line(":quit").unwrap();
    p.expect(Eof).unwrap();
}

/// The words a newcomer types (issue 28): `help` and `help NAME` without the
/// colon, `:help` with a misspelt topic suggests it, `:info` on a loaded clip
/// says where it came from, and `exit` (or `quit`) leaves.
#[test]
fn repl_takes_help_and_exit_as_people_type_them() {
    for leave in ["exit", "quit"] {
        let data = tempfile::tempdir().unwrap();
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_mx"));
        cmd.env("XDG_DATA_HOME", data.path())
            .env("HOME", data.path())
            .env("NO_COLOR", "1")
            .env("TERM", "xterm");
        let mut p = Session::spawn(cmd).expect("spawn mx in a pty");
        p.set_expect_timeout(Some(Duration::from_secs(20)));
        p.expect("mx> ").unwrap();
        p.send_line("help sin").unwrap();
        p.expect("Sine (radians).").unwrap();
        p.send_line(":help motoin").unwrap();
        p.expect("did you mean `motion`?").unwrap();
        let walk = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/walk.bvh");
        p.send_line(format!(
            "let walk = load(\"{walk}\"); print(\"loaded\" + \"!\")"
        ))
        .unwrap();
        p.expect("loaded!").unwrap();
        p.send_line(":info walk").unwrap();
        p.expect("clip from ").unwrap();
        p.expect("walk.bvh: ").unwrap();
        p.expect(" frames at ").unwrap();
        p.expect(" joints").unwrap();
        p.send_line(leave).unwrap();
        p.expect(Eof).unwrap();
    }
}

/// Tab inside a string (issue 28): a file path in `load("…` (relative to the
/// folder the REPL runs in), and a DOF name of a motion bound in the session
/// in `only("…`.
#[test]
fn tab_completes_paths_and_dof_names_inside_strings() {
    let data = tempfile::tempdir().unwrap();
    let folder = tempfile::tempdir().unwrap();
    std::fs::create_dir(folder.path().join("clips")).unwrap();
    let walk = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/walk.bvh");
    std::fs::copy(walk, folder.path().join("clips/walk.bvh")).unwrap();
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_mx"));
    cmd.current_dir(folder.path())
        .env("XDG_DATA_HOME", data.path())
        .env("HOME", data.path())
        .env("NO_COLOR", "1")
        .env("TERM", "xterm");
    let mut p = Session::spawn(cmd).expect("spawn mx in a pty");
    p.set_expect_timeout(Some(Duration::from_secs(20)));
    p.expect("mx> ").unwrap();
    // `cl` → `clips/`, then `wa` → `walk.bvh`: the line runs only if both completed.
    p.send("let w = load(\"cl").unwrap();
    p.send("\t").unwrap();
    p.expect("clips/").unwrap();
    p.send("wa").unwrap();
    p.send("\t").unwrap();
    p.expect("walk.bvh").unwrap();
    p.send_line("\"); print(\"loaded\" + \"!\")").unwrap();
    p.expect("loaded!").unwrap();
    // `LeftFoot.Z` → `LeftFoot.Zrotation`, one of w's DOFs.
    p.send("print(dofs(w.only(\"LeftFoot.Z").unwrap();
    p.send("\t").unwrap();
    p.send_line("\")))").unwrap();
    p.expect("[\"LeftFoot.Zrotation\"]").unwrap();
    p.send_line(":quit").unwrap();
    p.expect(Eof).unwrap();
}

/// A line that begins with an operator continues the one above within one
/// input (a block still open, or lines pasted together); at the prompt, with
/// nothing above it, the error says why; a glued minus stays unary.
#[test]
fn a_line_may_begin_with_an_operator_in_the_repl() {
    let data = tempfile::tempdir().unwrap();
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_mx"));
    cmd.env("XDG_DATA_HOME", data.path())
        .env("HOME", data.path())
        .env("NO_COLOR", "1")
        .env("TERM", "xterm");
    let mut p = Session::spawn(cmd).expect("spawn mx in a pty");
    p.set_expect_timeout(Some(Duration::from_secs(20)));
    p.expect("mx> ").unwrap();
    // typed line by line while the block is open; each input prints a word its
    // echo does not contain, so the next is typed once it has run
    p.send_line("let f = fn(x) {").unwrap();
    p.send_line("  x").unwrap();
    p.send_line("    + 1").unwrap();
    p.send_line("}; print(\"typed\" + \"!\", f(41))").unwrap();
    p.expect("typed! 42").unwrap();
    // lines pasted at once (bracketed paste), then Enter
    p.send("\x1b[200~let y = 40\n  + 2\nprint(\"pasted\" + \"!\", y)\x1b[201~")
        .unwrap();
    p.send("\r").unwrap();
    p.expect("pasted! 42").unwrap();
    // nothing open above: the error explains
    p.send_line("+ 1").unwrap();
    p.expect("continues the expression on the line above")
        .unwrap();
    // a glued minus is a new statement's unary minus
    p.send_line("-y").unwrap();
    p.expect("-42").unwrap();
    p.send_line(":quit").unwrap();
    p.expect(Eof).unwrap();
}
