//! Intervals: a list of functions of time over [start, stop]. More than one
//! function means the interval is multiply defined (a conflict).

use std::sync::Arc;

use super::curve::{Curve, TimeFunction};
use super::error::{MotionError, finite};
use super::func::Func;
use super::time_tol;

/// `(f₁, …, fₙ, start, stop)` of Rose §4. Invariant (kept by the
/// constructors and every operation): finite times, `start < stop`, at least
/// one function. Intervals are closed: defined at both ends.
#[derive(Clone, Debug, PartialEq)]
pub struct Interval {
    pub start: f64,
    pub stop: f64,
    pub funcs: Vec<Func>,
}

impl Interval {
    /// One function over [start, stop]; `Err` for non-finite or empty spans.
    pub fn new(func: Func, start: f64, stop: f64) -> Result<Interval, MotionError> {
        Interval::with_funcs(vec![func], start, stop)
    }

    /// Several functions (multiply defined) over [start, stop].
    pub fn with_funcs(funcs: Vec<Func>, start: f64, stop: f64) -> Result<Interval, MotionError> {
        check_span(start, stop)?;
        if funcs.is_empty() {
            return Err(MotionError::NoFunction);
        }
        for f in &funcs {
            finite("time shift", f.shift)?;
            finite("value offset", f.offset)?;
            if !(f.scale.is_finite() && f.scale > 0.0) {
                return Err(MotionError::BadScale { d: f.scale });
            }
        }
        Ok(Interval { start, stop, funcs })
    }

    /// A constant value over [start, stop].
    pub fn constant(value: f64, start: f64, stop: f64) -> Result<Interval, MotionError> {
        Interval::new(Func::new(Curve::constant(value)?), start, stop)
    }

    /// A function of (global) time over [start, stop].
    pub fn function(
        f: Arc<dyn TimeFunction>,
        start: f64,
        stop: f64,
    ) -> Result<Interval, MotionError> {
        Interval::new(Func::new(Curve::Function(f)), start, stop)
    }

    /// A curve evaluated at global time over [start, stop].
    pub fn curve(c: Curve, start: f64, stop: f64) -> Result<Interval, MotionError> {
        Interval::new(Func::new(c), start, stop)
    }

    /// The first function; `Err(NoFunction)` for an interval built by hand with none.
    pub fn first_func(&self) -> Result<&Func, MotionError> {
        self.funcs.first().ok_or(MotionError::NoFunction)
    }

    pub fn duration(&self) -> f64 {
        self.stop - self.start
    }

    /// More than one function: sampling here is an error.
    pub fn is_conflict(&self) -> bool {
        self.funcs.len() > 1
    }

    /// Closed containment, with a tolerance of a few ulps of rounding
    /// (see [`time_tol`]) so grid times like k/R that land a rounding error
    /// outside an end still count as inside.
    pub fn contains(&self, t: f64) -> bool {
        t >= self.start - time_tol(self.start) && t <= self.stop + time_tol(self.stop)
    }

    /// The interval after time t ↦ ts + d·t (ts finite and d > 0 checked by
    /// the caller); `Err` if the image is not finite or shorter than the time
    /// resolution, or a function's time map overflows.
    pub(crate) fn affine_checked(&self, ts: f64, d: f64) -> Result<Interval, MotionError> {
        let out = self.affine(ts, d);
        let ok = out.start.is_finite()
            && out.stop.is_finite()
            && out.stop - out.start > time_tol(out.start)
            && out
                .funcs
                .iter()
                .all(|f| f.shift.is_finite() && f.scale.is_finite() && f.scale > 0.0);
        if ok {
            Ok(out)
        } else {
            Err(MotionError::AffineDegenerate {
                ts,
                d,
                start: self.start,
                stop: self.stop,
                new_start: out.start,
                new_stop: out.stop,
            })
        }
    }

    /// The interval after time t ↦ ts + d·t, unchecked (shifts with d = 1).
    pub(crate) fn affine(&self, ts: f64, d: f64) -> Interval {
        Interval {
            start: ts + d * self.start,
            stop: ts + d * self.stop,
            funcs: self.funcs.iter().map(|f| f.affine(ts, d)).collect(),
        }
    }
}

/// `Ok` when start and stop are finite and start < stop.
pub(crate) fn check_span(start: f64, stop: f64) -> Result<(), MotionError> {
    finite("interval start time", start)?;
    finite("interval stop time", stop)?;
    if stop <= start {
        return Err(MotionError::EmptyInterval { start, stop });
    }
    Ok(())
}
