//! Foot contact inside SP's gaps (issues 25, 35, 42): the `contact:`
//! option, the typed [`ContactPlan`] (`plan.rs`), planning it from the
//! stances around each gap (`context.rs`), from the example SP follows
//! (`example.rs`) or, without one, a step planner (`steps.rs`), the
//! sources merged edges first (`merge.rs`), taking it
//! as given (`given.rs`), reading a motion's own (`capture.rs`) and
//! re-planning from a solve's result (`replan.rs`). Floor, "up", contact points and the stance test
//! are `ground`'s.

pub mod capture;
pub mod context;
pub mod example;
pub mod feet;
pub mod given;
pub mod merge;
pub mod plan;
pub mod replan;
pub mod steps;

pub use capture::{Tracks, capture_plan};
pub use context::Context;
pub use example::{ExampleStances, PlanPoint, Timing, example_plan};
pub use given::{GivenStance, plan_given};
pub use merge::with_edges;
pub use plan::{ContactPlan, GapPlan, PointPlan, Source, Stance};
pub use replan::Replan;
pub use steps::Phase;

/// `SP(…, contact: …)`.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum Contact {
    /// The default (issue 42): the body's contact points (`ground`'s: its
    /// ankle and toe joints), stances planned per gap; the body stands on
    /// the ground wherever it has feet, gravity acts and a floor is found
    /// (`sp::stands`), and is SP as Rose's otherwise.
    #[default]
    Auto,
    /// `contact: ["Toes_L", …]`: these links, stances planned per gap.
    Named(Vec<String>),
    /// `contact: [{point, from, to, at}, …]` (or a capture's `contacts()`):
    /// the stances stated, not planned; the points named there, the others
    /// free.
    Given(Vec<GivenStance>),
    /// `contact: "none"`: no contact planning, Rose's support alone
    /// (`support:`), as before issue 42.
    None,
}
