//! How good is a fill? A motion scored against a reference over gaps, by
//! the definitions of the in-betweening benchmark (`data/inbetween/README.md`,
//! after Harvey et al. 2020), in one place that the benchmark, `mx report`
//! and the language's `compare(…)` all call:
//!
//! - `accuracy.rs`: L2P (mean joint-position error, cm, and the worst joint
//!   and frame), L2Q and NPSS over the gap's frames, from forward kinematics
//!   of both motions on one body; `metrics.rs`: L2Q and NPSS themselves;
//! - `grounding.rs`: skate, depth and ground residual over the gap by
//!   `ground`'s rules (its contact points, 2 cm, μ 0.8) against the
//!   reference's floor, with their per-frame series;
//! - `plan.rs`: a contact plan (SP's `GapPlan`) against the reference's own
//!   contacts: stance edges within 0.1 s and per-frame agreement;
//! - `compare.rs`: the gaps SP filled (from its report) or a named span,
//!   each scored beside the reference's own ground measures.
//!
//! Layering: uses `lie`, `model`, `motion`, `ground` and `spacetime` (SP's
//! report and contact plan); used by `report` and `lang`. Knows nothing of
//! the language. Not behind the `report` feature: `compare` is a built-in.

pub mod accuracy;
pub mod compare;
pub mod error;
pub mod grounding;
pub mod metrics;
pub mod plan;

pub use accuracy::{Accuracy, JointPoses, accuracy, joint_poses};
pub use compare::{
    Comparison, GapScore, compare, filled_spans, frame_period, frames_inside, score_gap,
};
pub use error::{ScoreError, Which};
pub use grounding::{FRICTION, GroundFrames, Grounding, floor_of, ground_options, grounding};
pub use plan::{EDGE_TOLERANCE, PlanAccuracy, given_contacts, plan_accuracy, reference_plan};
