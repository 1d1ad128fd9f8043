//! The contact forces that best hold a motion up, per frame: the one
//! friction-cone solve that [`super::ground_residual`] summarises and the
//! viewer draws as arrows.
//!
//! Per frame: inverse dynamics of the floating base (RNEA with the motion's
//! q, q̇, q̈, its velocities and accelerations the curves' own derivatives)
//! gives the wrench the world must apply through the root joint
//! ([`crate::dynamics::root_wrench`]), moved to the centre of mass; the
//! points within `height` of the floor push on it through their friction
//! cones (μ), the best forces found by [`super::cone::best_contact_forces`]
//! with moments weighed by the body length `L` (the largest extent of the
//! body's joints at the first frame). A point farther from the floor carries
//! no force. What the forces leave is the residual: a force (N) and a moment
//! about the centre of mass (N·m).

use super::body::{centre_of_mass, check_floating, length_scale};
use super::cone::best_contact_forces;
use super::floor::up_direction;
use super::points::{
    ContactPoint, GroundOptions, check_coordinates, contact_points, frame_times, sample_state,
    tracks,
};
use super::series::ForceSeries;
use super::{GroundError, invalid, invalid_option};
use crate::dynamics::{Workspace, inverse_dynamics, root_wrench};
use crate::lie::Wrench;
use crate::model::Model;
use crate::motion::Mu;
use nalgebra::Vector3;

/// Per frame, the contact forces at each point and what they leave.
#[derive(Clone, Debug, PartialEq)]
pub struct GroundForces {
    pub times: Vec<f64>,
    /// Seconds between frames.
    pub frame_time: f64,
    pub points: Vec<ContactPoint>,
    /// Unit up vector (against gravity).
    pub up: Vector3<f64>,
    /// `positions[k][j]`: point `j` at frame `k` (m, world): where its force acts.
    pub positions: Vec<Vec<Vector3<f64>>>,
    /// `forces[k][j]`: the force on the body at point `j` (N, world); zero
    /// where the point is not within `height` of the floor.
    pub forces: Vec<Vec<Vector3<f64>>>,
    /// `in_contact[k][j]`: point `j` was within `height` of the floor.
    pub in_contact: Vec<Vec<bool>>,
    /// Centre of mass per frame (m, world).
    pub com: Vec<Vector3<f64>>,
    /// The external force the motion needs per frame (N, world; the body's
    /// weight upward when it stands still).
    pub needed: Vec<Vector3<f64>>,
    /// What no contact force supplies: force (N, world) ...
    pub residual_force: Vec<Vector3<f64>>,
    /// ... and moment about the centre of mass (N·m, world).
    pub residual_moment: Vec<Vector3<f64>>,
    /// The cone problem reached its tolerance (`false`: approximate, flagged).
    pub solved: Vec<bool>,
    /// Body weight (N), the length scale L (m), the floor (m along up), μ.
    pub weight: f64,
    pub length: f64,
    pub floor: f64,
    pub friction: f64,
}

impl GroundForces {
    /// The residual force at frame `k` as % of body weight.
    pub fn percent_bw(&self, k: usize) -> f64 {
        self.residual_force[k].norm() / self.weight * 100.0
    }

    /// The sum of the contact forces at frame `k` (N, world).
    pub fn total(&self, k: usize) -> Vector3<f64> {
        self.forces[k].iter().sum()
    }

    /// The per-frame numbers alone, on the frames' grid.
    pub fn series(&self) -> ForceSeries {
        ForceSeries {
            times: self.times.clone(),
            frame_time: self.frame_time,
            points: self.points.iter().map(|p| p.name.clone()).collect(),
            forces: self.forces.clone(),
            residual_force: self.residual_force.clone(),
            residual_moment: self.residual_moment.clone(),
            percent_bw: (0..self.times.len()).map(|k| self.percent_bw(k)).collect(),
        }
    }

    /// As a motion on the frames' clock, one DOF per number: `POINT.Fx/Fy/Fz`
    /// (N, world axes) per contact point, then `residual.Fx/Fy/Fz` (N),
    /// `residual.Mx/My/Mz` (N·m about the centre of mass) and
    /// `residual.percent_bw` (% of body weight). Sampled curves, so `plot`,
    /// `save(…, "x.csv")` and the algebra take it as any motion
    /// ([`ForceSeries::to_motion`]).
    pub fn to_motion(&self) -> Result<Mu, GroundError> {
        self.series().to_motion()
    }
}

/// Checks `friction`: a coefficient ≥ 0.
fn check_friction(friction: f64) -> Result<(), GroundError> {
    if !(friction.is_finite() && friction >= 0.0) {
        return Err(invalid_option(
            "friction",
            format!("friction must be a finite coefficient ≥ 0, got {friction}"),
        ));
    }
    Ok(())
}

/// The mass of `body`; `Err` when it has none to weigh against.
fn body_mass(body: &Model) -> Result<f64, GroundError> {
    let mass = body.total_mass();
    if !(mass > 0.0 && mass.is_finite()) {
        return Err(invalid(format!(
            "the body `{}` has no mass: ground forces are fractions of its weight",
            body.name
        )));
    }
    Ok(mass)
}

/// The contact forces of `m` on `body` with friction coefficient `friction`
/// (see the module doc), at the motion's frames (`opts.rate` to choose).
pub fn ground_forces(
    m: &Mu,
    body: &Model,
    opts: &GroundOptions,
    friction: f64,
) -> Result<GroundForces, GroundError> {
    opts.check()?;
    check_friction(friction)?;
    check_coordinates(m, body)?;
    let gravity = opts.gravity_of(body);
    check_floating(body, &up_direction(&gravity)?)?;
    let mass = body_mass(body)?;
    let pts = contact_points(body, opts.points.as_deref())?;
    let tr = tracks(m, body, &pts, opts)?;
    let floor = tr.floor(opts.floor);
    let (times, frame_time) = frame_times(m, opts.rate)?;
    let n = body.nq();
    let (mut q, mut v, mut a, mut tau) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut ws = Workspace::new(body);
    let mut poses = Vec::with_capacity(body.num_links());
    let mut out = GroundForces {
        times: times.clone(),
        frame_time,
        points: pts.clone(),
        up: tr.up,
        positions: tr.positions.clone(),
        forces: vec![],
        in_contact: vec![],
        com: vec![],
        needed: vec![],
        residual_force: vec![],
        residual_moment: vec![],
        solved: vec![],
        weight: mass * gravity.norm(),
        length: 1.0,
        floor,
        friction,
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
        let w = Wrench::new(mu_c.x, mu_c.y, mu_c.z, f.x, f.y, f.z);
        let touching: Vec<bool> = (0..pts.len())
            .map(|j| tr.height(k, j) - floor <= opts.height)
            .collect();
        let arms: Vec<Vector3<f64>> = (0..pts.len())
            .filter(|&j| touching[j])
            .map(|j| tr.positions[k][j] - c)
            .collect();
        let s = best_contact_forces(&w, &arms, &tr.up, friction, out.length)?;
        let mut solved_forces = s.forces.into_iter();
        let forces = touching
            .iter()
            .map(|&on| {
                if on {
                    solved_forces.next().unwrap_or_default()
                } else {
                    Vector3::zeros()
                }
            })
            .collect();
        out.forces.push(forces);
        out.in_contact.push(touching);
        out.com.push(c);
        out.needed.push(f);
        out.residual_force
            .push(Vector3::new(s.residual[3], s.residual[4], s.residual[5]));
        out.residual_moment
            .push(Vector3::new(s.residual[0], s.residual[1], s.residual[2]));
        out.solved.push(s.solved);
    }
    Ok(out)
}
