//! motion (being built).
