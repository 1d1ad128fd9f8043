//! Joint values: a joint of the library (type name "Joint") and sampled joint
//! motion (type name "Samples"); bodies and scenes take joints through
//! `Args::joint`.

use std::any::Any;
use std::sync::Arc;

use crate::lang::value::{HostObject, Value};
use crate::lie::Se3;
use crate::model::joint::Joint;
use crate::model::joints::{JointSamples, SplineCurveJoint};

/// A joint as an mx value.
#[derive(Debug, Clone)]
pub struct JointValue {
    pub joint: Arc<dyn Joint>,
    /// Set for spline curve joints (for `.frames` / `.knots`).
    pub curve: Option<Arc<SplineCurveJoint>>,
    /// The smoothing weight a fitted curve joint was made with (`.smooth`).
    pub smooth: Option<f64>,
}

impl JointValue {
    pub fn new(j: impl Joint + 'static) -> Self {
        JointValue {
            joint: Arc::new(j),
            curve: None,
            smooth: None,
        }
    }
    /// A spline curve joint, keeping its frames and knots for `.frames`/`.knots`.
    pub fn curve(j: SplineCurveJoint) -> Self {
        let c = Arc::new(j);
        JointValue {
            joint: c.clone(),
            curve: Some(c),
            smooth: None,
        }
    }
    /// A curve joint fitted to samples with smoothing weight `w`.
    pub fn fitted(j: SplineCurveJoint, w: f64) -> Self {
        JointValue {
            smooth: Some(w),
            ..Self::curve(j)
        }
    }
}

impl HostObject for JointValue {
    fn type_name(&self) -> &'static str {
        "Joint"
    }
    fn summary(&self) -> String {
        format!("<{} joint, {} dof>", self.joint.kind(), self.joint.dof())
    }
    fn as_any(&self) -> &dyn Any {
        self
    }
    fn field_names(&self) -> &'static [&'static str] {
        &["kind", "dof", "frames", "smooth", "knots", "domain"]
    }
    fn read_field(&self, name: &str) -> Option<Value> {
        match name {
            "kind" => Some(Value::str(self.joint.kind())),
            "dof" => Some(Value::Number(self.joint.dof() as f64)),
            "frames" => self
                .curve
                .as_ref()
                .map(|c| Value::list(c.frames().iter().map(matrix_value).collect())),
            "smooth" => self.smooth.map(Value::Number),
            "knots" => self.curve.as_ref().map(|c| numbers(c.basis().knots())),
            "domain" => self.curve.as_ref().map(|c| {
                let (a, b) = c.domain();
                numbers(&[a, b])
            }),
            _ => None,
        }
    }
}

/// Sampled joint motion as an mx value (type name "Samples").
#[derive(Debug, Clone)]
pub struct SamplesValue(pub Arc<JointSamples>);

impl HostObject for SamplesValue {
    fn type_name(&self) -> &'static str {
        "Samples"
    }
    fn summary(&self) -> String {
        let (a, b) = self.0.range();
        format!("<{} joint samples, q in [{a}, {b}]>", self.0.len())
    }
    fn as_any(&self) -> &dyn Any {
        self
    }
    fn field_names(&self) -> &'static [&'static str] {
        &["q", "count", "transforms"]
    }
    fn read_field(&self, name: &str) -> Option<Value> {
        match name {
            "q" => Some(numbers(&self.0.q)),
            "count" => Some(Value::Number(self.0.len() as f64)),
            "transforms" => Some(Value::list(
                self.0.transforms.iter().map(matrix_value).collect(),
            )),
            _ => None,
        }
    }
}

pub fn numbers(x: &[f64]) -> Value {
    Value::list(x.iter().map(|&v| Value::Number(v)).collect())
}

/// A 4×4 homogeneous matrix as a list of rows.
pub fn matrix_value(t: &Se3) -> Value {
    let m = t.to_matrix();
    Value::list(
        (0..4)
            .map(|i| numbers(&[m[(i, 0)], m[(i, 1)], m[(i, 2)], m[(i, 3)]]))
            .collect(),
    )
}
