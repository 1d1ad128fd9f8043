//! Snapshots of the diagnostics for many kinds of bad input: the message, the
//! exact span (drawn under the source), the label and the help line.
//! Rendered without colour so snapshots are stable.

use mx::Interpreter;

fn diagnose(src: &str) -> String {
    let mut mx = Interpreter::new();
    mx.capture_output();
    mx.set_file_root(Some(std::env::temp_dir().join("mx-diag-tests")));
    mx.set_step_budget(Some(50_000));
    mx.set_max_depth(200);
    match mx.eval_named("bad.mx", src) {
        Ok(v) => panic!("expected an error from {src:?}, got {}", v.repr()),
        Err(d) => format!("[{}]\n{}", d.error().kind.code(), d.render_plain()),
    }
}

const WALK: &str = "let walk = mu({x: interval(fn(t) = t, 0, 2.4), y: interval(1, 0, 2.4)})\n";

macro_rules! case {
    ($name:ident, $src:expr) => {
        #[test]
        fn $name() {
            insta::assert_snapshot!(stringify!($name), diagnose(&$src));
        }
    };
}

case!(unknown_name_did_you_mean, format!("{WALK}print(wakl)"));
case!(unknown_function, "let m = 1\nprint(intreval(1, 0, 1))");
case!(unknown_method, format!("{WALK}walk.onyl(\"x\")"));
case!(wrong_argument_type, "sin(\"x\")");
case!(too_many_arguments, "sin(1, 2)");
case!(missing_argument, "interval(1, 0)");
case!(
    unknown_named_argument,
    format!("{WALK}save(walk, \"x.csv\", rat: 30)")
);
case!(user_function_arity, "fn f(t) = t\nf(1, 2)");
case!(division_by_zero, "let a = 3\nlet b = a - 3\nprint(a / b)");
case!(recursion_too_deep, "fn down(n) = down(n + 1)\ndown(0)");
case!(
    nesting_too_deep_brackets,
    format!("let x = {}1", "[\n".repeat(100_000))
);
case!(
    nesting_too_deep_lambdas,
    format!("let f = {}x", "fn(x) =\n".repeat(100_000))
);
case!(
    step_budget,
    "fn count(n) = if n > 0 { count(n - 1) } else { 0 }\nmap(range(1000), fn(i) = count(100))"
);
case!(clip_outside_span, format!("{WALK}clip(2.0, 3.5, walk)"));
case!(
    sampling_a_conflict,
    format!("{WALK}sample(walk + walk, 0.5)")
);
case!(
    csv_of_a_conflict,
    format!("{WALK}save(walk + shift(walk, 1), \"c.csv\", rate: 10)")
);
case!(csv_without_rate, format!("{WALK}save(walk, \"c.csv\")"));
case!(unclosed_bracket, "let xs = [1, 2,\n  3\nprint(xs)");
case!(unterminated_string, "print(\"hello)\n");
case!(bad_unit_suffix, "let t = 2sec");
case!(missing_operand, "let x = 1 +* 2");
case!(if_condition_not_bool, "if 1 { 2 } else { 3 }");
case!(call_a_number, "let x = 1\nx(2)");
case!(add_number_and_string, "1 + \"a\"");
case!(missing_record_field, "let r = {alpha: 1}\nr.alpah");
case!(index_out_of_range, "[1, 2, 3][3]");
case!(mu_field_not_motion, "mu({x: 1})");
case!(mixing_mu_and_dof, format!("{WALK}walk + interval(1, 0, 1)"));
case!(unknown_file_format, format!("{WALK}save(walk, \"x.xyz\")"));
case!(
    path_outside_root,
    format!("{WALK}save(walk, \"../x.json\")")
);
case!(only_matches_nothing, format!("{WALK}walk.only(\"Arm*\")"));
case!(duplicate_record_field, "{a: 1, a: 2}");
case!(empty_interval, "interval(1, 2, 1)");
case!(sqrt_domain, "sqrt(-1)");
case!(
    error_inside_function_of_time,
    "let m = mu({x: interval(fn(t) = 1 / (t - t), 0, 1)})\nsample(m, 0.5)"
);

/// The source text an engine error points at: the engine names the
/// parameter at fault and the diagnostic finds the argument, named or
/// positional, without the built-in checking the value itself.
fn pointed_at(src: &str) -> (String, String) {
    let mut mx = Interpreter::new();
    mx.capture_output();
    let e = match mx.eval_named("bad.mx", src) {
        Ok(v) => panic!("expected an error from {src:?}, got {}", v.repr()),
        Err(d) => d.error().clone(),
    };
    let s = e.span.expect("a span");
    (src[s.start as usize..s.end as usize].to_string(), e.message)
}

#[test]
fn engine_errors_point_at_the_argument_they_name() {
    let two = "let a = mu({x: interval(1, 0, 1)})\nlet b = mu({x: interval(2, 0, 1)})\n";
    // blend's weight: positional; the range is the engine's check
    let (at, msg) = pointed_at(&format!("{two}blend(a, b, 1.5)"));
    assert_eq!(at, "1.5");
    assert!(msg.contains("weight must lie in [0, 1], got 1.5"), "{msg}");
    // layer's weight: named (it used to point at the whole call)
    let (at, _) = pointed_at(&format!("{two}layer(a, b, w: -1)"));
    assert_eq!(at, "-1");
    // resample's rate
    let (at, msg) = pointed_at(&format!("{two}resample(a, 0)"));
    assert_eq!(at, "0");
    assert!(msg.contains("sampling rate"), "{msg}");
}

#[test]
fn sp_option_errors_come_from_the_engine_and_point_at_the_option() {
    // SP's ranges are checked once, by the engine (`SpOptions::check`); the
    // diagnostic points at the argument the engine names
    let walk = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/data/walk.bvh");
    let head = format!(
        "let w = load(\"{walk}\")\nlet m = w - clip_in_place(0.4, 0.6, w)\nlet b = body_of(w)\n"
    );
    for (call, at, says, help) in [
        (
            "SP(m, body: b, coefficients: 1)",
            "1",
            "from 2 to 200",
            "B-spline",
        ),
        (
            "SP(m, body: b, continuity: 2, coefficients: 2)",
            "2",
            "from 3 to 200",
            "B-spline",
        ),
        (
            "SP(m, body: b, samples: 0)",
            "0",
            "`samples: 0`",
            "Gauss points",
        ),
        (
            "SP(m, body: b, samples: 1e12)",
            "1e12",
            "from 1 to 100000",
            "Gauss points",
        ),
        (
            "SP(m, body: b, iterations: 1e9)",
            "1e9",
            "from 0 to 1000000",
            "solver iterations",
        ),
        (
            "SP(m, body: b, tolerance: 2)",
            "2",
            "in (0, 1)",
            "25 iterations",
        ),
        ("SP(m, body: b, smoothness: -1)", "-1", "non-negative", "λ"),
        (
            "SP(m, body: b, time_constant: 0)",
            "0",
            "positive time",
            "damps",
        ),
        (
            "SP(m, body: b, support: [\"Lefty\"])",
            "[\"Lefty\"]",
            "no frame named `Lefty`",
            "frames",
        ),
        (
            "SP(m, body: b, contact: [\"Toez\"])",
            "[\"Toez\"]",
            "to plant",
            "frames",
        ),
    ] {
        let src = format!("{head}{call}");
        let mut mx = Interpreter::new();
        mx.capture_output();
        let e = mx.eval_named("bad.mx", &src).unwrap_err().error().clone();
        let s = e.span.expect("a span");
        assert_eq!(
            &src[s.start as usize..s.end as usize],
            at,
            "{call}: {}",
            e.message
        );
        assert!(e.message.contains(says), "{call}: {}", e.message);
        let h = e.help.clone().unwrap_or_default();
        assert!(h.contains(help), "{call}: help {h}");
    }
    // the nearest names come with an unknown support frame, joints first
    let (_, msg) = pointed_at(&format!("{head}SP(m, body: b, support: [\"LeftFot\"])"));
    assert!(msg.contains("LeftFoot"), "{msg}");
    assert!(!msg.contains("LeftFoot.X"), "{msg}");
}
