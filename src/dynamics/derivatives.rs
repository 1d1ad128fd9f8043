//! Analytic derivatives of inverse dynamics: `∂τ/∂q` and `∂τ/∂q̇`
//! (`∂τ/∂q̈ = M`, see [`mass_matrix`](super::mass_matrix)).
//!
//! Forward-mode differentiation of the RNEA, one coordinate at a time: a
//! coordinate of link j changes `V, V̇, F` only in j's subtree, and `F` along
//! the path from j to the root, so a column costs O(subtree + depth).
//! Differentiating `X_j = offset · G(q)`: `∂(Ad_{X⁻¹} W)/∂q_k = −ad_{s_k} Ad_{X⁻¹} W`
//! and `∂(Ad*_{X⁻¹} F)/∂q_k = Ad*_{X⁻¹}(∂F − ad*_{s_k} F)`.
//!
//! For joints whose Jacobian depends on q, `∂(Ṡ q̇)/∂q` needs the third
//! derivative of the joint map, which the `Joint` trait does not give: that one
//! term is a central difference of the joint's Hessian (step 1e-5, error ~1e-10
//! relative). Every other term, and everything for revolute/prismatic joints, is exact.

use crate::dynamics::DynamicsError;
use crate::dynamics::rnea::{check_inputs, rnea_core};
use crate::dynamics::workspace::{Workspace, sdot_v};
use crate::lie::{Twist, ad, ad_dual};
use crate::model::Model;
use crate::model::joint::{Derivatives, Joint, JointKinematics};
use nalgebra::{DMatrix, Vector3};

/// `∂(Ṡ(q) q̇)/∂q_k` of one joint by a difference of its Hessian: central, or
/// one-sided (second order) where the central stencil would straddle an end of
/// the coordinate's range: a spline joint's Hessian may jump there (SimmSpline
/// extends linearly past its knots), and the inside value is the one wanted.
pub(crate) fn sdot_v_dq(
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

/// Fills `dtau_dq` and `dtau_dv` (nq × nq; `[i][j] = ∂τ_i/∂x_j`) at `(q, q̇, q̈)`.
#[allow(clippy::too_many_arguments)]
pub fn rnea_derivatives(
    model: &Model,
    ws: &mut Workspace,
    q: &[f64],
    v: &[f64],
    a: &[f64],
    gravity: &Vector3<f64>,
    dtau_dq: &mut DMatrix<f64>,
    dtau_dv: &mut DMatrix<f64>,
) -> Result<(), DynamicsError> {
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
    let mut tau = std::mem::take(&mut ws.tau);
    rnea_core(model, ws, q, v, a, gravity, None, &mut tau);
    ws.tau = tau;
    // Entries outside a column's subtree and ancestors stay zero.
    dtau_dq.fill(0.0);
    dtau_dv.fill(0.0);
    for x in ws.mark.iter_mut() {
        *x = 0;
    }
    for j in 0..model.num_links() {
        let l = model.link(j);
        for k in 0..l.dof {
            let col = l.q_index + k;
            // ∂/∂q_k
            let (dv, da) = seed_q(model, ws, j, k, q, v, a);
            sweep(model, ws, j, dv, da, Some(k), dtau_dq, col);
            // ∂/∂q̇_k
            let (dv, da) = seed_v(model, ws, j, k, v);
            sweep(model, ws, j, dv, da, None, dtau_dv, col);
        }
    }
    Ok(())
}

/// Derivative of `V_j`, `V̇_j` with respect to coordinate k of link j.
fn seed_q(
    model: &Model,
    ws: &mut Workspace,
    j: usize,
    k: usize,
    q: &[f64],
    v: &[f64],
    a: &[f64],
) -> (Twist, Twist) {
    let l = model.link(j);
    let r = l.q_index..l.q_index + l.dof;
    let kin = &ws.kin[j];
    let sk = kin.s[k];
    let mut dsv = Twist::zeros();
    let mut dsa = Twist::zeros();
    if !l.constant_jacobian {
        for m in 0..l.dof {
            dsv += kin.ds[m][k] * v[l.q_index + m];
            dsa += kin.ds[m][k] * a[l.q_index + m];
        }
    }
    let dv = -ad(&sk, &ws.wv[j]) + dsv;
    let mut da = -ad(&sk, &ws.wa[j]) + dsa + ad(&dv, &ws.sv[j]) + ad(&ws.v[j], &dsv);
    if !l.constant_jacobian {
        let lim = l
            .limits
            .get(k)
            .map_or((f64::NEG_INFINITY, f64::INFINITY), |x| (x.lower, x.upper));
        da += sdot_v_dq(
            l.joint.as_ref(),
            lim,
            &q[r.clone()],
            &v[r],
            k,
            &mut ws.scratch,
        );
    }
    (dv, da)
}

/// Derivative of `V_j`, `V̇_j` with respect to velocity k of link j.
fn seed_v(model: &Model, ws: &Workspace, j: usize, k: usize, v: &[f64]) -> (Twist, Twist) {
    let l = model.link(j);
    let kin = &ws.kin[j];
    let sk = kin.s[k];
    let mut da = ad(&sk, &ws.sv[j]) + ad(&ws.v[j], &sk);
    if !l.constant_jacobian {
        for m in 0..l.dof {
            da += (kin.ds[m][k] + kin.ds[k][m]) * v[l.q_index + m];
        }
    }
    (sk, da)
}

/// Propagates a seed at link j through its subtree and up to the root, writing
/// column `col` of `out`. `qk = Some(k)` adds the terms of a configuration
/// derivative (moving X_j and S_j).
#[allow(clippy::too_many_arguments)]
fn sweep(
    model: &Model,
    ws: &mut Workspace,
    j: usize,
    dv: Twist,
    da: Twist,
    qk: Option<usize>,
    out: &mut DMatrix<f64>,
    col: usize,
) {
    let nl = model.num_links();
    // A link carries the stamp j + 1 exactly when it is in j's subtree: only
    // sweeps of j write that stamp, and they write it on that subtree. So the
    // marks need no reset between columns.
    let stamp = j + 1;
    ws.mark[j] = stamp;
    ws.dv[j] = dv;
    ws.da[j] = da;
    for i in j..nl {
        let l = model.link(i);
        if i != j {
            match l.parent {
                Some(p) if ws.mark[p] == stamp => {
                    ws.mark[i] = stamp;
                    ws.dv[i] = ws.xt[i].inv_ad_twist(&ws.dv[p]);
                    ws.da[i] = ws.xt[i].inv_ad_twist(&ws.da[p]) + ad(&ws.dv[i], &ws.sv[i]);
                }
                _ => continue,
            }
        }
        let g = &l.inertia;
        ws.df[i] = g.mul_twist(&ws.da[i])
            - ad_dual(&ws.dv[i], &g.mul_twist(&ws.v[i]))
            - ad_dual(&ws.v[i], &g.mul_twist(&ws.dv[i]));
    }
    for i in (j + 1..nl).rev() {
        if ws.mark[i] != stamp {
            continue;
        }
        let l = model.link(i);
        for m in 0..l.dof {
            out[(l.q_index + m, col)] = ws.kin[i].s[m].dot(&ws.df[i]);
        }
        if let Some(p) = l.parent {
            let up = ws.xt[i].ad_wrench(&ws.df[i]);
            ws.df[p] += up;
        }
    }
    let l = model.link(j);
    for m in 0..l.dof {
        let mut x = ws.kin[j].s[m].dot(&ws.df[j]);
        if let Some(k) = qk
            && !l.constant_jacobian
        {
            x += ws.kin[j].ds[m][k].dot(&ws.f[j]);
        }
        out[(l.q_index + m, col)] = x;
    }
    // Up the path to the root.
    let mut df = ws.df[j];
    if let Some(k) = qk {
        df -= ad_dual(&ws.kin[j].s[k], &ws.f[j]);
    }
    let mut c = j;
    while let Some(p) = model.link(c).parent {
        df = ws.xt[c].ad_wrench(&df);
        let lp = model.link(p);
        for m in 0..lp.dof {
            out[(lp.q_index + m, col)] = ws.kin[p].s[m].dot(&df);
        }
        c = p;
    }
}
