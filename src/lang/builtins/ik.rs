//! Inverse kinematics: `ik` and `ik_report`. The work is done by
//! `crate::ik`; this file converts targets and options and attaches the
//! report to the motion `ik` returns (as SP's travels with SP's result:
//! the value is the motion for every other built-in, and any operation on
//! it makes a new motion, which IK did not produce).

use std::sync::Arc;

use crate::ik::{self, IkOptions, IkReport, Target};
use crate::lang::args::{ArgValue, Args};
use crate::lang::ast::Span;
use crate::lang::diagnostics::{ErrorKind, MxError, MxResult};
use crate::lang::host::body::Body;
use crate::lang::host::errors::diagnostic;
use crate::lang::host::motion::{Motion, Provenance, provenance};
use crate::lang::host::sp_report::{num, record};
use crate::lang::registry::Registry;
use crate::lang::topic::Topic;
use crate::lang::value::{HostObject, Value};
use crate::motion::channel::{Channel, Found, channel_for};
use crate::motion::{Dof, Mu};

/// `ik_report(m)`: reads like a record, prints as text.
#[derive(Clone, Debug)]
struct IkReportValue(Arc<IkReport>);

impl IkReportValue {
    fn text(&self) -> String {
        let r = &self.0;
        let mut s = format!(
            "ik: {} frames over [{}, {}] s, {} DOFs moved, iterations per frame mean {:.2} max {}, {} frames not within {} m",
            r.frames,
            r.span.0,
            r.span.1,
            r.dofs.len(),
            r.mean_iterations,
            r.max_iterations,
            r.unconverged_frames,
            r.tolerance
        );
        for t in &r.targets {
            s.push_str(&format!(
                "\n  {}: residual max {:.3e} m (t = {:.4} s), mean {:.3e} m, {} frames unreachable",
                t.link, t.max_residual, t.worst_time, t.mean_residual, t.unreachable_frames
            ));
            if t.max_orientation_residual > 0.0 {
                s.push_str(&format!(
                    ", orientation within {:.3e} rad",
                    t.max_orientation_residual
                ));
            }
        }
        s
    }
}

impl HostObject for IkReportValue {
    fn type_name(&self) -> &'static str {
        "IkReport"
    }
    fn summary(&self) -> String {
        self.text()
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
    fn field_names(&self) -> &'static [&'static str] {
        &[
            "targets",
            "max",
            "frames",
            "iterations",
            "mean_iterations",
            "unconverged",
            "dofs",
            "tolerance",
            "text",
        ]
    }
    fn read_field(&self, name: &str) -> Option<Value> {
        let r = &self.0;
        Some(match name {
            "targets" => Value::list(
                r.targets
                    .iter()
                    .map(|t| {
                        record(vec![
                            ("link", Value::str(&t.link)),
                            ("max", num(t.max_residual)),
                            ("mean", num(t.mean_residual)),
                            ("unreachable", num(t.unreachable_frames as f64)),
                            ("worst_time", num(t.worst_time)),
                            ("orientation_max", num(t.max_orientation_residual)),
                        ])
                    })
                    .collect(),
            ),
            "max" => num(r.targets.iter().map(|t| t.max_residual).fold(0.0, f64::max)),
            "frames" => num(r.frames as f64),
            "iterations" => num(r.max_iterations as f64),
            "mean_iterations" => num(r.mean_iterations),
            "unconverged" => num(r.unconverged_frames as f64),
            "dofs" => Value::list(r.dofs.iter().map(Value::str).collect()),
            "tolerance" => num(r.tolerance),
            "text" => Value::str(self.text()),
            _ => return None,
        })
    }
}

/// The one DOF of `m` for `axis`: named `axis`, `link.axis` or the one
/// ending in `.axis` ([`channel_for`]).
fn axis_dof(m: &Mu, link: &str, axis: &str, span: Span) -> MxResult<Dof> {
    let names: Vec<&str> = m.names().collect();
    match channel_for(&names, link, axis) {
        Found::One(n) => Ok(m.get(n).cloned().unwrap_or_default()),
        Found::Missing => Err(MxError::value(format!("the target of {link} has no DOF `{axis}` (or `….{axis}`)"))
            .at(span)
            .label("missing a coordinate")
            .help("a target is a motion of the link's world position: DOFs x, y, z (or Link.x, Link.y, Link.z, as positions(m, body) gives)")),
        Found::Several(found) => Err(MxError::value(format!("the target of {link} has several DOFs for `{axis}`: {}", found.join(", ")))
            .at(span)
            .label("ambiguous")
            .help("give one motion per link: {LeftFoot: p} with DOFs x, y, z")),
    }
}

/// A target's optional orientation: DOFs `rx ry rz` (a world rotation
/// vector, radians), all three or none.
fn orientation_dofs(m: &Mu, link: &str, span: Span) -> MxResult<Option<[Dof; 3]>> {
    let names: Vec<&str> = m.names().collect();
    let has = |axis: &str| channel_for(&names, link, axis) != Found::Missing;
    match ["rx", "ry", "rz"].map(has) {
        [false, false, false] => Ok(None),
        [true, true, true] => Ok(Some([
            axis_dof(m, link, "rx", span)?,
            axis_dof(m, link, "ry", span)?,
            axis_dof(m, link, "rz", span)?,
        ])),
        _ => Err(MxError::value(format!(
            "the target of {link} has part of an orientation: give all of rx, ry, rz or none"
        ))
        .at(span)
        .label("incomplete orientation")
        .help("an orientation target is the link frame's world rotation vector (axis × angle, radians) in DOFs rx, ry, rz")),
    }
}

/// Targets from a record `{Link: motion}` or one motion with `Link.x/.y/.z` DOFs.
fn targets_of(a: &Args, arg: &ArgValue) -> MxResult<Vec<Target>> {
    let mk = |link: &str, m: &Mu, span: Span| -> MxResult<Target> {
        Ok(Target {
            link: link.to_string(),
            position: [
                axis_dof(m, link, "x", span)?,
                axis_dof(m, link, "y", span)?,
                axis_dof(m, link, "z", span)?,
            ],
            orientation: orientation_dofs(m, link, span)?,
            weight: 1.0,
        })
    };
    if let Some(rec) = arg.value.as_record() {
        let mut out = vec![];
        for (link, v) in rec.iter() {
            let Some(Motion::Mu(m)) = v.as_object::<Motion>() else {
                return Err(a.type_error(
                    "targets",
                    &format!("a motion (Mu) of {link}'s position for each link"),
                    arg,
                ));
            };
            out.push(mk(link, m, arg.span)?);
        }
        return Ok(out);
    }
    let Some(Motion::Mu(m)) = arg.value.as_object::<Motion>() else {
        return Err(a.type_error(
            "targets",
            "a record {Link: position motion} or a motion with DOFs Link.x, Link.y, Link.z",
            arg,
        ));
    };
    let mut links: Vec<&str> = vec![];
    for n in m.names() {
        let Channel {
            joint: link,
            suffix: Some(axis),
            ..
        } = Channel::parse(n)
        else {
            return Err(MxError::value(format!("target DOF `{n}` is not named Link.x, Link.y or Link.z"))
                .at(arg.span)
                .label("unnamed link")
                .help("a motion of targets names its DOFs Link.x, Link.y, Link.z, as positions(m, body) does"));
        };
        if !matches!(axis, "x" | "y" | "z" | "rx" | "ry" | "rz") {
            return Err(MxError::value(format!(
                "target DOF `{n}` is not a position (.x, .y, .z) or an orientation (.rx, .ry, .rz)"
            ))
            .at(arg.span)
            .label("not x, y or z")
            .help("`only(targets, \"LeftFoot.*\")` keeps one link's position"));
        }
        if !links.contains(&link) {
            links.push(link);
        }
    }
    if links.is_empty() {
        return Err(MxError::value("the targets motion has no DOFs")
            .at(arg.span)
            .label("empty"));
    }
    links
        .iter()
        .map(|l| {
            let sub: Mu = m
                .dofs
                .iter()
                .filter(|(n, _)| {
                    let c = Channel::parse(n);
                    c.suffix.is_some() && c.joint == *l
                })
                .map(|(n, d)| (n.clone(), d.clone()))
                .collect();
            mk(l, &sub, arg.span)
        })
        .collect()
}

/// `only:` as a list of patterns.
fn patterns(a: &Args, arg: &ArgValue) -> MxResult<Vec<String>> {
    match &arg.value {
        Value::Str(s) => Ok(vec![s.to_string()]),
        Value::List(l) => l
            .iter()
            .map(|x| {
                x.as_str().map(str::to_string).ok_or_else(|| {
                    a.type_error("only", "a DOF name or glob, or a list of them", arg)
                })
            })
            .collect(),
        _ => Err(a.type_error("only", "a DOF name or glob, or a list of them", arg)),
    }
}

fn run_ik(a: &mut Args) -> MxResult<Value> {
    let barg = a.arg("body")?;
    let body: Body = a.free_body_of(
        "body",
        &barg,
        "a body (body_of(clip), human(clip), body([...]), load(\"x.urdf\"))",
    )?;
    let (m, marg) = a.mu("m")?;
    let targ = a.arg("targets")?;
    let mut targets = targets_of(a, &targ)?;
    let mut options = IkOptions::default();
    if let Some(w) = a.opt_named("weights") {
        let Some(rec) = w.value.as_record() else {
            return Err(a.type_error("weights", "a record {Link: weight}", &w));
        };
        for (link, v) in rec.iter() {
            let Some(t) = targets.iter_mut().find(|t| t.link == *link) else {
                return Err(MxError::value(format!("weights: {link} has no target"))
                    .at(w.span)
                    .label("no such target")
                    .help("weights are given per target link, by the same names as the targets"));
            };
            t.weight = v
                .as_number()
                .ok_or_else(|| a.type_error("weights", "a record of positive numbers", &w))?;
        }
    }
    if let Some(o) = a.opt_named("only") {
        options.only = Some(patterns(a, &o)?);
    }
    options.settings.tolerance = a.named_number_or("tolerance", options.settings.tolerance)?;
    let iters = a.named_number_or("iterations", options.settings.max_iterations as f64)?;
    if !(iters.is_finite() && iters >= 1.0 && iters.fract() == 0.0) {
        return Err(a.error(
            ErrorKind::Value,
            format!("iterations must be a whole number ≥ 1, got {iters}"),
        ));
    }
    options.settings.max_iterations = iters as usize;
    if let Some(r) = a.opt_named("rate") {
        let Value::Number(rate) = r.value else {
            return Err(a.type_error("rate", "frames per second", &r));
        };
        options.rate = Some(rate);
    }
    let span = a.call_span();
    // the engine names the input at fault (`targets`, `m`, `tolerance`, …)
    let (out, report) =
        ik::ik(&body.model, &m, &targets, &options).map_err(|e| diagnostic(&e, a, span))?;
    if report.unconverged_frames > 0 {
        eprintln!(
            "warning: ik: {} of {} frames not within {} m (largest residual {:.3e} m); ik_report(m) has the details",
            report.unconverged_frames,
            report.frames,
            report.tolerance,
            report
                .targets
                .iter()
                .map(|t| t.max_residual)
                .fold(0.0, f64::max)
        );
    }
    // the input's clip (its skeleton) stays with the result; the report joins it
    let clip = provenance(&marg.value).and_then(|p| p.clip.clone());
    Ok(Motion::Mu(out).with_provenance(Provenance {
        clip,
        ik_report: Some(Arc::new(report)),
        ..Provenance::default()
    }))
}

/// Inverse kinematics.
pub fn register(reg: &mut Registry) {
    reg.topic(Topic::Motion);
    reg.add(
        "ik(body, m, targets, only: pattern, weights: {Link: w}, tolerance: 1e-6, iterations: 50, rate: Hz)",
        "m with each frame moved so that each target link's origin follows its target: targets is a record {Link: p} \
         (p a motion of the world position, DOFs x, y, z) or one motion with DOFs Link.x, Link.y, Link.z (what \
         positions(m, body) gives); a target with DOFs rx, ry, rz too (Link.rx … in one motion) also sets the link \
         frame's world orientation, as a rotation vector (axis × angle, radians; 1 rad counts as 0.1 m). Each frame is solved by damped least squares (Levenberg–Marquardt, adaptive damping) \
         on the analytic joint Jacobians, joint limits respected, warm-started from the previous frame plus m's own \
         change; only: the DOFs it may move (default: all on the targets' chains); weights: per target, when not all can \
         be met. Frames: m's frame rate (or rate:) where m and every target are defined; the moved DOFs are sampled \
         there, the others are m's. An unreachable target gets as close as it can; ik_report(result) says by how much.",
        |a, _| run_ik(a),
    );
    reg.add(
        "ik_report(m)",
        "What ik did to produce m: `targets` (per target: link, max and mean residual in m, unreachable = frames \
         farther than the tolerance, worst_time, orientation_max in rad), `max` (largest residual), `frames`, `iterations` (most per frame), \
         `mean_iterations`, `unconverged` (frames with some target not met), `dofs` (moved), `tolerance`, `text`. \
         Only the motion ik returned has a report.",
        |a, _| {
            let arg = a.arg("m")?;
            match provenance(&arg.value).and_then(|p| p.ik_report.clone()) {
                Some(r) => Ok(Value::object(IkReportValue(r))),
                None => Err(MxError::value("`ik_report`: this value was not returned by ik, so it has no report")
                    .at(arg.span)
                    .label("not a motion ik returned")
                    .help("call ik_report on ik's result itself: `let m = ik(b, walk, t); print(ik_report(m))`")),
            }
        },
    );
}
