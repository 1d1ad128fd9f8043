//! Spacetime transitions on the 44-DOF human of `data/reference/human44.urdf`
//! (z up, 6 root coordinates then 38 joints): the analytic gradient against
//! central differences, end continuity, SP below the Hermite baseline, and
//! no aliasing of the torque quadrature.

use crate::common;

use mx::model::Model;
use mx::spacetime::objective::Inputs;
use mx::spacetime::{
    BodyDynamics, Continuity, EndState, GapDof, Objective, SolveOptions, TransitionSettings,
    solve_group,
};

fn human44() -> Option<Model> {
    let dir = common::shared_dir()?;
    Some(
        Model::from_urdf_file(dir.join("data/reference/human44.urdf")).expect("human44.urdf loads"),
    )
}

/// A smooth synthetic motion for every coordinate: small root sway, limb swings.
fn motion(i: usize, t: f64) -> [f64; 3] {
    let w = 2.0 + 0.37 * i as f64;
    let amp = if i < 6 { 0.05 } else { 0.4 };
    let ph = 0.9 * i as f64;
    let base = if i == 2 { 1.0 } else { 0.0 }; // pelvis height for root_tz
    [
        base + amp * (w * t + ph).sin(),
        amp * w * (w * t + ph).cos(),
        -amp * w * w * (w * t + ph).sin(),
    ]
}

fn inputs(
    t: f64,
    q: &mut [f64],
    v: &mut [f64],
    a: &mut [f64],
) -> Result<(), mx::spacetime::SpError> {
    for i in 0..q.len() {
        let s = motion(i, t);
        q[i] = s[0];
        v[i] = s[1];
        a[i] = s[2];
    }
    Ok(())
}

fn gap(coord: usize, t0: f64, t1: f64) -> GapDof {
    let s = motion(coord, t0);
    let e = motion(coord, t1);
    GapDof {
        coord,
        t0,
        t1,
        start: EndState {
            q: s[0],
            v: s[1],
            a: s[2],
        },
        end: EndState {
            q: e[0],
            v: e[1],
            a: e[2],
        },
    }
}

#[test]
fn gradient_matches_central_differences_on_44_dofs() {
    let Some(model) = human44() else { return };
    assert_eq!(model.nq(), 44);
    let body = BodyDynamics::new(&model);
    let gaps: Vec<GapDof> = (0..44).map(|c| gap(c, 0.3, 0.9)).collect();
    let settings = TransitionSettings {
        coefficients: 4,
        samples: 10,
        continuity: Continuity::C1,
    };
    let inputs: &Inputs = &inputs;
    let obj = Objective::new(&body, gaps, &settings, vec![1.0; 44], inputs).unwrap();
    let mut s = obj.scratch();
    // away from the Hermite start so every term of the gradient is exercised
    let x: Vec<f64> = obj
        .hermite_start()
        .iter()
        .enumerate()
        .map(|(i, v)| v + 0.2 * (1.3 * i as f64).sin())
        .collect();
    let mut g = vec![0.0; x.len()];
    obj.eval(&mut s, &x, Some(&mut g)).unwrap();
    let gmax = g.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut worst = 0.0f64;
    for i in 0..x.len() {
        let h = 1e-6 * (1.0 + x[i].abs());
        let (mut xp, mut xm) = (x.clone(), x.clone());
        xp[i] += h;
        xm[i] -= h;
        let fd = (obj.eval(&mut s, &xp, None).unwrap() - obj.eval(&mut s, &xm, None).unwrap())
            / (2.0 * h);
        worst = worst.max((fd - g[i]).abs() / gmax);
    }
    println!(
        "44-DOF gradient: {} unknowns, max |fd − g| / max|g| = {worst:.2e}",
        x.len()
    );
    assert!(worst <= 1e-6, "relative gradient error {worst}");
}

#[test]
fn transition_of_all_joints_beats_hermite_and_joins_exactly() {
    let Some(model) = human44() else { return };
    let body = BodyDynamics::new(&model);
    // all DOFs but the root (Fig. 8 kind), a 0.6 s gap; root torques are unactuated: weight 0
    let gaps: Vec<GapDof> = (6..44).map(|c| gap(c, 1.0, 1.6)).collect();
    let mut w = vec![1.0; 44];
    w[..6].fill(0.0);
    let settings = TransitionSettings::default();
    let inputs: &Inputs = &inputs;
    let obj = Objective::new(&body, gaps.clone(), &settings, w.clone(), inputs).unwrap();
    let sol = solve_group(&obj, &SolveOptions::default()).unwrap();
    let r = &sol.report;
    // No aliasing: the solution's energy under a 200-point rule is what the
    // solver's own quadrature said (a coarse rule lets the optimiser hide
    // torque between nodes; see MIN_POINTS_PER_PIECE).
    let fine_settings = TransitionSettings {
        samples: 200,
        ..settings.clone()
    };
    let fine = Objective::new(&body, gaps, &fine_settings, w, inputs).unwrap();
    let e_fine = fine.eval(&mut fine.scratch(), &sol.x, None).unwrap();
    println!(
        "energy by the solver's {} nodes {:.4}, by 200 points {e_fine:.4}",
        obj.n_nodes(),
        r.energy
    );
    assert!(
        (e_fine - r.energy).abs() <= 0.01 * r.energy,
        "aliasing: {} by the solver's rule, {e_fine} by 200 points",
        r.energy
    );
    println!(
        "human44 0.6 s gap, 38 DOFs: {} {} vars, {} iterations, {} evaluations, Hermite {:.4} → SP {:.4}, |g| {:.2e}, {} in {:.1} ms",
        r.method,
        r.n_vars,
        r.iterations,
        r.evaluations,
        r.initial_energy,
        r.energy,
        r.grad_norm,
        r.stop,
        r.seconds * 1e3
    );
    assert!(r.energy < r.initial_energy);
    let (mut jq, mut jv) = (0.0f64, 0.0f64);
    for (d, dof) in obj.dofs().iter().enumerate() {
        let c = &obj.curves()[d];
        for (t, want) in [(dof.t0, dof.start), (dof.t1, dof.end)] {
            let got = c.eval(&sol.coefficients[d], t);
            jq = jq.max((got[0] - want.q).abs());
            jv = jv.max((got[1] - want.v).abs());
        }
    }
    println!("end jumps: position {jq:.1e}, velocity {jv:.1e}");
    assert!(jq <= 1e-9 && jv <= 1e-6);
}
