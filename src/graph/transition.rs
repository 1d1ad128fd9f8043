//! One transition: a up to frame i, a gap, then b from frame j moved by the
//! search's alignment, filled by SP (`crate::spacetime::sp`, the entry the
//! language's `SP` uses, so the library improves when SP does).
//!
//! The motion SP sees holds `context` frames of a before the gap (a's own
//! curves, so the end velocity is the clip's) and `context` frames of b after
//! it (b's rows turned and moved, and each joint's rotations re-expressed
//! nearest a's at the join, so no joint spins round).
//! With SP's default `root: "shift"` the part after the gap is moved on to
//! continue the root's path; the alignment recorded is the one realised, fitted
//! between b's frame j and the transition's last frame.

use super::error::TransitionError;
use super::library::{LibClip, Library};
use super::planar::{Planar, fit};
use super::search::Point;
use super::settings::Settings;
use crate::mocap::bvh::{self, BvhFile};
use crate::mocap::{self, bvh::Units};
use crate::motion::{Mu, affine, clip_in_place, plus};
use crate::spacetime::{SpOptions, SpReport, sp, torque_energy};

/// A filled transition.
pub struct Transition {
    /// The gap's frames with both joins: a's frame i first, b's frame j (moved) last.
    pub file: BvhFile,
    /// Frames strictly inside the gap.
    pub gap: usize,
    /// ∫Στ² over the transition (SP's objective without its prior).
    pub energy: f64,
    /// Where b's frames go: b's frame j maps onto the last frame.
    pub align: Planar,
    /// What SP filled (the motion it saw, gap filled), for continuity checks.
    pub filled: Mu,
    pub report: SpReport,
    /// Times of the gap's ends in `filled`.
    pub t0: f64,
    pub t1: f64,
}

/// The gap length in frames for a transition of this distance: `min_gap` for
/// a perfect match rising linearly to `max_gap` at the threshold.
pub fn gap_frames(s: &Settings, distance: f64) -> usize {
    let r = if s.threshold > 0.0 {
        (distance / s.threshold).clamp(0.0, 1.0)
    } else {
        1.0
    };
    s.min_gap + (r * (s.max_gap - s.min_gap) as f64).round() as usize
}

/// SP's options at the library's settings (SP's defaults unless a setting names one).
pub fn sp_options(s: &Settings) -> SpOptions {
    let mut o = SpOptions::default();
    if let Some(c) = s.coefficients {
        o.settings.coefficients = c;
    }
    if let Some(n) = s.samples {
        o.settings.samples = n;
    }
    if let Some(n) = s.iterations {
        o.solve.max_iters = n;
    }
    if let Some(t) = s.tolerance {
        o.solve.tolerance = t;
    }
    o
}

/// Rows `from..to` of a clip's file.
fn rows(c: &LibClip, from: usize, to: usize) -> Vec<f64> {
    let n = c.file.skeleton.channel_count();
    c.file.values[from * n..to * n].to_vec()
}

/// A rotation channel (`Joint.Xrotation`), by the motion's channel rule.
fn is_rotation(channel: &str) -> bool {
    crate::motion::channel::rotation_axis(channel).is_some()
}

/// Re-expresses b's rotations (rows of `values`) nearest a's at the join
/// (`near`, a's row at frame i), continuously along the rows: of the two
/// Euler triples of a rotation and their whole turns, the nearest. Otherwise
/// SP would swing a joint the long way between two spellings of one pose
/// (a foot at Z ≈ 180° written as −180°, or as (α + π, π − β, γ + π)).
fn nearest_euler(sk: &crate::mocap::bvh::Skeleton, values: &mut [f64], near: &[f64]) {
    use crate::motion::rotation::{from_euler, to_euler_near};
    let nch = sk.channel_count();
    let starts = sk.channel_starts();
    for (jt, joint) in sk.joints.iter().enumerate() {
        let rot: Vec<(usize, usize)> = joint
            .channels
            .iter()
            .enumerate()
            .filter(|(_, c)| c.is_rotation())
            .map(|(k, c)| (starts[jt] + k, c.axis()))
            .collect();
        if rot.len() == 3 {
            let axes = [rot[0].1, rot[1].1, rot[2].1];
            let mut prev: Option<([f64; 3], [f64; 3])> = None;
            for row in values.chunks_mut(nch) {
                let e: [f64; 3] = std::array::from_fn(|k| row[rot[k].0].to_radians());
                let target = match prev {
                    None => std::array::from_fn(|k| near[rot[k].0].to_radians()),
                    Some((orig, written)) => std::array::from_fn(|k| written[k] + e[k] - orig[k]),
                };
                let x = to_euler_near(axes, &from_euler(axes, e), target);
                for k in 0..3 {
                    row[rot[k].0] = x[k].to_degrees();
                }
                prev = Some((e, x));
            }
        } else {
            // one or two rotation channels: whole turns only
            for &(c, _) in &rot {
                let turns = ((near[c] - values[c]) / 360.0).round() * 360.0;
                if turns != 0.0 {
                    for row in values.chunks_mut(nch) {
                        row[c] += turns;
                    }
                }
            }
        }
    }
}

/// Fills the transition from a at `point.i` to b at `point.j`, b first moved by
/// `point.align`, with a gap of `gap` frames.
pub fn fill(
    lib: &Library,
    a: &LibClip,
    b: &LibClip,
    point: &Point,
    gap: usize,
    s: &Settings,
) -> Result<Transition, TransitionError> {
    let (i, j, align) = (point.i, point.j, &point.align);
    let dt = lib.frame_time;
    let nch = lib.skeleton.channel_count();
    let ca = s.context.min(i).max(1);
    let cb = s.context.min(b.frames() - 1 - j).max(1);
    if i == 0 || j + 1 >= b.frames() {
        return Err(TransitionError::NoContext {
            i,
            a_frames: a.frames(),
            j,
            b_frames: b.frames(),
        });
    }
    // b's frames j ..= j + cb, moved onto a's floor position and heading
    let mut vb = rows(b, j, j + cb + 1);
    lib.root.transform_rows(&mut vb, nch, align);
    // a's side is a's motion, unwrapped from its first frame: its values at i, in degrees
    let t_i = i as f64 * dt;
    let near: Vec<f64> = lib
        .skeleton
        .channel_names()
        .iter()
        .zip(a.file.frame(i))
        .map(|(n, raw)| match a.clip.mu.sample_value(n, t_i) {
            Ok(Some(v)) if is_rotation(n) => v.to_degrees(),
            _ => *raw,
        })
        .collect();
    nearest_euler(&lib.skeleton, &mut vb, &near);
    let fb = BvhFile {
        skeleton: lib.skeleton.clone(),
        frame_time: dt,
        values: vb,
    };
    let mut clip_b = mocap::from_bvh(&fb, Units::MetresPerUnit(lib.metres_per_unit))
        .map_err(TransitionError::Frames)?;
    // from_bvh unwraps from the first row, which already sits nearest a: no further turns
    let t0 = i as f64 * dt;
    let t1 = t0 + (gap + 1) as f64 * dt;
    clip_b.mu = affine(t1, 1.0, &clip_b.mu)?;
    let before = clip_in_place(t0 - ca as f64 * dt, t0, &a.clip.mu)?;
    let cut = plus(&before, &clip_b.mu);
    // SP splits its quadrature into as many chunks as its pool has threads, and the sums'
    // order moves the last bits; on a pool of its own with one thread the transition is
    // the same bytes whatever --threads, shard or caller (pairs give the parallelism).
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .map_err(|e| TransitionError::Thread(e.to_string()))?;
    let (filled, report) = pool
        .install(|| sp(&cut, &lib.body, &sp_options(s)))
        .map_err(TransitionError::Sp)?;
    drop(pool);
    let piece = clip_in_place(t0, t1, &filled)?;
    let energy = torque_energy(&piece, &lib.body, None).map_err(TransitionError::Energy)?;
    let (file, _) = mocap::to_motion::to_bvh(&piece, &lib.skeleton, lib.metres_per_unit, dt)
        .map_err(TransitionError::Write)?;
    if file.frame_count() != gap + 2 {
        return Err(TransitionError::FrameCount {
            got: file.frame_count(),
            want: gap + 2,
        });
    }
    let last =
        bvh::fk::world_positions(&file, gap + 1, lib.metres_per_unit)[lib.root.joint..].to_vec();
    let realised = fit(&last, &b.points[j]);
    Ok(Transition {
        file,
        gap,
        energy,
        align: realised,
        filled,
        report,
        t0,
        t1,
    })
}
