//! `resample`: every curve replaced by the spline through its samples at a rate.

use super::super::error::MotionError;
use super::super::mu::Mu;
use super::{grid, map_intervals, sampled};

/// `resample(m, rate)`: every interval of every DOF sampled at `rate` Hz on
/// its own span and replaced by the C² spline through the samples.
pub fn resample(m: &Mu, rate: f64) -> Result<Mu, MotionError> {
    if !(rate.is_finite() && rate > 0.0) {
        return Err(MotionError::BadRate { rate });
    }
    map_intervals(m, |name, i| {
        let times = grid(i.start, i.stop, 1.0 / rate);
        if times.len() > 50_000_000 {
            return Err(MotionError::TooManySamples {
                span: i.stop - i.start,
                rate,
                rows: times.len() as f64,
            });
        }
        if i.is_conflict() {
            return Err(MotionError::Conflict {
                dof: name.to_string(),
                start: i.start,
                stop: i.stop,
                t: i.start,
            });
        }
        let f = i.first_func()?;
        let v = times
            .iter()
            .map(|&t| f.value(t))
            .collect::<Result<Vec<f64>, _>>()?;
        Ok(Some(sampled(&times, v)?))
    })
}
