//! `mx.Body`: a multibody model (from URDF, `body_of(clip)`, `human(clip)`
//! or mx code) with inverse/forward dynamics and the mass matrix on one
//! state or a batch of states, computed in parallel with the GIL released
//! (the class itself is in `objects.rs`).

use mx::dynamics::{DynamicsError, Workspace, forward_dynamics, inverse_dynamics, mass_matrix};
use mx::lang::Value;
use mx::mocap::{Missing, positions};
use mx::model::Model;
use nalgebra::{DMatrix, Vector3};
use numpy::{PyArray1, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;

use crate::arrays::f64_array;
use crate::convert::to_py;
use crate::errors::{raise_diag, type_error, value_error};
use crate::html::html_escape;
use crate::objects::{PyBody, PyMotion};
use crate::runtime::Builtins;

/// Inputs of one dynamics call, each [N, nq] (or [nq]), C-contiguous
/// float64 arrays whose memory the computation reads in place.
/// One state is copied (cheaper than NumPy's borrow tracking).
struct Batch<'py> {
    arrays: Vec<Input<'py>>,
    n: usize,
    batched: bool,
}

enum Input<'py> {
    Copied(Vec<f64>),
    Borrowed(numpy::PyReadonlyArrayDyn<'py, f64>),
}

impl Batch<'_> {
    fn slices(&self) -> Vec<&[f64]> {
        self.arrays
            .iter()
            .map(|a| match a {
                Input::Copied(v) => v.as_slice(),
                Input::Borrowed(a) => a.as_slice().expect("made C-contiguous in batch()"),
            })
            .collect()
    }
}

fn batch<'py>(
    py: Python<'py>,
    m: &Model,
    fname: &str,
    inputs: &[(&str, &Bound<'py, PyAny>)],
) -> PyResult<Batch<'py>> {
    let nq = m.nq();
    let mut arrays = Vec::new();
    let mut shape: Option<(usize, bool)> = None;
    for (name, obj) in inputs {
        let a = f64_array(py, obj, name)?;
        let (n, batched) = match a.shape() {
            [k] if *k == nq => (1, false),
            [n, k] if *k == nq => (*n, true),
            s => {
                return Err(value_error(
                    py,
                    format!(
                        "{fname}: `{name}` has shape {s:?}; expected ({nq},) for one state or (N, {nq}) for a batch \
                         (the body's {nq} coordinates: {})",
                        short_list(m.coordinate_names())
                    ),
                ));
            }
        };
        if let Some(prev) = shape
            && prev != (n, batched)
        {
            return Err(value_error(
                py,
                format!(
                    "{fname}: `{name}` has shape {:?} but `{}` had {}",
                    a.shape(),
                    inputs[0].0,
                    if prev.1 {
                        format!("({}, {nq})", prev.0)
                    } else {
                        format!("({nq},)")
                    }
                ),
            ));
        }
        shape = Some((n, batched));
        let input = if !batched {
            Input::Copied(match a.to_vec() {
                Ok(v) => v,
                Err(_) => a.readonly().as_array().iter().copied().collect(),
            })
        } else if a.is_c_contiguous() {
            Input::Borrowed(a.readonly())
        } else {
            let c = py
                .import("numpy")?
                .getattr("ascontiguousarray")?
                .call1((a,))?
                .cast_into::<numpy::PyArrayDyn<f64>>()?;
            Input::Borrowed(c.readonly())
        };
        let flat = match &input {
            Input::Copied(v) => v.as_slice(),
            Input::Borrowed(a) => a.as_slice().expect("C-contiguous"),
        };
        if let Some(k) = flat.iter().position(|x| !x.is_finite()) {
            let (row, col) = (k / nq, k % nq);
            let at = if batched {
                format!("[{row}, {col}]")
            } else {
                format!("[{col}]")
            };
            return Err(value_error(
                py,
                format!(
                    "{fname}: `{name}{at}` (coordinate `{}`) is {}; inputs must be finite",
                    m.coordinate_names()[col],
                    flat[k]
                ),
            ));
        }
        arrays.push(input);
    }
    let (n, batched) = shape.unwrap_or((1, false));
    Ok(Batch { arrays, n, batched })
}

fn short_list(names: &[String]) -> String {
    let mut s: Vec<&str> = names.iter().take(6).map(String::as_str).collect();
    if names.len() > 6 {
        s.push("…");
    }
    s.join(", ")
}

fn gravity_of(py: Python<'_>, m: &Model, g: Option<Vec<f64>>) -> PyResult<Vector3<f64>> {
    match g {
        None => Ok(m.default_gravity),
        Some(g) if g.len() == 3 && g.iter().all(|x| x.is_finite()) => {
            Ok(Vector3::new(g[0], g[1], g[2]))
        }
        Some(g) => Err(value_error(
            py,
            format!("gravity must be 3 finite numbers, got {g:?}"),
        )),
    }
}

impl PyBody {
    /// Run `f(ws, state index, output row)` for every state: one state on the
    /// cached workspace, a batch in parallel (rayon) with the GIL released.
    fn run<'py, F>(
        &self,
        py: Python<'py>,
        fname: &str,
        b: &Batch,
        width: usize,
        f: F,
    ) -> PyResult<Bound<'py, PyAny>>
    where
        F: Fn(&mut Workspace, usize, &mut [f64]) -> Result<(), DynamicsError> + Sync,
    {
        let mut out = vec![0.0; b.n * width];
        let r = if b.n == 1 {
            let mut ws = self.ws.lock().unwrap_or_else(|p| p.into_inner());
            f(&mut ws, 0, &mut out).map_err(|e| (0, e))
        } else {
            let m = &self.model;
            // A few blocks of states per thread, each on one workspace: rayon's
            // per-item splitting (and a workspace per split) cost more than a
            // small model's dynamics.
            let width = width.max(1);
            let per = b.n.div_ceil(4 * rayon::current_num_threads()).max(1);
            py.detach(|| {
                out.par_chunks_mut(width * per)
                    .enumerate()
                    .try_for_each(|(c, rows)| {
                        let mut ws = Workspace::new(m);
                        for (j, row) in rows.chunks_mut(width).enumerate() {
                            let i = c * per + j;
                            f(&mut ws, i, row).map_err(|e| (i, e))?;
                        }
                        Ok(())
                    })
            })
        };
        if let Err((i, e)) = r {
            let at = if b.batched {
                format!(" (state {i})")
            } else {
                String::new()
            };
            return Err(value_error(py, format!("{fname}{at}: {e}")));
        }
        // One state: NumPy allocates and copies the few numbers, cheaper than
        // handing it a Rust buffer to own (which costs a capsule object per
        // call). A batch hands its buffer over, so nothing is copied.
        let a = if b.n == 1 {
            PyArray1::from_slice(py, &out)
        } else {
            PyArray1::from_vec(py, out)
        };
        let nq = self.model.nq();
        Ok(match (b.batched, width == nq) {
            (false, true) => a.into_any(),
            (false, false) => a.reshape([nq, nq])?.into_any(),
            (true, true) => a.reshape([b.n, nq])?.into_any(),
            (true, false) => a.reshape([b.n, nq, nq])?.into_any(),
        })
    }
}

/// `f(model, ws, q, v, x, gravity, out)`: inverse or forward dynamics.
type StateFn = fn(
    &Model,
    &mut Workspace,
    &[f64],
    &[f64],
    &[f64],
    &Vector3<f64>,
    &mut [f64],
) -> Result<(), DynamicsError>;

impl PyBody {
    /// A function of (q, v, x) per state, e.g. inverse dynamics of (q, v, a).
    fn per_state<'py>(
        &self,
        py: Python<'py>,
        fname: &str,
        inputs: [(&str, &Bound<'py, PyAny>); 3],
        gravity: Option<Vec<f64>>,
        f: StateFn,
    ) -> PyResult<Bound<'py, PyAny>> {
        let m = &*self.model;
        let g = gravity_of(py, m, gravity)?;
        if let Some(r) = self.one_state(py, fname, &inputs, &g, f) {
            return r;
        }
        let b = batch(py, m, fname, &inputs)?;
        let nq = m.nq();
        let x = b.slices();
        let (q, v, w) = (x[0], x[1], x[2]);
        self.run(py, fname, &b, nq, |ws, i, out| {
            let r = i * nq..(i + 1) * nq;
            f(m, ws, &q[r.clone()], &v[r.clone()], &w[r], &g, out)
        })
    }

    /// The common single state, three finite 1-D float64 arrays of nq, read in
    /// place and answered in a NumPy array written directly: no Rust buffer
    /// at all, since in a per-call loop this glue costs as much as a small
    /// robot's dynamics. `None` for anything else, which [`batch`] then
    /// handles (and explains when it is wrong).
    fn one_state<'py>(
        &self,
        py: Python<'py>,
        fname: &str,
        inputs: &[(&str, &Bound<'py, PyAny>); 3],
        g: &Vector3<f64>,
        f: StateFn,
    ) -> Option<PyResult<Bound<'py, PyAny>>> {
        let m = &*self.model;
        let nq = m.nq();
        let mut x: [&[f64]; 3] = [&[]; 3];
        for (k, (_, obj)) in inputs.iter().enumerate() {
            let a = obj.cast::<PyArray1<f64>>().ok()?;
            // SAFETY: we hold the GIL and do not release it until the slices
            // are dropped, so no Python code can resize or write the arrays
            // meanwhile; `as_slice` itself checks contiguity.
            let s = unsafe { a.as_slice() }.ok()?;
            if s.len() != nq || !s.iter().all(|v| v.is_finite()) {
                return None;
            }
            x[k] = s;
        }
        // SAFETY: the new array is written in full below before Python sees it
        // (or dropped on error).
        let out = unsafe { PyArray1::<f64>::new(py, nq, false) };
        let o = unsafe { out.as_slice_mut() }.expect("a new array is contiguous");
        let mut ws = self.ws.lock().unwrap_or_else(|p| p.into_inner());
        Some(match f(m, &mut ws, x[0], x[1], x[2], g, o) {
            Ok(()) => Ok(out.into_any()),
            Err(e) => Err(value_error(py, format!("{fname}: {e}"))),
        })
    }
}

#[pymethods]
impl PyBody {
    /// A body from a URDF file (fixed base; Pinocchio's joint order and gravity [0, 0, -9.81]).
    #[staticmethod]
    fn from_urdf(py: Python<'_>, path: std::path::PathBuf) -> PyResult<Py<PyAny>> {
        if path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .as_deref()
            != Some("urdf")
        {
            return Err(value_error(
                py,
                format!("from_urdf: {} is not a .urdf file", path.display()),
            ));
        }
        let v = Builtins::get()
            .call("load", vec![Value::str(path.to_string_lossy())], vec![])
            .map_err(|e| raise_diag(py, &e))?;
        to_py(py, &v)
    }

    /// The coordinate names, in the order every array uses.
    #[getter]
    fn coordinates(&self) -> Vec<String> {
        self.model.coordinate_names().to_vec()
    }
    #[getter]
    fn nq(&self) -> usize {
        self.model.nq()
    }
    #[getter]
    fn name(&self) -> String {
        self.model.name.clone()
    }
    /// Total mass (kg).
    #[getter]
    fn mass(&self) -> f64 {
        self.model.total_mass()
    }
    #[getter]
    fn links(&self) -> Vec<String> {
        self.model.links().iter().map(|l| l.name.clone()).collect()
    }
    /// The gravity dynamics uses unless a call passes `gravity=`.
    #[getter]
    fn gravity(&self) -> [f64; 3] {
        let g = self.model.default_gravity;
        [g[0], g[1], g[2]]
    }

    /// Joint torques τ = M(q) a + C(q, v) v + g(q): arrays [nq] or batches [N, nq].
    #[pyo3(signature = (q, v, a, gravity = None))]
    fn inverse_dynamics<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
        a: &Bound<'py, PyAny>,
        gravity: Option<Vec<f64>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        self.per_state(
            py,
            "inverse_dynamics",
            [("q", q), ("v", v), ("a", a)],
            gravity,
            inverse_dynamics,
        )
    }

    /// Joint accelerations under torques `tau` (articulated-body algorithm).
    #[pyo3(signature = (q, v, tau, gravity = None))]
    fn forward_dynamics<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
        tau: &Bound<'py, PyAny>,
        gravity: Option<Vec<f64>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        self.per_state(
            py,
            "forward_dynamics",
            [("q", q), ("v", v), ("tau", tau)],
            gravity,
            forward_dynamics,
        )
    }

    /// The joint-space mass matrix M(q): [nq, nq], or [N, nq, nq] for a batch.
    fn mass_matrix<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let m = &*self.model;
        let b = batch(py, m, "mass_matrix", &[("q", q)])?;
        let nq = m.nq();
        let x = b.slices();
        let q = x[0];
        self.run(py, "mass_matrix", &b, nq * nq, |ws, i, out| {
            let mut mm = DMatrix::zeros(nq, nq);
            mass_matrix(m, ws, &q[i * nq..(i + 1) * nq], &mut mm)?;
            // DMatrix is column-major; M is symmetric, but write rows explicitly.
            for r in 0..nq {
                for c in 0..nq {
                    out[r * nq + c] = mm[(r, c)];
                }
            }
            Ok(())
        })
    }

    /// World positions of the body's joints over the motion (its frame rate,
    /// or `rate` Hz): a dict with `times` [T], `joints` (names), `parents`
    /// (index or None) and `xyz` [T, J, 3] in metres.
    #[pyo3(signature = (motion, rate = None))]
    fn positions<'py>(
        &self,
        py: Python<'py>,
        motion: &Bound<'py, PyMotion>,
        rate: Option<f64>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let Some(mx::lang::builtins::motion::Motion::Mu(mu)) = motion
            .get()
            .value
            .as_object::<mx::lang::builtins::motion::Motion>(
        ) else {
            return Err(type_error(
                py,
                "positions: the motion must be a motion unit (Mu)",
            ));
        };
        if let Some(r) = rate
            && !(r.is_finite() && r > 0.0)
        {
            return Err(value_error(
                py,
                format!("positions: rate must be positive, got {r}"),
            ));
        }
        let m = &self.model;
        let p = py
            .detach(|| positions(mu, m, rate, Missing::Error))
            .map_err(|e| value_error(py, format!("positions: {e}")))?;
        let nj = p.names.len();
        let mut xyz = Vec::with_capacity(p.times.len() * nj * 3);
        for frame in &p.points {
            for pt in frame {
                xyz.extend_from_slice(&[pt[0], pt[1], pt[2]]);
            }
        }
        let d = PyDict::new(py);
        d.set_item("times", PyArray1::from_vec(py, p.times.clone()))?;
        d.set_item("joints", p.names.clone())?;
        d.set_item("parents", p.parents.clone())?;
        d.set_item(
            "xyz",
            PyArray1::from_vec(py, xyz).reshape([p.times.len(), nj, 3])?,
        )?;
        Ok(d)
    }

    fn __repr__(&self) -> String {
        self.value.repr()
    }

    /// In a notebook: a short table (name, mass, links, coordinates).
    fn _repr_html_(&self) -> String {
        let m = &self.model;
        let coords = m.coordinate_names();
        let mut s = format!(
            "<table><tr><th>Body</th><td>{}</td></tr><tr><th>mass</th><td>{:.2} kg</td></tr>\
             <tr><th>links</th><td>{}</td></tr><tr><th>coordinates</th><td>{}</td></tr>",
            html_escape(&m.name),
            m.total_mass(),
            m.num_links(),
            coords.len()
        );
        s.push_str(&format!(
            "<tr><th>names</th><td>{}</td></tr></table>",
            html_escape(&short_list(coords))
        ));
        s
    }
}
