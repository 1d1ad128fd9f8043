//! What Tab completes at the cursor of a line of mx (the REPL's completer):
//! names in scope and `:commands` in code; inside a string, what the argument
//! it stands for takes (issue 28): a file path for a `path` parameter
//! (`load("ex…`, `save(m, "out/…`, `:load ex…`), a DOF name of the motions
//! bound in the session for a DOF parameter (`only(m, "Hips.X…`,
//! `walk.only("Left…`, `get(m, "…`, `ik(…, only: "…`). Which parameter a string
//! is for is read from the built-in's own signature, so a new built-in with a
//! `path` or `pattern` parameter completes without a change here.
//!
//! Pure text in, candidates out (plus a folder listing for paths), so it is
//! tested without a terminal; `src/repl.rs` hands the result to rustyline.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use super::host::motion::Motion;
use super::interpreter::Interpreter;

/// The REPL commands Tab completes after `:`.
pub const COMMANDS: &[&str] = &[
    ":help", ":type", ":info", ":load", ":time", ":plot", ":quit",
];

/// What the session offers to complete from, taken after each input.
#[derive(Clone, Debug, Default)]
pub struct Scope {
    /// Every name in scope (globals first, then built-ins).
    pub names: Vec<String>,
    /// The parameter names of each documented function, from its signature.
    pub params: BTreeMap<String, Vec<String>>,
    /// Each global bound to a motion unit, with its DOF names.
    pub motions: Vec<(String, Vec<String>)>,
    /// The folder relative paths are read against (the REPL's current folder).
    pub folder: PathBuf,
}

impl Scope {
    /// The names, signatures and bound motions of `interp`; paths relative to `folder`.
    pub fn of(interp: &Interpreter, folder: PathBuf) -> Scope {
        let params = interp
            .help_entries()
            .into_iter()
            .map(|e| (e.name, params_of(&e.signature)))
            .collect();
        let mut scope = Scope {
            params,
            folder,
            ..Scope::default()
        };
        scope.refresh(interp);
        scope
    }

    /// Take the names and bound motions again after an input. The signatures
    /// stay: built-ins do not change within a session, and reading them
    /// means rendering every doc (and parsing the prelude's).
    pub fn refresh(&mut self, interp: &Interpreter) {
        self.names = interp.names();
        self.motions.clear();
        for n in &self.names {
            if let Some(v) = interp.get(n)
                && let Some(Motion::Mu(mu)) = v.as_object::<Motion>()
            {
                self.motions
                    .push((n.clone(), mu.names().map(String::from).collect()));
            }
        }
    }
}

/// One completion: what the list shows and what replaces the word.
#[derive(Clone, Debug, PartialEq)]
pub struct Candidate {
    pub display: String,
    pub replacement: String,
}

impl Candidate {
    fn same(s: String) -> Self {
        Candidate {
            display: s.clone(),
            replacement: s,
        }
    }
}

/// The candidates for the text before `pos` in `line`, and the byte offset
/// where the replaced word starts.
pub fn complete(line: &str, pos: usize, scope: &Scope) -> (usize, Vec<Candidate>) {
    let before = &line[..pos];
    if let Some(arg) = load_command_argument(before) {
        let start = pos - arg.len();
        return paths(arg, start, scope, false);
    }
    match cursor(before) {
        Cursor::Comment => (pos, vec![]),
        Cursor::Code => names(before, scope),
        Cursor::Str { start, call } => {
            let text = &before[start..];
            match call.as_ref().map(|c| c.kind(scope)) {
                Some(Kind::Path) => paths(text, start, scope, true),
                Some(Kind::Dof) => dofs(text, start, call.as_ref(), scope),
                _ => (pos, vec![]),
            }
        }
    }
}

/// What an argument takes, from its parameter's name.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Path,
    Dof,
    Other,
}

fn kind_of(function: &str, param: &str) -> Kind {
    match param {
        "path" | "file" => Kind::Path,
        // `only(m, pattern, ...)`, `mask(m, pattern, w)`, `ik(…, only: pattern)`,
        // the prelude's `hold(names, …)`, `get(m, name)`
        "pattern" | "only" | "names" | "dof" | "dofs" => Kind::Dof,
        "name" if function == "get" => Kind::Dof,
        _ => Kind::Other,
    }
}

/// The call a string is an argument of.
#[derive(Clone, Debug, Default, PartialEq)]
struct Call {
    function: String,
    /// The positional index (counting a method's receiver), if not named.
    index: Option<usize>,
    /// The name of a named argument (`only: "…`).
    named: Option<String>,
    /// The first argument (or the method's receiver) when it is a plain name.
    receiver: Option<String>,
}

impl Call {
    fn kind(&self, scope: &Scope) -> Kind {
        if let Some(n) = &self.named {
            return kind_of(&self.function, n);
        }
        let (Some(params), Some(i)) = (scope.params.get(&self.function), self.index) else {
            return Kind::Other;
        };
        match param_at(params, i) {
            Some(p) => kind_of(&self.function, p),
            None => Kind::Other,
        }
    }
}

/// Where the cursor is.
#[derive(Debug, PartialEq)]
enum Cursor {
    Code,
    Comment,
    /// Inside a string whose text starts at byte `start`, maybe an argument of `call`.
    Str {
        start: usize,
        call: Option<Call>,
    },
}

/// An open bracket before the cursor.
struct Frame {
    open: char,
    at: usize,
    commas: usize,
    /// Where the current argument's text starts, and the first argument's end.
    arg_start: usize,
    first_end: Option<usize>,
}

/// Reads `before` as mx tokens far enough to know whether the cursor is in
/// code, a comment or a string, and which call's argument a string is.
fn cursor(before: &str) -> Cursor {
    let mut stack: Vec<Frame> = Vec::new();
    let mut string: Option<usize> = None;
    let (mut line_comment, mut block_comment) = (false, false);
    let mut chars = before.char_indices().peekable();
    while let Some((i, c)) = chars.next() {
        if string.is_some() {
            match c {
                '\\' => {
                    chars.next();
                }
                '"' => string = None,
                _ => {}
            }
            continue;
        }
        if line_comment {
            line_comment = c != '\n';
            continue;
        }
        if block_comment {
            if c == '*' && chars.peek().map(|p| p.1) == Some('/') {
                chars.next();
                block_comment = false;
            }
            continue;
        }
        match c {
            '"' => string = Some(i),
            '/' if chars.peek().map(|p| p.1) == Some('/') => line_comment = true,
            '/' if chars.peek().map(|p| p.1) == Some('*') => {
                chars.next();
                block_comment = true;
            }
            '(' | '[' | '{' => stack.push(Frame {
                open: c,
                at: i,
                commas: 0,
                arg_start: i + 1,
                first_end: None,
            }),
            ')' | ']' | '}' => {
                stack.pop();
            }
            ',' => {
                if let Some(f) = stack.last_mut() {
                    f.commas += 1;
                    f.arg_start = i + 1;
                    f.first_end.get_or_insert(i);
                }
            }
            _ => {}
        }
    }
    if line_comment || block_comment {
        return Cursor::Comment;
    }
    let Some(q) = string else {
        return Cursor::Code;
    };
    Cursor::Str {
        start: q + 1,
        call: call_around(before, q, &stack),
    }
}

/// The call whose argument the string opened at `q` is (directly, or as an
/// element of a list argument); none inside a record or a bare bracket.
fn call_around(before: &str, q: usize, stack: &[Frame]) -> Option<Call> {
    let k = stack.iter().rposition(|f| f.open != '[')?;
    let frame = &stack[k];
    if frame.open != '(' {
        return None;
    }
    let head = before[..frame.at].trim_end();
    let function = trailing_name(head)?;
    let dot = head[..head.len() - function.len()].trim_end();
    let method = dot.ends_with('.');
    let receiver = if method {
        trailing_name(dot[..dot.len() - 1].trim_end())
            .filter(|r| is_name(r))
            .map(String::from)
    } else {
        let end = frame.first_end.unwrap_or(q);
        let first = before[frame.at + 1..end].trim();
        (frame.commas > 0 && is_name(first)).then(|| first.to_string())
    };
    let arg = before[frame.arg_start..q].trim_start();
    let named = named_argument(arg);
    let index = named
        .is_none()
        .then_some(frame.commas + usize::from(method));
    Some(Call {
        function: function.to_string(),
        index,
        named,
        receiver,
    })
}

/// `name:` at the start of an argument's text.
fn named_argument(arg: &str) -> Option<String> {
    let end = arg
        .find(|c: char| !(c.is_alphanumeric() || c == '_'))
        .unwrap_or(arg.len());
    let (name, rest) = arg.split_at(end);
    (!name.is_empty() && rest.trim_start().starts_with(':')).then(|| name.to_string())
}

/// The identifier `text` ends with.
fn trailing_name(text: &str) -> Option<&str> {
    let start = text
        .char_indices()
        .rev()
        .find(|(_, c)| !(c.is_alphanumeric() || *c == '_'))
        .map(|(i, c)| i + c.len_utf8())
        .unwrap_or(0);
    let name = &text[start..];
    (!name.is_empty() && !name.starts_with(|c: char| c.is_ascii_digit())).then_some(name)
}

fn is_name(s: &str) -> bool {
    trailing_name(s) == Some(s)
}

/// The parameter names of a signature: `only(m, pattern, ...)` → `m`,
/// `pattern`, `...`; `ik(body, only: pattern)` → `body`, `only`;
/// `hold(names, tf = nil)` → `names`, `tf`.
pub fn params_of(signature: &str) -> Vec<String> {
    let Some(open) = signature.find('(') else {
        return vec![];
    };
    let inner = signature[open + 1..].trim_end();
    let inner = inner.strip_suffix(')').unwrap_or(inner);
    super::signature::split_top(inner, ',')
        .into_iter()
        .filter_map(|part| {
            let name = part.split([':', '=']).next().unwrap_or("").trim();
            (!name.is_empty()).then(|| name.to_string())
        })
        .collect()
}

/// The parameter positional argument `i` binds: past a trailing `...` the one
/// before it repeats; `...options` takes only named arguments.
fn param_at(params: &[String], i: usize) -> Option<&str> {
    let rest = params.iter().position(|p| p.starts_with("..."));
    match rest {
        Some(r) if i >= r => (params[r] == "..." && r > 0).then(|| params[r - 1].as_str()),
        _ => params.get(i).map(String::as_str),
    }
}

/// A name in scope or a `:command`, from the word before the cursor.
fn names(before: &str, scope: &Scope) -> (usize, Vec<Candidate>) {
    let start = before
        .char_indices()
        .rev()
        .find(|(_, c)| !(c.is_alphanumeric() || *c == '_' || *c == ':'))
        .map(|(i, c)| i + c.len_utf8())
        .unwrap_or(0);
    let word = &before[start..];
    if word.is_empty() {
        return (before.len(), vec![]);
    }
    let found: BTreeSet<&str> = if word.starts_with(':') {
        COMMANDS
            .iter()
            .copied()
            .filter(|c| c.starts_with(word))
            .collect()
    } else {
        scope
            .names
            .iter()
            .map(String::as_str)
            .filter(|n| n.starts_with(word))
            .collect()
    };
    (
        start,
        found
            .into_iter()
            .map(|s| Candidate::same(s.to_string()))
            .collect(),
    )
}

/// The argument of `:load` / `:l` being typed, if the line is one.
fn load_command_argument(before: &str) -> Option<&str> {
    let t = before.trim_start();
    [":load ", ":l "]
        .iter()
        .find_map(|c| t.strip_prefix(c))
        .map(str::trim_start)
}

/// DOF names of the session's motions starting with the string's text: the
/// receiver's own when it is a bound motion, else every bound motion's.
fn dofs(text: &str, start: usize, call: Option<&Call>, scope: &Scope) -> (usize, Vec<Candidate>) {
    let own = call
        .and_then(|c| c.receiver.as_ref())
        .and_then(|r| scope.motions.iter().find(|(n, _)| n == r));
    let pools: Vec<&Vec<String>> = match own {
        Some((_, d)) => vec![d],
        None => scope.motions.iter().map(|(_, d)| d).collect(),
    };
    let prefix = unescape(text);
    let found: BTreeSet<&str> = pools
        .into_iter()
        .flatten()
        .map(String::as_str)
        .filter(|d| d.starts_with(&prefix))
        .collect();
    (
        start,
        found
            .into_iter()
            .map(|d| Candidate {
                display: d.to_string(),
                replacement: escape(d),
            })
            .collect(),
    )
}

/// Folder entries completing the last component of `text` (which starts at
/// byte `start` of the line); folders end in `/`. Hidden entries only when the
/// component starts with a dot. `quoted`: inside an mx string (escape `"` and `\`).
fn paths(text: &str, start: usize, scope: &Scope, quoted: bool) -> (usize, Vec<Candidate>) {
    let cut = text.rfind('/').map_or(0, |i| i + 1);
    let (dir, part) = text.split_at(cut);
    let (dir, part) = if quoted {
        (unescape(dir), unescape(part))
    } else {
        (dir.to_string(), part.to_string())
    };
    let folder = folder_of(&dir, &scope.folder);
    let Ok(entries) = std::fs::read_dir(&folder) else {
        return (start + cut, vec![]);
    };
    let mut found: Vec<(String, bool)> = entries
        .flatten()
        .filter_map(|e| {
            let name = e.file_name().to_str()?.to_string();
            let is_dir = e.path().is_dir();
            (name.starts_with(&part) && (part.starts_with('.') || !name.starts_with('.')))
                .then_some((name, is_dir))
        })
        .collect();
    found.sort();
    let out = found
        .into_iter()
        .map(|(name, is_dir)| {
            let shown = if is_dir { format!("{name}/") } else { name };
            Candidate {
                replacement: if quoted {
                    escape(&shown)
                } else {
                    shown.clone()
                },
                display: shown,
            }
        })
        .collect();
    (start + cut, out)
}

/// The folder a typed directory part names: absolute, `~/…`, or relative to `base`.
fn folder_of(dir: &str, base: &Path) -> PathBuf {
    if dir.is_empty() {
        return base.to_path_buf();
    }
    if let Some(rest) = dir.strip_prefix("~/")
        && let Some(home) = std::env::var_os("HOME")
    {
        return PathBuf::from(home).join(rest);
    }
    base.join(dir) // an absolute `dir` replaces `base`
}

/// A string's text as typed read back, as the parser reads it; text that
/// is not yet a whole string (a trailing `\`) as it stands.
fn unescape(s: &str) -> String {
    crate::lang::parser::build::unescape(s).unwrap_or_else(|_| s.to_string())
}

/// Text to put inside an mx string (the language's own quoting, without
/// the quotes).
fn escape(s: &str) -> String {
    let q = crate::lang::value::quote(s);
    q[1..q.len() - 1].to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scope() -> Scope {
        let mut params = BTreeMap::new();
        for sig in [
            "load(path)",
            "save(x, path, ...options)",
            "only(m, pattern, ...)",
            "get(m, name)",
            "env(name)",
            "ik(body, m, targets, only: pattern, weights: {Link: w}, tolerance: 1e-6)",
            "print(x, ...)",
        ] {
            let name = sig.split('(').next().unwrap().to_string();
            params.insert(name, params_of(sig));
        }
        Scope {
            names: vec!["walk".into(), "wave".into(), "load".into()],
            params,
            motions: vec![
                (
                    "walk".into(),
                    vec![
                        "Hips.Xposition".into(),
                        "Hips.Xrotation".into(),
                        "Head.Zrotation".into(),
                    ],
                ),
                (
                    "run".into(),
                    vec!["Hips.Yrotation".into(), "Pelvis.tilt".into()],
                ),
            ],
            folder: PathBuf::from("/nonexistent"),
        }
    }

    fn replacements(line: &str, scope: &Scope) -> (usize, Vec<String>) {
        let (start, c) = complete(line, line.len(), scope);
        (start, c.into_iter().map(|c| c.replacement).collect())
    }

    #[test]
    fn signatures_give_parameter_names() {
        assert_eq!(params_of("only(m, pattern, ...)"), ["m", "pattern", "..."]);
        assert_eq!(
            params_of("planar(normal: [0, 0, 1], x_axis: [1, 0, 0])"),
            ["normal", "x_axis"]
        );
        assert_eq!(
            params_of("hold(names, value, ts, tf = nil)"),
            ["names", "value", "ts", "tf"]
        );
        let p = params_of("save(x, path, ...options)");
        assert_eq!(param_at(&p, 1), Some("path"));
        assert_eq!(param_at(&p, 2), None, "options are named only");
        let p = params_of("only(m, pattern, ...)");
        assert_eq!(param_at(&p, 3), Some("pattern"), "a trailing ... repeats");
    }

    #[test]
    fn the_cursor_knows_strings_comments_and_the_call() {
        assert_eq!(cursor("let x = 1 + "), Cursor::Code);
        assert_eq!(cursor("let x = \"a\" + y"), Cursor::Code);
        assert_eq!(cursor("1 // load(\"a"), Cursor::Comment);
        assert_eq!(cursor("/* \"a */ b"), Cursor::Code);
        let Cursor::Str { start, call } = cursor("save(m, \"out/x\\\"y") else {
            panic!("in a string")
        };
        assert_eq!(start, 9);
        let call = call.unwrap();
        assert_eq!((call.function.as_str(), call.index), ("save", Some(1)));
        assert_eq!(call.receiver.as_deref(), Some("m"));
        let Cursor::Str { call, .. } = cursor("walk.only(\"Hi") else {
            panic!()
        };
        let call = call.unwrap();
        assert_eq!(
            (call.index, call.receiver.as_deref()),
            (Some(1), Some("walk"))
        );
        let Cursor::Str { call, .. } = cursor("ik(b, m, t, only: [\"Hips\", \"He") else {
            panic!()
        };
        assert_eq!(call.unwrap().named.as_deref(), Some("only"));
        let Cursor::Str { call, .. } = cursor("f({a: \"x") else {
            panic!()
        };
        assert_eq!(call, None, "a record's value is no argument");
        let Cursor::Str { call, .. } = cursor("print((1, \"x") else {
            panic!()
        };
        assert_eq!(call, None, "a bare parenthesis is no call");
    }

    #[test]
    fn dof_names_complete_inside_dof_arguments() {
        let s = scope();
        // the receiver's own DOFs
        assert_eq!(
            replacements("walk.only(\"Hips.X", &s),
            (11, vec!["Hips.Xposition".into(), "Hips.Xrotation".into()])
        );
        assert_eq!(replacements("only(walk, \"He", &s).1, ["Head.Zrotation"]);
        // an unknown receiver: every bound motion's
        assert_eq!(
            replacements("only(walk + run, \"Hips.", &s).1,
            ["Hips.Xposition", "Hips.Xrotation", "Hips.Yrotation"]
        );
        assert_eq!(replacements("get(run, \"Pel", &s).1, ["Pelvis.tilt"]);
        assert_eq!(
            replacements("only(walk, \"Hips.Xr\", \"He", &s).1,
            ["Head.Zrotation"]
        );
        assert_eq!(
            replacements("ik(b, walk, t, only: [\"He", &s).1,
            ["Head.Zrotation"]
        );
        // not a DOF argument: nothing
        assert!(replacements("env(\"Hi", &s).1.is_empty());
        assert!(replacements("print(\"Hi", &s).1.is_empty());
        assert!(replacements("let s = \"Hi", &s).1.is_empty());
    }

    #[test]
    fn paths_complete_inside_path_arguments_and_after_load() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("clips")).unwrap();
        std::fs::write(dir.path().join("clips/walk.bvh"), "").unwrap();
        std::fs::write(dir.path().join("clips/wave \"x\".bvh"), "").unwrap();
        std::fs::write(dir.path().join("clips/.hidden"), "").unwrap();
        std::fs::write(dir.path().join("cat.json"), "").unwrap();
        let s = Scope {
            folder: dir.path().to_path_buf(),
            ..scope()
        };
        assert_eq!(
            replacements("load(\"c", &s),
            (6, vec!["cat.json".into(), "clips/".into()])
        );
        assert_eq!(
            replacements("let w = load(\"clips/w", &s),
            (20, vec!["walk.bvh".into(), "wave \\\"x\\\".bvh".into()])
        );
        assert_eq!(
            replacements("walk.save(\"clips/wa", &s).1.len(),
            2,
            "a method's path"
        );
        assert_eq!(replacements("save(walk, \"clips/.h", &s).1, [".hidden"]);
        assert_eq!(
            replacements(":load clips/wal", &s),
            (12, vec!["walk.bvh".into()])
        );
        let abs = format!("load(\"{}/cl", dir.path().display());
        assert_eq!(replacements(&abs, &s).1, ["clips/"]);
        assert!(replacements("load(\"zz", &s).1.is_empty());
        assert!(
            replacements("only(walk, \"c", &s).1.is_empty(),
            "no paths for a DOF"
        );
    }

    #[test]
    fn names_and_commands_complete_in_code() {
        let s = scope();
        assert_eq!(
            replacements("1 + wa", &s),
            (4, vec!["walk".into(), "wave".into()])
        );
        assert_eq!(replacements(":he", &s).1, [":help"]);
        assert!(replacements("1 + ", &s).1.is_empty());
    }

    #[test]
    fn the_scope_holds_the_sessions_motions_and_signatures() {
        let mut i = Interpreter::new();
        let walk = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/walk.bvh");
        let mut s = Scope::of(&i, PathBuf::from("."));
        assert!(s.motions.is_empty());
        i.eval_str(&format!("let walk = load(\"{walk}\")")).unwrap();
        s.refresh(&i);
        let (_, dofs) = s
            .motions
            .iter()
            .find(|(n, _)| n == "walk")
            .expect("walk is a motion");
        assert!(dofs.iter().any(|d| d == "Hips.Xposition"), "{dofs:?}");
        // a format's options are named only (`animation:`), after the path
        assert_eq!(s.params["load"], ["path", "...options"]);
        assert_eq!(
            replacements("walk.only(\"LeftFoot.Z", &s).1,
            ["LeftFoot.Zrotation"]
        );
    }
}
