//! Motion CSV and JSON files.

use std::sync::Arc;

use mx::io::ContentError;
use mx::io::csv::{save_csv, to_csv_string};
use mx::io::motion_json::{from_json_str, load_json, save_json, to_json_string};
use mx::motion::*;

fn c(v: f64, a: f64, b: f64) -> Interval {
    Interval::constant(v, a, b).unwrap()
}

/// A toy "function of time" whose source is its slope: `k*t`.
#[derive(Debug)]
struct Slope(f64);
impl TimeFunction for Slope {
    fn eval(&self, t: f64) -> Result<f64, mx::motion::FnError> {
        Ok(self.0 * t)
    }
    fn source(&self) -> Option<String> {
        Some(format!("{}*t", self.0))
    }
}

fn compile(src: &str) -> Result<Arc<dyn TimeFunction>, ContentError> {
    let k = src.strip_suffix("*t").ok_or("not k*t")?;
    Ok(Arc::new(Slope(
        k.parse::<f64>()
            .map_err(|e| ContentError::new(e.to_string()))?,
    )))
}

#[derive(Debug)]
struct Host;
impl TimeFunction for Host {
    fn eval(&self, t: f64) -> Result<f64, mx::motion::FnError> {
        Ok(t)
    }
}

#[test]
fn csv_header_rows_and_empty_cells() {
    let mut m = Mu::new();
    m.insert(
        "b",
        Dof::new(vec![c(0.1, 0.0, 0.5), c(2.0, 1.0, 1.0 + 1.0 / 3.0)]).unwrap(),
    );
    m.insert(
        "a,x",
        Dof::from(Interval::function(Arc::new(Slope(1.0)), 0.25, 1.0).unwrap()),
    );
    let text = to_csv_string(&m, 4.0, None).unwrap();
    assert_eq!(
        text,
        "t,b,\"a,x\"\n0,0.1,\n0.25,0.1,0.25\n0.5,0.1,0.5\n0.75,,0.75\n1,2,1\n1.25,2,\n"
    );
}

#[test]
fn csv_includes_both_ends_without_drift() {
    // 0.7 s to 2.4 s at 30 Hz: 0.7·30 = 21.000000000000004 in floating point.
    let m: Mu = [("x".to_string(), Dof::from(c(1.0, 0.7, 2.4)))]
        .into_iter()
        .collect();
    let text = to_csv_string(&m, 30.0, None).unwrap();
    let rows: Vec<&str> = text.lines().skip(1).collect();
    assert_eq!(rows.len(), 72 - 21 + 1);
    assert_eq!(rows[0], "0.7,1");
    assert_eq!(*rows.last().unwrap(), "2.4,1");
    // 60 s at 120 Hz: exactly 7201 rows, the last at t = 60.
    let m: Mu = [("x".to_string(), Dof::from(c(1.0, 0.0, 60.0)))]
        .into_iter()
        .collect();
    let text = to_csv_string(&m, 120.0, None).unwrap();
    assert_eq!(text.lines().count(), 7202);
    assert_eq!(text.lines().last().unwrap(), "60,1");
}

#[test]
fn csv_conflict_is_an_error_naming_dof_and_span() {
    let a: Mu = [("Hips.Yrotation".to_string(), Dof::from(c(1.0, 0.0, 2.0)))]
        .into_iter()
        .collect();
    let b: Mu = [("Hips.Yrotation".to_string(), Dof::from(c(2.0, 1.0, 3.0)))]
        .into_iter()
        .collect();
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("out.csv");
    let e = save_csv(&plus(&a, &b), &p, 10.0).unwrap_err().to_string();
    assert!(e.contains("Hips.Yrotation") && e.contains("[1, 2]"), "{e}");
    assert!(!p.exists(), "a failed save writes nothing");
}

#[test]
fn csv_bad_rates_and_empty_motion() {
    let m: Mu = [("x".to_string(), Dof::from(c(1.0, 0.0, 1.0)))]
        .into_iter()
        .collect();
    for r in [0.0, -30.0, f64::NAN, f64::INFINITY] {
        assert!(
            matches!(to_csv_string(&m, r, None), Err(MotionError::BadRate { .. })),
            "{r}"
        );
    }
    assert!(matches!(
        to_csv_string(&m, 1e12, None),
        Err(MotionError::TooManySamples { .. })
    ));
    let empty: Mu = [("x".to_string(), Dof::empty())].into_iter().collect();
    assert_eq!(to_csv_string(&empty, 30.0, None).unwrap(), "t,x\n");
}

fn rich_motion() -> Mu {
    let samples = Curve::samples(
        0.0,
        1.0 / 120.0,
        (0..240).map(|k| (k as f64 * 0.1).sin() * 0.1).collect(),
    )
    .unwrap();
    let herm = Curve::Hermite(HermiteCurve::new(0.0, 0.1, 0.0, 1.0, 0.3, -0.2).unwrap());
    let basis = mx::spline::BSplineBasis::clamped_uniform(3, 7, 0.0, 1.5).unwrap();
    let coeffs = vec![0.0, 0.3, -0.2, 0.5, 0.1, 0.9, 1.0];
    let spline = Curve::spline(mx::spline::BSplineCurve::new(basis, coeffs).unwrap()).unwrap();
    let mut m = Mu::new();
    m.insert(
        "spline",
        Dof::from(Interval::curve(spline, 0.2, 1.5).unwrap()),
    );
    m.insert(
        "Hips.Xposition",
        Dof::from(Interval::curve(samples, 0.0, 239.0 / 120.0).unwrap()),
    );
    m.insert(
        "slope",
        Dof::new(vec![
            Interval::function(Arc::new(Slope(0.1)), 0.1, 0.7).unwrap(),
        ])
        .unwrap(),
    );
    m.insert("h", Dof::from(Interval::curve(herm, 0.0, 1.0).unwrap()));
    // Shared curves, affine maps, a conflict and a gap.
    let a = affine(0.3, 0.7, &m).unwrap();
    let b = clip(0.2, 0.9, &m).unwrap();
    plus(&concatenate(&m, &a), &b)
}

#[test]
fn json_round_trips_exactly() {
    let m = rich_motion();
    assert!(!conflicts(&m).is_empty() && !gaps(&m).is_empty());
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("m.json");
    save_json(&m, &p).unwrap();
    let back = load_json(&p, &compile).unwrap();
    assert_eq!(back, m);
    // Same text again: nothing was lost or reordered.
    assert_eq!(to_json_string(&back).unwrap(), to_json_string(&m).unwrap());
    // And the same samples, bit for bit.
    let names: Vec<String> = m.names().map(str::to_string).collect();
    for n in &names {
        for k in 0..400 {
            let t = k as f64 / 97.0;
            match (m.sample(n, t), back.sample(n, t)) {
                (Ok(a), Ok(b)) => assert_eq!(
                    a.map(|v| v.map(f64::to_bits)),
                    b.map(|v| v.map(f64::to_bits))
                ),
                (Err(a), Err(b)) => assert_eq!(a, b),
                (a, b) => panic!("{n} at {t}: {a:?} vs {b:?}"),
            }
        }
    }
}

#[test]
fn json_refuses_host_functions_and_bad_files() {
    let m: Mu = [(
        "x".to_string(),
        Dof::from(Interval::function(Arc::new(Host), 0.0, 1.0).unwrap()),
    )]
    .into_iter()
    .collect();
    let e = to_json_string(&m).unwrap_err().to_string();
    assert!(e.contains("'x'") && e.contains("no mx source"), "{e}");

    for (bad, why) in [
        ("{", "not an mx motion"),
        (
            r#"{"format":"other","version":1,"curves":[],"dofs":[]}"#,
            "format",
        ),
        (
            r#"{"format":"mx-motion","version":9,"curves":[],"dofs":[]}"#,
            "version 9",
        ),
        (
            r#"{"format":"mx-motion","version":1,"curves":[],"dofs":[{"name":"x","intervals":[{"start":0,"stop":1,"funcs":[{"curve":3,"shift":0,"scale":1,"offset":0}]}]}]}"#,
            "curve 3",
        ),
        (
            r#"{"format":"mx-motion","version":1,"curves":[{"kind":"constant","value":1}],"dofs":[{"name":"x","intervals":[{"start":1,"stop":1,"funcs":[{"curve":0,"shift":0,"scale":1,"offset":0}]}]}]}"#,
            "empty",
        ),
        (
            r#"{"format":"mx-motion","version":1,"curves":[{"kind":"samples","t0":0,"dt":0,"values":[1]}],"dofs":[]}"#,
            "step",
        ),
        (
            r#"{"format":"mx-motion","version":1,"curves":[{"kind":"constant","value":1}],"dofs":[{"name":"x","intervals":[{"start":0,"stop":2,"funcs":[{"curve":0,"shift":0,"scale":1,"offset":0}]},{"start":1,"stop":3,"funcs":[{"curve":0,"shift":0,"scale":1,"offset":0}]}]}]}"#,
            "sorted and disjoint",
        ),
        (
            r#"{"format":"mx-motion","version":1,"curves":[{"kind":"function","source":"sin(t)"}],"dofs":[]}"#,
            "cannot compile",
        ),
        (
            r#"{"format":"mx-motion","version":1,"curves":[{"kind":"spline","basis":{"kind":"knots","degree":1,"knots":[0,0,1,1]},"coeffs":[1]}],"dofs":[]}"#,
            "curve 0",
        ),
    ] {
        let e = from_json_str(bad, &compile).unwrap_err().to_string();
        assert!(e.contains(why), "{bad}: {e}");
    }
    let e = load_json("/no/such/file.json", &compile)
        .unwrap_err()
        .to_string();
    assert!(e.contains("/no/such/file.json"), "{e}");
}

#[test]
fn json_checks_spline_coefficients() {
    let bad = r#"{"format":"mx-motion","version":1,"curves":[{"kind":"spline","basis":{"kind":"knots","degree":1,"knots":[0,0,1,1]},"coeffs":[1]}],"dofs":[]}"#;
    let e = from_json_str(bad, &compile).unwrap_err().to_string();
    assert!(e.contains("needs 2 coefficients"), "{e}");
}

#[test]
fn csv_loads_back_what_it_saved() {
    use mx::io::csv::{from_csv_str, load_csv};
    let mut m = Mu::new();
    let vals: Vec<f64> = (0..61).map(|k| (k as f64 * 0.05).sin()).collect();
    m.insert(
        "a,\"q\"",
        Dof::new(vec![
            Interval::curve(Curve::samples(0.0, 0.05, vals.clone()).unwrap(), 0.0, 1.0).unwrap(),
            Interval::curve(Curve::samples(0.0, 0.05, vals).unwrap(), 2.0, 3.0).unwrap(),
        ])
        .unwrap(),
    );
    m.insert("b", Dof::from(c(0.1, 0.5, 3.0)));
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("m.csv");
    save_csv(&m, &p, 20.0).unwrap();
    let back = load_csv(&p).unwrap();
    assert_eq!(back.names().collect::<Vec<_>>(), vec!["a,\"q\"", "b"]);
    assert_eq!(gaps(&back).len(), 1);
    // Same text when saved again: every value at every grid time is exact.
    assert_eq!(
        to_csv_string(&back, 20.0, None).unwrap(),
        std::fs::read_to_string(&p).unwrap()
    );

    for (bad, why) in [
        ("", "empty"),
        ("x,a\n0,1\n", "first column"),
        ("t,a\n0,1\n0.1\n", "line 3"),
        ("t,a\n0,1\n0.1,x\n", "not a finite number"),
        ("t,a\n0,1\n0.1,2\n0.35,3\n", "uniform grid"),
        ("t,a\n0,1\n0.1,\n0.2,3\n0.3,4\n", "isolated"),
        ("t,a,a\n0,1,1\n1,2,2\n", "twice"),
        ("t,\"a\n0,1\n", "unclosed quote"),
    ] {
        let e = from_csv_str(bad).unwrap_err().to_string();
        assert!(e.contains(why), "{bad:?}: {e}");
    }
}
