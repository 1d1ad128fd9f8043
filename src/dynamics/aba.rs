//! Forward dynamics: the O(n) articulated-body algorithm for multi-DOF,
//! configuration-dependent joints (spline-joint paper, appendix A), run in
//! link-aligned frames: each link's quantities are expressed with the world's
//! orientation at the link's origin, with joint columns `J_i = R_i S_i`:
//!
//! ```text
//! backward:  U_i = Ia_i J_i,  D_i = J_iᵀ U_i,  u_i = τ_i − J_iᵀ p_i
//!            Ia_λ += Xᵀ(Ia_i − U_i D_i⁻¹ U_iᵀ)X,   p_λ += Xᵀ(p_i + (Ia_i − U D⁻¹ Uᵀ) c_i + U_i D_i⁻¹ u_i)
//! forward:   q̈_i = D_i⁻¹ (u_i − U_iᵀ (X a_λ + c_i)),  a_i = X a_λ + c_i + J_i q̈_i
//! ```
//! with `c_i = X v_λ × J_i q̇_i + R_i(Ṡ_i q̇_i)`, `p_i = v_i ×* Y_i v_i − F_ext,i`
//! to start and the base accelerating at `−g`. `X` moves a twist from the
//! parent's origin to the child's: a pure translation, so passing an
//! articulated inertia up costs a third of the per-link frame's 6×6 congruence,
//! while every quantity stays as precise as in the link's own frame (a single
//! world frame loses digits on links far from its origin).

#![allow(clippy::needless_range_loop)] // index loops over coupled arrays read clearer here

use crate::dynamics::DynamicsError;
use crate::dynamics::rnea::{check_fext, check_inputs, check_out};
use crate::dynamics::state::Forces;
use crate::dynamics::workspace::{
    Workspace, aligned_velocity_pass, base_acceleration, shift_twist,
};
use crate::lie::{Se3, Twist, Wrench, ad_dual};
use crate::model::Model;
use crate::model::joint::AxisMotion;
use nalgebra::{Matrix3, Matrix6, Vector3};

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
    aba_core(model, ws, q, v, &Forces::new(tau, gravity), qdd)
}

/// Forward dynamics under `forces`, external wrenches included
/// (`fext[i]` on link i, link frame).
pub fn forward_dynamics_ext(
    model: &Model,
    ws: &mut Workspace,
    q: &[f64],
    v: &[f64],
    forces: &Forces,
    qdd: &mut [f64],
) -> Result<(), DynamicsError> {
    check_inputs(
        model,
        ws,
        &[("q", q), ("v", v), ("tau", forces.tau)],
        forces.gravity,
    )?;
    check_out(model, "qdd", qdd)?;
    if let Some(fext) = forces.fext {
        check_fext(model, fext)?;
    }
    aba_core(model, ws, q, v, forces, qdd)
}

/// A wrench given at a child's origin, expressed at its parent's (`d` = child − parent).
#[inline]
fn wrench_to_parent(f: &Wrench, d: &Vector3<f64>) -> Wrench {
    let n = Vector3::new(f[3], f[4], f[5]);
    let m = Vector3::new(f[0], f[1], f[2]) + d.cross(&n);
    Wrench::new(m.x, m.y, m.z, n.x, n.y, n.z)
}

/// `out += Xᵀ Ia X` for the translation `X` of [`shift_twist`]: by 3×3 blocks,
/// `[[A + P Bᵀ − Y P, Y], [Yᵀ, C]]` with `Y = B + P C`, `P = [d]`. The products
/// with the skew matrix `P` are cross products (`P M` column by column, `M P`
/// row by row): 54 multiplications instead of 81, added straight into the
/// parent's blocks.
#[inline]
fn add_inertia_to_parent(out: &mut Matrix6<f64>, ia: &Matrix6<f64>, d: &Vector3<f64>) {
    let a: Matrix3<f64> = ia.fixed_view::<3, 3>(0, 0).into_owned();
    let b: Matrix3<f64> = ia.fixed_view::<3, 3>(0, 3).into_owned();
    let c: Matrix3<f64> = ia.fixed_view::<3, 3>(3, 3).into_owned();
    // P C and P Bᵀ: d × each column of C, d × each row of B.
    let pc = Matrix3::from_columns(&[
        d.cross(&c.column(0)),
        d.cross(&c.column(1)),
        d.cross(&c.column(2)),
    ]);
    let pbt = Matrix3::from_columns(&[
        d.cross(&b.row(0).transpose()),
        d.cross(&b.row(1).transpose()),
        d.cross(&b.row(2).transpose()),
    ]);
    let y = b + pc;
    // Row i of Y P is (row i of Y) × d.
    let yp = Matrix3::from_rows(&[
        y.row(0).transpose().cross(d).transpose(),
        y.row(1).transpose().cross(d).transpose(),
        y.row(2).transpose().cross(d).transpose(),
    ]);
    let tl = a + pbt - yp;
    let mut o = out.fixed_view_mut::<3, 3>(0, 0);
    o += tl;
    let mut o = out.fixed_view_mut::<3, 3>(0, 3);
    o += y;
    let mut o = out.fixed_view_mut::<3, 3>(3, 0);
    o += y.transpose();
    let mut o = out.fixed_view_mut::<3, 3>(3, 3);
    o += c;
}

pub(crate) fn aba_core(
    model: &Model,
    ws: &mut Workspace,
    q: &[f64],
    v: &[f64],
    forces: &Forces,
    qdd: &mut [f64],
) -> Result<(), DynamicsError> {
    let (tau, gravity, fext) = (forces.tau, forces.gravity, forces.fext);
    aligned_velocity_pass(model, ws, q, v);
    for (i, l) in model.links().iter().enumerate() {
        let t = &Se3::from_rotation(ws.world[i].r);
        // Massless links (between the axes of one anatomical joint: half of a
        // URDF human's links) start with no inertia and no bias wrench.
        if l.inertia.is_zero() {
            ws.ia[i] = Matrix6::zeros();
            ws.pa[i] = match fext {
                Some(fe) => -t.ad_wrench(&fe[i]),
                None => Wrench::zeros(),
            };
            continue;
        }
        let y = l.inertia.transformed(t);
        let ov = &ws.ov[i];
        ws.ia[i] = y.matrix();
        let mut p = -ad_dual(ov, &y.mul_twist(ov));
        if let Some(fe) = fext {
            p -= t.ad_wrench(&fe[i]);
        }
        ws.pa[i] = p;
    }
    for i in (0..model.num_links()).rev() {
        let l = model.link(i);
        let n = l.dof;
        let qi = l.q_index;
        let ia = ws.ia[i];
        // Singularity is judged against the size of Ia along the joint: the
        // largest diagonal entry bounds every entry of a PSD matrix.
        let diag = (0..6).fold(0.0f64, |m, k| m.max(ia[(k, k)].abs()));
        let mut pa = ws.pa[i];
        let mut iaa = ia;
        if n == 1 {
            let j = ws.jw[qi];
            // A one-axis joint's link-aligned column is zero in one half (the
            // axis passes through the link's origin): U = Ia J needs only
            // that half's three columns of Ia, 18 multiplications instead of 36.
            let u = match l.axis.map(|a| a.motion) {
                Some(AxisMotion::Rotation) => ia.fixed_columns::<3>(0) * j.fixed_rows::<3>(0),
                Some(AxisMotion::Translation) => ia.fixed_columns::<3>(3) * j.fixed_rows::<3>(3),
                None => ia * j,
            };
            let d = j.dot(&u);
            let scale = (diag * j.norm_squared()).max(f64::MIN_POSITIVE);
            if d <= 1e-14 * scale || !d.is_finite() {
                return Err(singular(model, i));
            }
            let dinv = 1.0 / d;
            let uu = tau[qi] - j.dot(&pa);
            ws.u[i][0] = u;
            ws.uu[i][0] = uu;
            ws.dinv[i][(0, 0)] = dinv;
            if l.parent.is_some() {
                iaa -= u * (u.transpose() * dinv);
                pa += u * (dinv * uu);
            }
        } else if n > 1 {
            let mut d = Matrix6::<f64>::identity();
            let mut jn2 = 0.0f64;
            for j in 0..n {
                let jj = ws.jw[qi + j];
                jn2 = jn2.max(jj.norm_squared());
                ws.u[i][j] = ia * jj;
                ws.uu[i][j] = tau[qi + j] - jj.dot(&pa);
            }
            for j in 0..n {
                for k in 0..n {
                    d[(j, k)] = ws.jw[qi + j].dot(&ws.u[i][k]);
                }
            }
            let scale = (diag * jn2).max(f64::MIN_POSITIVE);
            // Padding with the identity keeps the unused block invertible.
            let chol = d.cholesky().ok_or_else(|| singular(model, i))?;
            let dd = chol.l().diagonal();
            let (lo, hi) = dd
                .iter()
                .take(n)
                .fold((f64::INFINITY, 0.0f64), |(lo, hi), x| {
                    (lo.min(*x), hi.max(*x))
                });
            if lo * lo <= 1e-14 * scale || hi.is_nan() {
                return Err(singular(model, i));
            }
            let dinv = chol.inverse();
            ws.dinv[i] = dinv;
            if l.parent.is_some() {
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
            }
        }
        if let Some(p) = l.parent {
            pa += iaa * ws.c[i];
            let d = ws.shift[i];
            add_inertia_to_parent(&mut ws.ia[p], &iaa, &d);
            ws.pa[p] += wrench_to_parent(&pa, &d);
        }
    }
    let a0 = base_acceleration(gravity);
    for (i, l) in model.links().iter().enumerate() {
        let ap = match l.parent {
            Some(p) => shift_twist(&ws.oa[p], &ws.shift[i]),
            None => a0,
        };
        let a1: Twist = ap + ws.c[i];
        let n = l.dof;
        let qi = l.q_index;
        let mut ai = a1;
        if n == 1 {
            let x = ws.dinv[i][(0, 0)] * (ws.uu[i][0] - ws.u[i][0].dot(&a1));
            qdd[qi] = x;
            ai += ws.jw[qi] * x;
        } else {
            let mut r = [0.0; 6];
            for j in 0..n {
                r[j] = ws.uu[i][j] - ws.u[i][j].dot(&a1);
            }
            for j in 0..n {
                let mut x = 0.0;
                for k in 0..n {
                    x += ws.dinv[i][(j, k)] * r[k];
                }
                qdd[qi + j] = x;
                ai += ws.jw[qi + j] * x;
            }
        }
        ws.oa[i] = ai;
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
