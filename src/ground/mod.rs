//! Does a motion stand on the ground? Measures anyone can run on any motion
//! (captured, filled, simulated), on any body: where its contact points touch
//! the floor, how fast they slide while they do, how deep they sink, and how
//! much of the external wrench the motion needs no friction-cone contact
//! forces at those points can supply.
//!
//! It is also the one home of contact for SP: "up" and the floor plane
//! (`floor.rs`), the contact thresholds and the stance test (`stance.rs`),
//! the contact points and the floor of a motion's recorded part
//! (`points.rs`), and the floating root as a motion moves it (`root.rs`). SP's contact planning and support hold build
//! on these.
//!
//! `points.rs` picks the contact points (a body's ankle and toe joints, or
//! links the caller names), samples their world positions at the motion's
//! frame rate and places the floor (the lowest height they reach);
//! `contacts.rs` finds the intervals where each point touches the floor;
//! `skate.rs` measures foot skate and penetration; `forces.rs` runs inverse
//! dynamics of the floating base per frame (on `body.rs`: the floating root,
//! the centre of mass, the length scale) and gives the best contact forces
//! per point, which `cone.rs` solves as a small SOCP (by `clarabel`), and
//! what they leave; `series.rs` holds those numbers on the frame grid and as
//! the motion the language's `ground_forces` is (one DOF per number), both
//! ways, for files that carry them; `residual.rs` summarises that as the
//! ground residual.
//!
//! Layering: uses `lie`, `model`, `dynamics`, `motion`; used by `spacetime`
//! (SP's contact planning, support hold and root), `report` and `lang`.
//! Knows nothing of the language.

mod body;
pub mod cone;
pub mod contacts;
pub mod floor;
pub mod forces;
pub mod points;
pub mod residual;
pub mod root;
pub mod series;
pub mod skate;
pub mod stance;

pub use contacts::{
    ContactInterval, Contacts, PointContacts, contacts, contacts_of_tracks, runs_of,
};
pub use floor::{FloorPlane, horizontal, up_direction, up_of};
pub use forces::{GroundForces, ground_forces};
pub use points::{
    ContactPoint, Floor, GroundOptions, Tracks, contact_points, default_contact_points,
    recorded_floor, tracks,
};
pub use residual::{GroundResidual, ground_residual};
pub use root::{body_link, moving_root};
pub use series::ForceSeries;
pub use skate::{Penetration, Skate, foot_skate, penetration};
pub use stance::{
    CONTACT_HEIGHT, CONTACT_SPEED, GROUND_BAND, in_stance, plan_speed_limit, plan_stances,
};

/// Why a ground measure could not run: bad input, named.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GroundError {
    #[error("{0}")]
    Invalid(String),
    /// An option out of its range or naming what the body lacks: `option` is
    /// its name as the language spells it (`height`, `points`).
    #[error("{message}")]
    InvalidOption {
        option: &'static str,
        message: String,
    },
    #[error(transparent)]
    Motion(#[from] crate::motion::MotionError),
    #[error(transparent)]
    Model(#[from] crate::model::ModelError),
    #[error(transparent)]
    Dynamics(#[from] crate::dynamics::DynamicsError),
}

pub(crate) fn invalid(msg: impl Into<String>) -> GroundError {
    GroundError::Invalid(msg.into())
}

/// A [`GroundError::InvalidOption`] of `option`.
pub(crate) fn invalid_option(option: &'static str, message: impl Into<String>) -> GroundError {
    GroundError::InvalidOption {
        option,
        message: message.into(),
    }
}

impl GroundError {
    /// The option at fault, when the error is about one.
    pub fn option(&self) -> Option<&'static str> {
        match self {
            GroundError::InvalidOption { option, .. } => Some(option),
            _ => None,
        }
    }
}
