//! Values both ways (numbers, strings, bools, lists, dicts; motions, bodies
//! and other host objects as Python objects), keyword arguments, and the
//! shared built-ins every module-level function calls.

use std::sync::OnceLock;

use mx::Interpreter;
use mx::cancel::CancelToken;
use mx::lang::ast::Span;
use mx::lang::builtins::ArgValue;
use mx::lang::builtins::body::Body;
use mx::lang::builtins::motion::Motion;
use mx::lang::{Context, Diagnostic, Evaluator, MxError, Value};
use pyo3::exceptions::PyKeyError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

use crate::body::PyBody;
use crate::errors::{raise_diag, type_error};
use crate::motion::PyMotion;

/// The standard built-ins and the prelude, shared by module-level calls
/// (`mx.load`, `Motion.affine`, …); `print` goes to Python's `sys.stdout`.
pub struct Builtins {
    interp: Interpreter,
}

impl Builtins {
    pub fn get() -> &'static Builtins {
        static B: OnceLock<Builtins> = OnceLock::new();
        B.get_or_init(|| {
            let mut interp = Interpreter::new();
            interp.set_output(crate::interp::python_stdout());
            Builtins { interp }
        })
    }

    /// A context of its own (a fresh cancellation token unless one is given).
    pub fn context_with(&self, cancel: CancelToken) -> Context {
        let mut c = self.interp.context();
        c.cancel = cancel;
        c
    }

    /// Call the built-in or prelude function `name`.
    pub fn call(
        &self,
        name: &str,
        pos: Vec<Value>,
        named: Vec<(String, Value)>,
    ) -> Result<Value, Diagnostic> {
        Self::call_in(&self.context_with(CancelToken::new()), name, pos, named)
    }

    pub fn call_in(
        ctx: &Context,
        name: &str,
        pos: Vec<Value>,
        named: Vec<(String, Value)>,
    ) -> Result<Value, Diagnostic> {
        let f = Self::get().interp.get(name).ok_or_else(|| {
            Diagnostic::new(MxError::host(format!("mx has no function `{name}`")), None)
        })?;
        call_value(ctx, &f, pos, named)
    }

    pub fn lookup(&self, name: &str) -> Option<Value> {
        self.interp.get(name)
    }

    /// `(signature, doc)` of a built-in or prelude function.
    pub fn help(&self, name: &str) -> Option<(String, String)> {
        self.interp.help_entry(name).map(|e| (e.signature, e.doc))
    }

    /// `(name, signature, doc)` of every built-in and prelude function.
    pub fn all_help(&self) -> Vec<(String, String, String)> {
        self.interp
            .help_entries()
            .into_iter()
            .filter(|e| e.signature.starts_with(&format!("{}(", e.name)))
            .map(|e| (e.name, e.signature, e.doc))
            .collect()
    }
}

fn arg(value: Value) -> ArgValue {
    ArgValue {
        value,
        span: Span::default(),
        name: None,
    }
}

/// Call a function value with positional and named arguments.
pub fn call_value(
    ctx: &Context,
    f: &Value,
    pos: Vec<Value>,
    named: Vec<(String, Value)>,
) -> Result<Value, Diagnostic> {
    let s = Span::default();
    let pos = pos.into_iter().map(arg).collect();
    let named = named.into_iter().map(|(n, v)| (n, s, arg(v))).collect();
    Evaluator::new(ctx.clone())
        .call_with(f, s, s, pos, named)
        .map_err(|e| Diagnostic::new(e, None))
}

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
        crate::motion::real_dtype(py, obj, "a NumPy value passed to mx")?;
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

/// An mx function (user-defined or built-in), callable from Python.
#[pyclass(name = "Function", module = "mx", frozen)]
pub struct PyFunction {
    pub value: Value,
    pub ctx: Context,
}

#[pymethods]
impl PyFunction {
    #[pyo3(signature = (*args, **kw))]
    fn __call__(
        &self,
        py: Python<'_>,
        args: &Bound<'_, PyTuple>,
        kw: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Py<PyAny>> {
        let pos = args
            .iter()
            .map(|a| from_py(&a))
            .collect::<PyResult<Vec<_>>>()?;
        let named = kwargs(kw)?;
        let ctx = self.ctx.clone();
        let f = self.value.clone();
        let r =
            crate::interp::cancellable(py, Some(&ctx.cancel), || call_value(&ctx, &f, pos, named))?;
        to_py(py, &r.map_err(|e| raise_diag(py, &e))?)
    }

    fn __repr__(&self) -> String {
        self.value.repr()
    }
}

/// Any other mx value (a joint, a scene, an SP report…): its fields are attributes.
#[pyclass(name = "Object", module = "mx", frozen)]
pub struct PyObject_ {
    pub value: Value,
}

#[pymethods]
impl PyObject_ {
    /// The mx type name (`Joint`, `Scene`, …).
    #[getter]
    fn r#type(&self) -> &'static str {
        self.value.type_name()
    }

    fn __getattr__(&self, py: Python<'_>, name: &str) -> PyResult<Py<PyAny>> {
        match &self.value {
            Value::Object(o) => match o.field(name) {
                Some(v) => to_py(py, &v),
                None => Err(PyErr::new::<pyo3::exceptions::PyAttributeError, _>(
                    format!("{} has no field `{name}`", o.type_name()),
                )),
            },
            _ => Err(PyKeyError::new_err(name.to_string())),
        }
    }

    fn __repr__(&self) -> String {
        self.value.repr()
    }
}
