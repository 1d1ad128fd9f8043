//! Bodies, inertias, joints and kinematic trees.

pub mod joint;
pub mod joint_fit;
pub mod joints;

pub use joint::{Derivatives, Joint, JointKinematics, Limit, MAX_JOINT_DOF};
pub mod body;
pub mod coupling;
pub mod files;
pub mod kinematics;
pub mod link_tree;
pub mod root;
pub mod topology;
pub mod tree;

// the readers, at the paths they have always had (`model::urdf::load_urdf`, …)
pub use files::{osim, urdf};

pub use body::{Inertia, InertiaError};
pub use coupling::{Coupling, Follower};
pub use root::RootCoords;
pub use topology::joint_points;
pub use tree::{Link, Model, ModelError};
