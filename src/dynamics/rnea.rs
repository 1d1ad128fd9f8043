//! Inverse dynamics: the recursive Newton–Euler algorithm in the Lie-group
//! form of the spline-joint paper (eq. 7–16), body-frame twists:
//!
//! ```text
//! V_i  = Ad_{X_i⁻¹} V_p + S_i q̇_i
//! V̇_i  = Ad_{X_i⁻¹} V̇_p + S_i q̈_i + Ṡ_i q̇_i + ad_{V_i}(S_i q̇_i)
//! F_i  = G_i V̇_i − ad*_{V_i} G_i V_i − F_ext,i + Σ_children Ad*_{X_c⁻¹} F_c
//! τ_i  = S_iᵀ F_i
//! ```
//! with `X_i = offset_i · G_i(q_i)` and the base accelerating at `−g`.

use crate::dynamics::DynamicsError;
use crate::dynamics::external::{PointForce, check_points, point_wrenches};
use crate::dynamics::state::JointState;
use crate::dynamics::workspace::{Workspace, base_acceleration, s_mul, velocity_pass};
use crate::lie::{Wrench, ad_dual};
use crate::model::Model;
use nalgebra::Vector3;

/// Checks the common inputs of the algorithms.
pub(crate) fn check_inputs(
    model: &Model,
    ws: &Workspace,
    vecs: &[(&str, &[f64])],
    gravity: &Vector3<f64>,
) -> Result<(), DynamicsError> {
    ws.check(model)?;
    for (name, x) in vecs {
        model.check_vec(name, x, model.nq())?;
    }
    if !gravity.iter().all(|g| g.is_finite()) {
        return Err(DynamicsError::Input(
            "gravity must be a finite vector".into(),
        ));
    }
    Ok(())
}

pub(crate) fn check_out(model: &Model, name: &str, x: &[f64]) -> Result<(), DynamicsError> {
    if x.len() != model.nq() {
        return Err(DynamicsError::Input(format!(
            "output `{name}` has {} entries; it must have one per coordinate ({})",
            x.len(),
            model.nq()
        )));
    }
    Ok(())
}

/// The RNEA after input checks; leaves `V`, `V̇`, `F` in the workspace.
pub(crate) fn rnea_core(
    model: &Model,
    ws: &mut Workspace,
    x: &JointState,
    gravity: &Vector3<f64>,
    fext: Option<&[Wrench]>,
    tau: &mut [f64],
) {
    velocity_pass(model, ws, x.q, x.v, true);
    rnea_sweeps(model, ws, x.a, gravity, fext, tau);
}

/// The RNEA with world forces at link points (checked): their link-frame
/// wrenches (`ws.pf`) from the poses of the velocity pass, then the sweeps.
/// Leaves the links' world poses in `ws.world` (unless there are no forces:
/// then it is [`rnea_core`], the same operations).
pub(crate) fn rnea_points(
    model: &Model,
    ws: &mut Workspace,
    x: &JointState,
    gravity: &Vector3<f64>,
    forces: &[PointForce],
    tau: &mut [f64],
) {
    if forces.is_empty() {
        return rnea_core(model, ws, x, gravity, None, tau);
    }
    velocity_pass(model, ws, x.q, x.v, true);
    point_wrenches(model, ws, forces);
    let pf = std::mem::take(&mut ws.pf);
    rnea_sweeps(model, ws, x.a, gravity, Some(&pf), tau);
    ws.pf = pf;
}

/// The RNEA's acceleration and force sweeps, after a velocity pass.
pub(crate) fn rnea_sweeps(
    model: &Model,
    ws: &mut Workspace,
    a: &[f64],
    gravity: &Vector3<f64>,
    fext: Option<&[Wrench]>,
    tau: &mut [f64],
) {
    let a0 = base_acceleration(gravity);
    for (i, l) in model.links().iter().enumerate() {
        let wa = match l.parent {
            Some(p) => ws.xt[i].inv_ad_twist(&ws.a[p]),
            None => ws.xt[i].inv_ad_twist(&a0),
        };
        let ai = wa + s_mul(&ws.kin[i], &a[l.q_index..l.q_index + l.dof]) + ws.c[i];
        ws.wa[i] = wa;
        ws.a[i] = ai;
        let g = &l.inertia;
        // Massless links (between the axes of one anatomical joint) carry no
        // inertial wrench: half of a URDF human's links.
        let mut f = if g.is_zero() {
            Wrench::zeros()
        } else {
            g.mul_twist(&ai) - ad_dual(&ws.v[i], &g.mul_twist(&ws.v[i]))
        };
        if let Some(fe) = fext {
            f -= fe[i];
        }
        ws.f[i] = f;
    }
    for i in (0..model.num_links()).rev() {
        let l = model.link(i);
        for j in 0..l.dof {
            tau[l.q_index + j] = ws.kin[i].s[j].dot(&ws.f[i]);
        }
        if let Some(p) = l.parent {
            let fp = ws.xt[i].ad_wrench(&ws.f[i]);
            ws.f[p] += fp;
        }
    }
}

/// Inverse dynamics `τ = M(q) q̈ + C(q, q̇) q̇ + g(q)`.
pub fn inverse_dynamics(
    model: &Model,
    ws: &mut Workspace,
    q: &[f64],
    v: &[f64],
    a: &[f64],
    gravity: &Vector3<f64>,
    tau: &mut [f64],
) -> Result<(), DynamicsError> {
    check_inputs(model, ws, &[("q", q), ("v", v), ("a", a)], gravity)?;
    check_out(model, "tau", tau)?;
    rnea_core(model, ws, &JointState::new(q, v, a), gravity, None, tau);
    Ok(())
}

/// Inverse dynamics with external wrenches: `fext[i]` acts on link `i`, given
/// in link i's frame, moment about its origin (`[μ; η]`).
pub fn inverse_dynamics_ext(
    model: &Model,
    ws: &mut Workspace,
    x: &JointState,
    gravity: &Vector3<f64>,
    fext: &[Wrench],
    tau: &mut [f64],
) -> Result<(), DynamicsError> {
    check_state(model, ws, x, gravity, tau)?;
    check_fext(model, fext)?;
    rnea_core(model, ws, x, gravity, Some(fext), tau);
    Ok(())
}

/// Inverse dynamics with world forces at link points:
/// `τ = ID(q, q̇, q̈) − Σ_c J_cᵀ [m_c; f_c]`, the joint forces that, with the
/// given forces, produce the motion (see [`PointForce`]).
pub fn inverse_dynamics_at_points(
    model: &Model,
    ws: &mut Workspace,
    x: &JointState,
    gravity: &Vector3<f64>,
    forces: &[PointForce],
    tau: &mut [f64],
) -> Result<(), DynamicsError> {
    check_state(model, ws, x, gravity, tau)?;
    check_points(model, forces)?;
    rnea_points(model, ws, x, gravity, forces, tau);
    Ok(())
}

/// The state, gravity and output of an inverse dynamics call.
fn check_state(
    model: &Model,
    ws: &Workspace,
    x: &JointState,
    gravity: &Vector3<f64>,
    tau: &[f64],
) -> Result<(), DynamicsError> {
    check_inputs(model, ws, &[("q", x.q), ("v", x.v), ("a", x.a)], gravity)?;
    check_out(model, "tau", tau)
}

pub(crate) fn check_fext(model: &Model, fext: &[Wrench]) -> Result<(), DynamicsError> {
    if fext.len() != model.num_links() {
        return Err(DynamicsError::Input(format!(
            "external wrenches: {} given, need one per link ({})",
            fext.len(),
            model.num_links()
        )));
    }
    if fext.iter().any(|f| !f.iter().all(|x| x.is_finite())) {
        return Err(DynamicsError::Input(
            "external wrenches must be finite".into(),
        ));
    }
    Ok(())
}

/// `C(q, q̇) q̇ + g(q)`: inverse dynamics at zero acceleration.
pub fn nonlinear_effects(
    model: &Model,
    ws: &mut Workspace,
    q: &[f64],
    v: &[f64],
    gravity: &Vector3<f64>,
    out: &mut [f64],
) -> Result<(), DynamicsError> {
    check_inputs(model, ws, &[("q", q), ("v", v)], gravity)?;
    check_out(model, "nle", out)?;
    // Reuse `out` as the zero acceleration: rnea_core reads a[i] before writing tau[i]
    // only per link, so give it a separate zero slice from the workspace.
    let mut zero = std::mem::take(&mut ws.tau);
    zero.iter_mut().for_each(|x| *x = 0.0);
    rnea_core(model, ws, &JointState::new(q, v, &zero), gravity, None, out);
    ws.tau = zero;
    Ok(())
}

/// The wrench the world applies to the tree through its root joints in the
/// last RNEA run on `ws` (`inverse_dynamics*`): moment about the world origin
/// and force, world axes. For a body whose root joint is free (6 DOFs) this is
/// the external wrench its motion needs: what contacts must supply.
pub fn root_wrench(model: &Model, ws: &Workspace) -> Wrench {
    let mut w = Wrench::zeros();
    for (i, l) in model.links().iter().enumerate() {
        if l.parent.is_none() {
            w += ws.xt[i].ad_wrench(&ws.f[i]);
        }
    }
    w
}
