//! Small procedural clips the project makes itself (a walk cycle, an arm
//! wave, a run, a kick and an arm raise on one 19-joint skeleton), so examples run on a fresh clone without
//! third-party motion capture. `examples/make_data.rs` writes them to
//! `examples/data/`; a test checks the committed files equal what this makes.
//!
//! Skeleton: y up, facing +z, T-pose rest (arms along ±x), centimetres;
//! `Hips` has 6 channels (Xposition Yposition Zposition Zrotation Xrotation
//! Yrotation), every other joint `Zrotation Xrotation Yrotation`.

use super::bvh::{BvhFile, BvhJoint, Channel, Skeleton};
use nalgebra::Vector3;
use std::f64::consts::PI;

/// Frames per second of the generated clips.
pub const FPS: f64 = 30.0;

/// (name, parent, offset cm, end site cm)
type Spec = (
    &'static str,
    Option<&'static str>,
    [f64; 3],
    Option<[f64; 3]>,
);

const JOINTS: [Spec; 19] = [
    ("Hips", None, [0.0, 0.0, 0.0], None),
    ("Spine", Some("Hips"), [0.0, 10.0, 0.0], None),
    ("Chest", Some("Spine"), [0.0, 20.0, 0.0], None),
    ("Neck", Some("Chest"), [0.0, 22.0, 0.0], None),
    (
        "Head",
        Some("Neck"),
        [0.0, 10.0, 0.0],
        Some([0.0, 18.0, 0.0]),
    ),
    ("LeftShoulder", Some("Chest"), [4.0, 18.0, 0.0], None),
    ("LeftArm", Some("LeftShoulder"), [15.0, 0.0, 0.0], None),
    ("LeftForeArm", Some("LeftArm"), [28.0, 0.0, 0.0], None),
    (
        "LeftHand",
        Some("LeftForeArm"),
        [25.0, 0.0, 0.0],
        Some([18.0, 0.0, 0.0]),
    ),
    ("RightShoulder", Some("Chest"), [-4.0, 18.0, 0.0], None),
    ("RightArm", Some("RightShoulder"), [-15.0, 0.0, 0.0], None),
    ("RightForeArm", Some("RightArm"), [-28.0, 0.0, 0.0], None),
    (
        "RightHand",
        Some("RightForeArm"),
        [-25.0, 0.0, 0.0],
        Some([-18.0, 0.0, 0.0]),
    ),
    ("LeftUpLeg", Some("Hips"), [9.0, -3.0, 0.0], None),
    ("LeftLeg", Some("LeftUpLeg"), [0.0, -42.0, 0.0], None),
    (
        "LeftFoot",
        Some("LeftLeg"),
        [0.0, -41.0, 0.0],
        Some([0.0, -6.0, 15.0]),
    ),
    ("RightUpLeg", Some("Hips"), [-9.0, -3.0, 0.0], None),
    ("RightLeg", Some("RightUpLeg"), [0.0, -42.0, 0.0], None),
    (
        "RightFoot",
        Some("RightLeg"),
        [0.0, -41.0, 0.0],
        Some([0.0, -6.0, 15.0]),
    ),
];

/// Standing hip height (cm) so the feet (ankle + 6 cm) touch y = 0.
const HIP_HEIGHT: f64 = 3.0 + 42.0 + 41.0 + 6.0;

/// The skeleton shared by the generated clips.
pub fn skeleton() -> Skeleton {
    use Channel::*;
    let mut joints: Vec<BvhJoint> = Vec::new();
    for (name, parent, off, end) in JOINTS {
        let parent = parent.and_then(|p| joints.iter().position(|j| j.name == p));
        let channels = if parent.is_none() {
            vec![
                Xposition, Yposition, Zposition, Zrotation, Xrotation, Yrotation,
            ]
        } else {
            vec![Zrotation, Xrotation, Yrotation]
        };
        joints.push(BvhJoint {
            name: name.into(),
            parent,
            offset: Vector3::from(off),
            channels,
            end_sites: end.map(Vector3::from).into_iter().collect(),
        });
    }
    Skeleton {
        joints,
        inertias: None,
    }
}

/// Builds a clip: `pose(t)` returns (joint, channel, value) settings over a
/// zero pose; values are rounded to 1e-4 so the files stay small and exact.
fn clip(frames: usize, pose: impl Fn(f64) -> Vec<(&'static str, Channel, f64)>) -> BvhFile {
    let skeleton = skeleton();
    let names = skeleton.channel_names();
    let n = names.len();
    let mut values = vec![0.0; frames * n];
    for f in 0..frames {
        let t = f as f64 / FPS;
        let row = &mut values[f * n..(f + 1) * n];
        // Arms hang at the sides unless the pose says otherwise.
        set(&names, row, "Hips", Channel::Yposition, HIP_HEIGHT);
        set(&names, row, "LeftArm", Channel::Zrotation, -80.0);
        set(&names, row, "RightArm", Channel::Zrotation, 80.0);
        for (j, c, v) in pose(t) {
            set(&names, row, j, c, v);
        }
        for v in row.iter_mut() {
            *v = (*v * 1e4).round() / 1e4 + 0.0; // `+ 0.0` turns −0 into 0
        }
    }
    BvhFile {
        skeleton,
        frame_time: 1.0 / FPS,
        values,
    }
}

fn set(names: &[String], row: &mut [f64], joint: &str, c: Channel, v: f64) {
    let key = format!("{joint}.{}", c.name());
    if let Some(i) = names.iter().position(|n| *n == key) {
        row[i] = v;
    }
}

/// Two strides of a steady walk (1 s per stride, 1.2 m/s forward along +z):
/// hip flexion, knee bend in swing, ankle roll, opposite arm swing, pelvis
/// twist and the hips' double-frequency bob. 61 frames, 2 s.
pub fn walk() -> BvhFile {
    use Channel::*;
    clip(61, |t| {
        let ph = 2.0 * PI * t; // stride phase: one left and one right step per second
        let hip = |p: f64| -25.0 * p.sin() + 5.0; // flexion is negative X rotation
        // Knee flexes in swing (hip moving forward), nearly straight in stance.
        let knee = |p: f64| 5.0 + 55.0 * (0.5 + 0.5 * (p - 1.3).sin()).powi(3);
        let ankle = |p: f64| 10.0 * (p + 0.5).sin();
        vec![
            ("Hips", Zposition, 120.0 * t),
            ("Hips", Yposition, HIP_HEIGHT - 2.0 + 1.5 * (2.0 * ph).cos()),
            ("Hips", Yrotation, 6.0 * ph.sin()),
            ("Hips", Zrotation, 3.0 * ph.cos()),
            ("Chest", Yrotation, -8.0 * ph.sin()),
            ("LeftUpLeg", Xrotation, hip(ph)),
            ("RightUpLeg", Xrotation, hip(ph + PI)),
            ("LeftLeg", Xrotation, knee(ph)),
            ("RightLeg", Xrotation, knee(ph + PI)),
            ("LeftFoot", Xrotation, ankle(ph)),
            ("RightFoot", Xrotation, ankle(ph + PI)),
            // Arms swing against the legs; elbows stay a little bent.
            ("LeftArm", Xrotation, -20.0 * (ph + PI).sin()),
            ("RightArm", Xrotation, -20.0 * ph.sin()),
            (
                "LeftForeArm",
                Yrotation,
                -15.0 - 10.0 * (ph + PI).sin().max(0.0),
            ),
            ("RightForeArm", Yrotation, 15.0 + 10.0 * ph.sin().max(0.0)),
        ]
    })
}

/// Standing, the right arm rises over 0.5 s, waves the forearm three times
/// (0.6 s each) and comes down. 91 frames, 3 s.
pub fn wave() -> BvhFile {
    use Channel::*;
    clip(91, |t| {
        // Smooth 0→1→0 envelope: up by 0.5 s, down from 2.4 s to 3 s.
        let s = |x: f64| {
            let x = x.clamp(0.0, 1.0);
            x * x * (3.0 - 2.0 * x)
        };
        let lift = s(t / 0.5) * (1.0 - s((t - 2.4) / 0.6));
        let wag = if (0.5..2.3).contains(&t) {
            (2.0 * PI * (t - 0.5) / 0.6).sin()
        } else {
            0.0
        };
        vec![
            ("Hips", Yposition, HIP_HEIGHT - 1.0),
            ("RightArm", Zrotation, 80.0 - 150.0 * lift),
            ("RightForeArm", Zrotation, -40.0 * lift + 25.0 * lift * wag),
            ("Chest", Zrotation, 3.0 * lift),
            ("Head", Yrotation, -10.0 * lift),
        ]
    })
}

/// Smooth 0→1 step over x ∈ [0, 1] (zero slope at both ends).
fn smoothstep(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

/// One second of a run (1.4 strides per second, 3 m/s along +z): larger hip
/// and knee swings than the walk, a deeper bob, elbows bent. 31 frames, 1 s.
pub fn run() -> BvhFile {
    use Channel::*;
    clip(31, |t| {
        let ph = 2.0 * PI * 1.4 * t;
        let hip = |p: f64| -40.0 * p.sin() + 10.0;
        let knee = |p: f64| 15.0 + 85.0 * (0.5 + 0.5 * (p - 1.2).sin()).powi(2);
        let ankle = |p: f64| 15.0 * (p + 0.5).sin();
        vec![
            ("Hips", Zposition, 300.0 * t),
            ("Hips", Yposition, HIP_HEIGHT - 6.0 + 3.0 * (2.0 * ph).cos()),
            ("Hips", Xrotation, -8.0), // leaning forward
            ("Hips", Yrotation, 8.0 * ph.sin()),
            ("Chest", Yrotation, -12.0 * ph.sin()),
            ("LeftUpLeg", Xrotation, hip(ph)),
            ("RightUpLeg", Xrotation, hip(ph + PI)),
            ("LeftLeg", Xrotation, knee(ph)),
            ("RightLeg", Xrotation, knee(ph + PI)),
            ("LeftFoot", Xrotation, ankle(ph)),
            ("RightFoot", Xrotation, ankle(ph + PI)),
            ("LeftArm", Xrotation, -35.0 * (ph + PI).sin()),
            ("RightArm", Xrotation, -35.0 * ph.sin()),
            ("LeftForeArm", Yrotation, -80.0),
            ("RightForeArm", Yrotation, 80.0),
        ]
    })
}

/// Standing, the right leg kicks forward: the hip flexes to 75° with the knee
/// bent, the knee snaps straight at the top, and the leg comes back down.
/// 46 frames, 1.5 s.
pub fn kick() -> BvhFile {
    use Channel::*;
    clip(46, |t| {
        // 0–0.3 s still, kick up by 0.75 s, down by 1.2 s, then still
        let up = smoothstep((t - 0.3) / 0.45) * (1.0 - smoothstep((t - 0.75) / 0.45));
        let snap = smoothstep((t - 0.5) / 0.25) * (1.0 - smoothstep((t - 0.75) / 0.3));
        vec![
            ("Hips", Yposition, HIP_HEIGHT - 1.0),
            ("Hips", Xrotation, 10.0 * up), // leaning back
            ("RightUpLeg", Xrotation, -75.0 * up),
            ("RightLeg", Xrotation, 70.0 * up * (1.0 - snap)),
            ("RightFoot", Xrotation, -20.0 * up),
            ("LeftLeg", Xrotation, 10.0 * up),
            ("LeftArm", Zrotation, -80.0 + 35.0 * up),
            ("RightArm", Zrotation, 80.0 - 35.0 * up),
        ]
    })
}

/// Rose's Fig. 10 setting: the right upper arm held out sideways
/// (horizontal) with the forearm pointing straight up for 0.5 s, then the
/// forearm swings down to horizontal over 0.5 s and stays; upper arm and
/// wrist keep the same angles at the start and the end. 46 frames, 1.5 s.
pub fn arm_raise() -> BvhFile {
    use Channel::*;
    clip(46, |t| {
        let s = smoothstep((t - 0.5) / 0.5);
        vec![
            ("Hips", Yposition, HIP_HEIGHT - 1.0),
            ("RightArm", Zrotation, 0.0),
            ("RightForeArm", Zrotation, -90.0 * (1.0 - s)),
            ("RightHand", Zrotation, 0.0),
        ]
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mocap::bvh::fk::{end_site_positions, world_positions};

    #[test]
    fn walk_feet_touch_the_ground_and_hips_advance() {
        let w = walk();
        assert_eq!(w.frame_count(), 61);
        let mut min_foot = f64::INFINITY;
        for f in 0..w.frame_count() {
            let ends = end_site_positions(&w, f, 0.01);
            // End sites: head, left hand, right hand, left foot, right foot.
            let low = ends[3].y.min(ends[4].y);
            min_foot = min_foot.min(low);
            assert!(low > -0.05 && low < 0.12, "frame {f}: lowest foot at {low}");
        }
        assert!(min_foot < 0.03);
        let p0 = world_positions(&w, 0, 0.01)[0];
        let p1 = world_positions(&w, 60, 0.01)[0];
        assert!(((p1.z - p0.z) - 2.4).abs() < 1e-9);
    }

    #[test]
    fn wave_raises_the_right_hand_above_the_head() {
        let w = wave();
        let ends = end_site_positions(&w, 45, 0.01);
        assert!(
            ends[2].y > ends[0].y - 0.1,
            "right hand {} vs head {}",
            ends[2].y,
            ends[0].y
        );
        let rest = end_site_positions(&w, 0, 0.01);
        assert!(rest[2].y < 1.0, "hand hangs at rest: {}", rest[2].y);
    }
}
