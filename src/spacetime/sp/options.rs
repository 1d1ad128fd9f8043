//! What `SP(m, body: b, …)` is asked: the options, the kinematic prior's
//! knobs, how the root and the support limbs are filled.

use crate::model::Model;
use crate::spacetime::contact::Contact;
use crate::spacetime::error::{SpError, invalid_option};
use crate::spacetime::objective::TransitionSettings;
use crate::spacetime::reference::LibrarySource;
use crate::spacetime::solve::{GroundSettings, SolveOptions};
use nalgebra::Vector3;

/// Options of `SP(m, body: b, …)`.
#[derive(Clone, Debug, Default)]
pub struct SpOptions {
    pub settings: TransitionSettings,
    pub solve: SolveOptions,
    /// Gravity; `None`: the body's default.
    pub gravity: Option<Vector3<f64>>,
    /// Which limbs are held in place by IK over each gap (Rose §3.2.2).
    pub support: Support,
    /// How the root's horizontal position is filled (`root:`).
    pub root: RootFill,
    /// The kinematic prior added to ∫Στ² (`smoothness:`, `time_constant:`).
    pub prior: Prior,
    /// A clip library the prior's example may come from (`example: lib`).
    pub library: Option<LibrarySource>,
    /// Foot contact planned per gap (`contact:`); used with `support: "auto"`,
    /// which it replaces (see [`crate::spacetime::contact`]).
    pub contact: Contact,
    /// The floor's height along −gravity (`floor:`); `None`: the lowest
    /// contact point of the motion's recorded part.
    pub floor: Option<f64>,
    /// How a standing body's groups are solved: the base term's schedule,
    /// re-plans, the ground's weights and friction (`replan:` sets the
    /// re-plans).
    pub ground: GroundSettings,
}

/// Most free coefficients per DOF and gap (`coefficients:`): more buys no
/// accuracy (Rose uses 5–10) and the dense solve grows with their square.
pub const MAX_COEFFICIENTS: usize = 200;
/// Most Gauss points per gap (`samples:`).
pub const MAX_SAMPLES: usize = 100_000;
/// Most solver iterations per gap group (`iterations:`): a typo like 1e9
/// would run until cancelled.
pub const MAX_ITERATIONS: u64 = 1_000_000;

impl SpOptions {
    /// Checks every option against its range and `model` (frames named by
    /// `support:` and `contact:`), before any work: an error names the option
    /// at fault ([`SpError::InvalidOption`]), so the language points at it
    /// without checking again.
    pub fn check(&self, model: &Model) -> Result<(), SpError> {
        let s = &self.settings;
        let min = s.continuity.fixed_per_end();
        if !(min..=MAX_COEFFICIENTS).contains(&s.coefficients) {
            return Err(invalid_option(
                "coefficients",
                format!(
                    "`coefficients: {}` must be a whole number from {min} to {MAX_COEFFICIENTS} with continuity: {}",
                    s.coefficients,
                    s.continuity.order()
                ),
            ));
        }
        if !(1..=MAX_SAMPLES).contains(&s.samples) {
            return Err(invalid_option(
                "samples",
                format!(
                    "`samples: {}` must be a whole number from 1 to {MAX_SAMPLES}",
                    s.samples
                ),
            ));
        }
        if self.solve.max_iters > MAX_ITERATIONS {
            return Err(invalid_option(
                "iterations",
                format!(
                    "`iterations: {}` must be a whole number from 0 to {MAX_ITERATIONS}",
                    self.solve.max_iters
                ),
            ));
        }
        let tol = self.solve.tolerance;
        if !(tol > 0.0 && tol < 1.0) {
            return Err(invalid_option(
                "tolerance",
                format!("`tolerance:` must be a number in (0, 1), found {tol}"),
            ));
        }
        if let Some(g) = self.gravity
            && !g.iter().all(|x| x.is_finite())
        {
            return Err(invalid_option(
                "gravity",
                format!(
                    "`gravity:` must be finite, found [{}, {}, {}]",
                    g.x, g.y, g.z
                ),
            ));
        }
        self.prior.check()?;
        if let Some(h) = self.floor
            && !h.is_finite()
        {
            return Err(invalid_option(
                "floor",
                format!("`floor:` must be a finite height in metres, found {h}"),
            ));
        }
        if let Support::Auto { box_size } = self.support
            && !(box_size.is_finite() && box_size >= 0.0)
        {
            return Err(invalid_option(
                "support",
                format!(
                    "support box size {box_size} m must be finite and non-negative (default 0.02)"
                ),
            ));
        }
        // planning replaces the support limbs: a support given beside points
        // or stances named would be silently ignored. Beside the default
        // `contact: "auto"` a `support:` asks for Rose's support IK, and the
        // body does not stand (`sp::stands`); the language refuses an
        // explicit "auto" beside one.
        if matches!(self.contact, Contact::Named(_) | Contact::Given(_))
            && self.support != Support::default()
        {
            return Err(SpError::ContactReplacesSupport);
        }
        if let Support::Named(names) = &self.support {
            crate::spacetime::hold::named(model, names, "support")?;
        }
        if let Contact::Named(names) = &self.contact {
            crate::spacetime::hold::named(model, names, "contact")?;
        }
        if let Contact::Given(given) = &self.contact {
            for g in given {
                g.check()?;
                crate::spacetime::hold::named(model, std::slice::from_ref(&g.point), "contact")?;
            }
        }
        Ok(())
    }

    /// What the option `option` (as the language spells it) means and takes:
    /// the one text the help line under its error shows, whether the engine
    /// found the value out of range or the language found it of the wrong type,
    /// and the one `:help SP` lists ([`SP_OPTIONS`]).
    pub fn help(option: &str) -> Option<&'static str> {
        SP_OPTIONS.iter().find(|o| o.name == option).map(|o| o.help)
    }
}

/// One option of `SP(…)` as the language writes it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OptionDoc {
    pub name: &'static str,
    /// The default as `SP(…)`'s usage line shows it.
    pub default: &'static str,
    /// What it means and takes ([`SpOptions::help`]).
    pub help: &'static str,
}

/// SP's options in the order its usage line lists them: the one statement of
/// what each means, from which the language makes `SP(…)`'s signature, its
/// `:help` and the help under an option's error.
pub const SP_OPTIONS: [OptionDoc; 14] = [
    OptionDoc {
        name: "coefficients",
        default: "5",
        help: "free B-spline coefficients per DOF and gap: at least 2 with continuity: 1, 3 with continuity: 2 \
               (default 5, as in Rose's Fig. 8; Rose uses 5–10)",
    },
    OptionDoc {
        name: "samples",
        default: "20",
        help: "Gauss points of the torque integral per gap, at least 6 per B-spline piece (default 20)",
    },
    OptionDoc {
        name: "continuity",
        default: "1",
        help: "1: position and velocity continuous at the gap ends (Rose's transitions); 2: acceleration too",
    },
    OptionDoc {
        name: "support",
        default: "\"auto\"",
        help: "frames (links) of the body held by IK, e.g. a clip's joints: [\"LeftFoot\", \"RightFoot\"]; \
               [] for none; \"auto\" (default) detects them",
    },
    OptionDoc {
        name: "gravity",
        default: "[x, y, z]",
        help: "a finite vector in m/s², e.g. [0, -9.81, 0]",
    },
    OptionDoc {
        name: "iterations",
        default: "300",
        help: "solver iterations per gap group (default 300)",
    },
    OptionDoc {
        name: "tolerance",
        default: "1e-3",
        help: "the solver stops when 25 iterations lower the energy by less than this fraction (default 1e-3)",
    },
    OptionDoc {
        name: "objective",
        default: "\"effort\"",
        help: "\"effort\" (default): ∫Στ² plus a kinematic prior λ Σ M_dd² ∫ q̈² + q̇²/T² that holds light and \
               gimbal-locked DOFs (smoothness: λ, time_constant: T), lowered tenfold until the transition costs at \
               least 1 % less ∫Στ² than the Hermite curves; \"torque\": Rose's ∫Στ² alone",
    },
    OptionDoc {
        name: "smoothness",
        default: "1e6",
        help: "weight λ of the kinematic prior against ∫Στ² (default 1e6; 0 is objective: \"torque\")",
    },
    OptionDoc {
        name: "time_constant",
        default: "\"auto\"",
        help: "the prior damps the end velocities over about this time (e.g. 0.1s; \"auto\", the default: \
               (0.32 s)²/gap length)",
    },
    OptionDoc {
        name: "example",
        default: "\"self\"",
        help: "\"self\" (default): where the motion repeats (a walk, a run), the prior follows the velocities of the \
               stretch of m whose 0.3 s on each side best match those around the gap, λ Σ M_dd² ∫ (q̈ − r̈)² + (q̇ − ṙ)²/T², \
               if it matches better than the context's own mean pose; \"none\": the plain prior; a clip library \
               (library(…)): the stretch of its clips that best matches the gap's context, turned and moved onto the gap \
               in the floor plane (sp_report names clip, time, warp and mismatch); [lib, \"self\"]: the better of the two",
    },
    OptionDoc {
        name: "root",
        default: "\"auto\"",
        help: "\"auto\" (default): per gap, \"pinned\" when the recorded x–z displacement across it is within 0.5 m + \
               half the displacement T (v₀ + v₁)/2 the end velocities predict, i.e. a hole inside one recording, else \
               \"shift\"; \"shift\" (Rose): what follows the gap moves to continue the root's path; \"pinned\": the motion \
               after the gap stays where it was recorded and the root's x–z is a Hermite curve",
    },
    OptionDoc {
        name: "contact",
        default: "\"auto\"",
        help: "\"auto\" (default): the body stands on the ground wherever it has feet, gravity acts and a floor is found: \
               each gap's stances planned from its edges, the example's own stances (or a step planner's), re-planned from \
               the solve, the feet held there and the body carried by them (a footless body is SP as before); \"none\": \
               Rose's support: alone; frames (links) of the body, e.g. [\"Toes_L\", \"Toes_R\"]; or the stances \
               themselves, [{point, from, to, at}, …] or contacts(capture, body); sp_report(result).contacts lists the plan",
    },
    OptionDoc {
        name: "floor",
        default: "\"auto\"",
        help: "the floor's height (m) under contact:; \"auto\" (default): the lowest contact point of the motion's \
               recorded part",
    },
];

/// The kinematic prior SP adds to Rose's ∫Στ² (see [`prior_weights`]):
/// Σ_d λ s_d² ∫ ((q̈_d − r̈_d)² + (q̇_d − ṙ_d)²/T²) dt over the gap DOFs, s_d
/// the DOF's own inertia (the mass-matrix diagonal at the gap's start) and r
/// the motion's own example where it repeats (zero without one; see
/// [`crate::spacetime::reference`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Prior {
    /// λ (`smoothness:`); 0 is Rose's objective alone (`objective: "torque"`).
    pub smoothness: f64,
    /// T in seconds (`time_constant:`); `f64::INFINITY` drops the q̇ term;
    /// `None`: [`AUTO_TIME_SCALE`]² / d for a gap of d seconds.
    pub time_constant: Option<f64>,
    /// Follow the motion's own example where it repeats (`example: "self"`,
    /// the default; `"none"`: the plain prior). See [`crate::spacetime::reference`].
    pub example: bool,
    /// With an example (the motion's own or a library's): anchor the
    /// transition on the example's poses laid in the world
    /// (`objective::ExampleTerm`) in one solve at the prior's full weight
    /// (the default), instead of the prior on its derivatives lowered until
    /// the transition costs less ∫Στ² than Hermite (`false`: SP before
    /// issue 36, the bench's "today's SP").
    pub anchor: bool,
}

/// τ₀ of the default time constant T = τ₀²/d: the longer a gap, the sooner
/// its end velocities stop telling where the motion goes (Hermite, which
/// keeps them, wins on short gaps; slerp, which has none, on long ones). On
/// the shared in-betweening clips (one window per clip, root given) fixed T
/// were best at about 0.3 s for 15-frame gaps, 0.1 s for 30 and 0.07–0.1 s
/// for 45, which τ₀ = 0.32 s reproduces (`cargo bench --bench inbetween`).
pub const AUTO_TIME_SCALE: f64 = 0.32;

/// The default weight λ of the prior: large enough that the prior decides
/// the motion and ∫Στ² only breaks its ties, until the effort check lowers it.
/// λ = 1e3 (a row of `cargo bench --bench inbetween`) costs less ∫Στ² than
/// Hermite in 199 of 200 windows against 157 here, and is as close to the
/// capture at 5–15 frames, but 5 % farther at 30 and 45, and it folds a
/// dash's chest and neck 0.58 rad away from any pose the clip has (Hermite:
/// 0.18), which `tests/it/inbetween.rs` refuses.
pub const DEFAULT_SMOOTHNESS: f64 = 1e6;

impl Default for Prior {
    fn default() -> Self {
        Prior {
            smoothness: DEFAULT_SMOOTHNESS,
            time_constant: None,
            example: true,
            anchor: true,
        }
    }
}

impl Prior {
    /// `smoothness:` a non-negative number (0: Rose's ∫Στ² alone);
    /// `time_constant:` a positive time (∞ drops the velocity term).
    pub fn check(&self) -> Result<(), SpError> {
        if !(self.smoothness >= 0.0 && self.smoothness.is_finite()) {
            return Err(invalid_option(
                "smoothness",
                format!(
                    "`smoothness:` must be a non-negative number, found {}",
                    self.smoothness
                ),
            ));
        }
        if let Some(t) = self.time_constant
            && (t.is_nan() || t <= 0.0)
        {
            return Err(invalid_option(
                "time_constant",
                format!("`time_constant:` must be a positive time or \"auto\", found {t}"),
            ));
        }
        Ok(())
    }

    /// Rose's objective: ∫Στ² alone (`objective: "torque"`).
    pub fn none() -> Prior {
        Prior {
            smoothness: 0.0,
            time_constant: None,
            example: false,
            anchor: true,
        }
    }

    /// T for a gap of `d` seconds.
    pub fn time_constant_for(&self, d: f64) -> f64 {
        self.time_constant
            .unwrap_or(AUTO_TIME_SCALE * AUTO_TIME_SCALE / d.max(1e-9))
    }
}

/// `SP(…, root: …)`: how a gap in the root's horizontal position is filled.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RootFill {
    /// Per gap, [`RootFill::Pinned`] when the two sides look like one
    /// recording (the recorded x–z displacement across the gap is within
    /// [`root_tolerance`] of what the end velocities predict), otherwise
    /// [`RootFill::Shift`] (`"auto"`, the default): a hole cut inside one
    /// recording keeps the frames after it where they were recorded, two
    /// recordings joined are made to continue each other.
    #[default]
    Auto,
    /// Rose §3.2.1: x–z from the interpolated velocities, and the motion after
    /// the gap translated to continue from where that path ends (`"shift"`).
    Shift,
    /// The motion after the gap stays where it was; the root's x–z is the
    /// cubic Hermite curve between the two sides (`"pinned"`: in-betweening,
    /// where the frames after the gap are where they were captured).
    Pinned,
}

/// Support limbs of `SP(…, support: …)`.
#[derive(Clone, Debug, PartialEq)]
pub enum Support {
    /// Detect them: a joint frame whose world position stays inside a cube of
    /// this edge (m) over the end of the motion before a gap and the start of
    /// the motion after it.
    Auto { box_size: f64 },
    /// `support: ["LeftFoot", …]`: these frames, named as the body names them.
    Named(Vec<String>),
    /// `support: []`: no IK.
    Off,
}

impl Default for Support {
    fn default() -> Self {
        Support::Auto { box_size: 0.02 }
    }
}

/// Fixed part (m) of the largest mismatch [`RootFill::Auto`] pins.
pub const ROOT_TOLERANCE_FIXED: f64 = 0.5;
/// Part of the predicted displacement added to [`ROOT_TOLERANCE_FIXED`].
pub const ROOT_TOLERANCE_RELATIVE: f64 = 0.5;

/// The largest mismatch between the recorded and the predicted x–z
/// displacement across a gap (both in m) that [`RootFill::Auto`] takes for one
/// recording: 0.5 m + half the predicted displacement. Why: inside one
/// recording the velocities at the ends mispredict a walk's displacement by
/// 21 cm over 0.5 s and 38 cm over 1 s (a step changes speed within the gap;
/// Bandai walks, issue 25); two recordings joined start wherever each was
/// captured in the room, metres apart, unless an animator lined them up, in
/// which case keeping them where they are is what was asked.
pub fn root_tolerance(predicted: f64) -> f64 {
    ROOT_TOLERANCE_FIXED + ROOT_TOLERANCE_RELATIVE * predicted
}

#[cfg(test)]
mod tests {
    use super::super::fixture::{body, motion};
    use super::*;

    /// The engine itself refuses points or stances named beside a
    /// `support:` it would ignore, before any work, naming `contact`; beside
    /// the default `contact: "auto"` a stated support is Rose's (the body
    /// does not stand), and the default support is no clash.
    #[test]
    fn contact_beside_a_given_support_is_refused_by_the_engine() {
        let model = body();
        let m = motion(&model, &[3, 4], (0.8, 1.2));
        for support in [
            Support::Off,
            Support::Named(vec!["thigh".into()]),
            Support::Auto { box_size: 0.05 },
        ] {
            let named = SpOptions {
                support: support.clone(),
                contact: Contact::Named(vec!["shin".into()]),
                ..Default::default()
            };
            let e = named.check(&model).unwrap_err();
            assert_eq!(e, SpError::ContactReplacesSupport, "{support:?}");
            assert_eq!(e.option(), Some("contact"));
            let e = crate::spacetime::sp(&m, &model, &named).unwrap_err();
            assert_eq!(e, SpError::ContactReplacesSupport);
            let auto = SpOptions {
                support: support.clone(),
                ..Default::default()
            };
            assert_eq!(auto.check(&model), Ok(()), "{support:?}");
        }
        let planned = SpOptions {
            contact: Contact::Auto,
            ..Default::default()
        };
        assert_eq!(planned.check(&model), Ok(()));
        let off = SpOptions {
            support: Support::Off,
            ..Default::default()
        };
        assert_eq!(off.check(&model), Ok(()));
    }

    /// Every option an error can name has its one help text.
    #[test]
    fn every_checked_option_has_help() {
        for o in [
            "coefficients",
            "samples",
            "iterations",
            "tolerance",
            "gravity",
            "smoothness",
            "time_constant",
            "floor",
            "support",
            "contact",
        ] {
            assert!(SpOptions::help(o).is_some(), "{o}");
        }
        assert_eq!(SpOptions::help("nonsense"), None);
        // each option once, each with its own text
        for (i, o) in SP_OPTIONS.iter().enumerate() {
            assert!(!o.help.is_empty() && !o.default.is_empty(), "{}", o.name);
            for p in &SP_OPTIONS[i + 1..] {
                assert!(
                    o.name != p.name && o.help != p.help,
                    "{} {}",
                    o.name,
                    p.name
                );
            }
        }
    }
}
