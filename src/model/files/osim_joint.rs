//! Reading an OpenSim `CustomJoint` from `.osim` XML (OpenSim 4 layout:
//! `coordinates/Coordinate`, `frames/PhysicalOffsetFrame`,
//! `SpatialTransform/TransformAxis`).

use crate::lie::Se3;
use crate::model::joint::Limit;
use crate::model::joints::function_based::{
    FunctionJoint, FunctionJointError, TransformAxis, body_fixed_xyz, coordinate_index,
};
use crate::model::joints::scalar_function::ScalarFunction;
use crate::spline::{GcvSpline, SimmSpline};
use nalgebra::Vector3;
use roxmltree::{Document, Node};

fn e<T>(m: impl Into<String>) -> Result<T, FunctionJointError> {
    Err(FunctionJointError(m.into()))
}

fn child<'a, 'i>(n: Node<'a, 'i>, tag: &str) -> Option<Node<'a, 'i>> {
    n.children()
        .find(|c| c.is_element() && c.tag_name().name() == tag)
}

fn text<'a>(n: Node<'a, '_>, tag: &str) -> Option<&'a str> {
    child(n, tag).map(|c| c.text().unwrap_or(""))
}

fn nums(s: &str) -> Result<Vec<f64>, FunctionJointError> {
    s.split_whitespace()
        .map(|t| {
            t.parse::<f64>()
                .map_err(|_| FunctionJointError(format!("'{t}' is not a number")))
        })
        .collect()
}

fn vec3(n: Node, tag: &str) -> Result<Vector3<f64>, FunctionJointError> {
    let v = nums(text(n, tag).unwrap_or("0 0 0"))?;
    if v.len() != 3 {
        return e(format!("<{tag}> must hold 3 numbers"));
    }
    Ok(Vector3::new(v[0], v[1], v[2]))
}

pub(crate) fn custom_joint_from_xml(
    xml: &str,
    joint_name: &str,
) -> Result<FunctionJoint, FunctionJointError> {
    let doc =
        Document::parse(xml).map_err(|er| FunctionJointError(format!("invalid XML: {er}")))?;
    let Some(j) = doc
        .descendants()
        .find(|n| n.has_tag_name("CustomJoint") && n.attribute("name") == Some(joint_name))
    else {
        let names: Vec<&str> = doc
            .descendants()
            .filter(|n| n.has_tag_name("CustomJoint"))
            .filter_map(|n| n.attribute("name"))
            .collect();
        return e(format!(
            "no CustomJoint named '{joint_name}' in the model; it has: {}",
            names.join(", ")
        ));
    };
    let mut names = Vec::new();
    let mut limits = Vec::new();
    let mut defaults = Vec::new();
    if let Some(cs) = child(j, "coordinates") {
        for c in cs.children().filter(|c| c.has_tag_name("Coordinate")) {
            names.push(c.attribute("name").unwrap_or("q").to_string());
            let r = nums(text(c, "range").unwrap_or(""))?;
            limits.push(if r.len() == 2 {
                Limit {
                    lower: r[0],
                    upper: r[1],
                }
            } else {
                Limit::NONE
            });
            defaults.push(
                nums(text(c, "default_value").unwrap_or("0"))?
                    .first()
                    .copied()
                    .unwrap_or(0.0),
            );
        }
    }
    // offset frames owned by the joint, by name
    let frame = |socket: &str| -> Result<Se3, FunctionJointError> {
        let Some(sock) = text(j, socket) else {
            return Ok(Se3::identity());
        };
        let sock = sock.trim();
        let owned = child(j, "frames").and_then(|fs| {
            fs.children().find(|f| {
                f.has_tag_name("PhysicalOffsetFrame")
                    && f.attribute("name") == Some(sock.rsplit('/').next().unwrap_or(sock))
            })
        });
        match owned {
            Some(f) => {
                let o = vec3(f, "orientation")?;
                Ok(Se3::new(
                    body_fixed_xyz([o.x, o.y, o.z]),
                    vec3(f, "translation")?,
                ))
            }
            None => Ok(Se3::identity()), // the socket names a body directly
        }
    };
    let parent = frame("socket_parent_frame")?;
    let childf = frame("socket_child_frame")?;
    let Some(st) = child(j, "SpatialTransform") else {
        return e(format!(
            "CustomJoint '{joint_name}' has no SpatialTransform"
        ));
    };
    let mut axes = Vec::new();
    for ta in st.children().filter(|c| c.has_tag_name("TransformAxis")) {
        let label = ta.attribute("name").unwrap_or("?").to_string();
        let cnames: Vec<String> = text(ta, "coordinates")
            .unwrap_or("")
            .split_whitespace()
            .map(str::to_string)
            .collect();
        let coordinate = coordinate_index(&names, &cnames, &label)?;
        let axis = vec3(ta, "axis")?;
        let fnode = ta
            .children()
            .find(|c| c.is_element() && !matches!(c.tag_name().name(), "coordinates" | "axis"))
            .ok_or_else(|| FunctionJointError(format!("transform axis {label} has no function")))?;
        let function = function_from_xml(fnode)
            .map_err(|m| FunctionJointError(format!("transform axis {label}: {}", m.0)))?;
        axes.push(TransformAxis {
            axis,
            coordinate,
            function,
        });
    }
    if axes.len() != 6 {
        return e(format!(
            "CustomJoint '{joint_name}' has {} transform axes; expected 6",
            axes.len()
        ));
    }
    let mut it = axes.into_iter();
    let mut next = || {
        it.next()
            .ok_or_else(|| FunctionJointError("missing transform axis".into()))
    };
    let rot = [next()?, next()?, next()?];
    let tr = [next()?, next()?, next()?];
    let mut joint = FunctionJoint::new(joint_name, names, rot, tr, parent, childf)?;
    joint.set_coordinate_info(limits, defaults);
    Ok(joint)
}

/// OpenSim's `GCVSpline`: `half_order` (default 3, quintic), `x`, `y` and
/// `error_variance`. OpenSim recomputes its coefficients from the points when
/// it loads (a written `coefficients` element is not read); with
/// `error_variance` 0 the spline interpolates and mx builds the same one.
fn gcv_spline(n: Node) -> Result<ScalarFunction, FunctionJointError> {
    let one = |tag: &str, default: &str| -> Result<f64, FunctionJointError> {
        match nums(text(n, tag).unwrap_or(default))?.as_slice() {
            [v] => Ok(*v),
            _ => e(format!("GCVSpline <{tag}> must hold one number")),
        }
    };
    let half = one("half_order", "3")?;
    if half.fract() != 0.0 || half < 1.0 {
        return e(format!(
            "GCVSpline <half_order> is {half}; expected 1, 2 or 3"
        ));
    }
    let variance = one("error_variance", "0")?;
    if variance != 0.0 {
        return e(format!(
            "GCVSpline with <error_variance> {variance} is a smoothing spline, whose smoothing mx does not \
             reproduce; mx reads interpolating GCVSplines (error_variance 0)"
        ));
    }
    let x = nums(text(n, "x").unwrap_or(""))?;
    let y = nums(text(n, "y").unwrap_or(""))?;
    Ok(ScalarFunction::GcvSpline(
        GcvSpline::new(half as usize, x, y).map_err(|m| FunctionJointError(m.to_string()))?,
    ))
}

/// An OpenSim `Function` element (Constant, LinearFunction, SimmSpline,
/// NaturalCubicSpline, GCVSpline, PiecewiseLinearFunction, PolynomialFunction,
/// MultiplierFunction); functions of several variables are a clear error.
pub(crate) fn function_from_xml(n: Node) -> Result<ScalarFunction, FunctionJointError> {
    match n.tag_name().name() {
        // OpenSim 3.x wraps the function: <function><LinearFunction>…</LinearFunction></function>
        "function" => match n.children().find(|c| c.is_element()) {
            Some(inner) => function_from_xml(inner),
            None => e("<function> holds no function"),
        },
        "Constant" => Ok(ScalarFunction::Constant {
            value: nums(text(n, "value").unwrap_or("0"))?
                .first()
                .copied()
                .unwrap_or(0.0),
        }),
        "LinearFunction" => {
            let c = nums(text(n, "coefficients").unwrap_or(""))?;
            if c.len() != 2 {
                return e("LinearFunction needs 2 coefficients (slope, intercept)");
            }
            Ok(ScalarFunction::Linear {
                slope: c[0],
                intercept: c[1],
            })
        }
        "SimmSpline" => {
            let x = nums(text(n, "x").unwrap_or(""))?;
            let y = nums(text(n, "y").unwrap_or(""))?;
            Ok(ScalarFunction::SimmSpline(
                SimmSpline::new(x, y).map_err(|m| FunctionJointError(m.to_string()))?,
            ))
        }
        "NaturalCubicSpline" => {
            let x = nums(text(n, "x").unwrap_or(""))?;
            let y = nums(text(n, "y").unwrap_or(""))?;
            Ok(ScalarFunction::SimmSpline(
                SimmSpline::natural(x, y).map_err(|m| FunctionJointError(m.to_string()))?,
            ))
        }
        "PiecewiseLinearFunction" => {
            let x = nums(text(n, "x").unwrap_or(""))?;
            let y = nums(text(n, "y").unwrap_or(""))?;
            ScalarFunction::piecewise_linear(x, y)
        }
        "GCVSpline" => gcv_spline(n),
        "MultivariatePolynomialFunction" => e(
            "MultivariatePolynomialFunction is a function of several coordinates; mx reads functions of one",
        ),
        "PolynomialFunction" => Ok(ScalarFunction::Polynomial {
            coefficients: nums(text(n, "coefficients").unwrap_or(""))?,
        }),
        "MultiplierFunction" => {
            let scale = nums(text(n, "scale").unwrap_or("1"))?
                .first()
                .copied()
                .unwrap_or(1.0);
            let inner = child(n, "function")
                .and_then(|f| f.children().find(|c| c.is_element()))
                .ok_or_else(|| {
                    FunctionJointError("MultiplierFunction has no inner function".into())
                })?;
            Ok(ScalarFunction::Multiplier {
                scale,
                function: Box::new(function_from_xml(inner)?),
            })
        }
        other => e(format!(
            "function type '{other}' is not supported (Constant, LinearFunction, SimmSpline, NaturalCubicSpline, \
             GCVSpline, PiecewiseLinearFunction, PolynomialFunction, MultiplierFunction are)"
        )),
    }
}

impl FunctionJoint {
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
        custom_joint_from_xml(xml, joint_name)
    }
}

impl ScalarFunction {
    /// One OpenSim `Function` element as XML text (`<SimmSpline>…</SimmSpline>`,
    /// `<GCVSpline>…</GCVSpline>`, …), as a CustomJoint's transform axis reads it.
    pub fn from_osim_xml(xml: &str) -> Result<ScalarFunction, FunctionJointError> {
        let doc =
            Document::parse(xml).map_err(|er| FunctionJointError(format!("invalid XML: {er}")))?;
        function_from_xml(doc.root_element())
    }
}
