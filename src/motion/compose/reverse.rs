//! `reverse`: a motion played backwards over its own span.

use std::sync::Arc;

use super::super::curve::{Curve, TimeFunction};
use super::super::error::{FnError, MotionError};
use super::super::func::Func;
use super::super::interval::Interval;
use super::super::mu::Mu;
use super::map_intervals;

/// A function of time played backwards about `pivot`: t ↦ f(pivot − t).
#[derive(Debug)]
struct Reversed {
    func: Func,
    pivot: f64,
}

impl TimeFunction for Reversed {
    fn eval(&self, t: f64) -> Result<f64, FnError> {
        Ok(self.func.value(self.pivot - t)?)
    }
}

/// `reverse(m)`: time reversal over m's own span (t ↦ start + stop − t), so
/// velocities change sign. Sampled data is reversed exactly (the spline
/// through reversed samples is the reversed spline); other curves are
/// evaluated backwards. Its own inverse.
pub fn reverse(m: &Mu) -> Result<Mu, MotionError> {
    let Some((s, e)) = m.span() else {
        return Err(MotionError::EmptyMotion { op: "reverse" });
    };
    let pivot = s + e;
    map_intervals(m, |_, i| {
        let (a, b) = (pivot - i.stop, pivot - i.start);
        let funcs = i
            .funcs
            .iter()
            .map(|f| match f.curve.as_ref() {
                Curve::Constant(_) => Ok(f.clone()),
                Curve::Samples(c) if f.scale == 1.0 => {
                    // local time u = t − shift; reversed local time starts at pivot − shift − t_end
                    let mut v = c.values().to_vec();
                    v.reverse();
                    let t0 = pivot - 2.0 * f.shift - c.t_end();
                    Ok(Func {
                        curve: Arc::new(Curve::samples(t0, c.dt(), v)?),
                        shift: f.shift,
                        scale: 1.0,
                        offset: f.offset,
                    })
                }
                _ => Ok(Func::new(Curve::Function(Arc::new(Reversed {
                    func: f.clone(),
                    pivot,
                })))),
            })
            .collect::<Result<Vec<_>, MotionError>>()?;
        Ok(Some(Interval {
            start: a,
            stop: b,
            funcs,
        }))
    })
}
