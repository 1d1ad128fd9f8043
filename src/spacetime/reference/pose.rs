//! How far apart two poses are, whatever chart their angles are written in.
//!
//! An example is chosen by how well its context matches the gap's, and a
//! joint follows it when it is close at the gap's ends. Compared channel by
//! channel, Euler angles give another answer for the same motion written on
//! another skeleton: a walk on a z-up skeleton has every joint rotation
//! turned (R·Rj·Rᵀ), and its Euler angles are other numbers for the same
//! poses (a y-up walk found its own repeat at ρ 0.69, its z-up copy none
//! under 3.4). So a joint whose channels are BVH rotations about named axes
//! is compared as one rotation: the geodesic angle between the two
//! rotations its channels make (applied in the coordinates' order, as BVH
//! and the model apply them), which conjugation by any R leaves unchanged.
//! Angles that name no axis (an OpenSim coordinate) are compared one by one
//! as before (wrapped).

use super::joints::Joints;
use super::wrap;
use crate::motion::channel::rotation_axis;
use nalgebra::{Quaternion, Unit, UnitQuaternion, Vector3};

/// The angle coordinates of a list, grouped into what is compared as one.
#[derive(Clone, Debug)]
pub(super) struct PoseMetric {
    blocks: Vec<Block>,
    /// Per position in the list: its block, `None` for a translation.
    block_of: Vec<Option<usize>>,
}

#[derive(Clone, Debug)]
enum Block {
    /// One joint's rotation channels: (position in the list, axis), in the
    /// order they are applied.
    Rotation(Vec<(usize, Vector3<f64>)>),
    /// One angle on its own (position in the list).
    Angle(usize),
}

/// One block's value in a pose.
#[derive(Clone, Copy, Debug)]
pub(super) enum Part {
    Rotation(UnitQuaternion<f64>),
    Angle(f64),
}

/// A pose as the metric compares it: one [`Part`] per block.
pub(super) type Pose = Vec<Part>;

impl PoseMetric {
    /// Over `coords` (model coordinates, `names[c]` each): the angles
    /// (`rotation(c)`) grouped by joint. A joint is one rotation when every
    /// one of its angle channels names its axis; else its angles stand alone.
    pub fn new(
        names: &[String],
        coords: &[usize],
        rotation: &dyn Fn(usize) -> bool,
        joints: &Joints,
    ) -> Self {
        let mut blocks: Vec<Block> = vec![];
        let mut block_of = vec![None; coords.len()];
        for i in 0..coords.len() {
            if block_of[i].is_some() || !rotation(coords[i]) {
                continue;
            }
            let mut members: Vec<usize> = (i..coords.len())
                .filter(|&j| rotation(coords[j]) && joints.same(coords[i], coords[j]))
                .collect();
            members.sort_by_key(|&j| coords[j]);
            let axes: Option<Vec<(usize, Vector3<f64>)>> = members
                .iter()
                .map(|&j| rotation_axis(&names[coords[j]]).map(|a| (j, Vector3::ith(a, 1.0))))
                .collect();
            match axes {
                Some(axes) => {
                    for &j in &members {
                        block_of[j] = Some(blocks.len());
                    }
                    blocks.push(Block::Rotation(axes));
                }
                None => {
                    for &j in &members {
                        block_of[j] = Some(blocks.len());
                        blocks.push(Block::Angle(j));
                    }
                }
            }
        }
        PoseMetric { blocks, block_of }
    }

    /// Whether list position i is a channel of a three-channel BVH joint:
    /// its example is laid as rotations re-expressed on the motion's own
    /// Euler branch (`lay.rs`), so a wrap of its channel in the data (±π)
    /// is no jump in the laid curve.
    pub fn unwrapped_when_laid(&self, i: usize) -> bool {
        self.block_of[i]
            .is_some_and(|b| matches!(&self.blocks[b], Block::Rotation(a) if a.len() == 3))
    }

    /// The pose whose list position i has value `value(i)` (radians for angles).
    pub fn pose(&self, value: impl Fn(usize) -> f64) -> Pose {
        self.blocks
            .iter()
            .map(|b| match b {
                Block::Rotation(axes) => Part::Rotation(axes.iter().fold(
                    UnitQuaternion::identity(),
                    |q, (j, axis)| {
                        q * UnitQuaternion::from_axis_angle(&Unit::new_unchecked(*axis), value(*j))
                    },
                )),
                Block::Angle(j) => Part::Angle(value(*j)),
            })
            .collect()
    }

    /// Per block, the angle (rad) between the poses `a` and `b`.
    pub fn angles(&self, a: &Pose, b: &Pose) -> Vec<f64> {
        a.iter().zip(b).map(|(x, y)| part_angle(x, y)).collect()
    }

    /// Σ over blocks of the squared angle between `a` and `b`.
    pub fn distance2(&self, a: &Pose, b: &Pose) -> f64 {
        a.iter()
            .zip(b)
            .map(|(x, y)| {
                let d = part_angle(x, y);
                d * d
            })
            .sum()
    }

    /// Σ over blocks of the poses' squared spread about their mean (for a
    /// rotation: the normalised sum of its quaternions, signs taken with the
    /// first; for an angle: the wrapped mean).
    pub fn spread(&self, poses: &[Pose]) -> f64 {
        let Some(first) = poses.first() else {
            return 0.0;
        };
        (0..self.blocks.len())
            .map(|b| {
                let mean = mean_part(&first[b], poses.iter().map(|p| &p[b]));
                poses
                    .iter()
                    .map(|p| {
                        let d = part_angle(&p[b], &mean);
                        d * d
                    })
                    .sum::<f64>()
            })
            .sum()
    }

    /// Whether list position i is close to its example at both ends, given
    /// each block's angle there (`ends`): `limit` per channel, so a joint of
    /// n channels within `limit`·√n as one rotation (the largest turn a
    /// joint with each channel `limit` off makes, as the per-channel rule
    /// allowed; a one-channel joint, a knee, is held to `limit` exactly).
    /// A translation always is (translations are compared once the example
    /// is laid, `lay.rs`).
    pub fn close(&self, i: usize, ends: &[Vec<f64>], limit: f64) -> bool {
        match self.block_of[i] {
            None => true,
            Some(b) => {
                let channels = match &self.blocks[b] {
                    Block::Rotation(axes) => axes.len(),
                    Block::Angle(_) => 1,
                };
                let limit = limit * (channels as f64).sqrt();
                ends.iter().all(|e| e[b] <= limit)
            }
        }
    }
}

fn part_angle(a: &Part, b: &Part) -> f64 {
    match (a, b) {
        (Part::Rotation(x), Part::Rotation(y)) => x.angle_to(y),
        (Part::Angle(x), Part::Angle(y)) => wrap(x - y).abs(),
        _ => f64::NAN,
    }
}

fn mean_part<'a>(first: &Part, parts: impl Iterator<Item = &'a Part>) -> Part {
    match first {
        Part::Rotation(q0) => {
            let mut sum = Quaternion::new(0.0, 0.0, 0.0, 0.0);
            for p in parts {
                if let Part::Rotation(q) = p {
                    let q = q.into_inner();
                    sum += if q.dot(q0) < 0.0 { -q } else { q };
                }
            }
            Part::Rotation(UnitQuaternion::from_quaternion(sum))
        }
        Part::Angle(a0) => {
            let rel: Vec<f64> = parts
                .filter_map(|p| match p {
                    Part::Angle(a) => Some(wrap(a - a0)),
                    Part::Rotation(_) => None,
                })
                .collect();
            Part::Angle(a0 + rel.iter().sum::<f64>() / rel.len().max(1) as f64)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Rotation3;

    fn names() -> Vec<String> {
        ["Hips.Zrotation", "Hips.Xrotation", "Hips.Yrotation", "knee"]
            .map(String::from)
            .to_vec()
    }

    /// ZXY Euler angles of a rotation matrix (R = Rz Rx Ry).
    fn zxy(r: &Rotation3<f64>) -> [f64; 3] {
        let m = r.matrix();
        let x = m[(2, 1)].clamp(-1.0, 1.0).asin();
        let z = (-m[(0, 1)]).atan2(m[(1, 1)]);
        let y = (-m[(2, 0)]).atan2(m[(2, 2)]);
        [z, x, y]
    }

    fn rot(a: [f64; 3]) -> Rotation3<f64> {
        Rotation3::from_axis_angle(&Vector3::z_axis(), a[0])
            * Rotation3::from_axis_angle(&Vector3::x_axis(), a[1])
            * Rotation3::from_axis_angle(&Vector3::y_axis(), a[2])
    }

    #[test]
    fn the_distance_and_spread_do_not_change_when_every_rotation_is_turned() {
        let names = names();
        let coords = [0, 1, 2, 3];
        let metric = PoseMetric::new(&names, &coords, &|_| true, &Joints::by_name(&names));
        let turn = Rotation3::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_2);
        let poses = [
            [0.3, -0.2, 1.1, 0.4],
            [0.35, -0.1, 1.0, 0.5],
            [2.9, 0.4, -3.0, -3.1],
        ];
        let as_pose = |p: &[f64; 4]| metric.pose(|i| p[i]);
        let turned = |p: &[f64; 4]| {
            let e = zxy(&(turn * rot([p[0], p[1], p[2]]) * turn.inverse()));
            [e[0], e[1], e[2], p[3]]
        };
        let plain: Vec<Pose> = poses.iter().map(as_pose).collect();
        let other: Vec<Pose> = poses.iter().map(|p| as_pose(&turned(p))).collect();
        for i in 0..poses.len() {
            for j in 0..poses.len() {
                let (a, b) = (
                    metric.distance2(&plain[i], &plain[j]),
                    metric.distance2(&other[i], &other[j]),
                );
                assert!((a - b).abs() < 1e-9 * (1.0 + a), "{a} vs {b}");
            }
            // the channels themselves are other numbers
            assert!(
                poses[i][..3]
                    .iter()
                    .zip(&turned(&poses[i]))
                    .any(|(x, y)| (x - y).abs() > 0.1)
            );
        }
        let (a, b) = (metric.spread(&plain), metric.spread(&other));
        assert!((a - b).abs() < 1e-9 * (1.0 + a), "{a} vs {b}");
        // the lone angle (no axis in its name) wraps: 3.1 and −3.1 are 0.083 apart
        let d = metric.angles(&plain[2], &metric.pose(|i| [2.9, 0.4, -3.0, 3.1][i]));
        assert!(
            (d[1] - (2.0 * std::f64::consts::PI - 6.2)).abs() < 1e-12,
            "{d:?}"
        );
    }

    #[test]
    fn at_gimbal_lock_two_triples_of_one_rotation_are_no_distance_apart() {
        // ZXY with X = 90°: Z and Y turn about one axis, so (z, 90°, y) and
        // (z + 1, 90°, y − 1) are one rotation, 1.4 rad apart channel by channel
        let names = names();
        let metric = PoseMetric::new(&names, &[0, 1, 2], &|_| true, &Joints::by_name(&names));
        let half = std::f64::consts::FRAC_PI_2;
        let a = metric.pose(|i| [0.3, half, 0.2][i]);
        let b = metric.pose(|i| [1.3, half, -0.8][i]);
        let d = metric.distance2(&a, &b);
        assert!(d.is_finite() && d < 1e-14, "{d}");
        let spread = metric.spread(&[a.clone(), b.clone(), a]);
        assert!(spread.is_finite() && spread < 1e-14, "{spread}");
    }

    #[test]
    fn a_joint_with_an_unnamed_axis_is_compared_angle_by_angle() {
        let names: Vec<String> = ["hip_flexion", "hip_adduction"].map(String::from).to_vec();
        let joints = Joints::by_name(&names);
        let metric = PoseMetric::new(&names, &[0, 1], &|_| true, &joints);
        let (a, b) = (
            metric.pose(|i| [0.1, 0.2][i]),
            metric.pose(|i| [0.4, -0.2][i]),
        );
        assert!((metric.distance2(&a, &b) - (0.09 + 0.16)).abs() < 1e-12);
    }
}
