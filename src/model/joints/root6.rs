//! The 6-DOF root (free) joint of the paper's human model: three translations
//! along the parent's x, y, z axes, then three body-fixed Euler rotations
//! (order chosen; BVH uses "zxy"). Coordinates: tx, ty, tz, r_a, r_b, r_c.
//! The rotation part has the gimbal-lock singularity of [`super::spherical`].

use super::poe::{PoeFactor, poe_kinematics, poe_sdot_v_dq};
use super::spherical::EulerOrder;
use crate::lie::{Se3, Twist};
use crate::model::joint::{Derivatives, Joint, JointKinematics, Limit, MAX_JOINT_DOF};

#[derive(Clone, Debug)]
pub struct Root6 {
    order: EulerOrder,
}

impl Root6 {
    pub fn new(order: EulerOrder) -> Self {
        Root6 { order }
    }
    pub fn order(&self) -> EulerOrder {
        self.order
    }

    fn factors(&self, q: &[f64]) -> [PoeFactor; 6] {
        let t = |k: usize| {
            let a = EulerOrder::axis(k);
            PoeFactor::of_coordinate(
                Twist::new(0.0, 0.0, 0.0, a.x, a.y, a.z),
                k,
                [q[k], 1.0, 0.0],
            )
        };
        let r = self.order.factors(q, 3);
        [t(0), t(1), t(2), r[0], r[1], r[2]]
    }
}

impl Joint for Root6 {
    fn kind(&self) -> &'static str {
        "root6"
    }
    fn dof(&self) -> usize {
        6
    }
    fn coordinate_suffixes(&self) -> Vec<String> {
        let mut v: Vec<String> = vec!["tx".into(), "ty".into(), "tz".into()];
        v.extend(
            self.order
                .0
                .iter()
                .map(|&i| format!("r{}", ['x', 'y', 'z'][i])),
        );
        v
    }
    fn kinematics(&self, q: &[f64], want: Derivatives, out: &mut JointKinematics) {
        poe_kinematics(&Se3::identity(), &self.factors(q), None, 6, want, out);
    }
    fn sdot_v_dq(&self, q: &[f64], v: &[f64], out: &mut [Twist; MAX_JOINT_DOF]) -> bool {
        // φ linear in q: no third-derivative term of its own.
        poe_sdot_v_dq(&self.factors(q), None, 6, v, out);
        true
    }
    fn limits(&self) -> Vec<Limit> {
        vec![Limit::NONE; 6]
    }
}
