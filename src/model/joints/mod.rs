//! The joint library: one file per joint type.

pub mod function_based;
mod osim;
pub mod poe;
pub mod prismatic;
pub mod revolute;
pub mod scalar_function;

pub use function_based::{FunctionJoint, FunctionJointError, TransformAxis};
pub use prismatic::Prismatic;
pub use revolute::Revolute;
pub use scalar_function::ScalarFunction;
