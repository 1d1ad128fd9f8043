//! The operators that mix poses: `blend`, `crossfade` (a blend with a
//! smoothstep weight after an `align`), `layer` (additive) and `mask`.

use std::sync::Arc;

use nalgebra::UnitQuaternion;

use super::super::curve::TimeFunction;
use super::super::error::{FnError, MotionError};
use super::super::mu::Mu;
use super::super::rotation;
use super::align::align_at;
use super::mix::{Mixer, group_axes, group_values, groups, mix};
use super::{Weight, bad_option, err, native_dt};

struct BlendMix<'a> {
    w: &'a Weight,
}

impl Mixer for BlendMix<'_> {
    fn weights(&self, t: f64) -> Result<Vec<f64>, MotionError> {
        let w = self.w.at("blend", t)?;
        Ok(vec![1.0 - w, w])
    }
    fn pick(&self, t: f64) -> Result<Option<usize>, MotionError> {
        let w = self.w.at("blend", t)?;
        Ok(if w == 0.0 {
            Some(0)
        } else if w == 1.0 {
            Some(1)
        } else {
            None
        })
    }
    fn rot(
        &self,
        _: usize,
        t: f64,
        qs: &[UnitQuaternion<f64>],
    ) -> Result<UnitQuaternion<f64>, MotionError> {
        let w = self.w.at("blend", t)?;
        Ok(if w == 0.0 {
            qs[0]
        } else if w == 1.0 {
            qs[1]
        } else {
            rotation::slerp_signed(&qs[0], &qs[1], w)
        })
    }
    fn whole(&self, same: bool) -> Option<usize> {
        match self.w {
            _ if same => Some(0),
            Weight::Const(w) if *w == 0.0 => Some(0),
            Weight::Const(w) if *w == 1.0 => Some(1),
            _ => None,
        }
    }
    fn scalar(&self, _: usize, t: f64, xs: &[f64]) -> Result<f64, MotionError> {
        let w = self.w.at("blend", t)?;
        Ok(if w == 1.0 {
            xs[1]
        } else {
            xs[0] + w * (xs[1] - xs[0])
        })
    }
}

/// `blend(a, b, w)`: where both define a DOF, a mixed toward b by w (joint
/// rotations slerped, other DOFs linear); where only one does, that one.
/// `Err` when a and b have no DOF in common or w leaves [0, 1].
pub fn blend(a: &Mu, b: &Mu, w: &Weight) -> Result<Mu, MotionError> {
    blend_dt(a, b, w, native_dt(&[a, b]))
}

fn blend_dt(a: &Mu, b: &Mu, w: &Weight, dt: f64) -> Result<Mu, MotionError> {
    if !a.names().any(|n| b.get(n).is_some()) {
        let few = |m: &Mu| m.names().take(4).collect::<Vec<_>>().join(", ");
        return Err(err(
            "blend",
            format!(
                "the motions have no DOF in common (a has {}…, b has {}…)",
                few(a),
                few(b)
            ),
        ));
    }
    if let Weight::Const(x) = w {
        w.at("blend", 0.0).map_err(|_| {
            bad_option(
                "blend",
                "w",
                format!("the weight must lie in [0, 1], got {x}"),
            )
        })?;
    }
    mix(&[a, b], &super::super::plus(a, b), &BlendMix { w }, dt)
}

/// The smoothstep 3s² − 2s³ from 0 at `t0` to 1 at `t1`, as a weight.
#[derive(Debug)]
struct Smoothstep {
    t0: f64,
    t1: f64,
}

impl TimeFunction for Smoothstep {
    fn eval(&self, t: f64) -> Result<f64, FnError> {
        let s = ((t - self.t0) / (self.t1 - self.t0)).clamp(0.0, 1.0);
        Ok(s * s * (3.0 - 2.0 * s))
    }
}

/// `crossfade(a, b, d)`: b aligned to a's root pose at a's end minus d,
/// started there, and blended from a to b over the overlap with a smoothstep
/// weight (zero slope at both ends, so value and velocity are continuous).
pub fn crossfade(a: &Mu, b: &Mu, d: f64, up: usize) -> Result<Mu, MotionError> {
    let (Some((a0, a1)), Some((b0, b1))) = (a.span(), b.span()) else {
        return Err(MotionError::EmptyMotion { op: "crossfade" });
    };
    if !(d.is_finite() && d > 0.0 && d <= (a1 - a0).min(b1 - b0)) {
        return Err(bad_option(
            "crossfade",
            "d",
            format!(
                "the overlap d must be positive and no longer than either motion ({} s and {} s), got {d}",
                a1 - a0,
                b1 - b0
            ),
        ));
    }
    let t0 = a1 - d;
    let shifted = super::super::affine(t0 - b0, 1.0, b)?;
    let aligned = align_at(a, t0, &shifted, up)?;
    let w = Weight::Func(Arc::new(Smoothstep { t0, t1: a1 }));
    blend_dt(a, &aligned, &w, native_dt(&[a, b]))
}

struct LayerMix {
    w: f64,
    refs: Vec<Vec<f64>>,
    axes: Vec<Option<[usize; 3]>>,
}

impl Mixer for LayerMix {
    fn weights(&self, _: f64) -> Result<Vec<f64>, MotionError> {
        Ok(vec![1.0, self.w])
    }
    fn rot(
        &self,
        g: usize,
        _: f64,
        qs: &[UnitQuaternion<f64>],
    ) -> Result<UnitQuaternion<f64>, MotionError> {
        let r = &self.refs[g];
        let axes = self.axes[g].unwrap_or([0, 1, 2]);
        let q_ref = rotation::from_euler(axes, [r[0], r[1], r[2]]);
        let d = q_ref.inverse() * qs[1];
        let d = rotation::align_sign(&UnitQuaternion::identity(), &d);
        Ok(qs[0] * rotation::pow_signed(&d, self.w))
    }
    fn scalar(&self, g: usize, _: f64, xs: &[f64]) -> Result<f64, MotionError> {
        Ok(xs[0] + self.w * (xs[1] - self.refs[g][0]))
    }
    fn whole(&self, _: bool) -> Option<usize> {
        (self.w == 0.0).then_some(0)
    }
}

/// `layer(base, delta, w, reference)`: additive animation. Each joint's
/// rotation becomes base · (ref⁻¹·delta)^w and each scalar base + w·(delta −
/// ref), where ref is `reference`'s first frame (default: delta's first frame).
pub fn layer(base: &Mu, delta: &Mu, w: f64, reference: Option<&Mu>) -> Result<Mu, MotionError> {
    Weight::Const(w).at("layer", 0.0)?;
    let common: Vec<&str> = base.names().filter(|n| delta.get(n).is_some()).collect();
    if common.is_empty() {
        return Err(err("layer", "the base and the delta have no DOF in common"));
    }
    let reference = reference.unwrap_or(delta);
    let Some((r0, _)) = reference.span() else {
        return Err(MotionError::EmptyMotion { op: "layer" });
    };
    let gs = groups(&common);
    let refs = group_values(reference, &gs, r0, "layer")?;
    let axes = group_axes(&gs);
    mix(
        &[base, delta],
        base,
        &LayerMix { w, refs, axes },
        native_dt(&[base, delta]),
    )
}

struct MaskMix {
    w: f64,
    refs: Vec<Vec<f64>>,
    axes: Vec<Option<[usize; 3]>>,
}

impl Mixer for MaskMix {
    fn weights(&self, _: f64) -> Result<Vec<f64>, MotionError> {
        Ok(vec![self.w])
    }
    fn rot(
        &self,
        g: usize,
        _: f64,
        qs: &[UnitQuaternion<f64>],
    ) -> Result<UnitQuaternion<f64>, MotionError> {
        let r = &self.refs[g];
        let q_ref = rotation::from_euler(self.axes[g].unwrap_or([0, 1, 2]), [r[0], r[1], r[2]]);
        Ok(rotation::slerp(&q_ref, &qs[0], self.w))
    }
    fn scalar(&self, g: usize, _: f64, xs: &[f64]) -> Result<f64, MotionError> {
        Ok(self.refs[g][0] + self.w * (xs[0] - self.refs[g][0]))
    }
    fn whole(&self, _: bool) -> Option<usize> {
        (self.w == 1.0).then_some(0)
    }
}

/// `mask(m, patterns, w)`: the DOFs matching `patterns` with their motion
/// away from the reference pose (m's first frame) scaled by w (w = 1: m,
/// w = 0: held at the reference); the other DOFs unchanged.
pub fn mask(m: &Mu, patterns: &[&str], w: f64) -> Result<Mu, MotionError> {
    Weight::Const(w).at("mask", 0.0)?;
    let picked = super::super::only(m, patterns)?;
    let Some((t0, _)) = picked.span() else {
        return Err(MotionError::EmptyMotion { op: "mask" });
    };
    let gs = groups(&picked.names().collect::<Vec<_>>());
    let refs = group_values(&picked, &gs, t0, "mask")?;
    let axes = group_axes(&gs);
    let scaled = mix(
        &[&picked],
        &picked,
        &MaskMix { w, refs, axes },
        native_dt(&[m]),
    )?;
    let mut out = m.clone();
    for (n, d) in scaled.dofs {
        out.insert(n, d);
    }
    Ok(out)
}
