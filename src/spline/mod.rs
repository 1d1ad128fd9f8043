//! spline (being built).
