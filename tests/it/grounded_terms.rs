//! The grounded objective's terms (`spacetime::objective`: base, stance,
//! floor, clearance, and the contact forces) on a captured walk's window:
//! each term's gradient against central differences of the objective, its
//! Gauss–Newton rows against central differences of its residual, and known
//! answers on a standing body.

use crate::common::shared_files;
use mx::ground::{FloorPlane, default_contact_points, up_direction};
use mx::mocap::{self, bvh::Units};
use mx::model::{Model, RootCoords};
use mx::motion::{Dof, Interval, JointSampler, Mu};
use mx::spacetime::objective::{
    BaseTerm, Clearance, ContactForces, GapLayout, GroundScale, PointTerm, Term, clearance_term,
    floor_term, stance_term,
};
use mx::spacetime::{
    BodyDynamics, Continuity, EndState, GapDof, GapPlan, Objective, PointPlan, SpError, Stance,
    TransitionSettings,
};
use nalgebra::{DMatrix, Vector3};

/// Friction of the cone problems (a shoe on a floor).
const FRICTION: f64 = 0.8;

/// The first walk of `data/inbetween`: its body and motion.
fn walk() -> Option<(Model, Mu)> {
    let path = shared_files("inbetween", ".bvh")
        .into_iter()
        .find(|p| p.to_string_lossy().contains("walk"))?;
    let clip = mocap::load(&path, Units::Auto).unwrap();
    let (body, _) = mocap::body_of(&clip.skeleton, 70.0, clip.units.metres_per_unit).unwrap();
    Some((body, clip.mu))
}

/// A window of a motion: its gap DOFs (the moving root and every coordinate
/// that moves the first contact point), laid out with few nodes.
struct Window {
    names: Vec<String>,
    t0: f64,
    t1: f64,
    layout: GapLayout,
}

fn window(body: &Model, mu: &Mu, t0: f64, t1: f64) -> Window {
    let names = body.coordinate_names().to_vec();
    let sampler = JointSampler::new(mu, &names);
    let up = up_direction(&body.default_gravity).unwrap();
    let root = RootCoords::detect(body, Some(&up));
    let foot = default_contact_points(body)[0].link;
    let mut coords: Vec<usize> = root
        .all
        .iter()
        .copied()
        .filter(|c| !root.fixed.contains(c))
        .collect();
    let mut l = Some(foot);
    while let Some(i) = l {
        let link = body.link(i);
        coords.extend((link.q_index..link.q_index + link.dof).filter(|c| !root.all.contains(c)));
        l = link.parent;
    }
    let n = body.nq();
    let end = |t: f64, c: usize| {
        let [mut q, mut v, mut a] = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
        sampler.state(t, &mut q, &mut v, &mut a).unwrap();
        EndState {
            q: q[c],
            v: v[c],
            a: a[c],
        }
    };
    let dofs = coords
        .iter()
        .map(|&c| GapDof {
            coord: c,
            t0,
            t1,
            start: end(t0, c),
            end: end(t1, c),
        })
        .collect();
    let settings = TransitionSettings {
        coefficients: 5,
        samples: 6,
        continuity: Continuity::C1,
    };
    Window {
        names,
        t0,
        t1,
        layout: GapLayout::new(dofs, &settings).unwrap(),
    }
}

/// The objective of `terms` alone (no torque, no prior) on `mu` over `w`.
fn objective<'a>(
    body: &'a BodyDynamics<'a>,
    mu: &Mu,
    w: &Window,
    terms: Vec<Box<dyn Term<BodyDynamics<'a>> + 'a>>,
) -> Objective<'a, BodyDynamics<'a>> {
    let sampler = JointSampler::new(mu, &w.names);
    let inputs = |t: f64, q: &mut [f64], v: &mut [f64], a: &mut [f64]| {
        sampler
            .state(t, q, v, a)
            .map(|_| ())
            .map_err(|e| SpError::Invalid(e.to_string()))
    };
    let zero = vec![0.0; body.model.nq()];
    let mut obj = Objective::on_layout(body, w.layout.clone(), zero, &inputs).unwrap();
    for t in terms {
        obj = obj.with_term(t);
    }
    obj
}

/// The configuration of `mu` at t.
fn pose(body: &Model, mu: &Mu, t: f64) -> Vec<f64> {
    let names = body.coordinate_names().to_vec();
    let n = body.nq();
    let [mut q, mut v, mut a] = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
    JointSampler::new(mu, &names)
        .state(t, &mut q, &mut v, &mut a)
        .unwrap();
    q
}

/// A plan on the window: the first contact point planted 1 cm off where it
/// is at the start over the first 40 %, the second where it is at the end
/// over the last 40 %, the rest free.
fn plan(body: &Model, mu: &Mu, w: &Window) -> GapPlan {
    let (q0, q1) = (pose(body, mu, w.t0), pose(body, mu, w.t1));
    let at = |q: &[f64], l: usize| body.point_position(q, l, &Vector3::zeros()).unwrap();
    let span = w.t1 - w.t0;
    let points = default_contact_points(body)
        .into_iter()
        .enumerate()
        .map(|(j, p)| PointPlan {
            name: p.name.clone(),
            link: p.link,
            // unread here: clearance_term takes its standing heights beside the plan
            stand: 0.0,
            stances: match j {
                0 => vec![Stance::planted(
                    w.t0,
                    w.t0 + 0.4 * span,
                    at(&q0, p.link) + Vector3::new(0.01, 0.0, -0.01),
                )],
                1 => vec![Stance::planted(w.t1 - 0.4 * span, w.t1, at(&q1, p.link))],
                _ => vec![],
            },
        })
        .collect();
    GapPlan {
        t0: w.t0,
        t1: w.t1,
        points,
    }
}

/// A floor through the window's feet: 2 cm above the lowest contact point
/// at the start, so some points are below it at some nodes.
fn floor(body: &BodyDynamics, mu: &Mu, w: &Window) -> FloorPlane {
    let q = pose(body.model, mu, w.t0);
    let up = up_direction(&body.gravity).unwrap();
    let low = default_contact_points(body.model)
        .iter()
        .map(|p| {
            up.dot(
                &body
                    .model
                    .point_position(&q, p.link, &Vector3::zeros())
                    .unwrap(),
            )
        })
        .fold(f64::INFINITY, f64::min);
    FloorPlane::new(&body.gravity, low + 0.02).unwrap()
}

/// x: the Hermite start moved a little, so no residual is at a special value.
fn unknowns(obj: &Objective<BodyDynamics>) -> Vec<f64> {
    let mut x = obj.hermite_start();
    for (i, v) in x.iter_mut().enumerate() {
        *v += 0.01 * (1.3 * i as f64).cos();
    }
    x
}

/// ∂e/∂x against central differences; the worst error relative to the
/// gradient's largest entry.
fn gradient_error(obj: &Objective<BodyDynamics>, x: &[f64]) -> f64 {
    let mut s = obj.scratch();
    let mut g = vec![0.0; x.len()];
    obj.eval(&mut s, x, Some(&mut g)).unwrap();
    let scale = g.iter().fold(1e-300f64, |m, v| m.max(v.abs()));
    let mut worst = 0.0f64;
    for i in 0..x.len() {
        let h = 1e-6;
        let (mut xp, mut xm) = (x.to_vec(), x.to_vec());
        xp[i] += h;
        xm[i] -= h;
        let fd = (obj.eval(&mut s, &xp, None).unwrap() - obj.eval(&mut s, &xm, None).unwrap())
            / (2.0 * h);
        worst = worst.max((fd - g[i]).abs() / scale);
    }
    worst
}

/// A node's residual: r(k, [q, q̇, q̈]).
type NodeResidual<'r> = dyn FnMut(usize, [&[f64]; 3]) -> Vec<f64> + 'r;

/// H/2 = Σ_k w_k W J_kᵀ J_k with J_k the central differences of node k's
/// residual `r(k, q, q̇, q̈)` through x (weight W on every row).
fn gauss_newton_by_differences(
    obj: &Objective<BodyDynamics>,
    x: &[f64],
    weight: f64,
    r: &mut NodeResidual,
) -> DMatrix<f64> {
    let nv = x.len();
    let mut h = DMatrix::zeros(nv, nv);
    let wk = obj.layout().nodes().1.to_vec();
    for (k, wk) in wk.iter().enumerate() {
        let mut cols = vec![];
        for i in 0..nv {
            let d = 1e-6;
            let (mut xp, mut xm) = (x.to_vec(), x.to_vec());
            xp[i] += d;
            xm[i] -= d;
            let [qp, vp, ap] = obj.node_state(&xp, k);
            let [qm, vm, am] = obj.node_state(&xm, k);
            let (rp, rm) = (r(k, [&qp, &vp, &ap]), r(k, [&qm, &vm, &am]));
            cols.push(
                rp.iter()
                    .zip(&rm)
                    .map(|(p, m)| (p - m) / (2.0 * d))
                    .collect::<Vec<f64>>(),
            );
        }
        let m = cols.first().map_or(0, |c| c.len());
        let j = DMatrix::from_fn(m, nv, |a, b| cols[b][a]);
        h += j.transpose() * j * (wk * weight);
    }
    h
}

/// `max|a − b| / max|b|`.
fn matrix_error(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    let scale = b.amax();
    assert!(scale > 0.0, "the Gauss–Newton part is empty");
    (a - b).amax() / scale
}

/// Each point term's gradient and Gauss–Newton rows, with the rows active
/// at the window: stance (a point held 1 cm off), floor (a floor above the
/// lowest foot), clearance (swinging points to clear the floor).
#[test]
fn the_point_terms_gradients_and_gauss_newton_rows_match_central_differences() {
    let Some((model, mu)) = walk() else { return };
    let body = BodyDynamics::new(&model);
    let (s0, s1) = mu.span().unwrap();
    let mid = 0.5 * (s0 + s1);
    let w = window(&model, &mu, mid, mid + 0.6);
    let plan = plan(&model, &mu, &w);
    let fl = floor(&body, &mu, &w);
    let q0 = pose(&model, &mu, w.t0);
    let scale = GroundScale::of(&body, &q0).unwrap();
    let stands = vec![fl.height; plan.points.len()];
    let weight = 1e3;
    let build = |name: &str| -> PointTerm {
        match name {
            "stance" => stance_term(&body, &plan, &w.layout, weight),
            "floor" => floor_term(&body, &plan, fl, &w.layout, weight),
            _ => clearance_term(
                &body,
                &plan,
                &stands,
                fl,
                Clearance::of(&scale),
                &w.layout,
                weight,
            ),
        }
        .unwrap()
    };
    for name in ["stance", "floor", "clearance"] {
        let obj = objective(&body, &mu, &w, vec![Box::new(build(name))]);
        let x = unknowns(&obj);
        let mut s = obj.scratch();
        let e = obj.eval(&mut s, &x, None).unwrap();
        assert!(e > 0.0, "{name}: the window must exercise the term");
        let ge = gradient_error(&obj, &x);
        let term = build(name);
        let h = obj.half_gauss_newton(&mut s, &x).unwrap();
        let hd = gauss_newton_by_differences(&obj, &x, weight, &mut |k, [q, _, _]| {
            term.residual(k, q).unwrap()
        });
        let he = matrix_error(&h, &hd);
        eprintln!("{name}: e = {e:.3e}, gradient error {ge:.1e}, Gauss–Newton error {he:.1e}");
        assert!(ge < 1e-6, "{name}: gradient error {ge:e}");
        assert!(he < 1e-6, "{name}: Gauss–Newton error {he:e}");
    }
}

/// The base term with the forces the cone problem picks at the window's
/// nodes: gradient (forces held) and the six exact rows.
#[test]
fn the_base_terms_gradient_and_gauss_newton_rows_match_central_differences() {
    let Some((model, mu)) = walk() else { return };
    let body = BodyDynamics::new(&model);
    let (s0, s1) = mu.span().unwrap();
    let mid = 0.5 * (s0 + s1);
    let w = window(&model, &mu, mid, mid + 0.6);
    let plan = plan(&model, &mu, &w);
    let scale = GroundScale::of(&body, &pose(&model, &mu, w.t0)).unwrap();
    let weight = 10.0;
    let base = BaseTerm::new(&body, scale, weight).unwrap();
    let mut obj = objective(&body, &mu, &w, vec![Box::new(base)]);
    let x = unknowns(&obj);
    let mut s = obj.scratch();
    let e = obj.eval(&mut s, &x, None).unwrap_err();
    assert!(e.to_string().contains("contact forces"), "{e}");
    let forces = ContactForces::new(&body, &plan, scale, FRICTION, obj.layout())
        .unwrap()
        .solve(&obj, &x)
        .unwrap();
    assert!(forces.iter().any(|f| !f.forces.is_empty()));
    obj.set_forces(forces.clone()).unwrap();
    let e = obj.eval(&mut s, &x, None).unwrap();
    let ge = gradient_error(&obj, &x);
    let term = BaseTerm::new(&body, scale, weight).unwrap();
    let mut ws = mx::dynamics::Workspace::new(&model);
    let h = obj.half_gauss_newton(&mut s, &x).unwrap();
    let hd = gauss_newton_by_differences(&obj, &x, weight, &mut |k, [q, v, a]| {
        let x = mx::dynamics::JointState::new(q, v, a);
        term.residual(&mut ws, x, &forces[k]).unwrap().to_vec()
    });
    let he = matrix_error(&h, &hd);
    eprintln!("base: e = {e:.3e}, gradient error {ge:.1e}, Gauss–Newton error {he:.1e}");
    assert!(ge < 1e-6, "gradient error {ge:e}");
    assert!(he < 1e-6, "Gauss–Newton error {he:e}");
    // the continuation's step: the weight scales e, by name
    obj.set_weight("base", 2.0 * weight).unwrap();
    let e2 = obj.eval(&mut s, &x, None).unwrap();
    assert!((e2 - 2.0 * e).abs() <= 1e-12 * e, "{e2} vs 2 × {e}");
    assert!(obj.set_weight("torque", 1.0).is_err());
    assert!(obj.set_weight("base", f64::NAN).is_err());
}

/// Known answers on the walk's body standing still at its first frame's
/// pose: every contact point planted where it is, the cone's forces leave
/// no base residual; with no stance (the body lifted 10 cm) the whole
/// weight is left, 100 % in force and none in moment about the centre of
/// mass; a point at its anchor costs no stance.
#[test]
fn a_standing_body_is_balanced_and_a_lifted_one_is_not() {
    let Some((model, mu)) = walk() else { return };
    let body = BodyDynamics::new(&model);
    let (s0, _) = mu.span().unwrap();
    let mut q = pose(&model, &mu, s0);
    // a still motion at that pose (the window's gap DOFs stay put: zero ends)
    let still = |q: Vec<f64>| {
        let mut m = Mu::new();
        for (name, v) in model.coordinate_names().iter().zip(q) {
            let i = Interval::constant(v, -1.0, 2.0).unwrap();
            m.insert(name.clone(), Dof::new(vec![i]).unwrap());
        }
        m
    };
    let (t0, t1) = (0.0, 0.5);
    let points = default_contact_points(&model);
    let anchors: Vec<Vector3<f64>> = points
        .iter()
        .map(|p| model.point_position(&q, p.link, &Vector3::zeros()).unwrap())
        .collect();
    let plan = |planted: bool| GapPlan {
        t0,
        t1,
        points: points
            .iter()
            .zip(&anchors)
            .map(|(p, a)| PointPlan {
                name: p.name.clone(),
                link: p.link,
                stand: 0.0, // unread: clearance_term takes its standing heights beside the plan
                stances: if planted {
                    vec![Stance::planted(t0, t1, *a)]
                } else {
                    vec![]
                },
            })
            .collect(),
    };
    let scale = GroundScale::of(&body, &q).unwrap();
    let up = up_direction(&body.gravity).unwrap();
    let root = RootCoords::detect(&model, Some(&up));
    for planted in [true, false] {
        if !planted {
            for &c in &root.vertical {
                q[c] += 0.1;
            }
        }
        let m = still(q.clone());
        let w = window(&model, &m, t0, t1);
        let plan = plan(planted);
        let base = BaseTerm::new(&body, scale, 1.0).unwrap();
        let stance = stance_term(&body, &plan, &w.layout, 1.0).unwrap();
        let mut obj = objective(&body, &m, &w, vec![Box::new(base), Box::new(stance)]);
        let x = obj.hermite_start();
        let forces = ContactForces::new(&body, &plan, scale, FRICTION, obj.layout())
            .unwrap()
            .solve(&obj, &x)
            .unwrap();
        obj.set_forces(forces).unwrap();
        let mut s = obj.scratch();
        let mut g = vec![0.0; x.len()];
        let e = obj.eval(&mut s, &x, Some(&mut g)).unwrap();
        if planted {
            eprintln!("standing: base + stance = {e:.2e}");
            assert!(e < 1e-10, "standing still on its feet leaves {e:e}");
            assert!(g.iter().all(|v| v.abs() < 1e-6), "at rest, gradient {g:?}");
        } else {
            // ∫ 1 dt: 100 % of the weight in force, no moment about the CoM
            let span = t1 - t0;
            eprintln!("lifted: base = {e:.6} over {span} s");
            assert!((e / span - 1.0).abs() < 1e-9, "{e} vs {span}");
        }
    }
}
