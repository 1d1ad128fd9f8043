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
fn walk() -> Option<(Model, [Vec<f64>; 3])> {
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
fn feet(body: &Model) -> Vec<PointForce> {
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
