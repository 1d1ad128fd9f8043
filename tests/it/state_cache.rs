//! `mx::dynamics::StateCache`: one state's passes, shared by whoever asks at
//! that state. Its τ, root wrench and reverse sweeps are those of the
//! uncached algorithms to the bit; its poses and point Jacobians are forward
//! kinematics' and their derivatives; and a request at another state (only
//! q̈, only the forces, only q changed) is answered as a fresh cache would,
//! never from a stale pass. On random trees with configuration-dependent
//! joints, the library's spline joints, and a captured walk with forces
//! under its feet.

use crate::dynamics_points::{feet, walk};
use crate::support::{Rng, random_tree, spline_chain};
use mx::dynamics::{
    InverseDynamicsPass, JointState, Loaded, PointForce, StateCache, StateGradient, Workspace,
    inverse_dynamics_at_points, root_wrench, torque_sq_gradient_at_points,
};
use mx::lie::Twist;
use mx::model::Model;
use nalgebra::Vector3;

/// Bodies with states and forces: random trees (with and without
/// configuration-dependent joints), a spline-joint chain, and the walk.
fn cases() -> Vec<(Model, [Vec<f64>; 3], Vec<PointForce>)> {
    let mut rng = Rng::new(42);
    let mut out = vec![];
    for (n, poe) in [(7, false), (12, true)] {
        let m = random_tree(&mut rng, n, poe);
        let st = [0; 3].map(|_| rng.vec(m.nq(), -1.5, 1.5));
        let forces = vec![
            PointForce::at(n - 1, rng.v3(0.2), rng.v3(30.0)),
            PointForce::at(n / 2, rng.v3(0.2), rng.v3(30.0)).with_moment(rng.v3(2.0)),
        ];
        out.push((m, st, forces));
    }
    let m = spline_chain(&mut rng);
    let st = [0; 3].map(|_| rng.vec(m.nq(), -0.5, 0.5));
    let last = m.num_links() - 1;
    out.push((m, st, vec![PointForce::at(last, rng.v3(0.1), rng.v3(20.0))]));
    if let Some((m, st)) = walk() {
        let forces = feet(&m);
        out.push((m, st, forces));
    }
    out
}

fn bits(x: &[f64]) -> Vec<u64> {
    x.iter().map(|v| v.to_bits()).collect()
}

/// The gradient of τ̄·τ + ρ·w_root by the uncached pass.
fn pass_gradient(m: &Model, s: &Loaded, tbar: &[f64], rho: &Twist) -> [Vec<f64>; 3] {
    let mut ws = Workspace::new(m);
    let n = m.nq();
    let mut pass = InverseDynamicsPass::new(m, &mut ws, s.x, s.gravity, s.forces).unwrap();
    let [mut q, mut v, mut a] = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
    let grad = StateGradient {
        q: &mut q,
        v: &mut v,
        a: &mut a,
    };
    pass.reverse(tbar, rho, grad).unwrap();
    [q, v, a]
}

fn cached_gradient(
    c: &mut StateCache,
    m: &Model,
    s: &Loaded,
    tbar: Option<&[f64]>,
    rho: Option<&Twist>,
) -> [Vec<f64>; 3] {
    let n = m.nq();
    let [mut q, mut v, mut a] = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
    let grad = StateGradient {
        q: &mut q,
        v: &mut v,
        a: &mut a,
    };
    c.reverse(m, s, tbar, rho, grad).unwrap();
    [q, v, a]
}

#[test]
fn its_passes_are_the_uncached_algorithms_to_the_bit() {
    let g = Vector3::new(0.3, -9.80665, 0.5);
    for (m, [q, v, a], forces) in cases() {
        let n = m.nq();
        for forces in [&forces[..], &[]] {
            let s = Loaded {
                x: JointState::new(&q, &v, &a),
                gravity: &g,
                forces,
            };
            let mut cache = StateCache::new(&m);
            let mut ws = Workspace::new(&m);
            let mut tau = vec![0.0; n];
            inverse_dynamics_at_points(&m, &mut ws, &s.x, &g, forces, &mut tau).unwrap();
            assert_eq!(bits(cache.tau(&m, &s).unwrap()), bits(&tau), "{}", m.name);
            let w = root_wrench(&m, &ws);
            assert_eq!(cache.root_wrench(&m, &s).unwrap(), w);
            // several sweeps after one pass, each the uncached pass's
            let tbar: Vec<f64> = (0..n).map(|i| 0.1 * ((i % 7) as f64 - 3.0)).collect();
            let rho = Twist::new(0.3, -0.2, 0.5, 1.0, -0.7, 0.4);
            for _ in 0..2 {
                let got = cached_gradient(&mut cache, &m, &s, Some(&tbar), Some(&rho));
                assert_eq!(got, pass_gradient(&m, &s, &tbar, &rho), "{}", m.name);
            }
            // a seed on τ alone is the torque adjoint's
            let wts: Vec<f64> = (0..n).map(|i| 0.5 + (i % 3) as f64).collect();
            let [mut gq, mut gv, mut ga] = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
            let grad = StateGradient {
                q: &mut gq,
                v: &mut gv,
                a: &mut ga,
            };
            torque_sq_gradient_at_points(&m, &mut ws, &s.x, &g, &wts, forces, grad).unwrap();
            let tb: Vec<f64> = tau.iter().zip(&wts).map(|(t, w)| t * (2.0 * w)).collect();
            let got = cached_gradient(&mut cache, &m, &s, Some(&tb), None);
            assert_eq!(got, [gq, gv, ga], "{}", m.name);
        }
    }
}

#[test]
fn its_poses_and_point_jacobians_are_forward_kinematics() {
    let g = Vector3::new(0.0, -9.81, 0.0);
    for (m, [q, v, a], _) in cases() {
        let mut cache = StateCache::new(&m);
        let x = JointState::new(&q, &v, &a);
        let mut fk = vec![];
        m.forward_kinematics(&q, &mut fk).unwrap();
        let poses = cache.poses(&m, &x).unwrap().to_vec();
        for (p, f) in poses.iter().zip(&fk) {
            assert!(
                (p.p - f.p).amax() < 1e-12 * (1.0 + f.p.amax()),
                "{}",
                m.name
            );
            assert!((p.r - f.r).amax() < 1e-12, "{}", m.name);
        }
        // τ after the poses is still inverse dynamics' (the pass is shared)
        let s = Loaded {
            x,
            gravity: &g,
            forces: &[],
        };
        let mut ws = Workspace::new(&m);
        let mut tau = vec![0.0; m.nq()];
        inverse_dynamics_at_points(&m, &mut ws, &x, &g, &[], &mut tau).unwrap();
        assert_eq!(bits(cache.tau(&m, &s).unwrap()), bits(&tau));
        let link = m.num_links() - 1;
        let cols = cache.point_jacobian(&m, &x, link).unwrap().to_vec();
        let mut moved = vec![false; m.nq()];
        for (c, col) in &cols {
            moved[*c] = true;
            let h = 1e-6 * (1.0 + q[*c].abs());
            let (mut qp, mut qm) = (q.clone(), q.clone());
            qp[*c] += h;
            qm[*c] -= h;
            let at = |q: &[f64]| m.point_position(q, link, &Vector3::zeros()).unwrap();
            let fd = (at(&qp) - at(&qm)) / (2.0 * h);
            assert!(
                (fd - col).amax() < 1e-6 * (1.0 + fd.amax()),
                "{}: {c}",
                m.name
            );
        }
        // every other coordinate leaves the link's origin where it is
        for c in (0..m.nq()).filter(|c| !moved[*c]) {
            let mut qp = q.clone();
            qp[c] += 0.1;
            let p = m.point_position(&qp, link, &Vector3::zeros()).unwrap();
            assert!((p - poses[link].p).amax() < 1e-12, "{}: {c}", m.name);
        }
        assert!(cache.point_jacobian(&m, &x, m.num_links()).is_err());
    }
}

#[test]
fn a_request_at_another_state_is_never_answered_from_a_stale_pass() {
    let g = Vector3::new(0.0, -9.81, 0.0);
    for (m, [q, v, a], forces) in cases() {
        let n = m.nq();
        let fresh = |s: &Loaded| {
            let mut c = StateCache::new(&m);
            let tau = c.tau(&m, s).unwrap().to_vec();
            let poses = c.poses(&m, &s.x).unwrap().to_vec();
            (tau, poses)
        };
        let a2: Vec<f64> = a.iter().map(|x| x + 0.25).collect();
        let mut q2 = q.clone();
        q2[n - 1] += 0.3;
        let mut moved = forces.clone();
        moved[0].force.x += 5.0;
        let states = [
            (&q, &a, &forces),
            (&q, &a2, &forces),
            (&q, &a, &moved),
            (&q2, &a, &forces),
            (&q, &a, &forces),
        ];
        let mut cache = StateCache::new(&m);
        for (q, a, f) in states {
            let s = Loaded {
                x: JointState::new(q, &v, a),
                gravity: &g,
                forces: f,
            };
            // poses first, then τ: the order terms ask in varies
            let poses = cache.poses(&m, &s.x).unwrap().to_vec();
            let tau = cache.tau(&m, &s).unwrap().to_vec();
            let (ft, fp) = fresh(&s);
            assert_eq!(bits(&tau), bits(&ft), "{}", m.name);
            assert_eq!(poses, fp, "{}", m.name);
            let rho = Twist::new(0.0, 0.0, 0.0, 0.0, 1.0, 0.0);
            let got = cached_gradient(&mut cache, &m, &s, None, Some(&rho));
            assert_eq!(got, pass_gradient(&m, &s, &vec![0.0; n], &rho));
        }
    }
}
