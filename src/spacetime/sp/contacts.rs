//! Stage 3 with `contact:` (see [`crate::spacetime::contact`]): per group of
//! overlapping gaps, plan each contact frame's plants from the motion around
//! it, solve the gap DOFs on the chains of the planted frames by IK (planted
//! frames held, every contact frame on those chains kept at or above the
//! floor) and write those curves back.

use super::checks::motion_err;
use super::filling::Filling;
use super::held::{moves, span, write_support_solve};
use super::options::SpOptions;
use super::report::GapContacts;
use crate::spacetime::contact::{self, Contact, Context};
use crate::spacetime::error::SpError;
use crate::spacetime::objective::GapDof;
use crate::spacetime::solve::group_overlapping;
use crate::spacetime::support::{self, Floor, SupportObjective};
use nalgebra::Vector3;

/// Seconds between the poses the default floor is read from.
const FLOOR_STEP: f64 = 1.0 / 30.0;

/// The gaps left for the spacetime solve after the contact plan's chains
/// were solved by IK and written into the motion.
pub(super) fn hold_contacts(
    f: &mut Filling<'_>,
    opts: &SpOptions,
    gaps: Vec<GapDof>,
) -> Result<Vec<GapDof>, SpError> {
    let gravity = f.gravity;
    if gravity.norm() == 0.0 {
        return Ok(gaps); // no gravity, no floor: nothing stands on anything
    }
    let up = -gravity / gravity.norm();
    let (candidates, named) = match &opts.contact {
        Contact::Named(n) => (support::named(f.model, n, "contact")?, true),
        _ => (support::candidates(f.model), false),
    };
    let height = match opts.floor {
        Some(h) => h,
        None => match recorded_floor(f, &candidates, &up)? {
            Some(h) => h,
            None => return Ok(gaps), // never fully defined: nothing to stand on
        },
    };
    let floor = contact::floor(&gravity, height)?;
    let plan = Plan {
        up,
        candidates: &candidates,
        named,
        height,
        floor,
    };
    let mut left = vec![];
    for group in group_overlapping(gaps) {
        left.extend(hold_group(f, opts, &plan, group)?);
    }
    Ok(left)
}

/// The floor's height under the motion's recorded part: every pose where the
/// whole body is defined (`None`: there is none).
fn recorded_floor(
    f: &Filling<'_>,
    candidates: &[usize],
    up: &Vector3<f64>,
) -> Result<Option<f64>, SpError> {
    let Some((s, e)) = f.motion.span() else {
        return Ok(None);
    };
    let sampler = f.sampler();
    let n = ((e - s) / FLOOR_STEP).ceil() as usize;
    let mut qs = vec![];
    for k in 0..=n {
        let q = sampler
            .positions((s + k as f64 * FLOOR_STEP).min(e))
            .map_err(motion_err)?;
        if q.iter().all(|v| v.is_finite()) {
            qs.push(q);
        }
    }
    contact::floor_of(f.model, candidates, up, &qs)
}

/// What every group's contact plan shares.
struct Plan<'c> {
    up: Vector3<f64>,
    candidates: &'c [usize],
    named: bool,
    height: f64,
    floor: Floor,
}

/// One group: plan its contacts, report them, and hold the planted frames'
/// chains by IK. Returns the group's gaps on no planted chain.
fn hold_group(
    f: &mut Filling<'_>,
    opts: &SpOptions,
    plan: &Plan<'_>,
    group: Vec<GapDof>,
) -> Result<Vec<GapDof>, SpError> {
    let model = f.model;
    let (t0, t1) = span(&group);
    let solved = {
        let sampler = f.sampler();
        let configuration = |t: f64| sampler.positions(t).map_err(motion_err);
        let ctx = Context::new(
            model,
            plan.up,
            plan.candidates,
            plan.named,
            plan.height,
            (t0, t1),
            &configuration,
        )?;
        let plants = ctx.plan();
        let phases = ctx.phases(&plants);
        // the chains of the planted frames are solved by IK
        let planted: Vec<usize> = ctx
            .frames()
            .iter()
            .zip(&plants)
            .filter(|(_, p)| !p.is_empty())
            .map(|(&fr, _)| fr)
            .collect();
        let on_chain = |c: usize| planted.iter().any(|&fr| moves(model, fr, c));
        let (ik, rest): (Vec<GapDof>, Vec<GapDof>) =
            group.into_iter().partition(|d| on_chain(d.coord));
        if ik.is_empty() {
            (phases, rest, None)
        } else {
            // every contact frame those DOFs move: planted ones held, all above the floor
            let (frames, frame_plants): (Vec<usize>, Vec<_>) = ctx
                .frames()
                .iter()
                .zip(plants)
                .filter(|(fr, _)| ik.iter().any(|d| moves(model, **fr, d.coord)))
                .map(|(&fr, p)| (fr, p))
                .unzip();
            let obj = SupportObjective::planned(
                model,
                frames.clone(),
                frame_plants,
                plan.floor,
                ik,
                &opts.settings,
                &configuration,
            )?;
            let x = obj.solve(&opts.solve.cancel)?;
            (phases, rest, Some((obj, x, frames)))
        }
    };
    let (phases, rest, held) = solved;
    f.report.contacts.push(GapContacts {
        t0,
        t1,
        floor: plan.height,
        phases,
    });
    if let Some((obj, x, frames)) = held {
        write_support_solve(f, &obj, &x, &frames, (t0, t1), true)?;
    }
    Ok(rest)
}

#[cfg(test)]
mod tests {
    use super::super::fixture::{Y_UP, body, motion};
    use super::*;

    #[test]
    fn each_group_gets_a_contact_schedule_and_no_gravity_means_no_floor() {
        let model = body();
        let m = motion(&model, &[3, 4], (0.8, 1.2));
        let opts = SpOptions {
            contact: Contact::Named(vec!["foot".into()]),
            floor: Some(-2.0),
            ..Default::default()
        };
        let mut f = Filling::new(&m, &model, Vector3::zeros());
        let gaps = f.gaps().unwrap();
        assert_eq!(hold_contacts(&mut f, &opts, gaps.clone()).unwrap(), gaps);
        assert!(f.report.contacts.is_empty());
        let mut f = Filling::new(&m, &model, Y_UP);
        // a floor far below: the foot is never planted, nothing held by IK
        let left = hold_contacts(&mut f, &opts, gaps.clone()).unwrap();
        assert_eq!(left, gaps);
        let c = &f.report.contacts;
        assert_eq!(c.len(), 1);
        assert_eq!((c[0].t0, c[0].t1, c[0].floor), (0.8, 1.2, -2.0));
        assert!(c[0].phases.iter().all(|p| p.plants.is_empty()), "{c:?}");
    }
}
