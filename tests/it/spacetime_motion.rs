//! SP, fill(m, "hermite") and torque_energy on whole motions of the 44-DOF
//! human (`data/reference/human44.urdf`, z up): continuity at every transition
//! end, SP below Hermite, the root shift, and the hard cases.

use crate::common::{self, jumps};

use mx::model::Model;
use mx::motion::{Curve, Dof, Interval, Mu};
use mx::spacetime::{Contact, RootFill, SpError, SpOptions, fill_hermite, sp, torque_energy};

fn human44() -> Option<Model> {
    let dir = common::shared_dir()?;
    Some(
        Model::from_urdf_file(dir.join("data/reference/human44.urdf")).expect("human44.urdf loads"),
    )
}

/// A calm, walk-like synthetic motion: root moving forward at 1.2 m/s,
/// joints swinging at about 1 Hz with human-sized amplitudes.
fn value(c: usize, t: f64) -> f64 {
    match c {
        0 => 1.2 * t,
        1 => 0.02 * (2.0 * t).sin(),
        2 => 0.95 + 0.02 * (12.0 * t).cos(),
        3..=5 => 0.05 * (3.0 * t + c as f64).sin(),
        _ => 0.25 * (6.0 * t + 0.7 * c as f64).sin() + 0.05 * (1.3 * c as f64).cos(),
    }
}

const RATE: f64 = 120.0;

/// The motion of coordinate c on [a, b] as uniform samples (a C² spline), plus `offset`.
fn piece(c: usize, a: f64, b: f64, offset: f64) -> Interval {
    let n = ((b - a) * RATE).round() as usize;
    let vals = (0..=n)
        .map(|k| value(c, a + k as f64 / RATE) + offset)
        .collect();
    Interval::curve(Curve::samples(a, 1.0 / RATE, vals).unwrap(), a, b).unwrap()
}

/// Every coordinate defined on [0, 3] except `gap` on (g0, g1) for the DOFs in `gapped`;
/// after the gap the root x is `x_offset` further (recorded elsewhere in the room).
fn motion(model: &Model, gapped: &[usize], g0: f64, g1: f64, x_offset: f64) -> Mu {
    let mut m = Mu::new();
    for (c, name) in model.coordinate_names().iter().enumerate() {
        let dof = if gapped.contains(&c) {
            let off = if c == 0 { x_offset } else { 0.0 };
            Dof::new(vec![piece(c, 0.0, g0, 0.0), piece(c, g1, 3.0, off)]).unwrap()
        } else {
            Dof::from(piece(c, 0.0, 3.0, 0.0))
        };
        m.insert(name.clone(), dof);
    }
    m
}

fn fast() -> SpOptions {
    SpOptions::default()
}

#[test]
fn sp_fills_a_whole_body_gap_continuously_below_hermite_and_shifts_the_root() {
    let Some(model) = human44() else { return };
    let all: Vec<usize> = (0..44).collect();
    let m = motion(&model, &all, 1.0, 1.6, 3.0);
    let (filled, report) = sp(&m, &model, &fast()).unwrap();
    print!("{report}");
    assert!(mx::motion::gaps(&filled).is_empty());
    let (jq, jv) = jumps(&filled);
    println!("transition ends: position jump {jq:.1e}, velocity jump {jv:.1e}");
    assert!(jq <= 1e-9 && jv <= 1e-6, "{jq} {jv}");
    // root: p(t2) = p(t1) + T (v1 + v2)/2 = 1.2 + 0.6·1.2, the run started 3 m further
    let shift = report.root[0]
        .shift
        .iter()
        .find(|(n, _)| n == "root_tx")
        .unwrap()
        .1;
    let expect = (1.2 + 0.6 * 1.2) - (1.2 * 1.6 + 3.0);
    assert!((shift - expect).abs() < 1e-6, "shift {shift} vs {expect}");
    // 3 m from where the velocities lead: two recordings, so root: "auto" shifts
    assert!(report.pinned.is_empty(), "{:?}", report.pinned);
    let after = filled.sample("root_tx", 2.0).unwrap().unwrap()[0];
    assert!(
        (after - 1.2 * 2.0).abs() < 1e-6,
        "the motion after the gap continues the path: {after}"
    );
    let e_sp = torque_energy(&filled, &model, None).unwrap();
    let e_h = torque_energy(&fill_hermite(&m).unwrap(), &model, None).unwrap();
    println!("torque energy over the motion: SP {e_sp:.3} < Hermite {e_h:.3}");
    assert!(e_sp < e_h);
}

/// Every DOF of `m` agrees with `filled` at `t` to 1e-9.
fn unchanged_at(m: &Mu, filled: &Mu, t: f64) {
    for (name, _) in &m.dofs {
        let want = m.sample(name, t).unwrap().unwrap()[0];
        let got = filled.sample(name, t).unwrap().unwrap()[0];
        assert!((got - want).abs() <= 1e-9, "{name} at {t}: {got} vs {want}");
    }
}

#[test]
fn a_hole_inside_one_recording_keeps_the_frames_after_it_where_they_were() {
    let Some(model) = human44() else { return };
    let all: Vec<usize> = (0..44).collect();
    // the root walks 1.2 m/s straight through the hole: one recording
    let m = motion(&model, &all, 1.0, 1.6, 0.0);
    // the kinematic root fill (Rose §3.2.1) is SP's where it does not stand
    // on the ground (standing, the root is solved with the body)
    let opts = SpOptions {
        contact: Contact::None,
        ..fast()
    };
    let (filled, report) = sp(&m, &model, &opts).unwrap();
    print!("{report}");
    assert!(report.root.is_empty(), "{:?}", report.root);
    assert_eq!(report.pinned.len(), 1, "{:?}", report.pinned);
    let p = &report.pinned[0];
    assert!(p.auto && p.mismatch < 0.01 && p.tolerance > 0.5, "{p:?}");
    assert!(report.to_string().contains("pinned"), "{report}");
    for t in [1.6, 1.7, 2.0, 2.5, 3.0] {
        unchanged_at(&m, &filled, t);
    }
    let (jq, jv) = jumps(&filled);
    assert!(jq <= 1e-9 && jv <= 1e-6, "{jq} {jv}");
    // Rose's shift on the same motion, asked for, still moves what follows
    let shift = SpOptions {
        root: RootFill::Shift,
        ..fast()
    };
    let (_, rose) = sp(&m, &model, &shift).unwrap();
    assert_eq!(rose.root.len(), 1);
    assert!(rose.pinned.is_empty());
}

#[test]
fn fig10_like_arm_gap_moves_the_shoulder_and_wrist() {
    let Some(model) = human44() else { return };
    // the right arm chain only, a 0.8 s gap
    let arm: Vec<usize> = (0..44)
        .filter(|&c| {
            model.coordinate_names()[c].starts_with("right_")
                && !model.coordinate_names()[c].contains("hip")
                && !model.coordinate_names()[c].contains("knee")
                && !model.coordinate_names()[c].contains("ankle")
                && !model.coordinate_names()[c].contains("toe")
        })
        .collect();
    assert!(arm.len() >= 7);
    let m = motion(&model, &arm, 1.2, 2.0, 0.0);
    // Rose's objective: the coupling of Fig. 10 (the default's prior keeps it small)
    let rose = SpOptions {
        prior: mx::spacetime::Prior::none(),
        ..fast()
    };
    let (filled, report) = sp(&m, &model, &rose).unwrap();
    print!("{report}");
    assert_eq!(report.groups.len(), 1);
    assert!(report.groups[0].energy < report.groups[0].initial_energy);
    let (jq, jv) = jumps(&filled);
    assert!(jq <= 1e-9 && jv <= 1e-6);
    let e_sp = torque_energy(&filled, &model, None).unwrap();
    let e_h = torque_energy(&fill_hermite(&m).unwrap(), &model, None).unwrap();
    println!("arm: SP {e_sp:.4} < Hermite {e_h:.4}");
    assert!(e_sp < e_h);
}

#[test]
fn a_conflict_is_an_error() {
    let Some(model) = human44() else { return };
    let mut m = motion(&model, &[], 1.0, 1.6, 0.0);
    let name = "left_elbow";
    let d = m
        .get(name)
        .unwrap()
        .plus(&Dof::from(Interval::constant(0.3, 1.0, 1.5).unwrap()));
    m.insert(name, d);
    match sp(&m, &model, &fast()) {
        Err(SpError::Conflict { dof, t0, t1 }) => {
            assert_eq!(dof, name);
            assert!(t1 > t0, "[{t0}, {t1}]");
        }
        other => panic!("expected a conflict error, got {other:?}"),
    }
    assert!(fill_hermite(&m).is_err());
    assert!(torque_energy(&m, &model, None).is_err());
}

#[test]
fn gaps_at_the_start_or_end_stay_undefined_and_are_reported() {
    let Some(model) = human44() else { return };
    let mut m = motion(&model, &[], 1.0, 1.6, 0.0);
    let n = "left_knee";
    m.insert(
        n,
        Dof::from(piece(model.coordinate_index(n).unwrap(), 0.5, 3.0, 0.0)),
    );
    let (out, report) = sp(&m, &model, &fast()).unwrap();
    assert!(report.groups.is_empty());
    assert_eq!(report.undefined.len(), 1);
    assert_eq!(report.undefined[0].dof, n);
    assert!(
        out.sample(n, 0.25).unwrap().is_none(),
        "the start stays undefined"
    );
    assert!(format!("{report}").contains("stays undefined"));
    // and torque energy refuses undefined motion with a clear message
    let e = torque_energy(&out, &model, None).unwrap_err().to_string();
    assert!(e.contains(n) && e.contains("undefined"), "{e}");
}

#[test]
fn a_zero_length_gap_needs_no_transition() {
    let Some(model) = human44() else { return };
    // touching intervals [0, 1] and [1, 3]: no gap, motion unchanged
    let m = motion(&model, &[10, 11], 1.0, 1.0, 0.0);
    let (out, report) = sp(&m, &model, &fast()).unwrap();
    assert!(report.groups.is_empty());
    assert_eq!(out, m);
}

#[test]
fn identical_end_states_five_second_gap_and_ends_more_than_pi_apart() {
    let Some(model) = human44() else { return };
    let c = model.coordinate_index("left_elbow").unwrap();
    let names = model.coordinate_names();
    // identical end states: a constant joint with a gap
    let mut m = motion(&model, &[], 1.0, 1.6, 0.0);
    m.insert(
        &names[c],
        Dof::new(vec![
            Interval::constant(0.4, 0.0, 1.0).unwrap(),
            Interval::constant(0.4, 1.6, 3.0).unwrap(),
        ])
        .unwrap(),
    );
    let (out, r) = sp(&m, &model, &fast()).unwrap();
    let g = &r.groups[0];
    assert!(g.energy.is_finite() && g.energy <= g.initial_energy);
    assert!(jumps(&out).0 <= 1e-9);

    // a 5 s gap (motion on [0, 1] and [6, 8])
    let mut m = Mu::new();
    for (i, n) in names.iter().enumerate() {
        let d = if i == c {
            Dof::new(vec![piece(i, 0.0, 1.0, 0.0), piece(i, 6.0, 8.0, 0.0)]).unwrap()
        } else {
            Dof::from(piece(i, 0.0, 8.0, 0.0))
        };
        m.insert(n.clone(), d);
    }
    let (out, r) = sp(&m, &model, &fast()).unwrap();
    let g = &r.groups[0];
    println!(
        "5 s gap: {} iterations, energy {:.4} (Hermite {:.4})",
        g.iterations, g.energy, g.initial_energy
    );
    assert!(g.energy.is_finite() && g.energy < g.initial_energy);
    let (jq, jv) = jumps(&out);
    assert!(jq <= 1e-9 && jv <= 1e-6);

    // ends more than π apart: unwrapped angles are joined as they are, never wrapped
    let mut m = motion(&model, &[], 1.0, 1.6, 0.0);
    m.insert(
        &names[c],
        Dof::new(vec![
            Interval::constant(-0.5, 0.0, 1.0).unwrap(),
            Interval::constant(3.5, 1.6, 3.0).unwrap(),
        ])
        .unwrap(),
    );
    let (out, _) = sp(&m, &model, &fast()).unwrap();
    let mid = out.sample(&names[c], 1.3).unwrap().unwrap()[0];
    let end = out.sample(&names[c], 1.6 - 1e-9).unwrap().unwrap()[0];
    assert!((end - 3.5).abs() < 1e-6, "{end}");
    assert!(mid > -0.5 && mid < 3.5, "{mid}");
    assert!(jumps(&out).0 <= 1e-9);
}

#[test]
fn a_gap_dof_the_body_does_not_have_is_a_clear_error() {
    let Some(model) = human44() else { return };
    let mut m = motion(&model, &[], 1.0, 1.6, 0.0);
    m.insert(
        "tail",
        Dof::new(vec![
            Interval::constant(0.0, 0.0, 1.0).unwrap(),
            Interval::constant(1.0, 2.0, 3.0).unwrap(),
        ])
        .unwrap(),
    );
    let e = sp(&m, &model, &fast()).unwrap_err().to_string();
    assert!(e.contains("tail") && e.contains("hermite"), "{e}");
    // but Hermite fills it
    let f = fill_hermite(&m).unwrap();
    assert!(mx::motion::gaps(&f).is_empty());
}
