//! Field access on records and record-like host values (`r.name`,
//! `sp_report(m).groups`): the error for a field that is not there. Which
//! fields a value has is [`Value::keys`], the one list `keys`, `has` and
//! field access share.

use super::args::describe;
use super::ast::Span;
use super::diagnostics::{MxError, did_you_mean};
use super::value::Value;

/// `v.name` found nothing: say what `v` has instead (the closest name, else
/// every field), or that it has no fields at all.
pub fn no_field(v: &Value, name: &str, at: Span) -> MxError {
    let Some(keys) = v.keys() else {
        return MxError::type_error(format!("{} has no fields", describe(v)))
            .at(at)
            .label(format!("field of {}", v.type_name()))
            .help("fields exist on records `{a: 1}` and on values such as `sp_report(m)`; to call a function write `x.f()`");
    };
    let what = match v {
        Value::Record(_) => "this record".to_string(),
        other => format!("a {}", other.type_name()),
    };
    let e = MxError::value(format!("{what} has no field `{name}`"))
        .at(at)
        .label("no such field");
    match did_you_mean(name, keys.iter().map(String::as_str)) {
        Some(s) => e.help(format!("did you mean `{s}`?")),
        None if keys.is_empty() => e.help("it has no fields"),
        None => e.help(format!("its fields are: {}", keys.join(", "))),
    }
}
