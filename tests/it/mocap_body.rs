//! body_of: coordinates are exactly the clip's DOFs, de Leva masses sum to
//! the total, and forward kinematics of the body through `positions` equals
//! BVH forward kinematics of the file at every checked frame.

use crate::common;

use mx::mocap::bvh::{self, Units};
use mx::mocap::{Missing, body_of::body_of, positions, to_motion};
use std::path::Path;

fn check(path: &Path) {
    let name = path.file_name().unwrap().to_string_lossy().to_string();
    let raw = bvh::read_file(path).unwrap();
    let clip = to_motion::load(path, Units::Auto).unwrap();
    let s = clip.units.metres_per_unit;
    let (body, report) = body_of(&clip.skeleton, 70.0, s).unwrap();
    assert!(
        !report.used_fallback,
        "{name}: names not recognised: {:?}",
        report.joints
    );
    let dofs: Vec<&str> = clip.mu.names().collect();
    assert_eq!(
        body.coordinate_names()
            .iter()
            .map(String::as_str)
            .collect::<Vec<_>>(),
        dofs,
        "{name}"
    );
    assert!(
        (body.total_mass() - 70.0).abs() < 1e-9,
        "{name}: {}",
        body.total_mass()
    );
    let p = positions(&clip.mu, &body, None, Missing::Error).unwrap();
    assert_eq!(p.times.len(), clip.frames, "{name}");
    for f in (0..clip.frames).step_by(clip.frames / 10 + 1) {
        let want = bvh::fk::world_positions(&raw, f, s);
        for (j, jt) in raw.skeleton.joints.iter().enumerate() {
            let k = p
                .names
                .iter()
                .position(|n| *n == jt.name)
                .unwrap_or_else(|| panic!("{name}: no point {}", jt.name));
            let d = (p.points[f][k] - want[j]).norm();
            assert!(d < 1e-9, "{name} frame {f} {}: off by {d} m", jt.name);
        }
        let ends = bvh::fk::end_site_positions(&raw, f, s);
        let got: Vec<_> = p
            .names
            .iter()
            .enumerate()
            .filter(|(_, n)| n.ends_with(".end"))
            .map(|(k, _)| p.points[f][k])
            .collect();
        assert_eq!(got.len(), ends.len());
        for (a, b) in got.iter().zip(&ends) {
            assert!((a - b).norm() < 1e-9, "{name}: end site");
        }
    }
}

#[test]
fn every_shared_clip_has_a_body_matching_its_fk() {
    for p in common::shared_files("mocap", ".bvh") {
        check(&p);
    }
}

#[test]
fn example_clips_have_bodies() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/data");
    check(&dir.join("walk.bvh"));
    check(&dir.join("wave.bvh"));
}

#[test]
fn de_leva_masses_on_bandai() {
    let Some(dir) = common::shared_dir() else {
        return;
    };
    let clip = to_motion::load(
        &dir.join("data/mocap/bandai1_walk_normal_001.bvh"),
        Units::Auto,
    )
    .unwrap();
    let (body, _) = body_of(&clip.skeleton, 80.0, clip.units.metres_per_unit).unwrap();
    let m = |n: &str| body.link(body.link_index(n).unwrap()).inertia.mass;
    // Thigh 14.16 %, shank 4.33 %, head+neck 6.94 % of 80 kg (all groups present).
    assert!((m("UpperLeg_L") - 0.1416 * 80.0).abs() < 1e-9);
    assert!((m("LowerLeg_R") - 0.0433 * 80.0).abs() < 1e-9);
    assert!((m("Neck") + m("Head") - 0.0694 * 80.0).abs() < 1e-9);
    assert_eq!(m("joint_Root"), 0.0);
    // The thigh's COM lies 40.95 % down the bone towards the knee.
    let thigh = body.link(body.link_index("UpperLeg_L").unwrap());
    let c = thigh.inertia.com();
    let bone = clip.skeleton.joints[clip.skeleton.find("LowerLeg_L").unwrap()].offset * 0.01;
    assert!((c - bone * 0.4095).norm() < 1e-9, "{c} vs {bone}");
}

#[test]
fn bad_mass_unknown_names_and_missing_dofs() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/data");
    let clip = to_motion::load(&dir.join("walk.bvh"), Units::Auto).unwrap();
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let e = body_of(&clip.skeleton, bad, 0.01).unwrap_err().to_string();
        assert!(e.contains("mass"), "{e}");
    }
    // Unknown names: fall back to mass by bone length, still the full total.
    let mut sk = clip.skeleton.clone();
    for (i, j) in sk.joints.iter_mut().enumerate() {
        j.name = format!("b{i}");
    }
    let (body, rep) = body_of(&sk, 70.0, 0.01).unwrap();
    assert!(rep.used_fallback);
    assert!((body.total_mass() - 70.0).abs() < 1e-9);
    // A motion lacking the body's DOFs: an error naming them.
    let (body, _) = body_of(&clip.skeleton, 70.0, 0.01).unwrap();
    let arm = mx::motion::only(&clip.mu, &["RightArm.*"]).unwrap();
    let e = positions(&arm, &body, None, Missing::Error)
        .unwrap_err()
        .to_string();
    assert!(e.contains("Hips.Xposition"), "{e}");
    // …but drawable with Missing::Hold.
    assert!(positions(&arm, &body, None, Missing::Hold).is_ok());
}
