//! Bodies, inertias, joints and kinematic trees.

pub mod joint;
pub mod joints;

pub use joint::{Derivatives, Joint, JointKinematics, Limit, MAX_JOINT_DOF};
