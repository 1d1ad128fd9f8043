//! One clip of the benchmark: read (at its own rate or the protocol's), its
//! body, root and floor, the windows it holds and the motion a method sees
//! in one of them (the gap cut out).

use super::protocol::{BODY_MASS, Protocol, RootMode};
use crate::mocap::bvh::{Skeleton, Units};
use crate::mocap::{self};
use crate::model::Model;
use crate::motion::{Curve, Dof, Interval, Mu};
use crate::report::error::ReportError;
use crate::report::regrid::regrid;
use crate::score::floor_of;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// One clip of the benchmark: its captured motion and the body of its skeleton.
pub struct Case {
    pub name: String,
    /// The file (name without extension) the clip was read from: its own
    /// name, or the clip a time warp or mirror was made of.
    pub source: String,
    pub capture: Mu,
    pub body: Model,
    pub frame_time: f64,
    pub frames: usize,
    /// DOFs of the root (the skeleton's first joint and, while it never moves,
    /// its first child: Bandai's all-zero `joint_Root` above `Hips`).
    pub root_dofs: Vec<String>,
    /// The floor: `ground`'s floor of the captured clip, the lowest height
    /// its contact points reach (`score::floor_of`).
    pub floor: f64,
    /// The clip's skeleton and length unit (a library's features are read through them).
    pub skeleton: Arc<Skeleton>,
    pub metres_per_unit: f64,
}

impl Case {
    /// The clip at `path` at its own frame rate.
    pub fn load(path: &Path) -> Result<Case, ReportError> {
        Case::load_at(path, None)
    }

    /// The clip at `path`, resampled to `rate` Hz when it was captured at
    /// another rate ([`regrid`]): the protocol counts frames at 30 fps
    /// ([`super::PROTOCOL_RATE`]), so a 120 Hz clip is read as its every
    /// fourth frame and a gap of 30 frames is 1 s on every clip.
    pub fn load_at(path: &Path, rate: Option<f64>) -> Result<Case, ReportError> {
        let clip = mocap::load(path, Units::Auto).map_err(|source| ReportError::Clip {
            path: path.to_path_buf(),
            source,
        })?;
        let in_file = |e: ReportError| ReportError::InFile {
            path: path.to_path_buf(),
            source: Box::new(e),
        };
        let name = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let (mu, frame_time, frames) = match rate {
            Some(r) if ((1.0 / clip.frame_time) - r).abs() > 1e-3 * r => {
                let dt = 1.0 / r;
                let span = (clip.frames - 1) as f64 * clip.frame_time;
                let (mu, frames) = regrid(&clip.mu, span, 1.0, dt).map_err(in_file)?;
                (mu, dt, frames)
            }
            _ => (clip.mu, clip.frame_time, clip.frames),
        };
        Case::from_motion(
            &name,
            &name,
            mu,
            Arc::new(clip.skeleton),
            clip.units.metres_per_unit,
            (frame_time, frames),
        )
        .map_err(in_file)
    }

    /// A case from a motion sampled every `frame_time` s over `frames`
    /// frames from t = 0, played on `skeleton`'s body; `source` names the
    /// file it came from (a leave-one-out library leaves that file out).
    pub fn from_motion(
        name: &str,
        source: &str,
        mu: Mu,
        skeleton: Arc<Skeleton>,
        metres_per_unit: f64,
        (frame_time, frames): (f64, usize),
    ) -> Result<Case, ReportError> {
        let (body, _) = mocap::body_of(&skeleton, BODY_MASS, metres_per_unit)?;
        let root_dofs = root_dofs(&skeleton, &mu, (frame_time, frames));
        let floor = floor_of(&mu, &body, 1.0 / frame_time)?;
        Ok(Case {
            floor,
            name: name.to_string(),
            source: source.to_string(),
            capture: mu,
            body,
            frame_time,
            frames,
            root_dofs,
            metres_per_unit,
            skeleton,
        })
    }

    /// Every `.bvh` file in `dir`, sorted by name.
    pub fn load_dir(dir: &Path) -> Result<Vec<Case>, ReportError> {
        let folder = |source| ReportError::Folder {
            path: dir.to_path_buf(),
            source,
        };
        let mut paths: Vec<PathBuf> = std::fs::read_dir(dir)
            .map_err(folder)?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x.eq_ignore_ascii_case("bvh")))
            .collect();
        paths.sort();
        paths.iter().map(|p| Case::load(p)).collect()
    }

    /// `e` as an error of this clip (its name in front).
    pub fn error(&self, e: ReportError) -> ReportError {
        ReportError::in_clip(&self.name, e)
    }

    /// The time of frame `frame` (s).
    pub fn time(&self, frame: usize) -> f64 {
        frame as f64 * self.frame_time
    }

    /// The gap of `gap` frames from frame `first` as SP reports a gap: the
    /// last frame before it and the first after it (s).
    pub fn gap_span(&self, first: usize, gap: usize) -> (f64, f64) {
        (self.time(first - 1), self.time(first + gap))
    }

    /// Window starts for gap length `gap` under `p`.
    pub fn windows(&self, p: &Protocol, gap: usize) -> Vec<usize> {
        let need = 2 * p.context + gap;
        // a window needs a frame on each side of its gap, and a gap
        if p.context == 0 || gap == 0 || self.frames < need {
            return vec![];
        }
        let all: Vec<usize> = (0..=self.frames - need).step_by(p.stride.max(1)).collect();
        match p.windows_per_clip {
            Some(k) if k < all.len() => (0..k)
                .map(|i| all[(2 * i + 1) * all.len() / (2 * k)])
                .collect(),
            _ => all,
        }
    }

    /// The motion a method sees: frames `start .. start + context` and
    /// `start + context + gap ..` as two separate sampled curves per DOF (the
    /// root's DOFs whole when given).
    pub fn cut(
        &self,
        start: usize,
        context: usize,
        gap: usize,
        root: RootMode,
    ) -> Result<Mu, ReportError> {
        if context == 0 || gap == 0 || start + 2 * context + gap > self.frames {
            return Err(ReportError::NoWindow {
                clip: self.name.clone(),
                start,
                context,
                gap,
                frames: self.frames,
            });
        }
        let a = start;
        let b = start + context; // first gap frame
        let c = b + gap; // first frame after the gap
        let end = self.frames;
        let mut out = Mu::new();
        for (name, _) in &self.capture.dofs {
            let piece = |from: usize, to: usize| -> Result<Interval, ReportError> {
                let v = self.samples(name, from, to)?;
                let curve = Curve::samples(self.time(from), self.frame_time, v)?;
                Ok(Interval::curve(curve, self.time(from), self.time(to - 1))?)
            };
            let keep_whole = root == RootMode::Given && self.root_dofs.contains(name);
            let dof = if keep_whole {
                Dof::new(vec![piece(a, end)?])
            } else {
                Dof::new(vec![piece(a, b)?, piece(c, end)?])
            }?;
            out.insert(name.clone(), dof);
        }
        Ok(out)
    }

    /// The captured values of DOF `name` at frames `from .. to`.
    fn samples(&self, name: &str, from: usize, to: usize) -> Result<Vec<f64>, ReportError> {
        (from..to)
            .map(|k| {
                let t = self.time(k);
                self.capture
                    .sample(name, t)?
                    .map(|s| s[0])
                    .ok_or_else(|| ReportError::Undefined {
                        dof: name.to_string(),
                        t,
                    })
            })
            .collect()
    }
}

/// DOFs of the root: the skeleton's first joint's and, while a joint never
/// moves over the clip's `frames` (every `frame_time` s), its first child's.
fn root_dofs(skeleton: &Skeleton, mu: &Mu, (frame_time, frames): (f64, usize)) -> Vec<String> {
    let names = skeleton.channel_names();
    let starts = skeleton.channel_starts();
    let joint_dofs = |j: usize| -> Vec<String> {
        let n = skeleton.joints[j].channels.len();
        names[starts[j]..starts[j] + n].to_vec()
    };
    let constant = |dof: &str| {
        let v0 = mu.sample(dof, 0.0).ok().flatten().map(|s| s[0]);
        (0..frames).all(|k| {
            let t = k as f64 * frame_time;
            mu.sample(dof, t).ok().flatten().map(|s| s[0]) == v0
        })
    };
    let mut out = vec![];
    let mut j = 0;
    loop {
        let dofs = joint_dofs(j);
        let still = dofs.iter().all(|d| constant(d));
        out.extend(dofs);
        match skeleton.children(j).next() {
            Some(k) if still => j = k,
            _ => break,
        }
    }
    out
}
