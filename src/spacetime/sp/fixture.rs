//! A small body and motions for the stages' unit tests: a root sliding in
//! x and y (y up) and turning about z, a hip and a knee, and a sliding bone
//! (a translation DOF, as a BVH joint's position channel).

use crate::lie::Se3;
use crate::model::joints::{Prismatic, Revolute};
use crate::model::{Inertia, Model};
use crate::motion::{Curve, Dof, Interval, Mu};
use nalgebra::Vector3;
use std::sync::Arc;

pub const Y_UP: Vector3<f64> = Vector3::new(0.0, -9.8, 0.0);

/// Coordinates: x, y (root slides), rz (pelvis), hip, knee, bone (a slide).
pub fn body() -> Model {
    let mut m = Model::new("t");
    let z = Inertia::zero();
    let mass = |kg| Inertia::point(kg, Vector3::new(0.0, -0.2, 0.0)).unwrap();
    let slide = |ax| Arc::new(Prismatic::new(ax).unwrap());
    let hinge = |ax| Arc::new(Revolute::new(ax).unwrap());
    let below = Se3::from_translation(Vector3::new(0.0, -0.4, 0.0));
    let p = m
        .add_link("sx", None, "x", slide(Vector3::x()), Se3::identity(), z)
        .unwrap();
    let p = m
        .add_link("sy", Some(p), "y", slide(Vector3::y()), Se3::identity(), z)
        .unwrap();
    let p = m
        .add_link(
            "pelvis",
            Some(p),
            "rz",
            hinge(Vector3::z()),
            Se3::identity(),
            mass(10.0),
        )
        .unwrap();
    let p = m
        .add_link(
            "thigh",
            Some(p),
            "hip",
            hinge(Vector3::z()),
            below,
            mass(5.0),
        )
        .unwrap();
    let p = m
        .add_link(
            "shin",
            Some(p),
            "knee",
            hinge(Vector3::z()),
            below,
            mass(3.0),
        )
        .unwrap();
    m.add_link(
        "foot",
        Some(p),
        "bone",
        slide(Vector3::y()),
        below,
        mass(1.0),
    )
    .unwrap();
    m
}

/// Coordinate `c`'s smooth motion (a walk to the right, limbs swinging, the
/// bone at its constant offset).
pub fn value(c: usize, t: f64) -> f64 {
    match c {
        0 => 1.1 * t,
        1 => 0.9 + 0.01 * (9.0 * t).sin(),
        2 => 0.05 * (3.0 * t).sin(),
        3 => 0.4 * (6.0 * t).sin(),
        4 => 0.3 + 0.2 * (6.0 * t + 1.0).sin(),
        _ => 0.25,
    }
}

/// Every coordinate on [0, 2] sampled at 60 Hz, with the coordinates in
/// `gapped` undefined on (g0, g1).
pub fn motion(model: &Model, gapped: &[usize], (g0, g1): (f64, f64)) -> Mu {
    let piece = |c: usize, a: f64, b: f64| {
        let n = ((b - a) * 60.0).round() as usize;
        let vals = (0..=n).map(|k| value(c, a + k as f64 / 60.0)).collect();
        Interval::curve(Curve::samples(a, 1.0 / 60.0, vals).unwrap(), a, b).unwrap()
    };
    let mut m = Mu::new();
    for (c, name) in model.coordinate_names().iter().enumerate() {
        let dof = if gapped.contains(&c) {
            Dof::new(vec![piece(c, 0.0, g0), piece(c, g1, 2.0)]).unwrap()
        } else {
            Dof::from(piece(c, 0.0, 2.0))
        };
        m.insert(name.clone(), dof);
    }
    m
}
