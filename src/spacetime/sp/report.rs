//! What SP did ([`SpReport`]), one list per stage, and how it prints.

use crate::spacetime::contact::ContactPlan;
use crate::spacetime::hold::HeldFrame;
use crate::spacetime::reference::Example;
use crate::spacetime::solve::{GapReport, GroundSettings};
use std::fmt;

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
    /// The largest mismatch `"auto"` pins ([`super::root_tolerance`]).
    pub tolerance: f64,
}

/// A gap of the root left open for the transitions (grounded SP, `root:
/// "auto"` inside one recording): its coordinates are unknowns of the solve,
/// the frames after the gap stay where they were recorded.
#[derive(Clone, Debug, PartialEq)]
pub struct FreeRoot {
    pub t0: f64,
    pub t1: f64,
    /// The root coordinates solved over it.
    pub dofs: Vec<String>,
}

/// A stretch of a gap where no contact point is planned to stand for
/// longer than [`MAX_AIR`]: the body is in the air there unless it is a
/// jump, and SP says so (issue 42: never left silently in the air).
#[derive(Clone, Debug, PartialEq)]
pub struct Unplanned {
    pub t0: f64,
    pub t1: f64,
}

/// Longest stretch (s) with no point planned to stand that is not named:
/// twice a run's flight (0.1–0.15 s).
pub const MAX_AIR: f64 = 0.3;

/// The stretches of `plan`'s gap where no point stands for longer than
/// [`MAX_AIR`].
pub fn unplanned(plan: &crate::spacetime::contact::GapPlan) -> Vec<Unplanned> {
    let mut stances: Vec<(f64, f64)> = plan
        .points
        .iter()
        .flat_map(|p| p.stances.iter().map(|s| (s.t0, s.t1)))
        .collect();
    stances.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out = vec![];
    let mut covered = plan.t0;
    for (a, b) in stances.into_iter().chain([(plan.t1, plan.t1)]) {
        if a - covered > MAX_AIR {
            out.push(Unplanned { t0: covered, t1: a });
        }
        covered = covered.max(b);
    }
    out
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
    /// Gaps of the root solved with the rest (grounded SP).
    pub free_root: Vec<FreeRoot>,
    /// The contact plan (`contact:` other than `"none"`, under gravity, on
    /// a motion with a recorded part), from [`super::Filling::contacts`].
    pub contacts: Option<ContactPlan>,
    /// Translation DOFs constant on both sides of their gap (bone offsets),
    /// held at that constant rather than optimised.
    pub constant: Vec<Undefined>,
    /// When the body stood: the settings its groups were solved with.
    pub ground: Option<GroundSettings>,
    /// Stretches no plan source could plant a point in ([`unplanned`]).
    pub unplanned: Vec<Unplanned>,
}

impl fmt::Display for SpReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.groups.is_empty()
            && self.root.is_empty()
            && self.free_root.is_empty()
            && self.hermite.is_empty()
            && self.constant.is_empty()
        {
            writeln!(f, "SP: no interior gaps (nothing to fill)")?;
        }
        for (i, g) in self.groups.iter().enumerate() {
            write_group(f, i, g)?;
        }
        self.write_root(f)?;
        self.write_held(f)?;
        self.write_interpolated(f)
    }
}

impl SpReport {
    /// The root's lines: shifted and pinned gaps.
    fn write_root(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
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
        for r in &self.free_root {
            writeln!(
                f,
                "root over [{:.4}, {:.4}] s: solved with the body under the ground's forces ({}), the motion after the gap where it was",
                r.t0,
                r.t1,
                r.dofs.join(", ")
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
        Ok(())
    }

    /// Support frames held and contacts planned.
    fn write_held(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
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
        let Some(plan) = &self.contacts else {
            return Ok(());
        };
        if let Some(g) = &self.ground {
            writeln!(f, "ground: {}", g.describe())?;
        }
        for u in &self.unplanned {
            writeln!(
                f,
                "no contact point planned to stand over [{:.4}, {:.4}] s ({:.2} s in the air): give contact: stances there if the body stands",
                u.t0,
                u.t1,
                u.t1 - u.t0
            )?;
        }
        for g in &plan.gaps {
            for c in &g.points {
                if c.stances.is_empty() {
                    writeln!(
                        f,
                        "contact {} over [{:.4}, {:.4}] s: not planted (kept above the floor at {:.4} m)",
                        c.name, g.t0, g.t1, plan.floor.height
                    )?;
                }
                for p in &c.stances {
                    writeln!(
                        f,
                        "contact {} over [{:.4}, {:.4}] s: planted [{:.4}, {:.4}] s at ({:.3}, {:.3}, {:.3}){} ({}{})",
                        c.name,
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
                        },
                        p.source.name(),
                        match p.solved {
                            Some(e) => format!(", solved within {:.1} cm", 100.0 * e),
                            None => String::new(),
                        }
                    )?;
                }
            }
        }
        Ok(())
    }

    /// DOFs filled by Hermite curves, held constant, or left undefined.
    fn write_interpolated(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
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

/// One solved group's line.
fn write_group(f: &mut fmt::Formatter<'_>, i: usize, g: &GapReport) -> fmt::Result {
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
        100.0 * (g.energy - g.initial_energy) / g.initial_energy.abs().max(f64::MIN_POSITIVE),
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
        example_clause(g),
        g.seconds * 1e3
    )
}

/// What the group's prior followed, or why no example.
fn example_clause(g: &GapReport) -> String {
    let fit = |ex: &Example| {
        ex.fit.map_or(String::new(), |f| {
            format!(
                ", laid {:.1} / {:.1} cm from the end states",
                100.0 * f.start,
                100.0 * f.end
            )
        })
    };
    let how = if g.tried.is_empty() {
        "prior follows"
    } else {
        "anchored on"
    };
    match &g.example {
        Some(ex @ Example { clip: Some(c), .. }) => format!(
            "; {how} clip `{}` from {:.3} s (warp {}) on {} of {} DOFs (mismatch {:.3}, features {:.3}{})",
            c.name,
            c.time,
            c.warp,
            ex.follow.len(),
            ex.of,
            ex.mismatch,
            c.features,
            fit(ex)
        ),
        Some(ex) => format!(
            "; {how} the motion {:+.3} s away on {} of {} DOFs (mismatch {:.3}{})",
            ex.shift,
            ex.follow.len(),
            ex.of,
            ex.mismatch,
            fit(ex)
        ),
        None => g
            .why_no_example()
            .map_or(String::new(), |why| format!("; no example ({why})")),
    }
}

fn abbreviate(names: &[String]) -> String {
    if names.len() <= 4 {
        names.join(", ")
    } else {
        format!("{}, … {}", names[..3].join(", "), names[names.len() - 1])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_empty_report_says_so_and_each_stage_has_its_line() {
        assert_eq!(
            SpReport::default().to_string(),
            "SP: no interior gaps (nothing to fill)\n"
        );
        let u = |dof: &str| Undefined {
            dof: dof.into(),
            start: 0.5,
            stop: 1.0,
        };
        let r = SpReport {
            hermite: vec![u("root.Yposition")],
            constant: vec![u("knee.Xposition")],
            undefined: vec![u("toe")],
            ..Default::default()
        };
        let text = r.to_string();
        assert_eq!(text.lines().count(), 3, "{text}");
        assert!(text.contains("root.Yposition on [0.5000, 1.0000] s: root, cubic Hermite"));
        assert!(text.contains("held at its value"), "{text}");
        assert!(text.contains("toe stays undefined"), "{text}");
        assert_eq!(
            abbreviate(&["a".into(), "b".into(), "c".into(), "d".into(), "e".into()]),
            "a, b, c, … e"
        );
    }
}
