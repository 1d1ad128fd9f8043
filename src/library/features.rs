//! Motion-matching features of one frame (Clavet 2016, Holden et al. 2020),
//! from a motion driving a BVH skeleton.
//!
//! A frame has two vectors of [`DIM`] numbers, both in the body's heading
//! frame (origin the pelvis centre on the floor, axes across the hips, up,
//! forward): the *before* vector describes how the motion arrives at the
//! frame, the *after* vector how it leaves it. A gap [t0, t1] is matched by
//! the before vector at t0 (the gap's context before it) and the after
//! vector at t1 (the context after it), so neither reads inside the gap.
//!
//! | dims | feature |
//! | --- | --- |
//! | 0–11 | left/right foot, left/right hand, relative to the pelvis centre |
//! | 12–17 | left/right foot velocity over one grid step (back, or ahead) |
//! | 18–19 | the pelvis's floor velocity over one grid step |
//! | 20–21 | where the pelvis was (will be) [`HORIZON`] seconds away, on the floor |
//! | 22–23 | which way the body faced (will face) then: sin and cos of the turn |
//!
//! Feet and hands are what an eye compares first (contacts, reaches); the
//! trajectory says where the body goes. Other joints follow these closely in
//! human motion and would only dilute the distance (Clavet's set has 27
//! numbers; this one 24, so the k-d tree stays within reach of its pruning).
//! Up is the one the clip's skeleton stands along (`mocap::up`, y for the
//! usual BVH skeleton), so a z-up copy of a clip has the features of the
//! clip itself.

use crate::mocap::bvh::{Skeleton, joint_local_transform};
use crate::mocap::up::channel_value;
use crate::motion::Mu;
use nalgebra::Vector3;

/// Numbers per feature vector.
pub const DIM: usize = 24;

/// How far (s) the trajectory features look back or ahead: the
/// in-betweening protocol's ten frames of context at 30 Hz.
pub const HORIZON: f64 = 1.0 / 3.0;

/// The feature groups, each normalised as one (a position keeps its
/// direction): `(first dim, dims)`.
pub const GROUPS: [(usize, usize); 9] = [
    (0, 3),
    (3, 3),
    (6, 3),
    (9, 3),
    (12, 3),
    (15, 3),
    (18, 2),
    (20, 2),
    (22, 2),
];

/// The joints the features read, as indices into a skeleton's joints.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct KeyJoints {
    /// Left, right.
    pub feet: [usize; 2],
    pub hands: [usize; 2],
    /// The hip joints (the feet's grandparents): the pelvis centre is their
    /// midpoint and the line between them gives the heading.
    pub hips: [usize; 2],
}

#[derive(Clone, Copy, PartialEq)]
enum Side {
    Left,
    Right,
}

fn side(name: &str) -> Option<Side> {
    let l = name.to_ascii_lowercase();
    let b = name.as_bytes();
    // `LFoot`: a capital side letter before a capitalised word
    let capital = |c: u8| b.len() > 2 && b[0] == c && b[1].is_ascii_uppercase();
    if l.starts_with("left") || l.starts_with("l_") || l.ends_with("_l") || capital(b'L') {
        Some(Side::Left)
    } else if l.starts_with("right") || l.starts_with("r_") || l.ends_with("_r") || capital(b'R') {
        Some(Side::Right)
    } else {
        None
    }
}

fn is_part(name: &str, words: &[&str]) -> bool {
    let l = name.to_ascii_lowercase();
    words.iter().any(|w| l.contains(w))
        && !["thumb", "index", "finger", "toe", "end", "site"]
            .iter()
            .any(|x| l.contains(x))
}

/// Why a skeleton has no key joints to read features from.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum KeyJointsError {
    /// What was not found (`left foot`, `right hand`, …).
    #[error(
        "no joint for the {} (looked for names with foot/ankle and hand/wrist and a side: Left…, …_L, L…)",
        .0.join(", ")
    )]
    Missing(Vec<String>),
    #[error("the foot `{0}` has no thigh above it")]
    NoThigh(String),
    #[error("both feet hang from one joint: no hip line to face by")]
    OneHip,
}

impl KeyJoints {
    /// Finds feet (`foot`, `ankle`), hands (`hand`, `wrist`) and the hips by
    /// name, the one nearest the root where several match (`LeftHand`, not
    /// `LeftHandIndex1`). The error names what is missing.
    pub fn find(sk: &Skeleton) -> Result<KeyJoints, KeyJointsError> {
        let find = |words: &[&str], s: Side| {
            sk.joints
                .iter()
                .position(|j| is_part(&j.name, words) && side(&j.name) == Some(s))
        };
        let foot = ["foot", "ankle"];
        let hand = ["hand", "wrist"];
        let mut missing = vec![];
        let mut get = |words: &[&str], s: Side, what: &str| {
            let i = find(words, s);
            if i.is_none() {
                missing.push(what.to_string());
            }
            i.unwrap_or(0)
        };
        let feet = [
            get(&foot, Side::Left, "left foot"),
            get(&foot, Side::Right, "right foot"),
        ];
        let hands = [
            get(&hand, Side::Left, "left hand"),
            get(&hand, Side::Right, "right hand"),
        ];
        if !missing.is_empty() {
            return Err(KeyJointsError::Missing(missing));
        }
        let grandparent = |j: usize| {
            sk.joints[j]
                .parent
                .and_then(|p| sk.joints[p].parent)
                .ok_or_else(|| KeyJointsError::NoThigh(sk.joints[j].name.clone()))
        };
        let hips = [grandparent(feet[0])?, grandparent(feet[1])?];
        if hips[0] == hips[1] {
            return Err(KeyJointsError::OneHip);
        }
        Ok(KeyJoints { feet, hands, hips })
    }
}

/// World positions (metres) of the key joints on a time grid, `None` where
/// the motion is undefined. Order: feet, hands, hips (6 points).
pub fn key_positions(
    mu: &Mu,
    sk: &Skeleton,
    metres_per_unit: f64,
    keys: &KeyJoints,
    times: &[f64],
) -> Vec<Option<[Vector3<f64>; 6]>> {
    let wanted = [
        keys.feet[0],
        keys.feet[1],
        keys.hands[0],
        keys.hands[1],
        keys.hips[0],
        keys.hips[1],
    ];
    // only the joints on the key joints' chains need forward kinematics
    let mut needed = vec![false; sk.joints.len()];
    for &w in &wanted {
        let mut j = Some(w);
        while let Some(i) = j {
            needed[i] = true;
            j = sk.joints[i].parent;
        }
    }
    let names: Vec<Vec<String>> = sk
        .joints
        .iter()
        .map(|j| {
            j.channels
                .iter()
                .map(|c| format!("{}.{}", j.name, c.name()))
                .collect()
        })
        .collect();
    let dofs: Vec<Vec<Option<&crate::motion::Dof>>> = names
        .iter()
        .map(|ns| ns.iter().map(|n| mu.get(n)).collect())
        .collect();
    let mut world = vec![crate::lie::Se3::identity(); sk.joints.len()];
    let mut vals = Vec::with_capacity(6);
    times
        .iter()
        .map(|&t| {
            for (i, j) in sk.joints.iter().enumerate() {
                if !needed[i] {
                    continue;
                }
                vals.clear();
                for ((c, name), dof) in j.channels.iter().zip(&names[i]).zip(&dofs[i]) {
                    // (a channel the motion lacks stays at rest)
                    vals.push(channel_value(j, *c, *dof, name, t, metres_per_unit)?);
                }
                let local = joint_local_transform(j, &vals, metres_per_unit);
                world[i] = match j.parent {
                    Some(p) => world[p].compose(&local),
                    None => local,
                };
            }
            Some(wanted.map(|w| world[w].p))
        })
        .collect()
}

/// The pelvis centre and the unit across (left − right hip) and forward
/// vectors on the floor (across `up`) of one frame's key positions.
fn heading(p: &[Vector3<f64>; 6], up: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
    let centre = (p[4] + p[5]) / 2.0;
    let across = p[4] - p[5];
    // (for up = y exactly today's numbers: the y component zeroed)
    let across = across - up * across.dot(up);
    let across = if across.norm() > 1e-9 {
        across.normalize()
    } else {
        // any direction on the floor: x, or z when up is x
        let x = Vector3::x();
        let side = if up.x.abs() > 0.5 { Vector3::z() } else { x };
        side - up * side.dot(up)
    };
    let forward = across.cross(up);
    (centre, across, forward)
}

/// The features of grid frame `f` looking `dir` = −1 (before) or +1 (after),
/// from key positions on a grid of `rate` Hz with `horizon` frames of
/// trajectory, heights along the unit `up` (`mocap::up::skeleton_up`);
/// `None` where a frame they read is outside or undefined.
pub fn frame_features(
    pos: &[Option<[Vector3<f64>; 6]>],
    f: usize,
    dir: i64,
    (horizon, rate): (usize, f64),
    up: &Vector3<f64>,
) -> Option<[f32; DIM]> {
    let at = |k: i64| -> Option<&[Vector3<f64>; 6]> {
        let i = f as i64 + k * dir;
        if i < 0 {
            return None;
        }
        pos.get(i as usize)?.as_ref()
    };
    let p = at(0)?;
    let q = at(1)?;
    let far = at(horizon as i64)?;
    let (c, across, fwd) = heading(p, up);
    let local = |v: Vector3<f64>| [v.dot(&across), v.dot(up), v.dot(&fwd)];
    let floor = |v: Vector3<f64>| [v.dot(&across), v.dot(&fwd)];
    let mut out = [0f32; DIM];
    let mut put = |at: usize, xs: &[f64]| {
        for (o, x) in out[at..at + xs.len()].iter_mut().zip(xs) {
            *o = *x as f32;
        }
    };
    for (j, point) in p.iter().take(4).enumerate() {
        put(3 * j, &local(point - c));
    }
    // velocity forward in time on both sides: (later − earlier) / step
    let s = dir as f64 * rate;
    for j in 0..2 {
        put(12 + 3 * j, &local((q[j] - p[j]) * s));
    }
    let (cq, _, _) = heading(q, up);
    put(18, &floor((cq - c) * s));
    let (cf, _, ff) = heading(far, up);
    put(20, &floor(cf - c));
    put(22, &[ff.dot(&across), ff.dot(&fwd)]);
    Some(out)
}
