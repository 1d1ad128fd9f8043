//! Prismatic joint: translation by q along a fixed unit axis.

use crate::lie::{Se3, Twist};
use crate::model::joint::{Derivatives, Joint, JointKinematics, Limit};
use nalgebra::{Unit, Vector3};

#[derive(Clone, Debug)]
pub struct Prismatic {
    axis: Unit<Vector3<f64>>,
    limit: Limit,
}

impl Prismatic {
    /// A prismatic joint along `axis` (normalised here). `None` for a zero or non-finite axis.
    pub fn new(axis: Vector3<f64>) -> Option<Self> {
        if !axis.iter().all(|x| x.is_finite()) {
            return None;
        }
        Unit::try_new(axis, 1e-12).map(|axis| Prismatic {
            axis,
            limit: Limit::NONE,
        })
    }

    pub fn with_limit(mut self, limit: Limit) -> Self {
        self.limit = limit;
        self
    }

    pub fn axis(&self) -> Vector3<f64> {
        self.axis.into_inner()
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
        out.transform = Se3::from_translation(self.axis.into_inner() * q[0]);
        if want >= Derivatives::Jacobian {
            let a = self.axis;
            out.s[0] = Twist::new(0.0, 0.0, 0.0, a.x, a.y, a.z);
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
}
