//! The host value types built-ins share: motions with their provenance
//! (`motion.rs`), bodies (`body.rs`), joints (`joint.rs`), scenes
//! (`scene.rs`), SP's report (`sp_report.rs`) and clip libraries (`library.rs`); the typed argument getters
//! for them on [`crate::lang::Args`] (`args.rs`); and the engine errors as
//! diagnostics (`errors.rs`). Built-in files import these, never each other.

pub mod args;
pub mod body;
pub mod errors;
pub mod joint;
pub mod library;
pub mod motion;
pub mod scene;
pub mod sp_report;

pub use body::Body;
pub use joint::{JointValue, SamplesValue};
pub use library::LibraryValue;
pub use motion::{ClipSource, Motion, Provenance, Sourced, as_mu, provenance};
pub use scene::SceneValue;
pub use sp_report::SpReportValue;
