//! Transition libraries at scale: a motion graph (Kovar, Gleicher & Pighin
//! 2002) over a folder of clips of one skeleton, its transitions filled by
//! SP (Rose et al. 1996). `mx graph build/merge/info/walk`.
//!
//! - `library.rs`: the clips, checked to share one skeleton; each frame's joint point cloud
//! - `planar.rs`: ground-plane rigid motions: Kovar's point-cloud fit, applied to root channels
//! - `search.rs`: transition points, local minima of the window distance
//! - `transition.rs`: one gap cut, b aligned, filled by `spacetime::sp`, written as BVH frames
//! - `shard.rs`: the deterministic share of the pairs (`--shard i/n` or Slurm's array variables)
//! - `store.rs`: the output folder, atomic writes, resume, merge
//! - `model.rs`: `graph.json` (nodes are clip segments, edges transitions and continuations)
//! - `error.rs`: the typed errors (options, clips, root, one transition)
//! - `build.rs`: a shard's run (rayon, progress bar, log); `info.rs`; `walk.rs`
//!
//! Layering: uses `mocap`, `motion`, `spacetime`, `io`; knows nothing of the language.

pub mod build;
pub mod error;
pub mod info;
pub mod library;
pub mod model;
pub mod planar;
pub mod search;
pub mod settings;
pub mod shard;
pub mod store;
pub mod transition;
pub mod walk;

pub use build::{BuildOptions, BuildSummary, build};
pub use model::Graph;
pub use settings::Settings;
pub use shard::Shard;
pub use store::{merge, read_graph};

pub use error::{ClipError, GraphError, RootError, TransitionError};
