//! Splines: B-spline bases and scalar curves, least-squares fitting, and the
//! cumulative basis used by spline curve joints on SE(3).

pub mod bspline;
pub mod fit;
pub mod gcv;

pub use bspline::{BSplineBasis, BSplineCurve, MAX_DEGREE, SplineError};
pub use fit::{fit_least_squares, fit_weighted};
pub use gcv::GcvSpline;
pub mod simm;
pub use simm::SimmSpline;
pub mod tensor;
pub use tensor::{TensorEval, TensorSpline};
