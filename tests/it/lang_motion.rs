//! The motion forms of the language, end to end: the public surface of
//! issue 2 as written, save/load, and mx functions of time sampled from
//! rayon threads (as spacetime optimisation does).

use mx::Interpreter;
use mx::lang::builtins::motion::as_mu;
use rayon::prelude::*;

fn run(src: &str) -> (mx::Value, String) {
    let mut mx = Interpreter::new();
    let out = mx.capture_output();
    let v = match mx.eval_str(src) {
        Ok(v) => v,
        Err(d) => panic!("{}", d.render_plain()),
    };
    let s = String::from_utf8(out.lock().unwrap().clone()).unwrap();
    (v, s)
}

#[test]
fn the_three_cases_of_each_operator() {
    // Disjoint, overlapping and nested intervals on one DOF.
    let (_, out) = run("
        let a = mu({x: interval(1, 0, 2)})
        let disjoint = mu({x: interval(2, 3, 4)})
        let overlap = mu({x: interval(2, 1, 3)})
        let inside = mu({x: interval(2, 0.5, 1.5)})
        print(span(a & disjoint), span(a & overlap), span(a & inside))
        print(gaps(a - disjoint), span(a - overlap), gaps(a - inside))
        print(conflicts(a + disjoint), conflicts(a + overlap), conflicts(a + inside))
        print(conflicts(a & overlap))
    ");
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines[0], "nil [1, 2] [0.5, 1.5]");
    assert_eq!(
        lines[1],
        "[{dof: \"x\", start: 2, stop: 3}] [0, 3] [{dof: \"x\", start: 0.5, stop: 1.5}]"
    );
    assert_eq!(
        lines[2],
        "[] [{dof: \"x\", start: 1, stop: 2}] [{dof: \"x\", start: 0.5, stop: 1.5}]"
    );
    assert_eq!(lines[3], "[{dof: \"x\", start: 1, stop: 2}]");
}

#[test]
fn functions_of_time_give_values_and_derivatives() {
    let (v, _) = run(
        "let k = interval(fn(t) = 0.1 * sin(2 * pi * t), 0s, 2s)\n[sample(k, 0.25), sample(k, 0, deriv: 1), sample(k, 0.25, deriv: 2)]",
    );
    let xs: Vec<f64> = v
        .as_list()
        .unwrap()
        .iter()
        .map(|x| x.as_number().unwrap())
        .collect();
    let w = 2.0 * std::f64::consts::PI;
    assert!((xs[0] - 0.1).abs() < 1e-15);
    assert!((xs[1] - 0.1 * w).abs() < 1e-9, "velocity {}", xs[1]);
    assert!((xs[2] + 0.1 * w * w).abs() < 1e-5, "acceleration {}", xs[2]);
}

#[test]
fn csv_and_json_round_trip_through_the_language() {
    let dir = tempfile::tempdir().unwrap();
    let mut mx = Interpreter::new();
    mx.capture_output();
    mx.set_file_root(Some(dir.path().to_path_buf()));
    let src = "
        let k = 3
        fn bounce(t) = 0.1 * sin(k * t)
        let m = mu({b: dof(interval(2, 0, 0.5), interval(bounce, 1, 2)), a: interval(fn(t) = t * t, 0, 2)})
        save(m, \"m.csv\", rate: 4)
        save(m, \"sub/m.json\")
        let back = load(\"sub/m.json\")
        [back == m, sample(back, 1.5), sample(m, 1.5)]";
    let v = match mx.eval_str(src) {
        Ok(v) => v,
        Err(d) => panic!("{}", d.render_plain()),
    };
    let l = v.as_list().unwrap();
    assert_eq!(l[0].as_bool(), Some(true));
    assert!(l[1].equals(&l[2]));
    let csv = std::fs::read_to_string(dir.path().join("m.csv")).unwrap();
    let rows: Vec<&str> = csv.lines().collect();
    assert_eq!(rows[0], "t,b,a", "columns in first-definition order");
    assert_eq!(rows.len(), 1 + 9, "t = 0, 0.25, …, 2");
    assert_eq!(rows[3], "0.5,2,0.25");
    assert_eq!(rows[4], "0.75,,0.5625", "undefined is an empty cell");
}

#[test]
fn mx_functions_sample_in_parallel_from_rayon_threads() {
    let (v, _) = run(
        "mu({x: interval(fn(t) = 2 * t + sin(t), 0, 10), y: interval(fn(t) = if t < 5 { t } else { 10 - t }, 0, 10)})",
    );
    let mu = as_mu(&v).expect("a Mu").clone();
    let times: Vec<f64> = (0..=1000).map(|k| k as f64 / 100.0).collect();
    let par: Vec<(f64, f64)> = times
        .par_iter()
        .map(|&t| {
            (
                mu.sample_value("x", t).unwrap().unwrap(),
                mu.sample_value("y", t).unwrap().unwrap(),
            )
        })
        .collect();
    for (t, (x, y)) in times.iter().zip(par) {
        assert_eq!(x, 2.0 * t + t.sin());
        assert_eq!(y, if *t < 5.0 { *t } else { 10.0 - t });
    }
}

#[test]
fn prelude_helpers() {
    let (_, out) = run("
        let a = mu({x: interval(1, 0, 1)})
        let b = mu({x: interval(2, 0, 2)})
        print(span(shift(a, 2)), duration(repeat(a, 4)), gaps(gap_between(a, b, 0.5)), span(stretch(shift(a, 1), 3)))");
    assert_eq!(out, "[2, 3] 4 [{dof: \"x\", start: 1, stop: 1.5}] [1, 4]\n");
}

#[test]
fn a_failing_function_of_time_names_the_dof_and_the_time() {
    // `y` fails past t = 1 (1 / 0 is an error in mx); `x` is fine.
    let src = "fn bad(t) = if t < 1 { t } else { 1 / 0 }\n\
               let m = mu({x: interval(1, 0, 2), \"Hips.Yrotation\": interval(bad, 0, 2)})\n";
    let dir = tempfile::tempdir().unwrap();
    for (call, t) in [
        ("sample(m, 1.5)", "1.5"),
        ("save(m, \"out.csv\", rate: 4)", "1"),
    ] {
        let mut mx = Interpreter::new();
        mx.capture_output();
        mx.set_file_root(Some(dir.path().to_path_buf()));
        let e = mx.eval_str(&format!("{src}{call}")).unwrap_err();
        let msg = e.render_plain();
        assert!(msg.contains("DOF 'Hips.Yrotation'"), "{call}: {msg}");
        assert!(msg.contains(&format!("t = {t}")), "{call}: {msg}");
        assert!(msg.contains("division by zero"), "{call}: {msg}");
    }
}

#[test]
fn negative_zero_is_written_as_minus_zero_everywhere_and_reads_back() {
    let dir = tempfile::tempdir().unwrap();
    let mut mx = Interpreter::new();
    let out = mx.capture_output();
    mx.set_file_root(Some(dir.path().to_path_buf()));
    let src = "let m = mu({x: interval(-0.0, 0, 1)})\n\
               print(-0.0, sample(m, 0.5).x, -0 == 0, [-0], {a: -0})\n\
               save(m, \"z.csv\", rate: 2)\n\
               save(m, \"z.json\")\n\
               print(sample(load(\"z.json\"), 0.5).x, sample(load(\"z.csv\"), 0.5).x)";
    if let Err(d) = mx.eval_str(src) {
        panic!("{}", d.render_plain());
    }
    let printed = String::from_utf8(out.lock().unwrap().clone()).unwrap();
    let lines: Vec<&str> = printed.lines().collect();
    assert_eq!(lines[0], "-0 -0 true [-0] {a: -0}");
    // JSON and CSV both keep the sign bit: the round trips are exact.
    assert_eq!(lines[1], "-0 -0");
    let csv = std::fs::read_to_string(dir.path().join("z.csv")).unwrap();
    assert_eq!(csv, "t,x\n0,-0\n0.5,-0\n1,-0\n");
}
