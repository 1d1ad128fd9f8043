//! BVH ↔ motion unit. A clip becomes an MU with one DOF per channel, named
//! `Joint.channel` exactly as in the file (`RightForeArm.Zrotation`,
//! `Hips.Xposition`), rotations in radians (unwrapped, so each curve is
//! continuous), positions in metres, each DOF one interval holding the frames
//! as a C² cubic-interpolated `Curve::Samples`, so q̇ and q̈ exist.
//!
//! Back: the MU is sampled at the frame times and written through the
//! skeleton it came from (or any skeleton whose channels it names).

use super::MocapError;
use super::bvh::{self, BvhFile, Skeleton, UnitChoice, Units};
use crate::motion::{Curve, Dof, Interval, Mu};
use std::path::Path;

/// A loaded clip: the motion, the skeleton it drives and how it was read.
#[derive(Clone, Debug)]
pub struct Clip {
    pub mu: Mu,
    pub skeleton: Skeleton,
    /// The length scale used (stated or detected) and why.
    pub units: UnitChoice,
    pub frame_time: f64,
    pub frames: usize,
    /// How many ±360° wraps were removed from rotation channels.
    pub wraps_removed: usize,
    /// What the reader tolerated in a loose file (see `bvh::parse_with_warnings`).
    pub warnings: Vec<bvh::BvhWarning>,
}

impl Clip {
    /// A one-line summary for the user, stating the unit choice.
    pub fn summary(&self) -> String {
        format!(
            "{} frames at {:.4} s ({:.1} fps), {} joints, {} DOFs; {}; {} angle wraps removed",
            self.frames,
            self.frame_time,
            1.0 / self.frame_time,
            self.skeleton.joints.len(),
            self.mu.len(),
            self.units.reason,
            self.wraps_removed
        )
    }
}

/// Reads a BVH file into a [`Clip`], keeping the reader's warnings in it.
pub fn load(path: &Path, units: Units) -> Result<Clip, MocapError> {
    let (file, warnings) = bvh::read_file_with_warnings(path)?;
    let mut clip = from_bvh(&file, units)?;
    clip.warnings = warnings;
    Ok(clip)
}

/// Converts parsed BVH data into a [`Clip`].
pub fn from_bvh(file: &BvhFile, units: Units) -> Result<Clip, MocapError> {
    from_bvh_at(file, units, 0.0)
}

/// [`from_bvh`] with its first frame at time `start` (s): some of a longer
/// clip's frames, on that clip's clock (a clip library reads the stretch a
/// match needs, not the whole take).
pub fn from_bvh_at(file: &BvhFile, units: Units, start: f64) -> Result<Clip, MocapError> {
    let units = bvh::resolve_units(units, &file.skeleton)?;
    let frames = file.frame_count();
    if frames == 0 {
        return Err(MocapError::invalid(
            "the BVH file has no frames (Frames: 0): nothing to load as motion",
        ));
    }
    let dt = file.frame_time;
    // A single frame is held for one frame time (an interval needs start < stop).
    let stop = start
        + if frames > 1 {
            (frames - 1) as f64 * dt
        } else {
            dt
        };
    let nch = file.skeleton.channel_count().max(1);
    let kinds = file.skeleton.joints.iter().flat_map(|j| j.channels.iter());
    let names = file.skeleton.channel_names();
    let mut wraps_removed = 0;
    let mut mu = Mu::new();
    for (c, (name, kind)) in names.into_iter().zip(kinds).enumerate() {
        // The column is copied out of the frame table once, into the Vec the
        // curve keeps; unwrapping and scaling happen in place in it (cloning
        // the whole file to unwrap it first doubled the copying).
        let mut values: Vec<f64> = file.values.iter().skip(c).step_by(nch).copied().collect();
        let scale = if kind.is_rotation() {
            wraps_removed += bvh::unwrap_degrees_in(values.iter_mut());
            1f64.to_radians()
        } else {
            units.metres_per_unit
        };
        values.iter_mut().for_each(|v| *v *= scale);
        let curve = if frames == 1 {
            Curve::constant(values[0])?
        } else {
            Curve::samples(start, dt, values)?
        };
        mu.insert(name, Dof::new(vec![Interval::curve(curve, start, stop)?])?);
    }
    Ok(Clip {
        mu,
        skeleton: file.skeleton.clone(),
        units,
        frame_time: dt,
        frames,
        wraps_removed,
        warnings: Vec::new(),
    })
}

/// What [`to_bvh`] did besides converting.
#[derive(Clone, Debug, Default)]
pub struct ToBvhReport {
    /// Channels the MU does not name, written at their rest value (0 for
    /// rotations, the OFFSET component for positions).
    pub filled_at_rest: Vec<String>,
    /// DOFs of the MU the skeleton has no channel for (not written).
    pub not_in_skeleton: Vec<String>,
}

/// Samples `mu` every `frame_time` seconds over its span and writes the values
/// through `skeleton` (degrees; lengths divided by `metres_per_unit`).
/// Undefined or conflicting samples are errors naming the DOF and time.
pub fn to_bvh(
    mu: &Mu,
    skeleton: &Skeleton,
    metres_per_unit: f64,
    frame_time: f64,
) -> Result<(BvhFile, ToBvhReport), MocapError> {
    if !(frame_time.is_finite() && frame_time > 0.0) {
        return Err(MocapError::invalid(format!(
            "frame time must be a positive number of seconds, got {frame_time}"
        )));
    }
    if !(metres_per_unit.is_finite() && metres_per_unit > 0.0) {
        return Err(MocapError::invalid(format!(
            "unit scale must be positive, got {metres_per_unit}"
        )));
    }
    let (t0, t1) = mu.span().ok_or_else(|| {
        MocapError::invalid("the motion is empty: no DOF is defined anywhere, nothing to save")
    })?;
    // Frame count by rounding, so a span of (n−1)·dt gives exactly n frames.
    let steps = ((t1 - t0) / frame_time + 1e-6).floor();
    if steps > 10_000_000.0 {
        return Err(MocapError::invalid(format!(
            "{steps} frames at {frame_time} s is too many; use a longer frame time"
        )));
    }
    let frames = steps as usize + 1;
    let mut report = ToBvhReport::default();
    let names = skeleton.channel_names();
    for n in mu.names() {
        if !names.iter().any(|c| c == n) {
            report.not_in_skeleton.push(n.to_string());
        }
    }
    let nch = names.len();
    let mut values = vec![0.0; frames * nch];
    let mut c = 0;
    for j in &skeleton.joints {
        for kind in &j.channels {
            let name = &names[c];
            match mu.get(name) {
                None => {
                    report.filled_at_rest.push(name.clone());
                    let rest = if kind.is_rotation() {
                        0.0
                    } else {
                        j.offset[kind.axis()]
                    };
                    for f in 0..frames {
                        values[f * nch + c] = rest;
                    }
                }
                Some(dof) => {
                    for f in 0..frames {
                        let t = (t0 + f as f64 * frame_time).min(t1);
                        let v = dof.sample_value(name, t)?.ok_or_else(|| {
                            MocapError::invalid(format!(
                                "DOF `{name}` is undefined at t = {t:.4} s; fill the gap (e.g. with SP) or clip the motion before saving"
                            ))
                        })?;
                        values[f * nch + c] = if kind.is_rotation() {
                            v.to_degrees()
                        } else {
                            v / metres_per_unit
                        };
                    }
                }
            }
            c += 1;
        }
    }
    Ok((
        BvhFile {
            skeleton: skeleton.clone(),
            frame_time,
            values,
        },
        report,
    ))
}

/// Writes `mu` as a BVH file through `skeleton`.
pub fn save(
    mu: &Mu,
    skeleton: &Skeleton,
    metres_per_unit: f64,
    frame_time: f64,
    path: &Path,
) -> Result<ToBvhReport, MocapError> {
    let (file, report) = to_bvh(mu, skeleton, metres_per_unit, frame_time)?;
    bvh::write_file(&file, path)?;
    Ok(report)
}

/// The frame time of a loaded clip (at its path of old; it lives with the motions).
pub use crate::motion::sample_period;
