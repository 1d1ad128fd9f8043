//! Fixed (weld) joint: a constant transform, no coordinates.

use crate::lie::Se3;
use crate::model::joint::{Derivatives, Joint, JointKinematics};

#[derive(Clone, Debug)]
pub struct Fixed {
    pub transform: Se3,
}

impl Fixed {
    pub fn new(transform: Se3) -> Self {
        Fixed { transform }
    }
}

impl Joint for Fixed {
    fn kind(&self) -> &'static str {
        "fixed"
    }
    fn dof(&self) -> usize {
        0
    }
    fn kinematics(&self, _q: &[f64], _want: Derivatives, out: &mut JointKinematics) {
        out.transform = self.transform;
    }
    fn constant_jacobian(&self) -> bool {
        true
    }
}
