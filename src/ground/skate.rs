//! Foot skate and penetration.
//!
//! Skate (`data/inbetween/README.md`): the horizontal speed of a contact
//! point over each step between frames, counted where the point ends the
//! step within `height` of the floor; its mean and worst (cm/s). Beside it
//! the height-weighted sliding of Zhang et al. 2018 (*Mode-Adaptive Neural
//! Networks for Quadruped Motion Control*, SIGGRAPH, §7): per point and step
//! `v · (2 − 2^(h/H))` where the point is below `H` above the floor (0 above),
//! averaged over every point and step, with `H` the `height` option (2 cm;
//! they used 2.5 cm) and `h` clamped at 0 so a point below the floor weighs
//! as one on it — a foot that skates while barely touching counts less than
//! one that skates planted.
//!
//! Penetration: how far the lowest point goes below the floor (cm), where and when.

use super::GroundError;
use super::points::{GroundOptions, Tracks, contact_points, tracks};
use crate::model::Model;
use crate::motion::Mu;

/// Foot skate of a motion (speeds in cm/s).
#[derive(Clone, Debug, PartialEq)]
pub struct Skate {
    /// Mean horizontal speed over steps ending within `height` of the floor.
    pub mean: f64,
    /// The fastest such step, its point and the frame it ends at.
    pub worst: f64,
    pub worst_point: String,
    pub worst_frame: usize,
    /// Steps counted (points × steps near the floor).
    pub steps: usize,
    /// Zhang et al. 2018's height-weighted sliding, mean over every point and step.
    pub weighted: f64,
    /// The floor it was measured against (m, along up).
    pub floor: f64,
}

/// Penetration of a motion.
#[derive(Clone, Debug, PartialEq)]
pub struct Penetration {
    /// Depth of the lowest point below the floor (cm); 0 when none goes below.
    pub depth: f64,
    /// The lowest point, its frame and time (of the deepest, or of the lowest when none is below).
    pub point: String,
    pub frame: usize,
    pub time: f64,
    pub floor: f64,
}

/// Skate over sampled tracks.
pub fn skate_of_tracks(tr: &Tracks, opts: &GroundOptions) -> Result<Skate, GroundError> {
    opts.check()?;
    let floor = tr.floor(opts.floor);
    let h_max = opts.height;
    let (mut sum, mut n) = (0.0, 0usize);
    let (mut worst, mut worst_point, mut worst_frame) = (0.0, String::new(), 0);
    let (mut weighted, mut all) = (0.0, 0usize);
    for k in 1..tr.times.len() {
        for (j, p) in tr.points.iter().enumerate() {
            let v = tr.step_speed(k, j) * 100.0;
            let h = tr.height(k, j) - floor;
            all += 1;
            if h <= h_max {
                sum += v;
                n += 1;
                if v > worst || worst_point.is_empty() {
                    worst = v;
                    worst_point = p.name.clone();
                    worst_frame = k;
                }
            }
            let w = if h_max > 0.0 {
                (2.0 - (h.max(0.0) / h_max).exp2()).max(0.0)
            } else if h <= 0.0 {
                1.0
            } else {
                0.0
            };
            weighted += v * w;
        }
    }
    Ok(Skate {
        mean: if n == 0 { 0.0 } else { sum / n as f64 },
        worst,
        worst_point,
        worst_frame,
        steps: n,
        weighted: if all == 0 { 0.0 } else { weighted / all as f64 },
        floor,
    })
}

/// Penetration over sampled tracks.
pub fn penetration_of_tracks(
    tr: &Tracks,
    opts: &GroundOptions,
) -> Result<Penetration, GroundError> {
    opts.check()?;
    let floor = tr.floor(opts.floor);
    let (mut low, mut point, mut frame) = (f64::INFINITY, 0, 0);
    for k in 0..tr.times.len() {
        for j in 0..tr.points.len() {
            let h = tr.height(k, j);
            if h < low {
                (low, point, frame) = (h, j, k);
            }
        }
    }
    Ok(Penetration {
        depth: ((floor - low) * 100.0).max(0.0),
        point: tr
            .points
            .get(point)
            .map(|p| p.name.clone())
            .unwrap_or_default(),
        frame,
        time: tr.times.get(frame).copied().unwrap_or(0.0),
        floor,
    })
}

/// Per step between frames (`k − 1 → k`, k ≥ 1, so one fewer than the
/// frames): the fastest horizontal speed (cm/s) of a point that ends the step
/// within `height` of the floor, 0 where none does — the steps
/// [`skate_of_tracks`] averages and takes its worst from.
pub fn skate_per_step(tr: &Tracks, opts: &GroundOptions) -> Result<Vec<f64>, GroundError> {
    opts.check()?;
    let floor = tr.floor(opts.floor);
    Ok((1..tr.times.len())
        .map(|k| {
            (0..tr.points.len())
                .filter(|&j| tr.height(k, j) - floor <= opts.height)
                .map(|j| tr.step_speed(k, j) * 100.0)
                .fold(0.0, f64::max)
        })
        .collect())
}

/// Per frame: how far the lowest point is below the floor (cm; 0 when none
/// is) — the depths [`penetration_of_tracks`] takes the deepest of.
pub fn depth_per_frame(tr: &Tracks, opts: &GroundOptions) -> Result<Vec<f64>, GroundError> {
    opts.check()?;
    let floor = tr.floor(opts.floor);
    Ok((0..tr.times.len())
        .map(|k| {
            let low = (0..tr.points.len())
                .map(|j| tr.height(k, j))
                .fold(f64::INFINITY, f64::min);
            ((floor - low) * 100.0).max(0.0)
        })
        .collect())
}

/// Foot skate of `m` on `body` (see the module doc).
pub fn foot_skate(m: &Mu, body: &Model, opts: &GroundOptions) -> Result<Skate, GroundError> {
    let pts = contact_points(body, opts.points.as_deref())?;
    skate_of_tracks(&tracks(m, body, &pts, opts)?, opts)
}

/// The deepest contact point of `m` below the floor.
pub fn penetration(m: &Mu, body: &Model, opts: &GroundOptions) -> Result<Penetration, GroundError> {
    let pts = contact_points(body, opts.points.as_deref())?;
    penetration_of_tracks(&tracks(m, body, &pts, opts)?, opts)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ground::ContactPoint;
    use nalgebra::Vector3;

    /// One point sliding at 0.1 m/s along x at height `h` over a floor at 0 (y up).
    fn sliding(h: f64) -> Tracks {
        Tracks {
            points: vec![ContactPoint {
                name: "toe".into(),
                link: 0,
            }],
            times: (0..5).map(|k| k as f64 * 0.1).collect(),
            frame_time: 0.1,
            up: Vector3::y(),
            positions: (0..5)
                .map(|k| vec![Vector3::new(0.01 * k as f64, h, 0.0)])
                .collect(),
        }
    }

    #[test]
    fn skate_and_its_weighting() {
        let o = GroundOptions {
            floor: crate::ground::Floor::At(0.0),
            ..Default::default()
        };
        let s = skate_of_tracks(&sliding(0.0), &o).unwrap();
        assert!((s.mean - 10.0).abs() < 1e-9 && (s.worst - 10.0).abs() < 1e-9);
        assert_eq!(s.steps, 4);
        // on the floor the weight is 1
        assert!((s.weighted - 10.0).abs() < 1e-9);
        // at half the height threshold: 2 − √2 of the speed
        let s = skate_of_tracks(&sliding(0.01), &o).unwrap();
        assert!((s.weighted - 10.0 * (2.0 - 2f64.sqrt())).abs() < 1e-9);
        // above the threshold: not counted, weight 0
        let s = skate_of_tracks(&sliding(0.03), &o).unwrap();
        assert_eq!((s.steps, s.mean, s.weighted), (0, 0.0, 0.0));
        // penetration: 3 cm below a floor stated at 0
        let p = penetration_of_tracks(&sliding(-0.03), &o).unwrap();
        assert!((p.depth - 3.0).abs() < 1e-9, "{p:?}");
        // the per-step and per-frame series are what the measures summarise
        for h in [-0.03, 0.0, 0.01, 0.03] {
            let tr = sliding(h);
            let s = skate_of_tracks(&tr, &o).unwrap();
            let steps = skate_per_step(&tr, &o).unwrap();
            assert_eq!(steps.len(), tr.times.len() - 1);
            assert_eq!(steps.iter().copied().fold(0.0, f64::max), s.worst);
            let p = penetration_of_tracks(&tr, &o).unwrap();
            let depths = depth_per_frame(&tr, &o).unwrap();
            assert_eq!(depths.iter().copied().fold(0.0, f64::max), p.depth);
        }
    }
}
