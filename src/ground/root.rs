//! The floating root as a motion moves it: [`crate::model::RootCoords`],
//! with a constant placeholder above the moving root skipped (Bandai's
//! all-zero `joint_Root` above `Hips`), "up" from gravity by [`up_of`].

use super::floor::up_of;
use crate::model::{Model, RootCoords};
use crate::motion::Mu;
use nalgebra::Vector3;

/// The link whose horizontal speed is the body's, which SP's planning rule
/// ([`super::plan_stances`]) scales a point's speed limit by: the last link
/// of the root chain (a BVH skeleton's hips). `None` for a body without a
/// root chain.
pub fn body_link(model: &Model, up: &Vector3<f64>) -> Option<usize> {
    let root = RootCoords::detect(model, Some(up));
    model.coordinate_link(*root.all.last()?)
}

/// The root of `model` as it moves in `motion` under `gravity`: leading
/// massless single-child links whose coordinates are all constant in
/// `motion` are skipped ([`RootCoords::detect_skipping`]). Coordinates the
/// motion does not name, or whose curves are not provably constant, count as
/// moving.
pub fn moving_root(model: &Model, gravity: &Vector3<f64>, motion: &Mu) -> RootCoords {
    let names = model.coordinate_names();
    RootCoords::detect_skipping(model, up_of(gravity).as_ref(), |c| {
        motion
            .get(&names[c])
            .is_some_and(|d| d.is_constant(&names[c]))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lie::Se3;
    use crate::model::RootCoords;
    use crate::model::joints::{Prismatic, Revolute};
    use crate::model::{Inertia, Model};
    use crate::motion::{Curve, Dof, Interval, Mu};
    use nalgebra::Vector3;
    use std::sync::Arc;

    /// A placeholder slide (`place`) above a moving slide pair (`x`, `y`) and
    /// a massive hinge, as Bandai's `joint_Root` sits above `Hips`.
    fn model() -> Model {
        let mut m = Model::new("t");
        let z = Inertia::zero();
        let slide = |ax| Arc::new(Prismatic::new(ax).unwrap());
        let p = m
            .add_link(
                "place",
                None,
                "place",
                slide(Vector3::x()),
                Se3::identity(),
                z,
            )
            .unwrap();
        let p = m
            .add_link("sx", Some(p), "x", slide(Vector3::x()), Se3::identity(), z)
            .unwrap();
        let p = m
            .add_link("sy", Some(p), "y", slide(Vector3::y()), Se3::identity(), z)
            .unwrap();
        let mass = Inertia::point(10.0, Vector3::zeros()).unwrap();
        let r = m
            .add_link(
                "pelvis",
                Some(p),
                "rz",
                Arc::new(Revolute::new(Vector3::z()).unwrap()),
                Se3::identity(),
                mass,
            )
            .unwrap();
        m.add_link(
            "thigh",
            Some(r),
            "hip",
            Arc::new(Revolute::new(Vector3::x()).unwrap()),
            Se3::identity(),
            mass,
        )
        .unwrap();
        m
    }

    fn motion(values: &[(&str, Vec<f64>)]) -> Mu {
        let mut mu = Mu::new();
        for (n, v) in values {
            let stop = 0.1 * (v.len() - 1) as f64;
            let c = Curve::samples(0.0, 0.1, v.clone()).unwrap();
            mu.insert(
                n.to_string(),
                Dof::new(vec![Interval::curve(c, 0.0, stop).unwrap()]).unwrap(),
            );
        }
        mu
    }

    const Y_UP: Vector3<f64> = Vector3::new(0.0, -9.8, 0.0);

    #[test]
    fn a_constant_placeholder_above_the_moving_root_is_skipped() {
        let m = model();
        let mu = motion(&[
            ("place", vec![0.0; 4]),
            ("x", vec![0.0, 0.1, 0.3, 0.6]),
            ("y", vec![0.9; 4]),
            ("rz", vec![0.0, 0.1, 0.0, 0.1]),
            ("hip", vec![0.2, 0.1, 0.0, 0.1]),
        ]);
        let rc = moving_root(&m, &Y_UP, &mu);
        assert_eq!(rc.fixed, vec![0]);
        assert_eq!(rc.all, vec![0, 1, 2, 3]);
        assert_eq!(rc.horizontal, vec![1]);
        assert_eq!(rc.vertical, vec![2]);
        assert_eq!(rc.rotations, vec![3]);
        // structure alone takes the placeholder as the root's first slide
        let plain = RootCoords::detect(&m, up_of(&Y_UP).as_ref());
        assert_eq!(plain.horizontal, vec![0, 1]);
        assert!(plain.fixed.is_empty());
    }

    #[test]
    fn a_moving_placeholder_or_a_still_body_skips_nothing() {
        let m = model();
        let plain = RootCoords::detect(&m, up_of(&Y_UP).as_ref());
        let moving = motion(&[("place", vec![0.0, 0.0, 0.5, 0.0]), ("x", vec![0.0; 4])]);
        assert_eq!(moving_root(&m, &Y_UP, &moving), plain);
        // nothing on the root chain moves: the structural root stands
        let still = motion(&[
            ("place", vec![0.0; 4]),
            ("x", vec![1.0; 4]),
            ("y", vec![0.9; 4]),
            ("rz", vec![0.3; 4]),
        ]);
        assert_eq!(moving_root(&m, &Y_UP, &still), plain);
        // a DOF the motion lacks counts as moving
        assert_eq!(moving_root(&m, &Y_UP, &Mu::new()), plain);
    }
}
