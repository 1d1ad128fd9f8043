//! Known answers of SP's contact plans (issue 42), on every locomotion clip
//! of `$MX_SHARED/data/inbetween` (walk, run, dash, turn by name; each file a
//! case): a window in the middle of each, the protocol's 10 context frames.
//!
//! - re-planning the capture's own fill with the capture's own plan returns
//!   that plan (the re-plan reads the motion, it does not drift);
//! - SP given the capture's own contacts (`contact:` with each stance's
//!   `at`) keeps each planted point within 1 cm of its anchor.

use crate::common;

use mx::ground::FloorPlane;
use mx::motion::{JointSampler, Mu};
use mx::report::inbetween::{Case, Protocol, RootMode, is_locomotion};
use mx::spacetime::contact::GivenStance;
use mx::spacetime::contact::{GapPlan, Replan, Source, capture_plan};
use mx::spacetime::sp::contact_floor;
use mx::spacetime::{Contact, SpError, SpOptions, sp};

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

/// Issue 42's known answer: with the capture's contacts as the plan (each
/// stance at the capture's own anchor, on a natural cut), SP keeps every
/// planted point within 1 cm of its anchor over its stance.
#[test]
#[ignore = "fails today (28 locomotion clips, natural cut of 30 frames): of 167 stances the median \
            point is 1.47 cm from its anchor, 121 over 1 cm, worst 6.3 cm (a dash's toe); the stance \
            term is a penalty (1e10): at 1e11 the median is 0.82 cm (72 over), at 1e12 0.58 cm (47 \
            over, worst 3.1 cm), and a stiffer stance cost skate and L2P on the bench (3e10: skate \
            1.65x, L2P 0.78x) - a hard constraint per stance is the fix, not yet built"]
fn given_the_captures_contacts_sp_keeps_the_feet_within_a_centimetre_of_them() {
    let mut worst: (f64, String) = (0.0, String::new());
    let mut all: Vec<f64> = vec![];
    for case in cases() {
        let Some(start) = middle(&case, 30) else {
            continue;
        };
        let cut = case.cut(start, 10, 30, RootMode::Filled).unwrap();
        let floor = floor_of(&case, &cut);
        let plan = captures_plan(&case, &cut, floor);
        let given: Vec<GivenStance> = plan
            .points
            .iter()
            .flat_map(|p| {
                p.stances.iter().map(|s| GivenStance {
                    point: p.name.clone(),
                    from: s.t0,
                    to: s.t1,
                    at: Some(s.p0),
                })
            })
            .collect();
        let o = SpOptions {
            contact: Contact::Given(given),
            ..Default::default()
        };
        let (_, report) = sp(&cut, &case.body, &o).unwrap();
        let solved = report.contacts.expect("a plan");
        for p in solved.gaps.iter().flat_map(|g| &g.points) {
            for s in p.stances.iter().filter(|s| s.source == Source::Given) {
                let err = s.solved.expect("scored after the solve");
                all.push(err);
                if err > worst.0 {
                    worst = (
                        err,
                        format!("{} {} [{:.3}, {:.3}]", case.name, p.name, s.t0, s.t1),
                    );
                }
            }
        }
    }
    all.sort_by(f64::total_cmp);
    let over = all.iter().filter(|&&e| e > 0.01).count();
    println!(
        "{} stances: median {:.2} cm, {over} over 1 cm; worst {:.2} cm: {}",
        all.len(),
        100.0 * all.get(all.len() / 2).copied().unwrap_or(0.0),
        100.0 * worst.0,
        worst.1
    );
    assert!(
        worst.0 <= 0.01,
        "{}: {:.2} cm from its anchor",
        worst.1,
        100.0 * worst.0
    );
}
