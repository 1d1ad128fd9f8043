//! Minimise one group's objective with argmin: BFGS for small problems, where
//! the dense inverse-Hessian update is cheap and converges in fewer steps;
//! L-BFGS beyond, where (nm)² per step would dominate (Rose §3.2.3).
//! The solver works in variables whitened by a Gauss–Newton preconditioner;
//! the body's pose (hence its mass matrix and gravity torques) moves away
//! from the Hermite start as the solve proceeds, so the solve runs in rounds
//! of `relinearise_every` iterations: after each, the preconditioner is
//! rebuilt at the best point so far and the quasi-Newton run restarts there.
//! The solve ends when the last 25 iterations (`stall_window`, checked after
//! every iteration, across rounds) lowered the energy by less than
//! `tolerance` (relative): the objective is non-convex and its gradient never
//! gets small in relative terms before the energy has stopped moving, so
//! energy progress is the honest stopping rule. Measured on the 44-DOF Fig. 8 case
//! (`cargo bench --bench spacetime`): see the solver table there.
//! Evaluation shares one pass for cost and gradient (the adjoint gives both),
//! remembers the best point seen, and polls a `CancelToken`.
//!
//! Measured alternatives that did not pay on the 44-DOF Fig. 8 case (5
//! coefficients, 190 unknowns; the default needs 150 iterations, 175
//! evaluations and 6 preconditioner builds to land 0.3 % above the converged
//! optimum):
//! - Gauss–Newton or Levenberg–Marquardt steps: the residual is large (τ does
//!   not vanish at the optimum) and the ignored Σ τ ∂²τ curvature is of the
//!   same size as JᵀJ, so LM keeps λ ≈ 0.1 and after 60 steps (46 Jacobian
//!   builds) stands where L-BFGS is after 40 iterations.
//! - Dense BFGS (argmin) on all 190 unknowns: 2–3 evaluations per iteration
//!   and 500–900 evaluations in all.
//! - An L-BFGS whose correction pairs survive re-linearisation (H₀ = the new
//!   Gauss–Newton inverse): 218–260 evaluations, no better.
//! - Re-linearising every 5–15 iterations: 145–176 evaluations (as many) for
//!   1.5–3 times the preconditioner builds; every 35–75: 225–276.
//! - Leaving the ∂τ/∂q̇ blocks out of the preconditioner: twice the iterations.
//! - A coarse first solve on 2–4 Gauss points per piece: the coarse problem
//!   needs as many iterations as the fine one.
//!
//! The files, in the order a solve runs: [`options`] and [`report`] (what
//! goes in, what comes out); [`groups`] splits a motion's gaps into groups
//! solved in parallel, each by [`continuation`] (the prior lowered step by
//! step until the transition costs less torque than Hermite) over
//! [`problem`] (what every group shares); each step is one quasi-Newton
//! [`run`] in rounds, evaluating through [`eval`] (cost and gradient in one
//! pass, the best point kept) under the [`stall`] rule.

mod continuation;
mod eval;
pub mod ground_model;
mod group;
pub mod groups;
pub mod options;
pub mod problem;
pub mod report;
mod run;
mod stall;

pub use ground_model::{GroundModel, GroundSettings, GroundStep, PlanSource};
pub use groups::{group_overlapping, solve_all};
pub use options::SolveOptions;
pub use problem::{FindExample, LayExample, PriorTerm, Problem};
pub use report::{GapReport, GroupSolution, StopReason};
pub use run::{solve_group, solve_group_from};
