//! OpenSim CoordinateCouplerConstraints enforced as coupled coordinates,
//! against OpenSim 4.6 (references by `scripts/opensim_refs.py` in
//! `tests/data/opensim/couplers/`, every `.osim` there a case): per random
//! state of the independent coordinates, the dependent coordinates' values,
//! the mass matrix Gᵀ M G, inverse dynamics Gᵀ τ, and forward dynamics
//! against Simbody's own with the constraints enforced (Lagrange
//! multipliers, no G involved).

use crate::common;

use std::path::PathBuf;

use mx::Interpreter;
use mx::dynamics::{
    Forces, JointState, Workspace, coupled_forward_dynamics, coupled_inverse_dynamics,
    coupled_mass_matrix,
};
use mx::model::Model;
use nalgebra::Vector3;
use serde_json::Value;

const REL_TOL: f64 = 1e-9;

fn dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/opensim/couplers")
}

fn cases() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir())
        .expect("tests/data/opensim/couplers")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "osim"))
        .collect();
    v.sort();
    assert!(!v.is_empty(), "no coupler models in {}", dir().display());
    v
}

fn f64s(v: &Value) -> Vec<f64> {
    common::json_f64s(v)
}

/// max |a − b| / max(max |b|, 1)
fn rel(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let scale = b.iter().fold(1.0f64, |m, x| m.max(x.abs()));
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
        / scale
}

#[test]
fn couplers_agree_with_opensim_in_the_independent_coordinates() {
    for osim in cases() {
        let loaded = Model::from_osim_file(&osim).unwrap();
        let c = loaded.coupling().unwrap().expect("the model has couplers");
        assert!(!c.is_linear(), "SimmSpline and Polynomial couplers");
        let r: Value =
            serde_json::from_str(&std::fs::read_to_string(osim.with_extension("json")).unwrap())
                .unwrap();
        let names: Vec<&str> = r["coordinates"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_str().unwrap())
            .collect();
        assert_eq!(c.names(), names.as_slice());
        let m = &loaded.model;
        let g = f64s(&r["gravity"]);
        let g = Vector3::new(g[0], g[1], g[2]);
        let mut ws = Workspace::new(m);
        let (mut wq, mut wm, mut wid, mut wfd) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        let states = r["states"].as_array().unwrap();
        assert!(!states.is_empty());
        for s in states {
            let (q, u, ud) = (f64s(&s["q"]), f64s(&s["u"]), f64s(&s["udot"]));
            let n = q.len();
            let mut full = vec![0.0; m.nq()];
            c.expand_q(&q, &mut full);
            wq = wq.max(rel(&full, &f64s(&s["q_full"])));
            let mm = coupled_mass_matrix(m, &c, &mut ws, &q).unwrap();
            let want: Vec<f64> = s["M"].as_array().unwrap().iter().flat_map(f64s).collect();
            let got: Vec<f64> = (0..n)
                .flat_map(|i| (0..n).map(move |j| (i, j)))
                .map(|(i, j)| mm[(i, j)])
                .collect();
            wm = wm.max(rel(&got, &want));
            let mut tau = vec![0.0; n];
            coupled_inverse_dynamics(m, &c, &mut ws, &JointState::new(&q, &u, &ud), &g, &mut tau)
                .unwrap();
            wid = wid.max(rel(&tau, &f64s(&s["tau"])));
            let mut qdd = vec![0.0; n];
            let zero = vec![0.0; n];
            coupled_forward_dynamics(m, &c, &mut ws, &q, &u, &Forces::new(&zero, &g), &mut qdd)
                .unwrap();
            wfd = wfd.max(rel(&qdd, &f64s(&s["udot_fd"])));
        }
        eprintln!(
            "{}: q_dependent {wq:.1e}, M {wm:.1e}, ID {wid:.1e}, FD (constrained, Simbody) {wfd:.1e} ({} states)",
            osim.file_name().unwrap().to_string_lossy(),
            states.len()
        );
        assert!(wq <= 1e-13, "dependent coordinates off by {wq:e}");
        for (what, e) in [("M", wm), ("ID", wid), ("FD", wfd)] {
            assert!(
                e <= REL_TOL,
                "{}: {what} relative error {e:e}",
                osim.display()
            );
        }
    }
}

fn path_str(p: &std::path::Path) -> String {
    format!("{:?}", p.display().to_string())
}

#[test]
fn couplers_are_enforced_by_default_and_free_on_request() {
    let osim = &cases()[0];
    let mut mx = Interpreter::new();
    mx.eval_str(&format!("let b = load({})", path_str(osim)))
        .unwrap();
    mx.eval_str(&format!(
        "let f = load({}, couplers: false)",
        path_str(osim)
    ))
    .unwrap();
    let n = |src: &str, mx: &mut Interpreter| mx.eval_str(src).unwrap().as_number().unwrap();
    assert_eq!(n("len(coordinates(b))", &mut mx), 2.0);
    assert_eq!(n("len(b.defaults)", &mut mx), 2.0);
    assert_eq!(n("len(coordinates(f))", &mut mx), 5.0);
    let report = mx.eval_str("b.report").unwrap();
    let report = report.as_str().unwrap();
    assert!(
        report.contains("c = f(a) (c_follows_a), enforced"),
        "{report}"
    );
    let report = mx.eval_str("f.report").unwrap();
    assert!(report.as_str().unwrap().contains("not enforced"));
    // the language's dynamics take the coupled body
    let tau = mx
        .eval_str("inverse_dynamics(b, [0.2, -0.1], [0.5, 1], [0, 0])")
        .unwrap();
    assert_eq!(tau.as_list().map(|l| l.len()), Some(2));
    let e = mx
        .eval_str(&format!("load({}, couplers: 1)", path_str(osim)))
        .unwrap_err()
        .to_string();
    assert!(e.contains("couplers"), "{e}");
}

#[test]
fn a_coupler_following_a_dependent_coordinate_is_a_clear_error() {
    let text = std::fs::read_to_string(&cases()[0]).unwrap();
    // d follows b, itself dependent on a
    let chained = text.replace(
        "<independent_coordinate_names>e</independent_coordinate_names>",
        "<independent_coordinate_names>b</independent_coordinate_names>",
    );
    assert_ne!(chained, text);
    let loaded = Model::from_osim_str(&chained).unwrap();
    let e = loaded.coupling().unwrap_err().to_string();
    assert!(
        e.contains("cannot be enforced") && e.contains("`d` follows `b`"),
        "{e}"
    );
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("chained.osim");
    std::fs::write(&p, &chained).unwrap();
    let mut mx = Interpreter::new();
    let e = mx
        .eval_str(&format!("load({})", path_str(&p)))
        .unwrap_err()
        .to_string();
    assert!(e.contains("cannot be enforced"), "{e}");
    assert!(
        mx.eval_str(&format!("load({}, couplers: false)", path_str(&p)))
            .is_ok()
    );
}
