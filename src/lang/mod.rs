//! The mx language: grammar (`grammar/mx.pest`), parser to a spanned AST,
//! tree-walking evaluator over persistent environments, built-ins,
//! diagnostics (miette) and the embedding API [`Interpreter`].

pub mod ast;
pub mod builtins;
pub mod diagnostics;
pub mod env;
pub mod eval;
pub mod interpreter;
pub mod nesting;
pub mod parser;
pub mod resolve;
pub mod timefn;
pub mod value;

pub use builtins::{Args, Registry};
pub use diagnostics::{Diagnostic, ErrorKind, MxError, MxResult};
pub use eval::{Context, Evaluator};
pub use interpreter::Interpreter;
pub use value::{HostObject, Value};
