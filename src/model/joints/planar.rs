//! Planar joint: translations q0, q1 along two orthogonal in-plane axes u and
//! v = n × u, then rotation q2 about the plane normal n:
//! G = exp([0;u] q0) exp([0;v] q1) exp([n;0] q2).

use super::error::{JointSpecError, jerr, unit};
use super::poe::{PoeFactor, poe_kinematics, poe_sdot_v_dq};
use crate::lie::{Se3, Twist};
use crate::model::joint::{Derivatives, Joint, JointKinematics, Limit, MAX_JOINT_DOF};
use nalgebra::Vector3;

#[derive(Clone, Debug)]
pub struct Planar {
    u: Vector3<f64>,
    v: Vector3<f64>,
    n: Vector3<f64>,
}

impl Planar {
    /// A plane with normal `normal`; `u` is the in-plane x axis (its component
    /// along the normal is removed).
    pub fn new(normal: Vector3<f64>, u: Vector3<f64>) -> Result<Self, JointSpecError> {
        let n = unit(normal, "planar joint normal")?;
        let u = u - n * n.dot(&u);
        if u.norm() < 1e-9 {
            return jerr(
                "planar joint in-plane axis is parallel to the normal: give an axis in the plane",
            );
        }
        let u = u.normalize();
        Ok(Planar {
            u,
            v: n.cross(&u),
            n,
        })
    }
    fn factors(&self, q: &[f64]) -> [PoeFactor; 3] {
        let tr = |a: &Vector3<f64>| Twist::new(0.0, 0.0, 0.0, a.x, a.y, a.z);
        let n = self.n;
        [
            PoeFactor::of_coordinate(tr(&self.u), 0, [q[0], 1.0, 0.0]),
            PoeFactor::of_coordinate(tr(&self.v), 1, [q[1], 1.0, 0.0]),
            PoeFactor::of_coordinate(
                Twist::new(n.x, n.y, n.z, 0.0, 0.0, 0.0),
                2,
                [q[2], 1.0, 0.0],
            ),
        ]
    }

    /// The x–y plane (rotation about z).
    pub fn xy() -> Self {
        Planar {
            u: Vector3::x(),
            v: Vector3::y(),
            n: Vector3::z(),
        }
    }
}

impl Joint for Planar {
    fn kind(&self) -> &'static str {
        "planar"
    }
    fn dof(&self) -> usize {
        3
    }
    fn coordinate_suffixes(&self) -> Vec<String> {
        vec!["x".into(), "y".into(), "angle".into()]
    }
    fn kinematics(&self, q: &[f64], want: Derivatives, out: &mut JointKinematics) {
        poe_kinematics(&Se3::identity(), &self.factors(q), None, 3, want, out);
    }
    fn sdot_v_dq(&self, q: &[f64], v: &[f64], out: &mut [Twist; MAX_JOINT_DOF]) -> bool {
        // φ linear in q: no third-derivative term of its own.
        poe_sdot_v_dq(&self.factors(q), None, 3, v, out);
        true
    }
    fn limits(&self) -> Vec<Limit> {
        vec![Limit::NONE; 3]
    }
}
