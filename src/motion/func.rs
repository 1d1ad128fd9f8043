//! A curve seen through an affine map of time and an offset of value. Time
//! operations (affine, clip, concatenate) edit the map instead of wrapping
//! the curve again, so any chain of them costs one evaluation.

use std::sync::Arc;

use super::curve::Curve;
use super::error::MotionError;

/// `value(t) = curve((t − shift) / scale) + offset`.
#[derive(Clone, Debug)]
pub struct Func {
    pub curve: Arc<Curve>,
    pub shift: f64,
    pub scale: f64,
    pub offset: f64,
}

impl Func {
    /// The curve evaluated at global time (identity map, no offset).
    pub fn new(curve: Curve) -> Func {
        Func::from_arc(Arc::new(curve))
    }

    pub fn from_arc(curve: Arc<Curve>) -> Func {
        Func {
            curve,
            shift: 0.0,
            scale: 1.0,
            offset: 0.0,
        }
    }

    /// The curve's own time at global time `t`.
    #[inline]
    pub fn local_time(&self, t: f64) -> f64 {
        (t - self.shift) / self.scale
    }

    /// Value, first and second derivative with respect to global time.
    pub fn eval(&self, t: f64) -> Result<[f64; 3], MotionError> {
        let [v, d, dd] = self.curve.eval(self.local_time(t))?;
        Ok([
            self.offset_value(v),
            d / self.scale,
            dd / (self.scale * self.scale),
        ])
    }

    pub fn value(&self, t: f64) -> Result<f64, MotionError> {
        Ok(self.offset_value(self.curve.value(self.local_time(t))?))
    }

    /// `v + offset`, except that no offset leaves `v` as it is: −0 + 0 would
    /// be +0, and a curve's −0 should sample (and print) as −0.
    #[inline]
    fn offset_value(&self, v: f64) -> f64 {
        if self.offset == 0.0 {
            v
        } else {
            v + self.offset
        }
    }

    /// The same function after time t ↦ ts + d·t: the new function at the
    /// image time equals the old one at the pre-image (t − ts)/d.
    pub fn affine(&self, ts: f64, d: f64) -> Func {
        Func {
            curve: self.curve.clone(),
            shift: ts + d * self.shift,
            scale: d * self.scale,
            offset: self.offset,
        }
    }

    /// Exact structural equality (bit-equal maps, same curve).
    pub fn same_as(&self, other: &Func) -> bool {
        self.shift.to_bits() == other.shift.to_bits()
            && self.scale.to_bits() == other.scale.to_bits()
            && self.offset.to_bits() == other.offset.to_bits()
            && (Arc::ptr_eq(&self.curve, &other.curve) || self.curve.same_as(&other.curve))
    }
}

impl PartialEq for Func {
    fn eq(&self, other: &Self) -> bool {
        self.same_as(other)
    }
}
