//! The motion's own example for a gap: the stretch of the same motion, a
//! shift Δ away, whose frames around it look most like the frames around the
//! gap. A walk or a run repeats itself; what the person did in the gap is
//! then best told by what they did one cycle earlier or later, which no end
//! state carries (two interpolated ends cannot make a step).
//!
//! SP's prior follows the example's velocities and accelerations instead of
//! zero ([`super::sp::Prior`]): it is minimised by the example plus the
//! smooth correction that meets the gap's end states. A motion that does not
//! repeat (a bow, a wave) has no stretch that matches well, and then the
//! prior stays the plain one.

use super::error::SpError;
use super::objective::GapDof;
use crate::library::Library;
use crate::library::features::{KeyJoints, key_positions};
use crate::mocap::bvh::Skeleton;
use crate::motion::{Curve, Dof, Interval, Mu};
use nalgebra::Vector3;
use std::f64::consts::PI;
use std::sync::Arc;

/// Grid step (s) the motion is compared on: a capture's usual frame time.
const STEP: f64 = 1.0 / 30.0;

/// Context (s) compared on each side of the gap: the in-betweening protocol's
/// ten frames at 30 Hz (`$MX_SHARED/data/inbetween/README.md`).
const CONTEXT: f64 = 0.3;

/// How far (s) from the gap an example is looked for: a long recording is
/// searched only this near the gap (the cost is linear in the span).
const SEARCH_SPAN: f64 = 30.0;

/// Longest gap (s) an example is looked for: a cycle copied from the same
/// motion tells nothing over longer, and the search's grid grows with it.
const MAX_GAP: f64 = 10.0;

/// Fewest context samples worth comparing (both sides together).
const MIN_CONTEXT_SAMPLES: usize = 4;

/// Largest mismatch ρ (see [`Example::mismatch`]) of an accepted example.
/// Measured by `cargo bench --bench inbetween` (50 shared clips, one window
/// each, root given): with ρ ≤ 0.5 instead, SP came 0.81 × Hermite at
/// 30-frame gaps against 0.76 here (before [`Example::trust`]); in a first
/// look, with the example alone corrected to its ends, windows with ρ between
/// 1 and 3 came farther from the capture than Hermite in 7 of 9 (a turning
/// walk whose cycles differ).
pub const MAX_MISMATCH: f64 = 1.0;

/// Largest difference (rad) between a DOF and its example at either end of
/// the gap for the DOF to follow it: the prior's motion is the example plus
/// a smooth ramp between the two end differences, so it stays this close to
/// poses the person took. A joint with a channel farther off keeps the plain
/// prior on all its channels (channel by channel, a kick's spine turned
/// 1.6 rad away from any pose of the clip: one Euler channel followed and its
/// siblings did not). With 0.15 a walk's toe ended 67 cm off where one leg
/// joint followed and the next did not; with no limit a punch's upper arm
/// turned 0.62 rad from its sides (`tests/it/inbetween.rs` allows 0.48).
pub const MAX_END_DIFFERENCE: f64 = 0.25;

/// A rotation coordinate that turns by more than this between two grid
/// samples is taken to wrap (±π in the data), and such a stretch is no example.
const MAX_TURN_PER_STEP: f64 = PI / 2.0;

/// The stretch of the motion a group of gaps follows.
#[derive(Clone, Debug, PartialEq)]
pub struct Example {
    /// Δ (s): the gap at t follows the motion at t + Δ.
    pub shift: f64,
    /// ρ: over the context on both sides of the gap, the squared difference
    /// between the motion and the motion Δ away, over the context's own
    /// squared spread about its mean (rotation coordinates, angles wrapped).
    /// 0 is a perfect repeat; 1 is no better than the context's mean pose.
    pub mismatch: f64,
    /// The model coordinates that follow it: those within
    /// [`MAX_END_DIFFERENCE`] of it at both ends of the gap.
    pub follow: Vec<usize>,
    /// The group's gap coordinates (followers or not).
    pub of: usize,
    /// A library stretch (`example: lib`) instead of the motion `shift` away.
    pub clip: Option<ClipStretch>,
}

impl Example {
    /// How much of the example the prior follows: 1 − ρ, all of a perfect
    /// repeat and less of a looser match, so that a context that matched
    /// by chance (a step the person did not take in the gap) weighs little.
    pub fn trust(&self) -> f64 {
        (1.0 - self.mismatch).clamp(0.0, 1.0)
    }
}

/// The best example for `gaps` (one group: they share the span the example
/// must cover), or `None` when no stretch of `m` is defined around a shifted
/// copy of the gap, or none matches within [`MAX_MISMATCH`].
///
/// `names[c]` is the DOF of model coordinate c; `rotation(c)` says whether it
/// is an angle (only angles are compared: translations are in the motion's
/// own units and mostly bone offsets).
pub fn find(
    m: &Mu,
    names: &[String],
    rotation: &dyn Fn(usize) -> bool,
    gaps: &[GapDof],
) -> Result<Option<Example>, SpError> {
    let (Some(t0), Some(t1)) = (
        gaps.iter().map(|g| g.t0).reduce(f64::min),
        gaps.iter().map(|g| g.t1).reduce(f64::max),
    ) else {
        return Ok(None);
    };
    // a zero-length gap (or a degenerate span) has no stretch to copy, nor
    // has one longer than any cycle
    if !(t1 - t0 > 1e-9 && t1 - t0 <= MAX_GAP) {
        return Ok(None);
    }
    let Some((start, stop)) = m.span() else {
        return Ok(None);
    };
    let (start, stop) = (start.max(t0 - SEARCH_SPAN), stop.min(t1 + SEARCH_SPAN));
    // the grid: t0 + k h, with the gap's end on it
    let n = ((t1 - t0) / STEP).round().max(1.0) as i64;
    let h = (t1 - t0) / n as f64;
    let k_lo = ((start - t0) / h).ceil() as i64;
    let k_hi = ((stop - t0) / h).floor() as i64;
    if k_hi - k_lo < 2 * n {
        return Ok(None);
    }
    let mut coords: Vec<usize> = gaps.iter().map(|g| g.coord).collect();
    coords.sort_unstable();
    coords.dedup();
    let angles: Vec<bool> = coords.iter().map(|&c| rotation(c)).collect();
    if !angles.iter().any(|&a| a) {
        return Ok(None);
    }
    // every gap coordinate on the grid, NaN where undefined
    let len = (k_hi - k_lo + 1) as usize;
    let mut x = vec![vec![f64::NAN; len]; coords.len()];
    for (row, &c) in x.iter_mut().zip(&coords) {
        for (j, v) in row.iter_mut().enumerate() {
            let t = (t0 + (k_lo + j as i64) as f64 * h).clamp(start, stop);
            if let Some(s) = m
                .sample(&names[c], t)
                .map_err(|e| SpError::Evaluation(e.to_string()))?
            {
                *v = s[0];
            }
        }
    }
    let at = |k: i64| (k - k_lo) as usize;
    // whether every gap coordinate is defined at each grid point (once: the
    // shift search asks it for every point of every candidate window)
    let everywhere: Vec<bool> = (0..len)
        .map(|j| x.iter().all(|row| row[j].is_finite()))
        .collect();
    let defined = |k: i64| k >= k_lo && k <= k_hi && everywhere[at(k)];
    // the context: up to CONTEXT before t0 and after t1, where defined
    let reach = (CONTEXT / h).round() as i64;
    let before: Vec<i64> = (0..=reach)
        .map(|j| -j)
        .take_while(|&k| defined(k))
        .collect();
    let after: Vec<i64> = (0..=reach)
        .map(|j| n + j)
        .take_while(|&k| defined(k))
        .collect();
    let context: Vec<i64> = before.iter().chain(&after).copied().collect();
    if context.len() < MIN_CONTEXT_SAMPLES {
        return Ok(None);
    }
    let lo = before.last().copied().unwrap_or(0);
    let hi = after.last().copied().unwrap_or(n);
    let wrap = |d: f64| (d + PI).rem_euclid(2.0 * PI) - PI;
    // the context's spread about its mean pose
    let mut spread = 0.0;
    for (row, _) in x.iter().zip(&angles).filter(|(_, a)| **a) {
        let first = row[at(context[0])];
        let rel: Vec<f64> = context.iter().map(|&k| wrap(row[at(k)] - first)).collect();
        let mean = rel.iter().sum::<f64>() / rel.len() as f64;
        spread += rel.iter().map(|r| (r - mean) * (r - mean)).sum::<f64>();
    }
    if spread <= 0.0 {
        return Ok(None);
    }
    let mut best: Option<(i64, f64)> = None;
    for s in (k_lo - lo)..=(k_hi - hi) {
        // the shifted window must lie wholly in defined, unwrapped data
        if s == 0 || !(lo..=hi).all(|k| defined(k + s)) {
            continue;
        }
        let wraps = x.iter().zip(&angles).filter(|(_, a)| **a).any(|(row, _)| {
            (lo..hi).any(|k| (row[at(k + s + 1)] - row[at(k + s)]).abs() > MAX_TURN_PER_STEP)
        });
        if wraps {
            continue;
        }
        let mut e = 0.0;
        for (row, _) in x.iter().zip(&angles).filter(|(_, a)| **a) {
            for &k in &context {
                let d = wrap(row[at(k + s)] - row[at(k)]);
                e += d * d;
            }
        }
        let rho = e / spread;
        if best.is_none_or(|(_, b)| rho < b) {
            best = Some((s, rho));
        }
    }
    let Some((s, rho)) = best.filter(|(_, rho)| *rho <= MAX_MISMATCH) else {
        return Ok(None);
    };
    // which channels are close to the example at both gap ends
    let close: Vec<bool> = x
        .iter()
        .map(|row| {
            [0, n]
                .iter()
                .all(|&k| wrap(row[at(k + s)] - row[at(k)]).abs() <= MAX_END_DIFFERENCE)
        })
        .collect();
    let follow = whole_joints(&coords, &close, names);
    if follow.is_empty() {
        return Ok(None);
    }
    Ok(Some(Example {
        shift: s as f64 * h,
        mismatch: rho,
        follow,
        of: coords.len(),
        clip: None,
    }))
}

/// `SP(…, example: lib)`: a clip library the example may come from, and the
/// skeleton the motion drives (the gap's features are read through it).
#[derive(Clone)]
pub struct LibrarySource {
    pub library: Arc<Library>,
    pub skeleton: Arc<Skeleton>,
    pub metres_per_unit: f64,
}

impl std::fmt::Debug for LibrarySource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "LibrarySource({} clips)", self.library.clips.len())
    }
}

/// Library stretches tried per gap: the index ranks them by their features,
/// and the best of these by ρ (the same measure as the motion's own
/// example's) is the one followed.
const LIBRARY_CANDIDATES: usize = 5;

/// Sampling step (s) of a library example on the gap's clock: fine enough
/// that its cubic reproduces the clip's own 30–120 Hz curves.
const EXAMPLE_STEP: f64 = 1.0 / 240.0;

/// The library stretch an example is, laid on the gap's clock.
#[derive(Clone, Debug)]
pub struct ClipStretch {
    pub name: String,
    /// Clip time (s) at the gap's start.
    pub time: f64,
    /// Clip time per gap time.
    pub warp: f64,
    /// The index's feature mismatch ([`crate::library::Match::mismatch`]).
    pub features: f64,
    /// The stretch (with the context either side) on the gap's clock, its
    /// root turned and moved in the floor plane to where the motion is at t0,
    /// DOFs named as the body's coordinates.
    pub motion: Arc<Mu>,
    names: Arc<Vec<String>>,
}

impl PartialEq for ClipStretch {
    fn eq(&self, o: &Self) -> bool {
        (&self.name, self.time, self.warp, self.features) == (&o.name, o.time, o.warp, o.features)
    }
}

impl ClipStretch {
    /// q, q̇, q̈ of the body's coordinates at gap time t (those it has).
    pub fn inputs(
        &self,
    ) -> impl Fn(f64, &mut [f64], &mut [f64], &mut [f64]) -> Result<(), SpError> + Sync + '_ {
        move |t, q, v, a| {
            for (i, n) in self.names.iter().enumerate() {
                if let Some([x, dx, ddx]) = self
                    .motion
                    .sample(n, t)
                    .map_err(|e| SpError::Evaluation(e.to_string()))?
                {
                    q[i] = x;
                    v[i] = dx;
                    a[i] = ddx;
                }
            }
            Ok(())
        }
    }
}

/// The example for a group of gaps from the motion itself (`self`), a
/// library, or both (the lower ρ kept).
pub fn choose(
    m: &Mu,
    names: &[String],
    rotation: &dyn Fn(usize) -> bool,
    gaps: &[GapDof],
    own: bool,
    library: Option<&LibrarySource>,
) -> Result<Option<Example>, SpError> {
    let mine = if own {
        find(m, names, rotation, gaps)?
    } else {
        None
    };
    let theirs = match library {
        Some(l) => from_library(m, names, rotation, gaps, l)?,
        None => None,
    };
    Ok(match (mine, theirs) {
        (Some(a), Some(b)) => Some(if b.mismatch < a.mismatch { b } else { a }),
        (a, b) => a.or(b),
    })
}

/// The floor-plane map (rotation about the vertical, then translation) that
/// takes a clip's pelvis at one frame onto the motion's at another.
struct FloorMap {
    cos: f64,
    sin: f64,
    from: Vector3<f64>,
    to: Vector3<f64>,
}

impl FloorMap {
    fn between(a: &[Vector3<f64>; 6], b: &[Vector3<f64>; 6]) -> FloorMap {
        let flat = |p: &[Vector3<f64>; 6]| {
            let c = (p[4] + p[5]) / 2.0;
            let mut across = p[4] - p[5];
            across.y = 0.0;
            let n = across.norm().max(1e-12);
            (Vector3::new(c.x, 0.0, c.z), across / n)
        };
        let (ca, ua) = flat(a);
        let (cb, ub) = flat(b);
        // (x, z) as x + i z: the turn taking ua to ub
        FloorMap {
            cos: ua.x * ub.x + ua.z * ub.z,
            sin: ua.x * ub.z - ua.z * ub.x,
            from: ca,
            to: cb,
        }
    }
    fn apply(&self, x: f64, z: f64) -> (f64, f64) {
        let (dx, dz) = (x - self.from.x, z - self.from.z);
        (
            self.to.x + dx * self.cos - dz * self.sin,
            self.to.z + dx * self.sin + dz * self.cos,
        )
    }
}

/// The best library stretch for `gaps`, scored like the motion's own
/// example (ρ over the context, angles), or `None` when the motion has no
/// context to match, its skeleton no key joints, or nothing matches within
/// [`MAX_MISMATCH`].
pub fn from_library(
    m: &Mu,
    names: &[String],
    rotation: &dyn Fn(usize) -> bool,
    gaps: &[GapDof],
    src: &LibrarySource,
) -> Result<Option<Example>, SpError> {
    let (Some(t0), Some(t1)) = (
        gaps.iter().map(|g| g.t0).reduce(f64::min),
        gaps.iter().map(|g| g.t1).reduce(f64::max),
    ) else {
        return Ok(None);
    };
    if !(t1 - t0 > 1e-9 && t1 - t0 <= MAX_GAP) {
        return Ok(None);
    }
    let lib = &src.library;
    let Ok(query) = lib.query(m, &src.skeleton, src.metres_per_unit, t0, t1) else {
        return Ok(None);
    };
    let Ok(my_keys) = KeyJoints::find(&src.skeleton) else {
        return Ok(None);
    };
    let Some(Some(mine)) =
        key_positions(m, &src.skeleton, src.metres_per_unit, &my_keys, &[t0]).pop()
    else {
        return Ok(None);
    };
    let mut coords: Vec<usize> = gaps.iter().map(|g| g.coord).collect();
    coords.sort_unstable();
    coords.dedup();
    let angles: Vec<usize> = coords.iter().copied().filter(|&c| rotation(c)).collect();
    if angles.is_empty() {
        return Ok(None);
    }
    let err = |e: String| SpError::Evaluation(e);
    // the context: CONTEXT either side on the STEP grid, where m is defined
    let reach = (CONTEXT / STEP).round() as i64;
    let value = |n: &str, t: f64| m.sample_value(n, t).ok().flatten();
    let context: Vec<f64> = (0..=reach)
        .map(|k| t0 - k as f64 * STEP)
        .chain((0..=reach).map(|k| t1 + k as f64 * STEP))
        .filter(|&t| angles.iter().all(|&c| value(&names[c], t).is_some()))
        .collect();
    if context.len() < MIN_CONTEXT_SAMPLES {
        return Ok(None);
    }
    let wrap = |d: f64| (d + PI).rem_euclid(2.0 * PI) - PI;
    let mut spread = 0.0;
    for &c in &angles {
        let first = value(&names[c], context[0]).unwrap_or(0.0);
        let rel: Vec<f64> = context
            .iter()
            .map(|&t| wrap(value(&names[c], t).unwrap_or(0.0) - first))
            .collect();
        let mean = rel.iter().sum::<f64>() / rel.len() as f64;
        spread += rel.iter().map(|r| (r - mean) * (r - mean)).sum::<f64>();
    }
    if spread <= 0.0 {
        return Ok(None);
    }
    let names_arc = Arc::new(names.to_vec());
    let mut best: Option<Example> = None;
    for cand in lib.match_gap(&query, LIBRARY_CANDIDATES) {
        let entry = &lib.clips[cand.clip];
        let clip = entry.motion().map_err(|e| err(e.0))?;
        let Some(Some(theirs)) = key_positions(
            &clip.mu,
            &clip.skeleton,
            clip.units.metres_per_unit,
            &entry.keys,
            &[cand.time],
        )
        .pop() else {
            continue;
        };
        let map = FloorMap::between(&theirs, &mine);
        let motion = laid_on_gap(&clip, &entry.keys, &cand, &map, m, names, &coords, (t0, t1))?;
        let at = |c: usize, t: f64| motion.sample_value(&names[c], t).ok().flatten();
        let mut e = 0.0;
        for &c in &angles {
            for &t in &context {
                if let (Some(x), Some(y)) = (at(c, t), value(&names[c], t)) {
                    let d = wrap(x - y);
                    e += d * d;
                } else {
                    e = f64::INFINITY;
                }
            }
        }
        let rho = e / spread;
        // (a NaN ρ is refused too)
        let acceptable = rho <= MAX_MISMATCH;
        if !acceptable || best.as_ref().is_some_and(|b| b.mismatch <= rho) {
            continue;
        }
        let close: Vec<bool> = coords
            .iter()
            .map(|&c| {
                [t0, t1]
                    .iter()
                    .all(|&t| match (at(c, t), value(&names[c], t)) {
                        (Some(x), Some(y)) => {
                            let d = if rotation(c) { wrap(x - y) } else { x - y };
                            d.abs() <= MAX_END_DIFFERENCE
                        }
                        _ => false,
                    })
            })
            .collect();
        let follow = whole_joints(&coords, &close, names);
        if follow.is_empty() {
            continue;
        }
        best = Some(Example {
            shift: 0.0,
            mismatch: rho,
            follow,
            of: coords.len(),
            clip: Some(ClipStretch {
                name: cand.name.clone(),
                time: cand.time,
                warp: cand.warp,
                features: cand.mismatch,
                motion: Arc::new(motion),
                names: names_arc.clone(),
            }),
        });
    }
    Ok(best)
}

/// The joint that carries the body through the world: the first joint from
/// the skeleton's root down to the hips with position channels that move
/// (Bandai's all-zero `joint_Root` is skipped for its `Hips`).
/// The coordinates of `coords` whose joint has every channel `close` (a
/// joint's channels follow an example together or not at all: one Euler
/// channel following and its siblings not is a rotation neither side has).
fn whole_joints(coords: &[usize], close: &[bool], names: &[String]) -> Vec<usize> {
    let joint = |c: usize| {
        names[c]
            .rsplit_once('.')
            .map_or(names[c].as_str(), |(j, _)| j)
    };
    coords
        .iter()
        .filter(|&&c| {
            coords
                .iter()
                .zip(close)
                .all(|(&o, &ok)| ok || joint(o) != joint(c))
        })
        .copied()
        .collect()
}

fn moving_root(clip: &crate::mocap::Clip, keys: &KeyJoints) -> Option<usize> {
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

/// The stretch of `clip` a match names, resampled on the gap's clock over
/// the gap and its context (clip time s + w (t − t0)), its moving root turned
/// about the vertical and moved in the floor plane by `map`; only the gap
/// coordinates. `m` gives the angles the root's turned Euler angles are
/// taken nearest to.
#[allow(clippy::too_many_arguments)]
fn laid_on_gap(
    clip: &crate::mocap::Clip,
    keys: &KeyJoints,
    cand: &crate::library::Match,
    map: &FloorMap,
    m: &Mu,
    names: &[String],
    coords: &[usize],
    (t0, t1): (f64, f64),
) -> Result<Mu, SpError> {
    use crate::motion::rotation::{euler_joints, from_euler, to_euler_near};
    use nalgebra::UnitQuaternion;
    let ev = |e: crate::motion::MotionError| SpError::Evaluation(e.to_string());
    let (lo, hi) = clip.mu.span().unwrap_or((0.0, 0.0));
    let from = t0 - CONTEXT - 2.0 * STEP;
    let n = ((t1 + CONTEXT + 2.0 * STEP - from) / EXAMPLE_STEP).ceil() as usize + 1;
    let clock = |k: usize| {
        let t = from + k as f64 * EXAMPLE_STEP;
        (cand.time + cand.warp * (t - t0)).clamp(lo, hi)
    };
    let sample = |name: &str, k: usize| -> Result<f64, SpError> {
        clip.mu
            .sample_value(name, clock(k))
            .map_err(ev)
            .map(|v| v.unwrap_or(f64::NAN))
    };
    let series =
        |name: &str| -> Result<Vec<f64>, SpError> { (0..n).map(|k| sample(name, k)).collect() };
    let root = moving_root(clip, keys).map(|i| clip.skeleton.joints[i].name.clone());
    let mut aligned: std::collections::HashMap<String, Vec<f64>> = Default::default();
    if let Some(root) = &root {
        let (xn, zn) = (format!("{root}.Xposition"), format!("{root}.Zposition"));
        if let (Ok(xs), Ok(zs)) = (series(&xn), series(&zn)) {
            let (xs, zs): (Vec<f64>, Vec<f64>) =
                xs.iter().zip(&zs).map(|(&x, &z)| map.apply(x, z)).unzip();
            aligned.insert(xn, xs);
            aligned.insert(zn, zs);
        }
        // the root's orientation turned by the same angle about the vertical
        let dofs: Vec<String> = clip.mu.names().map(String::from).collect();
        let turn = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), -map.sin.atan2(map.cos));
        if let Some(ej) = euler_joints(dofs.iter().map(String::as_str))
            .into_iter()
            .find(|e| &e.joint == root)
        {
            let cols: Vec<Vec<f64>> = ej
                .dofs
                .iter()
                .map(|d| series(d))
                .collect::<Result<_, _>>()?;
            let mut near: [f64; 3] = std::array::from_fn(|i| {
                m.sample_value(&ej.dofs[i], t0)
                    .ok()
                    .flatten()
                    .unwrap_or(cols[i][0])
            });
            // start at t0 (nearest m's own angles there), then outwards
            let k0 = ((t0 - from) / EXAMPLE_STEP).round() as usize;
            let mut out = vec![[f64::NAN; 3]; n];
            let mut turned = |k: usize, near: &mut [f64; 3]| {
                let q = turn * from_euler(ej.axes, [cols[0][k], cols[1][k], cols[2][k]]);
                let e = to_euler_near(ej.axes, &q, *near);
                *near = e;
                out[k] = e;
            };
            let start = near;
            for k in k0..n {
                turned(k, &mut near);
            }
            near = start;
            for k in (0..k0).rev() {
                turned(k, &mut near);
            }
            for (i, d) in ej.dofs.iter().enumerate() {
                aligned.insert(d.clone(), out.iter().map(|e| e[i]).collect());
            }
        }
    }
    let mut out = Mu::new();
    for &c in coords {
        let name = &names[c];
        let v = match aligned.remove(name) {
            Some(v) => v,
            None => series(name)?,
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spacetime::EndState;

    /// A motion of `f` sampled at 30 Hz over [0, 6] s with a gap (2, 3).
    fn with_gap(names: &[&str], f: &dyn Fn(usize, f64) -> f64) -> (Mu, Vec<GapDof>) {
        let dt = 1.0 / 30.0;
        let mut m = Mu::new();
        let mut gaps = vec![];
        for (c, name) in names.iter().enumerate() {
            let piece = |a: usize, b: usize| {
                let v: Vec<f64> = (a..=b).map(|k| f(c, k as f64 * dt)).collect();
                let curve = Curve::samples(a as f64 * dt, dt, v).unwrap();
                Interval::curve(curve, a as f64 * dt, b as f64 * dt).unwrap()
            };
            m.insert(
                name.to_string(),
                Dof::new(vec![piece(0, 60), piece(90, 180)]).unwrap(),
            );
            let end = |t: f64| EndState {
                q: f(c, t),
                v: 0.0,
                a: 0.0,
            };
            gaps.push(GapDof {
                coord: c,
                t0: 2.0,
                t1: 3.0,
                start: end(2.0),
                end: end(3.0),
            });
        }
        (m, gaps)
    }

    #[test]
    fn a_periodic_motion_follows_itself_a_whole_number_of_periods_away() {
        let period = 1.2;
        let f = |c: usize, t: f64| (2.0 * PI * t / period + c as f64).sin() * 0.8;
        let names = ["a", "b"];
        let (m, gaps) = with_gap(&names, &f);
        let names: Vec<String> = names.iter().map(|s| s.to_string()).collect();
        let ex = find(&m, &names, &|_| true, &gaps)
            .unwrap()
            .expect("an example");
        let periods = ex.shift / period;
        assert!((periods - periods.round()).abs() < 0.03, "{ex:?}");
        assert!(ex.mismatch < 1e-3, "{ex:?}");
        assert_eq!((ex.follow, ex.of), (vec![0, 1], 2));
    }

    #[test]
    fn a_dof_far_from_its_example_at_an_end_keeps_the_plain_prior() {
        // a, c, d repeat every second; b drifts 0.15 rad/s, so every copy of
        // it far enough away to clear the gap (2 s or more) is 0.3 rad off
        let f = |c: usize, t: f64| {
            (2.0 * PI * t + c as f64).sin() * 0.8 + if c == 1 { 0.15 * t } else { 0.0 }
        };
        let names = ["a", "b", "c", "d"];
        let (m, gaps) = with_gap(&names, &f);
        let names: Vec<String> = names.iter().map(|s| s.to_string()).collect();
        let ex = find(&m, &names, &|_| true, &gaps)
            .unwrap()
            .expect("an example");
        assert!((ex.shift - ex.shift.round()).abs() < 0.05, "{ex:?}");
        assert_eq!((ex.follow, ex.of), (vec![0, 2, 3], 4));
    }

    #[test]
    fn a_zero_length_or_huge_gap_has_no_example() {
        let f = |_: usize, t: f64| (2.0 * PI * t).sin();
        let names = ["a"];
        let (m, mut gaps) = with_gap(&names, &f);
        gaps[0].t1 = gaps[0].t0;
        let names: Vec<String> = names.iter().map(|s| s.to_string()).collect();
        assert_eq!(find(&m, &names, &|_| true, &gaps).unwrap(), None);
        // nor one longer than any cycle (whose grid would be huge)
        gaps[0].t1 = gaps[0].t0 + 1e7;
        assert_eq!(find(&m, &names, &|_| true, &gaps).unwrap(), None);
        assert_eq!(find(&m, &names, &|_| true, &[]).unwrap(), None);
    }

    #[test]
    fn a_motion_that_never_repeats_has_no_example() {
        // a slow turn: every other stretch is a different pose
        let f = |c: usize, t: f64| 0.3 * t + 0.1 * c as f64;
        let names = ["a"];
        let (m, gaps) = with_gap(&names, &f);
        let names: Vec<String> = names.iter().map(|s| s.to_string()).collect();
        assert_eq!(find(&m, &names, &|_| true, &gaps).unwrap(), None);
        // nor a motion without angles, nor one too short to hold a copy
        assert_eq!(find(&m, &names, &|_| false, &gaps).unwrap(), None);
    }

    #[test]
    fn a_stretch_through_a_wrapped_angle_is_no_example() {
        // periodic, but every copy outside the gap crosses a ±π wrap
        let period = 1.0;
        let f = |_: usize, t: f64| {
            let u = (2.0 * PI * t / period).sin() * 0.5;
            if (t - 2.5).abs() > 0.6 && (t / period).fract() > 0.45 && (t / period).fract() < 0.55 {
                u + 2.0 * PI
            } else {
                u
            }
        };
        let names = ["a"];
        let (m, gaps) = with_gap(&names, &f);
        let names: Vec<String> = names.iter().map(|s| s.to_string()).collect();
        if let Some(ex) = find(&m, &names, &|_| true, &gaps).unwrap() {
            // any example left must avoid every wrap
            let k = (ex.shift * 30.0).round() as i64;
            for j in -9..=39 {
                let t = 2.0 + (j + k) as f64 / 30.0;
                let y = m.sample("a", t).unwrap().unwrap()[0];
                assert!(y.abs() < 1.0, "{ex:?} crosses a wrap at {t}");
            }
        }
    }
}
