//! Per-call dynamics timings on a URDF, side by side with Pinocchio's C++
//! timer when it is built (`$MX_SHARED/tools/pinocchio/build.sh
//! /tmp/pinocchio-bench`, or `$MX_PINOCCHIO_BENCH`), run in the same session on
//! the same file. The measurement is the one of `benches/dynamics.rs`, which
//! also counts instructions per call under callgrind through [`drive`].

use crate::dynamics::{
    CrbaFrame, DynamicsError, JointState, StateGradient, Workspace, forward_dynamics,
    inverse_dynamics, mass_matrix, mass_matrix_in, rnea_derivatives, torque_sq_gradient,
};
use crate::model::Model;
use crate::report::error::ReportError;
use nalgebra::DMatrix;
use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The algorithms timed beside Pinocchio, in the order of [`pinocchio`]'s and
/// [`per_call`]'s results (named as Pinocchio's timer names them).
pub const ALGORITHMS: [&str; 4] = ["rnea", "aba", "crba", "rnea_derivatives"];

/// Everything mx times, by the index [`drive`] and [`per_call_of`] take: the
/// four of [`ALGORITHMS`], the adjoint Σwτ² gradient, and the mass matrix by
/// each pass whatever the workspace would choose (`crba_world`, `crba_link`).
pub const TIMED: [&str; 7] = [
    "rnea",
    "aba",
    "crba",
    "rnea_derivatives",
    "adjoint",
    "crba_world",
    "crba_link",
];

/// Median µs per call of `f(i)` over `n` states, timing each call after a warm-up.
pub fn median_us(n: usize, mut f: impl FnMut(usize)) -> f64 {
    for i in 0..n.min(200) {
        f(i);
    }
    let mut t: Vec<f64> = (0..n)
        .map(|i| {
            let s = Instant::now();
            f(i);
            s.elapsed().as_secs_f64() * 1e6
        })
        .collect();
    t.sort_by(|a, b| a.total_cmp(b));
    t[n / 2]
}

/// Path of Pinocchio's timer: `$MX_PINOCCHIO_BENCH`, else `$PINOCCHIO_BENCH`,
/// else where `build.sh` puts it by default.
pub fn pinocchio_exe() -> PathBuf {
    std::env::var_os("MX_PINOCCHIO_BENCH")
        .or_else(|| std::env::var_os("PINOCCHIO_BENCH"))
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("/tmp/pinocchio-bench/bench"))
}

/// Pinocchio's medians in µs (rnea, aba, crba, rnea_derivatives), if its timer runs.
pub fn pinocchio(urdf: &Path) -> Option<[f64; 4]> {
    let out = std::process::Command::new(pinocchio_exe())
        .arg(urdf)
        .output()
        .ok()?;
    let text = String::from_utf8_lossy(&out.stdout);
    let get = |name: &str| -> Option<f64> {
        text.lines()
            .find(|l| l.split_whitespace().next() == Some(name))
            .and_then(|l| l.split_whitespace().nth(1))
            .and_then(|x| x.parse().ok())
    };
    Some([
        get(ALGORITHMS[0])?,
        get(ALGORITHMS[1])?,
        get(ALGORITHMS[2])?,
        get(ALGORITHMS[3])?,
    ])
}

/// Random states `(q, q̇, q̈)` (a fixed xorshift seed, so every run times the same ones).
fn random_states(n: usize, n_states: usize) -> Vec<[Vec<f64>; 3]> {
    let mut s = 0x1234_5678u64;
    let mut r = |lo: f64, hi: f64| {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        lo + (hi - lo) * ((s >> 11) as f64 / (1u64 << 53) as f64)
    };
    (0..n_states)
        .map(|_| {
            [
                (0..n).map(|_| r(-1.0, 1.0)).collect(),
                (0..n).map(|_| r(-2.0, 2.0)).collect(),
                (0..n).map(|_| r(-5.0, 5.0)).collect(),
            ]
        })
        .collect()
}

/// One model's states and every output buffer: each call allocates nothing.
struct Calls<'a> {
    model: &'a Model,
    states: Vec<[Vec<f64>; 3]>,
    ws: Workspace,
    out: Vec<f64>,
    grad: [Vec<f64>; 3],
    w: Vec<f64>,
    mm: DMatrix<f64>,
    dq: DMatrix<f64>,
    dv: DMatrix<f64>,
}

impl<'a> Calls<'a> {
    fn new(model: &'a Model, n_states: usize) -> Self {
        let n = model.nq();
        Calls {
            model,
            states: random_states(n, n_states),
            ws: Workspace::new(model),
            out: vec![0.0; n],
            grad: [vec![0.0; n], vec![0.0; n], vec![0.0; n]],
            w: vec![1.0; n],
            mm: DMatrix::zeros(n, n),
            dq: DMatrix::zeros(n, n),
            dv: DMatrix::zeros(n, n),
        }
    }

    /// Algorithm `k` (as [`TIMED`]) at state `i`.
    fn call(&mut self, k: usize, i: usize) -> Result<(), DynamicsError> {
        let model = self.model;
        let g = model.default_gravity;
        let [q, v, a] = &self.states[i];
        let ws = &mut self.ws;
        match k {
            0 => inverse_dynamics(model, ws, q, v, a, &g, &mut self.out)?,
            1 => forward_dynamics(model, ws, q, v, a, &g, &mut self.out)?,
            2 => mass_matrix(model, ws, q, &mut self.mm)?,
            3 => rnea_derivatives(
                model,
                ws,
                &JointState::new(q, v, a),
                &g,
                &mut self.dq,
                &mut self.dv,
            )?,
            5 => mass_matrix_in(model, ws, q, &mut self.mm, CrbaFrame::World)?,
            6 => mass_matrix_in(model, ws, q, &mut self.mm, CrbaFrame::Link)?,
            _ => {
                let [gq, gv, ga] = &mut self.grad;
                let j = torque_sq_gradient(
                    model,
                    ws,
                    &JointState::new(q, v, a),
                    &g,
                    &self.w,
                    StateGradient {
                        q: gq,
                        v: gv,
                        a: ga,
                    },
                )?;
                black_box(j);
            }
        }
        black_box((&self.out, &self.mm, &self.dq));
        Ok(())
    }
}

/// Our medians in µs: rnea, aba, crba, rnea_derivatives, adjoint Σwτ² gradient.
pub fn per_call(model: &Model, n_states: usize) -> Result<[f64; 5], ReportError> {
    let t = per_call_of(model, n_states, &[0, 1, 2, 3, 4])?;
    Ok([t[0], t[1], t[2], t[3], t[4]])
}

/// Our medians in µs of the algorithms `which` (indices into [`TIMED`]), timed
/// one after another on the same states.
pub fn per_call_of(
    model: &Model,
    n_states: usize,
    which: &[usize],
) -> Result<Vec<f64>, ReportError> {
    let mut calls = Calls::new(model, n_states);
    // Check once that every algorithm accepts the model before timing (errors, not panics).
    for &k in which {
        calls.call(k, 0)?;
    }
    Ok(which
        .iter()
        .map(|&k| {
            median_us(n_states, |i| {
                let _ = calls.call(k, i);
            })
        })
        .collect())
}

/// Runs algorithm `algorithm` (a name of [`TIMED`]) `n_calls` times,
/// cycling over 64 random states, and nothing else: the driver a process runs
/// under callgrind, so that two runs of different lengths differ only by calls
/// and their difference gives instructions per call.
pub fn drive(model: &Model, algorithm: &str, n_calls: usize) -> Result<(), ReportError> {
    let k = TIMED.iter().position(|a| *a == algorithm).ok_or_else(|| {
        ReportError::UnknownAlgorithm {
            name: algorithm.to_string(),
            known: TIMED.join(", "),
        }
    })?;
    let mut calls = Calls::new(model, 64);
    for i in 0..n_calls {
        calls.call(k, i % 64)?;
    }
    Ok(())
}
