//! The library's layers, enforced: each top-level module of `src/` may use only
//! the modules listed before it in ARCHITECTURE.md's module table, and the files
//! of one folder import each other without loops. The Python bindings' files
//! (`python/src/`) are held to their own table the same way.
//!
//! This reads the source rather than the compiled crate, so it names the file and
//! line of an offending `crate::…` (or `super::…`) path. Why a test and not one
//! crate per layer is said in ARCHITECTURE.md ("Layers, enforced").

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

/// Folders (module paths) whose files may import each other in a loop (only for the
/// loop check, never for the layer order). Empty: `lang`'s evaluator and built-ins
/// were the last knot, untied by storing a built-in's body type-erased beside `Value`.
const LOOPS_ALLOWED_UNDER: &[&str] = &[];

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

// ---------------------------------------------------------------- the layer order

/// The library's table in ARCHITECTURE.md starts with this header row…
const LIBRARY_TABLE: &str = "| module |";
/// …and the Python bindings' with this one.
const PYTHON_TABLE: &str = "| python module |";

/// The module names of ARCHITECTURE.md's table that starts with `header`, in
/// order; names sharing a row (`main.rs`, `repl.rs`) share a rank.
fn layer_ranks(architecture: &str, header: &str) -> BTreeMap<String, usize> {
    let mut ranks = BTreeMap::new();
    let mut in_table = false;
    let mut rank = 0;
    for line in architecture.lines() {
        let line = line.trim();
        if line.starts_with(header) {
            in_table = true;
            continue;
        }
        if !in_table {
            continue;
        }
        if !line.starts_with('|') {
            break;
        }
        if line.starts_with("| ---") || line.starts_with("|---") {
            continue;
        }
        let first_cell = line.trim_start_matches('|').split('|').next().unwrap_or("");
        let names: Vec<&str> = first_cell
            .split('`')
            .skip(1)
            .step_by(2)
            .map(|n| n.trim_end_matches(".rs"))
            .collect();
        assert!(
            !names.is_empty(),
            "ARCHITECTURE.md: a module row names no module: {line}"
        );
        for n in names {
            ranks.insert(n.to_string(), rank);
        }
        rank += 1;
    }
    assert!(
        rank > 3,
        "ARCHITECTURE.md: no `{header} owns |` table found"
    );
    ranks
}

// ---------------------------------------------------------------- reading paths

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Ident(String),
    Path, // `::`
    Open,
    Close,
    Comma,
    Semi,
    Star,
    Other,
}

/// Rust tokens, enough to follow paths: comments, strings and char literals are
/// skipped, so a `crate::` in a doc comment or a message does not count.
fn tokenize(src: &str) -> Vec<(Tok, usize)> {
    let b = src.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    let mut line = 1;
    let count_lines = |from: usize, to: usize, line: &mut usize| {
        *line += b[from..to].iter().filter(|&&c| c == b'\n').count();
    };
    while i < b.len() {
        let c = b[i];
        match c {
            b'\n' => {
                line += 1;
                i += 1;
            }
            _ if c.is_ascii_whitespace() => i += 1,
            b'/' if b.get(i + 1) == Some(&b'/') => {
                while i < b.len() && b[i] != b'\n' {
                    i += 1;
                }
            }
            b'/' if b.get(i + 1) == Some(&b'*') => {
                let start = i;
                let mut depth = 0;
                while i < b.len() {
                    if b[i] == b'/' && b.get(i + 1) == Some(&b'*') {
                        depth += 1;
                        i += 2;
                    } else if b[i] == b'*' && b.get(i + 1) == Some(&b'/') {
                        depth -= 1;
                        i += 2;
                        if depth == 0 {
                            break;
                        }
                    } else {
                        i += 1;
                    }
                }
                count_lines(start, i.min(b.len()), &mut line);
            }
            b'"' => {
                let start = i;
                i += 1;
                while i < b.len() && b[i] != b'"' {
                    i += if b[i] == b'\\' { 2 } else { 1 };
                }
                i += 1;
                count_lines(start, i.min(b.len()), &mut line);
            }
            b'r' if matches!(b.get(i + 1), Some(b'"') | Some(b'#'))
                && raw_string_start(b, i + 1) =>
            {
                let start = i;
                let mut j = i + 1;
                let mut hashes = 0;
                while b[j] == b'#' {
                    hashes += 1;
                    j += 1;
                }
                j += 1; // the opening quote
                let closing: Vec<u8> = std::iter::once(b'"')
                    .chain(std::iter::repeat_n(b'#', hashes))
                    .collect();
                while j < b.len() && !b[j..].starts_with(&closing) {
                    j += 1;
                }
                i = (j + closing.len()).min(b.len());
                count_lines(start, i, &mut line);
            }
            b'\'' => {
                // a char literal ('x', '\n', '\u{1F600}') or a lifetime ('a)
                if b.get(i + 1) == Some(&b'\\') {
                    i += 2;
                    while i < b.len() && b[i] != b'\'' {
                        i += 1;
                    }
                    i += 1;
                } else {
                    let ch_len = src[i + 1..].chars().next().map_or(1, char::len_utf8);
                    if b.get(i + 1 + ch_len) == Some(&b'\'') {
                        i += 2 + ch_len;
                    } else {
                        i += 1; // a lifetime: its name follows as an identifier
                    }
                }
            }
            _ if c == b'_' || c.is_ascii_alphabetic() => {
                let start = i;
                while i < b.len() && (b[i] == b'_' || b[i].is_ascii_alphanumeric()) {
                    i += 1;
                }
                out.push((Tok::Ident(src[start..i].to_string()), line));
            }
            b':' if b.get(i + 1) == Some(&b':') => {
                out.push((Tok::Path, line));
                i += 2;
            }
            b'{' => {
                out.push((Tok::Open, line));
                i += 1;
            }
            b'}' => {
                out.push((Tok::Close, line));
                i += 1;
            }
            b',' => {
                out.push((Tok::Comma, line));
                i += 1;
            }
            b';' => {
                out.push((Tok::Semi, line));
                i += 1;
            }
            b'*' => {
                out.push((Tok::Star, line));
                i += 1;
            }
            _ => {
                out.push((Tok::Other, line));
                i += 1;
            }
        }
    }
    out
}

fn raw_string_start(b: &[u8], mut j: usize) -> bool {
    while j < b.len() && b[j] == b'#' {
        j += 1;
    }
    b.get(j) == Some(&b'"')
}

/// A path written in a file: its segments as written (`crate`, `super`, `self`
/// first), the line, and whether it is a `pub use` (a re-export).
#[derive(Clone, Debug)]
struct Written {
    segments: Vec<String>,
    line: usize,
    reexport: bool,
    /// The inline modules (`mod tests { … }`) the path sits in, for `super`.
    inline: Vec<String>,
}

/// Expands a path (or use tree) starting at `toks[i]` into full paths.
fn expand(toks: &[(Tok, usize)], i: &mut usize, prefix: Vec<String>, out: &mut Vec<Vec<String>>) {
    let mut path = prefix;
    loop {
        match toks.get(*i).map(|t| &t.0) {
            Some(Tok::Ident(s)) => {
                path.push(s.clone());
                *i += 1;
            }
            Some(Tok::Open) => {
                *i += 1;
                loop {
                    match toks.get(*i).map(|t| &t.0) {
                        Some(Tok::Close) => {
                            *i += 1;
                            break;
                        }
                        Some(Tok::Comma) => *i += 1,
                        None => return,
                        _ => {
                            let before = *i;
                            expand(toks, i, path.clone(), out);
                            if *i == before {
                                *i += 1;
                            }
                        }
                    }
                }
                return;
            }
            Some(Tok::Star) => {
                *i += 1;
                break;
            }
            _ => break,
        }
        if toks.get(*i).map(|t| &t.0) == Some(&Tok::Path) {
            *i += 1;
        } else {
            break;
        }
    }
    // `self` inside a group names the group's own path
    if path.last().map(String::as_str) == Some("self") {
        path.pop();
    }
    if !path.is_empty() {
        out.push(path);
    }
}

/// Every `crate::…`, `super::…` and `self::…` path in a file.
fn written_paths(src: &str) -> Vec<Written> {
    let toks = tokenize(src);
    let mut found = Vec::new();
    // inline modules: (name, brace depth at which its body opened)
    let mut inline: Vec<(String, usize)> = Vec::new();
    let mut depth = 0usize;
    let mut i = 0;
    while i < toks.len() {
        match &toks[i].0 {
            Tok::Open => depth += 1,
            Tok::Close => {
                if inline.last().is_some_and(|(_, d)| *d == depth) {
                    inline.pop();
                }
                depth = depth.saturating_sub(1);
            }
            Tok::Ident(m) if m == "mod" => {
                if let (Some((Tok::Ident(name), _)), Some((Tok::Open, _))) =
                    (toks.get(i + 1), toks.get(i + 2))
                {
                    inline.push((name.clone(), depth + 1));
                }
            }
            // `use child::Item` (2018 paths relative to this module): read as `self::child::Item`
            Tok::Ident(u)
                if u == "use"
                    && matches!(&toks.get(i + 1).map(|t| &t.0), Some(Tok::Ident(h)) if !matches!(h.as_str(), "crate" | "super" | "self"))
                    && toks.get(i + 2).map(|t| &t.0) == Some(&Tok::Path) =>
            {
                let line = toks[i].1;
                let reexport = is_pub_use(&toks, i + 1);
                let mut j = i + 1;
                let mut paths = Vec::new();
                expand(&toks, &mut j, vec!["self".to_string()], &mut paths);
                for segments in paths {
                    found.push(Written {
                        segments,
                        line,
                        reexport,
                        inline: inline.iter().map(|(n, _)| n.clone()).collect(),
                    });
                }
                i = j.max(i + 1);
                continue;
            }
            Tok::Ident(head)
                if (head == "crate" || head == "super" || head == "self")
                    && toks.get(i + 1).map(|t| &t.0) == Some(&Tok::Path)
                    && (i == 0 || toks[i - 1].0 != Tok::Path) =>
            {
                let line = toks[i].1;
                let reexport = is_pub_use(&toks, i);
                let mut j = i;
                let mut paths = Vec::new();
                expand(&toks, &mut j, Vec::new(), &mut paths);
                for segments in paths {
                    found.push(Written {
                        segments,
                        line,
                        reexport,
                        inline: inline.iter().map(|(n, _)| n.clone()).collect(),
                    });
                }
                i = j.max(i + 1);
                continue;
            }
            _ => {}
        }
        i += 1;
    }
    found
}

/// Whether the path at `toks[i]` is the start of a `pub use` (or `pub(crate) use`).
fn is_pub_use(toks: &[(Tok, usize)], i: usize) -> bool {
    if i == 0 || toks[i - 1].0 != Tok::Ident("use".into()) {
        return false;
    }
    let mut k = i - 1;
    while k > 0 {
        k -= 1;
        match &toks[k].0 {
            Tok::Ident(s) if s == "pub" => return true,
            Tok::Ident(s) if s == "crate" || s == "super" || s == "in" => {}
            Tok::Other => {} // the parentheses of pub(crate)
            _ => return false,
        }
    }
    false
}

// ---------------------------------------------------------------- the crate's files

/// One source file, as the module path it defines.
struct File {
    rel: String,
    module: Vec<String>,
    paths: Vec<Written>,
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = fs::read_dir(dir)
        .expect("read src/")
        .flatten()
        .map(|e| e.path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

fn module_of(rel: &Path) -> Vec<String> {
    let mut parts: Vec<String> = rel
        .iter()
        .map(|s| s.to_string_lossy().into_owned())
        .collect();
    let last = parts.pop().unwrap();
    let stem = last.trim_end_matches(".rs");
    if !matches!(stem, "mod" | "lib") {
        parts.push(stem.to_string());
    }
    parts
}

/// The files of the crate whose sources are in `src` (relative to the repository).
fn load_files(src: &str) -> Vec<File> {
    let dir = root().join(src);
    let mut paths = Vec::new();
    rust_files(&dir, &mut paths);
    paths
        .into_iter()
        .map(|p| {
            let rel = p.strip_prefix(&dir).unwrap().to_path_buf();
            let text = fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            File {
                rel: format!("{src}/{}", rel.display()),
                module: module_of(&rel),
                paths: written_paths(&text),
            }
        })
        .collect()
}

fn load_crate() -> Vec<File> {
    load_files("src")
}

/// Files made from sources in memory (`name.rs` → text), for the checker's own tests.
fn files_from(sources: &[(&str, &str)]) -> Vec<File> {
    sources
        .iter()
        .map(|(name, text)| File {
            rel: name.to_string(),
            module: module_of(Path::new(name)),
            paths: written_paths(text),
        })
        .collect()
}

/// Resolves paths to the file that defines them, following a module's `pub use`
/// re-exports (so `crate::dynamics::Workspace` leads to `dynamics/workspace.rs`).
struct Resolver {
    modules: BTreeSet<Vec<String>>,
    /// per module: re-exported name → the full path it stands for
    reexports: BTreeMap<Vec<String>, BTreeMap<String, Vec<String>>>,
}

impl Resolver {
    fn new(files: &[File]) -> Self {
        let modules = files.iter().map(|f| f.module.clone()).collect();
        let mut r = Resolver {
            modules,
            reexports: BTreeMap::new(),
        };
        for f in files {
            let mut map = BTreeMap::new();
            for w in f.paths.iter().filter(|w| w.reexport && w.inline.is_empty()) {
                if let Some(full) = r.absolute(&f.module, w)
                    && let Some(name) = full.last()
                {
                    map.insert(name.clone(), full);
                }
            }
            r.reexports.insert(f.module.clone(), map);
        }
        r
    }

    /// The path written in module `at` made absolute (without the leading `crate`).
    fn absolute(&self, at: &[String], w: &Written) -> Option<Vec<String>> {
        let mut base: Vec<String> = at.iter().cloned().chain(w.inline.iter().cloned()).collect();
        let mut segs = w.segments.iter().peekable();
        match segs.peek().map(|s| s.as_str()) {
            Some("crate") => {
                segs.next();
                base.clear();
            }
            Some("self") => {
                segs.next();
            }
            Some("super") => {
                while segs.peek().map(|s| s.as_str()) == Some("super") {
                    segs.next();
                    base.pop()?;
                }
            }
            _ => return None,
        }
        base.extend(segs.cloned());
        Some(base)
    }

    /// The module (file) that defines the absolute path `path`.
    fn file_of(&self, path: &[String]) -> Option<Vec<String>> {
        let mut path = path.to_vec();
        for _ in 0..8 {
            let n = (0..=path.len())
                .rev()
                .find(|&n| self.modules.contains(&path[..n]))?;
            let module = path[..n].to_vec();
            match path
                .get(n)
                .and_then(|item| self.reexports.get(&module)?.get(item))
            {
                Some(target) if target != &path[..=n] => {
                    let mut next = target.clone();
                    next.extend(path[n + 1..].iter().cloned());
                    path = next;
                }
                _ => return Some(module),
            }
        }
        None
    }
}

/// An import of one module by another: from → to, where it is written.
#[derive(Clone, Debug)]
struct Edge {
    from: Vec<String>,
    to: Vec<String>,
    at: String,
    /// written inside a `mod tests { … }`: a unit test may compare with a sibling
    in_tests: bool,
}

fn edges(files: &[File]) -> Vec<Edge> {
    let r = Resolver::new(files);
    let mut out = Vec::new();
    for f in files {
        // the binary's files (main.rs, repl.rs) say `crate::` of the binary crate
        if f.module.len() == 1 && matches!(f.module[0].as_str(), "main" | "repl") {
            continue;
        }
        for w in &f.paths {
            let Some(abs) = r.absolute(&f.module, w) else {
                continue;
            };
            let Some(to) = r.file_of(&abs) else { continue };
            out.push(Edge {
                from: f.module.clone(),
                to,
                at: format!("{}:{}: {}", f.rel, w.line, w.segments.join("::")),
                in_tests: w.inline.iter().any(|m| m == "tests"),
            });
        }
    }
    out
}

// ---------------------------------------------------------------- the checks

/// The row a module belongs to: its top-level name, `lib` for the crate root.
fn top_of(module: &[String]) -> String {
    module.first().cloned().unwrap_or_else(|| "lib".into())
}

/// Files whose module has no row in the table (the crate root may go unlisted).
fn unlisted(files: &[File], ranks: &BTreeMap<String, usize>) -> BTreeSet<String> {
    files
        .iter()
        .filter(|f| !f.module.is_empty() && !ranks.contains_key(&top_of(&f.module)))
        .map(|f| f.rel.clone())
        .collect()
}

/// Every import of a module listed after the importing one, as `file:line: path (why)`.
fn order_violations(files: &[File], ranks: &BTreeMap<String, usize>) -> Vec<String> {
    let mut wrong = Vec::new();
    for e in edges(files) {
        let (from, to) = (top_of(&e.from), top_of(&e.to));
        let (Some(rf), Some(rt)) = (ranks.get(&from), ranks.get(&to)) else {
            continue;
        };
        if rf < rt {
            wrong.push(format!("{}  (`{from}` is listed before `{to}`)", e.at));
        }
    }
    wrong
}

/// Every import loop between files of one folder, each as its walk and the
/// lines that make it. `top_level`: also between the crate's top-level files
/// (the library leaves those to the layer order; the bindings' files share rows).
fn loop_violations(files: &[File], top_level: bool) -> Vec<String> {
    // sibling graph: for an edge a::x::… → a::y::…, the siblings x → y under a
    let mut graph: BTreeMap<Vec<String>, BTreeMap<String, BTreeMap<String, String>>> =
        BTreeMap::new();
    for e in edges(files).into_iter().filter(|e| !e.in_tests) {
        let common = e.from.iter().zip(&e.to).take_while(|(a, b)| a == b).count();
        let (Some(x), Some(y)) = (e.from.get(common), e.to.get(common)) else {
            continue; // a module using its parent or its own children
        };
        let parent = e.from[..common].to_vec();
        graph
            .entry(parent)
            .or_default()
            .entry(x.clone())
            .or_default()
            .entry(y.clone())
            .or_insert(e.at);
    }
    let mut loops = Vec::new();
    for (parent, g) in &graph {
        if parent.is_empty() && !top_level {
            continue; // the top level: the layer order forbids its loops
        }
        if LOOPS_ALLOWED_UNDER
            .iter()
            .any(|a| parent.first().map(String::as_str) == Some(a))
        {
            continue;
        }
        for cycle in cycles(g) {
            let steps: Vec<String> = cycle.windows(2).map(|w| g[&w[0]][&w[1]].clone()).collect();
            loops.push(format!(
                "in {}: {}\n    {}",
                if parent.is_empty() {
                    "the crate root".to_string()
                } else {
                    parent.join("::")
                },
                cycle.join(" → "),
                steps.join("\n    ")
            ));
        }
    }
    loops
}

#[test]
fn no_module_imports_one_listed_after_it() {
    let arch = fs::read_to_string(root().join("ARCHITECTURE.md")).expect("read ARCHITECTURE.md");
    let ranks = layer_ranks(&arch, LIBRARY_TABLE);
    let files = load_crate();
    let unlisted = unlisted(&files, &ranks);
    assert!(
        unlisted.is_empty(),
        "these files belong to no module of ARCHITECTURE.md's table; add a row for their module: {unlisted:?}"
    );
    let wrong = order_violations(&files, &ranks);
    assert!(
        wrong.is_empty(),
        "imports against the layer order of ARCHITECTURE.md:\n  {}",
        wrong.join("\n  ")
    );
}

#[test]
fn files_of_one_folder_import_each_other_without_loops() {
    let loops = loop_violations(&load_crate(), false);
    assert!(
        loops.is_empty(),
        "import loops between files of one folder:\n  {}",
        loops.join("\n  ")
    );
}

/// The Python bindings (`python/src`, issue 24): each file imports only the
/// rows above it in ARCHITECTURE.md's Python table, files sharing a row do not
/// import each other in a loop, and every row names a file that exists.
#[test]
fn python_bindings_import_downward_without_loops() {
    let arch = fs::read_to_string(root().join("ARCHITECTURE.md")).expect("read ARCHITECTURE.md");
    let ranks = layer_ranks(&arch, PYTHON_TABLE);
    let files = load_files("python/src");
    let unlisted = unlisted(&files, &ranks);
    assert!(
        unlisted.is_empty(),
        "these files of python/src have no row in ARCHITECTURE.md's Python table: {unlisted:?}"
    );
    let present: BTreeSet<String> = files.iter().map(|f| top_of(&f.module)).collect();
    let missing: Vec<&String> = ranks.keys().filter(|m| !present.contains(*m)).collect();
    assert!(
        missing.is_empty(),
        "ARCHITECTURE.md's Python table names files python/src does not have: {missing:?}"
    );
    let wrong = order_violations(&files, &ranks);
    assert!(
        wrong.is_empty(),
        "python/src imports against the layer order of ARCHITECTURE.md:\n  {}",
        wrong.join("\n  ")
    );
    let loops = loop_violations(&files, true);
    assert!(
        loops.is_empty(),
        "import loops in python/src:\n  {}",
        loops.join("\n  ")
    );
}

/// One cycle per strongly connected group of siblings (as a closed walk a → … → a).
fn cycles(g: &BTreeMap<String, BTreeMap<String, String>>) -> Vec<Vec<String>> {
    let mut seen_in_cycle = BTreeSet::new();
    let mut out = Vec::new();
    for start in g.keys() {
        if seen_in_cycle.contains(start) {
            continue;
        }
        // breadth-first search back to `start`, remembering parents
        let mut prev: BTreeMap<String, String> = BTreeMap::new();
        let mut queue = std::collections::VecDeque::from([start.clone()]);
        let mut closed = None;
        while let Some(n) = queue.pop_front() {
            for next in g.get(&n).into_iter().flat_map(|m| m.keys()) {
                if next == start {
                    closed = Some(n.clone());
                    break;
                }
                if !prev.contains_key(next) {
                    prev.insert(next.clone(), n.clone());
                    queue.push_back(next.clone());
                }
            }
            if closed.is_some() {
                break;
            }
        }
        if let Some(mut n) = closed {
            let mut back = Vec::new(); // from the last step back to start's successor
            while &n != start {
                back.push(n.clone());
                n = prev[&n].clone();
            }
            let mut walk = vec![start.clone()];
            walk.extend(back.into_iter().rev());
            walk.push(start.clone());
            for m in &walk {
                seen_in_cycle.insert(m.clone());
            }
            out.push(walk);
        }
    }
    out
}

// ---------------------------------------------------------------- the checker's own tests

#[test]
fn the_reader_follows_groups_super_and_skips_strings_and_comments() {
    let src = r##"
        use crate::{model::Model, dynamics::{self, rnea::inverse_dynamics}};
        // use crate::report::nothing;
        /* crate::report::neither */
        let s = "crate::report::not_this";
        let r = r#"crate::report::nor_this"#;
        let c = '"'; fn f<'a>(x: &'a str) {}
        pub use super::derivatives::Variation;
        mod tests { use super::helper; }
        x = crate::spline::fit(1);
    "##;
    let got: Vec<(String, bool, Vec<String>)> = written_paths(src)
        .into_iter()
        .map(|w| (w.segments.join("::"), w.reexport, w.inline))
        .collect();
    let want = vec![
        ("crate::model::Model".to_string(), false, vec![]),
        ("crate::dynamics".into(), false, vec![]),
        (
            "crate::dynamics::rnea::inverse_dynamics".into(),
            false,
            vec![],
        ),
        ("super::derivatives::Variation".into(), true, vec![]),
        ("super::helper".into(), false, vec!["tests".to_string()]),
        ("crate::spline::fit".into(), false, vec![]),
    ];
    assert_eq!(got, want);
}

#[test]
fn the_loop_finder_finds_a_loop_and_only_a_loop() {
    let mut g: BTreeMap<String, BTreeMap<String, String>> = BTreeMap::new();
    fn add(g: &mut BTreeMap<String, BTreeMap<String, String>>, a: &str, b: &str) {
        g.entry(a.into())
            .or_default()
            .insert(b.into(), format!("{a}->{b}"));
    }
    add(&mut g, "a", "b");
    add(&mut g, "b", "c");
    add(&mut g, "a", "c");
    assert!(cycles(&g).is_empty());
    add(&mut g, "c", "a");
    let found = cycles(&g);
    assert!(!found.is_empty());
    for walk in &found {
        assert_eq!(walk.first(), walk.last());
        assert!(walk.len() >= 3);
        assert!(
            walk.windows(2).all(|w| g[&w[0]].contains_key(&w[1])),
            "{walk:?} is not a walk"
        );
    }
}

/// The loop the bindings had (convert ↔ motion, body ↔ motion) is caught: an
/// import up the table by the order check, a loop within one row by the loop check.
#[test]
fn the_checker_catches_a_made_up_loop_in_the_bindings() {
    let table = "| python module | owns |\n| --- | --- |\n| `errors` | a |\n| `convert` | b |\n| `motion` · `body` | c |\n| `lib.rs` | d |\n";
    let ranks = layer_ranks(table, PYTHON_TABLE);
    let downward = files_from(&[
        ("errors.rs", "pub fn raise() {}"),
        ("convert.rs", "use crate::errors::raise;"),
        (
            "motion.rs",
            "use crate::convert::to_py; use crate::errors::raise;",
        ),
        ("body.rs", "use crate::{convert::to_py, motion::PyMotion};"),
        ("lib.rs", "mod body; use crate::motion::PyMotion;"),
    ]);
    assert!(order_violations(&downward, &ranks).is_empty());
    assert!(loop_violations(&downward, true).is_empty());

    let up = files_from(&[
        ("errors.rs", ""),
        (
            "convert.rs",
            "fn f() { let m = crate::motion::PyMotion::new(); }",
        ),
        ("motion.rs", "use crate::convert::to_py;"),
    ]);
    let wrong = order_violations(&up, &ranks);
    assert_eq!(wrong.len(), 1, "{wrong:?}");
    assert!(
        wrong[0].starts_with("convert.rs:1: crate::motion::PyMotion::new"),
        "{wrong:?}"
    );

    let sideways = files_from(&[
        ("motion.rs", "use crate::body::short_list;"),
        ("body.rs", "use crate::motion::{PyMotion, f64_array};"),
        ("lib.rs", "use crate::errors::x;"),
    ]);
    assert!(
        order_violations(&sideways, &ranks).is_empty(),
        "one row: no order between them"
    );
    let loops = loop_violations(&sideways, true);
    assert_eq!(loops.len(), 1, "{loops:?}");
    assert!(loops[0].contains("body → motion → body"), "{loops:?}");
    assert!(
        loop_violations(&sideways, false).is_empty(),
        "the library's check leaves the top level to the order"
    );
    // an upward import into the crate root counts too
    let into_root = files_from(&[
        ("motion.rs", "use crate::load;"),
        ("lib.rs", "pub fn load() {}"),
    ]);
    assert_eq!(order_violations(&into_root, &ranks).len(), 1);
}

#[test]
fn the_table_gives_ranks_in_order() {
    let arch = "x\n| module | owns |\n| --- | --- |\n| `lie` | a |\n| `spline` | b |\n| `model` | c |\n| `main.rs`, `repl.rs` | d |\n\nafter";
    let r = layer_ranks(arch, LIBRARY_TABLE);
    assert!(r["lie"] < r["spline"] && r["spline"] < r["model"]);
    assert_eq!(r["main"], r["repl"]);
    assert!(!r.contains_key("after"));
}
