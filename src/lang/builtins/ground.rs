//! Ground built-ins: `contacts`, `foot_skate`, `penetration`,
//! `ground_residual`, `ground_forces`. The work is done by `crate::ground`; this file reads
//! the shared options (`points:`, `floor:`, `height:`, `speed:`,
//! `friction:`), converts errors and returns records.

use indexmap::IndexMap;

use crate::ground::{self, Floor, GroundError, GroundOptions};
use crate::lang::args::Args;
use crate::lang::ast::Span;
use crate::lang::diagnostics::{ErrorKind, MxError, MxResult};
use crate::lang::host::errors::diagnostic;
use crate::lang::host::{Body, Motion};
use crate::lang::registry::Registry;
use crate::lang::topic::Topic;
use crate::lang::value::Value;
use crate::motion::Mu;

/// A ground error at the argument it names (`height`, `points`, …), else at `span`.
fn ground_error(e: GroundError, a: &Args, span: Span) -> MxError {
    diagnostic(&e, a, span)
}

/// `m` and `body`, the first two arguments of every ground built-in.
fn motion_and_body(a: &mut Args) -> MxResult<(Mu, Body)> {
    let marg = a.arg("m")?;
    let m = a.mu_of("m", &marg)?;
    let barg = a.arg("body")?;
    let body = a.free_body_of("body", &barg, "a body, e.g. body_of(clip)")?;
    if body.coupling.is_some() {
        return Err(MxError::new(
            ErrorKind::Value,
            "ground measures take a body without coupled coordinates (load the URDF without `mimic: true`)",
        )
        .at(barg.span));
    }
    Ok((m, body))
}

/// The options every ground built-in shares.
fn options(a: &mut Args) -> MxResult<GroundOptions> {
    let mut o = GroundOptions::default();
    if let Some(p) = a.opt_named("points") {
        let bad = |a: &Args| {
            a.type_error(
                "points",
                "a list of link names, e.g. [\"Foot_L\", \"Toes_L\"]",
                &p,
            )
        };
        let Value::List(items) = &p.value else {
            return Err(bad(a));
        };
        o.points = Some(
            items
                .iter()
                .map(|v| match v {
                    Value::Str(s) => Ok(s.to_string()),
                    _ => Err(bad(a)),
                })
                .collect::<MxResult<_>>()?,
        );
    }
    if let Some(f) = a.opt_named("floor") {
        o.floor = match &f.value {
            Value::Str(s) if &**s == "auto" => Floor::Auto,
            Value::Number(x) if x.is_finite() => Floor::At(*x),
            _ => {
                return Err(a.type_error(
                    "floor",
                    "a height in metres, or \"auto\" (the lowest contact point)",
                    &f,
                ));
            }
        };
    }
    o.height = a.named_number_or("height", o.height)?;
    o.speed = a.named_number_or("speed", o.speed)?;
    let span = a.call_span();
    o.check().map_err(|e| ground_error(e, a, span))?;
    Ok(o)
}

fn num(x: f64) -> Value {
    Value::Number(x)
}

fn nums(x: &[f64]) -> Value {
    Value::list(x.iter().map(|&v| Value::Number(v)).collect())
}

fn rec(fields: Vec<(&str, Value)>) -> Value {
    Value::record(
        fields
            .into_iter()
            .map(|(k, v)| (k.to_string(), v))
            .collect::<IndexMap<_, _>>(),
    )
}

pub fn register(reg: &mut Registry) {
    reg.topic(Topic::Dynamics);
    reg.add(
        "contacts(m, body, points: [...], floor: \"auto\", height: 0.02, speed: 0.3)",
        "Where each contact point of body touches the floor over m, sampled at m's frame rate: a record `{floor, frame_time, points: {NAME: [{start, stop, first, last}, …]}}` \
         (times in s, frame indices from 0). A point touches while within `height` (m) of the floor and moving horizontally slower than `speed` (m/s; `inf` turns the test off). \
         Contact points: the body's ankle and toe joints (names with Foot, Toe, Ankle, Heel or calcn; e.g. Bandai's Foot_L, Toes_L, CMU's LeftFoot, LeftToeBase), or the links `points` names. \
         The floor: the lowest height any contact point reaches (\"up\" against the body's gravity), or the height `floor` states.",
        |a, _| {
            let (m, body) = motion_and_body(a)?;
            let o = options(a)?;
            let span = a.call_span();
            let c = ground::contacts(&m, &body.model, &o).map_err(|e| ground_error(e, a, span))?;
            let points: IndexMap<String, Value> = c
                .points
                .iter()
                .map(|p| {
                    let ivs = p
                        .intervals
                        .iter()
                        .map(|i| {
                            rec(vec![
                                ("start", num(i.start)),
                                ("stop", num(i.stop)),
                                ("first", num(i.first as f64)),
                                ("last", num(i.last as f64)),
                            ])
                        })
                        .collect();
                    (p.name.clone(), Value::list(ivs))
                })
                .collect();
            Ok(rec(vec![
                ("floor", num(c.floor)),
                ("frame_time", num(c.frame_time)),
                ("points", Value::record(points)),
            ]))
        },
    );
    reg.add(
        "foot_skate(m, body, points: [...], floor: \"auto\", height: 0.02, speed: 0.3)",
        "Foot skate of m: the horizontal speed (cm/s) of each contact point over each frame step ending within `height` of the floor (data/inbetween's definition), \
         as `{mean, worst, worst_point, worst_frame, steps, weighted, floor}`; `weighted` is Zhang et al. 2018's sliding v·(2 − 2^(h/H)) (H = height) averaged over every point and step. \
         Contact points and floor as for `contacts`.",
        |a, _| {
            let (m, body) = motion_and_body(a)?;
            let o = options(a)?;
            let span = a.call_span();
            let s = ground::foot_skate(&m, &body.model, &o).map_err(|e| ground_error(e, a, span))?;
            Ok(rec(vec![
                ("mean", num(s.mean)),
                ("worst", num(s.worst)),
                ("worst_point", Value::str(&s.worst_point)),
                ("worst_frame", num(s.worst_frame as f64)),
                ("steps", num(s.steps as f64)),
                ("weighted", num(s.weighted)),
                ("floor", num(s.floor)),
            ]))
        },
    );
    reg.add(
        "penetration(m, body, points: [...], floor: \"auto\", height: 0.02, speed: 0.3)",
        "How far the lowest contact point of m goes below the floor: `{depth, point, frame, time, floor}` (depth in cm, 0 when nothing goes below; \
         with the default floor, the lowest point itself, nothing can). State the floor (e.g. the capture's, `contacts(capture, b).floor`) to score a filled motion.",
        |a, _| {
            let (m, body) = motion_and_body(a)?;
            let o = options(a)?;
            let span = a.call_span();
            let p = ground::penetration(&m, &body.model, &o).map_err(|e| ground_error(e, a, span))?;
            Ok(rec(vec![
                ("depth", num(p.depth)),
                ("point", Value::str(&p.point)),
                ("frame", num(p.frame as f64)),
                ("time", num(p.time)),
                ("floor", num(p.floor)),
            ]))
        },
    );
    reg.add(
        "ground_residual(m, body, friction: 0.8, points: [...], floor: \"auto\", height: 0.02, speed: 0.3)",
        "Per frame, the part of the external wrench m needs (inverse dynamics of the floating base: the wrench across the body's 6-DOF root) that no contact forces at the points within `height` of the floor, \
         each inside its friction cone (coefficient `friction`), can supply; moments weigh as the force that makes them at a body length. \
         Returns `{force_mean, force_worst, force_worst_frame, moment_mean, moment_worst, moment_worst_frame, force, moment, needed, in_contact, weight, floor, unsolved}`: force as % of body weight, \
         moment about the centre of mass in N·m, per-frame lists, the body weight (N), and the frames whose cone problem solved only approximately.",
        |a, _| {
            let (m, body) = motion_and_body(a)?;
            let friction = a.named_number_or("friction", 0.8)?;
            let o = options(a)?;
            let span = a.call_span();
            let r = ground::ground_residual(&m, &body.model, &o, friction).map_err(|e| ground_error(e, a, span))?;
            let contact: Vec<f64> = r.in_contact.iter().map(|&n| n as f64).collect();
            Ok(rec(vec![
                ("force_mean", num(r.mean_force)),
                ("force_worst", num(r.worst_force)),
                ("force_worst_frame", num(r.worst_force_frame as f64)),
                ("moment_mean", num(r.mean_moment)),
                ("moment_worst", num(r.worst_moment)),
                ("moment_worst_frame", num(r.worst_moment_frame as f64)),
                ("force", nums(&r.force)),
                ("moment", nums(&r.moment)),
                ("needed", nums(&r.needed)),
                ("in_contact", nums(&contact)),
                ("weight", num(r.weight)),
                ("floor", num(r.floor)),
                ("unsolved", num(r.unsolved as f64)),
            ]))
        },
    );
    reg.add(
        "ground_forces(m, body, friction: 0.8, points: [...], floor: \"auto\", height: 0.02, speed: 0.3)",
        "Per frame of m, the contact forces that best hold body up and what they leave: the same friction-cone solve as `ground_residual` (contact points within `height` of the floor push, \
         each inside its cone of coefficient `friction`; a point farther away carries nothing). A motion on m's frames, one DOF per number: `POINT.Fx`, `.Fy`, `.Fz` per contact point \
         (N, world axes, the force on the body), `residual.Fx/Fy/Fz` (N) and `residual.Mx/My/Mz` (N·m about the centre of mass), what no contact force supplies, and \
         `residual.percent_bw` (the residual force as % of body weight). `plot` and `save(…, \"x.csv\")` take it as any motion; a body standing still gets its weight from its feet.",
        |a, _| {
            let (m, body) = motion_and_body(a)?;
            let friction = a.named_number_or("friction", 0.8)?;
            let o = options(a)?;
            let span = a.call_span();
            let g = ground::ground_forces(&m, &body.model, &o, friction).map_err(|e| ground_error(e, a, span))?;
            let mu = g.to_motion().map_err(|e| ground_error(e, a, span))?;
            Ok(Value::object(Motion::Mu(mu)))
        },
    );
}
