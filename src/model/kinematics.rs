//! Forward kinematics: the world pose of every link.

use crate::lie::Se3;
use crate::model::joint::{Derivatives, JointKinematics};
use crate::model::tree::{Model, ModelError};

impl Model {
    /// World pose of every link at configuration `q` (`out[i]` maps link-i
    /// coordinates to world coordinates). `out` is resized to the number of links;
    /// reuse it across calls to avoid allocation.
    pub fn forward_kinematics(&self, q: &[f64], out: &mut Vec<Se3>) -> Result<(), ModelError> {
        self.check_vec("q", q, self.nq())?;
        out.clear();
        let mut jk = JointKinematics::default();
        for l in self.links() {
            l.joint.kinematics(
                &q[l.q_index..l.q_index + l.dof],
                Derivatives::Transform,
                &mut jk,
            );
            let local = l.offset.compose(&jk.transform);
            let pose = match l.parent {
                Some(p) => out[p].compose(&local),
                None => local,
            };
            out.push(pose);
        }
        Ok(())
    }

    /// World position of a point given in a link's frame.
    pub fn point_position(
        &self,
        q: &[f64],
        link: usize,
        point: &nalgebra::Vector3<f64>,
    ) -> Result<nalgebra::Vector3<f64>, ModelError> {
        if link >= self.num_links() {
            return Err(ModelError::Invalid(format!(
                "link index {link} out of range (the model has {} links)",
                self.num_links()
            )));
        }
        let mut poses = Vec::with_capacity(self.num_links());
        self.forward_kinematics(q, &mut poses)?;
        Ok(poses[link].act_point(point))
    }
}

/// How a point moves with one coordinate: ∂p/∂q_i for a point `p` (world) on
/// a link below the joint placed at `pose` (world pose of the joint's child
/// frame), where `s = [ω; v]` is the coordinate's column of the joint's
/// body-frame Jacobian S(q). In the joint frame the point moves by ω × r + v
/// with r = Rᵀ(p − o); rotated to the world, R(ω × r + v). The analytic
/// Jacobian of forward kinematics that the hold IK (`spacetime::hold`) and
/// per-frame IK (`ik`) share.
#[inline]
pub fn point_velocity(
    pose: &Se3,
    s: &crate::lie::Twist,
    p: &nalgebra::Vector3<f64>,
) -> nalgebra::Vector3<f64> {
    let (w, v) = (s.fixed_rows::<3>(0), s.fixed_rows::<3>(3));
    let rl = pose.r.transpose() * (p - pose.p);
    pose.r * (w.cross(&rl) + v)
}

/// The world angular velocity of every link below the joint placed at
/// `pose` per unit of the coordinate whose Jacobian column is `s`: R ω.
#[inline]
pub fn angular_velocity(pose: &Se3, s: &crate::lie::Twist) -> nalgebra::Vector3<f64> {
    pose.r * s.fixed_rows::<3>(0)
}
