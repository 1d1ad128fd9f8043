//! The function-based joint: six exponentials, each driven by a scalar
//! function of one coordinate — exactly an OpenSim `CustomJoint`
//! (Simbody `MobilizedBody::FunctionBased`):
//!
//!   R_F_M(q) = Rot(f1(q), a1) · Rot(f2(q), a2) · Rot(f3(q), a3)
//!   t_F_M(q) = g1(q) b1 + g2(q) b2 + g3(q) b3            (axes in F)
//!   G(q) = T_parent_F · T_F_M(q) · T_child_M⁻¹
//!
//! As a product of exponentials (translations commute and come first):
//!   G = T_parent_F · e^{[0;b1]g1} e^{[0;b2]g2} e^{[0;b3]g3} e^{[a1;0]f1} e^{[a2;0]f2} e^{[a3;0]f3} · T_child_M⁻¹
//! so the Jacobian and Hessian come from the recursion of [`super::poe`].
//!
//! Reading one from OpenSim files (`from_osim_file`, `from_osim_str`,
//! `from_opensim_samples_json`) lives with the other readers in `model::files`.

use super::poe::{PoeFactor, poe_kinematics, poe_sdot_v_dq};
use super::scalar_function::ScalarFunction;
use crate::lie::{Se3, Twist};
use crate::model::joint::{Derivatives, Joint, JointKinematics, Limit, MAX_JOINT_DOF};
use nalgebra::{Matrix3, Rotation3, Vector3};

/// One of the six transform axes.
#[derive(Debug, Clone, PartialEq)]
pub struct TransformAxis {
    /// Unit axis (in F).
    pub axis: Vector3<f64>,
    /// Index of the coordinate the function reads, or `None` for a constant.
    pub coordinate: Option<usize>,
    pub function: ScalarFunction,
}

#[derive(Debug, Clone, PartialEq)]
pub struct FunctionJoint {
    name: String,
    coordinates: Vec<String>,
    limits: Vec<Limit>,
    defaults: Vec<f64>,
    /// rotation1..3
    rotations: [TransformAxis; 3],
    /// translation1..3
    translations: [TransformAxis; 3],
    parent_offset: Se3,
    /// T_child_M⁻¹ (stored inverted: it is the tail of the product)
    child_offset_inv: Se3,
    /// T_F_M(q)⁻¹ in place of T_F_M(q) (a reversed OpenSim 3.x joint).
    reversed: bool,
}

/// Why a function-based joint could not be built (the joint library's error).
pub use super::error::JointSpecError as FunctionJointError;

fn err<T>(msg: impl Into<String>) -> Result<T, FunctionJointError> {
    Err(FunctionJointError(format!(
        "function-based joint: {}",
        msg.into()
    )))
}

/// R = Rx(a)·Ry(b)·Rz(c): OpenSim's body-fixed X-Y-Z orientation of an offset frame.
pub fn body_fixed_xyz(a: [f64; 3]) -> Matrix3<f64> {
    let rx = Rotation3::from_axis_angle(&Vector3::x_axis(), a[0]);
    let ry = Rotation3::from_axis_angle(&Vector3::y_axis(), a[1]);
    let rz = Rotation3::from_axis_angle(&Vector3::z_axis(), a[2]);
    (rx * ry * rz).into_inner()
}

impl FunctionJoint {
    /// Builds the joint from its parts. Axes are normalised; rotation and
    /// translation axes must be non-zero; coordinate indices must be < `coordinates.len()`.
    pub fn new(
        name: impl Into<String>,
        coordinates: Vec<String>,
        rotations: [TransformAxis; 3],
        translations: [TransformAxis; 3],
        parent_offset: Se3,
        child_offset: Se3,
    ) -> Result<Self, FunctionJointError> {
        let n = coordinates.len();
        if n > MAX_JOINT_DOF {
            return err(format!(
                "{n} coordinates; at most {MAX_JOINT_DOF} are supported"
            ));
        }
        let mut rotations = rotations;
        let mut translations = translations;
        for (k, ax) in rotations
            .iter_mut()
            .chain(translations.iter_mut())
            .enumerate()
        {
            let norm = ax.axis.norm();
            if !(norm.is_finite() && norm > 1e-12) {
                return err(format!(
                    "transform axis {} has a zero or non-finite direction",
                    k + 1
                ));
            }
            ax.axis /= norm;
            if let Some(i) = ax.coordinate
                && i >= n
            {
                return err(format!(
                    "transform axis {} reads coordinate {i}, but the joint has {n}",
                    k + 1
                ));
            }
        }
        Ok(FunctionJoint {
            name: name.into(),
            limits: vec![Limit::NONE; n],
            defaults: vec![0.0; n],
            coordinates,
            rotations,
            translations,
            parent_offset,
            child_offset_inv: child_offset.inverse(),
            reversed: false,
        })
    }

    /// The joint run backwards: G(q) = T_parent_F · T_F_M(q)⁻¹ · T_child_M⁻¹,
    /// the inverse being the six exponentials in reverse order with negated
    /// angles and displacements (how OpenSim 4 reads a 3.x joint marked
    /// `<reverse>true</reverse>`: the mobilizer from child to parent).
    pub fn reversed(mut self) -> Self {
        self.reversed = !self.reversed;
        self
    }

    pub fn with_limits(mut self, limits: Vec<Limit>) -> Self {
        if limits.len() == self.coordinates.len() {
            self.limits = limits;
        }
        self
    }

    pub fn name(&self) -> &str {
        &self.name
    }
    pub fn coordinate_names(&self) -> &[String] {
        &self.coordinates
    }
    pub fn default_values(&self) -> &[f64] {
        &self.defaults
    }
    pub fn parent_offset(&self) -> Se3 {
        self.parent_offset
    }
    pub fn child_offset(&self) -> Se3 {
        self.child_offset_inv.inverse()
    }

    /// The six transform-axis functions at q, in the order f1..f3, g1..g3.
    pub fn axis_values(&self, q: &[f64]) -> [f64; 6] {
        let mut v = [0.0; 6];
        for (k, ax) in self.rotations.iter().chain(&self.translations).enumerate() {
            v[k] = ax.function.eval(ax.coordinate.map_or(0.0, |i| q[i]))[0];
        }
        v
    }

    pub(crate) fn set_coordinate_info(&mut self, limits: Vec<Limit>, defaults: Vec<f64>) {
        self.limits = limits;
        self.defaults = defaults;
    }

    /// The six factors at `q`; with `v`, each also carries its third
    /// derivative contracted with the velocity (for [`poe_sdot_v_dq`]).
    fn factors(&self, q: &[f64], v: Option<&[f64]>) -> [PoeFactor; 6] {
        let mk = |ax: &TransformAxis, rot: bool| {
            let a = ax.axis;
            let tw = if rot {
                Twist::new(a.x, a.y, a.z, 0.0, 0.0, 0.0)
            } else {
                Twist::new(0.0, 0.0, 0.0, a.x, a.y, a.z)
            };
            match ax.coordinate {
                Some(i) => match v {
                    Some(v) => PoeFactor::of_coordinate3(tw, i, ax.function.eval3(q[i]), v[i]),
                    None => PoeFactor::of_coordinate(tw, i, ax.function.eval(q[i])),
                },
                None => PoeFactor::new(tw, ax.function.eval(0.0)[0]),
            }
        };
        let t = &self.translations;
        let r = &self.rotations;
        if self.reversed {
            // (e^{X1 φ1} ⋯ e^{X6 φ6})⁻¹ = e^{−X6 φ6} ⋯ e^{−X1 φ1}
            let neg = |mut f: PoeFactor| {
                f.phi = -f.phi;
                f.dphi.iter_mut().for_each(|x| *x = -*x);
                f.ddphi.iter_mut().flatten().for_each(|x| *x = -*x);
                f.dddphi_vv.iter_mut().for_each(|x| *x = -*x);
                f
            };
            return [
                neg(mk(&r[2], true)),
                neg(mk(&r[1], true)),
                neg(mk(&r[0], true)),
                neg(mk(&t[2], false)),
                neg(mk(&t[1], false)),
                neg(mk(&t[0], false)),
            ];
        }
        [
            mk(&t[0], false),
            mk(&t[1], false),
            mk(&t[2], false),
            mk(&r[0], true),
            mk(&r[1], true),
            mk(&r[2], true),
        ]
    }
}

pub(crate) fn coordinate_index(
    names: &[String],
    cnames: &[String],
    label: &str,
) -> Result<Option<usize>, FunctionJointError> {
    match cnames {
        [] => Ok(None),
        [c] => names.iter().position(|n| n == c).map(Some).ok_or_else(|| {
            FunctionJointError(format!(
                "transform axis {label} reads unknown coordinate '{c}'"
            ))
        }),
        _ => err(format!(
            "transform axis {label} is a function of {} coordinates; only functions of one coordinate are supported",
            cnames.len()
        )),
    }
}

impl Joint for FunctionJoint {
    fn kind(&self) -> &'static str {
        "function_based"
    }

    fn dof(&self) -> usize {
        self.coordinates.len()
    }

    fn coordinate_suffixes(&self) -> Vec<String> {
        if self.coordinates.len() == 1 {
            vec![String::new()]
        } else {
            self.coordinates.clone()
        }
    }

    fn kinematics(&self, q: &[f64], want: Derivatives, out: &mut JointKinematics) {
        let f = self.factors(q, None);
        poe_kinematics(
            &self.parent_offset,
            &f,
            Some(&self.child_offset_inv),
            self.dof(),
            want,
            out,
        );
    }

    fn sdot_v_dq(&self, q: &[f64], v: &[f64], out: &mut [Twist; MAX_JOINT_DOF]) -> bool {
        let f = self.factors(q, Some(v));
        poe_sdot_v_dq(&f, Some(&self.child_offset_inv), self.dof(), v, out);
        true
    }

    fn limits(&self) -> Vec<Limit> {
        self.limits.clone()
    }
}
