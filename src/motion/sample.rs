//! Sampling: a DOF's value (and derivatives) at a time, and whole motions on a
//! uniform grid of times k/R.
//!
//! At a touching endpoint (one interval stops where the next starts) the
//! instant belongs to both; a singly defined interval is preferred over a
//! conflict, and among singly defined ones the interval that *starts* there
//! (right-continuity, as a motion "switches" at that instant).

use super::dof::Dof;
use super::error::MotionError;
use super::interval::Interval;
use super::mu::Mu;
use crate::cancel::CancelToken;

/// What a DOF holds at one instant.
#[derive(Clone, Copy, Debug)]
pub enum Located<'a> {
    Undefined,
    Single(&'a Interval),
    Conflict(&'a Interval),
}

impl Dof {
    /// The interval that defines the DOF at `t` (see the module note on endpoints).
    pub fn locate(&self, t: f64) -> Located<'_> {
        // First interval whose (tolerant) stop is ≥ t; then it and at most one
        // touching successor can contain t.
        let k = self
            .intervals
            .partition_point(|i| i.stop + super::time_tol(i.stop) < t);
        self.locate_from(k, t)
    }

    /// `locate` given the index of the first interval that does not end before `t`.
    fn locate_from(&self, k: usize, t: f64) -> Located<'_> {
        let mut best: Option<&Interval> = None;
        for i in self.intervals[k..].iter().take(2) {
            if !i.contains(t) {
                continue;
            }
            best = match best {
                None => Some(i),
                Some(b) if b.is_conflict() && !i.is_conflict() => Some(i),
                Some(b) if b.is_conflict() == i.is_conflict() => Some(i), // the later one starts at t
                keep => keep,
            };
        }
        match best {
            None => Located::Undefined,
            Some(i) if i.is_conflict() => Located::Conflict(i),
            Some(i) => Located::Single(i),
        }
    }

    /// `[q, q̇, q̈]` at `t`; `Ok(None)` where undefined; `Err` in a conflict
    /// (named `dof_name`) or if the curve fails.
    pub fn sample(&self, dof_name: &str, t: f64) -> Result<Option<[f64; 3]>, MotionError> {
        check_time(t)?;
        match self.locate(t) {
            Located::Undefined => Ok(None),
            Located::Single(i) => Ok(Some(
                i.first_func()?.eval(t).map_err(|e| of_dof(e, dof_name))?,
            )),
            Located::Conflict(i) => Err(conflict(dof_name, i, t)),
        }
    }

    /// Values at ascending `times` (as `sample_value` at each), walking the
    /// intervals once instead of searching for every time.
    pub fn sample_values_sorted(
        &self,
        dof_name: &str,
        times: &[f64],
    ) -> Result<Vec<Option<f64>>, MotionError> {
        let mut out = Vec::with_capacity(times.len());
        let mut k = 0;
        for &t in times {
            while k < self.intervals.len()
                && self.intervals[k].stop + super::time_tol(self.intervals[k].stop) < t
            {
                k += 1;
            }
            out.push(match self.locate_from(k, t) {
                Located::Undefined => None,
                Located::Single(i) => {
                    Some(i.first_func()?.value(t).map_err(|e| of_dof(e, dof_name))?)
                }
                Located::Conflict(i) => return Err(conflict(dof_name, i, t)),
            });
        }
        Ok(out)
    }

    /// The value only (one curve evaluation).
    pub fn sample_value(&self, dof_name: &str, t: f64) -> Result<Option<f64>, MotionError> {
        check_time(t)?;
        match self.locate(t) {
            Located::Undefined => Ok(None),
            Located::Single(i) => Ok(Some(
                i.first_func()?.value(t).map_err(|e| of_dof(e, dof_name))?,
            )),
            Located::Conflict(i) => Err(conflict(dof_name, i, t)),
        }
    }
}

/// A failing function of time names the DOF it was sampled for (the curve
/// itself does not know which DOF holds it).
fn of_dof(e: MotionError, dof_name: &str) -> MotionError {
    match e {
        MotionError::Function {
            t,
            message,
            dof: None,
        } => MotionError::Function {
            t,
            message,
            dof: Some(dof_name.to_string()),
        },
        other => other,
    }
}

fn check_time(t: f64) -> Result<(), MotionError> {
    if t.is_finite() {
        Ok(())
    } else {
        Err(MotionError::BadTime { t })
    }
}

fn conflict(dof: &str, i: &Interval, t: f64) -> MotionError {
    MotionError::Conflict {
        dof: dof.to_string(),
        start: i.start,
        stop: i.stop,
        t,
    }
}

impl Mu {
    /// `[q, q̇, q̈]` of DOF `name` at `t`. `Ok(None)`: undefined there —
    /// outside its intervals, or a DOF this motion does not name (undefined
    /// everywhere, as in Rose §4). `Err`: a conflict (naming the DOF and time
    /// span), a non-finite time or a curve failure. To treat an unknown name
    /// as a typo instead, look it up with [`Mu::dof`] (did-you-mean error).
    pub fn sample(&self, name: &str, t: f64) -> Result<Option<[f64; 3]>, MotionError> {
        match self.get(name) {
            Some(d) => d.sample(name, t),
            None => check_time(t).map(|_| None),
        }
    }

    pub fn sample_value(&self, name: &str, t: f64) -> Result<Option<f64>, MotionError> {
        match self.get(name) {
            Some(d) => d.sample_value(name, t),
            None => check_time(t).map(|_| None),
        }
    }
}

/// Refuse grids beyond this many rows (a typo like `rate: 1e9` should not eat memory).
pub const MAX_GRID_ROWS: f64 = 50_000_000.0;

/// The times k/R (integer k) inside [start, stop], both ends included when
/// they are multiples of 1/R. Computed as k/R, never by accumulating 1/R, so
/// there is no drift.
pub fn grid_times(span: (f64, f64), rate: f64) -> Result<Vec<f64>, MotionError> {
    if !(rate.is_finite() && rate > 0.0) {
        return Err(MotionError::BadRate { rate });
    }
    let (start, stop) = span;
    // Tolerance: start·R may be an integer plus rounding error.
    let k0 = (start * rate - 1e-9 * (start * rate).abs().max(1.0)).ceil();
    let k1 = (stop * rate + 1e-9 * (stop * rate).abs().max(1.0)).floor();
    if !(k0.is_finite() && k1.is_finite()) {
        return Err(MotionError::NonFinite {
            what: "sampling grid bound",
            value: k1,
        });
    }
    let rows = k1 - k0 + 1.0;
    if rows > MAX_GRID_ROWS {
        return Err(MotionError::TooManySamples {
            span: stop - start,
            rate,
            rows,
        });
    }
    if rows < 1.0 {
        return Ok(Vec::new());
    }
    Ok((0..rows as i64).map(|j| (k0 + j as f64) / rate).collect())
}

/// A motion sampled on a grid: `values[d][k]` is DOF `names[d]` at `times[k]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    pub names: Vec<String>,
    pub times: Vec<f64>,
    pub values: Vec<Vec<Option<f64>>>,
}

/// Sample every DOF's value at the times k/R inside the motion's span. An
/// empty motion gives no rows. `Err` on a conflict (naming DOF and span), a
/// failing curve, or cancellation.
pub fn sample_grid(m: &Mu, rate: f64, cancel: Option<&CancelToken>) -> Result<Grid, MotionError> {
    let times = match m.span() {
        Some(span) => grid_times(span, rate)?,
        None => {
            if !(rate.is_finite() && rate > 0.0) {
                return Err(MotionError::BadRate { rate });
            }
            Vec::new()
        }
    };
    let mut values = Vec::with_capacity(m.len());
    for (name, dof) in &m.dofs {
        if let Some(c) = cancel {
            c.check()?;
        }
        values.push(dof.sample_values_sorted(name, &times)?);
    }
    Ok(Grid {
        names: m.names().map(str::to_string).collect(),
        times,
        values,
    })
}

/// A clip's frames: its frame time ([`sample_period`]) and how many frames its
/// span holds (the multiples of the frame time in it, as [`grid_times`]
/// counts them, at least 1); `None` when no DOF is a sampled curve or nothing
/// is defined. Files written from `mu` (BVH, glTF, positions) have this many frames.
pub fn frames(mu: &Mu) -> Result<Option<(f64, usize)>, MotionError> {
    let (Some(dt), Some(span)) = (sample_period(mu), mu.span()) else {
        return Ok(None);
    };
    Ok(Some((dt, grid_times(span, 1.0 / dt)?.len().max(1))))
}

/// The frame time of the first sampled curve in `mu` (how a loaded clip was
/// sampled), if any.
pub fn sample_period(mu: &Mu) -> Option<f64> {
    mu.dofs
        .values()
        .flat_map(|d| &d.intervals)
        .flat_map(|i| &i.funcs)
        .find_map(|f| match f.curve.as_ref() {
            super::curve::Curve::Samples(s) => Some(s.dt() * f.scale),
            _ => None,
        })
}
