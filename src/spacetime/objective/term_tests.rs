//! A term added from outside, reading an extra unknown: its value and
//! gradient reach the objective's, and its Gauss–Newton rows the
//! preconditioner's, blocks with the extras included.

use super::tests::{assert_gradient, gaps, known_motion};
use super::*;
use crate::spacetime::planar2::TwoLinkArm;
use nalgebra::DMatrix;

/// (q_c − z)², z the layout's first extra unknown: a residual linear in the
/// unknowns whatever coordinate c is, so its Gauss–Newton part is its exact
/// Hessian.
struct Pull {
    coord: usize,
}

impl Term<TwoLinkArm> for Pull {
    fn name(&self) -> &str {
        "pull"
    }

    fn node(&self, node: &mut Node<'_, TwoLinkArm>, sum: &mut NodeSum<'_>) -> Result<(), SpError> {
        let r = node.q[self.coord] - node.extras[0];
        sum.add(r * r);
        if let Some(g) = sum.gradient() {
            g.q[self.coord] += 2.0 * r;
            g.add_extra(0, -2.0 * r);
        }
        Ok(())
    }

    fn gauss_newton(
        &self,
        _node: &mut Node<'_, TwoLinkArm>,
        gn: &mut GaussNewtonNode<'_>,
    ) -> Result<(), SpError> {
        let n = gn.coords().len();
        let d0 = DMatrix::from_fn(1, n, |_, i| f64::from(gn.coords()[i] == self.coord));
        let d = [d0, DMatrix::zeros(1, n), DMatrix::zeros(1, n)];
        gn.add_rows(&d, &[1.0], Some(&DMatrix::from_element(1, 1, -1.0)));
        Ok(())
    }
}

fn with_pull<'a>(arm: &'a TwoLinkArm, torque: Vec<f64>) -> Objective<'a, TwoLinkArm> {
    let layout = GapLayout::new(gaps(), &with_settings())
        .unwrap()
        .with_extras(vec![0.3])
        .unwrap();
    Objective::on_layout(arm, layout, torque, &known_motion)
        .unwrap()
        .with_prior(&[[0.3, 0.7], [2.0, 0.05]])
        .unwrap()
        .with_term(Box::new(Pull { coord: 1 }))
}

#[test]
fn the_extras_follow_the_coefficients_in_the_unknowns() {
    let arm = TwoLinkArm::default();
    let obj = with_pull(&arm, vec![1.0, 1.5]);
    let l = obj.layout();
    assert_eq!(l.n_extras(), 1);
    assert_eq!(obj.n_vars(), l.n_coefficients() + 1);
    let x = obj.hermite_start();
    assert_eq!(l.extras(&x), &[0.3]);
    // the curves read the coefficients only
    let mut y = x.clone();
    l.extras_mut(&mut y)[0] = -4.0;
    assert_eq!(obj.coefficients(&x), obj.coefficients(&y));
    assert!(
        GapLayout::new(gaps(), &TransitionSettings::default())
            .unwrap()
            .with_extras(vec![f64::NAN])
            .is_err()
    );
    let names: Vec<&str> = obj.terms().map(|t| t.name()).collect();
    assert_eq!(names, ["torque", "prior", "pull"]);
}

#[test]
fn an_added_terms_gradient_reaches_the_coefficients_and_the_extras() {
    let arm = TwoLinkArm::default();
    let obj = with_pull(&arm, vec![1.0, 1.5]);
    let mut x = obj.hermite_start();
    for (i, v) in x.iter_mut().enumerate() {
        *v += 0.2 * (i as f64).sin();
    }
    let e = obj.eval(&mut obj.scratch(), &x, None).unwrap();
    // the term adds its quadrature: e minus the same objective without it
    let plain = arm_objective(&arm)
        .with_prior(&[[0.3, 0.7], [2.0, 0.05]])
        .unwrap();
    let e0 = plain
        .eval(&mut plain.scratch(), &x[..plain.n_vars()], None)
        .unwrap();
    let z = obj.layout().extras(&x)[0];
    let weights = obj.layout().nodes().1;
    let pull: f64 = (0..obj.n_nodes())
        .map(|k| weights[k] * (obj.node_state(&x, k)[0][1] - z).powi(2))
        .sum();
    assert!((e - e0 - pull).abs() < 1e-12 * e, "{} vs {pull}", e - e0);
    let g = assert_gradient(&obj, &x);
    assert!(g[x.len() - 1] != 0.0);
}

fn with_settings() -> TransitionSettings {
    TransitionSettings {
        coefficients: 6,
        samples: 12,
        continuity: Continuity::C2,
    }
}

#[test]
fn gauss_newton_rows_with_extras_give_the_exact_hessian_of_a_quadratic() {
    // no torque: prior and pull are quadratic in the unknowns, so H/2 from
    // the terms' rows is half the Hessian, which central differences of the
    // gradient give exactly (up to rounding)
    let arm = TwoLinkArm::default();
    let obj = with_pull(&arm, vec![0.0, 0.0]);
    let mut s = obj.scratch();
    let x = obj.hermite_start();
    let h = obj.half_gauss_newton(&mut s, &x).unwrap();
    let n = x.len();
    let mut fd = DMatrix::zeros(n, n);
    let (mut gp, mut gm) = (vec![0.0; n], vec![0.0; n]);
    for j in 0..n {
        let step = 1e-3;
        let (mut xp, mut xm) = (x.clone(), x.clone());
        xp[j] += step;
        xm[j] -= step;
        obj.eval(&mut s, &xp, Some(&mut gp)).unwrap();
        obj.eval(&mut s, &xm, Some(&mut gm)).unwrap();
        for i in 0..n {
            fd[(i, j)] = (gp[i] - gm[i]) / (2.0 * step) / 2.0;
        }
    }
    let err = (&h - &fd).amax() / fd.amax();
    assert!(err < 1e-8, "H/2 from the rows vs differences: {err:e}");
    // the extra's own block and its coupling are there
    assert!(h[(n - 1, n - 1)] > 0.0);
    assert!((0..n - 1).any(|i| h[(i, n - 1)] != 0.0));
}

/// A leg on a sliding, turning root (y up): x, y, rz, hip, knee.
fn leg() -> crate::model::Model {
    use crate::lie::Se3;
    use crate::model::joints::{Prismatic, Revolute};
    use crate::model::{Inertia, Model};
    use nalgebra::Vector3;
    use std::sync::Arc;
    let mut m = Model::new("leg");
    let mass = |kg| Inertia::point(kg, Vector3::new(0.05, -0.2, 0.0)).unwrap();
    let below = Se3::from_translation(Vector3::new(0.0, -0.4, 0.0));
    let mut p = None;
    for (link, coord, slide, axis, at, kg) in [
        ("sx", "x", true, Vector3::x(), Se3::identity(), 0.0),
        ("sy", "y", true, Vector3::y(), Se3::identity(), 0.0),
        ("pelvis", "rz", false, Vector3::z(), Se3::identity(), 10.0),
        ("thigh", "hip", false, Vector3::z(), below, 5.0),
        ("shin", "knee", false, Vector3::z(), below, 3.0),
    ] {
        let joint: Arc<dyn crate::model::joint::Joint> = if slide {
            Arc::new(Prismatic::new(axis).unwrap())
        } else {
            Arc::new(Revolute::new(axis).unwrap())
        };
        let inertia = if kg > 0.0 { mass(kg) } else { Inertia::zero() };
        p = Some(m.add_link(link, p, coord, joint, at, inertia).unwrap());
    }
    m
}

#[test]
fn forces_at_the_nodes_enter_the_torque_term_and_its_gradient() {
    use crate::dynamics::PointForce;
    use crate::spacetime::torque::BodyDynamics;
    use nalgebra::Vector3;
    let model = leg();
    let body = BodyDynamics {
        model: &model,
        gravity: Vector3::new(0.0, -9.8, 0.0),
    };
    let gap = |coord, start: [f64; 2], end: [f64; 2]| GapDof {
        coord,
        t0: 0.2,
        t1: 0.8,
        start: EndState {
            q: start[0],
            v: start[1],
            a: 0.0,
        },
        end: EndState {
            q: end[0],
            v: end[1],
            a: 0.0,
        },
    };
    let inputs = |t: f64, q: &mut [f64], v: &mut [f64], a: &mut [f64]| {
        for c in 0..5 {
            let w = 1.0 + c as f64;
            q[c] = 0.3 * (w * t).sin();
            v[c] = 0.3 * w * (w * t).cos();
            a[c] = -0.3 * w * w * (w * t).sin();
        }
        Ok(())
    };
    let dofs = vec![
        gap(3, [0.2, 0.5], [-0.3, 0.0]),
        gap(4, [0.4, 0.0], [0.9, -1.0]),
    ];
    let mut obj = Objective::new(&body, dofs, &with_settings(), vec![1.0; 5], &inputs).unwrap();
    let mut s = obj.scratch();
    let mut x = obj.hermite_start();
    x.iter_mut()
        .enumerate()
        .for_each(|(i, v)| *v += 0.1 * (i as f64).cos());
    let e0 = obj.eval(&mut s, &x, None).unwrap();
    // the ground pushes up under the shin's end, more as time goes on
    let nodes = obj.layout().nodes().0.to_vec();
    let forces: Vec<NodeForces> = nodes
        .iter()
        .map(|t| {
            let f = Vector3::new(30.0 * t, 80.0 + 100.0 * t, 0.0);
            NodeForces {
                forces: vec![
                    PointForce::at(4, Vector3::new(0.02, -0.4, 0.0), f)
                        .with_moment(Vector3::new(0.0, 0.0, 5.0)),
                ],
                reference: Vector3::zeros(),
            }
        })
        .collect();
    assert!(obj.set_forces(forces[1..].to_vec()).is_err());
    obj.set_forces(forces).unwrap();
    let e = obj.eval(&mut s, &x, None).unwrap();
    assert!(
        (e - e0).abs() > 1e-3 * e0,
        "the forces change e: {e} vs {e0}"
    );
    assert_gradient(&obj, &x);
    // no forces again: the objective as it was, to the bit
    obj.set_forces(vec![]).unwrap();
    assert_eq!(obj.eval(&mut s, &x, None).unwrap(), e0);
}

/// The arm's objective on the test gaps, torque alone.
fn arm_objective(arm: &TwoLinkArm) -> Objective<'_, TwoLinkArm> {
    Objective::new(arm, gaps(), &with_settings(), vec![1.0, 1.5], &known_motion).unwrap()
}

/// A term that reads the body's passes at its node.
struct ReadsPoses;

impl Term<TwoLinkArm> for ReadsPoses {
    fn name(&self) -> &str {
        "reads poses"
    }

    fn node(&self, node: &mut Node<'_, TwoLinkArm>, sum: &mut NodeSum<'_>) -> Result<(), SpError> {
        sum.add(node.poses()?.len() as f64);
        Ok(())
    }
}

#[test]
fn a_term_reading_the_bodys_passes_on_a_model_without_one_is_a_clear_error() {
    // the two-link arm is a hand-checked model, not a multibody body: the
    // torque term uses its own adjoint, and a term asking for link poses
    // is told why it cannot have them
    let arm = TwoLinkArm::default();
    let obj = arm_objective(&arm).with_term(Box::new(ReadsPoses));
    let x = obj.hermite_start();
    let e = obj.eval(&mut obj.scratch(), &x, None).unwrap_err();
    assert!(e.to_string().contains("multibody"), "{e}");
}
