//! The example from a clip library (`SP(…, example: lib)`): the index ranks
//! stretches by their features, and the best few are scored by ρ over the
//! gap's context like the motion's own example.

use super::laid::{FloorMap, laid_on_gap};
use super::pose::{Pose, PoseMetric};
use super::{
    CONTEXT, Example, Joints, MAX_END_DIFFERENCE, MAX_MISMATCH, MIN_CONTEXT_SAMPLES, NoExample,
    STEP, gap_coords, gap_span, span_seconds,
};
use crate::library::features::{KeyJoints, key_positions};
use crate::library::{Library, Match};
use crate::mocap::bvh::Skeleton;
use crate::mocap::up::skeleton_up;
use crate::motion::Mu;
pub use crate::spacetime::contact::ExampleStances;
use crate::spacetime::error::SpError;
use crate::spacetime::objective::GapDof;
use nalgebra::Vector3;
use std::sync::Arc;

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
    /// The clip's own stances over the stretch, on the gap's clock, from the
    /// contact labels the library stored at build time (`ground`'s planning
    /// rule on the clip as recorded); `None` when the library has none for
    /// it, and the contact plan then reads them off the laid poses.
    pub stances: Option<Vec<ExampleStances>>,
}

/// The clip's planning stances ([`crate::library::ClipLabels`], stored
/// when it was indexed) over the gap and [`CONTEXT`] either side, on the
/// gap's clock: clip time s is gap time t0 + (s − time) / warp. `None` when
/// the clip has no labels.
fn stances_on_gap(
    entry: &crate::library::LibClip,
    cand: &Match,
    (t0, t1): (f64, f64),
) -> Result<Option<Vec<ExampleStances>>, SpError> {
    let Some(labels) = entry.labels()? else {
        return Ok(None);
    };
    let (from, to) = (t0 - CONTEXT, t1 + CONTEXT);
    let gap_time = |s: f64| t0 + (s - cand.time) / cand.warp;
    let clip_time = |t: f64| cand.time + cand.warp * (t - t0);
    Ok(Some(
        labels
            .plan_spans(clip_time(from), clip_time(to))
            .into_iter()
            .map(|(point, spans)| ExampleStances {
                point: point.to_string(),
                spans: spans
                    .into_iter()
                    .map(|(a, b)| (gap_time(a).max(from), gap_time(b).min(to)))
                    .collect(),
            })
            .collect(),
    ))
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
                if let Some([x, dx, ddx]) = self.motion.sample(n, t).map_err(SpError::Motion)? {
                    q[i] = x;
                    v[i] = dx;
                    a[i] = ddx;
                }
            }
            Ok(())
        }
    }
}

/// The best library stretch for `gaps`, scored like the motion's own
/// example (ρ over the context, angles), or `None` when the motion has no
/// context to match, its skeleton no key joints, or nothing matches within
/// [`MAX_MISMATCH`]; joints by the name convention ([`Joints::by_name`]).
pub fn from_library(
    m: &Mu,
    names: &[String],
    rotation: &dyn Fn(usize) -> bool,
    gaps: &[GapDof],
    src: &LibrarySource,
) -> Result<Option<Example>, SpError> {
    from_library_with(m, names, rotation, &Joints::by_name(names), gaps, src)
}

/// [`from_library`] with the coordinates' joints given.
pub fn from_library_with(
    m: &Mu,
    names: &[String],
    rotation: &dyn Fn(usize) -> bool,
    joints: &Joints,
    gaps: &[GapDof],
    src: &LibrarySource,
) -> Result<Option<Example>, SpError> {
    Ok(search(m, names, rotation, joints, gaps, src)?.ok())
}

/// [`from_library_with`], saying why there is none.
pub(super) fn search(
    m: &Mu,
    names: &[String],
    rotation: &dyn Fn(usize) -> bool,
    joints: &Joints,
    gaps: &[GapDof],
    src: &LibrarySource,
) -> Result<Result<Example, NoExample>, SpError> {
    let Some((t0, t1)) = gap_span(gaps) else {
        return Ok(Err(NoExample::Span {
            seconds: span_seconds(gaps),
        }));
    };
    let lib = &src.library;
    if lib.clips.is_empty() {
        return Ok(Err(NoExample::LibraryEmpty));
    }
    let query = match lib.query(m, &src.skeleton, src.metres_per_unit, t0, t1) {
        Ok(q) => q,
        Err(e) => return Ok(Err(NoExample::NoFeatures(e.to_string()))),
    };
    let my_keys = match KeyJoints::find(&src.skeleton) {
        Ok(k) => k,
        Err(e) => return Ok(Err(NoExample::NoFeatures(e.to_string()))),
    };
    let Some(Some(mine)) =
        key_positions(m, &src.skeleton, src.metres_per_unit, &my_keys, &[t0]).pop()
    else {
        return Ok(Err(NoExample::NoFeatures(format!(
            "the key joints are undefined at the gap's start ({t0:.3} s)"
        ))));
    };
    let gap = match LibraryGap::new(m, names, rotation, joints, gaps, (t0, t1), mine) {
        // the up the motion's skeleton stands along, as `body_of` reads it
        Ok(g) => g.standing(skeleton_up(&src.skeleton, Some(m), src.metres_per_unit)),
        Err(why) => return Ok(Err(why)),
    };
    let mut best: Option<Example> = None;
    let mut best_rho = f64::INFINITY;
    for cand in lib.match_gap(&query, LIBRARY_CANDIDATES) {
        let bar = best.as_ref().map(|b| b.mismatch);
        match gap.try_stretch(lib, &cand, bar)? {
            Ok(ex) => best = Some(ex),
            Err(rho) => best_rho = best_rho.min(rho),
        }
    }
    Ok(
        best.ok_or(if best_rho.is_finite() && best_rho > MAX_MISMATCH {
            NoExample::NoMatch {
                best: best_rho,
                threshold: MAX_MISMATCH,
            }
        } else {
            NoExample::NoStretch
        }),
    )
}

/// What every library candidate of one group of gaps is scored against.
struct LibraryGap<'a> {
    m: &'a Mu,
    names: &'a [String],
    joints: &'a Joints,
    span: (f64, f64),
    /// The motion's key joint positions at t0.
    mine: [Vector3<f64>; 6],
    /// The up the motion's skeleton stands along (`mocap::up`).
    up: Vector3<f64>,
    coords: Vec<usize>,
    /// Context times: [`CONTEXT`] either side on the [`STEP`] grid, where
    /// the motion is defined.
    context: Vec<f64>,
    /// The context's own squared spread (the ρ scale).
    spread: f64,
    /// How poses are compared, and the motion's own at each context time
    /// and at the gap's two ends.
    metric: PoseMetric,
    poses: Vec<Pose>,
    ends: [Pose; 2],
    names_arc: Arc<Vec<String>>,
}

impl<'a> LibraryGap<'a> {
    /// Why not when no gap coordinate is an angle, the context is too
    /// short, or it does not move.
    fn new(
        m: &'a Mu,
        names: &'a [String],
        rotation: &'a dyn Fn(usize) -> bool,
        joints: &'a Joints,
        gaps: &[GapDof],
        (t0, t1): (f64, f64),
        mine: [Vector3<f64>; 6],
    ) -> Result<Self, NoExample> {
        let coords = gap_coords(gaps);
        let angles: Vec<usize> = coords.iter().copied().filter(|&c| rotation(c)).collect();
        if angles.is_empty() {
            return Err(NoExample::NoAngles);
        }
        let reach = (CONTEXT / STEP).round() as i64;
        let value = |n: &str, t: f64| m.sample_value(n, t).ok().flatten();
        let context: Vec<f64> = (0..=reach)
            .map(|k| t0 - k as f64 * STEP)
            .chain((0..=reach).map(|k| t1 + k as f64 * STEP))
            .filter(|&t| angles.iter().all(|&c| value(&names[c], t).is_some()))
            .collect();
        if context.len() < MIN_CONTEXT_SAMPLES {
            return Err(NoExample::NoContext);
        }
        let metric = PoseMetric::new(names, &coords, rotation, joints);
        let pose_at = |t: f64| metric.pose(|i| value(&names[coords[i]], t).unwrap_or(f64::NAN));
        let poses: Vec<Pose> = context.iter().map(|&t| pose_at(t)).collect();
        let ends = [pose_at(t0), pose_at(t1)];
        let total = metric.spread(&poses);
        if total <= 0.0 {
            return Err(NoExample::NoContext);
        }
        Ok(LibraryGap {
            m,
            names,
            joints,
            span: (t0, t1),
            mine,
            up: Vector3::y(),
            coords,
            context,
            spread: total,
            metric,
            poses,
            ends,
            names_arc: Arc::new(names.to_vec()),
        })
    }

    fn standing(self, up: Vector3<f64>) -> Self {
        LibraryGap { up, ..self }
    }

    fn value(&self, c: usize, t: f64) -> Option<f64> {
        self.m.sample_value(&self.names[c], t).ok().flatten()
    }

    /// The example of candidate `cand` if it matches within
    /// [`MAX_MISMATCH`], better than `bar` (the best ρ so far), and some
    /// whole joint follows it; else its ρ (∞ when it has none).
    fn try_stretch(
        &self,
        lib: &Library,
        cand: &Match,
        bar: Option<f64>,
    ) -> Result<Result<Example, f64>, SpError> {
        let entry = &lib.clips[cand.clip];
        let clip = entry.motion()?;
        let Some(Some(theirs)) = key_positions(
            &clip.mu,
            &clip.skeleton,
            clip.units.metres_per_unit,
            &entry.keys,
            &[cand.time],
        )
        .pop() else {
            return Ok(Err(f64::INFINITY));
        };
        // a clip of another up has other joint frames: its channels are not
        // the motion's poses, whatever turn lays its root
        if skeleton_up(&clip.skeleton, Some(&clip.mu), clip.units.metres_per_unit) != self.up {
            return Ok(Err(f64::INFINITY));
        }
        let map = FloorMap::between(&theirs, &self.mine, &self.up);
        let names = self.names;
        let motion = laid_on_gap(
            &clip,
            &entry.keys,
            cand,
            &map,
            self.m,
            names,
            &self.coords,
            self.span,
        )?;
        let at = |c: usize, t: f64| motion.sample_value(&names[c], t).ok().flatten();
        let theirs_at = |t: f64| {
            self.metric
                .pose(|i| at(self.coords[i], t).unwrap_or(f64::NAN))
        };
        // (an angle undefined in the stretch makes ρ NaN: refused below)
        let e: f64 = self
            .context
            .iter()
            .zip(&self.poses)
            .map(|(&t, mine)| self.metric.distance2(&theirs_at(t), mine))
            .sum();
        let rho = e / self.spread;
        // (a NaN ρ is refused too)
        let acceptable = rho <= MAX_MISMATCH;
        if !acceptable || bar.is_some_and(|b| b <= rho) {
            return Ok(Err(if rho.is_nan() { f64::INFINITY } else { rho }));
        }
        let (t0, t1) = self.span;
        // angles, a joint's as one rotation (translations, the root's among
        // them, are compared once the example is laid in the world, `lay.rs`)
        let ends: Vec<Vec<f64>> = [t0, t1]
            .iter()
            .zip(&self.ends)
            .map(|(&t, mine)| self.metric.angles(&theirs_at(t), mine))
            .collect();
        let close: Vec<bool> = self
            .coords
            .iter()
            .enumerate()
            .map(|(i, &c)| {
                [t0, t1]
                    .iter()
                    .all(|&t| at(c, t).is_some() && self.value(c, t).is_some())
                    && self.metric.close(i, &ends, MAX_END_DIFFERENCE)
            })
            .collect();
        let follow = self.joints.whole(&self.coords, &close);
        if follow.is_empty() {
            return Ok(Err(f64::INFINITY));
        }
        Ok(Ok(Example {
            shift: 0.0,
            mismatch: rho,
            follow,
            of: self.coords.len(),
            clip: Some(ClipStretch {
                name: cand.name.clone(),
                time: cand.time,
                warp: cand.warp,
                features: cand.mismatch,
                motion: Arc::new(motion),
                names: self.names_arc.clone(),
                stances: stances_on_gap(entry, cand, self.span)?,
            }),
            fit: None,
        }))
    }
}
