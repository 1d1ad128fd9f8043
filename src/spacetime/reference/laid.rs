//! A library stretch laid on the gap's clock: resampled over the gap and its
//! context, its moving root turned and moved onto the motion's.

use super::{CONTEXT, STEP};
use crate::ground::horizontal;
use crate::library::Match;
use crate::library::features::KeyJoints;
use crate::mocap::Clip;
use crate::motion::{Curve, Dof, Interval, MotionError, Mu};
use crate::spacetime::error::SpError;
use nalgebra::{Unit, UnitQuaternion, Vector3};
use std::collections::HashMap;

/// Sampling step (s) of a library example on the gap's clock: fine enough
/// that its cubic reproduces the clip's own 30–120 Hz curves.
pub(super) const EXAMPLE_STEP: f64 = 1.0 / 240.0;

/// The floor-plane map (rotation about up, then translation along the
/// floor) that takes a clip's pelvis at one frame onto the motion's at
/// another. Up is the one both skeletons stand along (`mocap::up`): y for
/// BVH's usual skeletons, z for a z-up one.
pub(super) struct FloorMap {
    up: Unit<Vector3<f64>>,
    /// The turn about up (rad).
    angle: f64,
    /// The clip's and the motion's pelvis centres on the floor (no height).
    from: Vector3<f64>,
    to: Vector3<f64>,
}

impl FloorMap {
    pub(super) fn between(
        a: &[Vector3<f64>; 6],
        b: &[Vector3<f64>; 6],
        up: &Vector3<f64>,
    ) -> FloorMap {
        let flat = |p: &[Vector3<f64>; 6]| {
            let c = (p[4] + p[5]) / 2.0;
            let across = horizontal(&(p[4] - p[5]), up);
            let n = across.norm().max(1e-12);
            (horizontal(&c, up), across / n)
        };
        let (ca, ua) = flat(a);
        let (cb, ub) = flat(b);
        FloorMap {
            up: Unit::new_normalize(*up),
            angle: up.dot(&ua.cross(&ub)).atan2(ua.dot(&ub)),
            from: ca,
            to: cb,
        }
    }

    /// The turn about up.
    pub(super) fn turn(&self) -> UnitQuaternion<f64> {
        UnitQuaternion::from_axis_angle(&self.up, self.angle)
    }

    /// A position of the clip's (m) where the motion has it: turned about up
    /// and moved along the floor; its height is kept.
    pub(super) fn apply(&self, p: &Vector3<f64>) -> Vector3<f64> {
        self.to + self.turn() * (p - self.from)
    }
}

fn ev(e: MotionError) -> SpError {
    SpError::Motion(e)
}

/// The joint that carries the body through the world: the first joint from
/// the skeleton's root down to the hips with position channels that move
/// (Bandai's all-zero `joint_Root` is skipped for its `Hips`).
fn moving_root(clip: &Clip, keys: &KeyJoints) -> Option<usize> {
    let sk = &clip.skeleton;
    let mut chain = vec![];
    let mut j = Some(keys.hips[0]);
    while let Some(i) = j {
        chain.push(i);
        j = sk.joints[i].parent;
    }
    let (lo, hi) = clip.mu.span()?;
    chain.into_iter().rev().find(|&i| {
        let jt = &sk.joints[i];
        jt.channels.iter().any(|c| !c.is_rotation())
            && jt.channels.iter().any(|c| {
                let name = format!("{}.{}", jt.name, c.name());
                let at = |k: usize| {
                    clip.mu
                        .sample_value(&name, lo + (hi - lo) * k as f64 / 8.0)
                        .ok()
                        .flatten()
                };
                (1..=8).any(|k| match (at(0), at(k)) {
                    (Some(a), Some(b)) => (a - b).abs() > 1e-9,
                    _ => false,
                })
            })
    })
}

/// The clip read on the gap's clock: sample k is at gap time
/// `from + k EXAMPLE_STEP`, clip time s + w (t − t0), clamped to the clip.
struct Clock<'a> {
    clip: &'a Clip,
    cand: &'a Match,
    t0: f64,
    from: f64,
    n: usize,
    span: (f64, f64),
}

impl Clock<'_> {
    fn sample(&self, name: &str, k: usize) -> Result<f64, SpError> {
        let t = self.from + k as f64 * EXAMPLE_STEP;
        let (lo, hi) = self.span;
        let at = (self.cand.time + self.cand.warp * (t - self.t0)).clamp(lo, hi);
        self.clip
            .mu
            .sample_value(name, at)
            .map_err(ev)
            .map(|v| v.unwrap_or(f64::NAN))
    }

    fn series(&self, name: &str) -> Result<Vec<f64>, SpError> {
        (0..self.n).map(|k| self.sample(name, k)).collect()
    }
}

/// The stretch of `clip` a match names, resampled on the gap's clock over
/// the gap and its context (clip time s + w (t − t0)), its moving root turned
/// about the vertical and moved in the floor plane by `map`; only the gap
/// coordinates. `m` gives the angles the root's turned Euler angles are
/// taken nearest to.
#[allow(clippy::too_many_arguments)]
pub(super) fn laid_on_gap(
    clip: &Clip,
    keys: &KeyJoints,
    cand: &Match,
    map: &FloorMap,
    m: &Mu,
    names: &[String],
    coords: &[usize],
    (t0, t1): (f64, f64),
) -> Result<Mu, SpError> {
    let from = t0 - CONTEXT - 2.0 * STEP;
    let n = ((t1 + CONTEXT + 2.0 * STEP - from) / EXAMPLE_STEP).ceil() as usize + 1;
    let clock = Clock {
        clip,
        cand,
        t0,
        from,
        n,
        span: clip.mu.span().unwrap_or((0.0, 0.0)),
    };
    let root = moving_root(clip, keys).map(|i| clip.skeleton.joints[i].name.clone());
    let mut aligned = match &root {
        Some(root) => aligned_root(&clock, root, map, m)?,
        None => HashMap::new(),
    };
    let mut out = Mu::new();
    for &c in coords {
        let name = &names[c];
        let v = match aligned.remove(name) {
            Some(v) => v,
            None => clock.series(name)?,
        };
        if v.iter().any(|x| !x.is_finite()) {
            continue;
        }
        let stop = from + (n - 1) as f64 * EXAMPLE_STEP;
        let curve = Curve::samples(from, EXAMPLE_STEP, v).map_err(ev)?;
        let iv = Interval::curve(curve, from, stop).map_err(ev)?;
        out.insert(name.to_string(), Dof::new(vec![iv]).map_err(ev)?);
    }
    Ok(out)
}

/// The moving root's position channels moved by `map` (one it lacks read as
/// 0 and not written: a root without a vertical slide), and its Euler
/// channels turned by the same angle about up (nearest `m`'s own angles at
/// t0, then outwards), by channel name.
fn aligned_root(
    clock: &Clock,
    root: &str,
    map: &FloorMap,
    m: &Mu,
) -> Result<HashMap<String, Vec<f64>>, SpError> {
    use crate::motion::rotation::{euler_joints, from_euler, to_euler_near};
    let mut aligned: HashMap<String, Vec<f64>> = HashMap::new();
    let names = ["Xposition", "Yposition", "Zposition"].map(|c| format!("{root}.{c}"));
    let series = names.each_ref().map(|n| clock.series(n).ok());
    if series.iter().filter(|s| s.is_some()).count() >= 2 {
        let at = |i: usize, k: usize| series[i].as_ref().map_or(0.0, |s| s[k]);
        let moved: Vec<Vector3<f64>> = (0..clock.n)
            .map(|k| map.apply(&Vector3::new(at(0, k), at(1, k), at(2, k))))
            .collect();
        for (i, n) in names.iter().enumerate() {
            if series[i].is_some() {
                aligned.insert(n.clone(), moved.iter().map(|p| p[i]).collect());
            }
        }
    }
    let dofs: Vec<String> = clock.clip.mu.names().map(String::from).collect();
    let turn = map.turn();
    let Some(ej) = euler_joints(dofs.iter().map(String::as_str))
        .into_iter()
        .find(|e| e.joint == root)
    else {
        return Ok(aligned);
    };
    let cols: Vec<Vec<f64>> = ej
        .dofs
        .iter()
        .map(|d| clock.series(d))
        .collect::<Result<_, _>>()?;
    let t0 = clock.t0;
    let mut near: [f64; 3] = std::array::from_fn(|i| {
        m.sample_value(&ej.dofs[i], t0)
            .ok()
            .flatten()
            .unwrap_or(cols[i][0])
    });
    // start at t0 (nearest m's own angles there), then outwards
    let k0 = ((t0 - clock.from) / EXAMPLE_STEP).round() as usize;
    let mut out = vec![[f64::NAN; 3]; clock.n];
    let mut turned = |k: usize, near: &mut [f64; 3]| {
        let q = turn * from_euler(ej.axes, [cols[0][k], cols[1][k], cols[2][k]]);
        let e = to_euler_near(ej.axes, &q, *near);
        *near = e;
        out[k] = e;
    };
    let start = near;
    for k in k0..clock.n {
        turned(k, &mut near);
    }
    near = start;
    for k in (0..k0).rev() {
        turned(k, &mut near);
    }
    for (i, d) in ej.dofs.iter().enumerate() {
        aligned.insert(d.clone(), out.iter().map(|e| e[i]).collect());
    }
    Ok(aligned)
}
