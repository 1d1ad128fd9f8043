//! The right knee of the *loaded* gait2392 model swinging as a pendulum,
//! against the shared OpenSim reference (`knee_r_gait2392_pendulum.json`,
//! accuracy 1e-12): every coordinate but `knee_angle_r` is driven at rate 0
//! (held), `hip_flexion_r` at the run's femur flexion and ankle, subtalar and
//! mtp at 0, which is the reference's femur fixed in ground with the foot
//! welded to the shank. The tibia-only runs have no foot, which the whole model
//! cannot leave out: they are checked by `tests/knee_pendulum.rs`.

use crate::common;

use std::sync::Arc;

use mx::cancel::CancelToken;
use mx::dynamics::{Integrator, Scene, State, simulate};
use mx::model::Model;
use serde_json::Value;

#[test]
fn gait2392_right_knee_swings_as_opensim_says() {
    let models = common::shared_files("opensim", ".osim");
    let Some(osim) = models.iter().find(|p| {
        p.file_name()
            .is_some_and(|n| n == "gait2392_thelen2003muscle.osim")
    }) else {
        return;
    };
    let m = Arc::new(Model::from_osim_file(osim).unwrap().model);
    let knee = m.coordinate_index("knee_angle_r").unwrap();
    let hip = m.coordinate_index("hip_flexion_r").unwrap();
    let mut checked = 0;
    for refp in common::shared_files("opensim", "_pendulum.json") {
        let r: Value = serde_json::from_str(&std::fs::read_to_string(&refp).unwrap()).unwrap();
        for run in r["runs"].as_array().unwrap() {
            let name = run["name"].as_str().unwrap();
            if !name.starts_with("shank_foot") {
                eprintln!("{name}: tibia alone, not this model (see tests/knee_pendulum.rs)");
                continue;
            }
            let mut scene = Scene::new(m.clone())
                .with_gravity(m.default_gravity)
                .unwrap();
            for k in 0..m.nq() {
                if k != knee {
                    scene = scene.with_driven(k, 0.0).unwrap();
                }
            }
            let mut q = vec![0.0; m.nq()];
            q[hip] = run["femur_flexion_rad"].as_f64().unwrap();
            q[knee] = run["q0"].as_f64().unwrap();
            let mut v = vec![0.0; m.nq()];
            v[knee] = run["u0"].as_f64().unwrap();
            let t = common::json_f64s(&run["t"]);
            let q_ref = common::json_f64s(&run["q_accuracy_1e-12"]);
            let tr = simulate(
                &scene,
                t[t.len() - 1],
                t[1] - t[0],
                Integrator::DormandPrince {
                    rtol: 1e-12,
                    atol: 1e-12,
                },
                &State { q, v },
                &CancelToken::new(),
                &mut |_| {},
            )
            .unwrap();
            assert_eq!(tr.t.len(), t.len());
            let e =
                tr.q.iter()
                    .zip(&q_ref)
                    .map(|(q, r)| (q[knee] - r).abs())
                    .fold(0.0, f64::max);
            let held = tr.q.last().unwrap()[hip] - run["femur_flexion_rad"].as_f64().unwrap();
            eprintln!(
                "{name}: max |q_knee − OpenSim| = {e:.2e} rad over {} samples",
                t.len()
            );
            assert!(held.abs() < 1e-12, "{name}: the hip moved by {held:e}");
            assert!(e < 1e-9, "{name}: knee angle off by {e:e} rad");
            checked += 1;
        }
    }
    assert!(checked > 0, "no shank+foot pendulum run in the shared data");
}
