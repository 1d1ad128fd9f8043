//! Foot contact in SP (`SpOptions::contact`, issue 25) on the walks of
//! `$MX_SHARED/data/inbetween`: one 30-frame window per walk, every DOF cut
//! (root filled, pinned). Checked: a contact schedule is planned in every
//! gap, the transition joins its context continuously, the frames after the
//! gap stay where they were captured, and `Contact::None` is SP as it was.
//! Printed, not yet asserted (the goals are not met): ground skate and the
//! deepest foot point. Measured (debug run, 8 walks): skate capture 13.6,
//! `Contact::None` 88.5, `Contact::Auto` 87.4 cm/s; deepest 0 / 6.2 / 6.2 cm.
//! The planted IK holds the feet only to 1.5–7 cm of their plants with the
//! Hermite root, and a foot not planted in a gap is on no IK chain, so the
//! floor does not reach it. The planned IK's gradient (floor active) is
//! checked in `spacetime_support`.

use crate::common;

use mx::model::Model;
use mx::motion::{Dof, Interval, Mu};
use mx::report::inbetween::{Case, Protocol, RootMode};
use mx::spacetime::sp::contact_floor;
use mx::spacetime::{Contact, RootFill, SpOptions, sp};
use nalgebra::Vector3;

/// The foot points of the protocol: `Foot_*` and `Toes_*` joints.
fn feet(body: &Model) -> Vec<usize> {
    body.links()
        .iter()
        .enumerate()
        .filter(|(_, l)| {
            (l.name.starts_with("Foot_") || l.name.starts_with("Toes_")) && !l.name.contains('.')
        })
        .map(|(i, _)| i)
        .collect()
}

/// Heights above the floor (m) and positions of `links` at t.
fn points(body: &Model, m: &Mu, links: &[usize], t: f64) -> Vec<Vector3<f64>> {
    let q: Vec<f64> = body
        .coordinate_names()
        .iter()
        .map(|n| m.sample(n, t).unwrap().unwrap()[0])
        .collect();
    let mut poses = vec![];
    body.forward_kinematics(&q, &mut poses).unwrap();
    links.iter().map(|&l| poses[l].p).collect()
}

/// (skate cm/s summed, frames counted, deepest cm below the floor) over frames
/// `k0..=k1`: horizontal speed of a foot point between consecutive frames
/// while within 2 cm of the floor.
fn ground(
    case: &Case,
    m: &Mu,
    up: &Vector3<f64>,
    floor: f64,
    k0: usize,
    k1: usize,
) -> (f64, usize, f64) {
    let links = feet(&case.body);
    let dt = case.frame_time;
    let ps: Vec<_> = (k0..=k1)
        .map(|k| points(&case.body, m, &links, k as f64 * dt))
        .collect();
    let (mut sum, mut n, mut deepest) = (0.0, 0, 0.0f64);
    for w in ps.windows(2) {
        for (a, b) in w[0].iter().zip(&w[1]) {
            let h = up.dot(a) - floor;
            deepest = deepest.max(-h);
            if h <= 0.02 {
                let d = b - a;
                sum += (d - up * up.dot(&d)).norm() / dt * 100.0;
                n += 1;
            }
        }
    }
    for b in &ps[ps.len() - 1] {
        deepest = deepest.max(floor - up.dot(b));
    }
    (sum, n, deepest.max(0.0) * 100.0)
}

#[test]
fn walk_gaps_get_a_contact_schedule_and_keep_their_context() {
    let files = common::shared_files("inbetween", ".bvh");
    if files.is_empty() {
        return; // no shared data on a developer machine (fails in CI)
    }
    let walks: Vec<_> = files
        .iter()
        .filter(|p| p.file_name().unwrap().to_string_lossy().contains("_walk_"))
        .collect();
    assert!(!walks.is_empty(), "no walk in data/inbetween");
    let p = Protocol {
        gaps: vec![30],
        windows_per_clip: Some(1),
        ..Protocol::default()
    };
    let (mut capture, mut none, mut auto) = ([0.0, 0.0], [0.0, 0.0], [0.0, 0.0]);
    let mut worst_depth = [0.0f64; 3];
    for path in walks {
        let case = Case::load(path).unwrap();
        let links = feet(&case.body);
        assert!(links.len() >= 4, "{}: foot points {links:?}", case.name);
        let g = case.body.default_gravity;
        let up = -g / g.norm();
        let floor = (0..case.frames)
            .flat_map(|k| {
                points(
                    &case.body,
                    &case.capture,
                    &links,
                    k as f64 * case.frame_time,
                )
            })
            .map(|p| up.dot(&p))
            .fold(f64::INFINITY, f64::min);
        let start = case.windows(&p, 30)[0];
        let cut = case.cut(start, p.context, 30, RootMode::Filled).unwrap();
        // the gap's frames and the context frame on each side
        let (k0, k1) = (start + p.context - 1, start + p.context + 30);
        let opts = |contact: Contact| {
            let mut o = SpOptions {
                root: RootFill::Pinned,
                contact,
                ..Default::default()
            };
            // a kinematic root stands only when contact: is stated
            o.ground.stand_root_given = true;
            o
        };
        let (with_none, _) = sp(&cut, &case.body, &opts(Contact::None)).unwrap();
        let (with_auto, report) = sp(&cut, &case.body, &opts(Contact::Auto)).unwrap();
        print!("{report}");
        let plan = report.contacts.as_ref().expect("a contact plan");
        assert!(!plan.gaps.is_empty(), "{}: no contact plan", case.name);
        // the plan stands on ground's floor of the recorded part, with
        // ground's contact points only (never the massless joint_Root)
        let recorded = contact_floor(&cut, &case.body, &g, &opts(Contact::Auto))
            .unwrap()
            .unwrap();
        assert_eq!(plan.floor, recorded, "{}", case.name);
        let points = mx::ground::contact_points(&case.body, None).unwrap();
        for gp in &plan.gaps {
            for p in &gp.points {
                assert!(
                    points.iter().any(|c| c.link == p.link),
                    "{}: {} planned",
                    case.name,
                    p.name
                );
            }
        }
        // with the root pinned (kinematic) the default options do not stand:
        // they are contact: "none"
        let (default, _) = sp(
            &cut,
            &case.body,
            &SpOptions {
                root: RootFill::Pinned,
                ..Default::default()
            },
        )
        .unwrap();
        let t_mid = (k0 + 15) as f64 * case.frame_time;
        for name in case.body.coordinate_names() {
            assert_eq!(
                default.sample(name, t_mid).unwrap(),
                with_none.sample(name, t_mid).unwrap(),
                "{name}"
            );
        }
        // continuity at the gap ends, and the frames after the gap untouched
        let mx_jumps = crate::common::jumps(&with_auto);
        assert!(
            mx_jumps.0 <= 1e-9 && mx_jumps.1 <= 1e-6,
            "{}: {mx_jumps:?}",
            case.name
        );
        for k in [k1, k1 + 5] {
            let t = k as f64 * case.frame_time;
            for name in case.body.coordinate_names() {
                let a = cut.sample(name, t).unwrap().unwrap()[0];
                let b = with_auto.sample(name, t).unwrap().unwrap()[0];
                assert!((a - b).abs() <= 1e-9, "{}: {name} at {t}", case.name);
            }
        }
        for (i, (m, acc)) in [
            (&case.capture, &mut capture),
            (&with_none, &mut none),
            (&with_auto, &mut auto),
        ]
        .into_iter()
        .enumerate()
        {
            let (s, n, d) = ground(&case, m, &up, floor, k0, k1);
            acc[0] += s;
            acc[1] += n as f64;
            worst_depth[i] = worst_depth[i].max(d);
            println!(
                "{} [{}]: skate {:.1} cm/s over {n} foot-frames, deepest {d:.2} cm",
                case.name,
                ["capture", "contact none", "contact auto"][i],
                s / (n.max(1) as f64)
            );
        }
    }
    let mean = |a: [f64; 2]| a[0] / a[1].max(1.0);
    println!(
        "walks, 30-frame gap, root filled: skate capture {:.1}, contact none {:.1}, contact auto {:.1} cm/s; \
         deepest capture {:.2}, none {:.2}, auto {:.2} cm",
        mean(capture),
        mean(none),
        mean(auto),
        worst_depth[0],
        worst_depth[1],
        worst_depth[2]
    );
    // the capture itself is on the floor it defines
    assert!(worst_depth[0] <= 1e-9, "{}", worst_depth[0]);
}

/// The contact plan's floor is `ground`'s: on every clip of
/// `data/inbetween` and `data/mocap`, cut naturally (every DOF) over a
/// second in its middle, the floor SP's plan stands on equals `contacts()`'s
/// floor of the recorded part (the frames before and after the gap) within
/// 1 mm. (It used to be the lowest of every joint, so the massless
/// `joint_Root` at the origin of a Bandai skeleton: 0.0000 m under feet at
/// 0.04 m.) Beside it, printed: how far that is from the whole capture's
/// `contacts()` floor, which differs only where the capture's lowest foot
/// frame is inside the gap, which SP cannot see.
#[test]
fn the_plan_s_floor_is_ground_s_floor_on_every_clip() {
    let files: Vec<_> = ["inbetween", "mocap"]
        .iter()
        .flat_map(|d| common::shared_files(d, ".bvh"))
        .collect();
    if files.is_empty() {
        return; // no shared data on a developer machine (fails in CI)
    }
    let floor_of = |m: &Mu, body: &Model| {
        mx::ground::contacts(m, body, &Default::default())
            .unwrap()
            .floor
    };
    let without = |m: &Mu, a: f64, b: f64| {
        let hole = Dof::from(Interval::constant(0.0, a, b).unwrap());
        let mut out = Mu::new();
        for (name, d) in &m.dofs {
            out.insert(name.clone(), d.minus(&hole));
        }
        out
    };
    let (mut worst, mut whole) = ((0.0f64, String::new()), (0.0f64, String::new()));
    for path in &files {
        let case = Case::load(path).unwrap();
        let g = case.body.default_gravity;
        // one second (or the middle third of a shorter clip) cut from the middle
        let n = case.frames;
        let gap = ((1.0 / case.frame_time).round() as usize).min(n / 3).max(1);
        let a = (n - gap) / 2;
        let (t0, t1) = (
            a as f64 * case.frame_time,
            (a + gap) as f64 * case.frame_time,
        );
        // (a hole reaching outside the clip would stay defined there: `−` keeps either side's part)
        let (start, end) = case.capture.span().unwrap();
        let cut = without(&case.capture, t0, t1);
        // the recorded frames: up to the gap's first end, from its last
        let half = 0.5 * case.frame_time;
        let recorded = floor_of(&without(&case.capture, t0 + half, end), &case.body).min(floor_of(
            &without(&case.capture, start, t1 - half),
            &case.body,
        ));
        let capture = floor_of(&case.capture, &case.body);
        let opts = SpOptions {
            contact: Contact::Auto,
            ..Default::default()
        };
        let plan = contact_floor(&cut, &case.body, &g, &opts)
            .unwrap()
            .unwrap_or_else(|| panic!("{}: no floor", case.name))
            .height;
        let (d, dw) = ((plan - recorded).abs(), (plan - capture).abs());
        println!(
            "{}: plan floor {plan:.4} m, contacts() of the recorded part {recorded:.4} m, of the whole capture {capture:.4} m (|Δ| {:.2} mm)",
            case.name,
            dw * 1e3
        );
        if d > worst.0 {
            worst = (d, case.name.clone());
        }
        if dw > whole.0 {
            whole = (dw, case.name.clone());
        }
    }
    println!(
        "{} clips: worst |plan floor − contacts() floor| {:.3} mm on the recorded part ({}), {:.2} mm against the whole capture ({})",
        files.len(),
        worst.0 * 1e3,
        worst.1,
        whole.0 * 1e3,
        whole.1
    );
    assert!(worst.0 <= 1e-3, "{worst:?}");
}
