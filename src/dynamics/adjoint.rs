//! The gradient of `J = Σ wᵢ τᵢ²` with respect to q, q̇ and q̈ by the adjoint
//! (reverse) sweep of the RNEA: O(n) per sample, the spacetime objective's
//! gradient (Rose 1996 §3 computes the O(n²) Jacobians instead).
//!
//! Reverse of the RNEA of [`rnea`](super::rnea), with `X_i = Ad_{X_i⁻¹}` and
//! adjoint variables `F̄, V̄, Λ = V̄̇`:
//!
//! ```text
//! τ̄ = 2 w τ
//! F̄_i = X_i F̄_p + S_i τ̄_i                                  (root → leaves)
//! Λ_i = G_i F̄_i + Σ_c X_cᵀ Λ_c
//! V̄_i = ad*_{F̄_i}(G_i V_i) − G_i ad_{V_i} F̄_i − ad*_{S q̇}Λ_i + Σ_c X_cᵀ V̄_c    (leaves → root)
//! q̈̄ = Sᵀ Λ,   q̇̄ = Sᵀ (V̄ + ad*_{V} Λ) (+ Hessian terms),
//! q̄_k = s_k·(ad*_{X V_p} V̄ + ad*_{X V̇_p} Λ + ad*_{X F̄_p} F) (+ Hessian terms)
//! ```

use crate::dynamics::DynamicsError;
use crate::dynamics::derivatives::sdot_v_gradient;
use crate::dynamics::external::{PointForce, add_turning_gradient, check_points};
use crate::dynamics::rnea::{check_inputs, check_out, rnea_points};
use crate::dynamics::state::{JointState, StateGradient};
use crate::dynamics::workspace::Workspace;
use crate::lie::{Twist, Wrench, ad, ad_dual};
use crate::model::Model;
use crate::model::joint::MAX_JOINT_DOF;
use nalgebra::Vector3;

/// Returns `Σ wᵢ τᵢ²` with `τ` the inverse dynamics at `(q, q̇, q̈)`, and writes
/// its gradient with respect to `q`, `q̇`, `q̈` into `grad` (written, not added).
pub fn torque_sq_gradient(
    model: &Model,
    ws: &mut Workspace,
    x: &JointState,
    gravity: &Vector3<f64>,
    weights: &[f64],
    grad: StateGradient,
) -> Result<f64, DynamicsError> {
    torque_sq_gradient_at_points(model, ws, x, gravity, weights, &[], grad)
}

/// [`torque_sq_gradient`] with world forces at link points
/// (`τ = ID − Σ_c J_cᵀ [m_c; f_c]`, see [`PointForce`]): the gradient is exact
/// with the forces held fixed in the world (their points move with q).
pub fn torque_sq_gradient_at_points(
    model: &Model,
    ws: &mut Workspace,
    x: &JointState,
    gravity: &Vector3<f64>,
    weights: &[f64],
    forces: &[PointForce],
    grad: StateGradient,
) -> Result<f64, DynamicsError> {
    let (q, v, a) = (x.q, x.v, x.a);
    let StateGradient {
        q: gq,
        v: gv,
        a: ga,
    } = grad;
    check_inputs(
        model,
        ws,
        &[("q", q), ("v", v), ("a", a), ("weights", weights)],
        gravity,
    )?;
    check_out(model, "gq", gq)?;
    check_out(model, "gv", gv)?;
    check_out(model, "ga", ga)?;
    check_points(model, forces)?;
    let mut tau = std::mem::take(&mut ws.tau);
    rnea_points(model, ws, x, gravity, forces, &mut tau);
    let mut cost = 0.0;
    for i in 0..tau.len() {
        cost += weights[i] * tau[i] * tau[i];
        // τ̄ is kept in place of τ from here on.
        tau[i] *= 2.0 * weights[i];
    }
    reverse_sweep(model, ws, x, &tau, None, [gq, gv, ga]);
    ws.tau = tau;
    if !forces.is_empty() {
        add_turning_gradient(model, ws, forces, gq);
    }
    Ok(cost)
}

/// The reverse sweep after an RNEA on `ws` at `x`: writes into `gq, gv, ga`
/// the gradient of τ̄·τ + ρ·w_root with respect to q, q̇, q̈, τ̄ = `tbar`
/// and ρ = `root` (none: 0), w_root the wrench the world applies through
/// the root joints ([`crate::dynamics::root_wrench`]). The world is the
/// roots' parent, so ρ enters as the parent's F̄ does for any link: the
/// derivative of each root's own transform is then the `X F̄_p` term. The
/// forces' turning part is not added here ([`add_turning_gradient`]).
pub(crate) fn reverse_sweep(
    model: &Model,
    ws: &mut Workspace,
    x: &JointState,
    tbar: &[f64],
    root: Option<&Twist>,
    [gq, gv, ga]: [&mut [f64]; 3],
) {
    let (q, v, a) = (x.q, x.v, x.a);
    // Reuse the derivative buffers: dv = V̄, da = Λ, df = F̄.
    for (i, l) in model.links().iter().enumerate() {
        let mut fb = Twist::zeros();
        for m in 0..l.dof {
            fb += ws.kin[i].s[m] * tbar[l.q_index + m];
        }
        match (l.parent, root) {
            (Some(p), _) => fb += ws.xt[i].inv_ad_twist(&ws.df[p]),
            (None, Some(rho)) => fb += ws.xt[i].inv_ad_twist(rho),
            (None, None) => {}
        }
        ws.df[i] = fb;
        let g = &l.inertia;
        ws.da[i] = g.mul_twist(&fb);
        ws.dv[i] = ad_dual(&fb, &g.mul_twist(&ws.v[i])) - g.mul_twist(&ad(&ws.v[i], &fb));
    }
    for i in (0..model.num_links()).rev() {
        let l = model.link(i);
        let lam = ws.da[i];
        // Through V̇_i = X V̇_p + S q̈ + Ṡ q̇ + ad(V_i, S q̇).
        ws.dv[i] -= ad_dual(&ws.sv[i], &lam);
        let ubar = ad_dual(&ws.v[i], &lam);
        let vb = ws.dv[i];
        // F̄ minus its own S τ̄ part is X F̄_p.
        let mut xfp = ws.df[i];
        for m in 0..l.dof {
            xfp -= ws.kin[i].s[m] * tbar[l.q_index + m];
        }
        let qterm = ad_dual(&ws.wv[i], &vb) + ad_dual(&ws.wa[i], &lam) + ad_dual(&xfp, &ws.f[i]);
        let kin = &ws.kin[i];
        for k in 0..l.dof {
            let c = l.q_index + k;
            let sk = kin.s[k];
            ga[c] = sk.dot(&lam);
            gv[c] = sk.dot(&(vb + ubar));
            gq[c] = sk.dot(&qterm);
        }
        if !l.constant_jacobian {
            let r = l.q_index..l.q_index + l.dof;
            for k in 0..l.dof {
                let c = l.q_index + k;
                let mut gqk = 0.0;
                let mut gvk = 0.0;
                for m in 0..l.dof {
                    let dsmk = kin.ds[m][k];
                    let vm = v[l.q_index + m];
                    gqk += tbar[l.q_index + m] * dsmk.dot(&ws.f[i])
                        + vm * dsmk.dot(&(vb + ubar))
                        + a[l.q_index + m] * dsmk.dot(&lam);
                    gvk += vm * (kin.ds[m][k] + kin.ds[k][m]).dot(&lam);
                }
                gq[c] += gqk;
                gv[c] += gvk;
            }
            let mut third = [Twist::zeros(); MAX_JOINT_DOF];
            sdot_v_gradient(l, &q[r.clone()], &v[r], &mut ws.scratch, &mut third);
            for k in 0..l.dof {
                gq[l.q_index + k] += third[k].dot(&lam);
            }
        }
        if let Some(p) = l.parent {
            let xt = ws.xt[i];
            let up_a = xt.ad_wrench(&lam);
            let up_v = xt.ad_wrench(&vb);
            ws.da[p] += up_a;
            ws.dv[p] += up_v;
        }
    }
}

/// Inverse dynamics with world forces at link points at one state, kept so
/// that any number of reverse sweeps can follow it: the gradient of any
/// function of the torques and of the root's wrench for the price of one
/// RNEA plus one sweep each (a residual's Jacobian rows, one sweep a row).
/// Holds the workspace until dropped.
pub struct InverseDynamicsPass<'w> {
    model: &'w Model,
    ws: &'w mut Workspace,
    x: JointState<'w>,
    forces: &'w [PointForce],
    tau: Vec<f64>,
}

impl<'w> InverseDynamicsPass<'w> {
    /// Runs the RNEA at `x` with the forces `forces` acting
    /// (`τ = ID − Σ J_cᵀ [m_c; f_c]`, as [`crate::dynamics::inverse_dynamics_at_points`]).
    pub fn new(
        model: &'w Model,
        ws: &'w mut Workspace,
        x: JointState<'w>,
        gravity: &Vector3<f64>,
        forces: &'w [PointForce],
    ) -> Result<Self, DynamicsError> {
        check_inputs(model, ws, &[("q", x.q), ("v", x.v), ("a", x.a)], gravity)?;
        check_points(model, forces)?;
        let mut tau = std::mem::take(&mut ws.tau);
        rnea_points(model, ws, &x, gravity, forces, &mut tau);
        Ok(InverseDynamicsPass {
            model,
            ws,
            x,
            forces,
            tau,
        })
    }

    /// τ at the state.
    pub fn tau(&self) -> &[f64] {
        &self.tau
    }

    /// The wrench the world applies through the root joints (moment about
    /// the world origin, force; world axes): with a free root, what the
    /// forces leave for the ground to supply.
    pub fn root_wrench(&self) -> Wrench {
        crate::dynamics::root_wrench(self.model, self.ws)
    }

    /// Writes into `grad` the gradient with respect to q, q̇, q̈ of
    /// `tau_bar · τ + root_bar · w_root` (a vector–Jacobian product; for
    /// J(τ, w_root), the seeds are ∂J/∂τ and ∂J/∂w_root), the forces held
    /// fixed in the world. `root_bar` pairs with the wrench `[moment; force]`
    /// component by component.
    pub fn reverse(
        &mut self,
        tau_bar: &[f64],
        root_bar: &Twist,
        grad: StateGradient,
    ) -> Result<(), DynamicsError> {
        let model = self.model;
        check_out(model, "tau_bar", tau_bar)?;
        let StateGradient { q, v, a } = grad;
        for (name, g) in [("gq", &*q), ("gv", &*v), ("ga", &*a)] {
            check_out(model, name, g)?;
        }
        if !tau_bar.iter().chain(root_bar.iter()).all(|x| x.is_finite()) {
            return Err(DynamicsError::Input(
                "the seeds of a reverse sweep must be finite".into(),
            ));
        }
        reverse_sweep(
            model,
            self.ws,
            &self.x,
            tau_bar,
            Some(root_bar),
            [&mut *q, &mut *v, &mut *a],
        );
        if !self.forces.is_empty() {
            add_turning_gradient(model, self.ws, self.forces, q);
        }
        Ok(())
    }
}

impl Drop for InverseDynamicsPass<'_> {
    fn drop(&mut self) {
        // the workspace keeps its buffer
        self.ws.tau = std::mem::take(&mut self.tau);
    }
}
