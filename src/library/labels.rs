//! A clip's contact labels, taken once when it is indexed and stored with it
//! (in the `.mxlib`'s clip section), so a gap that follows the clip gets its
//! footfalls without recomputing them per query.
//!
//! Per contact point (`ground`'s default points of the clip's body: its foot
//! and toe joints, by name) and per frame of the clip (its own frame rate,
//! the grid `contacts()` samples), two labels, stored as runs of frames:
//! - `contact`: `contacts()`'s rule with its defaults: within
//!   [`crate::ground::CONTACT_HEIGHT`] of the floor (the lowest any point
//!   reaches over the clip) and slower than [`crate::ground::CONTACT_SPEED`];
//! - `plan`: SP's planning rule ([`crate::ground::plan_stances`]), the point
//!   standing at its own lowest height over the clip, its speed limit scaled
//!   by the body's speed ([`crate::ground::body_link`]), as the contact plan
//!   reads a capture (`spacetime::contact::capture_plan`). These are the
//!   stances a library example carries into a gap's plan.

use super::LibraryError;
use crate::ground::{self, GroundOptions};
use crate::mocap::{Clip, body_of};
use serde::{Deserialize, Serialize};

/// Runs of labelled frames: `[first, last]`, inclusive, in order.
pub type Runs = Vec<[u32; 2]>;

/// One contact point's labels over a clip.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PointLabels {
    /// The point's link: its joint's name, as the clip's body names it.
    pub name: String,
    /// Frames in contact by `contacts()`'s rule.
    pub contact: Runs,
    /// Frames in stance by SP's planning rule.
    pub plan: Runs,
    /// The height (m, along up) the point stands at by the planning rule:
    /// its lowest over the clip.
    pub stand: f64,
}

/// Every contact point's labels over a clip's frames.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ClipLabels {
    /// Time (s) of frame 0 and between frames.
    pub start: f64,
    pub frame_time: f64,
    pub frames: usize,
    /// The floor height (m, along up) of the `contact` labels.
    pub floor: f64,
    pub points: Vec<PointLabels>,
}

/// Any mass: neither rule depends on it (`body_of` needs one).
const MASS: f64 = 70.0;

/// The runs of `flags` (frames of the clip), by `ground`'s one rule.
fn runs(flags: &[bool]) -> Runs {
    ground::runs_of(flags)
        .into_iter()
        .map(|(a, b)| [a as u32, b as u32])
        .collect()
}

/// Per frame, whether it lies in one of `runs`.
pub fn flags(runs: &[[u32; 2]], frames: usize) -> Vec<bool> {
    let mut out = vec![false; frames];
    for &[a, b] in runs {
        for f in out.iter_mut().take(b as usize + 1).skip(a as usize) {
            *f = true;
        }
    }
    out
}

impl ClipLabels {
    /// The labels of `clip` on its own body (`body_of` its skeleton). A
    /// clip whose body has no foot contact point has none (an empty list).
    pub fn of(clip: &Clip) -> Result<ClipLabels, LibraryError> {
        let fail = |e: String| LibraryError::new(format!("contact labels: {e}"));
        let (body, _) = body_of(&clip.skeleton, MASS, clip.units.metres_per_unit)
            .map_err(|e| fail(e.to_string()))?;
        let opts = GroundOptions::default();
        let mut points = ground::default_contact_points(&body);
        let n_points = points.len();
        let up = ground::up_direction(&opts.gravity_of(&body)).map_err(|e| fail(e.to_string()))?;
        // the body's link rides along as one more tracked point
        let body_at = ground::body_link(&body, &up);
        if let Some(l) = body_at {
            points.push(ground::ContactPoint {
                name: body.link(l).name.clone(),
                link: l,
            });
        }
        let mut tracks =
            ground::tracks(&clip.mu, &body, &points, &opts).map_err(|e| fail(e.to_string()))?;
        let body_path: Vec<_> = tracks
            .positions
            .iter_mut()
            .map(|p| {
                let b = if body_at.is_some() { p.pop() } else { None };
                b.unwrap_or_else(nalgebra::Vector3::zeros)
            })
            .collect();
        tracks.points.truncate(n_points);
        let contacts =
            ground::contacts_of_tracks(&tracks, &opts).map_err(|e| fail(e.to_string()))?;
        let labels = contacts
            .points
            .iter()
            .enumerate()
            .map(|(j, pc)| {
                let path: Vec<_> = tracks.positions.iter().map(|p| p[j]).collect();
                let stand = path.iter().map(|x| up.dot(x)).fold(f64::INFINITY, f64::min);
                let plan = ground::plan_stances(&path, &body_path, tracks.frame_time, stand, &up);
                PointLabels {
                    name: pc.name.clone(),
                    contact: runs(&pc.in_contact),
                    plan: runs(&plan),
                    stand,
                }
            })
            .collect();
        Ok(ClipLabels {
            start: tracks.times.first().copied().unwrap_or(0.0),
            frame_time: tracks.frame_time,
            frames: tracks.times.len(),
            floor: contacts.floor,
            points: labels,
        })
    }

    /// Time (s) of frame `f`.
    pub fn time(&self, f: u32) -> f64 {
        self.start + f as f64 * self.frame_time
    }

    /// Each point's planning stances that overlap clip times [from, to], as
    /// clip-time intervals (first frame's time, last frame's time), in order.
    pub fn plan_spans(&self, from: f64, to: f64) -> Vec<(&str, Vec<(f64, f64)>)> {
        self.points
            .iter()
            .map(|p| {
                let spans = p
                    .plan
                    .iter()
                    .map(|&[a, b]| (self.time(a), self.time(b)))
                    .filter(|&(a, b)| b >= from && a <= to)
                    .collect();
                (p.name.as_str(), spans)
            })
            .collect()
    }

    /// The labels as stored (JSON).
    pub fn to_bytes(&self) -> Vec<u8> {
        serde_json::to_vec(self).expect("labels serialise")
    }

    /// Labels stored by [`ClipLabels::to_bytes`].
    pub fn from_bytes(bytes: &[u8]) -> Option<ClipLabels> {
        serde_json::from_slice(bytes).ok()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_and_flags_are_inverse() {
        for f in [
            vec![],
            vec![true],
            vec![false, true, true, false, true],
            vec![true, true, false, false, true, true],
        ] {
            let r = runs(&f);
            assert_eq!(flags(&r, f.len()), f, "{r:?}");
        }
        assert_eq!(
            runs(&[false, true, true, false, true]),
            vec![[1, 2], [4, 4]]
        );
    }
}
