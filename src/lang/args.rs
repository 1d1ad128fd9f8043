//! The arguments of one built-in call ([`Args`]): taken by name — from a
//! named argument `x: …` if given, else the next positional one — with
//! missing, surplus and ill-typed arguments reported at the argument's span
//! and the signature as help. Getters for the host types (motions, bodies,
//! joints) are on `Args` too, in [`super::host::args`].

use std::marker::PhantomData;
use std::sync::Arc;

use indexmap::IndexMap;

use super::ast::Span;
use super::diagnostics::{ErrorKind, MxError, MxResult};
use super::signature::Signature;
use super::value::{HostObject, Value};

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
    signature: Arc<Signature>,
    call_span: Span,
    positional: Vec<ArgValue>,
    named: Vec<(String, Span, ArgValue, bool)>,
    cursor: usize,
    /// Positional arguments taken so far, by the parameter name they were
    /// taken as: an engine error naming a parameter points at its argument.
    taken: Vec<(String, Span)>,
    /// Parameters the built-in asked for that its signature does not list:
    /// a defect of the built-in, reported by [`Args::finish`].
    undeclared: Vec<String>,
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
        signature: Arc<Signature>,
        call_span: Span,
        positional: Vec<ArgValue>,
        named: Vec<(String, Span, ArgValue)>,
    ) -> Self {
        Args {
            signature,
            call_span,
            positional,
            named: named
                .into_iter()
                .map(|(n, s, v)| (n, s, v, false))
                .collect(),
            cursor: 0,
            taken: vec![],
            undeclared: vec![],
        }
    }

    /// The function's name (from its signature).
    pub fn name(&self) -> &str {
        self.signature.name()
    }
    pub fn call_span(&self) -> Span {
        self.call_span
    }
    pub fn signature(&self) -> &Signature {
        &self.signature
    }

    /// Note a parameter the signature does not list (see [`Args::finish`]).
    fn declare(&mut self, name: &str) {
        if !self.signature.accepts(name) && !self.undeclared.iter().any(|n| n == name) {
            self.undeclared.push(name.to_string());
        }
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
        self.declare(name);
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
            let arg = self.positional[self.cursor - 1].clone();
            self.taken.push((name.to_string(), arg.span));
            return Some(arg);
        }
        None
    }

    /// Where the caller wrote parameter `name`'s argument (named, or taken
    /// positionally as `name`), if they did.
    pub fn span_of(&self, name: &str) -> Option<Span> {
        self.named
            .iter()
            .find(|(n, ..)| n == name)
            .map(|(_, _, v, _)| v.span)
            .or_else(|| self.taken.iter().find(|(n, _)| n == name).map(|t| t.1))
    }

    /// Whether the call names `name` (`support: …`), without taking it.
    pub fn has_named(&self, name: &str) -> bool {
        self.named.iter().any(|(n, _, _, _)| n == name)
    }

    /// The named argument `name` only (never positional), e.g. `rate: 30`.
    pub fn opt_named(&mut self, name: &str) -> Option<ArgValue> {
        self.declare(name);
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
            // a misspelt named argument (`bdy:` for `body`) is the likely
            // cause: point at it rather than at the whole call
            let typo = self.named.iter().find(|(n, _, _, used)| {
                !used && super::diagnostics::did_you_mean(n, [name]).is_some()
            });
            if let Some((n, s, _, _)) = typo {
                return MxError::new(
                    ErrorKind::Arity,
                    format!("`{}` has no parameter named `{n}`", self.name()),
                )
                .at(*s)
                .label("unknown parameter")
                .help(format!("did you mean `{name}`? usage: {}", self.signature));
            }
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
                crate::fmt_num::format_number(x)
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
        if let Some(n) = self.undeclared.first() {
            return Err(MxError::host(format!(
                "built-in `{}` reads the parameter `{n}`, which its signature `{}` does not list",
                self.name(),
                self.signature
            ))
            .at(self.call_span)
            .help("a defect of mx: add the parameter to the signature, which `mx check`, the usage line and `:help` read"));
        }
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
            let known = self.signature.params();
            let mut e = MxError::new(
                ErrorKind::Arity,
                format!("`{}` has no parameter named `{n}`", self.name()),
            )
            .at(*s)
            .label("unknown parameter");
            e = match super::diagnostics::did_you_mean(n, known.iter().copied()) {
                Some(s) => e.help(format!("did you mean `{s}`? usage: {}", self.signature)),
                None => e.help(format!("usage: {}", self.signature)),
            };
            return Err(e);
        }
        Ok(())
    }
}

/// "a number (3)", "a string", "a Mu" — for type errors.
pub fn describe(v: &Value) -> String {
    match v {
        Value::Nil => "nil".into(),
        Value::Number(x) => format!("the number {}", crate::fmt_num::format_number(*x)),
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
