//! mx diagnostics as Python exceptions (`mx._errors`: `MxError` and its
//! subclasses, which also derive from the matching built-in exception).

use mx::lang::{Diagnostic, ErrorKind, Location};
use pyo3::prelude::*;

/// The exception for an mx diagnostic: the rendered text, the short message,
/// the kind and, when the error points into mx source, its place as data
/// (`Diagnostic::place`: file, line, column, their ends and the span).
pub fn raise_diag(py: Python<'_>, d: &Diagnostic) -> PyErr {
    let e = d.error();
    make(
        py,
        e.kind,
        &d.render_plain(),
        &e.message,
        d.place(),
        e.help.as_deref(),
    )
}

/// An error about arguments given from Python (no mx source to point at).
pub fn error(py: Python<'_>, kind: ErrorKind, message: impl AsRef<str>) -> PyErr {
    let m = message.as_ref();
    make(py, kind, m, m, None, None)
}

pub fn value_error(py: Python<'_>, message: impl AsRef<str>) -> PyErr {
    error(py, ErrorKind::Value, message)
}

pub fn type_error(py: Python<'_>, message: impl AsRef<str>) -> PyErr {
    error(py, ErrorKind::Type, message)
}

fn make(
    py: Python<'_>,
    kind: ErrorKind,
    diagnostic: &str,
    message: &str,
    place: Option<&Location>,
    help: Option<&str>,
) -> PyErr {
    let kind = kind.code().trim_start_matches("mx::");
    let at = place.map(|p| {
        (
            p.file.as_str(),
            p.line,
            p.column,
            p.end_line,
            p.end_column,
            p.span,
        )
    });
    let built = py.import("mx._errors").and_then(|m| {
        m.getattr("_make")?
            .call1((kind, diagnostic, message, at, help))
    });
    match built {
        Ok(exc) => PyErr::from_value(exc),
        Err(e) => e,
    }
}
