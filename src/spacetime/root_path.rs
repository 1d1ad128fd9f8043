//! Root motion over a transition (Rose §3.2.1): the root is kinematic.
//!
//! The floor is the x–z plane (y up). Horizontally the root velocity is
//! interpolated linearly from v₁ (end of the first motion, t₁) to v₂ (start of
//! the second, t₂) and integrated from p(t₁):
//!
//!   p(t) = p(t₁) + v₁ (t − t₁) + (v₂ − v₁) (t − t₁)² / (2T),   T = t₂ − t₁,
//!
//! a C¹ path that ends where the integration takes it, generally not where the
//! second motion starts; the caller translates the second motion in x–z by
//! [`RootTransition::shift`] so the two join up (a walk followed by a run
//! recorded elsewhere in the room). Vertically the paper interpolates y
//! linearly; we use the cubic Hermite curve between the same end heights and
//! vertical velocities, which keeps y C¹ like x–z (and is linear when both end
//! velocities equal the secant slope).

use super::error::{SpError, invalid};
use super::hermite;
use super::transition::EndState;

/// The root's horizontal and vertical states at both ends of a gap.
#[derive(Clone, Debug, PartialEq)]
pub struct RootTransition {
    pub t1: f64,
    pub t2: f64,
    /// x, z at t₁ and their velocities at t₁ and t₂.
    pub p1: [f64; 2],
    pub v1: [f64; 2],
    pub v2: [f64; 2],
    /// y at both ends (position and velocity).
    pub y1: EndState,
    pub y2: EndState,
}

impl RootTransition {
    pub fn new(
        t1: f64,
        t2: f64,
        p1: [f64; 2],
        v1: [f64; 2],
        v2: [f64; 2],
        y1: EndState,
        y2: EndState,
    ) -> Result<Self, SpError> {
        if !(t1.is_finite() && t2.is_finite()) || t2 <= t1 {
            return Err(invalid(format!(
                "root transition span [{t1}, {t2}] must have positive finite length"
            )));
        }
        let all = [
            p1[0], p1[1], v1[0], v1[1], v2[0], v2[1], y1.q, y1.v, y2.q, y2.v,
        ];
        if all.iter().any(|v| !v.is_finite()) {
            return Err(invalid(
                "the root's end states around the gap are not finite",
            ));
        }
        Ok(RootTransition {
            t1,
            t2,
            p1,
            v1,
            v2,
            y1,
            y2,
        })
    }

    /// Horizontal [x, z] position, velocity and acceleration at t (clamped into the gap).
    pub fn xz(&self, t: f64) -> [[f64; 2]; 3] {
        let tt = self.t2 - self.t1;
        let s = (t.clamp(self.t1, self.t2)) - self.t1;
        let mut out = [[0.0; 2]; 3];
        #[allow(clippy::needless_range_loop)] // i indexes four arrays at once
        for i in 0..2 {
            let dv = self.v2[i] - self.v1[i];
            out[0][i] = self.p1[i] + self.v1[i] * s + dv * s * s / (2.0 * tt);
            out[1][i] = self.v1[i] + dv * s / tt;
            out[2][i] = dv / tt;
        }
        out
    }

    /// y, ẏ, ÿ at t.
    pub fn y(&self, t: f64) -> [f64; 3] {
        hermite::cubic(self.t1, self.t2, &self.y1, &self.y2, t)
    }

    /// Where the integrated path ends: p(t₂) = p(t₁) + T (v₁ + v₂)/2.
    pub fn end_xz(&self) -> [f64; 2] {
        self.xz(self.t2)[0]
    }

    /// The x–z translation to apply to the motion after the gap so that it
    /// starts at p(t₂), given where it starts now.
    pub fn shift(&self, second_start_xz: [f64; 2]) -> [f64; 2] {
        let e = self.end_xz();
        [e[0] - second_start_xz[0], e[1] - second_start_xz[1]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rt(v1: [f64; 2], v2: [f64; 2]) -> RootTransition {
        RootTransition::new(
            1.0,
            1.6,
            [0.5, -2.0],
            v1,
            v2,
            EndState {
                q: 0.9,
                v: 0.1,
                a: 0.0,
            },
            EndState {
                q: 0.95,
                v: -0.2,
                a: 0.0,
            },
        )
        .unwrap()
    }

    #[test]
    fn matches_velocities_and_integrates_the_linear_velocity() {
        let r = rt([1.2, 0.1], [3.0, -0.4]);
        let s = r.xz(1.0);
        assert_eq!(s[0], [0.5, -2.0]);
        assert_eq!(s[1], [1.2, 0.1]);
        let e = r.xz(1.6);
        assert!((e[1][0] - 3.0).abs() < 1e-14 && (e[1][1] + 0.4).abs() < 1e-14);
        // trapezoid of a linear velocity is exact
        let end = r.end_xz();
        assert!((end[0] - (0.5 + 0.6 * (1.2 + 3.0) / 2.0)).abs() < 1e-14);
        assert!((end[1] - (-2.0 + 0.6 * (0.1 - 0.4) / 2.0)).abs() < 1e-14);
        // derivative consistency
        let h = 1e-6;
        let d = (r.xz(1.3 + h)[0][0] - r.xz(1.3 - h)[0][0]) / (2.0 * h);
        assert!((d - r.xz(1.3)[1][0]).abs() < 1e-8);
    }

    #[test]
    fn shift_moves_the_second_motion_onto_the_path() {
        let r = rt([1.0, 0.0], [1.0, 0.0]);
        // the run was recorded 3 m away
        let sh = r.shift([3.6, 1.0]);
        assert!((sh[0] - (1.1 - 3.6)).abs() < 1e-14 && (sh[1] - (-2.0 - 1.0)).abs() < 1e-14);
    }

    #[test]
    fn y_is_c1_at_both_ends() {
        let r = rt([0.0; 2], [0.0; 2]);
        let a = r.y(1.0);
        let b = r.y(1.6);
        assert!((a[0] - 0.9).abs() < 1e-15 && (a[1] - 0.1).abs() < 1e-12);
        assert!((b[0] - 0.95).abs() < 1e-15 && (b[1] + 0.2).abs() < 1e-12);
    }

    #[test]
    fn degenerate_spans_are_errors() {
        let y = EndState::default();
        assert!(RootTransition::new(1.0, 1.0, [0.0; 2], [0.0; 2], [0.0; 2], y, y).is_err());
        assert!(RootTransition::new(1.0, 0.0, [0.0; 2], [0.0; 2], [0.0; 2], y, y).is_err());
        assert!(RootTransition::new(0.0, 1.0, [f64::NAN, 0.0], [0.0; 2], [0.0; 2], y, y).is_err());
    }
}
