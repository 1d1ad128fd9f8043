//! A two-link planar arm with point masses at the link ends, whose torques are
//! known in closed form (Spong, Hutchinson & Vidyasagar, *Robot Modeling and
//! Control*, §7.4). It is a [`TorqueModel`] with an exactly known gradient, used
//! to test the transition solver independently of the multibody engine.

use super::error::SpError;
use super::torque::TorqueModel;
use crate::dynamics::{JointState, PointForce, StateGradient};

/// Joint 1 at the origin rotating in the vertical plane (angle from the
/// horizontal), joint 2 at the end of link 1; gravity `g` pulls along −y.
#[derive(Clone, Debug)]
pub struct TwoLinkArm {
    pub m1: f64,
    pub m2: f64,
    pub l1: f64,
    pub l2: f64,
    pub g: f64,
}

impl Default for TwoLinkArm {
    fn default() -> Self {
        TwoLinkArm {
            m1: 2.0,
            m2: 1.2,
            l1: 0.35,
            l2: 0.3,
            g: 9.80665,
        }
    }
}

impl TwoLinkArm {
    /// Mass matrix, Coriolis coefficient h = −m₂l₁l₂ sin q₂ and gravity terms at q.
    fn terms(&self, q: &[f64]) -> ([f64; 3], f64, [f64; 2]) {
        let (c1, c2, c12) = (q[0].cos(), q[1].cos(), (q[0] + q[1]).cos());
        let s2 = q[1].sin();
        let TwoLinkArm { m1, m2, l1, l2, g } = *self;
        let m11 = (m1 + m2) * l1 * l1 + m2 * l2 * l2 + 2.0 * m2 * l1 * l2 * c2;
        let m12 = m2 * l2 * l2 + m2 * l1 * l2 * c2;
        let m22 = m2 * l2 * l2;
        let h = -m2 * l1 * l2 * s2;
        let g1 = (m1 + m2) * g * l1 * c1 + m2 * g * l2 * c12;
        let g2 = m2 * g * l2 * c12;
        ([m11, m12, m22], h, [g1, g2])
    }

    /// Kinetic plus potential energy (for the power-balance test).
    pub fn energy(&self, q: &[f64], v: &[f64]) -> f64 {
        let ([m11, m12, m22], _, _) = self.terms(q);
        let TwoLinkArm { m1, m2, l1, l2, g } = *self;
        let ke = 0.5 * (m11 * v[0] * v[0] + 2.0 * m12 * v[0] * v[1] + m22 * v[1] * v[1]);
        let y1 = l1 * q[0].sin();
        let y2 = y1 + l2 * (q[0] + q[1]).sin();
        ke + m1 * g * y1 + m2 * g * y2
    }

    fn tau(&self, q: &[f64], v: &[f64], a: &[f64]) -> [f64; 2] {
        let ([m11, m12, m22], h, [g1, g2]) = self.terms(q);
        [
            m11 * a[0] + m12 * a[1] + h * (v[1] * v[1] + 2.0 * v[0] * v[1]) + g1,
            m12 * a[0] + m22 * a[1] - h * v[0] * v[0] + g2,
        ]
    }
}

fn check_len(n: usize, q: &[f64], v: &[f64], a: &[f64]) -> Result<(), SpError> {
    if q.len() != n || v.len() != n || a.len() != n {
        return Err(SpError::Dynamics(crate::dynamics::DynamicsError::Input(
            format!(
                "the two-link arm has {n} coordinates; got q, q̇, q̈ of lengths {}, {}, {}",
                q.len(),
                v.len(),
                a.len()
            ),
        )));
    }
    Ok(())
}

/// The arm has no links to push on: it is a closed-form test model.
fn no_forces(ext: &[PointForce]) -> Result<(), SpError> {
    if ext.is_empty() {
        Ok(())
    } else {
        Err(SpError::Invalid(
            "the two-link arm takes no external forces (use a body model)".into(),
        ))
    }
}

impl TorqueModel for TwoLinkArm {
    type Workspace = ();

    fn nq(&self) -> usize {
        2
    }

    fn workspace(&self) {}

    fn torques(
        &self,
        _: &mut (),
        q: &[f64],
        v: &[f64],
        a: &[f64],
        ext: &[PointForce],
        tau: &mut [f64],
    ) -> Result<(), SpError> {
        check_len(2, q, v, a)?;
        no_forces(ext)?;
        tau[..2].copy_from_slice(&self.tau(q, v, a));
        Ok(())
    }

    fn torque_sq_grad(
        &self,
        _: &mut (),
        x: &JointState,
        ext: &[PointForce],
        w: &[f64],
        grad: StateGradient,
    ) -> Result<f64, SpError> {
        no_forces(ext)?;
        let (q, v, a) = (x.q, x.v, x.a);
        let StateGradient {
            q: gq,
            v: gv,
            a: ga,
        } = grad;
        check_len(2, q, v, a)?;
        let t = self.tau(q, v, a);
        let ([m11, m12, m22], h, _) = self.terms(q);
        let TwoLinkArm { m2, l1, l2, g, m1 } = *self;
        let (s1, s2, s12, c2) = (q[0].sin(), q[1].sin(), (q[0] + q[1]).sin(), q[1].cos());
        // ∂τ/∂q
        let dt_dq1 = [
            -(m1 + m2) * g * l1 * s1 - m2 * g * l2 * s12,
            -m2 * g * l2 * s12,
        ];
        let dm11 = -2.0 * m2 * l1 * l2 * s2;
        let dm12 = -m2 * l1 * l2 * s2;
        let dh = -m2 * l1 * l2 * c2;
        let dt_dq2 = [
            dm11 * a[0] + dm12 * a[1] + dh * (v[1] * v[1] + 2.0 * v[0] * v[1]) - m2 * g * l2 * s12,
            dm12 * a[0] - dh * v[0] * v[0] - m2 * g * l2 * s12,
        ];
        // ∂τ/∂q̇
        let dt_dv1 = [2.0 * h * v[1], -2.0 * h * v[0]];
        let dt_dv2 = [2.0 * h * (v[1] + v[0]), 0.0];
        // ∂τ/∂q̈ = M
        let dt_da1 = [m11, m12];
        let dt_da2 = [m12, m22];
        let r = [2.0 * w[0] * t[0], 2.0 * w[1] * t[1]];
        let dot = |d: [f64; 2]| r[0] * d[0] + r[1] * d[1];
        gq[0] = dot(dt_dq1);
        gq[1] = dot(dt_dq2);
        gv[0] = dot(dt_dv1);
        gv[1] = dot(dt_dv2);
        ga[0] = dot(dt_da1);
        ga[1] = dot(dt_da2);
        Ok(w[0] * t[0] * t[0] + w[1] * t[1] * t[1])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn power_balance_tau_dot_v_equals_energy_rate() {
        // Along q(t) = (sin 1.3t, 0.7 cos 2t): τ·q̇ = dE/dt (no friction).
        let arm = TwoLinkArm::default();
        let path = |t: f64| {
            (
                [(1.3 * t).sin(), 0.7 * (2.0 * t).cos()],
                [1.3 * (1.3 * t).cos(), -1.4 * (2.0 * t).sin()],
                [-1.69 * (1.3 * t).sin(), -2.8 * (2.0 * t).cos()],
            )
        };
        for i in 0..20 {
            let t = 0.17 * i as f64;
            let (q, v, a) = path(t);
            let mut tau = [0.0; 2];
            arm.torques(&mut (), &q, &v, &a, &[], &mut tau).unwrap();
            let h = 1e-5;
            let (qp, vp, _) = path(t + h);
            let (qm, vm, _) = path(t - h);
            let de = (arm.energy(&qp, &vp) - arm.energy(&qm, &vm)) / (2.0 * h);
            let p = tau[0] * v[0] + tau[1] * v[1];
            assert!(
                (p - de).abs() < 1e-6 * (1.0 + de.abs()),
                "t={t}: {p} vs {de}"
            );
        }
    }

    #[test]
    fn gradient_matches_central_differences() {
        let arm = TwoLinkArm::default();
        let w = [1.0, 2.5];
        let x0 = [0.3, -1.1, 0.8, 2.0, -3.0, 1.5];
        let f = |x: &[f64]| {
            let mut g = [0.0; 6];
            let (gq, rest) = g.split_at_mut(2);
            let (gv, ga) = rest.split_at_mut(2);
            let e = arm
                .torque_sq_grad(
                    &mut (),
                    &JointState::new(&x[0..2], &x[2..4], &x[4..6]),
                    &[],
                    &w,
                    StateGradient {
                        q: gq,
                        v: gv,
                        a: ga,
                    },
                )
                .unwrap();
            (e, g)
        };
        let (_, g) = f(&x0);
        for i in 0..6 {
            let h = 1e-6;
            let mut xp = x0;
            let mut xm = x0;
            xp[i] += h;
            xm[i] -= h;
            let fd = (f(&xp).0 - f(&xm).0) / (2.0 * h);
            assert!(
                (fd - g[i]).abs() < 1e-6 * (1.0 + g[i].abs()),
                "i={i}: {fd} vs {}",
                g[i]
            );
        }
    }

    #[test]
    fn wrong_lengths_are_errors() {
        let arm = TwoLinkArm::default();
        let mut tau = [0.0; 2];
        assert!(
            arm.torques(&mut (), &[0.0], &[0.0, 0.0], &[0.0, 0.0], &[], &mut tau)
                .is_err()
        );
    }
}
