//! Whole OpenSim models (`.osim`: OpenSim 4 files, and 3.x files whose
//! joints sit inside their child bodies) as a [`Model`].
//!
//! Each OpenSim body is one link whose frame is the body frame. A joint
//! between parent frame F (on the parent body P) and child frame M (on the
//! child body B) places B at `T_P_F · T_F_M(q) · T_B_M⁻¹`: the link offset is
//! `T_P_F` (offset frames composed exactly, chains of PhysicalOffsetFrames
//! included) and the joint carries `T_F_M(q) · T_B_M⁻¹`. Every joint type is
//! parametrised as OpenSim (Simbody) does, with the coordinates' speeds equal
//! to q̇ — except BallJoint and FreeJoint, whose OpenSim speeds are angular
//! velocities: mx uses q̇ of the same body-fixed X-Y-Z angles (the same
//! configurations; OpenSim's M_u = Nᵀ M_q N with q̇ = N u).
//!
//! | OpenSim | T_F_M(q) |
//! | --- | --- |
//! | CustomJoint | R = Rot(f1, a1)·Rot(f2, a2)·Rot(f3, a3), t = g1 b1 + g2 b2 + g3 b3 |
//! | PinJoint | Rz(q) |
//! | SliderJoint | translation q along x |
//! | UniversalJoint | Rx(q1)·Ry(q2) |
//! | GimbalJoint, BallJoint | Rx(q1)·Ry(q2)·Rz(q3) |
//! | FreeJoint | Rx(q1)·Ry(q2)·Rz(q3), t = (q4, q5, q6) in F |
//! | PlanarJoint | Rz(q1), t = (q2, q3, 0) in F |
//! | WeldJoint | identity |
//!
//! A reversed OpenSim 3.x joint (`<reverse>true</reverse>`) is what OpenSim
//! 4's updater makes of it: parent and child frames swapped, so between the
//! same two frames the joint carries T_F_M(q)⁻¹ (`FunctionJoint::reversed`).
//!
//! Links follow the JointSet's order (a joint whose parent body has no joint
//! yet waits until it has), coordinates each joint's own order: OpenSim's
//! CoordinateSet order whenever the JointSet lists parents first.
//! Forces, muscles, contact, markers, controllers, probes and geometry are not
//! dynamics mx simulates: they are counted in the report, never an error.

use std::collections::HashMap;
use std::sync::Arc;

use nalgebra::{Matrix3, Vector3};
use roxmltree::{Document, Node};

use crate::lie::Se3;
use crate::model::body::Inertia;
use crate::model::coupling::{Coupling, Follower};
use crate::model::files::osim_joint::function_from_xml;
use crate::model::joint::{Joint, Limit};
use crate::model::joints::function_based::body_fixed_xyz;
use crate::model::joints::{
    Fixed, FunctionJoint, Prismatic, Revolute, ScalarFunction, TransformAxis,
};
use crate::model::tree::{Model, ModelError};

/// How a coordinate moves (`.mot` files give rotational ones in degrees).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MotionType {
    Rotational,
    Translational,
    /// Used by both rotation and translation axes of a CustomJoint.
    Coupled,
}

/// One coordinate as the file states it.
#[derive(Debug, Clone, PartialEq)]
pub struct OsimCoordinate {
    pub name: String,
    pub joint: String,
    pub motion: MotionType,
    pub range: Limit,
    pub default_value: f64,
    pub default_speed: f64,
    pub clamped: bool,
    pub locked: bool,
}

/// A `CoordinateCouplerConstraint`: `dependent = function(independent)`.
#[derive(Debug, Clone, PartialEq)]
pub struct Coupler {
    pub name: String,
    pub dependent: String,
    pub independent: String,
    pub function: ScalarFunction,
}

/// What loading found beside the kinematic tree.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct OsimReport {
    /// The document's `Version` attribute (e.g. 40000).
    pub version: u32,
    /// In model coordinate order.
    pub coordinates: Vec<OsimCoordinate>,
    pub couplers: Vec<Coupler>,
    /// Whether the body the model became follows the couplers (set by whoever
    /// builds it from [`OsimModel::coupling`]; the report's text says which).
    pub couplers_enforced: bool,
    /// What mx does not simulate, counted: ("muscles", "Thelen2003Muscle", 92), …
    pub ignored: Vec<(String, String, usize)>,
    pub warnings: Vec<String>,
}

impl OsimReport {
    /// The coordinate named `name`.
    pub fn coordinate(&self, name: &str) -> Option<&OsimCoordinate> {
        self.coordinates.iter().find(|c| c.name == name)
    }

    /// A few lines for people: what was loaded, what was ignored, warnings.
    pub fn text(&self, model: &Model) -> String {
        let mut s = format!(
            "OpenSim model {} (format {}): {} bodies, {} coordinates, {:.3} kg, gravity [{}, {}, {}]\n",
            model.name,
            self.version,
            model.num_links(),
            model.nq(),
            model.total_mass(),
            model.default_gravity.x,
            model.default_gravity.y,
            model.default_gravity.z
        );
        let locked: Vec<&str> = self
            .coordinates
            .iter()
            .filter(|c| c.locked)
            .map(|c| c.name.as_str())
            .collect();
        if !locked.is_empty() {
            s += &format!(
                "locked in the file (mx keeps them as free coordinates; hold them with `driven:`): {}\n",
                locked.join(", ")
            );
        }
        for c in &self.couplers {
            s += &if self.couplers_enforced {
                format!(
                    "coupled coordinate: {} = f({}) ({}), enforced: {} is no coordinate of the body\n",
                    c.dependent, c.independent, c.name, c.dependent
                )
            } else {
                format!(
                    "coupled coordinate: {} = f({}) ({}), not enforced: {} stays a free coordinate, as in OpenSim's calcM\n",
                    c.dependent, c.independent, c.name, c.dependent
                )
            };
        }
        let mut by_what: Vec<(String, Vec<String>, usize)> = Vec::new();
        for (what, kind, n) in &self.ignored {
            match by_what.iter_mut().find(|(w, _, _)| w == what) {
                Some(e) => {
                    e.1.push(format!("{n} {kind}"));
                    e.2 += n;
                }
                None => by_what.push((what.clone(), vec![format!("{n} {kind}")], *n)),
            }
        }
        for (what, kinds, n) in by_what {
            s += &format!("{n} {what} ignored ({})\n", kinds.join(", "));
        }
        for w in &self.warnings {
            s += &format!("warning: {w}\n");
        }
        s
    }
}

/// A model read from `.osim` with its report.
#[derive(Debug, Clone)]
pub struct OsimModel {
    pub model: Model,
    pub report: OsimReport,
}

impl OsimModel {
    /// The CoordinateCouplerConstraints as coupled coordinates
    /// (dependent = f(independent)); `None` when the model has none. A
    /// dependent coordinate that another coupler reads, or one coupled twice,
    /// is an error naming the couplers.
    pub fn coupling(&self) -> Result<Option<Coupling>, ModelError> {
        if self.report.couplers.is_empty() {
            return Ok(None);
        }
        let index = |n: &str| {
            self.model
                .coordinate_index(n)
                .expect("couplers name model coordinates (checked on reading)")
        };
        let followers: Vec<Follower> = self
            .report
            .couplers
            .iter()
            .map(|c| Follower {
                coordinate: index(&c.dependent),
                source: index(&c.independent),
                function: c.function.clone(),
            })
            .collect();
        let names: Vec<&str> = self
            .report
            .couplers
            .iter()
            .map(|c| c.name.as_str())
            .collect();
        Coupling::new(&self.model, &followers)
            .map(Some)
            .map_err(|e| {
                ModelError::Invalid(format!(
                    "the CoordinateCouplerConstraints ({}) cannot be enforced: {e}",
                    names.join(", ")
                ))
            })
    }
}

fn err<T>(msg: impl Into<String>) -> Result<T, ModelError> {
    Err(ModelError::Invalid(msg.into()))
}

struct Ctx<'a, 'i> {
    doc: &'a Document<'i>,
}

impl<'a, 'i> Ctx<'a, 'i> {
    fn line(&self, n: Node) -> u32 {
        self.doc.text_pos_at(n.range().start).row
    }
    fn at(&self, n: Node) -> String {
        format!("<{}> at line {}", n.tag_name().name(), self.line(n))
    }
}

fn child<'a, 'i>(n: Node<'a, 'i>, tag: &str) -> Option<Node<'a, 'i>> {
    n.children()
        .find(|c| c.is_element() && c.tag_name().name() == tag)
}

fn elements<'a, 'i>(n: Node<'a, 'i>) -> impl Iterator<Item = Node<'a, 'i>> {
    n.children().filter(|c| c.is_element())
}

/// The `<objects>` of a set (`<BodySet><objects>…`), or nothing.
fn objects<'a, 'i>(n: Option<Node<'a, 'i>>) -> Vec<Node<'a, 'i>> {
    n.and_then(|s| child(s, "objects"))
        .map(|o| elements(o).collect())
        .unwrap_or_default()
}

/// 3.x: the joint element inside a body's `<Joint>` (none for ground).
fn joint_of_body<'a, 'i>(b: Node<'a, 'i>) -> Option<Node<'a, 'i>> {
    child(b, "Joint").and_then(|j| elements(j).next())
}

fn text<'a>(n: Node<'a, '_>, tag: &str) -> Option<&'a str> {
    child(n, tag).map(|c| c.text().unwrap_or("").trim())
}

fn nums(cx: &Ctx, n: Node, tag: &str, default: &str) -> Result<Vec<f64>, ModelError> {
    let t = text(n, tag).unwrap_or(default);
    t.split_whitespace()
        .map(|w| {
            w.parse::<f64>().map_err(|_| {
                ModelError::Invalid(format!("<{tag}> of {}: '{w}' is not a number", cx.at(n)))
            })
        })
        .collect()
}

fn num(cx: &Ctx, n: Node, tag: &str, default: f64) -> Result<f64, ModelError> {
    match nums(cx, n, tag, "")?.as_slice() {
        [] => Ok(default),
        [x] => Ok(*x),
        many => err(format!(
            "<{tag}> of {} holds {} numbers; expected one",
            cx.at(n),
            many.len()
        )),
    }
}

fn vec3(cx: &Ctx, n: Node, tag: &str) -> Result<Vector3<f64>, ModelError> {
    let v = nums(cx, n, tag, "0 0 0")?;
    if v.len() != 3 {
        return err(format!(
            "<{tag}> of {} must hold 3 numbers, not {}",
            cx.at(n),
            v.len()
        ));
    }
    Ok(Vector3::new(v[0], v[1], v[2]))
}

fn flag(n: Node, tag: &str) -> bool {
    text(n, tag).is_some_and(|t| t.eq_ignore_ascii_case("true"))
}

fn name_of(n: Node) -> String {
    n.attribute("name").unwrap_or("").to_string()
}

/// The last component of a socket path (`/bodyset/femur_r` → `femur_r`).
fn last(path: &str) -> &str {
    path.trim_end_matches('/')
        .rsplit('/')
        .next()
        .unwrap_or(path)
}

/// Where a frame is: on `body` (`None` = ground) at `T_body_frame`.
type Placed = (Option<String>, Se3);

struct Frames<'a, 'i> {
    ground: String,
    bodies: HashMap<String, ()>,
    /// PhysicalOffsetFrames owned by bodies, ground or the model (not joints), by name.
    free: HashMap<String, Vec<Node<'a, 'i>>>,
}

impl<'a, 'i> Frames<'a, 'i> {
    fn resolve(
        &self,
        cx: &Ctx,
        path: &str,
        local: &[Node<'a, 'i>],
        depth: usize,
        what: &str,
    ) -> Result<Placed, ModelError> {
        if depth > 32 {
            return err(format!(
                "{what}: the offset frames around '{path}' form a cycle"
            ));
        }
        let name = last(path);
        let frame = local
            .iter()
            .find(|f| f.attribute("name") == Some(name))
            .copied();
        if frame.is_none() && (name == self.ground || path == "/ground") {
            return Ok((None, Se3::identity()));
        }
        if frame.is_none() && self.bodies.contains_key(name) {
            return Ok((Some(name.to_string()), Se3::identity()));
        }
        let frame = match (frame, self.free.get(name).map(Vec::as_slice)) {
            (Some(f), _) => f,
            (None, Some([f])) => *f,
            (None, Some(many)) if !many.is_empty() => {
                return err(format!(
                    "{what}: frame '{path}' is ambiguous: {} offset frames are named '{name}'",
                    many.len()
                ));
            }
            _ => {
                return err(format!(
                    "{what}: frame '{path}' names no body, ground or offset frame of the model"
                ));
            }
        };
        let Some(parent) = text(frame, "socket_parent") else {
            return err(format!(
                "{what}: offset frame '{name}' ({}) has no <socket_parent>",
                cx.at(frame)
            ));
        };
        let o = vec3(cx, frame, "orientation")?;
        let local_t = Se3::new(
            body_fixed_xyz([o.x, o.y, o.z]),
            vec3(cx, frame, "translation")?,
        );
        // A frame's parent is named relative to it: a sibling of the same owner or a full path.
        let (body, t) = self.resolve(cx, parent, local, depth + 1, what)?;
        Ok((body, t.compose(&local_t)))
    }
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
fn pad(given: Vec<TransformAxis>) -> [TransformAxis; 3] {
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

impl Model {
    /// Reads an OpenSim model file.
    pub fn from_osim_file(path: impl AsRef<std::path::Path>) -> Result<OsimModel, ModelError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path)
            .map_err(|e| ModelError::Invalid(format!("cannot read `{}`: {e}", path.display())))?;
        Self::from_osim_str(&text).map_err(|e| match e {
            ModelError::Invalid(m) => ModelError::Invalid(format!("{}: {m}", path.display())),
            other => other,
        })
    }

    /// Parses OpenSim model XML.
    pub fn from_osim_str(xml: &str) -> Result<OsimModel, ModelError> {
        let doc = Document::parse(xml).map_err(|e| {
            ModelError::Invalid(format!(
                "not a well-formed OpenSim model (invalid XML: {e})"
            ))
        })?;
        read(&doc)
    }
}

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

// One pass over the document in the file's phases (`// ---- bodies`, `joints`,
// `build`); a joint's coordinates and transform axes, the constraints and what
// mx does not simulate are read by the functions below it.
fn read(doc: &Document) -> Result<OsimModel, ModelError> {
    let cx = Ctx { doc };
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
        Some(_) => vec3(&cx, m, "gravity")?,
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

    // ---- bodies and free-standing offset frames ----
    let body_nodes = objects(child(m, "BodySet"));
    let mut bodies: HashMap<String, Node> = HashMap::new();
    let mut body_order: Vec<String> = Vec::new();
    for b in &body_nodes {
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
        if v3 && n == ground {
            continue;
        }
        if bodies.insert(n.clone(), *b).is_some() {
            return err(format!("two bodies are named '{n}' ({})", cx.at(*b)));
        }
        body_order.push(n);
    }
    let joint_nodes: Vec<Node> = if v3 {
        body_order
            .iter()
            .filter_map(|b| joint_of_body(bodies[b]))
            .collect()
    } else {
        objects(child(m, "JointSet"))
    };
    let mut free: HashMap<String, Vec<Node>> = HashMap::new();
    for f in m
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
        ground: ground.clone(),
        bodies: bodies.keys().map(|k| (k.clone(), ())).collect(),
        free,
    };

    // ---- joints: parse, then order parents first ----
    struct J<'a, 'i> {
        node: Node<'a, 'i>,
        name: String,
        parent: Placed,
        child_body: String,
        child_frame: Se3,
        /// A 3.x `<reverse>true</reverse>`: T_F_M(q)⁻¹ between the same frames.
        reversed: bool,
    }
    let mut joints: Vec<J> = Vec::new();
    let mut child_of: HashMap<String, String> = HashMap::new();
    for j in &joint_nodes {
        let name = name_of(*j);
        let what = format!("joint '{name}' ({})", cx.at(*j));
        let (parent, (cb, child_frame)) = if v3 {
            let pose = |o: &str, t: &str| -> Result<Se3, ModelError> {
                let o = vec3(&cx, *j, o)?;
                Ok(Se3::new(body_fixed_xyz([o.x, o.y, o.z]), vec3(&cx, *j, t)?))
            };
            let Some(pb) = text(*j, "parent_body") else {
                return err(format!("{what} has no <parent_body>"));
            };
            let parent = match pb {
                p if p == ground => (None, pose("orientation_in_parent", "location_in_parent")?),
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
                frames.resolve(&cx, pp, &local, 0, &what)?,
                frames.resolve(&cx, cp, &local, 0, &what)?,
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
        joints.push(J {
            node: *j,
            name,
            parent,
            child_body,
            child_frame,
            reversed: v3 && flag(*j, "reverse"),
        });
    }
    for b in &body_order {
        if !child_of.contains_key(b) {
            return err(format!(
                "body '{b}' ({}) has no joint; OpenSim would give it a free joint to ground — add one",
                cx.at(bodies[b])
            ));
        }
    }
    let mut order: Vec<usize> = Vec::with_capacity(joints.len());
    let mut placed: HashMap<String, usize> = HashMap::new(); // body → link index
    let mut done = vec![false; joints.len()];
    while order.len() < joints.len() {
        let next = (0..joints.len()).find(|&k| {
            !done[k]
                && match &joints[k].parent.0 {
                    None => true,
                    Some(p) => placed.contains_key(p),
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
        placed.insert(joints[k].child_body.clone(), order.len());
        order.push(k);
    }

    // ---- build ----
    let model_name = m.attribute("name").unwrap_or("opensim");
    let mut model = Model::new(model_name);
    model.default_gravity = gravity;
    let mut names: Vec<String> = Vec::new();
    for &k in &order {
        let j = &joints[k];
        let what = format!("joint '{}' ({})", j.name, cx.at(j.node));
        let kind = j.node.tag_name().name();
        let mut coords = read_coordinates(&cx, j.node, &j.name, &what, v3, &names)?;
        let cnames: Vec<String> = coords.iter().map(|c| c.name.clone()).collect();
        let limits: Vec<Limit> = coords.iter().map(|c| c.range).collect();
        let (rot, tr) = if kind == "CustomJoint" {
            spatial_transform(&cx, j.node, &what, &mut coords)?
        } else {
            standard_transform(kind, &what, &mut coords)?
        };
        let parent_link = j.parent.0.as_ref().map(|p| placed[p]);
        let offset = j.parent.1;
        let child_identity = j.child_frame == Se3::identity();
        let joint: Arc<dyn Joint> = match kind {
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
                    cnames.clone(),
                    pad(rot),
                    pad(tr),
                    Se3::identity(),
                    j.child_frame,
                )
                .map_err(|e| ModelError::Invalid(format!("{what}: {}", e.0)))
                .map(|fj| if j.reversed { fj.reversed() } else { fj })?
                .with_limits(limits.clone()),
            ),
        };
        let inertia = inertia_of(&cx, bodies[&j.child_body])?;
        model.add_link(&j.child_body, parent_link, &j.name, joint, offset, inertia)?;
        names.extend(cnames);
        report.coordinates.extend(coords);
    }
    model.set_coordinate_names(names)?;

    // ---- constraints, and what mx does not simulate ----
    read_constraints(&cx, m, &model, &mut report)?;
    count_ignored(m, &mut report);
    Ok(OsimModel { model, report })
}

/// A joint's coordinates as the file states them (OpenSim 4 `coordinates`,
/// 3.x `CoordinateSet/objects`); a name already in `names` is an error.
fn read_coordinates(
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
fn spatial_transform(
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
fn standard_transform(
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
fn read_constraints(
    cx: &Ctx,
    m: Node,
    model: &Model,
    report: &mut OsimReport,
) -> Result<(), ModelError> {
    for c in objects(child(m, "ConstraintSet")) {
        let t = c.tag_name().name();
        let cname = name_of(c);
        let enforced = text(c, "isEnforced")
            .or_else(|| text(c, "isDisabled").map(|d| if d == "true" { "false" } else { "true" }))
            .is_none_or(|v| v != "false");
        if !enforced {
            report.warnings.push(format!(
                "constraint '{cname}' ({}) is not enforced; ignored",
                cx.at(c)
            ));
            continue;
        }
        if t != "CoordinateCouplerConstraint" {
            return err(format!(
                "constraint '{cname}' ({}) is a {t}, which changes the kinematics and which mx does not read; mx reads CoordinateCouplerConstraint",
                cx.at(c)
            ));
        }
        let what = format!("CoordinateCouplerConstraint '{cname}' ({})", cx.at(c));
        let ind: Vec<&str> = text(c, "independent_coordinate_names")
            .unwrap_or("")
            .split_whitespace()
            .collect();
        let dep = text(c, "dependent_coordinate_name")
            .unwrap_or("")
            .to_string();
        let [ind] = ind.as_slice() else {
            return err(format!(
                "{what} couples {} independent coordinates; mx reads couplers of one",
                ind.len()
            ));
        };
        for n in [*ind, dep.as_str()] {
            if model.coordinate_index(n).is_none() {
                return err(format!(
                    "{what} names coordinate '{n}', which the model does not have"
                ));
            }
        }
        let f = child(c, "coupled_coordinates_function")
            .and_then(|f| elements(f).next())
            .ok_or_else(|| {
                ModelError::Invalid(format!("{what} has no <coupled_coordinates_function>"))
            })?;
        let function = function_from_xml(f)
            .map_err(|m| ModelError::Invalid(format!("{what}, {}: {}", cx.at(f), m.0)))?;
        report.couplers.push(Coupler {
            name: cname,
            dependent: dep,
            independent: ind.to_string(),
            function,
        });
    }

    Ok(())
}

/// Counts what mx does not simulate (forces, markers, geometry, …) into the report.
fn count_ignored(m: Node, report: &mut OsimReport) {
    let mut count = |what: &str, kind: &str| match report
        .ignored
        .iter_mut()
        .find(|(w, k, _)| w == what && k == kind)
    {
        Some(e) => e.2 += 1,
        None => report.ignored.push((what.into(), kind.into(), 1)),
    };
    for f in objects(child(m, "ForceSet")) {
        let k = f.tag_name().name();
        let what = if k.ends_with("Muscle") || k.contains("Muscle") {
            "muscles"
        } else if k.ends_with("Actuator") {
            "actuators"
        } else if k.contains("Contact") || k.contains("HuntCrossley") || k.contains("Elastic") {
            "contact forces"
        } else {
            "forces"
        };
        count(what, k);
    }
    for (set, what) in [
        ("MarkerSet", "markers"),
        ("ContactGeometrySet", "contact geometry"),
        ("ControllerSet", "controllers"),
        ("ProbeSet", "probes"),
    ] {
        for x in objects(child(m, set)) {
            count(what, x.tag_name().name());
        }
    }
    for g in m.descendants().filter(|n| {
        n.is_element()
            && n.parent()
                .is_some_and(|p| p.has_tag_name("attached_geometry"))
    }) {
        count("geometry", g.tag_name().name());
    }
    for w in m.descendants().filter(|n| {
        n.parent().is_some_and(|p| p.has_tag_name("objects"))
            && n.ancestors().any(|a| a.has_tag_name("WrapObjectSet"))
    }) {
        count("wrap objects", w.tag_name().name());
    }
}
