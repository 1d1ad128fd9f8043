//! Universal joint: G = exp([a0;0] q0) · exp([a1;0] q1), two rotations about
//! axes through the origin (a0 in the parent, a1 in the intermediate frame).
//! S = [Ad⁻¹_{exp(a1 q1)} s0, s1], ∂s0*/∂q1 = ad_{s0*} s1 (paper §4.1), via
//! the product-of-exponentials recursion.

use super::error::{JointSpecError, jerr, unit};
use super::poe::{PoeFactor, poe_kinematics, poe_sdot_v_dq};
use crate::lie::{Se3, Twist};
use crate::model::joint::{Derivatives, Joint, JointKinematics, Limit, MAX_JOINT_DOF};
use nalgebra::Vector3;

#[derive(Clone, Debug)]
pub struct Universal {
    axes: [Vector3<f64>; 2],
    limits: [Limit; 2],
}

impl Universal {
    /// The axes must not be parallel (the joint would lose a degree of freedom).
    pub fn new(a0: Vector3<f64>, a1: Vector3<f64>) -> Result<Self, JointSpecError> {
        let a0 = unit(a0, "universal joint first axis")?;
        let a1 = unit(a1, "universal joint second axis")?;
        if a0.cross(&a1).norm() < 1e-9 {
            return jerr("universal joint axes are parallel: give two independent axes");
        }
        Ok(Universal {
            axes: [a0, a1],
            limits: [Limit::NONE; 2],
        })
    }
    pub fn with_limits(mut self, l0: Limit, l1: Limit) -> Self {
        self.limits = [l0, l1];
        self
    }

    fn factors(&self, q: &[f64]) -> [PoeFactor; 2] {
        [
            PoeFactor::of_coordinate(rot_twist(&self.axes[0]), 0, [q[0], 1.0, 0.0]),
            PoeFactor::of_coordinate(rot_twist(&self.axes[1]), 1, [q[1], 1.0, 0.0]),
        ]
    }
}

pub(crate) fn rot_twist(a: &Vector3<f64>) -> Twist {
    Twist::new(a.x, a.y, a.z, 0.0, 0.0, 0.0)
}

impl Joint for Universal {
    fn kind(&self) -> &'static str {
        "universal"
    }
    fn dof(&self) -> usize {
        2
    }
    fn kinematics(&self, q: &[f64], want: Derivatives, out: &mut JointKinematics) {
        poe_kinematics(&Se3::identity(), &self.factors(q), None, 2, want, out);
    }
    fn sdot_v_dq(&self, q: &[f64], v: &[f64], out: &mut [Twist; MAX_JOINT_DOF]) -> bool {
        // φ linear in q: no third-derivative term of its own.
        poe_sdot_v_dq(&self.factors(q), None, 2, v, out);
        true
    }
    fn limits(&self) -> Vec<Limit> {
        self.limits.to_vec()
    }
}
