//! Spacetime transition work–precision (Rose et al. 1996, Fig. 8 kind): every
//! joint of the 44-DOF human in one 0.6 s gap, for each combination of free
//! coefficients per DOF × quadrature samples × solver tolerance. Each solution's
//! torque energy is re-measured with one common fine quadrature so settings
//! compare on the same scale; the gap is relative to the best of the table.

use super::plot::{Figure, Series};
use crate::model::Model;
use crate::spacetime::objective::Inputs;
use crate::spacetime::{
    BodyDynamics, Continuity, EndState, GapDof, Objective, SolveOptions, SpError,
    TransitionSettings, solve_group,
};
use std::path::Path;

pub struct Row {
    pub coefficients: usize,
    pub samples: usize,
    pub grad_rtol: f64,
    pub n_vars: usize,
    pub iterations: u64,
    /// Σwτ² dt with the common fine quadrature.
    pub energy: f64,
    pub gap: f64,
    pub continuity: f64,
    pub ms: f64,
    pub hermite_energy: f64,
}

pub struct Outcome {
    pub dofs: usize,
    pub duration: f64,
    pub rows: Vec<Row>,
    pub figures: Vec<Figure>,
    pub default_ms: Option<f64>,
}

/// End states of every coordinate from a smooth synthetic motion: small root
/// sway, limb swings at distinct frequencies (the 44-DOF test's motion).
pub fn motion(i: usize, t: f64) -> [f64; 3] {
    let w = 2.0 + 0.37 * i as f64;
    let amp = if i < 6 { 0.05 } else { 0.4 };
    let ph = 0.9 * i as f64;
    let base = if i == 2 { 1.0 } else { 0.0 };
    [
        base + amp * (w * t + ph).sin(),
        amp * w * (w * t + ph).cos(),
        -amp * w * w * (w * t + ph).sin(),
    ]
}

fn inputs(t: f64, q: &mut [f64], v: &mut [f64], a: &mut [f64]) -> Result<(), SpError> {
    for i in 0..q.len() {
        let s = motion(i, t);
        q[i] = s[0];
        v[i] = s[1];
        a[i] = s[2];
    }
    Ok(())
}

fn gap(coord: usize, t0: f64, t1: f64) -> GapDof {
    let (s, e) = (motion(coord, t0), motion(coord, t1));
    let es = |x: [f64; 3]| EndState {
        q: x[0],
        v: x[1],
        a: x[2],
    };
    GapDof {
        coord,
        t0,
        t1,
        start: es(s),
        end: es(e),
    }
}

pub const DEFAULT_TOL: f64 = 1e-6;

pub fn run(urdf: &Path, smoke: bool, tick: &mut dyn FnMut()) -> Result<Outcome, String> {
    let model = Model::from_urdf_file(urdf).map_err(|e| format!("{}: {e}", urdf.display()))?;
    let n = model.nq();
    if n < 7 {
        return Err(format!(
            "{}: expected a human with a 6-DOF root, got {n} coordinates",
            urdf.display()
        ));
    }
    let body = BodyDynamics::new(&model);
    let (t0, t1) = (1.0, 1.6);
    let gaps: Vec<GapDof> = (6..n).map(|c| gap(c, t0, t1)).collect();
    let mut w = vec![1.0; n];
    w[..6].fill(0.0); // the root is unactuated
    let inputs: &Inputs = &inputs;
    let d = TransitionSettings::default();
    let (coefs, samples, tols): (Vec<usize>, Vec<usize>, Vec<f64>) = if smoke {
        (vec![4, d.coefficients], vec![d.samples], vec![DEFAULT_TOL])
    } else {
        (
            vec![4, 6, d.coefficients, 12],
            vec![10, d.samples, 40],
            vec![1e-3, DEFAULT_TOL],
        )
    };
    let fine_samples = if smoke { 40 } else { 200 };
    let mut rows = Vec::new();
    for &m in &coefs {
        for &k in &samples {
            for &tol in &tols {
                let settings = TransitionSettings {
                    coefficients: m,
                    samples: k,
                    continuity: Continuity::C1,
                };
                let started = std::time::Instant::now();
                let obj = Objective::new(&body, gaps.clone(), &settings, w.clone(), inputs)
                    .map_err(|e| e.to_string())?;
                let sol = solve_group(
                    &obj,
                    &SolveOptions {
                        grad_rtol: tol,
                        ..Default::default()
                    },
                )
                .map_err(|e| e.to_string())?;
                let ms = started.elapsed().as_secs_f64() * 1e3;
                let fine = Objective::new(
                    &body,
                    gaps.clone(),
                    &TransitionSettings {
                        samples: fine_samples,
                        ..settings.clone()
                    },
                    w.clone(),
                    inputs,
                )
                .map_err(|e| e.to_string())?;
                let mut s = fine.scratch();
                let energy = fine.eval(&mut s, &sol.x, None).map_err(|e| e.to_string())?;
                let hermite_energy = fine
                    .eval(&mut s, &fine.hermite_start(), None)
                    .map_err(|e| e.to_string())?;
                // Continuity: the worst jump of q, q̇ (scaled by the gap length) at both ends.
                let mut jump = 0.0f64;
                for (i, dof) in obj.dofs().iter().enumerate() {
                    let c = &obj.curves()[i];
                    for (t, want) in [(dof.t0, dof.start), (dof.t1, dof.end)] {
                        let got = c.eval(&sol.coefficients[i], t);
                        jump = jump
                            .max((got[0] - want.q).abs())
                            .max((got[1] - want.v).abs() * (t1 - t0));
                    }
                }
                rows.push(Row {
                    coefficients: m,
                    samples: k,
                    grad_rtol: tol,
                    n_vars: sol.report.n_vars,
                    iterations: sol.report.iterations,
                    energy,
                    gap: 0.0,
                    continuity: jump,
                    ms,
                    hermite_energy,
                });
                tick();
            }
        }
    }
    let best = rows.iter().map(|r| r.energy).fold(f64::INFINITY, f64::min);
    for r in &mut rows {
        r.gap = (r.energy - best) / best.abs().max(f64::MIN_POSITIVE);
    }
    let is_default = |r: &Row| {
        r.coefficients == d.coefficients && r.samples == d.samples && r.grad_rtol == DEFAULT_TOL
    };
    let default_ms = rows.iter().find(|r| is_default(r)).map(|r| r.ms);
    let series = |f: &dyn Fn(&Row) -> (f64, f64)| -> Vec<Series> {
        coefs
            .iter()
            .map(|&m| {
                let mut rs: Vec<&Row> = rows.iter().filter(|r| r.coefficients == m).collect();
                rs.sort_by(|a, b| a.ms.total_cmp(&b.ms));
                Series {
                    label: format!("{m} coefficients/DOF"),
                    points: rs.iter().map(|r| f(r)).collect(),
                    default_at: rs.iter().position(|r| is_default(r)),
                }
            })
            .collect()
    };
    let figures = vec![
        Figure {
            file: "spacetime_energy.svg".into(),
            title: format!(
                "{} DOFs, {:.1} s gap: torque-energy gap to the best",
                n - 6,
                t1 - t0
            ),
            x_label: "solve time (ms, this machine)".into(),
            y_label: "(E − E_best) / E_best".into(),
            series: series(&|r| (r.ms, r.gap)),
        },
        Figure {
            file: "spacetime_continuity.svg".into(),
            title: "Continuity at the gap ends".into(),
            x_label: "solve time (ms, this machine)".into(),
            y_label: "max(|Δq|, |Δq̇|·T) at the ends".into(),
            series: series(&|r| (r.ms, r.continuity)),
        },
    ];
    Ok(Outcome {
        dofs: n - 6,
        duration: t1 - t0,
        rows,
        figures,
        default_ms,
    })
}
