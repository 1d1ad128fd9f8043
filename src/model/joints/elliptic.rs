//! Elliptic joint (paper eq. 17–20): the child slides along the ellipse
//! (a sin q, −b cos q, 0) of the parent's x–y plane, turning so that it stays
//! tangent to it:
//!   G(q) = H · [exp([k] φ(q)), p(q)],   φ = atan2(b sin q, a cos q)
//!   S = [φ' k;  e^{−[k]φ} p'(q)]
//!   dS/dq = [φ'' k;  e^{−[k]φ} (p'' − φ' k × p')]
//! with p' = (a cos q, b sin q, 0) and p'' = (−a sin q, b cos q, 0). For k = z
//! this is the paper's eq. (20); the form above holds for any unit k because
//! [k] commutes with exp([k]φ). H is a constant placement (identity by default).
//! The dynamics' third-derivative term differentiates dS/dq once more the same way:
//!   d²S/dq² = [φ''' k;  e^{−[k]φ} (X' − φ' k × X)],  X = p'' − φ' k × p',
//!   X' = p''' − φ'' k × p' − φ' k × p'',  p''' = −p'.

use super::error::{JointSpecError, jerr, unit};
use crate::lie::{Se3, Twist, exp_so3};
use crate::model::joint::{Derivatives, Joint, JointKinematics, MAX_JOINT_DOF};
use nalgebra::Vector3;

#[derive(Clone, Debug)]
pub struct Elliptic {
    a: f64,
    b: f64,
    k: Vector3<f64>,
    h: Se3,
}

impl Elliptic {
    /// Semi-axes a, b > 0, rotation axis z.
    pub fn new(a: f64, b: f64) -> Result<Self, JointSpecError> {
        Self::with_axis(a, b, Vector3::z(), Se3::identity())
    }

    pub fn with_axis(a: f64, b: f64, k: Vector3<f64>, h: Se3) -> Result<Self, JointSpecError> {
        if !(a.is_finite() && b.is_finite() && a > 0.0 && b > 0.0) {
            return jerr(format!(
                "elliptic joint semi-axes must be positive and finite, got a = {a}, b = {b}"
            ));
        }
        Ok(Elliptic {
            a,
            b,
            k: unit(k, "elliptic joint rotation axis")?,
            h,
        })
    }
}

impl Joint for Elliptic {
    fn kind(&self) -> &'static str {
        "elliptic"
    }
    fn dof(&self) -> usize {
        1
    }
    fn kinematics(&self, q: &[f64], want: Derivatives, out: &mut JointKinematics) {
        let (a, b, k) = (self.a, self.b, self.k);
        let (s, c) = q[0].sin_cos();
        let phi = (b * s).atan2(a * c);
        let r = exp_so3(&(k * phi));
        let p = Vector3::new(a * s, -b * c, 0.0);
        out.transform = self.h.compose(&Se3::new(r, p));
        if want < Derivatives::Jacobian {
            return;
        }
        // φ' = ab / D, D = a² cos² q + b² sin² q
        let d = a * a * c * c + b * b * s * s;
        let dphi = a * b / d;
        let dp = Vector3::new(a * c, b * s, 0.0);
        let v = r.transpose() * dp;
        let w = k * dphi;
        out.s[0] = Twist::new(w.x, w.y, w.z, v.x, v.y, v.z);
        if want >= Derivatives::Hessian {
            let dd = 2.0 * (b * b - a * a) * s * c;
            let ddphi = -a * b * dd / (d * d);
            let ddp = Vector3::new(-a * s, b * c, 0.0);
            let dv = r.transpose() * (ddp - k.cross(&dp) * dphi);
            let dw = k * ddphi;
            out.ds[0][0] = Twist::new(dw.x, dw.y, dw.z, dv.x, dv.y, dv.z);
        }
    }
    fn sdot_v_dq(&self, q: &[f64], v: &[f64], out: &mut [Twist; MAX_JOINT_DOF]) -> bool {
        // Ṡ q̇ = dS/dq q̇², so its q-derivative is d²S/dq² q̇².
        let (a, b, k) = (self.a, self.b, self.k);
        let (s, c) = q[0].sin_cos();
        let phi = (b * s).atan2(a * c);
        let rt = exp_so3(&(k * phi)).transpose();
        // φ' = ab / D with D = a² cos² q + b² sin² q, and its next two derivatives.
        let d = a * a * c * c + b * b * s * s;
        let d1 = 2.0 * (b * b - a * a) * s * c;
        let d2 = 2.0 * (b * b - a * a) * (c * c - s * s);
        let dphi = a * b / d;
        let ddphi = -a * b * d1 / (d * d);
        let dddphi = -a * b * (d2 / (d * d) - 2.0 * d1 * d1 / (d * d * d));
        let dp = Vector3::new(a * c, b * s, 0.0);
        let ddp = Vector3::new(-a * s, b * c, 0.0);
        let x = ddp - k.cross(&dp) * dphi;
        let dx = -dp - k.cross(&dp) * ddphi - k.cross(&ddp) * dphi;
        let dv = rt * (dx - k.cross(&x) * dphi) * (v[0] * v[0]);
        let dw = k * (dddphi * v[0] * v[0]);
        out[0] = Twist::new(dw.x, dw.y, dw.z, dv.x, dv.y, dv.z);
        true
    }
}
