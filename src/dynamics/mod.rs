//! dynamics (being built).
