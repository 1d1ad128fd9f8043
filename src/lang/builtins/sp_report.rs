//! The report SP attaches to the motion it returns, and `sp_report(m)`.
//!
//! A motion value is a plain `Mu` (every motion built-in takes it), so the
//! report travels beside it: a table keyed by the identity of the returned
//! value's allocation. `let m = SP(…)` shares that allocation, so
//! `sp_report(m)` finds it; any operation on `m` makes a new motion, which
//! SP did not produce. Entries hold a `Weak`, so a dropped motion's report
//! goes with the next insertion, and the allocation (hence the key) cannot be
//! reused while its entry exists.

use std::sync::{Arc, Mutex, Weak};

use indexmap::IndexMap;

use crate::lang::value::{HostObject, Value};
use crate::spacetime::SpReport;
use crate::spacetime::sp::Undefined;

type Entry = (Weak<dyn HostObject>, Arc<SpReport>);

static REPORTS: Mutex<Vec<Entry>> = Mutex::new(Vec::new());

fn same(a: &Weak<dyn HostObject>, b: &Arc<dyn HostObject>) -> bool {
    std::ptr::addr_eq(a.as_ptr(), Arc::as_ptr(b))
}

/// Attach `report` to `motion` (a value SP is about to return).
pub fn remember(motion: &Value, report: SpReport) {
    let Value::Object(o) = motion else { return };
    let mut table = REPORTS.lock().unwrap_or_else(|p| p.into_inner());
    table.retain(|(w, _)| w.strong_count() > 0);
    table.push((Arc::downgrade(o), Arc::new(report)));
}

/// The report of a motion SP returned, if `v` is one.
pub fn report_of(v: &Value) -> Option<Arc<SpReport>> {
    let Value::Object(o) = v else { return None };
    let table = REPORTS.lock().unwrap_or_else(|p| p.into_inner());
    table
        .iter()
        .find(|(w, _)| w.strong_count() > 0 && same(w, o))
        .map(|(_, r)| r.clone())
}

/// `sp_report(m)`: reads like a record (`r.groups[0].energy`), prints as text.
#[derive(Clone, Debug)]
pub struct SpReportValue(pub Arc<SpReport>);

fn num(x: f64) -> Value {
    Value::Number(x)
}

fn record(fields: Vec<(&str, Value)>) -> Value {
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

impl SpReportValue {
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
                        ("stop", Value::str(&g.stop)),
                        ("converged", Value::Bool(g.converged())),
                        ("prior_scale", num(g.prior_scale)),
                        ("solves", num(g.solves as f64)),
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

/// The fields `sp_report(m)` has, in the order `keys` would show them.
pub const FIELDS: [&str; 6] = ["groups", "root", "hermite", "constant", "undefined", "text"];

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
    fn field(&self, name: &str) -> Option<Value> {
        match name {
            "groups" => Some(self.groups()),
            "root" => Some(self.root()),
            "hermite" => Some(spans(&self.0.hermite)),
            "constant" => Some(spans(&self.0.constant)),
            "undefined" => Some(spans(&self.0.undefined)),
            "text" => Some(Value::str(self.summary())),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lang::builtins::motion::Motion;
    use crate::motion::Mu;

    #[test]
    fn a_report_follows_its_value_not_an_equal_one_and_goes_with_it() {
        let m = Value::object(Motion::Mu(Mu::new()));
        let other = Value::object(Motion::Mu(Mu::new()));
        remember(&m, SpReport::default());
        assert!(report_of(&m.clone()).is_some());
        assert!(report_of(&other).is_none());
        let weak = match &m {
            Value::Object(o) => Arc::downgrade(o),
            _ => unreachable!(),
        };
        drop(m);
        assert_eq!(weak.strong_count(), 0);
        remember(&other, SpReport::default());
        let table = REPORTS.lock().unwrap();
        assert!(!table.iter().any(|(w, _)| Weak::ptr_eq(w, &weak)));
    }
}
