//! String built-ins beside `split` and `join` (core.rs): `starts_with`,
//! `ends_with` and `number`. Like every built-in they are methods too:
//! `name.ends_with(".bvh")`, `"3.2".number()`.

use crate::lang::args::Args;
use crate::lang::diagnostics::{MxError, MxResult};
use crate::lang::parser::number_literal;
use crate::lang::registry::Registry;
use crate::lang::topic::Topic;
use crate::lang::value::{Value, quote};

pub fn register(reg: &mut Registry) {
    reg.topic(Topic::Language);
    reg.add(
        "starts_with(s, prefix)",
        "Whether the string s begins with prefix (case-sensitive; every string starts with \"\"): `\"LeftFoot\".starts_with(\"Left\")` is true.",
        |a, _| {
            let s = a.string("s")?;
            let p = a.string("prefix")?;
            Ok(Value::Bool(s.starts_with(p.as_ref())))
        },
    );
    reg.add(
        "ends_with(s, suffix)",
        "Whether the string s ends with suffix (case-sensitive; every string ends with \"\"): `\"walk.bvh\".ends_with(\".bvh\")` is true.",
        |a, _| {
            let s = a.string("s")?;
            let p = a.string("suffix")?;
            Ok(Value::Bool(s.ends_with(p.as_ref())))
        },
    );
    reg.add(
        "number(s)",
        "The number a string holds, read as the language reads a number literal: `number(\"3.2\")` is 3.2, `\"-1e-3\"`, `\".5\"`, and units as in scripts: `\"250ms\"` is 0.25, `\"90deg\"` is π/2. Spaces around it are ignored; anything else (`\"3,2\"`, `\"\"`, `\"nan\"`) is an error naming `s`. A number is returned as it is.",
        |a, _| number(a),
    );
}

/// `number(s)`: a string read as a number literal (see [`number_literal`]).
fn number(a: &mut Args) -> MxResult<Value> {
    let arg = a.arg("s")?;
    let text = match &arg.value {
        Value::Number(x) => return Ok(Value::Number(*x)),
        Value::Str(s) => s.clone(),
        _ => return Err(a.type_error("s", "a string (or a number)", &arg)),
    };
    match number_literal(text.trim()) {
        Some(x) => Ok(Value::Number(x)),
        None => {
            let shown: String = text.chars().take(40).collect();
            Err(MxError::value(format!(
                "`number`: `s` is {}, which is not a number",
                quote(&shown)
            ))
            .at(arg.span)
            .label("not a number")
            .help(
                "write it as a number literal: `3.2`, `-1e-3`, `.5`, with a unit if any \
                 (`250ms`, `2s`, `90deg`, `1.2rad`); a decimal point, not a comma; \
                 at most about 1.8e308",
            ))
        }
    }
}
