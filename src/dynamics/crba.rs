//! The joint-space mass matrix by the composite-rigid-body algorithm:
//! `M_ij = S_iᵀ I^c_j S_j` (i an ancestor of j) with `I^c_j` the inertia of the
//! subtree of link j, all in the world frame.

use crate::dynamics::DynamicsError;
use crate::dynamics::crba_frame::CrbaFrame;
use crate::dynamics::crba_local::mass_matrix_local;
use crate::dynamics::workspace::Workspace;
use crate::model::joint::Derivatives;
use crate::model::{Inertia, Model};
use nalgebra::DMatrix;

/// Fills `m` (nq × nq, symmetric) with the mass matrix `M(q)`, by the pass
/// the workspace chose for its model.
pub fn mass_matrix(
    model: &Model,
    ws: &mut Workspace,
    q: &[f64],
    m: &mut DMatrix<f64>,
) -> Result<(), DynamicsError> {
    let frame = if ws.crba_in_link_frames {
        CrbaFrame::Link
    } else {
        CrbaFrame::World
    };
    mass_matrix_in(model, ws, q, m, frame)
}

/// [`mass_matrix`] by a pass the caller names (the dynamics bench times both).
pub fn mass_matrix_in(
    model: &Model,
    ws: &mut Workspace,
    q: &[f64],
    m: &mut DMatrix<f64>,
    frame: CrbaFrame,
) -> Result<(), DynamicsError> {
    ws.check(model)?;
    model.check_vec("q", q, model.nq())?;
    let n = model.nq();
    if m.nrows() != n || m.ncols() != n {
        return Err(DynamicsError::Input(format!(
            "the mass-matrix output is {}×{}; it must be {n}×{n}",
            m.nrows(),
            m.ncols()
        )));
    }
    // Entries between coordinates of different branches are never written below.
    let out = m.as_mut_slice();
    out.fill(0.0);
    // (A workspace checks only the sizes of its model: test the link order too.)
    if frame == CrbaFrame::Link && model.subtree_coordinates(0).is_some() {
        mass_matrix_local(model, ws, q, out);
    } else {
        mass_matrix_world(model, ws, q, out);
    }
    Ok(())
}

/// The world-frame CRBA on a zeroed column-major `out` (n × n): any link order.
fn mass_matrix_world(model: &Model, ws: &mut Workspace, q: &[f64], out: &mut [f64]) {
    let n = model.nq();
    // Everything in the world frame (as Pinocchio does): composite inertias then
    // add up without transforms, and each entry above the diagonal block is a
    // plain dot product `J_aᵀ (I^c_i J_i)` instead of a transform per ancestor.
    for (i, l) in model.links().iter().enumerate() {
        // The frame the joint moves in: the parent's placement times the fixed
        // offset (most URDF offsets only translate: no rotation product then).
        let before = match (l.parent, l.offset_rotates) {
            (Some(p), true) => ws.world[p].compose(&l.offset),
            (Some(p), false) => ws.world[p].translated(&l.offset.p),
            (None, _) => l.offset,
        };
        let world = match &l.axis {
            // Revolute/prismatic: a constant motion subspace, placed directly.
            Some(axis) => {
                let world = axis.place(&before, q[l.q_index]);
                ws.jw[l.q_index] = axis.twist_in(&world);
                world
            }
            None => {
                l.joint.kinematics(
                    &q[l.q_index..l.q_index + l.dof],
                    Derivatives::Jacobian,
                    &mut ws.kin[i],
                );
                let world = before.compose(&ws.kin[i].transform);
                for j in 0..l.dof {
                    ws.jw[l.q_index + j] = world.ad_twist(&ws.kin[i].s[j]);
                }
                world
            }
        };
        ws.world[i] = world;
        // Massless links (between the axes of one anatomical joint) add nothing.
        ws.ic[i] = if l.inertia.is_zero() {
            Inertia::zero()
        } else {
            l.inertia.transformed(&world)
        };
    }
    for i in (0..model.num_links()).rev() {
        let l = model.link(i);
        let ic = ws.ic[i];
        let own = l.q_index..l.q_index + l.dof;
        for col in own.clone() {
            ws.ag[col] = ic.mul_twist(&ws.jw[col]);
        }
        match model.subtree_coordinates(i) {
            // Depth-first models (URDF, BVH): the coordinates below link i are one
            // range whose momenta `ag` are final, so each of i's columns is filled
            // down its contiguous lower part (as Pinocchio does row-wise).
            Some(subtree) => {
                for col in own {
                    let jc = ws.jw[col];
                    let column = col * n;
                    out[column + col] = jc.dot(&ws.ag[col]);
                    for row in col + 1..subtree.end {
                        let x = jc.dot(&ws.ag[row]);
                        out[column + row] = x;
                        out[row * n + col] = x;
                    }
                }
            }
            // Interleaved subtrees: walk from each column to the root instead.
            None => {
                for col in own {
                    let f = ws.ag[col];
                    let column = col * n;
                    out[column + col] = ws.jw[col].dot(&f);
                    let mut next = model.coordinate_parent(col);
                    while let Some(row) = next {
                        let x = ws.jw[row].dot(&f);
                        out[column + row] = x;
                        out[row * n + col] = x;
                        next = model.coordinate_parent(row);
                    }
                }
            }
        }
        if let Some(p) = l.parent {
            ws.ic[p] += ic;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lie::Se3;
    use crate::model::Joint;
    use crate::model::joints::{EulerOrder, Fixed, Prismatic, Revolute, Spherical};
    use nalgebra::{Matrix3, Rotation3, Vector3};
    use std::sync::Arc;

    /// The tree  0 ─┬─ 1 ─ 2      (link 3 a massless fixed joint under 1)
    ///              └─ 4 ─ 5      added depth-first, or interleaved (0, 1, 4, 2, 3, 5).
    /// Mixes coordinate-axis and general revolutes, a prismatic, a 3-DOF spherical,
    /// a rotated offset and a zero-DOF link.
    fn tree(order: &[usize]) -> Model {
        let parents = [None, Some(0), Some(1), Some(1), Some(0), Some(4)];
        let joint = |i: usize| -> Arc<dyn Joint> {
            match i {
                0 => Arc::new(Revolute::new(Vector3::z()).unwrap()),
                1 => Arc::new(Spherical::new(EulerOrder([2, 0, 1]))),
                2 => Arc::new(Revolute::new(Vector3::new(0.3, -0.4, 0.8)).unwrap()),
                3 => Arc::new(Fixed::new(Se3::identity())),
                4 => Arc::new(Prismatic::new(-Vector3::x()).unwrap()),
                _ => Arc::new(Revolute::new(-Vector3::y()).unwrap()),
            }
        };
        let mut m = Model::new("tree");
        let mut index = [0; 6];
        for &i in order {
            let offset = Se3::new(
                Rotation3::from_euler_angles(0.1 * i as f64, 0.0, if i == 2 { 0.7 } else { 0.0 })
                    .into_inner(),
                Vector3::new(0.1, 0.2 * i as f64, -0.3),
            );
            let inertia = if i == 3 {
                Inertia::zero()
            } else {
                Inertia::from_com(
                    1.0 + i as f64,
                    Vector3::new(0.05, -0.1, 0.2),
                    Matrix3::from_diagonal(&Vector3::new(0.1, 0.2, 0.15)),
                )
                .unwrap()
            };
            index[i] = m
                .add_link(
                    &format!("l{i}"),
                    parents[i].map(|p| index[p]),
                    &format!("j{i}"),
                    joint(i),
                    offset,
                    inertia,
                )
                .unwrap();
        }
        m
    }

    /// A depth-first tree that takes every path of the link-frame pass: rotations
    /// about ±x, ±y, z behind translating offsets (the fast path), a general
    /// axis, a rotating offset, a prismatic, a spherical, a massless link in a
    /// chain and a massless leaf, two branches.
    fn mixed_chain() -> Model {
        // (parent, joint, offset rotates, has mass)
        type Spec = (Option<usize>, Arc<dyn Joint>, bool, bool);
        let joints: [Spec; 10] = [
            (
                None,
                Arc::new(Revolute::new(Vector3::z()).unwrap()),
                false,
                true,
            ),
            (
                Some(0),
                Arc::new(Revolute::new(-Vector3::y()).unwrap()),
                false,
                false,
            ),
            (
                Some(1),
                Arc::new(Revolute::new(Vector3::x()).unwrap()),
                false,
                true,
            ),
            (
                Some(2),
                Arc::new(Revolute::new(Vector3::new(0.3, -0.4, 0.8)).unwrap()),
                false,
                true,
            ),
            (Some(3), Arc::new(Fixed::new(Se3::identity())), false, false),
            (
                Some(2),
                Arc::new(Revolute::new(-Vector3::x()).unwrap()),
                true,
                true,
            ),
            (
                Some(5),
                Arc::new(Prismatic::new(Vector3::y()).unwrap()),
                false,
                true,
            ),
            (
                Some(6),
                Arc::new(Spherical::new(EulerOrder([0, 1, 2]))),
                false,
                true,
            ),
            (
                Some(0),
                Arc::new(Revolute::new(Vector3::y()).unwrap()),
                false,
                true,
            ),
            (
                Some(8),
                Arc::new(Revolute::new(-Vector3::z()).unwrap()),
                false,
                true,
            ),
        ];
        let mut m = Model::new("mixed");
        for (i, (parent, joint, rotates, massive)) in joints.into_iter().enumerate() {
            let r = if rotates {
                Rotation3::from_euler_angles(0.4, -0.2, 0.9).into_inner()
            } else {
                Matrix3::identity()
            };
            let offset = Se3::new(r, Vector3::new(0.1 * i as f64, -0.2, 0.05 * i as f64));
            let inertia = if massive {
                Inertia::from_com(
                    0.5 + i as f64,
                    Vector3::new(0.03 * i as f64, -0.1, 0.2),
                    Matrix3::new(0.1, 0.01, -0.02, 0.01, 0.2, 0.03, -0.02, 0.03, 0.15),
                )
                .unwrap()
            } else {
                Inertia::zero()
            };
            m.add_link(
                &format!("l{i}"),
                parent,
                &format!("j{i}"),
                joint,
                offset,
                inertia,
            )
            .unwrap();
        }
        m
    }

    /// The link-frame pass and the world-frame pass give the same matrix, on a
    /// model that takes every path of the link-frame pass.
    #[test]
    fn link_frames_and_world_frame_give_the_same_matrix() {
        let model = mixed_chain();
        assert!(model.subtree_coordinates(0).is_some());
        let n = model.nq();
        let mut ws = Workspace::new(&model);
        for s in 0..5 {
            let q: Vec<f64> = (0..n).map(|k| (0.7 * (k + s) as f64).sin() * 1.3).collect();
            let (mut a, mut b) = (vec![0.0; n * n], vec![0.0; n * n]);
            mass_matrix_local(&model, &mut ws, &q, &mut a);
            mass_matrix_world(&model, &mut ws, &q, &mut b);
            let scale = b.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            for k in 0..n * n {
                let d = (a[k] - b[k]).abs();
                assert!(
                    d < 1e-13 * scale,
                    "entry {k}: {} vs {} (state {s})",
                    a[k],
                    b[k]
                );
            }
        }
    }

    /// Both ways of filling the matrix (contiguous subtree ranges, walks to the
    /// root) give the same matrix up to the coordinate permutation, and it is
    /// `Σ_links J_iᵀ I_i J_i` built from scratch.
    #[test]
    fn depth_first_and_interleaved_orders_give_the_same_matrix() {
        let dfs = tree(&[0, 1, 2, 3, 4, 5]);
        let mixed = tree(&[0, 1, 4, 2, 3, 5]);
        assert!(dfs.subtree_coordinates(1).is_some());
        assert!(mixed.subtree_coordinates(1).is_none());
        let n = dfs.nq();
        let q = [0.3, -0.7, 0.4, 1.1, 0.9, 0.25, -1.3];
        // Coordinate k of `dfs` is coordinate perm[k] of `mixed`.
        let names = dfs.coordinate_names();
        let perm: Vec<usize> = names
            .iter()
            .map(|c| mixed.coordinate_index(c).unwrap())
            .collect();
        let mut qm = [0.0; 7];
        for k in 0..n {
            qm[perm[k]] = q[k];
        }
        let (mut a, mut b) = (DMatrix::zeros(n, n), DMatrix::from_element(n, n, 7.0));
        mass_matrix(&dfs, &mut Workspace::new(&dfs), &q, &mut a).unwrap();
        mass_matrix(&mixed, &mut Workspace::new(&mixed), &qm, &mut b).unwrap();
        let scale = a.amax();
        for r in 0..n {
            for c in 0..n {
                let d = (a[(r, c)] - b[(perm[r], perm[c])]).abs();
                assert!(d < 1e-14 * scale, "M[{r},{c}] differs by {d:e}");
            }
        }
        // From scratch: world Jacobian columns of each link, J_iᵀ I_i J_i.
        let mut ws = Workspace::new(&dfs);
        let mut world = vec![Se3::identity(); dfs.num_links()];
        let mut expect = DMatrix::zeros(n, n);
        let mut cols: Vec<Option<crate::lie::Twist>> = vec![None; n];
        for (i, l) in dfs.links().iter().enumerate() {
            let kin = &mut ws.kin[i];
            l.joint
                .kinematics(&q[l.q_index..l.q_index + l.dof], Derivatives::Jacobian, kin);
            let before = l.parent.map_or(l.offset, |p| world[p].compose(&l.offset));
            world[i] = before.compose(&kin.transform);
            for j in 0..l.dof {
                cols[l.q_index + j] = Some(world[i].ad_twist(&kin.s[j]));
            }
            let g = l.inertia.transformed(&world[i]);
            // The columns of link i's ancestors (and its own) move it.
            let mut moving = vec![false; n];
            let mut a = Some(i);
            while let Some(k) = a {
                let lk = dfs.link(k);
                moving[lk.q_index..lk.q_index + lk.dof].fill(true);
                a = lk.parent;
            }
            for r in 0..n {
                for c in 0..n {
                    if moving[r] && moving[c] {
                        expect[(r, c)] += cols[r].unwrap().dot(&g.mul_twist(&cols[c].unwrap()));
                    }
                }
            }
        }
        assert!((&a - &expect).amax() < 1e-13 * scale, "{a}\n{expect}");
    }
}
