//! Motion capture: BVH in and out, and (as the model and motion layers land)
//! bodies built from a clip's skeleton and joint positions over time.
//!
//! Layering: uses `lie`, `spline`, `model`, `dynamics`, `motion`; used by
//! `spacetime`, `io` and `lang`. Knows nothing of the language.

pub mod body_of;
pub mod bvh;
mod error;
pub mod human;
pub mod positions;
pub mod segments;
/// The project's own procedural clips (`examples/data/*.bvh`): fixtures of the
/// report and the tests.
#[cfg(feature = "report")]
pub mod synth;
pub mod to_motion;
pub mod up;

pub use body_of::{body_of, body_of_motion};
pub use error::MocapError;
pub use positions::{Missing, Poses, Positions, frame_times, poses_at, positions, positions_at};
pub use to_motion::{Clip, from_bvh, from_bvh_at, load};
