//! SP's example term: Σ_d c_d ∫ (q_d − r_d)² dt over the gap DOFs that
//! follow an example, r the example's poses laid in the world over the gap
//! (`reference::LaidExample`, root included where the root is cut).
//!
//! Why positions: the prior (`prior.rs`) follows the example's velocities
//! and accelerations, which leave its poses free up to a smooth ramp; the
//! torque term then drags that ramp toward low-effort poses no person takes
//! (a leg swung through lower, a turn cut short). Anchoring the poses
//! themselves keeps the transition on the example wherever its ends allow,
//! and the laid example already meets the gap's end states, so the anchor
//! and the end states never pull against each other.
//!
//! The term is quadratic in the unknowns, so its Gauss–Newton block is its
//! exact Hessian.

use super::super::error::{SpError, invalid};
use super::super::torque::TorqueModel;
use super::Inputs;
use super::layout::GapLayout;
use super::term::{GaussNewtonNode, Node, NodeSum, Term};
use std::f64::consts::PI;

/// The example term's weights and the poses it pulls toward.
#[derive(Clone, Debug)]
pub struct ExampleTerm {
    /// Per gap DOF of the layout, c_d (0: the DOF does not follow).
    weights: Vec<f64>,
    /// Per gap DOF and node, r_d(t_k) (0 where the DOF does not follow or
    /// its gap does not hold the node).
    target: Vec<Vec<f64>>,
}

impl ExampleTerm {
    /// The term on `layout` (of a body with `nq` coordinates) pulling gap
    /// DOF d toward the q of `example` with weight `per_coord[d.coord]`
    /// (0: not at all). The example must be defined at every node of a
    /// weighted DOF's gap.
    pub fn new(
        layout: &GapLayout,
        nq: usize,
        example: &Inputs,
        per_coord: &[f64],
    ) -> Result<Self, SpError> {
        if per_coord.len() != nq {
            return Err(invalid(format!(
                "example weights have {} entries but the body has {nq} coordinates",
                per_coord.len()
            )));
        }
        if per_coord.iter().any(|w| !w.is_finite() || *w < 0.0) {
            return Err(invalid("example weights must be finite and non-negative"));
        }
        let weights: Vec<f64> = layout.dofs.iter().map(|d| per_coord[d.coord]).collect();
        let mut target = vec![vec![0.0; layout.nodes.len()]; layout.dofs.len()];
        let (mut q, mut v, mut a) = (vec![0.0; nq], vec![0.0; nq], vec![0.0; nq]);
        for (k, &t) in layout.nodes.iter().enumerate() {
            q.fill(f64::NAN);
            example(t, &mut q, &mut v, &mut a)?;
            for (d, dof) in layout.dofs.iter().enumerate() {
                if weights[d] == 0.0 || layout.active[d][k].is_none() {
                    continue;
                }
                let r = q[dof.coord];
                if !r.is_finite() {
                    return Err(invalid(format!(
                        "the example is undefined at {t:.4} s on coordinate {} of its gap",
                        dof.coord
                    )));
                }
                target[d][k] = r;
            }
        }
        Ok(ExampleTerm { weights, target })
    }

    /// Whether any DOF follows.
    pub fn is_on(&self) -> bool {
        self.weights.iter().any(|&w| w > 0.0)
    }
}

/// The example term's weight on a DOF whose prior weighs q̈ by `c_a`, over
/// a gap of `seconds`, for an example trusted `trust` (0–1,
/// `reference::Example::trust`): c = trust · c_a (π/T)⁴. A position error
/// shaped like the gap's lowest mode (a half sine over T) costs as much here
/// as its acceleration costs in the prior, so neither term's units dominate
/// the other whatever the gap's length.
pub fn position_weight(c_a: f64, seconds: f64, trust: f64) -> f64 {
    if seconds <= 0.0 {
        return 0.0;
    }
    trust.clamp(0.0, 1.0) * c_a * (PI / seconds).powi(4)
}

impl<M: TorqueModel> Term<M> for ExampleTerm {
    fn name(&self) -> &str {
        "example"
    }

    fn node(&self, node: &mut Node<'_, M>, sum: &mut NodeSum<'_>) -> Result<(), SpError> {
        let (layout, k) = (node.layout, node.k);
        let alive = || {
            (0..layout.dofs.len())
                .filter(move |&d| self.weights[d] > 0.0 && layout.active[d][k].is_some())
                .map(|d| (d, layout.dofs[d].coord))
        };
        for (d, c) in alive() {
            let e = node.q[c] - self.target[d][k];
            sum.add(self.weights[d] * e * e);
        }
        if let Some(g) = sum.gradient() {
            for (d, c) in alive() {
                g.q[c] += 2.0 * self.weights[d] * (node.q[c] - self.target[d][k]);
            }
        }
        Ok(())
    }

    /// Its exact half-Hessian at the node, w_k c_d r₀r₀ᵀ per DOF.
    fn gauss_newton(
        &self,
        _node: &mut Node<'_, M>,
        gn: &mut GaussNewtonNode<'_>,
    ) -> Result<(), SpError> {
        let (wk, nf) = (gn.wk(), gn.layout.n_free);
        for &(di, rd) in gn.alive() {
            let c = self.weights[di];
            if c == 0.0 {
                continue;
            }
            for p in rd.live.clone() {
                for l in rd.live.clone().filter(|&l| l >= p) {
                    gn.add(
                        di * nf + p,
                        di * nf + l,
                        wk * c * rd.rows[0][p] * rd.rows[0][l],
                    );
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::{assert_gradient, gaps, known_motion};
    use super::super::{Objective, TransitionSettings};
    use super::*;
    use crate::spacetime::planar2::TwoLinkArm;
    use crate::spacetime::transition::Continuity;
    use nalgebra::DMatrix;

    fn settings() -> TransitionSettings {
        TransitionSettings {
            coefficients: 6,
            samples: 16,
            continuity: Continuity::C2,
        }
    }

    /// An example r(t) = (cos t, 1 − t) the gaps of [`gaps`] can follow.
    fn example(t: f64, q: &mut [f64], v: &mut [f64], a: &mut [f64]) -> Result<(), SpError> {
        q[0] = t.cos();
        v[0] = -t.sin();
        a[0] = -t.cos();
        q[1] = 1.0 - t;
        v[1] = -1.0;
        a[1] = 0.0;
        Ok(())
    }

    fn objective<'a>(
        arm: &'a TwoLinkArm,
        torque: Vec<f64>,
        c: [f64; 2],
    ) -> Objective<'a, TwoLinkArm> {
        let obj = Objective::new(arm, gaps(), &settings(), torque, &known_motion).unwrap();
        let term = ExampleTerm::new(obj.layout(), 2, &example, &c).unwrap();
        assert!(term.is_on());
        obj.with_term(Box::new(term))
    }

    #[test]
    fn its_integral_is_the_weighted_squared_distance_to_the_example() {
        let arm = TwoLinkArm::default();
        let plain =
            Objective::new(&arm, gaps(), &settings(), vec![1.0, 1.5], &known_motion).unwrap();
        let with = objective(&arm, vec![1.0, 1.5], [0.7, 0.0]);
        let x: Vec<f64> = (0..plain.n_vars())
            .map(|i| 0.2 * (i as f64).sin())
            .collect();
        let e0 = plain.eval(&mut plain.scratch(), &x, None).unwrap();
        let e1 = with.eval(&mut with.scratch(), &x, None).unwrap();
        let d = &plain.dofs()[0];
        let c = plain.coefficients(&x);
        let n = 20000;
        let mut sum = 0.0;
        for i in 0..=n {
            let t = d.t0 + (d.t1 - d.t0) * i as f64 / n as f64;
            let s = plain.curves()[0].eval(&c[0], t);
            let w = if i == 0 || i == n { 0.5 } else { 1.0 };
            let e = s[0] - t.cos();
            sum += w * 0.7 * e * e * (d.t1 - d.t0) / n as f64;
        }
        assert!((e1 - e0 - sum).abs() < 1e-6 * sum, "{} vs {sum}", e1 - e0);
    }

    #[test]
    fn its_gradient_matches_central_differences() {
        let arm = TwoLinkArm::default();
        let obj = objective(&arm, vec![1.0, 1.5], [0.7, 2.0]);
        let x: Vec<f64> = (0..obj.n_vars()).map(|i| 0.3 * (i as f64).cos()).collect();
        assert_gradient(&obj, &x);
    }

    #[test]
    fn its_gauss_newton_block_is_its_exact_hessian() {
        // no torque: the term alone is quadratic
        let arm = TwoLinkArm::default();
        let obj = objective(&arm, vec![0.0, 0.0], [0.7, 2.0]);
        let mut s = obj.scratch();
        let x = obj.hermite_start();
        let h = obj.half_gauss_newton(&mut s, &x).unwrap();
        let n = x.len();
        let mut fd = DMatrix::zeros(n, n);
        let (mut gp, mut gm) = (vec![0.0; n], vec![0.0; n]);
        for j in 0..n {
            let (mut xp, mut xm) = (x.clone(), x.clone());
            xp[j] += 1e-3;
            xm[j] -= 1e-3;
            obj.eval(&mut s, &xp, Some(&mut gp)).unwrap();
            obj.eval(&mut s, &xm, Some(&mut gm)).unwrap();
            for i in 0..n {
                fd[(i, j)] = (gp[i] - gm[i]) / 2e-3 / 2.0;
            }
        }
        let err = (&h - &fd).amax() / fd.amax();
        assert!(err < 1e-8, "H/2 from the term vs differences: {err:e}");
    }

    #[test]
    fn bad_weights_and_an_undefined_example_are_errors() {
        let arm = TwoLinkArm::default();
        let obj = Objective::new(&arm, gaps(), &settings(), vec![1.0, 1.5], &known_motion).unwrap();
        assert!(ExampleTerm::new(obj.layout(), 2, &example, &[1.0]).is_err());
        assert!(ExampleTerm::new(obj.layout(), 2, &example, &[-1.0, 0.0]).is_err());
        let undefined = |_: f64, q: &mut [f64], _: &mut [f64], _: &mut [f64]| {
            q[1] = f64::NAN;
            Ok(())
        };
        let err = ExampleTerm::new(obj.layout(), 2, &undefined, &[0.0, 1.0]).unwrap_err();
        assert!(err.to_string().contains("undefined"), "{err}");
        // a DOF it does not weigh may be undefined
        assert!(
            !ExampleTerm::new(obj.layout(), 2, &undefined, &[0.0, 0.0])
                .unwrap()
                .is_on()
        );
    }

    #[test]
    fn the_position_weight_grows_as_the_gap_shortens() {
        assert_eq!(position_weight(2.0, 0.0, 1.0), 0.0);
        let (short, long) = (
            position_weight(2.0, 0.5, 1.0),
            position_weight(2.0, 1.0, 1.0),
        );
        assert!((short / long - 16.0).abs() < 1e-12);
        assert!((position_weight(2.0, 1.0, 0.5) - 0.5 * long).abs() < 1e-12);
    }
}
