//! Spacetime built-ins (Rose et al. 1996): `SP`, `sp_report`, `fill`,
//! `torque_energy`, `cyclify`, `loop`. The work is done by `crate::spacetime`;
//! this file checks options (errors point at the argument), converts values
//! and errors, shows a progress bar for long solves and passes the
//! interpreter's cancellation token to the solver (Ctrl-C in the REPL).

use std::sync::Arc;

use crate::lang::args::{ArgValue, Args};
use crate::lang::ast::Span;
use crate::lang::busy::Busy;
use crate::lang::diagnostics::{ErrorKind, MxError, MxResult};
use crate::lang::eval::Evaluator;
use crate::lang::host::errors::diagnostic;
use crate::lang::host::motion::{Provenance, provenance, skeleton_of};
use crate::lang::host::sp_report::report_of;
use crate::lang::host::{LibraryValue, Motion, SpReportValue};
use crate::lang::registry::Registry;
use crate::lang::topic::Topic;
use crate::lang::value::Value;
use crate::library::Library;
use crate::model::Model;
use crate::motion::Mu;
use crate::motion::cyclify::{CyclifyOptions, cyclify, floor_drift, loop_motion};
use crate::spacetime::contact::GivenStance;
use crate::spacetime::reference::LibrarySource;
use crate::spacetime::sp::SP_OPTIONS;
use crate::spacetime::{
    Contact, Continuity, Prior, Progress, ProgressEvent, RootFill, SpError, SpOptions, Support,
    Tally, fill_hermite, sp, torque_energy,
};
use nalgebra::Vector3;

/// Methods `fill(m, method)` knows.
const FILL_METHODS: [&str; 3] = ["hermite", "slerp", "linear"];

/// SP's errors through the one engine-error mapping: an invalid option
/// points at the argument that gave it.
fn sp_error(e: SpError, a: &Args, span: Span) -> MxError {
    diagnostic(&e, a, span)
}

fn mu_arg(a: &mut Args, name: &str) -> MxResult<(Mu, ArgValue)> {
    a.mu(name)
}

fn body_arg(a: &mut Args) -> MxResult<Arc<Model>> {
    let arg = a.arg("body")?;
    let body = a.free_body_of(
        "body",
        &arg,
        "a body whose coordinates are the motion's DOFs, e.g. body_of(clip)",
    )?;
    Ok(body.model)
}

fn vec3(a: &Args, arg: &ArgValue, name: &str) -> MxResult<nalgebra::Vector3<f64>> {
    a.vector3(arg, name)
}

fn bad_option(a: &Args, arg: &ArgValue, msg: String, help: &str) -> MxError {
    MxError::value(format!("`{}`: {msg}", a.name()))
        .at(arg.span)
        .label("this option")
        .help(help.to_string())
}

/// [`bad_option`] for an option of `SP`, with the engine's one text of what
/// it takes ([`SpOptions::help`]).
fn bad_sp_option(a: &Args, arg: &ArgValue, option: &str, msg: String) -> MxError {
    bad_option(a, arg, msg, SpOptions::help(option).unwrap_or_default())
}

/// A whole number given as the named option `name` (its range is the
/// engine's to check: `SpOptions::check`).
fn whole(a: &mut Args, name: &str) -> MxResult<Option<usize>> {
    let Some(arg) = a.opt_named(name) else {
        return Ok(None);
    };
    match arg.value {
        // (a huge number saturates, and the engine's range check reports it)
        Value::Number(x) if x.fract() == 0.0 && x >= 0.0 => Ok(Some(x as usize)),
        _ => Err(a.type_error(name, "a whole number", &arg)),
    }
}

fn continuity(a: &mut Args) -> MxResult<Continuity> {
    let Some(arg) = a.opt_named("continuity") else {
        return Ok(Continuity::C1);
    };
    match arg.value {
        Value::Number(x) if x == 1.0 || x == 2.0 => {
            Ok(Continuity::from_order(x as i64)
                .map_err(|e| bad_option(a, &arg, e.to_string(), ""))?)
        }
        _ => Err(bad_sp_option(
            a,
            &arg,
            "continuity",
            format!("`continuity:` must be 1 or 2, found {}", arg.value.repr()),
        )),
    }
}

/// `support: ["LeftFoot", …]` (frames the body names; the engine checks
/// them), `[]` (none) or `"auto"`.
fn support(a: &mut Args) -> MxResult<Support> {
    let Some(arg) = a.opt_named("support") else {
        return Ok(Support::default());
    };
    match &arg.value {
        Value::Str(s) if &**s == "auto" => Ok(Support::default()),
        Value::List(items) if items.is_empty() => Ok(Support::Off),
        Value::List(_) => Ok(Support::Named(frame_names(a, &arg, "support")?)),
        _ => Err(a.type_error(
            "support",
            "a list of frame names like [\"LeftFoot\"], [] for none, or \"auto\"",
            &arg,
        )),
    }
}

/// The strings of the list option `name`.
fn frame_names(a: &Args, arg: &ArgValue, name: &str) -> MxResult<Vec<String>> {
    let items = arg.value.as_list().unwrap_or_default();
    items
        .iter()
        .map(|v| {
            v.as_str()
                .map(str::to_string)
                .ok_or_else(|| a.type_error(name, "a list of frame names (strings)", arg))
        })
        .collect()
}

/// The stances of `contact: [{point, from, to, at}, …]` or of a capture's
/// `contacts(m, body)` record (`{points: {NAME: [{start, stop}, …]}}`).
fn given_stances(a: &Args, arg: &ArgValue) -> MxResult<Vec<GivenStance>> {
    let want = "a list of records {point: \"Toes_L\", from: t0, to: t1, at: [x, y, z] (optional)}, or contacts(capture, body)";
    let bad = |msg: String| bad_option(a, arg, msg, want);
    let num = |r: &indexmap::IndexMap<String, Value>, k: &str, what: &str| -> MxResult<f64> {
        r.get(k)
            .and_then(Value::as_number)
            .ok_or_else(|| bad(format!("{what} needs a number `{k}:` (s)")))
    };
    let at =
        |r: &indexmap::IndexMap<String, Value>, what: &str| -> MxResult<Option<Vector3<f64>>> {
            let Some(v) = r.get("at") else {
                return Ok(None);
            };
            let xs: Option<Vec<f64>> = match v {
                Value::List(items) => items.iter().map(Value::as_number).collect(),
                _ => None,
            };
            match xs.as_deref() {
                Some([x, y, z]) => Ok(Some(Vector3::new(*x, *y, *z))),
                _ => Err(bad(format!("{what}: `at:` needs a position [x, y, z] (m)"))),
            }
        };
    match &arg.value {
        Value::List(items) => items
            .iter()
            .enumerate()
            .map(|(i, v)| {
                let what = format!("stance {}", i + 1);
                let r = v
                    .as_record()
                    .ok_or_else(|| bad(format!("{what} is a {}, not a record", v.type_name())))?;
                let point = r
                    .get("point")
                    .and_then(|p| p.as_str())
                    .ok_or_else(|| bad(format!("{what} needs `point:` (a link's name)")))?;
                Ok(GivenStance {
                    point: point.to_string(),
                    from: num(r, "from", &what)?,
                    to: num(r, "to", &what)?,
                    at: at(r, &what)?,
                })
            })
            .collect(),
        Value::Record(r) => {
            let points = r
                .get("points")
                .and_then(Value::as_record)
                .ok_or_else(|| bad("a record needs `points:` as contacts() gives".into()))?;
            let mut out = vec![];
            for (name, ivs) in points {
                let Value::List(ivs) = ivs else {
                    return Err(bad(format!("points.{name} needs a list of intervals")));
                };
                for iv in ivs.iter() {
                    let what = format!("points.{name}");
                    let r = iv.as_record().ok_or_else(|| {
                        bad(format!("{what}: an interval is a record {{start, stop}}"))
                    })?;
                    out.push(GivenStance {
                        point: name.clone(),
                        from: num(r, "start", &what)?,
                        to: num(r, "stop", &what)?,
                        at: at(r, &what)?,
                    });
                }
            }
            Ok(out)
        }
        _ => Err(bad("not a list or a record".into())),
    }
}

/// `contact: "auto"` (the default: the body stands where it can), `"none"`
/// (Rose's supports alone), `"auto"` (a
/// stance schedule planned per gap for the frames near the floor, held by the
/// support IK with the floor below), `["Toes_L", …]` (those frames), or the
/// stances themselves: `[{point, from, to, at}, …]` or `contacts(capture, b)`.
/// Planning replaces `support:`: the engine rejects the two together.
fn contact(a: &mut Args) -> MxResult<Contact> {
    let Some(arg) = a.opt_named("contact") else {
        return Ok(Contact::default());
    };
    match &arg.value {
        Value::Str(s) if &**s == "none" => Ok(Contact::None),
        Value::Str(s) if &**s == "auto" => Ok(Contact::Auto),
        Value::List(items) if !items.is_empty() && items.iter().all(|v| v.as_str().is_some()) => {
            Ok(Contact::Named(frame_names(a, &arg, "contact")?))
        }
        Value::List(items) if !items.is_empty() => Ok(Contact::Given(given_stances(a, &arg)?)),
        Value::Record(_) => Ok(Contact::Given(given_stances(a, &arg)?)),
        _ => Err(a.type_error(
            "contact",
            "\"none\", \"auto\", a list of frame names like [\"Toes_L\"], a list of stances [{point: \"Toes_L\", from: 2.1, to: 2.5}] or contacts(capture, body)",
            &arg,
        )),
    }
}

/// `floor: h`: the floor's height (m, along −gravity) for `contact:`.
fn floor(a: &mut Args) -> MxResult<Option<f64>> {
    let Some(arg) = a.opt_named("floor") else {
        return Ok(None);
    };
    match arg.value {
        Value::Number(h) => Ok(Some(h)),
        Value::Str(ref s) if &**s == "auto" => Ok(None),
        _ => Err(bad_sp_option(
            a,
            &arg,
            "floor",
            format!(
                "`floor:` must be a height in metres or \"auto\", found {}",
                arg.value.repr()
            ),
        )),
    }
}

/// `root: "auto"` (the default: pinned inside one recording, shifted between
/// two), `"shift"` (Rose's) or `"pinned"` (the frames after the gap stay put).
fn root_fill(a: &mut Args) -> MxResult<RootFill> {
    let Some(arg) = a.opt_named("root") else {
        return Ok(RootFill::default());
    };
    match arg.value.as_str() {
        Some("auto") => Ok(RootFill::Auto),
        Some("shift") => Ok(RootFill::Shift),
        Some("pinned") => Ok(RootFill::Pinned),
        _ => Err(bad_sp_option(
            a,
            &arg,
            "root",
            format!(
                "`root:` must be \"auto\", \"shift\" or \"pinned\", found {}",
                arg.value.repr()
            ),
        )),
    }
}

/// `objective: "effort"` (default: ∫Στ² plus the kinematic prior) or `"torque"`
/// (Rose's ∫Στ² alone), with `smoothness:` (λ) and `time_constant:` (T) of the prior.
/// The clip library in `example: lib` or `example: [lib, "self"]`.
fn library_in(v: &Value) -> Option<Arc<Library>> {
    let is_lib = |v: &Value| v.as_object::<LibraryValue>().map(|l| l.0.clone());
    match v.as_list() {
        Some(l)
            if l.iter()
                .all(|v| v.as_str() == Some("self") || is_lib(v).is_some()) =>
        {
            let libs: Vec<_> = l.iter().filter_map(is_lib).collect();
            (libs.len() == 1).then(|| libs[0].clone())
        }
        Some(_) => None,
        None => is_lib(v),
    }
}

fn prior(a: &mut Args, library: &mut Option<Arc<Library>>) -> MxResult<Prior> {
    let mut p = Prior::default();
    if let Some(arg) = a.opt_named("objective") {
        match arg.value.as_str() {
            Some("effort") => {}
            Some("torque") => p = Prior::none(),
            _ => {
                return Err(bad_sp_option(
                    a,
                    &arg,
                    "objective",
                    format!(
                        "`objective:` must be \"effort\" or \"torque\", found {}",
                        arg.value.repr()
                    ),
                ));
            }
        }
    }
    // the ranges of smoothness: and time_constant: are the engine's (`Prior::check`)
    if let Some(arg) = a.opt_named("smoothness") {
        match arg.value {
            Value::Number(x) => p.smoothness = x,
            _ => return Err(a.type_error("smoothness", "a non-negative number", &arg)),
        }
    }
    if let Some(arg) = a.opt_named("time_constant") {
        match arg.value {
            Value::Str(ref t) if &**t == "auto" => p.time_constant = None,
            Value::Number(x) => p.time_constant = Some(x),
            _ => {
                return Err(bad_sp_option(
                    a,
                    &arg,
                    "time_constant",
                    format!(
                        "`time_constant:` must be a positive time or \"auto\", found {}",
                        arg.value.repr()
                    ),
                ));
            }
        }
    }
    if let Some(arg) = a.opt_named("example") {
        match arg.value.as_str() {
            Some("self") => p.example = true,
            Some("none") => p.example = false,
            // a library (`example: lib`, `[lib, "self"]`): `library_option` reads it
            _ if let Some(lib) = library_in(&arg.value) => {
                p.example = arg
                    .value
                    .as_list()
                    .is_some_and(|l| l.iter().any(|v| v.as_str() == Some("self")));
                *library = Some(lib);
            }
            _ => {
                return Err(bad_sp_option(
                    a,
                    &arg,
                    "example",
                    format!(
                        "`example:` must be \"self\", \"none\", a clip library or [library, \"self\"], found {}",
                        arg.value.repr()
                    ),
                ));
            }
        }
    }
    Ok(p)
}

fn sp_options(a: &mut Args, ev: &Evaluator, (m, marg): (&Mu, &ArgValue)) -> MxResult<SpOptions> {
    let mut o = SpOptions::default();
    // ranges are the engine's to check (`SpOptions::check`), which names the
    // option at fault; here only the types
    o.settings.continuity = continuity(a)?;
    if let Some(n) = whole(a, "coefficients")? {
        o.settings.coefficients = n;
    }
    if let Some(n) = whole(a, "samples")? {
        o.settings.samples = n;
    }
    if let Some(n) = whole(a, "iterations")? {
        o.solve.max_iters = n as u64;
    }
    if let Some(arg) = a.opt_named("tolerance") {
        match arg.value {
            Value::Number(x) => o.solve.tolerance = x,
            _ => return Err(a.type_error("tolerance", "a number in (0, 1)", &arg)),
        }
    }
    if let Some(g) = a.opt_named("gravity") {
        o.gravity = Some(vec3(a, &g, "gravity")?);
    }
    // an explicit `contact: "auto"` beside a `support:` asks for both; the
    // default contact gives way to a stated support (Rose's, not standing)
    let (contact_given, support_given) = (a.has_named("contact"), a.has_named("support"));
    o.support = support(a)?;
    o.contact = contact(a)?;
    let explicit_auto = contact_given && o.contact == Contact::Auto;
    // stated, it stands a given root too (see GroundSettings::stand_root_given)
    o.ground.stand_root_given = contact_given;
    if explicit_auto && support_given && o.support != Support::default() {
        let span = a.span_of("contact").unwrap_or(a.call_span());
        return Err(sp_error(SpError::ContactReplacesSupport, a, span));
    }
    o.floor = floor(a)?;
    o.root = root_fill(a)?;
    let mut library = None;
    o.prior = prior(a, &mut library)?;
    if let Some(library) = library {
        // the gap's features are read through the skeleton m drives
        let clip = skeleton_of(&marg.value, m, ev).ok_or_else(|| {
            MxError::new(
                ErrorKind::Value,
                "`example: lib` needs the skeleton m drives, and no loaded clip's skeleton names all its DOFs",
            )
            .at(marg.span)
            .help("load the .bvh the motion came from first")
        })?;
        o.library = Some(LibrarySource {
            library,
            skeleton: clip.skeleton.clone(),
            metres_per_unit: clip.metres_per_unit,
        });
    }
    o.solve.cancel = ev.ctx.cancel.clone();
    Ok(o)
}

fn run_sp(a: &mut Args, ev: &mut Evaluator) -> MxResult<Value> {
    let (m, marg) = mu_arg(a, "m")?;
    let model = body_arg(a)?;
    let mut opts = sp_options(a, ev, (&m, &marg))?;
    let busy = Busy::start(
        "SP",
        "{spinner} {prefix} [{elapsed}] {bar:30} {msg} (Ctrl-C cancels)",
    );
    let bar = busy.bar().clone();
    // within a group: its continuation's solve, the iteration and the evaluations
    let tally = Arc::new(Tally::default());
    opts.solve.progress = Progress::new(move |e| {
        if let ProgressEvent::Groups(n) = e {
            bar.set_length(n as u64);
        }
        if tally.record(e) {
            bar.set_position(tally.done());
            bar.set_message(tally.message());
        }
    });
    let result = sp(&m, &model, &opts);
    drop(busy);
    // A cancelled solve returns no motion at all, never a partly solved one.
    ev.check_cancel(a.call_span())?;
    let (filled, report) = result.map_err(|e| {
        let span = if matches!(e, SpError::Conflict { .. }) {
            marg.span
        } else {
            a.call_span()
        };
        sp_error(e, a, span)
    })?;
    // a solve cut short is no result to pass off as one: say so where the user looks
    for g in report.groups.iter().filter(|g| !g.converged()) {
        eprintln!(
            "warning: SP gap [{:.4}, {:.4}] s ({} DOFs) did not converge: {} (|∇e| {:.3e}); raise iterations: or check the gap",
            g.t0,
            g.t1,
            g.coords.len(),
            g.stop,
            g.grad_norm
        );
    }
    for u in &report.unplanned {
        eprintln!(
            "warning: SP plans no foot on the ground over [{:.4}, {:.4}] s ({:.2} s in the air); give contact: stances there if the body stands",
            u.t0,
            u.t1,
            u.t1 - u.t0
        );
    }
    // The result keeps the input's clip (to save it as BVH) and carries the report.
    Ok(Motion::Mu(filled).with_provenance(Provenance {
        clip: provenance(&marg.value).and_then(|p| p.clip.clone()),
        sp_report: Some(Arc::new(report)),
        ..Provenance::default()
    }))
}

fn run_cyclify(a: &mut Args, ev: &mut Evaluator) -> MxResult<Value> {
    let (m, _) = mu_arg(a, "m")?;
    let ts = a.finite("t_start")?;
    let te = a.finite("t_end")?;
    let mut opts = CyclifyOptions {
        // BVH clips are y up: a walk advances in the floor plane x–z.
        drift: floor_drift(&m),
        ..Default::default()
    };
    if let Some(arg) = a.opt_named("drift") {
        let Some(list) = arg.value.as_list() else {
            return Err(a.type_error("drift", "a list of DOF names", &arg));
        };
        let mut names = vec![];
        for v in list {
            match v.as_str() {
                Some(n) if m.get(n).is_some() => names.push(n.to_string()),
                Some(n) => {
                    return Err(bad_option(
                        a,
                        &arg,
                        format!("`drift:` names `{n}`, which is not a DOF of the motion"),
                        "`dofs(m)` lists the DOF names",
                    ));
                }
                None => return Err(a.type_error("drift", "a list of DOF names", &arg)),
            }
        }
        opts.drift = names;
    }
    if let Some(arg) = a.opt_named("knot_spacing") {
        match arg.value {
            Value::Number(x) if x.is_finite() && x > 0.0 => opts.knot_spacing = x,
            _ => {
                return Err(bad_option(
                    a,
                    &arg,
                    "`knot_spacing:` must be a positive number of seconds".into(),
                    "detail finer than this is smoothed (default 1/30 s)",
                ));
            }
        }
    }
    ev.check_cancel(a.call_span())?;
    let busy = Busy::start("cyclify", "{spinner} {prefix} [{elapsed}]");
    let r = cyclify(&m, ts, te, &opts);
    drop(busy);
    let (out, _) = r.map_err(|e| sp_error(e.into(), a, a.call_span()))?;
    Ok(Value::object(Motion::Mu(out)))
}

/// `SP(…)`'s usage line: its two arguments, then every option of
/// [`SP_OPTIONS`] with its default.
fn sp_signature() -> String {
    let options: Vec<String> = SP_OPTIONS
        .iter()
        .map(|o| format!("{}: {}", o.name, o.default))
        .collect();
    format!("SP(m, body: b, {})", options.join(", "))
}

/// `:help SP`: what SP does, then each option in the engine's one text of it
/// ([`SP_OPTIONS`], the help under an option's error too).
fn sp_doc() -> String {
    let options: Vec<String> = SP_OPTIONS
        .iter()
        .map(|o| format!("{}: {}.", o.name, o.help))
        .collect();
    format!(
        "Spacetime transitions (Rose et al. 1996): every interior gap of every DOF of m is filled with the cubic \
         B-spline minimising ∫Στ² dt (joint torques of `body`, whose coordinates must be m's DOFs, e.g. body_of(clip)); \
         the root moves kinematically; position and velocity (continuity: 2: also acceleration) match at both gap ends. \
         {} \
         Translation DOFs constant on both sides (bone offsets) stay constant. Gaps at the start or end stay undefined; a conflict is an error. \
         sp_report(result) tells what was done. Ctrl-C cancels.",
        options.join(" ")
    )
}

pub fn register(reg: &mut Registry) {
    reg.topic(Topic::Spacetime);
    reg.add(&sp_signature(), &sp_doc(), run_sp);
    reg.add(
        "sp_report(m)",
        "What SP did to produce m: `groups` (per gap group: dofs, t0, t1, method, unknowns, iterations, evaluations, \
         initial_energy (∫Στ² of the Hermite start), energy (∫Στ² of the result), grad_norm, stop = why the solver \
         stopped, converged (false: stopped short, also warned on stderr), prior_scale (the factor the prior ended at), example (the stretch followed, or nil: source \"self\"/\"library\", clip, time, warp, from–to (s, the stretch on its own clock), shift, mismatch (ρ), end_distance_start/end_distance_end (m, mean joint distance of its laid poses to the gap's end states), end_angle, dofs), no_example (why none, or nil), tried (each source asked: {source, mismatch} or {source, why}), \
         solves, seconds), `root` (t0, t1, shift applied to the motion after each gap), `pinned` (gaps whose root x–z was pinned: t0, t1, auto, \
         mismatch in m between the recorded and the predicted displacement, tolerance), `hermite` (root DOFs filled by \
         Hermite curves), `constant` (bone-offset DOFs held constant: dof, start, stop), `undefined` \
         (DOFs left undefined at the start/end: dof, start, stop), `text`. print shows it as text. Only the motion SP \
         returned has a report (an operation on it makes a new motion).",
        |a, _| {
            let arg = a.arg("m")?;
            match report_of(&arg.value) {
                Some(r) => Ok(Value::object(SpReportValue(r))),
                None => Err(MxError::value(format!(
                    "`sp_report`: {} was not returned by SP, so it has no report",
                    match &arg.name {
                        Some(n) => format!("`{n}`"),
                        None => "this value".into(),
                    }
                ))
                .at(arg.span)
                .label("not a motion SP returned")
                .help("call sp_report on SP's result itself: `let m = SP(x, body: b); print(sp_report(m))`")),
            }
        },
    );
    reg.add(
        "fill(m, method)",
        "m with every interior gap of every DOF filled; method \"hermite\": the cubic Hermite curve between the same \
         end values and velocities (the baseline SP improves on); \"slerp\": the in-betweening literature's \
         interpolation (each joint's rotation slerped as a quaternion between the end poses, written back as \
         continuous Euler channels in the joint's order; every other DOF, root positions included, linear); \"linear\": every DOF, joint rotation channels included, a straight line \
         between the end values. Gaps at the start/end stay undefined; a conflict is an error.",
        |a, _| {
            let (m, marg) = mu_arg(a, "m")?;
            let arg = a.arg("method")?;
            let Some(method) = arg.value.as_str() else {
                return Err(a.type_error("method", "a method name like \"hermite\"", &arg));
            };
            if !FILL_METHODS.contains(&method) {
                return Err(bad_option(
                    a,
                    &arg,
                    format!("unknown fill method `{method}`"),
                    &format!(
                        "known methods: {}",
                        FILL_METHODS.map(|m| format!("\"{m}\"")).join(", ")
                    ),
                ));
            }
            let out = if method == "linear" {
                crate::motion::fill_linear(&m).map_err(|e| {
                    MxError::value(format!("fill: {e}"))
                        .at(marg.span)
                        .help("resolve conflicts first (e.g. a − b) so every DOF has one value")
                })?
            } else if method == "slerp" {
                crate::motion::fill_slerp(&m).map_err(|e| {
                    MxError::value(format!("fill: {e}"))
                        .at(marg.span)
                        .help("resolve conflicts first (e.g. a − b) so every DOF has one value")
                })?
            } else {
                fill_hermite(&m).map_err(|e| sp_error(e, a, marg.span))?
            };
            Ok(Value::object(Motion::Mu(out)))
        },
    );
    reg.add(
        "torque_energy(m, body, gravity: [x, y, z])",
        "∫ Σ τ² dt over m's span: the joint torques of `body` moving as m (root coordinates excluded, as in SP's \
         objective). m must be defined everywhere (fill gaps first) and free of conflicts.",
        |a, _| {
            let (m, marg) = mu_arg(a, "m")?;
            let model = body_arg(a)?;
            let g = match a.opt_named("gravity") {
                Some(g) => Some(vec3(a, &g, "gravity")?),
                None => None,
            };
            let e = torque_energy(&m, &model, g).map_err(|e| sp_error(e, a, marg.span))?;
            Ok(Value::Number(e))
        },
    );
    reg.add(
        "cyclify(m, t_start, t_end, drift: [...], knot_spacing: 1/30)",
        "One cycle of m near [t_start, t_end] made to loop with C² continuity (Rose §3.3): the best-matching pair of \
         times near the marks is found, the remaining jump spread over the cycle, and a cubic B-spline fitted with \
         cyclic constraints. `drift` DOFs keep their advance per cycle (default: every *Xposition and *Zposition DOF, \
         the floor plane of a y-up clip). Use loop(c, n) to repeat it.",
        run_cyclify,
    );
    reg.add(
        "loop(m, n) | loop(m, ts, tf)",
        "A cyclified motion (cyclify(m, ts, te)) played n times back to back; drifting DOFs continue from where the \
         previous cycle ended. loop(m, ts, tf): m repeated periodically over [ts, tf] (extrapolate(m, ts, tf, \"loop\")).",
        |a, _| {
            let (m, marg) = mu_arg(a, "m")?;
            if a.remaining() == 2 {
                let ts = a.finite("ts")?;
                let tf = a.finite("tf")?;
                return crate::motion::extrapolate(&m, ts, tf, crate::motion::Extrapolation::Loop)
                    .map(|m| Value::object(Motion::Mu(m)))
                    .map_err(|e| crate::lang::host::errors::motion_error(e, marg.span));
            }
            let n = a.count("n")?;
            let out = loop_motion(&m, n).map_err(|e| sp_error(e.into(), a, marg.span))?;
            Ok(Value::object(Motion::Mu(out)))
        },
    );
}
