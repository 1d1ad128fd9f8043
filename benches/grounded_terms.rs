//! The grounded terms' cost per quadrature node (issue 35 item 1's speed
//! goal: a grounded solve ≤ 3× today's SP; the spike's finite-difference
//! node Jacobians made it 11–17×).
//!
//! On the first walk of `$MX_SHARED/data/inbetween`, a 1 s window with every
//! coordinate but the root's fixed placeholders as a gap DOF (SP's case with
//! the root cut), the first contact point planted over the first half and
//! the second over the second half, a floor through the lowest foot: per
//! node, the objective-and-gradient evaluation and the Gauss–Newton
//! preconditioner with the torque term alone (today's SP) and with the
//! base, stance, floor and clearance terms added, and one re-solve of the
//! contact forces. One thread (`RAYON_NUM_THREADS=1` is set here), best of
//! `MX_BENCH_REPS` (default 5) runs; the ratios are the numbers to read.
//!
//! Run: `cargo bench --bench grounded_terms`; a single part under callgrind:
//! `MX_BENCH_ONLY=<torque|grounded|forces|gn-torque|gn-grounded> MX_BENCH_REPS=1
//! valgrind --tool=callgrind target/release/deps/grounded_terms-*` (instructions
//! per node = the `run` function's inclusive count / nodes / repetitions).

mod common;
use common::shared;

use mx::ground::{FloorPlane, default_contact_points, up_direction};
use mx::mocap::{self, bvh::Units};
use mx::model::RootCoords;
use mx::motion::JointSampler;
use mx::spacetime::objective::{
    BaseTerm, Clearance, ContactForces, GroundScale, clearance_term, floor_term, stance_term,
};
use mx::spacetime::{
    BodyDynamics, EndState, GapDof, GapPlan, Objective, PointPlan, SpError, Stance,
    TransitionSettings,
};
use nalgebra::Vector3;
use std::time::Instant;

/// Best wall time of `reps` runs of `f` (s).
#[inline(never)]
fn run(reps: usize, mut f: impl FnMut()) -> f64 {
    (0..reps)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

fn main() {
    // one thread: per-node cost, not the machine's load
    // SAFETY: set before any thread starts
    unsafe { std::env::set_var("RAYON_NUM_THREADS", "1") };
    let reps: usize = std::env::var("MX_BENCH_REPS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(5);
    let only = std::env::var("MX_BENCH_ONLY").ok();
    let wants = |part: &str| only.as_deref().is_none_or(|o| o == part);
    let dir = shared().join("data/inbetween");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", dir.display()))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.to_string_lossy().contains("walk") && p.extension().is_some_and(|x| x == "bvh")
        })
        .collect();
    files.sort();
    let path = files.first().expect("a walk in data/inbetween");
    let clip = mocap::load(path, Units::Auto).unwrap();
    let (model, _) = mocap::body_of(&clip.skeleton, 70.0, clip.units.metres_per_unit).unwrap();
    let body = BodyDynamics::new(&model);
    let names = model.coordinate_names().to_vec();
    let sampler = JointSampler::new(&clip.mu, &names);
    let inputs = |t: f64, q: &mut [f64], v: &mut [f64], a: &mut [f64]| {
        sampler
            .state(t, q, v, a)
            .map(|_| ())
            .map_err(|e| SpError::Invalid(e.to_string()))
    };
    let n = model.nq();
    let state = |t: f64| {
        let [mut q, mut v, mut a] = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
        inputs(t, &mut q, &mut v, &mut a).unwrap();
        [q, v, a]
    };
    let (s0, s1) = clip.mu.span().unwrap();
    let (t0, t1) = (0.5 * (s0 + s1) - 0.5, 0.5 * (s0 + s1) + 0.5);
    let up = up_direction(&body.gravity).unwrap();
    let root = RootCoords::detect(&model, Some(&up));
    let ends = (state(t0), state(t1));
    let end = |s: &[Vec<f64>; 3], c: usize| EndState {
        q: s[0][c],
        v: s[1][c],
        a: s[2][c],
    };
    let dofs: Vec<GapDof> = (0..n)
        .filter(|c| !root.fixed.contains(c))
        .map(|c| GapDof {
            coord: c,
            t0,
            t1,
            start: end(&ends.0, c),
            end: end(&ends.1, c),
        })
        .collect();
    let mut weights = vec![1.0; n];
    for &c in &root.all {
        weights[c] = 0.0;
    }
    let settings = TransitionSettings::default();
    let torque_only = Objective::new(&body, dofs.clone(), &settings, weights.clone(), &inputs)
        .unwrap()
        .with_prior(&vec![[1e-3, 1e-5]; n])
        .unwrap();
    let layout = torque_only.layout().clone();
    let nodes = torque_only.n_nodes();
    // the plan: first point planted at its start position over the first
    // half, the second at its end position over the second half
    let points = default_contact_points(&model);
    let at = |q: &[f64], l: usize| model.point_position(q, l, &Vector3::zeros()).unwrap();
    let mid = 0.5 * (t0 + t1);
    let plan = GapPlan {
        t0,
        t1,
        points: points
            .iter()
            .enumerate()
            .map(|(j, p)| PointPlan {
                name: p.name.clone(),
                link: p.link,
                // unread: clearance_term takes its standing heights beside the plan
                stand: 0.0,
                stances: match j {
                    0 => vec![Stance::planted(t0, mid, at(&ends.0[0], p.link))],
                    1 => vec![Stance::planted(mid, t1, at(&ends.1[0], p.link))],
                    _ => vec![],
                },
            })
            .collect(),
    };
    let low = points
        .iter()
        .map(|p| up.dot(&at(&ends.0[0], p.link)))
        .fold(f64::INFINITY, f64::min);
    let floor = FloorPlane::new(&body.gravity, low).unwrap();
    let scale = GroundScale::of(&body, &ends.0[0]).unwrap();
    let stands = vec![low; points.len()];
    let mut grounded = Objective::on_layout(&body, layout.clone(), weights, &inputs)
        .unwrap()
        .with_prior(&vec![[1e-3, 1e-5]; n])
        .unwrap()
        .with_term(Box::new(BaseTerm::new(&body, scale, 1e7).unwrap()))
        .with_term(Box::new(stance_term(&body, &plan, &layout, 1e10).unwrap()))
        .with_term(Box::new(
            floor_term(&body, &plan, floor, &layout, 1e9).unwrap(),
        ))
        .with_term(Box::new(
            clearance_term(
                &body,
                &plan,
                &stands,
                floor,
                Clearance::of(&scale),
                &layout,
                1e9,
            )
            .unwrap(),
        ));
    let x = grounded.hermite_start();
    let forces = ContactForces::new(&body, &plan, scale, 0.8, &layout).unwrap();
    let f = forces.solve(&grounded, &x).unwrap();
    grounded.set_forces(f).unwrap();
    let mut g = vec![0.0; x.len()];
    let (mut st, mut sg) = (torque_only.scratch(), grounded.scratch());
    println!(
        "{}: {} coordinates, {} gap DOFs, {} unknowns, {nodes} nodes, {reps} repetitions (best)",
        path.file_name().unwrap().to_string_lossy(),
        n,
        dofs.len(),
        x.len()
    );
    let per_node = |s: f64| s / nodes as f64 * 1e6;
    let row = |part: &str, what: &str, base: Option<f64>, f: &mut dyn FnMut()| -> Option<f64> {
        if !wants(part) {
            return None;
        }
        let s = run(reps, f);
        match base {
            Some(b) => println!("{what:<44} {:>9.2} µs/node  {:>5.2}×", per_node(s), s / b),
            None => println!("{what:<44} {:>9.2} µs/node", per_node(s)),
        }
        Some(s)
    };
    let t = row(
        "torque",
        "eval + gradient, torque + prior (today)",
        None,
        &mut || {
            torque_only.eval(&mut st, &x, Some(&mut g)).unwrap();
        },
    );
    row(
        "grounded",
        "eval + gradient, + base/stance/floor/clearance",
        t,
        &mut || {
            grounded.eval(&mut sg, &x, Some(&mut g)).unwrap();
        },
    );
    row(
        "forces",
        "contact forces re-solved (cone per node)",
        t,
        &mut || {
            forces.solve(&grounded, &x).unwrap();
        },
    );
    let p = row(
        "gn-torque",
        "Gauss–Newton preconditioner, torque + prior",
        None,
        &mut || {
            torque_only.half_gauss_newton(&mut st, &x).unwrap();
        },
    );
    row(
        "gn-grounded",
        "Gauss–Newton preconditioner, grounded",
        p,
        &mut || {
            grounded.half_gauss_newton(&mut sg, &x).unwrap();
        },
    );
}
