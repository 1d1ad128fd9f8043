//! A motion laid on a new frame grid: what the in-betweening protocol reads
//! a clip captured at another rate through (`inbetween::Case::load_at`), and
//! what makes the held-out clips played faster or slower (`heldout`). A leaf
//! of `report`, so both can use it without importing each other.

use super::error::ReportError;
use crate::motion::{Curve, Dof, Interval, Mu};

/// `mu` played `speed` times as fast, sampled every `dt` s from t = 0 over
/// the `span` seconds of `mu` it covers (`speed` 1: resampled only); each
/// DOF becomes one sampled curve. Returns the motion and its frame count.
pub fn regrid(mu: &Mu, span: f64, speed: f64, dt: f64) -> Result<(Mu, usize), ReportError> {
    if !(speed.is_finite() && speed > 0.0 && dt.is_finite() && dt > 0.0 && span >= 0.0) {
        return Err(ReportError::Grid {
            speed,
            step: dt,
            span,
        });
    }
    // frames whose source time k·dt·speed stays within the span (to rounding)
    let frames = (span / (speed * dt) + 1e-6).floor() as usize + 1;
    let mut out = Mu::new();
    for (name, _) in &mu.dofs {
        let mut values = Vec::with_capacity(frames);
        for k in 0..frames {
            let t = (k as f64 * dt * speed).min(span);
            let Some(s) = mu.sample(name, t)? else {
                return Err(ReportError::Undefined {
                    dof: name.clone(),
                    t,
                });
            };
            values.push(s[0]);
        }
        let curve = Curve::samples(0.0, dt, values)?;
        let interval = Interval::curve(curve, 0.0, (frames - 1) as f64 * dt)?;
        out.insert(name.clone(), Dof::new(vec![interval])?);
    }
    Ok((out, frames))
}
