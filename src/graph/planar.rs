//! Rigid motions of the ground plane (a turn about the up axis and a shift
//! along the floor): Kovar et al.'s alignment of two point clouds, and the
//! same motion applied to a clip's root channels.
//!
//! The floor is x–z and y is up, as in BVH clips and `spacetime::root`.

use super::error::RootError;
use crate::mocap::bvh::{Channel, Skeleton};
use crate::motion::rotation::{from_euler, to_euler_near};
use nalgebra::{UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

/// p ↦ R_y(turn)·p + (x, 0, z).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Planar {
    /// Radians about +y.
    pub turn: f64,
    pub x: f64,
    pub z: f64,
}

impl Planar {
    pub const IDENTITY: Planar = Planar {
        turn: 0.0,
        x: 0.0,
        z: 0.0,
    };

    pub fn rotation(&self) -> UnitQuaternion<f64> {
        UnitQuaternion::from_axis_angle(&Vector3::y_axis(), self.turn)
    }

    pub fn apply(&self, p: &Vector3<f64>) -> Vector3<f64> {
        let (s, c) = self.turn.sin_cos();
        Vector3::new(c * p.x + s * p.z + self.x, p.y, -s * p.x + c * p.z + self.z)
    }

    /// `self ∘ other`: first `other`, then `self`.
    pub fn then_after(&self, other: &Planar) -> Planar {
        let shifted = self.apply(&Vector3::new(other.x, 0.0, other.z));
        Planar {
            turn: self.turn + other.turn,
            x: shifted.x,
            z: shifted.z,
        }
    }
}

/// The ground-plane motion T minimising Σ_k |a_k − T b_k|² over matched
/// points (Kovar, Gleicher & Pighin 2002, eq. 1 with equal weights): both
/// clouds centred, the turn is the angle of Σ (â × b̂)·y against Σ â·b̂ in x–z,
/// the shift carries b's centroid onto a's.
pub fn fit(a: &[Vector3<f64>], b: &[Vector3<f64>]) -> Planar {
    debug_assert_eq!(a.len(), b.len());
    let n = a.len().max(1) as f64;
    let ca = a.iter().sum::<Vector3<f64>>() / n;
    let cb = b.iter().sum::<Vector3<f64>>() / n;
    let (mut sin, mut cos) = (0.0, 0.0);
    for (p, q) in a.iter().zip(b) {
        let (p, q) = (p - ca, q - cb);
        // R_y(θ) q = (c qx + s qz, ·, −s qx + c qz); p·Rq = c (px qx + pz qz) + s (px qz − pz qx)
        cos += p.x * q.x + p.z * q.z;
        sin += p.x * q.z - p.z * q.x;
    }
    let turn = if sin == 0.0 && cos == 0.0 {
        0.0
    } else {
        sin.atan2(cos)
    };
    let rotated = Planar {
        turn,
        x: 0.0,
        z: 0.0,
    }
    .apply(&cb);
    Planar {
        turn,
        x: ca.x - rotated.x,
        z: ca.z - rotated.z,
    }
}

/// Root-mean-square distance between matched points after `t` moves `b`.
pub fn rms_after(a: &[Vector3<f64>], b: &[Vector3<f64>], t: &Planar) -> f64 {
    let n = a.len().max(1) as f64;
    let sum: f64 = a
        .iter()
        .zip(b)
        .map(|(p, q)| (p - t.apply(q)).norm_squared())
        .sum();
    (sum / n).sqrt()
}

/// Where a clip's ground-plane motion enters a frame row: the first joint
/// with moving channels (Bandai's `Hips` under a still `joint_Root`), the
/// world position of its parent (still ancestors, without rotation) and its
/// channels.
#[derive(Clone, Debug)]
pub struct RootChannels {
    /// The root joint's index in the skeleton; the joints before it are still.
    pub joint: usize,
    /// Metres per file unit (rows hold file units).
    metres_per_unit: f64,
    /// World position of the root joint's parent frame, metres.
    parent: Vector3<f64>,
    /// Channel index (in the row) of the x, y, z position.
    pos: [usize; 3],
    /// Row indices and axes of the three rotation channels, in file order.
    rot: [usize; 3],
    axes: [usize; 3],
}

impl RootChannels {
    /// Finds the root joint of `sk`: the first joint, going down from the
    /// top while joints are still and have one child, with a moving channel.
    /// `moving[c]`: channel c changes over the library; `row`: any frame
    /// (still channels have the same value in every frame).
    pub fn find(
        sk: &Skeleton,
        moving: &[bool],
        row: &[f64],
        metres_per_unit: f64,
    ) -> Result<RootChannels, RootError> {
        let starts = sk.channel_starts();
        let mut j = sk
            .joints
            .iter()
            .position(|jt| jt.parent.is_none())
            .ok_or(RootError::NoRoot)?;
        // world position of the current joint's parent frame (file units)
        let mut base = Vector3::zeros();
        loop {
            let joint = &sk.joints[j];
            let range = starts[j]..starts[j] + joint.channels.len();
            let still = range.clone().all(|c| !moving[c]);
            let kids: Vec<usize> = sk.children(j).collect();
            if !(still && kids.len() == 1) {
                break;
            }
            // A still joint passes its parent's frame on shifted: allowed only unrotated.
            let mut p = joint.offset;
            for (k, ch) in joint.channels.iter().enumerate() {
                let v = row[starts[j] + k];
                if ch.is_rotation() {
                    if v.abs() > 1e-9 {
                        return Err(RootError::RotatedStill {
                            joint: joint.name.clone(),
                            channel: ch.name().to_string(),
                            value: v,
                        });
                    }
                } else {
                    p[ch.axis()] = v;
                }
            }
            base += p;
            j = kids[0];
        }
        let joint = &sk.joints[j];
        let mut pos = [usize::MAX; 3];
        let mut rot = vec![];
        for (k, ch) in joint.channels.iter().enumerate() {
            let c = starts[j] + k;
            match ch {
                Channel::Xposition => pos[0] = c,
                Channel::Yposition => pos[1] = c,
                Channel::Zposition => pos[2] = c,
                _ => rot.push((c, ch.axis())),
            }
        }
        if pos.contains(&usize::MAX) || rot.len() != 3 {
            return Err(RootError::Channels(joint.name.clone()));
        }
        Ok(RootChannels {
            joint: j,
            metres_per_unit,
            parent: base * metres_per_unit,
            pos,
            rot: [rot[0].0, rot[1].0, rot[2].0],
            axes: [rot[0].1, rot[1].1, rot[2].1],
        })
    }

    /// The root's world position (metres) in a frame row: a position channel
    /// replaces its joint's OFFSET, so it is the parent's position plus the channels.
    fn position(&self, row: &[f64]) -> Vector3<f64> {
        let p = Vector3::new(row[self.pos[0]], row[self.pos[1]], row[self.pos[2]]);
        self.parent + p * self.metres_per_unit
    }

    /// Moves the frames (rows of `nch` values, degrees and file units) by `t`:
    /// root position p ↦ t(p), rotation R ↦ R_y(turn)·R written back as
    /// Euler angles continuous along the rows.
    pub fn transform_rows(&self, values: &mut [f64], nch: usize, t: &Planar) {
        let q_turn = t.rotation();
        let mut prev: Option<([f64; 3], [f64; 3])> = None; // (original, written) radians
        for row in values.chunks_mut(nch) {
            let p = t.apply(&self.position(row));
            let local = (p - self.parent) / self.metres_per_unit;
            for k in 0..3 {
                row[self.pos[k]] = local[k];
            }
            let e: [f64; 3] = std::array::from_fn(|k| row[self.rot[k]].to_radians());
            let near = match prev {
                None => e,
                Some((orig, written)) => std::array::from_fn(|k| written[k] + e[k] - orig[k]),
            };
            let x = to_euler_near(self.axes, &(q_turn * from_euler(self.axes, e)), near);
            for k in 0..3 {
                row[self.rot[k]] = x[k].to_degrees();
            }
            prev = Some((e, x));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fit_recovers_a_ground_plane_motion() {
        let b: Vec<Vector3<f64>> = (0..12)
            .map(|k| {
                let k = k as f64;
                Vector3::new(k.sin(), 0.1 * k, (1.7 * k).cos() + 0.3 * k)
            })
            .collect();
        let t = Planar {
            turn: 2.4,
            x: 1.5,
            z: -0.7,
        };
        let a: Vec<Vector3<f64>> = b.iter().map(|p| t.apply(p)).collect();
        let f = fit(&a, &b);
        assert!((f.turn - t.turn).abs() < 1e-12, "{f:?}");
        assert!((f.x - t.x).abs() < 1e-12 && (f.z - t.z).abs() < 1e-12);
        assert!(rms_after(&a, &b, &f) < 1e-12);
        // a cloud that is not a rigid copy keeps a positive distance
        let mut c = a.clone();
        c[3].y += 0.5;
        assert!(rms_after(&c, &b, &fit(&c, &b)) > 0.1);
    }

    #[test]
    fn composition_applies_the_inner_motion_first() {
        let s = Planar {
            turn: 0.3,
            x: 1.0,
            z: 2.0,
        };
        let o = Planar {
            turn: -1.1,
            x: -0.5,
            z: 0.25,
        };
        let p = Vector3::new(0.4, 1.0, -2.0);
        let c = s.then_after(&o);
        assert!((c.apply(&p) - s.apply(&o.apply(&p))).norm() < 1e-12);
    }
}
