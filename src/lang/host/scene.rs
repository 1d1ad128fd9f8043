//! The scene value (`scene(body, gravity:, springs:, …)`): a body and the
//! effects it declares.

use super::body::Body;
use crate::dynamics::Scene;
use crate::lang::value::{HostObject, Value};
use crate::model::Model;

/// A scene: a body and the effects it declares.
#[derive(Clone, Debug)]
pub struct SceneValue {
    pub scene: Scene,
}

/// `1 spring`, `2 springs`: the plural only when the count is not one.
fn count(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

impl HostObject for SceneValue {
    fn type_name(&self) -> &'static str {
        "Scene"
    }
    fn summary(&self) -> String {
        let s = &self.scene;
        let mut fx = Vec::new();
        if let Some(g) = s.gravity {
            fx.push(format!("gravity [{}, {}, {}]", g.x, g.y, g.z));
        }
        if s.damping.is_some() {
            fx.push("damping".into());
        }
        if !s.springs.is_empty() {
            fx.push(count(s.springs.len(), "spring"));
        }
        if !s.forces.is_empty() {
            fx.push(count(s.forces.len(), "force"));
        }
        if s.limits.is_some() {
            fx.push("joint limits".into());
        }
        format!(
            "Scene of `{}` ({})",
            s.model.name,
            if fx.is_empty() {
                "no effects".to_string()
            } else {
                fx.join(", ")
            }
        )
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
    fn field_names(&self) -> &'static [&'static str] {
        &["body", "coordinates"]
    }
    fn read_field(&self, name: &str) -> Option<Value> {
        match name {
            "body" => Some(Value::object(Body::from_model(self.scene.model.clone()))),
            "coordinates" => Some(names_value(&self.scene.model)),
            _ => None,
        }
    }
}

pub fn names_value(m: &Model) -> Value {
    Value::list(m.coordinate_names().iter().map(Value::str).collect())
}
