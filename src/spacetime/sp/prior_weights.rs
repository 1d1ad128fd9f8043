//! The weights of SP's kinematic prior per coordinate (see [`prior_weights`]).

use super::checks::motion_err;
#[cfg(test)]
use super::options::AUTO_TIME_SCALE;
use super::options::Prior;
use crate::model::Model;
use crate::motion::{JointSampler, Mu};
use crate::spacetime::error::SpError;
use crate::spacetime::objective::GapDof;

/// Fewest kg·m² (or kg) a DOF's inertia scale counts as, so that a massless
/// link (an End Site, a placeholder) still gets a finite prior.
const MIN_INERTIA_SCALE: f64 = 1e-6;

/// Least inertia scale of a gap DOF, as a fraction of the largest in its gap:
/// a DOF that moves almost no mass (a toe of zero mass, a finger) would get
/// almost no prior and no torque, leaving the solver free to swing it (the
/// preconditioned steps are large exactly where the objective is flat).
const RELATIVE_INERTIA_FLOOR: f64 = 0.1;

/// Per model coordinate, the weights [c_v, c_a] of SP's kinematic prior
/// (zero for coordinates without a gap): c_a = λ s², c_v = λ s²/T², where
/// s = M_dd, the coordinate's own inertia at the start of its first gap (at
/// least [`RELATIVE_INERTIA_FLOOR`] of the largest in that gap).
///
/// Why: ∫Στ² alone leaves DOFs that barely move any mass (fingers, toes, a
/// hand turning about its long axis, two Euler channels near gimbal lock
/// turning against each other) free to do anything, and lets heavy limbs drift
/// toward low-gravity poses far from what a person does. (s q̈)² is the torque
/// the DOF would need to accelerate its own inertia alone, so the prior is in
/// torque² units and holds every DOF in proportion to its own torque scale,
/// light or heavy. Its q̈ part alone is minimised by the cubic Hermite curve
/// (with position and velocity fixed at both ends), so without an example SP
/// never ends above Hermite in e = ∫Στ² + prior; the q̇/T² part damps the end
/// velocities over a time T, as captured motion does over long gaps (the slerp
/// baseline, with no velocity at all, beats Hermite there). With an example r
/// the prior is minimised by r plus the smooth correction that meets the end
/// states.
pub fn prior_weights(
    model: &Model,
    m: &Mu,
    gaps: &[GapDof],
    prior: &Prior,
) -> Result<Vec<[f64; 2]>, SpError> {
    let n = model.nq();
    let mut out = vec![[0.0; 2]; n];
    if prior.smoothness == 0.0 || gaps.is_empty() {
        return Ok(out);
    }
    prior.check()?;
    let names = model.coordinate_names();
    let mut ws = crate::dynamics::Workspace::new(model);
    let mut mm = nalgebra::DMatrix::zeros(n, n);
    let mut done = vec![false; n];
    let sampler = JointSampler::new(m, names);
    for g in gaps {
        if done[g.coord] {
            continue;
        }
        // the pose just before the gap, every coordinate defined there (0 where not)
        let q: Vec<f64> = sampler
            .positions(g.t0)
            .map_err(motion_err)?
            .into_iter()
            .map(|x| if x.is_nan() { 0.0 } else { x })
            .collect();
        crate::dynamics::mass_matrix(model, &mut ws, &q, &mut mm).map_err(SpError::Dynamics)?;
        let same_gap = |h: &&GapDof| (h.t0 - g.t0).abs() <= crate::motion::time_tol(g.t0);
        let largest = gaps
            .iter()
            .filter(same_gap)
            .map(|h| mm[(h.coord, h.coord)])
            .fold(0.0, f64::max);
        let floor = (RELATIVE_INERTIA_FLOOR * largest).max(MIN_INERTIA_SCALE);
        for h in gaps.iter().filter(same_gap) {
            if !done[h.coord] {
                let s = mm[(h.coord, h.coord)].max(floor);
                let ca = prior.smoothness * s * s;
                let t = prior.time_constant_for(h.t1 - h.t0);
                out[h.coord] = [ca / (t * t), ca];
                done[h.coord] = true;
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::super::filling::Filling;
    use super::super::fixture::{Y_UP, body, motion};
    use super::*;

    #[test]
    fn only_gap_dofs_get_a_prior_in_proportion_to_their_inertia() {
        let model = body();
        let m = motion(&model, &[3, 4], (0.8, 1.2));
        let gaps = Filling::new(&m, &model, Y_UP).gaps().unwrap();
        let w = prior_weights(&model, &m, &gaps, &Prior::default()).unwrap();
        for (c, [cv, ca]) in w.iter().enumerate() {
            assert_eq!(*ca > 0.0 && *cv > 0.0, c == 3 || c == 4, "{c}: {w:?}");
        }
        // the hip moves thigh and shin, the knee the shin alone
        assert!(w[3][1] > w[4][1], "{w:?}");
        // T = τ₀²/d for a gap of d seconds
        let t = AUTO_TIME_SCALE * AUTO_TIME_SCALE / 0.4;
        assert!(
            (w[3][0] - w[3][1] / (t * t)).abs() <= 1e-9 * w[3][0],
            "{w:?}"
        );
        assert!(
            prior_weights(&model, &m, &gaps, &Prior::none())
                .unwrap()
                .iter()
                .flatten()
                .all(|v| *v == 0.0)
        );
        let bad = Prior {
            smoothness: -1.0,
            ..Prior::default()
        };
        assert!(prior_weights(&model, &m, &gaps, &bad).is_err());
        let bad = Prior {
            time_constant: Some(0.0),
            ..Prior::default()
        };
        assert!(prior_weights(&model, &m, &gaps, &bad).is_err());
    }
}
