//! The one `Body` value every domain shares: a multibody model, plus what a
//! body made from a motion-capture clip remembers (its skeleton, and the
//! anatomical model `fit` needs). A URDF body and a body from `body_of(clip)`
//! are the same type, so `inverse_dynamics`, `SP` and `view` take either.

use std::sync::Arc;

use crate::lang::value::{HostObject, Value};
use crate::mocap;
use crate::mocap::bvh::Skeleton;
use crate::model::{Coupling, Model};

/// A body (multibody model) value.
#[derive(Clone, Debug)]
pub struct Body {
    pub model: Arc<Model>,
    /// The BVH skeleton it was built from, with metres per file unit.
    pub skeleton: Option<(Arc<Skeleton>, f64)>,
    /// Set for the anatomical model made by `human(clip)` (what `fit` needs).
    pub human: Option<Arc<mocap::human::Human>>,
    /// Coupled coordinates (`load("robot.urdf", mimic: true)`): the body's
    /// coordinates are then the independent ones.
    pub coupling: Option<Arc<Coupling>>,
    /// Set for a body loaded from an OpenSim model: its coordinates' kinds,
    /// couplers and what loading ignored.
    pub osim: Option<Arc<crate::model::osim::OsimReport>>,
}

impl Body {
    /// A body with no motion-capture origin (URDF, code, a scene's body).
    pub fn from_model(model: Arc<Model>) -> Self {
        Body {
            model,
            skeleton: None,
            human: None,
            coupling: None,
            osim: None,
        }
    }

    /// The model, for a use that needs every coordinate free: an error naming
    /// `what` for a body with coupled (mimic) coordinates.
    pub fn free_model(&self, what: &str) -> Result<Arc<Model>, String> {
        match &self.coupling {
            None => Ok(self.model.clone()),
            Some(_) => Err(format!(
                "{what} does not take a body with coupled coordinates yet; \
                 load the URDF without `mimic: true`, or the OpenSim model with `couplers: false`, to use it"
            )),
        }
    }

    /// The names of the body's coordinates (the independent ones when coupled).
    pub fn coordinate_names(&self) -> &[String] {
        match &self.coupling {
            Some(c) => c.names(),
            None => self.model.coordinate_names(),
        }
    }

    /// `(coordinate, rotational)` for every coordinate, when the body knows
    /// them (an OpenSim body); rotational means "in degrees in a .mot file".
    pub fn coordinate_kinds(&self) -> Option<Vec<(String, bool)>> {
        let r = self.osim.as_ref()?;
        Some(
            r.coordinates
                .iter()
                .map(|c| {
                    (
                        c.name.clone(),
                        c.motion == crate::model::osim::MotionType::Rotational,
                    )
                })
                .collect(),
        )
    }
}

impl HostObject for Body {
    fn type_name(&self) -> &'static str {
        "Body"
    }
    fn summary(&self) -> String {
        let ignored = match &self.osim {
            Some(r) if !r.ignored.is_empty() => {
                let mut by: Vec<(&str, usize)> = Vec::new();
                for (what, _, n) in &r.ignored {
                    match by.iter_mut().find(|(w, _)| w == what) {
                        Some(e) => e.1 += n,
                        None => by.push((what, *n)),
                    }
                }
                let parts: Vec<String> = by.iter().map(|(w, n)| format!("{n} {w}")).collect();
                format!("; ignored: {}", parts.join(", "))
            }
            _ => String::new(),
        };
        format!(
            "Body {} ({} links, {} coordinates, {:.1} kg{ignored})",
            self.model.name,
            self.model.num_links(),
            self.coordinate_names().len(),
            self.model.total_mass()
        )
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
    fn field_names(&self) -> &'static [&'static str] {
        &[
            "name",
            "mass",
            "coordinates",
            "nq",
            "links",
            "report",
            "defaults",
        ]
    }
    fn read_field(&self, name: &str) -> Option<Value> {
        match name {
            "coordinates" => Some(Value::list(
                self.coordinate_names().iter().map(Value::str).collect(),
            )),
            "nq" => Some(Value::Number(self.coordinate_names().len() as f64)),
            "name" => Some(Value::str(&self.model.name)),
            "mass" => Some(Value::Number(self.model.total_mass())),
            "report" => self.osim.as_ref().map(|r| Value::str(r.text(&self.model))),
            "defaults" => self.osim.as_ref().map(|r| {
                // the body's own coordinates: the independent ones when coupled
                let names = self.coordinate_names();
                Value::list(
                    r.coordinates
                        .iter()
                        .filter(|c| names.contains(&c.name))
                        .map(|c| Value::Number(c.default_value))
                        .collect(),
                )
            }),
            "links" => Some(Value::list(
                self.model
                    .links()
                    .iter()
                    .map(|l| Value::str(&l.name))
                    .collect(),
            )),
            _ => None,
        }
    }
}
