//! Quick gap filling, the kinematic baselines a spacetime transition (SP)
//! improves on and a cheap preview while editing: bridge every interior gap
//! of every DOF with the cubic Hermite curve that matches position and
//! velocity at both ends ([`fill_hermite`]), or with the interpolation of the
//! in-betweening literature ([`fill_slerp`]: each joint's rotation slerped as a
//! quaternion between the end poses, every other DOF linear).

use super::curve::{Curve, HermiteCurve};
use super::dof::Dof;
use super::error::MotionError;
use super::interval::Interval;
use super::mu::Mu;
use super::rotation::{self, EulerJoint};
use nalgebra::UnitQuaternion;
use std::sync::Arc;

/// `m` with every interior gap filled by a C¹ Hermite cubic. Ends stay
/// undefined. A conflict anywhere is an error (as for SP: resolve it first).
pub fn fill_hermite(m: &Mu) -> Result<Mu, MotionError> {
    let mut out = Mu::new();
    for (name, dof) in &m.dofs {
        let intervals = bridges(name, dof)?
            .into_iter()
            .map(|b| {
                let h = HermiteCurve::new(b.t0, b.q0, b.v0, b.t1, b.q1, b.v1)?;
                Interval::curve(Curve::Hermite(h), b.t0, b.t1)
            })
            .collect::<Result<Vec<_>, _>>()?;
        let filled = if intervals.is_empty() {
            dof.clone()
        } else {
            dof.plus(&Dof { intervals })
        };
        out.insert(name.clone(), filled);
    }
    Ok(out)
}

/// One gap of one DOF: its span and the values and velocities at its two ends.
#[derive(Clone, Copy, Debug)]
struct Bridge {
    t0: f64,
    t1: f64,
    q0: f64,
    q1: f64,
    v0: f64,
    v1: f64,
}

/// The interior gaps of `dof` with their end states; a conflict is an error.
fn bridges(name: &str, dof: &Dof) -> Result<Vec<Bridge>, MotionError> {
    if let Some(i) = dof.intervals.iter().find(|i| i.is_conflict()) {
        return Err(MotionError::Conflict {
            dof: name.to_string(),
            start: i.start,
            stop: i.stop,
            t: i.start,
        });
    }
    let mut out = vec![];
    for w in dof.intervals.windows(2) {
        let (l, r) = (&w[0], &w[1]);
        if r.start - l.stop <= super::time_tol(l.stop) {
            continue;
        }
        let [q0, v0, _] = l.first_func()?.eval(l.stop)?;
        let [q1, v1, _] = r.first_func()?.eval(r.start)?;
        out.push(Bridge {
            t0: l.stop,
            t1: r.start,
            q0,
            q1,
            v0,
            v1,
        });
    }
    Ok(out)
}

/// Steps of the path that keeps a slerped rotation's Euler channels
/// continuous (each step's angles are chosen nearest the previous step's).
const SLERP_TRACK_STEPS: usize = 64;

/// The slerp between two joint rotations over [t0, t1], and the continuous
/// Euler path it traces (for choosing, at any time, the Euler triple that
/// continues the curve).
#[derive(Debug)]
struct SlerpPath {
    t0: f64,
    t1: f64,
    axes: [usize; 3],
    from: UnitQuaternion<f64>,
    to: UnitQuaternion<f64>,
    track: Vec<[f64; 3]>,
}

impl SlerpPath {
    fn new(t0: f64, t1: f64, axes: [usize; 3], start: [f64; 3], end: [f64; 3]) -> SlerpPath {
        let from = rotation::from_euler(axes, start);
        let to = rotation::align_sign(&from, &rotation::from_euler(axes, end));
        let mut track = vec![start];
        for k in 1..=SLERP_TRACK_STEPS {
            let s = k as f64 / SLERP_TRACK_STEPS as f64;
            let prev = track[k - 1];
            track.push(rotation::to_euler_near(
                axes,
                &rotation::slerp(&from, &to, s),
                prev,
            ));
        }
        SlerpPath {
            t0,
            t1,
            axes,
            from,
            to,
            track,
        }
    }

    fn euler_at(&self, t: f64) -> [f64; 3] {
        let s = ((t - self.t0) / (self.t1 - self.t0)).clamp(0.0, 1.0);
        let x = s * SLERP_TRACK_STEPS as f64;
        let k = (x.floor() as usize).min(SLERP_TRACK_STEPS - 1);
        let f = x - k as f64;
        let near: [f64; 3] =
            std::array::from_fn(|i| self.track[k][i] * (1.0 - f) + self.track[k + 1][i] * f);
        rotation::to_euler_near(self.axes, &rotation::slerp(&self.from, &self.to, s), near)
    }
}

/// One Euler channel of a [`SlerpPath`], as a curve of time.
#[derive(Debug)]
struct SlerpChannel {
    path: Arc<SlerpPath>,
    index: usize,
}

impl super::curve::TimeFunction for SlerpChannel {
    fn eval(&self, t: f64) -> Result<f64, super::error::FnError> {
        Ok(self.path.euler_at(t)[self.index])
    }
}

/// `fill(m, "slerp")`: the interpolation baseline of the in-betweening
/// literature (Harvey et al. 2020: root positions linear, joint rotations
/// slerped). Every joint whose three rotation channels share a gap has its
/// rotation slerped between the end poses (as unit quaternions, the shorter
/// arc) and written back as continuous Euler channels in the joint's own
/// order; every other DOF is linear between its end values. Exact at the
/// gap ends in value (not in velocity). Ends stay undefined; a conflict is an error.
pub fn fill_slerp(m: &Mu) -> Result<Mu, MotionError> {
    let mut gaps: indexmap::IndexMap<&str, Vec<Bridge>> = indexmap::IndexMap::new();
    for (name, dof) in &m.dofs {
        gaps.insert(name, bridges(name, dof)?);
    }
    let mut fill: indexmap::IndexMap<&str, Vec<Interval>> = indexmap::IndexMap::new();
    for EulerJoint { dofs, axes, .. } in rotation::euler_joints(m.names()) {
        // the names as `m` holds them (so the maps can borrow them from `m`)
        let key = |n: &String| m.dofs.get_key_value(n).map(|(k, _)| k.as_str());
        let (Some(a), Some(b), Some(c)) = (key(&dofs[0]), key(&dofs[1]), key(&dofs[2])) else {
            continue;
        };
        let same = |x: &Bridge, y: &Bridge| {
            (x.t0 - y.t0).abs() <= super::time_tol(x.t0)
                && (x.t1 - y.t1).abs() <= super::time_tol(x.t1)
        };
        let mut joint_gaps = vec![];
        for g in &gaps[a] {
            let gb = gaps[b].iter().find(|y| same(g, y));
            let gc = gaps[c].iter().find(|y| same(g, y));
            if let (Some(gb), Some(gc)) = (gb, gc) {
                joint_gaps.push([*g, *gb, *gc]);
            }
        }
        for [ga, gb, gc] in joint_gaps {
            let path = Arc::new(SlerpPath::new(
                ga.t0,
                ga.t1,
                axes,
                [ga.q0, gb.q0, gc.q0],
                [ga.q1, gb.q1, gc.q1],
            ));
            for (index, (name, g)) in [(a, ga), (b, gb), (c, gc)].into_iter().enumerate() {
                let f = Arc::new(SlerpChannel {
                    path: path.clone(),
                    index,
                });
                fill.entry(name)
                    .or_default()
                    .push(Interval::function(f, g.t0, g.t1)?);
                if let Some(list) = gaps.get_mut(name) {
                    list.retain(|x| !same(x, &g));
                }
            }
        }
    }
    linear_bridges(&gaps, &mut fill)?;
    Ok(with_fill(m, fill))
}

/// A straight line across every gap in `gaps`, added to `fill`.
fn linear_bridges<'a>(
    gaps: &indexmap::IndexMap<&'a str, Vec<Bridge>>,
    fill: &mut indexmap::IndexMap<&'a str, Vec<Interval>>,
) -> Result<(), MotionError> {
    for (name, list) in gaps {
        for g in list {
            let slope = (g.q1 - g.q0) / (g.t1 - g.t0);
            let h = HermiteCurve::new(g.t0, g.q0, slope, g.t1, g.q1, slope)?;
            fill.entry(name)
                .or_default()
                .push(Interval::curve(Curve::Hermite(h), g.t0, g.t1)?);
        }
    }
    Ok(())
}

/// `fill(m, "linear")`: every interior gap of every DOF bridged by the
/// straight line between its end values, channel by channel (joint rotations
/// included: use `fill_slerp` to interpolate rotations as rotations). Ends
/// stay undefined; a conflict is an error.
pub fn fill_linear(m: &Mu) -> Result<Mu, MotionError> {
    let mut gaps: indexmap::IndexMap<&str, Vec<Bridge>> = indexmap::IndexMap::new();
    for (name, dof) in &m.dofs {
        gaps.insert(name, bridges(name, dof)?);
    }
    let mut fill = indexmap::IndexMap::new();
    linear_bridges(&gaps, &mut fill)?;
    Ok(with_fill(m, fill))
}

/// `m` with the bridges of `fill` added to its DOFs.
fn with_fill(m: &Mu, fill: indexmap::IndexMap<&str, Vec<Interval>>) -> Mu {
    let mut out = m.clone();
    for (name, mut intervals) in fill {
        intervals.sort_by(|x, y| x.start.total_cmp(&y.start));
        if let Some(dof) = out.dofs.get_mut(name) {
            *dof = dof.plus(&Dof { intervals });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::{conflicts, gaps, minus};

    #[test]
    fn fills_interior_gaps_continuously() {
        let f = Curve::Hermite(HermiteCurve::new(0.0, 0.0, 1.0, 4.0, 2.0, -1.0).unwrap());
        let walk: Mu = [(
            "x".to_string(),
            Dof::from(Interval::curve(f, 0.0, 4.0).unwrap()),
        )]
        .into_iter()
        .collect();
        let hole: Mu = [(
            "x".to_string(),
            Dof::from(Interval::constant(0.0, 1.0, 2.5).unwrap()),
        )]
        .into_iter()
        .collect();
        let m = minus(&walk, &hole);
        assert_eq!(gaps(&m).len(), 1);
        let filled = fill_hermite(&m).unwrap();
        assert!(gaps(&filled).is_empty() && conflicts(&filled).is_empty());
        // Position and velocity continuous at both ends of the bridge.
        for t in [1.0, 2.5] {
            let a = m.sample("x", t).unwrap().unwrap();
            let e = 1e-7;
            let left = filled.sample("x", t - e).unwrap().unwrap();
            let right = filled.sample("x", t + e).unwrap().unwrap();
            assert!((left[0] - a[0]).abs() < 1e-6 && (right[0] - a[0]).abs() < 1e-6);
            assert!((left[1] - a[1]).abs() < 1e-5 && (right[1] - a[1]).abs() < 1e-5);
        }
    }

    #[test]
    fn conflicts_are_an_error() {
        let a: Mu = [(
            "x".to_string(),
            Dof::from(Interval::constant(0.0, 0.0, 2.0).unwrap()),
        )]
        .into_iter()
        .collect();
        let b: Mu = [(
            "x".to_string(),
            Dof::from(Interval::constant(1.0, 1.0, 3.0).unwrap()),
        )]
        .into_iter()
        .collect();
        assert!(matches!(
            fill_hermite(&crate::motion::plus(&a, &b)),
            Err(MotionError::Conflict { .. })
        ));
    }
}
