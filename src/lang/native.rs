//! Registering functions and file formats written in Rust: the typed side
//! of [`Registry`]. The closures take their arguments from [`Args`] and may
//! call back into the [`Evaluator`]; they are stored type-erased (see
//! [`super::value::NativeBody`]) and the evaluator takes them back out.

use std::path::Path;
use std::sync::Arc;

use super::args::Args;
use super::diagnostics::MxResult;
use super::eval::{BuiltinFn, Evaluator, LoadFn, SaveFn};
use super::registry::Registry;
use super::value::Value;

impl Registry {
    /// Register a function. `signature` is e.g. `"save(x, path, rate: 30)"`;
    /// the name is the part before `(`.
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
        let body: Box<BuiltinFn> = Box::new(f);
        self.insert_function(name, signature, doc, Arc::new(body));
    }

    /// Let `load("x.<ext>")` read this format.
    pub fn loader<F>(&mut self, ext: &str, doc: &str, f: F)
    where
        F: Fn(&Path, &mut Args, &mut Evaluator) -> MxResult<Value> + Send + Sync + 'static,
    {
        let body: Box<LoadFn> = Box::new(f);
        self.format_entry(ext, doc).load = Some(Arc::new(body));
    }

    /// Let `save(x, "f.<ext>", …)` write this format.
    pub fn saver<F>(&mut self, ext: &str, doc: &str, f: F)
    where
        F: Fn(&Value, &Path, &mut Args, &mut Evaluator) -> MxResult<()> + Send + Sync + 'static,
    {
        let body: Box<SaveFn> = Box::new(f);
        self.format_entry(ext, doc).save = Some(Arc::new(body));
    }
}
