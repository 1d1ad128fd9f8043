//! The protocol's parameters: gap lengths, window stride, context, the root
//! settings, the frame rate frames are counted at, and which clips are
//! locomotion.

/// The protocol's parameters (defaults: the shared folder's README).
#[derive(Clone, Debug)]
pub struct Protocol {
    /// Gap lengths in frames.
    pub gaps: Vec<usize>,
    /// Frames between window starts.
    pub stride: usize,
    /// Context frames kept before the gap (and at least as many after it).
    pub context: usize,
    /// At most this many windows per clip and gap length (evenly spread); `None`: all.
    pub windows_per_clip: Option<usize>,
    /// Root settings to run.
    pub roots: Vec<RootMode>,
}

impl Default for Protocol {
    fn default() -> Self {
        Protocol {
            gaps: vec![5, 15, 30, 45],
            stride: 40,
            context: 10,
            windows_per_clip: None,
            roots: vec![RootMode::Given, RootMode::Filled],
        }
    }
}

/// Whether the root's channels are kept inside the gap.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RootMode {
    Given,
    Filled,
}

impl RootMode {
    pub fn label(self) -> &'static str {
        match self {
            RootMode::Given => "root given",
            RootMode::Filled => "natural cut",
        }
    }
}

/// The frame rate the protocol counts frames at (Hz): gaps of 15/30/45
/// frames are 0.5/1/1.5 s, whatever rate a clip was captured at.
pub const PROTOCOL_RATE: f64 = 30.0;

/// Body mass of the benchmark's bodies (kg), `body_of`'s default.
pub const BODY_MASS: f64 = 70.0;

/// Whether a clip is locomotion (its name has walk, run, dash or turn: the
/// subset shown on its own).
pub fn is_locomotion(clip: &str) -> bool {
    let c = clip.to_ascii_lowercase();
    ["walk", "run", "dash", "turn"]
        .iter()
        .any(|k| c.contains(k))
}
