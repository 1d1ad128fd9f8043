//! Forward dynamics: the O(n) articulated-body algorithm for multi-DOF,
//! configuration-dependent joints (spline-joint paper, appendix A; the
//! transforms written `Ad_{G*}` there are those of the child's joint).
//!
//! ```text
//! backward:  U_i = Î_i S_i,  D_i = S_iᵀ U_i,  u_i = τ_i − S_iᵀ b̂_i
//!            Î_p += Ad*ᵀ (Î_i − U_i D_i⁻¹ U_iᵀ) Ad,   b̂_p += Ad* (b̂_i + Ia_i c_i + U_i D_i⁻¹ u_i)
//! forward:   q̈_i = D_i⁻¹ (u_i − U_iᵀ (Ad_{X_i⁻¹} V̇_p + c_i)),  V̇_i = Ad V̇_p + c_i + S_i q̈_i
//! ```
//! with `c_i = ad_{V_i} S_i q̇_i + Ṡ_i q̇_i` and `b̂_i = −ad*_{V_i} G_i V_i − F_ext,i` to start.

#![allow(clippy::needless_range_loop)] // index loops over coupled arrays read clearer here

use crate::dynamics::DynamicsError;
use crate::dynamics::rnea::{check_fext, check_inputs, check_out};
use crate::dynamics::workspace::{Workspace, base_acceleration, velocity_pass};
use crate::lie::{Twist, Wrench, ad_dual};
use crate::model::Model;
use nalgebra::{Matrix6, Vector3};

/// Forward dynamics: `q̈ = M⁻¹ (τ − C q̇ − g)`.
pub fn forward_dynamics(
    model: &Model,
    ws: &mut Workspace,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
    gravity: &Vector3<f64>,
    qdd: &mut [f64],
) -> Result<(), DynamicsError> {
    check_inputs(model, ws, &[("q", q), ("v", v), ("tau", tau)], gravity)?;
    check_out(model, "qdd", qdd)?;
    aba_core(model, ws, q, v, tau, gravity, None, qdd)
}

/// Forward dynamics with external wrenches (`fext[i]` on link i, link frame).
#[allow(clippy::too_many_arguments)]
pub fn forward_dynamics_ext(
    model: &Model,
    ws: &mut Workspace,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
    gravity: &Vector3<f64>,
    fext: &[Wrench],
    qdd: &mut [f64],
) -> Result<(), DynamicsError> {
    check_inputs(model, ws, &[("q", q), ("v", v), ("tau", tau)], gravity)?;
    check_out(model, "qdd", qdd)?;
    check_fext(model, fext)?;
    aba_core(model, ws, q, v, tau, gravity, Some(fext), qdd)
}

/// `Ad_{X⁻¹}ᵀ Ia Ad_{X⁻¹}`: an articulated inertia of the child moved to the
/// parent frame, by 3×3 blocks. With `C = R·block·Rᵀ` and `P = [p]`:
/// `[[C11 + P C21 − Y P, Y], [Yᵀ, C22]]`, `Y = C12 + P C22`
/// (a quarter of the work of the two 6×6 products).
#[inline]
pub(crate) fn to_parent(x: &crate::lie::Se3, ia: &Matrix6<f64>) -> Matrix6<f64> {
    let r = &x.r;
    let rt = r.transpose();
    let a11 = ia.fixed_view::<3, 3>(0, 0);
    let a12 = ia.fixed_view::<3, 3>(0, 3);
    let a22 = ia.fixed_view::<3, 3>(3, 3);
    let c11 = r * a11 * rt;
    let c12 = r * a12 * rt;
    let c22 = r * a22 * rt;
    let p = crate::lie::skew(&x.p);
    let y = c12 + p * c22;
    let tl = c11 + p * c12.transpose() - y * p;
    let mut out = Matrix6::zeros();
    out.fixed_view_mut::<3, 3>(0, 0).copy_from(&tl);
    out.fixed_view_mut::<3, 3>(0, 3).copy_from(&y);
    out.fixed_view_mut::<3, 3>(3, 0).copy_from(&y.transpose());
    out.fixed_view_mut::<3, 3>(3, 3).copy_from(&c22);
    out
}

#[allow(clippy::too_many_arguments)]
pub(crate) fn aba_core(
    model: &Model,
    ws: &mut Workspace,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
    gravity: &Vector3<f64>,
    fext: Option<&[Wrench]>,
    qdd: &mut [f64],
) -> Result<(), DynamicsError> {
    velocity_pass(model, ws, q, v, true);
    for (i, l) in model.links().iter().enumerate() {
        let g = &l.inertia;
        ws.ia[i] = g.matrix();
        let mut p = -ad_dual(&ws.v[i], &g.mul_twist(&ws.v[i]));
        if let Some(fe) = fext {
            p -= fe[i];
        }
        ws.pa[i] = p;
    }
    for i in (0..model.num_links()).rev() {
        let l = model.link(i);
        let n = l.dof;
        let ia = ws.ia[i];
        let kin = &ws.kin[i];
        let mut d = Matrix6::<f64>::identity();
        for j in 0..n {
            ws.u[i][j] = ia * kin.s[j];
            ws.uu[i][j] = tau[l.q_index + j] - kin.s[j].dot(&ws.pa[i]);
        }
        for j in 0..n {
            for k in 0..n {
                d[(j, k)] = kin.s[j].dot(&ws.u[i][k]);
            }
        }
        let scale = ia.abs().max().max(f64::MIN_POSITIVE);
        let dinv = if n == 1 {
            // The common case, without a 6×6 factorisation.
            if d[(0, 0)] <= 1e-14 * scale || !d[(0, 0)].is_finite() {
                return Err(singular(model, i));
            }
            let mut m = Matrix6::identity();
            m[(0, 0)] = 1.0 / d[(0, 0)];
            m
        } else {
            // Padding with the identity keeps the unused block invertible.
            let chol = d.cholesky().ok_or_else(|| singular(model, i))?;
            let dd = chol.l().diagonal();
            let (lo, hi) = dd
                .iter()
                .take(n.max(1))
                .fold((f64::INFINITY, 0.0f64), |(lo, hi), x| {
                    (lo.min(*x), hi.max(*x))
                });
            if n > 0 && (lo * lo <= 1e-14 * scale || hi.is_nan()) {
                return Err(singular(model, i));
            }
            chol.inverse()
        };
        ws.dinv[i] = dinv;
        if let Some(p) = l.parent {
            let mut iaa = ia;
            let mut pa = ws.pa[i];
            let mut dinv_u = [0.0; 6];
            for j in 0..n {
                for k in 0..n {
                    dinv_u[j] += dinv[(j, k)] * ws.uu[i][k];
                }
            }
            for j in 0..n {
                for k in 0..n {
                    let djk = dinv[(j, k)];
                    if djk != 0.0 {
                        iaa -= ws.u[i][j] * ws.u[i][k].transpose() * djk;
                    }
                }
                pa += ws.u[i][j] * dinv_u[j];
            }
            pa += iaa * ws.c[i];
            let xt = ws.xt[i];
            ws.ia[p] += to_parent(&xt, &iaa);
            ws.pa[p] += xt.ad_wrench(&pa);
        }
    }
    let a0 = base_acceleration(gravity);
    for (i, l) in model.links().iter().enumerate() {
        let ap = match l.parent {
            Some(p) => ws.xt[i].inv_ad_twist(&ws.a[p]),
            None => ws.xt[i].inv_ad_twist(&a0),
        };
        let a1: Twist = ap + ws.c[i];
        let n = l.dof;
        let mut r = [0.0; 6];
        for j in 0..n {
            r[j] = ws.uu[i][j] - ws.u[i][j].dot(&a1);
        }
        let mut ai = a1;
        for j in 0..n {
            let mut x = 0.0;
            for k in 0..n {
                x += ws.dinv[i][(j, k)] * r[k];
            }
            qdd[l.q_index + j] = x;
            ai += ws.kin[i].s[j] * x;
        }
        ws.a[i] = ai;
    }
    if let Some(k) = qdd.iter().position(|x| !x.is_finite()) {
        return Err(DynamicsError::Singular(format!(
            "forward dynamics produced a non-finite acceleration for `{}`; the state may be too extreme",
            model.coordinate_names()[k]
        )));
    }
    Ok(())
}

fn singular(model: &Model, i: usize) -> DynamicsError {
    let l = model.link(i);
    DynamicsError::Singular(format!(
        "forward dynamics is singular at joint `{}` (link `{}`): the links it carries have no \
         inertia along its motion; give them mass/inertia or remove the joint",
        l.joint_name, l.name
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lie::Se3;
    use nalgebra::{Rotation3, Vector3};

    #[test]
    fn blockwise_congruence_matches_the_matrices() {
        let t = Se3::new(
            Rotation3::from_euler_angles(0.7, -0.4, 2.1).into_inner(),
            Vector3::new(0.3, -1.2, 0.5),
        );
        let b = Matrix6::from_fn(|i, j| {
            ((i * 7 + j * 3) % 5) as f64 - 2.0 + (i == j) as u8 as f64 * 9.0
        });
        let ia = b + b.transpose();
        let m = t.inverse().ad_matrix();
        let expect = m.transpose() * ia * m;
        assert!((to_parent(&t, &ia) - expect).abs().max() < 1e-12 * expect.abs().max());
    }
}
