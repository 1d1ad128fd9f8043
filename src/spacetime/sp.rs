//! SP over a whole motion (Rose §3.2): find every interior gap of every DOF,
//! move the root kinematically, solve the remaining gap DOFs as spacetime
//! transitions (overlapping gaps together, disjoint ones in parallel), and
//! write the curves back into the motion. Also the Hermite baseline
//! (`fill(m, "hermite")`) and the torque energy of a motion.

use super::contact::{Contact, ContactPhase};
use super::error::{SpError, invalid};
use super::solve::{PriorTerm, Problem, solve_all};
use super::objective::{GapDof, Inputs, TransitionSettings};
use super::quadrature::GaussLegendre;
use super::reference::Example;
use super::root::{RootCoords, RootTransition};
use super::solve::{GapReport, SolveOptions};
use super::support::HeldFrame;
use super::torque::{BodyDynamics, TorqueModel};
use super::transition::EndState;
use crate::model::Model;
use crate::motion::{Curve, Dof, Func, HermiteCurve, Interval, Mu, conflicts};
use nalgebra::Vector3;
use std::fmt;

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
    pub library: Option<super::reference::LibrarySource>,
    /// Foot contact planned per gap (`contact:`); used with `support: "auto"`,
    /// which it replaces (see [`super::contact`]).
    pub contact: Contact,
    /// The floor's height along −gravity (`floor:`); `None`: the lowest
    /// contact point of the motion's recorded part.
    pub floor: Option<f64>,
}

/// The kinematic prior SP adds to Rose's ∫Στ² (see [`prior_weights`]):
/// Σ_d λ s_d² ∫ ((q̈_d − r̈_d)² + (q̇_d − ṙ_d)²/T²) dt over the gap DOFs, s_d
/// the DOF's own inertia (the mass-matrix diagonal at the gap's start) and r
/// the motion's own example where it repeats (zero without one; see
/// [`super::reference`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Prior {
    /// λ (`smoothness:`); 0 is Rose's objective alone (`objective: "torque"`).
    pub smoothness: f64,
    /// T in seconds (`time_constant:`); `f64::INFINITY` drops the q̇ term;
    /// `None`: [`AUTO_TIME_SCALE`]² / d for a gap of d seconds.
    pub time_constant: Option<f64>,
    /// Follow the motion's own example where it repeats (`example: "self"`,
    /// the default; `"none"`: the plain prior). See [`super::reference`].
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

/// How the root was moved over one gap.
#[derive(Clone, Debug, PartialEq)]
pub struct RootShift {
    pub t0: f64,
    pub t1: f64,
    /// (coordinate name, translation applied to the motion after the gap).
    pub shift: Vec<(String, f64)>,
}

/// A gap whose root x–z was pinned: the motion after it stays where it was.
#[derive(Clone, Debug, PartialEq)]
pub struct PinnedRoot {
    pub t0: f64,
    pub t1: f64,
    /// `true` when `root: "auto"` chose it (one recording), `false` when asked for.
    pub auto: bool,
    /// How far (m) the recorded x–z displacement across the gap is from the
    /// one the end velocities predict, T (v₀ + v₁)/2 (Rose's path).
    pub mismatch: f64,
    /// The largest mismatch `"auto"` pins ([`root_tolerance`]).
    pub tolerance: f64,
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

/// The contact schedule of one gap (`contact:`).
#[derive(Clone, Debug, PartialEq)]
pub struct GapContacts {
    pub t0: f64,
    pub t1: f64,
    /// The floor's height along −gravity (m).
    pub floor: f64,
    /// Every contact frame near the floor around the gap, planted or not.
    pub phases: Vec<ContactPhase>,
}

/// A stretch of a DOF left undefined (gaps at the very start or end are not transitions).
#[derive(Clone, Debug, PartialEq)]
pub struct Undefined {
    pub dof: String,
    pub start: f64,
    pub stop: f64,
}

/// What SP did: one entry per solved group of gaps.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SpReport {
    pub groups: Vec<GapReport>,
    pub root: Vec<RootShift>,
    /// DOFs filled by the cubic Hermite curve (root rotations and vertical).
    pub hermite: Vec<Undefined>,
    pub undefined: Vec<Undefined>,
    /// Support frames held by IK (Rose §3.2.2), one entry per frame and gap.
    pub support: Vec<HeldFrame>,
    /// Gaps whose root x–z was pinned (the motion after them not moved).
    pub pinned: Vec<PinnedRoot>,
    /// Per gap, the contact schedule (`contact:` other than `"none"`).
    pub contacts: Vec<GapContacts>,
    /// Translation DOFs constant on both sides of their gap (bone offsets),
    /// held at that constant rather than optimised.
    pub constant: Vec<Undefined>,
}

impl fmt::Display for SpReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.groups.is_empty()
            && self.root.is_empty()
            && self.hermite.is_empty()
            && self.constant.is_empty()
        {
            writeln!(f, "SP: no interior gaps (nothing to fill)")?;
        }
        for (i, g) in self.groups.iter().enumerate() {
            writeln!(
                f,
                "gap {} [{:.4}, {:.4}] s, {} DOF{} ({}): {} {} unknowns, {} iterations, {} evaluations, ∫Στ² {:.6e} (Hermite {:.6e}, {:+.2}%), |∇e| {:.3e}, {}{}{} ({:.1} ms)",
                i + 1,
                g.t0,
                g.t1,
                g.names.len(),
                if g.names.len() == 1 { "" } else { "s" },
                abbreviate(&g.names),
                g.method,
                g.n_vars,
                g.iterations,
                g.evaluations,
                g.energy,
                g.initial_energy,
                100.0 * (g.energy - g.initial_energy)
                    / g.initial_energy.abs().max(f64::MIN_POSITIVE),
                g.grad_norm,
                g.stop,
                if g.solves > 1 {
                    // the continuation stops under Hermite's effort, or at its last step above it
                    format!(
                        "; prior ×{} after {} solves ({})",
                        crate::fmt_num::format_number(g.prior_scale),
                        g.solves,
                        if g.energy < g.initial_energy {
                            "lowered until the effort fell below Hermite's"
                        } else {
                            "still above Hermite's effort at the lowest prior"
                        }
                    )
                } else {
                    String::new()
                },
                match &g.example {
                    Some(ex @ Example { clip: Some(c), .. }) => format!(
                        "; prior follows clip `{}` from {:.3} s (warp {}) on {} of {} DOFs (mismatch {:.3}, features {:.3})",
                        c.name,
                        c.time,
                        c.warp,
                        ex.follow.len(),
                        ex.of,
                        ex.mismatch,
                        c.features
                    ),
                    Some(ex) => format!(
                        "; prior follows the motion {:+.3} s away on {} of {} DOFs (mismatch {:.3})",
                        ex.shift,
                        ex.follow.len(),
                        ex.of,
                        ex.mismatch
                    ),
                    None => String::new(),
                },
                g.seconds * 1e3
            )?;
        }
        for r in &self.root {
            let s: Vec<String> = r
                .shift
                .iter()
                .map(|(n, d)| format!("{n} {d:+.4}"))
                .collect();
            writeln!(
                f,
                "root over [{:.4}, {:.4}] s: x–z from interpolated velocities; motion after the gap translated by {}",
                r.t0,
                r.t1,
                s.join(", ")
            )?;
        }
        for p in &self.pinned {
            writeln!(
                f,
                "root over [{:.4}, {:.4}] s: pinned, the motion after the gap stays where it was ({}; recorded x–z displacement {:.3} m from the end velocities' prediction{})",
                p.t0,
                p.t1,
                if p.auto {
                    "root: \"auto\" took both sides for one recording"
                } else {
                    "root: \"pinned\""
                },
                p.mismatch,
                if p.auto {
                    format!(", at most {:.3} m", p.tolerance)
                } else {
                    String::new()
                }
            )?;
        }
        for h in &self.support {
            writeln!(
                f,
                "support {} ({}) held over [{:.4}, {:.4}] s by IK on {}: moves {:.4} m from its planted path ({:.4} m on the Hermite start, without IK)",
                h.frame,
                if h.detected { "detected" } else { "named" },
                h.t0,
                h.t1,
                abbreviate(&h.dofs),
                h.moved,
                h.moved_before
            )?;
        }
        for g in &self.contacts {
            for c in &g.phases {
                if c.plants.is_empty() {
                    writeln!(
                        f,
                        "contact {} over [{:.4}, {:.4}] s: not planted (kept above the floor at {:.4} m)",
                        c.frame, g.t0, g.t1, g.floor
                    )?;
                }
                for p in &c.plants {
                    writeln!(
                        f,
                        "contact {} over [{:.4}, {:.4}] s: planted [{:.4}, {:.4}] s at ({:.3}, {:.3}, {:.3}){}",
                        c.frame,
                        g.t0,
                        g.t1,
                        p.t0,
                        p.t1,
                        p.p0.x,
                        p.p0.y,
                        p.p0.z,
                        if (p.p1 - p.p0).norm() > 0.0 {
                            format!(" to ({:.3}, {:.3}, {:.3})", p.p1.x, p.p1.y, p.p1.z)
                        } else {
                            String::new()
                        }
                    )?;
                }
            }
        }
        for h in &self.hermite {
            writeln!(
                f,
                "{} on [{:.4}, {:.4}] s: root, cubic Hermite",
                h.dof, h.start, h.stop
            )?;
        }
        if !self.constant.is_empty() {
            let names: Vec<String> = self.constant.iter().map(|c| c.dof.clone()).collect();
            writeln!(
                f,
                "{} translation DOF{} constant on both sides of {} gap held at {} value (bone offsets keep their length): {}",
                names.len(),
                if names.len() == 1 { "" } else { "s" },
                if names.len() == 1 { "its" } else { "their" },
                if names.len() == 1 { "its" } else { "their" },
                abbreviate(&names)
            )?;
        }
        for u in &self.undefined {
            writeln!(
                f,
                "{} stays undefined on [{:.4}, {:.4}] s (a gap at the start or end is not a transition)",
                u.dof, u.start, u.stop
            )?;
        }
        Ok(())
    }
}

fn abbreviate(names: &[String]) -> String {
    if names.len() <= 4 {
        names.join(", ")
    } else {
        format!("{}, … {}", names[..3].join(", "), names[names.len() - 1])
    }
}

fn motion_err(e: crate::motion::MotionError) -> SpError {
    SpError::Evaluation(e.to_string())
}

/// Error on any conflict (SP needs one value per DOF where it is defined).
fn check_conflicts(m: &Mu) -> Result<(), SpError> {
    if let Some(c) = conflicts(m).first() {
        return Err(SpError::Conflict(format!(
            "DOF '{}' is multiply defined on [{}, {}] (a conflict): SP fills gaps, it cannot choose between motions; \
             remove one of them there (e.g. a − b) before SP",
            c.dof, c.start, c.stop
        )));
    }
    Ok(())
}

/// DOFs undefined at the start or end of the motion's span.
fn undefined_ends(m: &Mu) -> Vec<Undefined> {
    let Some((s, e)) = m.span() else {
        return vec![];
    };
    let mut out = vec![];
    for (name, d) in &m.dofs {
        match d.span() {
            None => out.push(Undefined {
                dof: name.clone(),
                start: s,
                stop: e,
            }),
            Some((a, b)) => {
                if a - s > crate::motion::time_tol(s) {
                    out.push(Undefined {
                        dof: name.clone(),
                        start: s,
                        stop: a,
                    });
                }
                if e - b > crate::motion::time_tol(b) {
                    out.push(Undefined {
                        dof: name.clone(),
                        start: b,
                        stop: e,
                    });
                }
            }
        }
    }
    out
}

/// [q, q̇, q̈] of a DOF at a gap end (the neighbouring interval's value).
fn end_state(m: &Mu, name: &str, t: f64) -> Result<EndState, SpError> {
    match m.sample(name, t).map_err(motion_err)? {
        Some([q, v, a]) => Ok(EndState { q, v, a }),
        None => Err(SpError::Evaluation(format!(
            "DOF '{name}' is undefined at the gap end t = {t}"
        ))),
    }
}

fn insert_curve(dof: &mut Dof, curve: Curve, t0: f64, t1: f64) -> Result<(), SpError> {
    let iv = Interval::curve(curve, t0, t1).map_err(motion_err)?;
    *dof = dof.plus(&Dof::from(iv));
    Ok(())
}

fn hermite_curve(t0: f64, t1: f64, a: &EndState, b: &EndState) -> Result<Curve, SpError> {
    Ok(Curve::Hermite(
        HermiteCurve::new(t0, a.q, a.v, t1, b.q, b.v).map_err(motion_err)?,
    ))
}

/// `fill(m, "hermite")`: every interior gap of every DOF becomes the cubic
/// Hermite curve between the end values and velocities
/// ([`crate::motion::fill_hermite`]). Conflicts are an error, worded for SP.
pub fn fill_hermite(m: &Mu) -> Result<Mu, SpError> {
    check_conflicts(m)?;
    crate::motion::fill_hermite(m).map_err(motion_err)
}

/// Shift every interval of `dof` that starts at or after `t` by `delta` in value.
fn shift_after(dof: &mut Dof, t: f64, delta: f64) {
    for iv in dof.intervals.iter_mut() {
        if iv.start >= t - crate::motion::time_tol(t) {
            for f in iv.funcs.iter_mut() {
                *f = Func {
                    offset: f.offset + delta,
                    ..f.clone()
                };
            }
        }
    }
}

/// Fill the root's gaps (§3.2.1): horizontal translations from interpolated
/// velocities (shifting what follows), the vertical and rotations by Hermite.
fn fill_root(
    m: &mut Mu,
    model: &Model,
    root: &RootCoords,
    how: RootFill,
    report: &mut SpReport,
) -> Result<(), SpError> {
    let names = model.coordinate_names();
    let pinned = pinned_gaps(m, model, root, how)?;
    let is_pinned = |t0: f64, t1: f64| {
        pinned.iter().any(|p| {
            (p.t0 - t0).abs() <= crate::motion::time_tol(t0)
                && (p.t1 - t1).abs() <= crate::motion::time_tol(t1)
        })
    };
    report.pinned.extend(pinned.iter().cloned());
    for &c in &root.all {
        let name = &names[c];
        let Some(dof) = m.get(name) else { continue };
        let gaps = dof.gaps();
        for (t0, t1) in gaps {
            let a = end_state(m, name, t0)?;
            let b = end_state(m, name, t1)?;
            let curve;
            if root.horizontal.contains(&c) && !is_pinned(t0, t1) {
                // one horizontal component of p(t); y of RootTransition is unused here
                let rt = RootTransition::new(t0, t1, [a.q, 0.0], [a.v, 0.0], [b.v, 0.0], a, b)?;
                let shift = rt.end_xz()[0] - b.q;
                let dof = m
                    .dofs
                    .get_mut(name)
                    .ok_or_else(|| invalid("root DOF vanished"))?;
                shift_after(dof, t1, shift);
                // p(t) is the Hermite cubic with end value p(t2) and the same velocities
                let end = EndState {
                    q: b.q + shift,
                    ..b
                };
                curve = hermite_curve(t0, t1, &a, &end)?;
                match report.root.iter_mut().find(|r| r.t0 == t0 && r.t1 == t1) {
                    Some(r) => r.shift.push((name.clone(), shift)),
                    None => report.root.push(RootShift {
                        t0,
                        t1,
                        shift: vec![(name.clone(), shift)],
                    }),
                }
            } else {
                curve = hermite_curve(t0, t1, &a, &b)?;
                report.hermite.push(Undefined {
                    dof: name.clone(),
                    start: t0,
                    stop: t1,
                });
            }
            let dof = m
                .dofs
                .get_mut(name)
                .ok_or_else(|| invalid("root DOF vanished"))?;
            insert_curve(dof, curve, t0, t1)?;
        }
    }
    Ok(())
}

/// The gaps of the root's horizontal coordinates that keep the motion after
/// them in place: all of them for [`RootFill::Pinned`], none for
/// [`RootFill::Shift`], and for [`RootFill::Auto`] those whose recorded x–z
/// displacement is within [`root_tolerance`] of T (v₀ + v₁)/2. Horizontal
/// coordinates gapped over the same span are judged together (their vector).
fn pinned_gaps(
    m: &Mu,
    model: &Model,
    root: &RootCoords,
    how: RootFill,
) -> Result<Vec<PinnedRoot>, SpError> {
    let names = model.coordinate_names();
    // per gap span: (squared mismatch, squared predicted displacement)
    let mut spans: Vec<(f64, f64, f64, f64)> = vec![];
    for &c in &root.horizontal {
        let Some(dof) = m.get(&names[c]) else {
            continue;
        };
        for (t0, t1) in dof.gaps() {
            let a = end_state(m, &names[c], t0)?;
            let b = end_state(m, &names[c], t1)?;
            let predicted = (t1 - t0) * (a.v + b.v) / 2.0;
            let off = (b.q - a.q) - predicted;
            let same = |s: &&mut (f64, f64, f64, f64)| {
                (s.0 - t0).abs() <= crate::motion::time_tol(t0)
                    && (s.1 - t1).abs() <= crate::motion::time_tol(t1)
            };
            match spans.iter_mut().find(same) {
                Some(s) => {
                    s.2 += off * off;
                    s.3 += predicted * predicted;
                }
                None => spans.push((t0, t1, off * off, predicted * predicted)),
            }
        }
    }
    Ok(spans
        .into_iter()
        .filter_map(|(t0, t1, off2, pred2)| {
            let (mismatch, tolerance) = (off2.sqrt(), root_tolerance(pred2.sqrt()));
            let p = |auto| PinnedRoot {
                t0,
                t1,
                auto,
                mismatch,
                tolerance,
            };
            match how {
                RootFill::Shift => None,
                RootFill::Pinned => Some(p(false)),
                RootFill::Auto => (mismatch <= tolerance).then(|| p(true)),
            }
        })
        .collect())
}

/// Inputs of the objective from a motion: every body coordinate sampled at t,
/// NaN where undefined.
fn motion_inputs<'a>(
    m: &'a Mu,
    names: &'a [String],
) -> impl Fn(f64, &mut [f64], &mut [f64], &mut [f64]) -> Result<(), SpError> + Sync + 'a {
    move |t, q, v, a| {
        for (i, n) in names.iter().enumerate() {
            if let Some([x, dx, ddx]) = m.sample(n, t).map_err(motion_err)? {
                q[i] = x;
                v[i] = dx;
                a[i] = ddx;
            }
        }
        Ok(())
    }
}

/// Checks that the motion can drive the body: every DOF with a gap is a body
/// coordinate, and every body coordinate is in the motion.
fn check_names(m: &Mu, model: &Model) -> Result<(), SpError> {
    let names = model.coordinate_names();
    let missing: Vec<&String> = names.iter().filter(|n| m.get(n).is_none()).collect();
    if !missing.is_empty() {
        return Err(invalid(format!(
            "the motion has no DOF for {} of the body's coordinates ({}{}); the body must be the one the motion was made for \
             (e.g. human(walk) for a clip) — torques need every coordinate",
            missing.len(),
            missing
                .iter()
                .take(5)
                .map(|s| s.as_str())
                .collect::<Vec<_>>()
                .join(", "),
            if missing.len() > 5 { ", …" } else { "" }
        )));
    }
    for (name, d) in &m.dofs {
        if !d.gaps().is_empty() && model.coordinate_index(name).is_none() {
            return Err(invalid(format!(
                "DOF '{name}' has a gap but the body has no coordinate of that name, so SP cannot compute its torques; \
                 fill it another way (fill(m, \"hermite\")) or use the body the motion was made for"
            )));
        }
    }
    Ok(())
}

/// `SP(m, body: b, …)`: the motion with every interior gap filled. Gaps at the
/// start or end stay undefined (listed in the report).
pub fn sp(m: &Mu, model: &Model, opts: &SpOptions) -> Result<(Mu, SpReport), SpError> {
    check_conflicts(m)?;
    check_names(m, model)?;
    let gravity = opts.gravity.unwrap_or(model.default_gravity);
    // the root as it moves in m: a constant placeholder above it is skipped
    let root = RootCoords::detect_in(model, &gravity, m);
    let mut report = SpReport {
        undefined: undefined_ends(m),
        ..Default::default()
    };
    let mut out = m.clone();
    fill_root(&mut out, model, &root, opts.root, &mut report)?;

    let names = model.coordinate_names();
    let mut gaps = vec![];
    for (c, name) in names.iter().enumerate() {
        let Some(dof) = out.get(name) else { continue };
        for (t0, t1) in dof.gaps() {
            gaps.push(GapDof {
                coord: c,
                t0,
                t1,
                start: end_state(&out, name, t0)?,
                end: end_state(&out, name, t1)?,
            });
        }
    }
    // what the prior's transitions must undercut: the motion filled by Hermite curves
    let hermite_all = fill_hermite(&out)?;
    let gaps = hold_constant_offsets(&mut out, model, gaps, &mut report)?;
    let gaps = hold_supports(&mut out, model, &gravity, opts, gaps, &mut report)?;
    if gaps.is_empty() {
        return Ok((out, report));
    }
    let weights = joint_weights(model, &root);
    let baseline = |t0: f64, t1: f64| -> Result<f64, SpError> {
        let piece = crate::motion::clip_in_place(t0, t1, &hermite_all).map_err(motion_err)?;
        torque_energy(&piece, model, Some(gravity))
    };
    let rotation = |c: usize| !is_translation(model, c);
    let example = |group: &[GapDof]| -> Result<Option<Example>, SpError> {
        super::reference::choose(
            &out,
            names,
            &rotation,
            group,
            opts.prior.example,
            opts.library.as_ref(),
        )
    };
    let prior = PriorTerm {
        weights: prior_weights(model, &out, &gaps, &opts.prior)?,
        baseline: &baseline,
        example: &example,
    };
    let body = BodyDynamics { model, gravity };
    let inputs_fn = motion_inputs(&out, names);
    let inputs: &Inputs = &inputs_fn;
    let problem = Problem {
        model: &body,
        settings: &opts.settings,
        weights: &weights,
        prior: Some(&prior),
        inputs,
        opts: &opts.solve,
        names,
    };
    let solutions = solve_all(&problem, gaps)?;
    let mut result = out.clone();
    for sol in solutions {
        let r = sol.report.clone();
        // write each DOF's curve back (the objective's order is the report's order)
        for ((&c, coefs), gap) in r.coords.iter().zip(sol.coefficients).zip(sol.curves.iter()) {
            let curve = gap.to_curve(coefs)?;
            let dof = result
                .dofs
                .get_mut(&names[c])
                .ok_or_else(|| invalid("gap DOF vanished"))?;
            insert_curve(dof, Curve::Spline(curve), gap.t0(), gap.t1())?;
        }
        report.groups.push(r);
    }
    Ok((result, report))
}

/// Whether model coordinate `c` is the coordinate of a 1-DOF sliding joint.
fn is_translation(model: &Model, c: usize) -> bool {
    model.links().iter().any(|l| {
        l.dof == 1
            && l.q_index == c
            && l.axis
                .is_some_and(|a| a.motion == crate::model::joint::AxisMotion::Translation)
    })
}

/// How far (m) a translation may vary across a gap and still count as a
/// constant bone offset: Bandai's position channels carry the offset with
/// rounding noise of ~1e-8 m.
const OFFSET_TOLERANCE: f64 = 1e-6;

/// Translation DOFs whose two sides hold one value (a BVH joint's position
/// channels, which are its bone offset, up to rounding noise): the gap is the
/// cubic Hermite curve between the sides, which stays within
/// [`OFFSET_TOLERANCE`] of that value. Optimising them would let bones
/// stretch, which no torque forbids. Returns the gaps left to solve.
fn hold_constant_offsets(
    m: &mut Mu,
    model: &Model,
    gaps: Vec<GapDof>,
    report: &mut SpReport,
) -> Result<Vec<GapDof>, SpError> {
    let names = model.coordinate_names();
    let mut left = vec![];
    for g in gaps {
        let span = g.t1 - g.t0;
        let still = |s: &EndState| {
            s.v.abs() * span <= OFFSET_TOLERANCE && s.a.abs() * span * span <= OFFSET_TOLERANCE
        };
        let same = (g.start.q - g.end.q).abs() <= OFFSET_TOLERANCE;
        if is_translation(model, g.coord) && same && still(&g.start) && still(&g.end) {
            let dof = m
                .dofs
                .get_mut(&names[g.coord])
                .ok_or_else(|| invalid("gap DOF vanished"))?;
            insert_curve(
                dof,
                hermite_curve(g.t0, g.t1, &g.start, &g.end)?,
                g.t0,
                g.t1,
            )?;
            report.constant.push(Undefined {
                dof: names[g.coord].clone(),
                start: g.t0,
                stop: g.t1,
            });
        } else {
            left.push(g);
        }
    }
    Ok(left)
}

/// Fewest kg·m² (or kg) a DOF's inertia scale counts as, so that a massless
/// link (an End Site, a placeholder) still gets a finite prior.
const MIN_INERTIA_SCALE: f64 = 1e-6;

/// Least inertia scale of a gap DOF, as a fraction of the largest in its gap:
/// a DOF that moves almost no mass (a toe of zero mass, a finger) would get
/// almost no prior and no torque, leaving the solver free to swing it (the
/// preconditioned steps are large exactly where the objective is flat).
const RELATIVE_INERTIA_FLOOR: f64 = 0.1;

/// Per model coordinate, the weights [c_v, c_a] of SP's kinematic prior
/// (zero for coordinates without a gap): c_a = λ s², c_v = λ s²/T², where
/// s = M_dd, the coordinate's own inertia at the start of its first gap (at
/// least [`RELATIVE_INERTIA_FLOOR`] of the largest in that gap).
///
/// Why: ∫Στ² alone leaves DOFs that barely move any mass (fingers, toes, a
/// hand turning about its long axis, two Euler channels near gimbal lock
/// turning against each other) free to do anything, and lets heavy limbs drift
/// toward low-gravity poses far from what a person does. (s q̈)² is the torque
/// the DOF would need to accelerate its own inertia alone, so the prior is in
/// torque² units and holds every DOF in proportion to its own torque scale,
/// light or heavy. Its q̈ part alone is minimised by the cubic Hermite curve
/// (with position and velocity fixed at both ends), so without an example SP
/// never ends above Hermite in e = ∫Στ² + prior; the q̇/T² part damps the end
/// velocities over a time T, as captured motion does over long gaps (the slerp
/// baseline, with no velocity at all, beats Hermite there). With an example r
/// the prior is minimised by r plus the smooth correction that meets the end
/// states.
pub fn prior_weights(
    model: &Model,
    m: &Mu,
    gaps: &[GapDof],
    prior: &Prior,
) -> Result<Vec<[f64; 2]>, SpError> {
    let n = model.nq();
    let mut out = vec![[0.0; 2]; n];
    if prior.smoothness == 0.0 || gaps.is_empty() {
        return Ok(out);
    }
    if !(prior.smoothness.is_finite() && prior.smoothness > 0.0) {
        return Err(invalid(format!(
            "smoothness: {} must be a positive number (0 is Rose's torque objective alone)",
            prior.smoothness
        )));
    }
    if let Some(t) = prior.time_constant
        && (t.is_nan() || t <= 0.0)
    {
        return Err(invalid(format!(
            "time_constant: {t} must be a positive time (e.g. 0.1s)"
        )));
    }
    let names = model.coordinate_names();
    let mut ws = crate::dynamics::Workspace::new(model);
    let mut mm = nalgebra::DMatrix::zeros(n, n);
    let mut done = vec![false; n];
    for g in gaps {
        if done[g.coord] {
            continue;
        }
        // the pose just before the gap, every coordinate defined there
        let mut q = vec![0.0; n];
        for (i, name) in names.iter().enumerate() {
            q[i] = m
                .sample(name, g.t0)
                .map_err(motion_err)?
                .map_or(0.0, |s| s[0]);
        }
        crate::dynamics::mass_matrix(model, &mut ws, &q, &mut mm)
            .map_err(|e| SpError::Evaluation(format!("dynamics: {e}")))?;
        let same_gap = |h: &&GapDof| (h.t0 - g.t0).abs() <= crate::motion::time_tol(g.t0);
        let largest = gaps
            .iter()
            .filter(same_gap)
            .map(|h| mm[(h.coord, h.coord)])
            .fold(0.0, f64::max);
        let floor = (RELATIVE_INERTIA_FLOOR * largest).max(MIN_INERTIA_SCALE);
        for h in gaps.iter().filter(same_gap) {
            if !done[h.coord] {
                let s = mm[(h.coord, h.coord)].max(floor);
                let ca = prior.smoothness * s * s;
                let t = prior.time_constant_for(h.t1 - h.t0);
                out[h.coord] = [ca / (t * t), ca];
                done[h.coord] = true;
            }
        }
    }
    Ok(out)
}

/// Support limbs (Rose §3.2.2, see [`super::support`]): per group of
/// overlapping gaps, find the support frames (detected or named), solve the
/// gap DOFs on their chains by IK and write those curves into `m`. Returns the
/// gaps left for the spacetime solve.
fn hold_supports(
    m: &mut Mu,
    model: &Model,
    gravity: &Vector3<f64>,
    opts: &SpOptions,
    gaps: Vec<GapDof>,
    report: &mut SpReport,
) -> Result<Vec<GapDof>, SpError> {
    use super::support::{self, SupportObjective};
    if opts.contact != Contact::None && matches!(opts.support, Support::Auto { .. }) {
        return hold_contacts(m, model, gravity, opts, gaps, report);
    }
    let named = match &opts.support {
        Support::Off => return Ok(gaps),
        Support::Named(names) => Some(support::named(model, names)?),
        Support::Auto { .. } => None,
    };
    let names = model.coordinate_names();
    let mut left = vec![];
    for group in super::solve::group_overlapping(gaps) {
        let t0 = group.iter().map(|d| d.t0).fold(f64::INFINITY, f64::min);
        let t1 = group.iter().map(|d| d.t1).fold(f64::NEG_INFINITY, f64::max);
        let configuration = |t: f64| -> Result<Vec<f64>, SpError> {
            let mut q = vec![f64::NAN; names.len()];
            for (i, n) in names.iter().enumerate() {
                if let Some([x, _, _]) = m.sample(n, t).map_err(motion_err)? {
                    q[i] = x;
                }
            }
            Ok(q)
        };
        let (frames, detected) = match (&named, &opts.support) {
            (Some(f), _) => (f.clone(), false),
            (None, Support::Auto { box_size }) => {
                let mut qs = vec![];
                for i in 0..support::WINDOW_SAMPLES {
                    let dt = support::WINDOW * i as f64 / (support::WINDOW_SAMPLES - 1) as f64;
                    for t in [t0 - dt, t1 + dt] {
                        let q = configuration(t)?;
                        // the motion may not reach that far: use what is defined
                        if q.iter().all(|v| v.is_finite()) {
                            qs.push(q);
                        }
                    }
                }
                (support::detect(model, &qs, gravity, *box_size)?, true)
            }
            _ => unreachable!("Off returned above"),
        };
        // the gap DOFs on the chains from the frames to the root are the IK
        // unknowns; a frame no gap DOF moves has nothing to solve
        let moves =
            |f: usize, c: usize| support::owner(model, c).is_some_and(|o| model.is_ancestor(o, f));
        let mut frames: Vec<usize> = frames
            .into_iter()
            .filter(|&f| group.iter().any(|d| moves(f, d.coord)))
            .collect();
        // A detected support is held only where interpolation would let it
        // slide out of its box: elsewhere (short gaps, mostly) the Hermite
        // curves already keep it planted, and IK would only add torque.
        if let (true, Support::Auto { box_size }) = (detected, &opts.support)
            && !frames.is_empty()
        {
            let chain: Vec<GapDof> = group
                .iter()
                .filter(|d| frames.iter().any(|&f| moves(f, d.coord)))
                .cloned()
                .collect();
            let probe = SupportObjective::new(
                model,
                frames.clone(),
                chain,
                &opts.settings,
                &configuration,
            )?;
            let drift = probe.largest_drift(&probe.hermite_start())?;
            frames = frames
                .into_iter()
                .zip(drift)
                .filter(|&(_, d)| d > *box_size)
                .map(|(f, _)| f)
                .collect();
        }
        let on_chain = |c: usize| frames.iter().any(|&f| moves(f, c));
        let (ik, rest): (Vec<GapDof>, Vec<GapDof>) =
            group.into_iter().partition(|d| on_chain(d.coord));
        left.extend(rest);
        if ik.is_empty() {
            continue;
        }
        let obj = SupportObjective::new(model, frames.clone(), ik, &opts.settings, &configuration)?;
        let x = obj.solve(&opts.solve.cancel)?;
        write_support_solve(&obj, &x, &frames, (t0, t1), detected, model, m, report)?;
    }
    Ok(left)
}

/// Every coordinate at t (NaN where undefined).
fn configuration_at(m: &Mu, names: &[String], t: f64) -> Result<Vec<f64>, SpError> {
    let mut q = vec![f64::NAN; names.len()];
    for (i, n) in names.iter().enumerate() {
        if let Some([x, _, _]) = m.sample(n, t).map_err(motion_err)? {
            q[i] = x;
        }
    }
    Ok(q)
}

/// Seconds between the poses the default floor is read from.
const FLOOR_STEP: f64 = 1.0 / 30.0;

/// Foot contact (`contact:`, see [`super::contact`]): per group of
/// overlapping gaps, plan each contact frame's plants from the motion around
/// it, solve the gap DOFs on the chains of the planted frames by IK (planted
/// frames held, every contact frame on those chains kept at or above the
/// floor) and write those curves into `m`. Returns the gaps left for the
/// spacetime solve.
fn hold_contacts(
    m: &mut Mu,
    model: &Model,
    gravity: &Vector3<f64>,
    opts: &SpOptions,
    gaps: Vec<GapDof>,
    report: &mut SpReport,
) -> Result<Vec<GapDof>, SpError> {
    use super::contact::{self, Context};
    use super::support::{self, SupportObjective};
    if gravity.norm() == 0.0 {
        return Ok(gaps); // no gravity, no floor: nothing stands on anything
    }
    let up = -gravity / gravity.norm();
    let names = model.coordinate_names();
    let (candidates, named) = match &opts.contact {
        Contact::Named(n) => (support::named(model, n)?, true),
        _ => (support::candidates(model), false),
    };
    let height = match opts.floor {
        Some(h) => h,
        None => {
            // the recorded part: every pose where the whole body is defined
            let Some((s, e)) = m.span() else {
                return Ok(gaps);
            };
            let n = ((e - s) / FLOOR_STEP).ceil() as usize;
            let mut qs = vec![];
            for k in 0..=n {
                let q = configuration_at(m, names, (s + k as f64 * FLOOR_STEP).min(e))?;
                if q.iter().all(|v| v.is_finite()) {
                    qs.push(q);
                }
            }
            match contact::floor_of(model, &candidates, &up, &qs)? {
                Some(h) => h,
                None => return Ok(gaps), // never fully defined: nothing to stand on
            }
        }
    };
    let floor = contact::floor(gravity, height)?;
    let mut left = vec![];
    for group in super::solve::group_overlapping(gaps) {
        let t0 = group.iter().map(|d| d.t0).fold(f64::INFINITY, f64::min);
        let t1 = group.iter().map(|d| d.t1).fold(f64::NEG_INFINITY, f64::max);
        let snapshot = m.clone();
        let configuration = |t: f64| configuration_at(&snapshot, names, t);
        let ctx = Context::new(
            model,
            up,
            &candidates,
            named,
            height,
            (t0, t1),
            &configuration,
        )?;
        let plants = ctx.plan();
        report.contacts.push(GapContacts {
            t0,
            t1,
            floor: height,
            phases: ctx.phases(&plants),
        });
        let moves =
            |f: usize, c: usize| support::owner(model, c).is_some_and(|o| model.is_ancestor(o, f));
        // the chains of the planted frames are solved by IK
        let planted: Vec<usize> = ctx
            .frames()
            .iter()
            .zip(&plants)
            .filter(|(_, p)| !p.is_empty())
            .map(|(&f, _)| f)
            .collect();
        let on_chain = |c: usize| planted.iter().any(|&f| moves(f, c));
        let (ik, rest): (Vec<GapDof>, Vec<GapDof>) =
            group.into_iter().partition(|d| on_chain(d.coord));
        left.extend(rest);
        if ik.is_empty() {
            continue;
        }
        // every contact frame those DOFs move: planted ones held, all above the floor
        let (frames, frame_plants): (Vec<usize>, Vec<_>) = ctx
            .frames()
            .iter()
            .zip(plants)
            .filter(|(f, _)| ik.iter().any(|d| moves(**f, d.coord)))
            .map(|(&f, p)| (f, p))
            .unzip();
        let obj = SupportObjective::planned(
            model,
            frames.clone(),
            frame_plants,
            floor,
            ik,
            &opts.settings,
            &configuration,
        )?;
        let x = obj.solve(&opts.solve.cancel)?;
        write_support_solve(&obj, &x, &frames, (t0, t1), true, model, m, report)?;
    }
    Ok(left)
}

/// Writes a solved support IK back into the motion (its chain's curves over
/// the gap) and records each held frame in the report, with how far it moved
/// under the Hermite curves and under IK.
#[allow(clippy::too_many_arguments)]
fn write_support_solve(
    obj: &super::support::SupportObjective,
    x: &[f64],
    frames: &[usize],
    (t0, t1): (f64, f64),
    detected: bool,
    model: &Model,
    m: &mut Mu,
    report: &mut SpReport,
) -> Result<(), SpError> {
    let names = model.coordinate_names();
    let before = obj.largest_drift(&obj.hermite_start())?;
    let after = obj.largest_drift(x)?;
    let dof_names: Vec<String> = obj.dofs().iter().map(|d| names[d.coord].clone()).collect();
    for (i, &f) in frames.iter().enumerate() {
        report.support.push(HeldFrame {
            frame: model.link(f).name.clone(),
            t0,
            t1,
            detected,
            dofs: dof_names.clone(),
            moved_before: before[i],
            moved: after[i],
        });
    }
    for ((gap, coefs), curve) in obj.dofs().iter().zip(obj.coefficients(x)).zip(obj.curves()) {
        let c = curve.to_curve(coefs)?;
        let dof = m.dofs.get_mut(&names[gap.coord]).ok_or_else(|| {
            invalid(format!(
                "SP lost the DOF {} while writing back its support IK",
                names[gap.coord]
            ))
        })?;
        insert_curve(dof, Curve::Spline(c), gap.t0, gap.t1)?;
    }
    Ok(())
}

/// 1 for every joint coordinate, 0 for the root's (nothing actuates the six
/// virtual root forces; Rose sums joint torques).
pub fn joint_weights(model: &Model, root: &RootCoords) -> Vec<f64> {
    let mut w = vec![1.0; model.nq()];
    for &c in &root.all {
        w[c] = 0.0;
    }
    w
}

/// Gauss points per piece in [`torque_energy`].
const ENERGY_POINTS: usize = 5;
/// Longest piece in [`torque_energy`] (s): pieces also break at every interval end.
const ENERGY_PIECE: f64 = 1.0 / 30.0;

/// `torque_energy(m, body)`: ∫ Σᵢ τᵢ² dt over the motion's span, τ the joint
/// torques (root coordinates excluded, as in SP's objective), by 5-point
/// Gauss–Legendre on pieces of at most 1/30 s that break at every interval end
/// of every DOF (where q̈ may jump). Undefined or conflicting motion is an error.
pub fn torque_energy(m: &Mu, model: &Model, gravity: Option<Vector3<f64>>) -> Result<f64, SpError> {
    check_conflicts(m)?;
    check_names(m, model)?;
    let gravity = gravity.unwrap_or(model.default_gravity);
    let Some((s, e)) = m.span() else {
        return Err(invalid(
            "torque_energy of an empty motion: it defines no DOF anywhere",
        ));
    };
    let root = RootCoords::detect_in(model, &gravity, m);
    let weights = joint_weights(model, &root);
    let names = model.coordinate_names();
    let mut breaks = vec![s, e];
    for n in names {
        if let Some(d) = m.get(n) {
            for iv in &d.intervals {
                breaks.push(iv.start);
                breaks.push(iv.stop);
            }
        }
    }
    breaks.sort_by(f64::total_cmp);
    breaks.dedup_by(|a, b| (*a - *b).abs() <= crate::motion::time_tol(*b));
    let rule = GaussLegendre::new(ENERGY_POINTS).map_err(|e| invalid(e.to_string()))?;
    let body = BodyDynamics { model, gravity };
    let mut ws = body.workspace();
    let n = model.nq();
    let (mut q, mut v, mut a, mut tau) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut total = 0.0;
    for w in breaks.windows(2) {
        let pieces = ((w[1] - w[0]) / ENERGY_PIECE).ceil().max(1.0) as usize;
        for p in 0..pieces {
            let a0 = w[0] + (w[1] - w[0]) * p as f64 / pieces as f64;
            let a1 = w[0] + (w[1] - w[0]) * (p + 1) as f64 / pieces as f64;
            let (ts, ws_) = rule.on(a0, a1);
            for (&t, &wq) in ts.iter().zip(&ws_) {
                for (i, name) in names.iter().enumerate() {
                    match m.sample(name, t).map_err(motion_err)? {
                        Some([x, dx, ddx]) => {
                            q[i] = x;
                            v[i] = dx;
                            a[i] = ddx;
                        }
                        None => {
                            return Err(SpError::Evaluation(format!(
                                "torque_energy: DOF '{name}' is undefined at t = {t}; fill the gap first (SP or fill(m, \"hermite\"))"
                            )));
                        }
                    }
                }
                body.torques(&mut ws, &q, &v, &a, &mut tau)?;
                total += wq
                    * tau
                        .iter()
                        .zip(&weights)
                        .map(|(t, w)| w * t * t)
                        .sum::<f64>();
            }
        }
    }
    Ok(total)
}
