//! `mx.Motion`: an mx motion (a motion unit, or a single DOF/interval) with
//! NumPy sampling, construction from arrays, the algebra as operators and
//! the motion functions as methods (the class itself is in `objects.rs`).

use mx::lang::ast::{BinOp, Span};
use mx::lang::builtins::motion::{Motion, motion_error};
use mx::lang::eval::binary_values;
use mx::lang::{Diagnostic, Value};
use mx::motion::Dof;
use numpy::{PyArray1, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyCFunction, PyDict, PyTuple};
use rayon::prelude::*;

use crate::arrays::f64_array;
use crate::convert::{from_py, kwargs, to_py, type_name};
use crate::errors::{raise_diag, type_error, value_error};
use crate::html::html_escape;
use crate::objects::PyMotion;
use crate::runtime::{Builtins, call_value, cancellable};

impl PyMotion {
    fn motion(&self) -> &Motion {
        self.value
            .as_object::<Motion>()
            .expect("a PyMotion holds a motion value")
    }

    /// `(name, dof)` pairs: a motion unit's DOFs, or one DOF named `value`.
    fn columns(&self) -> Vec<(String, Dof)> {
        match self.motion() {
            Motion::Mu(m) => m.dofs.iter().map(|(n, d)| (n.clone(), d.clone())).collect(),
            other => vec![("value".into(), other.as_dof().unwrap_or_default())],
        }
    }

    fn call(
        &self,
        py: Python<'_>,
        name: &str,
        mut pos: Vec<Value>,
        last: bool,
    ) -> PyResult<Py<PyAny>> {
        if last {
            pos.push(self.value.clone());
        } else {
            pos.insert(0, self.value.clone());
        }
        let v = Builtins::get()
            .call(name, pos, vec![])
            .map_err(|e| raise_diag(py, &e))?;
        to_py(py, &v)
    }
}

fn spans(py: Python<'_>, v: Result<Value, Diagnostic>) -> PyResult<Vec<(String, f64, f64)>> {
    let v = v.map_err(|e| raise_diag(py, &e))?;
    let mut out = Vec::new();
    for r in v.as_list().unwrap_or(&[]) {
        let Some(r) = r.as_record() else { continue };
        let num = |k: &str| r.get(k).and_then(Value::as_number).unwrap_or(f64::NAN);
        let dof = r
            .get("dof")
            .and_then(Value::as_str)
            .unwrap_or("")
            .to_string();
        out.push((dof, num("start"), num("stop")));
    }
    Ok(out)
}

#[pymethods]
impl PyMotion {
    /// The DOF names, in first-definition order.
    #[getter]
    fn dofs(&self) -> Vec<String> {
        self.columns().into_iter().map(|(n, _)| n).collect()
    }

    /// `(start, stop)` of everything defined, or None if nothing is.
    #[getter]
    fn span(&self) -> Option<(f64, f64)> {
        self.motion().span()
    }

    /// The mx type: `Mu`, `Dof` or `Interval`.
    #[getter]
    fn r#type(&self) -> &'static str {
        self.value.type_name()
    }

    /// Interior gaps (undefined with motion on both sides): `[(dof, start, stop), …]`.
    fn gaps(&self, py: Python<'_>) -> PyResult<Vec<(String, f64, f64)>> {
        spans(
            py,
            Builtins::get().call("gaps", vec![self.value.clone()], vec![]),
        )
    }

    /// Multiply defined stretches: `[(dof, start, stop), …]`.
    fn conflicts(&self, py: Python<'_>) -> PyResult<Vec<(String, f64, f64)>> {
        spans(
            py,
            Builtins::get().call("conflicts", vec![self.value.clone()], vec![]),
        )
    }

    /// Values at `times` as an array [T, D] (D = len(dofs)), NaN where a DOF
    /// is undefined; `deriv` 1 gives velocities, 2 accelerations. A scalar
    /// time gives a 1-D array [D]. Sampling a conflict raises MxMotionError.
    /// The array is written once, in place (column-major: the transpose of a
    /// [D, T] buffer).
    #[pyo3(signature = (times, deriv = 0))]
    fn sample<'py>(
        &self,
        py: Python<'py>,
        times: &Bound<'py, PyAny>,
        deriv: usize,
    ) -> PyResult<Bound<'py, PyAny>> {
        if deriv > 2 {
            return Err(value_error(
                py,
                format!("sample: deriv is 0, 1 or 2, got {deriv}"),
            ));
        }
        let arr = f64_array(py, times, "times")?;
        let scalar = arr.ndim() == 0;
        if arr.ndim() > 1 {
            return Err(value_error(
                py,
                format!("sample: `times` must be 1-D, got shape {:?}", arr.shape()),
            ));
        }
        let times: Vec<f64> = arr.to_vec()?;
        if let Some(k) = times.iter().position(|t| !t.is_finite()) {
            return Err(value_error(
                py,
                format!("sample: times[{k}] is {}, not a finite time", times[k]),
            ));
        }
        let cols = self.columns();
        let nt = times.len();
        let mut buf = vec![0.0; nt * cols.len()];
        let sorted = times.windows(2).all(|w| w[0] <= w[1]);
        let r = py.detach(|| {
            buf.par_chunks_mut(nt.max(1))
                .zip(cols.par_iter())
                .try_for_each(|(out, (name, dof))| fill(out, name, dof, &times, deriv, sorted))
        });
        r.map_err(|e| raise_diag(py, &Diagnostic::new(motion_error(e, Span::default()), None)))?;
        let a = PyArray1::from_vec(py, buf);
        if scalar {
            return Ok(a.into_any());
        }
        a.reshape([cols.len(), nt])?.into_any().getattr("T")
    }

    /// A motion unit from samples: `values[k, j]` is DOF `names[j]` at
    /// `times[k]` (evenly spaced), interpolated by a C² cubic spline; NaN
    /// cells are undefined. Sampling it at `times` gives `values` back exactly.
    #[staticmethod]
    fn from_array(
        py: Python<'_>,
        names: Vec<String>,
        times: &Bound<'_, PyAny>,
        values: &Bound<'_, PyAny>,
    ) -> PyResult<PyMotion> {
        let t = f64_array(py, times, "times")?;
        let v = f64_array(py, values, "values")?;
        if t.ndim() != 1 {
            return Err(value_error(
                py,
                format!("from_array: `times` must be 1-D, got shape {:?}", t.shape()),
            ));
        }
        let v = match v.ndim() {
            1 if names.len() == 1 => v.reshape([v.len(), 1])?,
            2 => v.cast_into::<numpy::PyArray2<f64>>()?,
            _ => {
                return Err(value_error(
                    py,
                    format!(
                        "from_array: `values` must be 2-D [times, dofs], got shape {:?}",
                        v.shape()
                    ),
                ));
            }
        };
        let (nt, nd) = (v.shape()[0], v.shape()[1]);
        if nt != t.len() || nd != names.len() {
            return Err(value_error(
                py,
                format!(
                    "from_array: `values` has shape ({nt}, {nd}) but there are {} times and {} names",
                    t.len(),
                    names.len()
                ),
            ));
        }
        if nt < 2 {
            return Err(value_error(
                py,
                "from_array: an interval needs at least two samples",
            ));
        }
        let times: Vec<f64> = t.to_vec()?;
        let ro = v.readonly();
        let view = ro.as_array();
        let cols: Vec<Vec<Option<f64>>> = (0..nd)
            .map(|j| {
                view.column(j)
                    .iter()
                    .map(|&x| (!x.is_nan()).then_some(x))
                    .collect()
            })
            .collect();
        let mu = mx::io::csv::mu_from_grid(&names, &times, &cols)
            .map_err(|e| value_error(py, format!("from_array: {e}")))?;
        Ok(PyMotion {
            value: Value::object(Motion::Mu(mu)),
        })
    }

    /// A pandas DataFrame indexed by time `t` with one column per DOF, sampled
    /// at `times` (default: the motion's own frame rate, else 30 Hz, over its span).
    #[pyo3(signature = (times = None, deriv = 0))]
    fn to_dataframe<'py>(
        &self,
        py: Python<'py>,
        times: Option<&Bound<'py, PyAny>>,
        deriv: usize,
    ) -> PyResult<Bound<'py, PyAny>> {
        let pd = py.import("pandas").map_err(|_| {
            PyErr::new::<pyo3::exceptions::PyImportError, _>(
                "Motion.to_dataframe needs pandas: pip install pandas",
            )
        })?;
        let times = match times {
            Some(t) => t.clone(),
            None => PyArray1::from_vec(py, self.frame_times(py)?).into_any(),
        };
        let data = self.sample(py, &times, deriv)?;
        let kw = PyDict::new(py);
        kw.set_item("name", "t")?;
        let index = pd.getattr("Index")?.call((times,), Some(&kw))?;
        let kw = PyDict::new(py);
        kw.set_item("index", index)?;
        kw.set_item("columns", self.dofs())?;
        pd.getattr("DataFrame")?.call((data,), Some(&kw))
    }

    /// The times of the motion's frames: its sampled data's rate (else 30 Hz) over its span.
    fn frame_times(&self, py: Python<'_>) -> PyResult<Vec<f64>> {
        let Some(span) = self.motion().span() else {
            return Ok(Vec::new());
        };
        let rate = match self.motion() {
            Motion::Mu(m) => mx::mocap::to_motion::sample_period(m).map(|dt| 1.0 / dt),
            _ => None,
        }
        .unwrap_or(30.0);
        mx::motion::grid_times(span, rate)
            .map_err(|e| raise_diag(py, &Diagnostic::new(motion_error(e, Span::default()), None)))
    }

    /// How many frames the motion has (the language's `frames(m)`).
    fn frames(&self, py: Python<'_>) -> PyResult<usize> {
        let v = Builtins::get()
            .call("frames", vec![self.value.clone()], vec![])
            .map_err(|e| raise_diag(py, &e))?;
        Ok(v.as_number().unwrap_or(0.0) as usize)
    }

    /// Seconds per frame (the language's `frame_time(m)`).
    fn frame_time(&self, py: Python<'_>) -> PyResult<f64> {
        let v = Builtins::get()
            .call("frame_time", vec![self.value.clone()], vec![])
            .map_err(|e| raise_diag(py, &e))?;
        Ok(v.as_number().unwrap_or(f64::NAN))
    }

    /// Write to a file by extension (`.json`, `.csv` with `rate=`, `.bvh`, `.glb`, `.gltf`, …).
    #[pyo3(signature = (path, **options))]
    fn save(
        &self,
        py: Python<'_>,
        path: std::path::PathBuf,
        options: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<()> {
        let named = kwargs(options)?;
        let pos = vec![self.value.clone(), Value::str(path.to_string_lossy())];
        let r = cancellable(py, None, || Builtins::get().call("save", pos, named))?;
        r.map_err(|e| raise_diag(py, &e))?;
        Ok(())
    }

    /// Time t ↦ ts + d·t (shift by ts, stretch by d > 0).
    fn affine(&self, py: Python<'_>, ts: f64, d: f64) -> PyResult<Py<PyAny>> {
        self.call(py, "affine", vec![ts.into(), d.into()], true)
    }

    /// The part inside [ts, tf], moved to start at time 0.
    fn clip(&self, py: Python<'_>, ts: f64, tf: f64) -> PyResult<Py<PyAny>> {
        self.call(py, "clip", vec![ts.into(), tf.into()], true)
    }

    /// The part inside [ts, tf], times unchanged.
    fn clip_in_place(&self, py: Python<'_>, ts: f64, tf: f64) -> PyResult<Py<PyAny>> {
        self.call(py, "clip_in_place", vec![ts.into(), tf.into()], true)
    }

    /// `other` appended, shifted to start where this motion ends.
    fn concatenate(&self, py: Python<'_>, other: &Bound<'_, PyMotion>) -> PyResult<Py<PyAny>> {
        self.call(py, "concatenate", vec![other.get().value.clone()], false)
    }

    /// The DOFs whose names match any of the patterns (exact names or globs).
    #[pyo3(signature = (*patterns))]
    fn only(&self, py: Python<'_>, patterns: Vec<String>) -> PyResult<Py<PyAny>> {
        self.call(
            py,
            "only",
            patterns.into_iter().map(Value::str).collect(),
            false,
        )
    }

    fn __add__(&self, py: Python<'_>, other: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        self.op(py, BinOp::Add, other)
    }
    fn __sub__(&self, py: Python<'_>, other: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        self.op(py, BinOp::Sub, other)
    }
    fn __and__(&self, py: Python<'_>, other: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        self.op(py, BinOp::Meet, other)
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other
            .cast::<PyMotion>()
            .is_ok_and(|o| self.value.equals(&o.get().value))
    }

    fn __len__(&self) -> usize {
        self.columns().len()
    }

    fn __contains__(&self, name: &str) -> bool {
        self.columns().iter().any(|(n, _)| n == name)
    }

    /// The DOF `name` (a Motion holding one DOF).
    fn __getitem__(&self, py: Python<'_>, name: &str) -> PyResult<Py<PyAny>> {
        let v = Builtins::get()
            .call("get", vec![self.value.clone(), Value::str(name)], vec![])
            .map_err(|_| PyErr::new::<pyo3::exceptions::PyKeyError, _>(name.to_string()))?;
        to_py(py, &v)
    }

    /// Any other mx function whose first argument is a motion, as a method
    /// (`m.shift(0.8)` = `shift(m, 0.8)`, like mx's method sugar).
    fn __getattr__(slf: &Bound<'_, Self>, name: &str) -> PyResult<Py<PyAny>> {
        let py = slf.py();
        let Some(f) = Builtins::get().lookup(name).filter(|f| f.is_callable()) else {
            return Err(PyErr::new::<pyo3::exceptions::PyAttributeError, _>(
                format!("Motion has no attribute or mx function `{name}`"),
            ));
        };
        let me = slf.get().value.clone();
        let method = PyCFunction::new_closure(
            py,
            None,
            None,
            move |args: &Bound<'_, PyTuple>,
                  kw: Option<&Bound<'_, PyDict>>|
                  -> PyResult<Py<PyAny>> {
                let py = args.py();
                let mut pos = vec![me.clone()];
                for a in args.iter() {
                    pos.push(from_py(&a)?);
                }
                let named = kwargs(kw)?;
                let ctx = Builtins::get().context_with(mx::cancel::CancelToken::new());
                let v = call_value(&ctx, &f, pos, named).map_err(|e| raise_diag(py, &e))?;
                to_py(py, &v)
            },
        )?;
        Ok(method.into_any().unbind())
    }

    fn __repr__(&self) -> String {
        self.value.repr()
    }

    /// In a notebook: the interactive HTML viewer on the clip's own body
    /// (`body_of`), else a table of the DOFs.
    fn _repr_html_(&self, py: Python<'_>) -> PyResult<String> {
        if let Motion::Mu(m) = self.motion()
            && let Ok(b) = Builtins::get().call("body_of", vec![self.value.clone()], vec![])
            && let Some(body) = b.as_object::<mx::lang::builtins::body::Body>()
            && let Ok(data) = mx::io::viewer::from_motion(m, &body.model, "motion", &[])
            && let Ok(html) = mx::io::viewer::html(&data)
        {
            return Ok(format!(
                "<iframe srcdoc=\"{}\" style=\"width:100%;height:560px;border:0\"></iframe>",
                html_escape(&html)
            ));
        }
        let mut s = format!(
            "<p>{}</p><table><tr><th>DOF</th><th>span</th><th>gaps</th></tr>",
            html_escape(&self.value.repr())
        );
        let gaps = self.gaps(py)?;
        for (name, dof) in self.columns().iter().take(50) {
            let span = dof
                .span()
                .map(|(a, b)| format!("{a:.3} – {b:.3} s"))
                .unwrap_or_else(|| "undefined".into());
            let n = gaps.iter().filter(|g| &g.0 == name).count();
            s.push_str(&format!(
                "<tr><td>{}</td><td>{span}</td><td>{n}</td></tr>",
                html_escape(name)
            ));
        }
        s.push_str("</table>");
        Ok(s)
    }
}

impl PyMotion {
    fn op(&self, py: Python<'_>, op: BinOp, other: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        let Ok(o) = other.cast::<PyMotion>() else {
            return Err(type_error(
                py,
                format!(
                    "the motion algebra combines two motions, not a motion and a {}",
                    type_name(other)
                ),
            ));
        };
        let s = Span::default();
        let v = binary_values(op, &self.value, &o.get().value, s, s, s)
            .map_err(|e| raise_diag(py, &Diagnostic::new(e, None)))?;
        to_py(py, &v)
    }
}

/// One DOF's column: values (or derivative `deriv`) at `times`, NaN where undefined.
fn fill(
    out: &mut [f64],
    name: &str,
    dof: &Dof,
    times: &[f64],
    deriv: usize,
    sorted: bool,
) -> Result<(), mx::motion::MotionError> {
    if deriv == 0 && sorted {
        for (o, v) in out.iter_mut().zip(dof.sample_values_sorted(name, times)?) {
            *o = v.unwrap_or(f64::NAN);
        }
        return Ok(());
    }
    for (o, &t) in out.iter_mut().zip(times) {
        *o = match dof.sample(name, t)? {
            Some(v) => v[deriv],
            None => f64::NAN,
        };
    }
    Ok(())
}
