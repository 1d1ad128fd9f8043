//! The report SP attaches to the motion it returns, and the `sp_report(m)`
//! value. The report is part of that motion value's [`Provenance`], so
//! `let m = SP(…)` keeps it and `sp_report(m)` finds it; any operation on
//! `m` makes a new motion, which SP did not produce.

use std::sync::Arc;

use indexmap::IndexMap;

use super::motion::{Provenance, provenance};
use crate::lang::value::{HostObject, Value};
use crate::spacetime::SpReport;
use crate::spacetime::reference::EndFit;
use crate::spacetime::solve::GapReport;
use crate::spacetime::sp::Undefined;

/// The report of a motion SP returned, if `v` is one.
pub fn report_of(v: &Value) -> Option<Arc<SpReport>> {
    provenance(v).and_then(|p: &Provenance| p.sp_report.clone())
}

/// `sp_report(m)`: reads like a record (`r.groups[0].energy`), prints as text.
#[derive(Clone, Debug)]
pub struct SpReportValue(pub Arc<SpReport>);

/// A number value (report fields).
pub fn num(x: f64) -> Value {
    Value::Number(x)
}

/// A record value from its fields in order (report fields).
pub fn record(fields: Vec<(&str, Value)>) -> Value {
    Value::record(
        fields
            .into_iter()
            .map(|(k, v)| (k.to_string(), v))
            .collect::<IndexMap<_, _>>(),
    )
}

fn spans(list: &[Undefined]) -> Value {
    Value::list(
        list.iter()
            .map(|u| {
                record(vec![
                    ("dof", Value::str(&u.dof)),
                    ("start", num(u.start)),
                    ("stop", num(u.stop)),
                ])
            })
            .collect(),
    )
}

/// The example a group followed (nil: none; `no_example` says why): its
/// source, clip and time span, its match cost and how far its laid poses
/// were from the gap's end states.
fn example(g: &GapReport) -> Value {
    let Some(ex) = &g.example else {
        return Value::Nil;
    };
    let clip = ex.clip.as_ref();
    let source = if clip.is_some() { "library" } else { "self" };
    // the stretch the gap followed, on the example's own clock
    let (from, to) = match clip {
        Some(c) => (c.time, c.time + c.warp * (g.t1 - g.t0)),
        None => (g.t0 + ex.shift, g.t1 + ex.shift),
    };
    let fit = |f: fn(&EndFit) -> f64| ex.fit.as_ref().map_or(Value::Nil, |e| num(f(e)));
    record(vec![
        ("source", Value::str(source)),
        ("shift", num(ex.shift)),
        ("mismatch", num(ex.mismatch)),
        ("clip", clip.map_or(Value::Nil, |c| Value::str(&c.name))),
        ("time", clip.map_or(Value::Nil, |c| num(c.time))),
        ("warp", clip.map_or(Value::Nil, |c| num(c.warp))),
        ("from", num(from)),
        ("to", num(to)),
        ("end_distance_start", fit(|e| e.start)),
        ("end_distance_end", fit(|e| e.end)),
        ("end_angle", fit(|e| e.angle)),
        (
            "dofs",
            Value::list(
                g.coords
                    .iter()
                    .zip(&g.names)
                    .filter(|(c, _)| ex.follow.contains(c))
                    .map(|(_, n)| Value::str(n))
                    .collect(),
            ),
        ),
    ])
}

/// Each example source asked for a group: `{source, mismatch}` or
/// `{source, why}`.
fn tried(g: &GapReport) -> Value {
    Value::list(
        g.tried
            .iter()
            .map(|(o, r)| match r {
                Ok(rho) => record(vec![
                    ("source", Value::str(o.label())),
                    ("mismatch", num(*rho)),
                ]),
                Err(why) => record(vec![
                    ("source", Value::str(o.label())),
                    ("why", Value::str(why.to_string())),
                ]),
            })
            .collect(),
    )
}

impl SpReportValue {
    fn pinned(&self) -> Value {
        Value::list(
            self.0
                .pinned
                .iter()
                .map(|p| {
                    record(vec![
                        ("t0", num(p.t0)),
                        ("t1", num(p.t1)),
                        ("auto", Value::Bool(p.auto)),
                        ("mismatch", num(p.mismatch)),
                        ("tolerance", num(p.tolerance)),
                    ])
                })
                .collect(),
        )
    }

    fn groups(&self) -> Value {
        Value::list(
            self.0
                .groups
                .iter()
                .map(|g| {
                    record(vec![
                        (
                            "dofs",
                            Value::list(g.names.iter().map(Value::str).collect()),
                        ),
                        ("t0", num(g.t0)),
                        ("t1", num(g.t1)),
                        ("method", Value::str(g.method)),
                        ("unknowns", num(g.n_vars as f64)),
                        ("iterations", num(g.iterations as f64)),
                        ("evaluations", num(g.evaluations as f64)),
                        ("initial_energy", num(g.initial_energy)),
                        ("energy", num(g.energy)),
                        ("grad_norm", num(g.grad_norm)),
                        ("stop", Value::str(g.stop.to_string())),
                        ("converged", Value::Bool(g.converged())),
                        ("prior_scale", num(g.prior_scale)),
                        ("solves", num(g.solves as f64)),
                        ("example", example(g)),
                        (
                            "no_example",
                            g.why_no_example().map_or(Value::Nil, Value::str),
                        ),
                        ("tried", tried(g)),
                        ("seconds", num(g.seconds)),
                    ])
                })
                .collect(),
        )
    }

    fn root(&self) -> Value {
        Value::list(
            self.0
                .root
                .iter()
                .map(|r| {
                    let shift: IndexMap<String, Value> =
                        r.shift.iter().map(|(n, d)| (n.clone(), num(*d))).collect();
                    record(vec![
                        ("t0", num(r.t0)),
                        ("t1", num(r.t1)),
                        ("shift", Value::record(shift)),
                    ])
                })
                .collect(),
        )
    }
}

impl SpReportValue {
    /// The contact plan as one flat list of stances, in gap and point order:
    /// `{point, from, to, at, source, gap, stand, floor, error}` — the first
    /// four as `contact:` takes them, so a plan can be edited and given back;
    /// `source` is what made it (context / example / steps / given /
    /// re-planned), `gap` the group's span [t0, t1], `stand` the height the
    /// point stands at, `floor` the floor's, and `error` the solved point's
    /// largest distance (m) from `at` over the stance (nil before a solve).
    /// A stance Rose's support moves along a path has `at_end` too.
    fn contacts(&self) -> Value {
        let point = |p: &nalgebra::Vector3<f64>| Value::list(vec![num(p.x), num(p.y), num(p.z)]);
        let Some(plan) = &self.0.contacts else {
            return Value::list(vec![]);
        };
        let mut out = vec![];
        for g in &plan.gaps {
            for ph in &g.points {
                for s in &ph.stances {
                    let mut fields = vec![
                        ("point", Value::str(&ph.name)),
                        ("from", num(s.t0)),
                        ("to", num(s.t1)),
                        ("at", point(&s.p0)),
                        ("source", Value::str(s.source.name())),
                        ("gap", Value::list(vec![num(g.t0), num(g.t1)])),
                        ("stand", num(ph.stand)),
                        ("floor", num(plan.floor.height)),
                        ("error", s.solved.map_or(Value::Nil, num)),
                    ];
                    if s.p1 != s.p0 {
                        fields.push(("at_end", point(&s.p1)));
                    }
                    out.push(record(fields));
                }
            }
        }
        Value::list(out)
    }
}

/// How one field of the report is read.
type Getter = fn(&SpReportValue) -> Value;

/// The fields of `sp_report(m)`, in the order `keys` would show them, each
/// with how it is read: the one list that [`HostObject::read_field`] answers from
/// and the Python bindings build their report dict from (`mx.sp`), so a
/// field added here reaches both.
const TABLE: [(&str, Getter); 8] = [
    ("groups", SpReportValue::groups),
    ("root", SpReportValue::root),
    ("pinned", SpReportValue::pinned),
    ("contacts", SpReportValue::contacts),
    ("hermite", |r| spans(&r.0.hermite)),
    ("constant", |r| spans(&r.0.constant)),
    ("undefined", |r| spans(&r.0.undefined)),
    ("text", |r| Value::str(r.summary())),
];

/// The names of [`TABLE`]'s fields, in order.
pub const FIELDS: [&str; TABLE.len()] = {
    let mut names = [""; TABLE.len()];
    let mut i = 0;
    while i < TABLE.len() {
        names[i] = TABLE[i].0;
        i += 1;
    }
    names
};

impl HostObject for SpReportValue {
    fn type_name(&self) -> &'static str {
        "SpReport"
    }
    fn summary(&self) -> String {
        self.0.to_string().trim_end().to_string()
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
    fn field_names(&self) -> &'static [&'static str] {
        &FIELDS
    }
    fn read_field(&self, name: &str) -> Option<Value> {
        TABLE
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, read)| read(self))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lang::host::motion::Motion;
    use crate::motion::Mu;

    /// The fields the Python dict lost before it was built from `FIELDS` are
    /// listed, once each (that every listed field is read holds by
    /// construction; pytest compares Python's dict with the table).
    #[test]
    fn the_field_list_is_what_the_report_answers() {
        assert!(FIELDS.contains(&"constant") && FIELDS.contains(&"contacts"));
        let mut unique = FIELDS.to_vec();
        unique.sort();
        unique.dedup();
        assert_eq!(unique.len(), FIELDS.len(), "a field is listed twice");
    }

    #[test]
    fn a_report_follows_its_value_not_an_equal_one() {
        let report = Provenance {
            sp_report: Some(Arc::new(SpReport::default())),
            ..Provenance::default()
        };
        let m = Motion::Mu(Mu::new()).with_provenance(report);
        let other = Value::object(Motion::Mu(Mu::new()));
        assert!(report_of(&m.clone()).is_some());
        assert!(report_of(&other).is_none());
        assert!(m.equals(&other), "provenance does not change equality");
        assert_eq!(m.repr(), other.repr(), "nor printing");
    }
}

#[cfg(test)]
mod example_tests {
    use super::*;
    use crate::spacetime::reference::{Example, NoExample, Origin};
    use crate::spacetime::solve::StopReason;

    fn group(
        example: Option<Example>,
        tried: Vec<crate::spacetime::reference::Tried>,
    ) -> GapReport {
        GapReport {
            coords: vec![0, 1],
            names: vec!["a".into(), "b".into()],
            t0: 1.0,
            t1: 1.5,
            n_vars: 8,
            method: "gn",
            iterations: 1,
            evaluations: 1,
            initial_energy: 1.0,
            energy: 1.0,
            grad_norm: 0.0,
            stop: StopReason::Converged,
            seconds: 0.0,
            prior_scale: 1.0,
            solves: 1,
            example,
            tried,
        }
    }

    fn field<'v>(v: &'v Value, name: &str) -> &'v Value {
        v.as_record()
            .and_then(|r| r.get(name))
            .unwrap_or_else(|| panic!("no field {name}"))
    }

    #[test]
    fn a_group_says_which_example_it_followed_and_how_well_it_fit() {
        let ex = Example {
            shift: -0.8,
            mismatch: 0.2,
            follow: vec![1],
            of: 2,
            clip: None,
            fit: Some(EndFit {
                start: 0.01,
                end: 0.03,
                angle: 0.1,
            }),
        };
        let g = group(
            Some(ex),
            vec![
                (Origin::Own, Ok(0.2)),
                (Origin::Library, Err(NoExample::LibraryEmpty)),
            ],
        );
        let e = example(&g);
        assert!(field(&e, "source").equals(&Value::str("self")));
        assert!(field(&e, "mismatch").equals(&num(0.2)));
        let Value::Number(from) = field(&e, "from") else {
            panic!("a number")
        };
        assert!((from - 0.2).abs() < 1e-12, "{from}");
        assert!(field(&e, "end_distance_end").equals(&num(0.03)));
        assert!(field(&e, "dofs").equals(&Value::list(vec![Value::str("b")])));
        assert!(g.why_no_example().is_none());
        let t = tried(&g);
        let Value::List(t) = &t else { panic!("a list") };
        assert_eq!(t.len(), 2);
        assert!(field(&t[1], "why").to_string().contains("empty"));
    }

    #[test]
    fn a_group_without_an_example_says_why() {
        let g = group(
            None,
            vec![(
                Origin::Library,
                Err(NoExample::NoMatch {
                    best: 1.7,
                    threshold: 1.0,
                }),
            )],
        );
        assert!(matches!(example(&g), Value::Nil));
        let why = g.why_no_example().expect("a reason");
        assert!(why.contains("library") && why.contains("1.7"), "{why}");
        // no source asked: nothing to explain
        assert!(group(None, vec![]).why_no_example().is_none());
    }
}
