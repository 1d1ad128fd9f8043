//! `warp`: a motion played on another clock.

use std::sync::Arc;

use super::super::curve::{Curve, TimeFunction};
use super::super::error::{FnError, MotionError};
use super::super::func::Func;
use super::super::interval::Interval;
use super::super::mu::Mu;
use super::super::time_tol;
use super::{bad_option, grid, map_intervals, native_dt};

/// A motion's function seen through a time warp: t ↦ func(f(t)).
#[derive(Debug)]
struct Warped {
    func: Func,
    f: Arc<dyn TimeFunction>,
}

impl TimeFunction for Warped {
    fn eval(&self, t: f64) -> Result<f64, FnError> {
        let u = self.f.eval(t)?;
        Ok(self.func.value(u)?)
    }
}

fn call(f: &dyn TimeFunction, t: f64) -> Result<f64, MotionError> {
    match f.eval(t) {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(v) => Err(bad_option(
            "warp",
            "f",
            format!("the warp returned {v} at t = {t}, not a finite number"),
        )),
        Err(e) => Err(MotionError::Function {
            t,
            message: e.to_string(),
            dof: None,
        }),
    }
}

/// The time t in [lo, hi] with f(t) = target (f increasing there), by bisection.
fn invert(f: &dyn TimeFunction, target: f64, mut lo: f64, mut hi: f64) -> Result<f64, MotionError> {
    // exact where f fixes the target (the identity warp keeps m's span)
    if (lo..=hi).contains(&target) && call(f, target)? == target {
        return Ok(target);
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if call(f, mid)? < target {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= time_tol(hi) * 1e-3 {
            break;
        }
    }
    Ok(0.5 * (lo + hi))
}

/// `warp(m, f)`: m played on the clock f, out(t) = m(f(t)), for f strictly
/// increasing. The result is defined where f(t) falls in m's span; f is
/// checked on a grid of m's sample step over that domain, and where it is not
/// increasing the error names the time.
pub fn warp(m: &Mu, f: Arc<dyn TimeFunction>) -> Result<Mu, MotionError> {
    let Some((s, e)) = m.span() else {
        return Err(MotionError::EmptyMotion { op: "warp" });
    };
    // Bracket the domain [f⁻¹(s), f⁻¹(e)], starting from m's span.
    let (mut lo, mut hi) = (s, e);
    let width = (e - s).max(1.0);
    let mut grow = width;
    for _ in 0..60 {
        let (flo, fhi) = (call(f.as_ref(), lo)?, call(f.as_ref(), hi)?);
        if flo <= s && fhi >= e {
            break;
        }
        if flo > s {
            lo -= grow;
        }
        if fhi < e {
            hi += grow;
        }
        grow *= 2.0;
    }
    if call(f.as_ref(), lo)? > s || call(f.as_ref(), hi)? < e {
        return Err(bad_option(
            "warp",
            "f",
            format!(
                "the warp never reaches m's span [{s}, {e}] (f({lo}) = {}, f({hi}) = {})",
                call(f.as_ref(), lo)?,
                call(f.as_ref(), hi)?
            ),
        ));
    }
    let d0 = invert(f.as_ref(), s, lo, hi)?;
    let d1 = invert(f.as_ref(), e, lo, hi)?;
    let times = grid(d0, d1, native_dt(&[m]) / 4.0);
    let mut prev = call(f.as_ref(), times[0])?;
    for w in times.windows(2) {
        let v = call(f.as_ref(), w[1])?;
        if v <= prev {
            return Err(bad_option(
                "warp",
                "f",
                format!(
                    "the warp must be strictly increasing, but f({}) = {prev} and f({}) = {v}",
                    w[0], w[1]
                ),
            ));
        }
        prev = v;
    }
    map_intervals(m, |_, i| {
        let a = if (i.start - s).abs() <= time_tol(s) {
            d0
        } else {
            invert(f.as_ref(), i.start, d0, d1)?
        };
        let b = if (i.stop - e).abs() <= time_tol(e) {
            d1
        } else {
            invert(f.as_ref(), i.stop, d0, d1)?
        };
        if b - a <= time_tol(a) {
            return Ok(None);
        }
        let funcs = i
            .funcs
            .iter()
            .map(|func| {
                Func::new(Curve::Function(Arc::new(Warped {
                    func: func.clone(),
                    f: f.clone(),
                })))
            })
            .collect();
        Ok(Some(Interval {
            start: a,
            stop: b,
            funcs,
        }))
    })
}
