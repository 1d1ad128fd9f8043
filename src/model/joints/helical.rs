//! Helical (screw) joint: rotation q about a unit axis through the origin and
//! translation h·q along it (pitch h, metres per radian). G = exp([a; h a] q),
//! S = [a; h a] constant, ∇S = 0 (paper §4.1).

use super::error::{JointSpecError, unit};
use crate::lie::{Twist, exp_se3};
use crate::model::joint::{Derivatives, Joint, JointKinematics, Limit};
use nalgebra::Vector3;

#[derive(Clone, Debug)]
pub struct Helical {
    screw: Twist,
    limit: Limit,
}

impl Helical {
    pub fn new(axis: Vector3<f64>, pitch: f64) -> Result<Self, JointSpecError> {
        let a = unit(axis, "helical joint axis")?;
        if !pitch.is_finite() {
            return Err(JointSpecError(format!(
                "helical joint pitch must be finite, got {pitch}"
            )));
        }
        let v = a * pitch;
        Ok(Helical {
            screw: Twist::new(a.x, a.y, a.z, v.x, v.y, v.z),
            limit: Limit::NONE,
        })
    }
    pub fn with_limit(mut self, limit: Limit) -> Self {
        self.limit = limit;
        self
    }
}

impl Joint for Helical {
    fn kind(&self) -> &'static str {
        "helical"
    }
    fn dof(&self) -> usize {
        1
    }
    fn kinematics(&self, q: &[f64], want: Derivatives, out: &mut JointKinematics) {
        out.transform = exp_se3(&(self.screw * q[0]));
        if want >= Derivatives::Jacobian {
            out.s[0] = self.screw;
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
