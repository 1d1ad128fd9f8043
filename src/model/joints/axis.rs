//! The one-axis joints: revolute (rotation by q about a fixed unit axis through
//! the joint origin) and prismatic (translation by q along a fixed unit axis).
//! They differ only in the [`AxisMotion`] of their [`JointAxis`], so one generic
//! type serves both; [`Revolute`] and [`Prismatic`] name its two instances.

use crate::lie::Twist;
use crate::model::joint::{AxisMotion, Derivatives, Joint, JointAxis, JointKinematics, Limit};
use nalgebra::{Unit, Vector3};
use std::marker::PhantomData;

/// Which motion an [`AxisJoint`] makes, fixed by its type.
pub trait AxisKind: Clone + std::fmt::Debug + Send + Sync + 'static {
    const MOTION: AxisMotion;
    /// The joint's [`Joint::kind`].
    const KIND: &'static str;
}

/// Marker: the joint rotates about its axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rotation;
/// Marker: the joint slides along its axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Translation;

impl AxisKind for Rotation {
    const MOTION: AxisMotion = AxisMotion::Rotation;
    const KIND: &'static str = "revolute";
}

impl AxisKind for Translation {
    const MOTION: AxisMotion = AxisMotion::Translation;
    const KIND: &'static str = "prismatic";
}

/// A joint of one coordinate moving along or about a fixed unit axis.
#[derive(Clone, Debug)]
pub struct AxisJoint<K: AxisKind> {
    axis: JointAxis,
    limit: Limit,
    kind: PhantomData<K>,
}

/// Rotation by q about a fixed unit axis through the joint origin.
pub type Revolute = AxisJoint<Rotation>;
/// Translation by q along a fixed unit axis.
pub type Prismatic = AxisJoint<Translation>;

impl<K: AxisKind> AxisJoint<K> {
    /// A joint about (revolute) or along (prismatic) `axis`, normalised here.
    /// `None` for a zero or non-finite axis.
    pub fn new(axis: Vector3<f64>) -> Option<Self> {
        if !axis.iter().all(|x| x.is_finite()) {
            return None;
        }
        Unit::try_new(axis, 1e-12).map(|axis| AxisJoint {
            axis: JointAxis::new(K::MOTION, axis),
            limit: Limit::NONE,
            kind: PhantomData,
        })
    }

    pub fn with_limit(mut self, limit: Limit) -> Self {
        self.limit = limit;
        self
    }

    pub fn axis(&self) -> Vector3<f64> {
        self.axis.axis()
    }
}

impl<K: AxisKind> Joint for AxisJoint<K> {
    fn kind(&self) -> &'static str {
        K::KIND
    }

    fn dof(&self) -> usize {
        1
    }

    fn kinematics(&self, q: &[f64], want: Derivatives, out: &mut JointKinematics) {
        out.transform = self.axis.transform(q[0]);
        if want >= Derivatives::Jacobian {
            out.s[0] = self.axis.twist();
        }
        if want >= Derivatives::Hessian {
            out.ds[0][0] = Twist::zeros();
        }
    }

    fn limits(&self) -> Vec<Limit> {
        vec![self.limit]
    }

    fn constant_jacobian(&self) -> bool {
        true
    }

    fn joint_axis(&self) -> Option<JointAxis> {
        Some(self.axis)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_two_kinds_share_everything_but_the_motion() {
        let r = Revolute::new(Vector3::new(0.0, 0.0, 2.0)).unwrap();
        let p = Prismatic::new(Vector3::new(0.0, 0.0, 2.0)).unwrap();
        assert_eq!((r.kind(), p.kind()), ("revolute", "prismatic"));
        assert_eq!(r.axis(), Vector3::z());
        let (mut kr, mut kp) = (JointKinematics::default(), JointKinematics::default());
        r.kinematics(&[0.5], Derivatives::Jacobian, &mut kr);
        p.kinematics(&[0.5], Derivatives::Jacobian, &mut kp);
        assert_eq!(kr.s[0], Twist::new(0.0, 0.0, 1.0, 0.0, 0.0, 0.0));
        assert_eq!(kp.s[0], Twist::new(0.0, 0.0, 0.0, 0.0, 0.0, 1.0));
        assert!((kp.transform.p - Vector3::new(0.0, 0.0, 0.5)).norm() < 1e-15);
        assert!(Revolute::new(Vector3::zeros()).is_none());
        assert!(Prismatic::new(Vector3::new(f64::NAN, 0.0, 1.0)).is_none());
    }
}
