//! Limbs held by inverse kinematics over a gap: Rose's support limbs
//! (§3.2.2; found by `supports.rs` or named) and a contact plan's stances.
//!
//! Over the gap a held frame k is kept on its path p̂_k(t): for a support
//! frame the straight line from where it is at the gap's start to where it
//! is at the gap's end (the curves are fixed there, so r = 0 is reachable at
//! both ends; the two points are inside the box of each other), for a
//! planned contact point its stances' anchors (and above the floor
//! elsewhere), by minimising
//!
//! R = ∫ Σ_k ‖p_k(q(t)) − p̂_k(t)‖² dt
//!
//! over the free B-spline coefficients of the gap DOFs on the chains from the
//! held frames to the root — the same transition curves and quadrature as the
//! spacetime solve (`ik.rs`, solved by `solve.rs`). R is a sum of squares and the unknowns are few, so
//! Gauss–Newton with Levenberg–Marquardt damping converges in a few
//! iterations. The Jacobian is analytic: a coordinate i of link L moves a point
//! p by ∂p/∂q_i = R_L(ω_i × R_Lᵀ(p − o_L) + v_i), [ω_i; v_i] = column i of the
//! joint's S(q) in L's frame. The solved DOFs then become inputs of the
//! spacetime solve of the remaining ones.

use super::error::SpError;
use crate::lie::Se3;
use crate::model::Model;
use nalgebra::Vector3;

mod ik;
mod solve;
pub mod supports;

pub use ik::{HoldObjective, IK_STIFFNESS};
pub use supports::{WINDOW, WINDOW_SAMPLES, detect};

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
