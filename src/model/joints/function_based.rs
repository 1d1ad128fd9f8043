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

use super::poe::{PoeFactor, poe_kinematics, poe_sdot_v_dq};
use super::scalar_function::ScalarFunction;
use crate::lie::{Se3, Twist};
use crate::model::joint::{Derivatives, Joint, JointKinematics, Limit, MAX_JOINT_DOF};
use crate::spline::SimmSpline;
use nalgebra::{Matrix3, Matrix4, Rotation3, Vector3};
use serde_json::Value;

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
        })
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

    /// From the `joint` object of an OpenSim samples file
    /// (`data/opensim/*_samples.json`), or from the whole file (its `joint` is used).
    /// Offset frames are read from `T_body_frame` (4×4, rows first) or else from
    /// `translation` + `orientation_body_fixed_xyz`.
    pub fn from_opensim_samples_json(v: &Value) -> Result<Self, FunctionJointError> {
        let j = match v.get("joint") {
            Some(j) if v.get("transform_axes").is_none() => j,
            _ => v,
        };
        let name = j
            .get("name")
            .and_then(Value::as_str)
            .unwrap_or("joint")
            .to_string();
        let Some(axes) = j.get("transform_axes").and_then(Value::as_array) else {
            return err(format!(
                "joint '{name}' has no `transform_axes`: this object only names the joint (as in the pendulum file); \
                 read the `joint` object of the matching *_samples.json, or use FunctionJoint::from_osim_file(path, \"{name}\")"
            ));
        };
        // coordinates: `coordinate` (one object) or `coordinates` (a list of objects or names)
        let mut coords: Vec<(String, Limit, f64)> = Vec::new();
        let mut read_coord = |c: &Value| -> Result<(), FunctionJointError> {
            if let Some(s) = c.as_str() {
                coords.push((s.to_string(), Limit::NONE, 0.0));
                return Ok(());
            }
            let Some(cname) = c.get("name").and_then(Value::as_str) else {
                return err("a coordinate has no `name`");
            };
            let limit = match c.get("range").and_then(Value::as_array) {
                Some(r) if r.len() == 2 => match (r[0].as_f64(), r[1].as_f64()) {
                    (Some(lower), Some(upper)) => Limit { lower, upper },
                    _ => return err(format!("coordinate '{cname}': `range` must be two numbers")),
                },
                _ => Limit::NONE,
            };
            let def = c
                .get("default_value")
                .and_then(Value::as_f64)
                .unwrap_or(0.0);
            coords.push((cname.to_string(), limit, def));
            Ok(())
        };
        if let Some(c) = j.get("coordinate") {
            read_coord(c)?;
        } else if let Some(cs) = j.get("coordinates").and_then(Value::as_array) {
            for c in cs {
                read_coord(c)?;
            }
        } else {
            return err(format!(
                "joint '{name}' has neither `coordinate` nor `coordinates`"
            ));
        }
        let names: Vec<String> = coords.iter().map(|c| c.0.clone()).collect();
        if axes.len() != 6 {
            return err(format!(
                "joint '{name}' has {} transform axes; a CustomJoint has 6",
                axes.len()
            ));
        }
        let mut parsed = Vec::with_capacity(6);
        for (k, a) in axes.iter().enumerate() {
            let label = a
                .get("name")
                .and_then(Value::as_str)
                .unwrap_or("?")
                .to_string();
            let axis = vec3(a.get("axis")).ok_or_else(|| {
                FunctionJointError(format!(
                    "transform axis {} ({label}): `axis` must be 3 numbers",
                    k + 1
                ))
            })?;
            let cnames: Vec<String> = match a.get("coordinates") {
                Some(Value::Array(cs)) => cs
                    .iter()
                    .filter_map(|c| c.as_str().map(str::to_string))
                    .collect(),
                Some(Value::String(s)) => s.split_whitespace().map(str::to_string).collect(),
                _ => vec![],
            };
            let coordinate = coordinate_index(&names, &cnames, &label)?;
            let f = a.get("function").ok_or_else(|| {
                FunctionJointError(format!("transform axis {label} has no `function`"))
            })?;
            let function = function_from_json(f)
                .map_err(|e| FunctionJointError(format!("transform axis {label}: {e}")))?;
            parsed.push(TransformAxis {
                axis,
                coordinate,
                function,
            });
        }
        let parent = offset_from_json(j.get("parent_offset_frame_F"))?;
        let child = offset_from_json(j.get("child_offset_frame_M"))?;
        let mut it = parsed.into_iter();
        let mut next = || {
            it.next()
                .ok_or_else(|| FunctionJointError("missing transform axis".into()))
        };
        let rotations = [next()?, next()?, next()?];
        let translations = [next()?, next()?, next()?];
        let mut joint = FunctionJoint::new(name, names, rotations, translations, parent, child)?;
        joint.limits = coords.iter().map(|c| c.1).collect();
        joint.defaults = coords.iter().map(|c| c.2).collect();
        Ok(joint)
    }

    /// From an OpenSim model file (`.osim`), the `CustomJoint` named `joint_name`.
    pub fn from_osim_file(
        path: impl AsRef<std::path::Path>,
        joint_name: &str,
    ) -> Result<Self, FunctionJointError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path)
            .map_err(|e| FunctionJointError(format!("cannot read {}: {e}", path.display())))?;
        Self::from_osim_str(&text, joint_name)
    }

    /// From OpenSim XML text, the `CustomJoint` named `joint_name`.
    pub fn from_osim_str(xml: &str, joint_name: &str) -> Result<Self, FunctionJointError> {
        super::osim::custom_joint_from_xml(xml, joint_name)
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

fn vec3(v: Option<&Value>) -> Option<Vector3<f64>> {
    let a = v?.as_array()?;
    if a.len() != 3 {
        return None;
    }
    Some(Vector3::new(a[0].as_f64()?, a[1].as_f64()?, a[2].as_f64()?))
}

fn f64s(v: Option<&Value>) -> Option<Vec<f64>> {
    v?.as_array()?.iter().map(Value::as_f64).collect()
}

fn offset_from_json(v: Option<&Value>) -> Result<Se3, FunctionJointError> {
    let Some(v) = v else {
        return Ok(Se3::identity());
    };
    if let Some(rows) = v.get("T_body_frame").and_then(Value::as_array) {
        let mut m = Matrix4::zeros();
        if rows.len() != 4 {
            return err("`T_body_frame` must be a 4×4 matrix (rows first)");
        }
        for (i, r) in rows.iter().enumerate() {
            let r = f64s(Some(r)).filter(|r| r.len() == 4).ok_or_else(|| {
                FunctionJointError("`T_body_frame` rows must be 4 numbers".into())
            })?;
            for (j, x) in r.into_iter().enumerate() {
                m[(i, j)] = x;
            }
        }
        return Ok(Se3::from_matrix(&m));
    }
    let t = vec3(v.get("translation")).unwrap_or_else(Vector3::zeros);
    let o = vec3(v.get("orientation_body_fixed_xyz")).unwrap_or_else(Vector3::zeros);
    Ok(Se3::new(body_fixed_xyz([o.x, o.y, o.z]), t))
}

/// An OpenSim function from its JSON form (`type` + parameters).
pub fn function_from_json(f: &Value) -> Result<ScalarFunction, String> {
    let ty = f.get("type").and_then(Value::as_str).unwrap_or("");
    match ty {
        "Constant" => Ok(ScalarFunction::Constant {
            value: f
                .get("value")
                .and_then(Value::as_f64)
                .ok_or("Constant needs a numeric `value`")?,
        }),
        "LinearFunction" => {
            let c = f64s(f.get("coefficients"))
                .filter(|c| c.len() == 2)
                .ok_or("LinearFunction needs `coefficients` [slope, intercept]")?;
            Ok(ScalarFunction::Linear {
                slope: c[0],
                intercept: c[1],
            })
        }
        "SimmSpline" => {
            let x = f64s(f.get("x")).ok_or("SimmSpline needs numeric `x`")?;
            let y = f64s(f.get("y")).ok_or("SimmSpline needs numeric `y`")?;
            Ok(ScalarFunction::SimmSpline(
                SimmSpline::new(x, y).map_err(|e| e.to_string())?,
            ))
        }
        "PolynomialFunction" => Ok(ScalarFunction::Polynomial {
            coefficients: f64s(f.get("coefficients"))
                .ok_or("PolynomialFunction needs `coefficients`")?,
        }),
        "MultiplierFunction" => {
            let scale = f
                .get("scale")
                .and_then(Value::as_f64)
                .ok_or("MultiplierFunction needs `scale`")?;
            let inner = function_from_json(
                f.get("function")
                    .ok_or("MultiplierFunction needs `function`")?,
            )?;
            Ok(ScalarFunction::Multiplier {
                scale,
                function: Box::new(inner),
            })
        }
        other => Err(format!(
            "function type '{other}' is not supported (use Constant, LinearFunction, SimmSpline, PolynomialFunction or MultiplierFunction)"
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
