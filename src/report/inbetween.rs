//! The in-betweening benchmark: cut a gap out of a real clip, fill it, and
//! compare with the frames a person actually performed (the protocol of
//! `data/inbetween/README.md`, after Harvey et al. 2020's LaFAN1 benchmark).
//!
//! Windows start every `stride` frames; each keeps `context` frames before
//! the gap and every frame after it (at least `context` of them). The two
//! sides are separate sampled curves, so nothing a method sees was
//! interpolated through the frames it must recreate. With the root given the
//! root's channels keep their captured curve through the gap; with the root
//! filled every DOF is cut and the frames after the gap stay where they were
//! captured (SP's `root: "pinned"`).
//!
//! Metrics, over the gap's frames, from forward kinematics of the filled and
//! the captured motion on the same body: L2P (mean joint-position error, cm,
//! with the worst joint and frame), L2Q and NPSS as Harvey et al. report
//! them (the world joint orientations as sign-aligned unit quaternions: the
//! L2 distance of the stacked pose, and the similarity of their power
//! spectra over the gap; `super::metrics`), foot skate (mean
//! horizontal foot speed while within 5 cm of its lowest height in the
//! window, cm/s), the largest change of a bone's length (m), ∫Στ² over the
//! gap, and for SP its iterations, evaluations, convergence and time.
//! Beside them the README's ground measures (`crate::ground`) over the gap's
//! frames and the step on either side, against the floor of the whole
//! captured clip: skate (horizontal speed of a foot joint within 2 cm of the
//! floor, cm/s), penetration (deepest foot joint below it, cm) and the ground
//! residual (the force no friction-cone contact forces, μ 0.8, at foot joints
//! within 2 cm can supply, % of body weight); the capture is their reference
//! row, and the locomotion clips (walk, run, dash, turn) are summarised on their own.
//! Used by `benches/inbetween.rs`, `mx report` and the plausibility tests.

use super::leave_one_out::LeaveOneOut;
use super::metrics;
use crate::lie::Se3;
use crate::mocap::bvh::{Skeleton, Units};
use crate::mocap::{self, positions::joint_points};
use crate::model::Model;
use crate::motion::channel::Channel;
use crate::motion::{Curve, Dof, Interval, Mu};
use crate::report::error::ReportError;
use crate::spacetime::{SpOptions, sp, torque_energy};
use nalgebra::{Rotation3, UnitQuaternion, Vector3};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

/// The protocol's parameters (defaults: the shared folder's README).
#[derive(Clone, Debug)]
pub struct Protocol {
    /// Gap lengths in frames.
    pub gaps: Vec<usize>,
    /// Frames between window starts.
    pub stride: usize,
    /// Context frames kept before the gap (and at least as many after it).
    pub context: usize,
    /// At most this many windows per clip and gap length (evenly spread); `None`: all.
    pub windows_per_clip: Option<usize>,
    /// Root settings to run.
    pub roots: Vec<RootMode>,
}

impl Default for Protocol {
    fn default() -> Self {
        Protocol {
            gaps: vec![5, 15, 30, 45],
            stride: 40,
            context: 10,
            windows_per_clip: None,
            roots: vec![RootMode::Given, RootMode::Filled],
        }
    }
}

/// Whether the root's channels are kept inside the gap.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RootMode {
    Given,
    Filled,
}

impl RootMode {
    pub fn label(self) -> &'static str {
        match self {
            RootMode::Given => "root given",
            RootMode::Filled => "natural cut",
        }
    }
}

/// A way of filling the gaps.
#[derive(Clone, Debug)]
pub enum Method {
    Hermite,
    Slerp,
    /// The captured frames themselves: L2P 0 by definition; the row tells
    /// what a person's motion costs in ∫Στ² against the interpolations.
    Capture,
    /// SP with these options, under this label.
    Sp(String, Box<SpOptions>),
    /// SP with these options and, as the example's library, every clip of
    /// the folder but the window's own file ([`LeaveOneOut`]).
    SpLibrary(String, Box<SpOptions>, Arc<LeaveOneOut>),
}

impl Method {
    pub fn label(&self) -> &str {
        match self {
            Method::Hermite => "fill hermite",
            Method::Slerp => "fill slerp",
            Method::Capture => "capture (the answer)",
            Method::Sp(l, _) | Method::SpLibrary(l, _, _) => l,
        }
    }
}

/// One clip of the benchmark: its captured motion and the body of its skeleton.
pub struct Case {
    pub name: String,
    /// The file (name without extension) the clip was read from: its own
    /// name, or the clip a time warp or mirror was made of.
    pub source: String,
    pub capture: Mu,
    pub body: Model,
    pub frame_time: f64,
    pub frames: usize,
    /// DOFs of the root (the skeleton's first joint and, while it never moves,
    /// its first child: Bandai's all-zero `joint_Root` above `Hips`).
    pub root_dofs: Vec<String>,
    /// The floor: the lowest height a foot joint reaches in the captured clip (m).
    pub floor: f64,
    /// The clip's skeleton and length unit (a library's features are read through them).
    pub skeleton: Arc<Skeleton>,
    pub metres_per_unit: f64,
}

/// The frame rate the protocol counts frames at (Hz): gaps of 15/30/45
/// frames are 0.5/1/1.5 s, whatever rate a clip was captured at.
pub const PROTOCOL_RATE: f64 = 30.0;

/// Body mass of the benchmark's bodies (kg), `body_of`'s default.
pub const BODY_MASS: f64 = 70.0;

impl Case {
    /// The clip at `path` at its own frame rate.
    pub fn load(path: &Path) -> Result<Case, ReportError> {
        Case::load_at(path, None)
    }

    /// The clip at `path`, resampled to `rate` Hz when it was captured at
    /// another rate (`super::regrid::regrid`): the protocol counts frames at
    /// 30 fps ([`PROTOCOL_RATE`]), so a 120 Hz clip is read as its every
    /// fourth frame and a gap of 30 frames is 1 s on every clip.
    pub fn load_at(path: &Path, rate: Option<f64>) -> Result<Case, ReportError> {
        let clip =
            mocap::load(path, Units::Auto).map_err(|e| format!("{}: {e}", path.display()))?;
        let name = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let (mu, frame_time, frames) = match rate {
            Some(r) if ((1.0 / clip.frame_time) - r).abs() > 1e-3 * r => {
                let dt = 1.0 / r;
                let (mu, frames) = super::regrid::regrid(
                    &clip.mu,
                    (clip.frames - 1) as f64 * clip.frame_time,
                    1.0,
                    dt,
                )
                .map_err(|e| format!("{}: {e}", path.display()))?;
                (mu, dt, frames)
            }
            _ => (clip.mu, clip.frame_time, clip.frames),
        };
        Case::from_motion(
            &name,
            &name,
            mu,
            Arc::new(clip.skeleton),
            clip.units.metres_per_unit,
            (frame_time, frames),
        )
        .map_err(|e| ReportError::Check(format!("{}: {e}", path.display())))
    }

    /// A case from a motion sampled every `frame_time` s over `frames`
    /// frames from t = 0, played on `skeleton`'s body; `source` names the
    /// file it came from (a leave-one-out library leaves that file out).
    pub fn from_motion(
        name: &str,
        source: &str,
        mu: Mu,
        skeleton: Arc<Skeleton>,
        metres_per_unit: f64,
        (frame_time, frames): (f64, usize),
    ) -> Result<Case, ReportError> {
        let (body, _) = mocap::body_of_motion(&skeleton, &mu, BODY_MASS, metres_per_unit)
            .map_err(|e| e.to_string())?;
        let names = skeleton.channel_names();
        let starts = skeleton.channel_starts();
        let joint_dofs = |j: usize| -> Vec<String> {
            let n = skeleton.joints[j].channels.len();
            names[starts[j]..starts[j] + n].to_vec()
        };
        let constant = |dof: &str| {
            let v0 = mu.sample(dof, 0.0).ok().flatten().map(|s| s[0]);
            (0..frames).all(|k| {
                let t = k as f64 * frame_time;
                mu.sample(dof, t).ok().flatten().map(|s| s[0]) == v0
            })
        };
        let mut root_dofs = vec![];
        let mut j = 0;
        loop {
            let dofs = joint_dofs(j);
            let still = dofs.iter().all(|d| constant(d));
            root_dofs.extend(dofs);
            match skeleton.children(j).next() {
                Some(k) if still => j = k,
                _ => break,
            }
        }
        let feet = crate::ground::contact_points(&body, None).map_err(|e| e.to_string())?;
        let floor = crate::ground::tracks(&mu, &body, &feet, &ground_options(None, frame_time))
            .map_err(|e| e.to_string())?
            .lowest();
        Ok(Case {
            floor,
            name: name.to_string(),
            source: source.to_string(),
            capture: mu,
            body,
            frame_time,
            frames,
            root_dofs,
            metres_per_unit,
            skeleton,
        })
    }

    /// Every `.bvh` file in `dir`, sorted by name.
    pub fn load_dir(dir: &Path) -> Result<Vec<Case>, ReportError> {
        let mut paths: Vec<PathBuf> = std::fs::read_dir(dir)
            .map_err(|e| format!("{}: {e}", dir.display()))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x.eq_ignore_ascii_case("bvh")))
            .collect();
        paths.sort();
        paths.iter().map(|p| Case::load(p)).collect()
    }

    fn time(&self, frame: usize) -> f64 {
        frame as f64 * self.frame_time
    }

    /// Window starts for gap length `gap` under `p`.
    pub fn windows(&self, p: &Protocol, gap: usize) -> Vec<usize> {
        let need = 2 * p.context + gap;
        // a window needs a frame on each side of its gap, and a gap
        if p.context == 0 || gap == 0 || self.frames < need {
            return vec![];
        }
        let all: Vec<usize> = (0..=self.frames - need).step_by(p.stride.max(1)).collect();
        match p.windows_per_clip {
            Some(k) if k < all.len() => (0..k)
                .map(|i| all[(2 * i + 1) * all.len() / (2 * k)])
                .collect(),
            _ => all,
        }
    }

    /// The motion a method sees: frames `start .. start + context` and
    /// `start + context + gap ..` as two separate sampled curves per DOF (the
    /// root's DOFs whole when given).
    pub fn cut(
        &self,
        start: usize,
        context: usize,
        gap: usize,
        root: RootMode,
    ) -> Result<Mu, ReportError> {
        if context == 0 || gap == 0 || start + 2 * context + gap > self.frames {
            return Err(ReportError::Check(format!(
                "{}: no window of {context} context frames and a {gap}-frame gap at frame {start} in {} frames",
                self.name, self.frames
            )));
        }
        let a = start;
        let b = start + context; // first gap frame
        let c = b + gap; // first frame after the gap
        let end = self.frames;
        let mut out = Mu::new();
        for (name, _) in &self.capture.dofs {
            let values = |from: usize, to: usize| -> Result<Vec<f64>, ReportError> {
                (from..to)
                    .map(|k| {
                        self.capture
                            .sample(name, self.time(k))?
                            .map(|s| s[0])
                            .ok_or_else(|| {
                                ReportError::Check(format!("{name} undefined at frame {k}"))
                            })
                    })
                    .collect()
            };
            let piece = |from: usize, to: usize| -> Result<Interval, ReportError> {
                let v = values(from, to)?;
                let curve = Curve::samples(self.time(from), self.frame_time, v)?;
                Interval::curve(curve, self.time(from), self.time(to - 1))
                    .map_err(ReportError::from)
            };
            let keep_whole = root == RootMode::Given && self.root_dofs.contains(name);
            let dof = if keep_whole {
                Dof::new(vec![piece(a, end)?])
            } else {
                Dof::new(vec![piece(a, b)?, piece(c, end)?])
            }?;
            out.insert(name.clone(), dof);
        }
        Ok(out)
    }
}

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
    /// over the gap's frames ([`metrics`]).
    pub l2q: f64,
    /// NPSS over the gap's frames (world orientations' quaternion series;
    /// [`metrics::npss`]), and the capture's total power it is weighted by
    /// when windows are pooled.
    pub npss: f64,
    pub npss_weight: f64,
    /// Mean horizontal foot speed while the foot is near its lowest height (cm/s).
    pub skate: f64,
    /// Largest change of a bone's length over the gap (m).
    pub bone: f64,
    /// ∫Στ² over the gap.
    pub energy: f64,
    /// The README's ground measures over the gap (see the module doc): skate
    /// within 2 cm of the capture's floor (cm/s), depth below it (cm), ground
    /// residual mean and worst frame (% of body weight).
    pub ground_skate: f64,
    pub penetration: f64,
    pub residual: f64,
    pub residual_worst: f64,
    pub iterations: u64,
    pub evaluations: u64,
    /// `Some(false)`: an SP solve stopped short of its rule (flagged).
    pub converged: Option<bool>,
    pub seconds: f64,
}

/// World poses of the reported joints at time t.
fn poses(
    body: &Model,
    m: &Mu,
    t: f64,
    links: &[usize],
    buf: &mut Vec<Se3>,
) -> Result<Vec<Se3>, ReportError> {
    let names = body.coordinate_names();
    let mut q = vec![0.0; names.len()];
    for (k, n) in names.iter().enumerate() {
        q[k] = m
            .sample(n, t)?
            .map(|s| s[0])
            .ok_or_else(|| format!("{n} is undefined at t = {t}"))?;
    }
    body.forward_kinematics(&q, buf)?;
    Ok(links.iter().map(|&l| buf[l]).collect())
}

/// The ground measures' options at the protocol's settings (2 cm, the clip's frame rate).
fn ground_options(floor: Option<f64>, frame_time: f64) -> crate::ground::GroundOptions {
    crate::ground::GroundOptions {
        floor: floor.map_or(crate::ground::Floor::Auto, crate::ground::Floor::At),
        height: 0.02,
        rate: Some(1.0 / frame_time),
        ..Default::default()
    }
}

/// Friction coefficient of the ground residual (the README's μ).
pub const FRICTION: f64 = 0.8;

/// Whether a clip is locomotion (its name has walk, run, dash or turn: the
/// subset shown on its own).
pub fn is_locomotion(clip: &str) -> bool {
    let c = clip.to_ascii_lowercase();
    ["walk", "run", "dash", "turn"]
        .iter()
        .any(|k| c.contains(k))
}

fn is_foot(name: &str) -> bool {
    let n = name.to_ascii_lowercase();
    (n.contains("foot") || n.contains("toe") || n.contains("ankle")) && !n.ends_with(".end")
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
    let (links, parents) = joint_points(&case.body);
    let joint_names: Vec<String> = links
        .iter()
        .map(|&l| case.body.link(l).name.clone())
        .collect();
    let up = crate::ground::up_of(&case.body.default_gravity).unwrap_or_else(Vector3::y);
    let first = start + p.context;
    let root_links: Vec<bool> = links
        .iter()
        .map(|&l| {
            let joint = &case.body.link(l).name;
            case.root_dofs.iter().any(|d| {
                let c = Channel::parse(d);
                c.suffix.is_some() && c.joint == joint
            })
        })
        .collect();
    let mut buf = vec![];
    // captured and filled poses over the window's context, gap and first frame after
    let frames: Vec<usize> = (start..first + gap + 1).collect();
    let mut cap = vec![];
    let mut fil = vec![];
    for &k in &frames {
        let t = case.time(k);
        cap.push(poses(&case.body, &case.capture, t, &links, &mut buf)?);
        fil.push(poses(&case.body, filled, t, &links, &mut buf)?);
    }
    let in_gap = |i: usize| frames[i] >= first && frames[i] < first + gap;
    let quat =
        |x: &Se3| UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(x.r));
    // world orientations over the gap's frames, [joint][frame]
    let gap_quats = |all: &[Vec<Se3>]| -> Vec<Vec<UnitQuaternion<f64>>> {
        (0..links.len())
            .map(|j| {
                (0..frames.len())
                    .filter(|&i| in_gap(i))
                    .map(|i| quat(&all[i][j]))
                    .collect()
            })
            .collect()
    };
    let (fq, cq) = (gap_quats(&fil), gap_quats(&cap));
    let l2q = (0..gap)
        .map(|i| {
            let f: Vec<_> = fq.iter().map(|j| j[i]).collect();
            let c: Vec<_> = cq.iter().map(|j| j[i]).collect();
            metrics::l2q_frame(&f, &c)
        })
        .sum::<f64>()
        / gap.max(1) as f64;
    let series = |q: &[Vec<UnitQuaternion<f64>>]| -> Vec<Vec<f64>> {
        q.iter()
            .flat_map(|j| metrics::continuous_series(j))
            .collect()
    };
    let npss = metrics::npss(&series(&fq), &series(&cq));
    let (mut sum_p, mut count) = (0.0, 0usize);
    let (mut worst, mut worst_joint, mut worst_frame) = (0.0, String::new(), first);
    let mut bone: f64 = 0.0;
    for i in (0..frames.len()).filter(|&i| in_gap(i)) {
        for j in 0..links.len() {
            let e = (fil[i][j].p - cap[i][j].p).norm() * 100.0;
            sum_p += e;
            if e > worst {
                worst = e;
                worst_joint = joint_names[j].clone();
                worst_frame = frames[i];
            }
            count += 1;
            // (the root's link hangs from the origin by its position channels: no bone)
            if let (Some(pj), false) = (parents[j], root_links[j]) {
                let lf = (fil[i][j].p - fil[i][pj].p).norm();
                let lc = (cap[i][j].p - cap[i][pj].p).norm();
                bone = bone.max((lf - lc).abs());
            }
        }
    }
    // foot skate over the gap's frames (with the frames on either side for speed)
    let mut skate_sum = 0.0;
    let mut skate_n = 0usize;
    for j in (0..links.len()).filter(|&j| is_foot(&joint_names[j])) {
        let lowest = cap
            .iter()
            .map(|f| f[j].p.dot(&up))
            .fold(f64::INFINITY, f64::min);
        for i in 1..frames.len() {
            if !(in_gap(i) || in_gap(i - 1)) {
                continue;
            }
            if fil[i][j].p.dot(&up) - lowest <= 0.05 {
                let d = crate::ground::horizontal(&(fil[i][j].p - fil[i - 1][j].p), &up);
                skate_sum += d.norm() * 100.0 / case.frame_time;
                skate_n += 1;
            }
        }
    }
    let t0 = case.time(first - 1);
    let t1 = case.time(first + gap);
    let piece = crate::motion::clip_in_place(t0, t1, filled)?;
    let energy = torque_energy(&piece, &case.body, None)?;
    let go = ground_options(Some(case.floor), case.frame_time);
    let gerr = |e: crate::ground::GroundError| format!("{}: ground: {e}", case.name);
    let ground_skate = crate::ground::foot_skate(&piece, &case.body, &go)
        .map_err(gerr)?
        .mean;
    let penetration = crate::ground::penetration(&piece, &case.body, &go)
        .map_err(gerr)?
        .depth;
    let residual =
        crate::ground::ground_residual(&piece, &case.body, &go, FRICTION).map_err(gerr)?;
    Ok(WindowResult {
        clip: case.name.clone(),
        start,
        gap,
        root,
        method: method.to_string(),
        l2p: sum_p / count.max(1) as f64,
        worst,
        worst_joint,
        worst_frame,
        l2q,
        npss: npss.value(),
        npss_weight: npss.weight,
        skate: if skate_n == 0 {
            0.0
        } else {
            skate_sum / skate_n as f64
        },
        bone,
        energy,
        ground_skate,
        penetration,
        residual: residual.mean_force,
        residual_worst: residual.worst_force,
        iterations: 0,
        evaluations: 0,
        converged: None,
        seconds,
    })
}

/// What a method made of one window: the filled motion, SP's report, the time it took.
pub struct Filled {
    pub motion: Mu,
    pub report: Option<crate::spacetime::SpReport>,
    pub seconds: f64,
}

/// Fills the window at `start` (gap `gap` frames) with `method`.
pub fn fill_window(
    case: &Case,
    p: &Protocol,
    start: usize,
    gap: usize,
    root: RootMode,
    method: &Method,
) -> Result<Filled, ReportError> {
    let cut = case.cut(start, p.context, gap, root)?;
    // the leave-one-out library is built (once per file) before the clock starts
    let library = match method {
        Method::SpLibrary(_, _, l) => {
            let source = l.source(&case.source, case.skeleton.clone(), case.metres_per_unit);
            Some(source.map_err(|e| format!("{}: {e}", case.name))?)
        }
        _ => None,
    };
    let clock = Instant::now();
    let (motion, report) = match method {
        Method::Hermite => (crate::spacetime::fill_hermite(&cut)?, None),
        Method::Slerp => (crate::motion::fill_slerp(&cut)?, None),
        Method::Capture => (case.capture.clone(), None),
        Method::Sp(_, opts) | Method::SpLibrary(_, opts, _) => {
            let mut o = (**opts).clone();
            if library.is_some() {
                o.library = library;
            }
            let (m, r) = sp(&cut, &case.body, &o).map_err(|e| format!("{}: {e}", case.name))?;
            (m, Some(r))
        }
    };
    Ok(Filled {
        motion,
        report,
        seconds: clock.elapsed().as_secs_f64(),
    })
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
    let f = fill_window(case, p, start, gap, root, method)?;
    let mut r = score(
        case,
        p,
        (start, gap),
        root,
        method.label(),
        &f.motion,
        f.seconds,
    )?;
    if let Some(rep) = f.report {
        r.iterations = rep.groups.iter().map(|g| g.iterations).sum();
        r.evaluations = rep.groups.iter().map(|g| g.evaluations).sum();
        r.converged = Some(rep.groups.iter().all(|g| g.converged()));
    }
    Ok(r)
}

/// Every window of every case under every method (methods side by side on
/// the same windows), in parallel over windows (rayon; `RAYON_NUM_THREADS=1`
/// for one thread). Each window's methods run one after the other on one
/// thread, so their times compare; the results, in window order, do not
/// depend on the number of threads. SP rows whose options are the same
/// ([`same_options`]) are solved once per window and copied under each label.
pub fn run(
    cases: &[Case],
    p: &Protocol,
    methods: &[Method],
    progress: impl Fn(&WindowResult) + Sync,
) -> Result<Vec<WindowResult>, ReportError> {
    use rayon::prelude::*;
    let mut windows = vec![];
    for &root in &p.roots {
        for &gap in &p.gaps {
            for case in cases {
                for start in case.windows(p, gap) {
                    windows.push((root, gap, case, start));
                }
            }
        }
    }
    let firsts = [RootMode::Given, RootMode::Filled].map(|r| same_options(methods, r));
    let per_window: Vec<Result<Vec<WindowResult>, ReportError>> = windows
        .par_iter()
        .map(|&(root, gap, case, start)| {
            let mut rows: Vec<WindowResult> = Vec::with_capacity(methods.len());
            for (i, m) in methods.iter().enumerate() {
                let r = match firsts[usize::from(root == RootMode::Filled)][i] {
                    Some(j) => WindowResult {
                        method: m.label().to_string(),
                        ..rows[j].clone()
                    },
                    None => run_window(case, p, start, gap, root, m)?,
                };
                progress(&r);
                rows.push(r);
            }
            Ok(rows)
        })
        .collect();
    let mut out = Vec::with_capacity(windows.len() * methods.len());
    for rows in per_window {
        out.extend(rows?);
    }
    Ok(out)
}

/// For each method, the index of an earlier SP method with the same options
/// (their `Debug` text), whose result it shares; `None`: solve it. Only
/// [`Method::Sp`] rows share (a library row's options are filled per
/// window). With the root given no root channel is cut, so `root:` is moot
/// and left out of the comparison.
pub fn same_options(methods: &[Method], root: RootMode) -> Vec<Option<usize>> {
    let keys: Vec<Option<String>> = methods
        .iter()
        .map(|m| match m {
            Method::Sp(_, o) => {
                let mut o = (**o).clone();
                if root == RootMode::Given {
                    o.root = crate::spacetime::RootFill::default();
                }
                Some(format!("{o:?}"))
            }
            _ => None,
        })
        .collect();
    keys.iter()
        .enumerate()
        .map(|(i, k)| {
            let k = k.as_ref()?;
            keys[..i].iter().position(|e| e.as_ref() == Some(k))
        })
        .collect()
}

/// One row of the summary: a method at one gap length and root setting.
#[derive(Clone, Debug)]
pub struct Summary {
    pub root: RootMode,
    pub gap: usize,
    pub method: String,
    pub windows: usize,
    pub l2p: f64,
    pub worst: f64,
    pub worst_at: String,
    pub l2q: f64,
    /// NPSS pooled over the windows as LaFAN1's batch is (each window's
    /// dimensions weighted by the capture's power).
    pub npss: f64,
    pub skate: f64,
    pub bone: f64,
    pub energy: f64,
    /// Ground measures: mean skate (cm/s), mean and worst penetration (cm),
    /// mean residual and its worst frame over the windows (% of body weight).
    pub ground_skate: f64,
    pub penetration: f64,
    pub penetration_worst: f64,
    pub residual: f64,
    pub residual_worst: f64,
    /// Windows where this method is closer to the capture than Hermite (L2P).
    pub beats_hermite: usize,
    /// Windows whose ∫Στ² is below Hermite's.
    pub cheaper_than_hermite: usize,
    /// Windows whose worst joint error exceeds 1.5 × Hermite's worst + 5 cm.
    pub blowups: usize,
    pub not_converged: usize,
    pub iterations: f64,
    pub evaluations: f64,
    pub seconds: f64,
}

/// Means per (root, gap, method), each method compared window by window with Hermite.
pub fn summarise(results: &[WindowResult]) -> Vec<Summary> {
    let mut keys: Vec<(RootMode, usize, String)> = vec![];
    for r in results {
        let k = (r.root, r.gap, r.method.clone());
        if !keys.contains(&k) {
            keys.push(k);
        }
    }
    let hermite_of = |r: &WindowResult| {
        results.iter().find(|h| {
            h.method == Method::Hermite.label()
                && h.clip == r.clip
                && h.start == r.start
                && h.gap == r.gap
                && h.root == r.root
        })
    };
    keys.into_iter()
        .map(|(root, gap, method)| {
            let rows: Vec<&WindowResult> = results
                .iter()
                .filter(|r| r.root == root && r.gap == gap && r.method == method)
                .collect();
            let n = rows.len().max(1) as f64;
            let mean =
                |f: &dyn Fn(&WindowResult) -> f64| rows.iter().map(|r| f(r)).sum::<f64>() / n;
            let w = rows.iter().max_by(|a, b| a.worst.total_cmp(&b.worst));
            let (mut beats, mut cheaper, mut blowups) = (0, 0, 0);
            for r in &rows {
                if let Some(h) = hermite_of(r) {
                    beats += usize::from(r.l2p < h.l2p);
                    cheaper += usize::from(r.energy < h.energy);
                    blowups += usize::from(r.worst > 1.5 * h.worst + 5.0);
                }
            }
            Summary {
                root,
                gap,
                method,
                windows: rows.len(),
                l2p: mean(&|r| r.l2p),
                worst: w.map_or(0.0, |r| r.worst),
                worst_at: w.map_or(String::new(), |r| {
                    format!("{} {} @{}", r.clip, r.worst_joint, r.worst_frame)
                }),
                l2q: mean(&|r| r.l2q),
                npss: {
                    let mut pooled = metrics::NpssSum::default();
                    for r in &rows {
                        pooled.add(metrics::NpssSum {
                            weighted: r.npss * r.npss_weight,
                            weight: r.npss_weight,
                        });
                    }
                    pooled.value()
                },
                skate: mean(&|r| r.skate),
                bone: rows.iter().map(|r| r.bone).fold(0.0, f64::max),
                energy: mean(&|r| r.energy),
                ground_skate: mean(&|r| r.ground_skate),
                penetration: mean(&|r| r.penetration),
                penetration_worst: rows.iter().map(|r| r.penetration).fold(0.0, f64::max),
                residual: mean(&|r| r.residual),
                residual_worst: rows.iter().map(|r| r.residual_worst).fold(0.0, f64::max),
                beats_hermite: beats,
                cheaper_than_hermite: cheaper,
                blowups,
                not_converged: rows.iter().filter(|r| r.converged == Some(false)).count(),
                iterations: mean(&|r| r.iterations as f64),
                evaluations: mean(&|r| r.evaluations as f64),
                seconds: mean(&|r| r.seconds),
            }
        })
        .collect()
}

/// [`summarise`] over the locomotion clips only ([`is_locomotion`]).
pub fn summarise_locomotion(results: &[WindowResult]) -> Vec<Summary> {
    let loco: Vec<WindowResult> = results
        .iter()
        .filter(|r| is_locomotion(&r.clip))
        .cloned()
        .collect();
    summarise(&loco)
}

/// The summary as a Markdown table.
pub fn table(rows: &[Summary]) -> String {
    let mut s = String::from(
        "| root | gap | method | windows | L2P cm | ×Hermite | worst cm (where) | L2Q | NPSS | skate cm/s | bone Δ m | ∫Στ² | < Hermite L2P | < Hermite ∫Στ² | blow-ups | not converged | iters | evals | s/solve |\n\
         |---|---:|---|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        let h = rows
            .iter()
            .find(|h| h.root == r.root && h.gap == r.gap && h.method == Method::Hermite.label())
            .map_or(f64::NAN, |h| h.l2p);
        s.push_str(&format!(
            "| {} | {} | {} | {} | {:.2} | {:.2} | {:.1} ({}) | {:.3} | {:.4} | {:.1} | {:.1e} | {:.4e} | {}/{} | {}/{} | {} | {} | {:.0} | {:.0} | {:.3} |\n",
            r.root.label(),
            r.gap,
            r.method,
            r.windows,
            r.l2p,
            r.l2p / h,
            r.worst,
            r.worst_at,
            r.l2q,
            r.npss,
            r.skate,
            r.bone,
            r.energy,
            r.beats_hermite,
            r.windows,
            r.cheaper_than_hermite,
            r.windows,
            r.blowups,
            r.not_converged,
            r.iterations,
            r.evaluations,
            r.seconds
        ));
    }
    s
}

/// Label of SP at its defaults, the row issue 35's goals judge.
pub const SP_DEFAULTS: &str = "SP defaults";
/// Label of [`todays_sp`].
pub const TODAYS_SP: &str = "today's SP";

/// SP as it was before grounded SP changed the defaults: no contact
/// planning (`contact: "none"`), the kinematic root (`root: "pinned"`: the
/// frames after a cut root stay where they were captured, the root's x–z
/// a cubic between the sides) and the prior at its old weight with the
/// motion's own example. Every option that reproduces the old behaviour is
/// set here explicitly, so the row stays the "before" when a default moves
/// (the BOARD of issues 35/36 keeps this list).
pub fn todays_sp() -> SpOptions {
    use crate::spacetime::{Contact, Prior, RootFill, Support};
    SpOptions {
        contact: Contact::None,
        root: RootFill::Pinned,
        support: Support::Auto { box_size: 0.02 },
        prior: Prior {
            smoothness: 1e6,
            time_constant: None,
            example: true,
            anchor: false,
        },
        ..Default::default()
    }
}

/// The methods the benchmark and the report compare, on the same windows:
/// the two interpolation baselines, the capture itself (the reference row),
/// SP at its defaults, SP as it was before grounded SP ([`todays_sp`]) and
/// with foot contact planned (`contact: "auto"`).
pub fn methods() -> Vec<Method> {
    use crate::spacetime::SpOptions;
    vec![
        Method::Hermite,
        Method::Slerp,
        Method::Capture,
        Method::Sp(SP_DEFAULTS.into(), Box::default()),
        Method::Sp(TODAYS_SP.into(), Box::new(todays_sp())),
        Method::Sp(
            "SP contact: \"auto\"".into(),
            Box::new(SpOptions {
                contact: crate::spacetime::Contact::Auto,
                ..Default::default()
            }),
        ),
    ]
}

/// A row for each knob of SP's objective (`MX_INBETWEEN_KNOBS=1` in the
/// bench): Rose's ∫Στ² alone (`objective: "torque"`), the prior without the
/// example, the prior's weight (`smoothness:`), its time constant
/// (`time_constant:`, fixed instead of (0.32 s)²/gap), and SP without
/// support IK; each otherwise at the defaults.
pub fn knob_methods() -> Vec<Method> {
    use crate::spacetime::{Prior, SpOptions, Support};
    let sp = |label: &str, o: SpOptions| Method::Sp(label.into(), Box::new(o));
    let with_prior = |prior: Prior| SpOptions {
        prior,
        ..Default::default()
    };
    vec![
        sp("SP objective: \"torque\" (Rose)", with_prior(Prior::none())),
        sp(
            "SP example: \"none\"",
            with_prior(Prior {
                example: false,
                ..Prior::default()
            }),
        ),
        sp(
            "SP smoothness: 1e3",
            with_prior(Prior {
                smoothness: 1e3,
                ..Prior::default()
            }),
        ),
        sp(
            "SP time_constant: 0.1s",
            with_prior(Prior {
                time_constant: Some(0.1),
                ..Prior::default()
            }),
        ),
        sp(
            "SP time_constant: 0.3s",
            with_prior(Prior {
                time_constant: Some(0.3),
                ..Prior::default()
            }),
        ),
        sp(
            "SP support: []",
            SpOptions {
                support: Support::Off,
                ..Default::default()
            },
        ),
    ]
}

/// Label of SP following the leave-one-out library alone (issue 36's goals).
pub const SP_LIBRARY: &str = "SP example: lib (leave-one-out)";
/// Label of SP following `[lib, "self"]` (issue 36's goals).
pub const SP_LIBRARY_SELF: &str = "SP example: [lib, \"self\"] (leave-one-out)";

/// The rows that follow a clip library held out from the window's own file
/// (`MX_INBETWEEN_LIBRARY=1` in the bench): SP with `example: lib` and with
/// `example: [lib, "self"]`, lib every clip of the folder but the window's.
pub fn library_methods(libraries: Arc<LeaveOneOut>) -> Vec<Method> {
    use crate::spacetime::{Prior, SpOptions};
    let with = |label: &str, example_self: bool| {
        let o = SpOptions {
            prior: Prior {
                example: example_self,
                ..Prior::default()
            },
            ..Default::default()
        };
        Method::SpLibrary(label.into(), Box::new(o), libraries.clone())
    };
    vec![with(SP_LIBRARY, false), with(SP_LIBRARY_SELF, true)]
}

/// Every window's result as CSV rows (with a header), for plots and digging.
pub fn csv(results: &[WindowResult]) -> String {
    let mut s = String::from(
        "clip,start,gap,root,method,l2p_cm,worst_cm,worst_joint,worst_frame,l2q,npss,npss_weight,skate_cm_s,bone_m,energy,ground_skate_cm_s,penetration_cm,residual_pct_bw,residual_worst_pct_bw,iterations,evaluations,converged,seconds\n",
    );
    for r in results {
        s.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
            r.clip,
            r.start,
            r.gap,
            r.root.label(),
            r.method,
            r.l2p,
            r.worst,
            r.worst_joint,
            r.worst_frame,
            r.l2q,
            r.npss,
            r.npss_weight,
            r.skate,
            r.bone,
            r.energy,
            r.ground_skate,
            r.penetration,
            r.residual,
            r.residual_worst,
            r.iterations,
            r.evaluations,
            r.converged.map_or("", |c| if c { "yes" } else { "no" }),
            r.seconds
        ));
    }
    s
}
