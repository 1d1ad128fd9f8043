//! [`Interpreter`]: the embedding API. It owns the source texts (for
//! diagnostics), the global environment that grows with each `let`/`fn`, the
//! built-in registry, the limits, the file root and the cancellation token.
//!
//! ```
//! let mut mx = mx::Interpreter::new();
//! mx.eval_str("let double = fn(x) = 2 * x").unwrap();
//! assert_eq!(mx.eval_str("double(21)").unwrap().as_number(), Some(42.0));
//! ```

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use super::args::Args;
use super::ast::{Import, Program, SourceId, Span};
use super::diagnostics::{Diagnostic, ErrorKind, MxError, MxResult, Source};
use super::eval::{Context, Evaluator, Limits, Output};
use super::help::{self, Entry};
use super::host::Motion;
use super::host::sp_report::report_of;
use super::parser;
use super::registry::Registry;
use super::resolve::{Callee, Outside, Resolver};
use super::session::Session;
use super::value::{Env, Value};
use crate::cancel::CancelToken;

/// The standard library, written in mx and loaded by [`Interpreter::new`].
pub const PRELUDE: &str = include_str!("../../stdlib/prelude.mx");

pub struct Interpreter {
    globals: Env,
    ctx: Context,
}

/// A clone has the same globals, registry and settings but its own
/// [`Session`]: two interpreters never share mutable state.
impl Clone for Interpreter {
    fn clone(&self) -> Self {
        let mut ctx = self.ctx.clone();
        ctx.session = Arc::new(Session::new());
        ctx.sources = Arc::new(Mutex::new(self.sources().clone()));
        Interpreter {
            globals: self.globals.clone(),
            ctx,
        }
    }
}

impl Default for Interpreter {
    fn default() -> Self {
        Self::new()
    }
}

impl Interpreter {
    /// An interpreter with every built-in and the prelude loaded.
    pub fn new() -> Self {
        let mut i = Self::bare();
        if let Err(d) = i.eval_named("<prelude>", PRELUDE) {
            // The prelude ships with the binary and is tested; failing here is
            // a build defect, reported rather than panicking.
            eprintln!("warning: the prelude failed to load:\n{}", d.render_plain());
        }
        // what an imported script starts from: the built-ins and the prelude
        i.ctx.base = i.globals.clone();
        i
    }

    /// An interpreter with the built-ins but without the prelude.
    pub fn bare() -> Self {
        Interpreter {
            globals: Env::empty(),
            ctx: Context::new(Arc::new(Registry::standard())),
        }
    }

    // ---- configuration ----

    /// Register a host function, callable from mx. `signature` like `"f(x, y)"`.
    pub fn register<F>(&mut self, signature: &str, doc: &str, f: F)
    where
        F: Fn(&mut Args, &mut Evaluator) -> MxResult<Value> + Send + Sync + 'static,
    {
        Arc::make_mut(&mut self.ctx.registry).add(signature, doc, f);
    }

    /// Change the registry (add formats, constants…).
    pub fn registry_mut(&mut self) -> &mut Registry {
        Arc::make_mut(&mut self.ctx.registry)
    }
    pub fn registry(&self) -> &Registry {
        &self.ctx.registry
    }

    /// Limit each top-level evaluation to `steps` evaluation steps (`None`: no limit).
    pub fn set_step_budget(&mut self, steps: Option<u64>) {
        self.ctx.limits.max_steps = steps;
    }
    /// Limit the nesting of mx function calls.
    pub fn set_max_depth(&mut self, depth: usize) {
        self.ctx.limits.max_depth = depth;
    }
    pub fn limits(&self) -> Limits {
        self.ctx.limits
    }

    /// Confine `load`/`save` to files under `root` (`None`: anywhere).
    pub fn set_file_root(&mut self, root: Option<PathBuf>) {
        self.ctx.file_root = root.map(Arc::new);
    }

    /// Send `print` output somewhere other than stdout.
    pub fn set_output(&mut self, out: Output) {
        self.ctx.out = out;
    }

    /// Capture `print` output in a shared buffer (tests, embedders).
    pub fn capture_output(&mut self) -> Arc<Mutex<Vec<u8>>> {
        let buf = Arc::new(Mutex::new(Vec::new()));
        self.ctx.out = Arc::new(Mutex::new(SharedBuf(buf.clone())));
        buf
    }

    /// The token that cancels running evaluations (hand it to a Ctrl-C handler).
    pub fn cancel_token(&self) -> CancelToken {
        self.ctx.cancel.clone()
    }

    /// A context for evaluating values (e.g. mx functions) outside `eval_*`.
    pub fn context(&self) -> Context {
        self.ctx.clone()
    }

    // ---- globals ----

    pub fn get(&self, name: &str) -> Option<Value> {
        self.globals
            .get(name)
            .cloned()
            .or_else(|| self.ctx.registry.lookup(name))
    }
    pub fn set(&mut self, name: &str, value: impl Into<Value>) {
        self.globals = self.globals.bind(name, value.into());
    }
    /// Every name in scope: user globals first, then built-ins.
    pub fn names(&self) -> Vec<String> {
        let mut v = self.globals.names();
        v.extend(self.ctx.registry.names().map(String::from));
        v
    }

    // ---- evaluation ----

    fn sources(&self) -> std::sync::MutexGuard<'_, Vec<Source>> {
        self.ctx.sources.lock().unwrap_or_else(|p| p.into_inner())
    }

    fn add_source(&mut self, name: &str, text: &str) -> SourceId {
        let mut sources = self.sources();
        sources.push(Source {
            name: name.to_string(),
            text: Arc::from(text),
        });
        (sources.len() - 1) as SourceId
    }

    /// Attach the source text to an error for display (an input's, or an
    /// imported script's).
    pub fn diagnostic(&self, e: MxError) -> Diagnostic {
        let sources = self.sources();
        let src = e.span.and_then(|s| sources.get(s.file as usize));
        Diagnostic::new(e, src)
    }

    /// Evaluate source text; `let`/`fn` at top level stay defined.
    pub fn eval_str(&mut self, src: &str) -> Result<Value, Diagnostic> {
        self.eval_named("<input>", src)
    }

    /// Evaluate a file.
    pub fn eval_file(&mut self, path: impl AsRef<Path>) -> Result<Value, Diagnostic> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|e| {
            self.diagnostic(
                MxError::new(
                    ErrorKind::Io,
                    format!("cannot read {}: {e}", path.display()),
                )
                .help("check the file name and that the file is UTF-8 text"),
            )
        })?;
        // the script's relative paths are its folder's, for this run only
        let dir = path
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .map(|d| Arc::new(d.to_path_buf()));
        let outer = std::mem::replace(&mut self.ctx.script_dir, dir);
        // the script itself heads the import chain: importing it again is a cycle
        let chain = path
            .canonicalize()
            .map(|c| Arc::new(vec![c]))
            .unwrap_or_default();
        let outer_chain = std::mem::replace(&mut self.ctx.chain, chain);
        let result = self.eval_named(&path.display().to_string(), &text);
        self.ctx.script_dir = outer;
        self.ctx.chain = outer_chain;
        result
    }

    /// Evaluate source text under a display name (used in diagnostics).
    pub fn eval_named(&mut self, name: &str, src: &str) -> Result<Value, Diagnostic> {
        let program = self.parse_named(name, src)?;
        let mut ev = Evaluator::new(self.ctx.clone());
        match ev.exec(&program.stmts, self.globals.clone()) {
            Ok((v, env)) => {
                self.globals = env;
                Ok(v)
            }
            Err(e) => Err(self.diagnostic(e)),
        }
    }

    /// Parse only (registers the source for later diagnostics).
    pub fn parse_named(&mut self, name: &str, src: &str) -> Result<Program, Diagnostic> {
        let id = self.add_source(name, src);
        parser::parse_program(src, id).map_err(|e| self.diagnostic(e))
    }

    /// Parse and check without running (`mx check`): names, named
    /// arguments, imports (see [`super::resolve`]).
    pub fn check_named(&mut self, name: &str, src: &str) -> Result<(), Diagnostic> {
        let program = self.parse_named(name, src)?;
        let mut outside = Checking::new(self, self.ctx.script_dir.as_deref().cloned(), vec![]);
        let first = Resolver::new(&mut outside).program(&program);
        first.map_err(|e| self.diagnostic(e))
    }

    /// Like [`Self::check_named`], but every independent error (`mx check`):
    /// each statement that does not parse (the parser reads on at the next
    /// statement) and each error of the statements that do, in source order,
    /// then those of the scripts it imports; empty when the script checks.
    pub fn check_all_named(&mut self, name: &str, src: &str) -> Vec<Diagnostic> {
        let dir = self.ctx.script_dir.as_deref().cloned();
        self.check_all_in(name, src, dir, vec![])
    }

    /// [`Self::check_all_named`] of the script `path` whose text is `src`:
    /// its imports are read from its folder.
    pub fn check_script(&mut self, path: &Path, src: &str) -> Vec<Diagnostic> {
        let dir = path.parent().map(Path::to_path_buf);
        let chain = path.canonicalize().into_iter().collect();
        self.check_all_in(&path.display().to_string(), src, dir, chain)
    }

    fn check_all_in(
        &mut self,
        name: &str,
        src: &str,
        dir: Option<PathBuf>,
        chain: Vec<PathBuf>,
    ) -> Vec<Diagnostic> {
        let id = self.add_source(name, src);
        let (program, mut errors) = parser::parse_program_recovering(src, id);
        let mut outside = Checking::new(self, dir, chain);
        errors.extend(Resolver::new(&mut outside).program_all(&program));
        // the script's errors in source order, then each imported script's
        // (stable: a syntax error and a name at one place keep that order)
        errors.sort_by_key(|e| e.span.map_or((u32::MAX, 0), |s| (s.file, s.start)));
        errors.into_iter().map(|e| self.diagnostic(e)).collect()
    }

    /// Evaluate one expression and report its type (REPL `:type`) without
    /// keeping any binding.
    pub fn type_of(&mut self, src: &str) -> Result<String, Diagnostic> {
        let id = self.add_source("<input>", src);
        let expr = parser::parse_expr(src, id).map_err(|e| self.diagnostic(e))?;
        let mut ev = Evaluator::new(self.ctx.clone());
        let v = ev
            .eval(&expr, &self.globals)
            .map_err(|e| self.diagnostic(e))?;
        Ok(v.type_name().to_string())
    }

    /// Call a function value (mx or built-in) from Rust.
    pub fn call(&mut self, f: &Value, args: Vec<Value>) -> Result<Value, Diagnostic> {
        let mut ev = Evaluator::new(self.ctx.clone());
        ev.call(f, args, Span::default())
            .map_err(|e| self.diagnostic(e))
    }
}

/// Help and what the REPL shows about values.
impl Interpreter {
    /// Every documented name: the built-ins, then the prelude's functions
    /// (those still bound to the prelude's definition).
    pub fn help_entries(&self) -> Vec<Entry> {
        let mut entries = help::builtin_entries(&self.ctx.registry);
        entries.extend(help::prelude_entries(PRELUDE).into_iter().filter(|e| {
            matches!(self.globals.get(&e.name), Some(Value::Function(c))
                if c.def.name.as_deref() == Some(e.name.as_str()))
        }));
        entries
    }

    /// The help for one name (built-in or prelude function).
    pub fn help_entry(&self, name: &str) -> Option<Entry> {
        self.help_entries().into_iter().find(|e| e.name == name)
    }

    /// The text of `:help WORD`: every name by topic for an empty word, one
    /// topic's names and docs, `formats`, one name's signature and doc, or
    /// what a global holds; `Err` for a word that is none of these.
    pub fn help(&self, word: &str) -> Result<String, String> {
        let word = word.trim();
        if word.is_empty() {
            return Ok(help::overview(&self.help_entries()));
        }
        if word == "formats" {
            return Ok(help::formats_text(&self.ctx.registry));
        }
        if let Some(e) = self.help_entry(word) {
            return Ok(help::entry_text(&e) + "\n");
        }
        if let Some(t) = super::topic::Topic::parse(word) {
            return Ok(help::topic_text(&self.help_entries(), t));
        }
        match self.get(word) {
            Some(v) => Ok(format!("{word}: {} = {}\n", v.type_name(), v.repr())),
            None => {
                // the topics, `formats`, every documented name and every global
                let mut words: Vec<String> = super::topic::Topic::ALL
                    .iter()
                    .map(|t| t.key().to_string())
                    .collect();
                words.push("formats".into());
                words.extend(self.help_entries().into_iter().map(|e| e.name));
                words.extend(self.names());
                Err(
                    match super::diagnostics::did_you_mean(word, words.iter().map(String::as_str)) {
                        Some(s) => format!("no built-in or name `{word}`; did you mean `{s}`?"),
                        None => format!("no built-in or name `{word}`"),
                    },
                )
            }
        }
    }

    /// The reference page `docs/reference.md` (`mx help --markdown`).
    pub fn help_markdown(&self) -> String {
        help::markdown(&self.help_entries(), &self.ctx.registry)
    }

    /// The report SP attached to the motion it returned, as text (`:info`).
    pub fn sp_report_text(v: &Value) -> Option<String> {
        report_of(v).map(|r| r.to_string())
    }

    /// The clip a loaded motion came from, described (`:info`): file,
    /// frames, rate, units, joints; `None` for a motion not read from a clip.
    pub fn clip_text(v: &Value) -> Option<String> {
        let clip = super::host::motion::provenance(v)?.clip.as_ref()?;
        let mu = Self::motion_of(v)?;
        Some(clip.describe(&mu))
    }

    /// A motion value as a motion unit (a DOF or interval as one DOF named
    /// `value`), e.g. to plot it; `None` for a value that is no motion.
    pub fn motion_of(v: &Value) -> Option<crate::motion::Mu> {
        match v.as_object::<Motion>()? {
            Motion::Mu(m) => Some(m.clone()),
            other => {
                let mut m = crate::motion::Mu::new();
                if let Some(d) = other.as_dof() {
                    m.insert("value", d);
                }
                Some(m)
            }
        }
    }

    /// Whether `src` is unfinished input (open brackets, a dangling operator):
    /// the REPL then reads another line.
    pub fn is_incomplete(src: &str) -> bool {
        parser::is_incomplete(src)
    }
}

/// What `mx check` knows outside the script: the globals, the built-ins'
/// signatures, and the scripts it imports, each read and checked in turn.
struct Checking {
    globals: Env,
    base: Env,
    registry: Arc<Registry>,
    sources: super::eval::Sources,
    /// The folder imports are read from (the checked script's).
    dir: Option<PathBuf>,
    /// The scripts being checked, outermost first (for cycles).
    chain: Vec<PathBuf>,
}

impl Checking {
    fn new(i: &Interpreter, dir: Option<PathBuf>, chain: Vec<PathBuf>) -> Self {
        Checking {
            globals: i.globals.clone(),
            base: i.ctx.base.clone(),
            registry: i.ctx.registry.clone(),
            sources: i.ctx.sources.clone(),
            dir,
            chain,
        }
    }
}

impl Outside for Checking {
    fn known(&self, n: &str) -> bool {
        self.globals.get(n).is_some() || self.registry.lookup(n).is_some()
    }

    fn names(&self) -> Vec<String> {
        let mut v = self.globals.names();
        v.extend(self.registry.names().map(String::from));
        v
    }

    fn callee(&self, n: &str) -> Option<Callee> {
        match self.globals.get(n) {
            Some(Value::Function(c)) => Some(Callee::of_fn(&c.def)),
            Some(Value::Builtin(b)) => Some(Callee::of_signature(&b.signature)),
            Some(_) => None,
            None => self
                .registry
                .function(n)
                .map(|b| Callee::of_signature(&b.signature)),
        }
    }

    fn import(&mut self, imp: &Import, errors: &mut Vec<MxError>) -> Option<Vec<String>> {
        let path = match &self.dir {
            Some(d) if Path::new(imp.path.as_ref()).is_relative() => d.join(imp.path.as_ref()),
            _ => PathBuf::from(imp.path.as_ref()),
        };
        let read = path.canonicalize().and_then(|c| {
            let text = std::fs::read_to_string(&c)?;
            Ok((c, text))
        });
        let (canon, text) = match read {
            Ok(r) => r,
            Err(e) => {
                errors.push(
                    MxError::new(
                        ErrorKind::Io,
                        format!("cannot import `{}`: {e}", path.display()),
                    )
                    .at(imp.path_span)
                    .label("cannot be read")
                    .help("an import is read from the importing script's folder"),
                );
                return None;
            }
        };
        if let Some(k) = self.chain.iter().position(|p| *p == canon) {
            let names: Vec<String> = self.chain[k..]
                .iter()
                .chain([&canon])
                .map(|p| {
                    p.file_name().map_or_else(
                        || p.display().to_string(),
                        |n| n.to_string_lossy().into_owned(),
                    )
                })
                .collect();
            errors.push(
                MxError::new(
                    ErrorKind::Value,
                    format!("import cycle: {}", names.join(" → ")),
                )
                .at(imp.path_span)
                .label("imports a script that imports this one")
                .help("move what both scripts need into a third one that imports neither"),
            );
            return None;
        }
        let id = {
            let mut s = self.sources.lock().unwrap_or_else(|p| p.into_inner());
            s.push(Source {
                name: path.display().to_string(),
                text: Arc::from(text.as_str()),
            });
            (s.len() - 1) as SourceId
        };
        let (program, parse_errors) = parser::parse_program_recovering(&text, id);
        errors.extend(parse_errors);
        // the imported script is checked as it runs: from the built-ins and
        // the prelude, in its own folder
        let globals = std::mem::replace(&mut self.globals, self.base.clone());
        let dir = std::mem::replace(&mut self.dir, canon.parent().map(Path::to_path_buf));
        self.chain.push(canon);
        errors.extend(Resolver::new(self).program_all(&program));
        self.chain.pop();
        self.dir = dir;
        self.globals = globals;
        Some(
            program
                .stmts
                .iter()
                .filter_map(super::eval::defined_name)
                .filter(|n| !n.starts_with('_'))
                .map(str::to_string)
                .collect(),
        )
    }
}

/// `Write` into a shared byte buffer.
struct SharedBuf(Arc<Mutex<Vec<u8>>>);

impl std::io::Write for SharedBuf {
    fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
        self.0
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .extend_from_slice(b);
        Ok(b.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(src: &str) -> (Result<Value, Diagnostic>, String) {
        let mut i = Interpreter::new();
        let out = i.capture_output();
        let r = i.eval_str(src);
        let s = String::from_utf8(out.lock().unwrap().clone()).unwrap();
        (r, s)
    }

    fn val(src: &str) -> Value {
        match run(src).0 {
            Ok(v) => v,
            Err(d) => panic!("{src}: {}", d.render_plain()),
        }
    }

    fn err(src: &str) -> Diagnostic {
        match run(src).0 {
            Ok(v) => panic!("{src}: expected an error, got {v}"),
            Err(d) => d,
        }
    }

    #[test]
    fn arithmetic_units_and_print() {
        assert_eq!(val("1 + 2 * 3").as_number(), Some(7.0));
        assert_eq!(val("250ms + 1s").as_number(), Some(1.25));
        assert_eq!(val("90deg").as_number(), Some(std::f64::consts::FRAC_PI_2));
        let (_, out) = run("print(0.1, 1e-12, [1, 2], {a: 1, b: \"x\"}, \"hi\", true)");
        assert_eq!(out, "0.1 1e-12 [1, 2] {a: 1, b: \"x\"} hi true\n");
    }

    #[test]
    fn functions_closures_recursion_named_args() {
        assert_eq!(val("fn f(t) = t * 2\nf(21)").as_number(), Some(42.0));
        assert_eq!(
            val("let k = 3; let g = fn(x) = x + k; g(1)").as_number(),
            Some(4.0)
        );
        assert_eq!(
            val("fn fact(n) = if n <= 1 { 1 } else { n * fact(n - 1) }\nfact(10)").as_number(),
            Some(3628800.0)
        );
        assert_eq!(
            val("fn f(a, b = 10) = a - b\nf(b: 1, a: 5) + f(20)").as_number(),
            Some(14.0)
        );
        assert_eq!(val("map([1, 2, 3], fn(x) = x * x)").repr(), "[1, 4, 9]");
        assert_eq!(
            val("[1, 2, 3].map(fn(x) = x + 1).sum()").as_number(),
            Some(9.0)
        );
        assert_eq!(
            val("let r = {f: fn(x) = x * 10}; r.f(2)").as_number(),
            Some(20.0)
        );
        assert_eq!(val("{ let a = 2; a * a }").as_number(), Some(4.0));
    }

    #[test]
    fn errors_have_kinds_spans_and_help() {
        let d = err("let walk = 1\nwolk + 1");
        assert_eq!(d.kind(), ErrorKind::UnknownName);
        assert!(d.error().help.as_deref().unwrap_or("").contains("walk"));
        assert_eq!(err("1 / 0").kind(), ErrorKind::DivisionByZero);
        assert_eq!(err("sin(\"x\")").kind(), ErrorKind::Type);
        assert_eq!(err("sin(1, 2)").kind(), ErrorKind::Arity);
        assert_eq!(err("fn f(n) = f(n + 1)\nf(0)").kind(), ErrorKind::Recursion);
        assert_eq!(err("sqrt(-1)").kind(), ErrorKind::Value);
    }

    #[test]
    fn step_budget_and_cancellation_stop_loops() {
        let mut i = Interpreter::new();
        i.set_step_budget(Some(10_000));
        i.set_max_depth(1_000_000);
        let d = i.eval_str("fn f(n) = f(n + 1)\nf(0)").unwrap_err();
        assert_eq!(d.kind(), ErrorKind::StepBudget);
        let mut i = Interpreter::new();
        i.cancel_token().cancel();
        let d = i.eval_str("sum(map(range(5000), fn(x) = x))").unwrap_err();
        assert_eq!(d.kind(), ErrorKind::Cancelled);
    }

    #[test]
    fn file_root_confines_paths() {
        let mut i = Interpreter::new();
        i.set_file_root(Some(std::env::temp_dir()));
        let ev = Evaluator::new(i.context());
        assert!(ev.resolve_path("../etc/passwd", Span::default()).is_err());
        assert!(ev.resolve_path("/etc/passwd", Span::default()).is_err());
        assert!(ev.resolve_path("a/../b.json", Span::default()).is_ok());
    }

    #[test]
    fn check_resolves_names_without_running() {
        let mut i = Interpreter::new();
        assert!(i.check_named("t", "fn f(x) = x + 1\nprint(f(2))").is_ok());
        let d = i.check_named("t", "let walk = 1\nprint(wakl)").unwrap_err();
        assert_eq!(d.kind(), ErrorKind::UnknownName);
        // check does not run: an error at run time is not reported.
        assert!(i.check_named("t", "1 / 0").is_ok());
    }
}
