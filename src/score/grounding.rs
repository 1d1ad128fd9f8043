//! Does a fill stand on the ground? `ground`'s measures over one gap, by
//! `ground`'s rules and nothing else: its contact points (a body's ankle and
//! toe joints), the 2 cm contact height, "up" against gravity, and the
//! floor of the reference (the lowest height its contact points reach where
//! it is recorded). So the benchmark, `compare(…)`, `foot_skate(m, b)`,
//! `penetration(m, b, floor: f)` and `ground_residual(m, b)` agree by
//! construction: each is `ground` run on `clip_in_place(t0, t1, m)`, the gap
//! with the step into and out of it, at the reference's frame rate.

use super::error::{ScoreError, Which};
use crate::ground::skate::{
    depth_per_frame, penetration_of_tracks, skate_of_tracks, skate_per_step,
};
use crate::ground::{
    CONTACT_HEIGHT, Floor, GroundOptions, contact_points, ground_residual, recorded_floor, tracks,
};
use crate::model::Model;
use crate::motion::{Mu, clip_in_place};

/// Friction coefficient of the ground residual (`data/inbetween/README.md`'s μ).
pub const FRICTION: f64 = 0.8;

/// The ground measures of one motion over one gap.
#[derive(Clone, Debug, PartialEq)]
pub struct Grounding {
    /// Mean horizontal speed of a contact point over the steps it ends within
    /// 2 cm of the floor (cm/s): `foot_skate(…).mean`.
    pub skate: f64,
    /// How far the lowest contact point goes below the floor (cm): `penetration(…).depth`.
    pub depth: f64,
    /// The ground residual's mean and worst frame (% of body weight): `ground_residual(…)`.
    pub residual: f64,
    pub residual_worst: f64,
    /// The same per frame, for figures.
    pub frames: GroundFrames,
}

/// Per-frame ground measures over a gap and its two edge frames.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct GroundFrames {
    pub times: Vec<f64>,
    /// Per step into frame k (k ≥ 1; one fewer than `times`): the fastest
    /// contact point ending it within 2 cm of the floor (cm/s, 0: none).
    pub skate: Vec<f64>,
    /// Per frame: the lowest contact point's depth below the floor (cm, 0: above).
    pub depth: Vec<f64>,
    /// Per frame: the ground residual's force (% of body weight).
    pub residual: Vec<f64>,
}

/// `ground`'s options for a gap: the floor stated, the 2 cm contact height,
/// frames at `rate` Hz, the body's contact points.
pub fn ground_options(floor: f64, rate: f64) -> GroundOptions {
    GroundOptions {
        floor: Floor::At(floor),
        height: CONTACT_HEIGHT,
        rate: Some(rate),
        ..Default::default()
    }
}

/// The floor of `reference` on `body` sampled at `rate` Hz: the lowest
/// height its contact points reach where every coordinate is defined
/// (`ground::recorded_floor`, the floor `contacts(reference, body)` reports).
pub fn floor_of(reference: &Mu, body: &Model, rate: f64) -> Result<f64, ScoreError> {
    let err = ScoreError::ground(Which::Reference);
    let opts = GroundOptions {
        rate: Some(rate),
        ..Default::default()
    };
    let points = contact_points(body, None).map_err(&err)?;
    recorded_floor(reference, body, &points, &opts)
        .map_err(err)?
        .ok_or(ScoreError::NoFloor)
}

/// Skate, depth and residual of `m` (which: the argument it is) over the
/// gap [t0, t1] (both edge frames included) against `floor`, at `rate` Hz.
pub fn grounding(
    (m, which): (&Mu, Which),
    body: &Model,
    (t0, t1): (f64, f64),
    floor: f64,
    rate: f64,
) -> Result<Grounding, ScoreError> {
    let err = ScoreError::ground(which);
    let piece = clip_in_place(t0, t1, m).map_err(ScoreError::motion(which))?;
    let opts = ground_options(floor, rate);
    let points = contact_points(body, None).map_err(&err)?;
    let tr = tracks(&piece, body, &points, &opts).map_err(&err)?;
    let skate = skate_of_tracks(&tr, &opts).map_err(&err)?;
    let depth = penetration_of_tracks(&tr, &opts).map_err(&err)?;
    let residual = ground_residual(&piece, body, &opts, FRICTION).map_err(&err)?;
    Ok(Grounding {
        skate: skate.mean,
        depth: depth.depth,
        residual: residual.mean_force,
        residual_worst: residual.worst_force,
        frames: GroundFrames {
            skate: skate_per_step(&tr, &opts).map_err(&err)?,
            depth: depth_per_frame(&tr, &opts).map_err(&err)?,
            times: tr.times,
            residual: residual.force,
        },
    })
}
