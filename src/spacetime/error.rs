//! Errors of the spacetime layer: each says what was wrong and what to do.

use crate::cancel::Cancelled;
use crate::dynamics::DynamicsError;
use crate::ground::GroundError;
use crate::library::LibraryError;
use crate::model::ModelError;
use crate::motion::MotionError;
use crate::motion::cyclify::CyclifyError;
use crate::spline::SplineError;

#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SpError {
    /// Bad parameters or data given by the user.
    #[error("{0}")]
    Invalid(String),
    /// An option of `SP(…)` out of its range, or naming what the body lacks:
    /// `option` is its name as the language spells it (`coefficients`,
    /// `support`), so a diagnostic can point at the argument.
    #[error("{message}")]
    InvalidOption {
        option: &'static str,
        message: String,
    },
    /// `contact:` and a `support:` other than the default given together:
    /// contact planning holds the feet itself, in place of the support limbs.
    #[error("`contact:` plans the feet itself and replaces `support:`")]
    ContactReplacesSupport,
    /// The motion is multiply defined where a transition needs one value:
    /// DOF `dof` on [t0, t1].
    #[error(
        "DOF '{dof}' is multiply defined on [{t0}, {t1}] (a conflict): SP fills gaps, it cannot choose between motions; \
         remove one of them there (e.g. a − b) before SP"
    )]
    Conflict { dof: String, t0: f64, t1: f64 },
    /// DOF `dof` is undefined at t where `need` requires a value.
    #[error("{}", need.message(dof, *t))]
    Undefined { dof: String, t: f64, need: Need },
    /// The body is not fully defined where a step needs every coordinate and
    /// no single DOF is at fault (the message says where).
    #[error("{0}")]
    Incomplete(String),
    /// The motion could not be sampled.
    #[error(transparent)]
    Motion(#[from] MotionError),
    /// The dynamics (torques, mass matrix) failed.
    #[error("dynamics: {0}")]
    Dynamics(#[from] DynamicsError),
    /// Forward kinematics rejected a configuration.
    #[error("forward kinematics: {0}")]
    Kinematics(ModelError),
    /// A transition curve could not be built from its coefficients.
    #[error("transition curve: {0}")]
    Curve(#[from] SplineError),
    /// A reference clip of the library could not be loaded.
    #[error(transparent)]
    Library(#[from] LibraryError),
    /// Cyclification could not sample or fit the motion.
    #[error(transparent)]
    Cyclify(CyclifyError),
    /// The solver or the objective met a non-finite value or failed, with no
    /// lower-layer error to carry.
    #[error("{0}")]
    Numerical(String),
    /// The project's example data could not be built (its error type is not
    /// comparable, so its text is kept).
    #[error("{0}")]
    Data(String),
    #[error("spacetime solve cancelled")]
    Cancelled,
}

/// What needed a value of a DOF where it is undefined (the wording of
/// [`SpError::Undefined`]).
#[derive(Clone, Debug, PartialEq)]
pub enum Need {
    /// The end of a gap, whose state a transition starts from.
    GapEnd,
    /// `torque_energy`, which integrates the whole body.
    TorqueEnergy,
    /// The transition of the listed gaps (`coordinate on [t0, t1], …`).
    Transition(String),
}

impl Need {
    fn message(&self, dof: &str, t: f64) -> String {
        match self {
            Need::GapEnd => format!("DOF '{dof}' is undefined at the gap end t = {t}"),
            Need::TorqueEnergy => format!(
                "torque_energy: DOF '{dof}' is undefined at t = {t}; fill the gap first (SP or fill(m, \"hermite\"))"
            ),
            Need::Transition(gaps) => format!(
                "{dof} is undefined at t = {t} but the transition of {gaps} needs the whole body there; \
                 define it (e.g. extend its motion, or fill its own gap first)"
            ),
        }
    }
}

impl From<Cancelled> for SpError {
    fn from(_: Cancelled) -> Self {
        SpError::Cancelled
    }
}

/// Cyclification lives with the motion operations; the language reports its
/// errors as it reports SP's.
impl From<CyclifyError> for SpError {
    fn from(e: CyclifyError) -> Self {
        match e {
            CyclifyError::Invalid(m) => SpError::Invalid(m),
            e @ CyclifyError::Evaluation(_) => SpError::Cyclify(e),
        }
    }
}

/// The ground measures SP builds on (floor, contact points) fail as the
/// layers below them do, or on bad input; SP reports them as its own.
impl From<GroundError> for SpError {
    fn from(e: GroundError) -> Self {
        match e {
            GroundError::Invalid(m) => SpError::Invalid(m),
            // gravity is SP's option too; ground's others are not SP's
            GroundError::InvalidOption {
                option: "gravity",
                message,
            } => SpError::InvalidOption {
                option: "gravity",
                message,
            },
            GroundError::InvalidOption { message, .. } => SpError::Invalid(message),
            GroundError::Motion(e) => SpError::Motion(e),
            GroundError::Model(e) => SpError::Kinematics(e),
            GroundError::Dynamics(e) => SpError::Dynamics(e),
        }
    }
}

impl SpError {
    /// The option at fault, when the error is about one.
    pub fn option(&self) -> Option<&'static str> {
        match self {
            SpError::InvalidOption { option, .. } => Some(option),
            SpError::ContactReplacesSupport => Some("contact"),
            _ => None,
        }
    }
}

pub(crate) fn invalid(msg: impl Into<String>) -> SpError {
    SpError::Invalid(msg.into())
}

/// An [`SpError::InvalidOption`] of `option`.
pub(crate) fn invalid_option(option: &'static str, message: impl Into<String>) -> SpError {
    SpError::InvalidOption {
        option,
        message: message.into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spacetime::planar2::TwoLinkArm;
    use crate::spacetime::{Continuity, TorqueModel, TransitionCurve};

    #[test]
    fn lower_layer_errors_are_kept_whole() {
        // too few coefficients for the curve's basis: the spline's own error
        let c = TransitionCurve::new(0.0, 1.0, 5, Continuity::C1).unwrap();
        let e = c.to_curve(vec![0.0; 2]).unwrap_err();
        assert!(matches!(e, SpError::Curve(_)), "{e:?}");
        assert!(e.to_string().starts_with("transition curve: "), "{e}");
        // wrong state lengths: the dynamics' input error
        let arm = TwoLinkArm::default();
        let mut tau = vec![0.0; 2];
        let e = arm
            .torques(
                &mut arm.workspace(),
                &[0.0],
                &[0.0; 2],
                &[0.0; 2],
                &[],
                &mut tau,
            )
            .unwrap_err();
        assert!(
            matches!(e, SpError::Dynamics(DynamicsError::Input(_))),
            "{e:?}"
        );
        // cyclify's evaluation failure is carried, its bad input is SP's Invalid
        let e = SpError::from(CyclifyError::Evaluation("x".into()));
        assert_eq!(e, SpError::Cyclify(CyclifyError::Evaluation("x".into())));
        let e = SpError::from(CyclifyError::Invalid("y".into()));
        assert_eq!(e, SpError::Invalid("y".into()));
    }

    #[test]
    fn conflict_and_undefined_keep_their_wording() {
        let e = SpError::Conflict {
            dof: "hip".into(),
            t0: 0.5,
            t1: 0.8,
        };
        assert!(
            e.to_string()
                .starts_with("DOF 'hip' is multiply defined on [0.5, 0.8] (a conflict)"),
            "{e}"
        );
        let e = SpError::Undefined {
            dof: "knee".into(),
            t: 1.5,
            need: Need::GapEnd,
        };
        assert_eq!(
            e.to_string(),
            "DOF 'knee' is undefined at the gap end t = 1.5"
        );
    }
}
