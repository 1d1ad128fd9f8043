//! Consistency of the dynamics algorithms with each other and with finite
//! differences, on random trees including configuration-dependent joints, and
//! the numerical hard cases.

use crate::support;

use mx::dynamics::{
    DynamicsError, JointState, StateGradient, Workspace, forward_dynamics, inverse_dynamics,
    kinetic_energy, mass_matrix, nonlinear_effects, potential_energy, rnea_derivatives,
    torque_sq_gradient,
};
use mx::model::Model;
use nalgebra::{DMatrix, DVector, Vector3};
use support::{Rng, random_tree, spline_chain};

fn maxabs(x: &[f64]) -> f64 {
    x.iter().fold(0.0, |m, v| m.max(v.abs()))
}

const G: Vector3<f64> = Vector3::new(0.3, -9.80665, 0.5);

#[test]
fn aba_agrees_with_solving_the_mass_matrix() {
    let mut rng = Rng::new(7);
    for (n, poe) in [(1, false), (6, false), (9, true), (15, true)] {
        let m = random_tree(&mut rng, n, poe);
        let nq = m.nq();
        let mut ws = Workspace::new(&m);
        for _ in 0..5 {
            let q = rng.vec(nq, -3.0, 3.0);
            let v = rng.vec(nq, -2.0, 2.0);
            let tau = rng.vec(nq, -5.0, 5.0);
            let mut qdd = vec![0.0; nq];
            forward_dynamics(&m, &mut ws, &q, &v, &tau, &G, &mut qdd).unwrap();
            let mut mm = DMatrix::zeros(nq, nq);
            mass_matrix(&m, &mut ws, &q, &mut mm).unwrap();
            let mut nle = vec![0.0; nq];
            nonlinear_effects(&m, &mut ws, &q, &v, &G, &mut nle).unwrap();
            let rhs = DVector::from_vec(tau.iter().zip(&nle).map(|(t, b)| t - b).collect());
            let sol = mm.clone().cholesky().expect("M is SPD").solve(&rhs);
            let e = (DVector::from_vec(qdd.clone()) - &sol).amax() / sol.amax().max(1.0);
            assert!(e < 1e-9, "n={n} poe={poe}: ABA vs M⁻¹ err {e:e}");
            // and RNEA(q, v, ABA) gives τ back
            let mut t2 = vec![0.0; nq];
            inverse_dynamics(&m, &mut ws, &q, &v, &qdd, &G, &mut t2).unwrap();
            let e2 = t2
                .iter()
                .zip(&tau)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            assert!(e2 < 1e-9 * maxabs(&tau).max(1.0), "RNEA∘ABA err {e2:e}");
            // M is symmetric and KE = ½ vᵀ M v
            assert!((&mm - mm.transpose()).amax() < 1e-12 * mm.amax());
            let vv = DVector::from_vec(v.clone());
            let ke = kinetic_energy(&m, &mut ws, &q, &v).unwrap();
            assert!((ke - 0.5 * vv.dot(&(&mm * &vv))).abs() < 1e-11 * ke.max(1.0));
        }
    }
}

/// g(q) = ∂PE/∂q: the gravity torque is the gradient of the potential energy.
#[test]
fn gravity_torque_is_the_gradient_of_potential_energy() {
    let mut rng = Rng::new(11);
    let m = random_tree(&mut rng, 9, true);
    let nq = m.nq();
    let mut ws = Workspace::new(&m);
    let q = rng.vec(nq, -2.0, 2.0);
    let zero = vec![0.0; nq];
    let mut g = vec![0.0; nq];
    nonlinear_effects(&m, &mut ws, &q, &zero, &G, &mut g).unwrap();
    for k in 0..nq {
        let h = 1e-6;
        let mut qp = q.clone();
        qp[k] += h;
        let mut qm = q.clone();
        qm[k] -= h;
        let d = (potential_energy(&m, &mut ws, &qp, &G).unwrap()
            - potential_energy(&m, &mut ws, &qm, &G).unwrap())
            / (2.0 * h);
        assert!(
            (d - g[k]).abs() < 1e-7 * (1.0 + g[k].abs()),
            "k={k}: {d} vs {}",
            g[k]
        );
    }
}

fn tau_at(m: &Model, ws: &mut Workspace, q: &[f64], v: &[f64], a: &[f64]) -> Vec<f64> {
    let mut t = vec![0.0; m.nq()];
    inverse_dynamics(m, ws, q, v, a, &G, &mut t).unwrap();
    t
}

#[test]
fn rnea_derivatives_match_finite_differences() {
    let mut rng = Rng::new(3);
    // poe: the test joint without an analytic ∂(Ṡq̇)/∂q (Hessian differenced);
    // spline: the library's q-dependent joints with theirs.
    for (poe, spline) in [(false, false), (true, false), (true, true)] {
        let m = if spline {
            spline_chain(&mut rng)
        } else {
            random_tree(&mut rng, 9, poe)
        };
        let nq = m.nq();
        let mut ws = Workspace::new(&m);
        let q = rng.vec(nq, -2.0, 2.0);
        let v = rng.vec(nq, -2.0, 2.0);
        let a = rng.vec(nq, -5.0, 5.0);
        let mut dq = DMatrix::zeros(nq, nq);
        let mut dv = DMatrix::zeros(nq, nq);
        rnea_derivatives(
            &m,
            &mut ws,
            &JointState::new(&q, &v, &a),
            &G,
            &mut dq,
            &mut dv,
        )
        .unwrap();
        let h = 1e-6;
        let mut worst: f64 = 0.0;
        for k in 0..nq {
            for (which, mat) in [(0, &dq), (1, &dv)] {
                let (mut xp, mut xm) = if which == 0 {
                    (q.clone(), q.clone())
                } else {
                    (v.clone(), v.clone())
                };
                xp[k] += h;
                xm[k] -= h;
                let (tp, tm) = if which == 0 {
                    (
                        tau_at(&m, &mut ws, &xp, &v, &a),
                        tau_at(&m, &mut ws, &xm, &v, &a),
                    )
                } else {
                    (
                        tau_at(&m, &mut ws, &q, &xp, &a),
                        tau_at(&m, &mut ws, &q, &xm, &a),
                    )
                };
                for i in 0..nq {
                    let fd = (tp[i] - tm[i]) / (2.0 * h);
                    worst = worst.max((fd - mat[(i, k)]).abs() / (1.0 + fd.abs()));
                }
            }
        }
        eprintln!("poe={poe} spline={spline}: ∂τ analytic vs central FD worst rel err {worst:.2e}");
        assert!(worst < 1e-6, "poe={poe} spline={spline}: {worst:e}");
    }
}

#[test]
fn adjoint_gradient_matches_finite_differences_and_the_jacobians() {
    let mut rng = Rng::new(5);
    for (poe, spline) in [(false, false), (true, false), (true, true)] {
        let m = if spline {
            spline_chain(&mut rng)
        } else {
            random_tree(&mut rng, 12, poe)
        };
        let nq = m.nq();
        let mut ws = Workspace::new(&m);
        let q = rng.vec(nq, -2.0, 2.0);
        let v = rng.vec(nq, -2.0, 2.0);
        let a = rng.vec(nq, -5.0, 5.0);
        let w = rng.vec(nq, 0.1, 2.0);
        let (mut gq, mut gv, mut ga) = (vec![0.0; nq], vec![0.0; nq], vec![0.0; nq]);
        let j = torque_sq_gradient(
            &m,
            &mut ws,
            &JointState::new(&q, &v, &a),
            &G,
            &w,
            StateGradient {
                q: &mut gq,
                v: &mut gv,
                a: &mut ga,
            },
        )
        .unwrap();
        let tau = tau_at(&m, &mut ws, &q, &v, &a);
        let j_ref: f64 = tau.iter().zip(&w).map(|(t, w)| w * t * t).sum();
        assert!((j - j_ref).abs() < 1e-12 * j_ref);
        // Against the analytic Jacobians: ∇J = 2 Jᵀ W τ.
        let mut dq = DMatrix::zeros(nq, nq);
        let mut dv = DMatrix::zeros(nq, nq);
        let mut mm = DMatrix::zeros(nq, nq);
        rnea_derivatives(
            &m,
            &mut ws,
            &JointState::new(&q, &v, &a),
            &G,
            &mut dq,
            &mut dv,
        )
        .unwrap();
        mass_matrix(&m, &mut ws, &q, &mut mm).unwrap();
        let wt = DVector::from_iterator(nq, tau.iter().zip(&w).map(|(t, w)| 2.0 * w * t));
        let scale = wt.amax() * mm.amax().max(dq.amax()).max(1.0);
        for (g, jac, name) in [(&gq, &dq, "q"), (&gv, &dv, "v"), (&ga, &mm, "a")] {
            let expect = jac.transpose() * &wt;
            let e = (DVector::from_vec(g.clone()) - &expect).amax() / scale;
            eprintln!("poe={poe} spline={spline}: adjoint ∂J/∂{name} vs 2Jᵀwτ err {e:.2e}");
            assert!(e < 1e-9, "poe={poe} spline={spline} {name}: {e:e}");
        }
        // And against central differences of J.
        let h = 1e-6;
        let jfun = |ws: &mut Workspace, q: &[f64], v: &[f64], a: &[f64]| -> f64 {
            tau_at(&m, ws, q, v, a)
                .iter()
                .zip(&w)
                .map(|(t, w)| w * t * t)
                .sum()
        };
        for k in 0..nq {
            for (which, g) in [(0, &gq), (1, &gv), (2, &ga)] {
                let mut xs = [q.clone(), v.clone(), a.clone()];
                xs[which][k] += h;
                let jp = jfun(&mut ws, &xs[0], &xs[1], &xs[2]);
                xs[which][k] -= 2.0 * h;
                let jm = jfun(&mut ws, &xs[0], &xs[1], &xs[2]);
                let fd = (jp - jm) / (2.0 * h);
                assert!(
                    (fd - g[k]).abs() < 1e-6 * (j_ref + fd.abs()),
                    "poe={poe} spline={spline} x{which}[{k}]: fd {fd} vs {}",
                    g[k]
                );
            }
        }
    }
}

/// The hard-case registry's chain, so the report's table and this test build the same model.
fn chain(n: usize, masses: &[f64]) -> Model {
    mx::report::hard_cases::chain(n, masses).expect("chain builds")
}

fn aba_vs_m(m: &Model, rng: &mut Rng) -> f64 {
    let nq = m.nq();
    let mut ws = Workspace::new(m);
    let q = rng.vec(nq, -0.5, 0.5);
    let v = rng.vec(nq, -1.0, 1.0);
    let tau = rng.vec(nq, -1.0, 1.0);
    let mut qdd = vec![0.0; nq];
    forward_dynamics(m, &mut ws, &q, &v, &tau, &G, &mut qdd).unwrap();
    assert!(qdd.iter().all(|x| x.is_finite()));
    // Conditioning-free check (README): M (q̈ − q̈*) residual through RNEA.
    let mut t2 = vec![0.0; nq];
    inverse_dynamics(m, &mut ws, &q, &v, &qdd, &G, &mut t2).unwrap();
    t2.iter()
        .zip(&tau)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max)
        / maxabs(&tau).max(1.0)
}

#[test]
fn long_chain_of_500_links() {
    let mut rng = Rng::new(1);
    let m = chain(500, &[1.0, 0.5]);
    let e = aba_vs_m(&m, &mut rng);
    eprintln!("500-link chain: |RNEA(ABA(τ)) − τ| / |τ| = {e:.2e}");
    assert!(e < 1e-8);
}

#[test]
fn tiny_mass_beside_a_heavy_one() {
    let mut rng = Rng::new(2);
    let m = chain(4, &[100.0, 1e-9]);
    let e = aba_vs_m(&m, &mut rng);
    eprintln!("1e-9 kg beside 100 kg: residual {e:.2e}");
    assert!(e < 1e-8);
}

#[test]
fn massless_tip_is_a_clear_error() {
    let m = chain(3, &[1.0, 1.0, 0.0]);
    let mut ws = Workspace::new(&m);
    let mut qdd = vec![0.0; 3];
    let r = forward_dynamics(&m, &mut ws, &[0.1; 3], &[0.0; 3], &[0.0; 3], &G, &mut qdd);
    match r {
        Err(DynamicsError::Singular(msg)) => assert!(msg.contains("j2"), "{msg}"),
        other => panic!("expected a singularity error, got {other:?}"),
    }
}

#[test]
fn bad_inputs_are_errors_not_panics() {
    let m = chain(3, &[1.0]);
    let mut ws = Workspace::new(&m);
    let mut t = vec![0.0; 3];
    let e = inverse_dynamics(&m, &mut ws, &[0.0; 2], &[0.0; 3], &[0.0; 3], &G, &mut t).unwrap_err();
    assert!(e.to_string().contains("q has 2 entries"), "{e}");
    let e = inverse_dynamics(
        &m,
        &mut ws,
        &[0.0, f64::NAN, 0.0],
        &[0.0; 3],
        &[0.0; 3],
        &G,
        &mut t,
    )
    .unwrap_err();
    assert!(e.to_string().contains("not a finite number"), "{e}");
    let other = chain(4, &[1.0]);
    let e = inverse_dynamics(
        &other,
        &mut ws,
        &[0.0; 4],
        &[0.0; 4],
        &[0.0; 4],
        &G,
        &mut [0.0; 4],
    )
    .unwrap_err();
    assert!(e.to_string().contains("another model"), "{e}");
    let mut small = DMatrix::zeros(2, 2);
    assert!(mass_matrix(&m, &mut ws, &[0.0; 3], &mut small).is_err());
}
