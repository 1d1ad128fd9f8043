//! Prismatic joint: translation by q along a fixed unit axis.

use crate::lie::Twist;
use crate::model::joint::{AxisMotion, Derivatives, Joint, JointAxis, JointKinematics, Limit};
use nalgebra::{Unit, Vector3};

#[derive(Clone, Debug)]
pub struct Prismatic {
    axis: JointAxis,
    limit: Limit,
}

impl Prismatic {
    /// A prismatic joint along `axis` (normalised here). `None` for a zero or non-finite axis.
    pub fn new(axis: Vector3<f64>) -> Option<Self> {
        if !axis.iter().all(|x| x.is_finite()) {
            return None;
        }
        Unit::try_new(axis, 1e-12).map(|axis| Prismatic {
            axis: JointAxis::new(AxisMotion::Translation, axis),
            limit: Limit::NONE,
        })
    }

    pub fn with_limit(mut self, limit: Limit) -> Self {
        self.limit = limit;
        self
    }

    pub fn axis(&self) -> Vector3<f64> {
        self.axis.axis()
    }
}

impl Joint for Prismatic {
    fn kind(&self) -> &'static str {
        "prismatic"
    }

    fn dof(&self) -> usize {
        1
    }

    fn kinematics(&self, q: &[f64], want: Derivatives, out: &mut JointKinematics) {
        out.transform = self.axis.transform(q[0]);
        if want >= Derivatives::Jacobian {
            out.s[0] = self.axis.twist();
        }
        if want >= Derivatives::Hessian {
            out.ds[0][0] = Twist::zeros();
        }
    }

    fn limits(&self) -> Vec<Limit> {
        vec![self.limit]
    }

    fn constant_jacobian(&self) -> bool {
        true
    }

    fn joint_axis(&self) -> Option<JointAxis> {
        Some(self.axis)
    }
}
