//! Reading bodies and joints from files: URDF (`urdf.rs`), whole OpenSim models
//! (`osim/`), single OpenSim `CustomJoint`s from `.osim` XML (`osim_joint.rs`)
//! and from the JSON of the reference samples (`osim_json.rs`). BVH, which gives
//! motions as well as skeletons, stays with the capture code in `mocap::bvh`.
//!
//! The readers build on the joint library and the link tree; nothing in those
//! knows of a file format.

pub mod osim;
pub(crate) mod osim_joint;
mod osim_json;
pub mod urdf;

pub use osim_json::function_from_json;
