//! Analytic derivatives of inverse dynamics: `∂τ/∂q` and `∂τ/∂q̇`
//! (`∂τ/∂q̈ = M`, see [`mass_matrix`](super::mass_matrix)).
//!
//! The algorithm of Carpentier & Mansard (RSS 2018), as Pinocchio runs it:
//! one forward and one backward pass in the world frame, where a coordinate
//! `q_k` moves everything carried by its joint rigidly (`∂x/∂q_k = J_k × x`)
//! and only an "intrinsic" part of each quantity is left to propagate:
//!
//! ```text
//! forward (per column k, λ = parent):  dV/dq_k = v_λ × J_k + h_k
//!     dA/dq_k = a_λ × J_k + v_λ × dV/dq_k + ha_k + v_k × h_k + ∂(Ṡq̇)/∂q_k
//!     dA/dq̇_k = v_λ × J_k + v_k × J_k + hv_k
//! backward (composites Y, Ẏ = variation, F):
//!     τ_j ⪯ k: J_jᵀ (Y_k dA_k + Ẏ_k dV_k + J_k ×* F_k),   τ_j ≻ k: (Y_j J_j)ᵀ dA_k + (Ẏ_jᵀ J_j)ᵀ dV_k
//! ```
//! `J_k = Ad_{T_k} s_k` are world joint columns; `h, ha, hv` (world images of
//! `∇S·q̇`, `∇S·q̈` and `(∇S + ∇Sᵀ)·q̇`) are zero unless the joint's Jacobian
//! depends on q. A link's entries are written while walking its ancestors, so
//! any parents-first link order works (subtrees need not be contiguous).
//!
//! For those q-dependent joints, `∂(Ṡ q̇)/∂q` needs the third derivative of the
//! joint map: every joint of the library gives it analytically
//! ([`Joint::sdot_v_dq`]); for a joint defined elsewhere that does not, that one
//! term is a difference of the joint's Hessian (step 1e-5, error ~1e-10 relative).

#![allow(clippy::needless_range_loop)] // index loops over coupled arrays read clearer here

use crate::dynamics::DynamicsError;
use crate::dynamics::rnea::check_inputs;
use crate::dynamics::state::JointState;
use crate::dynamics::variation::Variation;
use crate::dynamics::workspace::{Workspace, base_acceleration, sdot_v, world_velocity_pass};
use crate::lie::{Twist, Wrench, ad, ad_dual};
use crate::model::joint::{Derivatives, Joint, JointKinematics, MAX_JOINT_DOF};
use crate::model::{Inertia, Model};
use nalgebra::{DMatrix, Vector3};

/// `out[m] = ∂(Ṡ(q) q̇)/∂q_m` for the coordinates of link `l` (`q`, `v` its own):
/// the joint's analytic third derivative, else a difference of its Hessian.
pub(crate) fn sdot_v_gradient(
    l: &crate::model::tree::Link,
    q: &[f64],
    v: &[f64],
    scratch: &mut JointKinematics,
    out: &mut [Twist; MAX_JOINT_DOF],
) {
    if l.joint.sdot_v_dq(q, v, out) {
        return;
    }
    for (k, o) in out.iter_mut().enumerate().take(l.dof) {
        *o = sdot_v_dq_by_differences(l.joint.as_ref(), limit_of(l, k), q, v, k, scratch);
    }
}

/// `∂(Ṡ(q) q̇)/∂q_k` of one joint by a difference of its Hessian: central, or
/// one-sided (second order) where the central stencil would straddle an end of
/// the coordinate's range: a spline joint's Hessian may jump there (SimmSpline
/// extends linearly past its knots), and the inside value is the one wanted.
fn sdot_v_dq_by_differences(
    joint: &dyn Joint,
    limit: (f64, f64),
    q: &[f64],
    v: &[f64],
    k: usize,
    scratch: &mut JointKinematics,
) -> Twist {
    let mut qq = [0.0; 6];
    qq[..q.len()].copy_from_slice(q);
    let x = q[k];
    let h = 1e-5 * (1.0 + x.abs());
    let mut at = |d: f64| {
        qq[k] = x + d;
        joint.kinematics(&qq[..q.len()], Derivatives::Hessian, scratch);
        sdot_v(scratch, v)
    };
    // Side: +1 forward, −1 backward, 0 central.
    let mut side = 0.0;
    for (b, inside) in [(limit.0, 1.0), (limit.1, -1.0)] {
        if b.is_finite() && x - h < b && b < x + h || x == b {
            side = if x == b {
                inside
            } else if x < b {
                -1.0
            } else {
                1.0
            };
        }
    }
    if side == 0.0 {
        (at(h) - at(-h)) / (2.0 * h)
    } else {
        let s = side * h;
        (at(0.0) * -3.0 + at(s) * 4.0 - at(2.0 * s)) / (2.0 * s)
    }
}

/// The limits of coordinate k of a link, as a pair.
fn limit_of(l: &crate::model::tree::Link, k: usize) -> (f64, f64) {
    l.limits
        .get(k)
        .map_or((f64::NEG_INFINITY, f64::INFINITY), |x| (x.lower, x.upper))
}

/// Fills `dtau_dq` and `dtau_dv` (nq × nq; `[i][j] = ∂τ_i/∂x_j`) at `(q, q̇, q̈)`.
pub fn rnea_derivatives(
    model: &Model,
    ws: &mut Workspace,
    x: &JointState,
    gravity: &Vector3<f64>,
    dtau_dq: &mut DMatrix<f64>,
    dtau_dv: &mut DMatrix<f64>,
) -> Result<(), DynamicsError> {
    let (q, v, a) = (x.q, x.v, x.a);
    check_inputs(model, ws, &[("q", q), ("v", v), ("a", a)], gravity)?;
    let n = model.nq();
    for (name, m) in [("dtau_dq", &*dtau_dq), ("dtau_dv", &*dtau_dv)] {
        if m.nrows() != n || m.ncols() != n {
            return Err(DynamicsError::Input(format!(
                "`{name}` is {}×{}; it must be {n}×{n}",
                m.nrows(),
                m.ncols()
            )));
        }
    }
    forward_pass(model, ws, q, v, a, gravity);
    // Entries between coordinates on different branches are never written below.
    let (dq, dv) = (dtau_dq.as_mut_slice(), dtau_dv.as_mut_slice());
    dq.fill(0.0);
    dv.fill(0.0);
    backward_pass(model, ws, n, dq, dv);
    Ok(())
}

/// World poses, twists, accelerations, inertias, forces and variations per
/// link, and the columns `J, dV/dq, dA/dq, dA/dq̇` per coordinate.
fn forward_pass(
    model: &Model,
    ws: &mut Workspace,
    q: &[f64],
    v: &[f64],
    a: &[f64],
    gravity: &Vector3<f64>,
) {
    world_velocity_pass(model, ws, q, v);
    let a0 = base_acceleration(gravity);
    for (i, l) in model.links().iter().enumerate() {
        let qi = l.q_index;
        let r = qi..qi + l.dof;
        let (vp, ap) = match l.parent {
            Some(p) => (ws.ov[p], ws.oa[p]),
            None => (Twist::zeros(), a0),
        };
        let t = ws.world[i];
        let ov = ws.ov[i];
        let mut third = [Twist::zeros(); MAX_JOINT_DOF];
        if !l.constant_jacobian {
            sdot_v_gradient(l, &q[r.clone()], &v[r], &mut ws.scratch, &mut third);
        }
        let kin = &ws.kin[i];
        let mut oa = ap + ws.c[i];
        for m in 0..l.dof {
            oa += ws.jw[qi + m] * a[qi + m];
        }
        for m in 0..l.dof {
            let c = qi + m;
            let jm = ws.jw[c];
            let mut dvdq = ad(&vp, &jm);
            let mut dadq = ad(&ap, &jm);
            let mut dadv = dvdq + ad(&ov, &jm);
            if !l.constant_jacobian {
                let mut hv = Twist::zeros();
                let mut ha = Twist::zeros();
                let mut hvv = Twist::zeros();
                for n in 0..l.dof {
                    hv += kin.ds[n][m] * v[qi + n];
                    ha += kin.ds[n][m] * a[qi + n];
                    hvv += (kin.ds[n][m] + kin.ds[m][n]) * v[qi + n];
                }
                let h = t.ad_twist(&hv);
                dvdq += h;
                dadq += t.ad_twist(&(ha + third[m])) + ad(&ov, &h);
                dadv += t.ad_twist(&hvv);
            }
            dadq += ad(&vp, &dvdq);
            ws.dvdq[c] = dvdq;
            ws.dadq[c] = dadq;
            ws.dadv[c] = dadv;
        }
        // Massless links (half of a URDF human's) carry no force and no variation.
        if l.inertia.is_zero() {
            ws.of[i] = Wrench::zeros();
            ws.doy[i] = Variation::zero();
            ws.ic[i] = Inertia::zero();
        } else {
            let y = l.inertia.transformed(&t);
            let yv = y.mul_twist(&ov);
            ws.of[i] = y.mul_twist(&oa) - ad_dual(&ov, &yv);
            ws.doy[i] = Variation::new(&y, &ov, &yv);
            ws.ic[i] = y;
        }
        ws.oa[i] = oa;
    }
}

/// Leaves to root: subtree composites, then each link's own block and the
/// entries it shares with every ancestor (`out[col * n + row]`, column-major).
fn backward_pass(model: &Model, ws: &mut Workspace, n: usize, dq: &mut [f64], dv: &mut [f64]) {
    for j in (0..model.num_links()).rev() {
        let l = model.link(j);
        let qj = l.q_index;
        let y = ws.ic[j];
        let d = ws.doy[j];
        let f = ws.of[j];
        // Per own column: ∂F/∂q (intrinsic), ∂F/∂q̇, Y J and Ẏᵀ J.
        let mut gq = [Wrench::zeros(); MAX_JOINT_DOF];
        let mut gv = [Wrench::zeros(); MAX_JOINT_DOF];
        let mut yj = [Wrench::zeros(); MAX_JOINT_DOF];
        let mut dyj = [Vector3::zeros(); MAX_JOINT_DOF];
        for m in 0..l.dof {
            let c = qj + m;
            let jm = ws.jw[c];
            gq[m] = y.mul_twist(&ws.dadq[c]) + d.apply(&ws.dvdq[c]);
            gv[m] = y.mul_twist(&ws.dadv[c]) + d.apply(&jm);
            yj[m] = y.mul_twist(&jm);
            dyj[m] = d.transpose_apply(&jm);
        }
        // The joint's own block (∂s/∂q meets the subtree force when S moves with q).
        let f_local = if l.constant_jacobian {
            Wrench::zeros()
        } else {
            ws.world[j].inv_ad_wrench(&f)
        };
        for m in 0..l.dof {
            for k in 0..l.dof {
                let row = qj + k;
                let jk = &ws.jw[row];
                let mut x = jk.dot(&gq[m]);
                if !l.constant_jacobian {
                    x += ws.kin[j].ds[k][m].dot(&f_local);
                }
                dq[(qj + m) * n + row] = x;
                dv[(qj + m) * n + row] = jk.dot(&gv[m]);
            }
        }
        // Ancestors see the subtree force turned by J too.
        for m in 0..l.dof {
            gq[m] -= ad_dual(&ws.jw[qj + m], &f);
        }
        let mut c = j;
        while let Some(p) = model.link(c).parent {
            let lp = model.link(p);
            for pm in lp.q_index..lp.q_index + lp.dof {
                let jp = &ws.jw[pm];
                let (dvq, daq, dav) = (&ws.dvdq[pm], &ws.dadq[pm], &ws.dadv[pm]);
                let jp_w = Vector3::new(jp[0], jp[1], jp[2]);
                let dvq_w = Vector3::new(dvq[0], dvq[1], dvq[2]);
                for m in 0..l.dof {
                    let col = qj + m;
                    // row j, column of the ancestor: τ_j ≻ k
                    dq[pm * n + col] = yj[m].dot(daq) + dyj[m].dot(&dvq_w);
                    dv[pm * n + col] = yj[m].dot(dav) + dyj[m].dot(&jp_w);
                    // row of the ancestor, column j: τ_j ⪯ k
                    dq[col * n + pm] = jp.dot(&gq[m]);
                    dv[col * n + pm] = jp.dot(&gv[m]);
                }
            }
            c = p;
        }
        if let Some(p) = l.parent {
            ws.ic[p] += y;
            ws.doy[p].add(&d);
            ws.of[p] += f;
        }
    }
}
