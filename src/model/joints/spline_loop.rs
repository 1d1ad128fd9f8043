//! A closed 1-DOF spline curve joint: the cumulative cubic B-spline on SE(3)
//! of the paper (eq. 21–24) with uniform *periodic* knots, so the curve through
//! control frames Ǧ_0 … Ǧ_{m−1} closes on itself (Ǧ_m = Ǧ_0) and q can run
//! round it for ever (a bead on a closed wire). On the span s ≤ q/h < s + 1
//! only four frames matter (eq. 24):
//!   G(q) = Ǧ_{s−3} Π_{l=1..3} exp(ẑ_{s−3+l} B̃_l(t)),   t = q/h − s,
//! with ẑ_j = log(Ǧ_{j−1}⁻¹ Ǧ_j) (indices modulo m) and the cumulative uniform
//! cubic basis B̃_1 = 1 − (1−t)³/6, B̃_2 = (1 + 3t + 3t² − 2t³)/6, B̃_3 = t³/6.

use super::curve::MAX_FRAME_ANGLE;
use super::error::{JointSpecError, jerr};
use super::poe::{PoeFactor, poe_kinematics, poe_sdot_v_dq};
use crate::lie::{Se3, Twist, log_se3, rotation_angle};
use crate::model::joint::{Derivatives, Joint, JointKinematics, MAX_JOINT_DOF};

#[derive(Clone, Debug)]
pub struct SplineLoopJoint {
    frames: Vec<Se3>,
    /// twists[j] = ẑ_j = log(Ǧ_{j−1}⁻¹ Ǧ_j), j modulo m.
    twists: Vec<Twist>,
    /// Knot spacing: one lap is `frames.len() · h`.
    h: f64,
}

impl SplineLoopJoint {
    /// A closed curve through `frames` (at least 4) with one lap every `period` of q.
    pub fn new(frames: Vec<Se3>, period: f64) -> Result<Self, JointSpecError> {
        let m = frames.len();
        if m < 4 {
            return jerr(format!(
                "a closed spline curve joint needs at least 4 control frames, got {m}"
            ));
        }
        if !(period.is_finite() && period > 0.0) {
            return jerr(format!(
                "the period must be a finite number > 0, got {period}"
            ));
        }
        let mut twists = Vec::with_capacity(m);
        for j in 0..m {
            let (a, b) = (&frames[(j + m - 1) % m], &frames[j]);
            if !a.r.iter().chain(a.p.iter()).all(|x| x.is_finite()) {
                return jerr(format!("control frame {} is not finite", (j + m - 1) % m));
            }
            let rel = a.inv_compose(b);
            if rotation_angle(&rel.r) > MAX_FRAME_ANGLE {
                return jerr(format!(
                    "control frames {} and {j} are π apart in rotation: the curve between them is ambiguous; insert a frame",
                    (j + m - 1) % m
                ));
            }
            twists.push(log_se3(&rel));
        }
        Ok(SplineLoopJoint {
            frames,
            twists,
            h: period / m as f64,
        })
    }

    pub fn frames(&self) -> &[Se3] {
        &self.frames
    }
    /// The q of one lap.
    pub fn period(&self) -> f64 {
        self.h * self.frames.len() as f64
    }
}

impl Joint for SplineLoopJoint {
    fn kind(&self) -> &'static str {
        "spline_loop"
    }
    fn dof(&self) -> usize {
        1
    }
    fn kinematics(&self, q: &[f64], want: Derivatives, out: &mut JointKinematics) {
        let (head, f) = self.factors(q[0], 0.0);
        poe_kinematics(&self.frames[head], &f, None, 1, want, out);
    }
    fn sdot_v_dq(&self, q: &[f64], v: &[f64], out: &mut [Twist; MAX_JOINT_DOF]) -> bool {
        let (_, f) = self.factors(q[0], v[0]);
        poe_sdot_v_dq(&f, None, 1, v, out);
        true
    }
}

impl SplineLoopJoint {
    /// The index of the head control frame at `q` and the three factors after
    /// it, each cumulative basis function's third derivative contracted with
    /// the velocity `v` (for [`poe_sdot_v_dq`]).
    fn factors(&self, q: f64, v: f64) -> (usize, [PoeFactor; 3]) {
        let m = self.frames.len() as i64;
        let u = q / self.h;
        let s = u.floor();
        let t = u - s;
        let s = (s as i64).rem_euclid(m);
        let idx = |k: i64| (s + k).rem_euclid(m) as usize;
        let (h, h2) = (self.h, self.h * self.h);
        let h3 = h2 * h;
        let w = 1.0 - t;
        // Cumulative basis values and their first three q-derivatives.
        let b = [
            [1.0 - w * w * w / 6.0, w * w / 2.0 / h, -w / h2, 1.0 / h3],
            [
                (1.0 + 3.0 * t + 3.0 * t * t - 2.0 * t * t * t) / 6.0,
                (1.0 + 2.0 * t - 2.0 * t * t) / 2.0 / h,
                (1.0 - 2.0 * t) / h2,
                -2.0 / h3,
            ],
            [t * t * t / 6.0, t * t / 2.0 / h, t / h2, 1.0 / h3],
        ];
        let f: [PoeFactor; 3] = std::array::from_fn(|l| {
            PoeFactor::of_coordinate3(self.twists[idx(l as i64 - 2)], 0, b[l], v)
        });
        (idx(-3), f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lie::so3::exp_so3;
    use nalgebra::Vector3;

    fn ring() -> SplineLoopJoint {
        let frames = (0..8)
            .map(|k| {
                let a = k as f64 * std::f64::consts::TAU / 8.0;
                let r = exp_so3(&Vector3::new(0.0, 0.0, a));
                Se3::new(r, Vector3::new(a.cos(), a.sin(), 0.1 * (2.0 * a).sin()))
            })
            .collect();
        SplineLoopJoint::new(frames, std::f64::consts::TAU).unwrap()
    }

    #[test]
    fn closes_on_itself_with_continuous_jacobian() {
        let j = ring();
        let (mut a, mut b) = (JointKinematics::default(), JointKinematics::default());
        for q in [0.0, 0.3, 2.0] {
            j.kinematics(&[q], Derivatives::Hessian, &mut a);
            j.kinematics(&[q + j.period()], Derivatives::Hessian, &mut b);
            assert!((a.transform.p - b.transform.p).norm() < 1e-12);
            assert!((a.s[0] - b.s[0]).norm() < 1e-12);
        }
        // continuity across a knot (q = h): left and right limits agree
        let h = j.period() / 8.0;
        j.kinematics(&[h - 1e-9], Derivatives::Hessian, &mut a);
        j.kinematics(&[h + 1e-9], Derivatives::Hessian, &mut b);
        assert!((a.transform.p - b.transform.p).norm() < 1e-8);
        assert!((a.s[0] - b.s[0]).norm() < 1e-7);
        assert!((a.ds[0][0] - b.ds[0][0]).norm() < 1e-6);
    }

    #[test]
    fn jacobian_matches_finite_differences() {
        let j = ring();
        let (mut a, mut b, mut c) = (
            JointKinematics::default(),
            JointKinematics::default(),
            JointKinematics::default(),
        );
        let (q, e) = (1.234, 1e-6);
        j.kinematics(&[q], Derivatives::Hessian, &mut a);
        j.kinematics(&[q + e], Derivatives::Hessian, &mut b);
        j.kinematics(&[q - e], Derivatives::Hessian, &mut c);
        let fd = log_se3(&c.transform.inv_compose(&b.transform)) / (2.0 * e);
        assert!((fd - a.s[0]).norm() < 1e-6, "{fd} vs {}", a.s[0]);
        let dfd = (b.s[0] - c.s[0]) / (2.0 * e);
        assert!((dfd - a.ds[0][0]).norm() < 1e-5);
    }
}
