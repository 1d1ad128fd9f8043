//! Why a fill could not be scored: the span, the motion or the body at
//! fault, named by the argument the language calls it (`m`, `reference`,
//! `t0`), so a diagnostic points there.

use crate::ground::GroundError;
use crate::model::ModelError;
use crate::motion::MotionError;
use crate::spacetime::SpError;

/// Which of the two motions an error is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Which {
    /// The motion being scored (`m`).
    Filled,
    /// What it is scored against (`reference`).
    Reference,
}

impl Which {
    /// The argument's name as the language spells it.
    pub fn argument(self) -> &'static str {
        match self {
            Which::Filled => "m",
            Which::Reference => "reference",
        }
    }
}

#[derive(Debug, thiserror::Error)]
pub enum ScoreError {
    /// A span that is not an interval of time.
    #[error("the span [{t0}, {t1}] s is not a gap: it needs finite times with t0 < t1")]
    BadSpan { t0: f64, t1: f64 },
    /// A span with no frame of the grid strictly inside it.
    #[error(
        "the span [{t0}, {t1}] s holds no frame at {rate} Hz: a gap is scored on the frames strictly between its two ends"
    )]
    NoFrames { t0: f64, t1: f64, rate: f64 },
    /// `m` says of no gap that SP filled it.
    #[error(
        "`m` names no gap SP filled ({why}); give the span: compare(m, reference, body, t0, t1)"
    )]
    NoFilledGaps { why: &'static str },
    /// A motion is undefined at a frame the score needs.
    #[error(
        "`{}`: DOF `{dof}` is undefined at t = {t:.4} s, inside the span scored; both motions need every coordinate of the body there",
        which.argument()
    )]
    Undefined { which: Which, dof: String, t: f64 },
    /// The reference is defined at no frame of its own: no floor to measure against.
    #[error(
        "`reference` has no frame where every coordinate of the body is defined: no floor to measure depth against"
    )]
    NoFloor,
    /// A motion could not be sampled or cut.
    #[error("`{}`: {source}", which.argument())]
    Motion {
        which: Which,
        #[source]
        source: MotionError,
    },
    /// A ground measure refused a motion (a body without feet, without gravity, …).
    #[error("`{}`: {source}", which.argument())]
    Ground {
        which: Which,
        #[source]
        source: GroundError,
    },
    /// Forward kinematics rejected a configuration.
    #[error("forward kinematics: {0}")]
    Kinematics(#[from] ModelError),
    /// The reference's own contacts could not be read as a plan.
    #[error("the reference's contacts: {0}")]
    Plan(#[source] SpError),
}

impl ScoreError {
    /// The argument at fault, as the language spells it.
    pub fn argument(&self) -> Option<&'static str> {
        match self {
            ScoreError::BadSpan { .. } | ScoreError::NoFrames { .. } => Some("t0"),
            ScoreError::NoFilledGaps { .. } => Some("m"),
            ScoreError::Undefined { which, .. } | ScoreError::Motion { which, .. } => {
                Some(which.argument())
            }
            ScoreError::Ground { which, source } => {
                Some(source.option().unwrap_or(which.argument()))
            }
            ScoreError::NoFloor | ScoreError::Plan(_) => Some("reference"),
            ScoreError::Kinematics(_) => Some("body"),
        }
    }

    pub(crate) fn motion(which: Which) -> impl Fn(MotionError) -> ScoreError {
        move |source| ScoreError::Motion { which, source }
    }

    pub(crate) fn ground(which: Which) -> impl Fn(GroundError) -> ScoreError {
        move |source| ScoreError::Ground { which, source }
    }
}
