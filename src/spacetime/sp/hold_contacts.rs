//! Stage 3 with `contact:` (see [`crate::spacetime::contact`]): put the
//! contact plan on the [`Filling`] — the floor (`ground`'s floor of the
//! recorded part, or `floor:`) and, per group of overlapping gaps, each
//! contact point's stances planned from the motion around it — then solve the
//! gap DOFs on the chains of the planted points by IK (planted points held,
//! every contact point on those chains kept at or above the floor) and write
//! those curves back.

use super::checks::motion_err;
use super::filling::Filling;
use super::held_limbs::{moves, span, write_hold_solve};
use super::options::SpOptions;
use crate::ground::{self, FloorPlane, GroundOptions, up_of};
use crate::model::Model;
use crate::motion::Mu;
use crate::spacetime::contact::{Contact, ContactPlan, Context, plan_given};
use crate::spacetime::error::SpError;
use crate::spacetime::hold::{self, HoldObjective};
use crate::spacetime::objective::GapDof;
use crate::spacetime::solve::group_overlapping;
use nalgebra::Vector3;

/// The links `contact:` plans (named, or `ground`'s contact points of the
/// body) and whether they were named.
pub(super) fn contact_links(
    model: &Model,
    contact: &Contact,
) -> Result<(Vec<usize>, bool), SpError> {
    Ok(match contact {
        Contact::Named(n) => (hold::named(model, n, "contact")?, true),
        Contact::Given(g) => {
            let mut names: Vec<String> = g.iter().map(|s| s.point.clone()).collect();
            names.sort();
            names.dedup();
            (hold::named(model, &names, "contact")?, true)
        }
        _ => (
            ground::default_contact_points(model)
                .into_iter()
                .map(|p| p.link)
                .collect(),
            false,
        ),
    })
}

/// The floor SP's contact plan stands on for `m` (the motion as given, its
/// gaps unfilled) under `gravity`: `floor:` when stated, else `ground`'s
/// floor of the recorded part ([`ground::recorded_floor`]) over the plan's
/// contact points. `None`: no gravity (nothing is up), or no contact point,
/// or no frame where the whole body is recorded.
pub fn contact_floor(
    m: &Mu,
    model: &Model,
    gravity: &Vector3<f64>,
    opts: &SpOptions,
) -> Result<Option<FloorPlane>, SpError> {
    let Some(up) = up_of(gravity) else {
        return Ok(None);
    };
    let (links, _) = contact_links(model, &opts.contact)?;
    if links.is_empty() {
        return Ok(None);
    }
    let height = match opts.floor {
        Some(h) => Some(h),
        None => {
            let points: Vec<ground::ContactPoint> = links
                .iter()
                .map(|&link| ground::ContactPoint {
                    name: model.link(link).name.clone(),
                    link,
                })
                .collect();
            let o = GroundOptions {
                gravity: Some(*gravity),
                ..Default::default()
            };
            ground::recorded_floor(m, model, &points, &o)?
        }
    };
    Ok(height.map(|height| FloorPlane { up, height }))
}

/// The gaps left for the spacetime solve after the contact plan's chains
/// were solved by IK and written into the motion (SP on a body that does
/// not stand: the grounded solve plans and holds its feet itself).
pub(super) fn hold_contacts(
    f: &mut Filling<'_>,
    opts: &SpOptions,
    gaps: Vec<GapDof>,
) -> Result<Vec<GapDof>, SpError> {
    let Some(floor) = contact_floor(f.recorded, f.model, &f.gravity, opts)? else {
        return Ok(gaps); // nothing to stand on, or nothing to stand with
    };
    let (links, named) = contact_links(f.model, &opts.contact)?;
    f.contacts = Some(ContactPlan::new(floor));
    let mut left = vec![];
    for group in group_overlapping(gaps) {
        left.extend(hold_group(f, opts, (&links, named), &floor, group)?);
    }
    Ok(left)
}

/// One group: plan its contacts onto the filling's plan, and hold the
/// planted points' chains by IK. Returns the group's gaps on no planted chain.
fn hold_group(
    f: &mut Filling<'_>,
    opts: &SpOptions,
    (links, named): (&[usize], bool),
    floor: &FloorPlane,
    group: Vec<GapDof>,
) -> Result<Vec<GapDof>, SpError> {
    let (model, root) = (f.model, &f.root);
    let (t0, t1) = span(&group);
    let solved = {
        let sampler = f.sampler();
        let configuration = |t: f64| sampler.positions(t).map_err(motion_err);
        let ctx = Context::new(model, floor, links, named, (t0, t1), &configuration)?;
        let plan = match &opts.contact {
            Contact::Given(given) => {
                let points: Vec<(usize, f64)> = ctx.points().collect();
                plan_given(model, given, &points, (t0, t1), &configuration)?
            }
            _ => ctx.plan(),
        };
        // the chains of the planted points are solved by IK
        let on_chain = |c: usize| {
            plan.points
                .iter()
                .any(|p| !p.stances.is_empty() && moves(model, root, p.link, c))
        };
        let (ik, rest): (Vec<GapDof>, Vec<GapDof>) =
            group.into_iter().partition(|d| on_chain(d.coord));
        if ik.is_empty() {
            (plan, rest, None)
        } else {
            // every contact point those DOFs move: planted ones held, all above the floor
            let (frames, stances): (Vec<usize>, Vec<_>) = plan
                .points
                .iter()
                .filter(|p| ik.iter().any(|d| moves(model, root, p.link, d.coord)))
                .map(|p| (p.link, p.stances.clone()))
                .unzip();
            let obj = HoldObjective::planned(
                model,
                frames.clone(),
                stances,
                *floor,
                ik,
                &opts.settings,
                &configuration,
            )?;
            let x = obj.solve(&opts.solve.cancel)?;
            (plan, rest, Some((obj, x, frames)))
        }
    };
    let (plan, rest, held) = solved;
    if let Some(contacts) = f.contacts.as_mut() {
        contacts.gaps.push(plan);
    }
    if let Some((obj, x, frames)) = held {
        write_hold_solve(f, &obj, &x, &frames, (t0, t1), true)?;
    }
    Ok(rest)
}

#[cfg(test)]
mod tests {
    use super::super::fixture::{Y_UP, body, motion};
    use super::*;

    #[test]
    fn each_group_gets_a_contact_plan_and_no_gravity_means_no_floor() {
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
        assert!(f.contacts.is_none());
        let mut f = Filling::new(&m, &model, Y_UP);
        // a floor far below: the foot is never planted, nothing held by IK
        let left = hold_contacts(&mut f, &opts, gaps.clone()).unwrap();
        assert_eq!(left, gaps);
        let plan = f.contacts.as_ref().unwrap();
        assert_eq!((plan.floor.height, plan.floor.up), (-2.0, Vector3::y()));
        assert_eq!(plan.gaps.len(), 1);
        assert_eq!((plan.gaps[0].t0, plan.gaps[0].t1), (0.8, 1.2));
        let points = &plan.gaps[0].points;
        assert!(points.iter().all(|p| p.stances.is_empty()), "{plan:?}");
        // the report lists the plan the filling carried
        let (_, report) = f.finish();
        assert_eq!(report.contacts.unwrap().gaps.len(), 1);
    }

    #[test]
    fn given_stances_are_the_plan_anchored_at_the_gap_edge_they_touch() {
        use crate::spacetime::contact::{GivenStance, Source};
        let model = body();
        let m = motion(&model, &[3, 4], (0.8, 1.2));
        let given = |from: f64, to: f64, at: Option<Vector3<f64>>| GivenStance {
            point: "foot".into(),
            from,
            to,
            at,
        };
        let opts = |g: Vec<GivenStance>| SpOptions {
            contact: Contact::Given(g),
            floor: Some(-2.0),
            ..Default::default()
        };
        let here = Vector3::new(0.1, -1.9, 0.2);
        let o = opts(vec![given(0.5, 0.9, None), given(1.0, 1.1, Some(here))]);
        o.check(&model).unwrap();
        let mut f = Filling::new(&m, &model, Y_UP);
        let gaps = f.gaps().unwrap();
        hold_contacts(&mut f, &o, gaps.clone()).unwrap();
        let plan = &f.contacts.as_ref().unwrap().gaps[0];
        let foot = &plan.points[0];
        assert_eq!(foot.name, "foot");
        assert_eq!(foot.stances.len(), 2, "{plan:?}");
        let (a, b) = (&foot.stances[0], &foot.stances[1]);
        assert_eq!((a.t0, a.t1, a.source), (0.8, 0.9, Source::Given));
        assert_eq!(
            (b.t0, b.t1, b.p0, b.source),
            (1.0, 1.1, here, Source::Given)
        );
        // anchored where the motion has the foot at the gap's start
        let sampler = f.sampler();
        let q = sampler.positions(0.8).unwrap();
        let mut poses = vec![];
        model.forward_kinematics(&q, &mut poses).unwrap();
        assert!((a.p0 - poses[foot.link].p).norm() < 1e-12);
        // inside the gap without at: an error naming the point
        let mut f = Filling::new(&m, &model, Y_UP);
        let err = hold_contacts(&mut f, &opts(vec![given(0.9, 1.0, None)]), gaps.clone())
            .unwrap_err()
            .to_string();
        assert!(err.contains("foot") && err.contains("at:"), "{err}");
        // bad times, an unknown point: SpOptions::check says so
        let err = opts(vec![given(1.0, 0.9, None)]).check(&model).unwrap_err();
        assert!(err.to_string().contains("from ≤ to"), "{err}");
        let mut nobody = given(0.5, 0.9, None);
        nobody.point = "hand".into();
        assert!(opts(vec![nobody]).check(&model).is_err());
    }

    #[test]
    fn the_floor_is_the_recorded_feet_s_never_another_link_s() {
        let model = body();
        let m = motion(&model, &[3, 4], (0.8, 1.2));
        let auto = SpOptions {
            contact: Contact::Auto,
            ..Default::default()
        };
        let floor = contact_floor(&m, &model, &Y_UP, &auto).unwrap().unwrap();
        // the lowest the foot reaches where the body is recorded, by ground
        let foot = ground::contact_points(&model, None).unwrap();
        assert!(foot.iter().all(|p| p.name == "foot"), "{foot:?}");
        let o = GroundOptions {
            gravity: Some(Y_UP),
            ..Default::default()
        };
        let low = ground::recorded_floor(&m, &model, &foot, &o)
            .unwrap()
            .unwrap();
        assert_eq!(floor.height, low);
        // every other joint is ignored: the root link sits above the foot's floor
        assert!(floor.height < 0.0, "{}", floor.height);
        // a stated floor wins; no gravity, no floor
        let at = SpOptions {
            floor: Some(0.25),
            ..auto.clone()
        };
        assert_eq!(
            contact_floor(&m, &model, &Y_UP, &at)
                .unwrap()
                .unwrap()
                .height,
            0.25
        );
        assert!(
            contact_floor(&m, &model, &Vector3::zeros(), &auto)
                .unwrap()
                .is_none()
        );
    }
}
