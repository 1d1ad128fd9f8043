//! Foot contact inside SP's gaps (issue 25): the `contact:` option, the
//! typed [`ContactPlan`] (`plan.rs`), planning it from the stances around
//! each gap (`context.rs`), taking it as given (`given.rs`) and reading a
//! motion's own (`capture.rs`). Floor, "up", contact points and the stance test
//! are `ground`'s.

pub mod capture;
pub mod context;
pub mod given;
pub mod plan;

pub use capture::capture_plan;
pub use context::Context;
pub use given::{GivenStance, plan_given};
pub use plan::{ContactPlan, GapPlan, PointPlan, Source, Stance};

/// `SP(…, contact: …)`.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum Contact {
    /// The body's contact points (`ground`'s: its ankle and toe joints),
    /// stances planned per gap.
    Auto,
    /// `contact: ["Toes_L", …]`: these links, stances planned per gap.
    Named(Vec<String>),
    /// `contact: [{point, from, to, at}, …]` (or a capture's `contacts()`):
    /// the stances stated, not planned; the points named there, the others
    /// free.
    Given(Vec<GivenStance>),
    /// No contact planning: Rose's support alone (`support:`), as before.
    #[default]
    None,
}
