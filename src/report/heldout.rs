//! Clips the in-betweening benchmark was not tuned on: other folders (the
//! hidden benchmark's recordings, `$MX_SHARED/data/mocap`'s Bandai and CMU
//! clips), read at the protocol's 30 fps whatever rate they were captured
//! at, and clips made from them that no one has seen: played 0.8× and 1.25×
//! as fast, and mirrored left for right.
//!
//! A 120 Hz clip is resampled (its every fourth frame), not scored in
//! seconds at its own rate: every method then sees the same 10 context
//! frames (⅓ s) and gaps of 15/30/45 frames (0.5/1/1.5 s) as on the 30 fps
//! clips, and the per-frame measures (skate's finite differences, NPSS's
//! spectrum) mean the same thing on every clip.

use super::error::ReportError;
use super::inbetween::{Case, PROTOCOL_RATE, is_locomotion};
use super::regrid::regrid;
use crate::mocap::bvh::Skeleton;
use crate::motion::channel::mirror_name;
use std::path::{Path, PathBuf};

/// The horizontal axis that separates the skeleton's left from its right at
/// rest (0 = x, 1 = y, 2 = z): the one along which joints and their mirror
/// images (`Foot_L`/`Foot_R`, `LeftFoot`/`RightFoot`) lie farthest apart.
/// `None` when no joint has a mirror image.
pub fn lateral_axis(skeleton: &Skeleton) -> Option<usize> {
    let mut rest: Vec<nalgebra::Vector3<f64>> = vec![];
    for j in &skeleton.joints {
        let p = j.parent.map_or(nalgebra::Vector3::zeros(), |q| rest[q]);
        rest.push(p + j.offset);
    }
    let mut spread = [0.0f64; 3];
    let mut found = false;
    for (i, j) in skeleton.joints.iter().enumerate() {
        let Some(other) = mirror_name(&j.name) else {
            continue;
        };
        let Some(k) = skeleton.joints.iter().position(|o| o.name == other) else {
            continue;
        };
        found = true;
        for (a, s) in spread.iter_mut().enumerate() {
            *s += (rest[i][a] - rest[k][a]).abs();
        }
    }
    found.then(|| {
        (0..3)
            .max_by(|&a, &b| spread[a].total_cmp(&spread[b]))
            .unwrap_or(0)
    })
}

/// `case` played `speed` times as fast (0.8: slower, 1.25: faster), at its
/// own frame time, named `NAME~speed0.8`.
pub fn warped(case: &Case, speed: f64) -> Result<Case, ReportError> {
    let span = (case.frames - 1) as f64 * case.frame_time;
    let (mu, frames) = regrid(&case.capture, span, speed, case.frame_time)?;
    Case::from_motion(
        &format!("{}~speed{speed}", case.name),
        &case.source,
        mu,
        case.skeleton.clone(),
        case.metres_per_unit,
        (case.frame_time, frames),
    )
}

/// `case` mirrored left for right ([`crate::motion::compose::mirror`] in
/// the plane normal to its [`lateral_axis`]), named `NAME~mirror`.
pub fn mirrored(case: &Case) -> Result<Case, ReportError> {
    let axis = lateral_axis(&case.skeleton).ok_or_else(|| ReportError::NoMirror {
        clip: case.name.clone(),
    })?;
    let mu = crate::motion::compose::mirror(&case.capture, axis)
        .map_err(|e| ReportError::in_clip(&case.name, e.into()))?;
    Case::from_motion(
        &format!("{}~mirror", case.name),
        &case.source,
        mu,
        case.skeleton.clone(),
        case.metres_per_unit,
        (case.frame_time, case.frames),
    )
}

/// Which clips a run takes: by name (globs on the file name without its
/// extension, any may match; none: all) and locomotion only.
#[derive(Clone, Debug, Default)]
pub struct ClipFilter {
    pub globs: Vec<glob::Pattern>,
    pub locomotion: bool,
}

impl ClipFilter {
    /// `walk*,run*` style globs (comma-separated); a bad one is an error naming it.
    pub fn parse(globs: &str, locomotion: bool) -> Result<ClipFilter, ReportError> {
        let globs = globs
            .split(',')
            .map(str::trim)
            .filter(|g| !g.is_empty())
            .map(|g| {
                glob::Pattern::new(g).map_err(|source| ReportError::Glob {
                    glob: g.to_string(),
                    source,
                })
            })
            .collect::<Result<_, _>>()?;
        Ok(ClipFilter { globs, locomotion })
    }

    pub fn keeps(&self, name: &str) -> bool {
        (self.globs.is_empty() || self.globs.iter().any(|g| g.matches(name)))
            && (!self.locomotion || is_locomotion(name))
    }
}

/// The `.bvh` files of `dirs` whose names `filter` keeps, sorted by name
/// within each folder, folders in the order given. A folder that cannot be
/// read, or names no clip at all, is an error naming it.
pub fn clip_paths(dirs: &[PathBuf], filter: &ClipFilter) -> Result<Vec<PathBuf>, ReportError> {
    let mut out = vec![];
    for dir in dirs {
        let mut paths: Vec<PathBuf> = std::fs::read_dir(dir)
            .map_err(|source| ReportError::Folder {
                path: dir.clone(),
                source,
            })?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x.eq_ignore_ascii_case("bvh")))
            .collect();
        if paths.is_empty() {
            return Err(ReportError::NoClips { path: dir.clone() });
        }
        paths.sort();
        out.extend(paths.into_iter().filter(|p| keeps_path(filter, p)));
    }
    Ok(out)
}

fn keeps_path(filter: &ClipFilter, p: &Path) -> bool {
    p.file_stem()
        .is_some_and(|s| filter.keeps(&s.to_string_lossy()))
}

/// Made-up clips of the cases: each played at every speed of `speeds` and,
/// with `mirror`, mirrored; in the order of `cases`. A clip that cannot be
/// mirrored (no left/right twins) is left out of the mirrors.
pub fn variants(cases: &[Case], speeds: &[f64], mirror: bool) -> Result<Vec<Case>, ReportError> {
    use rayon::prelude::*;
    let per_case: Vec<Result<Vec<Case>, ReportError>> = cases
        .par_iter()
        .map(|c| {
            let mut out = vec![];
            for &s in speeds {
                out.push(warped(c, s)?);
            }
            if mirror && lateral_axis(&c.skeleton).is_some() {
                out.push(mirrored(c)?);
            }
            Ok(out)
        })
        .collect();
    let mut out = vec![];
    for v in per_case {
        out.extend(v?);
    }
    Ok(out)
}

/// Every clip of `paths` at the protocol's rate ([`PROTOCOL_RATE`]).
pub fn load(paths: &[PathBuf]) -> Result<Vec<Case>, ReportError> {
    use rayon::prelude::*;
    paths
        .par_iter()
        .map(|p| Case::load_at(p, Some(PROTOCOL_RATE)))
        .collect()
}
