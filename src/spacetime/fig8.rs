//! The Fig. 8 case of Rose et al. (§5): every joint DOF of a 44-DOF human
//! left undefined for 0.6 s of a walk and re-made as one transition (the root
//! is an input). One builder for the benchmark (`benches/spacetime.rs`), the
//! report and the tests, so they all measure the same problem; the body and
//! the motion are its inputs — `human44.urdf` of the shared reference data, or
//! the project's own walk ([`example_walk`]) on a fresh clone.

use super::error::{SpError, invalid};
use super::objective::{GapDof, Inputs, Objective, TransitionSettings};
use super::sp::joint_weights;
use super::torque::BodyDynamics;
use super::transition::EndState;
use crate::model::Model;
use crate::motion::Mu;

/// Start and end (s) of the gap in [`example_walk`]: the paper's 0.6 s.
pub const EXAMPLE_GAP: (f64, f64) = (0.6, 1.2);

/// One transition problem: the gaps of every joint DOF over [t0, t1] of a
/// motion, with their end states from it, and the weights (root unactuated).
pub struct Case<'m> {
    pub body: BodyDynamics<'m>,
    pub motion: Mu,
    pub gaps: Vec<GapDof>,
    pub weights: Vec<f64>,
}

/// The case on `model` driven by `motion`, which must define every
/// coordinate over [t0, t1] (the gap's end states and the root inside it come from it).
pub fn case<'m>(model: &'m Model, motion: Mu, t0: f64, t1: f64) -> Result<Case<'m>, SpError> {
    let body = BodyDynamics::new(model);
    let root = crate::ground::moving_root(model, &body.gravity, &motion);
    let names = model.coordinate_names();
    let state = |n: &str, t: f64| -> Result<EndState, SpError> {
        match motion.sample(n, t).map_err(SpError::Motion)? {
            Some([q, v, a]) => Ok(EndState { q, v, a }),
            None => Err(invalid(format!(
                "Fig. 8 case: the motion does not define {n} at t = {t}"
            ))),
        }
    };
    let mut gaps = vec![];
    for (c, n) in names.iter().enumerate() {
        if root.all.contains(&c) {
            continue;
        }
        gaps.push(GapDof {
            coord: c,
            t0,
            t1,
            start: state(n, t0)?,
            end: state(n, t1)?,
        });
    }
    Ok(Case {
        weights: joint_weights(model, &root),
        body,
        motion,
        gaps,
    })
}

impl Case<'_> {
    /// Every coordinate of the motion at t (the gap DOFs' values are ignored by the objective).
    pub fn inputs(
        &self,
        t: f64,
        q: &mut [f64],
        v: &mut [f64],
        a: &mut [f64],
    ) -> Result<(), SpError> {
        for (i, n) in self.body.model.coordinate_names().iter().enumerate() {
            if let Some([x, dx, ddx]) = self.motion.sample(n, t).map_err(SpError::Motion)? {
                q[i] = x;
                v[i] = dx;
                a[i] = ddx;
            }
        }
        Ok(())
    }

    /// The objective at these settings.
    pub fn objective(
        &self,
        settings: &TransitionSettings,
    ) -> Result<Objective<'_, BodyDynamics<'_>>, SpError> {
        let inputs = |t: f64, q: &mut [f64], v: &mut [f64], a: &mut [f64]| self.inputs(t, q, v, a);
        let inputs: &Inputs = &inputs;
        Objective::new(
            &self.body,
            self.gaps.clone(),
            settings,
            self.weights.clone(),
            inputs,
        )
    }
}

/// The project's own data: `human(walk)` (44 DOFs) and the procedural walk
/// of `mocap::synth` fitted to it.
pub fn example_walk() -> Result<(Model, Mu), SpError> {
    use crate::mocap::{bvh, human, synth};
    let err = |e: crate::mocap::MocapError| SpError::Data(e.to_string());
    let f = synth::walk();
    let s = bvh::detect_units(&f.skeleton).metres_per_unit;
    let h = human::human(&f.skeleton, s, 70.0).map_err(err)?;
    let (mu, _) = human::fit(&f, s, &h, Default::default(), None).map_err(err)?;
    Ok((h.model, mu))
}
