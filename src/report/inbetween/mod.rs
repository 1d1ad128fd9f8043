//! The in-betweening benchmark: cut a gap out of a real clip, fill it, and
//! compare with the frames a person actually performed (the protocol of
//! `data/inbetween/README.md`, after Harvey et al. 2020's LaFAN1 benchmark).
//!
//! Windows start every `stride` frames; each keeps `context` frames before
//! the gap and every frame after it (at least `context` of them). The two
//! sides are separate sampled curves, so nothing a method sees was
//! interpolated through the frames it must recreate. With the root given the
//! root's channels keep their captured curve through the gap; with the root
//! filled every DOF is cut and the frames after the gap stay where they were
//! captured (SP's `root: "pinned"`).
//!
//! The scores are `crate::score`'s, the ones `compare(m, reference, body)`
//! gives: L2P (mean joint-position error over the gap's frames, cm, with the
//! worst joint and frame), L2Q and NPSS as Harvey et al. report them; and
//! `ground`'s measures by `ground`'s rules over the gap's frames and the
//! frame on either side, against the floor of the whole captured clip:
//! skate (horizontal speed of a contact point — an ankle or toe joint —
//! within 2 cm of the floor, cm/s), penetration (deepest contact point below
//! it, cm) and the ground residual (the force no friction-cone contact
//! forces, μ 0.8, at contact points within 2 cm can supply, % of body
//! weight); the capture is their reference row, and the locomotion clips
//! (walk, run, dash, turn) are summarised on their own. Where SP planned
//! contacts, its plan against the capture's (`score::plan`: stance edges
//! within 0.1 s, per-frame agreement). The benchmark adds what only it
//! reports: the largest change of a bone's length (m), ∫Στ² over the gap,
//! and for SP its iterations, evaluations, convergence and time.
//!
//! One job per file: the parameters (`protocol.rs`), a clip and its windows
//! (`case.rs`), the methods (`methods.rs`), one method on one window
//! (`window.rs`), every window in parallel (`run.rs`), the summary, its table
//! and CSV (`summary.rs`). Used by `benches/inbetween.rs`, `mx report` and
//! the plausibility tests.

mod case;
mod methods;
mod protocol;
mod run;
mod summary;
mod window;

pub use case::Case;
pub use methods::{
    Method, SP_CAPTURE_CONTACTS, SP_DEFAULTS, SP_LIBRARY, SP_LIBRARY_SELF, TODAYS_SP, knob_methods,
    library_methods, methods, todays_sp,
};
pub use protocol::{BODY_MASS, PROTOCOL_RATE, Protocol, RootMode, is_locomotion};
pub use run::{run, same_options};
pub use summary::{Summary, csv, summarise, summarise_locomotion, table};
pub use window::{Filled, WindowResult, fill_window, plan_score, run_window, score};

/// Friction coefficient of the ground residual (the README's μ).
pub use crate::score::FRICTION;
