//! A kinematic tree: links joined to their parents by joints.
//!
//! Link `i` carries the frame of its joint's child side. Its pose in the parent
//! link's frame is `offset_i · G_i(q_i)`, where `offset_i` is the fixed placement
//! of the joint frame in the parent frame and `G_i` the joint transform. Links
//! are stored parents-first (a parent's index is always smaller than its
//! child's), which is the order every recursive algorithm walks.

use crate::lie::Se3;
use crate::model::body::Inertia;
use crate::model::joint::{AxisMotion, Joint, JointAxis};
use nalgebra::Vector3;
use std::collections::HashMap;
use std::sync::Arc;

/// Why a model could not be built or used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModelError {
    #[error("{0}")]
    Invalid(String),
    #[error("URDF: {0}")]
    Urdf(String),
    /// A URDF file that cannot be read (the message names it).
    #[error("URDF: {0}")]
    UrdfUnreadable(String),
    /// A URDF document that is not well-formed XML with a `<robot>` root.
    #[error("URDF: {0}")]
    UrdfMalformed(String),
    /// A URDF whose links and joints are not a tree (`path`: the file's).
    #[error("URDF: {}{error}", path.as_ref().map(|p| format!("{}: ", p.display())).unwrap_or_default())]
    UrdfTree {
        path: Option<std::path::PathBuf>,
        error: crate::model::link_tree::TreeError,
    },
    /// Links that do not form a tree (the language's `body([...])`).
    #[error(transparent)]
    Tree(#[from] crate::model::link_tree::TreeError),
}

/// One link and the joint that carries it.
#[derive(Clone, Debug)]
pub struct Link {
    pub name: String,
    /// Index of the parent link, `None` for a link attached to the world (fixed base).
    pub parent: Option<usize>,
    /// Placement of the joint frame in the parent link frame.
    pub offset: Se3,
    pub joint_name: String,
    pub joint: Arc<dyn Joint>,
    /// Inertia in this link's frame.
    pub inertia: Inertia,
    /// Index of the joint's first coordinate in `q`.
    pub q_index: usize,
    /// Number of coordinates of the joint (cached `joint.dof()`).
    pub dof: usize,
    /// Cached `joint.constant_jacobian()`: lets the algorithms skip Hessian terms.
    pub constant_jacobian: bool,
    /// Cached `joint.limits()` (no allocation in the algorithms).
    pub limits: Vec<crate::model::joint::Limit>,
    /// Cached `joint.joint_axis()`: the world-frame algorithms place
    /// revolute/prismatic links without a dynamic call.
    pub axis: Option<JointAxis>,
    /// False when `offset` is a pure translation (most URDF joint origins):
    /// placing the link then needs no rotation product.
    pub offset_rotates: bool,
}

/// A tree of links with a fixed base.
#[derive(Clone, Debug, Default)]
pub struct Model {
    pub name: String,
    links: Vec<Link>,
    children: Vec<Vec<usize>>,
    coordinate_names: Vec<String>,
    /// Coordinate name → index: `coordinate_index` is called per DOF name
    /// when motions meet models (hundreds of names × every operation).
    coordinate_lookup: HashMap<String, usize>,
    /// Per coordinate, the link whose joint it belongs to.
    coordinate_links: Vec<usize>,
    /// Per coordinate, the coordinate before it on the path to the root (the
    /// previous coordinate of the same joint, else the last one of the nearest
    /// ancestor joint with coordinates): the mass matrix walks these chains.
    coordinate_parent: Vec<Option<usize>>,
    /// Per link, the last link of its subtree and one past the subtree's last
    /// coordinate; only meaningful while `depth_first` holds.
    subtree_last_link: Vec<usize>,
    subtree_end: Vec<usize>,
    /// True while every subtree is a contiguous run of links (each link added
    /// under the last link or one of its ancestors, as URDF and BVH loading do):
    /// the mass matrix then fills contiguous row ranges.
    depth_first: bool,
    nq: usize,
    /// The gravity a model loaded from a file starts with (URDF: `[0, 0, −9.81]`,
    /// Pinocchio's default, so results match it); code may override it.
    pub default_gravity: Vector3<f64>,
}

impl Model {
    /// An empty model, default gravity `[0, 0, −9.81]` (z up, as URDF and Pinocchio).
    pub fn new(name: &str) -> Self {
        Model {
            name: name.to_string(),
            default_gravity: Vector3::new(0.0, 0.0, -9.81),
            ..Default::default()
        }
    }

    /// Adds a link carried by `joint` and returns its index.
    /// `parent` must be an existing link (or `None` for the world); names must be unique.
    pub fn add_link(
        &mut self,
        name: &str,
        parent: Option<usize>,
        joint_name: &str,
        joint: Arc<dyn Joint>,
        offset: Se3,
        inertia: Inertia,
    ) -> Result<usize, ModelError> {
        if let Some(p) = parent
            && p >= self.links.len()
        {
            return Err(ModelError::Invalid(format!(
                "link `{name}`: parent index {p} does not exist (the model has {} links; add parents first)",
                self.links.len()
            )));
        }
        if self.links.iter().any(|l| l.name == name) {
            return Err(ModelError::Invalid(format!(
                "a link named `{name}` already exists; link names must be unique"
            )));
        }
        if self.links.iter().any(|l| l.joint_name == joint_name) {
            return Err(ModelError::Invalid(format!(
                "a joint named `{joint_name}` already exists; joint names must be unique"
            )));
        }
        if !offset
            .r
            .iter()
            .chain(offset.p.iter())
            .all(|x| x.is_finite())
        {
            return Err(ModelError::Invalid(format!(
                "link `{name}`: the joint offset must be finite"
            )));
        }
        let dof = joint.dof();
        if dof > crate::model::joint::MAX_JOINT_DOF {
            return Err(ModelError::Invalid(format!(
                "joint `{joint_name}` has {dof} coordinates; at most 6 are supported"
            )));
        }
        let idx = self.links.len();
        for s in joint.coordinate_suffixes().iter().take(dof) {
            let name = if s.is_empty() {
                joint_name.to_string()
            } else {
                format!("{joint_name}.{s}")
            };
            // first wins, as the linear scan this replaces did
            self.coordinate_lookup
                .entry(name.clone())
                .or_insert(self.coordinate_names.len());
            self.coordinate_names.push(name);
            self.coordinate_links.push(idx);
        }
        // The last coordinate of the nearest ancestor joint that has any.
        let mut before = None;
        let mut a = parent;
        while let Some(p) = a {
            let lp = &self.links[p];
            if lp.dof > 0 {
                before = Some(lp.q_index + lp.dof - 1);
                break;
            }
            a = lp.parent;
        }
        for k in 0..dof {
            self.coordinate_parent.push(if k == 0 {
                before
            } else {
                Some(self.nq + k - 1)
            });
        }
        if idx == 0 {
            self.depth_first = true;
        }
        if let Some(p) = parent {
            self.depth_first &= self.subtree_last_link[p] == idx - 1;
        }
        self.subtree_last_link.push(idx);
        self.subtree_end.push(self.nq + dof);
        let mut a = parent;
        while let Some(p) = a {
            self.subtree_last_link[p] = idx;
            self.subtree_end[p] = self.nq + dof;
            a = self.links[p].parent;
        }
        self.links.push(Link {
            name: name.to_string(),
            parent,
            offset,
            joint_name: joint_name.to_string(),
            constant_jacobian: joint.constant_jacobian(),
            limits: joint.limits(),
            axis: joint.joint_axis(),
            offset_rotates: offset.r != nalgebra::Matrix3::identity(),
            joint,
            inertia,
            q_index: self.nq,
            dof,
        });
        self.children.push(Vec::new());
        if let Some(p) = parent {
            self.children[p].push(idx);
        }
        self.nq += dof;
        Ok(idx)
    }

    /// Number of coordinates (= number of velocities: every joint is parametrised
    /// by plain coordinates).
    pub fn nq(&self) -> usize {
        self.nq
    }

    /// Same as [`Model::nq`].
    pub fn nv(&self) -> usize {
        self.nq
    }

    /// Coordinate names in `q` order: `joint` for a 1-DOF joint, `joint.suffix` otherwise.
    pub fn coordinate_names(&self) -> &[String] {
        &self.coordinate_names
    }

    /// Renames every coordinate (e.g. to an OpenSim model's coordinate names):
    /// one name per coordinate, all distinct and non-empty.
    pub fn set_coordinate_names(&mut self, names: Vec<String>) -> Result<(), ModelError> {
        if names.len() != self.nq {
            return Err(ModelError::Invalid(format!(
                "{} coordinate names for a model with {} coordinates",
                names.len(),
                self.nq
            )));
        }
        let mut seen = std::collections::HashSet::new();
        for n in &names {
            if n.is_empty() || !seen.insert(n.as_str()) {
                return Err(ModelError::Invalid(format!(
                    "coordinate name `{n}` is empty or used twice; coordinate names must be unique"
                )));
            }
        }
        self.coordinate_lookup = names
            .iter()
            .enumerate()
            .map(|(i, n)| (n.clone(), i))
            .collect();
        self.coordinate_names = names;
        Ok(())
    }

    /// The coordinate before coordinate `k` on its path to the root, if any
    /// (coordinates of one joint follow each other, then the nearest ancestor
    /// joint's last coordinate).
    #[inline]
    pub fn coordinate_parent(&self, k: usize) -> Option<usize> {
        self.coordinate_parent[k]
    }

    /// The coordinates of link `i` and all its descendants, when they form one
    /// contiguous range (see `depth_first`); `None` when links were added in an
    /// order that interleaves subtrees.
    #[inline]
    pub fn subtree_coordinates(&self, i: usize) -> Option<std::ops::Range<usize>> {
        self.depth_first
            .then(|| self.links[i].q_index..self.subtree_end[i])
    }

    pub fn links(&self) -> &[Link] {
        &self.links
    }

    /// `true` when link `a` is `b` or one of its ancestors.
    pub fn is_ancestor(&self, a: usize, b: usize) -> bool {
        let mut l = Some(b);
        while let Some(i) = l {
            if i == a {
                return true;
            }
            l = self.link(i).parent;
        }
        false
    }

    pub fn link(&self, i: usize) -> &Link {
        &self.links[i]
    }

    pub fn num_links(&self) -> usize {
        self.links.len()
    }

    pub fn children(&self, i: usize) -> &[usize] {
        &self.children[i]
    }

    pub fn link_index(&self, name: &str) -> Option<usize> {
        self.links.iter().position(|l| l.name == name)
    }

    pub fn joint_index(&self, joint_name: &str) -> Option<usize> {
        self.links.iter().position(|l| l.joint_name == joint_name)
    }

    /// Index of a coordinate by name.
    pub fn coordinate_index(&self, name: &str) -> Option<usize> {
        self.coordinate_lookup.get(name).copied()
    }

    /// The link whose joint carries coordinate `c` (`None` past `nq`).
    pub fn coordinate_link(&self, c: usize) -> Option<usize> {
        self.coordinate_links.get(c).copied()
    }

    /// What coordinate `c` moves, when its joint is a single revolute or
    /// prismatic axis: rotation or translation. `None` for coordinates of
    /// multi-DOF and function-based joints, whose coordinates need not be
    /// either (and past `nq`).
    pub fn coordinate_motion(&self, c: usize) -> Option<AxisMotion> {
        let l = &self.links[self.coordinate_link(c)?];
        match (l.dof, &l.axis) {
            (1, Some(a)) => Some(a.motion),
            _ => None,
        }
    }

    /// The coordinates of link `i`'s joint (empty for a fixed joint).
    pub fn joint_coordinates(&self, i: usize) -> std::ops::Range<usize> {
        let l = &self.links[i];
        l.q_index..l.q_index + l.dof
    }

    /// Total mass of all links.
    pub fn total_mass(&self) -> f64 {
        self.links.iter().map(|l| l.inertia.mass).sum()
    }

    /// Replaces the inertia of link `i`.
    pub fn set_inertia(&mut self, i: usize, inertia: Inertia) -> Result<(), ModelError> {
        let n = self.links.len();
        let l = self.links.get_mut(i).ok_or_else(|| {
            ModelError::Invalid(format!(
                "link index {i} out of range (the model has {n} links)"
            ))
        })?;
        l.inertia = inertia;
        Ok(())
    }

    /// Errors unless `x` has length `n` and is finite: every algorithm checks its inputs.
    pub(crate) fn check_vec(&self, what: &str, x: &[f64], n: usize) -> Result<(), ModelError> {
        if x.len() != n {
            return Err(ModelError::Invalid(format!(
                "{what} has {} entries but the model `{}` has {n} coordinates ({})",
                x.len(),
                self.name,
                self.coordinate_names.join(", ")
            )));
        }
        if let Some(k) = x.iter().position(|v| !v.is_finite()) {
            return Err(ModelError::Invalid(format!(
                "{what}[{k}] (`{}`) is not a finite number",
                self.coordinate_names
                    .get(k)
                    .map(String::as_str)
                    .unwrap_or("?")
            )));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::joints::{Fixed, Prismatic, Revolute, Spherical};

    /// base (slider x) → fixed → ball (3 coordinates) → elbow (hinge).
    fn arm() -> Model {
        let mut m = Model::new("arm");
        let x = Vector3::x();
        let id = Se3::identity();
        let i = Inertia::default();
        let slide = Arc::new(Prismatic::new(x).unwrap());
        let b = m.add_link("base", None, "slide", slide, id, i).unwrap();
        let f = m.add_link("plate", Some(b), "weld", Arc::new(Fixed::new(id)), id, i);
        let ball = Arc::new(Spherical::new(crate::model::joints::EulerOrder([2, 0, 1])));
        let s = m.add_link("upper", Some(f.unwrap()), "shoulder", ball, id, i);
        let hinge = Arc::new(Revolute::new(x).unwrap());
        m.add_link("fore", Some(s.unwrap()), "elbow", hinge, id, i)
            .unwrap();
        m
    }

    #[test]
    fn coordinates_know_their_link_and_motion() {
        let m = arm();
        assert_eq!(m.nq(), 5);
        let names = m.coordinate_names().to_vec();
        for (c, n) in names.iter().enumerate() {
            assert_eq!(m.coordinate_index(n), Some(c), "{n}");
        }
        assert_eq!(m.coordinate_index("nope"), None);
        let links: Vec<_> = (0..5).map(|c| m.coordinate_link(c).unwrap()).collect();
        assert_eq!(links, [0, 2, 2, 2, 3]);
        assert_eq!(m.coordinate_link(5), None);
        assert_eq!(m.coordinate_motion(0), Some(AxisMotion::Translation));
        assert_eq!(m.coordinate_motion(1), None, "a ball's coordinate");
        assert_eq!(m.coordinate_motion(4), Some(AxisMotion::Rotation));
        assert_eq!(m.joint_coordinates(1), 1..1, "a fixed joint has none");
        assert_eq!(m.joint_coordinates(2), 1..4);
    }

    #[test]
    fn renamed_coordinates_are_found_by_their_new_names() {
        let mut m = arm();
        let names: Vec<String> = (0..5).map(|k| format!("c{k}")).collect();
        m.set_coordinate_names(names).unwrap();
        assert_eq!(m.coordinate_index("c3"), Some(3));
        assert_eq!(m.coordinate_index("slide"), None);
    }
}
