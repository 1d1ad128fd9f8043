//! Motion ↔ JSON, exact: every number is written in round-trip form
//! (serde_json's `float_roundtrip`), curves shared between intervals are
//! stored once, and functions of time are stored as their mx source and
//! compiled again on load by a function the caller supplies (the
//! interpreter), so this module needs no language types.
//!
//! Layout (`version` 1):
//! ```json
//! {"format":"mx-motion","version":1,
//!  "curves":[{"kind":"constant","value":1.5},
//!            {"kind":"samples","t0":0,"dt":0.008333,"values":[…]},
//!            {"kind":"function","source":"fn(t) = sin(t)"},
//!            {"kind":"hermite","t0":0,"t1":1,"q0":0,"v0":0,"q1":1,"v1":0}],
//!  "dofs":[{"name":"Hips.Xposition","intervals":[
//!            {"start":0,"stop":2,"funcs":[{"curve":0,"shift":0,"scale":1,"offset":0}]}]}]}
//! ```

use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::atomic::write_atomic;
use super::{ContentError, FileError};
use crate::motion::{
    Curve, Dof, Func, HermiteCurve, Interval, Mu, SampledCurve, TimeFunction, time_tol,
};

pub const FORMAT: &str = "mx-motion";
pub const VERSION: u32 = 1;

/// Compiles the mx source of a function of time back into a function.
pub type CompileFn<'a> = &'a dyn Fn(&str) -> Result<Arc<dyn TimeFunction>, ContentError>;

#[derive(Serialize, Deserialize)]
struct File {
    format: String,
    version: u32,
    curves: Vec<CurveJson>,
    dofs: Vec<DofJson>,
}

#[derive(Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
enum CurveJson {
    Constant {
        value: f64,
    },
    Samples(SampledCurve),
    Function {
        source: String,
    },
    Hermite(HermiteCurve),
    Spline(crate::spline::BSplineCurve),
    /// A laid example plus SP's correction (`Curve::Sum`).
    Sum {
        base: Box<CurveJson>,
        correction: Box<CurveJson>,
    },
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct DofJson {
    name: String,
    intervals: Vec<IntervalJson>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct IntervalJson {
    start: f64,
    stop: f64,
    funcs: Vec<FuncJson>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct FuncJson {
    curve: usize,
    shift: f64,
    scale: f64,
    offset: f64,
}

/// Write `mu` atomically as JSON. Fails (writing nothing) when a function of
/// time has no mx source, e.g. a host function.
pub fn save_json(mu: &Mu, path: impl AsRef<Path>) -> Result<(), FileError> {
    let path = path.as_ref();
    let text = to_json_string(mu).map_err(|m| FileError::content(path, m))?;
    write_atomic(path, text.as_bytes())
}

/// Read a motion written by [`save_json`].
pub fn load_json(path: impl AsRef<Path>, compile_fn: CompileFn) -> Result<Mu, FileError> {
    let path = path.as_ref();
    let text = std::fs::read_to_string(path).map_err(|source| FileError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    from_json_str(&text, compile_fn).map_err(|m| FileError::content(path, m))
}

/// The JSON text (compact: sample arrays stay one line).
pub fn to_json_string(mu: &Mu) -> Result<String, ContentError> {
    let mut curves: Vec<CurveJson> = Vec::new();
    let mut index: HashMap<*const Curve, usize> = HashMap::new();
    let mut dofs = Vec::with_capacity(mu.len());
    for (name, dof) in &mu.dofs {
        let mut intervals = Vec::with_capacity(dof.intervals.len());
        for iv in &dof.intervals {
            let mut funcs = Vec::with_capacity(iv.funcs.len());
            for f in &iv.funcs {
                let key = Arc::as_ptr(&f.curve);
                let id = match index.get(&key) {
                    Some(&id) => id,
                    None => {
                        curves.push(curve_json(&f.curve, name)?);
                        index.insert(key, curves.len() - 1);
                        curves.len() - 1
                    }
                };
                funcs.push(FuncJson {
                    curve: id,
                    shift: f.shift,
                    scale: f.scale,
                    offset: f.offset,
                });
            }
            intervals.push(IntervalJson {
                start: iv.start,
                stop: iv.stop,
                funcs,
            });
        }
        dofs.push(DofJson {
            name: name.clone(),
            intervals,
        });
    }
    let file = File {
        format: FORMAT.into(),
        version: VERSION,
        curves,
        dofs,
    };
    serde_json::to_string(&file)
        .map_err(|e| ContentError::new(format!("cannot encode the motion as JSON: {e}")))
}

fn curve_json(c: &Curve, dof: &str) -> Result<CurveJson, ContentError> {
    Ok(match c {
        Curve::Constant(v) => CurveJson::Constant { value: *v },
        Curve::Samples(s) => CurveJson::Samples(s.clone()),
        Curve::Hermite(h) => CurveJson::Hermite(h.clone()),
        Curve::Spline(c) => CurveJson::Spline(c.clone()),
        Curve::Sum(a, b) => CurveJson::Sum {
            base: Box::new(curve_json(a, dof)?),
            correction: Box::new(curve_json(b, dof)?),
        },
        Curve::Function(f) => CurveJson::Function {
            source: f.source().ok_or_else(|| {
                ContentError::new(format!(
                    "DOF '{dof}' uses a function of time that has no mx source (a host function?), so it cannot be saved as JSON; sample it first (save as CSV) or define it in mx"
                ))
            })?,
        },
    })
}

/// One curve of the file (`k`: its index, for messages).
fn curve_from_json(c: CurveJson, k: usize, compile_fn: &CompileFn) -> Result<Curve, ContentError> {
    Ok(match c {
        CurveJson::Constant { value } => {
            Curve::constant(value).map_err(|e| ContentError::new(format!("curve {k}: {e}")))?
        }
        CurveJson::Samples(s) => Curve::Samples(s),
        CurveJson::Hermite(h) => Curve::Hermite(
            HermiteCurve::new(h.t0, h.q0, h.v0, h.t1, h.q1, h.v1)
                .map_err(|e| ContentError::new(format!("curve {k}: {e}")))?,
        ),
        CurveJson::Spline(c) => {
            Curve::spline(c).map_err(|e| ContentError::new(format!("curve {k}: {e}")))?
        }
        CurveJson::Sum { base, correction } => Curve::Sum(
            Arc::new(curve_from_json(*base, k, compile_fn)?),
            Arc::new(curve_from_json(*correction, k, compile_fn)?),
        ),
        CurveJson::Function { source } => Curve::Function(compile_fn(&source).map_err(|e| {
            ContentError::new(format!("curve {k}: cannot compile `{source}`: {e}"))
        })?),
    })
}

/// Parse and validate a motion from JSON text.
pub fn from_json_str(text: &str, compile_fn: CompileFn) -> Result<Mu, ContentError> {
    let file: File = serde_json::from_str(text)
        .map_err(|e| ContentError::new(format!("not an mx motion JSON file: {e}")))?;
    if file.format != FORMAT {
        return Err(ContentError::new(format!(
            "format is '{}', expected '{FORMAT}'",
            file.format
        )));
    }
    if file.version != VERSION {
        return Err(ContentError::new(format!(
            "motion file version {} is not supported (this mx reads version {VERSION})",
            file.version
        )));
    }
    let mut curves: Vec<Arc<Curve>> = Vec::with_capacity(file.curves.len());
    for (k, c) in file.curves.into_iter().enumerate() {
        let curve = curve_from_json(c, k, &compile_fn)?;
        curves.push(Arc::new(curve));
    }
    let mut mu = Mu::new();
    for d in file.dofs {
        if mu.get(&d.name).is_some() {
            return Err(ContentError::new(format!("DOF '{}' appears twice", d.name)));
        }
        let mut intervals: Vec<Interval> = Vec::with_capacity(d.intervals.len());
        for iv in d.intervals {
            let mut funcs = Vec::with_capacity(iv.funcs.len());
            for f in iv.funcs {
                let curve = curves.get(f.curve).ok_or_else(|| {
                    ContentError::new(format!(
                        "DOF '{}': curve {} does not exist",
                        d.name, f.curve
                    ))
                })?;
                funcs.push(Func {
                    curve: curve.clone(),
                    shift: f.shift,
                    scale: f.scale,
                    offset: f.offset,
                });
            }
            let iv = Interval::with_funcs(funcs, iv.start, iv.stop)
                .map_err(|e| ContentError::new(format!("DOF '{}': {e}", d.name)))?;
            if let Some(prev) = intervals.last()
                && iv.start < prev.stop - time_tol(prev.stop)
            {
                return Err(ContentError::new(format!(
                    "DOF '{}': interval [{}, {}] starts before the previous one stops ({}); intervals must be sorted and disjoint",
                    d.name, iv.start, iv.stop, prev.stop
                )));
            }
            intervals.push(iv);
        }
        mu.insert(d.name, Dof { intervals });
    }
    Ok(mu)
}
