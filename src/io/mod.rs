//! io (being built).

pub mod plot;
