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
