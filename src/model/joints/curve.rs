//! The 1-DOF spline curve joint (paper §5.1, eq. 21–24): a cumulative
//! B-spline on SE(3) through control frames Ǧ_0 … Ǧ_m,
//!   G(q) = Ǧ_0 Π_{j=1..m} exp(ẑ_j B̃_j(q)),  ẑ_j = log(Ǧ_{j−1}⁻¹ Ǧ_j),
//!   B̃_j = Σ_{l ≥ j} B_l  (cumulative basis),
//! which on the span of q reduces to Ǧ_{f} Π_{i=1..p} exp(ẑ_{f+i} B̃_{f+i}(q))
//! (f = first non-zero basis function, p = degree: three factors for cubics).
//! Non-uniform knots are allowed. Cubic with simple knots gives C² motion.
//!
//! Outside the knot domain [q_a, q_b] the joint continues as the screw motion
//! tangent at the end: G(q) = G(q_b) exp(S(q_b)(q − q_b)) (likewise below
//! q_a). It is C¹ there, S stays constant and non-zero, ∇S = 0 — the SE(3)
//! analogue of OpenSim's linear extension of splines.

use super::error::{JointSpecError, jerr};
use super::poe::{PoeFactor, poe_kinematics, poe_sdot_v_dq};
use crate::lie::{Se3, Twist, exp_se3, log_se3, rotation_angle};
use crate::model::joint::{Derivatives, Joint, JointKinematics, Limit, MAX_JOINT_DOF};
use crate::spline::BSplineBasis;
use std::f64::consts::PI;

/// Consecutive control frames must be less than π − this apart in rotation:
/// at π the logarithm (and hence the curve) is ambiguous.
pub const MAX_FRAME_ANGLE: f64 = PI - 1e-6;

#[derive(Clone, Debug)]
pub struct SplineCurveJoint {
    frames: Vec<Se3>,
    /// twists[j−1] = ẑ_j
    twists: Vec<Twist>,
    basis: BSplineBasis,
    limit: Limit,
}

impl SplineCurveJoint {
    /// Control frames on a B-spline basis (degree 2…5, not periodic) with as
    /// many coefficients as frames.
    pub fn new(frames: Vec<Se3>, basis: BSplineBasis) -> Result<Self, JointSpecError> {
        if basis.is_periodic() {
            return jerr("a spline curve joint needs a non-periodic basis");
        }
        if basis.degree() < 2 {
            return jerr(format!(
                "a spline curve joint needs degree ≥ 2 (3 for C² motion), got {}",
                basis.degree()
            ));
        }
        if frames.len() != basis.n_coeffs() {
            return jerr(format!(
                "{} control frames given, but the knot vector defines {} (frames = knots − degree − 1)",
                frames.len(),
                basis.n_coeffs()
            ));
        }
        let twists = relative_twists(&frames)?;
        Ok(SplineCurveJoint {
            frames,
            twists,
            basis,
            limit: Limit::NONE,
        })
    }

    /// Control frames with knots, cubic. `knots` is either the full knot vector
    /// (frames + 4 values), the breakpoints of a clamped cubic (frames − 2
    /// increasing values, ends included), or one parameter per control frame
    /// (frames values, increasing): then a clamped knot vector is built by averaging
    /// (u_{j+3} = (t_j + t_{j+1} + t_{j+2})/3, Piegl & Tiller eq. 9.8), so the
    /// joint passes through the first and last frames at t_0 and t_m.
    pub fn from_knots(frames: Vec<Se3>, knots: &[f64]) -> Result<Self, JointSpecError> {
        let m1 = frames.len();
        if m1 < 4 {
            return jerr(format!(
                "a cubic spline curve joint needs at least 4 control frames, got {m1}"
            ));
        }
        let increasing =
            |k: &[f64]| k.iter().all(|x| x.is_finite()) && k.windows(2).all(|w| w[1] > w[0]);
        let knots = if knots.len() == m1 + 4 {
            knots.to_vec()
        } else if knots.len() == m1 - 2 {
            // the distinct breakpoints of a clamped cubic (ends included)
            if !increasing(knots) {
                return jerr("breakpoints must be finite and strictly increasing");
            }
            let mut k = vec![knots[0]; 3];
            k.extend_from_slice(knots);
            k.extend([knots[knots.len() - 1]; 3]);
            k
        } else if knots.len() == m1 {
            if knots.windows(2).any(|w| w[1] <= w[0] || w[1].is_nan())
                || knots.iter().any(|k| !k.is_finite())
            {
                return jerr("per-frame knot values must be finite and strictly increasing");
            }
            clamped_from_parameters(knots)
        } else {
            return jerr(format!(
                "{} knots for {m1} control frames: give one knot per frame ({m1}), the {} breakpoints of a clamped cubic, or a full cubic knot vector ({})",
                knots.len(),
                m1 - 2,
                m1 + 4
            ));
        };
        let basis = BSplineBasis::new(3, knots)
            .map_err(|e| JointSpecError(format!("spline curve joint knots: {e}")))?;
        Self::new(frames, basis)
    }

    pub fn with_limit(mut self, limit: Limit) -> Self {
        self.limit = limit;
        self
    }
    pub fn frames(&self) -> &[Se3] {
        &self.frames
    }
    pub fn basis(&self) -> &BSplineBasis {
        &self.basis
    }
    /// The knot domain [q_a, q_b] (see the module doc for outside it).
    pub fn domain(&self) -> (f64, f64) {
        self.basis.domain()
    }

    /// Replaces the control frames (same count), re-checking the π rule.
    pub fn set_frames(&mut self, frames: Vec<Se3>) -> Result<(), JointSpecError> {
        if frames.len() != self.frames.len() {
            return jerr("set_frames: the number of control frames cannot change");
        }
        self.twists = relative_twists(&frames)?;
        self.frames = frames;
        Ok(())
    }

    /// Kinematics strictly inside the domain (q clamped into it).
    fn inside(&self, q: f64, want: Derivatives, out: &mut JointKinematics) {
        let (first, f) = self.factors(q, 0.0);
        let p = self.basis.degree();
        poe_kinematics(&self.frames[first], &f[..p], None, 1, want, out);
    }

    /// The index of the first control frame acting at `q` (inside the domain)
    /// and the factors exp(ĝ B̃(q)) after it, the third derivative of each B̃
    /// contracted with the velocity `v` (for [`poe_sdot_v_dq`]).
    fn factors(&self, q: f64, v: f64) -> (usize, [PoeFactor; 5]) {
        let p = self.basis.degree();
        let mut b = [[0.0; 6]; 4];
        let first = self.basis.eval_nonzero(q, 3, &mut b);
        let mut f = [PoeFactor::new(Twist::zeros(), 0.0); 5];
        // cumulative sums from the top: B̃_{first+i} = Σ_{l=i..p} B_{first+l}
        let mut acc = [0.0; 4];
        for i in (1..=p).rev() {
            for d in 0..4 {
                acc[d] += b[d][i];
            }
            f[i - 1] = PoeFactor::of_coordinate3(self.twists[first + i - 1], 0, acc, v);
        }
        (first, f)
    }

    /// Minimum of ‖S(q)‖ over `n` evenly spaced points of the domain, and where:
    /// S must not vanish (paper §5, requirement 2).
    pub fn min_jacobian_norm(&self, n: usize) -> (f64, f64) {
        let (a, b) = self.domain();
        let mut k = JointKinematics::default();
        let mut best = (a, f64::INFINITY);
        for i in 0..=n.max(1) {
            let q = a + (b - a) * i as f64 / n.max(1) as f64;
            self.kinematics(&[q], Derivatives::Jacobian, &mut k);
            let s = k.s[0].norm();
            if s < best.1 {
                best = (q, s);
            }
        }
        best
    }

    /// An error if ‖S(q)‖ falls below `tol` somewhere in the domain.
    pub fn check_jacobian(&self, tol: f64) -> Result<(), JointSpecError> {
        let (q, s) = self.min_jacobian_norm(400);
        if s < tol {
            return jerr(format!(
                "the spline joint's Jacobian nearly vanishes at q = {q:.6} (‖S‖ = {s:.3e} < {tol:.1e}): \
                 the joint would not move there; spread the control frames or remove coincident ones"
            ));
        }
        Ok(())
    }
}

fn relative_twists(frames: &[Se3]) -> Result<Vec<Twist>, JointSpecError> {
    let mut tw = Vec::with_capacity(frames.len().saturating_sub(1));
    for (j, w) in frames.windows(2).enumerate() {
        if w.iter()
            .any(|f| f.r.iter().chain(f.p.iter()).any(|x| !x.is_finite()))
        {
            return jerr(format!("control frame {} is not finite", j));
        }
        let rel = w[0].inv_compose(&w[1]);
        let ang = rotation_angle(&rel.r);
        if ang > MAX_FRAME_ANGLE {
            return jerr(format!(
                "control frames {j} and {} are {:.6} rad apart in rotation (≥ π): the curve between them is ambiguous; insert an intermediate frame",
                j + 1,
                ang
            ));
        }
        tw.push(log_se3(&rel));
    }
    Ok(tw)
}

/// Clamped cubic knot vector from one parameter per control point (averaging).
pub fn clamped_from_parameters(t: &[f64]) -> Vec<f64> {
    let m1 = t.len();
    let mut k = vec![t[0]; 4];
    for j in 1..m1.saturating_sub(3) {
        k.push((t[j] + t[j + 1] + t[j + 2]) / 3.0);
    }
    k.extend([t[m1 - 1]; 4]);
    k
}

/// Natural parameterization (paper §6.1 with the erratum: no square):
/// q̌_0 = q0, q̌_j = q̌_{j−1} + ‖log(Ǧ_{j−1}⁻¹ Ǧ_j)‖ (unweighted twist norm).
pub fn natural_parameters(frames: &[Se3], q0: f64) -> Vec<f64> {
    let mut q = vec![q0];
    for w in frames.windows(2) {
        let last = *q.last().unwrap_or(&q0);
        q.push(last + log_se3(&w[0].inv_compose(&w[1])).norm());
    }
    q
}

impl Joint for SplineCurveJoint {
    fn kind(&self) -> &'static str {
        "spline_curve"
    }
    fn dof(&self) -> usize {
        1
    }
    fn kinematics(&self, q: &[f64], want: Derivatives, out: &mut JointKinematics) {
        let (a, b) = self.domain();
        let q = q[0];
        if q >= a && q <= b {
            self.inside(q, want, out);
            return;
        }
        let qe = if q < a { a } else { b };
        self.inside(qe, Derivatives::Jacobian, out);
        let s = out.s[0];
        out.transform = out.transform.compose(&exp_se3(&(s * (q - qe))));
        if want >= Derivatives::Hessian {
            out.ds[0][0] = Twist::zeros();
        }
    }
    fn sdot_v_dq(&self, q: &[f64], v: &[f64], out: &mut [Twist; MAX_JOINT_DOF]) -> bool {
        let (a, b) = self.domain();
        if q[0] < a || q[0] > b {
            // Past the ends the joint continues as a screw motion: S is constant.
            out[0] = Twist::zeros();
        } else {
            // The head frame is constant and does not enter.
            let (_, f) = self.factors(q[0], v[0]);
            poe_sdot_v_dq(&f[..self.basis.degree()], None, 1, v, out);
        }
        true
    }
    fn limits(&self) -> Vec<Limit> {
        vec![self.limit]
    }
}
