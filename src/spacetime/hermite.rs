//! Hermite interpolation between two end states: the cubic is the baseline
//! every spacetime transition must beat (`fill(m, "hermite")`); the quintic,
//! which also matches accelerations, starts a C² solve.

use super::transition::EndState;
use crate::motion::HermiteCurve;

/// Cubic Hermite curve on [t0, t1] through `a.q`, `b.q` with slopes `a.v`, `b.v`:
/// returns [q, q̇, q̈] at t. A zero-length span returns the start state.
pub fn cubic(t0: f64, t1: f64, a: &EndState, b: &EndState, t: f64) -> [f64; 3] {
    if t1 - t0 <= 0.0 {
        return [a.q, a.v, 0.0];
    }
    // The same curve `fill(m, "hermite")` writes into a motion: one formula for both.
    let curve = HermiteCurve {
        t0,
        t1,
        q0: a.q,
        v0: a.v,
        q1: b.q,
        v1: b.v,
    };
    curve.eval(t.clamp(t0, t1))
}

/// The cubic of [`cubic`] continued beyond [t0, t1] as the same polynomial
/// (not held at its end values), so a blend that adds it to samples past
/// the ends stays smooth across them: held constant, it bent the laid
/// example's velocity at the gap's edges (issue 42: a 0.4 rad/s kink made a
/// 670 % BW spike in the ground residual at the first frame of a fill).
pub fn cubic_continued(t0: f64, t1: f64, a: &EndState, b: &EndState, t: f64) -> [f64; 3] {
    if t1 - t0 <= 0.0 {
        return [a.q + a.v * (t - t0), a.v, 0.0];
    }
    HermiteCurve {
        t0,
        t1,
        q0: a.q,
        v0: a.v,
        q1: b.q,
        v1: b.v,
    }
    .eval(t)
}

/// Quintic Hermite curve on [t0, t1] matching q, q̇, q̈ at both ends: [q, q̇, q̈] at t.
pub fn quintic(t0: f64, t1: f64, a: &EndState, b: &EndState, t: f64) -> [f64; 3] {
    let h = t1 - t0;
    if h <= 0.0 {
        return [a.q, a.v, a.a];
    }
    let s = ((t - t0) / h).clamp(0.0, 1.0);
    // Polynomial in s: c0 + c1 s + … + c5 s⁵ with derivatives scaled by h.
    let (p0, v0, a0) = (a.q, a.v * h, a.a * h * h);
    let (p1, v1, a1) = (b.q, b.v * h, b.a * h * h);
    let c0 = p0;
    let c1 = v0;
    let c2 = 0.5 * a0;
    let c3 = 10.0 * (p1 - p0) - 6.0 * v0 - 4.0 * v1 - 1.5 * a0 + 0.5 * a1;
    let c4 = -15.0 * (p1 - p0) + 8.0 * v0 + 7.0 * v1 + 1.5 * a0 - a1;
    let c5 = 6.0 * (p1 - p0) - 3.0 * (v0 + v1) - 0.5 * a0 + 0.5 * a1;
    let q = c0 + s * (c1 + s * (c2 + s * (c3 + s * (c4 + s * c5))));
    let ds = c1 + s * (2.0 * c2 + s * (3.0 * c3 + s * (4.0 * c4 + s * 5.0 * c5)));
    let dds = 2.0 * c2 + s * (6.0 * c3 + s * (12.0 * c4 + s * 20.0 * c5));
    [q, ds / h, dds / (h * h)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_continued_cubic_is_the_cubic_inside_and_smooth_past_the_ends() {
        let (a, b) = (
            EndState {
                q: 0.2,
                v: -0.5,
                a: 0.0,
            },
            EndState {
                q: 1.0,
                v: 0.3,
                a: 0.0,
            },
        );
        for t in [0.1, 0.5, 0.9] {
            assert_eq!(
                cubic(0.0, 1.0, &a, &b, t),
                cubic_continued(0.0, 1.0, &a, &b, t)
            );
        }
        // just past t0 the slope is still a.v, not 0 as the held cubic's
        let before = cubic_continued(0.0, 1.0, &a, &b, -1e-3);
        assert!((before[1] - a.v).abs() < 1e-2, "{before:?}");
        assert_eq!(cubic(0.0, 1.0, &a, &b, -1e-3)[0], a.q);
    }

    fn st(q: f64, v: f64, a: f64) -> EndState {
        EndState { q, v, a }
    }

    #[test]
    fn cubic_matches_ends_and_is_consistent() {
        let (a, b) = (st(0.3, -1.0, 0.0), st(4.0, 2.5, 0.0));
        let (t0, t1) = (1.0, 1.6);
        let s = cubic(t0, t1, &a, &b, t0);
        assert!((s[0] - a.q).abs() < 1e-15 && (s[1] - a.v).abs() < 1e-13);
        let e = cubic(t0, t1, &a, &b, t1);
        assert!((e[0] - b.q).abs() < 1e-14 && (e[1] - b.v).abs() < 1e-13);
        let t = 1.27;
        let h = 1e-6;
        let (p, m) = (cubic(t0, t1, &a, &b, t + h), cubic(t0, t1, &a, &b, t - h));
        let c = cubic(t0, t1, &a, &b, t);
        assert!(((p[0] - m[0]) / (2.0 * h) - c[1]).abs() < 1e-6);
        assert!(((p[1] - m[1]) / (2.0 * h) - c[2]).abs() < 1e-5);
    }

    #[test]
    fn quintic_matches_all_three_at_both_ends() {
        let (a, b) = (st(0.3, -1.0, 7.0), st(-4.0, 2.5, -3.0));
        let (t0, t1) = (0.5, 5.5);
        let s = quintic(t0, t1, &a, &b, t0);
        let e = quintic(t0, t1, &a, &b, t1);
        for (x, y) in s
            .iter()
            .zip([a.q, a.v, a.a])
            .chain(e.iter().zip([b.q, b.v, b.a]))
        {
            assert!((x - y).abs() < 1e-11, "{x} vs {y}");
        }
        let t = 2.0;
        let h = 1e-5;
        let (p, m) = (
            quintic(t0, t1, &a, &b, t + h),
            quintic(t0, t1, &a, &b, t - h),
        );
        let c = quintic(t0, t1, &a, &b, t);
        assert!(((p[0] - m[0]) / (2.0 * h) - c[1]).abs() < 1e-7);
        assert!(((p[1] - m[1]) / (2.0 * h) - c[2]).abs() < 1e-7);
    }
}
