//! [`Registry`]: every built-in function, constant and file format of an
//! interpreter, with the doc strings `:help` and `docs/reference.md` show.
//!
//! ```
//! let mut reg = mx::lang::Registry::new();
//! reg.add("sin(x)", "Sine of x (radians).", |a, _| Ok(a.number("x")?.sin().into()));
//! ```
//!
//! The first argument is the signature shown by `:help` (the name is the part
//! before `(`); the closure takes its arguments from `Args`. The typed
//! registration methods (`add`, `loader`, `saver`) are in `native.rs`, with
//! the calling convention they need; this file only stores and looks up. Surplus
//! arguments are reported automatically after the function returns.
//! `load(path)` and `save(x, path, …)` dispatch on the file extension through
//! `Registry::loader` / `Registry::saver`, so a domain adds a format with
//! one line too. Each function belongs to the [`Topic`] current when it was
//! added ([`Registry::topic`]), which groups `:help`.

use std::sync::Arc;

use indexmap::IndexMap;

use super::signature::Signature;
use super::topic::Topic;
pub use super::value::Builtin;
use super::value::{NativeBody, Value};

/// A file format `load`/`save` knows, by extension (lower case, no dot).
/// Its reader and writer are stored type-erased (see [`NativeBody`]); the
/// evaluator's `Format::reader` / `Format::writer` give them back typed.
#[derive(Clone)]
pub struct Format {
    pub ext: String,
    pub doc: String,
    pub load: Option<NativeBody>,
    pub save: Option<NativeBody>,
}

/// Everything built in: functions, constants and file formats.
#[derive(Clone, Default)]
pub struct Registry {
    functions: IndexMap<String, Arc<Builtin>>,
    constants: IndexMap<String, (Value, String)>,
    formats: IndexMap<String, Format>,
    /// The topic functions added now are listed under.
    current: Topic,
}

impl Registry {
    pub fn new() -> Self {
        Self::default()
    }

    /// List the functions added from now on under `topic` in `:help`.
    pub fn topic(&mut self, topic: Topic) -> &mut Self {
        self.current = topic;
        self
    }

    /// Register a built-in made by `Registry::add` (`native.rs`).
    pub(crate) fn insert_function(
        &mut self,
        name: String,
        signature: &str,
        doc: &str,
        func: NativeBody,
    ) {
        let b = Builtin {
            name: name.clone(),
            signature: Arc::new(Signature::parse(signature)),
            doc: doc.to_string(),
            topic: self.current,
            func,
        };
        self.functions.insert(name, Arc::new(b));
    }

    /// Register a named constant (e.g. `pi`).
    pub fn constant(&mut self, name: &str, doc: &str, value: Value) {
        self.constants
            .insert(name.to_string(), (value, doc.to_string()));
    }

    pub(crate) fn format_entry(&mut self, ext: &str, doc: &str) -> &mut Format {
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
    /// `(name, value, doc)` of every constant, in registration order.
    pub fn constants(&self) -> impl Iterator<Item = (&str, &Value, &str)> {
        self.constants
            .iter()
            .map(|(n, (v, d))| (n.as_str(), v, d.as_str()))
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
