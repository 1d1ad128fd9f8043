//! The document phase: the header (format version, gravity, ground, unknown
//! elements), the bodies, and every joint with its parent and child frames
//! resolved, in build order (a joint whose parent body has no joint yet waits
//! until it has). Nothing is built here; `build.rs` turns this into links.

use std::collections::HashMap;

use nalgebra::Vector3;
use roxmltree::{Document, Node};

use super::OsimReport;
use super::frames::{Frames, Placed};
use super::xml::{Ctx, child, elements, err, flag, joint_of_body, name_of, objects, text, vec3};
use crate::lie::Se3;
use crate::model::joints::function_based::body_fixed_xyz;
use crate::model::tree::ModelError;

const MODEL_KNOWN: &[&str] = &[
    "Ground",
    "gravity",
    "credits",
    "publications",
    "length_units",
    "force_units",
    "assembly_accuracy",
    "BodySet",
    "JointSet",
    "ConstraintSet",
    "ForceSet",
    "MarkerSet",
    "ContactGeometrySet",
    "ControllerSet",
    "ProbeSet",
    "ComponentSet",
    "components",
    "defaults",
    "validatedModel",
    "FrameGeometry",
    "attached_geometry",
];

/// One joint as the file places it.
pub(super) struct JointDecl<'a, 'i> {
    pub(super) node: Node<'a, 'i>,
    pub(super) name: String,
    /// The parent frame F: on a body (`None` = ground) at `T_P_F`.
    pub(super) parent: Placed,
    pub(super) child_body: String,
    /// `T_B_M`: the child frame M on the child body B.
    pub(super) child_frame: Se3,
    /// A 3.x `<reverse>true</reverse>`: T_F_M(q)⁻¹ between the same frames.
    pub(super) reversed: bool,
}

/// What the build phase needs of the file.
pub(super) struct OsimDocument<'a, 'i> {
    /// The `<Model>` element.
    pub(super) model: Node<'a, 'i>,
    /// OpenSim 3.x (format < 40000): coordinates and functions sit elsewhere.
    pub(super) v3: bool,
    pub(super) gravity: Vector3<f64>,
    pub(super) bodies: HashMap<String, Node<'a, 'i>>,
    /// Parents first: the i-th joint makes link i.
    pub(super) joints: Vec<JointDecl<'a, 'i>>,
    /// The version and the warnings so far; the build adds the coordinates.
    pub(super) report: OsimReport,
}

/// The header facts the later phases share.
struct Header<'a, 'i> {
    model: Node<'a, 'i>,
    v3: bool,
    gravity: Vector3<f64>,
    ground: String,
    report: OsimReport,
}

pub(super) fn read<'a, 'i>(cx: &Ctx<'a, 'i>) -> Result<OsimDocument<'a, 'i>, ModelError> {
    let h = header(cx, cx.doc)?;
    let (bodies, body_order) = read_bodies(cx, &h)?;
    let joint_nodes: Vec<Node> = if h.v3 {
        body_order
            .iter()
            .filter_map(|b| joint_of_body(bodies[b]))
            .collect()
    } else {
        objects(child(h.model, "JointSet"))
    };
    let mut free: HashMap<String, Vec<Node>> = HashMap::new();
    for f in h
        .model
        .descendants()
        .filter(|n| n.has_tag_name("PhysicalOffsetFrame"))
    {
        // Frames a joint owns are resolved in that joint's scope.
        let owned_by_joint = f.ancestors().any(|a| joint_nodes.contains(&a));
        if !owned_by_joint {
            free.entry(name_of(f)).or_default().push(f);
        }
    }
    let frames = Frames {
        ground: h.ground.clone(),
        bodies: bodies.keys().map(|k| (k.clone(), ())).collect(),
        free,
    };
    let joints = read_joints(cx, &h, &bodies, &frames, &joint_nodes)?;
    for b in &body_order {
        if !joints.iter().any(|j| &j.child_body == b) {
            return err(format!(
                "body '{b}' ({}) has no joint; OpenSim would give it a free joint to ground — add one",
                cx.at(bodies[b])
            ));
        }
    }
    Ok(OsimDocument {
        model: h.model,
        v3: h.v3,
        gravity: h.gravity,
        bodies,
        joints: parents_first(cx, joints)?,
        report: h.report,
    })
}

fn header<'a, 'i>(cx: &Ctx, doc: &'a Document<'i>) -> Result<Header<'a, 'i>, ModelError> {
    let root = doc.root_element();
    if root.tag_name().name() != "OpenSimDocument" {
        return err(format!(
            "not an OpenSim model: the root element is <{}>, not <OpenSimDocument>",
            root.tag_name().name()
        ));
    }
    let version: u32 = root
        .attribute("Version")
        .and_then(|v| v.trim().parse().ok())
        .unwrap_or(0);
    let Some(m) = child(root, "Model") else {
        return err("not an OpenSim model: <OpenSimDocument> holds no <Model>");
    };
    // OpenSim 3.x (format < 40000): bodies hold their joint (`<Joint><PinJoint>…`,
    // `parent_body`, `location_in_parent`/`orientation_in_parent` and
    // `location`/`orientation` for F and M), ground is a body of the BodySet,
    // coordinates sit in `CoordinateSet/objects`, functions in `<function>`.
    let v3 = version < 40000;
    let mut report = OsimReport {
        version,
        ..Default::default()
    };
    for c in elements(m) {
        let t = c.tag_name().name();
        if !MODEL_KNOWN.contains(&t) {
            report
                .warnings
                .push(format!("{} is not an element mx knows; ignored", cx.at(c)));
        }
    }
    if let Some(u) = text(m, "length_units")
        && !u.is_empty()
        && !u.eq_ignore_ascii_case("meters")
    {
        report.warnings.push(format!(
            "length_units is '{u}'; mx reads every length as metres, as OpenSim does"
        ));
    }
    let gravity = match child(m, "gravity") {
        Some(_) => vec3(cx, m, "gravity")?,
        None => Vector3::new(0.0, -9.80665, 0.0),
    };
    let ground = if v3 {
        objects(child(m, "BodySet"))
            .into_iter()
            .find(|b| joint_of_body(*b).is_none())
            .map(name_of)
            .unwrap_or_else(|| "ground".into())
    } else {
        child(m, "Ground")
            .map(name_of)
            .filter(|n| !n.is_empty())
            .unwrap_or_else(|| "ground".into())
    };
    Ok(Header {
        model: m,
        v3,
        gravity,
        ground,
        report,
    })
}

/// The BodySet's bodies by name, and their order in the file (3.x: ground left out).
#[allow(clippy::type_complexity)]
fn read_bodies<'a, 'i>(
    cx: &Ctx,
    h: &Header<'a, 'i>,
) -> Result<(HashMap<String, Node<'a, 'i>>, Vec<String>), ModelError> {
    let mut bodies: HashMap<String, Node> = HashMap::new();
    let mut body_order: Vec<String> = Vec::new();
    for b in &objects(child(h.model, "BodySet")) {
        if b.tag_name().name() != "Body" {
            return err(format!(
                "{} in the BodySet is not a Body; mx reads OpenSim Body elements only",
                cx.at(*b)
            ));
        }
        let n = name_of(*b);
        if n.is_empty() {
            return err(format!("{} has no name", cx.at(*b)));
        }
        if h.v3 && n == h.ground {
            continue;
        }
        if bodies.insert(n.clone(), *b).is_some() {
            return err(format!("two bodies are named '{n}' ({})", cx.at(*b)));
        }
        body_order.push(n);
    }
    Ok((bodies, body_order))
}

/// Every joint with its frames placed, in the file's order; a body that is the
/// child of two joints is an error (mx reads trees).
fn read_joints<'a, 'i>(
    cx: &Ctx,
    h: &Header<'a, 'i>,
    bodies: &HashMap<String, Node<'a, 'i>>,
    frames: &Frames<'a, 'i>,
    joint_nodes: &[Node<'a, 'i>],
) -> Result<Vec<JointDecl<'a, 'i>>, ModelError> {
    let mut joints: Vec<JointDecl> = Vec::new();
    let mut child_of: HashMap<String, String> = HashMap::new();
    for j in joint_nodes {
        let name = name_of(*j);
        let what = format!("joint '{name}' ({})", cx.at(*j));
        let (parent, (cb, child_frame)) = if h.v3 {
            let pose = |o: &str, t: &str| -> Result<Se3, ModelError> {
                let o = vec3(cx, *j, o)?;
                Ok(Se3::new(body_fixed_xyz([o.x, o.y, o.z]), vec3(cx, *j, t)?))
            };
            let Some(pb) = text(*j, "parent_body") else {
                return err(format!("{what} has no <parent_body>"));
            };
            let parent = match pb {
                p if p == h.ground => (None, pose("orientation_in_parent", "location_in_parent")?),
                p if bodies.contains_key(p) => (
                    Some(p.to_string()),
                    pose("orientation_in_parent", "location_in_parent")?,
                ),
                p => {
                    return err(format!(
                        "{what}: parent body '{p}' is not a body of the model"
                    ));
                }
            };
            let body = j.ancestors().find(|a| a.has_tag_name("Body")).map(name_of);
            (parent, (body, pose("orientation", "location")?))
        } else {
            let local: Vec<Node> = child(*j, "frames")
                .map(|f| {
                    elements(f)
                        .filter(|x| x.has_tag_name("PhysicalOffsetFrame"))
                        .collect()
                })
                .unwrap_or_default();
            let (Some(pp), Some(cp)) = (
                text(*j, "socket_parent_frame"),
                text(*j, "socket_child_frame"),
            ) else {
                return err(format!(
                    "{what} needs <socket_parent_frame> and <socket_child_frame>"
                ));
            };
            (
                frames.resolve(cx, pp, &local, 0, &what)?,
                frames.resolve(cx, cp, &local, 0, &what)?,
            )
        };
        let cp = "its child frame";
        let Some(child_body) = cb else {
            return err(format!(
                "{what}: the child frame '{cp}' is on ground; ground cannot move"
            ));
        };
        if let Some(prev) = child_of.insert(child_body.clone(), name.clone()) {
            return err(format!(
                "{what}: body '{child_body}' is already the child of joint '{prev}'; mx reads trees (a closed loop needs a constraint)"
            ));
        }
        joints.push(JointDecl {
            node: *j,
            name,
            parent,
            child_body,
            child_frame,
            reversed: h.v3 && flag(*j, "reverse"),
        });
    }
    Ok(joints)
}

/// The joints reordered so that each comes after the joint of its parent body:
/// the file's order wherever it allows (OpenSim's CoordinateSet order whenever
/// the JointSet lists parents first).
fn parents_first<'a, 'i>(
    cx: &Ctx,
    joints: Vec<JointDecl<'a, 'i>>,
) -> Result<Vec<JointDecl<'a, 'i>>, ModelError> {
    let mut order: Vec<usize> = Vec::with_capacity(joints.len());
    let mut placed: HashMap<&str, ()> = HashMap::new();
    let mut done = vec![false; joints.len()];
    while order.len() < joints.len() {
        let next = (0..joints.len()).find(|&k| {
            !done[k]
                && match &joints[k].parent.0 {
                    None => true,
                    Some(p) => placed.contains_key(p.as_str()),
                }
        });
        let Some(k) = next else {
            let k = (0..joints.len())
                .find(|&k| !done[k])
                .expect("some joint is left");
            return err(format!(
                "joint '{}' ({}) hangs from body '{}', which no joint connects to ground (the joints form a loop)",
                joints[k].name,
                cx.at(joints[k].node),
                joints[k].parent.0.as_deref().unwrap_or("?")
            ));
        };
        done[k] = true;
        placed.insert(joints[k].child_body.as_str(), ());
        order.push(k);
    }
    let mut slots: Vec<Option<JointDecl>> = joints.into_iter().map(Some).collect();
    Ok(order
        .into_iter()
        .map(|k| slots[k].take().expect("each joint is placed once"))
        .collect())
}
