//! Mocap reconstruction work–precision on the project's own clip
//! (`examples/data/walk.bvh`): B-spline coefficients per second (clamped, and
//! periodic = the cyclic fit used for cyclification) and the sampling rate of
//! a sampled curve → reconstruction error against time.

use super::plot::{Figure, Series};
use super::timed;
use crate::mocap::bvh::Units;
use crate::motion::Curve;
use crate::report::error::ReportError;
use crate::spline::{BSplineBasis, fit_least_squares};
use std::path::Path;

pub struct Row {
    pub method: &'static str,
    /// Coefficients per second or samples per second.
    pub rate: f64,
    pub count: usize,
    pub max_deg: f64,
    pub rms_deg: f64,
    pub ms: f64,
}

pub struct Outcome {
    pub clip: String,
    pub channels: usize,
    pub frames: usize,
    pub duration: f64,
    pub frame_rate: f64,
    pub rows: Vec<Row>,
    pub figures: Vec<Figure>,
}

/// Rotation channels of the clip as (frame values in radians).
fn rotation_channels(clip: &crate::mocap::Clip) -> Result<Vec<Vec<f64>>, ReportError> {
    let names = clip.skeleton.channel_names();
    let kinds: Vec<bool> = clip
        .skeleton
        .joints
        .iter()
        .flat_map(|j| j.channels.iter().map(|c| c.is_rotation()))
        .collect();
    let mut out = Vec::new();
    for (name, rot) in names.iter().zip(kinds) {
        if !rot {
            continue;
        }
        let dof = clip.mu.dof(name)?;
        let mut v = Vec::with_capacity(clip.frames);
        for k in 0..clip.frames {
            let t = k as f64 * clip.frame_time;
            let s = dof.sample(name, t)?.ok_or_else(|| ReportError::Undefined {
                dof: name.clone(),
                t,
            })?;
            v.push(s[0]);
        }
        out.push(v);
    }
    Ok(out)
}

fn stats(errs: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut m, mut s, mut n) = (0.0f64, 0.0, 0usize);
    for e in errs {
        m = m.max(e.abs());
        s += e * e;
        n += 1;
    }
    (m.to_degrees(), (s / n.max(1) as f64).sqrt().to_degrees())
}

/// The clip's rotation channels, loaded once, measured three ways: clamped
/// and periodic fits per coefficient rate ([`spline_rows`]), resampling
/// against a 240 Hz grid ([`sampling_rows`]), into one list of rows, which
/// the figures then draw ([`figures`]).
pub fn run(clip_path: &Path, smoke: bool, tick: &mut dyn FnMut()) -> Result<Outcome, ReportError> {
    let clip = crate::mocap::load(clip_path, Units::Auto).map_err(|source| ReportError::Clip {
        path: clip_path.to_path_buf(),
        source,
    })?;
    let chans = rotation_channels(&clip)?;
    let dt = clip.frame_time;
    let duration = (clip.frames - 1) as f64 * dt;
    let mut rows = spline_rows(&chans, dt, smoke, tick)?;
    rows.extend(sampling_rows(&chans, dt, smoke, tick)?);
    let frame_rate = 1.0 / dt;
    Ok(Outcome {
        clip: clip_path.display().to_string(),
        channels: chans.len(),
        frames: clip.frames,
        duration,
        frame_rate,
        figures: figures(&rows, frame_rate),
        rows,
    })
}

/// One fit's row (`method`, coefficients per second, coefficients): every
/// channel fitted on `basis` through its first `fit_frames` frames (times
/// `ts`), its error measured at every frame.
fn fit_row(
    (method, rate, count): (&'static str, f64, usize),
    basis: &BSplineBasis,
    chans: &[Vec<f64>],
    ts: &[f64],
    fit_frames: usize,
) -> Result<Row, ReportError> {
    let (r, secs) = timed(|| -> Result<Vec<f64>, ReportError> {
        let mut errs = Vec::new();
        for y in chans {
            let c = fit_least_squares(basis, &ts[..fit_frames], &y[..fit_frames])?;
            errs.extend(ts.iter().zip(y).map(|(t, v)| c.eval(*t)[0] - v));
        }
        Ok(errs)
    });
    let (max_deg, rms_deg) = stats(r?.into_iter());
    Ok(Row {
        method,
        rate,
        count,
        max_deg,
        rms_deg,
        ms: secs * 1e3,
    })
}

/// Per coefficient rate (per second): a clamped cubic through every frame,
/// and a periodic one (cyclified: one cycle is the whole clip, the last
/// frame the first again).
fn spline_rows(
    chans: &[Vec<f64>],
    dt: f64,
    smoke: bool,
    tick: &mut dyn FnMut(),
) -> Result<Vec<Row>, ReportError> {
    let frames = chans.first().map_or(0, Vec::len);
    let duration = (frames - 1) as f64 * dt;
    let ts: Vec<f64> = (0..frames).map(|k| k as f64 * dt).collect();
    let rates: &[f64] = if smoke {
        &[4.0, 12.0]
    } else {
        &[2.0, 3.0, 4.0, 6.0, 8.0, 12.0, 16.0, 24.0]
    };
    let mut rows = Vec::new();
    for &cps in rates {
        let n = ((cps * duration).round() as usize + 3).clamp(4, frames);
        let basis = BSplineBasis::clamped_uniform(3, n, 0.0, duration)?;
        rows.push(fit_row(
            ("clamped B-spline", cps, n),
            &basis,
            chans,
            &ts,
            frames,
        )?);
        let np = ((cps * duration).round() as usize).clamp(4, frames - 1);
        let pb = BSplineBasis::periodic_uniform(3, np, 0.0, duration)?;
        rows.push(fit_row(
            ("periodic B-spline (cyclified)", cps, np),
            &pb,
            chans,
            &ts,
            frames - 1,
        )?);
        tick();
    }
    Ok(rows)
}

/// Per sampling rate: the clip's own curve resampled, rebuilt as a sampled
/// curve and compared with the original on a 240 Hz grid.
fn sampling_rows(
    chans: &[Vec<f64>],
    dt: f64,
    smoke: bool,
    tick: &mut dyn FnMut(),
) -> Result<Vec<Row>, ReportError> {
    let frames = chans.first().map_or(0, Vec::len);
    let duration = (frames - 1) as f64 * dt;
    let fine: Vec<f64> = (0..=(duration * 240.0).round() as usize)
        .map(|k| k as f64 / 240.0)
        .collect();
    let originals: Vec<Curve> = chans
        .iter()
        .map(|y| Curve::samples(0.0, dt, y.clone()).map_err(ReportError::from))
        .collect::<Result<_, _>>()?;
    let sps_list: &[f64] = if smoke {
        &[10.0, 30.0]
    } else {
        &[5.0, 7.5, 10.0, 15.0, 30.0, 60.0, 120.0]
    };
    let mut rows = Vec::new();
    for &sps in sps_list {
        let n = (duration * sps).round() as usize;
        let h = duration / n as f64;
        let (r, secs) = timed(|| -> Result<Vec<f64>, ReportError> {
            let mut errs = Vec::new();
            for c in &originals {
                let vals: Vec<f64> = (0..=n)
                    .map(|k| c.value(k as f64 * h))
                    .collect::<Result<_, _>>()?;
                let re = Curve::samples(0.0, h, vals)?;
                for &t in &fine {
                    let t = t.min(duration);
                    errs.push(re.value(t)? - c.value(t)?);
                }
            }
            Ok(errs)
        });
        let (max_deg, rms_deg) = stats(r?.into_iter());
        rows.push(Row {
            method: "sampled curve",
            rate: sps,
            count: n + 1,
            max_deg,
            rms_deg,
            ms: secs * 1e3,
        });
        tick();
    }
    Ok(rows)
}

/// The section's two figures: B-spline fits and sampled curves, error against time.
fn figures(rows: &[Row], frame_rate: f64) -> Vec<Figure> {
    let series =
        |label: &str, m: &str, f: &dyn Fn(&Row) -> (f64, f64), default_rate: Option<f64>| {
            let rs: Vec<&Row> = rows.iter().filter(|r| r.method == m).collect();
            Series {
                label: label.to_string(),
                points: rs.iter().map(|r| f(r)).collect(),
                default_at: default_rate
                    .and_then(|d| rs.iter().position(|r| (r.rate - d).abs() < 1e-9)),
            }
        };
    let max = |r: &Row| (r.ms, r.max_deg);
    vec![
        Figure {
            file: "mocap_bspline.svg".into(),
            title: "walk.bvh: B-spline coefficients → max error at the frames".into(),
            x_label: "fit time, all rotation channels (ms, this machine)".into(),
            y_label: "max error (°)".into(),
            series: vec![
                series("clamped B-spline", "clamped B-spline", &max, None),
                series(
                    "periodic B-spline (cyclified)",
                    "periodic B-spline (cyclified)",
                    &max,
                    None,
                ),
            ],
        },
        Figure {
            file: "mocap_sampling.svg".into(),
            title: "walk.bvh: samples per second → reconstruction error".into(),
            x_label: "resample + evaluate time (ms, this machine)".into(),
            y_label: "error on a 240 Hz grid (°)".into(),
            series: vec![
                series(
                    "sampled curve, max",
                    "sampled curve",
                    &max,
                    Some(frame_rate),
                ),
                series(
                    "sampled curve, rms",
                    "sampled curve",
                    &|r| (r.ms, r.rms_deg),
                    Some(frame_rate),
                ),
            ],
        },
    ]
}
