//! The mx language: grammar (`grammar/mx.pest`), parser to a spanned AST,
//! tree-walking evaluator over persistent environments, built-ins,
//! diagnostics (miette) and the embedding API [`Interpreter`].

pub mod args;
pub mod ast;
pub mod builtins;
pub mod busy;
pub mod completion;
pub mod diagnostics;
pub mod env;
pub mod eval;
pub mod fields;
pub mod help;
pub mod host;
pub mod interpreter;
pub mod native;
pub mod nesting;
pub mod parser;
pub mod registry;
pub mod resolve;
pub mod session;
pub mod signature;
pub mod timefn;
pub mod topic;
pub mod value;

pub use args::Args;
pub use diagnostics::{Diagnostic, ErrorKind, Location, MxError, MxResult};
pub use eval::{Context, Evaluator};
pub use interpreter::Interpreter;
pub use registry::Registry;
pub use signature::Signature;
pub use topic::Topic;
pub use value::{HostObject, Value};
