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

/// Whether a point `above` metres above its reference height, moving
/// horizontally at `speed` (m/s), is in stance under the thresholds
/// `height` (m) and `max_speed` (m/s; `f64::INFINITY` turns the speed test off).
pub fn in_stance(above: f64, speed: f64, height: f64, max_speed: f64) -> bool {
    above <= height && speed < max_speed
}

#[cfg(test)]
mod tests {
    use super::*;

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
