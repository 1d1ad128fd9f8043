//! The one `Body` value every domain shares: a multibody model, plus what a
//! body made from a motion-capture clip remembers (its skeleton, and the
//! anatomical model `fit` needs). A URDF body and a body from `body_of(clip)`
//! are the same type, so `inverse_dynamics`, `SP` and `view` take either.

use std::sync::Arc;

use crate::lang::value::{HostObject, Value};
use crate::mocap;
use crate::mocap::bvh::Skeleton;
use crate::model::Model;

/// A body (multibody model) value.
#[derive(Clone, Debug)]
pub struct Body {
    pub model: Arc<Model>,
    /// The BVH skeleton it was built from, with metres per file unit.
    pub skeleton: Option<(Arc<Skeleton>, f64)>,
    /// Set for the anatomical model made by `human(clip)` (what `fit` needs).
    pub human: Option<Arc<mocap::human::Human>>,
}

impl Body {
    /// A body with no motion-capture origin (URDF, code, a scene's body).
    pub fn from_model(model: Arc<Model>) -> Self {
        Body {
            model,
            skeleton: None,
            human: None,
        }
    }
}

impl HostObject for Body {
    fn type_name(&self) -> &'static str {
        "Body"
    }
    fn summary(&self) -> String {
        format!(
            "Body {} ({} links, {} coordinates, {:.1} kg)",
            self.model.name,
            self.model.num_links(),
            self.model.nq(),
            self.model.total_mass()
        )
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
    fn field(&self, name: &str) -> Option<Value> {
        match name {
            "coordinates" => Some(Value::list(
                self.model
                    .coordinate_names()
                    .iter()
                    .map(Value::str)
                    .collect(),
            )),
            "nq" => Some(Value::Number(self.model.nq() as f64)),
            "name" => Some(Value::str(&self.model.name)),
            "mass" => Some(Value::Number(self.model.total_mass())),
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
