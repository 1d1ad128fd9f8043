//! IK over time: a motion's frames moved so that links follow target
//! motions.
//!
//! The frames are the motion's own (its sample period, else 60 Hz, or a
//! given rate) over the times where the motion and every target are
//! defined. Frame k starts from the previous frame's solution plus the
//! input motion's change since then, q₀(t_k) = q*(t_{k−1}) + q(t_k) −
//! q(t_{k−1}): a warm start that stays a handful of iterations from the
//! answer and keeps the input's own movement in the DOFs no target pins
//! down (the first frame starts from the input pose).
//!
//! The result is the input motion with every moved DOF replaced by its
//! solved samples (a C² sampled curve over the solved frames); DOFs no
//! target needs are the input's, unchanged.

use super::frame::{Goal, Settings, Solver};
use super::{IkError, invalid};
use crate::lie::exp_so3;
use crate::model::Model;
use crate::motion::sample_period;
use crate::motion::{Curve, Dof, Interval, Mu, grid_times};
use nalgebra::{Matrix3, Vector3};

/// One link's target: its world position over time as three DOFs.
#[derive(Clone, Debug)]
pub struct Target {
    /// The link's name in the body.
    pub link: String,
    /// x, y, z (metres, world frame).
    pub position: [Dof; 3],
    /// The link frame's world orientation as a rotation vector rx, ry, rz
    /// (axis × angle, radians), when it matters.
    pub orientation: Option<[Dof; 3]>,
    /// Relative weight (> 0); only matters when not every target can be met.
    pub weight: f64,
}

/// Options of [`ik`].
#[derive(Clone, Debug, Default)]
pub struct IkOptions {
    pub settings: Settings,
    /// Coordinate names or globs IK may move (default: every coordinate on a
    /// target link's chain).
    pub only: Option<Vec<String>>,
    /// Frames per second (default: the motion's own, else 60).
    pub rate: Option<f64>,
}

/// How close one target came.
#[derive(Clone, Debug, PartialEq)]
pub struct TargetReport {
    pub link: String,
    /// Largest and mean distance (m) over the frames.
    pub max_residual: f64,
    pub mean_residual: f64,
    /// Frames where the distance stayed above the tolerance.
    pub unreachable_frames: usize,
    /// Time of the largest distance.
    pub worst_time: f64,
    /// Largest angle (rad) between the link's frame and its target
    /// orientation (0 without one).
    pub max_orientation_residual: f64,
}

/// What IK did.
#[derive(Clone, Debug, PartialEq)]
pub struct IkReport {
    pub targets: Vec<TargetReport>,
    pub frames: usize,
    /// Iterations per frame: most and mean.
    pub max_iterations: usize,
    pub mean_iterations: f64,
    /// Frames where some target was not met within the tolerance.
    pub unconverged_frames: usize,
    /// The DOFs IK moved.
    pub dofs: Vec<String>,
    pub tolerance: f64,
    /// First and last solved time (s).
    pub span: (f64, f64),
}

/// The link named `name`, or an error listing the nearest names.
fn link_index(body: &Model, name: &str) -> Result<usize, IkError> {
    body.link_index(name).ok_or_else(|| {
        let mut near: Vec<(f64, &str)> = body
            .links()
            .iter()
            .map(|l| {
                let s = strsim::normalized_damerau_levenshtein(
                    &name.to_lowercase(),
                    &l.name.to_lowercase(),
                );
                (s, l.name.as_str())
            })
            .collect();
        near.sort_by(|a, b| b.0.total_cmp(&a.0));
        let list: Vec<&str> = near.iter().take(5).map(|(_, s)| *s).collect();
        invalid(
            "targets",
            format!(
                "the body has no link named '{name}'; the nearest names are {}",
                list.join(", ")
            ),
        )
    })
}

/// Which coordinates IK may move.
fn allowed(body: &Model, m: &Mu, only: &Option<Vec<String>>) -> Result<Vec<bool>, IkError> {
    let names = body.coordinate_names();
    Ok(match only {
        None => vec![true; names.len()],
        Some(pats) => {
            // match against the body's coordinates, named as the motion's DOFs
            let mut coords = Mu::new();
            for n in names {
                coords.insert(n.clone(), m.get(n).cloned().unwrap_or_else(Dof::empty));
            }
            let refs: Vec<&str> = pats.iter().map(String::as_str).collect();
            let chosen = crate::motion::only(&coords, &refs)?;
            names.iter().map(|n| chosen.get(n).is_some()).collect()
        }
    })
}

/// Intersection of the spans of the motion's body coordinates and the targets.
fn common_span(m: &Mu, names: &[String], targets: &[Target]) -> Result<(f64, f64), IkError> {
    let mut span = (f64::NEG_INFINITY, f64::INFINITY);
    let mut cut =
        |s: Option<(f64, f64)>, what: &str, argument: &'static str| -> Result<(), IkError> {
            let s =
                s.ok_or_else(|| invalid(argument, format!("{what} is not defined anywhere")))?;
            span = (span.0.max(s.0), span.1.min(s.1));
            Ok(())
        };
    for n in names {
        cut(
            m.get(n).and_then(Dof::span),
            &format!("the motion's DOF `{n}`"),
            "m",
        )?;
    }
    for t in targets {
        for (d, axis) in t.position.iter().zip(["x", "y", "z"]) {
            cut(
                d.span(),
                &format!("the target {}.{axis}", t.link),
                "targets",
            )?;
        }
        for (d, axis) in t.orientation.iter().flatten().zip(["rx", "ry", "rz"]) {
            cut(
                d.span(),
                &format!("the target {}.{axis}", t.link),
                "targets",
            )?;
        }
    }
    if span
        .0
        .partial_cmp(&span.1)
        .is_none_or(|o| o == std::cmp::Ordering::Greater)
    {
        return Err(invalid(
            "targets",
            format!(
                "the motion and the targets are never defined at the same time (common span [{}, {}] is empty)",
                span.0, span.1
            ),
        ));
    }
    Ok(span)
}

/// Three target DOFs sampled at `t` (finite, or a clear error naming them).
fn target_at(
    link: &str,
    dofs: &[Dof; 3],
    axes: [&str; 3],
    t: f64,
) -> Result<Vector3<f64>, IkError> {
    let mut out = Vector3::zeros();
    for (k, (d, axis)) in dofs.iter().zip(axes).enumerate() {
        let name = format!("{link}.{axis}");
        let v = d.sample_value(&name, t)?.ok_or_else(|| {
            invalid(
                "targets",
                format!("the target {name} is undefined at t = {t:.4} s"),
            )
        })?;
        if !v.is_finite() {
            return Err(invalid(
                "targets",
                format!("the target {name} is {v} at t = {t:.4} s; targets must be finite"),
            ));
        }
        out[k] = v;
    }
    Ok(out)
}

/// Moves `m`'s frames so that each target's link follows its position (and
/// orientation, where one is given).
pub fn ik(
    body: &Model,
    m: &Mu,
    targets: &[Target],
    options: &IkOptions,
) -> Result<(Mu, IkReport), IkError> {
    if targets.is_empty() {
        return Err(invalid(
            "targets",
            "no targets: give at least one link and its position",
        ));
    }
    let s = options.settings;
    if !(s.tolerance.is_finite() && s.tolerance > 0.0) {
        return Err(invalid(
            "tolerance",
            format!(
                "the tolerance must be a positive number of metres, got {}",
                s.tolerance
            ),
        ));
    }
    if s.max_iterations == 0 {
        return Err(invalid(
            "iterations",
            "the iteration limit must be at least 1",
        ));
    }
    let names = body.coordinate_names().to_vec();
    if let Some(missing) = names.iter().find(|n| m.get(n).is_none()) {
        return Err(invalid(
            "m",
            format!(
                "the motion has no DOF `{missing}` for the body's coordinate of that name; use a body built for this motion"
            ),
        ));
    }
    let mut links = Vec::with_capacity(targets.len());
    for t in targets {
        if !(t.weight.is_finite() && t.weight > 0.0) {
            return Err(invalid(
                "weights",
                format!(
                    "the weight of target {} must be a positive number, got {}",
                    t.link, t.weight
                ),
            ));
        }
        let l = link_index(body, &t.link)?;
        if links.contains(&l) {
            return Err(invalid(
                "targets",
                format!("link {} has two targets", t.link),
            ));
        }
        links.push(l);
    }
    let allowed = allowed(body, m, &options.only)?;
    let mut solver = Solver::new(body, &links, &allowed)?;
    if solver.free().is_empty() {
        return Err(invalid(
            "targets",
            "no coordinate IK may move lies on a target link's chain; widen `only:` or pick other links",
        ));
    }
    let span = common_span(m, &names, targets)?;
    let rate = options
        .rate
        .unwrap_or_else(|| sample_period(m).map(|dt| 1.0 / dt).unwrap_or(60.0));
    let mut times = grid_times(span, rate)?;
    if times.is_empty() {
        times.push(span.0);
    }
    let sample_q =
        |t: f64, q: &mut [f64]| -> Result<(), IkError> {
            for (k, n) in names.iter().enumerate() {
                let v = m.dof(n)?.sample_value(n, t)?.ok_or_else(|| {
                invalid("m", format!(
                    "the motion's DOF `{n}` is undefined at t = {t:.4} s; fill the gap first"
                ))
            })?;
                q[k] = v;
            }
            Ok(())
        };
    let nf = solver.free().to_vec();
    let mut goals: Vec<Goal> = links
        .iter()
        .zip(targets)
        .map(|(&l, t)| Goal {
            link: l,
            position: Vector3::zeros(),
            orientation: t.orientation.as_ref().map(|_| Matrix3::identity()),
            weight: t.weight,
        })
        .collect();
    let (mut q_in, mut q_prev_in) = (vec![0.0; names.len()], vec![0.0; names.len()]);
    let mut q = vec![0.0; names.len()];
    let mut solved: Vec<Vec<f64>> = vec![Vec::with_capacity(times.len()); nf.len()];
    let mut residuals: Vec<Vec<f64>> = vec![Vec::with_capacity(times.len()); targets.len()];
    let mut turn_residuals = vec![0.0f64; targets.len()];
    let (mut iters_max, mut iters_sum, mut unconverged) = (0, 0usize, 0);
    for (k, &t) in times.iter().enumerate() {
        sample_q(t, &mut q_in)?;
        if k == 0 {
            q.copy_from_slice(&q_in);
        } else {
            for c in 0..q.len() {
                q[c] += q_in[c] - q_prev_in[c];
            }
            // coordinates IK does not move follow the input exactly
            for c in 0..q.len() {
                if !nf.contains(&c) {
                    q[c] = q_in[c];
                }
            }
        }
        for (g, tg) in goals.iter_mut().zip(targets) {
            g.position = target_at(&tg.link, &tg.position, ["x", "y", "z"], t)?;
            if let Some(o) = &tg.orientation {
                g.orientation = Some(exp_so3(&target_at(&tg.link, o, ["rx", "ry", "rz"], t)?));
            }
        }
        let fr = solver.solve(&mut q, &goals, &s)?;
        iters_max = iters_max.max(fr.iterations);
        iters_sum += fr.iterations;
        unconverged += usize::from(!fr.converged);
        for (r, e) in residuals.iter_mut().zip(&fr.position_error) {
            r.push(*e);
        }
        for (r, e) in turn_residuals.iter_mut().zip(&fr.orientation_error) {
            *r = r.max(*e);
        }
        for (col, &c) in solved.iter_mut().zip(&nf) {
            col.push(q[c]);
        }
        std::mem::swap(&mut q_in, &mut q_prev_in);
    }
    let mut out = m.clone();
    let (t0, t1) = (times[0], *times.last().unwrap_or(&times[0]));
    let dt = if times.len() > 1 {
        times[1] - times[0]
    } else {
        0.0
    };
    for (col, &c) in solved.into_iter().zip(&nf) {
        let curve = if times.len() > 1 {
            Curve::samples(t0, dt, col)?
        } else {
            Curve::constant(col[0])?
        };
        let stop = if times.len() > 1 { t1 } else { t0 };
        out.insert(
            names[c].clone(),
            Dof::new(vec![Interval::curve(curve, t0, stop)?])?,
        );
    }
    let report = IkReport {
        targets: targets
            .iter()
            .zip(&residuals)
            .zip(&turn_residuals)
            .map(|((tg, r), &turn)| {
                let (worst, max) = r
                    .iter()
                    .enumerate()
                    .fold((0, 0.0), |b, (i, &x)| if x > b.1 { (i, x) } else { b });
                TargetReport {
                    link: tg.link.clone(),
                    max_residual: max,
                    mean_residual: r.iter().sum::<f64>() / r.len() as f64,
                    unreachable_frames: r.iter().filter(|&&x| x > s.tolerance).count(),
                    worst_time: times[worst],
                    max_orientation_residual: turn,
                }
            })
            .collect(),
        frames: times.len(),
        max_iterations: iters_max,
        mean_iterations: iters_sum as f64 / times.len() as f64,
        unconverged_frames: unconverged,
        dofs: nf.iter().map(|&c| names[c].clone()).collect(),
        tolerance: s.tolerance,
        span: (t0, t1),
    };
    Ok((out, report))
}
