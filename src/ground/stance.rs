//! When a point stands on the ground: the thresholds and the test that
//! `contacts()` and SP's contact planning share.
//!
//! A point is in stance while it is within [`CONTACT_HEIGHT`] of its reference
//! height (the floor for `contacts()`; for SP's planning the point's own
//! lowest height around a gap, since an ankle joint never comes within 2 cm
//! of the floor while its toe does) and moves horizontally slower than
//! [`CONTACT_SPEED`]. Only points whose lowest height lies within
//! [`GROUND_BAND`] of the floor can carry the body at all.

/// Height (m) above the reference within which a point may be in stance:
/// `data/inbetween/README.md`'s 2 cm.
pub const CONTACT_HEIGHT: f64 = 0.02;
/// Horizontal speed (m/s) under which a low point is in stance: inside the
/// 0.2–0.5 m/s range foot-contact detectors use; on the captured walks of
/// `data/inbetween` a foot joint within 2 cm of the floor moves ~10 cm/s
/// on average (capture noise, rolling), and the swing foot passing low
/// moves well above 1 m/s.
pub const CONTACT_SPEED: f64 = 0.3;
/// A point that can carry the body reaches within this (m) of the floor: an
/// ankle and a toe of a person do, a still head or hand does not.
pub const GROUND_BAND: f64 = 0.15;

/// SP's planning rule (not the measures': `contacts()` and `foot_skate` keep
/// the fixed [`CONTACT_SPEED`]). A running foot is planted ~0.2 s, yet its
/// toe joint rolls forward at a good part of the body's speed while it is, so
/// the fixed 0.3 m/s cuts a run's stance to 1–3 frames. A planted point moves
/// at a fraction of the body's speed, a swinging one on average at twice it:
/// the speed limit scales with the body's horizontal speed (never below
/// [`CONTACT_SPEED`], which still decides for a body standing or shuffling).
/// Scaling a clip in time scales both speeds alike, so the rule plans the
/// same footfalls at 0.8× and 1.25× speed.
pub const PLAN_SPEED_FRACTION: f64 = 0.25;
/// Half-width (s) of the central difference a planning speed is taken over:
/// a time, not a frame count, so 30 Hz and 120 Hz clips see the same noise.
pub const PLAN_SPEED_WINDOW: f64 = 1.0 / 30.0;
/// Half-width (s) the body's speed is averaged over: half a walking step,
/// so the stride's surge does not move the limit within one stance.
pub const PLAN_BODY_WINDOW: f64 = 0.25;

/// The speed (m/s) under which a low point is planted for SP's plan while
/// the body moves horizontally at `body_speed` (m/s).
pub fn plan_speed_limit(body_speed: f64) -> f64 {
    CONTACT_SPEED.max(PLAN_SPEED_FRACTION * body_speed)
}

/// SP's planning stance test over uniformly spaced samples `dt` apart: per
/// sample, whether the point at `point[i]` is planted — within
/// [`CONTACT_HEIGHT`] of `stand` (its own lowest height along `up`) and
/// slower (over ±[`PLAN_SPEED_WINDOW`]) than [`plan_speed_limit`] of the
/// body's speed (`body[i]`, over ±[`PLAN_BODY_WINDOW`]). Differences are cut
/// at the samples' ends.
pub fn plan_stances(
    point: &[Vector3<f64>],
    body: &[Vector3<f64>],
    dt: f64,
    stand: f64,
    up: &Vector3<f64>,
) -> Vec<bool> {
    let speed = |p: &[Vector3<f64>], i: usize, w: f64| {
        let r = ((w / dt).round() as usize).max(1);
        let (a, b) = (i.saturating_sub(r), (i + r).min(p.len() - 1));
        if a == b {
            return 0.0;
        }
        horizontal(&(p[b] - p[a]), up).norm() / ((b - a) as f64 * dt)
    };
    (0..point.len())
        .map(|i| {
            let limit = plan_speed_limit(speed(body, i, PLAN_BODY_WINDOW));
            in_stance(
                up.dot(&point[i]) - stand,
                speed(point, i, PLAN_SPEED_WINDOW),
                CONTACT_HEIGHT,
                limit,
            )
        })
        .collect()
}

/// Whether a point `above` metres above its reference height, moving
/// horizontally at `speed` (m/s), is in stance under the thresholds
/// `height` (m) and `max_speed` (m/s; `f64::INFINITY` turns the speed test off).
pub fn in_stance(above: f64, speed: f64, height: f64, max_speed: f64) -> bool {
    above <= height && speed < max_speed
}

use super::floor::horizontal;
use nalgebra::Vector3;

#[cfg(test)]
mod tests {
    use super::*;

    /// A foot that rolls at 0.15× the body's speed for `stance` s and swings
    /// for `swing` s as fast as keeps up with the body, low on the floor throughout (so speed alone
    /// decides), sampled every `dt`: planted in its stances, wrong only within
    /// the speed's difference window of a lift-off or touch-down, whatever
    /// the speed and the rate.
    #[test]
    fn the_planning_rule_keeps_a_running_stance_at_any_speed_and_rate() {
        let up = Vector3::y();
        for (speed, dt) in [(1.2, 1.0 / 30.0), (3.5, 1.0 / 30.0), (3.5, 1.0 / 120.0)] {
            let (stance, swing) = (0.24, 0.48);
            let n = (3.0 / dt) as usize;
            let (mut foot, mut body) = (vec![], vec![]);
            let mut x = 0.0;
            let mut truth = vec![];
            for i in 0..n {
                let t = i as f64 * dt;
                body.push(Vector3::new(speed * t, 1.0, 0.0));
                let planted = (t % (stance + swing)) < stance;
                foot.push(Vector3::new(x, 0.0, 0.0));
                let fast = (stance + swing - 0.15 * stance) / swing;
                x += dt * speed * if planted { 0.15 } else { fast };
                truth.push(planted);
            }
            let flags = plan_stances(&foot, &body, dt, 0.0, &up);
            // at a dash the measures' fixed 0.3 m/s would see no stance at all
            assert!(speed < 2.0 || speed * 0.15 > CONTACT_SPEED);
            let cycle = stance + swing;
            for (i, (f, t)) in flags.iter().zip(&truth).enumerate() {
                let phase = (i as f64 * dt) % cycle;
                let edge = [0.0, stance, cycle]
                    .iter()
                    .map(|e| (phase - e).abs())
                    .fold(f64::INFINITY, f64::min);
                assert!(
                    f == t || edge <= PLAN_SPEED_WINDOW + dt,
                    "speed {speed} dt {dt} sample {i}: {f} vs {t}"
                );
            }
            let right = flags.iter().zip(&truth).filter(|(a, b)| a == b).count();
            assert!(right as f64 > 0.8 * n as f64, "speed {speed} dt {dt}");
        }
    }

    #[test]
    fn low_and_slow_is_stance() {
        assert!(in_stance(0.01, 0.1, CONTACT_HEIGHT, CONTACT_SPEED));
        assert!(in_stance(
            CONTACT_HEIGHT,
            0.0,
            CONTACT_HEIGHT,
            CONTACT_SPEED
        ));
        assert!(!in_stance(0.03, 0.1, CONTACT_HEIGHT, CONTACT_SPEED));
        assert!(!in_stance(
            0.0,
            CONTACT_SPEED,
            CONTACT_HEIGHT,
            CONTACT_SPEED
        ));
        assert!(in_stance(0.0, 5.0, CONTACT_HEIGHT, f64::INFINITY));
    }
}
