//! Bodies, inertias, joints and kinematic trees.

pub mod joint;
pub mod joints;

pub use joint::{Derivatives, Joint, JointKinematics, Limit, MAX_JOINT_DOF};
pub mod body;
pub mod coupling;
pub mod kinematics;
pub mod osim;
pub mod tree;
pub mod urdf;

pub use body::Inertia;
pub use coupling::{Coupling, Follower};
pub use tree::{Link, Model, ModelError};
