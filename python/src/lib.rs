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

/// `ground_forces(motion, body, friction=0.8, points=None, floor="auto",
/// height=0.02)`: mx's `ground_forces` as NumPy arrays — a dict with `times`
/// [T], `points` (names), `forces` [T, P, 3] (N, world), `in_contact` [T, P],
/// `residual_force` [T, 3] (N), `residual_moment` [T, 3] (N·m about the
/// centre of mass), `percent_bw` [T], `com` [T, 3], `weight` (N), `floor` (m).
/// `ground_forces(path, animation=None)` (no body): the forces a glTF file
/// carries (saved with `forces:`), on the animation's frames from 0 s — the
/// same `times`, `points`, `forces`, `residual_force`, `residual_moment`,
/// `percent_bw`, and `up` (the saved body's, in the file's axes).
#[pyfunction]
#[pyo3(signature = (motion, body = None, friction = 0.8, points = None, floor = None, height = None, animation = None))]
#[allow(clippy::too_many_arguments)]
fn ground_forces(
    py: Python<'_>,
    motion: &Bound<'_, PyAny>,
    body: Option<&Bound<'_, PyBody>>,
    friction: f64,
    points: Option<Vec<String>>,
    floor: Option<&Bound<'_, PyAny>>,
    height: Option<f64>,
    animation: Option<&Bound<'_, PyAny>>,
) -> PyResult<Py<PyAny>> {
    use mx::ground::{Floor, GroundOptions};
    use numpy::{PyArray1, PyArrayMethods};
    let Some(body) = body else {
        return saved_forces(py, motion, animation);
    };
    let mu = motion.cast::<PyMotion>().ok().and_then(|m| {
        match m.get().value.as_object::<mx::lang::host::Motion>() {
            Some(mx::lang::host::Motion::Mu(m)) => Some(m.clone()),
            _ => None,
        }
    });
    let Some(m) = mu else {
        return Err(errors::type_error(
            py,
            "`motion` must be a motion unit (Mu), e.g. mx.load(\"walk.bvh\"), or a glTF file's path without a body",
        ));
    };
    let mut o = GroundOptions {
        points,
        ..GroundOptions::default()
    };
    if let Some(h) = height {
        o.height = h;
    }
    match floor {
        None => {}
        Some(f) if f.extract::<String>().is_ok_and(|s| s == "auto") => {}
        Some(f) => {
            o.floor = Floor::At(f.extract::<f64>().map_err(|_| {
                errors::type_error(py, "`floor` must be a height in metres or \"auto\"")
            })?)
        }
    }
    let model = body.get().model.clone();
    let g = py
        .detach(move || mx::ground::ground_forces(&m, &model, &o, friction))
        .map_err(|e| errors::value_error(py, e.to_string()))?;
    let d = series_dict(py, &g.series())?;
    let (t, p) = (g.times.len(), g.points.len());
    let contact: Vec<bool> = g.in_contact.iter().flatten().copied().collect();
    d.set_item(
        "in_contact",
        PyArray1::from_vec(py, contact).reshape([t, p])?,
    )?;
    d.set_item("com", PyArray1::from_vec(py, flat(&g.com)).reshape([t, 3])?)?;
    d.set_item("weight", g.weight)?;
    d.set_item("floor", g.floor)?;
    Ok(d.into_any().unbind())
}

/// The forces glTF file `path` carries for `animation` (a name or an index).
fn saved_forces(
    py: Python<'_>,
    path: &Bound<'_, PyAny>,
    animation: Option<&Bound<'_, PyAny>>,
) -> PyResult<Py<PyAny>> {
    use mx::io::gltf::Which;
    let Ok(path) = path.extract::<std::path::PathBuf>() else {
        return Err(errors::type_error(
            py,
            "without `body`, `motion` must be the path of a glTF file saved with `forces:`",
        ));
    };
    let which = match animation {
        None => Which::First,
        Some(a) => match (a.extract::<usize>(), a.extract::<String>()) {
            (Ok(k), _) => Which::Index(k),
            (_, Ok(n)) => Which::Name(n),
            _ => {
                return Err(errors::type_error(
                    py,
                    "`animation` must be an animation's name or its index (0 first)",
                ));
            }
        },
    };
    let saved = py
        .detach(move || mx::io::gltf::load_forces(&path, which))
        .map_err(|e| errors::error(py, mx::lang::ErrorKind::Io, e.to_string()))?;
    let d = series_dict(py, &saved.series)?;
    if let Some(u) = saved.up {
        d.set_item("up", numpy::PyArray1::from_vec(py, vec![u.x, u.y, u.z]))?;
    }
    d.set_item("animation", saved.animation)?;
    Ok(d.into_any().unbind())
}

/// Rows of 3-vectors, flattened row by row.
fn flat(rows: &[nalgebra::Vector3<f64>]) -> Vec<f64> {
    rows.iter().flat_map(|v| [v.x, v.y, v.z]).collect()
}

/// The arrays both forms of `ground_forces` give: `times`, `points`,
/// `forces` [T, P, 3], `residual_force`, `residual_moment` [T, 3], `percent_bw`.
fn series_dict<'py>(
    py: Python<'py>,
    g: &mx::ground::ForceSeries,
) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
    use numpy::{PyArray1, PyArrayMethods};
    let (t, p) = (g.times.len(), g.points.len());
    let forces: Vec<f64> = g.forces.iter().flat_map(|fr| flat(fr)).collect();
    let d = pyo3::types::PyDict::new(py);
    d.set_item("times", PyArray1::from_vec(py, g.times.clone()))?;
    d.set_item("points", g.points.clone())?;
    d.set_item("forces", PyArray1::from_vec(py, forces).reshape([t, p, 3])?)?;
    d.set_item(
        "residual_force",
        PyArray1::from_vec(py, flat(&g.residual_force)).reshape([t, 3])?,
    )?;
    d.set_item(
        "residual_moment",
        PyArray1::from_vec(py, flat(&g.residual_moment)).reshape([t, 3])?,
    )?;
    d.set_item("percent_bw", PyArray1::from_vec(py, g.percent_bw.clone()))?;
    Ok(d)
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
    m.add_function(wrap_pyfunction!(ground_forces, m)?)?;
    m.add_function(wrap_pyfunction!(_doc, m)?)?;
    m.add_function(wrap_pyfunction!(_builtins, m)?)?;
    Ok(())
}
