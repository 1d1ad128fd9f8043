//! What the ground's dynamics need of a body: a floating root to take the
//! world's wrench, its centre of mass, and its length scale (the lever arm
//! that weighs a moment as a force). Shared by the contact forces
//! (`forces.rs`), the residual and SP's contact forces.

use super::{GroundError, invalid};
use crate::lie::Se3;
use crate::model::topology::joint_points;
use crate::model::{Model, RootCoords};
use nalgebra::Vector3;

/// Checks that the body's root can move freely: one root link, and a
/// floating root ([`RootCoords::is_floating`]: six coordinates or more down
/// to the first link with mass).
pub(crate) fn check_floating(body: &Model, up: &Vector3<f64>) -> Result<(), GroundError> {
    let roots = (0..body.num_links())
        .filter(|&i| body.link(i).parent.is_none())
        .count();
    if roots != 1 {
        return Err(invalid(format!(
            "ground forces need one root link; the body `{}` has {roots}",
            body.name
        )));
    }
    let root = RootCoords::detect(body, Some(up));
    if !root.is_floating() {
        return Err(invalid(format!(
            "ground forces need a floating base: the root of `{}` has {} coordinates down to its first link with mass, a free root has 6",
            body.name,
            root.all.len()
        )));
    }
    Ok(())
}

/// The body length scale: the largest extent of its joint points' bounding box.
pub(crate) fn length_scale(poses: &[Se3], body: &Model) -> f64 {
    let (links, _) = joint_points(body);
    let mut lo = Vector3::repeat(f64::INFINITY);
    let mut hi = Vector3::repeat(f64::NEG_INFINITY);
    for &l in &links {
        lo = lo.inf(&poses[l].p);
        hi = hi.sup(&poses[l].p);
    }
    (hi - lo).max().max(0.1)
}

/// The centre of mass of the links placed at `poses` (world, m).
pub(crate) fn centre_of_mass(poses: &[Se3], body: &Model) -> Vector3<f64> {
    let mut c = Vector3::zeros();
    let mut m = 0.0;
    for (i, l) in body.links().iter().enumerate() {
        if l.inertia.mass > 0.0 {
            c += poses[i].act_point(&l.inertia.com()) * l.inertia.mass;
            m += l.inertia.mass;
        }
    }
    c / m
}
