//! One method on one window: fill the gap, then score it against the
//! capture with `score`'s definitions (the ones `compare(…)` gives), plus
//! what only the benchmark reports: the largest change of a bone's length,
//! ∫Στ² over the gap, and SP's iterations, evaluations, convergence and time.

use super::case::Case;
use super::methods::Method;
use super::protocol::{Protocol, RootMode};
use crate::motion::channel::Channel;
use crate::motion::{Mu, clip_in_place};
use crate::report::error::ReportError;
use crate::score::{
    GroundFrames, JointPoses, PlanAccuracy, Which, given_contacts, grounding, joint_poses,
    plan_accuracy, reference_plan,
};
use crate::spacetime::{Contact, SpOptions, SpReport, sp, torque_energy};
use std::time::Instant;

/// What one method did on one window.
#[derive(Clone, Debug)]
pub struct WindowResult {
    pub clip: String,
    pub start: usize,
    pub gap: usize,
    pub root: RootMode,
    pub method: String,
    /// Mean joint-position error over the gap frames (cm).
    pub l2p: f64,
    /// Worst joint-position error (cm), its joint and frame.
    pub worst: f64,
    pub worst_joint: String,
    pub worst_frame: usize,
    /// Harvey et al.'s L2Q: per frame, the L2 norm of the stacked world
    /// orientations' difference (unit quaternions, sign-aligned), the mean
    /// over the gap's frames (`score::metrics`).
    pub l2q: f64,
    /// NPSS over the gap's frames (world orientations' quaternion series;
    /// `score::metrics::npss`), and the capture's total power it is weighted
    /// by when windows are pooled.
    pub npss: f64,
    pub npss_weight: f64,
    /// Largest change of a bone's length over the gap (m).
    pub bone: f64,
    /// ∫Στ² over the gap.
    pub energy: f64,
    /// `ground`'s measures over the gap and its edge frames, against the
    /// capture's floor (`score::grounding`): skate of a contact point within
    /// 2 cm of the floor (cm/s), depth below it (cm), ground residual mean
    /// and worst frame (% of body weight), and the same per frame.
    pub skate: f64,
    pub penetration: f64,
    pub residual: f64,
    pub residual_worst: f64,
    pub ground: GroundFrames,
    /// SP's contact plan against the capture's contacts (`score::plan`);
    /// `None` where the method planned none.
    pub plan: Option<PlanAccuracy>,
    pub iterations: u64,
    pub evaluations: u64,
    /// `Some(false)`: an SP solve stopped short of its rule (flagged).
    pub converged: Option<bool>,
    pub seconds: f64,
}

/// The largest change of a bone's length over the frames of `poses` (m):
/// each joint point against its parent's, but a root joint's (it hangs from
/// the origin by `case`'s root position channels: no bone).
fn bone_change(case: &Case, poses: &JointPoses) -> f64 {
    let root_links: Vec<bool> = poses
        .links
        .iter()
        .map(|&l| {
            let joint = &case.body.link(l).name;
            case.root_dofs.iter().any(|d| {
                let c = Channel::parse(d);
                c.suffix.is_some() && c.joint == joint
            })
        })
        .collect();
    let mut bone: f64 = 0.0;
    for (fil, cap) in poses.filled.iter().zip(&poses.reference) {
        for j in 0..poses.links.len() {
            if let (Some(pj), false) = (poses.parents[j], root_links[j]) {
                let lf = (fil[j].p - fil[pj].p).norm();
                let lc = (cap[j].p - cap[pj].p).norm();
                bone = bone.max((lf - lc).abs());
            }
        }
    }
    bone
}

/// Scores `filled` against the capture over the gap of the window at `start`
/// (`(start, gap)`: the window's first frame and the gap's length in frames).
pub fn score(
    case: &Case,
    p: &Protocol,
    (start, gap): (usize, usize),
    root: RootMode,
    method: &str,
    filled: &Mu,
    seconds: f64,
) -> Result<WindowResult, ReportError> {
    let first = start + p.context;
    let times: Vec<f64> = (first..first + gap).map(|k| case.time(k)).collect();
    let poses = joint_poses(&case.body, filled, &case.capture, &times)?;
    let a = poses.accuracy();
    let (t0, t1) = case.gap_span(first, gap);
    let energy = torque_energy(&clip_in_place(t0, t1, filled)?, &case.body, None)?;
    let g = grounding(
        (filled, Which::Filled),
        &case.body,
        (t0, t1),
        case.floor,
        1.0 / case.frame_time,
    )?;
    Ok(WindowResult {
        clip: case.name.clone(),
        start,
        gap,
        root,
        method: method.to_string(),
        l2p: a.l2p,
        worst: a.worst,
        worst_joint: a.worst_joint,
        worst_frame: first + a.worst_frame,
        l2q: a.l2q,
        npss: a.npss,
        npss_weight: a.npss_weight,
        bone: bone_change(case, &poses),
        energy,
        skate: g.skate,
        penetration: g.depth,
        residual: g.residual,
        residual_worst: g.residual_worst,
        ground: g.frames,
        plan: None,
        iterations: 0,
        evaluations: 0,
        converged: None,
        seconds,
    })
}

/// SP's contact plan of the window's gap against the capture's contacts
/// over it; `None` without a plan.
pub fn plan_score(
    case: &Case,
    p: &Protocol,
    (start, gap): (usize, usize),
    report: &SpReport,
) -> Result<Option<PlanAccuracy>, ReportError> {
    let first = start + p.context;
    let (t0, t1) = case.gap_span(first, gap);
    let Some(plan) = &report.contacts else {
        return Ok(None);
    };
    let Some(planned) = plan.gap_at(0.5 * (t0 + t1)) else {
        return Ok(None);
    };
    let links: Vec<usize> = planned.points.iter().map(|q| q.link).collect();
    let actual = reference_plan(&case.capture, &case.body, plan.floor.up, (t0, t1), &links)?;
    let times: Vec<f64> = (first..first + gap).map(|k| case.time(k)).collect();
    Ok(Some(plan_accuracy(planned, &actual, &times)))
}

/// What a method made of one window: the filled motion, SP's report, the time it took.
pub struct Filled {
    pub motion: Mu,
    pub report: Option<SpReport>,
    pub seconds: f64,
}

/// The options SP runs with for `method` (`None`: not SP), with what the
/// method is given made ahead: a held-out library (built once per file),
/// the capture's contacts.
fn sp_options(case: &Case, method: &Method) -> Result<Option<SpOptions>, ReportError> {
    Ok(match method {
        Method::Hermite | Method::Slerp | Method::Capture => None,
        Method::Sp(_, o) => Some((**o).clone()),
        Method::SpLibrary(_, o, l) => {
            let source = l.source(&case.source, case.skeleton.clone(), case.metres_per_unit)?;
            Some(SpOptions {
                library: Some(source),
                ..(**o).clone()
            })
        }
        Method::SpCaptureContacts(_, o) => {
            let mut given = SpOptions {
                contact: Contact::Given(given_contacts(&case.capture, &case.body)?),
                ..(**o).clone()
            };
            // a stated contact: it stands a given root too, as the language does
            given.ground.stand_root_given = true;
            Some(given)
        }
    })
}

/// Fills the window at `start` (gap `gap` frames) with `method`; errors name the clip.
pub fn fill_window(
    case: &Case,
    p: &Protocol,
    start: usize,
    gap: usize,
    root: RootMode,
    method: &Method,
) -> Result<Filled, ReportError> {
    let fill = || -> Result<Filled, ReportError> {
        let cut = case.cut(start, p.context, gap, root)?;
        // what SP is given is made before the clock starts
        let options = sp_options(case, method)?;
        let clock = Instant::now();
        let (motion, report) = match (options, method) {
            (Some(o), _) => {
                let (m, r) = sp(&cut, &case.body, &o)?;
                (m, Some(r))
            }
            (None, Method::Hermite) => (crate::spacetime::fill_hermite(&cut)?, None),
            (None, Method::Slerp) => (crate::motion::fill_slerp(&cut)?, None),
            (None, _) => (case.capture.clone(), None),
        };
        Ok(Filled {
            motion,
            report,
            seconds: clock.elapsed().as_secs_f64(),
        })
    };
    fill().map_err(|e| case.error(e))
}

/// Fills one window with one method and scores it.
pub fn run_window(
    case: &Case,
    p: &Protocol,
    start: usize,
    gap: usize,
    root: RootMode,
    method: &Method,
) -> Result<WindowResult, ReportError> {
    let in_clip = |e: ReportError| case.error(e);
    let f = fill_window(case, p, start, gap, root, method)?;
    let mut r = score(
        case,
        p,
        (start, gap),
        root,
        method.label(),
        &f.motion,
        f.seconds,
    )
    .map_err(in_clip)?;
    if let Some(rep) = f.report {
        r.iterations = rep.groups.iter().map(|g| g.iterations).sum();
        r.evaluations = rep.groups.iter().map(|g| g.evaluations).sum();
        r.converged = Some(rep.groups.iter().all(|g| g.converged()));
        r.plan = plan_score(case, p, (start, gap), &rep).map_err(in_clip)?;
    }
    Ok(r)
}
