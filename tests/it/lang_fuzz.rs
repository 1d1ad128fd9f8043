//! Fuzzing the parser and evaluator with 10,000+ random and mutated scripts:
//! none may panic, hang or overflow the stack. Each runs with a step budget,
//! a bounded recursion depth and file access confined to a temporary folder.

use std::panic::{AssertUnwindSafe, catch_unwind};

use mx::Interpreter;

use crate::support::Rng;

const TOKENS: &[&str] = &[
    "let ",
    "fn ",
    "if ",
    " else ",
    "true",
    "false",
    "x",
    "y",
    "t",
    "m",
    "f",
    "walk",
    "(",
    ")",
    "[",
    "]",
    "{",
    "}",
    ",",
    ";",
    "\n",
    ":",
    ".",
    "=",
    "+",
    "-",
    "−",
    "*",
    "/",
    "%",
    "&",
    "∧",
    "&&",
    "||",
    "!",
    "<",
    "<=",
    "==",
    "!=",
    ">",
    "1",
    "0",
    "2.5",
    "1e308",
    "-0",
    "250ms",
    "2s",
    "90deg",
    "1rad",
    "\"a\"",
    "\"x.json\"",
    "\"x.csv\"",
    "\"\\u{41}\"",
    "//c\n",
    "/*c*/",
    "interval",
    "dof",
    "mu",
    "affine",
    "clip",
    "clip_in_place",
    "concatenate",
    "only",
    "span",
    "gaps",
    "conflicts",
    "sample",
    "save",
    "load",
    "print",
    "map",
    "fold",
    "range",
    "len",
    "sin",
    "sqrt",
    "repeat",
    "shift",
    "gap_between",
    "rate: ",
    "deriv: ",
    "fn(t) = t",
    "mu({a: interval(1, 0, 1)})",
    "interval(fn(t) = t * t, 0, 2)",
    " ",
    "    ",
];

const SEEDS: &[&str] = &[
    include_str!("../../examples/tour.mx"),
    include_str!("../../stdlib/prelude.mx"),
    "fn f(n) = if n <= 0 { 0 } else { f(n - 1) + 1 }\nprint(f(10))",
    "let a = mu({x: interval(1, 0, 1), y: interval(fn(t) = t, 0, 2)})\nlet b = shift(a, 0.5)\nprint(a + b, a - b, a & b, conflicts(a + b))",
    "let m = mu({x: dof(interval(1, 0, 1), interval(2, 2, 3))})\nprint(gaps(m), clip(0.5, 2.5, m), concatenate(m, m))",
    "print(map(range(10), fn(i) = i * i).fold(0, fn(a, b) = a + b))",
    "let r = {a: 1, \"b.c\": [1, 2, {d: 3}]}\nprint(r.a, r[\"b.c\"][2].d, keys(r))",
    "save(mu({x: interval(fn(t) = sin(t), 0, 1)}), \"f.json\")\nprint(load(\"f.json\"))",
];

fn mutate(rng: &mut Rng, src: &str) -> String {
    let mut s: Vec<char> = src.chars().collect();
    for _ in 0..1 + rng.below(4) {
        let n = s.len().max(1);
        match rng.below(6) {
            0 if !s.is_empty() => {
                let a = rng.below(n);
                let b = (a + 1 + rng.below(20)).min(s.len());
                s.drain(a..b);
            }
            1 => {
                let at = rng.below(s.len() + 1);
                let tok: Vec<char> = rng.pick(TOKENS).chars().collect();
                s.splice(at..at, tok);
            }
            2 if !s.is_empty() => {
                let a = rng.below(n);
                let b = (a + 1 + rng.below(40)).min(s.len());
                let copy: Vec<char> = s[a..b].to_vec();
                let at = rng.below(s.len() + 1);
                s.splice(at..at, copy);
            }
            3 if s.len() > 1 => {
                let (a, b) = (rng.below(n), rng.below(n));
                s.swap(a, b);
            }
            4 => s.truncate(rng.below(s.len() + 1)),
            _ => {
                let at = rng.below(s.len() + 1);
                s.insert(
                    at,
                    char::from_u32(0x20 + rng.below(0x60) as u32).unwrap_or(' '),
                );
            }
        }
    }
    s.into_iter().collect()
}

fn random_script(rng: &mut Rng) -> String {
    (0..1 + rng.below(40)).map(|_| rng.pick(TOKENS)).collect()
}

#[test]
fn ten_thousand_scripts_never_panic_or_hang() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut base = Interpreter::new();
    base.capture_output();
    base.set_file_root(Some(dir.path().to_path_buf()));
    base.set_step_budget(Some(20_000));
    base.set_max_depth(150);

    let mut rng = Rng::from_state(0x9E37_79B9_7F4A_7C15);
    let n = 10_500;
    let (mut ok, mut errors) = (0, 0);
    let mut panics = Vec::new();
    let start = std::time::Instant::now();
    for i in 0..n {
        let script = if i % 3 == 0 {
            random_script(&mut rng)
        } else {
            let seed = SEEDS[rng.below(SEEDS.len())];
            mutate(&mut rng, seed)
        };
        let mut mx = base.clone();
        let result = catch_unwind(AssertUnwindSafe(|| {
            let _ = mx.check_named("fuzz.mx", &script);
            match mx.eval_named("fuzz.mx", &script) {
                Ok(_) => true,
                Err(d) => {
                    // Rendering must not panic either.
                    let _ = d.render_plain();
                    false
                }
            }
        }));
        match result {
            Ok(true) => ok += 1,
            Ok(false) => errors += 1,
            Err(_) => panics.push(script),
        }
    }
    eprintln!(
        "fuzz: {n} scripts in {:.1?}: {ok} ran, {errors} errors, {} panics",
        start.elapsed(),
        panics.len()
    );
    assert!(
        panics.is_empty(),
        "scripts that panicked:\n{}",
        panics
            .iter()
            .take(5)
            .cloned()
            .collect::<Vec<_>>()
            .join("\n-----\n")
    );
    // Both paths are exercised: some scripts run, many fail cleanly.
    assert!(ok > 100 && errors > 100, "ok {ok}, errors {errors}");
}

/// Pathologically deep or long scripts, through the whole interpreter (check,
/// evaluation, rendering the diagnostic, dropping the tree) on the test
/// harness's thread: nesting beyond the limit is refused with a diagnostic,
/// long chains of operators and `else if` run. None may abort the process.
#[test]
fn deep_and_long_scripts_never_abort() {
    let mut base = Interpreter::new();
    base.capture_output();
    let n = 100_000;
    for src in [
        format!("{}1{}", "(".repeat(n), ")".repeat(n)),
        format!("[\n{}1", "[\n".repeat(n)),
        format!("{}1", "{a: ".repeat(n)),
        format!("let f = {}1", "fn(x) =\n".repeat(n)),
        format!("if {}true{}", "if ".repeat(n), " { 1 }".repeat(n)),
        format!("{}1", "if true { ".repeat(n)),
    ] {
        let mut mx = base.clone();
        let _ = mx.check_named("deep.mx", &src);
        let d = mx.eval_named("deep.mx", &src).unwrap_err();
        assert!(d.error().message.contains("nesting too deep"), "{}", d);
        let text = d.render_plain();
        assert!(text.contains("too deep") && text.contains("help"), "{text}");
    }
    for (src, expect) in [
        (format!("1{}", " + 1".repeat(n)), format!("{}", n + 1)),
        (
            format!("let x = 2\n{}x", "-".repeat(n + 1)),
            "-2".to_string(),
        ),
        (format!("{}true", "not ".repeat(n)), "true".to_string()),
        (
            format!("let x = {n}\nif x == 0 {{ 0 }}{} else {{ -1 }}", {
                (1..=n)
                    .map(|i| format!(" else if x == {i} {{ {i} }}"))
                    .collect::<String>()
            }),
            format!("{n}"),
        ),
    ] {
        let mut mx = base.clone();
        mx.check_named("long.mx", &src)
            .unwrap_or_else(|d| panic!("{}", d.render_plain()));
        match mx.eval_named("long.mx", &src) {
            Ok(v) => assert_eq!(v.repr(), expect),
            Err(d) => panic!("{}", d.render_plain()),
        }
    }
}

/// miette pads to the error's column with a format width, which panics past
/// 65,535: errors far right on a long line are rendered by location.
#[test]
fn errors_far_right_on_a_long_line_render() {
    let mut mx = Interpreter::new();
    mx.capture_output();
    for (src, at) in [
        (format!("{}$", "1 + ".repeat(30_000)), "wide.mx:1:120001"),
        (
            format!("{}{}", "x + ".repeat(30_000), "(".repeat(2000)),
            "wide.mx:1:121001",
        ),
    ] {
        let d = mx.eval_named("wide.mx", &src).unwrap_err();
        let text = d.render_plain();
        assert!(text.contains(at), "{text}");
        assert!(d.render(true).contains("line too long to show"));
    }
}
