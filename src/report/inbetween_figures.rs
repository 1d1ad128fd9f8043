//! The in-betweening section's per-gap figures: for each root setting and
//! gap length it ran, one window (the locomotion window whose SP L2P is the
//! median of its kind, so the figure shows a typical gap, not the best or
//! the worst), filled again by SP at its defaults and by Hermite, and the
//! per-frame skate, depth and residual of the two and of the capture over
//! the whole window, the gap shaded (`ground_plot`). The measures are
//! `score::grounding`'s, the benchmark's own.

use super::error::ReportError;
use super::ground_plot::GroundFigure;
use super::inbetween::{
    Case, Method, Protocol, RootMode, SP_DEFAULTS, WindowResult, fill_window, is_locomotion,
    methods,
};
use crate::score::{GroundFrames, Which, grounding};

/// The window a figure of (root, gap) shows: among the SP rows of that
/// setting (locomotion clips when there are any), the one of median L2P.
pub fn typical_window(
    results: &[WindowResult],
    root: RootMode,
    gap: usize,
) -> Option<&WindowResult> {
    let of = |loco: bool| -> Vec<&WindowResult> {
        results
            .iter()
            .filter(|r| r.method == SP_DEFAULTS && r.root == root && r.gap == gap)
            .filter(|r| !loco || is_locomotion(&r.clip))
            .collect()
    };
    let mut rows = of(true);
    if rows.is_empty() {
        rows = of(false);
    }
    rows.sort_by(|a, b| a.l2p.total_cmp(&b.l2p).then(a.clip.cmp(&b.clip)));
    rows.get(rows.len() / 2).copied()
}

/// The figure of window `w` of `case`: SP at its defaults, Hermite and the
/// capture over the window's frames (context, gap, context), against the
/// capture's floor.
pub fn figure(case: &Case, p: &Protocol, w: &WindowResult) -> Result<GroundFigure, ReportError> {
    let first = w.start + p.context;
    let gap = case.gap_span(first, w.gap);
    let last = (first + w.gap + p.context).min(case.frames) - 1;
    let window = (case.time(w.start), case.time(last));
    let rate = 1.0 / case.frame_time;
    let frames = |m: &crate::motion::Mu| -> Result<GroundFrames, ReportError> {
        let g = grounding((m, Which::Filled), &case.body, window, case.floor, rate)?;
        Ok(g.frames)
    };
    let sp = methods()
        .into_iter()
        .find(|m| m.label() == SP_DEFAULTS)
        .unwrap_or(Method::Sp(SP_DEFAULTS.into(), Box::default()));
    let mut series = vec![];
    for (label, method) in [("SP defaults", sp), ("Hermite", Method::Hermite)] {
        let f = fill_window(case, p, w.start, w.gap, w.root, &method)?;
        series.push((label.to_string(), frames(&f.motion)?));
    }
    series.push(("capture".to_string(), frames(&case.capture)?));
    Ok(GroundFigure {
        file: format!(
            "inbetween_ground_{}_{}.svg",
            match w.root {
                RootMode::Given => "given",
                RootMode::Filled => "cut",
            },
            w.gap
        ),
        title: format!(
            "{} frame {}, {}-frame gap ({}): skate, depth, residual per frame",
            w.clip,
            w.start,
            w.gap,
            w.root.label()
        ),
        gap,
        series,
    })
}
