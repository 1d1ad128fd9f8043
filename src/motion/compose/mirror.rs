//! `mirror`: left and right swapped by name (the rule of
//! [`super::super::channel::mirror_name`]) and the motion reflected.

use std::sync::Arc;

use super::super::channel::{mirror_dof, position_axis, rotation_axis};
use super::super::curve::{Curve, HermiteCurve, SampledCurve, TimeFunction};
use super::super::dof::Dof;
use super::super::error::{FnError, MotionError};
use super::super::func::Func;
use super::super::interval::Interval;
use super::super::mu::Mu;
use super::err;

/// `c` negated (exact: coefficients and samples negated, not resampled).
fn negated(c: &Curve) -> Result<Curve, MotionError> {
    Ok(match c {
        Curve::Constant(v) => Curve::Constant(-v),
        Curve::Samples(s) => Curve::Samples(SampledCurve::new(
            s.t0(),
            s.dt(),
            s.values().iter().map(|v| -v).collect(),
        )?),
        Curve::Hermite(h) => Curve::Hermite(HermiteCurve {
            q0: -h.q0,
            v0: -h.v0,
            q1: -h.q1,
            v1: -h.v1,
            ..h.clone()
        }),
        Curve::Spline(c) => {
            let mut c = c.clone();
            c.coeffs.iter_mut().for_each(|v| *v = -*v);
            Curve::Spline(c)
        }
        Curve::Sum(a, b) => Curve::Sum(Arc::new(negated(a)?), Arc::new(negated(b)?)),
        Curve::Function(g) => Curve::Function(Arc::new(Negated(g.clone()))),
    })
}

/// `d` with every value negated (exact: curves are negated, not resampled).
fn negate(d: &Dof) -> Result<Dof, MotionError> {
    let intervals = d
        .intervals
        .iter()
        .map(|i| {
            let funcs = i
                .funcs
                .iter()
                .map(|f| {
                    let curve = negated(&f.curve)?;
                    Ok(Func {
                        curve: Arc::new(curve),
                        shift: f.shift,
                        scale: f.scale,
                        offset: -f.offset,
                    })
                })
                .collect::<Result<_, MotionError>>()?;
            Ok(Interval {
                start: i.start,
                stop: i.stop,
                funcs,
            })
        })
        .collect::<Result<_, MotionError>>()?;
    Ok(Dof { intervals })
}

#[derive(Debug)]
struct Negated(Arc<dyn TimeFunction>);

impl TimeFunction for Negated {
    fn eval(&self, t: f64) -> Result<f64, FnError> {
        self.0.eval(t).map(|v| -v)
    }
}

/// `mirror(m, axis)`: left and right swapped by name and the motion reflected
/// in the plane normal to `axis` (0 = x, 1 = y, 2 = z): positions along the
/// axis and rotations about the two other axes change sign. Exact, and its
/// own inverse. `Err` when no DOF name has a side.
pub fn mirror(m: &Mu, axis: usize) -> Result<Mu, MotionError> {
    if !m.names().any(|n| mirror_dof(n).is_some()) {
        let few: Vec<&str> = m.names().take(4).collect();
        return Err(err(
            "mirror",
            format!(
                "no DOF name has a side to swap (names like `LeftArm.Xrotation`, `Arm_L.…`, `LArm.…`; this motion has {}…)",
                few.join(", ")
            ),
        ));
    }
    let mut out = Mu::new();
    for name in m.names() {
        let target = mirror_dof(name)
            .filter(|n| m.get(n).is_some())
            .unwrap_or_else(|| name.to_string());
        let src = &m.dofs[target.as_str()];
        let flip = if let Some(a) = rotation_axis(name) {
            a != axis
        } else {
            position_axis(name) == Some(axis)
        };
        out.insert(
            name.to_string(),
            if flip { negate(src)? } else { src.clone() },
        );
    }
    Ok(out)
}
