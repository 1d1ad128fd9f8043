//! The animator's operators: `blend`, `crossfade`, `align`, `layer`, `mask`,
//! `mirror`, `reverse` (motions and lists), `warp`, `resample`,
//! `extrapolate` (behind the prelude's `hold(m, ts, tf)`). The work is
//! done by `crate::motion::compose`; this file converts values and errors.

use std::sync::Arc;

use crate::lang::args::{ArgValue, Args};
use crate::lang::diagnostics::{MxError, MxResult};
use crate::lang::host::errors::{diagnostic, motion_error};
use crate::lang::host::motion::Motion;
use crate::lang::registry::Registry;
use crate::lang::timefn::MxTimeFn;
use crate::lang::topic::Topic;
use crate::lang::value::Value;
use crate::motion::compose::{self, Weight};
use crate::motion::{Dof, Extrapolation, FnError, MotionError, Mu, TimeFunction};

fn mu_arg(a: &mut Args, name: &str) -> MxResult<(Mu, ArgValue)> {
    a.mu(name)
}

/// A compose error with the operator's help line: at the argument the
/// engine names (an out-of-range weight points at `w`), else at `span`.
fn fail(e: MotionError, a: &Args, span: crate::lang::ast::Span, help: &str) -> MxError {
    match e {
        MotionError::Compose { .. } | MotionError::InvalidOption { .. } => {
            diagnostic(&e, a, span).help(help.to_string())
        }
        other => motion_error(other, span),
    }
}

/// A DOF as a function of time (sampled data used as a warp).
#[derive(Debug)]
struct DofFn(Dof);

impl TimeFunction for DofFn {
    fn eval(&self, t: f64) -> Result<f64, FnError> {
        match self.0.sample("warp", t) {
            Ok(Some(v)) => Ok(v[0]),
            Ok(None) => Err(FnError::Host(format!(
                "the warp's data is not defined at t = {t}"
            ))),
            Err(e) => Err(e.into()),
        }
    }
}

/// A number or function of time as a weight; the engine checks it lies in
/// [0, 1] (its error names `w`, so the diagnostic points here).
fn weight(a: &Args, arg: &ArgValue, ev: &crate::lang::eval::Evaluator) -> MxResult<Weight> {
    match &arg.value {
        Value::Number(w) => Ok(Weight::Const(*w)),
        v if v.is_callable() => Ok(Weight::Func(Arc::new(MxTimeFn::new(
            v.clone(),
            ev.ctx.clone(),
        )))),
        _ => Err(a.type_error("w", "a number in [0, 1] or a function of time", arg)),
    }
}

/// The up axis of a named `up:` option ("y" default, or "z").
fn up_axis(a: &mut Args) -> MxResult<usize> {
    match a.opt_named("up") {
        None => Ok(1),
        Some(arg) => match arg.value.as_str() {
            Some("y") => Ok(1),
            Some("z") => Ok(2),
            _ => Err(MxError::value("up must be \"y\" or \"z\"")
                .at(arg.span)
                .label("unknown up axis")
                .help("BVH clips are y-up (the default); OpenSim and robot models are often z-up")),
        },
    }
}

/// The animator's operators.
pub fn register(reg: &mut Registry) {
    mixing(reg);
    reshaping(reg);
}

/// Mixing two motions: `blend`, `crossfade`, `align`, `layer`, `mask`.
fn mixing(reg: &mut Registry) {
    reg.topic(Topic::Motion);
    reg.add(
        "blend(a, b, w)",
        "a mixed toward b by w (a number in [0, 1] or a function of time): joint rotations slerped as unit quaternions \
         and written back as continuous Euler channels in each joint's order, other DOFs linear. Defined where both are; \
         where only one is defined, that one. The result is sampled at the inputs' finest sample step (120 Hz if none).",
        |a, ev| {
            let (x, _) = mu_arg(a, "a")?;
            let (y, _) = mu_arg(a, "b")?;
            let warg = a.arg("w")?;
            let w = weight(a, &warg, ev)?;
            compose::blend(&x, &y, &w).map(|m| Value::object(Motion::Mu(m))).map_err(|e| {
                fail(e, a, a.call_span(), "blend needs DOFs both motions name (`dofs(m)` lists them) and a weight in [0, 1]: 0 gives the first motion, 1 the second; a function of time `fn(t) = …` may vary in between")
            })
        },
    );
    reg.add(
        "crossfade(a, b, d, up: \"y\")",
        "a followed by b, overlapping by d seconds: b starts at a's end minus d, moved in the ground plane so its root \
         continues from a's root position and heading there (see align), and the overlap blends from a to b with a \
         smoothstep weight, so value and velocity are continuous at both ends of the overlap.",
        |a, _| {
            let (x, _) = mu_arg(a, "a")?;
            let (y, _) = mu_arg(a, "b")?;
            let darg = a.arg("d")?;
            let Value::Number(d) = darg.value else {
                return Err(a.type_error("d", "a duration in seconds", &darg));
            };
            let up = up_axis(a)?;
            compose::crossfade(&x, &y, d, up).map(|m| Value::object(Motion::Mu(m))).map_err(|e| {
                fail(e, a, darg.span, "the overlap must be positive and fit inside both motions; `span(m)` gives their spans")
            })
        },
    );
    reg.add(
        "align(a, b, up: \"y\")",
        "b moved rigidly in the ground plane (x–z for y-up bodies, x–y with up: \"z\") so that its first root position \
         and heading equal a's last. The root is the first joint with position channels.",
        |a, _| {
            let (x, _) = mu_arg(a, "a")?;
            let (y, _) = mu_arg(a, "b")?;
            let up = up_axis(a)?;
            compose::align(&x, &y, up)
                .map(|m| Value::object(Motion::Mu(m)))
                .map_err(|e| fail(e, a, a.call_span(), "both motions need root position channels (`Hips.Xposition` …)"))
        },
    );
    reg.add(
        "layer(base, delta, w: 1, reference: m)",
        "Additive animation: delta's change from a reference pose (default: delta's first frame; reference: m uses m's \
         first frame) composed onto base, scaled by w in [0, 1]: each joint rotation base·(ref⁻¹·delta)^w, each other \
         DOF base + w·(delta − ref). Where delta is undefined, base.",
        |a, _| {
            let (base, _) = mu_arg(a, "base")?;
            let (delta, _) = mu_arg(a, "delta")?;
            let w = a.named_number_or("w", 1.0)?;
            let reference = match a.opt_named("reference") {
                Some(r) => match r.value.as_object::<Motion>() {
                    Some(Motion::Mu(m)) => Some(m.clone()),
                    _ => return Err(a.type_error("reference", "a motion unit (its first frame is the reference pose)", &r)),
                },
                None => None,
            };
            compose::layer(&base, &delta, w, reference.as_ref())
                .map(|m| Value::object(Motion::Mu(m)))
                .map_err(|e| fail(e, a, a.call_span(), "w lies in [0, 1]; base and delta need DOFs in common"))
        },
    );
    reg.add(
        "mask(m, pattern, w)",
        "m with the DOFs matching pattern (a name, glob or list of them) scaled toward their reference pose (m's first \
         frame) by w in [0, 1]: w = 1 keeps their motion, w = 0 holds them at the reference; rotations as \
         quaternions. With blend, a partial-body blend: blend(a, b, 1) restricted by mask.",
        |a, _| {
            let (m, _) = mu_arg(a, "m")?;
            let parg = a.arg("pattern")?;
            let pats: Vec<String> = match &parg.value {
                Value::Str(s) => vec![s.to_string()],
                Value::List(l) => l.iter().filter_map(|x| x.as_str().map(str::to_string)).collect(),
                _ => return Err(a.type_error("pattern", "a DOF name or glob, or a list of them", &parg)),
            };
            let warg = a.arg("w")?;
            let Value::Number(w) = warg.value else {
                return Err(a.type_error("w", "a number in [0, 1]", &warg));
            };
            let refs: Vec<&str> = pats.iter().map(String::as_str).collect();
            compose::mask(&m, &refs, w)
                .map(|m| Value::object(Motion::Mu(m)))
                .map_err(|e| fail(e, a, parg.span, "w lies in [0, 1]"))
        },
    );
}

/// Reshaping one motion: `mirror`, `reverse`, `warp`, `resample`.
fn reshaping(reg: &mut Registry) {
    reg.topic(Topic::Motion);
    reg.add(
        "mirror(m, axis: \"x\")",
        "m with left and right swapped by name (`Left…`/`Right…`, `…_L`/`…_R`, `L…`/`R…` + capital) and reflected in \
         the plane normal to axis: positions along it and rotations about the other two axes change sign. Twice is \
         the identity.",
        |a, _| {
            let (m, marg) = mu_arg(a, "m")?;
            let axis = match a.opt_named("axis") {
                None => 0,
                Some(arg) => match arg.value.as_str() {
                    Some("x") => 0,
                    Some("y") => 1,
                    Some("z") => 2,
                    _ => {
                        return Err(MxError::value("axis must be \"x\", \"y\" or \"z\"")
                            .at(arg.span)
                            .label("unknown axis")
                            .help("the axis normal to the mirror plane: \"x\" for BVH clips facing z"));
                    }
                },
            };
            compose::mirror(&m, axis)
                .map(|m| Value::object(Motion::Mu(m)))
                .map_err(|e| fail(e, a, marg.span, "mirror needs joint names with sides, like LeftArm/RightArm or Arm_L/Arm_R"))
        },
    );
    reg.topic(Topic::Language);
    reg.add(
        "reverse(xs)",
        "A list in reverse order; a motion unit played backwards over its own span (t ↦ start + stop − t, \
         velocities negated; twice is the identity).",
        |a, _| {
            let arg = a.arg("xs")?;
            match (&arg.value, arg.value.as_object::<Motion>()) {
                (Value::List(xs), _) => Ok(Value::list(xs.iter().rev().cloned().collect())),
                (_, Some(Motion::Mu(m))) => compose::reverse(m)
                    .map(|m| Value::object(Motion::Mu(m)))
                    .map_err(|e| motion_error(e, arg.span)),
                _ => Err(a.type_error("xs", "a list or a motion unit (Mu)", &arg)),
            }
        },
    );
    reg.topic(Topic::Motion);
    reg.add(
        "warp(m, f)",
        "m played on the clock f: warp(m, f)(t) = m(f(t)), for f a strictly increasing function of time or an \
         Interval/Dof of sampled times. Defined where f(t) falls in m's span; an error names the time where f is not \
         increasing. warp(m, fn(t) = t / 2) plays m at half speed.",
        |a, ev| {
            let (m, _) = mu_arg(a, "m")?;
            let farg = a.arg("f")?;
            let f: Arc<dyn TimeFunction> = match (&farg.value, farg.value.as_object::<Motion>()) {
                (v, _) if v.is_callable() => Arc::new(MxTimeFn::new(v.clone(), ev.ctx.clone())),
                (_, Some(x)) if x.as_dof().is_some() => Arc::new(DofFn(x.as_dof().unwrap_or_default())),
                _ => return Err(a.type_error("f", "a function of time or an Interval/Dof", &farg)),
            };
            compose::warp(&m, f)
                .map(|m| Value::object(Motion::Mu(m)))
                .map_err(|e| fail(e, a, farg.span, "a time warp must be strictly increasing over the whole motion"))
        },
    );
    reg.add(
        "extrapolate(m, ts, tf, mode)",
        "m extended to [ts, tf] (and cut to it): mode \"hold\" holds each DOF's first value before its span and its last \
         after; \"loop\" repeats m periodically (period: m's span; seamless where m is cyclic, see cyclify; drifting DOFs \
         replay rather than continue, unlike loop(m, n)). The chain forms are hold(m, ts, tf) and loop(m, ts, tf); \
         extrapolation is always to a finite span, so the result samples, plots and composes like any motion.",
        |a, _| {
            let (m, marg) = mu_arg(a, "m")?;
            let ts = a.finite("ts")?;
            let tf = a.finite("tf")?;
            let mode_arg = a.arg("mode")?;
            let mode = match mode_arg.value.as_str() {
                Some("hold") => Extrapolation::Hold,
                Some("loop") => Extrapolation::Loop,
                _ => {
                    return Err(MxError::value("mode must be \"hold\" or \"loop\"")
                        .at(mode_arg.span)
                        .label("unknown mode")
                        .help("\"hold\": first/last pose held; \"loop\": periodic"));
                }
            };
            crate::motion::extrapolate(&m, ts, tf, mode)
                .map(|m| Value::object(Motion::Mu(m)))
                .map_err(|e| fail(e, a, marg.span, "extrapolate to a finite span [ts, tf] with ts < tf"))
        },
    );
    reg.add(
        "resample(m, rate)",
        "m with every interval of every DOF sampled at rate Hz and replaced by the C² spline through the samples.",
        |a, _| {
            let (m, _) = mu_arg(a, "m")?;
            let rarg = a.arg("rate")?;
            let Value::Number(rate) = rarg.value else {
                return Err(a.type_error("rate", "a rate in Hz", &rarg));
            };
            compose::resample(&m, rate)
                .map(|m| Value::object(Motion::Mu(m)))
                .map_err(|e| diagnostic(&e, a, rarg.span))
        },
    );
}
