//! The settings of a library build, recorded beside every shard's results so
//! a merge joins only shards built alike.

use serde::{Deserialize, Serialize};

use super::GraphError;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Settings {
    /// Transition points kept per ordered pair.
    pub k: usize,
    /// Frames of the point-cloud window (odd).
    pub window: usize,
    /// Pairs and points whose distance exceeds this (m, RMS) get no transition.
    pub threshold: f64,
    /// Gap frames for a perfect match, and at the threshold.
    pub min_gap: usize,
    pub max_gap: usize,
    /// Frames of each clip SP sees beside the gap.
    pub context: usize,
    /// SP options; `None`: SP's own default.
    pub coefficients: Option<usize>,
    pub samples: Option<usize>,
    pub iterations: Option<u64>,
    pub tolerance: Option<f64>,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            k: 3,
            window: 9,
            threshold: 0.15,
            min_gap: 4,
            max_gap: 20,
            context: 10,
            coefficients: None,
            samples: None,
            iterations: None,
            tolerance: None,
        }
    }
}

/// An invalid `--option`: its flag and the sentence.
fn bad(option: &'static str, message: String) -> GraphError {
    GraphError::InvalidOption { option, message }
}

impl Settings {
    /// Checks the values a user can get wrong.
    pub fn check(&self) -> Result<(), GraphError> {
        if self.k == 0 {
            return Err(bad(
                "k",
                "--k must be at least 1 (transition points per pair)".into(),
            ));
        }
        if self.window == 0 || self.window.is_multiple_of(2) {
            return Err(bad(
                "window",
                format!(
                    "--window must be an odd number of frames (the frame and as many on each side), got {}",
                    self.window
                ),
            ));
        }
        if !(self.threshold.is_finite() && self.threshold > 0.0) {
            return Err(bad(
                "threshold",
                format!(
                    "--threshold must be a positive distance in metres, got {}",
                    self.threshold
                ),
            ));
        }
        if self.min_gap == 0 || self.max_gap < self.min_gap {
            return Err(bad(
                "min-gap",
                format!(
                    "gaps must satisfy 1 <= --min-gap <= --max-gap, got {} and {}",
                    self.min_gap, self.max_gap
                ),
            ));
        }
        if self.context == 0 {
            return Err(bad("context", "--context must be at least 1 frame".into()));
        }
        if let Some(c) = self.coefficients
            && c < 2
        {
            return Err(bad(
                "coefficients",
                format!("--coefficients must be at least 2, got {c}"),
            ));
        }
        if let Some(t) = self.tolerance
            && !(t > 0.0 && t < 1.0)
        {
            return Err(bad(
                "tolerance",
                format!("--tolerance must lie in (0, 1), got {t}"),
            ));
        }
        Ok(())
    }
}
