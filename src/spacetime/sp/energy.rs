//! ∫Στ² of a whole motion (`torque_energy`), root coordinates excluded as
//! in SP's objective ([`joint_weights`]).

use super::checks::{check_conflicts, check_names, motion_err};
use crate::ground::moving_root;
use crate::model::Model;
use crate::model::RootCoords;
use crate::motion::{JointSampler, Mu};
use crate::spacetime::error::{SpError, invalid};
use crate::spacetime::quadrature::GaussLegendre;
use crate::spacetime::torque::{BodyDynamics, TorqueModel};
use nalgebra::Vector3;

/// 1 for every joint coordinate, 0 for the root's (nothing actuates the six
/// virtual root forces; Rose sums joint torques).
pub fn joint_weights(model: &Model, root: &RootCoords) -> Vec<f64> {
    let mut w = vec![1.0; model.nq()];
    for &c in &root.all {
        w[c] = 0.0;
    }
    w
}

/// Gauss points per piece in [`torque_energy`].
const ENERGY_POINTS: usize = 5;
/// Longest piece in [`torque_energy`] (s): pieces also break at every interval end.
const ENERGY_PIECE: f64 = 1.0 / 30.0;

/// `torque_energy(m, body)`: ∫ Σᵢ τᵢ² dt over the motion's span, τ the joint
/// torques (root coordinates excluded, as in SP's objective), by 5-point
/// Gauss–Legendre on pieces of at most 1/30 s that break at every interval end
/// of every DOF (where q̈ may jump). Undefined or conflicting motion is an error.
pub fn torque_energy(m: &Mu, model: &Model, gravity: Option<Vector3<f64>>) -> Result<f64, SpError> {
    check_conflicts(m)?;
    check_names(m, model)?;
    let gravity = gravity.unwrap_or(model.default_gravity);
    let Some((s, e)) = m.span() else {
        return Err(invalid(
            "torque_energy of an empty motion: it defines no DOF anywhere",
        ));
    };
    let root = moving_root(model, &gravity, m);
    let weights = joint_weights(model, &root);
    let names = model.coordinate_names();
    let mut breaks = vec![s, e];
    for n in names {
        if let Some(d) = m.get(n) {
            for iv in &d.intervals {
                breaks.push(iv.start);
                breaks.push(iv.stop);
            }
        }
    }
    breaks.sort_by(f64::total_cmp);
    breaks.dedup_by(|a, b| (*a - *b).abs() <= crate::motion::time_tol(*b));
    let rule = GaussLegendre::new(ENERGY_POINTS).map_err(|e| invalid(e.to_string()))?;
    let body = BodyDynamics { model, gravity };
    let mut ws = body.workspace();
    let n = model.nq();
    let (mut q, mut v, mut a, mut tau) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let sampler = JointSampler::new(m, names);
    let mut total = 0.0;
    for w in breaks.windows(2) {
        let pieces = ((w[1] - w[0]) / ENERGY_PIECE).ceil().max(1.0) as usize;
        for p in 0..pieces {
            let a0 = w[0] + (w[1] - w[0]) * p as f64 / pieces as f64;
            let a1 = w[0] + (w[1] - w[0]) * (p + 1) as f64 / pieces as f64;
            let (ts, ws_) = rule.on(a0, a1);
            for (&t, &wq) in ts.iter().zip(&ws_) {
                if let Some(i) = sampler
                    .state(t, &mut q, &mut v, &mut a)
                    .map_err(motion_err)?
                {
                    return Err(SpError::Undefined {
                        dof: names[i].to_string(),
                        t,
                        need: crate::spacetime::Need::TorqueEnergy,
                    });
                }
                body.torques(&mut ws, &q, &v, &a, &[], &mut tau)?;
                total += wq
                    * tau
                        .iter()
                        .zip(&weights)
                        .map(|(t, w)| w * t * t)
                        .sum::<f64>();
            }
        }
    }
    Ok(total)
}

#[cfg(test)]
mod tests {
    use super::super::fixture::{Y_UP, body, motion};
    use super::*;

    #[test]
    fn the_root_is_not_counted_and_an_undefined_dof_is_an_error() {
        let model = body();
        let root = moving_root(&model, &Y_UP, &motion(&model, &[], (0.0, 0.0)));
        let w = joint_weights(&model, &root);
        assert_eq!(w.len(), model.nq());
        for &c in &root.all {
            assert_eq!(w[c], 0.0);
        }
        assert_eq!(w[3], 1.0); // the hip
        let whole = motion(&model, &[], (0.0, 0.0));
        let e = torque_energy(&whole, &model, Some(Y_UP)).unwrap();
        assert!(e.is_finite() && e > 0.0, "{e}");
        // gravity is the body's unless given
        let free = torque_energy(&whole, &model, Some(Vector3::zeros())).unwrap();
        assert!(free.is_finite() && free > 0.0 && free != e, "{free} vs {e}");
        let gapped = motion(&model, &[4], (0.8, 1.2));
        let err = torque_energy(&gapped, &model, Some(Y_UP))
            .unwrap_err()
            .to_string();
        assert!(err.contains("'knee'") && err.contains("undefined"), "{err}");
    }
}
