//! The report's sections, in the order `generate` writes them: each one runs
//! its measurement (the files beside this one) and writes its prose, figures
//! and tables. A section that cannot run is listed as pending.

use super::doc::Doc;
use super::hard_cases::HardCase;
use super::{Options, cyclify, fit, hard_cases, ik, integrators, mocap, perf, spacetime};
use crate::report::error::ReportError;
use indicatif::ProgressBar;
use std::fmt::Write as _;
use std::path::PathBuf;

/// What the sections read and leave for each other while the report is written.
pub(super) struct Run<'a> {
    pub opts: &'a Options,
    pub smoke: bool,
    pub pb: &'a ProgressBar,
    /// The project's own walk (`examples/data/walk.bvh`).
    pub clip: PathBuf,
    /// ms of one default transition, from the spacetime section, for the performance one.
    pub st_default_ms: Option<f64>,
    /// The hard-case registry as it ran, for the summary.
    pub cases: Vec<HardCase>,
}

/// One section: its heading, its progress-bar message and steps (smoke, full), and its writer.
pub(super) struct Section {
    pub heading: &'static str,
    pub message: &'static str,
    pub steps: [u64; 2],
    pub write: fn(&mut Doc, &mut Run<'_>),
}

pub(super) const SECTIONS: &[Section] = &[
    Section {
        heading: "Spacetime transitions",
        message: "spacetime transitions",
        steps: [2, 40],
        write: spacetime_section,
    },
    Section {
        heading: "In-betweening against captured motion",
        message: "in-betweening",
        steps: [10, 2000],
        write: inbetween_section,
    },
    Section {
        heading: "Integrators",
        message: "integrators",
        steps: [8, 20],
        write: integrators_section,
    },
    Section {
        heading: "Spline-joint fitting",
        message: "spline-joint fitting",
        steps: [4, 15],
        write: fit_section,
    },
    Section {
        heading: "Mocap: B-spline fits, cyclification and sampling",
        message: "mocap sampling",
        steps: [4, 15],
        write: mocap_section,
    },
    Section {
        heading: "Cyclification",
        message: "cyclify",
        steps: [2, 6],
        write: cyclify_section,
    },
    Section {
        heading: "Inverse kinematics",
        message: "ik",
        steps: [2, 6],
        write: ik_section,
    },
    Section {
        heading: "Hard cases",
        message: "hard cases",
        steps: [1, 1],
        write: hard_cases_section,
    },
    Section {
        heading: "Performance (this machine)",
        message: "dynamics timings",
        steps: [2, 2],
        write: performance_section,
    },
];

fn spacetime_section(d: &mut Doc, run: &mut Run<'_>) {
    match spacetime::run(run.smoke, &mut || run.pb.inc(1)) {
        Ok(o) => {
            run.st_default_ms = o.default_ms;
            let def = crate::spacetime::TransitionSettings::default();
            let _ = writeln!(
                d.md,
                "The project's own walk (`examples/data/walk.bvh`, made by `mocap::synth`) is fitted to the \
                     44-DOF anatomical model `human(walk)`; all {} joint DOFs are left undefined for {:.1} s and \
                     re-made as Rose-et-al. transitions minimising Σ τ² (the root is an input), the paper's Fig. 8 \
                     case (`spacetime::fig8`, the same case `cargo bench --bench spacetime` measures). The knobs are \
                     the free B-spline coefficients per DOF (`coefficients:`), the Gauss points of the torque \
                     quadrature (`samples:`, at least 6 per B-spline piece) and the solver's tolerance (`tolerance:`: stop when the last 25 iterations lowered the energy by less than this fraction). Each solution's energy is \
                     re-measured with one fine quadrature so the settings compare on the same scale (a coarse \
                     quadrature can hide torque between its nodes); the gap is to the best of the table. The \
                     default ({} coefficients, {} samples, tolerance {:.0e}) is ringed. Fewer coefficients or \
                     samples are faster but leave torque energy on the table (a stiffer-looking motion); the extra \
                     energy that 12 or 20 coefficients save comes mostly from hands and feet oscillating, which \
                     Rose avoids by using few coefficients; the loose tolerance stops early. Continuity at the gap ends is exact by construction (end coefficients \
                     are fixed), which the second figure confirms at round-off.",
                o.dofs,
                o.duration,
                def.coefficients,
                def.samples,
                spacetime::default_tolerance()
            );
            for f in &o.figures {
                d.figure(f);
            }
            d.header(&[
                "coefficients/DOF",
                "samples",
                "tolerance",
                "unknowns",
                "iterations",
                "energy (fine quadrature)",
                "gap to best",
                "end jump",
                "Hermite energy",
                "ms",
            ]);
            for r in &o.rows {
                let cells = [
                    r.coefficients.to_string(),
                    r.samples.to_string(),
                    format!("{:.0e}", r.tolerance),
                    r.n_vars.to_string(),
                    r.iterations.to_string(),
                    d.n(r.energy),
                    d.n(r.gap),
                    d.n(r.continuity),
                    d.n(r.hermite_energy),
                    d.n(r.ms),
                ];
                d.row(&cells);
            }
        }
        Err(e) => d.pending("spacetime work–precision", &e.to_string()),
    }
}

fn inbetween_section(d: &mut Doc, run: &mut Run<'_>) {
    let pb = run.pb;
    super::inbetween_section::section(d, run.opts.shared.as_deref(), run.smoke, &|| pb.inc(1));
}

fn integrators_section(d: &mut Doc, run: &mut Run<'_>) {
    match integrators::run(run.opts.shared.as_deref(), run.smoke, &mut || run.pb.inc(1)) {
        Ok(o) => {
            let _ = writeln!(
                d.md,
                "The knob is the integrator and its step `dt` (fixed-step methods) or tolerance (adaptive \
                 Dormand–Prince 5(4), where `dt` is only the output interval). Error reference: {}. \
                 Energy drift is the worst relative change of total energy of a frictionless double pendulum \
                 over five times the span. The default, `dopri5` at tolerance 1e-8, is ringed. Explicit Euler \
                 is the cheapest per step but gains energy and needs tiny steps; semi-implicit Euler keeps the \
                 energy bounded at first order; RK4 is accurate at moderate steps but has no error control; \
                 loosening the adaptive tolerance buys speed with error roughly proportional to it.",
                o.reference
            );
            for f in &o.figures {
                d.figure(f);
            }
            d.header(&[
                "integrator",
                "setting",
                "max abs Δq (rad)",
                "ms",
                "energy drift",
                "ms (drift run)",
            ]);
            for r in &o.rows {
                let err = if r.error.is_finite() {
                    d.n(r.error)
                } else {
                    "failed (clear error)".into()
                };
                let dr = if r.energy_drift.is_finite() {
                    d.n(r.energy_drift)
                } else {
                    "failed (clear error)".into()
                };
                let cells = [
                    r.method.to_string(),
                    r.setting.clone(),
                    err,
                    d.n(r.ms),
                    dr,
                    d.n(r.drift_ms),
                ];
                d.row(&cells);
            }
        }
        Err(e) => d.pending("integrator work–precision", &e.to_string()),
    }
}

fn fit_section(d: &mut Doc, run: &mut Run<'_>) {
    match run.opts.shared.as_ref() {
        Some(sh) => match fit::run(sh, run.smoke, &mut || run.pb.inc(1)) {
            Ok(o) => {
                let _ = writeln!(
                    d.md,
                    "A spline curve joint (cumulative B-spline on SE(3)) is fitted to OpenSim's gait2392 knee samples. \
                     The knob is the number of control frames; the default ({}) is ringed. More frames follow the \
                     samples more closely at a higher fit (and evaluation) cost; too few leave millimetres of error in \
                     the tibia's path.",
                    fit::DEFAULT_FRAMES
                );
                for f in &o.figures[..1] {
                    d.figure(f);
                }
                d.header(&["frames", "max mm", "rms mm", "max °", "rms °", "fit ms"]);
                for r in &o.frames {
                    let cells = [
                        r.frames.to_string(),
                        d.n(r.max_mm),
                        d.n(r.rms_mm),
                        d.n(r.max_deg),
                        d.n(r.rms_deg),
                        d.n(r.ms),
                    ];
                    d.row(&cells);
                }
                let _ = writeln!(
                    d.md,
                    "\nSmoothing: the samples get 1 mm and 0.5° of Gaussian noise per axis and {} frames are fitted with \
                     smoothing weight w on ∫‖∇S‖². The default is w = 0 (ringed: plain least squares). Raising w \
                     lowers the wiggle energy ∫‖∇S‖² and the error to the clean samples until it starts flattening \
                     the true shape.",
                    o.noisy_frames
                );
                for f in &o.figures[1..] {
                    d.figure(f);
                }
                d.header(&["w", "∫‖∇S‖² dq", "max mm", "rms mm", "max °", "fit ms"]);
                for r in &o.smoothing {
                    let cells = [
                        format!("{:.0e}", r.weight),
                        d.n(r.energy),
                        d.n(r.max_mm),
                        d.n(r.rms_mm),
                        d.n(r.max_deg),
                        d.n(r.ms),
                    ];
                    d.row(&cells);
                }
            }
            Err(e) => d.pending("spline-joint fitting", &e.to_string()),
        },
        None => d.pending(
            "spline-joint fitting",
            "needs `$MX_SHARED/data/opensim/knee_r_gait2392_samples.json`",
        ),
    }
}

fn mocap_section(d: &mut Doc, run: &mut Run<'_>) {
    match mocap::run(&run.clip, run.smoke, &mut || run.pb.inc(1)) {
        Ok(o) => {
            let _ = writeln!(
                d.md,
                "The project's own clip `examples/data/walk.bvh` ({} rotation channels, {} frames, {:.2} s at {:.0} Hz). \
                 First knob: B-spline coefficients per second of a cubic least-squares fit to every frame, clamped or \
                 periodic (the periodic fit is the cyclic fit used for cyclification: the clip becomes one closed C² \
                 cycle). There is no library default for this knob; fewer coefficients smooth away fast detail. \
                 Second knob: the rate at which the clip's curve is resampled into a sampled curve, compared with the \
                 original on a 240 Hz grid; the clip's own {:.0} Hz is ringed. Resampling below the capture rate \
                 loses the fastest joint motion.",
                o.channels, o.frames, o.duration, o.frame_rate, o.frame_rate
            );
            for f in &o.figures {
                d.figure(f);
            }
            d.header(&[
                "method",
                "per second",
                "coefficients / samples",
                "max °",
                "rms °",
                "ms",
            ]);
            for r in &o.rows {
                let cells = [
                    r.method.to_string(),
                    d.n(r.rate),
                    r.count.to_string(),
                    d.n(r.max_deg),
                    d.n(r.rms_deg),
                    d.n(r.ms),
                ];
                d.row(&cells);
            }
        }
        Err(e) => d.pending("mocap sampling", &e.to_string()),
    }
}

fn cyclify_section(d: &mut Doc, run: &mut Run<'_>) {
    match cyclify::run(&run.clip, run.smoke, &mut || run.pb.inc(1)) {
        Ok(o) => {
            let _ = writeln!(
                d.md,
                "`cyclify(walk, {}s, {}s)` on `examples/data/walk.bvh` (Rose §3.3): the best pair of times in the two \
                 search windows was [{:.4}, {:.4}] s; the remaining jump is spread linearly and a cubic B-spline is \
                 fitted by least squares with the three cyclic constraints, so the loop is C² by construction. The \
                 knob is the fit's knot spacing (`knot_spacing:`, default 1/30 s, ringed): wider spacing smooths the \
                 stride (larger departure from the clip) and is cheaper; the seam closes to round-off at every \
                 spacing (the constraint is exact), which the seam columns show for two loops.",
                cyclify::MARKS.0,
                cyclify::MARKS.1,
                o.cycle.0,
                o.cycle.1
            );
            for f in &o.figures {
                d.figure(f);
            }
            d.header(&[
                "knot spacing (s)",
                "coefficients",
                "max °",
                "rms °",
                "seam q (rel)",
                "seam q̇",
                "seam q̈",
                "ms",
            ]);
            for r in &o.rows {
                let cells = [
                    d.n(r.knot_spacing),
                    r.coefficients.to_string(),
                    d.n(r.max_deg),
                    d.n(r.rms_deg),
                    d.n(r.seam[0]),
                    d.n(r.seam[1]),
                    d.n(r.seam[2]),
                    d.n(r.ms),
                ];
                d.row(&cells);
            }
        }
        Err(e) => d.pending("cyclify", &e.to_string()),
    }
}

fn ik_section(d: &mut Doc, run: &mut Run<'_>) {
    match ik::run(run.smoke, &mut || run.pb.inc(1)) {
        Ok(o) => {
            let _ = writeln!(
                d.md,
                "`ik(body, walk, {{foot_L: …, foot_R: …}})` on the project's human(walk) ({} coordinates, all free), \
                 both feet put where the walk has them 0.3 s later, {} frames at 60 Hz: Levenberg–Marquardt with \
                 adaptive damping, warm-started from the previous frame. The knob is `tolerance:` (default 1e-6 m); \
                 convergence is quadratic once close, so each hundredfold tighter tolerance costs about \
                 one more iteration per frame.",
                o.coordinates, o.frames
            );
            d.header(&[
                "tolerance (m)",
                "largest residual (m)",
                "iterations mean",
                "iterations max",
                "µs per frame",
            ]);
            for r in &o.rows {
                let cells = [
                    d.n(r.tolerance),
                    d.n(r.max_residual),
                    d.n(r.mean_iterations),
                    r.max_iterations.to_string(),
                    d.n(r.us_per_frame),
                ];
                d.row(&cells);
            }
        }
        Err(e) => d.pending("ik", &e.to_string()),
    }
}

fn hard_cases_section(d: &mut Doc, run: &mut Run<'_>) {
    run.cases = hard_cases::all();
    run.pb.inc(1);
    let _ = writeln!(
        d.md,
        "Every numerically delicate case of the suite, from `mx::report::hard_cases::all()` — the registry \
         `tests/it/hard_cases.rs` asserts, so this table and the tests cannot disagree. A case expecting a clear \
         error scores 0 when the error arrives with the expected words.\n"
    );
    d.header(&[
        "case",
        "module",
        "what the engine returns",
        "worst error",
        "bound",
        "passed",
    ]);
    for c in &run.cases {
        let cells = [
            c.name.to_string(),
            c.area.to_string(),
            c.returned.clone(),
            d.n(c.worst_error),
            d.n(c.bound),
            if c.passed {
                "yes".into()
            } else {
                "**NO**".into()
            },
        ];
        d.row(&cells);
    }
}

fn performance_section(d: &mut Doc, run: &mut Run<'_>) {
    let n_states = if run.smoke { 200 } else { 2000 };
    match run.opts.shared.as_ref() {
        Some(sh) => {
            let pin_available = perf::pinocchio_exe().exists();
            let _ = writeln!(
                d.md,
                "Median µs per call over {n_states} random states. {}\n",
                if pin_available {
                    format!(
                        "Pinocchio's timer (`{}`) ran on the same URDF in the same session; ratio = mx / Pinocchio.",
                        perf::pinocchio_exe().display()
                    )
                } else {
                    "Pinocchio's timer was not found: build it with `$MX_SHARED/tools/pinocchio/build.sh /tmp/pinocchio-bench` (or set `PINOCCHIO_BENCH`) and rerun for the ratios.".into()
                }
            );
            for (name, file) in [("human44", "human44.urdf"), ("ur5", "ur5_robot.urdf")] {
                let urdf = sh.join("data/reference").join(file);
                let r = crate::model::Model::from_urdf_file(&urdf)
                    .map_err(ReportError::from)
                    .and_then(|m| perf::per_call(&m, n_states).map(|t| (m.nq(), t)));
                run.pb.inc(1);
                match r {
                    Ok((nq, t)) => {
                        let pin = if pin_available {
                            perf::pinocchio(&urdf)
                        } else {
                            None
                        };
                        let _ = writeln!(d.md, "**{name}** (nq = {nq})\n");
                        d.header(&["algorithm", "mx µs", "Pinocchio µs", "ratio"]);
                        for (i, alg) in ["rnea", "aba", "crba", "rnea_derivatives"]
                            .iter()
                            .enumerate()
                        {
                            let (p, ratio) = match pin {
                                Some(p) => (d.n(p[i]), d.n(t[i] / p[i])),
                                None => ("not run".into(), "—".into()),
                            };
                            let cells = [alg.to_string(), d.n(t[i]), p, ratio];
                            d.row(&cells);
                        }
                        let adj = d.n(t[4]);
                        let rel = d.n(t[4] / t[0]);
                        let _ = writeln!(
                            d.md,
                            "| adjoint Σwτ² gradient | {adj} | — | {rel}× one RNEA |\n"
                        );
                    }
                    Err(e) => d.pending(&format!("dynamics timings on {file}"), &e.to_string()),
                }
            }
        }
        None => d.pending(
            "dynamics timings",
            "needs `$MX_SHARED/data/reference/*.urdf`",
        ),
    }
    match run.st_default_ms {
        Some(ms) => {
            let v = d.n(ms);
            let _ = writeln!(
                d.md,
                "Spacetime: one transition of every joint DOF of the 44-DOF human over a 0.6 s gap at the default settings takes **{v} ms** on this machine (set-up + solve, from the spacetime table above).\n"
            );
        }
        None => {
            let _ = writeln!(
                d.md,
                "Spacetime time per transition: not measured (the spacetime section did not run).\n"
            );
        }
    }
}
