//! The solver's settings (the transition's shape is `TransitionSettings`).

use crate::cancel::CancelToken;
use crate::spacetime::progress::Progress;

/// Solver settings (not the transition's shape: see `TransitionSettings`).
#[derive(Clone, Debug)]
pub struct SolveOptions {
    pub max_iters: u64,
    /// Stop when ‖∇e‖ falls below this fraction of its value at the start.
    pub grad_rtol: f64,
    /// Stop when the last `stall_window` iterations lowered the energy by
    /// less than this fraction of it (`tolerance:` in mx).
    pub tolerance: f64,
    /// Iterations over which `tolerance` is measured (checked after every one).
    pub stall_window: u64,
    /// Stop when an iteration lowers e by less than this fraction of the starting e.
    pub cost_rtol: f64,
    /// Use dense BFGS up to this many unknowns, L-BFGS above.
    pub bfgs_max_vars: usize,
    /// Correction pairs L-BFGS keeps.
    pub lbfgs_memory: usize,
    /// Iterations per round: the preconditioner is rebuilt at the best point
    /// and L-BFGS restarts after each (see the module docs).
    pub relinearise_every: u64,
    pub cancel: CancelToken,
    /// Told of every continuation step, iteration and objective evaluation
    /// (a progress bar's heartbeat).
    pub progress: Progress,
}

impl Default for SolveOptions {
    fn default() -> Self {
        SolveOptions {
            max_iters: 300,
            grad_rtol: 1e-6,
            tolerance: 1e-3,
            stall_window: 25,
            cost_rtol: 1e-12,
            bfgs_max_vars: 40,
            lbfgs_memory: 30,
            relinearise_every: 25,
            cancel: CancelToken::new(),
            progress: Default::default(),
        }
    }
}
