//! Spline-joint fitting work–precision on the OpenSim knee samples (paper
//! §6.2–6.3): control frames → max/RMS error against fit time, and the
//! smoothing weight → error to the clean samples against ∫‖∇S‖².

use super::plot::{Figure, Series};
use super::timed;
use crate::model::joint_fit::{FitOptions, fit_spline_joint, hessian_energy};
use crate::model::joints::{JointSamples, joint_error};
use crate::report::error::ReportError;
use std::path::Path;

pub struct FrameRow {
    pub frames: usize,
    pub max_mm: f64,
    pub rms_mm: f64,
    pub max_deg: f64,
    pub rms_deg: f64,
    pub ms: f64,
}

pub struct SmoothRow {
    pub weight: f64,
    pub energy: f64,
    pub max_mm: f64,
    pub rms_mm: f64,
    pub max_deg: f64,
    pub ms: f64,
}

pub struct Outcome {
    pub frames: Vec<FrameRow>,
    pub smoothing: Vec<SmoothRow>,
    pub noisy_frames: usize,
    pub figures: Vec<Figure>,
}

/// Noise of the smoothing study: 1 mm and 0.5° per axis (σ).
pub const NOISE_M: f64 = 1e-3;
pub const NOISE_DEG: f64 = 0.5;
pub const NOISE_SEED: u64 = 2024;

pub const DEFAULT_FRAMES: usize = 8;

/// The knee samples fitted with each count of control frames
/// ([`frame_rows`]), their noisy copy smoothed at each weight
/// ([`smoothing_rows`]), and the two [`figures`].
pub fn run(shared: &Path, smoke: bool, tick: &mut dyn FnMut()) -> Result<Outcome, ReportError> {
    let path = shared.join("data/opensim/knee_r_gait2392_samples.json");
    let clean = JointSamples::load(&path).map_err(|e| ReportError::InFile {
        path: path.clone(),
        source: Box::new(e.into()),
    })?;
    let frames = frame_rows(&clean, smoke, tick)?;
    let noisy_frames = 16;
    let smoothing = smoothing_rows(&clean, noisy_frames, smoke, tick)?;
    Ok(Outcome {
        figures: figures(&frames, &smoothing, noisy_frames),
        frames,
        smoothing,
        noisy_frames,
    })
}

/// Per count of control frames: the fit's error on the samples and its time.
fn frame_rows(
    clean: &JointSamples,
    smoke: bool,
    tick: &mut dyn FnMut(),
) -> Result<Vec<FrameRow>, ReportError> {
    let counts: &[usize] = if smoke {
        &[4, 8]
    } else {
        &[4, 5, 6, 8, 10, 12, 16, 24, 32]
    };
    let mut frames = Vec::new();
    for &n in counts {
        let opt = FitOptions {
            frames: n,
            ..Default::default()
        };
        let (r, secs) = timed(|| fit_spline_joint(clean, &opt));
        let r = r.map_err(|source| ReportError::Fit { frames: n, source })?;
        let e = joint_error(&r.joint, clean)?;
        frames.push(FrameRow {
            frames: n,
            max_mm: e.max_mm,
            rms_mm: e.rms_mm,
            max_deg: e.max_deg,
            rms_deg: e.rms_deg,
            ms: secs * 1e3,
        });
        tick();
    }
    Ok(frames)
}

/// Per smoothing weight: `noisy_frames` control frames fitted to the
/// samples with noise ([`NOISE_M`], [`NOISE_DEG`]), the curve's ∫‖∇S‖² and
/// its error to the clean samples.
fn smoothing_rows(
    clean: &JointSamples,
    noisy_frames: usize,
    smoke: bool,
    tick: &mut dyn FnMut(),
) -> Result<Vec<SmoothRow>, ReportError> {
    let (a, b) = clean.range();
    let dirty = clean.with_noise(NOISE_M, NOISE_DEG.to_radians(), NOISE_SEED);
    let weights: &[f64] = if smoke {
        &[0.0, 1e-3]
    } else {
        &[0.0, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2]
    };
    let mut smoothing = Vec::new();
    for &w in weights {
        let opt = FitOptions {
            frames: noisy_frames,
            smooth: w,
            ..Default::default()
        };
        let (r, secs) = timed(|| fit_spline_joint(&dirty, &opt));
        let r = r.map_err(|source| ReportError::Smoothing { weight: w, source })?;
        let e = joint_error(&r.joint, clean)?;
        smoothing.push(SmoothRow {
            weight: w,
            energy: hessian_energy(&r.joint, a, b, if smoke { 200 } else { 2000 }),
            max_mm: e.max_mm,
            rms_mm: e.rms_mm,
            max_deg: e.max_deg,
            ms: secs * 1e3,
        });
        tick();
    }
    Ok(smoothing)
}

/// Error against fit time per frame count; error against smoothness per weight.
fn figures(frames: &[FrameRow], smoothing: &[SmoothRow], noisy_frames: usize) -> Vec<Figure> {
    let d = frames.iter().position(|r| r.frames == DEFAULT_FRAMES);
    let col = |label: &str, f: &dyn Fn(&FrameRow) -> f64| Series {
        label: label.into(),
        points: frames.iter().map(|r| (r.ms, f(r))).collect(),
        default_at: d,
    };
    vec![
        Figure {
            file: "fit_frames.svg".into(),
            title: "Knee spline joint: control frames → error vs fit time".into(),
            x_label: "fit time (ms, this machine)".into(),
            y_label: "error on the OpenSim samples (mm or °)".into(),
            series: vec![
                col("max mm", &|r| r.max_mm),
                col("rms mm", &|r| r.rms_mm),
                col("max °", &|r| r.max_deg),
                col("rms °", &|r| r.rms_deg),
            ],
        },
        Figure {
            file: "fit_smoothing.svg".into(),
            title: format!("Smoothing noisy knee samples ({noisy_frames} frames)"),
            x_label: "∫‖∇S‖² dq".into(),
            y_label: "error to the clean samples (mm or °)".into(),
            series: vec![
                Series {
                    label: "max mm".into(),
                    points: smoothing.iter().map(|r| (r.energy, r.max_mm)).collect(),
                    default_at: smoothing.iter().position(|r| r.weight == 0.0),
                },
                Series {
                    label: "max °".into(),
                    points: smoothing.iter().map(|r| (r.energy, r.max_deg)).collect(),
                    default_at: smoothing.iter().position(|r| r.weight == 0.0),
                },
            ],
        },
    ]
}
