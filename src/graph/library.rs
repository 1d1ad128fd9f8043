//! The clips of a transition library: every `.bvh` file of a folder, sorted
//! by name, checked to share one skeleton, with each frame's joint point
//! cloud (for the transition-point search) and the motion SP sees.
//!
//! A clip that fails to load is kept as a [`ClipFailure`] (its pairs are
//! recorded as failed and the rest go on); a folder with no clips, clips of
//! different skeletons or fewer than two loadable clips are errors.

use super::error::{ClipError, GraphError};
use super::planar::RootChannels;
use crate::mocap::bvh::{self, BvhFile, Skeleton, Units};
use crate::mocap::{self, Clip};
use crate::model::Model;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Body mass of the bodies SP optimises (kg), `body_of`'s default.
pub const BODY_MASS: f64 = 70.0;

/// One loaded clip.
pub struct LibClip {
    pub name: String,
    pub path: PathBuf,
    /// The file as read (degrees, file units), for rows and forward kinematics.
    pub file: BvhFile,
    /// The motion (radians, metres) on the file's frame times.
    pub clip: Clip,
    /// `points[f]`: world positions in frame f (metres) of every joint from
    /// the root down (the still joints above it would only add the alignment's shift).
    pub points: Vec<Vec<Vector3<f64>>>,
}

impl LibClip {
    pub fn frames(&self) -> usize {
        self.clip.frames
    }
}

/// A clip that could not be used, and why.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ClipFailure {
    pub clip: String,
    pub error: String,
}

/// The loaded library.
pub struct Library {
    /// Every clip name found, sorted (loaded or not): the pair list is over these.
    pub names: Vec<String>,
    /// Loaded clips by position in `names` (`None`: it failed, see `failures`).
    pub clips: Vec<Option<LibClip>>,
    pub failures: Vec<ClipFailure>,
    pub skeleton: Skeleton,
    pub metres_per_unit: f64,
    pub frame_time: f64,
    /// SP's body, built once from the skeleton.
    pub body: Model,
    pub root: RootChannels,
}

/// Every `.bvh` file directly in `dir`, sorted by file name.
pub fn clip_paths(dir: &Path) -> Result<Vec<PathBuf>, GraphError> {
    let entries = std::fs::read_dir(dir).map_err(|e| {
        GraphError::new(format!(
            "cannot read the clip folder {}: {e}",
            dir.display()
        ))
    })?;
    let mut paths: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_file() && p.extension().is_some_and(|x| x.eq_ignore_ascii_case("bvh")))
        .collect();
    paths.sort();
    if paths.is_empty() {
        return Err(GraphError::new(format!(
            "no .bvh clips in {}: a transition library needs at least two clips of one skeleton",
            dir.display()
        )));
    }
    Ok(paths)
}

/// The clip's name: its file stem.
pub fn clip_name(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default()
}

fn load_clip(path: &Path) -> Result<LibClip, ClipError> {
    let (file, _) = bvh::read_file_with_warnings(path)?;
    let clip = mocap::from_bvh(&file, Units::Auto)?;
    Ok(LibClip {
        name: clip_name(path),
        path: path.to_path_buf(),
        file,
        clip,
        points: vec![],
    })
}

/// Where a clip's skeleton differs from the first clip's.
#[derive(Debug, thiserror::Error)]
enum SkeletonMismatch {
    #[error("{got} joints instead of {want}")]
    JointCount { got: usize, want: usize },
    #[error(
        "joint `{got}` (channels {got_channels}) where the first clip has `{want}` (channels {want_channels})"
    )]
    Joint {
        got: String,
        got_channels: String,
        want: String,
        want_channels: String,
    },
}

/// Joint names, parents and channels: what makes two clips one skeleton
/// (OFFSETs may differ slightly between takes; the first clip's are written).
fn same_skeleton(a: &Skeleton, b: &Skeleton) -> Result<(), SkeletonMismatch> {
    if a.joints.len() != b.joints.len() {
        return Err(SkeletonMismatch::JointCount {
            got: b.joints.len(),
            want: a.joints.len(),
        });
    }
    for (ja, jb) in a.joints.iter().zip(&b.joints) {
        if ja.name != jb.name || ja.parent != jb.parent || ja.channels != jb.channels {
            let names =
                |cs: &[bvh::Channel]| cs.iter().map(|c| c.name()).collect::<Vec<_>>().join(" ");
            return Err(SkeletonMismatch::Joint {
                got: jb.name.clone(),
                got_channels: names(&jb.channels),
                want: ja.name.clone(),
                want_channels: names(&ja.channels),
            });
        }
    }
    Ok(())
}

/// Loads every clip of `dir` (in parallel; the result does not depend on the order).
pub fn load(dir: &Path) -> Result<Library, GraphError> {
    use rayon::prelude::*;
    let paths = clip_paths(dir)?;
    let names: Vec<String> = paths.iter().map(|p| clip_name(p)).collect();
    for w in names.windows(2) {
        if w[0] == w[1] {
            return Err(GraphError::new(format!(
                "two clips in {} are both named `{}` (file names differing only in the extension's case)",
                dir.display(),
                w[0]
            )));
        }
    }
    let loaded: Vec<Result<LibClip, ClipError>> = paths.par_iter().map(|p| load_clip(p)).collect();
    let mut clips = vec![];
    let mut failures = vec![];
    let mut first: Option<(String, Skeleton, f64, f64)> = None;
    for (name, r) in names.iter().zip(loaded) {
        match r {
            Ok(c) => {
                match &first {
                    None => {
                        first = Some((
                            name.clone(),
                            c.file.skeleton.clone(),
                            c.clip.units.metres_per_unit,
                            c.clip.frame_time,
                        ))
                    }
                    Some((n0, sk, mpu, dt)) => {
                        if let Err(why) = same_skeleton(sk, &c.file.skeleton) {
                            return Err(GraphError::new(format!(
                                "clips of different skeletons: `{name}` has {why}; a library holds clips of one skeleton (like `{n0}`)"
                            )));
                        }
                        if (c.clip.units.metres_per_unit - mpu).abs() > 1e-12 * mpu {
                            return Err(GraphError::new(format!(
                                "`{name}` was read at {} m per unit but `{n0}` at {mpu}: the clips' units differ",
                                c.clip.units.metres_per_unit
                            )));
                        }
                        if (c.clip.frame_time - dt).abs() > 1e-9 {
                            return Err(GraphError::new(format!(
                                "`{name}` has frame time {} s but `{n0}` {dt} s: resample the clips to one frame rate",
                                c.clip.frame_time
                            )));
                        }
                    }
                }
                clips.push(Some(c));
            }
            Err(error) => {
                failures.push(ClipFailure {
                    clip: name.clone(),
                    error: error.to_string(),
                });
                clips.push(None);
            }
        }
    }
    let loaded = clips.iter().flatten().count();
    let Some((_, skeleton, metres_per_unit, frame_time)) = first else {
        return Err(GraphError::new(format!(
            "none of the {} clips in {} could be read; first: {}: {}",
            names.len(),
            dir.display(),
            failures[0].clip,
            failures[0].error
        )));
    };
    if loaded < 2 {
        return Err(GraphError::new(format!(
            "only {loaded} of the {} clips in {} could be read: a transition needs two clips{}",
            names.len(),
            dir.display(),
            failures
                .first()
                .map(|f| format!(" ({}: {})", f.clip, f.error))
                .unwrap_or_default()
        )));
    }
    let (body, _) = mocap::body_of(&skeleton, BODY_MASS, metres_per_unit)
        .map_err(|e| GraphError::new(format!("cannot build a body from the skeleton: {e}")))?;
    // channels that ever change anywhere in the library
    let nch = skeleton.channel_count();
    let mut moving = vec![false; nch];
    let first_row = clips
        .iter()
        .flatten()
        .next()
        .expect("two loaded")
        .file
        .frame(0)
        .to_vec();
    for c in clips.iter().flatten() {
        for f in 0..c.file.frame_count() {
            for (k, v) in c.file.frame(f).iter().enumerate() {
                moving[k] |= *v != first_row[k];
            }
        }
    }
    let root = RootChannels::find(&skeleton, &moving, &first_row, metres_per_unit)?;
    clips.par_iter_mut().flatten().for_each(|c| {
        c.points = (0..c.frames())
            .map(|f| bvh::fk::world_positions(&c.file, f, metres_per_unit)[root.joint..].to_vec())
            .collect();
    });
    Ok(Library {
        names,
        clips,
        failures,
        skeleton,
        metres_per_unit,
        frame_time,
        body,
        root,
    })
}
