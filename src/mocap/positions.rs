//! Forward kinematics over time: every joint's world position, for IK,
//! plots and the viewer.
//!
//! A body's coordinates are looked up in the motion by name. The points
//! reported are the body's links, except intermediate links of multi-DOF
//! joints (massless, named after their joint, one child attached with no
//! offset), which coincide with the next link; each point's parent is its nearest reported ancestor.

use super::MocapError;
use super::to_motion::sample_period;
use crate::lie::Se3;
use crate::model::Model;
use crate::motion::{Mu, grid_times};
use nalgebra::Vector3;

/// Joint positions over time.
#[derive(Clone, Debug)]
pub struct Positions {
    /// Link name of each point.
    pub names: Vec<String>,
    /// Parent point of each point (`None` at the root).
    pub parents: Vec<Option<usize>>,
    /// Link index of each point in the body.
    pub links: Vec<usize>,
    pub times: Vec<f64>,
    /// `points[k][j]`: world position (metres) of point `j` at `times[k]`.
    pub points: Vec<Vec<Vector3<f64>>>,
    /// `undefined[k]`: some coordinate the motion names was undefined at
    /// `times[k]` and held its last value (only with [`Missing::Hold`]).
    pub undefined: Vec<bool>,
}

/// What to do with body coordinates the motion does not define.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Missing {
    /// A coordinate the MU lacks, or a time where a DOF is undefined, is an
    /// error naming it (the language's `positions`).
    Error,
    /// Lacking coordinates are 0; undefined samples hold the last defined
    /// value (0 before any): for drawing motions with gaps (the viewer).
    Hold,
}

/// The links reported as joints (the topology lives with the model).
pub use crate::model::topology::joint_points;

/// Samples `mu` at `rate` Hz (default: the clip's own frame rate, else 30 Hz)
/// over its span and runs forward kinematics of `body` at each time.
pub fn positions(
    mu: &Mu,
    body: &Model,
    rate: Option<f64>,
    missing: Missing,
) -> Result<Positions, MocapError> {
    positions_at(mu, body, frame_times(mu, rate)?, missing)
}

/// The frame times of `mu`: every multiple of 1/`rate` in its span (default
/// rate: the clip's own frame rate, else 30 Hz); one time for a span shorter
/// than a frame. [`positions`], glTF files and `frames(m)` share this grid.
pub fn frame_times(mu: &Mu, rate: Option<f64>) -> Result<Vec<f64>, MocapError> {
    let rate = rate
        .or_else(|| sample_period(mu).map(|dt| 1.0 / dt))
        .unwrap_or(30.0);
    let span = mu
        .span()
        .ok_or_else(|| MocapError::invalid("the motion is empty: no DOF is defined anywhere"))?;
    let mut times = grid_times(span, rate)?;
    if times.is_empty() {
        times.push(span.0);
    }
    Ok(times)
}

/// Forward kinematics of `body` driven by `mu` at the given times.
pub fn positions_at(
    mu: &Mu,
    body: &Model,
    times: Vec<f64>,
    missing: Missing,
) -> Result<Positions, MocapError> {
    let p = poses_at(mu, body, times, missing)?;
    Ok(Positions {
        names: p.names,
        parents: p.parents,
        links: p.links,
        times: p.times,
        points: p
            .poses
            .iter()
            .map(|fr| fr.iter().map(|x| x.p).collect())
            .collect(),
        undefined: p.undefined,
    })
}

/// Joint frames over time: the points of [`Positions`] with their orientations
/// (what a glTF skeleton animates).
#[derive(Clone, Debug)]
pub struct Poses {
    /// Link name of each joint.
    pub names: Vec<String>,
    /// Parent joint of each joint (`None` at a root).
    pub parents: Vec<Option<usize>>,
    /// Link index of each joint in the body.
    pub links: Vec<usize>,
    pub times: Vec<f64>,
    /// `poses[k][j]`: world frame of joint `j` at `times[k]`.
    pub poses: Vec<Vec<Se3>>,
    /// As [`Positions::undefined`].
    pub undefined: Vec<bool>,
}

/// Forward kinematics of `body` driven by `mu` at the given times: every
/// joint's world frame.
pub fn poses_at(
    mu: &Mu,
    body: &Model,
    times: Vec<f64>,
    missing: Missing,
) -> Result<Poses, MocapError> {
    let coords = body.coordinate_names();
    let lacking: Vec<&str> = coords
        .iter()
        .filter(|c| mu.get(c).is_none())
        .map(String::as_str)
        .collect();
    if missing == Missing::Error && !lacking.is_empty() {
        let shown: Vec<&str> = lacking.iter().take(5).copied().collect();
        return Err(MocapError::invalid(format!(
            "the motion has no DOF for {} of the body's {} coordinates ({}{}); use a body built from this motion's clip, or a motion that defines them",
            lacking.len(),
            coords.len(),
            shown.join(", "),
            if lacking.len() > 5 { ", …" } else { "" }
        )));
    }
    let (links, parents) = joint_points(body);
    let mut q = vec![0.0; coords.len()];
    let mut poses: Vec<Se3> = Vec::with_capacity(body.num_links());
    let mut points = Vec::with_capacity(times.len());
    let mut undefined = Vec::with_capacity(times.len());
    for &t in &times {
        let mut held = false;
        for (k, name) in coords.iter().enumerate() {
            let Some(dof) = mu.get(name) else { continue };
            match dof.sample_value(name, t)? {
                Some(v) => q[k] = v,
                None if missing == Missing::Hold => held = true,
                None => {
                    return Err(MocapError::invalid(format!(
                        "DOF `{name}` is undefined at t = {t:.4} s; fill the gap (SP) or clip the motion first"
                    )));
                }
            }
        }
        body.forward_kinematics(&q, &mut poses)?;
        points.push(links.iter().map(|&l| poses[l]).collect());
        undefined.push(held);
    }
    Ok(Poses {
        names: links.iter().map(|&l| body.link(l).name.clone()).collect(),
        parents,
        links,
        times,
        poses: points,
        undefined,
    })
}
