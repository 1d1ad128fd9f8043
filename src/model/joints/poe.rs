//! The product-of-exponentials engine shared by most joints (spline-joint
//! paper eq. 26–31 and appendix B):
//!
//!   G(q) = H · Π_{k=1..m} exp(ĝ_k φ_k(q)) · C
//!
//! with constant twists ĝ_k, scalar functions φ_k of the coordinates, and
//! constant head H and tail C. The body Jacobian column i is
//!   μ_k^i = ĝ_k ∂φ_k/∂q_i + Ad⁻¹_{exp(ĝ_k φ_k)} μ_{k−1}^i,   s_i = Ad_{C}⁻¹ μ_m^i
//! and its derivative
//!   ∂μ_k^i/∂q_j = ĝ_k ∂²φ_k/∂q_i∂q_j
//!                 + Ad⁻¹_{exp(ĝ_k φ_k)} (∂μ_{k−1}^i/∂q_j + ad_{μ_{k−1}^i} ĝ_k ∂φ_k/∂q_j).
//!
//! The dynamics' derivatives also need one third-derivative term, the gradient
//! of `Ṡ q̇ = Σ_ij ∂s_i/∂q_j q̇_i q̇_j` at fixed q̇. Contracting the recursion
//! with q̇ (u = Σ μ^i q̇_i, w = Σ ∂μ^i/∂q_j q̇_i q̇_j; φ_v = Σ φ_i q̇_i, …) gives
//!   u_k = ĝ φ_v + Ad⁻¹ u_{k−1},   w_k = ĝ φ_vv + Ad⁻¹ X,   X = w_{k−1} + ad_{u_{k−1}} ĝ φ_v
//! and, since ∂(Ad⁻¹_{exp(ĝφ)} Y)/∂q_m = Ad⁻¹ (∂Y/∂q_m + φ_m ad_Y ĝ),
//!   ∂u_k/∂q_m = ĝ φ_vm + Ad⁻¹ (∂u_{k−1}/∂q_m + φ_m ad_{u_{k−1}} ĝ)
//!   ∂w_k/∂q_m = ĝ φ_vvm + Ad⁻¹ (∂w_{k−1}/∂q_m + ad_{∂u_{k−1}/∂q_m} ĝ φ_v
//!                                + ad_{u_{k−1}} ĝ φ_vm + φ_m ad_X ĝ)
//! ([`poe_sdot_v_dq`]); each factor supplies φ_vvm = Σ_ij ∂³φ/∂q_i∂q_j∂q_m q̇_i q̇_j.
// Index loops mirror the equations (several arrays per index); iterators would obscure them.
#![allow(clippy::needless_range_loop)]

use crate::lie::{Se3, Twist, ad, exp_se3};
use crate::model::joint::{Derivatives, JointKinematics, MAX_JOINT_DOF};

/// One factor exp(ĝ φ) of the product: the twist and φ with its derivatives
/// with respect to the joint coordinates.
#[derive(Clone, Copy, Debug)]
pub struct PoeFactor {
    pub twist: Twist,
    pub phi: f64,
    /// ∂φ/∂q_i
    pub dphi: [f64; MAX_JOINT_DOF],
    /// ∂²φ/∂q_i∂q_j
    pub ddphi: [[f64; MAX_JOINT_DOF]; MAX_JOINT_DOF],
    /// Σ_ij ∂³φ/∂q_i∂q_j∂q_m q̇_i q̇_j for each m: the third derivative
    /// contracted with the velocity, set only for [`poe_sdot_v_dq`] (zero when φ
    /// is at most quadratic, e.g. linear in the coordinates).
    pub dddphi_vv: [f64; MAX_JOINT_DOF],
}

impl PoeFactor {
    pub fn new(twist: Twist, phi: f64) -> Self {
        PoeFactor {
            twist,
            phi,
            dphi: [0.0; MAX_JOINT_DOF],
            ddphi: [[0.0; MAX_JOINT_DOF]; MAX_JOINT_DOF],
            dddphi_vv: [0.0; MAX_JOINT_DOF],
        }
    }

    /// A factor driven by one coordinate `i` through φ = f(q_i) with f', f''.
    pub fn of_coordinate(twist: Twist, i: usize, f: [f64; 3]) -> Self {
        let mut p = PoeFactor::new(twist, f[0]);
        p.dphi[i] = f[1];
        p.ddphi[i][i] = f[2];
        p
    }

    /// As [`PoeFactor::of_coordinate`], with the third derivative `f[3]` of f
    /// contracted with the coordinate's velocity `v_i` (for [`poe_sdot_v_dq`]).
    pub fn of_coordinate3(twist: Twist, i: usize, f: [f64; 4], v_i: f64) -> Self {
        let mut p = PoeFactor::of_coordinate(twist, i, [f[0], f[1], f[2]]);
        p.dddphi_vv[i] = f[3] * v_i * v_i;
        p
    }
}

/// `out[m] = ∂(Ṡ q̇)/∂q_m` (m < n, body frame) for G = head · Π exp(ĝ_k φ_k) ·
/// tail at fixed velocity `v`; the factors must carry `dddphi_vv` for this `v`.
/// The head does not enter (it is constant and left of every factor).
pub fn poe_sdot_v_dq(
    factors: &[PoeFactor],
    tail: Option<&Se3>,
    n: usize,
    v: &[f64],
    out: &mut [Twist; MAX_JOINT_DOF],
) {
    let mut u = Twist::zeros();
    let mut w = Twist::zeros();
    let mut du = [Twist::zeros(); MAX_JOINT_DOF];
    let mut dw = [Twist::zeros(); MAX_JOINT_DOF];
    for f in factors {
        let e = exp_se3(&(f.twist * f.phi));
        let g = &f.twist;
        let mut phi_v = 0.0;
        let mut phi_vv = 0.0;
        let mut phi_vm = [0.0; MAX_JOINT_DOF];
        for i in 0..n {
            phi_v += f.dphi[i] * v[i];
            for j in 0..n {
                phi_vv += f.ddphi[i][j] * v[i] * v[j];
                phi_vm[j] += f.ddphi[i][j] * v[i];
            }
        }
        let ad_u_g = ad(&u, g);
        let x = w + ad_u_g * phi_v;
        let ad_x_g = ad(&x, g);
        for m in 0..n {
            let dx = dw[m] + ad(&du[m], g) * phi_v + ad_u_g * phi_vm[m];
            dw[m] = g * f.dddphi_vv[m] + e.inv_ad_twist(&(dx + ad_x_g * f.dphi[m]));
            du[m] = g * phi_vm[m] + e.inv_ad_twist(&(du[m] + ad_u_g * f.dphi[m]));
        }
        w = g * phi_vv + e.inv_ad_twist(&x);
        u = g * phi_v + e.inv_ad_twist(&u);
    }
    for m in 0..n {
        out[m] = match tail {
            Some(c) => c.inv_ad_twist(&dw[m]),
            None => dw[m],
        };
    }
}

/// Fills `out` for G = head · Π exp(ĝ_k φ_k) · tail over `n` coordinates.
/// `tail = None` means the identity.
pub fn poe_kinematics(
    head: &Se3,
    factors: &[PoeFactor],
    tail: Option<&Se3>,
    n: usize,
    want: Derivatives,
    out: &mut JointKinematics,
) {
    let mut g = *head;
    let mut mu = [Twist::zeros(); MAX_JOINT_DOF];
    let mut dmu = [[Twist::zeros(); MAX_JOINT_DOF]; MAX_JOINT_DOF];
    let jac = want >= Derivatives::Jacobian;
    let hes = want >= Derivatives::Hessian;
    for f in factors {
        let e = exp_se3(&(f.twist * f.phi));
        g = g.compose(&e);
        if !jac {
            continue;
        }
        if hes {
            for i in 0..n {
                for j in 0..n {
                    let inner = dmu[i][j] + ad(&mu[i], &f.twist) * f.dphi[j];
                    dmu[i][j] = f.twist * f.ddphi[i][j] + e.inv_ad_twist(&inner);
                }
            }
        }
        for (i, m) in mu.iter_mut().enumerate().take(n) {
            *m = f.twist * f.dphi[i] + e.inv_ad_twist(m);
        }
    }
    match tail {
        Some(c) => {
            out.transform = g.compose(c);
            if jac {
                for i in 0..n {
                    out.s[i] = c.inv_ad_twist(&mu[i]);
                }
            }
            if hes {
                for i in 0..n {
                    for j in 0..n {
                        out.ds[i][j] = c.inv_ad_twist(&dmu[i][j]);
                    }
                }
            }
        }
        None => {
            out.transform = g;
            if jac {
                out.s[..n].copy_from_slice(&mu[..n]);
            }
            if hes {
                for i in 0..n {
                    out.ds[i][..n].copy_from_slice(&dmu[i][..n]);
                }
            }
        }
    }
}
