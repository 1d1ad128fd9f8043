//! Why a section of `mx report` could not be computed: a lower layer's
//! error kept whole, or one of the report's own kinds, each with the fields
//! that say what went wrong and where (the file, the clip, the DOF, the
//! figure), so a caller can tell a missing file from a bad fit without
//! reading the message.

use crate::dynamics::DynamicsError;
use crate::ground::GroundError;
use crate::ik::IkError;
use crate::io::plot::PlotError;
use crate::io::{ContentError, FileError};
use crate::library::LibraryError;
use crate::mocap::MocapError;
use crate::mocap::bvh::BvhError;
use crate::model::joints::JointSpecError;
use crate::model::{InertiaError, ModelError};
use crate::motion::MotionError;
use crate::motion::cyclify::CyclifyError;
use crate::score::ScoreError;
use crate::spacetime::SpError;
use crate::spline::SplineError;
use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    #[error(transparent)]
    Sp(#[from] SpError),
    #[error(transparent)]
    Dynamics(#[from] DynamicsError),
    #[error(transparent)]
    Model(#[from] ModelError),
    #[error(transparent)]
    Inertia(#[from] InertiaError),
    #[error(transparent)]
    Joint(#[from] JointSpecError),
    #[error(transparent)]
    Motion(#[from] MotionError),
    #[error(transparent)]
    Cyclify(#[from] CyclifyError),
    #[error(transparent)]
    Mocap(#[from] MocapError),
    #[error(transparent)]
    Bvh(#[from] BvhError),
    #[error(transparent)]
    Ik(#[from] IkError),
    #[error(transparent)]
    File(#[from] FileError),
    #[error(transparent)]
    Content(#[from] ContentError),
    #[error(transparent)]
    Ground(#[from] GroundError),
    #[error(transparent)]
    Spline(#[from] SplineError),
    #[error(transparent)]
    Plot(#[from] PlotError),
    #[error(transparent)]
    Score(#[from] ScoreError),
    #[error(transparent)]
    Library(#[from] LibraryError),
    /// A clip file that could not be read.
    #[error("clip {}: {source}", path.display())]
    Clip {
        path: PathBuf,
        #[source]
        source: MocapError,
    },
    /// A reference file that could not be read.
    #[error("cannot read {}: {source}", path.display())]
    Read {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A reference file that is not JSON.
    #[error("{}: {source}", path.display())]
    Json {
        path: PathBuf,
        #[source]
        source: serde_json::Error,
    },
    /// A reference file without a field the report reads, or with one of
    /// the wrong shape.
    #[error("{file}: missing or malformed {field}")]
    Field { file: &'static str, field: String },
    /// A folder that could not be listed.
    #[error("cannot list the folder {}: {source}", path.display())]
    Folder {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A folder with no clip in it.
    #[error("no .bvh clips in {}", path.display())]
    NoClips { path: PathBuf },
    /// The report's output (folder or page) could not be written.
    #[error("cannot write {}: {source}", path.display())]
    Write {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// An error while reading one file, with its path in front.
    #[error("{}: {source}", path.display())]
    InFile {
        path: PathBuf,
        #[source]
        source: Box<ReportError>,
    },
    /// An error of one clip of a benchmark, with its name in front.
    #[error("{clip}: {source}")]
    InClip {
        clip: String,
        #[source]
        source: Box<ReportError>,
    },
    /// A spline-joint fit of `frames` control frames that failed.
    #[error("fit with {frames} frames: {source}")]
    Fit {
        frames: usize,
        #[source]
        source: JointSpecError,
    },
    /// A smoothed spline-joint fit that failed at this weight.
    #[error("smoothing weight {weight}: {source}")]
    Smoothing {
        weight: f64,
        #[source]
        source: JointSpecError,
    },
    /// A window that does not fit in its clip.
    #[error(
        "{clip}: no window of {context} context frames and a {gap}-frame gap at frame {start} in {frames} frames"
    )]
    NoWindow {
        clip: String,
        start: usize,
        context: usize,
        gap: usize,
        frames: usize,
    },
    /// A DOF undefined where the report samples it.
    #[error("DOF `{dof}` is undefined at t = {t:.4} s")]
    Undefined { dof: String, t: f64 },
    /// A motion or series with nothing in it where a section needs frames.
    #[error("{what} is empty: no frames to measure")]
    Empty { what: &'static str },
    /// A link a section names that the body does not have.
    #[error("the body has no link `{link}`")]
    NoLink { link: String },
    /// A clip whose joints have no left/right twins to mirror.
    #[error("{clip}: no joint has a left/right twin to mirror")]
    NoMirror { clip: String },
    /// A clip glob that does not parse (`MX_INBETWEEN_CLIPS`).
    #[error("clip glob `{glob}`: {source}")]
    Glob {
        glob: String,
        #[source]
        source: glob::PatternError,
    },
    /// A new frame grid out of range: speed and step must be positive, the span ≥ 0.
    #[error(
        "regrid needs a positive speed and step and a span ≥ 0, found speed {speed}, step {step}, span {span}"
    )]
    Grid { speed: f64, step: f64, span: f64 },
    /// A figure with no finite point to draw.
    #[error("{file}: no finite points to plot")]
    EmptyFigure { file: String },
    /// A figure the plotting library could not draw (its message).
    #[error("{file}: {message}")]
    Draw { file: String, message: String },
    /// A model a section builds that cannot be built as asked.
    #[error("{model}: {why}")]
    BadModel {
        model: &'static str,
        why: &'static str,
    },
    /// An algorithm name the performance driver does not time.
    #[error("unknown algorithm `{name}`; one of {known}")]
    UnknownAlgorithm { name: String, known: String },
}

/// A revolute joint of a section's own model given a zero axis (a typo in
/// the section, never the user's input).
pub(crate) const ZERO_AXIS: ReportError = ReportError::BadModel {
    model: "revolute joint",
    why: "zero axis",
};

impl ReportError {
    /// `e` with `clip`'s name in front.
    pub fn in_clip(clip: &str, e: ReportError) -> ReportError {
        ReportError::InClip {
            clip: clip.to_string(),
            source: Box::new(e),
        }
    }
}
