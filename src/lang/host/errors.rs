//! Engine errors as diagnostics, through one trait: each engine error type
//! says its kind, its advice and (when it knows) the argument at fault, and
//! [`diagnostic`] turns any of them into a diagnostic pointing at that
//! argument. Built-ins therefore pass engine errors through instead of
//! checking the engine's options a second time.

use crate::dynamics::DynamicsError;
use crate::graph::GraphError;
use crate::lang::args::Args;
use crate::lang::ast::Span;
use crate::lang::diagnostics::{ErrorKind, MxError};
use crate::motion::MotionError;
use crate::shard::ShardError;
use crate::spacetime::SpError;

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
            SpError::Invalid(_) | SpError::InvalidOption { .. } => ErrorKind::Value,
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
            SpError::InvalidOption { option, .. } => sp_option_help(option),
            _ => None,
        }
    }
    fn argument(&self) -> Option<&'static str> {
        self.option()
    }
    fn label(&self) -> &'static str {
        match self {
            SpError::Cancelled | SpError::Invalid(_) | SpError::InvalidOption { .. } => {
                "in this call"
            }
            _ => "this motion",
        }
    }
}

/// What each of SP's options means, for the help line under its error (the
/// engine checks the value; this only explains it).
fn sp_option_help(option: &str) -> Option<&'static str> {
    Some(match option {
        "coefficients" => {
            "free B-spline coefficients per DOF and gap: at least 2 with continuity: 1, 3 with continuity: 2 \
             (default 5, as in Rose's Fig. 8; Rose uses 5–10)"
        }
        "samples" => {
            "Gauss points of the torque integral per gap, at least 6 per B-spline piece (default 20)"
        }
        "iterations" => "solver iterations per gap group (default 300)",
        "tolerance" => {
            "the solver stops when 25 iterations lower the energy by less than this fraction (default 1e-3)"
        }
        "smoothness" => {
            "weight λ of the kinematic prior against ∫Στ² (default 1e6; 0 is objective: \"torque\")"
        }
        "time_constant" => {
            "the prior damps the end velocities over about this time (e.g. 0.1s; \"auto\", the default: \
             (0.32 s)²/gap length)"
        }
        "floor" => "\"auto\" (default): the lowest contact point of the motion's recorded part",
        "support" | "contact" => {
            "name frames (links) of the body, e.g. a clip's joints: [\"LeftFoot\", \"RightFoot\"]"
        }
        "gravity" => "a finite vector in m/s², e.g. [0, -9.81, 0]",
        _ => return None,
    })
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
