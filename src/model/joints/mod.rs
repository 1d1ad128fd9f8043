//! The joint library: one file per joint type.

pub mod prismatic;
pub mod revolute;

pub use prismatic::Prismatic;
pub use revolute::Revolute;
