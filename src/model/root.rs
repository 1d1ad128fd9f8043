//! The floating root of a link tree (Rose §3.2.1: positioned kinematically,
//! not by torques): which coordinates place the body in the world, and which
//! of them translate horizontally or vertically. SP moves them by Rose's path;
//! the ground residual needs them free; `ground::moving_root` finds them as a
//! motion moves them.

use crate::model::{Derivatives, JointKinematics, Model};
use nalgebra::Vector3;

/// Which coordinates of a body are its root (Rose §3.2.1: positioned
/// kinematically, not by torques), and which of them translate horizontally
/// or vertically.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct RootCoords {
    /// Every root coordinate (its virtual forces are excluded from torque sums).
    pub all: Vec<usize>,
    /// Translations along horizontal world axes (the floor plane).
    pub horizontal: Vec<usize>,
    /// Translation along the vertical.
    pub vertical: Vec<usize>,
    /// Root rotations (interpolated by the cubic Hermite curve over a gap).
    pub rotations: Vec<usize>,
    /// Coordinates of massless links above the moving root that stay constant
    /// in the motion (the Bandai skeletons' all-zero `joint_Root`): they place
    /// the body rather than move it. They are in `all` (the world's force on
    /// the body passes through them unchanged, so counting them would count
    /// the root's virtual forces) and a gap in them is bridged by Hermite.
    pub fixed: Vec<usize>,
}

impl RootCoords {
    /// The root of `model`: the chain of links from the world while they are
    /// massless and have one child, up to and including the first link with
    /// mass (a 6-DOF free joint, or BVH/URDF roots written as three slides and
    /// three hinges). Translational coordinates are classified against `up`
    /// (`ground::up_of(gravity)`) at q = 0; without one (no gravity) z is
    /// taken as up so the split is still defined. A translation neither
    /// horizontal nor vertical (a tilted slide) is treated like a rotation.
    pub fn detect(model: &Model, up: Option<&Vector3<f64>>) -> RootCoords {
        Self::detect_skipping(model, up, |_| false)
    }

    /// Whether the root moves the body freely: six coordinates or more below
    /// the skipped placeholders (a free joint, or three slides and three
    /// hinges), so the world's wrench on the body is the root's.
    pub fn is_floating(&self) -> bool {
        self.all.len() - self.fixed.len() >= 6
    }

    /// As [`detect`](Self::detect), but leading massless single-child links
    /// whose coordinates are all `constant` are skipped (listed in `fixed`),
    /// and the root is the chain from the first link that moves. A skeleton
    /// whose top joint is a constant placeholder (Bandai's `joint_Root`, six
    /// zero channels above the moving `Hips`) so gets `Hips` as its root, as a
    /// skeleton without the placeholder would. If nothing on that chain moves
    /// (a motion that stands still) nothing is skipped.
    pub fn detect_skipping(
        model: &Model,
        up: Option<&Vector3<f64>>,
        constant: impl Fn(usize) -> bool,
    ) -> RootCoords {
        let mut out = RootCoords::default();
        if model.num_links() == 0 || model.link(0).parent.is_some() {
            return out;
        }
        let up = up.copied().unwrap_or_else(Vector3::z);
        let q0 = vec![0.0; model.nq()];
        let mut poses = vec![];
        if model.forward_kinematics(&q0, &mut poses).is_err() {
            return out;
        }
        let start = moving_root_link(model, &constant);
        let mut link = 0;
        while link != start {
            let l = model.link(link);
            out.all.extend(l.q_index..l.q_index + l.dof);
            out.fixed.extend(l.q_index..l.q_index + l.dof);
            link = model.children(link)[0];
        }
        let mut jk = JointKinematics::default();
        loop {
            let l = model.link(link);
            l.joint.kinematics(
                &q0[l.q_index..l.q_index + l.dof],
                Derivatives::Jacobian,
                &mut jk,
            );
            for j in 0..l.dof {
                let c = l.q_index + j;
                out.all.push(c);
                let s = jk.s[j];
                let w = Vector3::new(s[0], s[1], s[2]);
                let v = Vector3::new(s[3], s[4], s[5]);
                if w.norm() < 1e-12 && v.norm() > 0.0 {
                    let axis = poses[link].r * v / v.norm();
                    let d = axis.dot(&up).abs();
                    if d > 1.0 - 1e-9 {
                        out.vertical.push(c);
                    } else if d < 1e-9 {
                        out.horizontal.push(c);
                    } else {
                        out.rotations.push(c);
                    }
                } else {
                    out.rotations.push(c);
                }
            }
            let children = model.children(link);
            if l.inertia.mass > 0.0 || children.len() != 1 {
                break;
            }
            link = children[0];
        }
        out
    }
}

/// The first link from the world, down the chain of massless single-child
/// links, that has a coordinate not `constant`; the world's first link (0)
/// when there is none (nothing to skip).
fn moving_root_link(model: &Model, constant: &impl Fn(usize) -> bool) -> usize {
    let mut link = 0;
    loop {
        let l = model.link(link);
        if (l.q_index..l.q_index + l.dof).any(|c| !constant(c)) {
            return link;
        }
        let children = model.children(link);
        if l.inertia.mass > 0.0 || children.len() != 1 {
            return 0;
        }
        link = children[0];
    }
}

#[cfg(test)]
mod detect_tests {
    use super::*;
    use crate::lie::Se3;
    use crate::model::joints::{Prismatic, Revolute};
    use crate::model::{Inertia, Model};
    use nalgebra::Vector3;
    use std::sync::Arc;

    #[test]
    fn slides_and_hinges_to_the_first_massive_link() {
        let mut m = Model::new("t");
        let z = Inertia::zero();
        let mut p = None;
        for (i, ax) in [Vector3::x(), Vector3::y(), Vector3::z()]
            .into_iter()
            .enumerate()
        {
            p = Some(
                m.add_link(
                    &format!("s{i}"),
                    p,
                    &format!("t{i}"),
                    Arc::new(Prismatic::new(ax).unwrap()),
                    Se3::identity(),
                    z,
                )
                .unwrap(),
            );
        }
        let pelvis = Inertia::point(10.0, Vector3::zeros()).unwrap();
        let r = m
            .add_link(
                "pelvis",
                p,
                "rz",
                Arc::new(Revolute::new(Vector3::z()).unwrap()),
                Se3::identity(),
                pelvis,
            )
            .unwrap();
        m.add_link(
            "thigh",
            Some(r),
            "hip",
            Arc::new(Revolute::new(Vector3::x()).unwrap()),
            Se3::identity(),
            pelvis,
        )
        .unwrap();
        let rc = RootCoords::detect(&m, Some(&Vector3::y()));
        assert_eq!(rc.all, vec![0, 1, 2, 3]);
        assert_eq!(rc.horizontal, vec![0, 2]);
        assert_eq!(rc.vertical, vec![1]);
        assert_eq!(rc.rotations, vec![3]);
        assert!(
            !rc.is_floating(),
            "four coordinates do not move a body freely"
        );
        // without gravity z is up: the y slide is horizontal, the z slide vertical
        let rc = RootCoords::detect(&m, None);
        assert_eq!((rc.horizontal, rc.vertical), (vec![0, 1], vec![2]));
    }
}
