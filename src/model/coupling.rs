//! Coupled coordinates: some coordinates of a model follow others,
//! q_full[k] = f_k(q[source]) — linear for URDF `<mimic>` joints
//! (multiplier · q + offset, as Pinocchio's `buildModel(…, mimic=True)` makes
//! them), any scalar function for OpenSim's CoordinateCouplerConstraints
//! (a SimmSpline patella, say). The independent coordinates keep the model's
//! order with the followers left out.
//!
//! With q_full = F(q) and G = ∂F/∂q (diagonal per follower: f′(q_source)),
//! velocities map as q̇_full = G q̇, accelerations as q̈_full = G q̈ + c with
//! c_k = f″ q̇_source² (zero for linear followers), generalised forces back by
//! Gᵀ (virtual work), and the mass matrix of the independent coordinates is
//! Gᵀ M G (`dynamics::coupled`).

use crate::model::joints::ScalarFunction;
use crate::model::tree::{Model, ModelError};
use nalgebra::DMatrix;

/// One follower coordinate.
#[derive(Clone, Debug, PartialEq)]
pub struct Follower {
    /// The follower's index among the model's coordinates.
    pub coordinate: usize,
    /// The index of the coordinate it follows, among the model's coordinates.
    pub source: usize,
    /// q_follower = function(q_source).
    pub function: ScalarFunction,
}

impl Follower {
    /// q_follower = multiplier · q_source + offset (a URDF mimic joint).
    pub fn linear(coordinate: usize, source: usize, multiplier: f64, offset: f64) -> Follower {
        Follower {
            coordinate,
            source,
            function: ScalarFunction::Linear {
                slope: multiplier,
                intercept: offset,
            },
        }
    }
}

/// The coupling of a model's coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct Coupling {
    /// Per model coordinate: its independent coordinate and, for a follower,
    /// the function of it (None: the coordinate is that independent one).
    map: Vec<(usize, Option<ScalarFunction>)>,
    names: Vec<String>,
}

fn finite(f: &ScalarFunction) -> bool {
    match f {
        ScalarFunction::Constant { value } => value.is_finite(),
        ScalarFunction::Linear { slope, intercept } => slope.is_finite() && intercept.is_finite(),
        ScalarFunction::Multiplier { scale, function } => scale.is_finite() && finite(function),
        _ => f.eval(0.0).iter().all(|v| v.is_finite()),
    }
}

impl Coupling {
    /// Builds the coupling of `followers` on `model`. A follower may not
    /// follow another follower, nor itself; its function is finite.
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
            if !finite(&f.function) {
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
                Some(f) => (independent[f.source], Some(f.function.clone())),
                None => (independent[k], None),
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

    /// Whether every follower is linear (G is then constant and c zero).
    pub fn is_linear(&self) -> bool {
        self.map.iter().all(|(_, f)| {
            matches!(
                f,
                None | Some(ScalarFunction::Linear { .. } | ScalarFunction::Constant { .. })
            )
        })
    }

    /// Per model coordinate k: (independent index i, f, f′, f″) at q[i].
    fn at(&self, k: usize, q: &[f64]) -> (usize, [f64; 3]) {
        let (i, f) = &self.map[k];
        match f {
            None => (*i, [q[*i], 1.0, 0.0]),
            Some(f) => (*i, f.eval(q[*i])),
        }
    }

    /// Model coordinates from independent ones: F(q).
    pub fn expand_q(&self, q: &[f64], out: &mut [f64]) {
        for (k, o) in out.iter_mut().enumerate() {
            *o = self.at(k, q).1[0];
        }
    }

    /// Model velocities from independent ones at q: G(q) v.
    pub fn expand_v(&self, q: &[f64], v: &[f64], out: &mut [f64]) {
        for (k, o) in out.iter_mut().enumerate() {
            let (i, [_, d1, _]) = self.at(k, q);
            *o = d1 * v[i];
        }
    }

    /// Model accelerations at (q, v): G(q) a + c(q, v), c_k = f″ v_source².
    pub fn expand_a(&self, q: &[f64], v: &[f64], a: &[f64], out: &mut [f64]) {
        for (k, o) in out.iter_mut().enumerate() {
            let (i, [_, d1, d2]) = self.at(k, q);
            *o = d1 * a[i] + d2 * v[i] * v[i];
        }
    }

    /// Generalised forces on the independent coordinates at q: G(q)ᵀ f.
    pub fn reduce(&self, q: &[f64], full: &[f64], out: &mut [f64]) {
        out.iter_mut().for_each(|o| *o = 0.0);
        for (k, f) in full.iter().enumerate() {
            let (i, [_, d1, _]) = self.at(k, q);
            out[i] += d1 * f;
        }
    }

    /// G(q) = ∂F/∂q, full_nq × nq.
    pub fn jacobian(&self, q: &[f64]) -> DMatrix<f64> {
        let mut g = DMatrix::zeros(self.full_nq(), self.nq());
        for k in 0..self.full_nq() {
            let (i, [_, d1, _]) = self.at(k, q);
            g[(k, i)] = d1;
        }
        g
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::body::Inertia;
    use crate::model::joints::Revolute;
    use nalgebra::Vector3;
    use std::sync::Arc;

    fn chain(n: usize) -> Model {
        let mut m = Model::new("chain");
        for k in 0..n {
            let parent = k.checked_sub(1);
            m.add_link(
                &format!("l{k}"),
                parent,
                &format!("j{k}"),
                Arc::new(Revolute::new(Vector3::z()).unwrap()),
                crate::lie::Se3::identity(),
                Inertia::point(1.0, Vector3::x()).unwrap(),
            )
            .unwrap();
        }
        m
    }

    #[test]
    fn a_nonlinear_follower_maps_velocity_and_acceleration_by_the_chain_rule() {
        let m = chain(2);
        let f = ScalarFunction::Polynomial {
            coefficients: vec![0.3, -0.2, 0.7, 0.1],
        };
        let c = Coupling::new(
            &m,
            &[Follower {
                coordinate: 1,
                source: 0,
                function: f.clone(),
            }],
        )
        .unwrap();
        assert!(!c.is_linear());
        let (q, v, a) = ([0.4], [1.3], [-0.7]);
        let qf = |t: f64| {
            let mut o = [0.0; 2];
            c.expand_q(&[q[0] + v[0] * t + 0.5 * a[0] * t * t], &mut o);
            o
        };
        let h = 1e-4;
        let (p, z, n) = (qf(h), qf(0.0), qf(-h));
        let mut vf = [0.0; 2];
        let mut af = [0.0; 2];
        c.expand_v(&q, &v, &mut vf);
        c.expand_a(&q, &v, &a, &mut af);
        for k in 0..2 {
            assert!((vf[k] - (p[k] - n[k]) / (2.0 * h)).abs() < 1e-7);
            assert!((af[k] - (p[k] - 2.0 * z[k] + n[k]) / (h * h)).abs() < 1e-5);
        }
        let mut r = [0.0];
        c.reduce(&q, &[2.0, 3.0], &mut r);
        assert!((r[0] - (2.0 + 3.0 * f.eval(0.4)[1])).abs() < 1e-15);
    }
}
