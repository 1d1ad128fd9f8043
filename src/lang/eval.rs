//! The tree-walking evaluator.
//!
//! An [`Evaluator`] is cheap to make from a [`Context`] (all `Arc`s), so an mx
//! function can be evaluated on any thread (motion curves sampled by rayon).
//! It counts steps against a budget, polls the cancellation token, bounds the
//! depth of mx calls and grows the native stack on deep nesting, so no script
//! can hang the process or overflow its stack.

use std::io::Write;
use std::path::{Component, Path, PathBuf};
use std::sync::{Arc, Mutex};

use indexmap::IndexMap;

use super::args::{ArgValue, Args, describe};
use super::ast::*;
use super::diagnostics::{ErrorKind, MxError, MxResult, Source, did_you_mean};
use super::fields::no_field;
use super::registry::{Format, Registry};
use super::session::Session;
use super::value::{Builtin, Closure, Env, Value};
use crate::cancel::CancelToken;

/// The body of a built-in function (`Registry::add`).
pub type BuiltinFn = dyn Fn(&mut Args, &mut Evaluator) -> MxResult<Value> + Send + Sync;
/// Reads a file into a value: `(path, remaining args, evaluator)`.
pub type LoadFn = dyn Fn(&Path, &mut Args, &mut Evaluator) -> MxResult<Value> + Send + Sync;
/// Writes a value to a file: `(value, path, remaining args, evaluator)`.
/// The path is already confined to the interpreter's file root.
pub type SaveFn = dyn Fn(&Value, &Path, &mut Args, &mut Evaluator) -> MxResult<()> + Send + Sync;

impl Builtin {
    /// The Rust closure (`None` only for a `Builtin` assembled by hand with
    /// some other body).
    pub fn body(&self) -> Option<&BuiltinFn> {
        self.func.downcast_ref::<Box<BuiltinFn>>().map(|b| &**b)
    }
}

impl Format {
    /// The reader `load` calls, if the format can be read.
    pub fn reader(&self) -> Option<&LoadFn> {
        self.load
            .as_ref()?
            .downcast_ref::<Box<LoadFn>>()
            .map(|b| &**b)
    }
    /// The writer `save` calls, if the format can be written.
    pub fn writer(&self) -> Option<&SaveFn> {
        self.save
            .as_ref()?
            .downcast_ref::<Box<SaveFn>>()
            .map(|b| &**b)
    }
}

/// Named arguments of a call: `(name, name span, value)`.
pub type NamedArgs = Vec<(String, Span, ArgValue)>;

/// Where `print` writes (stdout for the CLI; a buffer in tests and embedders).
pub type Output = Arc<Mutex<dyn Write + Send>>;

/// The source texts of one interpreter, by [`SourceId`]: its inputs and the
/// scripts they import, so an error inside an imported script shows its line.
pub type Sources = Arc<Mutex<Vec<Source>>>;

/// Resource limits of an evaluation.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    /// Maximum evaluation steps (one per expression node) per top-level
    /// evaluation; `None` = unlimited.
    pub max_steps: Option<u64>,
    /// Maximum nesting of mx function calls.
    pub max_depth: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            max_steps: None,
            max_depth: 2_000,
        }
    }
}

/// What an evaluation needs besides the environment; clone it freely.
#[derive(Clone)]
pub struct Context {
    pub registry: Arc<Registry>,
    pub cancel: CancelToken,
    pub limits: Limits,
    /// When set, `load`/`save` may only touch files under this folder.
    pub file_root: Option<Arc<PathBuf>>,
    /// The folder of the script being run: its relative paths resolve
    /// against it, as a shell resolves a script's `source` (so
    /// `cd examples && mx run tour.mx` and `mx run examples/tour.mx` read the
    /// same files). `None` (the REPL, `mx eval`): the current folder.
    pub script_dir: Option<Arc<PathBuf>>,
    pub out: Output,
    /// What built-ins remember for this interpreter (shared by its
    /// evaluators, never by two interpreters).
    pub session: Arc<Session>,
    /// Every source text read so far (see [`Sources`]).
    pub sources: Sources,
    /// The environment an imported script starts from: the built-ins and
    /// the prelude, none of the importer's names.
    pub base: Env,
    /// The scripts being run, outermost first (canonical paths): an import
    /// of one of them is a cycle.
    pub chain: Arc<Vec<PathBuf>>,
}

impl Context {
    pub fn new(registry: Arc<Registry>) -> Self {
        Context {
            registry,
            cancel: CancelToken::new(),
            limits: Limits::default(),
            file_root: None,
            script_dir: None,
            out: Arc::new(Mutex::new(std::io::stdout())),
            session: Arc::new(Session::new()),
            sources: Arc::new(Mutex::new(Vec::new())),
            base: Env::empty(),
            chain: Arc::new(Vec::new()),
        }
    }
}

pub struct Evaluator {
    pub ctx: Context,
    steps: u64,
    depth: usize,
}

const STACK_RED_ZONE: usize = 128 * 1024;
const STACK_GROW: usize = 2 * 1024 * 1024;

impl Evaluator {
    pub fn new(ctx: Context) -> Self {
        Evaluator {
            ctx,
            steps: 0,
            depth: 0,
        }
    }

    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Count one step; fail on budget exhaustion or cancellation.
    #[inline]
    fn tick(&mut self, span: Span) -> MxResult<()> {
        self.steps += 1;
        if let Some(max) = self.ctx.limits.max_steps
            && self.steps > max
        {
            return Err(MxError::new(ErrorKind::StepBudget, format!("evaluation exceeded its budget of {max} steps"))
                .at(span)
                .label("still running here")
                .help("the script may loop forever; otherwise raise the step budget (Interpreter::set_step_budget)"));
        }
        if self.steps & 1023 == 0 {
            self.check_cancel(span)?;
        }
        Ok(())
    }

    /// Fail with `Cancelled` if the token was cancelled (built-ins with long
    /// loops call this too).
    pub fn check_cancel(&self, span: Span) -> MxResult<()> {
        if self.ctx.cancel.is_cancelled() {
            return Err(MxError::new(ErrorKind::Cancelled, "evaluation cancelled")
                .at(span)
                .label("stopped here"));
        }
        Ok(())
    }

    /// Run statements in `env`; returns the last expression's value and the
    /// environment extended by the `let`s and `fn`s.
    pub fn exec(&mut self, stmts: &[Stmt], mut env: Env) -> MxResult<(Value, Env)> {
        let mut last = Value::Nil;
        for s in stmts {
            match s {
                Stmt::Let(name, _, e) => {
                    let v = self.eval(e, &env)?;
                    env = env.bind(name.clone(), v);
                    last = Value::Nil;
                }
                Stmt::Fn(def) => {
                    let name = def.name.clone().unwrap_or_default();
                    let f = Value::Function(Arc::new(Closure {
                        def: def.clone(),
                        env: env.clone(),
                    }));
                    env = env.bind(name, f);
                    last = Value::Nil;
                }
                Stmt::Import(imp) => {
                    let v = self.import(imp)?;
                    env = env.bind(imp.name.clone(), v);
                    last = Value::Nil;
                }
                Stmt::Expr(e) => last = self.eval(e, &env)?,
            }
        }
        Ok((last, env))
    }

    /// `import "walks.mx" as walks`: run the script, relative to this one's
    /// folder, in an environment of its own (the built-ins and the prelude),
    /// and return its top-level names as a record. Names starting with `_`
    /// stay private; the script sees none of the importer's names.
    fn import(&mut self, imp: &Import) -> MxResult<Value> {
        let path = self.resolve_path(&imp.path, imp.path_span)?;
        let canon = path.canonicalize().map_err(|e| {
            MxError::new(
                ErrorKind::Io,
                format!("cannot import `{}`: {e}", path.display()),
            )
            .at(imp.path_span)
            .label("no such script")
            .help("an import is read from the importing script's folder (the current folder in the REPL and `mx eval`)")
        })?;
        if let Some(k) = self.ctx.chain.iter().position(|p| *p == canon) {
            let names: Vec<String> = self.ctx.chain[k..]
                .iter()
                .chain([&canon])
                .map(|p| script_name(p))
                .collect();
            return Err(MxError::new(
                ErrorKind::Value,
                format!("import cycle: {}", names.join(" → ")),
            )
            .at(imp.path_span)
            .label("imports a script that is still running")
            .help("move what both scripts need into a third one that imports neither"));
        }
        let text = std::fs::read_to_string(&canon).map_err(|e| {
            MxError::new(
                ErrorKind::Io,
                format!("cannot read `{}`: {e}", path.display()),
            )
            .at(imp.path_span)
            .help("an mx script is UTF-8 text")
        })?;
        let id = {
            let mut sources = self.ctx.sources.lock().unwrap_or_else(|p| p.into_inner());
            sources.push(Source {
                name: path.display().to_string(),
                text: Arc::from(text.as_str()),
            });
            (sources.len() - 1) as SourceId
        };
        let program = super::parser::parse_program(&text, id)?;
        let mut ctx = self.ctx.clone();
        ctx.script_dir = canon.parent().map(|d| Arc::new(d.to_path_buf()));
        let mut chain = (*self.ctx.chain).clone();
        chain.push(canon);
        ctx.chain = Arc::new(chain);
        // the imported script counts against the importer's step budget
        let mut ev = Evaluator {
            ctx,
            steps: self.steps,
            depth: self.depth,
        };
        let result = ev.exec(&program.stmts, self.ctx.base.clone());
        self.steps = ev.steps;
        let (_, env) = result?;
        let mut exports = IndexMap::new();
        for name in program.stmts.iter().filter_map(defined_name) {
            if !name.starts_with('_')
                && let Some(v) = env.get(name)
            {
                exports.insert(name.to_string(), v.clone());
            }
        }
        Ok(Value::record(exports))
    }

    pub fn eval(&mut self, e: &Expr, env: &Env) -> MxResult<Value> {
        stacker::maybe_grow(STACK_RED_ZONE, STACK_GROW, || self.eval_inner(e, env))
    }

    fn lookup(&self, name: &str, env: &Env) -> Option<Value> {
        env.get(name)
            .cloned()
            .or_else(|| self.ctx.registry.lookup(name))
    }

    fn unknown_name(&self, name: &str, span: Span, env: &Env, what: &str) -> MxError {
        let names = env.names();
        let suggestion = did_you_mean(
            name,
            names
                .iter()
                .map(String::as_str)
                .chain(self.ctx.registry.names()),
        );
        let e = MxError::new(ErrorKind::UnknownName, format!("unknown {what} `{name}`"))
            .at(span)
            .label("not defined");
        match suggestion {
            Some(s) => e.help(format!("did you mean `{s}`?")),
            None => e.help(
                "define it first with `let` or `fn`; `:help` in the REPL lists the built-ins",
            ),
        }
    }

    fn eval_inner(&mut self, e: &Expr, env: &Env) -> MxResult<Value> {
        self.tick(e.span)?;
        match &e.kind {
            ExprKind::Number(x) => Ok(Value::Number(*x)),
            ExprKind::Str(s) => Ok(Value::Str(s.clone())),
            ExprKind::Bool(b) => Ok(Value::Bool(*b)),
            ExprKind::Ident(name) => self
                .lookup(name, env)
                .ok_or_else(|| self.unknown_name(name, e.span, env, "name")),
            ExprKind::List(items) => {
                let v = items
                    .iter()
                    .map(|i| self.eval(i, env))
                    .collect::<MxResult<Vec<_>>>()?;
                Ok(Value::list(v))
            }
            ExprKind::Record(fields) => {
                let mut r = IndexMap::with_capacity(fields.len());
                for (k, _, v) in fields {
                    r.insert(k.clone(), self.eval(v, env)?);
                }
                Ok(Value::record(r))
            }
            ExprKind::Unary(op, x) => {
                let v = self.eval(x, env)?;
                match (op, &v) {
                    (UnOp::Neg, Value::Number(n)) => Ok(Value::Number(-n)),
                    (UnOp::Not, Value::Bool(b)) => Ok(Value::Bool(!b)),
                    (UnOp::Neg, _) => Err(MxError::type_error(format!(
                        "cannot negate {}",
                        describe(&v)
                    ))
                    .at(x.span)
                    .label("not a number")
                    .help("unary `-` applies to numbers")),
                    (UnOp::Not, _) => Err(MxError::type_error(format!(
                        "`!` needs a bool, found {}",
                        describe(&v)
                    ))
                    .at(x.span)
                    .label("not a bool")
                    .help("compare first, e.g. `!(x > 0)`")),
                }
            }
            ExprKind::Binary(op, a, b) => self.binary(*op, a, b, e.span, env),
            ExprKind::If(c, t, f) => {
                let cv = self.eval(c, env)?;
                match cv {
                    Value::Bool(true) => self.eval(t, env),
                    Value::Bool(false) => match f {
                        Some(f) => self.eval(f, env),
                        None => Ok(Value::Nil),
                    },
                    other => Err(MxError::type_error(format!(
                        "the condition of `if` must be a bool, found {}",
                        describe(&other)
                    ))
                    .at(c.span)
                    .label("not a bool")
                    .help("compare explicitly, e.g. `if x > 0 { … }`")),
                }
            }
            ExprKind::Block(stmts) => Ok(self.exec(stmts, env.clone())?.0),
            ExprKind::Lambda(def) => Ok(Value::Function(Arc::new(Closure {
                def: def.clone(),
                env: env.clone(),
            }))),
            ExprKind::Call(f, args) => {
                let fv = match &f.kind {
                    ExprKind::Ident(name) => self
                        .lookup(name, env)
                        .ok_or_else(|| self.unknown_name(name, f.span, env, "function"))?,
                    _ => self.eval(f, env)?,
                };
                let (pos, named) = self.eval_args(args, env)?;
                self.call_with(&fv, f.span, e.span, pos, named)
            }
            ExprKind::Method(recv, name, nspan, args) => {
                let rv = self.eval(recv, env)?;
                // A record's own callable field wins: `r.f(x)` calls `r.f`.
                if let Value::Record(r) = &rv
                    && let Some(fv) = r.get(name)
                    && fv.is_callable()
                {
                    let fv = fv.clone();
                    let (pos, named) = self.eval_args(args, env)?;
                    return self.call_with(&fv, *nspan, e.span, pos, named);
                }
                let fv = self.lookup(name, env).ok_or_else(|| {
                    let mut err = self.unknown_name(name, *nspan, env, "function");
                    err.message = format!(
                        "unknown function `{name}` (called as a method on {})",
                        describe(&rv)
                    );
                    err
                })?;
                let (mut pos, named) = self.eval_args(args, env)?;
                pos.insert(
                    0,
                    ArgValue {
                        value: rv,
                        span: recv.span,
                        name: ident_name(recv),
                    },
                );
                self.call_with(&fv, *nspan, e.span, pos, named)
            }
            ExprKind::Field(recv, name, nspan) => {
                let rv = self.eval(recv, env)?;
                rv.field(name).ok_or_else(|| no_field(&rv, name, *nspan))
            }
            ExprKind::Index(recv, idx) => {
                let rv = self.eval(recv, env)?;
                let iv = self.eval(idx, env)?;
                index(&rv, &iv, recv.span, idx.span)
            }
        }
    }

    fn eval_args(&mut self, args: &[Arg], env: &Env) -> MxResult<(Vec<ArgValue>, NamedArgs)> {
        let mut pos = Vec::with_capacity(args.len());
        let mut named: Vec<(String, Span, ArgValue)> = Vec::new();
        for a in args {
            let value = self.eval(&a.value, env)?;
            let av = ArgValue {
                value,
                span: a.value.span,
                name: ident_name(&a.value),
            };
            match &a.name {
                Some((n, s)) => {
                    if named.iter().any(|(m, _, _)| m == n) {
                        return Err(MxError::new(
                            ErrorKind::Arity,
                            format!("argument `{n}` is given twice"),
                        )
                        .at(*s)
                        .label("again here")
                        .help("give each named argument once"));
                    }
                    named.push((n.clone(), *s, av))
                }
                None => pos.push(av),
            }
        }
        Ok((pos, named))
    }

    /// Call a function value with already evaluated positional arguments
    /// (for built-ins such as `map`, and for motion curves).
    pub fn call(&mut self, f: &Value, args: Vec<Value>, span: Span) -> MxResult<Value> {
        let pos = args
            .into_iter()
            .map(|value| ArgValue {
                value,
                span,
                name: None,
            })
            .collect();
        self.call_with(f, span, span, pos, Vec::new())
    }

    pub fn call_with(
        &mut self,
        f: &Value,
        fspan: Span,
        call_span: Span,
        pos: Vec<ArgValue>,
        named: NamedArgs,
    ) -> MxResult<Value> {
        match f {
            Value::Builtin(b) => {
                let mut args = Args::new(b.signature.clone(), call_span, pos, named);
                let Some(body) = b.body() else {
                    return Err(
                        MxError::host(format!("built-in `{}` has no Rust body", b.name))
                            .at(call_span),
                    );
                };
                let v = body(&mut args, self).map_err(|e| e.or_at(call_span))?;
                args.finish()?;
                Ok(v)
            }
            Value::Function(c) => self.call_closure(c, f, call_span, pos, named),
            other => Err(
                MxError::type_error(format!("{} is not a function", describe(other)))
                    .at(fspan)
                    .label("cannot be called")
                    .help("only functions can be called: `fn f(x) = …` or built-ins like `sin(x)`"),
            ),
        }
    }

    fn call_closure(
        &mut self,
        c: &Arc<Closure>,
        fval: &Value,
        call_span: Span,
        pos: Vec<ArgValue>,
        named: NamedArgs,
    ) -> MxResult<Value> {
        let def = &c.def;
        let fname = def.name.as_deref().unwrap_or("<anonymous fn>");
        let sig = || {
            format!(
                "{}({})",
                def.name.as_deref().unwrap_or("fn"),
                def.params
                    .iter()
                    .map(|p| p.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        };
        if pos.len() > def.params.len() {
            let extra = &pos[def.params.len()];
            return Err(MxError::new(
                ErrorKind::Arity,
                format!(
                    "`{fname}` takes {} argument{}, got {}",
                    def.params.len(),
                    if def.params.len() == 1 { "" } else { "s" },
                    pos.len()
                ),
            )
            .at(extra.span)
            .label("unexpected argument")
            .help(format!("usage: {}", sig())));
        }
        for (n, s, _) in &named {
            if !def.params.iter().any(|p| &p.name == n) {
                let e = MxError::new(
                    ErrorKind::Arity,
                    format!("`{fname}` has no parameter named `{n}`"),
                )
                .at(*s)
                .label("unknown parameter");
                return Err(
                    match did_you_mean(n, def.params.iter().map(|p| p.name.as_str())) {
                        Some(m) => e.help(format!("did you mean `{m}`? usage: {}", sig())),
                        None => e.help(format!("usage: {}", sig())),
                    },
                );
            }
        }
        if self.depth >= self.ctx.limits.max_depth {
            return Err(MxError::new(ErrorKind::Recursion, format!("recursion too deep: more than {} nested calls", self.ctx.limits.max_depth))
                .at(call_span)
                .label(format!("call to `{fname}`"))
                .help("check that the recursion has a base case that is reached (e.g. `if n <= 0 { … } else { … }`)"));
        }
        let mut env = c.env.clone();
        if let Some(n) = &def.name {
            // Bind the function to its own name so it can recurse.
            env = env.bind(n.clone(), fval.clone());
        }
        let mut pos = pos.into_iter();
        for p in &def.params {
            let v = if let Some(i) = named.iter().position(|(n, _, _)| n == &p.name) {
                named[i].2.value.clone()
            } else if let Some(a) = pos.next() {
                a.value
            } else if let Some(d) = &p.default {
                self.eval(d, &env)?
            } else {
                return Err(MxError::new(
                    ErrorKind::Arity,
                    format!("`{fname}` is missing its argument `{}`", p.name),
                )
                .at(call_span)
                .label(format!("needs `{}`", p.name))
                .help(format!("usage: {}", sig())));
            };
            env = env.bind(p.name.clone(), v);
        }
        self.depth += 1;
        let r = self.eval(&def.body, &env);
        self.depth -= 1;
        r
    }

    fn binary(&mut self, op: BinOp, a: &Expr, b: &Expr, span: Span, env: &Env) -> MxResult<Value> {
        // Short-circuit logic.
        if matches!(op, BinOp::And | BinOp::Or) {
            let av = self.eval(a, env)?;
            let Value::Bool(x) = av else {
                return Err(logic_error(op, &av, a.span));
            };
            if (op == BinOp::And && !x) || (op == BinOp::Or && x) {
                return Ok(Value::Bool(x));
            }
            let bv = self.eval(b, env)?;
            return match bv {
                Value::Bool(y) => Ok(Value::Bool(y)),
                other => Err(logic_error(op, &other, b.span)),
            };
        }
        let av = self.eval(a, env)?;
        let bv = self.eval(b, env)?;
        binary_values(op, &av, &bv, a.span, b.span, span)
    }

    /// Confine `path` to the file root (if any): no absolute paths and no
    /// `..` escaping it. Without a root a relative path is taken from the
    /// running script's folder (else the current folder). Returns the path
    /// to use.
    pub fn resolve_path(&self, path: &str, span: Span) -> MxResult<PathBuf> {
        let p = Path::new(path);
        if path.is_empty() {
            return Err(MxError::new(ErrorKind::Io, "empty file name")
                .at(span)
                .help("give a file name such as \"out/walk.json\""));
        }
        let Some(root) = &self.ctx.file_root else {
            return Ok(match &self.ctx.script_dir {
                Some(dir) if p.is_relative() => dir.join(p),
                _ => p.to_path_buf(),
            });
        };
        let denied = || {
            MxError::new(
                ErrorKind::Io,
                format!("access to `{path}` is outside the allowed folder"),
            )
            .at(span)
            .label("outside the file root")
            .help(format!("use a relative path inside {}", root.display()))
        };
        let mut out = root.as_ref().clone();
        let mut depth = 0i32;
        for c in p.components() {
            match c {
                Component::Normal(x) => {
                    out.push(x);
                    depth += 1;
                }
                Component::CurDir => {}
                Component::ParentDir => {
                    depth -= 1;
                    if depth < 0 {
                        return Err(denied());
                    }
                    out.pop();
                }
                Component::RootDir | Component::Prefix(_) => return Err(denied()),
            }
        }
        // A symlink inside the root could still point out of it.
        if let (Ok(real_root), Some(parent)) = (root.canonicalize(), out.parent())
            && let Ok(real_parent) = parent.canonicalize()
            && !real_parent.starts_with(&real_root)
        {
            return Err(denied());
        }
        Ok(out)
    }

    /// Write one line to the output (`print`).
    pub fn write_line(&self, line: &str, span: Span) -> MxResult<()> {
        let mut out = self.ctx.out.lock().unwrap_or_else(|p| p.into_inner());
        writeln!(out, "{line}")
            .and_then(|_| out.flush())
            .map_err(|e| MxError::new(ErrorKind::Io, format!("cannot write output: {e}")).at(span))
    }
}

/// The name a top-level statement defines (`let`, `fn`, `import`).
pub fn defined_name(s: &Stmt) -> Option<&str> {
    match s {
        Stmt::Let(n, ..) => Some(n),
        Stmt::Fn(def) => def.name.as_deref(),
        Stmt::Import(i) => Some(&i.name),
        Stmt::Expr(_) => None,
    }
}

/// A script's file name for messages (`walks.mx`).
fn script_name(p: &Path) -> String {
    p.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| p.display().to_string())
}

fn ident_name(e: &Expr) -> Option<Arc<str>> {
    match &e.kind {
        ExprKind::Ident(n) => Some(Arc::from(n.as_str())),
        _ => None,
    }
}

fn logic_error(op: BinOp, v: &Value, span: Span) -> MxError {
    MxError::type_error(format!(
        "`{}` needs bools, found {}",
        op.symbol(),
        describe(v)
    ))
    .at(span)
    .label("not a bool")
    .help("combine comparisons, e.g. `x > 0 && x < 1`")
}

fn index(rv: &Value, iv: &Value, rspan: Span, ispan: Span) -> MxResult<Value> {
    match (rv, iv) {
        (Value::List(l), Value::Number(i)) => {
            let Some(j) = whole_index(*i, l.len()) else {
                return Err(MxError::value(format!(
                    "index {} is out of range for a list of {} item{}",
                    super::value::format_number(*i),
                    l.len(),
                    if l.len() == 1 { "" } else { "s" }
                ))
                .at(ispan)
                .label("out of range")
                .help("indices are whole numbers from 0 to len - 1 (or -1 for the last)"));
            };
            Ok(l[j].clone())
        }
        (Value::Str(text), Value::Number(i)) => {
            // by character, as `len` counts: "Hips"[0] is "H", "Hips"[-1] is "s"
            let n = text.chars().count();
            match whole_index(*i, n) {
                Some(j) => Ok(Value::str(
                    text.chars().nth(j).map(String::from).unwrap_or_default(),
                )),
                None => Err(MxError::value(format!(
                    "index {} is out of range for a string of {n} character{}",
                    super::value::format_number(*i),
                    if n == 1 { "" } else { "s" }
                ))
                .at(ispan)
                .label("out of range")
                .help("indices are whole numbers from 0 to len(s) - 1, or from -1 (the last) back to -len(s)")),
            }
        }
        (Value::Record(r), Value::Str(k)) => r.get(k.as_ref()).cloned().ok_or_else(|| {
            let e = MxError::value(format!(
                "this record has no field {}",
                super::value::quote(k)
            ))
            .at(ispan)
            .label("no such field");
            match did_you_mean(k, r.keys().map(String::as_str)) {
                Some(s) => e.help(format!("did you mean {}?", super::value::quote(&s))),
                None => e.help("`keys(r)` lists a record's fields"),
            }
        }),
        // a record-like value reads `v["name"]` as `v.name`
        (Value::Object(_), Value::Str(k)) if rv.keys().is_some() => {
            rv.field(k).ok_or_else(|| no_field(rv, k, ispan))
        }
        (Value::Str(_), other) => Err(MxError::type_error(format!(
            "a string index must be a number, found {}",
            describe(other)
        ))
        .at(ispan)
        .help("write `s[0]` for the first character; `s.split(\".\")` cuts a string into parts")),
        (Value::List(_), other) => Err(MxError::type_error(format!(
            "a list index must be a number, found {}",
            describe(other)
        ))
        .at(ispan)
        .help("write `xs[0]`")),
        (Value::Record(_), other) => Err(MxError::type_error(format!(
            "a record index must be a string, found {}",
            describe(other)
        ))
        .at(ispan)
        .help("write `r[\"name\"]` or `r.name`")),
        (other, _) => Err(
            MxError::type_error(format!("cannot index {}", describe(other)))
                .at(rspan)
                .help("only lists `xs[i]`, strings `s[i]` and records `r[\"key\"]` can be indexed"),
        ),
    }
}

/// Position `i` of `n` items as a whole number from the front (negative
/// counts from the back: -1 is the last); `None` when out of range or not whole.
fn whole_index(i: f64, n: usize) -> Option<usize> {
    let n = n as f64;
    let j = if i < 0.0 { n + i } else { i };
    (j.fract() == 0.0 && j >= 0.0 && j < n).then_some(j as usize)
}

/// Apply an infix operator to two values (also used by built-ins).
pub fn binary_values(
    op: BinOp,
    a: &Value,
    b: &Value,
    aspan: Span,
    bspan: Span,
    span: Span,
) -> MxResult<Value> {
    use Value::*;
    match (op, a, b) {
        (BinOp::Eq, _, _) => return Ok(Bool(a.equals(b))),
        (BinOp::Ne, _, _) => return Ok(Bool(!a.equals(b))),
        _ => {}
    }
    match (a, b) {
        (Number(x), Number(y)) => {
            let (x, y) = (*x, *y);
            return Ok(match op {
                BinOp::Add => Number(x + y),
                BinOp::Sub => Number(x - y),
                BinOp::Mul => Number(x * y),
                BinOp::Div | BinOp::Rem => {
                    if y == 0.0 {
                        return Err(MxError::new(ErrorKind::DivisionByZero, "division by zero")
                            .at(bspan)
                            .label("this is zero")
                            .help("guard the divisor, e.g. `if d != 0 { x / d } else { 0 }`"));
                    }
                    if op == BinOp::Div {
                        Number(x / y)
                    } else {
                        Number(x % y)
                    }
                }
                BinOp::Lt => Bool(x < y),
                BinOp::Le => Bool(x <= y),
                BinOp::Gt => Bool(x > y),
                BinOp::Ge => Bool(x >= y),
                BinOp::Meet => {
                    return Err(MxError::type_error(
                        "`&` (∧) is the intersection of motions, not defined on numbers",
                    )
                    .at(span)
                    .help("for logical and write `&&`; for numbers use `min`/`max`"));
                }
                _ => unreachable_op(op, span)?,
            });
        }
        (Str(x), Str(y)) => match op {
            BinOp::Add => return Ok(Value::str(format!("{x}{y}"))),
            BinOp::Lt => return Ok(Bool(x < y)),
            BinOp::Le => return Ok(Bool(x <= y)),
            BinOp::Gt => return Ok(Bool(x > y)),
            BinOp::Ge => return Ok(Bool(x >= y)),
            _ => {}
        },
        (List(x), List(y)) if op == BinOp::Add => {
            let mut v = Vec::with_capacity(x.len() + y.len());
            v.extend(x.iter().cloned());
            v.extend(y.iter().cloned());
            return Ok(Value::list(v));
        }
        _ => {}
    }
    // Host objects (motions…) define their own operators.
    let hosted = match (a, b) {
        (Object(o), _) => o.binary(op, b, true).or_else(|| {
            if let Object(p) = b {
                p.binary(op, a, false)
            } else {
                None
            }
        }),
        (_, Object(p)) => p.binary(op, a, false),
        _ => None,
    };
    match hosted {
        Some(Ok(v)) => Ok(v),
        Some(Err(msg)) => Err(MxError::new(ErrorKind::Motion, msg)
            .at(span)
            .label("in this operation")),
        None => Err(MxError::type_error(format!(
            "cannot apply `{}` to {} and {}",
            op.symbol(),
            describe(a),
            describe(b)
        ))
        .at(span)
        .label(format!(
            "{} {} {}",
            a.type_name(),
            op.symbol(),
            b.type_name()
        ))
        .help(op_help(op, a, b, aspan, bspan))),
    }
}

fn op_help(op: BinOp, a: &Value, b: &Value, _aspan: Span, _bspan: Span) -> String {
    match (op, a, b) {
        (BinOp::Add, Value::Str(_), _) | (BinOp::Add, _, Value::Str(_)) => {
            "to join text with a value write `\"text\" + str(x)`".into()
        }
        (BinOp::Add | BinOp::Sub | BinOp::Meet, _, _) => {
            "`+ - &` work on numbers (arithmetic) and on motions (union, difference, intersection); both sides must be the same kind".into()
        }
        (BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge, _, _) => "comparisons work on two numbers or two strings".into(),
        _ => "arithmetic works on numbers".into(),
    }
}

fn unreachable_op(op: BinOp, span: Span) -> MxResult<Value> {
    Err(MxError::type_error(format!("operator `{}` is not defined here", op.symbol())).at(span))
}
