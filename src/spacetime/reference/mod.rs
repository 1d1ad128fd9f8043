//! The motion's own example for a gap: the stretch of the same motion, a
//! shift Δ away, whose frames around it look most like the frames around the
//! gap. A walk or a run repeats itself; what the person did in the gap is
//! then best told by what they did one cycle earlier or later, which no end
//! state carries (two interpolated ends cannot make a step).
//!
//! SP's prior follows the example's velocities and accelerations instead of
//! zero ([`super::sp::Prior`]): it is minimised by the example plus the
//! smooth correction that meets the gap's end states. A motion that does not
//! repeat (a bow, a wave) has no stretch that matches well, and then the
//! prior stays the plain one.
//!
//! The search over the motion itself is `own.rs`, over a clip library
//! `library.rs` (a library stretch laid on the gap's clock: `laid.rs`); both
//! keep a joint's channels together (`joints.rs`).

use super::error::SpError;
use super::objective::GapDof;
use crate::model::Model;
use crate::motion::Mu;
use std::f64::consts::PI;

mod blend;
mod ends;
pub mod joints;
mod laid;
mod lay;
mod library;
mod own;
mod pose;
#[cfg(test)]
mod tests;

pub use joints::Joints;
pub use lay::{EndFit, LaidExample, Lay, MAX_END_OFFSET};
pub use library::{ClipStretch, ExampleStances, LibrarySource, from_library, from_library_with};
pub use own::{find, find_with};

/// Grid step (s) the motion is compared on: a capture's usual frame time.
const STEP: f64 = 1.0 / 30.0;

/// Context (s) compared on each side of the gap: the in-betweening protocol's
/// ten frames at 30 Hz (`$MX_SHARED/data/inbetween/README.md`).
const CONTEXT: f64 = 0.3;

/// How far (s) from the gap an example is looked for: a long recording is
/// searched only this near the gap (the cost is linear in the span).
const SEARCH_SPAN: f64 = 30.0;

/// Longest gap (s) an example is looked for: a cycle copied from the same
/// motion tells nothing over longer, and the search's grid grows with it.
const MAX_GAP: f64 = 10.0;

/// Fewest context samples worth comparing (both sides together).
const MIN_CONTEXT_SAMPLES: usize = 4;

/// Largest mismatch ρ (see [`Example::mismatch`]) of an accepted example.
/// Measured by `cargo bench --bench inbetween` (50 shared clips, one window
/// each, root given): with ρ ≤ 0.5 instead, SP came 0.81 × Hermite at
/// 30-frame gaps against 0.76 here (before [`Example::trust`]); in a first
/// look, with the example alone corrected to its ends, windows with ρ between
/// 1 and 3 came farther from the capture than Hermite in 7 of 9 (a turning
/// walk whose cycles differ).
pub const MAX_MISMATCH: f64 = 1.0;

/// Largest difference (rad) between a DOF and its example at either end of
/// the gap for the DOF to follow it: the prior's motion is the example plus
/// a smooth ramp between the two end differences, so it stays this close to
/// poses the person took. A joint with a channel farther off keeps the plain
/// prior on all its channels (channel by channel, a kick's spine turned
/// 1.6 rad away from any pose of the clip: one Euler channel followed and its
/// siblings did not). With 0.15 a walk's toe ended 67 cm off where one leg
/// joint followed and the next did not; with no limit a punch's upper arm
/// turned 0.62 rad from its sides (`tests/it/inbetween.rs` allows 0.48).
pub const MAX_END_DIFFERENCE: f64 = 0.25;

/// A rotation coordinate that turns by more than this between two grid
/// samples is taken to wrap (±π in the data), and such a stretch is no example.
const MAX_TURN_PER_STEP: f64 = PI / 2.0;

/// The stretch of the motion a group of gaps follows.
#[derive(Clone, Debug, PartialEq)]
pub struct Example {
    /// Δ (s): the gap at t follows the motion at t + Δ.
    pub shift: f64,
    /// ρ: over the context on both sides of the gap, the squared difference
    /// between the motion and the motion Δ away, over the context's own
    /// squared spread about its mean (rotation coordinates, angles wrapped).
    /// 0 is a perfect repeat; 1 is no better than the context's mean pose.
    pub mismatch: f64,
    /// The model coordinates that follow it: those within
    /// [`MAX_END_DIFFERENCE`] of it at both ends of the gap.
    pub follow: Vec<usize>,
    /// The group's gap coordinates (followers or not).
    pub of: usize,
    /// A library stretch (`example: lib`) instead of the motion `shift` away.
    pub clip: Option<ClipStretch>,
    /// How far its laid poses are from the gap's end states (set when it is
    /// laid, [`Lay::lay`]).
    pub fit: Option<EndFit>,
}

/// Why a group of gaps follows no example: what `sp_report` says instead
/// of naming one.
#[derive(Clone, Debug, PartialEq)]
pub enum NoExample {
    /// `example: "none"` and no library.
    NotAsked,
    /// The gap has no length, or is longer than [`MAX_GAP`] (no cycle
    /// copied from elsewhere tells anything over it).
    Span { seconds: f64 },
    /// No gap DOF is an angle (only angles are compared).
    NoAngles,
    /// Fewer than [`MIN_CONTEXT_SAMPLES`] frames around the gap where every
    /// gap DOF is defined, or a context that does not move (nothing to match).
    NoContext,
    /// The motion holds no stretch of the gap's length, with its context,
    /// away from the gap (too short, or undefined or wrapping elsewhere).
    NoStretch,
    /// The library holds no clip.
    LibraryEmpty,
    /// The library's features cannot be read off the motion (its skeleton
    /// lacks the key joints, or the context is undefined where they look).
    NoFeatures(String),
    /// The best stretch matched no better than the threshold.
    NoMatch { best: f64, threshold: f64 },
    /// The best stretch is too far from the motion at the gap's ends on every
    /// joint (its [`EndFit`]).
    FarAtEnds { start: f64, end: f64, angle: f64 },
    /// The example is undefined over the gap on every DOF (this one first).
    Undefined { dof: String },
}

impl std::fmt::Display for NoExample {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            NoExample::NotAsked => write!(f, "none asked (example: \"none\")"),
            NoExample::Span { seconds } => write!(
                f,
                "the gap of {seconds:.3} s is no example's (0 or over {MAX_GAP} s)"
            ),
            NoExample::NoAngles => write!(f, "no gap DOF is an angle to match"),
            NoExample::NoContext => write!(
                f,
                "too little moving context around the gap to match (fewer than {MIN_CONTEXT_SAMPLES} frames where every gap DOF is defined, or a still one)"
            ),
            NoExample::NoStretch => write!(
                f,
                "no stretch of the gap's length with its context elsewhere in the motion"
            ),
            NoExample::LibraryEmpty => write!(f, "the library is empty"),
            NoExample::NoFeatures(why) => write!(f, "the library cannot match it: {why}"),
            NoExample::NoMatch { best, threshold } => write!(
                f,
                "no match under the threshold (best mismatch {best:.3}, at most {threshold})"
            ),
            NoExample::FarAtEnds { start, end, angle } => write!(
                f,
                "the best match is too far from the gap's ends on every joint ({:.1} / {:.1} cm mean joint distance at start / end, {angle:.2} rad at worst)",
                100.0 * start,
                100.0 * end
            ),
            NoExample::Undefined { dof } => {
                write!(f, "the example is undefined over the gap ({dof} first)")
            }
        }
    }
}

/// Where an example came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Origin {
    /// The motion itself (`"self"`).
    Own,
    /// A clip library (`example: lib`).
    Library,
}

impl Origin {
    pub fn label(self) -> &'static str {
        match self {
            Origin::Own => "self",
            Origin::Library => "library",
        }
    }
}

/// One example source asked for a group of gaps: its best example's match
/// cost ρ, or why it gave none.
pub type Tried = (Origin, Result<f64, NoExample>);

/// Why a group of gaps follows no example, from each source `tried`
/// (`None` when it follows one, `followed`, or no source was asked).
pub fn why_none(tried: &[Tried], followed: bool) -> Option<String> {
    if followed || tried.is_empty() {
        return None;
    }
    let parts: Vec<String> = tried
        .iter()
        .map(|(o, r)| match r {
            Err(why) => format!("{}: {why}", o.label()),
            Ok(rho) => format!("{}: mismatch {rho:.3}, not followed", o.label()),
        })
        .collect();
    Some(parts.join("; "))
}

/// The example a group of gaps follows, laid over it, or why none is:
/// each source asked, with its best match cost or why it had none.
#[derive(Clone, Debug, Default)]
pub struct ExampleChoice {
    pub laid: Option<LaidExample>,
    /// Per source asked (`"self"`, the library), its example's ρ or why it
    /// gave none; the laid one is the lower ρ.
    pub tried: Vec<Tried>,
}

impl ExampleChoice {
    /// The example followed, if any.
    pub fn example(&self) -> Option<&Example> {
        self.laid.as_ref().map(|l| &l.example)
    }

    /// Why none is followed (`None` when one is): every source's reason,
    /// or [`NoExample::NotAsked`] when none was asked.
    pub fn why_none(&self) -> Option<String> {
        if self.laid.is_none() && self.tried.is_empty() {
            return Some(NoExample::NotAsked.to_string());
        }
        why_none(&self.tried, self.laid.is_some())
    }
}

impl Example {
    /// How much of the example the prior follows: 1 − ρ, all of a perfect
    /// repeat and less of a looser match, so that a context that matched
    /// by chance (a step the person did not take in the gap) weighs little.
    pub fn trust(&self) -> f64 {
        (1.0 - self.mismatch).clamp(0.0, 1.0)
    }
}

/// The example for a group of gaps from the motion itself (`self`), a
/// library, or both (the lower ρ kept). A joint's channels are its model's
/// joints as well as the name convention's ([`Joints::of_model`]), so OpenSim coordinates,
/// whose names carry no joint, still follow an example joint by joint.
pub fn choose_for(
    model: &Model,
    m: &Mu,
    names: &[String],
    rotation: &dyn Fn(usize) -> bool,
    gaps: &[GapDof],
    own: bool,
    library: Option<&LibrarySource>,
) -> Result<Option<Example>, SpError> {
    let joints = Joints::of_model(model, names);
    choose_with(m, names, rotation, &joints, gaps, own, library)
}

/// [`choose_for`] with the coordinates' joints given.
pub fn choose_with(
    m: &Mu,
    names: &[String],
    rotation: &dyn Fn(usize) -> bool,
    joints: &Joints,
    gaps: &[GapDof],
    own: bool,
    library: Option<&LibrarySource>,
) -> Result<Option<Example>, SpError> {
    let mut found = searched(m, names, rotation, joints, gaps, own, library)?;
    found.sort_by(|a, b| rank(a).total_cmp(&rank(b)));
    Ok(found.into_iter().find_map(|(_, r)| r.ok()))
}

/// A source and its best example or why it has none.
type Found = (Origin, Result<Example, NoExample>);

/// Each source asked (`own`: the motion itself; the library), with its best
/// example or why it has none.
fn searched(
    m: &Mu,
    names: &[String],
    rotation: &dyn Fn(usize) -> bool,
    joints: &Joints,
    gaps: &[GapDof],
    own: bool,
    library: Option<&LibrarySource>,
) -> Result<Vec<Found>, SpError> {
    let mut found = vec![];
    if own {
        found.push((Origin::Own, own::search(m, names, rotation, joints, gaps)?));
    }
    if let Some(l) = library {
        found.push((
            Origin::Library,
            library::search(m, names, rotation, joints, gaps, l)?,
        ));
    }
    Ok(found)
}

/// A source's match cost, for choosing between them (none: last).
fn rank(found: &Found) -> f64 {
    found.1.as_ref().map_or(f64::INFINITY, |e| e.mismatch)
}

/// The example a group of gaps follows, laid over it by `lay`: of the
/// sources asked (`own`: the motion itself, `"self"`; `library`), the one
/// of lower match cost ρ that can be laid (`[lib, "self"]` so picks per
/// gap), with every source's ρ or why it had none.
pub fn choose(
    lay: &Lay,
    gaps: &[GapDof],
    own: bool,
    library: Option<&LibrarySource>,
) -> Result<ExampleChoice, SpError> {
    let mut found = searched(
        lay.motion,
        lay.names,
        lay.rotation,
        lay.joints,
        gaps,
        own,
        library,
    )?;
    found.sort_by(|a, b| rank(a).total_cmp(&rank(b)));
    let mut choice = ExampleChoice::default();
    for (origin, found) in found {
        let entry = match found {
            Ok(ex) if choice.laid.is_none() => match lay.lay(&ex, gaps)? {
                Ok(laid) => {
                    choice.laid = Some(laid);
                    Ok(ex.mismatch)
                }
                Err(why) => Err(why),
            },
            Ok(ex) => Ok(ex.mismatch),
            Err(why) => Err(why),
        };
        choice.tried.push((origin, entry));
    }
    Ok(choice)
}

/// The span (t0, t1) of a group of gaps an example is looked for: none for
/// no gaps, a zero-length span (no stretch to copy) or one longer than
/// [`MAX_GAP`] (longer than any cycle).
fn gap_span(gaps: &[GapDof]) -> Option<(f64, f64)> {
    let t0 = gaps.iter().map(|g| g.t0).reduce(f64::min)?;
    let t1 = gaps.iter().map(|g| g.t1).reduce(f64::max)?;
    (t1 - t0 > 1e-9 && t1 - t0 <= MAX_GAP).then_some((t0, t1))
}

/// The length (s) of a group of gaps' span (0 for none).
fn span_seconds(gaps: &[GapDof]) -> f64 {
    let t0 = gaps.iter().map(|g| g.t0).fold(f64::INFINITY, f64::min);
    let t1 = gaps.iter().map(|g| g.t1).fold(f64::NEG_INFINITY, f64::max);
    if t1 >= t0 { t1 - t0 } else { 0.0 }
}

/// The sorted, distinct coordinates of a group of gaps.
fn gap_coords(gaps: &[GapDof]) -> Vec<usize> {
    let mut coords: Vec<usize> = gaps.iter().map(|g| g.coord).collect();
    coords.sort_unstable();
    coords.dedup();
    coords
}

/// An angle difference wrapped into [−π, π).
fn wrap(d: f64) -> f64 {
    (d + PI).rem_euclid(2.0 * PI) - PI
}
