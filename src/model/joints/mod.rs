//! The joint library: one file per joint type.
//!
//! Most joints are products of exponentials and share the recursion of
//! [`poe`] (spline-joint paper eq. 27–31) for their Jacobian and Hessian.

pub mod axis;
pub mod curve;
pub mod cylindrical;
pub mod elliptic;
pub mod error;
pub mod fixed;
pub mod function_based;
pub mod helical;
pub mod planar;
pub mod poe;
pub mod root6;
pub mod samples;
pub mod scalar_function;
pub mod spherical;
pub mod spline_loop;
pub mod spline_ndof;
pub mod spline_surface;
pub mod universal;

pub use axis::{AxisJoint, Prismatic, Revolute};
pub use curve::SplineCurveJoint;
pub use cylindrical::Cylindrical;
pub use elliptic::Elliptic;
pub use error::JointSpecError;
pub use fixed::Fixed;
pub use function_based::{FunctionJoint, FunctionJointError, TransformAxis};
pub use helical::Helical;
pub use planar::Planar;
pub use root6::Root6;
pub use samples::{JointError, JointSamples, joint_error};
pub use scalar_function::ScalarFunction;
pub use spherical::{EulerOrder, Spherical};
pub use spline_loop::SplineLoopJoint;
pub use spline_ndof::SplineJoint;
pub use spline_surface::{FrameGrid, SplineSurfaceJoint};
pub use universal::Universal;
