//! World forces at link points (`mx::dynamics::PointForce`) in inverse
//! dynamics and in the adjoint gradient of Σwτ², on a captured walk's body
//! (floating root, forces under both feet): τ with the forces is τ without
//! them minus Σ Jᵀ[m; f] built by hand from the points' Jacobians, and the
//! gradient with the forces held fixed matches central differences.

use crate::common::shared_files;
use mx::dynamics::{
    JointState, PointForce, StateGradient, Workspace, inverse_dynamics, inverse_dynamics_at_points,
    torque_sq_gradient, torque_sq_gradient_at_points,
};
use mx::lie::log_so3;
use mx::mocap::{self, bvh::Units};
use mx::model::Model;
use mx::motion::JointSampler;
use nalgebra::{DVector, Vector3};

/// The first walk of `data/inbetween`: its body, and its state mid-clip.
pub(crate) fn walk() -> Option<(Model, [Vec<f64>; 3])> {
    let path = shared_files("inbetween", ".bvh")
        .into_iter()
        .find(|p| p.to_string_lossy().contains("walk"))?;
    let clip = mocap::load(&path, Units::Auto).unwrap();
    let (body, _) = mocap::body_of(&clip.skeleton, 70.0, clip.units.metres_per_unit).unwrap();
    let names = body.coordinate_names();
    let sampler = JointSampler::new(&clip.mu, names);
    let (t0, t1) = clip.mu.span().unwrap();
    let t = 0.5 * (t0 + t1);
    let n = body.nq();
    let [mut q, mut v, mut a] = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
    sampler.state(t, &mut q, &mut v, &mut a).unwrap();
    assert!(q.iter().chain(&v).chain(&a).all(|x| x.is_finite()));
    Some((body, [q, v, a]))
}

/// Forces under both feet (ankles and toes), off the joints' origins, one
/// with a moment about up.
pub(crate) fn feet(body: &Model) -> Vec<PointForce> {
    let points = mx::ground::default_contact_points(body);
    let sides = |s: &str| points.iter().any(|p| p.name.to_lowercase().contains(s));
    assert!(sides("l") && sides("r"), "{points:?}");
    points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let k = i as f64;
            PointForce::at(
                p.link,
                Vector3::new(0.03 * k, -0.02, 0.05),
                Vector3::new(20.0 - 10.0 * k, 150.0 + 40.0 * k, 15.0 * k),
            )
            .with_moment(Vector3::new(0.0, 3.0 * k, 0.0))
        })
        .collect()
}

/// Σ_c J_cᵀ [m_c; f_c] by central differences of forward kinematics: the
/// point's position for the force, the link's rotation for the moment.
fn by_hand(body: &Model, q: &[f64], forces: &[PointForce]) -> Vec<f64> {
    let n = body.nq();
    let mut out = vec![0.0; n];
    let (mut plus, mut minus) = (vec![], vec![]);
    for c in 0..n {
        let h = 1e-6;
        let (mut qp, mut qm) = (q.to_vec(), q.to_vec());
        qp[c] += h;
        qm[c] -= h;
        body.forward_kinematics(&qp, &mut plus).unwrap();
        body.forward_kinematics(&qm, &mut minus).unwrap();
        for f in forces {
            let (tp, tm) = (plus[f.link], minus[f.link]);
            let dp = (tp.act_point(&f.point) - tm.act_point(&f.point)) / (2.0 * h);
            // world angular velocity per unit q̇_c: log(R₊ R₋ᵀ) / 2h
            let w = log_so3(&(tp.r * tm.r.transpose())) / (2.0 * h);
            out[c] += dp.dot(&f.force) + w.dot(&f.moment);
        }
    }
    out
}

#[test]
fn point_forces_take_away_their_jacobian_transpose() {
    let Some((body, [q, v, a])) = walk() else {
        return;
    };
    let forces = feet(&body);
    let g = body.default_gravity;
    let mut ws = Workspace::new(&body);
    let n = body.nq();
    let (mut t0, mut t1) = (vec![0.0; n], vec![0.0; n]);
    inverse_dynamics(&body, &mut ws, &q, &v, &a, &g, &mut t0).unwrap();
    let x = JointState::new(&q, &v, &a);
    inverse_dynamics_at_points(&body, &mut ws, &x, &g, &forces, &mut t1).unwrap();
    let jtf = by_hand(&body, &q, &forces);
    let expect: Vec<f64> = t0.iter().zip(&jtf).map(|(t, j)| t - j).collect();
    let scale = jtf.iter().fold(1.0f64, |m, v| m.max(v.abs()));
    let err = t1
        .iter()
        .zip(&expect)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max)
        / scale;
    eprintln!("τ with point forces vs τ − Σ Jᵀf by hand: rel err {err:.2e} (scale {scale:.0})");
    assert!(err < 1e-6, "{err:e}");
    // the forces matter: the root's rows change by the weight they carry
    assert!(t0.iter().zip(&t1).any(|(a, b)| (a - b).abs() > 1.0));
    // no forces: inverse dynamics as it was, to the bit
    inverse_dynamics_at_points(&body, &mut ws, &x, &g, &[], &mut t1).unwrap();
    assert_eq!(t0, t1);
}

#[test]
fn the_gradient_with_point_forces_matches_central_differences() {
    let Some((body, [q, v, a])) = walk() else {
        return;
    };
    let forces = feet(&body);
    let g = body.default_gravity;
    let n = body.nq();
    let w: Vec<f64> = (0..n).map(|i| 0.5 + (i % 3) as f64).collect();
    let mut ws = Workspace::new(&body);
    let (mut gq, mut gv, mut ga) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let x = JointState::new(&q, &v, &a);
    let grad = StateGradient {
        q: &mut gq,
        v: &mut gv,
        a: &mut ga,
    };
    let j = torque_sq_gradient_at_points(&body, &mut ws, &x, &g, &w, &forces, grad).unwrap();
    let mut tau = vec![0.0; n];
    let mut cost = |ws: &mut Workspace, s: &[Vec<f64>; 3]| -> f64 {
        let x = JointState::new(&s[0], &s[1], &s[2]);
        inverse_dynamics_at_points(&body, ws, &x, &g, &forces, &mut tau).unwrap();
        tau.iter().zip(&w).map(|(t, w)| w * t * t).sum()
    };
    let state = [q.clone(), v.clone(), a.clone()];
    assert!((j - cost(&mut ws, &state)).abs() < 1e-12 * j);
    let mut worst = 0.0f64;
    for (k, analytic) in [&gq, &gv, &ga].into_iter().enumerate() {
        let scale = analytic.iter().fold(1.0f64, |m, v| m.max(v.abs()));
        for c in 0..n {
            let h = 1e-6 * (1.0 + state[k][c].abs());
            let (mut p, mut m) = (state.clone(), state.clone());
            p[k][c] += h;
            m[k][c] -= h;
            let fd = (cost(&mut ws, &p) - cost(&mut ws, &m)) / (2.0 * h);
            worst = worst.max((fd - analytic[c]).abs() / scale);
        }
    }
    eprintln!("∂(Σwτ²)/∂(q, q̇, q̈) with point forces vs central differences: {worst:.2e}");
    assert!(worst < 1e-6, "{worst:e}");
    // without the turning of the forces with their links, q's gradient is wrong
    let (mut hq, mut hv, mut ha) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let none = StateGradient {
        q: &mut hq,
        v: &mut hv,
        a: &mut ha,
    };
    torque_sq_gradient(&body, &mut ws, &x, &g, &w, none).unwrap();
    let moved = DVector::from_vec(gq.clone()) - DVector::from_vec(hq);
    assert!(moved.amax() > 1e-3 * DVector::from_vec(gq).amax());
}

#[test]
fn a_bad_point_force_is_a_clear_error() {
    let Some((body, [q, v, a])) = walk() else {
        return;
    };
    let mut ws = Workspace::new(&body);
    let mut tau = vec![0.0; body.nq()];
    let x = JointState::new(&q, &v, &a);
    let g = body.default_gravity;
    let off = PointForce::at(body.num_links(), Vector3::zeros(), Vector3::y());
    let e = inverse_dynamics_at_points(&body, &mut ws, &x, &g, &[off], &mut tau).unwrap_err();
    assert!(e.to_string().contains("link"), "{e}");
    let nan = PointForce::at(0, Vector3::zeros(), Vector3::new(f64::NAN, 0.0, 0.0));
    let e = inverse_dynamics_at_points(&body, &mut ws, &x, &g, &[nan], &mut tau).unwrap_err();
    assert!(e.to_string().contains("finite"), "{e}");
}

/// The body and mid-clip state of the first clip of `data/{sub}` whose name
/// holds `name`.
pub(crate) fn clip_state(sub: &str, name: &str) -> Option<(Model, [Vec<f64>; 3])> {
    let path = shared_files(sub, ".bvh")
        .into_iter()
        .find(|p| p.to_string_lossy().contains(name))?;
    let clip = mocap::load(&path, Units::Auto).unwrap();
    let (body, _) = mocap::body_of(&clip.skeleton, 70.0, clip.units.metres_per_unit).unwrap();
    let sampler = JointSampler::new(&clip.mu, body.coordinate_names());
    let (t0, t1) = clip.mu.span().unwrap();
    let n = body.nq();
    let [mut q, mut v, mut a] = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
    sampler
        .state(0.4 * t0 + 0.6 * t1, &mut q, &mut v, &mut a)
        .unwrap();
    Some((body, [q, v, a]))
}

/// A reverse sweep's seeds on τ and on the root's wrench give the gradient
/// of τ̄·τ + ρ·w_root: checked against central differences on a Bandai walk
/// (a constant placeholder above the moving root) and a CMU clip (the
/// moving root is the first link, so its own transform's derivative is in
/// play), with forces under the feet; several sweeps after one pass agree
/// with a fresh pass each.
#[test]
fn a_reverse_sweep_seeded_on_the_root_wrench_matches_central_differences() {
    use mx::dynamics::{InverseDynamicsPass, root_wrench};
    use mx::lie::Twist;
    let cases = [walk(), clip_state("mocap", "cmu_131")];
    let mut ran = 0;
    for (body, [q, v, a]) in cases.into_iter().flatten() {
        ran += 1;
        let forces = feet(&body);
        let g = body.default_gravity;
        let n = body.nq();
        let mut ws = Workspace::new(&body);
        let tbar: Vec<f64> = (0..n).map(|i| 0.01 * ((i % 5) as f64 - 2.0)).collect();
        let seeds = [
            Twist::new(0.3, -0.2, 0.5, 1.0, -0.7, 0.4),
            Twist::new(0.0, 0.0, 0.0, 0.0, 1.0, 0.0),
        ];
        let mut tau = vec![0.0; n];
        let mut value = |ws: &mut Workspace, s: &[Vec<f64>; 3], rho: &Twist, tb: &[f64]| -> f64 {
            let x = JointState::new(&s[0], &s[1], &s[2]);
            inverse_dynamics_at_points(&body, ws, &x, &g, &forces, &mut tau).unwrap();
            let w = root_wrench(&body, ws);
            tau.iter().zip(tb).map(|(t, b)| t * b).sum::<f64>() + rho.dot(&w)
        };
        let state = [q.clone(), v.clone(), a.clone()];
        let x = JointState::new(&q, &v, &a);
        let mut grads = vec![];
        {
            let mut pass = InverseDynamicsPass::new(&body, &mut ws, x, &g, &forces).unwrap();
            for (i, rho) in seeds.iter().enumerate() {
                let tb: Vec<f64> = tbar.iter().map(|t| t * i as f64).collect();
                let [mut gq, mut gv, mut ga] = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
                let grad = StateGradient {
                    q: &mut gq,
                    v: &mut gv,
                    a: &mut ga,
                };
                pass.reverse(&tb, rho, grad).unwrap();
                grads.push([gq, gv, ga]);
            }
            // the pass's own numbers are inverse dynamics'
            let w = pass.root_wrench();
            assert!(w.iter().all(|x| x.is_finite()));
        }
        let mut worst = 0.0f64;
        for (i, (rho, analytic)) in seeds.iter().zip(&grads).enumerate() {
            let tb: Vec<f64> = tbar.iter().map(|t| t * i as f64).collect();
            for (k, gk) in analytic.iter().enumerate() {
                let scale = gk.iter().fold(1.0f64, |m, v| m.max(v.abs()));
                for c in 0..n {
                    let h = 1e-6 * (1.0 + state[k][c].abs());
                    let (mut p, mut m) = (state.clone(), state.clone());
                    p[k][c] += h;
                    m[k][c] -= h;
                    let fd =
                        (value(&mut ws, &p, rho, &tb) - value(&mut ws, &m, rho, &tb)) / (2.0 * h);
                    worst = worst.max((fd - gk[c]).abs() / scale);
                }
            }
        }
        eprintln!(
            "{}: reverse sweep seeded on τ and the root wrench vs central differences: {worst:.2e}",
            body.name
        );
        assert!(worst < 1e-6, "{worst:e}");
        // a seed on τ alone is the torque adjoint: Σwτ²'s gradient with τ̄ = 2wτ
        let w: Vec<f64> = (0..n).map(|i| 0.5 + (i % 3) as f64).collect();
        let [mut gq, mut gv, mut ga] = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
        let grad = StateGradient {
            q: &mut gq,
            v: &mut gv,
            a: &mut ga,
        };
        torque_sq_gradient_at_points(&body, &mut ws, &x, &g, &w, &forces, grad).unwrap();
        let mut pass = InverseDynamicsPass::new(&body, &mut ws, x, &g, &forces).unwrap();
        let tb: Vec<f64> = pass
            .tau()
            .iter()
            .zip(&w)
            .map(|(t, w)| 2.0 * w * t)
            .collect();
        let [mut hq, mut hv, mut ha] = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
        let grad = StateGradient {
            q: &mut hq,
            v: &mut hv,
            a: &mut ha,
        };
        pass.reverse(&tb, &Twist::zeros(), grad).unwrap();
        assert_eq!((gq, gv, ga), (hq, hv, ha));
        // bad seeds are named
        let grad = StateGradient {
            q: &mut vec![0.0; n],
            v: &mut vec![0.0; n],
            a: &mut vec![0.0; n],
        };
        let e = pass.reverse(&tb[1..], &Twist::zeros(), grad).unwrap_err();
        assert!(e.to_string().contains("tau_bar"), "{e}");
    }
    assert!(ran > 0 || crate::common::shared_dir().is_none());
}

/// ∂(−Σ J_cᵀ [m_c; f_c])/∂q, exact (`point_forces_jacobian`), against
/// central differences of inverse dynamics at rest without gravity (which
/// is −Σ J_cᵀ [m_c; f_c]), over a subset of the columns: on random trees
/// with configuration-dependent joints, the spline-joint chain and the walk.
#[test]
fn the_forces_jacobian_matches_central_differences() {
    use crate::support::{Rng, random_tree, spline_chain};
    use mx::dynamics::point_forces_jacobian;
    let mut rng = Rng::new(5);
    let mut cases: Vec<(Model, Vec<f64>, Vec<PointForce>)> = vec![];
    for (n, poe) in [(6, false), (11, true)] {
        let m = random_tree(&mut rng, n, poe);
        let q = rng.vec(m.nq(), -1.5, 1.5);
        let f = vec![
            PointForce::at(n - 1, rng.v3(0.2), rng.v3(30.0)).with_moment(rng.v3(2.0)),
            PointForce::at(n / 2, rng.v3(0.2), rng.v3(30.0)),
        ];
        cases.push((m, q, f));
    }
    let m = spline_chain(&mut rng);
    let q = rng.vec(m.nq(), -0.5, 0.5);
    let last = m.num_links() - 1;
    let f = vec![PointForce::at(last, rng.v3(0.1), rng.v3(20.0)).with_moment(rng.v3(1.0))];
    cases.push((m, q, f));
    if let Some((m, [q, _, _])) = walk() {
        let f = feet(&m);
        cases.push((m, q, f));
    }
    for (m, q, forces) in cases {
        let n = m.nq();
        let coords: Vec<usize> = (0..n).filter(|c| c % 3 != 1).collect();
        let mut ws = Workspace::new(&m);
        let mut jac = nalgebra::DMatrix::zeros(n, coords.len());
        point_forces_jacobian(&m, &mut ws, &q, &forces, &coords, &mut jac).unwrap();
        let rest = vec![0.0; n];
        let mut torques = |q: &[f64]| {
            let mut t = vec![0.0; n];
            let x = JointState::new(q, &rest, &rest);
            inverse_dynamics_at_points(&m, &mut ws, &x, &Vector3::zeros(), &forces, &mut t)
                .unwrap();
            t
        };
        let scale = jac.amax().max(1.0);
        let mut worst = 0.0f64;
        for (j, &c) in coords.iter().enumerate() {
            let h = 1e-6 * (1.0 + q[c].abs());
            let (mut qp, mut qm) = (q.clone(), q.clone());
            qp[c] += h;
            qm[c] -= h;
            let (tp, tm) = (torques(&qp), torques(&qm));
            for i in 0..n {
                worst = worst.max(((tp[i] - tm[i]) / (2.0 * h) - jac[(i, j)]).abs() / scale);
            }
        }
        eprintln!(
            "{}: forces' Jacobian vs central differences {worst:.1e}",
            m.name
        );
        assert!(worst < 1e-7, "{}: {worst:e}", m.name);
        // a wrong shape is named
        let mut bad = nalgebra::DMatrix::zeros(n, 1);
        let e = point_forces_jacobian(&m, &mut ws, &q, &forces, &coords, &mut bad).unwrap_err();
        assert!(e.to_string().contains("Jacobian"), "{e}");
    }
}
