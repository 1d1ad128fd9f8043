//! Getters on [`Args`] for the host types, so every built-in file takes a
//! motion, a body, a joint or a vector the same way, with the same message.

use std::sync::Arc;

use nalgebra::{Matrix4, Vector3};

use super::body::Body;
use super::motion::Motion;
use crate::lang::args::{ArgValue, Args};
use crate::lang::diagnostics::{MxError, MxResult};
use crate::lang::value::Value;
use crate::lie::Se3;
use crate::model::joint::Joint;
use crate::motion::Mu;

use super::joint::JointValue;

/// How most built-ins name the motion unit they expect.
pub const A_MU: &str = "a motion unit (Mu), e.g. load(\"walk.bvh\")";

impl Args {
    /// A motion argument (Interval, Dof or Mu).
    pub fn motion(&mut self, name: &str) -> MxResult<(Motion, ArgValue)> {
        let arg = self.arg(name)?;
        match arg.value.as_object::<Motion>() {
            Some(m) => Ok((m.clone(), arg)),
            None => Err(self.type_error(name, "a motion (Interval, Dof or Mu)", &arg)),
        }
    }

    /// A motion unit argument ([`A_MU`] in the type error).
    pub fn mu(&mut self, name: &str) -> MxResult<(Mu, ArgValue)> {
        self.mu_expecting(name, A_MU)
    }

    /// A motion unit argument; `expected` says what the type error asks for.
    pub fn mu_expecting(&mut self, name: &str, expected: &str) -> MxResult<(Mu, ArgValue)> {
        let arg = self.arg(name)?;
        let mu = self.mu_in(name, &arg, expected)?;
        Ok((mu, arg))
    }

    /// The motion unit in an argument already taken.
    pub fn mu_of(&self, name: &str, arg: &ArgValue) -> MxResult<Mu> {
        self.mu_in(name, arg, A_MU)
    }

    fn mu_in(&self, name: &str, arg: &ArgValue, expected: &str) -> MxResult<Mu> {
        match arg.value.as_object::<Motion>() {
            Some(Motion::Mu(m)) => Ok(m.clone()),
            _ => Err(self.type_error(name, expected, arg)),
        }
    }

    /// A body with every coordinate free (an argument already taken);
    /// `expected` says what the type error asks for.
    pub fn free_body_of(&self, name: &str, arg: &ArgValue, expected: &str) -> MxResult<Body> {
        match arg.value.as_object::<Body>() {
            Some(b) => match b.free_model(&format!("`{}`", self.name())) {
                Ok(_) => Ok(b.clone()),
                Err(m) => Err(MxError::value(m).at(arg.span)),
            },
            None => Err(self.type_error(name, expected, arg)),
        }
    }

    /// A joint argument.
    pub fn joint(&mut self, name: &str) -> MxResult<Arc<dyn Joint>> {
        Ok(self.object::<JointValue>(name, "a joint")?.joint.clone())
    }

    /// Three finite numbers `[x, y, z]` in an argument already taken; a type
    /// error asking for `expected` otherwise.
    pub fn vec3_of(&self, name: &str, arg: &ArgValue, expected: &str) -> MxResult<Vector3<f64>> {
        match finite_numbers(&arg.value) {
            Some(v) if v.len() == 3 => Ok(Vector3::new(v[0], v[1], v[2])),
            _ => Err(self.type_error(name, expected, arg)),
        }
    }

    /// Three finite numbers for a physical vector option (`gravity:`,
    /// points, forces); the message names the function and the option.
    pub fn vector3(&self, arg: &ArgValue, name: &str) -> MxResult<Vector3<f64>> {
        match finite_numbers(&arg.value) {
            Some(v) if v.len() == 3 => Ok(Vector3::new(v[0], v[1], v[2])),
            _ => Err(MxError::type_error(format!(
                "`{}`: `{name}` must be a list of 3 finite numbers",
                self.name()
            ))
            .at(arg.span)
            .help(format!("usage: {}", self.signature()))),
        }
    }

    /// A rigid transform from a 4×4 list of rows (the rotation block must be
    /// orthonormal) in an argument already taken.
    pub fn transform_of(&self, name: &str, arg: &ArgValue) -> MxResult<Se3> {
        let rows = arg.value.as_list().filter(|r| r.len() == 4 || r.len() == 3);
        let Some(rows) = rows else {
            return Err(self.type_error(name, "a 4×4 matrix (a list of 4 rows of 4 numbers)", arg));
        };
        let mut m = Matrix4::identity();
        for (i, r) in rows.iter().enumerate() {
            let r = r
                .as_list()
                .and_then(|r| r.iter().map(Value::as_number).collect::<Option<Vec<f64>>>());
            match r {
                Some(r) if r.len() == 4 && r.iter().all(|x| x.is_finite()) => {
                    for (j, x) in r.into_iter().enumerate() {
                        m[(i, j)] = x;
                    }
                }
                _ => {
                    return Err(self.type_error(
                        name,
                        "a 4×4 matrix (a list of 4 rows of 4 finite numbers)",
                        arg,
                    ));
                }
            }
        }
        let t = Se3::from_matrix(&m);
        let err = (t.r.transpose() * t.r - nalgebra::Matrix3::identity())
            .abs()
            .max();
        if err > 1e-6 || t.r.determinant() < 0.0 {
            return Err(MxError::value(format!(
                "`{name}`: the upper-left 3×3 block is not a rotation (‖RᵀR − I‖ = {err:.1e}); give a proper rigid transform"
            ))
            .at(arg.span)
            .help(format!("usage: {}", self.signature())));
        }
        Ok(t)
    }
}

/// Every element of a list as a finite number, or `None`.
fn finite_numbers(v: &Value) -> Option<Vec<f64>> {
    v.as_list()?
        .iter()
        .map(|x| x.as_number().filter(|x| x.is_finite()))
        .collect()
}
