//! Joint built-ins (issue 3 §5): joint constructors, `transform`, `jacobian`,
//! `load_samples`, `fit_spline_joint`, `joint_error`, OpenSim joints.
//!
//! Joints are `JointValue` host objects (`lang::host::joint`, type name
//! "Joint") holding an `Arc<dyn Joint>`; other domains take them with
//! `args.joint("joint")`.

use std::sync::Arc;

use indexmap::IndexMap;
use nalgebra::Vector3;

use crate::lang::args::{ArgValue, Args};
use crate::lang::diagnostics::{ErrorKind, MxError, MxResult};
use crate::lang::host::joint::{JointValue, SamplesValue, matrix_value, numbers};
use crate::lang::registry::Registry;
use crate::lang::topic::Topic;
use crate::lang::value::Value;
use crate::lie::Se3;
use crate::model::joint::{Derivatives, Joint, JointKinematics};
use crate::model::joint_fit::{FitOptions, KnotPlacement, fit_spline_joint, fit_spline_joint_auto};
use crate::model::joints::*;

fn value_error(a: &Args, at: &ArgValue, msg: impl Into<String>) -> MxError {
    MxError::value(msg)
        .at(at.span)
        .help(format!("usage: {}", a.signature()))
}

/// A joint-library error as a diagnostic on the call.
fn spec(a: &Args, e: impl std::fmt::Display) -> MxError {
    a.error(ErrorKind::Value, e.to_string())
}

fn vec3(a: &mut Args, name: &str) -> MxResult<Vector3<f64>> {
    let arg = a.arg(name)?;
    vec3_of(a, name, &arg)
}

fn vec3_of(a: &Args, name: &str, arg: &ArgValue) -> MxResult<Vector3<f64>> {
    a.vec3_of(name, arg, "a list of 3 finite numbers such as [0, 0, 1]")
}

fn vec3_or(a: &mut Args, name: &str, default: Vector3<f64>) -> MxResult<Vector3<f64>> {
    match a.opt(name) {
        Some(arg) => vec3_of(a, name, &arg),
        None => Ok(default),
    }
}

fn transform_of(a: &Args, name: &str, arg: &ArgValue) -> MxResult<Se3> {
    a.transform_of(name, arg)
}

fn joint_arg(a: &mut Args, name: &str) -> MxResult<Arc<dyn Joint>> {
    a.joint(name)
}

/// q as a number (1-DOF) or a list of numbers, checked against the joint.
fn coords(a: &mut Args, joint: &dyn Joint) -> MxResult<Vec<f64>> {
    let arg = a.arg("q")?;
    let q: Vec<f64> = match &arg.value {
        Value::Number(x) => vec![*x],
        Value::List(l) => match l.iter().map(Value::as_number).collect::<Option<Vec<f64>>>() {
            Some(v) => v,
            None => return Err(a.type_error("q", "a number or a list of numbers", &arg)),
        },
        _ => return Err(a.type_error("q", "a number or a list of numbers", &arg)),
    };
    if q.len() != joint.dof() {
        return Err(value_error(
            a,
            &arg,
            format!(
                "this {} joint has {} coordinate(s), but q has {}",
                joint.kind(),
                joint.dof(),
                q.len()
            ),
        ));
    }
    if let Some(x) = q.iter().find(|x| !x.is_finite()) {
        return Err(value_error(a, &arg, format!("q must be finite, found {x}")));
    }
    Ok(q)
}

fn twist_value(t: &crate::lie::Twist) -> Value {
    numbers(t.as_slice())
}

fn euler_order(a: &mut Args, default: EulerOrder) -> MxResult<EulerOrder> {
    match a.opt("order") {
        Some(arg) => match &arg.value {
            Value::Str(s) => EulerOrder::parse(s).map_err(|e| value_error(a, &arg, e.to_string())),
            _ => Err(a.type_error("order", "a string such as \"zyx\"", &arg)),
        },
        None => Ok(default),
    }
}

/// The joint built-ins, by topic.
pub fn register(reg: &mut Registry) {
    constructors(reg);
    evaluation(reg);
    design(reg);
}

/// The joint constructors: `revolute` … `opensim_joint`.
fn constructors(reg: &mut Registry) {
    reg.topic(Topic::Joints);
    // ---- constructors ----
    reg.add(
        "revolute(axis)",
        "A revolute joint: rotation by q about `axis` (e.g. [0, 0, 1]) through the origin.",
        |a, _| {
            let ax = vec3(a, "axis")?;
            let j = Revolute::new(ax)
                .ok_or_else(|| a.error(ErrorKind::Value, "revolute axis must be non-zero"))?;
            Ok(Value::object(JointValue::new(j)))
        },
    );
    reg.add(
        "prismatic(axis)",
        "A prismatic joint: translation by q (metres) along `axis`.",
        |a, _| {
            let ax = vec3(a, "axis")?;
            let j = Prismatic::new(ax)
                .ok_or_else(|| a.error(ErrorKind::Value, "prismatic axis must be non-zero"))?;
            Ok(Value::object(JointValue::new(j)))
        },
    );
    reg.add("helical(axis, pitch)", "A screw joint: rotation q about `axis` with translation pitch·q along it (metres per radian).", |a, _| {
        let ax = vec3(a, "axis")?;
        let pitch = a.finite("pitch")?;
        Ok(Value::object(JointValue::new(Helical::new(ax, pitch).map_err(|e| spec(a, e))?)))
    });
    reg.add(
        "cylindrical(axis)",
        "A cylindrical joint: q = [angle about axis, slide along axis].",
        |a, _| {
            let ax = vec3(a, "axis")?;
            Ok(Value::object(JointValue::new(
                Cylindrical::new(ax).map_err(|e| spec(a, e))?,
            )))
        },
    );
    reg.add(
        "universal(axis1, axis2)",
        "A universal joint: rotation q0 about axis1, then q1 about axis2 (not parallel).",
        |a, _| {
            let a0 = vec3(a, "axis1")?;
            let a1 = vec3(a, "axis2")?;
            Ok(Value::object(JointValue::new(
                Universal::new(a0, a1).map_err(|e| spec(a, e))?,
            )))
        },
    );
    reg.add(
        "spherical(order: \"zyx\")",
        "A ball joint in body-fixed Euler angles (order e.g. \"zyx\", \"zxy\", \"zxz\"); gimbal lock at q1 = ±π/2 (q1 = 0, π for orders like \"zxz\").",
        |a, _| {
            let o = euler_order(a, EulerOrder::ZYX)?;
            Ok(Value::object(JointValue::new(Spherical::new(o))))
        },
    );
    reg.add(
        "planar(normal: [0, 0, 1], x_axis: [1, 0, 0])",
        "A planar joint: q = [x, y, angle] in the plane with that normal.",
        |a, _| {
            let n = vec3_or(a, "normal", Vector3::z())?;
            let x = vec3_or(
                a,
                "x_axis",
                if n.cross(&Vector3::x()).norm() > 1e-6 {
                    Vector3::x()
                } else {
                    Vector3::y()
                },
            )?;
            Ok(Value::object(JointValue::new(
                Planar::new(n, x).map_err(|e| spec(a, e))?,
            )))
        },
    );
    reg.add(
        "fixed(transform)",
        "A weld: a constant 4×4 transform (identity when omitted).",
        |a, _| {
            let t = match a.opt("transform") {
                Some(arg) => transform_of(a, "transform", &arg)?,
                None => Se3::identity(),
            };
            Ok(Value::object(JointValue::new(Fixed::new(t))))
        },
    );
    reg.add(
        "root6(order: \"zxy\")",
        "A 6-DOF root joint: q = [tx, ty, tz, r1, r2, r3], translations then body-fixed Euler rotations in `order` (BVH uses \"zxy\").",
        |a, _| {
            let o = euler_order(a, EulerOrder::ZXY)?;
            Ok(Value::object(JointValue::new(Root6::new(o))))
        },
    );
    reg.add("elliptic(a, b)", "An elliptic joint (spline-joint paper eq. 17): the child slides along the ellipse with semi-axes a, b, staying tangent.", |a, _| {
        let x = a.finite("a")?;
        let y = a.finite("b")?;
        Ok(Value::object(JointValue::new(Elliptic::new(x, y).map_err(|e| spec(a, e))?)))
    });
    reg.add(
        "spline_joint(frames, knots)",
        "A 1-DOF spline curve joint through control frames (a list of 4×4 matrices), cumulative cubic B-spline on SE(3). `knots`: one value per frame, the frames − 2 breakpoints of a clamped cubic, or a full knot vector (frames + 4); when omitted, natural knots from 0 (step ‖log(G⁻¹G')‖).",
        |a, _| {
            let farg = a.arg("frames")?;
            let Some(list) = farg.value.as_list() else {
                return Err(a.type_error("frames", "a list of 4×4 matrices", &farg));
            };
            let mut frames = Vec::with_capacity(list.len());
            for f in list.iter() {
                let av = ArgValue { value: f.clone(), span: farg.span, name: None };
                frames.push(transform_of(a, "frames", &av)?);
            }
            let knots = match a.opt("knots") {
                Some(k) => match k.value.as_list().and_then(|l| l.iter().map(Value::as_number).collect::<Option<Vec<f64>>>()) {
                    Some(v) => v,
                    None => return Err(a.type_error("knots", "a list of numbers", &k)),
                },
                None => curve::natural_parameters(&frames, 0.0),
            };
            let j = SplineCurveJoint::from_knots(frames, &knots).map_err(|e| spec(a, e))?;
            Ok(Value::object(JointValue::curve(j)))
        },
    );
    reg.add(
        "opensim_joint(path, name)",
        "The CustomJoint `name` of an OpenSim model (.osim), exactly (SimmSpline, LinearFunction, Constant, offset frames); or, for a samples .json, its `joint`.",
        |a, ev| {
            let parg = a.arg("path")?;
            let Value::Str(path) = &parg.value else { return Err(a.type_error("path", "a file name string", &parg)) };
            let p = ev.resolve_path(path, parg.span)?;
            let is_json = path.to_ascii_lowercase().ends_with(".json");
            let name = if is_json {
                a.opt("name").and_then(|v| v.value.as_str_opt())
            } else {
                Some(a.string("name")?.to_string())
            };
            let j = if is_json {
                let text = std::fs::read_to_string(&p).map_err(|e| MxError::new(ErrorKind::Io, format!("cannot read {path}: {e}")).at(parg.span))?;
                let v: serde_json::Value = serde_json::from_str(&text).map_err(|e| MxError::new(ErrorKind::Io, format!("{path} is not JSON: {e}")).at(parg.span))?;
                let _ = name;
                FunctionJoint::from_opensim_samples_json(&v)
            } else {
                FunctionJoint::from_osim_file(&p, name.as_deref().unwrap_or(""))
            };
            Ok(Value::object(JointValue::new(j.map_err(|e| spec(a, e))?)))
        },
    );
}

/// Evaluating a joint: `transform`, `jacobian`, `hessian`.
fn evaluation(reg: &mut Registry) {
    reg.topic(Topic::Joints);
    reg.add(
        "transform(joint, q)",
        "The joint's 4×4 transform G(q) as a list of rows (q a number or a list).",
        |a, _| {
            let j = joint_arg(a, "joint")?;
            let q = coords(a, j.as_ref())?;
            let mut k = JointKinematics::default();
            j.kinematics(&q, Derivatives::Transform, &mut k);
            Ok(matrix_value(&k.transform))
        },
    );
    reg.add(
        "jacobian(joint, q)",
        "The body-frame Jacobian S(q): one twist [ω; v] (6 numbers) per coordinate.",
        |a, _| {
            let j = joint_arg(a, "joint")?;
            let q = coords(a, j.as_ref())?;
            let mut k = JointKinematics::default();
            j.kinematics(&q, Derivatives::Jacobian, &mut k);
            Ok(Value::list(
                k.s[..j.dof()].iter().map(twist_value).collect(),
            ))
        },
    );
    reg.add(
        "hessian(joint, q)",
        "The joint Hessian: rows i, columns k hold ∂s_i/∂q_k (twists of 6 numbers).",
        |a, _| {
            let j = joint_arg(a, "joint")?;
            let q = coords(a, j.as_ref())?;
            let mut k = JointKinematics::default();
            j.kinematics(&q, Derivatives::Hessian, &mut k);
            let n = j.dof();
            Ok(Value::list(
                (0..n)
                    .map(|i| Value::list(k.ds[i][..n].iter().map(twist_value).collect()))
                    .collect(),
            ))
        },
    );
}

/// Designing spline joints from samples: `load_samples`, `fit_spline_joint`, `joint_error`.
fn design(reg: &mut Registry) {
    reg.topic(Topic::Joints);
    reg.add(
        "load_samples(path)",
        "Joint samples (q and the 4×4 T_parent_child) from a JSON file in the layout of OpenSim's *_samples.json.",
        |a, ev| {
            let parg = a.arg("path")?;
            let Value::Str(path) = &parg.value else { return Err(a.type_error("path", "a file name string", &parg)) };
            let p = ev.resolve_path(path, parg.span)?;
            let s = JointSamples::load(&p).map_err(|e| MxError::new(ErrorKind::Io, e.to_string()).at(parg.span))?;
            Ok(Value::object(SamplesValue(Arc::new(s))))
        },
    );
    reg.add(
        "fit_spline_joint(samples, frames: 8, smooth: \"auto\", knots: \"uniform\")",
        "Fit a cubic spline curve joint with `frames` control frames to samples (paper §6.2). `smooth` trades data fit for a smaller joint Hessian (§6.3): \"auto\" (default) picks the weight of least generalised cross-validation score (w = 0 and 1e-6…1e-2, refined between decades), a number w in [0, 1) sets it (0 fits the data only). The weight used is the joint's `.smooth`. knots \"uniform\" or \"natural\".",
        |a, _| {
            let s = a.object::<SamplesValue>("samples", "joint samples (from load_samples)")?.0.clone();
            let farg = a.opt("frames");
            let frames = match &farg {
                Some(f) => match f.value.as_number() {
                    Some(x) if x >= 4.0 && x.fract() == 0.0 && x <= 10_000.0 => x as usize,
                    _ => return Err(value_error(a, f, "`frames` must be a whole number ≥ 4")),
                },
                None => 8,
            };
            // `smooth: "auto"` (None, the default): the weight of least generalised cross-validation score.
            let smooth = match a.opt("smooth") {
                Some(v) if v.value.as_str_opt().as_deref() == Some("auto") => None,
                Some(v) => match v.value.as_number() {
                    Some(x) => Some(x),
                    None => return Err(value_error(a, &v, "`smooth` must be a number in [0, 1) or \"auto\"")),
                },
                None => None,
            };
            let knots = match a.opt("knots") {
                Some(k) => match k.value.as_str_opt().as_deref() {
                    Some("uniform") => KnotPlacement::Uniform,
                    Some("natural") => KnotPlacement::Natural,
                    _ => return Err(value_error(a, &k, "`knots` must be \"uniform\" or \"natural\"")),
                },
                None => KnotPlacement::Uniform,
            };
            let opt = FitOptions { frames, smooth: smooth.unwrap_or(0.0), knots, ..Default::default() };
            let (r, w) = match smooth {
                Some(w) => fit_spline_joint(&s, &opt).map(|r| (r, w)),
                None => fit_spline_joint_auto(&s, &opt).map(|f| (f.fit, f.weight)),
            }
            .map_err(|e| spec(a, e))?;
            Ok(Value::object(JointValue::fitted(r.joint, w)))
        },
    );
    reg.add(
        "joint_error(joint, samples)",
        "How far a 1-DOF joint is from samples: {max_mm, rms_mm, max_deg, rms_deg} (translation in mm, rotation angle of R_fit⁻¹R_ref in degrees).",
        |a, _| {
            let j = joint_arg(a, "joint")?;
            let s = a.object::<SamplesValue>("samples", "joint samples (from load_samples)")?.0.clone();
            let e = joint_error(j.as_ref(), &s).map_err(|e| spec(a, e))?;
            let mut r = IndexMap::new();
            r.insert("max_mm".to_string(), Value::Number(e.max_mm));
            r.insert("rms_mm".to_string(), Value::Number(e.rms_mm));
            r.insert("max_deg".to_string(), Value::Number(e.max_deg));
            r.insert("rms_deg".to_string(), Value::Number(e.rms_deg));
            Ok(Value::record(r))
        },
    );
}

trait StrOpt {
    fn as_str_opt(&self) -> Option<String>;
}
impl StrOpt for Value {
    fn as_str_opt(&self) -> Option<String> {
        match self {
            Value::Str(s) => Some(s.to_string()),
            _ => None,
        }
    }
}
