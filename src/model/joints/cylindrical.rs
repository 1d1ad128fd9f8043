//! Cylindrical joint: rotation q0 about a unit axis and translation q1 along
//! it. The two motions commute, so S = [[a;0], [0;a]] is constant and ∇S = 0.

use super::error::{JointSpecError, unit};
use crate::lie::{Se3, Twist};
use crate::model::joint::{Derivatives, Joint, JointKinematics, Limit};
use nalgebra::{Rotation3, Unit, Vector3};

#[derive(Clone, Debug)]
pub struct Cylindrical {
    axis: Vector3<f64>,
    limits: [Limit; 2],
}

impl Cylindrical {
    pub fn new(axis: Vector3<f64>) -> Result<Self, JointSpecError> {
        Ok(Cylindrical {
            axis: unit(axis, "cylindrical joint axis")?,
            limits: [Limit::NONE; 2],
        })
    }
    pub fn with_limits(mut self, rotation: Limit, translation: Limit) -> Self {
        self.limits = [rotation, translation];
        self
    }
}

impl Joint for Cylindrical {
    fn kind(&self) -> &'static str {
        "cylindrical"
    }
    fn dof(&self) -> usize {
        2
    }
    fn coordinate_suffixes(&self) -> Vec<String> {
        vec!["angle".into(), "slide".into()]
    }
    fn kinematics(&self, q: &[f64], want: Derivatives, out: &mut JointKinematics) {
        let a = self.axis;
        let r = Rotation3::from_axis_angle(&Unit::new_unchecked(a), q[0]).into_inner();
        out.transform = Se3::new(r, a * q[1]);
        if want >= Derivatives::Jacobian {
            out.s[0] = Twist::new(a.x, a.y, a.z, 0.0, 0.0, 0.0);
            out.s[1] = Twist::new(0.0, 0.0, 0.0, a.x, a.y, a.z);
        }
        if want >= Derivatives::Hessian {
            for i in 0..2 {
                for j in 0..2 {
                    out.ds[i][j] = Twist::zeros();
                }
            }
        }
    }
    fn limits(&self) -> Vec<Limit> {
        self.limits.to_vec()
    }
    fn constant_jacobian(&self) -> bool {
        true
    }
}
