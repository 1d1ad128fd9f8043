//! How the differences between an aligned example and the motion's end
//! states are added to the example when it is laid (`lay.rs`), so that
//! the laid curve meets the motion at both ends of the gap.

use crate::spacetime::EndState;
use crate::spacetime::hermite;

/// Poses (m, mean joint distance, `lay::EndFit`) within which a laid example
/// is the motion's own continuation at both ends: its velocity differences
/// there are then the cut's end estimates' error (a cut piece's spline
/// ends one-sided: a dance at 30 Hz is off by up to 5 rad/s), not the
/// example's, and are met within [`LAYER_FRAMES`] instead of across the gap.
const CONTINUATION_FIT: f64 = 0.01;

/// Frames of the motion over which a continuation's velocity differences
/// are met at each end.
const LAYER_FRAMES: f64 = 3.0;

/// How the differences between the aligned example and the motion's end
/// states are added to the example.
pub(super) enum Blend {
    /// Positions and velocities by one cubic Hermite curve over the gap.
    Cubic,
    /// Positions by the cubic (zero end velocities), velocities each within
    /// a layer of this many seconds at its end.
    Layer(f64),
}

impl Blend {
    /// `Layer` when the example meets the end poses within [`CONTINUATION_FIT`]
    /// at both ends (`start`, `end`: mean joint distances, m) and the motion
    /// is sampled (`frame`: its frame time), else `Cubic`.
    pub fn for_fit(start: f64, end: f64, frame: Option<f64>) -> Blend {
        match frame {
            Some(dt) if start <= CONTINUATION_FIT && end <= CONTINUATION_FIT => {
                Blend::Layer(LAYER_FRAMES * dt)
            }
            _ => Blend::Cubic,
        }
    }

    /// The difference added at time t (outside [t0, t1] continued smoothly,
    /// for the laid curve's padding).
    pub fn at(&self, t0: f64, t1: f64, d0: &EndState, d1: &EndState, t: f64) -> f64 {
        match *self {
            Blend::Cubic => hermite::cubic_continued(t0, t1, d0, d1, t)[0],
            Blend::Layer(tau) => {
                let still = |e: &EndState| EndState { v: 0.0, ..*e };
                let tau = tau.min(0.5 * (t1 - t0));
                let positions = hermite::cubic_continued(t0, t1, &still(d0), &still(d1), t)[0];
                positions + d0.v * layer(t - t0, tau) - d1.v * layer(t1 - t, tau)
            }
        }
    }
}

/// 0 with slope 1 at u = 0, back to 0 with slope 0 at u = τ and beyond
/// (u (1 − u/τ)², continued below 0).
fn layer(u: f64, tau: f64) -> f64 {
    if tau <= 0.0 || u >= tau {
        0.0
    } else {
        u * (1.0 - u / tau).powi(2)
    }
}
