//! Values both ways: numbers, strings, bools, lists and dicts as themselves;
//! motions, bodies, functions and other host objects as the Python objects
//! of `objects.rs`; keyword arguments as named mx arguments.

use mx::cancel::CancelToken;
use mx::lang::builtins::body::Body;
use mx::lang::builtins::motion::Motion;
use mx::lang::{Context, Value};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

use crate::arrays::real_dtype;
use crate::errors::type_error;
use crate::objects::{PyBody, PyFunction, PyMotion, PyObject_};
use crate::runtime::Builtins;

/// Keyword arguments as named mx arguments.
pub fn kwargs(options: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<(String, Value)>> {
    let mut out = Vec::new();
    if let Some(d) = options {
        for (k, v) in d.iter() {
            out.push((k.extract::<String>()?, from_py(&v)?));
        }
    }
    Ok(out)
}

/// An mx value as a Python object (functions call back into the shared built-ins).
pub fn to_py(py: Python<'_>, v: &Value) -> PyResult<Py<PyAny>> {
    to_py_in(py, v, None)
}

/// An mx value as a Python object; functions keep `ctx` (their interpreter's
/// registry, limits and file root) to be called from Python.
pub fn to_py_in(py: Python<'_>, v: &Value, ctx: Option<&Context>) -> PyResult<Py<PyAny>> {
    let to_py = |py, x| to_py_in(py, x, ctx);
    Ok(match v {
        Value::Nil => py.None(),
        Value::Number(x) => PyFloat::new(py, *x).into_any().unbind(),
        Value::Bool(b) => PyBool::new(py, *b).to_owned().into_any().unbind(),
        Value::Str(s) => PyString::new(py, s).into_any().unbind(),
        Value::List(l) => {
            let out = PyList::empty(py);
            for x in l.iter() {
                out.append(to_py(py, x)?)?;
            }
            out.into_any().unbind()
        }
        Value::Record(r) => {
            let out = PyDict::new(py);
            for (k, x) in r.iter() {
                out.set_item(k, to_py(py, x)?)?;
            }
            out.into_any().unbind()
        }
        Value::Function(_) | Value::Builtin(_) => Py::new(
            py,
            PyFunction {
                value: v.clone(),
                ctx: ctx
                    .cloned()
                    .unwrap_or_else(|| Builtins::get().context_with(CancelToken::new())),
            },
        )?
        .into_any(),
        Value::Object(_) if v.as_object::<Motion>().is_some() => {
            Py::new(py, PyMotion { value: v.clone() })?.into_any()
        }
        Value::Object(_) if v.as_object::<Body>().is_some() => {
            Py::new(py, PyBody::new(v.clone()))?.into_any()
        }
        Value::Object(_) => Py::new(py, PyObject_ { value: v.clone() })?.into_any(),
    })
}

/// A Python object as an mx value.
pub fn from_py(obj: &Bound<'_, PyAny>) -> PyResult<Value> {
    let py = obj.py();
    if obj.is_none() {
        return Ok(Value::Nil);
    }
    if let Ok(b) = obj.cast::<PyBool>() {
        return Ok(Value::Bool(b.is_true()));
    }
    if let Ok(m) = obj.cast::<PyMotion>() {
        return Ok(m.get().value.clone());
    }
    if let Ok(b) = obj.cast::<PyBody>() {
        return Ok(b.get().value.clone());
    }
    if let Ok(f) = obj.cast::<PyFunction>() {
        return Ok(f.get().value.clone());
    }
    if let Ok(o) = obj.cast::<PyObject_>() {
        return Ok(o.get().value.clone());
    }
    if let Ok(s) = obj.cast::<PyString>() {
        return Ok(Value::str(s.to_cow()?));
    }
    if obj.cast::<PyInt>().is_ok() || obj.cast::<PyFloat>().is_ok() {
        return Ok(Value::Number(obj.extract::<f64>()?));
    }
    if obj.cast::<PyList>().is_ok() || obj.cast::<PyTuple>().is_ok() {
        return obj
            .try_iter()?
            .map(|x| from_py(&x?))
            .collect::<PyResult<Vec<_>>>()
            .map(Value::list);
    }
    if let Ok(d) = obj.cast::<PyDict>() {
        let mut r = indexmap::IndexMap::new();
        for (k, x) in d.iter() {
            let Ok(k) = k.extract::<String>() else {
                return Err(type_error(
                    py,
                    format!("an mx record needs string keys, found {}", type_name(&k)),
                ));
            };
            r.insert(k, from_py(&x)?);
        }
        return Ok(Value::record(r));
    }
    // NumPy arrays and scalars.
    if obj.hasattr("tolist")? && obj.hasattr("dtype")? {
        real_dtype(py, obj, "a NumPy value passed to mx")?;
        return from_py(&obj.call_method0("tolist")?);
    }
    if obj.is_callable() {
        return Err(type_error(
            py,
            "a Python function cannot be an mx value; register it with `Interpreter.register(name, fn)`",
        ));
    }
    Err(type_error(
        py,
        format!("cannot convert a Python {} to an mx value", type_name(obj)),
    ))
}

pub fn type_name(obj: &Bound<'_, PyAny>) -> String {
    obj.get_type()
        .name()
        .map(|n| n.to_string())
        .unwrap_or_else(|_| "object".into())
}
