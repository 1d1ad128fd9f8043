//! A BVH joint's local transform from its channel values.
//!
//! BVH rotation channels are intrinsic Euler angles applied in the order they
//! are written: `CHANNELS 3 Zrotation Xrotation Yrotation` means
//! `R = Rz(z) · Rx(x) · Ry(y)` (rotate about Z, then about the new X, then the
//! new Y), and a point in the child frame maps to the parent as
//! `x_parent = T + R x_child`. `T` is the OFFSET with every position channel
//! *replacing* its component (Bandai writes the offset into its position
//! channels; adding would double every bone).

use super::{BvhJoint, Channel};
use crate::lie::Se3;
use nalgebra::{Matrix3, Rotation3, Unit};

/// The rotation of one rotation channel by `degrees`; identity for a position channel.
pub fn channel_rotation(c: Channel, degrees: f64) -> Matrix3<f64> {
    if !c.is_rotation() {
        return Matrix3::identity();
    }
    let axis = Unit::new_unchecked(c.axis_vector());
    *Rotation3::from_axis_angle(&axis, degrees.to_radians()).matrix()
}

/// The joint's transform in its parent's frame (metres), given the joint's
/// channel values (degrees and file units) and the file's metres per unit.
pub fn joint_local_transform(joint: &BvhJoint, values: &[f64], metres_per_unit: f64) -> Se3 {
    let mut p = joint.offset;
    let mut r = Matrix3::identity();
    for (c, v) in joint.channels.iter().zip(values) {
        if c.is_rotation() {
            r *= channel_rotation(*c, *v);
        } else {
            p[c.axis()] = *v;
        }
    }
    Se3::new(r, p * metres_per_unit)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    fn joint(ch: &[Channel]) -> BvhJoint {
        BvhJoint {
            name: "j".into(),
            parent: None,
            offset: Vector3::new(1.0, 2.0, 3.0),
            channels: ch.to_vec(),
            end_sites: vec![],
        }
    }

    #[test]
    fn intrinsic_order_is_file_order() {
        use Channel::*;
        let j = joint(&[Zrotation, Xrotation, Yrotation]);
        let t = joint_local_transform(&j, &[30.0, 40.0, 50.0], 1.0);
        let expect = channel_rotation(Zrotation, 30.0)
            * channel_rotation(Xrotation, 40.0)
            * channel_rotation(Yrotation, 50.0);
        assert!((t.r - expect).norm() < 1e-14);
        // A different order gives a different rotation (the order matters).
        let j2 = joint(&[Yrotation, Xrotation, Zrotation]);
        let t2 = joint_local_transform(&j2, &[50.0, 40.0, 30.0], 1.0);
        assert!((t2.r - expect).norm() > 1e-3);
        // Rotating the child x axis by 90° about Z gives the parent y axis.
        let jz = joint(&[Zrotation]);
        let tz = joint_local_transform(&jz, &[90.0], 1.0);
        assert!((tz.r * Vector3::x() - Vector3::y()).norm() < 1e-15);
    }

    #[test]
    fn position_channels_replace_the_offset() {
        use Channel::*;
        let j = joint(&[Xposition, Zposition, Zrotation]);
        let t = joint_local_transform(&j, &[10.0, 30.0, 0.0], 0.01);
        assert!((t.p - Vector3::new(0.10, 0.02, 0.30)).norm() < 1e-15);
        let none = joint(&[]);
        let t0 = joint_local_transform(&none, &[], 0.01);
        assert!((t0.p - Vector3::new(0.01, 0.02, 0.03)).norm() < 1e-15);
    }
}
