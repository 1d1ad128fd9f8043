//! Loading a fixed-base model from URDF (parsed by `urdf-rs`).
//!
//! Follows Pinocchio's conventions so results can be compared directly:
//! the root link is welded to the world; fixed joints are merged (their child's
//! inertia is added to the moving body they hang from and their origins are
//! folded into the offsets below them); `<mimic>` is ignored by default (a
//! mimic joint is an independent coordinate, as in Pinocchio's plain
//! `buildModel`) and with [`UrdfOptions::mimic`] becomes a coupled coordinate
//! (`model::Coupling`, Pinocchio's `buildModel(…, mimic=True)`); the
//! coordinate order is depth-first with the
//! child joints of every link sorted by joint name (urdfdom keeps joints in a
//! name-sorted map). Gravity defaults to `[0, 0, −9.81]`, Pinocchio's default.
//! A `continuous` joint is an unlimited revolute joint with one coordinate (the
//! angle; Pinocchio stores (cos, sin) instead).
//!
//! Broken files are errors that name what is wrong, never a silently wrong
//! model: several roots, a cycle, a link or joint defined twice, a joint
//! naming a missing link, a mimic naming a missing joint (in either mode), a
//! negative mass, an inertia that is not positive semi-definite or breaks the
//! triangle inequality, a revolute or prismatic joint without `<limit>`
//! (urdfdom's rule).

use crate::lie::Se3;
use crate::model::body::Inertia;
use crate::model::coupling::{Coupling, Follower};
use crate::model::joint::{Joint, Limit};
use crate::model::joints::{Prismatic, Revolute};
use crate::model::link_tree::{TreeError, TreeJoint, roots, tree_order};
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
    let ic = inertia_matrix(l);
    // The inertia is given about the com in the <inertial><origin> frame.
    let local = Inertia::from_com(i.mass.value, Vector3::zeros(), ic)
        .map_err(|e| ModelError::Urdf(format!("link `{}`: {e}", l.name)))?;
    Ok(local.transformed(&t))
}

/// The rotational inertia of a URDF link about its centre of mass.
fn inertia_matrix(l: &urdf_rs::Link) -> Matrix3<f64> {
    let i = &l.inertial;
    Matrix3::new(
        i.inertia.ixx,
        i.inertia.ixy,
        i.inertia.ixz,
        i.inertia.ixy,
        i.inertia.iyy,
        i.inertia.iyz,
        i.inertia.ixz,
        i.inertia.iyz,
        i.inertia.izz,
    )
}

/// A rotational inertia about the centre of mass that a rigid body can have:
/// symmetric (checked by `Inertia::from_com`), principal moments ≥ 0 and each
/// at most the sum of the other two (a tolerance of 1e-9 of the largest).
fn check_inertia(link: &str, mass: f64, ic: &Matrix3<f64>) -> Result<(), ModelError> {
    if !(mass.is_finite() && mass >= 0.0) {
        return Err(ModelError::Urdf(format!(
            "link `{link}` has mass {mass}; a mass must be a finite number ≥ 0"
        )));
    }
    if !ic.iter().all(|x| x.is_finite()) {
        return Err(ModelError::Urdf(format!(
            "link `{link}`: the inertia has a non-finite entry"
        )));
    }
    let sym = (ic + ic.transpose()) * 0.5;
    let mut e: Vec<f64> = sym.symmetric_eigenvalues().iter().copied().collect();
    e.sort_by(f64::total_cmp);
    let tol = 1e-9 * e[2].abs().max(f64::MIN_POSITIVE);
    if e[0] < -tol {
        return Err(ModelError::Urdf(format!(
            "link `{link}`: the inertia is not positive definite (principal moments {:.3e}, {:.3e}, {:.3e}); \
             check the signs of ixx, iyy, izz and the size of the products ixy, ixz, iyz",
            e[0], e[1], e[2]
        )));
    }
    if e[2] > e[0] + e[1] + tol {
        return Err(ModelError::Urdf(format!(
            "link `{link}`: the principal moments {:.3e}, {:.3e}, {:.3e} break the triangle inequality \
             (the largest exceeds the sum of the others), which no rigid body has",
            e[0], e[1], e[2]
        )));
    }
    Ok(())
}

/// How to read a URDF.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct UrdfOptions {
    /// `<mimic>` joints become coupled coordinates (q = multiplier·q_source + offset).
    pub mimic: bool,
}

impl Model {
    /// Parses a URDF document (mimic joints are free coordinates).
    pub fn from_urdf_str(text: &str) -> Result<Model, ModelError> {
        Ok(Self::from_urdf_str_with(text, UrdfOptions::default())?.0)
    }

    /// Parses a URDF document; with `mimic`, also the coupling of its mimic
    /// joints (`None` when it has none or `mimic` is off).
    pub fn from_urdf_str_with(
        text: &str,
        options: UrdfOptions,
    ) -> Result<(Model, Option<Coupling>), ModelError> {
        let robot = urdf_rs::read_from_string(text).map_err(|e| {
            ModelError::UrdfMalformed(format!("could not parse the URDF ({e}); check that it is well-formed XML with a <robot> root"))
        })?;
        check_limits(text)?;
        let model = build(&robot)?;
        let coupling = mimic_coupling(&robot, &model, options.mimic)?;
        Ok((model, coupling))
    }

    /// Reads and parses a URDF file (mimic joints are free coordinates).
    pub fn from_urdf_file(path: impl AsRef<std::path::Path>) -> Result<Model, ModelError> {
        Ok(Self::from_urdf_file_with(path, UrdfOptions::default())?.0)
    }

    /// Reads and parses a URDF file with options (see [`Model::from_urdf_str_with`]).
    pub fn from_urdf_file_with(
        path: impl AsRef<std::path::Path>,
        options: UrdfOptions,
    ) -> Result<(Model, Option<Coupling>), ModelError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|e| {
            ModelError::UrdfUnreadable(format!("cannot read `{}`: {e}", path.display()))
        })?;
        // the file's name leads every message about its content
        Self::from_urdf_str_with(&text, options).map_err(|e| match e {
            ModelError::Urdf(m) => ModelError::Urdf(format!("{}: {m}", path.display())),
            ModelError::UrdfMalformed(m) => {
                ModelError::UrdfMalformed(format!("{}: {m}", path.display()))
            }
            ModelError::UrdfTree { error, .. } => ModelError::UrdfTree {
                path: Some(path.to_path_buf()),
                error,
            },
            other => other,
        })
    }
}

/// urdfdom's rule: a revolute or prismatic joint states its `<limit>`
/// (urdf-rs would fill in zeros silently).
fn check_limits(text: &str) -> Result<(), ModelError> {
    let doc = roxmltree::Document::parse(text)
        .map_err(|e| ModelError::UrdfMalformed(format!("could not parse the URDF XML: {e}")))?;
    let robot = doc.root_element();
    for j in robot.children().filter(|n| n.has_tag_name("joint")) {
        let kind = j.attribute("type").unwrap_or("");
        if matches!(kind, "revolute" | "prismatic")
            && !j.children().any(|c| c.has_tag_name("limit"))
        {
            let (line, _) = {
                let p = doc.text_pos_at(j.range().start);
                (p.row, p.col)
            };
            return Err(ModelError::Urdf(format!(
                "line {line}: {kind} joint `{}` has no <limit>; add <limit lower=\"…\" upper=\"…\" effort=\"…\" velocity=\"…\"/> \
                 (or make it `continuous` if it has no range)",
                j.attribute("name").unwrap_or("?")
            )));
        }
    }
    Ok(())
}

/// The coupling of the mimic joints (checked in either mode: a mimic naming
/// a joint that does not exist is a broken file).
fn mimic_coupling(
    robot: &urdf_rs::Robot,
    model: &Model,
    mimic: bool,
) -> Result<Option<Coupling>, ModelError> {
    let mut followers = Vec::new();
    for j in &robot.joints {
        let Some(m) = &j.mimic else { continue };
        let Some(src) = robot.joints.iter().find(|s| s.name == m.joint) else {
            return Err(ModelError::Urdf(format!(
                "joint `{}` mimics `{}`, which is not a joint of this robot",
                j.name, m.joint
            )));
        };
        let (Some(k), Some(s)) = (
            model.coordinate_index(&j.name),
            model.coordinate_index(&src.name),
        ) else {
            return Err(ModelError::Urdf(format!(
                "joint `{}` mimics `{}`, but mimic joints must both move (one coordinate each; \
                 a fixed joint has none)",
                j.name, m.joint
            )));
        };
        followers.push(Follower::linear(
            k,
            s,
            m.multiplier.unwrap_or(1.0),
            m.offset.unwrap_or(0.0),
        ));
    }
    if !mimic || followers.is_empty() {
        return Ok(None);
    }
    Coupling::new(model, &followers)
        .map(Some)
        .map_err(|e| ModelError::Urdf(e.to_string()))
}

// The tree's checks (names, joints between links that exist, cycles) are
// `link_tree`'s; a URDF adds one root, welded to the world, and Pinocchio's
// order (children by joint name), then builds depth first.
fn build(robot: &urdf_rs::Robot) -> Result<Model, ModelError> {
    let urdf = |error: TreeError| ModelError::UrdfTree { path: None, error };
    for l in &robot.links {
        // Every link, the root's too (welded to the world, but a broken file).
        check_inertia(&l.name, l.inertial.mass.value, &inertia_matrix(l))?;
    }
    let names: Vec<&str> = robot.links.iter().map(|l| l.name.as_str()).collect();
    // children of every link sorted by joint name: Pinocchio's order
    let mut joints: Vec<&urdf_rs::Joint> = robot.joints.iter().collect();
    joints.sort_by(|a, b| a.name.cmp(&b.name));
    let edges: Vec<TreeJoint> = joints
        .iter()
        .map(|j| TreeJoint {
            name: &j.name,
            parent: Some(&j.parent.link),
            child: &j.child.link,
        })
        .collect();
    let tree = tree_order(&names, &edges);
    // a cycle's message names the root it is not connected to, found first
    if let Err(e) = &tree
        && !matches!(e, TreeError::Cycle { .. })
    {
        return Err(urdf(e.clone()));
    }
    let root = match roots(&names, &edges).as_slice() {
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
    let order = tree.map_err(|e| match e {
        TreeError::Cycle {
            joints: mut stray, ..
        } => {
            // in the file's order
            stray.sort_by_key(|n| robot.joints.iter().position(|j| &j.name == n));
            ModelError::Urdf(format!(
                "the joints {} form a cycle not connected to the root link `{root}`",
                stray.join(", ")
            ))
        }
        e => urdf(e),
    })?;
    let links: HashMap<&str, &urdf_rs::Link> =
        robot.links.iter().map(|l| (l.name.as_str(), l)).collect();
    let mut model = Model::new(&robot.name);
    let mut inertias: Vec<Inertia> = Vec::new();
    // Per link placed: the moving body it belongs to and its pose in that body
    // (a fixed joint's child joins its parent's body).
    let mut placed: HashMap<&str, (Option<usize>, Se3)> =
        HashMap::from([(root, (None, Se3::identity()))]);
    for j in order.into_iter().map(|i| joints[i]) {
        let (body, acc) = placed[j.parent.link.as_str()];
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
                placed.insert(child.name.as_str(), (body, placement));
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
        placed.insert(child.name.as_str(), (Some(idx), Se3::identity()));
    }
    for (i, inertia) in inertias.into_iter().enumerate() {
        model.set_inertia(i, inertia)?;
    }
    Ok(model)
}
