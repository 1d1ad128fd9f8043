//! Judging a fill in one call: `compare(m, reference, body)` scores the gaps
//! SP filled in `m` (read from its report) or a span the caller names,
//! against `reference`, with the in-betweening benchmark's definitions from
//! the benchmark's own code (`report::inbetween` calls [`score_gap`]'s parts).
//!
//! Per gap [t0, t1] (the last frame before the hole and the first after it,
//! as SP reports a gap): L2P, L2Q and NPSS over the frames strictly inside
//! ([`super::accuracy`]); skate, depth and residual over the gap with its two
//! edge frames, by `ground`'s rules against the reference's floor
//! ([`super::grounding`]), for `m` and for the reference itself; and where
//! `m` carries SP's contact plan, the plan against the reference's contacts
//! ([`super::plan`]). Frames are the reference's (k · dt, dt its frame
//! period), so a 120 Hz capture is scored at 120 Hz. Over several gaps, each measure is the mean over gaps (NPSS pooled
//! by the reference's power, depth and residual also worst, the plan by its
//! counts), as the benchmark pools windows.

use super::accuracy::{Accuracy, accuracy};
use super::error::{ScoreError, Which};
use super::grounding::{Grounding, floor_of, grounding};
use super::metrics::NpssSum;
use super::plan::{PlanAccuracy, plan_accuracy, reference_plan};
use crate::model::Model;
use crate::motion::{Mu, sample_period};
use crate::spacetime::{ContactPlan, SpReport};

/// One gap scored.
#[derive(Clone, Debug, PartialEq)]
pub struct GapScore {
    pub t0: f64,
    pub t1: f64,
    /// The frames strictly inside the gap (s).
    pub times: Vec<f64>,
    pub accuracy: Accuracy,
    /// `m`'s ground measures and the reference's own, over the same frames.
    pub filled: Grounding,
    pub reference: Grounding,
    /// SP's plan against the reference's contacts, where `m` has one for the gap.
    pub plan: Option<PlanAccuracy>,
}

/// Every gap scored, against one floor at one frame rate.
#[derive(Clone, Debug, PartialEq)]
pub struct Comparison {
    /// The reference's floor (m, along up) and its frame rate (Hz).
    pub floor: f64,
    pub rate: f64,
    pub gaps: Vec<GapScore>,
}

impl Comparison {
    fn mean(&self, f: impl Fn(&GapScore) -> f64) -> f64 {
        self.gaps.iter().map(f).sum::<f64>() / self.gaps.len().max(1) as f64
    }

    fn most(&self, f: impl Fn(&GapScore) -> f64) -> f64 {
        self.gaps.iter().map(f).fold(0.0, f64::max)
    }

    pub fn l2p(&self) -> f64 {
        self.mean(|g| g.accuracy.l2p)
    }
    pub fn l2q(&self) -> f64 {
        self.mean(|g| g.accuracy.l2q)
    }
    /// NPSS pooled over the gaps, each weighted by the reference's power.
    pub fn npss(&self) -> f64 {
        let mut pooled = NpssSum::default();
        for g in &self.gaps {
            pooled.add(NpssSum {
                weighted: g.accuracy.npss * g.accuracy.npss_weight,
                weight: g.accuracy.npss_weight,
            });
        }
        pooled.value()
    }
    /// The gap with the worst joint error.
    pub fn worst(&self) -> Option<&GapScore> {
        self.gaps
            .iter()
            .max_by(|a, b| a.accuracy.worst.total_cmp(&b.accuracy.worst))
    }
    /// Mean skate, depth and residual of `m` (`reference`: of the reference).
    pub fn skate(&self, reference: bool) -> f64 {
        self.mean(|g| pick(g, reference).skate)
    }
    pub fn depth(&self, reference: bool) -> f64 {
        self.mean(|g| pick(g, reference).depth)
    }
    pub fn depth_worst(&self, reference: bool) -> f64 {
        self.most(|g| pick(g, reference).depth)
    }
    pub fn residual(&self, reference: bool) -> f64 {
        self.mean(|g| pick(g, reference).residual)
    }
    pub fn residual_worst(&self, reference: bool) -> f64 {
        self.most(|g| pick(g, reference).residual_worst)
    }
    /// The plan's counts pooled over the gaps that have one.
    pub fn plan(&self) -> Option<PlanAccuracy> {
        self.gaps.iter().filter_map(|g| g.plan).reduce(|mut a, b| {
            a.add(&b);
            a
        })
    }
}

fn pick(g: &GapScore, reference: bool) -> &Grounding {
    if reference { &g.reference } else { &g.filled }
}

/// The gaps SP filled, from its report: the spans of its solved groups and
/// of the DOFs it filled by Hermite or held constant; spans that overlap
/// are one gap.
pub fn filled_spans(report: &SpReport) -> Vec<(f64, f64)> {
    let mut spans: Vec<(f64, f64)> = report
        .groups
        .iter()
        .map(|g| (g.t0, g.t1))
        .chain(
            report
                .hermite
                .iter()
                .chain(&report.constant)
                .map(|u| (u.start, u.stop)),
        )
        .collect();
    spans.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut out: Vec<(f64, f64)> = vec![];
    for (a, b) in spans {
        match out.last_mut() {
            Some(last) if a < last.1 || (a - last.0).abs() <= 1e-9 * a.abs().max(1.0) => {
                last.1 = last.1.max(b);
            }
            _ => out.push((a, b)),
        }
    }
    out
}

/// The time between a reference's frames: its sampled curves' step, else
/// 1/30 s as `ground` samples a motion without frames.
pub fn frame_period(reference: &Mu) -> f64 {
    sample_period(reference).unwrap_or(1.0 / 30.0)
}

/// At most this many frames in one gap (a 10-minute gap at 1 kHz).
const MAX_FRAMES: f64 = 6e5;

/// The frames k · `period` strictly inside (t0, t1): a clip's own frame
/// times (frame k of a clip starting at 0 is at k · dt, as the benchmark
/// counts them).
pub fn frames_inside((t0, t1): (f64, f64), period: f64) -> Result<Vec<f64>, ScoreError> {
    if !(t0.is_finite() && t1.is_finite() && t0 < t1) {
        return Err(ScoreError::BadSpan { t0, t1 });
    }
    let rate = 1.0 / period;
    if !(period.is_finite() && period > 0.0) || (t1 - t0) * rate > MAX_FRAMES {
        return Err(ScoreError::NoFrames { t0, t1, rate });
    }
    let near = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(1.0);
    let (k0, k1) = ((t0 * rate).floor() as i64, (t1 * rate).ceil() as i64);
    let times: Vec<f64> = (k0..=k1)
        .map(|k| k as f64 * period)
        .filter(|&t| t > t0 && t < t1 && !near(t, t0) && !near(t, t1))
        .collect();
    if times.is_empty() {
        return Err(ScoreError::NoFrames { t0, t1, rate });
    }
    Ok(times)
}

/// One gap [t0, t1] of `m` against `reference` on `body`, against `floor`,
/// on frames `period` s apart, with SP's plan of it if any.
pub fn score_gap(
    (m, reference): (&Mu, &Mu),
    body: &Model,
    (t0, t1): (f64, f64),
    (floor, period): (f64, f64),
    plan: Option<&ContactPlan>,
) -> Result<GapScore, ScoreError> {
    let times = frames_inside((t0, t1), period)?;
    let rate = 1.0 / period;
    let accuracy = accuracy(body, m, reference, &times)?;
    let filled = grounding((m, Which::Filled), body, (t0, t1), floor, rate)?;
    let own = grounding((reference, Which::Reference), body, (t0, t1), floor, rate)?;
    let plan = match plan.and_then(|p| Some((p, p.gap_at(0.5 * (t0 + t1))?))) {
        Some((p, gap)) => {
            let links: Vec<usize> = gap.points.iter().map(|q| q.link).collect();
            let actual = reference_plan(reference, body, p.floor.up, (t0, t1), &links)?;
            Some(plan_accuracy(gap, &actual, &times))
        }
        None => None,
    };
    Ok(GapScore {
        t0,
        t1,
        times,
        accuracy,
        filled,
        reference: own,
        plan,
    })
}

/// `m` against `reference` on `body` over `spans`, or, when `spans` is
/// empty, over the gaps SP filled (`report`; an error without one).
pub fn compare(
    m: &Mu,
    reference: &Mu,
    body: &Model,
    spans: &[(f64, f64)],
    report: Option<&SpReport>,
) -> Result<Comparison, ScoreError> {
    let spans = match (spans, report) {
        ([], None) => {
            return Err(ScoreError::NoFilledGaps {
                why: "it carries no SP report: it was not returned by SP, or changed since",
            });
        }
        ([], Some(r)) => filled_spans(r),
        (s, _) => s.to_vec(),
    };
    if spans.is_empty() {
        return Err(ScoreError::NoFilledGaps {
            why: "its SP report lists no interior gap",
        });
    }
    let period = frame_period(reference);
    let rate = 1.0 / period;
    let floor = floor_of(reference, body, rate)?;
    let plan = report.and_then(|r| r.contacts.as_ref());
    let gaps = spans
        .iter()
        .map(|&span| score_gap((m, reference), body, span, (floor, period), plan))
        .collect::<Result<_, _>>()?;
    Ok(Comparison { floor, rate, gaps })
}
