//! Time integration of a [`Scene`]: explicit Euler (the spline-joint paper's),
//! semi-implicit (symplectic) Euler, classical RK4, and the adaptive embedded
//! Dormand–Prince 5(4) with a user tolerance. The state is `x = [q; q̇]`.

#![allow(clippy::needless_range_loop)] // index loops over coupled arrays read clearer here

use crate::cancel::CancelToken;
use crate::dynamics::DynamicsError;
use crate::dynamics::scene::{Scene, SceneWorkspace};

/// How to advance the state in time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Integrator {
    /// `q += h q̇; q̇ += h q̈` (both from the old state). First order.
    Euler,
    /// `q̇ += h q̈; q += h q̇_new`. First order, symplectic: energy stays bounded.
    SemiImplicitEuler,
    /// Classical fourth-order Runge–Kutta.
    Rk4,
    /// Dormand–Prince 5(4), error per step `≤ atol + rtol |x|` (max norm);
    /// `dt` is then only the output interval.
    DormandPrince { rtol: f64, atol: f64 },
}

impl Integrator {
    /// By name, as the language spells it: `euler`, `semi_implicit_euler` (`symplectic_euler`),
    /// `rk4`, `dopri5` (`adaptive`, `rk45`) with `tol` as both tolerances.
    pub fn from_name(name: &str, tol: Option<f64>) -> Result<Self, DynamicsError> {
        Ok(match name {
            "euler" | "explicit_euler" => Integrator::Euler,
            "semi_implicit_euler" | "symplectic_euler" => Integrator::SemiImplicitEuler,
            "rk4" => Integrator::Rk4,
            "dopri5" | "adaptive" | "rk45" | "dormand_prince" => {
                let t = tol.unwrap_or(1e-8);
                Integrator::DormandPrince { rtol: t, atol: t }
            }
            other => {
                return Err(DynamicsError::Input(format!(
                    "unknown integrator `{other}`; use euler, semi_implicit_euler, rk4 or dopri5"
                )));
            }
        })
    }
}

/// A simulated motion: samples every `dt`.
#[derive(Clone, Debug, Default)]
pub struct Trajectory {
    pub names: Vec<String>,
    pub t: Vec<f64>,
    pub q: Vec<Vec<f64>>,
    pub v: Vec<Vec<f64>>,
    /// Steps taken (accepted) and rejected, and evaluations of the dynamics.
    pub steps: usize,
    pub rejected: usize,
    pub evaluations: usize,
}

/// Initial state.
#[derive(Clone, Debug, PartialEq)]
pub struct State {
    pub q: Vec<f64>,
    pub v: Vec<f64>,
}

struct Stepper<'a> {
    scene: &'a Scene,
    sw: SceneWorkspace,
    n: usize,
    k: [Vec<f64>; 7],
    tmp: Vec<f64>,
    x5: Vec<f64>,
    qdd: Vec<f64>,
    evals: usize,
}

impl<'a> Stepper<'a> {
    /// `dx = [q̇; q̈(q, q̇)]`.
    fn deriv(&mut self, x: &[f64], out_idx: usize) -> Result<(), DynamicsError> {
        let n = self.n;
        self.evals += 1;
        self.scene
            .accelerations(&mut self.sw, &x[..n], &x[n..], &[], &mut self.qdd)?;
        let k = &mut self.k[out_idx];
        k[..n].copy_from_slice(&x[n..]);
        k[n..].copy_from_slice(&self.qdd);
        Ok(())
    }

    /// `tmp = x + h Σ c_j k_j`.
    fn combine(&mut self, x: &[f64], h: f64, coeffs: &[(usize, f64)]) {
        for i in 0..x.len() {
            let mut s = 0.0;
            for &(j, c) in coeffs {
                s += c * self.k[j][i];
            }
            self.tmp[i] = x[i] + h * s;
        }
    }

    fn fixed_step(
        &mut self,
        x: &mut [f64],
        h: f64,
        method: Integrator,
    ) -> Result<(), DynamicsError> {
        let n = self.n;
        match method {
            Integrator::Euler => {
                self.deriv(x, 0)?;
                for i in 0..2 * n {
                    x[i] += h * self.k[0][i];
                }
            }
            Integrator::SemiImplicitEuler => {
                self.deriv(x, 0)?;
                for i in 0..n {
                    x[n + i] += h * self.k[0][n + i];
                    x[i] += h * x[n + i];
                }
            }
            Integrator::Rk4 => {
                self.deriv(x, 0)?;
                self.combine(x, h, &[(0, 0.5)]);
                let t = std::mem::take(&mut self.tmp);
                self.deriv(&t, 1)?;
                self.tmp = t;
                self.combine(x, h, &[(1, 0.5)]);
                let t = std::mem::take(&mut self.tmp);
                self.deriv(&t, 2)?;
                self.tmp = t;
                self.combine(x, h, &[(2, 1.0)]);
                let t = std::mem::take(&mut self.tmp);
                self.deriv(&t, 3)?;
                self.tmp = t;
                for i in 0..2 * n {
                    x[i] += h / 6.0
                        * (self.k[0][i] + 2.0 * self.k[1][i] + 2.0 * self.k[2][i] + self.k[3][i]);
                }
            }
            Integrator::DormandPrince { .. } => {
                unreachable!("adaptive steps go through dopri_step")
            }
        }
        Ok(())
    }

    /// One Dormand–Prince attempt of size h from x: fills `x5` and returns the scaled error.
    fn dopri_step(
        &mut self,
        x: &[f64],
        h: f64,
        rtol: f64,
        atol: f64,
    ) -> Result<f64, DynamicsError> {
        const A: [&[(usize, f64)]; 6] = [
            &[(0, 1.0 / 5.0)],
            &[(0, 3.0 / 40.0), (1, 9.0 / 40.0)],
            &[(0, 44.0 / 45.0), (1, -56.0 / 15.0), (2, 32.0 / 9.0)],
            &[
                (0, 19372.0 / 6561.0),
                (1, -25360.0 / 2187.0),
                (2, 64448.0 / 6561.0),
                (3, -212.0 / 729.0),
            ],
            &[
                (0, 9017.0 / 3168.0),
                (1, -355.0 / 33.0),
                (2, 46732.0 / 5247.0),
                (3, 49.0 / 176.0),
                (4, -5103.0 / 18656.0),
            ],
            &[
                (0, 35.0 / 384.0),
                (2, 500.0 / 1113.0),
                (3, 125.0 / 192.0),
                (4, -2187.0 / 6784.0),
                (5, 11.0 / 84.0),
            ],
        ];
        // b5 − b4 (error weights)
        const E: [f64; 7] = [
            35.0 / 384.0 - 5179.0 / 57600.0,
            0.0,
            500.0 / 1113.0 - 7571.0 / 16695.0,
            125.0 / 192.0 - 393.0 / 640.0,
            -2187.0 / 6784.0 + 92097.0 / 339200.0,
            11.0 / 84.0 - 187.0 / 2100.0,
            -1.0 / 40.0,
        ];
        self.deriv(x, 0)?;
        for (s, row) in A.iter().enumerate() {
            self.combine(x, h, row);
            let t = std::mem::take(&mut self.tmp);
            let r = self.deriv(&t, s + 1);
            self.tmp = t;
            r?;
        }
        // The 7th stage was evaluated at the 5th-order solution (tmp).
        self.x5.copy_from_slice(&self.tmp);
        let mut err: f64 = 0.0;
        for i in 0..x.len() {
            let mut e = 0.0;
            for (j, ej) in E.iter().enumerate() {
                e += ej * self.k[j][i];
            }
            let sc = atol + rtol * x[i].abs().max(self.x5[i].abs());
            err = err.max((h * e).abs() / sc);
        }
        Ok(err)
    }
}

fn diverged(t: f64) -> DynamicsError {
    DynamicsError::Singular(format!(
        "the simulation diverged at t = {t:.6} s (the state is no longer finite); \
         use a smaller dt or a more stable integrator (semi_implicit_euler, rk4, dopri5)"
    ))
}

/// An error inside a step, with the time and the usual cure.
fn in_step(e: DynamicsError, t: f64) -> DynamicsError {
    match e {
        DynamicsError::Cancelled => e,
        other => DynamicsError::Singular(format!(
            "simulation stopped at t = {t:.6} s: {other}; if the motion was diverging, use a \
             smaller dt or a more stable integrator (semi_implicit_euler, rk4, dopri5)"
        )),
    }
}

/// Simulates `scene` from `init` for `duration` seconds, sampling every `dt`.
/// Polls `cancel` every step; `progress(fraction)` is called at every sample.
pub fn simulate(
    scene: &Scene,
    duration: f64,
    dt: f64,
    method: Integrator,
    init: &State,
    cancel: &CancelToken,
    progress: &mut dyn FnMut(f64),
) -> Result<Trajectory, DynamicsError> {
    let m = &*scene.model;
    m.check_vec("initial q", &init.q, m.nq())?;
    m.check_vec("initial v", &init.v, m.nq())?;
    if !(duration.is_finite() && duration >= 0.0) {
        return Err(DynamicsError::Input(format!(
            "duration must be ≥ 0 s, got {duration}"
        )));
    }
    if !(dt.is_finite() && dt > 0.0) {
        return Err(DynamicsError::Input(format!("dt must be > 0 s, got {dt}")));
    }
    let steps_f = (duration / dt).round();
    if steps_f > 1e8 {
        return Err(DynamicsError::Input(format!(
            "{duration} s at dt = {dt} s is {steps_f:e} samples; use a larger dt"
        )));
    }
    if let Integrator::DormandPrince { rtol, atol } = method
        && !(rtol.is_finite() && atol.is_finite() && rtol >= 0.0 && atol > 0.0
            || rtol > 0.0 && atol >= 0.0)
    {
        return Err(DynamicsError::Input(
            "adaptive tolerances must be finite and > 0".into(),
        ));
    }
    let nsteps = steps_f as usize;
    let n = m.nq();
    // The trajectory keeps q and q̇ at every sample: bound its memory (~1.6 GB).
    if (nsteps as f64 + 1.0) * (2 * n.max(1)) as f64 > 2e8 {
        return Err(DynamicsError::Input(format!(
            "{duration} s at dt = {dt} s gives {} samples of {n} coordinates, too many to keep; \
             use a larger dt or a shorter duration",
            nsteps + 1
        )));
    }
    let mut st = Stepper {
        scene,
        sw: SceneWorkspace::new(scene),
        n,
        k: std::array::from_fn(|_| vec![0.0; 2 * n]),
        tmp: vec![0.0; 2 * n],
        x5: vec![0.0; 2 * n],
        qdd: vec![0.0; n],
        evals: 0,
    };
    let mut x: Vec<f64> = init.q.iter().chain(&init.v).copied().collect();
    let mut tr = Trajectory {
        names: m.coordinate_names().to_vec(),
        t: Vec::with_capacity(nsteps + 1),
        q: Vec::with_capacity(nsteps + 1),
        v: Vec::with_capacity(nsteps + 1),
        ..Default::default()
    };
    let record = |tr: &mut Trajectory, t: f64, x: &[f64]| {
        tr.t.push(t);
        tr.q.push(x[..n].to_vec());
        tr.v.push(x[n..].to_vec());
    };
    record(&mut tr, 0.0, &x);
    let mut h_adapt = dt;
    for s in 0..nsteps {
        cancel.check()?;
        let t0 = s as f64 * dt;
        let t1 = (s + 1) as f64 * dt;
        match method {
            Integrator::DormandPrince { rtol, atol } => {
                let mut t = t0;
                while t < t1 {
                    let h = h_adapt.min(t1 - t);
                    if h <= 1e-14 * (1.0 + t.abs()) {
                        return Err(DynamicsError::Singular(format!(
                            "the adaptive step size underflowed at t = {t:.6} s; the motion may be \
                             singular there (or loosen the tolerance)"
                        )));
                    }
                    let err = st
                        .dopri_step(&x, h, rtol, atol)
                        .map_err(|e| in_step(e, t))?;
                    if err.is_nan() {
                        h_adapt = h * 0.2;
                        tr.rejected += 1;
                        continue;
                    }
                    if err <= 1.0 {
                        x.copy_from_slice(&st.x5);
                        t = if h == t1 - t { t1 } else { t + h };
                        tr.steps += 1;
                    } else {
                        tr.rejected += 1;
                    }
                    let fac = if err == 0.0 {
                        5.0
                    } else {
                        (0.9 * err.powf(-0.2)).clamp(0.2, 5.0)
                    };
                    // A step shortened to land on the output grid says little about
                    // the step size the motion allows: do not let it shrink the next one.
                    h_adapt = if err <= 1.0 && h < h_adapt {
                        h_adapt.max(h * fac)
                    } else {
                        h * fac
                    };
                    cancel.check()?;
                }
            }
            _ => {
                st.fixed_step(&mut x, dt, method)
                    .map_err(|e| in_step(e, t0))?;
                tr.steps += 1;
            }
        }
        if x.iter().any(|v| !v.is_finite()) {
            return Err(diverged(t1));
        }
        record(&mut tr, t1, &x);
        progress((s + 1) as f64 / nsteps as f64);
    }
    tr.evaluations = st.evals;
    Ok(tr)
}
