//! The ground residual: per frame, the part of the external wrench a motion
//! needs that no contact forces at the points on the floor can supply — the
//! summary of [`super::forces::ground_forces`], the one friction-cone solve
//! (its module doc says how): the force left as % of body weight, the moment
//! left about the centre of mass (N·m), per frame, mean and worst.

use super::GroundError;
use super::forces::ground_forces;
use super::points::GroundOptions;
use crate::model::Model;
use crate::motion::Mu;

/// SP's contact forces weigh moments and place forces as the residual does.
pub(crate) use super::body::{centre_of_mass, length_scale};

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

/// The ground residual of `m` on `body` with friction coefficient `friction`.
pub fn ground_residual(
    m: &Mu,
    body: &Model,
    opts: &GroundOptions,
    friction: f64,
) -> Result<GroundResidual, GroundError> {
    let g = ground_forces(m, body, opts, friction)?;
    let frames = g.times.len();
    let mut out = GroundResidual {
        times: g.times.clone(),
        force: (0..frames).map(|k| g.percent_bw(k)).collect(),
        moment: g.residual_moment.iter().map(|m| m.norm()).collect(),
        needed: g
            .needed
            .iter()
            .map(|f| f.norm() / g.weight * 100.0)
            .collect(),
        in_contact: g
            .in_contact
            .iter()
            .map(|fr| fr.iter().filter(|&&on| on).count())
            .collect(),
        mean_force: 0.0,
        worst_force: 0.0,
        worst_force_frame: 0,
        mean_moment: 0.0,
        worst_moment: 0.0,
        worst_moment_frame: 0,
        weight: g.weight,
        length: g.length,
        floor: g.floor,
        friction,
        unsolved: g.solved.iter().filter(|&&s| !s).count(),
    };
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
