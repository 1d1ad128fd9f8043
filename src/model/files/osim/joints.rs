//! A joint's coordinates and its transform: a CustomJoint's SpatialTransform
//! (three rotation and three translation axes, each a function of at most one
//! coordinate) or the fixed axes of the other joint types, as the
//! `TransformAxis` lists a `FunctionJoint` is made of.

use nalgebra::Vector3;
use roxmltree::Node;

use super::xml::{Ctx, child, elements, err, flag, name_of, num, nums, text, vec3};
use super::{MotionType, OsimCoordinate};
use crate::model::files::osim_joint::function_from_xml;
use crate::model::joint::Limit;
use crate::model::joints::{ScalarFunction, TransformAxis};
use crate::model::tree::ModelError;

pub(super) fn read_coordinates(
    cx: &Ctx,
    node: Node,
    joint: &str,
    what: &str,
    v3: bool,
    names: &[String],
) -> Result<Vec<OsimCoordinate>, ModelError> {
    let mut coords: Vec<OsimCoordinate> = Vec::new();
    let cs = if v3 {
        child(node, "CoordinateSet").and_then(|s| child(s, "objects"))
    } else {
        child(node, "coordinates")
    };
    if let Some(cs) = cs {
        for c in elements(cs).filter(|c| c.has_tag_name("Coordinate")) {
            let cname = name_of(c);
            if cname.is_empty() {
                return err(format!("{what}: {} has no name", cx.at(c)));
            }
            if names.contains(&cname) || coords.iter().any(|o| o.name == cname) {
                return err(format!(
                    "{what}: coordinate '{cname}' ({}) is used twice; coordinate names must be unique in a model",
                    cx.at(c)
                ));
            }
            let r = nums(cx, c, "range", "")?;
            let range = match r.as_slice() {
                [] => Limit::NONE,
                [lo, hi] if lo <= hi => Limit {
                    lower: *lo,
                    upper: *hi,
                },
                _ => {
                    return err(format!(
                        "{what}: coordinate '{cname}' ({}) has <range> {r:?}; expected min ≤ max",
                        cx.at(c)
                    ));
                }
            };
            coords.push(OsimCoordinate {
                name: cname,
                joint: joint.to_string(),
                motion: MotionType::Rotational,
                range,
                default_value: num(cx, c, "default_value", 0.0)?,
                default_speed: num(cx, c, "default_speed_value", 0.0)?,
                clamped: flag(c, "clamped"),
                locked: flag(c, "locked"),
            });
        }
    }
    Ok(coords)
}

/// A CustomJoint's SpatialTransform: three rotation and three translation
/// axes, each a function of at most one of the joint's coordinates, and each
/// coordinate's motion type by OpenSim's rule.
pub(super) fn spatial_transform(
    cx: &Ctx,
    node: Node,
    what: &str,
    coords: &mut [OsimCoordinate],
) -> Result<(Vec<TransformAxis>, Vec<TransformAxis>), ModelError> {
    let cnames: Vec<String> = coords.iter().map(|c| c.name.clone()).collect();
    let Some(st) = child(node, "SpatialTransform") else {
        return err(format!("{what} has no <SpatialTransform>"));
    };
    let mut rot = Vec::new();
    let mut tr = Vec::new();
    let mut decided = vec![false; coords.len()];
    let mut seen: Vec<String> = vec![];
    for ta in elements(st) {
        if !ta.has_tag_name("TransformAxis") {
            return err(format!(
                "{what}: {} in the SpatialTransform is not a TransformAxis",
                cx.at(ta)
            ));
        }
        let label = name_of(ta);
        let tw = format!("{what}, transform axis '{label}' ({})", cx.at(ta));
        let used: Vec<&str> = text(ta, "coordinates")
            .unwrap_or("")
            .split_whitespace()
            .collect();
        let coordinate = match used.as_slice() {
            [] => None,
            [c] => Some(cnames.iter().position(|n| n == c).ok_or_else(|| {
                ModelError::Invalid(format!(
                    "{tw} reads coordinate '{c}', which the joint does not have ({})",
                    cnames.join(", ")
                ))
            })?),
            many => {
                return err(format!(
                    "{tw} is a function of {} coordinates ({}); mx reads transform axes of one coordinate, as OpenSim's CustomJoint allows",
                    many.len(),
                    many.join(", ")
                ));
            }
        };
        let fnode = elements(ta).find(|c| !matches!(c.tag_name().name(), "coordinates" | "axis"));
        let function = match fnode {
            Some(f) => function_from_xml(f)
                .map_err(|m| ModelError::Invalid(format!("{tw}, {}: {}", cx.at(f), m.0)))?,
            None if coordinate.is_none() => ScalarFunction::Constant { value: 0.0 },
            None => return err(format!("{tw} reads a coordinate but has no function")),
        };
        let is_rot = label.starts_with("rotation");
        // exactly rotation1..3 / translation1..3: a fourth axis would be dropped
        if !matches!(
            label.as_str(),
            "rotation1"
                | "rotation2"
                | "rotation3"
                | "translation1"
                | "translation2"
                | "translation3"
        ) {
            return err(format!(
                "{tw}: the name must be rotation1..3 or translation1..3"
            ));
        }
        if seen.contains(&label) {
            return err(format!(
                "{tw}: the SpatialTransform has two axes named '{label}'"
            ));
        }
        seen.push(label.clone());
        // OpenSim's rule: the first axis that reads the coordinate
        // through the identity (LinearFunction 1·q + 0) makes it
        // rotational or translational; without one it is coupled.
        if let Some(i) = coordinate
            && !decided[i]
            && function
                == (ScalarFunction::Linear {
                    slope: 1.0,
                    intercept: 0.0,
                })
        {
            coords[i].motion = if is_rot {
                MotionType::Rotational
            } else {
                MotionType::Translational
            };
            decided[i] = true;
        }
        let axis = vec3(cx, ta, "axis")?;
        let ax = TransformAxis {
            axis,
            coordinate,
            function,
        };
        if is_rot { rot.push(ax) } else { tr.push(ax) }
    }
    for (c, d) in coords.iter_mut().zip(&decided) {
        if !d {
            c.motion = MotionType::Coupled;
        }
    }
    if rot.len() != 3 || tr.len() != 3 {
        return err(format!(
            "{what}: the SpatialTransform has {} rotation and {} translation axes; expected 3 and 3",
            rot.len(),
            tr.len()
        ));
    }
    Ok((rot, tr))
}

/// The fixed axes of the other joint types, each reading one coordinate
/// through the identity.
pub(super) fn standard_transform(
    kind: &str,
    what: &str,
    coords: &mut [OsimCoordinate],
) -> Result<(Vec<TransformAxis>, Vec<TransformAxis>), ModelError> {
    let Some((n, (r, t))) = standard_axes(kind) else {
        return err(format!(
            "{what}: joint type {kind} is not one mx reads (CustomJoint, PinJoint, SliderJoint, WeldJoint, BallJoint, FreeJoint, UniversalJoint, GimbalJoint, PlanarJoint)"
        ));
    };
    if coords.len() != n {
        return err(format!(
            "{what}: a {kind} has {n} coordinate(s), the file gives {}",
            coords.len()
        ));
    }
    for (_, i) in &t {
        coords[*i].motion = MotionType::Translational;
    }
    let mk = |(a, i): ([f64; 3], usize)| TransformAxis {
        axis: unit(a),
        coordinate: Some(i),
        function: linear(),
    };
    Ok((
        r.into_iter().map(mk).collect(),
        t.into_iter().map(mk).collect(),
    ))
}

/// The ConstraintSet: CoordinateCouplerConstraints into the report (any other
/// enforced constraint changes the kinematics and is an error).
/// The axes of a joint type other than CustomJoint: (rotations, translations),
/// each (axis, coordinate index).
type AxisSpec = (Vec<([f64; 3], usize)>, Vec<([f64; 3], usize)>);

fn standard_axes(kind: &str) -> Option<(usize, AxisSpec)> {
    const X: [f64; 3] = [1.0, 0.0, 0.0];
    const Y: [f64; 3] = [0.0, 1.0, 0.0];
    const Z: [f64; 3] = [0.0, 0.0, 1.0];
    Some(match kind {
        "PinJoint" => (1, (vec![(Z, 0)], vec![])),
        "SliderJoint" => (1, (vec![], vec![(X, 0)])),
        "UniversalJoint" => (2, (vec![(X, 0), (Y, 1)], vec![])),
        "GimbalJoint" | "BallJoint" => (3, (vec![(X, 0), (Y, 1), (Z, 2)], vec![])),
        "FreeJoint" => (
            6,
            (vec![(X, 0), (Y, 1), (Z, 2)], vec![(X, 3), (Y, 4), (Z, 5)]),
        ),
        "PlanarJoint" => (3, (vec![(Z, 0)], vec![(X, 1), (Y, 2)])),
        "WeldJoint" => (0, (vec![], vec![])),
        _ => return None,
    })
}

fn unit(a: [f64; 3]) -> Vector3<f64> {
    Vector3::new(a[0], a[1], a[2])
}

/// Three rotation and three translation axes from a list, padded with
/// constant-zero axes orthogonal to nothing in particular (x, y, z).
pub(super) fn pad(given: Vec<TransformAxis>) -> [TransformAxis; 3] {
    let mut v = given;
    let defaults = [Vector3::x(), Vector3::y(), Vector3::z()];
    while v.len() < 3 {
        v.push(TransformAxis {
            axis: defaults[v.len()],
            coordinate: None,
            function: ScalarFunction::Constant { value: 0.0 },
        });
    }
    let mut it = v.into_iter();
    [
        it.next().expect("padded to 3"),
        it.next().expect("padded to 3"),
        it.next().expect("padded to 3"),
    ]
}

fn linear() -> ScalarFunction {
    ScalarFunction::Linear {
        slope: 1.0,
        intercept: 0.0,
    }
}
