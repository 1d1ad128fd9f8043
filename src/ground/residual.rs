//! The ground residual: per frame, the part of the external wrench a motion
//! needs that no contact forces at the points on the floor can supply.
//!
//! Inverse dynamics of the floating base (RNEA with the motion's q, q̇, q̈ at
//! the frame, its velocities and accelerations the curves' own derivatives)
//! gives the wrench the world must apply through the root joint
//! ([`crate::dynamics::root_wrench`]): on Bandai bodies the generalised forces
//! of the all-zero `joint_Root`, on any body whose root has 6 DOFs the
//! external wrench. It is moved to the centre of mass; the points within
//! `height` of the floor push on it through their friction cones (μ), the
//! best forces found by [`super::cone::best_contact_forces`] with moments
//! weighed by the body length `L` (the largest extent of the body's joints at
//! the first frame: ~1.7 m for a person; a moment of L·1 N weighs as 1 N).
//! What is left is reported as force (% of body weight) and moment about the
//! centre of mass (N·m), per frame, mean and worst.

use super::cone::best_contact_forces;
use super::floor::up_direction;
use super::points::{
    GroundOptions, check_coordinates, contact_points, frame_times, sample_state, tracks,
};
use super::{GroundError, invalid, invalid_option};
use crate::dynamics::{Workspace, inverse_dynamics, root_wrench};
use crate::lie::Se3;
use crate::model::topology::joint_points;
use crate::model::{Model, RootCoords};
use crate::motion::Mu;
use nalgebra::Vector3;

/// The ground residual of a motion.
#[derive(Clone, Debug, PartialEq)]
pub struct GroundResidual {
    pub times: Vec<f64>,
    /// Per frame: unexplained force (% of body weight).
    pub force: Vec<f64>,
    /// Per frame: unexplained moment about the centre of mass (N·m).
    pub moment: Vec<f64>,
    /// Per frame: the force the motion needs (% of body weight; 100 standing still).
    pub needed: Vec<f64>,
    /// Per frame: how many contact points were within `height` of the floor.
    pub in_contact: Vec<usize>,
    pub mean_force: f64,
    pub worst_force: f64,
    pub worst_force_frame: usize,
    pub mean_moment: f64,
    pub worst_moment: f64,
    pub worst_moment_frame: usize,
    /// Body weight (N), the length scale L (m), the floor (m along up), μ.
    pub weight: f64,
    pub length: f64,
    pub floor: f64,
    pub friction: f64,
    /// Frames whose cone problem stopped short of full accuracy (flagged, still counted).
    pub unsolved: usize,
}

/// Checks that the body's root can move freely: one root link, and a
/// floating root ([`RootCoords::is_floating`]: six coordinates or more down
/// to the first link with mass).
fn check_floating(body: &Model, up: &Vector3<f64>) -> Result<(), GroundError> {
    let roots = (0..body.num_links())
        .filter(|&i| body.link(i).parent.is_none())
        .count();
    if roots != 1 {
        return Err(invalid(format!(
            "ground_residual needs one root link; the body `{}` has {roots}",
            body.name
        )));
    }
    let root = RootCoords::detect(body, Some(up));
    if !root.is_floating() {
        return Err(invalid(format!(
            "ground_residual needs a floating base: the root of `{}` has {} coordinates down to its first link with mass, a free root has 6",
            body.name,
            root.all.len()
        )));
    }
    Ok(())
}

/// The body length scale: the largest extent of its joint points' bounding box.
fn length_scale(poses: &[Se3], body: &Model) -> f64 {
    let (links, _) = joint_points(body);
    let mut lo = Vector3::repeat(f64::INFINITY);
    let mut hi = Vector3::repeat(f64::NEG_INFINITY);
    for &l in &links {
        lo = lo.inf(&poses[l].p);
        hi = hi.sup(&poses[l].p);
    }
    (hi - lo).max().max(0.1)
}

fn centre_of_mass(poses: &[Se3], body: &Model) -> Vector3<f64> {
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

/// The ground residual of `m` on `body` with friction coefficient `friction`.
pub fn ground_residual(
    m: &Mu,
    body: &Model,
    opts: &GroundOptions,
    friction: f64,
) -> Result<GroundResidual, GroundError> {
    opts.check()?;
    if !(friction.is_finite() && friction >= 0.0) {
        return Err(invalid_option(
            "friction",
            format!("friction must be a finite coefficient ≥ 0, got {friction}"),
        ));
    }
    check_coordinates(m, body)?;
    check_floating(body, &up_direction(&opts.gravity_of(body))?)?;
    let mass = body.total_mass();
    if !(mass > 0.0 && mass.is_finite()) {
        return Err(invalid(format!(
            "the body `{}` has no mass: the ground residual is a fraction of its weight",
            body.name
        )));
    }
    let gravity = opts.gravity_of(body);
    let weight = mass * gravity.norm();
    let pts = contact_points(body, opts.points.as_deref())?;
    let tr = tracks(m, body, &pts, opts)?;
    let floor = tr.floor(opts.floor);
    let (times, _) = frame_times(m, opts.rate)?;
    let n = body.nq();
    let (mut q, mut v, mut a, mut tau) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut ws = Workspace::new(body);
    let mut poses = Vec::with_capacity(body.num_links());
    let mut out = GroundResidual {
        times: times.clone(),
        force: vec![],
        moment: vec![],
        needed: vec![],
        in_contact: vec![],
        mean_force: 0.0,
        worst_force: 0.0,
        worst_force_frame: 0,
        mean_moment: 0.0,
        worst_moment: 0.0,
        worst_moment_frame: 0,
        weight,
        length: 1.0,
        floor,
        friction,
        unsolved: 0,
    };
    for (k, &t) in times.iter().enumerate() {
        sample_state(m, body, t, &mut q, Some((&mut v, &mut a)))?;
        inverse_dynamics(body, &mut ws, &q, &v, &a, &gravity, &mut tau)?;
        let w0 = root_wrench(body, &ws);
        body.forward_kinematics(&q, &mut poses)?;
        if k == 0 {
            out.length = length_scale(&poses, body);
        }
        let c = centre_of_mass(&poses, body);
        let f = Vector3::new(w0[3], w0[4], w0[5]);
        let mu_c = Vector3::new(w0[0], w0[1], w0[2]) - c.cross(&f);
        let w = crate::lie::Wrench::new(mu_c.x, mu_c.y, mu_c.z, f.x, f.y, f.z);
        let arms: Vec<Vector3<f64>> = (0..pts.len())
            .filter(|&j| tr.height(k, j) - floor <= opts.height)
            .map(|j| tr.positions[k][j] - c)
            .collect();
        let s = best_contact_forces(&w, &arms, &tr.up, friction, out.length)?;
        out.unsolved += usize::from(!s.solved);
        out.force.push(
            Vector3::new(s.residual[3], s.residual[4], s.residual[5]).norm() / weight * 100.0,
        );
        out.moment
            .push(Vector3::new(s.residual[0], s.residual[1], s.residual[2]).norm());
        out.needed.push(f.norm() / weight * 100.0);
        out.in_contact.push(arms.len());
    }
    let nf = out.force.len().max(1) as f64;
    out.mean_force = out.force.iter().sum::<f64>() / nf;
    out.mean_moment = out.moment.iter().sum::<f64>() / nf;
    for (k, (&f, &mo)) in out.force.iter().zip(&out.moment).enumerate() {
        if f > out.worst_force {
            (out.worst_force, out.worst_force_frame) = (f, k);
        }
        if mo > out.worst_moment {
            (out.worst_moment, out.worst_moment_frame) = (mo, k);
        }
    }
    Ok(out)
}
