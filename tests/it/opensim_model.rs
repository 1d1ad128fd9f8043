//! Whole OpenSim models against OpenSim 4.6 (references by `scripts/opensim_refs.py`):
//! every `.osim` in `$MX_SHARED/data/opensim` (references in `tests/data/opensim/<stem>.json`)
//! and every small per-joint-type model in `tests/data/opensim/joints`.
//!
//! Per random state: body poses in ground, the mass matrix (OpenSim's calcM
//! is in its speeds u, q̇ = N u, so M_u = Nᵀ M_q N), forward dynamics with no
//! applied force, and inverse dynamics at a random u̇ (τ_u = Nᵀ τ_q, with
//! q̈ = q̈_fd + N (u̇ − u̇_fd)). For every joint but Ball and Free, N = I.

use crate::common;

use std::path::{Path, PathBuf};

use mx::dynamics::{Workspace, forward_dynamics, inverse_dynamics, mass_matrix};
use mx::model::Model;
use mx::model::osim::MotionType;
use nalgebra::{DMatrix, DVector, Vector3};
use serde_json::Value;

const REL_TOL: f64 = 1e-9;

fn data_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/opensim")
}

fn vecf(v: &Value) -> Vec<f64> {
    common::json_f64s(v)
}

fn matf(v: &Value) -> DMatrix<f64> {
    let rows: Vec<Vec<f64>> = v.as_array().expect("rows").iter().map(vecf).collect();
    DMatrix::from_fn(rows.len(), rows.first().map_or(0, Vec::len), |i, j| {
        rows[i][j]
    })
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

#[derive(Default, Debug)]
struct Worst {
    pose: f64,
    mass: f64,
    fd: f64,
    id: f64,
    /// Models whose OpenSim velocity terms disagree with OpenSim's own mass
    /// matrix: mx's against the Lagrangian of calcM, and OpenSim's.
    lagrange: Option<(f64, f64)>,
}

fn check(osim: &Path, reference: &Path) -> Worst {
    let loaded = Model::from_osim_file(osim).unwrap_or_else(|e| panic!("{}: {e}", osim.display()));
    let m = &loaded.model;
    let r: Value = serde_json::from_str(
        &std::fs::read_to_string(reference)
            .unwrap_or_else(|e| panic!("{}: {e}", reference.display())),
    )
    .unwrap();
    let names: Vec<String> = r["coordinates"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap().to_string())
        .collect();
    assert_eq!(m.coordinate_names(), names.as_slice(), "{}", osim.display());
    let kinds: Vec<&str> = loaded
        .report
        .coordinates
        .iter()
        .map(|c| match c.motion {
            MotionType::Rotational => "rotational",
            MotionType::Translational => "translational",
            MotionType::Coupled => "coupled",
        })
        .collect();
    let want: Vec<&str> = r["motion_types"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    assert_eq!(kinds, want, "{}: coordinate motion types", osim.display());
    let g = vecf(&r["gravity"]);
    let g = Vector3::new(g[0], g[1], g[2]);
    assert!((m.default_gravity - g).norm() < 1e-15, "gravity");
    let n = m.nq();
    let mut ws = Workspace::new(m);
    let mut w = Worst::default();
    let mut poses = Vec::new();
    let states = r["states"].as_array().unwrap();
    assert!(!states.is_empty());
    for s in states {
        let q = vecf(&s["q"]);
        let qd = vecf(&s["qdot"]);
        let nmat = matf(&s["N"]);
        // poses
        m.forward_kinematics(&q, &mut poses).unwrap();
        for (body, p) in s["body_in_ground"].as_object().unwrap() {
            let k = m
                .link_index(body)
                .unwrap_or_else(|| panic!("no link {body}"));
            let rm = matf(&p["R"]);
            let pv = vecf(&p["p"]);
            for i in 0..3 {
                w.pose = w.pose.max((poses[k].p[i] - pv[i]).abs());
                for j in 0..3 {
                    w.pose = w.pose.max((poses[k].r[(i, j)] - rm[(i, j)]).abs());
                }
            }
        }
        // mass matrix
        let mut mq = DMatrix::zeros(n, n);
        mass_matrix(m, &mut ws, &q, &mut mq).unwrap();
        let mu = nmat.transpose() * &mq * &nmat;
        let want = matf(&s["M_u"]);
        w.mass = w.mass.max(rel(mu.as_slice(), want.as_slice()));
        if let Some(lag) = s.get("bias_lagrange_from_calcM") {
            let lag = vecf(lag);
            let zero = vec![0.0; n];
            let (mut b1, mut b0) = (vec![0.0; n], vec![0.0; n]);
            inverse_dynamics(m, &mut ws, &q, &qd, &zero, &g, &mut b1).unwrap();
            inverse_dynamics(m, &mut ws, &q, &zero, &zero, &g, &mut b0).unwrap();
            let bias: Vec<f64> = b1.iter().zip(&b0).map(|(a, b)| a - b).collect();
            let e = w.lagrange.get_or_insert((0.0, f64::INFINITY));
            e.0 = e.0.max(rel(&bias, &lag));
            e.1 = e.1.min(rel(&vecf(&s["bias_opensim"]), &lag));
            continue;
        }
        // forward dynamics, no applied force
        let mut qdd = vec![0.0; n];
        forward_dynamics(m, &mut ws, &q, &qd, &vec![0.0; n], &g, &mut qdd).unwrap();
        w.fd = w.fd.max(rel(&qdd, &vecf(&s["qdotdot_fd"])));
        // inverse dynamics at the reference's u̇
        let du = DVector::from_vec(vecf(&s["udot"])) - DVector::from_vec(vecf(&s["udot_fd"]));
        let acc = DVector::from_vec(vecf(&s["qdotdot_fd"])) + &nmat * du;
        let mut tau = vec![0.0; n];
        inverse_dynamics(m, &mut ws, &q, &qd, acc.as_slice(), &g, &mut tau).unwrap();
        let tau_u = nmat.transpose() * DVector::from_vec(tau);
        w.id = w.id.max(rel(tau_u.as_slice(), &vecf(&s["tau_u"])));
    }
    let dynamics = match w.lagrange {
        Some(_) => "FD and ID: against the Lagrangian, below".to_string(),
        None => format!("FD {:.1e}, ID {:.1e}", w.fd, w.id),
    };
    eprintln!(
        "{}: poses {:.1e}, M {:.1e}, {dynamics} ({} states, nq {n})",
        osim.file_name().unwrap().to_string_lossy(),
        w.pose,
        w.mass,
        states.len()
    );
    assert!(
        w.pose < 1e-12,
        "{}: poses off by {:e}",
        osim.display(),
        w.pose
    );
    assert!(
        w.mass <= REL_TOL,
        "{}: mass matrix relative error {:e}",
        osim.display(),
        w.mass
    );
    if let Some((mx_err, opensim_err)) = w.lagrange {
        eprintln!(
            "  velocity terms vs the Lagrangian of OpenSim's calcM: mx {mx_err:.1e}, OpenSim's own {opensim_err:.1e}"
        );
        // central differences (h = 1e-5) of calcM are good to ~1e-9
        assert!(
            mx_err < 1e-7,
            "{}: velocity terms off the Lagrangian by {mx_err:e}",
            osim.display()
        );
        assert!(
            opensim_err > 1e-3,
            "{}: OpenSim's velocity terms now agree with its mass matrix ({opensim_err:e}): compare FD and ID directly",
            osim.display()
        );
        return w;
    }
    for (what, e) in [
        ("mass matrix", w.mass),
        ("forward dynamics", w.fd),
        ("inverse dynamics", w.id),
    ] {
        assert!(
            e <= REL_TOL,
            "{}: {what} relative error {e:e}",
            osim.display()
        );
    }
    w
}

#[test]
fn shared_models_agree_with_opensim() {
    let models = common::shared_files("opensim", ".osim");
    for osim in &models {
        let stem = osim.file_stem().unwrap().to_string_lossy().to_string();
        let reference = data_dir().join(format!("{stem}.json"));
        assert!(
            reference.is_file(),
            "no OpenSim reference for {}: run `python scripts/opensim_refs.py` (needs `pip install opensim`) and commit tests/data/opensim/{stem}.json",
            osim.display()
        );
        check(osim, &reference);
    }
}

#[test]
fn every_joint_type_agrees_with_opensim() {
    let dir = data_dir().join("joints");
    let mut cases: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "osim"))
        .collect();
    cases.sort();
    let kinds: Vec<String> = cases
        .iter()
        .map(|p| p.file_stem().unwrap().to_string_lossy().to_string())
        .collect();
    for k in [
        "CustomJoint",
        "PinJoint",
        "SliderJoint",
        "WeldJoint",
        "BallJoint",
        "FreeJoint",
        "UniversalJoint",
        "GimbalJoint",
        "PlanarJoint",
        "OpenSim3Format",
        "OpenSim3Reversed",
    ] {
        assert!(kinds.iter().any(|x| x == k), "no reference model for {k}");
    }
    for osim in &cases {
        check(osim, &osim.with_extension("json"));
    }
}
