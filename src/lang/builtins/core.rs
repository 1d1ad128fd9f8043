//! Core built-ins: output, math, lists, records, strings, files.

use std::sync::Arc;

use indexmap::IndexMap;

use crate::lang::args::{Args, describe};
use crate::lang::diagnostics::{ErrorKind, MxError, MxResult};
use crate::lang::eval::Evaluator;
use crate::lang::registry::{Format, Registry};
use crate::lang::topic::Topic;
use crate::lang::value::Value;

fn num(x: f64) -> MxResult<Value> {
    Ok(Value::Number(x))
}

/// Register a one-argument math function.
fn unary(reg: &mut Registry, sig: &str, doc: &str, f: fn(f64) -> f64) {
    reg.add(sig, doc, move |a, _| num(f(a.number("x")?)));
}

/// A domain check for math functions (`sqrt(-1)`, `ln(0)`): NaN is an error, not a value.
fn checked(
    a: &mut Args,
    name: &str,
    f: fn(f64) -> f64,
    valid: fn(f64) -> bool,
    rule: &str,
) -> MxResult<Value> {
    let arg = a.arg(name)?;
    let Value::Number(x) = arg.value else {
        return Err(a.type_error(name, "a number", &arg));
    };
    if !valid(x) {
        return Err(MxError::value(format!(
            "`{}` is not defined at {}",
            a.name(),
            crate::lang::value::format_number(x)
        ))
        .at(arg.span)
        .label("outside the domain")
        .help(rule.to_string()));
    }
    num(f(x))
}

/// The core language built-ins, by topic.
pub fn register(reg: &mut Registry) {
    constants_and_output(reg);
    math(reg);
    list_basics(reg);
    list_functions(reg);
    records(reg);
    strings(reg);
    files(reg);
}

/// Constants, `print`, `str`, `type`, `error`, `assert`.
fn constants_and_output(reg: &mut Registry) {
    reg.topic(Topic::Language);
    use std::f64::consts;
    reg.constant("pi", "π = 3.14159…", Value::Number(consts::PI));
    reg.constant("tau", "τ = 2π", Value::Number(consts::TAU));
    reg.constant("e", "Euler's number 2.71828…", Value::Number(consts::E));
    reg.constant("inf", "Positive infinity.", Value::Number(f64::INFINITY));
    reg.constant("nil", "The empty value (what `print` returns).", Value::Nil);

    // ---- output ----
    reg.add(
        "print(x, ...)",
        "Write the arguments to stdout on one line, separated by spaces. Numbers print in the shortest form that reads back exactly; strings without quotes.",
        |a, ev| {
            let parts: Vec<String> = a.rest().iter().map(|v| v.value.display()).collect();
            ev.write_line(&parts.join(" "), a.call_span())?;
            Ok(Value::Nil)
        },
    );
    reg.add(
        "eprint(x, ...)",
        "Like `print`, but to stderr (progress and notes that must not mix with output).",
        |a, _| {
            let parts: Vec<String> = a.rest().iter().map(|v| v.value.display()).collect();
            eprintln!("{}", parts.join(" "));
            Ok(Value::Nil)
        },
    );
    reg.add("str(x)", "The text `print` would show for x.", |a, _| {
        Ok(Value::str(a.value("x")?.display()))
    });
    reg.add(
        "repr(x)",
        "x as mx source (strings quoted; numbers exact).",
        |a, _| Ok(Value::str(a.value("x")?.repr())),
    );
    reg.add(
        "fmt(x, digits: 4)",
        "The number x as text rounded to `digits` significant digits (1–17): `fmt(6.4666602, 3)` is \"6.47\". Summaries (spans) show 6; `repr(x)` gives the exact value.",
        |a, _| {
            let x = a.number("x")?;
            let d = a.number_or("digits", 4.0)?;
            if !(d.fract() == 0.0 && (1.0..=17.0).contains(&d)) {
                return Err(MxError::new(
                    ErrorKind::Value,
                    format!("digits must be a whole number from 1 to 17, got {}", crate::fmt_num::format_number(d)),
                )
                .at(a.call_span())
                .help("e.g. fmt(x, 3)"));
            }
            Ok(Value::str(crate::fmt_num::format_number(
                crate::fmt_num::round_significant(x, d as usize),
            )))
        },
    );
    reg.add(
        "env(name)",
        "The environment variable `name` as a string, nil when unset: `let shared = env(\"MX_SHARED\")`.",
        |a, _| {
            let n = a.string("name")?;
            Ok(match std::env::var(&*n) {
                Ok(v) => Value::str(v),
                Err(_) => Value::Nil,
            })
        },
    );
    reg.add(
        "type(x)",
        "The type name of x: number, bool, string, list, record, function, Mu, …",
        |a, _| Ok(Value::str(a.value("x")?.type_name())),
    );
    reg.add(
        "error(message)",
        "Stop with an error carrying `message`.",
        |a, _| {
            let m = a.string("message")?;
            Err(MxError::new(ErrorKind::Value, m.to_string())
                .at(a.call_span())
                .help("raised by `error(…)` in the script"))
        },
    );
    reg.add(
        "assert(cond, message: \"assertion failed\")",
        "Stop with an error unless `cond` is true.",
        |a, _| {
            let c = a.bool("cond")?;
            let m = match a.opt("message") {
                Some(v) => v.value.display(),
                None => "assertion failed".into(),
            };
            if c {
                Ok(Value::Nil)
            } else {
                Err(MxError::value(m)
                    .at(a.call_span())
                    .help("the asserted condition is false"))
            }
        },
    );
}

/// Numbers: elementary functions, rounding, `min`/`max`.
fn math(reg: &mut Registry) {
    reg.topic(Topic::Language);
    unary(reg, "abs(x)", "Absolute value.", f64::abs);
    unary(reg, "sin(x)", "Sine (radians).", f64::sin);
    unary(reg, "cos(x)", "Cosine (radians).", f64::cos);
    unary(reg, "tan(x)", "Tangent (radians).", f64::tan);
    unary(reg, "atan(x)", "Arc tangent, in (-π/2, π/2).", f64::atan);
    unary(reg, "exp(x)", "e to the power x.", f64::exp);
    unary(reg, "floor(x)", "Largest whole number ≤ x.", f64::floor);
    unary(reg, "ceil(x)", "Smallest whole number ≥ x.", f64::ceil);
    unary(
        reg,
        "round(x)",
        "Nearest whole number (halves away from zero).",
        f64::round,
    );
    unary(
        reg,
        "deg(x)",
        "Radians to degrees (`deg(pi)` = 180). Literals take a suffix instead: `90deg`.",
        f64::to_degrees,
    );
    unary(
        reg,
        "rad(x)",
        "Degrees to radians (`rad(180)` = π).",
        f64::to_radians,
    );
    reg.add("sqrt(x)", "Square root; x ≥ 0.", |a, _| {
        checked(a, "x", f64::sqrt, |x| x >= 0.0, "sqrt takes x ≥ 0")
    });
    reg.add("ln(x)", "Natural logarithm; x > 0.", |a, _| {
        checked(a, "x", f64::ln, |x| x > 0.0, "ln takes x > 0")
    });
    reg.add("log10(x)", "Base-10 logarithm; x > 0.", |a, _| {
        checked(a, "x", f64::log10, |x| x > 0.0, "log10 takes x > 0")
    });
    reg.add("asin(x)", "Arc sine; -1 ≤ x ≤ 1.", |a, _| {
        checked(
            a,
            "x",
            f64::asin,
            |x| (-1.0..=1.0).contains(&x),
            "asin takes -1 ≤ x ≤ 1",
        )
    });
    reg.add("acos(x)", "Arc cosine; -1 ≤ x ≤ 1.", |a, _| {
        checked(
            a,
            "x",
            f64::acos,
            |x| (-1.0..=1.0).contains(&x),
            "acos takes -1 ≤ x ≤ 1",
        )
    });
    reg.add(
        "atan2(y, x)",
        "Angle of the point (x, y) in (-π, π].",
        |a, _| {
            let y = a.number("y")?;
            num(y.atan2(a.number("x")?))
        },
    );
    reg.add("pow(x, y)", "x to the power y.", |a, _| {
        let x = a.number("x")?;
        num(x.powf(a.number("y")?))
    });
    reg.add("hypot(x, y)", "√(x² + y²) without overflow.", |a, _| {
        let x = a.number("x")?;
        num(x.hypot(a.number("y")?))
    });
    reg.add(
        "min(x, ...)",
        "Smallest of the numbers given, or of one list of numbers.",
        |a, _| extremum(a, true),
    );
    reg.add(
        "max(x, ...)",
        "Largest of the numbers given, or of one list of numbers.",
        |a, _| extremum(a, false),
    );
    reg.add("is_nan(x)", "Whether x is not a number.", |a, _| {
        Ok(Value::Bool(a.number("x")?.is_nan()))
    });
}

/// Lists: `len`, `range`, `linspace`.
fn list_basics(reg: &mut Registry) {
    reg.topic(Topic::Language);
    reg.add(
        "len(x)",
        "Number of items of a list or record, or characters of a string.",
        |a, _| {
            let v = a.arg("x")?;
            match &v.value {
                Value::List(l) => num(l.len() as f64),
                Value::Record(r) => num(r.len() as f64),
                Value::Str(s) => num(s.chars().count() as f64),
                _ => Err(a.type_error("x", "a list, record or string", &v)),
            }
        },
    );
    reg.add(
        "range(a, b: none, step: 1)",
        "`range(n)` = [0, 1, …, n−1]; `range(a, b)` = [a, …, b−1]; `range(a, b, step)` with step ≠ 0.",
        |a, _| {
            let first = a.number("a")?;
            let (start, stop) = match a.opt("b") {
                Some(v) => match v.value {
                    Value::Number(b) => (first, b),
                    _ => return Err(a.type_error("b", "a number", &v)),
                },
                None => (0.0, first),
            };
            let step = a.number_or("step", 1.0)?;
            if step == 0.0 || !step.is_finite() || !start.is_finite() || !stop.is_finite() {
                return Err(a.error(ErrorKind::Value, "range needs finite bounds and a non-zero step"));
            }
            let n = ((stop - start) / step).ceil().max(0.0);
            if n > 10_000_000.0 {
                return Err(a.error(ErrorKind::Value, format!("range would have {n} items (limit 10,000,000)")));
            }
            Ok(Value::list((0..n as usize).map(|i| Value::Number(start + i as f64 * step)).collect()))
        },
    );
    reg.add(
        "linspace(a, b, n)",
        "n evenly spaced numbers from a to b inclusive (n ≥ 2).",
        |a, _| {
            let (x, y) = (a.finite("a")?, a.finite("b")?);
            let n = a.count("n")?;
            if !(2..=10_000_000).contains(&n) {
                return Err(a.error(
                    ErrorKind::Value,
                    format!("linspace needs 2 ≤ n ≤ 10,000,000, got {n}"),
                ));
            }
            Ok(Value::list(
                (0..n)
                    .map(|i| {
                        Value::Number(if i + 1 == n {
                            y
                        } else {
                            x + (y - x) * i as f64 / (n - 1) as f64
                        })
                    })
                    .collect(),
            ))
        },
    );
}

/// Lists with functions: `map`, `filter`, `fold`, and `sum`, `sort`, `append`, `zip`.
fn list_functions(reg: &mut Registry) {
    reg.topic(Topic::Language);
    reg.add("map(xs, f)", "[f(x) for each x in xs].", |a, ev| {
        let xs = a.list("xs")?;
        let f = a.function("f")?;
        let span = a.call_span();
        let out = xs
            .iter()
            .map(|x| ev.call(&f, vec![x.clone()], span))
            .collect::<MxResult<Vec<_>>>()?;
        Ok(Value::list(out))
    });
    reg.add(
        "filter(xs, f)",
        "The items x of xs for which f(x) is true.",
        |a, ev| {
            let xs = a.list("xs")?;
            let f = a.function("f")?;
            let span = a.call_span();
            let mut out = Vec::new();
            for x in xs.iter() {
                match ev.call(&f, vec![x.clone()], span)? {
                    Value::Bool(true) => out.push(x.clone()),
                    Value::Bool(false) => {}
                    other => {
                        return Err(a.error(
                            ErrorKind::Type,
                            format!(
                                "filter's function must return a bool, returned {}",
                                describe(&other)
                            ),
                        ));
                    }
                }
            }
            Ok(Value::list(out))
        },
    );
    reg.add(
        "fold(xs, init, f)",
        "f(…f(f(init, x0), x1)…, xn): combine a list into one value.",
        |a, ev| {
            let xs = a.list("xs")?;
            let mut acc = a.value("init")?;
            let f = a.function("f")?;
            let span = a.call_span();
            for x in xs.iter() {
                acc = ev.call(&f, vec![acc, x.clone()], span)?;
            }
            Ok(acc)
        },
    );
    reg.add(
        "sum(xs)",
        "Sum of a list of numbers (0 for an empty list).",
        |a, _| num(a.list_of_numbers("xs")?.iter().sum()),
    );
    // reverse(xs) (lists and motions) is registered by compose.rs
    reg.add(
        "sort(xs)",
        "A list of numbers or of strings, sorted ascending.",
        |a, _| {
            let arg = a.arg("xs")?;
            let Value::List(xs) = &arg.value else {
                return Err(a.type_error("xs", "a list", &arg));
            };
            let mut v: Vec<Value> = xs.to_vec();
            if v.iter().all(|x| matches!(x, Value::Number(_))) {
                v.sort_by(|x, y| {
                    x.as_number()
                        .unwrap_or(0.0)
                        .total_cmp(&y.as_number().unwrap_or(0.0))
                });
            } else if v.iter().all(|x| matches!(x, Value::Str(_))) {
                v.sort_by(|x, y| x.as_str().cmp(&y.as_str()));
            } else {
                return Err(a.type_error("xs", "a list of numbers or a list of strings", &arg));
            }
            Ok(Value::list(v))
        },
    );
    reg.add("append(xs, x)", "A new list: xs followed by x.", |a, _| {
        let xs = a.list("xs")?;
        let x = a.value("x")?;
        let mut v = xs.to_vec();
        v.push(x);
        Ok(Value::list(v))
    });
    reg.add(
        "zip(xs, ys)",
        "[[x0, y0], [x1, y1], …] up to the shorter length.",
        |a, _| {
            let xs = a.list("xs")?;
            let ys = a.list("ys")?;
            Ok(Value::list(
                xs.iter()
                    .zip(ys.iter())
                    .map(|(x, y)| Value::list(vec![x.clone(), y.clone()]))
                    .collect(),
            ))
        },
    );
}

/// Records: `keys`, `values`, `has`, `with`.
fn records(reg: &mut Registry) {
    reg.topic(Topic::Language);
    reg.add(
        "keys(r)",
        "The field names of a record, in order, or of a value with fields (an SP report, an IK report, a body, a library…): exactly the names `r.name` reads.",
        |a, _| {
            let r = a.arg("r")?;
            match r.value.keys() {
                Some(k) => Ok(Value::list(k.into_iter().map(Value::str).collect())),
                None => Err(a.type_error("r", "a record or a value with fields (an SP report)", &r)),
            }
        },
    );
    reg.add(
        "has(r, key)",
        "Whether `r` has the field `key`: one of `keys(r)`, what `r.key` reads (a record, or a value with fields such as an SP report or a body).",
        |a, _| {
            let r = a.arg("r")?;
            let k = a.string("key")?;
            if r.value.keys().is_none() {
                return Err(a.type_error("r", "a record or a value with fields (an SP report)", &r));
            }
            Ok(Value::Bool(r.value.field(&k).is_some()))
        },
    );
    reg.add(
        "with(r, key, value)",
        "A copy of the record with `key` set to `value`.",
        |a, _| {
            let r = a.record("r")?;
            let k = a.string("key")?;
            let v = a.value("value")?;
            let mut m: IndexMap<String, Value> = (*r).clone();
            m.insert(k.to_string(), v);
            Ok(Value::Record(Arc::new(m)))
        },
    );
}

/// Strings: `join`, `split`.
fn strings(reg: &mut Registry) {
    reg.topic(Topic::Language);
    reg.add(
        "split(s, sep)",
        "The parts of s between occurrences of sep, in order: `\"Hips.Xrotation\".split(\".\")` is [\"Hips\", \"Xrotation\"]; `join` puts them back.",
        |a, _| {
            let s = a.string("s")?;
            let sep = a.arg("sep")?;
            let Value::Str(sep_s) = &sep.value else {
                return Err(a.type_error("sep", "a string", &sep));
            };
            if sep_s.is_empty() {
                return Err(MxError::value("`split`: `sep` is empty, and an empty separator splits nowhere")
                    .at(sep.span)
                    .label("empty")
                    .help("give the text between the parts, e.g. `s.split(\".\")`"));
            }
            Ok(Value::list(s.split(sep_s.as_ref()).map(Value::str).collect()))
        },
    );
    reg.add(
        "join(xs, sep)",
        "The items of xs as text, separated by sep.",
        |a, _| {
            let xs = a.list("xs")?;
            let sep = a.string("sep")?;
            Ok(Value::str(
                xs.iter().map(Value::display).collect::<Vec<_>>().join(&sep),
            ))
        },
    );
}

/// `load` and `save`, dispatching on the extension to the formats other domains register.
fn files(reg: &mut Registry) {
    reg.topic(Topic::Files);
    reg.add(
        "load(path, ...options)",
        "Read a file; the format follows the extension (`:help formats` lists them).",
        |a, ev| {
            let arg = a.arg("path")?;
            let Value::Str(path) = &arg.value else {
                return Err(a.type_error("path", "a file name string", &arg));
            };
            let (ext, fmt) = format_for(ev, path, arg.span)?;
            let Some(load) = fmt.reader() else {
                return Err(MxError::new(
                    ErrorKind::Io,
                    format!("cannot load .{ext} files (only save)"),
                )
                .at(arg.span)
                .help(formats_help(ev)));
            };
            let p = ev.resolve_path(path, arg.span)?;
            load(&p, a, ev).map_err(|e| e.or_at(arg.span))
        },
    );
    reg.add(
        "save(x, path, ...options)",
        "Write x to a file, atomically; the format follows the extension. Options depend on it (e.g. `rate: 30` for .csv).",
        |a, ev| {
            let x = a.value("x")?;
            let arg = a.arg("path")?;
            let Value::Str(path) = &arg.value else { return Err(a.type_error("path", "a file name string", &arg)) };
            let (ext, fmt) = format_for(ev, path, arg.span)?;
            let Some(save) = fmt.writer() else {
                return Err(MxError::new(ErrorKind::Io, format!("cannot save .{ext} files (only load)")).at(arg.span).help(formats_help(ev)));
            };
            let p = ev.resolve_path(path, arg.span)?;
            create_parent_folder(&p, arg.span)?;
            save(&x, &p, a, ev).map_err(|e| e.or_at(arg.span))?;
            Ok(Value::Nil)
        },
    );
}

/// Scripts write under folders they name (`out/…`): `save`, `view` and
/// `plot` create them.
pub(crate) fn create_parent_folder(
    p: &std::path::Path,
    span: crate::lang::ast::Span,
) -> MxResult<()> {
    if let Some(dir) = p.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| {
            MxError::new(
                ErrorKind::Io,
                format!("cannot create folder {}: {e}", dir.display()),
            )
            .at(span)
            .help("check the path and the folder's permissions")
        })?;
    }
    Ok(())
}

fn formats_help(ev: &Evaluator) -> String {
    let mut exts: Vec<String> = ev
        .ctx
        .registry
        .formats()
        .map(|f| format!(".{}", f.ext))
        .collect();
    exts.sort();
    if exts.is_empty() {
        "no file formats are registered".into()
    } else {
        format!("known formats: {}", exts.join(", "))
    }
}

fn format_for(
    ev: &Evaluator,
    path: &str,
    span: crate::lang::ast::Span,
) -> MxResult<(String, Format)> {
    let ext = std::path::Path::new(path)
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    match ev.ctx.registry.format(&ext) {
        Some(f) => Ok((ext, f.clone())),
        None => Err(MxError::new(
            ErrorKind::Io,
            if ext.is_empty() {
                format!("`{path}` has no extension to choose a file format by")
            } else {
                format!("unknown file format `.{ext}`")
            },
        )
        .at(span)
        .label("unknown format")
        .help(formats_help(ev))),
    }
}

fn extremum(a: &mut Args, is_min: bool) -> MxResult<Value> {
    let items = a.rest();
    let nums: Vec<f64> = match items.as_slice() {
        [one] if matches!(one.value, Value::List(_)) => {
            let Value::List(l) = &one.value else {
                unreachable!()
            };
            l.iter()
                .map(|v| {
                    v.as_number()
                        .ok_or_else(|| a.type_error("x", "a list of numbers", one))
                })
                .collect::<MxResult<_>>()?
        }
        _ => items
            .iter()
            .map(|v| {
                v.value
                    .as_number()
                    .ok_or_else(|| a.type_error("x", "a number", v))
            })
            .collect::<MxResult<_>>()?,
    };
    if nums.is_empty() {
        return Err(a.error(
            ErrorKind::Arity,
            format!("`{}` needs at least one number", a.name()),
        ));
    }
    let r = nums.iter().copied().fold(
        if is_min {
            f64::INFINITY
        } else {
            f64::NEG_INFINITY
        },
        |acc, x| {
            if x.is_nan() || acc.is_nan() {
                f64::NAN
            } else if is_min {
                acc.min(x)
            } else {
                acc.max(x)
            }
        },
    );
    num(r)
}
