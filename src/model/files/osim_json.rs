//! OpenSim joints and functions in the JSON of the reference samples
//! (`data/opensim/*_samples.json`, written by `scripts/opensim_refs.py`).

use crate::lie::Se3;
use crate::model::joint::Limit;
use crate::model::joints::function_based::{body_fixed_xyz, coordinate_index};
use crate::model::joints::{FunctionJoint, FunctionJointError, ScalarFunction, TransformAxis};
use crate::spline::SimmSpline;
use nalgebra::{Matrix4, Vector3};
use serde_json::Value;

fn err<T>(msg: impl Into<String>) -> Result<T, FunctionJointError> {
    Err(FunctionJointError(format!(
        "function-based joint: {}",
        msg.into()
    )))
}

impl FunctionJoint {
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
        joint.set_coordinate_info(
            coords.iter().map(|c| c.1).collect(),
            coords.iter().map(|c| c.2).collect(),
        );
        Ok(joint)
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
pub fn function_from_json(f: &Value) -> Result<ScalarFunction, FunctionJointError> {
    let ty = f.get("type").and_then(Value::as_str).unwrap_or("");
    match ty {
        "Constant" => Ok(ScalarFunction::Constant {
            value: f
                .get("value")
                .and_then(Value::as_f64)
                .ok_or_else(|| FunctionJointError("Constant needs a numeric `value`".into()))?,
        }),
        "LinearFunction" => {
            let c = f64s(f.get("coefficients"))
                .filter(|c| c.len() == 2)
                .ok_or_else(|| {
                    FunctionJointError(
                        "LinearFunction needs `coefficients` [slope, intercept]".into(),
                    )
                })?;
            Ok(ScalarFunction::Linear {
                slope: c[0],
                intercept: c[1],
            })
        }
        "SimmSpline" => {
            let x = f64s(f.get("x"))
                .ok_or_else(|| FunctionJointError("SimmSpline needs numeric `x`".into()))?;
            let y = f64s(f.get("y"))
                .ok_or_else(|| FunctionJointError("SimmSpline needs numeric `y`".into()))?;
            Ok(ScalarFunction::SimmSpline(
                SimmSpline::new(x, y).map_err(|e| FunctionJointError(e.to_string()))?,
            ))
        }
        "PolynomialFunction" => Ok(ScalarFunction::Polynomial {
            coefficients: f64s(f.get("coefficients")).ok_or_else(|| {
                FunctionJointError("PolynomialFunction needs `coefficients`".into())
            })?,
        }),
        "MultiplierFunction" => {
            let scale = f
                .get("scale")
                .and_then(Value::as_f64)
                .ok_or_else(|| FunctionJointError("MultiplierFunction needs `scale`".into()))?;
            let inner = function_from_json(f.get("function").ok_or_else(|| {
                FunctionJointError("MultiplierFunction needs `function`".into())
            })?)?;
            Ok(ScalarFunction::Multiplier {
                scale,
                function: Box::new(inner),
            })
        }
        other => Err(FunctionJointError(format!(
            "function type '{other}' is not supported (use Constant, LinearFunction, SimmSpline, PolynomialFunction or MultiplierFunction)"
        ))),
    }
}
