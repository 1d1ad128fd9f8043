//! Cyclification work–precision (Rose §3.3) on the project's own walk: the
//! knot spacing of the cyclic least-squares fit → how far the loop departs
//! from the clip and how well its seam closes, against time.

use super::plot::{Figure, Series};
use super::timed;
use crate::mocap::bvh::Units;
use crate::motion::Mu;
use crate::motion::cyclify::floor_drift;
use crate::motion::cyclify::{CyclifyOptions, cyclify, loop_motion};
use crate::report::error::ReportError;
use std::path::Path;

/// The marks given to `cyclify` (s): about one stride of `examples/data/walk.bvh`.
pub const MARKS: (f64, f64) = (0.5, 1.5);

pub struct Row {
    pub knot_spacing: f64,
    pub coefficients: usize,
    /// Worst departure of a rotation channel from the clip over the cycle (°).
    pub max_deg: f64,
    pub rms_deg: f64,
    /// Worst seam jumps of two loops in q (relative), q̇, q̈.
    pub seam: [f64; 3],
    pub ms: f64,
}

pub struct Outcome {
    pub cycle: (f64, f64),
    pub rows: Vec<Row>,
    pub figures: Vec<Figure>,
}

/// Largest jumps where consecutive intervals touch (a drifting DOF's advance
/// is part of its curve, not a jump).
fn seam_jumps(m: &Mu) -> Result<[f64; 3], ReportError> {
    let mut j = [0.0f64; 3];
    for d in m.dofs.values() {
        for w in d.intervals.windows(2) {
            let a = w[0].funcs[0].eval(w[0].stop)?;
            let b = w[1].funcs[0].eval(w[1].start)?;
            j[0] = j[0].max((a[0] - b[0]).abs() / (1.0 + a[0].abs()));
            j[1] = j[1].max((a[1] - b[1]).abs());
            j[2] = j[2].max((a[2] - b[2]).abs());
        }
    }
    Ok(j)
}

pub const DEFAULT_SPACING: f64 = 1.0 / 30.0;

pub fn run(clip_path: &Path, smoke: bool, tick: &mut dyn FnMut()) -> Result<Outcome, ReportError> {
    let clip = crate::mocap::load(clip_path, Units::Auto).map_err(|source| ReportError::Clip {
        path: clip_path.to_path_buf(),
        source,
    })?;
    let drift = floor_drift(&clip.mu);
    let rotations: Vec<String> = clip
        .mu
        .names()
        .filter(|n| n.ends_with("rotation"))
        .map(String::from)
        .collect();
    let spacings: &[f64] = if smoke {
        &[0.1, DEFAULT_SPACING]
    } else {
        &[
            0.2,
            0.1,
            1.0 / 15.0,
            DEFAULT_SPACING,
            1.0 / 60.0,
            1.0 / 120.0,
        ]
    };
    let mut rows = Vec::new();
    let mut cycle = MARKS;
    for &h in spacings {
        let opts = CyclifyOptions {
            drift: drift.clone(),
            knot_spacing: h,
            ..Default::default()
        };
        let (r, secs) = timed(|| cyclify(&clip.mu, MARKS.0, MARKS.1, &opts));
        let (cyc, rep) = r?;
        cycle = (rep.t1, rep.t2);
        let looped = loop_motion(&cyc, 2)?;
        let seam = seam_jumps(&looped)?;
        let (max, rms) = departure(&cyc, &clip.mu, &rotations, (rep.t1, rep.t2))?;
        rows.push(Row {
            knot_spacing: h,
            coefficients: rep.coefficients,
            max_deg: max.to_degrees(),
            rms_deg: rms.to_degrees(),
            seam,
            ms: secs * 1e3,
        });
        tick();
    }
    Ok(Outcome {
        cycle,
        figures: figures(&rows),
        rows,
    })
}

/// How far the cyclified motion departs from the clip over the cycle
/// [t1, t2], on a 240 Hz grid, over the rotation channels `rotations`: the
/// largest and the root-mean-square difference (rad).
fn departure(
    cyc: &crate::motion::Mu,
    clip: &crate::motion::Mu,
    rotations: &[String],
    (t1, t2): (f64, f64),
) -> Result<(f64, f64), ReportError> {
    let n = ((t2 - t1) * 240.0).round().max(1.0) as usize;
    let (mut max, mut sum, mut count) = (0.0f64, 0.0, 0usize);
    for name in rotations {
        for k in 0..=n {
            let t = t1 + (t2 - t1) * k as f64 / n as f64;
            let a = cyc.sample_value(name, t)?;
            let b = clip.sample_value(name, t)?;
            if let (Some(a), Some(b)) = (a, b) {
                let e = (a - b).abs();
                max = max.max(e);
                sum += e * e;
                count += 1;
            }
        }
    }
    Ok((max, (sum / count.max(1) as f64).sqrt()))
}

/// Departure against cyclify time, the default knot spacing ringed.
fn figures(rows: &[Row]) -> Vec<Figure> {
    let default_at = rows
        .iter()
        .position(|r| (r.knot_spacing - DEFAULT_SPACING).abs() < 1e-12);
    vec![Figure {
        file: "cyclify.svg".into(),
        title: "walk.bvh: cyclify knot spacing → departure from the clip".into(),
        x_label: "cyclify time (ms, this machine)".into(),
        y_label: "rotation departure over the cycle (°)".into(),
        series: vec![
            Series {
                label: "max".into(),
                points: rows.iter().map(|r| (r.ms, r.max_deg)).collect(),
                default_at,
            },
            Series {
                label: "rms".into(),
                points: rows.iter().map(|r| (r.ms, r.rms_deg)).collect(),
                default_at,
            },
        ],
    }]
}
