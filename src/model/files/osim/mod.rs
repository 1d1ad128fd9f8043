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
//!
//! The reader runs in phases, one file each: `xml.rs` (located errors and
//! accessors), `document.rs` (header, bodies, joints with their frames placed by
//! `frames.rs`, in build order), `build.rs` (links, joints, inertias;
//! `joints.rs` turns a joint's coordinates and axes into a transform), and
//! `constraints.rs` (couplers, and what mx does not simulate).

mod build;
mod constraints;
mod document;
mod frames;
mod joints;
mod xml;

use roxmltree::Document;

use crate::model::coupling::{Coupling, Follower};
use crate::model::joint::Limit;
use crate::model::joints::ScalarFunction;
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

/// The phases in order: the document, the links, then the constraints and the
/// count of what mx does not simulate.
fn read(doc: &Document) -> Result<OsimModel, ModelError> {
    let cx = xml::Ctx { doc };
    let parsed = document::read(&cx)?;
    let model_node = parsed.model;
    let mut osim = build::build(&cx, parsed)?;
    constraints::read_constraints(&cx, model_node, &osim.model, &mut osim.report)?;
    constraints::count_ignored(model_node, &mut osim.report);
    Ok(osim)
}
