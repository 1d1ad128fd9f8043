//! Known answers of SP's contact plans (issue 42), on every locomotion clip
//! of `$MX_SHARED/data/inbetween` (walk, run, dash, turn by name; each file a
//! case): a window in the middle of each, the protocol's 10 context frames.
//!
//! - re-planning the capture's own fill with the capture's own plan returns
//!   that plan (the re-plan reads the motion, it does not drift).

use crate::common;

use mx::ground::FloorPlane;
use mx::motion::{JointSampler, Mu};
use mx::report::inbetween::{Case, Protocol, RootMode, is_locomotion};
use mx::spacetime::contact::{GapPlan, Replan, Source, capture_plan};
use mx::spacetime::sp::contact_floor;
use mx::spacetime::{Contact, SpError, SpOptions};

/// The locomotion clips, resampled to the protocol's 30 fps.
fn cases() -> Vec<Case> {
    common::shared_files("inbetween", ".bvh")
        .into_iter()
        .filter(|p| {
            p.file_stem()
                .is_some_and(|s| is_locomotion(&s.to_string_lossy()))
        })
        .map(|p| Case::load_at(&p, Some(30.0)).unwrap())
        .collect()
}

/// A window in the middle of `case` with a `gap`-frame gap: its start frame.
fn middle(case: &Case, gap: usize) -> Option<usize> {
    let p = Protocol::default();
    let need = 2 * p.context + gap;
    (case.frames > need).then(|| (case.frames - need) / 2)
}

/// The capture's own plan over the gap of `cut`.
fn captures_plan(case: &Case, cut: &Mu, floor: FloorPlane) -> GapPlan {
    let names = case.body.coordinate_names();
    let gaps = mx::motion::gaps(cut);
    let (t0, t1) = gaps
        .iter()
        .map(|g| (g.start, g.stop))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |a, b| {
            (a.0.min(b.0), a.1.max(b.1))
        });
    let sampler = JointSampler::new(&case.capture, names);
    let configuration = |t: f64| sampler.positions(t).map_err(SpError::Motion);
    let links: Vec<usize> = mx::ground::default_contact_points(&case.body)
        .into_iter()
        .map(|p| p.link)
        .collect();
    capture_plan(&case.body, &floor, &links, (t0, t1), &configuration).unwrap()
}

fn floor_of(case: &Case, cut: &Mu) -> FloorPlane {
    let o = SpOptions {
        contact: Contact::Auto,
        ..Default::default()
    };
    contact_floor(cut, &case.body, &case.body.default_gravity, &o)
        .unwrap()
        .expect("a floor")
}

#[test]
fn re_planning_the_captures_own_fill_returns_the_captures_plan() {
    let mut tried = 0;
    for case in cases() {
        let Some(start) = middle(&case, 30) else {
            continue;
        };
        let cut = case.cut(start, 10, 30, RootMode::Filled).unwrap();
        let floor = floor_of(&case, &cut);
        let mut plan = captures_plan(&case, &cut, floor);
        // as if a planner (not the user) had made it, so the re-plan acts
        for p in &mut plan.points {
            for s in &mut p.stances {
                s.source = Source::Example;
            }
        }
        let names = case.body.coordinate_names();
        let sampler = JointSampler::new(&case.capture, names);
        let configuration = |t: f64| sampler.positions(t).map_err(SpError::Motion);
        let again = Replan {
            model: &case.body,
            up: floor.up,
            nodes: &[],
            forces: &[],
            weight: case.body.total_mass() * 9.80665,
        }
        .of(&plan, &configuration)
        .unwrap();
        assert_eq!(again, plan, "{}", case.name);
        tried += 1;
    }
    println!("{tried} windows re-planned");
}
