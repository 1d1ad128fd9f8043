//! Support limbs held by inverse kinematics over a transition (Rose §3.2.2).
//!
//! A support frame is a link whose world position stays inside a small box
//! over the end of the motion before a gap and the start of the motion after
//! it (a planted foot), or one the animator names. Detection looks at
//! [`WINDOW`] seconds on each side (6 samples per side): long enough to tell a
//! planted foot from a swinging one passing through its lowest point, short
//! enough to fit inside the stance phase of a walk (≈0.6 s). Only frames near
//! the ground count ([`GROUND_BAND`] above the body's lowest frame): a still
//! head or hand of a person standing is not carrying the body.
//!
//! Over the gap a support frame k is held on its planted path p̂_k(t), the
//! straight line from where it is at the gap's start to where it is at the
//! gap's end (the curves are fixed there, so r = 0 is reachable at both ends;
//! the two points are inside the box of each other), by minimising
//!
//! R = ∫ Σ_k ‖p_k(q(t)) − p̂_k(t)‖² dt
//!
//! over the free B-spline coefficients of the gap DOFs on the chains from the
//! held frames to the root — the same transition curves and quadrature as the
//! spacetime solve. R is a sum of squares and the unknowns are few, so
//! Gauss–Newton with Levenberg–Marquardt damping converges in a few
//! iterations. The Jacobian is analytic: a coordinate i of link L moves a point
//! p by ∂p/∂q_i = R_L(ω_i × R_Lᵀ(p − o_L) + v_i), [ω_i; v_i] = column i of the
//! joint's S(q) in L's frame. The solved DOFs then become inputs of the
//! spacetime solve of the remaining ones.

use super::error::{SpError, invalid};
use crate::lie::Se3;
use crate::model::Model;
use nalgebra::Vector3;

mod ik;
mod solve;

pub use ik::{IK_STIFFNESS, SupportObjective};

/// Seconds of motion looked at on each side of a gap to detect support frames.
pub const WINDOW: f64 = 0.1;
/// Samples per side in [`WINDOW`].
pub const WINDOW_SAMPLES: usize = 6;
/// A support frame lies within this height (m) of the body's lowest frame.
pub const GROUND_BAND: f64 = 0.15;

/// One support frame held over one gap.
#[derive(Clone, Debug, PartialEq)]
pub struct HeldFrame {
    /// The link's name.
    pub frame: String,
    pub t0: f64,
    pub t1: f64,
    /// `true` when found by the box test, `false` when named.
    pub detected: bool,
    /// The gap DOFs solved by IK (every held frame of the gap shares them).
    pub dofs: Vec<String>,
    /// Largest distance (m) from its planted path over the gap with the
    /// starting (Hermite) curves, i.e. without IK.
    pub moved_before: f64,
    /// The same after IK.
    pub moved: f64,
}

/// The world position of every link (by index) at configuration q.
fn link_positions(model: &Model, q: &[f64], poses: &mut Vec<Se3>) -> Result<(), SpError> {
    model
        .forward_kinematics(q, poses)
        .map_err(SpError::Kinematics)
}

/// The world positions of `frames` at time t of a fully defined configuration.
fn frame_positions(
    model: &Model,
    frames: &[usize],
    configuration: &dyn Fn(f64) -> Result<Vec<f64>, SpError>,
    t: f64,
) -> Result<Vec<Vector3<f64>>, SpError> {
    let q = configuration(t)?;
    if q.iter().any(|v| !v.is_finite()) {
        return Err(SpError::Incomplete(format!(
            "support IK: the body is not fully defined at the gap end t = {t}"
        )));
    }
    let mut poses = vec![];
    link_positions(model, &q, &mut poses)?;
    Ok(frames.iter().map(|&f| poses[f].p).collect())
}

/// The link that owns coordinate c.
pub(crate) fn owner(model: &Model, c: usize) -> Option<usize> {
    model.coordinate_link(c)
}

/// Candidate support frames: every link that is not an intermediate link of a
/// multi-DOF joint (those coincide with the next link).
pub(crate) fn candidates(model: &Model) -> Vec<usize> {
    crate::model::joint_points(model).0
}

/// Frames whose position stays in a cube of edge `box_size` over `q_before`
/// and `q_after` (configurations sampled on each side of the gap) and that lie
/// near the ground (see [`GROUND_BAND`]).
pub fn detect(
    model: &Model,
    configurations: &[Vec<f64>],
    gravity: &Vector3<f64>,
    box_size: f64,
) -> Result<Vec<usize>, SpError> {
    if !(box_size.is_finite() && box_size >= 0.0) {
        return Err(invalid(format!(
            "support box size {box_size} m must be finite and non-negative (default 0.02)"
        )));
    }
    let up = if gravity.norm() > 0.0 {
        -gravity / gravity.norm()
    } else {
        return Ok(vec![]); // no gravity: nothing is supported
    };
    let links = candidates(model);
    let mut lo = vec![Vector3::repeat(f64::INFINITY); links.len()];
    let mut hi = vec![Vector3::repeat(f64::NEG_INFINITY); links.len()];
    let mut lowest = f64::INFINITY;
    let mut poses = vec![];
    for q in configurations {
        link_positions(model, q, &mut poses)?;
        for (j, &l) in links.iter().enumerate() {
            let p = poses[l].p;
            lo[j] = lo[j].inf(&p);
            hi[j] = hi[j].sup(&p);
            lowest = lowest.min(p.dot(&up));
        }
    }
    if configurations.is_empty() {
        return Ok(vec![]);
    }
    Ok(links
        .iter()
        .enumerate()
        .filter(|&(j, _)| {
            let still = (hi[j] - lo[j]).iter().all(|d| *d <= box_size);
            // the frame's highest point over the windows is near the ground
            let h = 0.5 * (hi[j] + lo[j]);
            let near_ground = h.dot(&up) - lowest <= GROUND_BAND + box_size;
            still && near_ground
        })
        .map(|(_, &l)| l)
        .collect())
}

/// Links named by the user in `option` (`support`, `contact`); an unknown
/// name is an error listing the closest names.
pub fn named(model: &Model, names: &[String], option: &'static str) -> Result<Vec<usize>, SpError> {
    names
        .iter()
        .map(|n| {
            model
                .link_index(n)
                .ok_or_else(|| unknown_frame(model, n, option))
        })
        .collect()
}

/// "no frame named `n`", with the five nearest frame names. `body_of`
/// bodies carry a massless link per channel (`Hips.Xrotation`); where the
/// body has joints named without a dot, only those are suggested.
fn unknown_frame(model: &Model, n: &str, option: &'static str) -> SpError {
    let links: Vec<&str> = model.links().iter().map(|l| l.name.as_str()).collect();
    let joints: Vec<&str> = links.iter().copied().filter(|l| !l.contains('.')).collect();
    let shown = if joints.is_empty() { &links } else { &joints };
    let mut near: Vec<(f64, &str)> = shown
        .iter()
        .map(|l| {
            let score =
                strsim::normalized_damerau_levenshtein(&n.to_lowercase(), &l.to_lowercase());
            (score, *l)
        })
        .collect();
    near.sort_by(|a, b| b.0.total_cmp(&a.0));
    let list: Vec<&str> = near.iter().take(5).map(|(_, s)| *s).collect();
    let what = if option == "contact" {
        "to plant"
    } else {
        "to hold as a support limb"
    };
    crate::spacetime::error::invalid_option(
        option,
        format!(
            "the body has no frame named `{n}` {what}; the nearest names are {}",
            list.join(", ")
        ),
    )
}

/// Where a held frame must be over part of a gap: on the straight path from
/// `p0` at `t0` to `p1` at `t1` (a planted foot: `p0 == p1`).
#[derive(Clone, Debug, PartialEq)]
pub struct Plant {
    pub t0: f64,
    pub t1: f64,
    pub p0: Vector3<f64>,
    pub p1: Vector3<f64>,
}

impl Plant {
    fn covers(&self, t: f64) -> bool {
        t >= self.t0 && t <= self.t1
    }

    fn at(&self, t: f64) -> Vector3<f64> {
        let s = ((t - self.t0) / (self.t1 - self.t0)).clamp(0.0, 1.0);
        self.p0 * (1.0 - s) + self.p1 * s
    }
}

/// The floor of a contact schedule: the plane of points p with `up · p = height`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Floor {
    /// Unit vector against gravity.
    pub up: Vector3<f64>,
    pub height: f64,
}
