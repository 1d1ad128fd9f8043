//! Judging a fill in one call (`mx::score`, the language's `compare`): the
//! capture against itself scores 0; a Hermite fill scores what the
//! in-betweening benchmark reports for the same window, to 1e-12; the gaps
//! and the contact plan are read from SP's report; and the scores hold on
//! recordings of another rate (CMU's 120 Hz clip at its own rate) and on a
//! z-up copy of a clip. Every clip of `data/inbetween` and `data/mocap` is
//! a case.

use crate::common;
use mx::model::Model;
use mx::motion::Mu;
use mx::report::inbetween::{Case, Method, Protocol, RootMode, fill_window, score};
use mx::score::{GapScore, compare, reference_plan};
use mx::spacetime::{ContactPlan, SpReport};
use nalgebra::{Rotation3, Vector3};

const GAP: usize = 30;

fn cases() -> Vec<Case> {
    let mut files = common::shared_files("inbetween", ".bvh");
    files.extend(common::shared_files("mocap", ".bvh"));
    files.iter().map(|p| Case::load(p).unwrap()).collect()
}

fn one_window() -> Protocol {
    Protocol {
        windows_per_clip: Some(1),
        ..Protocol::default()
    }
}

/// The first window's gap as SP reports one: (last frame before, first after).
fn span(case: &Case, p: &Protocol, start: usize, gap: usize) -> (f64, f64) {
    case.gap_span(start + p.context, gap)
}

fn close(what: &str, a: f64, b: f64) {
    assert!(
        (a - b).abs() <= 1e-12,
        "{what}: compare {a} vs the benchmark's {b}"
    );
}

#[test]
fn the_capture_against_itself_scores_zero_on_every_clip() {
    let p = one_window();
    let mut checked = 0;
    for case in cases() {
        let Some(&start) = case.windows(&p, GAP).first() else {
            continue;
        };
        let s = span(&case, &p, start, GAP);
        let c = compare(&case.capture, &case.capture, &case.body, &[s], None).unwrap();
        let name = &case.name;
        assert_eq!((c.l2p(), c.l2q(), c.npss()), (0.0, 0.0, 0.0), "{name}");
        assert_eq!(c.worst().unwrap().accuracy.worst, 0.0, "{name}");
        // the ground measures are the capture's own, beside themselves
        for reference in [false, true] {
            assert!(c.skate(reference).is_finite() && c.residual(reference) > 0.0);
        }
        assert_eq!(c.skate(false), c.skate(true), "{name}");
        assert_eq!(c.depth(false), 0.0, "{name}: nothing below its own floor");
        assert_eq!(c.residual(false), c.residual(true), "{name}");
        assert_eq!(c.gaps[0].times.len(), GAP, "{name}: the gap's frames");
        assert!((c.rate * case.frame_time - 1.0).abs() < 1e-12, "{name}");
        checked += 1;
    }
    assert!(checked > 0 || common::shared_dir().is_none());
}

/// `compare` of a Hermite fill against the capture is the benchmark's row
/// for the same window, both root settings, every clip: one code.
#[test]
fn compare_on_a_hermite_fill_gives_the_benchmarks_numbers() {
    let p = one_window();
    let mut checked = 0;
    for case in cases() {
        let Some(&start) = case.windows(&p, GAP).first() else {
            continue;
        };
        let s = span(&case, &p, start, GAP);
        for root in [RootMode::Given, RootMode::Filled] {
            let f = fill_window(&case, &p, start, GAP, root, &Method::Hermite).unwrap();
            let r = score(&case, &p, (start, GAP), root, "h", &f.motion, 0.0).unwrap();
            let c = compare(&f.motion, &case.capture, &case.body, &[s], None).unwrap();
            let g: &GapScore = &c.gaps[0];
            let n = format!("{} {}", case.name, root.label());
            close(&format!("{n} l2p"), g.accuracy.l2p, r.l2p);
            close(&format!("{n} worst"), g.accuracy.worst, r.worst);
            assert_eq!(
                start + p.context + g.accuracy.worst_frame,
                r.worst_frame,
                "{n}"
            );
            assert_eq!(g.accuracy.worst_joint, r.worst_joint, "{n}");
            close(&format!("{n} l2q"), g.accuracy.l2q, r.l2q);
            close(&format!("{n} npss"), g.accuracy.npss, r.npss);
            close(&format!("{n} skate"), g.filled.skate, r.skate);
            close(&format!("{n} depth"), g.filled.depth, r.penetration);
            close(&format!("{n} residual"), g.filled.residual, r.residual);
            close(
                &format!("{n} worst residual"),
                g.filled.residual_worst,
                r.residual_worst,
            );
            assert_eq!(c.floor, case.floor, "{n}: the capture's floor");
            // the reference's own ground measures are the benchmark's capture row
            let cap = score(&case, &p, (start, GAP), root, "c", &case.capture, 0.0).unwrap();
            close(&format!("{n} capture skate"), g.reference.skate, cap.skate);
            close(
                &format!("{n} capture residual"),
                g.reference.residual,
                cap.residual,
            );
        }
        checked += 1;
    }
    assert!(checked > 0 || common::shared_dir().is_none());
}

/// The report of a fill whose gap [t0, t1] was filled by Hermite, with the
/// contact plan `plan` (SP's report as `compare` reads it).
fn report_with(m: &Mu, span: (f64, f64), plan: ContactPlan) -> SpReport {
    SpReport {
        hermite: m
            .names()
            .take(2)
            .map(|d| mx::spacetime::sp::Undefined {
                dof: d.to_string(),
                start: span.0,
                stop: span.1,
            })
            .collect(),
        contacts: Some(plan),
        ..SpReport::default()
    }
}

/// Without a span, `compare` scores the gaps the report names, and the plan
/// it carries against the capture's contacts: the capture's own plan scores
/// 1 on edges and frames, a plan with every point free scores the frames
/// where the capture is in the air and no edge.
#[test]
fn compare_reads_the_gaps_and_the_plan_from_sps_report() {
    let files = common::shared_files("inbetween", ".bvh");
    let Some(walk) = files
        .iter()
        .find(|p| p.to_string_lossy().contains("_walk_"))
    else {
        assert!(common::shared_dir().is_none(), "no walk in data/inbetween");
        return;
    };
    let case = Case::load(walk).unwrap();
    let p = one_window();
    let start = case.windows(&p, GAP)[0];
    let s = span(&case, &p, start, GAP);
    let f = fill_window(&case, &p, start, GAP, RootMode::Filled, &Method::Hermite).unwrap();
    let up = Vector3::y();
    let own = reference_plan(&case.capture, &case.body, up, s, &[]).unwrap();
    assert!(
        own.points.iter().any(|q| !q.stances.is_empty()),
        "a walk stands"
    );
    let floor = mx::ground::FloorPlane {
        up,
        height: case.floor,
    };
    let plan = |g| ContactPlan {
        floor,
        gaps: vec![g],
    };
    let report = report_with(&f.motion, s, plan(own.clone()));
    let c = compare(&f.motion, &case.capture, &case.body, &[], Some(&report)).unwrap();
    assert_eq!(c.gaps.len(), 1);
    assert_eq!((c.gaps[0].t0, c.gaps[0].t1), s, "the gap the report names");
    let given = compare(&f.motion, &case.capture, &case.body, &[s], None).unwrap();
    assert_eq!(c.l2p(), given.l2p(), "the same gap as named");
    let a = c.plan().expect("a plan to score");
    assert_eq!(a.agreement(), Some(1.0));
    assert!(a.edges().is_none_or(|e| e == 1.0), "{a:?}");
    // every point free: the frames where a point stands disagree
    let mut free = own.clone();
    for q in &mut free.points {
        q.stances.clear();
    }
    let report = report_with(&f.motion, s, plan(free));
    let c = compare(&f.motion, &case.capture, &case.body, &[], Some(&report)).unwrap();
    let a = c.plan().unwrap();
    assert!(a.agreement().unwrap() < 1.0, "{a:?}");
    assert_eq!(a.edges_planned, 0);
    // no report, no span: an error naming `m`
    let e = compare(&f.motion, &case.capture, &case.body, &[], None).unwrap_err();
    assert_eq!(e.argument(), Some("m"), "{e}");
}

/// `body` with the world turned so that its y axis points along z: the root
/// link's placement turned, gravity along −z. A y-up clip played on it is
/// the same motion, z-up.
fn z_up(body: &Model) -> Model {
    let turn = Rotation3::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_2);
    let r = mx::lie::Se3::new(*turn.matrix(), Vector3::zeros());
    let mut out = Model::new(&body.name);
    for l in body.links() {
        let offset = if l.parent.is_none() {
            r * l.offset
        } else {
            l.offset
        };
        out.add_link(
            &l.name,
            l.parent,
            &l.joint_name,
            l.joint.clone(),
            offset,
            l.inertia,
        )
        .unwrap();
    }
    out.set_coordinate_names(body.coordinate_names().to_vec())
        .unwrap();
    out.default_gravity = turn * body.default_gravity;
    out
}

/// CMU's clip at its own 120 Hz, and every clip of `data/mocap` played z-up:
/// the same numbers as y-up (positions, orientations and heights turn with
/// the world), the residual to the cone solver's accuracy.
#[test]
fn compare_holds_at_120_hz_and_on_a_z_up_copy() {
    let files = common::shared_files("mocap", ".bvh");
    let mut checked = 0;
    for path in &files {
        let case = Case::load(path).unwrap();
        // half a second of gap at the clip's own rate
        let gap = (0.5 / case.frame_time).round() as usize;
        let p = one_window();
        let Some(&start) = case.windows(&p, gap).first() else {
            continue;
        };
        let s = span(&case, &p, start, gap);
        let f = fill_window(&case, &p, start, gap, RootMode::Given, &Method::Hermite).unwrap();
        let y = compare(&f.motion, &case.capture, &case.body, &[s], None).unwrap();
        assert_eq!(y.gaps[0].times.len(), gap, "{}", case.name);
        assert!((y.rate * case.frame_time - 1.0).abs() < 1e-12);
        let zb = z_up(&case.body);
        let z = compare(&f.motion, &case.capture, &zb, &[s], None).unwrap();
        let n = &case.name;
        let near = |what: &str, a: f64, b: f64, tol: f64| {
            assert!(
                (a - b).abs() <= tol * b.abs().max(1.0),
                "{n} {what}: z-up {a} vs y-up {b}"
            );
        };
        near("l2p", z.l2p(), y.l2p(), 1e-9);
        near("l2q", z.l2q(), y.l2q(), 1e-9);
        // NPSS compares power spectra of the orientations' components, which
        // turning the world mixes: it is not invariant, and is not checked here
        for reference in [false, true] {
            near("skate", z.skate(reference), y.skate(reference), 1e-9);
            near("depth", z.depth(reference), y.depth(reference), 1e-9);
            near(
                "residual",
                z.residual(reference),
                y.residual(reference),
                1e-5,
            );
        }
        checked += 1;
    }
    assert!(checked > 0 || common::shared_dir().is_none());
}

/// `compare(…)` in the language is the engine's, and its errors point at
/// the argument at fault.
#[test]
fn compare_in_the_language() {
    let files = common::shared_files("inbetween", ".bvh");
    let Some(path) = files.first() else {
        return;
    };
    let case = Case::load(path).unwrap();
    let p = one_window();
    let start = case.windows(&p, GAP)[0];
    let (t0, t1) = span(&case, &p, start, GAP);
    let cut = case.cut(start, p.context, GAP, RootMode::Given).unwrap();
    let mut it = mx::Interpreter::new();
    it.set("cut", mx::Value::object(mx::lang::host::Motion::Mu(cut)));
    it.set(
        "c",
        mx::Value::object(mx::lang::host::Motion::Mu(case.capture.clone())),
    );
    let src = format!("let b = body_of(load({:?}))", path.display().to_string());
    it.eval_str(&src).unwrap();
    let r = it
        .eval_str(&format!(
            "compare(fill(cut, \"hermite\"), c, b, {t0}, {t1})"
        ))
        .unwrap();
    let field = |v: &mx::Value, k: &str| -> f64 {
        v.as_record()
            .unwrap()
            .get(k)
            .and_then(|x| x.as_number())
            .unwrap()
    };
    let h = fill_window(&case, &p, start, GAP, RootMode::Given, &Method::Hermite).unwrap();
    let bench = score(
        &case,
        &p,
        (start, GAP),
        RootMode::Given,
        "h",
        &h.motion,
        0.0,
    )
    .unwrap();
    close("l2p", field(&r, "l2p"), bench.l2p);
    close("skate", field(&r, "skate"), bench.skate);
    close("residual", field(&r, "residual"), bench.residual);
    let reference = r.as_record().unwrap().get("reference").unwrap().clone();
    assert!(field(&reference, "residual") > 0.0);
    assert!(matches!(
        r.as_record().unwrap().get("plan"),
        Some(mx::Value::Nil)
    ));
    // no SP report and no span: the error points at `m` and says what to do
    let e = it
        .eval_str("compare(fill(cut, \"hermite\"), c, b)")
        .unwrap_err();
    let text = format!("{e:?}");
    assert!(text.contains("SP") && text.contains("t0, t1"), "{text}");
    // a span backwards: at t0
    let e = it
        .eval_str(&format!("compare(c, c, b, {t1}, {t0})"))
        .unwrap_err();
    assert!(format!("{e:?}").contains("not a gap"), "{e:?}");
}
