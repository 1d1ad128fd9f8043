//! OpenSim files: `load("model.osim")` (a body), `load("x.mot")` /
//! `load("x.sto")` and `save(m, "x.mot", body:, rate:)` (Storage motion files).

use std::path::Path;
use std::sync::Arc;

use crate::io::storage::{self, Columns};
use crate::lang::args::{Args, describe};
use crate::lang::diagnostics::{ErrorKind, MxError, MxResult};
use crate::lang::eval::Evaluator;
use crate::lang::host::errors::file_error;
use crate::lang::host::{Body, Motion};
use crate::lang::registry::Registry;
use crate::lang::topic::Topic;
use crate::lang::value::Value;
use crate::model::Model;
use crate::motion::{Curve, Mu};

fn is_translation_name(n: &str) -> bool {
    n.ends_with("_tx") || n.ends_with("_ty") || n.ends_with("_tz")
}

/// The `body:` option's coordinates as (name, rotational), and a note when
/// the body does not say which are rotational (not an OpenSim body).
/// (coordinate, rotational) pairs, and a note on how they were decided.
type Kinds = (Vec<(String, bool)>, Option<String>);

fn body_kinds(a: &mut Args) -> MxResult<Option<Kinds>> {
    let Some(b) = a.opt_named("body") else {
        return Ok(None);
    };
    let Some(body) = b.value.as_object::<Body>() else {
        return Err(a.type_error("body", "a body, e.g. load(\"model.osim\")", &b));
    };
    Ok(Some(match body.coordinate_kinds() {
        Some(k) => (k, None),
        None => (
            body.model
                .coordinate_names()
                .iter()
                .map(|n| (n.clone(), !is_translation_name(n)))
                .collect(),
            Some(
                "the body is not an OpenSim model, so coordinates ending in _tx/_ty/_tz count as translations \
                 and the others as angles"
                    .to_string(),
            ),
        ),
    }))
}

fn load_motion(path: &Path, a: &mut Args, _ev: &mut Evaluator) -> MxResult<Value> {
    let kinds = body_kinds(a)?;
    let columns = match &kinds {
        Some((k, _)) => Columns::Body(k),
        None => Columns::ByName,
    };
    let (mu, notes) = storage::load_storage(path, columns).map_err(|e| {
        file_error(e, a.call_span()).help(
            "an OpenSim Storage file: `key=value` header lines, `endheader`, a `time` label line, rows of numbers",
        )
    })?;
    for n in notes
        .iter()
        .chain(kinds.as_ref().and_then(|k| k.1.as_ref()))
    {
        eprintln!("note: {}: {n}", path.display());
    }
    Ok(Value::object(Motion::Mu(mu)))
}

/// The sampling rate of a motion loaded from samples (every DOF on one grid).
fn native_rate(m: &Mu) -> Option<f64> {
    let mut rate = None;
    for name in m.names() {
        for iv in &m.get(name)?.intervals {
            let f = iv.first_func().ok()?;
            let Curve::Samples(s) = f.curve.as_ref() else {
                return None;
            };
            let r = 1.0 / (s.dt() * f.scale.abs());
            match rate {
                None => rate = Some(r),
                Some(x) if (x - r).abs() <= 1e-9 * r => {}
                Some(_) => return None,
            }
        }
    }
    rate
}

fn save_motion(v: &Value, path: &Path, a: &mut Args, _ev: &mut Evaluator) -> MxResult<()> {
    let Some(Motion::Mu(m)) = v.as_object::<Motion>() else {
        return Err(a.error(
            ErrorKind::Type,
            format!("a .mot file holds a motion unit (Mu), not {}", describe(v)),
        ));
    };
    let kinds = body_kinds(a)?;
    let rate = match a.opt_named("rate") {
        Some(r) => match r.value {
            Value::Number(x) if x.is_finite() && x > 0.0 => x,
            _ => return Err(a.type_error("rate", "a positive number of samples per second", &r)),
        },
        None => native_rate(m).ok_or_else(|| {
            a.error(
                ErrorKind::Arity,
                "this motion is not sampled on one grid: give the rate, e.g. `save(m, \"x.mot\", body: b, rate: 100)`",
            )
        })?,
    };
    let rotational: Box<dyn Fn(&str) -> bool> = match &kinds {
        Some((k, note)) => {
            let missing: Vec<&str> = m
                .names()
                .filter(|n| !k.iter().any(|(c, _)| c == n))
                .collect();
            if !missing.is_empty() {
                return Err(a.error(
                    ErrorKind::Value,
                    format!(
                        "DOF(s) {} are no coordinate of the body; save without `body:` or use `only(m, …)`",
                        missing.join(", ")
                    ),
                ));
            }
            if let Some(n) = note {
                eprintln!("note: {}: {n}", path.display());
            }
            let k = k.clone();
            Box::new(move |n: &str| k.iter().any(|(c, r)| c == n && *r))
        }
        None => {
            eprintln!(
                "note: {}: no `body:`, so DOFs ending in _tx/_ty/_tz are written as translations (metres) and the others as angles in degrees",
                path.display()
            );
            Box::new(|n: &str| !is_translation_name(n))
        }
    };
    storage::save_storage(m, path, rate, &*rotational).map_err(|e| file_error(e, a.call_span()))
}

fn load_osim(path: &Path, a: &mut Args, _ev: &mut Evaluator) -> MxResult<Value> {
    let couplers = match a.opt_named("couplers") {
        None => true,
        Some(v) => match v.value {
            Value::Bool(b) => b,
            _ => return Err(a.type_error("couplers", "true or false", &v)),
        },
    };
    let io_error = |e: crate::model::ModelError, a: &Args| {
        MxError::new(ErrorKind::Io, e.to_string()).at(a.call_span()).help(
            "mx reads OpenSim 3.x and 4 model files; the message names the element and its line",
        )
    };
    let mut loaded = Model::from_osim_file(path).map_err(|e| io_error(e, a))?;
    for w in &loaded.report.warnings {
        eprintln!("warning: {}: {w}", path.display());
    }
    let coupling = match couplers {
        true => loaded.coupling().map_err(|e| {
            io_error(e, a).help("load it with `couplers: false` to keep every coordinate free")
        })?,
        false => None,
    };
    loaded.report.couplers_enforced = coupling.is_some();
    let mut b = Body::from_model(Arc::new(loaded.model));
    b.coupling = coupling.map(Arc::new);
    b.osim = Some(Arc::new(loaded.report));
    Ok(Value::object(b))
}

pub fn register(reg: &mut Registry) {
    reg.topic(Topic::Dynamics);
    reg.loader(
        "osim",
        "An OpenSim model (4.x, or 3.x format 30000+) as a body: bodies, joints (CustomJoint, Pin, Slider, Weld, Ball, Free, Universal, Gimbal, Planar), coordinates named as in the model, its gravity; `body.report` lists what was ignored (muscles, forces, geometry). CoordinateCouplerConstraints are enforced (the dependent coordinate follows its function of the independent one, as in OpenSim's forward dynamics); `couplers: false` keeps dependent coordinates free, as OpenSim's calcM does.",
        load_osim,
    );
    for ext in ["mot", "sto"] {
        reg.loader(
            ext,
            "OpenSim Storage motion (.mot/.sto, versions 1 and 3): one DOF per column. `body:` maps columns to its coordinates by name and converts rotational ones from degrees when `inDegrees=yes`; without it, names ending _tx/_ty/_tz are translations.",
            load_motion,
        );
        reg.saver(
            ext,
            "OpenSim Storage motion: `save(m, \"x.mot\", body: b, rate: R)` writes rotational coordinates in degrees (inDegrees=yes), readable by OpenSim's STOFileAdapter; `rate` defaults to the motion's own sampling.",
            save_motion,
        );
    }
}
