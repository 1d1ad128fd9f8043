//! Documentation that cannot lie (issue 38): every ```mx block of README.md
//! and docs/**/*.md runs, and a ```text output block right after one must be
//! what it printed.
//!
//! - A block marked ```mx no-run is skipped (a sketch, or one that needs what
//!   the tests do not have).
//! - The blocks of one file run in order in one interpreter, so a block may use
//!   what earlier blocks of the same file defined (the README's sections build
//!   on its Getting started). Files do not share anything.
//! - Paths are the repository root's, as a reader running the examples from a
//!   fresh clone would type them (`examples/data/walk.bvh`); what a block
//!   writes lands in a temporary folder, never in the checkout. A block that
//!   needs the shared data reads `env("MX_SHARED")`, else `../shared`, as the
//!   tests do: the temporary root has the shared folder beside it. Without
//!   shared data (a developer machine; CI fails instead) such blocks are
//!   skipped with a note, and so is every later block of the file.
//! - A failure names the Markdown file and line: the block runs as a file whose
//!   line numbers are the Markdown file's own.

use crate::common;

use std::path::{Path, PathBuf};

/// One fenced code block of a Markdown file.
#[derive(Debug, Clone, PartialEq)]
pub struct Block {
    /// The fence's info string split into words: language first, then flags.
    pub info: Vec<String>,
    /// 1-based line of the opening fence.
    pub line: usize,
    pub text: String,
}

impl Block {
    fn lang(&self) -> &str {
        self.info.first().map(String::as_str).unwrap_or("")
    }
    fn has(&self, flag: &str) -> bool {
        self.info.iter().skip(1).any(|w| w == flag)
    }
    /// An mx block the test runs.
    pub fn runs(&self) -> bool {
        self.lang() == "mx" && !self.has("no-run")
    }
    /// A ```text output block: what the mx block before it prints.
    fn is_output(&self) -> bool {
        self.lang() == "text" && self.has("output")
    }
}

/// The fenced blocks of a Markdown text (backtick or tilde fences, indented
/// ones inside lists included, their indentation removed) with, for each, the
/// 1-based line of the last line before the next block, so an output block is
/// found only when nothing but blank lines separates it from its code.
pub fn blocks(markdown: &str) -> Vec<(Block, usize)> {
    let lines: Vec<&str> = markdown.lines().collect();
    let mut out: Vec<(Block, usize)> = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let line = lines[i];
        let indent = line.len() - line.trim_start().len();
        let rest = line.trim_start();
        let fence_char = rest.chars().next();
        let run = rest.chars().take_while(|&c| Some(c) == fence_char).count();
        if !matches!(fence_char, Some('`' | '~')) || run < 3 {
            i += 1;
            continue;
        }
        let fence = &rest[..run];
        let info: Vec<String> = rest[run..].split_whitespace().map(String::from).collect();
        let start = i;
        let mut body = Vec::new();
        i += 1;
        while i < lines.len() && !lines[i].trim().starts_with(fence) {
            let l = lines[i];
            let strip = l.len() - l.trim_start().len();
            body.push(&l[strip.min(indent)..]);
            i += 1;
        }
        // the closing fence (or the end of a file left open)
        i += 1;
        let mut text = body.join("\n");
        text.push('\n');
        let block = Block {
            info,
            line: start + 1,
            text,
        };
        out.push((block, i));
    }
    out
}

/// Whether only blank lines lie between 1-based lines `after` (exclusive) and
/// `before` (exclusive).
fn only_blank_between(lines: &[&str], after: usize, before: usize) -> bool {
    (after..before.saturating_sub(1)).all(|k| lines.get(k).is_none_or(|l| l.trim().is_empty()))
}

/// README.md and every .md under docs/, sorted.
fn markdown_files() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = vec![root.join("README.md")];
    let mut stack = vec![root.join("docs")];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "md") {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

/// A folder laid out like a fresh clone's root, in a temporary folder with
/// nothing beside it (no `../shared`): `examples/` copied (scripts write
/// under it, and `examples/..` must not lead back to the checkout), the other
/// folders blocks may read linked in.
pub fn clone_like_root() -> (tempfile::TempDir, PathBuf) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let tmp = tempfile::tempdir().unwrap();
    let work = tmp.path().join("repo");
    std::fs::create_dir(&work).unwrap();
    copy_dir(&root.join("examples"), &work.join("examples"));
    for name in ["stdlib", "docs", "tests", "scripts"] {
        std::os::unix::fs::symlink(root.join(name), work.join(name)).unwrap();
    }
    (tmp, work)
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let path = entry.unwrap().path();
        let dest = to.join(path.file_name().unwrap());
        if path.is_dir() {
            // what earlier runs wrote is no part of a clone
            if path.file_name().is_some_and(|n| n == "out") {
                continue;
            }
            copy_dir(&path, &dest);
        } else {
            std::fs::copy(&path, &dest).unwrap();
        }
    }
}

/// Marks where a block's output starts in the script's stdout: printed from
/// the block's opening fence line, which the script leaves blank otherwise,
/// so every other line keeps the Markdown file's line number.
fn marker(line: usize) -> String {
    format!("\u{1}block {line}")
}

/// One file's runnable blocks as one script at the Markdown file's line
/// numbers: prose lines blank, each block's fence line printing its marker.
/// Stops before the first block that needs the shared data when there is
/// none (`skipped` says where).
fn script_of(found: &[(Block, usize)], shared: bool) -> (String, Option<usize>) {
    let mut lines: Vec<String> = Vec::new();
    for (block, _) in found.iter().filter(|(b, _)| b.runs()) {
        if !shared && block.text.contains("MX_SHARED") {
            return (lines.join("\n") + "\n", Some(block.line));
        }
        lines.resize(block.line - 1, String::new());
        lines.push(format!("print({:?})", marker(block.line)));
        lines.extend(block.text.lines().map(String::from));
    }
    (lines.join("\n") + "\n", None)
}

/// What each block printed, by the line of its opening fence.
fn outputs_by_block(stdout: &str) -> Vec<(usize, String)> {
    let mut out: Vec<(usize, String)> = Vec::new();
    for line in stdout.lines() {
        match line
            .strip_prefix("\u{1}block ")
            .and_then(|n| n.parse().ok())
        {
            Some(n) => out.push((n, String::new())),
            None => {
                if let Some((_, text)) = out.last_mut() {
                    text.push_str(line);
                    text.push('\n');
                }
            }
        }
    }
    out
}

fn normalised(s: &str) -> String {
    s.lines()
        .map(str::trim_end)
        .collect::<Vec<_>>()
        .join("\n")
        .trim()
        .to_string()
}

/// Runs one file's blocks with the `mx` binary, in order in one session, in a
/// clone-like folder; returns its failures, each naming file and line. The
/// README runs as a reader of a fresh clone would: no shared data beside the
/// folder and `MX_SHARED` unset. The docs' blocks get the shared data when
/// there is some.
fn run_file(path: &Path, shared: Option<&Path>) -> Vec<String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let rel = path
        .strip_prefix(root)
        .unwrap_or(path)
        .display()
        .to_string();
    let readme = rel == "README.md";
    let shared = if readme { None } else { shared };
    let markdown = std::fs::read_to_string(path).unwrap();
    let lines: Vec<&str> = markdown.lines().collect();
    let found = blocks(&markdown);
    let (_tmp, work) = clone_like_root();
    if let Some(s) = shared {
        std::os::unix::fs::symlink(s, work.parent().unwrap().join("shared")).unwrap();
    }
    let (script, skipped) = script_of(&found, shared.is_some());
    if let Some(line) = skipped {
        eprintln!("SKIPPED: {rel}:{line} and after: no shared data");
    }
    // named as the Markdown file, so a diagnostic reads `README.md:LINE`
    let file = work.join(path.file_name().unwrap());
    std::fs::write(&file, script).unwrap();
    let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_mx"));
    cmd.arg("run")
        .arg(&file)
        .current_dir(&work)
        .env("NO_COLOR", "1");
    match shared {
        Some(s) => cmd.env("MX_SHARED", s),
        None => cmd.env_remove("MX_SHARED"),
    };
    let run = cmd.output().unwrap();
    let mut failures = Vec::new();
    if !run.status.success() {
        failures.push(format!(
            "{rel}: a ```mx block fails (the line below is the Markdown file's):\n{}",
            String::from_utf8_lossy(&run.stderr)
        ));
    }
    let printed = outputs_by_block(&String::from_utf8_lossy(&run.stdout));
    for (k, (block, end)) in found.iter().enumerate() {
        let Some((next, _)) = found.get(k + 1) else {
            continue;
        };
        if !(block.runs() && next.is_output() && only_blank_between(&lines, *end, next.line)) {
            continue;
        }
        let Some((_, got)) = printed.iter().find(|(l, _)| *l == block.line) else {
            continue; // skipped, or after the failure reported above
        };
        if normalised(got) != normalised(&next.text) {
            failures.push(format!(
                "{rel}:{}: the output shown differs from what the block at line {} prints; \
                 it prints:\n{}\n",
                next.line,
                block.line,
                got.trim_end()
            ));
        }
    }
    failures
}

#[test]
fn every_mx_block_of_the_readme_and_docs_runs() {
    let shared = common::shared_dir();
    let files = markdown_files();
    let failures: Vec<String> = std::thread::scope(|scope| {
        let handles: Vec<_> = files
            .iter()
            .map(|f| scope.spawn(|| run_file(f, shared.as_deref())))
            .collect();
        handles
            .into_iter()
            .flat_map(|h| h.join().unwrap())
            .collect()
    });
    assert!(failures.is_empty(), "\n{}", failures.join("\n\n"));
}

/// The README has runnable blocks (so the test above cannot pass on a README
/// whose fences it no longer recognises), and every mx block outside
/// `no-run` is one it runs.
#[test]
fn the_readme_has_runnable_blocks() {
    let readme =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("README.md")).unwrap();
    let found = blocks(&readme);
    assert!(
        found.iter().any(|(b, _)| b.runs()),
        "no ```mx block in README.md"
    );
    // the REPL transcripts became mx blocks: no `mx>` prompt is left to drift
    for (b, _) in &found {
        // a fresh clone has no shared data: nothing may reach for it
        assert!(
            !(b.runs() && (b.text.contains("MX_SHARED") || b.text.contains("../shared"))),
            "README.md:{}: a block reads the shared data, which a clone does not have; \
             put what it needs in examples/data",
            b.line
        );
        assert!(
            !b.text.lines().any(|l| l.trim_start().starts_with("mx> ")),
            "README.md:{}: a REPL transcript; write it as an ```mx block",
            b.line
        );
    }
}

#[test]
fn blocks_are_found_with_their_lines_flags_and_indentation() {
    let md = "text\n```mx\nlet a = 1\n```\n\n```text output\n1\n```\n- item\n\n  ```mx no-run\n  f(x)\n  ```\n~~~\nraw\n~~~\n";
    let b = blocks(md);
    assert_eq!(b.len(), 4);
    assert_eq!(b[0].0.line, 2);
    assert_eq!(b[0].0.text, "let a = 1\n");
    assert!(b[0].0.runs());
    assert!(b[1].0.is_output());
    let lines: Vec<&str> = md.lines().collect();
    assert!(only_blank_between(&lines, b[0].1, b[1].0.line));
    assert_eq!(b[2].0.line, 11);
    assert_eq!(b[2].0.text, "f(x)\n");
    assert!(!b[2].0.runs());
    assert_eq!(b[3].0.lang(), "");
    assert!(!only_blank_between(&lines, b[1].1, b[2].0.line));
}

/// The README's first command is the tour, built as the tour's own header
/// says (`--release`), and the output shown under it is what the tour prints
/// from a clone (its first lines; a last line `…` stands for the rest).
#[test]
fn the_readme_opens_with_the_tour_and_what_it_prints() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let found = blocks(&readme);
    let (first, _) = &found[0];
    assert_eq!(
        first.lang(),
        "sh",
        "README.md:{}: the first block is the commands",
        first.line
    );
    let command = |line: &str| line.split(" #").next().unwrap_or("").trim().to_string();
    let first_command = command(first.text.lines().next().unwrap_or(""));
    let tour = std::fs::read_to_string(root.join("examples/tour.mx")).unwrap();
    let header: Vec<String> = tour
        .lines()
        .take_while(|l| l.starts_with("//"))
        .filter_map(|l| {
            l.trim_start_matches('/')
                .trim()
                .strip_prefix("cargo ")
                .map(|c| format!("cargo {c}"))
        })
        .collect();
    assert_eq!(
        header,
        [first_command.clone()],
        "README.md:{}: the first command must be the one tour.mx's header gives",
        first.line
    );
    let (shown, _) = &found[1];
    assert!(
        shown.is_output(),
        "README.md:{}: what the tour prints follows its command",
        shown.line
    );
    let (_tmp, work) = clone_like_root();
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_mx"))
        .args(["run", "examples/tour.mx"])
        .current_dir(&work)
        .env_remove("MX_SHARED")
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let printed = String::from_utf8_lossy(&run.stdout).to_string();
    let printed: Vec<&str> = printed.lines().map(str::trim_end).collect();
    let mut want: Vec<&str> = shown.text.lines().map(str::trim_end).collect();
    if want.last() == Some(&"…") {
        want.pop();
    } else {
        assert_eq!(
            want.len(),
            printed.len(),
            "README.md:{}: shows the whole output",
            shown.line
        );
    }
    assert!(
        want.len() >= 3,
        "README.md:{}: show a few lines",
        shown.line
    );
    for (k, line) in want.iter().enumerate() {
        assert_eq!(
            Some(line),
            printed.get(k),
            "README.md:{}: line {} of the tour's output",
            shown.line + 1 + k,
            k + 1
        );
    }
}
