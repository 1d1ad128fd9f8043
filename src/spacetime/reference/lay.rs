//! An example's poses laid in the world over a group of gaps: the anchor SP's
//! example term pulls the transition to (`objective/example.rs`) and the
//! curve the transition is a correction of (`GapLayout::with_bases`).
//!
//! The example is the motion `shift` seconds away (`"self"`) or a library
//! stretch already on the gap's clock. Laying it takes two steps:
//! 1. **Aligned** (where the root is cut): the example's root is turned about
//!    the vertical and moved along the floor so that at the gap's start its
//!    heading and floor position are the motion's there, and likewise at the
//!    gap's end; between, the two alignments are blended (smoothstep), so a
//!    stride that is a little longer or turns a little more than the
//!    example's is spread over the gap, not put at one end.
//! 2. **Blended to the end states**: per DOF, the cubic Hermite curve of
//!    the remaining differences (position and velocity at both ends) is
//!    added, so the laid example meets the motion exactly at both ends and
//!    is the example itself where the two already agree.
//!
//! A DOF follows the example when its aligned example is within
//! [`super::MAX_END_DIFFERENCE`] (angles) or [`MAX_END_OFFSET`] (translations) of
//! the motion at both ends; a joint follows whole or not at all
//! ([`Joints::whole`]).

use super::blend::Blend;
use super::{Example, Joints, NoExample, wrap};
use crate::model::{Model, RootCoords};
use crate::motion::rotation::{euler_joints, from_euler, to_euler_near};
use crate::motion::{Curve, Dof, Interval, JointSampler, Mu};
use crate::spacetime::error::SpError;
use crate::spacetime::objective::GapDof;
use nalgebra::{Rotation3, Unit, UnitQuaternion, Vector3};
use std::collections::HashMap;
use std::f64::consts::{PI, TAU};
use std::sync::Arc;

/// Samples per second of a laid example: its interpolating spline then
/// reproduces the 30–120 Hz curves it is read from.
const LAY_RATE: f64 = 240.0;

/// Samples laid beyond each end of a gap, so the spline's ends (where its
/// derivatives are least accurate) fall outside the gap.
pub(super) const PAD: usize = 4;

/// Largest difference (m) between a translation DOF and its aligned example
/// at either end of the gap for the DOF to follow it (the root's height: a
/// person crouching where the example stands upright is no example of it).
pub const MAX_END_OFFSET: f64 = 0.25;

/// How far the example's laid poses are from the gap's end states, before
/// the blend that makes them meet: the measure of how well it fits where
/// it must join the motion.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EndFit {
    /// Mean distance (m) of the body's joints between the aligned example's
    /// pose and the motion's at the gap's start, and at its end.
    pub start: f64,
    pub end: f64,
    /// Largest angle difference (rad) of a gap DOF at either end.
    pub angle: f64,
}

/// An example laid over a group of gaps.
#[derive(Clone, Debug)]
pub struct LaidExample {
    /// The group's span.
    pub t0: f64,
    pub t1: f64,
    /// The example, its `follow` the DOFs laid and `fit` set.
    pub example: Example,
    /// Per DOF that follows: its model coordinate, its gap and the laid
    /// curve (defined a little beyond the gap at both ends).
    curves: Vec<LaidDof>,
}

#[derive(Clone, Debug)]
struct LaidDof {
    coord: usize,
    t0: f64,
    t1: f64,
    curve: Arc<Curve>,
}

impl LaidExample {
    /// The laid curve of model coordinate `coord`, if it follows.
    pub fn curve(&self, coord: usize) -> Option<&Arc<Curve>> {
        self.curves
            .iter()
            .find(|d| d.coord == coord)
            .map(|d| &d.curve)
    }

    /// q, q̇, q̈ at gap time t of the laid coordinates (the others, and a
    /// coordinate whose own gap does not reach t, left as they are): what
    /// the example term pulls toward and the prior follows.
    pub fn inputs(
        &self,
    ) -> impl Fn(f64, &mut [f64], &mut [f64], &mut [f64]) -> Result<(), SpError> + Sync + '_ {
        move |t, q, v, a| {
            for d in &self.curves {
                let tol = crate::motion::time_tol(t);
                if t < d.t0 - tol || t > d.t1 + tol {
                    continue;
                }
                let [x, dx, ddx] = d.curve.eval(t).map_err(SpError::Motion)?;
                q[d.coord] = x;
                v[d.coord] = dx;
                a[d.coord] = ddx;
            }
            Ok(())
        }
    }

    /// The model coordinates laid, in order.
    pub fn coords(&self) -> impl Iterator<Item = usize> + '_ {
        self.curves.iter().map(|d| d.coord)
    }

    /// Writes the laid curves into their gaps of `m` (DOFs named `names`);
    /// gaps of DOFs that do not follow stay as they are. With the Hermite
    /// curves written into those first (`fill(m, "hermite")`), the result is
    /// a whole motion over the gap that the ground measures can read: the
    /// example's own contacts, laid in the world.
    pub fn write_into(&self, m: &mut Mu, names: &[String]) -> Result<(), SpError> {
        for d in &self.curves {
            let name = &names[d.coord];
            let Some(dof) = m.get(name) else {
                continue;
            };
            let iv = Interval::curve((*d.curve).clone(), d.t0, d.t1).map_err(SpError::Motion)?;
            let filled = dof.plus(&Dof::from(iv));
            m.insert(name.clone(), filled);
        }
        Ok(())
    }
}

/// What laying an example needs from the motion and the body.
pub struct Lay<'a> {
    pub model: &'a Model,
    pub names: &'a [String],
    /// Against gravity; `None` (no gravity): the root is not aligned.
    pub up: Option<Vector3<f64>>,
    pub root: &'a RootCoords,
    /// The motion being filled (its end states and poses at the gap's ends).
    pub motion: &'a Mu,
    pub rotation: &'a (dyn Fn(usize) -> bool + Sync),
    pub joints: &'a Joints,
}

/// Where the example's value of a DOF is read.
struct Source<'a> {
    motion: &'a Mu,
    example: &'a Example,
}

impl Source<'_> {
    fn at(&self, name: &str, t: f64) -> Result<Option<[f64; 3]>, SpError> {
        match &self.example.clip {
            Some(c) => c.motion.sample(name, t),
            None => self.motion.sample(name, t + self.example.shift),
        }
        .map_err(SpError::Motion)
    }

    fn value(&self, name: &str, t: f64) -> Result<f64, SpError> {
        Ok(self.at(name, t)?.map_or(f64::NAN, |s| s[0]))
    }
}

fn smoothstep(t: f64, t0: f64, t1: f64) -> f64 {
    let u = ((t - t0) / (t1 - t0)).clamp(0.0, 1.0);
    u * u * (3.0 - 2.0 * u)
}

/// The grid of one gap: `PAD` samples beyond each end, both ends on it.
fn grid(t0: f64, t1: f64) -> (f64, f64, usize) {
    let n = ((t1 - t0) * LAY_RATE).ceil().max(2.0) as usize;
    let h = (t1 - t0) / n as f64;
    (t0 - PAD as f64 * h, h, n + 2 * PAD + 1)
}

impl Lay<'_> {
    /// `example` laid over `gaps` (one group), or why it cannot be: no
    /// DOF's example is defined over its gap and close to the motion at
    /// both ends.
    pub fn lay(
        &self,
        example: &Example,
        gaps: &[GapDof],
    ) -> Result<Result<LaidExample, NoExample>, SpError> {
        let (Some(t0), Some(t1)) = (
            gaps.iter().map(|g| g.t0).reduce(f64::min),
            gaps.iter().map(|g| g.t1).reduce(f64::max),
        ) else {
            return Ok(Err(NoExample::Span { seconds: 0.0 }));
        };
        let src = Source {
            motion: self.motion,
            example,
        };
        let mut aligned = self.aligned_root(&src, gaps)?;
        let mut series: Vec<(usize, f64, Vec<f64>)> = vec![];
        let mut undefined = None;
        for g in gaps {
            let name = &self.names[g.coord];
            let (from, h, n) = grid(g.t0, g.t1);
            let mut v = match aligned.remove(&g.coord) {
                Some(v) => v,
                None => (0..n)
                    .map(|k| src.value(name, from + k as f64 * h))
                    .collect::<Result<Vec<f64>, _>>()?,
            };
            if v.iter().any(|x| !x.is_finite()) {
                undefined.get_or_insert_with(|| name.clone());
                continue;
            }
            if (self.rotation)(g.coord) {
                // the example's turn nearest the motion's own at the start
                let k = ((g.start.q - v[PAD]) / TAU).round() * TAU;
                v.iter_mut().for_each(|x| *x += k);
            }
            series.push((g.coord, from, v));
        }
        self.on_the_motions_branch(&mut series, gaps);
        let gap_of = |c: usize| gaps.iter().find(|g| g.coord == c);
        // the aligned example at both ends of each DOF's gap
        let mut ends: Vec<(usize, [f64; 3], [f64; 3])> = vec![];
        for (c, from, v) in &series {
            let g = gap_of(*c).expect("a series per gap");
            let (_, h, _) = grid(g.t0, g.t1);
            let a = Curve::samples(*from, h, v.clone()).map_err(SpError::Motion)?;
            let at = |t: f64| a.eval(t).map_err(SpError::Motion);
            ends.push((*c, at(g.t0)?, at(g.t1)?));
        }
        let fit = self.end_fit(gaps, &ends, t0, t1)?;
        let close = self.close_at_ends(gaps, &ends);
        let coords: Vec<usize> = gaps.iter().map(|g| g.coord).collect();
        let follow = self.joints.whole(&coords, &close);
        if follow.is_empty() {
            return Ok(Err(match undefined {
                Some(dof) if ends.is_empty() => NoExample::Undefined { dof },
                _ => NoExample::FarAtEnds {
                    start: fit.start,
                    end: fit.end,
                    angle: fit.angle,
                },
            }));
        }
        let blend = Blend::for_fit(
            fit.start,
            fit.end,
            crate::motion::sample_period(self.motion),
        );
        let mut curves = vec![];
        for ((c, from, v), (_, a0, a1)) in series.iter().zip(&ends) {
            if !follow.contains(c) {
                continue;
            }
            let g = gap_of(*c).expect("a series per gap");
            let diff = |e: &crate::spacetime::EndState, s: &[f64; 3]| crate::spacetime::EndState {
                q: e.q - s[0],
                v: e.v - s[1],
                a: 0.0,
            };
            let (d0, d1) = (diff(&g.start, a0), diff(&g.end, a1));
            let (_, h, _) = grid(g.t0, g.t1);
            let r: Vec<f64> = v
                .iter()
                .enumerate()
                .map(|(k, x)| x + blend.at(g.t0, g.t1, &d0, &d1, from + k as f64 * h))
                .collect();
            curves.push(LaidDof {
                coord: *c,
                t0: g.t0,
                t1: g.t1,
                curve: Arc::new(Curve::samples(*from, h, r).map_err(SpError::Motion)?),
            });
        }
        let mut example = example.clone();
        example.follow = follow;
        example.of = coords.len();
        example.fit = Some(fit);
        Ok(Ok(LaidExample {
            t0,
            t1,
            example,
            curves,
        }))
    }

    /// The root's aligned series (see the module doc) by coordinate, on
    /// each root gap's grid; empty when the root is not cut, or is not
    /// three floor-plane-and-heading coordinates this can turn (two
    /// horizontal translations and an Euler joint by name), or the example
    /// is undefined there.
    fn aligned_root(
        &self,
        src: &Source,
        gaps: &[GapDof],
    ) -> Result<HashMap<usize, Vec<f64>>, SpError> {
        let none = HashMap::new();
        let Some(up) = self.up else {
            return Ok(none);
        };
        let root = self.root;
        let gap_of = |c: usize| gaps.iter().find(|g| g.coord == c);
        let Some(g0) = root.rotations.first().and_then(|&c| gap_of(c)) else {
            return Ok(none);
        };
        let (t0, t1) = (g0.t0, g0.t1);
        let same_gap = |c: &usize| {
            gap_of(*c).is_some_and(|g| {
                (g.t0 - t0).abs() <= crate::motion::time_tol(t0)
                    && (g.t1 - t1).abs() <= crate::motion::time_tol(t1)
            })
        };
        if root.horizontal.len() != 2
            || !root.horizontal.iter().all(same_gap)
            || !root.rotations.iter().all(same_gap)
        {
            return Ok(none);
        }
        let rot_names = root.rotations.iter().map(|&c| self.names[c].as_str());
        let Some(ej) = euler_joints(rot_names).into_iter().next() else {
            return Ok(none);
        };
        let Some(rot) = ej
            .dofs
            .iter()
            .map(|d| self.model.coordinate_index(d))
            .collect::<Option<Vec<usize>>>()
        else {
            return Ok(none);
        };
        let Some(frame) = self.floor_frame(&rot, &up, t0)? else {
            return Ok(none);
        };
        let hz = [root.horizontal[0], root.horizontal[1]];
        let value = |c: usize, t: f64| src.value(&self.names[c], t);
        let state = |c: usize, end: bool| {
            let g = gap_of(c).expect("a root gap");
            if end { g.end.q } else { g.start.q }
        };
        // the alignment at each end: heading turn θ and the floor map
        let mut ends = vec![];
        for (t, end) in [(t0, false), (t1, true)] {
            let e_rot = from_euler(
                ej.axes,
                [value(rot[0], t)?, value(rot[1], t)?, value(rot[2], t)?],
            );
            let m_rot = from_euler(
                ej.axes,
                [state(rot[0], end), state(rot[1], end), state(rot[2], end)],
            );
            let theta = twist(&(m_rot * e_rot.inverse()), &frame.u);
            let pe = [value(hz[0], t)?, value(hz[1], t)?];
            let pm = [state(hz[0], end), state(hz[1], end)];
            if !(theta.is_finite() && pe.iter().chain(&pm).all(|x| x.is_finite())) {
                return Ok(none);
            }
            ends.push((theta, pe, pm));
        }
        let (th0, pe0, pm0) = ends[0];
        let (mut th1, pe1, pm1) = ends[1];
        th1 = th0 + wrap(th1 - th0);
        let (from, h, n) = grid(t0, t1);
        let mut out: HashMap<usize, Vec<f64>> = HashMap::new();
        for c in hz.iter().chain(&rot) {
            out.insert(*c, vec![f64::NAN; n]);
        }
        let k0 = PAD;
        let near0: [f64; 3] = std::array::from_fn(|i| state(rot[i], false));
        let mut near = near0;
        let order: Vec<usize> = (k0..n).chain((0..k0).rev()).collect();
        for k in order {
            if k + 1 == k0 {
                near = near0;
            }
            let t = from + k as f64 * h;
            let s = smoothstep(t, t0, t1);
            let theta = th0 + s * (th1 - th0);
            let p = [value(hz[0], t)?, value(hz[1], t)?];
            let a = frame.map(p, pe0, pm0, th0);
            let b = frame.map(p, pe1, pm1, th1);
            for i in 0..2 {
                out.get_mut(&hz[i]).expect("inserted")[k] = (1.0 - s) * a[i] + s * b[i];
            }
            let e = [value(rot[0], t)?, value(rot[1], t)?, value(rot[2], t)?];
            if e.iter().any(|x| !x.is_finite()) {
                return Ok(none);
            }
            let turned = UnitQuaternion::from_axis_angle(&frame.u, theta) * from_euler(ej.axes, e);
            near = to_euler_near(ej.axes, &turned, near);
            for i in 0..3 {
                out.get_mut(&rot[i]).expect("inserted")[k] = near[i];
            }
        }
        Ok(out)
    }

    /// Up in the frame the root's Euler angles turn in (its parent link's,
    /// at the motion's pose at `t`), and the world axes of the two
    /// horizontal root coordinates; `None` when those are not two
    /// orthogonal floor-plane axes.
    fn floor_frame(
        &self,
        rot: &[usize],
        up: &Vector3<f64>,
        t: f64,
    ) -> Result<Option<FloorFrame>, SpError> {
        let model = self.model;
        let mut q = JointSampler::new(self.motion, self.names)
            .positions(t)
            .map_err(SpError::Motion)?;
        q.iter_mut()
            .filter(|x| !x.is_finite())
            .for_each(|x| *x = 0.0);
        let mut poses = vec![];
        let fk = |q: &[f64], poses: &mut Vec<crate::lie::Se3>| {
            model
                .forward_kinematics(q, poses)
                .map_err(|e| SpError::Numerical(format!("laying an example: {e}")))
        };
        fk(&q, &mut poses)?;
        let Some(link) = model.coordinate_link(rot[0]) else {
            return Ok(None);
        };
        let parent = model
            .link(link)
            .parent
            .map(|p| poses[p].r)
            .unwrap_or_else(nalgebra::Matrix3::identity);
        let u = Unit::new_normalize(parent.transpose() * up);
        let hz = [self.root.horizontal[0], self.root.horizontal[1]];
        let mut axes = [Vector3::zeros(); 2];
        for (i, &c) in hz.iter().enumerate() {
            let Some(l) = model.coordinate_link(c) else {
                return Ok(None);
            };
            let before = poses[l].p;
            let mut moved = q.clone();
            moved[c] += 1.0;
            let mut p2 = vec![];
            fk(&moved, &mut p2)?;
            axes[i] = p2[l].p - before;
        }
        let unit = |a: &Vector3<f64>| (a.norm() - 1.0).abs() < 1e-6;
        if !(unit(&axes[0]) && unit(&axes[1]))
            || axes[0].dot(&axes[1]).abs() > 1e-6
            || axes.iter().any(|a| a.dot(up).abs() > 1e-6)
        {
            return Ok(None);
        }
        Ok(Some(FloorFrame {
            u,
            up: Unit::new_normalize(*up),
            axes,
        }))
    }

    /// [`EndFit`] of the aligned example (`ends`: per DOF, its value at the
    /// gap's start and end).
    fn end_fit(
        &self,
        gaps: &[GapDof],
        ends: &[(usize, [f64; 3], [f64; 3])],
        t0: f64,
        t1: f64,
    ) -> Result<EndFit, SpError> {
        let sampler = JointSampler::new(self.motion, self.names);
        let mut angle: f64 = 0.0;
        let mut dist = [0.0; 2];
        for (i, t) in [t0, t1].into_iter().enumerate() {
            let mut q = sampler.positions(t).map_err(SpError::Motion)?;
            for g in gaps {
                q[g.coord] = if i == 0 { g.start.q } else { g.end.q };
            }
            let mut qa = q.clone();
            for (c, a, b) in ends {
                let x = if i == 0 { a[0] } else { b[0] };
                if (self.rotation)(*c) {
                    angle = angle.max(wrap(x - q[*c]).abs());
                }
                qa[*c] = x;
            }
            for x in q.iter_mut().chain(qa.iter_mut()) {
                if !x.is_finite() {
                    *x = 0.0;
                }
            }
            let (mut pm, mut pa) = (vec![], vec![]);
            let fk = |q: &[f64], p: &mut Vec<crate::lie::Se3>| {
                self.model
                    .forward_kinematics(q, p)
                    .map_err(|e| SpError::Numerical(format!("laying an example: {e}")))
            };
            fk(&q, &mut pm)?;
            fk(&qa, &mut pa)?;
            let n = pm.len().max(1) as f64;
            dist[i] = pm
                .iter()
                .zip(&pa)
                .map(|(a, b)| (a.p - b.p).norm())
                .sum::<f64>()
                / n;
        }
        Ok(EndFit {
            start: dist[0],
            end: dist[1],
            angle,
        })
    }
}

/// Up in the root rotation's parent frame, and the world axes of the two
/// horizontal root coordinates.
struct FloorFrame {
    u: Unit<Vector3<f64>>,
    up: Unit<Vector3<f64>>,
    axes: [Vector3<f64>; 2],
}

impl FloorFrame {
    /// Floor-plane point `p` (horizontal root coordinates) under the map
    /// that turns by `theta` about up and takes `pe` to `pm`.
    fn map(&self, p: [f64; 2], pe: [f64; 2], pm: [f64; 2], theta: f64) -> [f64; 2] {
        let d = self.axes[0] * (p[0] - pe[0]) + self.axes[1] * (p[1] - pe[1]);
        let turned = Rotation3::from_axis_angle(&self.up, theta) * d;
        [
            pm[0] + turned.dot(&self.axes[0]),
            pm[1] + turned.dot(&self.axes[1]),
        ]
    }
}

/// The angle of `r`'s twist about `axis` (its swing–twist split): the turn
/// about that axis, in (−π, π].
fn twist(r: &UnitQuaternion<f64>, axis: &Unit<Vector3<f64>>) -> f64 {
    let q = r.quaternion();
    let along = q.imag().dot(axis);
    let a = 2.0 * along.atan2(q.w);
    if a > PI {
        a - TAU
    } else if a <= -PI {
        a + TAU
    } else {
        a
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_twist_about_an_axis_is_the_turn_about_it() {
        let up = Vector3::y_axis();
        for a in [-3.0, -1.0, 0.0, 0.4, 3.1] {
            let yaw = UnitQuaternion::from_axis_angle(&up, a);
            let tilt = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 0.3);
            assert!((twist(&yaw, &up) - a).abs() < 1e-12, "{a}");
            // a tilt before the turn does not change the turn much
            assert!((twist(&(yaw * tilt), &up) - a).abs() < 1e-12, "{a}");
        }
    }

    #[test]
    fn the_smoothstep_blend_starts_flat_and_ends_flat() {
        assert_eq!(smoothstep(1.0, 1.0, 2.0), 0.0);
        assert_eq!(smoothstep(2.0, 1.0, 2.0), 1.0);
        assert_eq!(smoothstep(1.5, 1.0, 2.0), 0.5);
        assert_eq!(smoothstep(0.0, 1.0, 2.0), 0.0);
    }
}
