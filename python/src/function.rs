//! The methods of `mx.Function` (calling an mx function from Python) and
//! `mx.Object` (an mx value's fields as attributes).

use mx::lang::Value;
use pyo3::exceptions::PyKeyError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use crate::convert::{from_py, kwargs, to_py};
use crate::errors::raise_diag;
use crate::objects::{PyFunction, PyObject_};
use crate::runtime::{call_value, cancellable};

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
        let r = cancellable(py, Some(&ctx.cancel), || call_value(&ctx, &f, pos, named))?;
        to_py(py, &r.map_err(|e| raise_diag(py, &e))?)
    }

    fn __repr__(&self) -> String {
        self.value.repr()
    }
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
            Value::Object(o) => match self.value.field(name) {
                Some(v) => to_py(py, &v),
                None => Err(PyErr::new::<pyo3::exceptions::PyAttributeError, _>(
                    format!("{} has no field `{name}`", o.type_name()),
                )),
            },
            _ => Err(PyKeyError::new_err(name.to_string())),
        }
    }

    /// The value's fields, as mx's `keys(x)` lists them (what `x.name` reads).
    fn keys(&self) -> Vec<String> {
        self.value.keys().unwrap_or_default()
    }

    /// `dir(x)` lists the fields, so completion in IPython and Jupyter offers them.
    fn __dir__(&self) -> Vec<String> {
        let mut names = self.keys();
        names.extend(["keys".to_string(), "type".to_string()]);
        names
    }

    fn __repr__(&self) -> String {
        self.value.repr()
    }
}
