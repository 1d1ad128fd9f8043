//! The motion algebra on motion units (Rose 1996 §4), pushed down to DOFs
//! and from there to intervals (see `dof.rs`).
//!
//! Names: `∧` keeps the DOFs both operands name (a DOF missing from one
//! operand is undefined there, so the intersection is empty); `−` and `+`
//! keep every DOF of either, `a`'s first, then `b`'s new ones — the
//! first-definition order. A DOF may end up with no interval (still listed).

use glob::{MatchOptions, Pattern};

use super::dof::{Dof, check_affine};
use super::error::{MotionError, finite};
use super::mu::Mu;
use super::time_tol;

/// `a ∧ b`: where both are defined, carrying the functions of both.
pub fn and(a: &Mu, b: &Mu) -> Mu {
    a.dofs
        .iter()
        .filter_map(|(name, da)| Some((name.clone(), da.and(b.dofs.get(name)?))))
        .collect()
}

/// `a − b`: where exactly one is defined, each part keeping its own functions.
pub fn minus(a: &Mu, b: &Mu) -> Mu {
    union_with(a, b, Dof::minus)
}

/// `a + b` = `(a − b), (a ∧ b)`: the union; overlaps are multiply defined (conflicts).
pub fn plus(a: &Mu, b: &Mu) -> Mu {
    union_with(a, b, Dof::plus)
}

fn union_with(a: &Mu, b: &Mu, op: impl Fn(&Dof, &Dof) -> Dof) -> Mu {
    let empty = Dof::empty();
    let mut out = Mu::new();
    for (name, da) in &a.dofs {
        out.insert(name.clone(), op(da, b.dofs.get(name).unwrap_or(&empty)));
    }
    for (name, db) in &b.dofs {
        if !a.dofs.contains_key(name) {
            out.insert(name.clone(), op(&empty, db));
        }
    }
    out
}

/// Time t ↦ ts + d·t for every DOF; values at the pre-image time, so first
/// and second derivatives scale by 1/d and 1/d². `Err` unless d > 0 and both are finite.
pub fn affine(ts: f64, d: f64, m: &Mu) -> Result<Mu, MotionError> {
    check_affine(ts, d)?; // also for a motion with no DOF
    m.dofs
        .iter()
        .map(|(n, dof)| Ok((n.clone(), dof.affine(ts, d)?)))
        .collect()
}

/// Cut out [ts, tf] and move it to start at time 0.
pub fn clip(ts: f64, tf: f64, m: &Mu) -> Result<Mu, MotionError> {
    let cut = clip_in_place(ts, tf, m)?;
    Ok(cut
        .dofs
        .iter()
        .map(|(n, dof)| (n.clone(), dof.affine_unchecked(-ts, 1.0)))
        .collect())
}

/// Cut out [ts, tf], keeping its times. The window must lie inside the
/// motion's span (an error names both; add the motion's name with
/// [`MotionError::with_name`]).
pub fn clip_in_place(ts: f64, tf: f64, m: &Mu) -> Result<Mu, MotionError> {
    check_clip(ts, tf, m.span())?;
    Ok(m.dofs
        .iter()
        .map(|(n, dof)| (n.clone(), dof.window(ts, tf)))
        .collect())
}

/// The same checks for a single DOF (the language applies clip to DOFs and intervals too).
pub fn clip_dof(ts: f64, tf: f64, d: &Dof) -> Result<Dof, MotionError> {
    check_clip(ts, tf, d.span())?;
    Ok(d.window(ts, tf).affine_unchecked(-ts, 1.0))
}

pub fn clip_in_place_dof(ts: f64, tf: f64, d: &Dof) -> Result<Dof, MotionError> {
    check_clip(ts, tf, d.span())?;
    Ok(d.window(ts, tf))
}

fn check_clip(ts: f64, tf: f64, span: Option<(f64, f64)>) -> Result<(), MotionError> {
    finite("clip start time", ts)?;
    finite("clip stop time", tf)?;
    if tf <= ts {
        return Err(MotionError::ClipEmpty { ts, tf });
    }
    let span = span.ok_or(MotionError::EmptyMotion { op: "clip" })?;
    if ts < span.0 - time_tol(span.0) || tf > span.1 + time_tol(span.1) {
        return Err(MotionError::ClipOutside {
            ts,
            tf,
            span,
            name: None,
        });
    }
    Ok(())
}

/// `b` shifted to start where `a` ends, added to `a` (touching, so no
/// conflict). An empty operand contributes nothing.
pub fn concatenate(a: &Mu, b: &Mu) -> Mu {
    match (a.span(), b.span()) {
        (Some((_, end)), Some((start, _))) => {
            let shifted: Mu = b
                .dofs
                .iter()
                .map(|(n, d)| (n.clone(), d.affine_unchecked(end - start, 1.0)))
                .collect();
            plus(a, &shifted)
        }
        (None, _) => plus(a, b),
        (_, None) => plus(a, b),
    }
}

/// The DOFs whose names match any of `patterns` (exact names or globs such
/// as `RightArm*`), in `m`'s order. A pattern that matches nothing is an
/// error (almost always a typo).
pub fn only(m: &Mu, patterns: &[&str]) -> Result<Mu, MotionError> {
    let opts = MatchOptions {
        case_sensitive: true,
        require_literal_separator: false,
        require_literal_leading_dot: false,
    };
    let compiled: Vec<(&str, Option<Pattern>)> = patterns
        .iter()
        .map(|p| (*p, Pattern::new(p).ok()))
        .collect();
    let matches = |pat: &(&str, Option<Pattern>), name: &str| {
        pat.0 == name || pat.1.as_ref().is_some_and(|g| g.matches_with(name, opts))
    };
    for pat in &compiled {
        if !m.names().any(|n| matches(pat, n)) {
            let mut available: Vec<&str> = m.names().take(12).collect();
            if m.len() > 12 {
                available.push("…");
            }
            return Err(MotionError::NoMatch {
                pattern: pat.0.to_string(),
                available: available.join(", "),
            });
        }
    }
    Ok(m.dofs
        .iter()
        .filter(|(n, _)| compiled.iter().any(|p| matches(p, n)))
        .map(|(n, d)| (n.clone(), d.clone()))
        .collect())
}

/// Earliest start and latest stop over all DOFs.
pub fn span(m: &Mu) -> Option<(f64, f64)> {
    m.span()
}

/// A stretch of time on one DOF (a gap or a conflict).
#[derive(Clone, Debug, PartialEq)]
pub struct DofSpan {
    pub dof: String,
    pub start: f64,
    pub stop: f64,
}

/// Interior gaps of every DOF (undefined with defined motion on both sides):
/// what SP fills.
pub fn gaps(m: &Mu) -> Vec<DofSpan> {
    collect(m, Dof::gaps)
}

/// Multiply defined stretches of every DOF.
pub fn conflicts(m: &Mu) -> Vec<DofSpan> {
    collect(m, Dof::conflicts)
}

fn collect(m: &Mu, f: impl Fn(&Dof) -> Vec<(f64, f64)>) -> Vec<DofSpan> {
    m.dofs
        .iter()
        .flat_map(|(n, d)| {
            f(d).into_iter().map(move |(start, stop)| DofSpan {
                dof: n.clone(),
                start,
                stop,
            })
        })
        .collect()
}
