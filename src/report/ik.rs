//! IK work–precision: the tolerance of `ik` against its time per frame, on
//! the project's human(walk) (44 coordinates) with both feet put where the
//! walk has them 0.3 s later (reachable, ≈30 cm from each frame's pose) —
//! the case `benches/motion.rs` times.

use super::timed;
use crate::ik::{IkOptions, Settings, Target, ik};
use crate::motion::{Curve, Dof, Interval, affine, grid_times};
use crate::report::error::ReportError;

pub struct Row {
    pub tolerance: f64,
    /// Largest foot residual over the frames (m).
    pub max_residual: f64,
    pub mean_iterations: f64,
    pub max_iterations: usize,
    pub us_per_frame: f64,
}

pub struct Outcome {
    pub frames: usize,
    pub coordinates: usize,
    pub rows: Vec<Row>,
}

pub fn run(smoke: bool, tick: &mut dyn FnMut()) -> Result<Outcome, ReportError> {
    let (model, walk) = crate::spacetime::fig8::example_walk()?;
    let later = affine(-0.3, 1.0, &walk)?;
    let empty = || ReportError::Empty { what: "the walk" };
    let (s, e) = later.span().ok_or_else(empty)?;
    let e = e.min(walk.span().ok_or_else(empty)?.1);
    let ts = grid_times((s.max(0.0), e), 60.0)?;
    let p = crate::mocap::positions_at(&later, &model, ts.clone(), crate::mocap::Missing::Error)?;
    let target = |link: &str| -> Result<Target, ReportError> {
        let j = p
            .names
            .iter()
            .position(|n| n == link)
            .ok_or_else(|| ReportError::NoLink { link: link.into() })?;
        let axis = |k: usize| -> Result<Dof, ReportError> {
            let v: Vec<f64> = p.points.iter().map(|f| f[j][k]).collect();
            let c = Curve::samples(ts[0], ts[1] - ts[0], v)?;
            let stop = *ts.last().ok_or(ReportError::Empty {
                what: "the walk's grid",
            })?;
            Ok(Dof::from(Interval::curve(c, ts[0], stop)?))
        };
        Ok(Target {
            link: link.into(),
            position: [axis(0)?, axis(1)?, axis(2)?],
            orientation: None,
            weight: 1.0,
        })
    };
    let targets = [target("foot_L")?, target("foot_R")?];
    let tolerances: &[f64] = if smoke {
        &[1e-3, 1e-6]
    } else {
        &[1e-2, 1e-3, 1e-4, 1e-6, 1e-8, 1e-10]
    };
    let mut rows = vec![];
    let mut frames = 0;
    for &tolerance in tolerances {
        let opts = IkOptions {
            settings: Settings {
                tolerance,
                ..Default::default()
            },
            rate: Some(60.0),
            ..Default::default()
        };
        let (r, secs) = timed(|| ik(&model, &walk, &targets, &opts));
        let (_, rep) = r?;
        frames = rep.frames;
        rows.push(Row {
            tolerance,
            max_residual: rep
                .targets
                .iter()
                .map(|t| t.max_residual)
                .fold(0.0, f64::max),
            mean_iterations: rep.mean_iterations,
            max_iterations: rep.max_iterations,
            us_per_frame: secs * 1e6 / rep.frames as f64,
        });
        tick();
    }
    Ok(Outcome {
        frames,
        coordinates: model.nq(),
        rows,
    })
}
