//! spacetime (being built).
