//! Runtime values. Everything is `Arc`-based and `Send + Sync`: a closure can
//! become a motion curve that rayon threads evaluate during optimisation.
//!
//! Domain values (motions, bodies, scenes…) are [`HostObject`]s, so a new
//! domain adds a type in its own builtins file without touching [`Value`].

use std::any::Any;
use std::fmt;
use std::sync::Arc;

use indexmap::IndexMap;

use super::ast::{BinOp, FnDef};
use super::env::Scope;
use super::signature::Signature;
use super::topic::Topic;

/// The environments mx closures keep and the evaluator extends.
pub type Env = Scope<Value>;

/// A value of a domain type defined outside the core language.
pub trait HostObject: Send + Sync + fmt::Debug + 'static {
    /// Name shown in type errors and by `:type` (e.g. `"Mu"`).
    fn type_name(&self) -> &'static str;
    /// One line, used by `print` and the REPL.
    fn summary(&self) -> String;
    /// For downcasting in built-ins: `obj.as_any().downcast_ref::<T>()`.
    fn as_any(&self) -> &dyn Any;
    /// An infix operator with this object on the left (`self_left`) or right
    /// of `other`. `None` means "not supported" (a type error is reported).
    fn binary(
        &self,
        _op: BinOp,
        _other: &Value,
        _self_left: bool,
    ) -> Option<Result<Value, String>> {
        None
    }
    /// A record-like value's fields: every name `obj.name` can read on this
    /// type, in the order `keys` lists them (empty: the value has no fields).
    /// Field access, `keys`, `has`, the missing-field help and Python's
    /// attributes all go through [`Value::field`] and [`Value::keys`], which
    /// read only these names, so they cannot disagree.
    fn field_names(&self) -> &'static [&'static str] {
        &[]
    }
    /// Reads one of [`HostObject::field_names`]; `None` when this value lacks
    /// it (a body not read from OpenSim has no `report`). Call it through
    /// [`Value::field`].
    fn read_field(&self, _name: &str) -> Option<Value> {
        None
    }
    /// Structural equality with another object (default: identity only).
    fn equals(&self, _other: &dyn HostObject) -> bool {
        false
    }
    /// Data that travels with this value without being part of it (a
    /// motion's provenance: its clip's skeleton, SP's report). Printing and
    /// equality ignore it; [`Value::attachment`] reads it.
    fn attachment(&self) -> Option<&(dyn Any + Send + Sync)> {
        None
    }
}

/// A user-defined function together with the environment it closes over.
#[derive(Debug)]
pub struct Closure {
    pub def: Arc<FnDef>,
    pub env: Env,
}

/// The Rust closure behind a built-in or a file format, type-erased. Its
/// calling convention (`Args`, `Evaluator`) is defined by the evaluator,
/// which is built on values: naming it here would make `value.rs` and
/// `eval.rs` import each other. `Registry::add` stores a `Box<BuiltinFn>`
/// and the evaluator takes it back out (`Builtin::body`, in `eval.rs`).
pub type NativeBody = Arc<dyn Any + Send + Sync>;

/// A function implemented in Rust, as a value (`map(xs, sin)`); made by
/// `Registry::add`.
pub struct Builtin {
    pub name: String,
    /// `name(a, b, rate: 30)`: what it takes, shown in `:help` and in
    /// arity/type errors, checked by `mx check` and by [`super::args::Args`].
    pub signature: Arc<Signature>,
    pub doc: String,
    /// The `:help` group it is listed in.
    pub topic: Topic,
    pub func: NativeBody,
}

impl fmt::Debug for Builtin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "<builtin {}>", self.name)
    }
}

#[derive(Clone, Debug, Default)]
pub enum Value {
    /// The value of statements that produce nothing (`print`, `let`).
    #[default]
    Nil,
    Number(f64),
    Bool(bool),
    Str(Arc<str>),
    List(Arc<Vec<Value>>),
    Record(Arc<IndexMap<String, Value>>),
    Function(Arc<Closure>),
    Builtin(Arc<Builtin>),
    Object(Arc<dyn HostObject>),
}

impl Value {
    pub fn str(s: impl AsRef<str>) -> Value {
        Value::Str(Arc::from(s.as_ref()))
    }
    pub fn list(v: Vec<Value>) -> Value {
        Value::List(Arc::new(v))
    }
    pub fn record(r: IndexMap<String, Value>) -> Value {
        Value::Record(Arc::new(r))
    }
    pub fn object(o: impl HostObject) -> Value {
        Value::Object(Arc::new(o))
    }

    /// The type name shown in diagnostics and by `:type`.
    pub fn type_name(&self) -> &'static str {
        match self {
            Value::Nil => "nil",
            Value::Number(_) => "number",
            Value::Bool(_) => "bool",
            Value::Str(_) => "string",
            Value::List(_) => "list",
            Value::Record(_) => "record",
            Value::Function(_) | Value::Builtin(_) => "function",
            Value::Object(o) => o.type_name(),
        }
    }

    pub fn as_number(&self) -> Option<f64> {
        match self {
            Value::Number(x) => Some(*x),
            _ => None,
        }
    }
    pub fn as_bool(&self) -> Option<bool> {
        match self {
            Value::Bool(b) => Some(*b),
            _ => None,
        }
    }
    pub fn as_str(&self) -> Option<&str> {
        match self {
            Value::Str(s) => Some(s),
            _ => None,
        }
    }
    pub fn as_list(&self) -> Option<&[Value]> {
        match self {
            Value::List(l) => Some(l),
            _ => None,
        }
    }
    pub fn as_record(&self) -> Option<&IndexMap<String, Value>> {
        match self {
            Value::Record(r) => Some(r),
            _ => None,
        }
    }
    /// Downcast a host object to a concrete type.
    pub fn as_object<T: 'static>(&self) -> Option<&T> {
        match self {
            Value::Object(o) => o.as_any().downcast_ref::<T>(),
            _ => None,
        }
    }
    /// The attachment of a host object, if it is a `T` (see [`HostObject::attachment`]).
    pub fn attachment<T: 'static>(&self) -> Option<&T> {
        match self {
            Value::Object(o) => o.attachment()?.downcast_ref::<T>(),
            _ => None,
        }
    }
    /// `v.name`: a record's field, or a field a record-like host value
    /// lists (see [`HostObject::field_names`]). `None`: no such field.
    pub fn field(&self, name: &str) -> Option<Value> {
        match self {
            Value::Record(r) => r.get(name).cloned(),
            Value::Object(o) if o.field_names().contains(&name) => o.read_field(name),
            _ => None,
        }
    }
    /// The field names of a record or of a record-like host value, in order
    /// (a host value's optional fields only where it has them); `None` for a
    /// value without fields.
    pub fn keys(&self) -> Option<Vec<String>> {
        match self {
            Value::Record(r) => Some(r.keys().cloned().collect()),
            Value::Object(o) if !o.field_names().is_empty() => Some(
                o.field_names()
                    .iter()
                    .filter(|n| o.read_field(n).is_some())
                    .map(|n| n.to_string())
                    .collect(),
            ),
            _ => None,
        }
    }
    pub fn is_callable(&self) -> bool {
        matches!(self, Value::Function(_) | Value::Builtin(_))
    }

    /// Structural equality (functions and objects by identity unless the
    /// object says otherwise).
    pub fn equals(&self, other: &Value) -> bool {
        match (self, other) {
            (Value::Nil, Value::Nil) => true,
            (Value::Number(a), Value::Number(b)) => a == b,
            (Value::Bool(a), Value::Bool(b)) => a == b,
            (Value::Str(a), Value::Str(b)) => a == b,
            (Value::List(a), Value::List(b)) => {
                a.len() == b.len() && a.iter().zip(b.iter()).all(|(x, y)| x.equals(y))
            }
            (Value::Record(a), Value::Record(b)) => {
                a.len() == b.len() && a.iter().all(|(k, v)| b.get(k).is_some_and(|w| v.equals(w)))
            }
            (Value::Function(a), Value::Function(b)) => Arc::ptr_eq(a, b),
            (Value::Builtin(a), Value::Builtin(b)) => a.name == b.name,
            (Value::Object(a), Value::Object(b)) => {
                std::ptr::addr_eq(Arc::as_ptr(a), Arc::as_ptr(b)) || a.equals(b.as_ref())
            }
            _ => false,
        }
    }
}

/// The shared number formatter (see [`crate::fmt_num`]).
pub use crate::fmt_num::format_number;

fn is_plain_key(k: &str) -> bool {
    let mut chars = k.chars();
    matches!(chars.next(), Some(c) if c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
        && !matches!(
            k,
            "let" | "fn" | "if" | "else" | "true" | "false" | "and" | "or" | "not"
        )
}

/// A string literal as mx would read it back.
pub fn quote(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            '\r' => out.push_str("\\r"),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

impl Value {
    /// The form `print` uses: strings bare at top level, quoted inside containers.
    pub fn display(&self) -> String {
        match self {
            Value::Str(s) => s.to_string(),
            other => other.repr(),
        }
    }

    /// The form the REPL echoes: strings quoted.
    pub fn repr(&self) -> String {
        let mut s = String::new();
        self.write_repr(&mut s, 0);
        s
    }

    fn write_repr(&self, out: &mut String, depth: usize) {
        use std::fmt::Write;
        if depth > 64 {
            out.push('…');
            return;
        }
        match self {
            Value::Nil => out.push_str("nil"),
            Value::Number(x) => out.push_str(&format_number(*x)),
            Value::Bool(b) => out.push_str(if *b { "true" } else { "false" }),
            Value::Str(s) => out.push_str(&quote(s)),
            Value::List(l) => {
                out.push('[');
                for (i, v) in l.iter().enumerate() {
                    if i > 0 {
                        out.push_str(", ");
                    }
                    v.write_repr(out, depth + 1);
                }
                out.push(']');
            }
            Value::Record(r) => {
                out.push('{');
                for (i, (k, v)) in r.iter().enumerate() {
                    if i > 0 {
                        out.push_str(", ");
                    }
                    if is_plain_key(k) {
                        out.push_str(k);
                    } else {
                        out.push_str(&quote(k));
                    }
                    out.push_str(": ");
                    v.write_repr(out, depth + 1);
                }
                out.push('}');
            }
            Value::Function(c) => {
                let params: Vec<&str> = c.def.params.iter().map(|p| p.name.as_str()).collect();
                let _ = write!(
                    out,
                    "<fn {}({})>",
                    c.def.name.as_deref().unwrap_or(""),
                    params.join(", ")
                );
            }
            Value::Builtin(b) => {
                let _ = write!(out, "<builtin {}>", b.name);
            }
            Value::Object(o) => out.push_str(&o.summary()),
        }
    }
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.display())
    }
}

impl From<f64> for Value {
    fn from(x: f64) -> Self {
        Value::Number(x)
    }
}
impl From<bool> for Value {
    fn from(b: bool) -> Self {
        Value::Bool(b)
    }
}
impl From<&str> for Value {
    fn from(s: &str) -> Self {
        Value::str(s)
    }
}
impl From<String> for Value {
    fn from(s: String) -> Self {
        Value::str(s)
    }
}
impl From<Vec<Value>> for Value {
    fn from(v: Vec<Value>) -> Self {
        Value::list(v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_are_send_and_sync() {
        fn check<T: Send + Sync>() {}
        check::<Value>();
    }
}
