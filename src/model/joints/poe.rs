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
}

impl PoeFactor {
    pub fn new(twist: Twist, phi: f64) -> Self {
        PoeFactor {
            twist,
            phi,
            dphi: [0.0; MAX_JOINT_DOF],
            ddphi: [[0.0; MAX_JOINT_DOF]; MAX_JOINT_DOF],
        }
    }

    /// A factor driven by one coordinate `i` through φ = f(q_i) with f', f''.
    pub fn of_coordinate(twist: Twist, i: usize, f: [f64; 3]) -> Self {
        let mut p = PoeFactor::new(twist, f[0]);
        p.dphi[i] = f[1];
        p.ddphi[i][i] = f[2];
        p
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
