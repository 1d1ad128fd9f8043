//! Stage 3, support limbs (Rose §3.2.2, see [`crate::spacetime::hold`]):
//! per group of overlapping gaps, find the support frames (detected or
//! named), solve the gap DOFs on their chains by IK and write those curves
//! back (`contact:` plans the feet instead: [`super::hold_contacts`]).

use super::checks::motion_err;
use super::filling::Filling;
use super::held_limbs::{moves, span, write_hold_solve};
use super::options::{SpOptions, Support};
use crate::model::{Model, RootCoords};
use crate::spacetime::error::SpError;
use crate::spacetime::hold::{self, HoldObjective};
use crate::spacetime::objective::GapDof;
use crate::spacetime::solve::group_overlapping;

/// The gaps left for the spacetime solve after the support limbs' chains
/// were solved by IK and written into the motion.
pub(super) fn hold_supports(
    f: &mut Filling<'_>,
    opts: &SpOptions,
    gaps: Vec<GapDof>,
) -> Result<Vec<GapDof>, SpError> {
    let named = match &opts.support {
        Support::Off => return Ok(gaps),
        Support::Named(names) => Some(hold::named(f.model, names, "support")?),
        Support::Auto { .. } => None,
    };
    let mut left = vec![];
    for group in group_overlapping(gaps) {
        left.extend(hold_group(f, opts, named.as_deref(), group)?);
    }
    Ok(left)
}

/// The frames some gap DOF of `group` moves: the gap DOFs on the chains
/// from the frames to the root are the IK unknowns, and a frame no gap DOF
/// moves has nothing to solve.
fn moved_by(model: &Model, root: &RootCoords, frames: Vec<usize>, group: &[GapDof]) -> Vec<usize> {
    frames
        .into_iter()
        .filter(|&fr| group.iter().any(|d| moves(model, root, fr, d.coord)))
        .collect()
}

/// One group: its support frames, their chains solved by IK and written
/// back. Returns the group's gaps on no held chain.
fn hold_group(
    f: &mut Filling<'_>,
    opts: &SpOptions,
    named: Option<&[usize]>,
    group: Vec<GapDof>,
) -> Result<Vec<GapDof>, SpError> {
    let model = f.model;
    let (t0, t1) = span(&group);
    let detected = named.is_none();
    let solved = {
        let sampler = f.sampler();
        let configuration = |t: f64| sampler.positions(t).map_err(motion_err);
        let frames = match named {
            Some(frames) => moved_by(model, &f.root, frames.to_vec(), &group),
            None => detect_frames(f, opts, &group, &configuration)?,
        };
        let root = &f.root;
        let on_chain = |c: usize| frames.iter().any(|&fr| moves(model, root, fr, c));
        let (ik, rest): (Vec<GapDof>, Vec<GapDof>) =
            group.into_iter().partition(|d| on_chain(d.coord));
        if ik.is_empty() {
            return Ok(rest);
        }
        let obj = HoldObjective::new(model, frames.clone(), ik, &opts.settings, &configuration)?;
        let x = obj.solve(&opts.solve.cancel)?;
        (obj, x, frames, rest)
    };
    let (obj, x, frames, rest) = solved;
    write_hold_solve(f, &obj, &x, &frames, (t0, t1), detected)?;
    Ok(rest)
}

/// The support frames detected around a group: frames whose world position
/// stays in the box over the motion's ends next to the gap, that a gap DOF
/// moves, and that the Hermite start would let slide out of the box.
fn detect_frames(
    f: &Filling<'_>,
    opts: &SpOptions,
    group: &[GapDof],
    configuration: &dyn Fn(f64) -> Result<Vec<f64>, SpError>,
) -> Result<Vec<usize>, SpError> {
    let Support::Auto { box_size } = opts.support else {
        return Ok(vec![]);
    };
    let (model, (t0, t1)) = (f.model, span(group));
    let mut qs = vec![];
    for i in 0..hold::WINDOW_SAMPLES {
        let dt = hold::WINDOW * i as f64 / (hold::WINDOW_SAMPLES - 1) as f64;
        for t in [t0 - dt, t1 + dt] {
            let q = configuration(t)?;
            // the motion may not reach that far: use what is defined
            if q.iter().all(|v| v.is_finite()) {
                qs.push(q);
            }
        }
    }
    let root = &f.root;
    let frames = moved_by(
        model,
        root,
        hold::detect(model, &qs, &f.gravity, box_size)?,
        group,
    );
    if frames.is_empty() {
        return Ok(frames);
    }
    // A detected support is held only where interpolation would let it
    // slide out of its box: elsewhere (short gaps, mostly) the Hermite
    // curves already keep it planted, and IK would only add torque.
    let chain: Vec<GapDof> = group
        .iter()
        .filter(|d| frames.iter().any(|&fr| moves(model, root, fr, d.coord)))
        .cloned()
        .collect();
    let probe = HoldObjective::new(model, frames.clone(), chain, &opts.settings, configuration)?;
    let drift = probe.largest_drift(&probe.hermite_start())?;
    Ok(frames
        .into_iter()
        .zip(drift)
        .filter(|&(_, d)| d > box_size)
        .map(|(fr, _)| fr)
        .collect())
}

#[cfg(test)]
mod tests {
    use super::super::fixture::{Y_UP, body, motion};
    use super::*;
    use crate::spacetime::objective::TransitionSettings;

    fn gapped() -> (Model, crate::motion::Mu) {
        let model = body();
        let m = motion(&model, &[3, 4], (0.8, 1.2));
        (model, m)
    }

    #[test]
    fn a_named_support_holds_its_chain_and_leaves_nothing_to_solve() {
        let (model, m) = gapped();
        let mut f = Filling::new(&m, &model, Y_UP);
        let gaps = f.gaps().unwrap();
        let opts = SpOptions {
            support: Support::Named(vec!["foot".into()]),
            settings: TransitionSettings {
                coefficients: 3,
                samples: 8,
                ..Default::default()
            },
            ..Default::default()
        };
        let left = hold_supports(&mut f, &opts, gaps).unwrap();
        // hip and knee both move the foot: IK solved them both
        assert!(left.is_empty(), "{left:?}");
        let held = &f.report.support;
        assert_eq!(held.len(), 1);
        assert_eq!((held[0].frame.as_str(), held[0].detected), ("foot", false));
        assert_eq!(held[0].dofs, vec!["hip".to_string(), "knee".to_string()]);
        assert!(held[0].moved <= held[0].moved_before, "{held:?}");
        assert!(f.gaps().unwrap().is_empty());
    }

    #[test]
    fn no_support_leaves_every_gap() {
        let (model, m) = gapped();
        let mut f = Filling::new(&m, &model, Y_UP);
        let gaps = f.gaps().unwrap();
        let opts = SpOptions {
            support: Support::Off,
            ..Default::default()
        };
        assert_eq!(hold_supports(&mut f, &opts, gaps.clone()).unwrap(), gaps);
        assert!(f.report.support.is_empty());
    }
}
