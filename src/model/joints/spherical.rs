//! Spherical (ball) joint in Euler-angle coordinates.
//!
//! Coordinates: three body-fixed (intrinsic) angles in a chosen axis order,
//! R = R_a(q0) · R_b(q1) · R_c(q2), e.g. "zyx" (yaw, pitch, roll; the default)
//! or "zxy" (BVH). Singularities (gimbal lock), where the first and third axes
//! align and S loses rank:
//! - Tait–Bryan orders (three different axes): q1 = ±π/2 (det of the angular Jacobian = ±cos q1);
//! - proper Euler orders (first = third, e.g. "zxz"): q1 = 0 or π (det = ±sin q1).
//!
//! G, S and ∇S are finite everywhere (the product-of-exponentials recursion);
//! only the inverse map from angular velocity to q̇ blows up there.
//! [`Spherical::singularity_measure`] reports |det| so callers can detect it.

use super::error::{JointSpecError, jerr};
use super::poe::{PoeFactor, poe_kinematics, poe_sdot_v_dq};
use super::universal::rot_twist;
use crate::lie::{Se3, Twist};
use crate::model::joint::{Derivatives, Joint, JointKinematics, Limit, MAX_JOINT_DOF};
use nalgebra::{Matrix3, Vector3};

/// An Euler order: three axis indices (0 = x, 1 = y, 2 = z), consecutive ones distinct.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EulerOrder(pub [usize; 3]);

impl EulerOrder {
    pub const ZYX: EulerOrder = EulerOrder([2, 1, 0]);
    pub const ZXY: EulerOrder = EulerOrder([2, 0, 1]);
    pub const XYZ: EulerOrder = EulerOrder([0, 1, 2]);

    /// Parses "zyx", "XYZ", "zxz", …
    pub fn parse(s: &str) -> Result<Self, JointSpecError> {
        let ax: Vec<usize> = s
            .chars()
            .map(|c| match c.to_ascii_lowercase() {
                'x' => Ok(0),
                'y' => Ok(1),
                'z' => Ok(2),
                _ => jerr(format!(
                    "Euler order '{s}': use three letters from x, y, z such as \"zyx\""
                )),
            })
            .collect::<Result<_, _>>()?;
        if ax.len() != 3 || ax[0] == ax[1] || ax[1] == ax[2] {
            return jerr(format!(
                "Euler order '{s}': need three axes with no two consecutive equal, e.g. \"zyx\" or \"zxz\""
            ));
        }
        Ok(EulerOrder([ax[0], ax[1], ax[2]]))
    }

    pub fn name(&self) -> String {
        self.0.iter().map(|&i| ['x', 'y', 'z'][i]).collect()
    }

    pub(crate) fn axis(i: usize) -> Vector3<f64> {
        let mut v = Vector3::zeros();
        v[i] = 1.0;
        v
    }

    /// The three rotation factors driven by coordinates `first..first+3`.
    pub(crate) fn factors(&self, q: &[f64], first: usize) -> [PoeFactor; 3] {
        let f = |k: usize| {
            PoeFactor::of_coordinate(
                rot_twist(&Self::axis(self.0[k])),
                first + k,
                [q[first + k], 1.0, 0.0],
            )
        };
        [f(0), f(1), f(2)]
    }
}

#[derive(Clone, Debug)]
pub struct Spherical {
    order: EulerOrder,
    limits: [Limit; 3],
}

impl Spherical {
    pub fn new(order: EulerOrder) -> Self {
        Spherical {
            order,
            limits: [Limit::NONE; 3],
        }
    }
    pub fn with_limits(mut self, limits: [Limit; 3]) -> Self {
        self.limits = limits;
        self
    }
    pub fn order(&self) -> EulerOrder {
        self.order
    }

    /// |det| of the 3×3 angular part of S: 1 far from gimbal lock, 0 at it.
    pub fn singularity_measure(&self, q: &[f64]) -> f64 {
        let mut k = JointKinematics::default();
        self.kinematics(q, Derivatives::Jacobian, &mut k);
        let m = Matrix3::from_columns(&[
            k.s[0].fixed_rows::<3>(0).into_owned(),
            k.s[1].fixed_rows::<3>(0).into_owned(),
            k.s[2].fixed_rows::<3>(0).into_owned(),
        ]);
        m.determinant().abs()
    }
}

impl Default for Spherical {
    fn default() -> Self {
        Spherical::new(EulerOrder::ZYX)
    }
}

impl Joint for Spherical {
    fn kind(&self) -> &'static str {
        "spherical"
    }
    fn dof(&self) -> usize {
        3
    }
    fn coordinate_suffixes(&self) -> Vec<String> {
        self.order
            .0
            .iter()
            .map(|&i| format!("r{}", ['x', 'y', 'z'][i]))
            .collect()
    }
    fn kinematics(&self, q: &[f64], want: Derivatives, out: &mut JointKinematics) {
        poe_kinematics(
            &Se3::identity(),
            &self.order.factors(q, 0),
            None,
            3,
            want,
            out,
        );
    }
    fn sdot_v_dq(&self, q: &[f64], v: &[f64], out: &mut [Twist; MAX_JOINT_DOF]) -> bool {
        // φ linear in q: no third-derivative term of its own.
        poe_sdot_v_dq(&self.order.factors(q, 0), None, 3, v, out);
        true
    }
    fn limits(&self) -> Vec<Limit> {
        self.limits.to_vec()
    }
}
