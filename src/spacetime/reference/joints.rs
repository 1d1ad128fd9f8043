//! Which coordinates make one joint, for the rule that a joint's channels
//! follow an example together or not at all (one Euler channel following
//! and its siblings not is a rotation neither side has).
//!
//! By name, a joint is what comes before a channel's last dot
//! (`Hips.Xrotation`). OpenSim coordinates carry no dot (`hip_flexion_r`),
//! so on them the name says nothing; the model does: a coordinate belongs
//! to the link whose joint it drives, and one OpenSim joint is one link.
//! With a model both count: two coordinates are one joint when their names
//! say so (a BVH body has one link per channel) or when one link carries
//! both (an OpenSim or other multi-DOF joint).

use crate::model::Model;
use crate::motion::channel::Channel;
use std::collections::HashMap;

/// Per coordinate, the joint it belongs to.
#[derive(Clone, Debug, PartialEq)]
pub struct Joints {
    /// `of[c]`: a representative coordinate of c's joint (equal for one joint).
    of: Vec<usize>,
}

impl Joints {
    /// By the name convention alone: `names[c]` up to its last dot (the
    /// whole name when it has none).
    pub fn by_name(names: &[String]) -> Self {
        let mut first: HashMap<&str, usize> = HashMap::new();
        let of = names
            .iter()
            .enumerate()
            .map(|(c, n)| {
                let joint = Channel::parse(n).joint;
                *first.entry(joint).or_insert(c)
            })
            .collect();
        Joints { of }
    }

    /// By the name convention and by `model`'s links (model coordinate c is
    /// `names[c]`): the coordinates of one link are one joint too.
    pub fn of_model(model: &Model, names: &[String]) -> Self {
        let mut joints = Joints::by_name(names);
        for link in model.links().iter().filter(|l| l.dof > 1) {
            // (a body with more coordinates than names joins only those named)
            let end = (link.q_index + link.dof).min(names.len());
            for c in link.q_index + 1..end {
                joints.join(link.q_index, c);
            }
        }
        joints
    }

    /// Makes the joints of a and b one.
    fn join(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.of[a], self.of[b]);
        if ra == rb {
            return;
        }
        let keep = ra.min(rb);
        for r in self.of.iter_mut() {
            if *r == ra || *r == rb {
                *r = keep;
            }
        }
    }

    /// Whether coordinates a and b belong to one joint.
    pub fn same(&self, a: usize, b: usize) -> bool {
        self.of[a] == self.of[b]
    }

    /// The coordinates of `coords` whose joint has every channel among
    /// `coords` `close` (`close[i]` for `coords[i]`).
    pub fn whole(&self, coords: &[usize], close: &[bool]) -> Vec<usize> {
        coords
            .iter()
            .filter(|&&c| {
                coords
                    .iter()
                    .zip(close)
                    .all(|(&o, &ok)| ok || !self.same(o, c))
            })
            .copied()
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lie::Se3;
    use crate::model::Inertia;
    use crate::model::joints::{Cylindrical, Revolute};
    use nalgebra::Vector3;
    use std::sync::Arc;

    fn names(n: &[&str]) -> Vec<String> {
        n.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn by_name_a_joint_is_the_part_before_the_last_dot() {
        let j = Joints::by_name(&names(&[
            "Hips.Xrotation",
            "a",
            "Hips.Yrotation",
            "b",
            "x.y.z",
        ]));
        assert!(j.same(0, 2));
        assert!(!j.same(1, 3) && !j.same(0, 1) && !j.same(4, 0));
        // a joint with one channel off leaves all its channels out
        assert_eq!(j.whole(&[0, 1, 2], &[true, true, false]), vec![1]);
        assert_eq!(j.whole(&[0, 1, 2], &[true, false, true]), vec![0, 2]);
    }

    /// OpenSim-style names (no dot) on a model whose first link carries two
    /// coordinates: the model joins them, the name convention could not.
    #[test]
    fn a_models_multi_dof_link_is_one_joint() {
        let mut model = Model::new("two joints");
        let cyl = Arc::new(Cylindrical::new(Vector3::z()).unwrap());
        let l0 = model
            .add_link("a", None, "hip", cyl, Se3::identity(), Inertia::zero())
            .unwrap();
        let pin = Arc::new(Revolute::new(Vector3::x()).unwrap());
        model
            .add_link("b", Some(l0), "knee", pin, Se3::identity(), Inertia::zero())
            .unwrap();
        let n = names(&["hip_rotation", "hip_slide", "knee_angle"]);
        model.set_coordinate_names(n.clone()).unwrap();
        let by_name = Joints::by_name(&n);
        assert!(!by_name.same(0, 1));
        let j = Joints::of_model(&model, &n);
        assert!(j.same(0, 1) && !j.same(0, 2) && !j.same(1, 2));
        assert_eq!(j.whole(&[0, 1, 2], &[true, false, true]), vec![2]);
        // names the convention already joins stay joined
        let bvh = names(&["Hips.Zrotation", "Hips.Xrotation", "Knee.Xrotation"]);
        let j = Joints::of_model(&model, &bvh);
        assert!(j.same(0, 1) && !j.same(0, 2));
    }
}
