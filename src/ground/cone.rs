//! The per-frame friction-cone problem: the contact forces that best supply
//! a wanted wrench.
//!
//! Given the wrench `w = [μ; η]` (moment about a reference point, force) and
//! contact points at arms `r_j` from that point, find forces `f_j`, each in
//! its friction cone `‖f_j − (f_j·n) n‖ ≤ μ_s (f_j·n)` (`n` up), minimising
//!
//! ```text
//! ‖η − Σ f_j‖² + ‖μ − Σ r_j × f_j‖² / L²
//! ```
//!
//! A moment is weighed as the force that makes it at the lever arm `L` (a
//! body length): one N·m of moment counts as 1/L N. This is a convex
//! quadratic objective over second-order cones, solved by `clarabel`'s
//! interior point method (`P = AᵀA`, `q = −Aᵀb`, one `SecondOrderConeT(3)`
//! per point), in units scaled by the wrench's own size so that a 700 N body
//! and a 1 N test case are conditioned alike.

use super::{GroundError, invalid, invalid_option};
use crate::lie::Wrench;
use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};
use nalgebra::{DMatrix, DVector, Vector3};

/// The best contact forces and what they leave.
#[derive(Clone, Debug, PartialEq)]
pub struct ConeSolution {
    /// Force at each point (world axes, N).
    pub forces: Vec<Vector3<f64>>,
    /// `w` less the forces' wrench: `[moment; force]` about the reference point.
    pub residual: Wrench,
    /// The solver reached its tolerance (`false`: reduced accuracy, flagged).
    pub solved: bool,
}

/// Two unit vectors completing `n` to an orthonormal basis.
fn tangents(n: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let a = if n.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let t1 = n.cross(&a).normalize();
    (t1, n.cross(&t1))
}

/// Solves the problem of the module doc. `arms[j]`: point `j` less the
/// reference point (m); `up`: unit normal of the floor; `friction`: μ ≥ 0;
/// `length`: L > 0 (m).
pub fn best_contact_forces(
    wrench: &Wrench,
    arms: &[Vector3<f64>],
    up: &Vector3<f64>,
    friction: f64,
    length: f64,
) -> Result<ConeSolution, GroundError> {
    if !(friction.is_finite() && friction >= 0.0) {
        return Err(invalid_option(
            "friction",
            format!("friction must be a finite coefficient ≥ 0, got {friction}"),
        ));
    }
    if !(length.is_finite() && length > 0.0) {
        return Err(invalid(format!(
            "the length scale must be > 0 m, got {length}"
        )));
    }
    let moment = Vector3::new(wrench[0], wrench[1], wrench[2]);
    let force = Vector3::new(wrench[3], wrench[4], wrench[5]);
    let scale = force.norm().max(moment.norm() / length);
    if arms.is_empty() || scale == 0.0 || !scale.is_finite() {
        return Ok(ConeSolution {
            forces: vec![Vector3::zeros(); arms.len()],
            residual: *wrench,
            solved: scale.is_finite(),
        });
    }
    let n = 3 * arms.len();
    // b − A x: the scaled residual [force; moment / L]
    let mut a = DMatrix::<f64>::zeros(6, n);
    for (j, r) in arms.iter().enumerate() {
        let rl = r / length;
        for c in 0..3 {
            a[(c, 3 * j + c)] = 1.0;
            let m = rl.cross(&Vector3::ith(c, 1.0));
            for (row, v) in m.iter().enumerate() {
                a[(3 + row, 3 * j + c)] = *v;
            }
        }
    }
    let b = DVector::from_column_slice(&[
        force.x / scale,
        force.y / scale,
        force.z / scale,
        moment.x / (length * scale),
        moment.y / (length * scale),
        moment.z / (length * scale),
    ]);
    let p = a.transpose() * &a;
    let q = -(a.transpose() * &b);
    // clarabel takes the upper triangle of P
    let (mut pi, mut pj, mut pv) = (vec![], vec![], vec![]);
    for c in 0..n {
        for r in 0..=c {
            if p[(r, c)] != 0.0 {
                pi.push(r);
                pj.push(c);
                pv.push(p[(r, c)]);
            }
        }
    }
    let pm = CscMatrix::new_from_triplets(n, n, pi, pj, pv);
    // s = −G x ∈ SOC(3): [μ n·f; t1·f; t2·f]
    let (t1, t2) = tangents(up);
    let (mut gi, mut gj, mut gv) = (vec![], vec![], vec![]);
    for j in 0..arms.len() {
        for (row, dir) in [(0, up * friction), (1, t1), (2, t2)] {
            for (c, d) in dir.iter().enumerate() {
                if *d != 0.0 {
                    gi.push(3 * j + row);
                    gj.push(3 * j + c);
                    gv.push(-d);
                }
            }
        }
    }
    let gm = CscMatrix::new_from_triplets(n, n, gi, gj, gv);
    let h = vec![0.0; n];
    let cones: Vec<SupportedConeT<f64>> = (0..arms.len())
        .map(|_| SupportedConeT::SecondOrderConeT(3))
        .collect();
    let settings = DefaultSettingsBuilder::default()
        .verbose(false)
        .build()
        .map_err(|e| invalid(format!("clarabel settings: {e}")))?;
    let mut solver = DefaultSolver::new(&pm, q.as_slice(), &gm, &h, &cones, settings)
        .map_err(|e| invalid(format!("the friction-cone problem: {e:?}")))?;
    solver.solve();
    let status = solver.solution.status;
    let x = &solver.solution.x;
    if x.len() != n || x.iter().any(|v| !v.is_finite()) {
        return Err(invalid(format!(
            "the friction-cone problem did not solve ({status:?})"
        )));
    }
    let forces: Vec<Vector3<f64>> = (0..arms.len())
        .map(|j| Vector3::new(x[3 * j], x[3 * j + 1], x[3 * j + 2]) * scale)
        .collect();
    let mut residual = *wrench;
    for (f, r) in forces.iter().zip(arms) {
        let mut top = residual.fixed_rows_mut::<3>(0);
        top -= r.cross(f);
        let mut bottom = residual.fixed_rows_mut::<3>(3);
        bottom -= f;
    }
    Ok(ConeSolution {
        forces,
        residual,
        solved: matches!(status, SolverStatus::Solved),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn w(moment: [f64; 3], force: [f64; 3]) -> Wrench {
        Wrench::new(
            moment[0], moment[1], moment[2], force[0], force[1], force[2],
        )
    }

    #[test]
    fn a_push_outside_the_cone_leaves_its_distance_to_the_cone() {
        // one point at the reference, z up, want 3 N sideways and 1 N up, μ = 0.8:
        // in the (normal, tangential) plane the cone's edge is the ray (1, 0.8)/√1.64;
        // the residual is the distance of (1, 3) to it: |1·0.8 − 3·1| / √1.64.
        let s = best_contact_forces(
            &w([0.0; 3], [3.0, 0.0, 1.0]),
            &[Vector3::zeros()],
            &Vector3::z(),
            0.8,
            1.0,
        )
        .unwrap();
        assert!(s.solved);
        let want = 2.2 / 1.64f64.sqrt();
        let r = Vector3::new(s.residual[3], s.residual[4], s.residual[5]).norm();
        assert!((r - want).abs() < 1e-6, "{r} vs {want}");
        // the force supplied lies on the cone's edge: |t| = 0.8 n
        let f = s.forces[0];
        assert!((f.x.hypot(f.y) - 0.8 * f.z).abs() < 1e-6, "{f}");
        // inside the cone: supplied exactly
        let s = best_contact_forces(
            &w([0.0; 3], [0.5, 0.2, 1.0]),
            &[Vector3::zeros()],
            &Vector3::z(),
            0.8,
            1.0,
        )
        .unwrap();
        assert!(s.residual.norm() < 1e-6, "{}", s.residual);
        // pulling the body down: no contact can (forces push)
        let s = best_contact_forces(
            &w([0.0; 3], [0.0, 0.0, -2.0]),
            &[Vector3::zeros()],
            &Vector3::z(),
            0.8,
            1.0,
        )
        .unwrap();
        assert!((s.residual[5] + 2.0).abs() < 1e-6);
    }

    #[test]
    fn weight_between_two_feet_is_carried_and_outside_them_is_not() {
        // weight 10 N down → the body needs 10 N up; feet at x = ±0.1 m, 1 m below
        // the reference (the centre of mass), y up.
        let up = Vector3::y();
        let arms = [Vector3::new(-0.1, -1.0, 0.0), Vector3::new(0.1, -1.0, 0.0)];
        let s = best_contact_forces(&w([0.0; 3], [0.0, 10.0, 0.0]), &arms, &up, 0.8, 1.0).unwrap();
        assert!(s.residual.norm() < 1e-6, "{}", s.residual);
        assert!((s.forces[0].y - 5.0).abs() < 1e-4 && (s.forces[1].y - 5.0).abs() < 1e-4);
        // hand-solved: both feet at x = 0.5 (the centre of mass is outside the base),
        // one force f = (fx, fy) at arm (0.5, −1): residual force (−fx, 10 − fy) and
        // moment about z of −(0.5 fy + fx) (r × f, z: rx fy − ry fx = 0.5 fy + fx);
        // with μ large (the cone inactive) minimise fx² + (10 − fy)² + (0.5 fy + fx)².
        let arms = [Vector3::new(0.5, -1.0, 0.0)];
        let s =
            best_contact_forces(&w([0.0; 3], [0.0, 10.0, 0.0]), &arms, &up, 100.0, 1.0).unwrap();
        // normal equations: [2 0.5; 0.5 1.25] [fx; fy] = [0; 10]
        let det = 2.0 * 1.25 - 0.25;
        let (fx, fy) = (-0.5 * 10.0 / det, 2.0 * 10.0 / det);
        assert!(
            (s.forces[0].x - fx).abs() < 1e-5 && (s.forces[0].y - fy).abs() < 1e-5,
            "{:?}",
            s.forces
        );
    }
}
