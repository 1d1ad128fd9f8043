//! The n-DOF spline joint (paper eq. 25–26): six exponentials of constant
//! basis twists, each scaled by a tensor-product B-spline of the coordinates:
//!   G(q) = H · Π_{j=1..6} exp(ê_j φ_j(q)).
//! Like Euler angles, the rotation part can meet singularities; choose the
//! basis twists to keep them outside the joint limits.

use super::error::{JointSpecError, jerr};
use super::poe::{PoeFactor, poe_kinematics, poe_sdot_v_dq};
use crate::lie::{Se3, Twist};
use crate::model::joint::{Derivatives, Joint, JointKinematics, Limit, MAX_JOINT_DOF};
use crate::spline::TensorSpline;

#[derive(Clone, Debug)]
pub struct SplineJoint {
    head: Se3,
    twists: [Twist; 6],
    phis: Vec<TensorSpline>,
    n: usize,
}

impl SplineJoint {
    /// The usual basis: translations along x, y, z, then rotations about x, y, z.
    pub fn standard_twists() -> [Twist; 6] {
        let mut t = [Twist::zeros(); 6];
        for (k, tw) in t.iter_mut().enumerate() {
            tw[(k + 3) % 6] = 1.0;
        }
        t
    }

    /// `phis` are six tensor splines of the same number n of coordinates (n ≤ 6).
    pub fn new(
        head: Se3,
        twists: [Twist; 6],
        phis: Vec<TensorSpline>,
    ) -> Result<Self, JointSpecError> {
        if phis.len() != 6 {
            return jerr(format!(
                "an n-DOF spline joint needs 6 spline functions (one per basis twist), got {}",
                phis.len()
            ));
        }
        let n = phis[0].dim();
        if n == 0 || n > MAX_JOINT_DOF || phis.iter().any(|p| p.dim() != n) {
            return jerr(
                "the six spline functions of an n-DOF spline joint must all take the same number (1–6) of coordinates",
            );
        }
        if twists.iter().any(|t| t.iter().any(|x| !x.is_finite())) {
            return jerr("basis twists must be finite");
        }
        Ok(SplineJoint {
            head,
            twists,
            phis,
            n,
        })
    }

    pub fn twists(&self) -> &[Twist; 6] {
        &self.twists
    }
    pub fn functions(&self) -> &[TensorSpline] {
        &self.phis
    }
    /// The knot range of each coordinate (of the first function); outside it the
    /// splines continue with their end polynomials.
    pub fn domain(&self) -> Vec<(f64, f64)> {
        self.phis[0].bases().iter().map(|b| b.domain()).collect()
    }
}

impl Joint for SplineJoint {
    fn kind(&self) -> &'static str {
        "spline"
    }
    fn dof(&self) -> usize {
        self.n
    }
    fn kinematics(&self, q: &[f64], want: Derivatives, out: &mut JointKinematics) {
        poe_kinematics(&self.head, &self.factors(q, None), None, self.n, want, out);
    }
    fn sdot_v_dq(&self, q: &[f64], v: &[f64], out: &mut [Twist; MAX_JOINT_DOF]) -> bool {
        poe_sdot_v_dq(&self.factors(q, Some(v)), None, self.n, v, out);
        true
    }
    fn limits(&self) -> Vec<Limit> {
        vec![Limit::NONE; self.n]
    }
}

impl SplineJoint {
    /// The six factors at `q`; with `v`, each also carries its third
    /// derivative contracted with the velocity (for [`poe_sdot_v_dq`]).
    fn factors(&self, q: &[f64], v: Option<&[f64]>) -> [PoeFactor; 6] {
        let mut f = [PoeFactor::new(Twist::zeros(), 0.0); 6];
        for (k, fk) in f.iter_mut().enumerate() {
            let e = self.phis[k].eval(q);
            *fk = PoeFactor::new(self.twists[k], e.value);
            for i in 0..self.n {
                fk.dphi[i] = e.grad[i];
                for j in 0..self.n {
                    fk.ddphi[i][j] = e.hess[i][j];
                }
            }
            if let Some(v) = v {
                fk.dddphi_vv = self.phis[k].third_vv(q, v);
            }
        }
        f
    }
}
