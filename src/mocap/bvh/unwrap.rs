//! Angle unwrapping. Exporters wrap Euler angles into (−180°, 180°]; a curve
//! through such values jumps by ~360° and its spline derivatives explode.
//! Each sample is moved by a multiple of 360° to lie within 180° of the
//! previous (already unwrapped) one, so the curve is continuous and every
//! value still equals the file's modulo 360°.

/// Unwraps a sequence of angles in degrees in place; returns the number of
/// samples whose wrap count changed (the number of jumps removed).
/// Non-finite values are left alone and do not move the reference.
pub fn unwrap_degrees(a: &mut [f64]) -> usize {
    unwrap_degrees_in(a.iter_mut())
}

/// [`unwrap_degrees`] over any sequence of values, e.g. one channel's column
/// of a frame table in place (no copy out and back).
pub fn unwrap_degrees_in<'a>(a: impl Iterator<Item = &'a mut f64>) -> usize {
    let mut jumps = 0;
    let mut prev_raw: Option<f64> = None;
    let mut shift = 0.0;
    for v in a {
        if !v.is_finite() {
            continue;
        }
        let raw = *v;
        if let Some(p) = prev_raw {
            // Only steps larger than a half turn are wraps; an exact ±180° step
            // is ambiguous and left as written.
            let d = raw - p;
            let k = if d > 180.0 {
                ((d - 180.0) / 360.0).ceil()
            } else if d < -180.0 {
                -((-d - 180.0) / 360.0).ceil()
            } else {
                0.0
            };
            if k != 0.0 {
                jumps += 1;
                shift -= 360.0 * k;
            }
        }
        prev_raw = Some(raw);
        *v = raw + shift;
    }
    jumps
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn removes_wraps_and_keeps_values_mod_360() {
        let raw = [170.0, 179.0, -179.0, -170.0, 175.0, -175.0, 170.0];
        let mut a = raw;
        let n = unwrap_degrees(&mut a);
        assert_eq!(n, 4);
        for w in a.windows(2) {
            assert!((w[1] - w[0]).abs() <= 180.0, "{a:?}");
        }
        for (u, r) in a.iter().zip(raw) {
            let m = (u - r) / 360.0;
            assert!((m - m.round()).abs() < 1e-12);
        }
        assert_eq!(a[2], 181.0);
        assert_eq!(a[3], 190.0);
        assert_eq!(a[4], 175.0);
    }

    #[test]
    fn long_spin_accumulates() {
        // A steady 30°/frame spin wrapped into (−180, 180].
        let raw: Vec<f64> = (0..100)
            .map(|i| {
                let x = (i as f64 * 30.0) % 360.0;
                if x > 180.0 { x - 360.0 } else { x }
            })
            .collect();
        let mut a = raw.clone();
        unwrap_degrees(&mut a);
        for (i, v) in a.iter().enumerate() {
            assert!((v - 30.0 * i as f64).abs() < 1e-9);
        }
    }

    #[test]
    fn empty_single_and_nan_are_fine() {
        let mut e: [f64; 0] = [];
        assert_eq!(unwrap_degrees(&mut e), 0);
        let mut s = [500.0];
        assert_eq!(unwrap_degrees(&mut s), 0);
        assert_eq!(s[0], 500.0);
        let mut n = [170.0, f64::NAN, -170.0];
        unwrap_degrees(&mut n);
        assert_eq!(n[2], 190.0);
    }

    #[test]
    fn exact_half_turn_steps_are_kept() {
        let mut a = [0.0, 180.0, 0.0, -180.0];
        assert_eq!(unwrap_degrees(&mut a), 0);
        assert_eq!(a, [0.0, 180.0, 0.0, -180.0]);
    }
}
