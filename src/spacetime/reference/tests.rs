use super::*;
use crate::motion::{Curve, Dof, Interval};
use crate::spacetime::EndState;
use std::f64::consts::PI;

/// A motion of `f` sampled at 30 Hz over [0, 6] s with a gap (2, 3).
fn with_gap(names: &[&str], f: &dyn Fn(usize, f64) -> f64) -> (Mu, Vec<GapDof>) {
    let dt = 1.0 / 30.0;
    let mut m = Mu::new();
    let mut gaps = vec![];
    for (c, name) in names.iter().enumerate() {
        let piece = |a: usize, b: usize| {
            let v: Vec<f64> = (a..=b).map(|k| f(c, k as f64 * dt)).collect();
            let curve = Curve::samples(a as f64 * dt, dt, v).unwrap();
            Interval::curve(curve, a as f64 * dt, b as f64 * dt).unwrap()
        };
        m.insert(
            name.to_string(),
            Dof::new(vec![piece(0, 60), piece(90, 180)]).unwrap(),
        );
        let end = |t: f64| EndState {
            q: f(c, t),
            v: 0.0,
            a: 0.0,
        };
        gaps.push(GapDof {
            coord: c,
            t0: 2.0,
            t1: 3.0,
            start: end(2.0),
            end: end(3.0),
        });
    }
    (m, gaps)
}

#[test]
fn a_periodic_motion_follows_itself_a_whole_number_of_periods_away() {
    let period = 1.2;
    let f = |c: usize, t: f64| (2.0 * PI * t / period + c as f64).sin() * 0.8;
    let names = ["a", "b"];
    let (m, gaps) = with_gap(&names, &f);
    let names: Vec<String> = names.iter().map(|s| s.to_string()).collect();
    let ex = find(&m, &names, &|_| true, &gaps)
        .unwrap()
        .expect("an example");
    let periods = ex.shift / period;
    assert!((periods - periods.round()).abs() < 0.03, "{ex:?}");
    assert!(ex.mismatch < 1e-3, "{ex:?}");
    assert_eq!((ex.follow, ex.of), (vec![0, 1], 2));
}

#[test]
fn a_dof_far_from_its_example_at_an_end_keeps_the_plain_prior() {
    // a, c, d repeat every second; b drifts 0.15 rad/s, so every copy of
    // it far enough away to clear the gap (2 s or more) is 0.3 rad off
    let f = |c: usize, t: f64| {
        (2.0 * PI * t + c as f64).sin() * 0.8 + if c == 1 { 0.15 * t } else { 0.0 }
    };
    let names = ["a", "b", "c", "d"];
    let (m, gaps) = with_gap(&names, &f);
    let names: Vec<String> = names.iter().map(|s| s.to_string()).collect();
    let ex = find(&m, &names, &|_| true, &gaps)
        .unwrap()
        .expect("an example");
    assert!((ex.shift - ex.shift.round()).abs() < 0.05, "{ex:?}");
    assert_eq!((ex.follow, ex.of), (vec![0, 2, 3], 4));
}

#[test]
fn a_zero_length_or_huge_gap_has_no_example() {
    let f = |_: usize, t: f64| (2.0 * PI * t).sin();
    let names = ["a"];
    let (m, mut gaps) = with_gap(&names, &f);
    gaps[0].t1 = gaps[0].t0;
    let names: Vec<String> = names.iter().map(|s| s.to_string()).collect();
    assert_eq!(find(&m, &names, &|_| true, &gaps).unwrap(), None);
    // nor one longer than any cycle (whose grid would be huge)
    gaps[0].t1 = gaps[0].t0 + 1e7;
    assert_eq!(find(&m, &names, &|_| true, &gaps).unwrap(), None);
    assert_eq!(find(&m, &names, &|_| true, &[]).unwrap(), None);
}

#[test]
fn a_motion_that_never_repeats_has_no_example() {
    // a slow turn: every other stretch is a different pose
    let f = |c: usize, t: f64| 0.3 * t + 0.1 * c as f64;
    let names = ["a"];
    let (m, gaps) = with_gap(&names, &f);
    let names: Vec<String> = names.iter().map(|s| s.to_string()).collect();
    assert_eq!(find(&m, &names, &|_| true, &gaps).unwrap(), None);
    // nor a motion without angles, nor one too short to hold a copy
    assert_eq!(find(&m, &names, &|_| false, &gaps).unwrap(), None);
}

#[test]
fn a_stretch_through_a_wrapped_angle_is_no_example() {
    // periodic, but every copy outside the gap crosses a ±π wrap
    let period = 1.0;
    let f = |_: usize, t: f64| {
        let u = (2.0 * PI * t / period).sin() * 0.5;
        if (t - 2.5).abs() > 0.6 && (t / period).fract() > 0.45 && (t / period).fract() < 0.55 {
            u + 2.0 * PI
        } else {
            u
        }
    };
    let names = ["a"];
    let (m, gaps) = with_gap(&names, &f);
    let names: Vec<String> = names.iter().map(|s| s.to_string()).collect();
    // every copy outside the gap crosses a wrap: no example
    assert_eq!(find(&m, &names, &|_| true, &gaps).unwrap(), None);
    // the same motion without the wraps has one: the wraps are why
    let plain = |_: usize, t: f64| (2.0 * PI * t / period).sin() * 0.5;
    let (m, gaps) = with_gap(&["a"], &plain);
    assert!(find(&m, &names, &|_| true, &gaps).unwrap().is_some());
}

/// OpenSim names carry no joint: by name each coordinate is its own joint,
/// and one drifting channel of a two-coordinate joint leaves its sibling
/// following alone; on the body, the whole joint keeps the plain prior.
#[test]
fn a_joint_of_the_body_follows_whole_even_without_dotted_names() {
    use crate::lie::Se3;
    use crate::model::joints::{Cylindrical, Revolute};
    use crate::model::{Inertia, Model};
    use nalgebra::Vector3;
    use std::sync::Arc;
    let f = |c: usize, t: f64| {
        (2.0 * PI * t + c as f64).sin() * 0.8 + if c == 1 { 0.15 * t } else { 0.0 }
    };
    let names = ["hip_rotation", "hip_slide", "knee_angle"];
    let (m, gaps) = with_gap(&names, &f);
    let names: Vec<String> = names.iter().map(|s| s.to_string()).collect();
    let mut model = Model::new("hip and knee");
    let cyl = Arc::new(Cylindrical::new(Vector3::z()).unwrap());
    let hip = model
        .add_link("thigh", None, "hip", cyl, Se3::identity(), Inertia::zero())
        .unwrap();
    let pin = Arc::new(Revolute::new(Vector3::x()).unwrap());
    model
        .add_link(
            "shank",
            Some(hip),
            "knee",
            pin,
            Se3::identity(),
            Inertia::zero(),
        )
        .unwrap();
    model.set_coordinate_names(names.clone()).unwrap();
    let by_name = find(&m, &names, &|_| true, &gaps)
        .unwrap()
        .expect("an example");
    assert_eq!(by_name.follow, vec![0, 2]);
    let joints = Joints::of_model(&model, &names);
    let on_body = find_with(&m, &names, &|_| true, &joints, &gaps)
        .unwrap()
        .expect("an example");
    assert_eq!((on_body.follow, on_body.of), (vec![2], 3));
    assert_eq!(on_body.shift, by_name.shift);
    // `choose_for` reads the joints off the body
    let chosen = choose_for(&model, &m, &names, &|_| true, &gaps, true, None)
        .unwrap()
        .expect("an example");
    assert_eq!(chosen.follow, vec![2]);
}
