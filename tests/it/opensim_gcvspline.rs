//! OpenSim's GCVSpline (interpolating, error_variance 0) against OpenSim 4.6:
//! values, first and second derivatives inside and outside the knots, for
//! half orders 1–3 (references by `scripts/opensim_refs.py` in
//! `tests/data/opensim/functions/gcvspline.json`).

use crate::common;

use mx::model::joints::ScalarFunction;
use serde_json::Value;

/// max |a − b| / max(max |b|, 1)
fn rel(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(1.0f64, |m, v| m.max(v.abs()));
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
        / scale
}

/// Each case also carries the exact spline (50 digits). Interpolation through
/// close points is ill-conditioned in itself: where the closest two points are
/// under 1 % of the range apart (the 9- and 15-point quintic cases, 0.4 % and
/// 0.6 %), OpenSim's GCVSPL is itself 2e-13–7e-12 off the exact spline and
/// mx 1e-12–2e-11; there both are held to 2e-11 of the exact spline, and
/// elsewhere mx to OpenSim within 1e-12.
#[test]
fn gcvspline_evaluates_as_opensim_does() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/opensim/functions/gcvspline.json");
    let r: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let cases = r["cases"].as_array().unwrap();
    assert!(cases.len() >= 3);
    let (mut worst_opensim, mut worst_exact) = (0.0f64, 0.0f64);
    for c in cases {
        let f = ScalarFunction::from_osim_xml(c["xml"].as_str().unwrap()).unwrap();
        let t = common::json_f64s(&c["t"]);
        let x = knots(c["xml"].as_str().unwrap());
        let gap = x
            .windows(2)
            .map(|w| w[1] - w[0])
            .fold(f64::INFINITY, f64::min);
        let well_spaced = gap >= 0.01 * (x[x.len() - 1] - x[0]);
        let got: Vec<[f64; 3]> = t.iter().map(|x| f.eval(*x)).collect();
        let mut line = format!(
            "half_order {}, {} points (closest {:.1} % of the range):",
            c["half_order"],
            x.len(),
            100.0 * gap / (x[x.len() - 1] - x[0])
        );
        for (d, q) in ["value", "d1", "d2"].iter().enumerate() {
            let mine: Vec<f64> = got.iter().map(|g| g[d]).collect();
            let opensim = common::json_f64s(&c[*q]);
            let exact = common::json_f64s(&c[format!("{q}_exact").as_str()]);
            let (vs_opensim, vs_exact) = (rel(&mine, &opensim), rel(&mine, &exact));
            let opensim_own = rel(&opensim, &exact);
            line += &format!(
                " {q} mx–OpenSim {vs_opensim:.1e} (mx–exact {vs_exact:.1e}, OpenSim–exact {opensim_own:.1e});"
            );
            if well_spaced {
                assert!(vs_opensim <= 1e-12, "{line}");
            } else {
                assert!(vs_exact <= 2e-11 && opensim_own <= 2e-11, "{line}");
            }
            worst_opensim = worst_opensim.max(vs_opensim);
            worst_exact = worst_exact.max(vs_exact);
        }
        eprintln!("{line}");
    }
    eprintln!("worst: mx–OpenSim {worst_opensim:.1e}, mx–exact {worst_exact:.1e}");
}

fn knots(xml: &str) -> Vec<f64> {
    let x = xml
        .split("<x>")
        .nth(1)
        .unwrap()
        .split("</x>")
        .next()
        .unwrap();
    x.split_whitespace().map(|v| v.parse().unwrap()).collect()
}

#[test]
fn bad_gcvsplines_are_clear_errors() {
    let e = |xml: &str| ScalarFunction::from_osim_xml(xml).unwrap_err().0;
    let msg = e(
        "<GCVSpline><half_order>3</half_order><error_variance>0.01</error_variance>\
                 <x>0 1 2 3 4 5</x><y>0 1 0 1 0 1</y></GCVSpline>",
    );
    assert!(msg.contains("smoothing"), "{msg}");
    let msg = e("<GCVSpline><half_order>2</half_order><x>0 2 1 3</x><y>0 1 0 1</y></GCVSpline>");
    assert!(msg.contains("strictly increasing"), "{msg}");
    let msg = e("<GCVSpline><half_order>3</half_order><x>0 1 2</x><y>0 1 0</y></GCVSpline>");
    assert!(msg.contains("at least 6 points"), "{msg}");
    let msg = e("<GCVSpline><half_order>5</half_order><x>0 1 2</x><y>0 1 0</y></GCVSpline>");
    assert!(msg.contains("half_order"), "{msg}");
}
