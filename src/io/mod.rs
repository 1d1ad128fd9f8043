//! io (being built).

pub mod plot;
pub mod viewer;
