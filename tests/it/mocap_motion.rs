//! BVH → MU → BVH on every shared clip: DOF names as in the file, radians and
//! metres, continuous curves with derivatives, round trip within 1e-6, and
//! angles equal to the file's modulo 2π.

use crate::common;

use mx::mocap::bvh::{self, Units};
use mx::mocap::to_motion;
use std::f64::consts::TAU;
use std::path::Path;

fn check_clip(path: &Path) {
    let name = path.file_name().unwrap().to_string_lossy().to_string();
    let raw = bvh::read_file(path).unwrap();
    let clip = to_motion::load(path, Units::Auto).unwrap();
    let names = raw.skeleton.channel_names();
    assert_eq!(
        clip.mu.names().collect::<Vec<_>>(),
        names.iter().map(String::as_str).collect::<Vec<_>>()
    );
    let s = clip.units.metres_per_unit;
    let dt = raw.frame_time;
    let kinds: Vec<bvh::Channel> = raw
        .skeleton
        .joints
        .iter()
        .flat_map(|j| j.channels.clone())
        .collect();
    // Values at the frames: the file's, in radians/metres (angles mod 2π).
    for (c, n) in names.iter().enumerate() {
        let col = raw.column(c);
        for (f, v) in col.iter().enumerate().step_by(7) {
            let got = clip.mu.sample_value(n, f as f64 * dt).unwrap().unwrap();
            if kinds[c].is_rotation() {
                let d = (got - v.to_radians()) / TAU;
                assert!(
                    (d - d.round()).abs() * TAU < 1e-9,
                    "{name} {n} frame {f}: {got} vs {v}°"
                );
            } else {
                assert!((got - v * s).abs() < 1e-9, "{name} {n} frame {f}");
            }
        }
    }
    // Save and load again: every channel within 1e-6 at every frame.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("again.bvh");
    let report = to_motion::save(&clip.mu, &clip.skeleton, s, dt, &out).unwrap();
    assert!(report.filled_at_rest.is_empty() && report.not_in_skeleton.is_empty());
    let again = to_motion::load(&out, Units::MetresPerUnit(s)).unwrap();
    assert_eq!(again.frames, clip.frames, "{name}");
    for n in &names {
        for f in 0..clip.frames {
            let t = f as f64 * dt;
            let a = clip.mu.sample_value(n, t).unwrap().unwrap();
            let b = again.mu.sample_value(n, t).unwrap().unwrap();
            assert!((a - b).abs() < 1e-6, "{name} {n} frame {f}: {a} vs {b}");
        }
    }
}

#[test]
fn every_shared_clip_converts_and_round_trips() {
    for p in common::shared_files("mocap", ".bvh") {
        check_clip(&p);
    }
}

#[test]
fn example_clips_convert_and_round_trip() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/data");
    check_clip(&dir.join("walk.bvh"));
    check_clip(&dir.join("wave.bvh"));
}

#[test]
fn curves_are_continuous_and_have_derivatives() {
    let Some(dir) = common::shared_dir() else {
        return;
    };
    let clip = to_motion::load(
        &dir.join("data/mocap/bandai1_dance-short_normal_001.bvh"),
        Units::Auto,
    )
    .unwrap();
    let dt = clip.frame_time;
    for (n, dof) in &clip.mu.dofs {
        assert_eq!(dof.intervals.len(), 1);
        let mut prev = None;
        for f in 0..clip.frames {
            let [q, qd, qdd] = dof.sample(n, f as f64 * dt).unwrap().unwrap();
            assert!(q.is_finite() && qd.is_finite() && qdd.is_finite());
            if let Some(p) = prev {
                // Unwrapped: no frame-to-frame step beyond a half turn.
                assert!(
                    f64::abs(q - p) <= std::f64::consts::PI + 1e-9,
                    "{n} frame {f}"
                );
            }
            prev = Some(q);
        }
    }
    // q̇ from the spline matches a central difference of q between frames.
    let n = "Hips.Xposition";
    let t = 100.5 * dt;
    let h = 1e-5;
    let [_, qd, _] = clip.mu.sample(n, t).unwrap().unwrap();
    let fd = (clip.mu.sample_value(n, t + h).unwrap().unwrap()
        - clip.mu.sample_value(n, t - h).unwrap().unwrap())
        / (2.0 * h);
    assert!((qd - fd).abs() < 1e-5 * (1.0 + fd.abs()), "{qd} vs {fd}");
}

#[test]
fn single_frame_and_empty_clips() {
    let one = "HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nCHANNELS 1 Zrotation\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\n45\n";
    let clip = to_motion::from_bvh(&bvh::parse(one).unwrap(), Units::Auto).unwrap();
    let v = clip.mu.sample("a.Zrotation", 0.05).unwrap().unwrap();
    assert!((v[0] - std::f64::consts::FRAC_PI_4).abs() < 1e-15 && v[1] == 0.0);
    let none = one.replace("Frames: 1", "Frames: 0").replace("45\n", "");
    let e = to_motion::from_bvh(&bvh::parse(&none).unwrap(), Units::Auto).unwrap_err();
    assert!(e.to_string().contains("no frames"));
    let e = to_motion::from_bvh(&bvh::parse(one).unwrap(), Units::MetresPerUnit(-1.0)).unwrap_err();
    assert!(e.to_string().contains("positive"));
}

#[test]
fn saving_a_gap_is_an_error_naming_the_dof() {
    use mx::motion::{Dof, Interval, Mu};
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/data");
    let clip = to_motion::load(&dir.join("walk.bvh"), Units::Auto).unwrap();
    let hole = Mu::from_iter([(
        "LeftLeg.Xrotation".to_string(),
        Dof::new(vec![Interval::constant(0.0, 0.5, 0.8).unwrap()]).unwrap(),
    )]);
    let mu = mx::motion::minus(&clip.mu, &hole);
    let e = to_motion::to_bvh(&mu, &clip.skeleton, 0.01, clip.frame_time)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("LeftLeg.Xrotation") && e.contains("undefined"),
        "{e}"
    );
}
