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

/// Runs one file's blocks; returns its failures, each naming file and line.
fn run_file(path: &Path, shared: Option<&Path>) -> Vec<String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let rel = path
        .strip_prefix(root)
        .unwrap_or(path)
        .display()
        .to_string();
    let markdown = std::fs::read_to_string(path).unwrap();
    let lines: Vec<&str> = markdown.lines().collect();
    let found = blocks(&markdown);
    // A folder that looks like the repository root to the blocks: the
    // repository's own folders linked in, writes kept here.
    let tmp = tempfile::tempdir().unwrap();
    let work = tmp.path().join("repo");
    std::fs::create_dir(&work).unwrap();
    for name in ["examples", "stdlib", "docs", "tests", "scripts"] {
        std::os::unix::fs::symlink(root.join(name), work.join(name)).unwrap();
    }
    if let Some(s) = shared {
        std::os::unix::fs::symlink(s, tmp.path().join("shared")).unwrap();
    }
    let script = work.join(path.file_name().unwrap());
    let mut mx = mx::Interpreter::new();
    let printed = mx.capture_output();
    let mut failures = Vec::new();
    for (k, (block, end)) in found.iter().enumerate() {
        if !block.runs() {
            continue;
        }
        if shared.is_none() && block.text.contains("MX_SHARED") {
            eprintln!("SKIPPED: {rel}:{} and after: no shared data", block.line);
            break;
        }
        // the block's own lines at the Markdown file's line numbers
        let padded = "\n".repeat(block.line) + &block.text;
        std::fs::write(&script, padded).unwrap();
        printed.lock().unwrap().clear();
        if let Err(d) = mx.eval_file(&script) {
            failures.push(format!(
                "{rel}:{}: the ```mx block starting here fails:\n{}",
                block.line,
                d.render_plain()
            ));
            // later blocks may need what this one defined: report the first only
            break;
        }
        let Some((next, _)) = found.get(k + 1) else {
            continue;
        };
        if next.is_output() && only_blank_between(&lines, *end, next.line) {
            let got = String::from_utf8_lossy(&printed.lock().unwrap()).to_string();
            let norm = |s: &str| {
                s.lines()
                    .map(str::trim_end)
                    .collect::<Vec<_>>()
                    .join("\n")
                    .trim()
                    .to_string()
            };
            if norm(&got) != norm(&next.text) {
                failures.push(format!(
                    "{rel}:{}: the output shown differs from what the block at line {} prints; \
                     it prints:\n{}\n",
                    next.line,
                    block.line,
                    got.trim_end()
                ));
            }
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
