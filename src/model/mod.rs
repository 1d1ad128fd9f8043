//! Bodies, inertias, joints and kinematic trees.

pub mod joint;
pub mod joints;

pub use joint::{Derivatives, Joint, JointKinematics, Limit, MAX_JOINT_DOF};
pub mod body;
pub mod kinematics;
pub mod tree;
pub mod urdf;

pub use body::Inertia;
pub use tree::{Link, Model, ModelError};
