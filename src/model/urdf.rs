//! Loading a fixed-base model from URDF (parsed by `urdf-rs`).
//!
//! Follows Pinocchio's conventions so results can be compared directly:
//! the root link is welded to the world; fixed joints are merged (their child's
//! inertia is added to the moving body they hang from and their origins are
//! folded into the offsets below them); `<mimic>` is ignored (a mimic joint is
//! an independent coordinate); the coordinate order is depth-first with the
//! child joints of every link sorted by joint name (urdfdom keeps joints in a
//! name-sorted map). Gravity defaults to `[0, 0, −9.81]`, Pinocchio's default.
//! A `continuous` joint is an unlimited revolute joint with one coordinate (the
//! angle; Pinocchio stores (cos, sin) instead).

use crate::lie::Se3;
use crate::model::body::Inertia;
use crate::model::joint::{Joint, Limit};
use crate::model::joints::{Prismatic, Revolute};
use crate::model::tree::{Model, ModelError};
use nalgebra::{Matrix3, Rotation3, Vector3};
use std::collections::HashMap;
use std::sync::Arc;

fn pose(p: &urdf_rs::Pose) -> Se3 {
    Se3::new(
        Rotation3::from_euler_angles(p.rpy[0], p.rpy[1], p.rpy[2]).into_inner(),
        Vector3::new(p.xyz[0], p.xyz[1], p.xyz[2]),
    )
}

/// The inertia of a URDF link in the link frame.
fn link_inertia(l: &urdf_rs::Link) -> Result<Inertia, ModelError> {
    let i = &l.inertial;
    if i.mass.value == 0.0 {
        return Ok(Inertia::zero());
    }
    let t = pose(&i.origin);
    let ic = Matrix3::new(
        i.inertia.ixx,
        i.inertia.ixy,
        i.inertia.ixz,
        i.inertia.ixy,
        i.inertia.iyy,
        i.inertia.iyz,
        i.inertia.ixz,
        i.inertia.iyz,
        i.inertia.izz,
    );
    // The inertia is given about the com in the <inertial><origin> frame.
    let local = Inertia::from_com(i.mass.value, Vector3::zeros(), ic)
        .map_err(|e| ModelError::Urdf(format!("link `{}`: {e}", l.name)))?;
    Ok(local.transformed(&t))
}

impl Model {
    /// Parses a URDF document.
    pub fn from_urdf_str(text: &str) -> Result<Model, ModelError> {
        let robot = urdf_rs::read_from_string(text).map_err(|e| {
            ModelError::Urdf(format!("could not parse the URDF ({e}); check that it is well-formed XML with a <robot> root"))
        })?;
        build(&robot)
    }

    /// Reads and parses a URDF file.
    pub fn from_urdf_file(path: impl AsRef<std::path::Path>) -> Result<Model, ModelError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path)
            .map_err(|e| ModelError::Urdf(format!("cannot read `{}`: {e}", path.display())))?;
        Self::from_urdf_str(&text).map_err(|e| match e {
            ModelError::Urdf(m) => ModelError::Urdf(format!("{}: {m}", path.display())),
            other => other,
        })
    }
}

fn build(robot: &urdf_rs::Robot) -> Result<Model, ModelError> {
    let links: HashMap<&str, &urdf_rs::Link> =
        robot.links.iter().map(|l| (l.name.as_str(), l)).collect();
    let mut children: HashMap<&str, Vec<&urdf_rs::Joint>> = HashMap::new();
    let mut is_child: HashMap<&str, &str> = HashMap::new();
    for j in &robot.joints {
        for end in [&j.parent.link, &j.child.link] {
            if !links.contains_key(end.as_str()) {
                return Err(ModelError::Urdf(format!(
                    "joint `{}` refers to link `{end}`, which is not defined",
                    j.name
                )));
            }
        }
        if let Some(prev) = is_child.insert(j.child.link.as_str(), j.name.as_str()) {
            return Err(ModelError::Urdf(format!(
                "link `{}` is the child of both `{prev}` and `{}`; a URDF must be a tree",
                j.child.link, j.name
            )));
        }
        children.entry(j.parent.link.as_str()).or_default().push(j);
    }
    for v in children.values_mut() {
        v.sort_by(|a, b| a.name.cmp(&b.name));
    }
    let roots: Vec<&str> = robot
        .links
        .iter()
        .map(|l| l.name.as_str())
        .filter(|n| !is_child.contains_key(n))
        .collect();
    let root = match roots.as_slice() {
        [r] => *r,
        [] => {
            return Err(ModelError::Urdf(
                "no root link: the joints form a cycle".into(),
            ));
        }
        many => {
            return Err(ModelError::Urdf(format!(
                "several root links ({}); a URDF must be one tree",
                many.join(", ")
            )));
        }
    };
    let mut model = Model::new(&robot.name);
    let mut inertias: Vec<Inertia> = Vec::new();
    // Depth-first, children sorted by joint name: Pinocchio's order. Stack items:
    // (joint, moving body its parent link belongs to, pose of that parent link in the body).
    let mut stack: Vec<(&urdf_rs::Joint, Option<usize>, Se3)> = Vec::new();
    let push_children = |stack: &mut Vec<_>, lname: &str, body: Option<usize>, acc: Se3| {
        if let Some(kids) = children.get(lname) {
            // Reverse so the first name is popped first.
            for j in kids.iter().rev() {
                stack.push((*j, body, acc));
            }
        }
    };
    push_children(&mut stack, root, None, Se3::identity());
    let mut visited = 0usize;
    while let Some((j, body, acc)) = stack.pop() {
        visited += 1;
        if visited > robot.joints.len() {
            return Err(ModelError::Urdf("the joints form a cycle".into()));
        }
        let child = links[j.child.link.as_str()];
        let placement = acc.compose(&pose(&j.origin));
        let axis = Vector3::new(j.axis.xyz[0], j.axis.xyz[1], j.axis.xyz[2]);
        let limit = if j.limit.lower < j.limit.upper {
            Limit {
                lower: j.limit.lower,
                upper: j.limit.upper,
            }
        } else {
            Limit::NONE
        };
        let bad_axis = || {
            ModelError::Urdf(format!(
                "joint `{}` has a zero or non-finite axis {:?}",
                j.name, axis
            ))
        };
        let joint: Arc<dyn Joint> = match j.joint_type {
            urdf_rs::JointType::Fixed => {
                if let Some(b) = body {
                    inertias[b] += link_inertia(child)?.transformed(&placement);
                }
                push_children(&mut stack, child.name.as_str(), body, placement);
                continue;
            }
            urdf_rs::JointType::Revolute => {
                Arc::new(Revolute::new(axis).ok_or_else(bad_axis)?.with_limit(limit))
            }
            urdf_rs::JointType::Continuous => Arc::new(Revolute::new(axis).ok_or_else(bad_axis)?),
            urdf_rs::JointType::Prismatic => {
                Arc::new(Prismatic::new(axis).ok_or_else(bad_axis)?.with_limit(limit))
            }
            ref other => {
                return Err(ModelError::Urdf(format!(
                    "joint `{}` is of type {other:?}, which mx does not load yet; \
                     use revolute, continuous, prismatic or fixed joints (fixed base)",
                    j.name
                )));
            }
        };
        let idx = model.add_link(
            &child.name,
            body,
            &j.name,
            joint,
            placement,
            Inertia::zero(),
        )?;
        inertias.push(link_inertia(child)?);
        push_children(&mut stack, child.name.as_str(), Some(idx), Se3::identity());
    }
    for (i, inertia) in inertias.into_iter().enumerate() {
        model.set_inertia(i, inertia)?;
    }
    Ok(model)
}
