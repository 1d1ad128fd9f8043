//! Coupled coordinates: some coordinates of a model follow others,
//! q_full[k] = multiplier · q[source] + offset (URDF `<mimic>` joints, as
//! Pinocchio's `buildModel(…, mimic=True)` makes them). The independent
//! coordinates keep the model's order with the followers left out.
//!
//! With q_full = G q + b, velocities and accelerations map by G (the offsets
//! are constant), generalised forces back by Gᵀ, and the mass matrix of the
//! independent coordinates is Gᵀ M G (`dynamics::coupled`).

use crate::model::tree::{Model, ModelError};

/// One follower coordinate.
#[derive(Clone, Debug, PartialEq)]
pub struct Follower {
    /// The follower's index among the model's coordinates.
    pub coordinate: usize,
    /// The index of the coordinate it follows, among the model's coordinates.
    pub source: usize,
    pub multiplier: f64,
    pub offset: f64,
}

/// The coupling of a model's coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct Coupling {
    /// Per model coordinate: (independent index, multiplier, offset);
    /// independent coordinates map to themselves with (1, 0).
    map: Vec<(usize, f64, f64)>,
    names: Vec<String>,
}

impl Coupling {
    /// Builds the coupling of `followers` on `model`. A follower may not
    /// follow another follower, nor itself; multipliers and offsets are finite.
    pub fn new(model: &Model, followers: &[Follower]) -> Result<Coupling, ModelError> {
        let n = model.nq();
        let names = model.coordinate_names();
        let mut follows: Vec<Option<&Follower>> = vec![None; n];
        for f in followers {
            if f.coordinate >= n || f.source >= n {
                return Err(ModelError::Invalid(format!(
                    "coupled coordinate {} or its source {} is outside the model's {n} coordinates",
                    f.coordinate, f.source
                )));
            }
            if !(f.multiplier.is_finite() && f.offset.is_finite()) {
                return Err(ModelError::Invalid(format!(
                    "`{}` follows `{}` with a non-finite multiplier or offset",
                    names[f.coordinate], names[f.source]
                )));
            }
            if follows[f.coordinate].replace(f).is_some() {
                return Err(ModelError::Invalid(format!(
                    "`{}` follows two coordinates",
                    names[f.coordinate]
                )));
            }
        }
        for f in followers {
            if f.source == f.coordinate || follows[f.source].is_some() {
                return Err(ModelError::Invalid(format!(
                    "`{}` follows `{}`, which itself follows another coordinate; \
                     follow the independent one directly",
                    names[f.coordinate], names[f.source]
                )));
            }
        }
        let mut independent = vec![usize::MAX; n];
        let mut out_names = Vec::new();
        for k in 0..n {
            if follows[k].is_none() {
                independent[k] = out_names.len();
                out_names.push(names[k].clone());
            }
        }
        let map = (0..n)
            .map(|k| match follows[k] {
                Some(f) => (independent[f.source], f.multiplier, f.offset),
                None => (independent[k], 1.0, 0.0),
            })
            .collect();
        Ok(Coupling {
            map,
            names: out_names,
        })
    }

    /// The number of independent coordinates.
    pub fn nq(&self) -> usize {
        self.names.len()
    }

    /// The number of the model's coordinates.
    pub fn full_nq(&self) -> usize {
        self.map.len()
    }

    /// The independent coordinates' names, in order.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// Per model coordinate: (independent index, multiplier, offset).
    pub fn map(&self) -> &[(usize, f64, f64)] {
        &self.map
    }

    /// Model coordinates from independent ones: G q + b.
    pub fn expand_q(&self, q: &[f64], out: &mut [f64]) {
        for (o, &(i, m, b)) in out.iter_mut().zip(&self.map) {
            *o = m * q[i] + b;
        }
    }

    /// Model velocities (or accelerations) from independent ones: G v.
    pub fn expand_v(&self, v: &[f64], out: &mut [f64]) {
        for (o, &(i, m, _)) in out.iter_mut().zip(&self.map) {
            *o = m * v[i];
        }
    }

    /// Generalised forces on the independent coordinates: Gᵀ f.
    pub fn reduce(&self, full: &[f64], out: &mut [f64]) {
        out.iter_mut().for_each(|o| *o = 0.0);
        for (f, &(i, m, _)) in full.iter().zip(&self.map) {
            out[i] += m * f;
        }
    }
}
