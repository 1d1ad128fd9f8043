//! The build phase: one link per joint of the document, in its order (parents
//! first), with the joint its type asks for, the child body's inertia, and the
//! coordinates in each joint's own order.

use std::collections::HashMap;
use std::sync::Arc;

use nalgebra::{Matrix3, Vector3};
use roxmltree::Node;

use super::OsimModel;
use super::document::{JointDecl, OsimDocument};
use super::joints::{pad, read_coordinates, spatial_transform, standard_transform};
use super::xml::{Ctx, child, err, name_of, num, nums, vec3};
use crate::lie::Se3;
use crate::model::body::Inertia;
use crate::model::joint::{Joint, Limit};
use crate::model::joints::{Fixed, FunctionJoint, Prismatic, Revolute, TransformAxis};
use crate::model::tree::{Model, ModelError};

pub(super) fn build(cx: &Ctx, doc: OsimDocument) -> Result<OsimModel, ModelError> {
    let model_name = doc.model.attribute("name").unwrap_or("opensim");
    let mut model = Model::new(model_name);
    model.default_gravity = doc.gravity;
    let mut report = doc.report;
    let mut placed: HashMap<&str, usize> = HashMap::new(); // body → link index
    let mut names: Vec<String> = Vec::new();
    for (link, j) in doc.joints.iter().enumerate() {
        let what = format!("joint '{}' ({})", j.name, cx.at(j.node));
        let kind = j.node.tag_name().name();
        let mut coords = read_coordinates(cx, j.node, &j.name, &what, doc.v3, &names)?;
        let cnames: Vec<String> = coords.iter().map(|c| c.name.clone()).collect();
        let limits: Vec<Limit> = coords.iter().map(|c| c.range).collect();
        let (rot, tr) = if kind == "CustomJoint" {
            spatial_transform(cx, j.node, &what, &mut coords)?
        } else {
            standard_transform(kind, &what, &mut coords)?
        };
        let joint = joint_of(j, kind, &what, &cnames, &limits, rot, tr)?;
        let parent_link = j.parent.0.as_deref().map(|p| placed[p]);
        let inertia = inertia_of(cx, doc.bodies[&j.child_body])?;
        model.add_link(
            &j.child_body,
            parent_link,
            &j.name,
            joint,
            j.parent.1,
            inertia,
        )?;
        placed.insert(j.child_body.as_str(), link);
        names.extend(cnames);
        report.coordinates.extend(coords);
    }
    model.set_coordinate_names(names)?;
    Ok(OsimModel { model, report })
}

/// The joint a declaration asks for: a plain revolute or prismatic joint where
/// OpenSim's PinJoint or SliderJoint sits at the child body's origin, a fixed
/// one for a WeldJoint, and the general function-based joint otherwise.
fn joint_of(
    j: &JointDecl,
    kind: &str,
    what: &str,
    cnames: &[String],
    limits: &[Limit],
    rot: Vec<TransformAxis>,
    tr: Vec<TransformAxis>,
) -> Result<Arc<dyn Joint>, ModelError> {
    let child_identity = j.child_frame == Se3::identity();
    Ok(match kind {
        "WeldJoint" => Arc::new(Fixed::new(j.child_frame.inverse())),
        "PinJoint" if child_identity && !j.reversed => Arc::new(
            Revolute::new(Vector3::z())
                .expect("z is a unit axis")
                .with_limit(limits[0]),
        ),
        "SliderJoint" if child_identity && !j.reversed => Arc::new(
            Prismatic::new(Vector3::x())
                .expect("x is a unit axis")
                .with_limit(limits[0]),
        ),
        _ => Arc::new(
            FunctionJoint::new(
                j.name.clone(),
                cnames.to_vec(),
                pad(rot),
                pad(tr),
                Se3::identity(),
                j.child_frame,
            )
            .map_err(|e| ModelError::Invalid(format!("{what}: {}", e.0)))
            .map(|fj| if j.reversed { fj.reversed() } else { fj })?
            .with_limits(limits.to_vec()),
        ),
    })
}

fn inertia_of(cx: &Ctx, b: Node) -> Result<Inertia, ModelError> {
    let name = name_of(b);
    let mass = num(cx, b, "mass", 0.0)?;
    let com = vec3(cx, b, "mass_center")?;
    let i = if child(b, "inertia_xx").is_some() {
        [
            "inertia_xx",
            "inertia_yy",
            "inertia_zz",
            "inertia_xy",
            "inertia_xz",
            "inertia_yz",
        ]
        .iter()
        .map(|t| num(cx, b, t, 0.0))
        .collect::<Result<Vec<f64>, _>>()?
    } else {
        nums(cx, b, "inertia", "0 0 0 0 0 0")?
    };
    let i = match i.len() {
        6 => i,
        3 => vec![i[0], i[1], i[2], 0.0, 0.0, 0.0],
        n => {
            return err(format!(
                "body '{name}' ({}): <inertia> holds {n} numbers; expected Ixx Iyy Izz Ixy Ixz Iyz",
                cx.at(b)
            ));
        }
    };
    let ic = Matrix3::new(i[0], i[3], i[4], i[3], i[1], i[5], i[4], i[5], i[2]);
    Inertia::from_com(mass, com, ic)
        .map_err(|m| ModelError::Invalid(format!("body '{name}' ({}): {m}", cx.at(b))))
}
