//! mx diagnostics as Python exceptions (`mx._errors`: `MxError` and its
//! subclasses, which also derive from the matching built-in exception).

use mx::lang::{Diagnostic, ErrorKind};
use pyo3::prelude::*;

/// The exception for an mx diagnostic: the rendered text, the short message,
/// the kind and, when the error points into mx source, file, line and column.
pub fn raise_diag(py: Python<'_>, d: &Diagnostic) -> PyErr {
    let e = d.error();
    let (file, line, col) = d
        .location()
        .map(parse_location)
        .unwrap_or((None, None, None));
    make(
        py,
        e.kind,
        &d.render_plain(),
        &e.message,
        file,
        line,
        col,
        e.help.as_deref(),
    )
}

/// An error about arguments given from Python (no mx source to point at).
pub fn error(py: Python<'_>, kind: ErrorKind, message: impl AsRef<str>) -> PyErr {
    let m = message.as_ref();
    make(py, kind, m, m, None, None, None, None)
}

pub fn value_error(py: Python<'_>, message: impl AsRef<str>) -> PyErr {
    error(py, ErrorKind::Value, message)
}

pub fn type_error(py: Python<'_>, message: impl AsRef<str>) -> PyErr {
    error(py, ErrorKind::Type, message)
}

#[allow(clippy::too_many_arguments)]
fn make(
    py: Python<'_>,
    kind: ErrorKind,
    diagnostic: &str,
    message: &str,
    file: Option<String>,
    line: Option<usize>,
    col: Option<usize>,
    help: Option<&str>,
) -> PyErr {
    let kind = kind.code().trim_start_matches("mx::");
    let built = py.import("mx._errors").and_then(|m| {
        m.getattr("_make")?
            .call1((kind, diagnostic, message, file, line, col, help))
    });
    match built {
        Ok(exc) => PyErr::from_value(exc),
        Err(e) => e,
    }
}

/// `name:line:col`, maybe followed by ` (line too long to show)`; the name may
/// itself contain colons.
fn parse_location(loc: &str) -> (Option<String>, Option<usize>, Option<usize>) {
    let loc = loc.split(" (").next().unwrap_or(loc);
    let mut parts = loc.rsplitn(3, ':');
    let col = parts.next().and_then(|c| c.parse().ok());
    let line = parts.next().and_then(|l| l.parse().ok());
    match (parts.next(), line, col) {
        (Some(f), Some(l), Some(c)) => (Some(f.to_string()), Some(l), Some(c)),
        _ => (Some(loc.to_string()), None, None),
    }
}
