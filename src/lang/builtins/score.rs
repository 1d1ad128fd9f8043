//! Judging a fill in one call: `compare(m, reference, body)` and
//! `compare(m, reference, body, t0, t1)`. The work is `crate::score`'s (the
//! in-betweening benchmark's own definitions); this file reads the
//! arguments, finds the gaps SP filled in `m`'s report and returns a record.

use crate::lang::diagnostics::{ErrorKind, MxError};
use crate::lang::host::errors::diagnostic;
use crate::lang::host::sp_report::{num, record, report_of};
use crate::lang::registry::Registry;
use crate::lang::topic::Topic;
use crate::lang::value::Value;
use crate::score::{Comparison, GapScore, Grounding, PlanAccuracy, compare};

fn opt(x: Option<f64>) -> Value {
    x.map_or(Value::Nil, num)
}

/// The contact plan's shares and counts; nil without a plan.
fn plan(p: Option<PlanAccuracy>) -> Value {
    let Some(p) = p else {
        return Value::Nil;
    };
    record(vec![
        ("edges", opt(p.edges())),
        ("frames", opt(p.agreement())),
        ("edges_matched", num(p.edges_matched as f64)),
        ("edges_planned", num(p.edges_planned as f64)),
        ("edges_reference", num(p.edges_reference as f64)),
    ])
}

/// The worst joint error of a gap: `{error, joint, time}`.
fn worst(g: &GapScore) -> Value {
    record(vec![
        ("error", num(g.accuracy.worst)),
        ("joint", Value::str(&g.accuracy.worst_joint)),
        (
            "time",
            g.times
                .get(g.accuracy.worst_frame)
                .map_or(Value::Nil, |&t| num(t)),
        ),
    ])
}

fn ground(g: &Grounding) -> Vec<(&'static str, Value)> {
    vec![
        ("skate", num(g.skate)),
        ("depth", num(g.depth)),
        ("residual", num(g.residual)),
        ("residual_worst", num(g.residual_worst)),
    ]
}

fn gap(g: &GapScore) -> Value {
    let mut fields = vec![
        ("t0", num(g.t0)),
        ("t1", num(g.t1)),
        ("frames", num(g.times.len() as f64)),
        ("l2p", num(g.accuracy.l2p)),
        ("l2q", num(g.accuracy.l2q)),
        ("npss", num(g.accuracy.npss)),
        ("worst", worst(g)),
    ];
    fields.extend(ground(&g.filled));
    fields.push(("reference", record(ground(&g.reference))));
    fields.push(("plan", plan(g.plan)));
    record(fields)
}

/// Skate, depth (mean and worst), residual (mean and worst frame) pooled
/// over the gaps, of `m` or (`reference`) of the reference.
fn pooled_ground(c: &Comparison, reference: bool) -> Vec<(&'static str, Value)> {
    vec![
        ("skate", num(c.skate(reference))),
        ("depth", num(c.depth(reference))),
        ("depth_worst", num(c.depth_worst(reference))),
        ("residual", num(c.residual(reference))),
        ("residual_worst", num(c.residual_worst(reference))),
    ]
}

fn comparison(c: &Comparison) -> Value {
    let mut fields = vec![
        ("l2p", num(c.l2p())),
        ("l2q", num(c.l2q())),
        ("npss", num(c.npss())),
        ("worst", c.worst().map_or(Value::Nil, worst)),
    ];
    fields.extend(pooled_ground(c, false));
    fields.push(("reference", record(pooled_ground(c, true))));
    fields.push(("plan", plan(c.plan())));
    fields.push(("floor", num(c.floor)));
    fields.push(("rate", num(c.rate)));
    fields.push(("gaps", Value::list(c.gaps.iter().map(gap).collect())));
    record(fields)
}

pub fn register(reg: &mut Registry) {
    reg.topic(Topic::Spacetime);
    reg.add(
        "compare(m, reference, body) | compare(m, reference, body, t0, t1)",
        "Scores the gaps SP filled in m (read from its SP report), or the gap [t0, t1] (the last frame before the hole and the first after it, as sp_report gives a gap), \
         against `reference` (e.g. the capture a gap was cut from), by the in-betweening benchmark's definitions and code, at the reference's frame rate: \
         `l2p` (mean joint-position error over the gap's frames, cm), `l2q` and `npss` (Harvey et al. 2020's orientation measures), `worst` ({error, joint, time}), \
         and by the ground's rules (ankle and toe joints, 2 cm, against the reference's floor, over the gap and its edge frames) `skate` (cm/s, as foot_skate), \
         `depth` and `depth_worst` (cm below the floor, as penetration), `residual` and `residual_worst` (% of body weight, as ground_residual, μ 0.8), \
         beside the reference's own in `reference`; `plan`: SP's contact plan against the reference's contacts ({edges: share of stance starts and ends within 0.1 s, \
         frames: share of frames where a point stands in both or neither}, nil without a plan); `floor`, `rate`, and per gap the same in `gaps`. \
         Over several gaps each number is the mean over gaps (NPSS pooled, the plan by its counts). The capture against itself scores 0 on l2p, l2q and npss.",
        |a, _| {
            let marg = a.arg("m")?;
            let m = a.mu_of("m", &marg)?;
            let rarg = a.arg("reference")?;
            let reference = a.mu_of("reference", &rarg)?;
            let barg = a.arg("body")?;
            let body = a.free_body_of("body", &barg, "a body, e.g. body_of(clip)")?;
            if body.coupling.is_some() {
                return Err(MxError::new(
                    ErrorKind::Value,
                    "compare takes a body without coupled coordinates (load the URDF without `mimic: true`)",
                )
                .at(barg.span));
            }
            let spans = if a.remaining() == 2 {
                vec![(a.finite("t0")?, a.finite("t1")?)]
            } else {
                vec![]
            };
            let report = report_of(&marg.value);
            let span = a.call_span();
            let c = compare(&m, &reference, &body.model, &spans, report.as_deref())
                .map_err(|e| diagnostic(&e, a, span))?;
            Ok(comparison(&c))
        },
    );
}
