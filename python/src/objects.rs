//! The Python classes' data: `mx.Motion`, `mx.Body`, `mx.Function` and
//! `mx.Object`, each an mx value (a body also keeps its model and a
//! workspace). Only the structs live here, below `convert.rs`, which makes
//! them from mx values; their methods, which convert arguments, live above it
//! (`motion.rs`, `body.rs`, `function.rs`), so no file imports one that
//! imports it back.

use std::sync::{Arc, Mutex};

use mx::dynamics::Workspace;
use mx::lang::builtins::body::Body;
use mx::lang::{Context, Value};
use mx::model::Model;
use pyo3::prelude::*;

/// An mx motion: a motion unit, or a single DOF or interval (`motion.rs`).
#[pyclass(name = "Motion", module = "mx", frozen)]
pub struct PyMotion {
    pub value: Value,
}

/// A multibody model with its dynamics (`body.rs`).
#[pyclass(name = "Body", module = "mx", frozen)]
pub struct PyBody {
    pub value: Value,
    pub(crate) model: Arc<Model>,
    /// Reused by single-state calls (a batch gives each thread its own).
    pub(crate) ws: Mutex<Workspace>,
}

impl PyBody {
    pub fn new(value: Value) -> Self {
        let model = value
            .as_object::<Body>()
            .expect("a PyBody holds a body value")
            .model
            .clone();
        let ws = Mutex::new(Workspace::new(&model));
        PyBody { value, model, ws }
    }
}

/// An mx function (user-defined or built-in), callable from Python (`function.rs`).
#[pyclass(name = "Function", module = "mx", frozen)]
pub struct PyFunction {
    pub value: Value,
    /// The interpreter it came from (registry, limits, file root, cancel token).
    pub ctx: Context,
}

/// Any other mx value (a joint, a scene, an SP report…): its fields are
/// attributes (`function.rs`).
#[pyclass(name = "Object", module = "mx", frozen)]
pub struct PyObject_ {
    pub value: Value,
}
