//! Kinematically driven coordinates: coordinates that move at a constant rate
//! whatever the forces (a motor of unlimited torque), while the others respond
//! to the dynamics. A moving mechanism (the spinning wire frame of the beads)
//! and a deforming joint (a spline surface whose shape changes with time,
//! carried by an extra coordinate that runs like a clock) are both scenes with
//! driven coordinates, so the engine needs no time-dependent joint type: the
//! time dependence lives in a coordinate whose velocity is fixed.
//!
//! With P the driven and F the free coordinates, q̈_P = 0 and
//!   M_FF q̈_F = τ_F − h_F(q, q̇, g, f_ext),
//! where h is inverse dynamics at zero acceleration. Unlike the articulated-body
//! algorithm this never divides by M_PP, so a driven coordinate may move no mass
//! at some instant (a deforming surface that pauses). It costs a mass matrix and
//! a Cholesky factorisation (O(n³)): fine for the small mechanisms it serves;
//! scenes without driven coordinates keep the O(n) path.

use crate::dynamics::state::{Forces, JointState};
use crate::dynamics::workspace::Workspace;
use crate::dynamics::{DynamicsError, inverse_dynamics_ext, mass_matrix};
use crate::lie::Wrench;
use crate::model::Model;
use nalgebra::{DMatrix, DVector};

/// A coordinate held at a constant velocity `rate`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Driven {
    pub coordinate: usize,
    /// Its velocity (coordinate units per second), also its initial velocity.
    pub rate: f64,
}

/// Buffers for [`driven_accelerations`]; allocated once per scene workspace.
#[derive(Clone, Debug)]
pub struct DrivenBuffers {
    zeros: Vec<f64>,
    bias: Vec<f64>,
    no_force: Vec<Wrench>,
    mass: DMatrix<f64>,
    free: Vec<usize>,
}

impl DrivenBuffers {
    pub fn new(model: &Model, driven: &[Driven]) -> Self {
        let n = model.nq();
        DrivenBuffers {
            zeros: vec![0.0; n],
            bias: vec![0.0; n],
            no_force: vec![Wrench::zeros(); model.num_links()],
            mass: DMatrix::zeros(n, n),
            free: (0..n)
                .filter(|i| driven.iter().all(|d| d.coordinate != *i))
                .collect(),
        }
    }
}

/// `q̈` with the `driven` coordinates held at constant velocity, under joint
/// `forces` (joint forces, gravity and link wrenches in link frames, as RNEA takes them).
pub fn driven_accelerations(
    model: &Model,
    ws: &mut Workspace,
    buf: &mut DrivenBuffers,
    q: &[f64],
    v: &[f64],
    forces: &Forces,
    qdd: &mut [f64],
) -> Result<(), DynamicsError> {
    let tau = forces.tau;
    let fext = forces.fext.unwrap_or(&buf.no_force);
    let at_rest = JointState::new(q, v, &buf.zeros);
    inverse_dynamics_ext(model, ws, &at_rest, forces.gravity, fext, &mut buf.bias)?;
    mass_matrix(model, ws, q, &mut buf.mass)?;
    let f = &buf.free;
    let mff = DMatrix::from_fn(f.len(), f.len(), |r, c| buf.mass[(f[r], f[c])]);
    let rhs = DVector::from_fn(f.len(), |r, _| tau[f[r]] - buf.bias[f[r]]);
    let acc = mff.cholesky().map(|ch| ch.solve(&rhs)).ok_or_else(|| {
        DynamicsError::Singular(
            "the mass matrix of the free (not driven) coordinates is singular: a free coordinate moves no mass"
                .into(),
        )
    })?;
    qdd.iter_mut().for_each(|x| *x = 0.0);
    for (r, &i) in f.iter().enumerate() {
        qdd[i] = acc[r];
    }
    Ok(())
}
