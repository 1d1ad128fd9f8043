//! `ground_forces` (`mx::ground::ground_forces`): the contact forces per
//! point and the residual per frame, on cases with known answers (standing
//! still, lifted off the floor), against `ground_residual` and the friction
//! cones on every captured clip, and in the language as `plot` and `save`
//! take it.

use crate::common::shared_files;
use crate::ground::{flat_feet, held, load, standing};
use mx::ground::{self, Floor, GroundForces, GroundOptions};
use mx::motion::Curve;
use nalgebra::Vector3;

/// The horizontal point where the forces' moment about it vanishes: their
/// centre of pressure on the floor.
fn centre_of_pressure(g: &GroundForces, k: usize) -> Vector3<f64> {
    let mut p = Vector3::zeros();
    let mut total = 0.0;
    for (x, f) in g.positions[k].iter().zip(&g.forces[k]) {
        let n = f.dot(&g.up);
        p += x * n;
        total += n;
    }
    p / total
}

#[test]
fn a_standing_body_is_held_up_by_its_weight_under_its_centre_of_mass() {
    let Some((m, body, _)) = standing() else {
        return;
    };
    let g = ground::ground_forces(&m, &body, &flat_feet(), 0.8).unwrap();
    assert!(!g.times.is_empty());
    for k in 0..g.times.len() {
        let total = g.total(k);
        // the forces sum to the weight, upward
        assert!(
            (total - g.up * g.weight).norm() < 0.005 * g.weight,
            "frame {k}: Σf = {total} for a weight of {} N",
            g.weight
        );
        // under the centre of mass (the centre of pressure, horizontally)
        let d = ground::horizontal(&(centre_of_pressure(&g, k) - g.com[k]), &g.up).norm();
        assert!(
            d < 0.005,
            "frame {k}: the forces act {d} m from under the centre of mass"
        );
        assert!(g.percent_bw(k) < 0.5, "{}", g.percent_bw(k));
        assert!(g.in_contact[k].iter().all(|&c| c));
    }
    // each force points up, inside its cone
    for f in g.forces.iter().flatten() {
        let n = f.dot(&g.up);
        assert!(n >= -1e-9 && ground::horizontal(f, &g.up).norm() <= 0.8 * n + 1e-6 * g.weight);
    }
}

#[test]
fn a_body_lifted_10_cm_has_no_forces_and_its_weight_as_residual() {
    let Some((m, body, _)) = standing() else {
        return;
    };
    let floor = ground::contacts(&m, &body, &GroundOptions::default())
        .unwrap()
        .floor;
    let lifted = held(&m, &body, 0.0, |n, v| {
        Curve::constant(if n == "Hips.Yposition" { v + 0.10 } else { v }).unwrap()
    });
    let o = GroundOptions {
        floor: Floor::At(floor),
        ..Default::default()
    };
    let g = ground::ground_forces(&lifted, &body, &o, 0.8).unwrap();
    for k in 0..g.times.len() {
        assert!(g.forces[k].iter().all(|f| *f == Vector3::zeros()));
        assert!((g.residual_force[k] - g.up * g.weight).norm() < 1e-6 * g.weight);
        assert!((g.percent_bw(k) - 100.0).abs() < 1e-6);
    }
}

/// On every captured clip: the same numbers as `ground_residual` frame by
/// frame, every force inside its friction cone, and forces only at points
/// near the floor.
#[test]
fn ground_forces_on_a_capture_agree_with_ground_residual() {
    let files = shared_files("mocap", ".bvh");
    for path in &files {
        let (m, body, _) = load(path);
        let o = GroundOptions::default();
        let g = ground::ground_forces(&m, &body, &o, 0.8).unwrap();
        let r = ground::ground_residual(&m, &body, &o, 0.8).unwrap();
        assert_eq!(g.times, r.times);
        for k in 0..g.times.len() {
            assert_eq!(g.percent_bw(k), r.force[k], "{path:?} frame {k}");
            assert_eq!(g.residual_moment[k].norm(), r.moment[k]);
            let near = g.in_contact[k].iter().filter(|&&c| c).count();
            assert_eq!(near, r.in_contact[k]);
            // what the forces supply and what they leave make what is needed
            let needed = g.total(k) + g.residual_force[k];
            assert!((needed.norm() / g.weight * 100.0 - r.needed[k]).abs() < 1e-6);
            for (f, &on) in g.forces[k].iter().zip(&g.in_contact[k]) {
                let n = f.dot(&g.up);
                let t = ground::horizontal(f, &g.up).norm();
                assert!(on || *f == Vector3::zeros(), "a force off the floor");
                assert!(
                    n >= -1e-6 * g.weight && t <= 0.8 * n + 1e-6 * g.weight,
                    "{path:?} frame {k}: {f} outside its cone"
                );
            }
        }
    }
}

#[test]
fn ground_forces_in_the_language_plots_and_saves() {
    let dir = tempfile::tempdir().unwrap();
    let walk = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/data/walk.bvh");
    let mut mx = mx::Interpreter::new();
    mx.eval_str(&format!(
        "{{ let w = load({:?}); let b = body_of(w); let f = ground_forces(w, b); \
           plot(f.only([\"LeftFoot.*\"]), {:?}); save(f, {:?}); \
           plot(ground_forces(w, b).only([\"residual.percent_bw\"]), {:?}) }}",
        walk.display().to_string(),
        dir.path().join("f.svg").display().to_string(),
        dir.path().join("f.csv").display().to_string(),
        dir.path().join("r.svg").display().to_string(),
    ))
    .unwrap();
    let svg = std::fs::read_to_string(dir.path().join("f.svg")).unwrap();
    assert!(svg.contains("<svg") && svg.contains("LeftFoot.Fy"));
    let csv = std::fs::read_to_string(dir.path().join("f.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    for col in [
        "LeftFoot.Fx",
        "RightFoot.Fz",
        "residual.Fy",
        "residual.Mz",
        "residual.percent_bw",
    ] {
        assert!(header.contains(col), "{header}");
    }
    // the CSV's numbers are the engine's
    let (m, body, _) = load(&walk);
    let g = ground::ground_forces(&m, &body, &GroundOptions::default(), 0.8).unwrap();
    let cols: Vec<&str> = header.split(',').collect();
    let pct = cols
        .iter()
        .position(|c| *c == "residual.percent_bw")
        .unwrap();
    let rows: Vec<Vec<f64>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), g.times.len());
    for (k, row) in rows.iter().enumerate() {
        assert!((row[pct] - g.percent_bw(k)).abs() < 1e-9 * (1.0 + g.percent_bw(k)));
    }
    // bad input names its argument
    for (bad, says) in [
        ("ground_forces(w, b, friction: -1)", "friction must be"),
        ("ground_forces(w, b, points: [\"Nose\"])", "no link `Nose`"),
    ] {
        let e = mx
            .eval_str(&format!(
                "{{ let w = load({:?}); let b = body_of(w); {bad} }}",
                walk.display().to_string()
            ))
            .unwrap_err()
            .render_plain();
        assert!(e.contains(says), "{bad}: {e}");
    }
}
