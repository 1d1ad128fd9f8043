//! Ground measures (`mx::ground`): contacts, foot skate, penetration and the
//! ground residual on cases with known answers, and on every captured clip.

use crate::common::shared_files;
use mx::ground::{self, Floor, GroundOptions};
use mx::mocap::{self, bvh::Units};
use mx::model::Model;
use mx::motion::Mu;
use std::path::Path;

fn load(path: &Path) -> (Mu, Model, f64) {
    let clip = mocap::load(path, Units::Auto).unwrap();
    let (body, _) = mocap::body_of(&clip.skeleton, 70.0, clip.units.metres_per_unit).unwrap();
    (clip.mu, body, clip.frame_time)
}

fn first_walk() -> Option<(Mu, Model, f64)> {
    shared_files("inbetween", ".bvh")
        .into_iter()
        .find(|p| p.to_string_lossy().contains("walk_active_001"))
        .map(|p| load(&p))
}

#[test]
fn default_contact_points_are_the_ankles_and_toes() {
    let Some((_, body, _)) = first_walk() else {
        return;
    };
    let mut names: Vec<String> = ground::default_contact_points(&body)
        .into_iter()
        .map(|p| p.name)
        .collect();
    names.sort();
    assert_eq!(names, ["Foot_L", "Foot_R", "Toes_L", "Toes_R"]);
    // CMU's names, and a name given in the wrong case
    for p in shared_files("mocap", ".bvh") {
        if !p.to_string_lossy().contains("cmu") {
            continue;
        }
        let (_, b, _) = load(&p);
        let n: Vec<String> = ground::default_contact_points(&b)
            .into_iter()
            .map(|p| p.name)
            .collect();
        // CMU files name them LeftFoot/LeftToeBase or LeftAnkle/LeftToe
        for side in ["Left", "Right"] {
            assert!(
                n.iter()
                    .any(|x| x == &format!("{side}Foot") || x == &format!("{side}Ankle")),
                "{n:?}"
            );
            assert!(
                n.iter().any(|x| x.starts_with(&format!("{side}Toe"))),
                "{n:?}"
            );
        }
    }
    let pts = ground::contact_points(&body, Some(&["foot_l".to_string()])).unwrap();
    assert_eq!(pts[0].name, "Foot_L");
    let e = ground::contact_points(&body, Some(&["Foot_X".to_string()]))
        .unwrap_err()
        .to_string();
    assert!(e.contains("did you mean") && e.contains("Foot_L"), "{e}");
}

#[test]
fn a_walk_alternates_its_feet_on_the_floor() {
    let Some((m, body, dt)) = first_walk() else {
        return;
    };
    let c = ground::contacts(&m, &body, &GroundOptions::default()).unwrap();
    assert!((c.frame_time - dt).abs() < 1e-12);
    // floor: the lowest point, so some point touches it
    assert!(c.points.iter().any(|p| !p.intervals.is_empty()));
    for foot in ["Foot_L", "Foot_R", "Toes_L", "Toes_R"] {
        let p = c.points.iter().find(|p| p.name == foot).unwrap();
        let frames: usize = p.intervals.iter().map(|i| i.last - i.first + 1).sum();
        println!(
            "{foot}: {} intervals, {frames} of {} frames",
            p.intervals.len(),
            c.times.len()
        );
    }
    // a stated floor far below: nothing touches
    let none = ground::contacts(
        &m,
        &body,
        &GroundOptions {
            floor: Floor::At(c.floor - 1.0),
            ..Default::default()
        },
    )
    .unwrap();
    assert!(none.points.iter().all(|p| p.intervals.is_empty()));
    // speed: inf keeps every frame near the floor, so at least as many
    let all = ground::contacts(
        &m,
        &body,
        &GroundOptions {
            speed: f64::INFINITY,
            ..Default::default()
        },
    )
    .unwrap();
    for (a, b) in all.points.iter().zip(&c.points) {
        let n = |p: &ground::PointContacts| p.in_contact.iter().filter(|x| **x).count();
        assert!(n(a) >= n(b));
    }
}

#[test]
fn a_motion_with_a_gap_is_a_clear_error() {
    let Some((m, body, _)) = first_walk() else {
        return;
    };
    let cut = mx::motion::clip_in_place(1.0, 1.5, &m).unwrap();
    let holed = mx::motion::minus(&m, &cut);
    let e = ground::contacts(&holed, &body, &GroundOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("gap") && e.contains("undefined"), "{e}");
}
