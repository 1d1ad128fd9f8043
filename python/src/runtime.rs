//! The runtime under every class: the shared built-ins (one interpreter whose
//! functions `mx.load`, `Motion.affine`, … call), calling an mx function
//! value, and running long mx work on a worker thread so the calling thread
//! can watch for Ctrl-C (KeyboardInterrupt cancels the work through its
//! `CancelToken`) with the GIL released meanwhile. `print` goes to Python's
//! `sys.stdout`.

use std::io::Write;
use std::sync::{Arc, Mutex, OnceLock};
use std::time::{Duration, Instant};

use mx::Interpreter;
use mx::cancel::CancelToken;
use mx::lang::ast::Span;
use mx::lang::builtins::ArgValue;
use mx::lang::eval::Output;
use mx::lang::{Context, Diagnostic, ErrorKind, Evaluator, MxError, Value};
use pyo3::prelude::*;

use crate::errors::error;

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
            interp.set_output(python_stdout());
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

/// Stack of the worker thread (the evaluator also grows its stack on demand).
const WORKER_STACK: usize = 64 << 20;

/// Run `f` on a worker thread; meanwhile poll Python's signal handlers. A
/// KeyboardInterrupt cancels `cancel`, waits for `f` to stop and is raised.
pub fn cancellable<R: Send>(
    py: Python<'_>,
    cancel: Option<&CancelToken>,
    f: impl FnOnce() -> R + Send,
) -> PyResult<R> {
    cancellable_ticking(py, cancel, None, f)
}

/// [`cancellable`], calling `on_tick(elapsed_seconds)` every 0.1 s.
pub fn cancellable_ticking<R: Send>(
    py: Python<'_>,
    cancel: Option<&CancelToken>,
    on_tick: Option<&Py<PyAny>>,
    f: impl FnOnce() -> R + Send,
) -> PyResult<R> {
    let t0 = Instant::now();
    std::thread::scope(|s| {
        let (tx, mut rx) = std::sync::mpsc::channel();
        let worker = std::thread::Builder::new()
            .name("mx-eval".into())
            .stack_size(WORKER_STACK)
            .spawn_scoped(s, move || {
                let _ = tx.send(f());
            })
            .map_err(|e| error(py, ErrorKind::Host, format!("cannot start a thread: {e}")))?;
        let mut interrupted: Option<PyErr> = None;
        let result = loop {
            // The receiver moves into the GIL-free wait and back out.
            let (back, got) = py.detach(move || {
                let got = rx.recv_timeout(Duration::from_millis(100));
                (rx, got)
            });
            rx = back;
            match got {
                Ok(r) => break r,
                Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {}
                Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => {
                    let _ = worker.join();
                    return Err(error(
                        py,
                        ErrorKind::Host,
                        "the mx worker thread stopped unexpectedly",
                    ));
                }
            }
            if interrupted.is_none() {
                if let Err(e) = py.check_signals() {
                    if let Some(c) = cancel {
                        c.cancel();
                    }
                    interrupted = Some(e);
                } else if let Some(cb) = on_tick
                    && let Err(e) = cb.call1(py, (t0.elapsed().as_secs_f64(),))
                {
                    if let Some(c) = cancel {
                        c.cancel();
                    }
                    interrupted = Some(e);
                }
            }
        };
        let _ = worker.join();
        if let Some(c) = cancel {
            c.reset();
        }
        match interrupted {
            Some(e) => Err(e),
            None => Ok(result),
        }
    })
}

/// `print` output written to Python's `sys.stdout` (so notebooks and pytest's
/// capture see it).
pub fn python_stdout() -> Output {
    Arc::new(Mutex::new(PyStdout))
}

struct PyStdout;

impl Write for PyStdout {
    fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
        let text = String::from_utf8_lossy(b).into_owned();
        Python::attach(|py| {
            py.import("sys")
                .and_then(|sys| sys.getattr("stdout"))
                .and_then(|out| out.call_method1("write", (text,)))
                .map(|_| ())
                .map_err(|e| std::io::Error::other(e.to_string()))
        })?;
        Ok(b.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}
