//! Which way a clip's skeleton stands: the "up" `body_of` puts gravity
//! against, so a z-up skeleton (Blender and many tools export Z up) stands on
//! its floor instead of a wall.
//!
//! Up is the direction from the skeleton's feet (its joints named as feet:
//! `model::topology::is_foot_name`, the rule of `ground`'s contact points) to
//! their nearest common ancestor (the hips), snapped to the nearest ±axis:
//! - at rest (every channel zero, the OFFSETs), when the rest pose stands:
//!   the feet lie along one axis from the hips (a T- or A-pose);
//! - else over the motion's frames, when one is given and the body mostly
//!   stands in it (Bandai's rest pose is a cross of limbs along ±x, each
//!   joint's rotation channels stand it up);
//! - else y, BVH's convention: a skeleton without feet (an arm, a pendulum)
//!   keeps y-up, as do a rest pose and a motion that say nothing clear.

use super::bvh::{BvhJoint, Channel, Skeleton, joint_local_transform};
use crate::lie::Se3;
use crate::model::topology::is_foot_name;
use crate::motion::{Dof, Mu};
use nalgebra::Vector3;

/// Standard gravity (m/s²).
pub const STANDARD_GRAVITY: f64 = 9.80665;

/// Frames of a motion read for its up, evenly spread over its span.
const SAMPLES: usize = 32;

/// A direction names an axis when that axis carries at least this share of
/// it (within 41° of the axis): a rest pose sitting at 45° names none.
const AXIS_SHARE: f64 = 0.75;

/// The feet must lie at least this share of their distance from the hips
/// along the mean direction (at rest: a standing pose, not a cross of limbs;
/// over a motion: the mean of the frames' unit directions, so a body lying
/// as often one way as another names nothing).
const CONSISTENT: f64 = 0.5;

/// The unit ±axis `skeleton` stands along (see the module doc). `motion`
/// (DOFs named `Joint.channel`, radians and metres) is read only when the
/// rest pose does not stand; `metres_per_unit` is the file's length unit.
pub fn skeleton_up(sk: &Skeleton, motion: Option<&Mu>, metres_per_unit: f64) -> Vector3<f64> {
    let Some((feet, hips)) = feet_and_hips(sk) else {
        return Vector3::y();
    };
    let rest = rest_positions(sk);
    if let Some(up) = axis_of(std::slice::from_ref(&rest), &feet, hips, false) {
        return up;
    }
    let frames = motion
        .map(|m| frame_positions(sk, m, metres_per_unit))
        .unwrap_or_default();
    axis_of(&frames, &feet, hips, true).unwrap_or_else(Vector3::y)
}

/// Standard gravity (m/s²) against [`skeleton_up`] (its other components
/// +0, as `body_of`'s y-up constant has them).
pub fn skeleton_gravity(sk: &Skeleton, motion: Option<&Mu>, metres_per_unit: f64) -> Vector3<f64> {
    skeleton_up(sk, motion, metres_per_unit)
        .map(|u| if u == 0.0 { 0.0 } else { -u * STANDARD_GRAVITY })
}

/// The skeleton's foot joints and their nearest common ancestor; when that
/// is a foot itself (one leg), the skeleton's root. `None` without feet or
/// when no joint above them is left.
fn feet_and_hips(sk: &Skeleton) -> Option<(Vec<usize>, usize)> {
    let feet: Vec<usize> = (0..sk.joints.len())
        .filter(|&i| is_foot_name(&sk.joints[i].name))
        .collect();
    let chain = |j: usize| {
        let mut out = vec![];
        let mut k = Some(j);
        while let Some(i) = k {
            out.push(i);
            k = sk.joints[i].parent;
        }
        out
    };
    let mut common = chain(*feet.first()?);
    for &f in &feet[1..] {
        let c = chain(f);
        common.retain(|a| c.contains(a));
    }
    let nearest = *common.first()?;
    let hips = if feet.contains(&nearest) {
        *common.last()?
    } else {
        nearest
    };
    (!feet.contains(&hips)).then_some((feet, hips))
}

/// Joint positions at rest (file units): every channel zero, the OFFSETs.
fn rest_positions(sk: &Skeleton) -> Vec<Vector3<f64>> {
    let mut out: Vec<Vector3<f64>> = Vec::with_capacity(sk.joints.len());
    for j in &sk.joints {
        let p = j.parent.map_or_else(Vector3::zeros, |q| out[q]);
        out.push(p + j.offset);
    }
    out
}

/// BVH channel `c` of joint `j` at time t from its DOF `dof` (named `name`
/// in the motion), in the file's degrees and units; a channel the motion
/// lacks stays at rest. `None` where the DOF is undefined at t.
pub(crate) fn channel_value(
    j: &BvhJoint,
    c: Channel,
    dof: Option<&Dof>,
    name: &str,
    t: f64,
    metres_per_unit: f64,
) -> Option<f64> {
    Some(match dof {
        None if c.is_rotation() => 0.0,
        None => j.offset[c.axis()],
        Some(d) => {
            let v = d.sample_value(name, t).ok().flatten()?;
            if c.is_rotation() {
                v.to_degrees()
            } else {
                v / metres_per_unit
            }
        }
    })
}

/// Joint positions (metres) at up to [`SAMPLES`] frames of `mu` spread over
/// its span, those where every channel it names is defined; a channel it
/// lacks stays at rest.
fn frame_positions(sk: &Skeleton, mu: &Mu, metres_per_unit: f64) -> Vec<Vec<Vector3<f64>>> {
    let Some((lo, hi)) = mu.span() else {
        return vec![];
    };
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
    let pose = |t: f64| -> Option<Vec<Vector3<f64>>> {
        let mut world: Vec<Se3> = Vec::with_capacity(sk.joints.len());
        let mut values = vec![];
        for (j, names) in sk.joints.iter().zip(&names) {
            values.clear();
            for (c, name) in j.channels.iter().zip(names) {
                values.push(channel_value(
                    j,
                    *c,
                    mu.get(name),
                    name,
                    t,
                    metres_per_unit,
                )?);
            }
            let local = joint_local_transform(j, &values, metres_per_unit);
            world.push(match j.parent {
                Some(p) => world[p].compose(&local),
                None => local,
            });
        }
        Some(world.into_iter().map(|x| x.p).collect())
    };
    (0..SAMPLES)
        .filter_map(|k| pose(lo + (hi - lo) * k as f64 / (SAMPLES - 1) as f64))
        .collect()
}

/// The ±axis the feet-to-hips direction names over `poses`: each pose's
/// direction scaled by 1/(the feet's mean distance from the hips), or made
/// a unit vector when `unit` (frames of a motion weigh alike), averaged; `None` when the mean is not [`CONSISTENT`] or no axis carries
/// [`AXIS_SHARE`] of it.
fn axis_of(
    poses: &[Vec<Vector3<f64>>],
    feet: &[usize],
    hips: usize,
    unit: bool,
) -> Option<Vector3<f64>> {
    let mut sum = Vector3::zeros();
    let mut count = 0usize;
    for p in poses {
        let mean = feet.iter().map(|&f| p[f]).sum::<Vector3<f64>>() / feet.len() as f64;
        let d = p[hips] - mean;
        let scale = if unit {
            d.norm()
        } else {
            feet.iter().map(|&f| (p[hips] - p[f]).norm()).sum::<f64>() / feet.len() as f64
        };
        if scale > 0.0 && scale.is_finite() {
            sum += d / scale;
            count += 1;
        }
    }
    let mean = sum / count.max(1) as f64;
    let n = mean.norm();
    if !(count > 0 && n >= CONSISTENT) {
        return None;
    }
    let k = mean.iamax();
    (mean[k].abs() >= AXIS_SHARE * n).then(|| {
        let mut up = Vector3::zeros();
        up[k] = mean[k].signum();
        up
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mocap::body_of::{body_of, body_of_motion};
    use crate::mocap::bvh::{BvhJoint, Channel};
    use crate::motion::rotation::{from_euler, to_euler_near};
    use crate::motion::{Curve, Dof, Interval};
    use nalgebra::{Rotation3, UnitQuaternion};

    const ZXY: [usize; 3] = [2, 0, 1];
    const GRAVITY_Y_UP_TEST: [f64; 3] = crate::mocap::body_of::GRAVITY_Y_UP;

    /// A small humanoid (cm): hips with six channels, spine, head, two
    /// arms and two legs with feet and toes, every other joint ZXY; legs of
    /// `leg` cm per bone, spread `lean` cm forward so no two skeletons are
    /// alike. `cross`: the legs at rest along ±x (Bandai's rest), stood up
    /// by their hip rotations in the motion.
    fn humanoid(leg: f64, lean: f64, cross: bool) -> Skeleton {
        use Channel::*;
        let rot = vec![Zrotation, Xrotation, Yrotation];
        let mut joints: Vec<BvhJoint> = vec![];
        let mut add = |name: &str, parent: Option<usize>, o: [f64; 3]| {
            joints.push(BvhJoint {
                name: name.into(),
                parent,
                offset: Vector3::from(o),
                channels: if parent.is_none() {
                    vec![
                        Xposition, Yposition, Zposition, Zrotation, Xrotation, Yrotation,
                    ]
                } else {
                    rot.clone()
                },
                end_sites: vec![],
            });
            joints.len() - 1
        };
        let hips = add("Hips", None, [0.0, 2.0 * leg, 0.0]);
        let spine = add("Spine", Some(hips), [0.0, 20.0, 0.0]);
        add("Head", Some(spine), [0.0, 30.0, 0.0]);
        for (side, s) in [("Left", 1.0), ("Right", -1.0)] {
            let arm = add(&format!("{side}Arm"), Some(spine), [s * 15.0, 25.0, 0.0]);
            add(&format!("{side}Hand"), Some(arm), [s * 50.0, 0.0, 0.0]);
            let bone = |k: f64| {
                if cross {
                    [s * k * leg, 0.0, 0.0]
                } else {
                    [0.0, -k * leg, lean]
                }
            };
            let up = add(&format!("{side}UpLeg"), Some(hips), [s * 10.0, 0.0, 0.0]);
            let knee = add(&format!("{side}Leg"), Some(up), bone(1.0));
            let foot = add(&format!("{side}Foot"), Some(knee), bone(1.0));
            add(&format!("{side}ToeBase"), Some(foot), [0.0, -3.0, 12.0]);
        }
        Skeleton {
            joints,
            inertias: None,
        }
    }

    /// Every angle zero but the hips' `Zrotation` (degrees), held over 1 s.
    fn motion(sk: &Skeleton, hips_z: [f64; 2]) -> Mu {
        let mut mu = Mu::new();
        for j in &sk.joints {
            for c in &j.channels {
                let v = match (j.name.as_str(), c) {
                    ("LeftUpLeg", Channel::Zrotation) => hips_z[0].to_radians(),
                    ("RightUpLeg", Channel::Zrotation) => hips_z[1].to_radians(),
                    (_, c) if !c.is_rotation() => j.offset[c.axis()] * 0.01,
                    _ => 0.0,
                };
                let iv = Interval::curve(Curve::constant(v).unwrap(), 0.0, 1.0).unwrap();
                mu.insert(
                    format!("{}.{}", j.name, c.name()),
                    Dof::new(vec![iv]).unwrap(),
                );
            }
        }
        mu
    }

    /// `sk` and `mu` turned by `r`: offsets rotated, every joint's rotation
    /// conjugated (R·Rj·Rᵀ, back to its own ZXY order), the root's position
    /// channels rotated: the same physical pose on a turned skeleton.
    fn turned(sk: &Skeleton, mu: &Mu, r: &Rotation3<f64>) -> (Skeleton, Mu) {
        let mut out = sk.clone();
        for j in &mut out.joints {
            j.offset = r * j.offset;
        }
        let q = UnitQuaternion::from_rotation_matrix(r);
        let at = |n: &str| mu.sample_value(n, 0.0).unwrap().unwrap();
        let mut m = Mu::new();
        let mut put = |n: String, v: f64| {
            let iv = Interval::curve(Curve::constant(v).unwrap(), 0.0, 1.0).unwrap();
            m.insert(n, Dof::new(vec![iv]).unwrap());
        };
        for j in &sk.joints {
            let n = |c: &str| format!("{}.{c}", j.name);
            let a = [
                at(&n("Zrotation")),
                at(&n("Xrotation")),
                at(&n("Yrotation")),
            ];
            let e = to_euler_near(ZXY, &(q * from_euler(ZXY, a) * q.inverse()), a);
            for (c, v) in ["Zrotation", "Xrotation", "Yrotation"].iter().zip(e) {
                put(n(c), v);
            }
            if j.parent.is_none() {
                let p = r * Vector3::new(
                    at(&n("Xposition")),
                    at(&n("Yposition")),
                    at(&n("Zposition")),
                );
                for (c, v) in ["Xposition", "Yposition", "Zposition"].iter().zip(p.iter()) {
                    put(n(c), *v);
                }
            }
        }
        (out, m)
    }

    /// y → z, y → x and y → −y.
    fn turns() -> [(Rotation3<f64>, Vector3<f64>); 3] {
        let r = |axis: Vector3<f64>, deg: f64| {
            Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(axis), deg.to_radians())
        };
        [
            (r(Vector3::x(), 90.0), Vector3::z()),
            (r(Vector3::z(), -90.0), Vector3::x()),
            (r(Vector3::x(), 180.0), -Vector3::y()),
        ]
    }

    fn gravity_of(sk: &Skeleton, mu: Option<&Mu>) -> Vector3<f64> {
        match mu {
            Some(m) => body_of_motion(sk, m, 70.0, 0.01),
            None => body_of(sk, 70.0, 0.01),
        }
        .unwrap()
        .0
        .default_gravity
    }

    #[test]
    fn a_standing_skeleton_turned_gets_gravity_along_its_feet() {
        for (leg, lean) in [(45.0, 0.0), (38.0, 9.0), (52.0, -14.0)] {
            let sk = humanoid(leg, lean, false);
            let mu = motion(&sk, [0.0, 0.0]);
            assert_eq!(gravity_of(&sk, None), Vector3::from(GRAVITY_Y_UP_TEST));
            for (r, up) in turns() {
                let (t, tm) = turned(&sk, &mu, &r);
                let g = -up * STANDARD_GRAVITY;
                assert_eq!(gravity_of(&t, None), g, "{up:?}");
                assert_eq!(gravity_of(&t, Some(&tm)), g, "{up:?}");
                // the root's slide along up is its vertical, at q = 0
                let (b, _) = body_of(&t, 70.0, 0.01).unwrap();
                let root = crate::model::RootCoords::detect(&b, Some(&up));
                let names = b.coordinate_names();
                let axis = ["Hips.Xposition", "Hips.Yposition", "Hips.Zposition"][up.iamax()];
                assert_eq!(root.vertical.len(), 1);
                assert_eq!(names[root.vertical[0]], axis, "{up:?}");
                assert_eq!(root.horizontal.len(), 2);
            }
        }
    }

    #[test]
    fn a_rest_pose_that_does_not_stand_is_read_from_the_motion() {
        // legs along ±x at rest, swung down by the hip rotations
        let sk = humanoid(45.0, 0.0, true);
        let standing = motion(&sk, [-90.0, 90.0]);
        assert_eq!(
            skeleton_up(&sk, None, 0.01),
            Vector3::y(),
            "no clear rest: y"
        );
        assert_eq!(skeleton_up(&sk, Some(&standing), 0.01), Vector3::y());
        // the same legs swung up: the body stands on its head
        let hands = motion(&sk, [90.0, -90.0]);
        assert_eq!(skeleton_up(&sk, Some(&hands), 0.01), -Vector3::y());
        for (r, up) in turns() {
            let (t, tm) = turned(&sk, &standing, &r);
            assert_eq!(skeleton_up(&t, None, 0.01), Vector3::y(), "{up:?}");
            assert_eq!(skeleton_up(&t, Some(&tm), 0.01), up, "{up:?}");
        }
    }

    #[test]
    fn a_skeleton_without_feet_keeps_y_up() {
        // the z-up humanoid with its feet renamed: nothing says where the
        // floor is (an arm, a pendulum), so BVH's y stays up
        let sk = humanoid(45.0, 0.0, false);
        let (mut t, tm) = turned(&sk, &motion(&sk, [0.0, 0.0]), &turns()[0].0);
        for j in &mut t.joints {
            j.name = j.name.replace("Foot", "Paw").replace("ToeBase", "Claw");
        }
        assert_eq!(skeleton_up(&t, None, 0.01), Vector3::y());
        assert_eq!(skeleton_up(&t, Some(&tm), 0.01), Vector3::y());
        assert_eq!(gravity_of(&t, None), Vector3::from(GRAVITY_Y_UP_TEST));
    }
}
