//! The built-in function framework.
//!
//! Each domain registers its functions in its own file (`core.rs`,
//! `motion.rs`, later `joints.rs`, `dynamics.rs`, `mocap.rs`, `spacetime.rs`)
//! with one line per function:
//!
//! ```
//! let mut reg = mx::lang::Registry::new();
//! reg.add("sin(x)", "Sine of x (radians).", |a, _| Ok(a.number("x")?.sin().into()));
//! ```
//!
//! The first argument is the signature shown by `:help` (the name is the part
//! before `(`). Inside, [`Args`] takes arguments by name — from a named
//! argument `x: …` if given, else the next positional one — and reports
//! missing, surplus and ill-typed arguments with the span of the argument and
//! the signature as help. Surplus arguments are reported automatically after
//! the function returns.
//!
//! `load(path)` and `save(x, path, …)` dispatch on the file extension through
//! [`Registry::loader`] / [`Registry::saver`], so a domain adds a format with
//! one line too.

pub mod body;
pub mod busy;
pub mod compose;
pub mod core;
pub mod dynamics;
pub mod joints;
pub mod links;
pub mod mechanics;
pub mod mocap;
pub mod motion;
pub mod opensim;
pub mod sp_report;
pub mod spacetime;
pub mod spline_joints;

use std::fmt;
use std::marker::PhantomData;
use std::path::Path;
use std::sync::Arc;

use indexmap::IndexMap;

use super::ast::Span;
use super::diagnostics::{ErrorKind, MxError, MxResult};
use super::eval::Evaluator;
use super::value::{HostObject, Value};

/// The body of a built-in function.
pub type BuiltinFn = dyn Fn(&mut Args, &mut Evaluator) -> MxResult<Value> + Send + Sync;
/// Reads a file into a value: `(path, remaining args, evaluator)`.
pub type LoadFn = dyn Fn(&Path, &mut Args, &mut Evaluator) -> MxResult<Value> + Send + Sync;
/// Writes a value to a file: `(value, path, remaining args, evaluator)`.
/// The path is already confined to the interpreter's file root.
pub type SaveFn = dyn Fn(&Value, &Path, &mut Args, &mut Evaluator) -> MxResult<()> + Send + Sync;

pub struct Builtin {
    pub name: String,
    /// `name(a, b, rate: 30)`: shown in `:help` and in arity/type errors.
    pub signature: Arc<str>,
    pub doc: String,
    pub func: Arc<BuiltinFn>,
}

impl fmt::Debug for Builtin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "<builtin {}>", self.name)
    }
}

/// A file format `load`/`save` knows, by extension (lower case, no dot).
#[derive(Clone)]
pub struct Format {
    pub ext: String,
    pub doc: String,
    pub load: Option<Arc<LoadFn>>,
    pub save: Option<Arc<SaveFn>>,
}

/// Everything built in: functions, constants and file formats.
#[derive(Clone, Default)]
pub struct Registry {
    functions: IndexMap<String, Arc<Builtin>>,
    constants: IndexMap<String, (Value, String)>,
    formats: IndexMap<String, Format>,
}

impl Registry {
    pub fn new() -> Self {
        Self::default()
    }

    /// The registry with every domain's built-ins.
    pub fn standard() -> Self {
        let mut r = Registry::new();
        core::register(&mut r);
        motion::register(&mut r);
        compose::register(&mut r);
        joints::register(&mut r);
        spline_joints::register(&mut r);
        links::register(&mut r);
        mechanics::register(&mut r);
        dynamics::register(&mut r);
        mocap::register(&mut r);
        opensim::register(&mut r);
        spacetime::register(&mut r);
        r
    }

    /// Register a function. `signature` is e.g. `"save(x, path, rate: 30)"`.
    pub fn add<F>(&mut self, signature: &str, doc: &str, f: F)
    where
        F: Fn(&mut Args, &mut Evaluator) -> MxResult<Value> + Send + Sync + 'static,
    {
        let name = signature
            .split('(')
            .next()
            .unwrap_or(signature)
            .trim()
            .to_string();
        let b = Builtin {
            name: name.clone(),
            signature: Arc::from(signature),
            doc: doc.to_string(),
            func: Arc::new(f),
        };
        self.functions.insert(name, Arc::new(b));
    }

    /// Register a named constant (e.g. `pi`).
    pub fn constant(&mut self, name: &str, doc: &str, value: Value) {
        self.constants
            .insert(name.to_string(), (value, doc.to_string()));
    }

    /// Let `load("x.<ext>")` read this format.
    pub fn loader<F>(&mut self, ext: &str, doc: &str, f: F)
    where
        F: Fn(&Path, &mut Args, &mut Evaluator) -> MxResult<Value> + Send + Sync + 'static,
    {
        let e = self.format_entry(ext, doc);
        e.load = Some(Arc::new(f));
    }

    /// Let `save(x, "f.<ext>", …)` write this format.
    pub fn saver<F>(&mut self, ext: &str, doc: &str, f: F)
    where
        F: Fn(&Value, &Path, &mut Args, &mut Evaluator) -> MxResult<()> + Send + Sync + 'static,
    {
        let e = self.format_entry(ext, doc);
        e.save = Some(Arc::new(f));
    }

    fn format_entry(&mut self, ext: &str, doc: &str) -> &mut Format {
        let ext = ext.trim_start_matches('.').to_ascii_lowercase();
        self.formats.entry(ext.clone()).or_insert_with(|| Format {
            ext,
            doc: doc.to_string(),
            load: None,
            save: None,
        })
    }

    pub fn format(&self, ext: &str) -> Option<&Format> {
        self.formats.get(&ext.to_ascii_lowercase())
    }
    pub fn formats(&self) -> impl Iterator<Item = &Format> {
        self.formats.values()
    }

    pub fn function(&self, name: &str) -> Option<&Arc<Builtin>> {
        self.functions.get(name)
    }
    /// A function or constant as a value.
    pub fn lookup(&self, name: &str) -> Option<Value> {
        if let Some((v, _)) = self.constants.get(name) {
            return Some(v.clone());
        }
        self.functions.get(name).map(|b| Value::Builtin(b.clone()))
    }
    /// Every built-in name (functions and constants), in registration order.
    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.constants
            .keys()
            .chain(self.functions.keys())
            .map(String::as_str)
    }
    pub fn functions(&self) -> impl Iterator<Item = &Arc<Builtin>> {
        self.functions.values()
    }
    /// `(signature, doc)` for `:help name`.
    pub fn help(&self, name: &str) -> Option<(String, String)> {
        if let Some(b) = self.functions.get(name) {
            return Some((b.signature.to_string(), b.doc.clone()));
        }
        self.constants
            .get(name)
            .map(|(v, d)| (format!("{name} = {}", v.repr()), d.clone()))
    }
}

/// One argument as the caller wrote it.
#[derive(Clone, Debug)]
pub struct ArgValue {
    pub value: Value,
    pub span: Span,
    /// The variable name when the argument was written as a bare name
    /// (`clip(2, 3, walk)`), so messages can say "walk's span".
    pub name: Option<Arc<str>>,
}

/// The arguments of one call, taken by the built-in in order.
pub struct Args {
    signature: Arc<str>,
    call_span: Span,
    positional: Vec<ArgValue>,
    named: Vec<(String, Span, ArgValue, bool)>,
    cursor: usize,
}

/// A typed handle to a host object argument (derefs to `T`).
pub struct ObjRef<T> {
    value: Value,
    _t: PhantomData<T>,
}

impl<T: HostObject> ObjRef<T> {
    pub fn value(&self) -> &Value {
        &self.value
    }
}

impl<T: HostObject> std::ops::Deref for ObjRef<T> {
    type Target = T;
    fn deref(&self) -> &T {
        // Checked when the ObjRef was made (Args::object).
        self.value
            .as_object::<T>()
            .expect("ObjRef holds a value of its type")
    }
}

impl Args {
    pub fn new(
        signature: impl Into<Arc<str>>,
        call_span: Span,
        positional: Vec<ArgValue>,
        named: Vec<(String, Span, ArgValue)>,
    ) -> Self {
        Args {
            signature: signature.into(),
            call_span,
            positional,
            named: named
                .into_iter()
                .map(|(n, s, v)| (n, s, v, false))
                .collect(),
            cursor: 0,
        }
    }

    /// The function's name (from its signature).
    pub fn name(&self) -> &str {
        self.signature.split('(').next().unwrap_or(&self.signature)
    }
    pub fn call_span(&self) -> Span {
        self.call_span
    }
    pub fn signature(&self) -> &str {
        &self.signature
    }
    /// Positional arguments not taken yet.
    pub fn remaining(&self) -> usize {
        self.positional.len().saturating_sub(self.cursor)
    }

    /// An error about this call as a whole, with the usage as help.
    pub fn error(&self, kind: ErrorKind, message: impl Into<String>) -> MxError {
        MxError::new(kind, message)
            .at(self.call_span)
            .help(format!("usage: {}", self.signature))
    }

    /// The argument `name` if given (named, else next positional), else `None`.
    pub fn opt(&mut self, name: &str) -> Option<ArgValue> {
        if let Some(entry) = self
            .named
            .iter_mut()
            .find(|(n, _, _, used)| n == name && !*used)
        {
            entry.3 = true;
            return Some(entry.2.clone());
        }
        if self.cursor < self.positional.len() {
            self.cursor += 1;
            return Some(self.positional[self.cursor - 1].clone());
        }
        None
    }

    /// The named argument `name` only (never positional), e.g. `rate: 30`.
    pub fn opt_named(&mut self, name: &str) -> Option<ArgValue> {
        let entry = self
            .named
            .iter_mut()
            .find(|(n, _, _, used)| n == name && !*used)?;
        entry.3 = true;
        Some(entry.2.clone())
    }

    /// A required argument of any type.
    pub fn arg(&mut self, name: &str) -> MxResult<ArgValue> {
        self.opt(name).ok_or_else(|| {
            MxError::new(
                ErrorKind::Arity,
                format!("`{}` is missing its argument `{name}`", self.name()),
            )
            .at(self.call_span)
            .label(format!("needs `{name}`"))
            .help(format!("usage: {}", self.signature))
        })
    }

    pub fn value(&mut self, name: &str) -> MxResult<Value> {
        Ok(self.arg(name)?.value)
    }

    /// The error for an argument of the wrong type.
    pub fn type_error(&self, name: &str, expected: &str, got: &ArgValue) -> MxError {
        MxError::new(
            ErrorKind::Type,
            format!(
                "`{}` expects `{name}` to be {expected}, found {}",
                self.name(),
                describe(&got.value)
            ),
        )
        .at(got.span)
        .label(format!("this is {}", describe(&got.value)))
        .help(format!("usage: {}", self.signature))
    }

    fn num_of(&self, name: &str, a: &ArgValue) -> MxResult<f64> {
        match a.value {
            Value::Number(x) => Ok(x),
            _ => Err(self.type_error(name, "a number", a)),
        }
    }

    pub fn number(&mut self, name: &str) -> MxResult<f64> {
        let a = self.arg(name)?;
        self.num_of(name, &a)
    }
    pub fn number_or(&mut self, name: &str, default: f64) -> MxResult<f64> {
        match self.opt(name) {
            Some(a) => self.num_of(name, &a),
            None => Ok(default),
        }
    }
    /// A named-only number with a default (`rate: 30`).
    pub fn named_number_or(&mut self, name: &str, default: f64) -> MxResult<f64> {
        match self.opt_named(name) {
            Some(a) => self.num_of(name, &a),
            None => Ok(default),
        }
    }
    /// A finite number (not NaN/∞), with `what` explaining the requirement.
    pub fn finite(&mut self, name: &str) -> MxResult<f64> {
        let a = self.arg(name)?;
        let x = self.num_of(name, &a)?;
        if x.is_finite() {
            Ok(x)
        } else {
            Err(MxError::value(format!(
                "`{}`: `{name}` must be finite, found {}",
                self.name(),
                super::value::format_number(x)
            ))
            .at(a.span)
            .help(format!("usage: {}", self.signature)))
        }
    }
    /// A whole number ≥ 0 (counts, indices).
    pub fn count(&mut self, name: &str) -> MxResult<usize> {
        let a = self.arg(name)?;
        let x = self.num_of(name, &a)?;
        if x >= 0.0 && x.fract() == 0.0 && x < 1e15 {
            Ok(x as usize)
        } else {
            Err(self.type_error(name, "a whole number ≥ 0", &a))
        }
    }
    /// An optional whole number ≥ 0 with a default.
    pub fn count_or(&mut self, name: &str, default: usize) -> MxResult<usize> {
        match self.opt(name) {
            None => Ok(default),
            Some(a) => match a.value {
                Value::Number(x) if x >= 0.0 && x.fract() == 0.0 && x < 1e15 => Ok(x as usize),
                _ => Err(self.type_error(name, "a whole number ≥ 0", &a)),
            },
        }
    }
    pub fn bool(&mut self, name: &str) -> MxResult<bool> {
        let a = self.arg(name)?;
        match a.value {
            Value::Bool(b) => Ok(b),
            _ => Err(self.type_error(name, "a bool", &a)),
        }
    }
    pub fn bool_or(&mut self, name: &str, default: bool) -> MxResult<bool> {
        match self.opt(name) {
            Some(a) => match a.value {
                Value::Bool(b) => Ok(b),
                _ => Err(self.type_error(name, "a bool", &a)),
            },
            None => Ok(default),
        }
    }
    pub fn string(&mut self, name: &str) -> MxResult<Arc<str>> {
        let a = self.arg(name)?;
        match &a.value {
            Value::Str(s) => Ok(s.clone()),
            _ => Err(self.type_error(name, "a string", &a)),
        }
    }
    pub fn list(&mut self, name: &str) -> MxResult<Arc<Vec<Value>>> {
        let a = self.arg(name)?;
        match &a.value {
            Value::List(l) => Ok(l.clone()),
            _ => Err(self.type_error(name, "a list", &a)),
        }
    }
    pub fn list_of_numbers(&mut self, name: &str) -> MxResult<Vec<f64>> {
        let a = self.arg(name)?;
        let Value::List(l) = &a.value else {
            return Err(self.type_error(name, "a list of numbers", &a));
        };
        l.iter()
            .enumerate()
            .map(|(i, v)| {
                v.as_number().ok_or_else(|| {
                    MxError::type_error(format!(
                        "`{}` expects `{name}` to be a list of numbers, but element {i} is {}",
                        self.name(),
                        describe(v)
                    ))
                    .at(a.span)
                    .help(format!("usage: {}", self.signature))
                })
            })
            .collect()
    }
    pub fn record(&mut self, name: &str) -> MxResult<Arc<IndexMap<String, Value>>> {
        let a = self.arg(name)?;
        match &a.value {
            Value::Record(r) => Ok(r.clone()),
            _ => Err(self.type_error(name, "a record `{name: value, …}`", &a)),
        }
    }
    /// A callable (user function or built-in).
    pub fn function(&mut self, name: &str) -> MxResult<Value> {
        let a = self.arg(name)?;
        if a.value.is_callable() {
            Ok(a.value)
        } else {
            Err(self.type_error(name, "a function", &a))
        }
    }
    /// A host object of type `T`; `what` names it in errors (e.g. "a motion").
    pub fn object<T: HostObject>(&mut self, name: &str, what: &str) -> MxResult<ObjRef<T>> {
        let a = self.arg(name)?;
        if a.value.as_object::<T>().is_some() {
            Ok(ObjRef {
                value: a.value,
                _t: PhantomData,
            })
        } else {
            Err(self.type_error(name, what, &a))
        }
    }
    /// Every positional argument not taken yet (variadic functions).
    pub fn rest(&mut self) -> Vec<ArgValue> {
        let out = self.positional[self.cursor.min(self.positional.len())..].to_vec();
        self.cursor = self.positional.len();
        out
    }
    /// Named arguments not taken yet, in call order (e.g. options passed on to a saver).
    pub fn rest_named(&mut self) -> Vec<(String, ArgValue)> {
        let mut out = Vec::new();
        for (n, _, v, used) in self.named.iter_mut() {
            if !*used {
                *used = true;
                out.push((n.clone(), v.clone()));
            }
        }
        out
    }

    /// Error on arguments the function did not take (called by the evaluator
    /// after the built-in returns).
    pub fn finish(&self) -> MxResult<()> {
        if let Some(extra) = self.positional.get(self.cursor) {
            let n = self.positional.len();
            return Err(MxError::new(
                ErrorKind::Arity,
                format!(
                    "`{}` takes {} positional argument{}, got {n}",
                    self.name(),
                    self.cursor,
                    if self.cursor == 1 { "" } else { "s" }
                ),
            )
            .at(extra.span)
            .label("unexpected argument")
            .help(format!("usage: {}", self.signature)));
        }
        if let Some((n, s, _, _)) = self.named.iter().find(|(_, _, _, used)| !used) {
            let known = param_names(&self.signature);
            let mut e = MxError::new(
                ErrorKind::Arity,
                format!("`{}` has no parameter named `{n}`", self.name()),
            )
            .at(*s)
            .label("unknown parameter");
            e = match super::diagnostics::did_you_mean(n, known.iter().map(String::as_str)) {
                Some(s) => e.help(format!("did you mean `{s}`? usage: {}", self.signature)),
                None => e.help(format!("usage: {}", self.signature)),
            };
            return Err(e);
        }
        Ok(())
    }
}

/// Parameter names mentioned in a signature `f(a, b, rate: 30)`.
fn param_names(sig: &str) -> Vec<String> {
    let inner = sig
        .split_once('(')
        .map(|(_, r)| r.trim_end_matches(')'))
        .unwrap_or("");
    inner
        .split(',')
        .map(|p| {
            p.trim()
                .trim_start_matches("...")
                .split([':', '=', ' '])
                .next()
                .unwrap_or("")
                .trim()
                .to_string()
        })
        .filter(|p| !p.is_empty())
        .collect()
}

/// "a number (3)", "a string", "a Mu" — for type errors.
pub fn describe(v: &Value) -> String {
    match v {
        Value::Nil => "nil".into(),
        Value::Number(x) => format!("the number {}", super::value::format_number(*x)),
        Value::Bool(b) => format!("the bool {b}"),
        Value::Str(s) => {
            let short: String = s.chars().take(24).collect();
            format!("the string {}", super::value::quote(&short))
        }
        Value::List(l) => format!(
            "a list of {} item{}",
            l.len(),
            if l.len() == 1 { "" } else { "s" }
        ),
        Value::Record(_) => "a record".into(),
        Value::Function(_) | Value::Builtin(_) => "a function".into(),
        Value::Object(o) => format!("a {}", o.type_name()),
    }
}
