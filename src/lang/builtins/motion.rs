//! Motion built-ins: `interval`, `dof`, `mu`, the algebra (`& - +` as
//! operators), `affine`, `clip`, `clip_in_place`, `concatenate`, `only`,
//! `dofs`, `span`, `frames`, `frame_time`, `gaps`, `conflicts`, `sample`, and the `.csv`/`.json`
//! formats of `save`/`load`. The work is done by `crate::motion` and
//! `crate::io`; this file only converts values and errors.

use std::sync::Arc;

use indexmap::IndexMap;

use crate::lang::args::{ArgValue, Args, describe};
use crate::lang::diagnostics::{ErrorKind, MxError, MxResult};
use crate::lang::registry::Registry;
use crate::lang::timefn::{MxTimeFn, compile};
use crate::lang::topic::Topic;
use crate::lang::value::{Value, format_number};
use crate::motion::{self, Curve, Dof, Interval, MotionError, Mu};

// The motion value lives in `lang::host`; these keep the paths embedders use.
pub use crate::lang::host::errors::{file_error, motion_error};
pub use crate::lang::host::motion::{Motion, as_mu};

/// A DOF where a motion unit is expected: how to make it one.
const WRAP_A_DOF: &str = "a motion unit (Mu); wrap a DOF with `mu({name: d})`";

/// A motion unit: a non-motion is asked to be a motion, a DOF to be wrapped.
fn mu_arg(a: &mut Args, name: &str) -> MxResult<(Mu, ArgValue)> {
    match a.motion(name)? {
        (Motion::Mu(m), arg) => Ok((m, arg)),
        (_, arg) => Err(a.type_error(name, WRAP_A_DOF, &arg)),
    }
}

fn obj(m: Motion) -> MxResult<Value> {
    Ok(Value::object(m))
}

/// Apply a DOF-level and an MU-level version of an operation.
fn map_motion(
    m: &Motion,
    span: crate::lang::ast::Span,
    name: Option<&str>,
    on_dof: impl Fn(&Dof) -> Result<Dof, MotionError>,
    on_mu: impl Fn(&Mu) -> Result<Mu, MotionError>,
) -> MxResult<Value> {
    let named = |e: MotionError| {
        motion_error(
            if let Some(n) = name {
                e.with_name(n)
            } else {
                e
            },
            span,
        )
    };
    match m {
        Motion::Mu(x) => obj(Motion::Mu(on_mu(x).map_err(named)?)),
        other => {
            let d = other.as_dof().unwrap_or_default();
            obj(Motion::Dof(on_dof(&d).map_err(named)?))
        }
    }
}

fn span_value(s: Option<(f64, f64)>) -> Value {
    match s {
        Some((a, b)) => Value::list(vec![Value::Number(a), Value::Number(b)]),
        None => Value::Nil,
    }
}

fn spans_value(v: Vec<motion::DofSpan>) -> Value {
    Value::list(
        v.into_iter()
            .map(|s| {
                let mut r = IndexMap::new();
                r.insert("dof".to_string(), Value::str(&s.dof));
                r.insert("start".to_string(), Value::Number(s.start));
                r.insert("stop".to_string(), Value::Number(s.stop));
                Value::record(r)
            })
            .collect(),
    )
}

fn to_dof(a: &Args, v: &ArgValue, what: &str) -> MxResult<Dof> {
    match v.value.as_object::<Motion>().and_then(Motion::as_dof) {
        Some(d) => Ok(d),
        None => Err(a.type_error(what, "an Interval or a Dof", v)),
    }
}

/// The motion built-ins, by topic.
pub fn register(reg: &mut Registry) {
    making(reg);
    timing(reg);
    queries(reg);
    formats(reg);
}

/// Making motions: `interval`, `samples`, `dof`, `mu`.
fn making(reg: &mut Registry) {
    reg.topic(Topic::Motion);
    reg.add(
        "interval(f, ts, tf)",
        "An interval over [ts, tf]: f is a number (constant) or a function of time `fn(t) = …` (evaluated at global time).",
        |a, ev| {
            let f = a.arg("f")?;
            let ts = a.number("ts")?;
            let tf = a.number("tf")?;
            let span = a.call_span();
            let i = match &f.value {
                Value::Number(x) => Interval::constant(*x, ts, tf),
                v if v.is_callable() => Interval::function(Arc::new(MxTimeFn::new(v.clone(), ev.ctx.clone())), ts, tf),
                _ => return Err(a.type_error("f", "a number or a function of time", &f)),
            }
            .map_err(|e| motion_error(e, span))?;
            obj(Motion::Interval(i))
        },
    );
    reg.add(
        "samples(values, rate, t0: 0)",
        "An interval over sampled data: values[k] at time t0 + k/rate, interpolated by a C² cubic spline (value, velocity and acceleration).",
        |a, _| {
            let values = a.list_of_numbers("values")?;
            let rate = a.number("rate")?;
            let t0 = a.number_or("t0", 0.0)?;
            let span = a.call_span();
            if !(rate.is_finite() && rate > 0.0) {
                return Err(a.error(ErrorKind::Value, format!("samples: rate must be positive, got {}", format_number(rate))));
            }
            if values.len() < 2 {
                return Err(a.error(ErrorKind::Value, "samples needs at least 2 values to span a time"));
            }
            let dt = 1.0 / rate;
            let stop = t0 + (values.len() - 1) as f64 * dt;
            let c = Curve::samples(t0, dt, values).map_err(|e| motion_error(e, span))?;
            obj(Motion::Interval(Interval::curve(c, t0, stop).map_err(|e| motion_error(e, span))?))
        },
    );
    reg.add(
        "dof(i1, ...)",
        "A DOF from intervals (or DOFs); overlapping ones become an explicit conflict.",
        |a, _| {
            let mut d = Dof::empty();
            for (k, v) in a.rest().iter().enumerate() {
                d = d.plus(&to_dof(a, v, &format!("i{}", k + 1))?);
            }
            obj(Motion::Dof(d))
        },
    );
    reg.add(
        "mu(dofs)",
        "A motion unit from a record {name: dof_or_interval, …}; DOF order is the record's order.",
        |a, _| {
            let arg = a.arg("dofs")?;
            let Value::Record(r) = &arg.value else {
                return Err(a.type_error("dofs", "a record {name: dof_or_interval, …}", &arg));
            };
            let mut m = Mu::new();
            for (name, v) in r.iter() {
                match v.as_object::<Motion>() {
                    Some(Motion::Mu(_)) | None => {
                        return Err(MxError::type_error(format!(
                            "mu: field `{name}` must be an Interval or a Dof, found {}",
                            describe(v)
                        ))
                        .at(arg.span)
                        .help("usage: mu({name: dof_or_interval, …})"));
                    }
                    Some(x) => m.insert(name.clone(), x.as_dof().unwrap_or_default()),
                }
            }
            obj(Motion::Mu(m))
        },
    );
}

/// Moving and cutting motions in time: `affine`, `clip`, `clip_in_place`, `concatenate`, `only`.
fn timing(reg: &mut Registry) {
    reg.topic(Topic::Motion);
    reg.add(
        "affine(ts, d, m)",
        "Time t ↦ ts + d·t (shift by ts, stretch by d > 0); values are those at the pre-image time.",
        |a, _| {
            let ts = a.number("ts")?;
            let d = a.number("d")?;
            let (m, _) = a.motion("m")?;
            map_motion(&m, a.call_span(), None, |x| x.affine(ts, d), |x| motion::affine(ts, d, x))
        },
    );
    reg.add(
        "clip(ts, tf, m)",
        "The part of m inside [ts, tf], moved to start at time 0. [ts, tf] must lie inside m's span.",
        |a, _| {
            let ts = a.number("ts")?;
            let tf = a.number("tf")?;
            let (m, arg) = a.motion("m")?;
            map_motion(&m, a.call_span(), arg.name.as_deref(), |x| motion::ops::clip_dof(ts, tf, x), |x| motion::clip(ts, tf, x))
        },
    );
    reg.add(
        "clip_in_place(ts, tf, m)",
        "The part of m inside [ts, tf], times unchanged. [ts, tf] must lie inside m's span.",
        |a, _| {
            let ts = a.number("ts")?;
            let tf = a.number("tf")?;
            let (m, arg) = a.motion("m")?;
            map_motion(
                &m,
                a.call_span(),
                arg.name.as_deref(),
                |x| motion::ops::clip_in_place_dof(ts, tf, x),
                |x| motion::clip_in_place(ts, tf, x),
            )
        },
    );
    reg.add(
        "concatenate(a, b)",
        "a followed by b, shifted to start where a ends.",
        |a, _| {
            let (x, xa) = a.motion("a")?;
            let (y, ya) = a.motion("b")?;
            match (&x, &y) {
                (Motion::Mu(p), Motion::Mu(q)) => obj(Motion::Mu(motion::concatenate(p, q))),
                (Motion::Mu(_), _) => Err(a.type_error("b", "a Mu (like a)", &ya)),
                (_, Motion::Mu(_)) => Err(a.type_error("a", "a Mu (like b)", &xa)),
                _ => obj(Motion::Dof(
                    x.as_dof()
                        .unwrap_or_default()
                        .concatenate(&y.as_dof().unwrap_or_default()),
                )),
            }
        },
    );
    reg.add(
        "only(m, pattern, ...)",
        "The DOFs of m whose names match any pattern: exact names or globs (`RightArm*`, `Hips.?position`).",
        |a, _| {
            let (m, _) = mu_arg(a, "m")?;
            let pats = a.rest();
            if pats.is_empty() {
                return Err(a.error(ErrorKind::Arity, "only needs at least one name or pattern"));
            }
            let mut strs = Vec::new();
            for p in &pats {
                match &p.value {
                    Value::Str(s) => strs.push(s.to_string()),
                    Value::List(l) => {
                        for x in l.iter() {
                            match x.as_str() {
                                Some(s) => strs.push(s.to_string()),
                                None => return Err(a.type_error("pattern", "a string or a list of strings", p)),
                            }
                        }
                    }
                    _ => return Err(a.type_error("pattern", "a string", p)),
                }
            }
            let refs: Vec<&str> = strs.iter().map(String::as_str).collect();
            obj(Motion::Mu(motion::only(&m, &refs).map_err(|e| motion_error(e, a.call_span()))?))
        },
    );
}

/// The frame time and frame count of the argument `m`.
fn clip_frames(a: &mut Args) -> MxResult<(f64, usize)> {
    let (m, arg) = a.motion("m")?;
    let mu = match m {
        Motion::Mu(x) => x,
        other => Mu::from_iter([("value".to_string(), other.as_dof().unwrap_or_default())]),
    };
    motion::frames(&mu).map_err(|e| motion_error(e, arg.span))?.ok_or_else(|| {
        MxError::new(ErrorKind::Value, "this motion has no frames: none of its DOFs is sampled (made from a clip), or nothing is defined")
            .at(arg.span)
            .help("frames belong to loaded clips and what is made from them; a motion made of functions is sampled at `rate:` where it is saved")
    })
}

/// What a motion is: `dofs`, `span`, `frames`, `frame_time`, `gaps`, `conflicts`, `sample`, `get`.
fn queries(reg: &mut Registry) {
    reg.topic(Topic::Motion);
    reg.add(
        "dofs(m)",
        "The DOF names of a motion unit, in first-definition order.",
        |a, _| {
            let (m, _) = mu_arg(a, "m")?;
            Ok(Value::list(m.names().map(Value::str).collect()))
        },
    );
    reg.add(
        "span(m)",
        "[start, stop] of everything defined in m, or nil if nothing is.",
        |a, _| {
            let (m, _) = a.motion("m")?;
            Ok(span_value(m.span()))
        },
    );
    reg.add(
        "frames(m)",
        "How many frames m has: its span on the grid of its frame time (a loaded clip's frame count; what save and positions write).",
        |a, _| {
            Ok(Value::Number(clip_frames(a)?.1 as f64))
        },
    );
    reg.add(
        "frame_time(m)",
        "Seconds per frame of m (a loaded clip's frame time; 1 / frame_time(m) is its frame rate).",
        |a, _| Ok(Value::Number(clip_frames(a)?.0)),
    );
    reg.add(
        "gaps(m)",
        "Interior gaps (undefined with motion on both sides) as records {dof, start, stop}.",
        |a, _| {
            let (m, _) = a.motion("m")?;
            Ok(match m {
                Motion::Mu(x) => spans_value(motion::gaps(&x)),
                other => spans_value(dof_spans(&other, Dof::gaps)),
            })
        },
    );
    reg.add(
        "conflicts(m)",
        "Multiply defined stretches as records {dof, start, stop}.",
        |a, _| {
            let (m, _) = a.motion("m")?;
            Ok(match m {
                Motion::Mu(x) => spans_value(motion::conflicts(&x)),
                other => spans_value(dof_spans(&other, Dof::conflicts)),
            })
        },
    );
    reg.add(
        "sample(m, t, deriv: 0)",
        "Value of m at time t (deriv 1: velocity, 2: acceleration). An Interval/Dof gives a number; a Mu a record {dof: value}, nil where undefined. Conflicts are errors.",
        |a, _| {
            let (m, _) = a.motion("m")?;
            let t = a.finite("t")?;
            let k = a.count_or("deriv", 0)?;
            let span = a.call_span();
            if k > 2 {
                return Err(a.error(ErrorKind::Value, "deriv is 0 (value), 1 (velocity) or 2 (acceleration)"));
            }
            let pick = |r: Option<[f64; 3]>| r.map(|v| Value::Number(v[k])).unwrap_or(Value::Nil);
            match m {
                Motion::Mu(x) => {
                    let mut r = IndexMap::new();
                    for name in x.names() {
                        r.insert(name.to_string(), pick(x.sample(name, t).map_err(|e| motion_error(e, span))?));
                    }
                    Ok(Value::record(r))
                }
                other => {
                    let d = other.as_dof().unwrap_or_default();
                    match d.sample("value", t).map_err(|e| motion_error(e, span))? {
                        Some(v) => Ok(Value::Number(v[k])),
                        None => Err(motion_error(MotionError::Undefined { dof: "value".into(), t }, span)),
                    }
                }
            }
        },
    );
    reg.add(
        "get(m, name)",
        "The DOF `name` of a motion unit.",
        |a, _| {
            let (m, _) = mu_arg(a, "m")?;
            let n = a.string("name")?;
            let d = m.dof(&n).map_err(|e| motion_error(e, a.call_span()))?;
            obj(Motion::Dof(d.clone()))
        },
    );
}

/// The `.csv` and `.json` motion formats.
fn formats(reg: &mut Registry) {
    reg.saver(
        "csv",
        "Motion CSV: `save(m, \"x.csv\", rate: R)` samples at whole multiples of 1/R (default: the motion's own frame rate, when it is sampled).",
        |v, path, a, ev| {
            let Some(Motion::Mu(m)) = v.as_object::<Motion>() else {
                return Err(a.error(
                    ErrorKind::Type,
                    format!("CSV holds a motion unit (Mu), not {}", describe(v)),
                ));
            };
            let rate = a.opt_named("rate");
            if let Some((n, v)) = a.rest_named().into_iter().next() {
                let e = MxError::new(ErrorKind::Arity, format!("saving CSV has no option `{n}`"))
                    .at(v.span)
                    .label("unknown option");
                return Err(match crate::lang::diagnostics::did_you_mean(&n, ["rate"]) {
                    Some(s) => e.help(format!(
                        "did you mean `{s}`? e.g. `save(m, \"x.csv\", rate: 30)`"
                    )),
                    None => {
                        e.help("the only option is `rate`, e.g. `save(m, \"x.csv\", rate: 30)`")
                    }
                });
            }
            // without `rate`, a motion sampled on a grid (a clip, `ground_forces`) keeps its own
            let own = crate::motion::sample_period(m).map(|dt| 1.0 / dt);
            let rate = match (rate, own) {
                (Some(r), _) => match &r.value {
                    Value::Number(x) => *x,
                    _ => return Err(a.type_error("rate", "a number (Hz)", &r)),
                },
                (None, Some(x)) => x,
                (None, None) => {
                    return Err(a.error(
                        ErrorKind::Arity,
                        "saving CSV needs a sampling rate: `save(m, \"x.csv\", rate: 30)`",
                    ));
                }
            };
            let span = a.call_span();
            crate::io::csv::save_csv_cancellable(m, path, rate, Some(&ev.ctx.cancel))
                .map_err(|e| file_error(e, span))
        },
    );
    reg.loader(
        "csv",
        "Motion CSV as written by `save(m, \"x.csv\", rate: R)`: each run of filled cells becomes sampled data (C² cubic), empty cells stay undefined.",
        |path, a, _| {
            let m = crate::io::csv::load_csv(path).map_err(|e| file_error(e, a.call_span()))?;
            obj(Motion::Mu(m))
        },
    );
    reg.saver(
        "json",
        "Motion JSON (exact round trip; functions stored as mx source).",
        |v, path, a, _| {
            let Some(Motion::Mu(m)) = v.as_object::<Motion>() else {
                return Err(a.error(
                    ErrorKind::Type,
                    format!("motion JSON holds a motion unit (Mu), not {}", describe(v)),
                ));
            };
            crate::io::motion_json::save_json(m, path).map_err(|e| file_error(e, a.call_span()))
        },
    );
    reg.loader(
        "json",
        "Motion JSON written by `save(m, \"x.json\")`.",
        |path, a, ev| {
            let ctx = ev.ctx.clone();
            let compile_fn =
                move |src: &str| compile(src, &ctx).map_err(crate::io::ContentError::new);
            let m = crate::io::motion_json::load_json(path, &compile_fn)
                .map_err(|e| file_error(e, a.call_span()))?;
            obj(Motion::Mu(m))
        },
    );
}

fn dof_spans(m: &Motion, f: fn(&Dof) -> Vec<(f64, f64)>) -> Vec<motion::DofSpan> {
    f(&m.as_dof().unwrap_or_default())
        .into_iter()
        .map(|(start, stop)| motion::DofSpan {
            dof: "value".into(),
            start,
            stop,
        })
        .collect()
}
