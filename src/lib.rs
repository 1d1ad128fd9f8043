//! mx: a motion expression language, its interpreter, and a multibody dynamics
//! engine with spline joints.
//!
//! Layers, each using only the ones listed before it (see ARCHITECTURE.md):
//! `lie` → `spline` → `model` → `dynamics` → `motion` → `mocap` → `ik` → `ground` → `library` → `spacetime` → `score` → `io` → `graph` → `report` → `lang`.
//! Everything up to `io` is a library that knows nothing of the language.
//! The report generator and the fixtures only it, the benches and tests use
//! (`spacetime::fig8`, `spacetime::planar2`, `mocap::synth`) are behind the
//! `report` feature, on by default.

pub mod atomic_file;
pub mod cancel;
pub mod dynamics;
pub mod fmt_num;
pub mod graph;
pub mod ground;
pub mod ik;
pub mod io;
pub mod lang;
pub mod library;
pub mod lie;
pub mod mocap;
pub mod model;
pub mod motion;
/// `mx report` (behind the `report` feature, on by default).
#[cfg(feature = "report")]
pub mod report;
pub mod score;
pub mod shard;
pub mod spacetime;
pub mod spline;

pub use lang::{Interpreter, Value};
