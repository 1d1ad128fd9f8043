//! Bodies written in mx: `link(...)` describes one link the way Pinocchio and
//! OpenSim users think of it (a name, its parent by name, the joint that
//! carries it, the joint frame's fixed placement in the parent, mass, centre
//! of mass and inertia about the centre of mass), and `body([...])` checks the
//! links form a tree and builds the same `Body` value URDF loading gives.

use std::sync::Arc;

use indexmap::IndexMap;
use nalgebra::{Matrix3, Rotation3, Vector3};

use crate::lang::args::{ArgValue, Args};
use crate::lang::diagnostics::{ErrorKind, MxError, MxResult};
use crate::lang::host::errors::diagnostic;
use crate::lang::host::{Body, JointValue};
use crate::lang::registry::Registry;
use crate::lang::topic::Topic;
use crate::lang::value::{HostObject, Value};
use crate::lie::Se3;
use crate::model::joint::Joint;
use crate::model::link_tree::{TreeError, TreeJoint, tree_order};
use crate::model::{Inertia, Model, ModelError};

/// One link description, checked on its own (the tree is checked by `body`).
#[derive(Clone, Debug)]
pub struct LinkSpec {
    pub name: String,
    /// `None`: attached to the world.
    pub parent: Option<String>,
    pub joint: Arc<dyn Joint>,
    pub joint_name: String,
    pub offset: Se3,
    pub inertia: Inertia,
}

impl HostObject for LinkSpec {
    fn type_name(&self) -> &'static str {
        "Link"
    }
    fn summary(&self) -> String {
        format!(
            "<link {} on {} ({} joint, {} kg)>",
            self.name,
            self.parent.as_deref().unwrap_or("world"),
            self.joint.kind(),
            self.inertia.mass
        )
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
    fn field_names(&self) -> &'static [&'static str] {
        &["name", "parent", "mass"]
    }
    fn read_field(&self, name: &str) -> Option<Value> {
        match name {
            "name" => Some(Value::str(&self.name)),
            "parent" => Some(Value::str(self.parent.as_deref().unwrap_or("world"))),
            "mass" => Some(Value::Number(self.inertia.mass)),
            _ => None,
        }
    }
}

fn numbers_of(v: &Value) -> Option<Vec<f64>> {
    v.as_list()?
        .iter()
        .map(|x| x.as_number().filter(|x| x.is_finite()))
        .collect()
}

fn vec3_arg(a: &Args, name: &str, arg: &ArgValue) -> MxResult<Vector3<f64>> {
    a.vec3_of(name, arg, "a list of 3 finite numbers")
}

/// `offset:` as a translation [x, y, z] or a 4×4 transform; `rpy:` (URDF's
/// fixed-axis roll, pitch, yaw: R = Rz(y) Ry(p) Rx(r)) rotates it.
fn offset(a: &mut Args) -> MxResult<Se3> {
    let mut t = match a.opt_named("offset") {
        None => Se3::identity(),
        Some(arg) => match arg.value.as_list().map(|l| l.len()) {
            Some(3) if numbers_of(&arg.value).is_some() => {
                Se3::from_translation(vec3_arg(a, "offset", &arg)?)
            }
            Some(4) => a.transform_of("offset", &arg)?,
            _ => {
                return Err(a.type_error(
                    "offset",
                    "a translation [x, y, z] or a 4×4 transform",
                    &arg,
                ));
            }
        },
    };
    if let Some(arg) = a.opt_named("rpy") {
        let r = vec3_arg(a, "rpy", &arg)?;
        t.r *= Rotation3::from_euler_angles(r.x, r.y, r.z).into_inner();
    }
    Ok(t)
}

/// Inertia about the centre of mass: [ixx, iyy, izz] or a 3×3 matrix; must be
/// symmetric positive definite and satisfy the triangle inequality (a real body).
fn inertia_matrix(a: &Args, arg: &ArgValue) -> MxResult<Matrix3<f64>> {
    let bad = || {
        a.type_error(
            "inertia",
            "[ixx, iyy, izz] or a 3×3 matrix (kg·m², about the centre of mass)",
            arg,
        )
    };
    let l = arg.value.as_list().ok_or_else(bad)?;
    let m = if let Some(d) = numbers_of(&arg.value) {
        if d.len() != 3 {
            return Err(bad());
        }
        Matrix3::from_diagonal(&Vector3::new(d[0], d[1], d[2]))
    } else {
        let rows: Option<Vec<Vec<f64>>> = l.iter().map(numbers_of).collect();
        match rows {
            Some(r) if r.len() == 3 && r.iter().all(|r| r.len() == 3) => {
                Matrix3::from_fn(|i, j| r[i][j])
            }
            _ => return Err(bad()),
        }
    };
    let fail = |msg: String| {
        MxError::value(format!("`link`: {msg}")).at(arg.span).help(
            "inertia about the centre of mass, e.g. a 1 kg, 10 cm cube: [1/600, 1/600, 1/600]",
        )
    };
    let asym = (m - m.transpose()).abs().max();
    if asym > 1e-9 * (1.0 + m.abs().max()) {
        return Err(fail(format!(
            "the inertia matrix is not symmetric (mismatch {asym:.1e})"
        )));
    }
    let eig = m.symmetric_eigenvalues();
    let (lo, hi) = (eig.min(), eig.max());
    if lo <= 1e-12 * hi.max(1e-300) || lo <= 0.0 {
        return Err(fail(format!(
            "the inertia must be positive definite; its principal moments are {:.3e}, {:.3e}, {:.3e} (leave `inertia` out for a point mass)",
            eig[0], eig[1], eig[2]
        )));
    }
    let mut e = [eig[0], eig[1], eig[2]];
    e.sort_by(f64::total_cmp);
    if e[0] + e[1] < e[2] * (1.0 - 1e-9) {
        return Err(fail(format!(
            "no rigid body has principal moments {:.3e}, {:.3e}, {:.3e}: the two smaller must add up to at least the largest",
            e[0], e[1], e[2]
        )));
    }
    Ok(m)
}

fn make_link(a: &mut Args) -> MxResult<Value> {
    let name = a.string("name")?.to_string();
    if name.is_empty() || name == "world" {
        return Err(a.error(
            ErrorKind::Value,
            format!("a link cannot be named `{name}`; choose a name other than \"world\""),
        ));
    }
    let parent = match a.opt_named("parent") {
        None => None,
        Some(p) => match &p.value {
            Value::Nil => None,
            Value::Str(s) if &**s == "world" => None,
            Value::Str(s) => Some(s.to_string()),
            _ => return Err(a.type_error("parent", "a link name or \"world\"", &p)),
        },
    };
    let joint = a.object::<JointValue>("joint", "a joint (e.g. revolute([0, 0, 1]))")?;
    let joint = joint.joint.clone();
    let joint_name = match a.opt_named("joint_name") {
        None => name.clone(),
        Some(j) => match &j.value {
            Value::Str(s) if !s.is_empty() => s.to_string(),
            _ => return Err(a.type_error("joint_name", "a non-empty string", &j)),
        },
    };
    let offset = offset(a)?;
    let marg = a.arg("mass")?;
    let mass = match marg.value.as_number() {
        Some(m) if m.is_finite() && m > 0.0 => m,
        Some(m) => {
            return Err(MxError::value(format!(
                "`link`: the mass of `{name}` must be a finite number > 0 kg, got {m}"
            ))
            .at(marg.span)
            .help(
                "every link needs mass; a massless frame can be folded into its neighbour's offset",
            ));
        }
        None => return Err(a.type_error("mass", "a number (kg)", &marg)),
    };
    let com = match a.opt_named("com") {
        Some(c) => vec3_arg(a, "com", &c)?,
        None => Vector3::zeros(),
    };
    let i_com = match a.opt_named("inertia") {
        Some(i) => inertia_matrix(a, &i)?,
        None => Matrix3::zeros(),
    };
    let inertia =
        Inertia::from_com(mass, com, i_com).map_err(|e| diagnostic(&e, a, a.call_span()))?;
    Ok(Value::object(LinkSpec {
        name,
        parent,
        joint,
        joint_name,
        offset,
        inertia,
    }))
}

/// A model from link descriptions (any order; parents are placed first), the
/// tree checked by `model::link_tree` as a URDF's is.
pub fn model_from_links(
    name: &str,
    links: &[LinkSpec],
    gravity: Vector3<f64>,
) -> Result<Model, ModelError> {
    if links.is_empty() {
        return Err(ModelError::Invalid("a body needs at least one link".into()));
    }
    let names: Vec<&str> = links.iter().map(|l| l.name.as_str()).collect();
    let joints: Vec<TreeJoint> = links
        .iter()
        .map(|l| TreeJoint {
            name: &l.joint_name,
            parent: l.parent.as_deref(),
            child: &l.name,
        })
        .collect();
    let order = tree_order(&names, &joints)?;
    let mut m = Model::new(name);
    m.default_gravity = gravity;
    let mut placed: IndexMap<&str, usize> = IndexMap::new();
    for &i in &order {
        let l = &links[i];
        let parent = l.parent.as_deref().map(|p| placed[p]);
        let idx = m.add_link(
            &l.name,
            parent,
            &l.joint_name,
            l.joint.clone(),
            l.offset,
            l.inertia,
        )?;
        placed.insert(&l.name, idx);
    }
    Ok(m)
}

/// What to do about links that are not a tree, in the language's words.
fn tree_advice(e: &ModelError) -> Option<&'static str> {
    match e {
        ModelError::Tree(TreeError::DuplicateJoint(_)) => Some(
            "a joint is named after its link unless `joint_name:` says otherwise; joint names must be unique",
        ),
        ModelError::Tree(TreeError::UnknownLink { .. }) => {
            Some("a link's `parent:` names another link of the body, or \"world\" for the ground")
        }
        _ => None,
    }
}

fn make_body(a: &mut Args) -> MxResult<Value> {
    let larg = a.arg("links")?;
    let Some(list) = larg.value.as_list() else {
        return Err(a.type_error("links", "a list of link(...) values", &larg));
    };
    let mut links = Vec::with_capacity(list.len());
    for (k, v) in list.iter().enumerate() {
        match v.as_object::<LinkSpec>() {
            Some(l) => links.push(l.clone()),
            None => {
                return Err(MxError::type_error(format!(
                    "`body`: element {k} of `links` is {}, not a link(...)",
                    v.type_name()
                ))
                .at(larg.span)
                .help("usage: body([link(\"arm\", parent: \"world\", joint: revolute([0, 0, 1]), mass: 1), …])"));
            }
        }
    }
    let name = match a.opt_named("name") {
        Some(n) => match &n.value {
            Value::Str(s) => s.to_string(),
            _ => return Err(a.type_error("name", "a string", &n)),
        },
        None => "body".to_string(),
    };
    let gravity = match a.opt_named("gravity") {
        Some(g) => vec3_arg(a, "gravity", &g)?,
        None => Vector3::new(0.0, 0.0, -9.81),
    };
    let m = model_from_links(&name, &links, gravity).map_err(|e| {
        let err = MxError::value(format!("`body`: {e}")).at(larg.span);
        match tree_advice(&e) {
            Some(h) => err.help(h),
            None => err,
        }
    })?;
    Ok(Value::object(Body::from_model(Arc::new(m))))
}

pub fn register(reg: &mut Registry) {
    reg.topic(Topic::Dynamics);
    reg.add(
        "link(name, parent: \"world\", joint: j, offset: [x, y, z], rpy: [r, p, y], mass: m, com: [0, 0, 0], inertia: [ixx, iyy, izz], joint_name: name)",
        "One link of a body: carried by `joint` from its `parent` link (by name, or \"world\"). `offset` places the joint frame in the parent's frame \
         (a translation, or a 4×4 transform; `rpy` adds URDF's roll-pitch-yaw rotation). `mass` > 0 kg, `com` in the link frame, `inertia` about the \
         centre of mass as [ixx, iyy, izz] or a 3×3 matrix (positive definite; omitted: a point mass). The joint is named after the link unless `joint_name` says otherwise.",
        |a, _| make_link(a),
    );
    reg.add(
        "body(links, name: \"body\", gravity: [0, 0, -9.81])",
        "A body from a list of link(...) values in any order: the links must form a tree rooted at \"world\" (unique names, known parents, no cycles). \
         The same Body value as a URDF body: coordinates, inverse_dynamics, scene and simulate take it. `gravity` is its default for inverse_dynamics etc.",
        |a, _| make_body(a),
    );
}
