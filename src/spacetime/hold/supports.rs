//! Rose's support frames (§3.2.2): a link whose world position stays inside
//! a small box over the end of the motion before a gap and the start of the
//! motion after it (a planted foot). Detection looks at [`WINDOW`] seconds on
//! each side (6 samples per side): long enough to tell a planted foot from a
//! swinging one passing through its lowest point, short enough to fit inside
//! the stance phase of a walk (≈0.6 s). Only frames near the ground count
//! (`ground`'s [`GROUND_BAND`] above the body's lowest frame): a still head or
//! hand of a person standing is not carrying the body.

use super::{candidates, link_positions};
use crate::ground::{GROUND_BAND, up_of};
use crate::model::Model;
use crate::spacetime::error::{SpError, invalid};
use nalgebra::Vector3;

/// Seconds of motion looked at on each side of a gap to detect support frames.
pub const WINDOW: f64 = 0.1;
/// Samples per side in [`WINDOW`].
pub const WINDOW_SAMPLES: usize = 6;

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
    let Some(up) = up_of(gravity) else {
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
