//! `mx.Interpreter`: an mx interpreter of its own (globals persist between
//! `eval` calls), its work run through the runtime's worker thread, and
//! Python callables registered as mx functions.

use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use mx::Interpreter;
use mx::cancel::CancelToken;
use mx::lang::{Diagnostic, ErrorKind, MxError, Value};
use pyo3::exceptions::PyKeyError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use crate::convert::{from_py, to_py, to_py_in, type_name};
use crate::errors::{error, raise_diag, type_error, value_error};
use crate::runtime::{cancellable, python_stdout};

/// An mx interpreter: globals persist between `eval` calls.
///
/// `Interpreter(steps=None, root=None, max_depth=None, prelude=True)`:
/// `steps` limits each evaluation's steps, `root` confines `load`/`save` to
/// a folder, `max_depth` limits nested mx calls.
#[pyclass(name = "Interpreter", module = "mx", frozen)]
pub struct PyInterpreter {
    inner: Mutex<Interpreter>,
    cancel: CancelToken,
    /// A Python exception raised by a registered callback, re-raised as the
    /// cause of the mx error it turned into.
    pending: Arc<Mutex<Option<PyErr>>>,
}

impl PyInterpreter {
    fn with(
        &self,
        py: Python<'_>,
        f: impl FnOnce(&mut Interpreter) -> Result<Value, Diagnostic> + Send,
    ) -> PyResult<Py<PyAny>> {
        let r = cancellable(py, Some(&self.cancel), || {
            let mut guard = self.inner.try_lock().map_err(|_| {
                Diagnostic::new(
                    MxError::host(
                        "this interpreter is already evaluating (a callback cannot re-enter it)",
                    ),
                    None,
                )
            })?;
            f(&mut guard)
        })?;
        match r {
            Ok(v) => {
                let ctx = self.lock(py)?.context();
                to_py_in(py, &v, Some(&ctx))
            }
            Err(d) => {
                let e = raise_diag(py, &d);
                if let Some(cause) = self
                    .pending
                    .lock()
                    .unwrap_or_else(|p| p.into_inner())
                    .take()
                {
                    e.set_cause(py, Some(cause));
                }
                Err(e)
            }
        }
    }
}

#[pymethods]
impl PyInterpreter {
    #[new]
    #[pyo3(signature = (steps = None, root = None, max_depth = None, prelude = true))]
    fn new(
        py: Python<'_>,
        steps: Option<u64>,
        root: Option<PathBuf>,
        max_depth: Option<usize>,
        prelude: bool,
    ) -> PyResult<Self> {
        let mut i = if prelude {
            Interpreter::new()
        } else {
            Interpreter::bare()
        };
        i.set_step_budget(steps);
        if let Some(d) = max_depth {
            i.set_max_depth(d);
        }
        if let Some(r) = root {
            let r = r
                .canonicalize()
                .map_err(|e| error(py, ErrorKind::Io, format!("file root {}: {e}", r.display())))?;
            i.set_file_root(Some(r));
        }
        i.set_output(python_stdout());
        let cancel = i.cancel_token();
        Ok(PyInterpreter {
            inner: Mutex::new(i),
            cancel,
            pending: Arc::new(Mutex::new(None)),
        })
    }

    /// Evaluate mx source; `let`/`fn` at top level stay defined. Returns the
    /// value of the last statement (None for `let` and `print`).
    #[pyo3(signature = (src, name = "<input>"))]
    fn eval(&self, py: Python<'_>, src: String, name: &str) -> PyResult<Py<PyAny>> {
        let name = name.to_string();
        self.with(py, move |i| i.eval_named(&name, &src))
    }

    /// Run an mx script file.
    fn run(&self, py: Python<'_>, path: PathBuf) -> PyResult<Py<PyAny>> {
        self.with(py, move |i| i.eval_file(&path))
    }

    /// The value of a global (a `let`, a function, a built-in). KeyError if unknown.
    fn get(&self, py: Python<'_>, name: &str) -> PyResult<Py<PyAny>> {
        let v = self.lock(py)?.get(name);
        match v {
            Some(v) => {
                let ctx = self.lock(py)?.context();
                to_py_in(py, &v, Some(&ctx))
            }
            None => Err(PyKeyError::new_err(format!(
                "mx has no global named `{name}`"
            ))),
        }
    }

    /// Bind a global to a Python value (numbers, strings, bools, lists, dicts, motions, bodies).
    fn set(&self, py: Python<'_>, name: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let v = from_py(value)?;
        self.lock(py)?.set(name, v);
        Ok(())
    }

    fn __getitem__(&self, py: Python<'_>, name: &str) -> PyResult<Py<PyAny>> {
        self.get(py, name)
    }

    fn __setitem__(&self, py: Python<'_>, name: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
        self.set(py, name, value)
    }

    fn __contains__(&self, py: Python<'_>, name: &str) -> PyResult<bool> {
        Ok(self.lock(py)?.get(name).is_some())
    }

    /// Every name in scope: globals first, then built-ins.
    fn names(&self, py: Python<'_>) -> PyResult<Vec<String>> {
        Ok(self.lock(py)?.names())
    }

    /// Make the Python callable `fn` an mx function `name`. mx arguments
    /// arrive converted to Python (positional, and named ones as keywords);
    /// the return value is converted back. An exception inside `fn` becomes
    /// an mx error whose `__cause__` is the original exception.
    #[pyo3(signature = (name, r#fn, doc = None))]
    fn register(
        &self,
        py: Python<'_>,
        name: &str,
        r#fn: Py<PyAny>,
        doc: Option<String>,
    ) -> PyResult<()> {
        let bound = r#fn.bind(py);
        if !bound.is_callable() {
            return Err(type_error(
                py,
                format!(
                    "register: `fn` must be callable, found {}",
                    type_name(bound)
                ),
            ));
        }
        if name.is_empty() || !name.chars().all(|c| c.is_alphanumeric() || c == '_') {
            return Err(value_error(
                py,
                format!("register: `{name}` is not an mx name (letters, digits, _)"),
            ));
        }
        let doc = match doc {
            Some(d) => d,
            None => bound
                .getattr("__doc__")
                .ok()
                .and_then(|d| d.extract::<String>().ok())
                .unwrap_or_default(),
        };
        let signature = signature_of(py, name, bound);
        let pending = self.pending.clone();
        let fname = name.to_string();
        let callback = move |a: &mut mx::lang::Args, _ev: &mut mx::lang::Evaluator| {
            let pos: Vec<Value> = a.rest().into_iter().map(|x| x.value).collect();
            let named: Vec<(String, Value)> = a
                .rest_named()
                .into_iter()
                .map(|(n, x)| (n, x.value))
                .collect();
            Python::attach(|py| -> Result<Value, MxError> {
                let call = || -> PyResult<Value> {
                    let args = pos
                        .iter()
                        .map(|v| to_py(py, v))
                        .collect::<PyResult<Vec<_>>>()?;
                    let kw = PyDict::new(py);
                    for (n, v) in &named {
                        kw.set_item(n, to_py(py, v)?)?;
                    }
                    let r = r#fn.bind(py).call(PyTuple::new(py, args)?, Some(&kw))?;
                    from_py(&r)
                };
                call().map_err(|e| {
                    let msg = format!("Python function `{fname}` raised {}", describe_exc(py, &e));
                    *pending.lock().unwrap_or_else(|p| p.into_inner()) = Some(e);
                    MxError::host(msg).help("the Python exception is this error's __cause__")
                })
            })
        };
        self.lock(py)?.register(&signature, &doc, callback);
        Ok(())
    }

    /// `:help NAME`: the signature and doc of a built-in, None if unknown.
    fn help(&self, py: Python<'_>, name: &str) -> PyResult<Option<String>> {
        Ok(self
            .lock(py)?
            .help_entry(name)
            .map(|e| format!("{}\n\n{}", e.signature, e.doc)))
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        let l = self.lock(py)?.limits();
        Ok(format!(
            "mx.Interpreter(steps={})",
            l.max_steps
                .map(|s| s.to_string())
                .unwrap_or_else(|| "None".into())
        ))
    }
}

impl PyInterpreter {
    fn lock(&self, py: Python<'_>) -> PyResult<std::sync::MutexGuard<'_, Interpreter>> {
        self.inner.try_lock().map_err(|_| {
            error(
                py,
                ErrorKind::Host,
                "this interpreter is busy evaluating (called from one of its own callbacks?)",
            )
        })
    }
}

/// `name(a, b, c: default)` from `inspect.signature`, else `name(...)`.
fn signature_of(py: Python<'_>, name: &str, f: &Bound<'_, PyAny>) -> String {
    let params = (|| -> PyResult<Vec<String>> {
        let sig = py.import("inspect")?.getattr("signature")?.call1((f,))?;
        let mut out = Vec::new();
        for p in sig
            .getattr("parameters")?
            .call_method0("values")?
            .try_iter()?
        {
            let p = p?;
            let n: String = p.getattr("name")?.extract()?;
            let kind: String = p.getattr("kind")?.str()?.extract()?;
            out.push(match kind.as_str() {
                "VAR_POSITIONAL" => format!("...{n}"),
                "VAR_KEYWORD" => format!("**{n}"),
                _ => n,
            });
        }
        Ok(out)
    })();
    match params {
        Ok(p) => format!("{name}({})", p.join(", ")),
        Err(_) => format!("{name}(...)"),
    }
}

fn describe_exc(py: Python<'_>, e: &PyErr) -> String {
    let t = e
        .get_type(py)
        .name()
        .map(|n| n.to_string())
        .unwrap_or_else(|_| "an exception".into());
    match e.value(py).str() {
        Ok(s) if !s.to_string().is_empty() => format!("{t}: {s}"),
        _ => t,
    }
}
