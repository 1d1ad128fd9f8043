//! Scenes, effects and integrators.

use mx::cancel::CancelToken;
use mx::dynamics::{
    DynamicsError, ExternalForce, Integrator, LimitPenalty, Scene, SceneWorkspace, Spring, State,
    simulate,
};
use mx::lie::Se3;
use mx::model::joints::{Prismatic, Revolute};
use mx::model::{Inertia, Model};
use nalgebra::{Matrix3, Vector3};
use std::sync::Arc;

const G: Vector3<f64> = Vector3::new(0.0, -9.80665, 0.0);

/// A planar chain of `n` rods about z, hanging along −y.
fn pendulum(n: usize) -> Arc<Model> {
    let mut m = Model::new("pendulum");
    for i in 0..n {
        let inertia = Inertia::from_com(
            1.0,
            Vector3::new(0.0, -0.25, 0.0),
            Matrix3::from_diagonal(&Vector3::new(0.02, 0.001, 0.02)),
        )
        .unwrap();
        let off = Se3::from_translation(Vector3::new(0.0, if i == 0 { 0.0 } else { -0.5 }, 0.0));
        m.add_link(
            &format!("rod{i}"),
            if i == 0 { None } else { Some(i - 1) },
            &format!("j{i}"),
            Arc::new(Revolute::new(Vector3::z()).unwrap()),
            off,
            inertia,
        )
        .unwrap();
    }
    Arc::new(m)
}

/// A 2 kg point mass sliding along x.
fn slider() -> Arc<Model> {
    let mut m = Model::new("slider");
    m.add_link(
        "mass",
        None,
        "x",
        Arc::new(Prismatic::new(Vector3::x()).unwrap()),
        Se3::identity(),
        Inertia::point(2.0, Vector3::zeros()).unwrap(),
    )
    .unwrap();
    Arc::new(m)
}

fn run(
    scene: &Scene,
    dur: f64,
    dt: f64,
    method: Integrator,
    q0: &[f64],
) -> Result<mx::dynamics::Trajectory, DynamicsError> {
    let init = State {
        q: q0.to_vec(),
        v: vec![0.0; q0.len()],
    };
    simulate(
        scene,
        dur,
        dt,
        method,
        &init,
        &CancelToken::new(),
        &mut |_| {},
    )
}

#[test]
fn rk4_at_1ms_conserves_energy_over_10s() {
    let scene = Scene::new(pendulum(3)).with_gravity(G).unwrap();
    let tr = run(&scene, 10.0, 1e-3, Integrator::Rk4, &[1.2, -0.5, 0.8]).unwrap();
    let mut sw = SceneWorkspace::new(&scene);
    let e: Vec<f64> =
        tr.q.iter()
            .zip(&tr.v)
            .map(|(q, v)| scene.energy(&mut sw, q, v).unwrap())
            .collect();
    let kmax =
        tr.q.iter()
            .zip(&tr.v)
            .map(|(q, v)| {
                let mut ws = mx::dynamics::Workspace::new(&scene.model);
                mx::dynamics::kinetic_energy(&scene.model, &mut ws, q, v).unwrap()
            })
            .fold(0.0, f64::max);
    let drift = e.iter().map(|x| (x - e[0]).abs()).fold(0.0, f64::max) / e[0].abs().max(kmax);
    eprintln!(
        "RK4 1 ms, 10 s, triple pendulum: relative energy drift {drift:.2e} (KE max {kmax:.2} J)"
    );
    assert!(kmax > 1.0, "the pendulum must actually move");
    assert!(drift < 1e-6);
}

#[test]
fn spring_mass_matches_the_analytic_solution() {
    // m = 2, k = 50, spring from the world origin, rest length 0, start at x = 0.1:
    // x(t) = 0.1 cos(5 t). Zero-length rest is fine away from x = 0 where the
    // direction is defined; use an offset anchor so the length never vanishes.
    let spring = Spring {
        link_a: None,
        point_a: Vector3::new(-1.0, 0.0, 0.0),
        link_b: Some(0),
        point_b: Vector3::zeros(),
        stiffness: 50.0,
        damping: 0.0,
        rest_length: 1.0,
    };
    let scene = Scene::new(slider()).with_spring(spring).unwrap();
    for (method, tol) in [
        (Integrator::Rk4, 1e-8),
        (
            Integrator::DormandPrince {
                rtol: 1e-10,
                atol: 1e-12,
            },
            1e-8,
        ),
    ] {
        let tr = run(&scene, 2.0, 1e-3, method, &[0.1]).unwrap();
        let err =
            tr.t.iter()
                .zip(&tr.q)
                .map(|(t, q)| (q[0] - 0.1 * (5.0 * t).cos()).abs())
                .fold(0.0, f64::max);
        eprintln!(
            "{method:?}: spring-mass max error {err:.2e}, {} evaluations",
            tr.evaluations
        );
        assert!(err < tol, "{method:?}: {err:e}");
    }
}

#[test]
fn damping_dissipates_and_forces_accelerate() {
    let scene = Scene::new(pendulum(2))
        .with_gravity(G)
        .unwrap()
        .with_damping(&[0.5])
        .unwrap();
    let tr = run(&scene, 3.0, 1e-3, Integrator::Rk4, &[1.0, 0.5]).unwrap();
    let mut sw = SceneWorkspace::new(&scene);
    let e: Vec<f64> =
        tr.q.iter()
            .zip(&tr.v)
            .map(|(q, v)| scene.energy(&mut sw, q, v).unwrap())
            .collect();
    assert!(
        e.windows(2).all(|w| w[1] <= w[0] + 1e-9),
        "damped energy must not grow"
    );
    assert!(e[e.len() - 1] < e[0] - 0.1);
    // Constant force on the slider: x = ½ (F/m) t².
    let f = ExternalForce {
        link: 0,
        point: Vector3::new(0.0, 0.3, 0.0),
        force: Vector3::new(4.0, 0.0, 0.0),
    };
    let scene = Scene::new(slider()).with_force(f).unwrap();
    let tr = run(&scene, 1.0, 1e-2, Integrator::Rk4, &[0.0]).unwrap();
    let x = tr.q.last().unwrap()[0];
    assert!((x - 1.0).abs() < 1e-12, "x(1) = {x}");
}

#[test]
fn limit_penalty_holds_a_joint_near_its_limit() {
    let mut m = Model::new("limited");
    m.add_link(
        "rod",
        None,
        "j",
        Arc::new(
            Revolute::new(Vector3::z())
                .unwrap()
                .with_limit(mx::model::Limit {
                    lower: -0.3,
                    upper: 0.3,
                }),
        ),
        Se3::identity(),
        Inertia::from_com(1.0, Vector3::new(0.5, 0.0, 0.0), Matrix3::identity() * 0.01).unwrap(),
    )
    .unwrap();
    let m = Arc::new(m);
    let free = Scene::new(m.clone()).with_gravity(G).unwrap();
    let held = free
        .clone()
        .with_limits(LimitPenalty {
            stiffness: 2000.0,
            damping: 20.0,
        })
        .unwrap();
    let qf = run(&free, 1.0, 1e-3, Integrator::Rk4, &[0.0]).unwrap();
    let qh = run(&held, 1.0, 1e-3, Integrator::Rk4, &[0.0]).unwrap();
    let minf = qf.q.iter().map(|q| q[0]).fold(f64::INFINITY, f64::min);
    let minh = qh.q.iter().map(|q| q[0]).fold(f64::INFINITY, f64::min);
    eprintln!("free min {minf:.3}, limited min {minh:.3}");
    assert!(minf < -1.0);
    assert!(minh > -0.36 && minh < -0.3);
}

#[test]
fn explicit_euler_at_large_steps_is_finite_or_a_clear_error() {
    let scene = Scene::new(pendulum(3)).with_gravity(G).unwrap();
    for dt in [0.01, 0.1, 0.3] {
        match run(&scene, 20.0, dt, Integrator::Euler, &[1.2, -0.5, 0.8]) {
            Ok(tr) => assert!(tr.q.iter().flatten().all(|x| x.is_finite())),
            Err(DynamicsError::Singular(msg)) => {
                eprintln!("dt = {dt}: {msg}");
                assert!(msg.contains("smaller dt"), "{msg}");
            }
            Err(e) => panic!("dt = {dt}: unexpected error {e}"),
        }
    }
    // Semi-implicit Euler stays bounded at the same large step.
    let tr = run(
        &scene,
        20.0,
        0.01,
        Integrator::SemiImplicitEuler,
        &[1.2, -0.5, 0.8],
    )
    .unwrap();
    assert!(tr.v.iter().flatten().all(|x| x.abs() < 100.0));
}

#[test]
fn cancel_and_bad_arguments() {
    let scene = Scene::new(pendulum(2)).with_gravity(G).unwrap();
    let tok = CancelToken::new();
    tok.cancel();
    let init = State {
        q: vec![0.1, 0.0],
        v: vec![0.0; 2],
    };
    let r = simulate(&scene, 1.0, 1e-3, Integrator::Rk4, &init, &tok, &mut |_| {});
    assert_eq!(r.unwrap_err(), DynamicsError::Cancelled);
    let tok = CancelToken::new();
    assert!(simulate(&scene, 1.0, 0.0, Integrator::Rk4, &init, &tok, &mut |_| {}).is_err());
    assert!(simulate(&scene, -1.0, 0.1, Integrator::Rk4, &init, &tok, &mut |_| {}).is_err());
    let bad = State {
        q: vec![0.1],
        v: vec![0.0],
    };
    let e = simulate(&scene, 1.0, 0.1, Integrator::Rk4, &bad, &tok, &mut |_| {}).unwrap_err();
    assert!(e.to_string().contains("initial q"), "{e}");
    assert!(
        Scene::new(pendulum(2))
            .with_damping(&[1.0, 2.0, 3.0])
            .is_err()
    );
    assert!(Integrator::from_name("leapfrog", None).is_err());
    // Zero duration: just the initial state.
    let tr = simulate(&scene, 0.0, 0.1, Integrator::Rk4, &init, &tok, &mut |_| {}).unwrap();
    assert_eq!(tr.t, vec![0.0]);
}
