//! Forward kinematics straight on a BVH file: each joint's world transform in
//! one frame. The reference the model-based `mocap::positions` is checked
//! against, and what the units detection and tests measure heights with.

use super::{BvhFile, joint_local_transform};
use crate::lie::Se3;
use nalgebra::Vector3;

/// World transform of every joint (file order) in frame `f`, in metres.
pub fn world_transforms(file: &BvhFile, f: usize, metres_per_unit: f64) -> Vec<Se3> {
    let sk = &file.skeleton;
    let row = file.frame(f);
    let starts = sk.channel_starts();
    let mut out: Vec<Se3> = Vec::with_capacity(sk.joints.len());
    for (i, j) in sk.joints.iter().enumerate() {
        let vals = &row[starts[i]..starts[i] + j.channels.len()];
        let local = joint_local_transform(j, vals, metres_per_unit);
        // Parents precede children, so out[p] is ready.
        let world = match j.parent {
            Some(p) => out[p].compose(&local),
            None => local,
        };
        out.push(world);
    }
    out
}

/// World position of every joint (file order) in frame `f`, in metres.
pub fn world_positions(file: &BvhFile, f: usize, metres_per_unit: f64) -> Vec<Vector3<f64>> {
    world_transforms(file, f, metres_per_unit)
        .into_iter()
        .map(|t| t.p)
        .collect()
}

/// World positions of every End Site in frame `f` (in joint order), metres.
pub fn end_site_positions(file: &BvhFile, f: usize, metres_per_unit: f64) -> Vec<Vector3<f64>> {
    let w = world_transforms(file, f, metres_per_unit);
    file.skeleton
        .joints
        .iter()
        .zip(&w)
        .flat_map(|(j, t)| {
            j.end_sites
                .iter()
                .map(move |e| t.act_point(&(e * metres_per_unit)))
        })
        .collect()
}
