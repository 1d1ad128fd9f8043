//! What `SP(m, body: b, …)` is asked: the options, the kinematic prior's
//! knobs, how the root and the support limbs are filled.

use crate::model::Model;
use crate::spacetime::contact::Contact;
use crate::spacetime::error::{SpError, invalid_option};
use crate::spacetime::objective::TransitionSettings;
use crate::spacetime::reference::LibrarySource;
use crate::spacetime::solve::SolveOptions;
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
        if let Support::Named(names) = &self.support {
            crate::spacetime::hold::named(model, names, "support")?;
        }
        if let Contact::Named(names) = &self.contact {
            crate::spacetime::hold::named(model, names, "contact")?;
        }
        if let Contact::Given(given) = &self.contact {
            for g in given {
                g.check().map_err(|e| invalid_option("contact", e))?;
                crate::spacetime::hold::named(model, std::slice::from_ref(&g.point), "contact")?;
            }
        }
        Ok(())
    }
}

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
