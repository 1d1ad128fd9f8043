//! Every `*.json` in `$MX_SHARED/data/reference` against Pinocchio 4.1:
//! τ, M, g(q), nle, kinetic energy (1e-10), ABA (1e-8), ∂τ/∂q and ∂τ/∂v (1e-9),
//! with `err = max|x − ref| / max(1, max|ref|)` (the folder's README).

use crate::common;

use mx::dynamics::{
    JointState, Workspace, forward_dynamics, inverse_dynamics, kinetic_energy, mass_matrix,
    nonlinear_effects, rnea_derivatives,
};
use mx::model::Model;
use nalgebra::{DMatrix, Vector3};
use serde_json::Value;

fn vecf(v: &Value) -> Vec<f64> {
    common::json_f64s(v)
}

fn mat(v: &Value) -> Vec<Vec<f64>> {
    v.as_array().expect("rows").iter().map(vecf).collect()
}

use common::rel_err as err;

struct Case {
    model: Model,
    /// Per reference joint: (idx_q, nq) — a continuous joint is stored as (cos θ, sin θ).
    qlayout: Vec<(usize, usize)>,
    /// `perm[k]`: our coordinate index of the reference's coordinate k.
    perm: Vec<usize>,
    json: Value,
}

fn load(path: &std::path::Path) -> Case {
    let text = std::fs::read_to_string(path).expect("read json");
    let json: Value = serde_json::from_str(&text).expect("parse json");
    let urdf = path.with_file_name(json["urdf_file"].as_str().expect("urdf_file"));
    let model = Model::from_urdf_file(&urdf).unwrap_or_else(|e| panic!("{e}"));
    let names: Vec<String> = json["joints"]
        .as_array()
        .expect("joints")
        .iter()
        .map(|j| j["name"].as_str().expect("name").to_string())
        .collect();
    assert_eq!(
        names.len(),
        model.nq(),
        "{}: number of coordinates",
        path.display()
    );
    let perm: Vec<usize> = names
        .iter()
        .map(|n| {
            model
                .coordinate_index(n)
                .unwrap_or_else(|| panic!("joint {n} missing"))
        })
        .collect();
    let qlayout = json["joints"]
        .as_array()
        .expect("joints")
        .iter()
        .map(|j| {
            (
                j["idx_q"].as_u64().unwrap() as usize,
                j["nq"].as_u64().unwrap() as usize,
            )
        })
        .collect();
    Case {
        model,
        qlayout,
        perm,
        json,
    }
}

impl Case {
    /// Reference configuration to ours (angles for continuous joints).
    fn ours_q(&self, r: &[f64]) -> Vec<f64> {
        let per_joint: Vec<f64> = self
            .qlayout
            .iter()
            .map(|&(i, n)| if n == 2 { r[i + 1].atan2(r[i]) } else { r[i] })
            .collect();
        self.ours(&per_joint)
    }
    /// Reference-ordered vector to our order.
    fn ours(&self, r: &[f64]) -> Vec<f64> {
        let mut x = vec![0.0; r.len()];
        for (k, &p) in self.perm.iter().enumerate() {
            x[p] = r[k];
        }
        x
    }
    /// Our vector to reference order.
    fn theirs(&self, x: &[f64]) -> Vec<f64> {
        self.perm.iter().map(|&p| x[p]).collect()
    }
    fn theirs_mat(&self, m: &DMatrix<f64>) -> Vec<f64> {
        let mut out = Vec::new();
        for &i in &self.perm {
            for &j in &self.perm {
                out.push(m[(i, j)]);
            }
        }
        out
    }
}

#[derive(Default)]
struct Worst(Vec<(&'static str, f64)>);
impl Worst {
    fn put(&mut self, k: &'static str, e: f64) {
        match self.0.iter_mut().find(|(n, _)| *n == k) {
            Some(x) => x.1 = x.1.max(e),
            None => self.0.push((k, e)),
        }
    }
}

#[test]
fn pinocchio_references() {
    let files = common::shared_files("reference", ".json");
    for path in &files {
        let c = load(path);
        let m = &c.model;
        // The pinned convention: we match the order by name, and for URDF models
        // our order is Pinocchio's own.
        assert_eq!(
            c.perm,
            (0..m.nq()).collect::<Vec<_>>(),
            "{}: joint order",
            path.display()
        );
        assert_eq!(c.json["nv"].as_u64(), Some(m.nq() as u64));
        let g = Vector3::from_vec(vecf(&c.json["gravity"]));
        assert_eq!(g, m.default_gravity);
        let tm = c.json["total_mass"].as_f64().expect("total_mass");
        assert!(
            (m.total_mass() - tm).abs() < 1e-10 * tm.max(1.0),
            "total mass"
        );
        let n = m.nq();
        let mut ws = Workspace::new(m);
        let mut tau = vec![0.0; n];
        let mut qdd = vec![0.0; n];
        let mut mm = DMatrix::zeros(n, n);
        let mut dq = DMatrix::zeros(n, n);
        let mut dv = DMatrix::zeros(n, n);
        let mut worst = Worst::default();
        let flat = |v: &Value| -> Vec<f64> { mat(v).concat() };
        for s in c.json["samples"].as_array().expect("samples") {
            let q = c.ours_q(&vecf(&s["q"]));
            let v = c.ours(&vecf(&s["v"]));
            let a = c.ours(&vecf(&s["a"]));
            inverse_dynamics(m, &mut ws, &q, &v, &a, &g, &mut tau).unwrap();
            worst.put("tau", err(&c.theirs(&tau), &vecf(&s["tau"])));
            let tau_ref = c.ours(&vecf(&s["tau"]));
            forward_dynamics(m, &mut ws, &q, &v, &tau_ref, &g, &mut qdd).unwrap();
            worst.put("ddq_aba", err(&c.theirs(&qdd), &vecf(&s["ddq_aba"])));
            let zero = vec![0.0; n];
            nonlinear_effects(m, &mut ws, &q, &zero, &g, &mut tau).unwrap();
            worst.put(
                "gravity_torque",
                err(&c.theirs(&tau), &vecf(&s["gravity_torque"])),
            );
            nonlinear_effects(m, &mut ws, &q, &v, &g, &mut tau).unwrap();
            worst.put("nle", err(&c.theirs(&tau), &vecf(&s["nle"])));
            let ke = kinetic_energy(m, &mut ws, &q, &v).unwrap();
            worst.put(
                "kinetic_energy",
                err(&[ke], &[s["kinetic_energy"].as_f64().unwrap()]),
            );
            mass_matrix(m, &mut ws, &q, &mut mm).unwrap();
            worst.put("M", err(&c.theirs_mat(&mm), &flat(&s["M"])));
            rnea_derivatives(
                m,
                &mut ws,
                &JointState::new(&q, &v, &a),
                &g,
                &mut dq,
                &mut dv,
            )
            .unwrap();
            worst.put("dtau_dq", err(&c.theirs_mat(&dq), &flat(&s["dtau_dq"])));
            worst.put("dtau_dv", err(&c.theirs_mat(&dv), &flat(&s["dtau_dv"])));
        }
        eprintln!("{}:", path.file_name().unwrap().to_string_lossy());
        for (k, e) in &worst.0 {
            eprintln!("  {k:16} worst err {e:.2e}");
            let tol = match *k {
                "ddq_aba" => 1e-8,
                "dtau_dq" | "dtau_dv" => 1e-9,
                _ => 1e-10,
            };
            assert!(*e <= tol, "{}: {k} err {e:e} > {tol:e}", path.display());
        }
    }
}
