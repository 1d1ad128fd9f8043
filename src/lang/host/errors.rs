//! Engine errors as diagnostics, through one trait: each engine error type
//! says its kind, its advice and (when it knows) the argument at fault, and
//! [`diagnostic`] turns any of them into a diagnostic pointing at that
//! argument. Built-ins therefore pass engine errors through instead of
//! checking the engine's options a second time.

use crate::dynamics::DynamicsError;
use crate::graph::GraphError;
use crate::ground::GroundError;
use crate::ik::IkError;
use crate::io::FileError;
use crate::io::gltf::GltfError;
use crate::io::plot::PlotError;
use crate::io::viewer::ViewerError;
use crate::lang::args::Args;
use crate::lang::ast::Span;
use crate::lang::diagnostics::{ErrorKind, MxError};
use crate::library::LibraryError;
use crate::mocap::MocapError;
use crate::mocap::bvh::BvhError;
use crate::model::joints::JointSpecError;
use crate::model::link_tree::TreeError;
use crate::model::{InertiaError, ModelError};
use crate::motion::MotionError;
use crate::motion::cyclify::CyclifyError;
use crate::score::ScoreError;
use crate::shard::ShardError;
use crate::spacetime::{SpError, SpOptions};
use crate::spline::SplineError;

/// What the language needs from an engine error to report it.
pub trait EngineError: std::fmt::Display {
    /// The diagnostic's kind.
    fn kind(&self) -> ErrorKind;
    /// Advice for the help line; `None`: the call's usage.
    fn advice(&self) -> Option<&'static str> {
        None
    }
    /// The parameter at fault (`"w"`, `"rate"`), when the engine knows it.
    fn argument(&self) -> Option<&'static str> {
        None
    }
    /// The label at the call when no argument is at fault.
    fn label(&self) -> &'static str {
        "in this call"
    }
}

/// `e` as a diagnostic of the call `a`: at the argument the engine names
/// when the caller wrote it, else at `span`.
pub fn diagnostic(e: &dyn EngineError, a: &Args, span: Span) -> MxError {
    let at_argument = e.argument().and_then(|n| Some((n, a.span_of(n)?)));
    let err = MxError::new(e.kind(), e.to_string());
    let err = match at_argument {
        Some((name, s)) => err.at(s).label(format!("this `{name}`")),
        None => err.at(span).label(e.label()),
    };
    match e.advice() {
        Some(h) => err.help(h),
        None => err.help(format!("usage: {}", a.signature())),
    }
}

impl EngineError for MotionError {
    fn kind(&self) -> ErrorKind {
        match self {
            MotionError::Cancelled => ErrorKind::Cancelled,
            _ => ErrorKind::Motion,
        }
    }
    fn advice(&self) -> Option<&'static str> {
        Some(match self {
            MotionError::ClipOutside { .. } => "clip a window inside the span; `span(m)` gives it",
            MotionError::Conflict { .. } => {
                "a DOF defined twice there must be resolved first, e.g. `a + (b - a)` or `clip`"
            }
            MotionError::Undefined { .. } => {
                "sample only where the motion is defined; `gaps(m)` lists the holes"
            }
            MotionError::UnknownDof { .. } | MotionError::NoMatch { .. } => {
                "`dofs(m)` lists the DOF names"
            }
            MotionError::Cancelled => "cancelled by the user",
            _ => "see `:help` for the motion functions",
        })
    }
    fn argument(&self) -> Option<&'static str> {
        self.option()
    }
}

impl EngineError for DynamicsError {
    fn kind(&self) -> ErrorKind {
        match self {
            DynamicsError::Cancelled => ErrorKind::Cancelled,
            DynamicsError::Input(_) | DynamicsError::Model(_) => ErrorKind::Value,
            DynamicsError::Singular(_) => ErrorKind::Host,
        }
    }
}

impl EngineError for SpError {
    fn kind(&self) -> ErrorKind {
        match self {
            SpError::Cancelled => ErrorKind::Cancelled,
            SpError::Conflict { .. } => ErrorKind::Motion,
            SpError::Invalid(_)
            | SpError::InvalidOption { .. }
            | SpError::ContactReplacesSupport => ErrorKind::Value,
            // what the motion or the body could not give: the host's, as before they were typed
            SpError::Undefined { .. }
            | SpError::Incomplete(_)
            | SpError::Motion(_)
            | SpError::Dynamics(_)
            | SpError::Kinematics(_)
            | SpError::Curve(_)
            | SpError::Library(_)
            | SpError::Cyclify(_)
            | SpError::Numerical(_)
            | SpError::Data(_) => ErrorKind::Host,
        }
    }
    fn advice(&self) -> Option<&'static str> {
        match self {
            SpError::Cancelled => Some("cancelled by the user (Ctrl-C)"),
            SpError::Conflict { .. } => {
                Some("`conflicts(m)` lists where the motion is multiply defined")
            }
            SpError::InvalidOption { option, .. } => SpOptions::help(option),
            SpError::ContactReplacesSupport => Some("give one of the two"),
            _ => None,
        }
    }
    fn argument(&self) -> Option<&'static str> {
        self.option()
    }
    fn label(&self) -> &'static str {
        match self {
            SpError::Cancelled
            | SpError::Invalid(_)
            | SpError::InvalidOption { .. }
            | SpError::ContactReplacesSupport => "in this call",
            _ => "this motion",
        }
    }
}

impl EngineError for GraphError {
    fn kind(&self) -> ErrorKind {
        match self {
            GraphError::InvalidOption { .. } | GraphError::Shard(ShardError::Bad { .. }) => {
                ErrorKind::Value
            }
            _ => ErrorKind::Host,
        }
    }
    fn argument(&self) -> Option<&'static str> {
        self.option()
    }
}

impl EngineError for GroundError {
    fn kind(&self) -> ErrorKind {
        match self {
            GroundError::Motion(m) => m.kind(),
            GroundError::Dynamics(d) => d.kind(),
            _ => ErrorKind::Value,
        }
    }
    fn advice(&self) -> Option<&'static str> {
        match self {
            GroundError::Motion(m) => m.advice(),
            _ => None,
        }
    }
    fn argument(&self) -> Option<&'static str> {
        match self {
            GroundError::Motion(m) => m.option(),
            e => e.option(),
        }
    }
}

impl EngineError for IkError {
    fn kind(&self) -> ErrorKind {
        match self {
            IkError::Motion(m) => m.kind(),
            _ => ErrorKind::Value,
        }
    }
    fn advice(&self) -> Option<&'static str> {
        match self {
            IkError::Motion(m) => m.advice(),
            _ => None,
        }
    }
    fn argument(&self) -> Option<&'static str> {
        match self {
            IkError::Motion(m) => m.option(),
            e => e.argument(),
        }
    }
    fn label(&self) -> &'static str {
        "here"
    }
}

impl EngineError for LibraryError {
    fn kind(&self) -> ErrorKind {
        match self {
            LibraryError::File { .. } => ErrorKind::Io,
            _ => ErrorKind::Value,
        }
    }
    fn argument(&self) -> Option<&'static str> {
        self.option()
    }
}

/// The help under a file that cannot be read.
pub const MISSING_FILE_HELP: &str = "check the file name: a script's relative paths are taken from the script's own folder, the REPL's from the current folder";

impl EngineError for BvhError {
    fn kind(&self) -> ErrorKind {
        match self {
            BvhError::Unit(_) => ErrorKind::Value,
            _ => ErrorKind::Io,
        }
    }
    // the help says what to do about this error, not about BVH files
    fn advice(&self) -> Option<&'static str> {
        Some(match self {
            BvhError::Io { .. } => MISSING_FILE_HELP,
            BvhError::Parse { .. } => {
                "the BVH file is malformed at the line named; fix or re-export it"
            }
            BvhError::Invalid(_) => {
                "the BVH file's skeleton or motion is inconsistent as said; fix or re-export it"
            }
            BvhError::Unit(_) => return None,
        })
    }
    fn argument(&self) -> Option<&'static str> {
        match self {
            BvhError::Unit(_) => Some("unit"),
            _ => None,
        }
    }
}

impl EngineError for MocapError {
    fn kind(&self) -> ErrorKind {
        match self {
            MocapError::Motion(m) => m.kind(),
            MocapError::Bvh(b) => b.kind(),
            _ => ErrorKind::Value,
        }
    }
    fn advice(&self) -> Option<&'static str> {
        match self {
            MocapError::Motion(m) => m.advice(),
            MocapError::Bvh(b) => b.advice(),
            _ => None,
        }
    }
    fn argument(&self) -> Option<&'static str> {
        self.option()
    }
}

impl EngineError for FileError {
    fn kind(&self) -> ErrorKind {
        match self {
            FileError::Motion(m) => m.kind(),
            _ => ErrorKind::Io,
        }
    }
    fn advice(&self) -> Option<&'static str> {
        match self {
            FileError::Motion(m) => m.advice(),
            _ => Some("check the path, the folder's permissions and the file's content"),
        }
    }
    fn argument(&self) -> Option<&'static str> {
        match self {
            FileError::Motion(m) => m.option(),
            _ => None,
        }
    }
}

impl EngineError for GltfError {
    fn kind(&self) -> ErrorKind {
        match self {
            GltfError::File(f) => f.kind(),
            GltfError::Mocap(m) => m.kind(),
            GltfError::Invalid(_) | GltfError::Forces { .. } => ErrorKind::Io,
        }
    }
    fn advice(&self) -> Option<&'static str> {
        match self {
            GltfError::File(f) => f.advice(),
            GltfError::Mocap(m) => m.advice(),
            GltfError::Invalid(_) => {
                Some("mx reads glTF files holding a skin (skeleton) and an animation of its joints")
            }
            GltfError::Forces { .. } => Some(
                "the contact forces are those `save(m, \"x.glb\", body: b, forces: true)` writes; load the file without `forces:` for its motion",
            ),
        }
    }
    fn argument(&self) -> Option<&'static str> {
        match self {
            GltfError::File(f) => f.argument(),
            GltfError::Mocap(m) => m.argument(),
            GltfError::Invalid(_) => None,
            GltfError::Forces { .. } => Some("forces"),
        }
    }
}

impl EngineError for ModelError {
    fn kind(&self) -> ErrorKind {
        match self {
            ModelError::Invalid(_) | ModelError::Tree(_) => ErrorKind::Value,
            _ => ErrorKind::Io,
        }
    }
    // a URDF's: what to do about the file (the reader's messages say what is wrong in it)
    fn advice(&self) -> Option<&'static str> {
        Some(match self {
            ModelError::Invalid(_) | ModelError::Tree(_) => return None,
            ModelError::UrdfUnreadable(_) => MISSING_FILE_HELP,
            ModelError::UrdfMalformed(_) => {
                "the file is not well-formed XML with a <robot> root; open it in an XML viewer or export it again"
            }
            ModelError::UrdfTree {
                error: TreeError::UnknownLink { .. },
                ..
            } => "define that link or correct the joint's <parent>/<child> link name",
            ModelError::Urdf(_) | ModelError::UrdfTree { .. } => "fix the file as the message says",
        })
    }
}

impl EngineError for InertiaError {
    fn kind(&self) -> ErrorKind {
        ErrorKind::Value
    }
    fn argument(&self) -> Option<&'static str> {
        Some(self.quantity())
    }
}

impl EngineError for JointSpecError {
    fn kind(&self) -> ErrorKind {
        ErrorKind::Value
    }
}

impl EngineError for CyclifyError {
    fn kind(&self) -> ErrorKind {
        ErrorKind::Value
    }
}

impl EngineError for SplineError {
    fn kind(&self) -> ErrorKind {
        ErrorKind::Value
    }
}

impl EngineError for PlotError {
    fn kind(&self) -> ErrorKind {
        ErrorKind::Io
    }
}

impl EngineError for ViewerError {
    fn kind(&self) -> ErrorKind {
        match self {
            ViewerError::Io { .. } => ErrorKind::Io,
            ViewerError::Invalid(_) => ErrorKind::Value,
        }
    }
}

/// `e` as a diagnostic at `span`, for callers without the call's arguments
/// at hand: the engine's kind and advice, no argument to point at.
pub fn error_at(e: &dyn EngineError, span: Span) -> MxError {
    engine_error(e).at(span).label(e.label())
}

/// `e` as a diagnostic with its kind and advice, placed by the caller (a
/// loader's error is placed at the call by the evaluator).
pub fn engine_error(e: &dyn EngineError) -> MxError {
    let err = MxError::new(e.kind(), e.to_string());
    match e.advice() {
        Some(h) => err.help(h),
        None => err,
    }
}

/// A motion error as a diagnostic at `span`, with advice by kind (for
/// callers without the call's arguments at hand).
pub fn motion_error(e: MotionError, span: Span) -> MxError {
    let help = e.advice().unwrap_or_default();
    MxError::new(e.kind(), e.to_string())
        .at(span)
        .label("in this call")
        .help(help)
}

/// A file error at `span` (a motion error inside it keeps its advice).
pub fn file_error(e: crate::io::FileError, span: Span) -> MxError {
    match e {
        crate::io::FileError::Motion(m) => motion_error(m, span),
        other => MxError::new(ErrorKind::Io, other.to_string())
            .at(span)
            .help("check the path, the folder's permissions and the file's content"),
    }
}

/// A dynamics error on the call `a`.
pub fn dyn_error(e: DynamicsError, a: &Args) -> MxError {
    MxError::new(e.kind(), e.to_string())
        .at(a.call_span())
        .help(format!("usage: {}", a.signature()))
}

impl EngineError for ScoreError {
    fn kind(&self) -> ErrorKind {
        match self {
            ScoreError::Motion { source, .. } => source.kind(),
            ScoreError::Ground { source, .. } => source.kind(),
            ScoreError::Plan(e) => e.kind(),
            ScoreError::Undefined { .. } => ErrorKind::Motion,
            _ => ErrorKind::Value,
        }
    }
    fn advice(&self) -> Option<&'static str> {
        match self {
            ScoreError::NoFilledGaps { .. } => Some(
                "compare(m, reference, body, t0, t1) scores the gap [t0, t1]; `sp_report(m).groups` lists the gaps SP filled",
            ),
            ScoreError::BadSpan { .. } | ScoreError::NoFrames { .. } => Some(
                "t0 is the last frame before the gap and t1 the first after it, as `sp_report(m).groups` gives them",
            ),
            ScoreError::Undefined { .. } => Some(
                "both motions need every coordinate of the body over the gap; `gaps(m)` lists the holes",
            ),
            ScoreError::Motion { source, .. } => source.advice(),
            _ => None,
        }
    }
    fn argument(&self) -> Option<&'static str> {
        ScoreError::argument(self)
    }
}
