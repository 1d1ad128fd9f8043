//! The animator's operators beyond Rose's algebra: `blend`, `crossfade`,
//! `align`, `layer`, `mask`, `mirror`, `reverse`, `warp`, `resample`.
//!
//! Operators that mix poses (blend, crossfade, layer, mask) work on every
//! Euler joint's rotation as a unit quaternion ([`super::rotation`]) and write
//! the result back as continuous Euler channels in the joint's own order: the
//! output is sampled on a uniform grid (the inputs' finest sample step, 120 Hz
//! when no input is sampled data) and each frame's Euler triple is chosen
//! nearest the previous frame's, advanced by the inputs' weighted increments.
//! Every other DOF (root translation, scalars) mixes linearly. A joint's
//! rotation is mixed where all its channels are defined in every input.
//!
//! `mirror` and `reverse` are exact (no resampling of sampled data): mirror
//! negates the two rotation channels about axes other than the mirror axis
//! and the position along it, reverse plays each curve backwards.
//!
//! One file per operator family: [`mix`] (the group-by-group pose mixer the
//! blends share), [`blend`] (blend, crossfade, layer, mask), [`align`],
//! [`mirror`], [`reverse`], [`warp`], [`resample`]; here the helpers they
//! share (weights, the output grid, sampled intervals, spans).

use std::sync::Arc;

use super::curve::{Curve, TimeFunction};
use super::dof::Dof;
use super::error::MotionError;
use super::interval::Interval;
use super::mu::Mu;
use super::time_tol;

mod align;
mod blend;
mod mirror;
mod mix;
mod resample;
mod reverse;
mod warp;

pub use super::channel::mirror_name;
pub use align::{align, align_at};
pub use blend::{blend, crossfade, layer, mask};
pub use mirror::mirror;
pub use resample::resample;
pub use reverse::reverse;
pub use warp::warp;

/// The output step when no input holds sampled data: 120 Hz.
pub const DEFAULT_RATE: f64 = 120.0;

pub(super) fn err(op: &'static str, message: impl Into<String>) -> MotionError {
    MotionError::Compose {
        op,
        message: message.into(),
    }
}

/// An error about one argument of `op`, named as the language names it.
pub(super) fn bad_option(
    op: &'static str,
    option: &'static str,
    message: impl Into<String>,
) -> MotionError {
    MotionError::InvalidOption {
        op,
        option,
        message: message.into(),
    }
}

/// A weight: a constant or a function of (global) time.
#[derive(Clone, Debug)]
pub enum Weight {
    Const(f64),
    Func(Arc<dyn TimeFunction>),
}

impl Weight {
    /// The weight at `t`, checked to lie in [0, 1].
    pub fn at(&self, op: &'static str, t: f64) -> Result<f64, MotionError> {
        let w = match self {
            Weight::Const(w) => *w,
            Weight::Func(f) => f.eval(t).map_err(|e| MotionError::Function {
                t,
                message: e.to_string(),
                dof: None,
            })?,
        };
        if !(0.0..=1.0).contains(&w) {
            return Err(bad_option(
                op,
                "w",
                format!("the weight must lie in [0, 1], got {w} at t = {t}"),
            ));
        }
        Ok(w)
    }
}

/// The finest sample step of the sampled data in `ms`, else 1/120 s.
pub fn native_dt(ms: &[&Mu]) -> f64 {
    let mut dt = f64::INFINITY;
    for m in ms {
        for d in m.dofs.values() {
            for i in &d.intervals {
                for f in &i.funcs {
                    if let Curve::Samples(s) = f.curve.as_ref() {
                        dt = dt.min(s.dt() * f.scale);
                    }
                }
            }
        }
    }
    if dt.is_finite() {
        dt
    } else {
        1.0 / DEFAULT_RATE
    }
}

/// Uniform times over [s, e], the step at most `dt` (both ends included).
fn grid(s: f64, e: f64, dt: f64) -> Vec<f64> {
    let n = (((e - s) / dt) - 1e-9).ceil().max(1.0) as usize;
    let h = (e - s) / n as f64;
    (0..=n)
        .map(|k| if k == n { e } else { s + k as f64 * h })
        .collect()
}

/// One sampled-data interval through `values` at `times` (a uniform grid).
pub(super) fn sampled(times: &[f64], values: Vec<f64>) -> Result<Interval, MotionError> {
    let (s, e) = (times[0], times[times.len() - 1]);
    let dt = (e - s) / (times.len() - 1) as f64;
    Interval::curve(Curve::samples(s, dt, values)?, s, e)
}

/// The maximal spans where every DOF of `dofs` is defined.
pub(super) fn common_spans(dofs: &[&Dof]) -> Vec<(f64, f64)> {
    let Some(first) = dofs.first() else {
        return vec![];
    };
    let mut acc = (*first).clone();
    for d in &dofs[1..] {
        acc = acc.and(d);
    }
    let mut out: Vec<(f64, f64)> = vec![];
    for i in &acc.intervals {
        match out.last_mut() {
            Some(last) if i.start - last.1 <= time_tol(last.1) => last.1 = i.stop,
            _ => out.push((i.start, i.stop)),
        }
    }
    out
}

/// `m` with every interval of every DOF (named) mapped by `f`, or dropped
/// where `f` gives `None`; the results sorted by time.
pub(super) fn map_intervals(
    m: &Mu,
    mut f: impl FnMut(&str, &Interval) -> Result<Option<Interval>, MotionError>,
) -> Result<Mu, MotionError> {
    let mut out = Mu::new();
    for (name, d) in &m.dofs {
        let mut intervals = vec![];
        for i in &d.intervals {
            if let Some(x) = f(name, i)? {
                intervals.push(x);
            }
        }
        intervals.sort_by(|x, y| x.start.total_cmp(&y.start));
        out.insert(name.clone(), Dof { intervals });
    }
    Ok(out)
}
