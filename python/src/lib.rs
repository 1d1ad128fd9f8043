//! `mx._mx`: the Python extension module of mx (PyO3, abi3). The Python
//! package `mx/` around it re-exports these classes and adds the exception
//! hierarchy (`mx/_errors.py`), pandas/tqdm glue and the type stubs.
//!
//! Everything the language can do is reached through its built-ins, called
//! with Python values converted to mx values (`convert.rs`), so Python and mx
//! share behaviour and error messages. Array work (sampling, batched
//! dynamics) goes straight to the library with the GIL released.

// Layered bottom up as ARCHITECTURE.md's Python table lists them (errors,
// runtime, arrays and html, objects, convert, then the classes, then this
// module); tests/it/layers.rs checks that each file imports only lower ones.
mod arrays;
mod body;
mod convert;
mod errors;
mod function;
mod html;
mod interp;
mod motion;
mod objects;
mod runtime;

use pyo3::prelude::*;

use crate::convert::{kwargs, to_py};
use crate::errors::raise_diag;
use crate::interp::PyInterpreter;
use crate::objects::{PyBody, PyFunction, PyMotion, PyObject_};
use crate::runtime::{Builtins, cancellable, cancellable_ticking};

/// `load(path, **options)`: a motion, a body or another value from a file,
/// by its extension (`.bvh`, `.csv`, `.json`, `.urdf`, …).
#[pyfunction]
#[pyo3(signature = (path, **options))]
fn load(
    py: Python<'_>,
    path: std::path::PathBuf,
    options: Option<&Bound<'_, pyo3::types::PyDict>>,
) -> PyResult<Py<PyAny>> {
    let named = kwargs(options)?;
    let p = mx::Value::str(path.to_string_lossy());
    let v = cancellable(py, None, || Builtins::get().call("load", vec![p], named))?;
    let v = v.map_err(|e| raise_diag(py, &e))?;
    to_py(py, &v)
}

/// A body made from a clip by the mx built-in `name(clip, mass: …)`.
fn body_from_clip(
    py: Python<'_>,
    name: &str,
    motion: &Bound<'_, PyMotion>,
    mass: Option<f64>,
) -> PyResult<Py<PyAny>> {
    let pos = vec![motion.get().value.clone()];
    // no `mass`: the built-in's default (70 kg, or the total a glTF file states)
    let named = mass
        .map(|m| vec![("mass".into(), m.into())])
        .unwrap_or_default();
    let v = Builtins::get()
        .call(name, pos, named)
        .map_err(|e| raise_diag(py, &e))?;
    to_py(py, &v)
}

/// `body_of(motion, mass=None)`: a body whose coordinates are exactly a clip's
/// DOFs, with de Leva segments scaled by its bone lengths (70 kg by default),
/// or the body a glTF file mx wrote carries.
#[pyfunction]
#[pyo3(signature = (motion, mass = None))]
fn body_of(py: Python<'_>, motion: &Bound<'_, PyMotion>, mass: Option<f64>) -> PyResult<Py<PyAny>> {
    body_from_clip(py, "body_of", motion, mass)
}

/// `human(motion, mass=70)`: the 44-DOF anatomical model sized from a clip.
#[pyfunction]
#[pyo3(signature = (motion, mass = 70.0))]
fn human(py: Python<'_>, motion: &Bound<'_, PyMotion>, mass: f64) -> PyResult<Py<PyAny>> {
    body_from_clip(py, "human", motion, Some(mass))
}

/// `_sp(motion, body, options, on_tick)`: SP with the options of mx's `SP`,
/// returning `(filled motion, report dict)`. Ctrl-C cancels the solve and
/// raises KeyboardInterrupt. `on_tick(seconds)` is called about ten times a
/// second while it runs (the Python wrapper drives a tqdm bar with it).
#[pyfunction]
#[pyo3(signature = (motion, body, options = None, on_tick = None))]
fn _sp(
    py: Python<'_>,
    motion: &Bound<'_, PyMotion>,
    body: &Bound<'_, PyBody>,
    options: Option<&Bound<'_, pyo3::types::PyDict>>,
    on_tick: Option<Py<PyAny>>,
) -> PyResult<(Py<PyAny>, Py<PyAny>)> {
    let mut named = kwargs(options)?;
    named.insert(0, ("body".into(), body.get().value.clone()));
    let m = motion.get().value.clone();
    let b = Builtins::get();
    let cancel = mx::cancel::CancelToken::new();
    let ctx = b.context_with(cancel.clone());
    let r = cancellable_ticking(py, Some(&cancel), on_tick.as_ref(), || {
        let filled = Builtins::call_in(&ctx, "SP", vec![m], named)?;
        let report = Builtins::call_in(&ctx, "sp_report", vec![filled.clone()], vec![])?;
        Ok::<_, mx::lang::Diagnostic>((filled, report))
    })?;
    let (filled, report) = r.map_err(|e| raise_diag(py, &e))?;
    // The report reads like a record in mx; in Python it is a plain dict with
    // every field of the report's own list, so a field mx adds reaches Python.
    let dict = pyo3::types::PyDict::new(py);
    for key in report.keys().unwrap_or_default() {
        if let Some(v) = report.field(&key) {
            dict.set_item(&key, to_py(py, &v)?)?;
        }
    }
    Ok((to_py(py, &filled)?, dict.into_any().unbind()))
}

/// The doc string of a built-in (what `:help NAME` shows), for the Python
/// wrappers' docstrings.
#[pyfunction]
fn _doc(name: &str) -> Option<String> {
    Builtins::get()
        .help(name)
        .map(|(sig, doc)| format!("{sig}\n\n{doc}"))
}

/// Every built-in and prelude name with its signature and doc.
#[pyfunction]
fn _builtins() -> Vec<(String, String, String)> {
    Builtins::get().all_help()
}

#[pymodule]
fn _mx(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyInterpreter>()?;
    m.add_class::<PyMotion>()?;
    m.add_class::<PyBody>()?;
    m.add_class::<PyFunction>()?;
    m.add_class::<PyObject_>()?;
    m.add_function(wrap_pyfunction!(load, m)?)?;
    m.add_function(wrap_pyfunction!(body_of, m)?)?;
    m.add_function(wrap_pyfunction!(human, m)?)?;
    m.add_function(wrap_pyfunction!(_sp, m)?)?;
    m.add_function(wrap_pyfunction!(_doc, m)?)?;
    m.add_function(wrap_pyfunction!(_builtins, m)?)?;
    Ok(())
}
