//! Extrapolation: a motion extended past its span, by holding its first and
//! last poses (`hold(m, ts, tf)`) or by playing it periodically
//! (`loop(m, ts, tf)`).
//!
//! Intervals are finite by the algebra's invariant, so an extrapolation is
//! always to a stated span: "forever" is not a value, and every operation
//! downstream (sampling, span, SP) keeps working on finite pieces. The
//! extension is made of ordinary intervals: a hold adds a constant interval
//! before and after each DOF; a loop adds copies of each DOF's intervals
//! shifted by whole periods (the motion's span, the same for every DOF so
//! the joints stay in phase), cut at [ts, tf]. The copies share the
//! curves (`Func` maps, no resampling), and the motion itself is kept as
//! it is inside its span (at a seam, where a period ends and the next
//! begins, sampling gives the next period's start). A loop is seamless only where the motion is
//! cyclic (`cyclify` first); unlike `loop(m, n)` it replays drifting DOFs
//! (the root's travel) rather than continuing them.

use super::dof::Dof;
use super::error::MotionError;
use super::interval::Interval;
use super::mu::Mu;

/// How to extend a motion past its span.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Extrapolation {
    /// The first pose before, the last after.
    Hold,
    /// Periodic with the motion's span as period.
    Loop,
}

fn bad(op: &'static str, message: String) -> MotionError {
    MotionError::Compose { op, message }
}

/// `m` extended to cover [ts, tf] (which may also lie inside m's span: the
/// result is then cut to it).
pub fn extrapolate(m: &Mu, ts: f64, tf: f64, mode: Extrapolation) -> Result<Mu, MotionError> {
    let op = match mode {
        Extrapolation::Hold => "hold",
        Extrapolation::Loop => "loop",
    };
    if !(ts.is_finite() && tf.is_finite() && ts < tf) {
        return Err(bad(
            op,
            format!("the span [{ts}, {tf}] must be finite with ts < tf"),
        ));
    }
    let (a, b) = m
        .span()
        .ok_or_else(|| bad(op, "the motion is empty: no DOF is defined anywhere".into()))?;
    let period = b - a;
    if mode == Extrapolation::Loop && period <= 0.0 {
        return Err(bad(
            op,
            "the motion lasts no time: nothing to repeat".into(),
        ));
    }
    let mut out = Mu::new();
    for (name, dof) in &m.dofs {
        let Some((s, e)) = dof.span() else {
            out.insert(name.clone(), dof.clone());
            continue;
        };
        let d = match mode {
            Extrapolation::Hold => {
                let value = |t: f64| -> Result<f64, MotionError> {
                    dof.sample_value(name, t)?.ok_or_else(|| {
                        bad(
                            op,
                            format!("DOF `{name}` is undefined at its own end t = {t}"),
                        )
                    })
                };
                let mut parts = dof.intervals.clone();
                if ts < s {
                    parts.push(Interval::constant(value(s)?, ts, s)?);
                }
                if tf > e {
                    parts.push(Interval::constant(value(e)?, e, tf)?);
                }
                Dof::new(parts)?
            }
            Extrapolation::Loop => {
                // copies k·period for every k whose copy meets [ts, tf]
                // counted in f64 first: a huge span over a short motion must be an
                // error, not an i64 overflow
                let (k0, k1) = (((ts - b) / period).floor(), ((tf - a) / period).ceil());
                let copies = k1 - k0;
                if copies.is_nan() || copies > 100_000.0 {
                    return Err(bad(
                        op,
                        format!(
                            "[{ts}, {tf}] would need {} copies of the motion (at most 100000)",
                            k1 - k0
                        ),
                    ));
                }
                let (k0, k1) = (k0 as i64, k1 as i64);
                let mut parts = vec![];
                for k in k0..=k1 {
                    let shifted = if k == 0 {
                        dof.clone()
                    } else {
                        dof.affine(k as f64 * period, 1.0)?
                    };
                    parts.extend(shifted.intervals);
                }
                Dof::new(parts)?
            }
        };
        out.insert(name.clone(), d.window(ts, tf));
    }
    Ok(out)
}
