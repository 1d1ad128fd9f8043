//! Engine errors as diagnostics, with advice by kind: shared by every
//! built-in file that calls the engine part they come from.

use crate::dynamics::DynamicsError;
use crate::lang::args::Args;
use crate::lang::ast::Span;
use crate::lang::diagnostics::{ErrorKind, MxError};
use crate::motion::MotionError;

/// A motion error as a diagnostic at `span`, with advice by kind.
pub fn motion_error(e: MotionError, span: Span) -> MxError {
    let help = match &e {
        MotionError::ClipOutside { .. } => "clip a window inside the span; `span(m)` gives it",
        MotionError::Conflict { .. } => {
            "a DOF defined twice there must be resolved first, e.g. `a + (b - a)` or `clip`"
        }
        MotionError::Undefined { .. } => {
            "sample only where the motion is defined; `gaps(m)` lists the holes"
        }
        MotionError::UnknownDof { .. } | MotionError::NoMatch { .. } => {
            "`dofs(m)` lists the DOF names"
        }
        MotionError::Cancelled => "cancelled by the user",
        _ => "see `:help` for the motion functions",
    };
    let kind = if matches!(e, MotionError::Cancelled) {
        ErrorKind::Cancelled
    } else {
        ErrorKind::Motion
    };
    MxError::new(kind, e.to_string())
        .at(span)
        .label("in this call")
        .help(help)
}
/// A file error at `span` (a motion error inside it keeps its advice).
pub fn file_error(e: crate::io::FileError, span: Span) -> MxError {
    match e {
        crate::io::FileError::Motion(m) => motion_error(m, span),
        other => MxError::new(ErrorKind::Io, other.to_string())
            .at(span)
            .help("check the path, the folder's permissions and the file's content"),
    }
}

/// A dynamics error on the call `a`.
pub fn dyn_error(e: DynamicsError, a: &Args) -> MxError {
    let kind = match e {
        DynamicsError::Cancelled => ErrorKind::Cancelled,
        DynamicsError::Input(_) => ErrorKind::Value,
        DynamicsError::Singular(_) => ErrorKind::Host,
    };
    MxError::new(kind, e.to_string())
        .at(a.call_span())
        .help(format!("usage: {}", a.signature()))
}
