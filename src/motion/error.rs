//! Errors of the motion algebra. Every message says what went wrong and, where
//! it helps, what to do; the language layer adds source spans around them.

use thiserror::Error;

/// What can go wrong building, combining or sampling motions.
#[derive(Clone, Debug, PartialEq, Error)]
pub enum MotionError {
    /// A time, scale or value that must be a finite number was NaN or infinite.
    #[error("{what} must be a finite number, got {value}")]
    NonFinite { what: &'static str, value: f64 },

    /// An interval whose stop is not after its start.
    #[error(
        "interval [{start}, {stop}] is empty: an interval needs start < stop (swap the times or widen the interval)"
    )]
    EmptyInterval { start: f64, stop: f64 },

    /// An interval built with no function.
    #[error("an interval needs at least one function of time")]
    NoFunction,

    /// `affine` with a time scale that is not positive.
    #[error("affine time scale must be positive (time t ↦ ts + d·t), got d = {d}")]
    BadScale { d: f64 },

    /// `affine` that would push an interval's times beyond floating point or
    /// shrink it below the time resolution ([`crate::motion::time_tol`]).
    #[error(
        "affine(ts = {ts}, d = {d}) maps interval [{start}, {stop}] to [{new_start}, {new_stop}], which is not a usable time span; use a time scale d nearer 1"
    )]
    AffineDegenerate {
        ts: f64,
        d: f64,
        start: f64,
        stop: f64,
        new_start: f64,
        new_stop: f64,
    },

    /// A sampling time that is not a finite number.
    #[error("sample time must be a finite number, got {t}")]
    BadTime { t: f64 },

    /// `clip` / `clip_in_place` with a window that is not inside the motion's span.
    /// `name` is the motion's name when the caller knows it (e.g. the variable).
    #[error(
        "clip [{ts:?}, {tf:?}] lies outside {}span [{}, {}]",
        name.as_ref().map(|n| format!("{n}'s ")).unwrap_or_else(|| "the motion's ".into()),
        span.0, span.1
    )]
    ClipOutside {
        ts: f64,
        tf: f64,
        span: (f64, f64),
        name: Option<String>,
    },

    /// `clip` with an empty or reversed window.
    #[error("clip [{ts}, {tf}] is empty: the clip needs ts < tf")]
    ClipEmpty { ts: f64, tf: f64 },

    /// An operation that needs a time span was given a motion with no defined interval.
    #[error("{op} needs a motion that is defined somewhere, but this motion is empty")]
    EmptyMotion { op: &'static str },

    /// Sampling a region where a DOF is multiply defined.
    #[error(
        "DOF '{dof}' is multiply defined (a conflict) over [{start}, {stop}] (sampled at t = {t}); undefine one of the motions there (e.g. a + (b − a)) before sampling"
    )]
    Conflict {
        dof: String,
        start: f64,
        stop: f64,
        t: f64,
    },

    /// Sampling a region where a DOF is not defined, where a value was required.
    #[error("DOF '{dof}' is not defined at t = {t}")]
    Undefined { dof: String, t: f64 },

    /// A DOF name the motion does not have.
    #[error("the motion has no DOF named '{name}'{}", suggestion_text(suggestion))]
    UnknownDof {
        name: String,
        suggestion: Option<String>,
    },

    /// An `only` pattern that matched no DOF.
    #[error("pattern '{pattern}' matches no DOF of the motion (it has: {available})")]
    NoMatch { pattern: String, available: String },

    /// A function of time failed or returned a non-finite value. `dof` names
    /// the DOF being sampled when the failure happened while sampling one.
    #[error(
        "function of time failed {}at t = {t}: {message}",
        dof.as_ref().map(|d| format!("for DOF '{d}' ")).unwrap_or_default()
    )]
    Function {
        t: f64,
        message: String,
        dof: Option<String>,
    },

    /// Sampled data evaluated outside the times it covers.
    #[error(
        "sampled curve covers [{start}, {stop}] but was evaluated at t = {t}; keep the interval inside the data's time range"
    )]
    OutsideSamples { t: f64, start: f64, stop: f64 },

    /// Bad sampled data (no samples, bad step, non-finite values).
    #[error("bad sampled curve: {0}")]
    BadSamples(String),

    /// Sampling rate that is not a positive finite number.
    #[error("sampling rate must be a positive number of samples per second, got {rate}")]
    BadRate { rate: f64 },

    /// Too many samples requested (protects against `rate: 1e12`).
    #[error("sampling {span} s at {rate} Hz would need {rows} rows; lower the rate")]
    TooManySamples { span: f64, rate: f64, rows: f64 },

    /// An animator's operator (`blend`, `mirror`, `warp`, …) given motions it
    /// cannot combine; the message says what and where.
    #[error("{op}: {message}")]
    Compose { op: &'static str, message: String },

    /// An operator's argument out of its range (a weight outside [0, 1], a
    /// warp that is not increasing); `option` is the argument's name as the
    /// language spells it, so a diagnostic can point at it.
    #[error("{op}: {message}")]
    InvalidOption {
        op: &'static str,
        option: &'static str,
        message: String,
    },

    /// A computation was cancelled through its [`crate::cancel::CancelToken`].
    #[error("cancelled")]
    Cancelled,
}

/// Why a function of time ([`crate::motion::TimeFunction`]) gave no value.
#[derive(Clone, Debug, PartialEq, Error)]
pub enum FnError {
    /// The host's message (an mx runtime error, a value that is no number).
    #[error("{0}")]
    Host(String),
    /// A motion the function evaluates (a reversed, warped or sampled curve) failed.
    #[error(transparent)]
    Motion(Box<MotionError>),
}

impl From<String> for FnError {
    fn from(message: String) -> Self {
        FnError::Host(message)
    }
}

impl From<&str> for FnError {
    fn from(message: &str) -> Self {
        FnError::Host(message.to_string())
    }
}

impl From<MotionError> for FnError {
    fn from(e: MotionError) -> Self {
        FnError::Motion(Box::new(e))
    }
}

fn suggestion_text(s: &Option<String>) -> String {
    match s {
        Some(s) => format!("; did you mean '{s}'?"),
        None => String::new(),
    }
}

impl MotionError {
    /// The argument this error is about, when one argument is at fault.
    pub fn option(&self) -> Option<&'static str> {
        match self {
            MotionError::InvalidOption { option, .. } => Some(option),
            MotionError::BadRate { .. } | MotionError::TooManySamples { .. } => Some("rate"),
            _ => None,
        }
    }

    /// Attach the motion's name (as the user knows it) to a clip error.
    pub fn with_name(self, motion_name: &str) -> Self {
        match self {
            MotionError::ClipOutside { ts, tf, span, .. } => MotionError::ClipOutside {
                ts,
                tf,
                span,
                name: Some(motion_name.to_string()),
            },
            other => other,
        }
    }
}

impl From<crate::cancel::Cancelled> for MotionError {
    fn from(_: crate::cancel::Cancelled) -> Self {
        MotionError::Cancelled
    }
}

/// `Err(NonFinite)` unless `value` is finite.
pub(crate) fn finite(what: &'static str, value: f64) -> Result<f64, MotionError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(MotionError::NonFinite { what, value })
    }
}
