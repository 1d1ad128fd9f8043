//! Spacetime transition work–precision (Rose et al. 1996, Fig. 8 kind): every
//! joint of the 44-DOF human made from the project's own walk in one 0.6 s gap, for each combination of free
//! coefficients per DOF × quadrature samples × solver tolerance. Each solution's
//! torque energy is re-measured with one common fine quadrature so settings
//! compare on the same scale; the gap is relative to the best of the table.

use super::plot::{Figure, Series};
use crate::report::error::ReportError;
use crate::spacetime::{Continuity, SolveOptions, TransitionSettings, fig8, solve_group};

pub struct Row {
    pub coefficients: usize,
    pub samples: usize,
    /// The solver's stopping tolerance (relative energy progress over the last 25 iterations).
    pub tolerance: f64,
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

/// The solver's default stopping tolerance (`tolerance:`).
pub fn default_tolerance() -> f64 {
    SolveOptions::default().tolerance
}

/// The table on the project's own data: `human(walk)` (44 DOFs) with the
/// procedural walk fitted to it, every joint DOF left undefined over
/// [`fig8::EXAMPLE_GAP`] (the case `benches/spacetime.rs` measures too):
/// one [`solve_row`] per setting of [`settings_grid`], the energy gap to the
/// best of the table, and the [`figures`].
pub fn run(smoke: bool, tick: &mut dyn FnMut()) -> Result<Outcome, ReportError> {
    let (model, walk) = fig8::example_walk()?;
    let (t0, t1) = fig8::EXAMPLE_GAP;
    let case = fig8::case(&model, walk, t0, t1)?;
    let n_gap = case.gaps.len();
    let (coefs, samples, tols) = settings_grid(smoke);
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
                rows.push(solve_row(&case, &settings, tol, fine_samples)?);
                tick();
            }
        }
    }
    let best = rows.iter().map(|r| r.energy).fold(f64::INFINITY, f64::min);
    for r in &mut rows {
        r.gap = (r.energy - best) / best.abs().max(f64::MIN_POSITIVE);
    }
    let default_ms = rows.iter().find(|r| is_default(r)).map(|r| r.ms);
    Ok(Outcome {
        dofs: n_gap,
        duration: t1 - t0,
        figures: figures(&rows, &coefs, n_gap, t1 - t0),
        rows,
        default_ms,
    })
}

/// Whether a row is the library's default setting.
fn is_default(r: &Row) -> bool {
    let d = TransitionSettings::default();
    r.coefficients == d.coefficients && r.samples == d.samples && r.tolerance == default_tolerance()
}

/// The settings the table runs: coefficients per DOF, quadrature samples and
/// tolerances (the grid, plus the defaults wherever they sit; the
/// defaults and one more in smoke mode), sorted, without repeats.
fn settings_grid(smoke: bool) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
    let d = TransitionSettings::default();
    let (mut coefs, mut samples, mut tols): (Vec<usize>, Vec<usize>, Vec<f64>) = if smoke {
        (
            vec![3, d.coefficients],
            vec![d.samples],
            vec![default_tolerance()],
        )
    } else {
        (
            vec![3, 5, 8, 12, 20, d.coefficients],
            vec![10, 20, 40, 80, d.samples],
            vec![1e-2, 1e-3, 1e-4, default_tolerance()],
        )
    };
    coefs.sort_unstable();
    coefs.dedup();
    samples.sort_unstable();
    samples.dedup();
    tols.sort_by(|a, b| b.total_cmp(a));
    tols.dedup();
    (coefs, samples, tols)
}

/// One setting solved and re-measured: its energy on the common fine
/// quadrature (`fine_samples`), Hermite's there, and the worst jump of q and
/// q̇ (scaled by the gap length) at both ends.
fn solve_row(
    case: &fig8::Case<'_>,
    settings: &TransitionSettings,
    tol: f64,
    fine_samples: usize,
) -> Result<Row, ReportError> {
    let (t0, t1) = fig8::EXAMPLE_GAP;
    let started = std::time::Instant::now();
    let obj = case.objective(settings)?;
    let sol = solve_group(
        &obj,
        &SolveOptions {
            tolerance: tol,
            ..Default::default()
        },
    )?;
    let ms = started.elapsed().as_secs_f64() * 1e3;
    let fine = case.objective(&TransitionSettings {
        samples: fine_samples,
        ..settings.clone()
    })?;
    let mut s = fine.scratch();
    let energy = fine.eval(&mut s, &sol.x, None)?;
    let hermite_energy = fine.eval(&mut s, &fine.hermite_start(), None)?;
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
    Ok(Row {
        coefficients: settings.coefficients,
        samples: settings.samples,
        tolerance: tol,
        n_vars: sol.report.n_vars,
        iterations: sol.report.iterations,
        energy,
        gap: 0.0,
        continuity: jump,
        ms,
        hermite_energy,
    })
}

/// The energy gap and the continuity against solve time, one curve per
/// coefficient count, the default setting ringed.
fn figures(rows: &[Row], coefs: &[usize], n_gap: usize, duration: f64) -> Vec<Figure> {
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
    vec![
        Figure {
            file: "spacetime_energy.svg".into(),
            title: format!("{n_gap} DOFs, {duration:.1} s gap: torque-energy gap to the best"),
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
    ]
}
