//! The stall rule: a solver run that also stops when the best energy fell by
//! less than `tolerance` (relative) over the last `window` iterations,
//! counted across rounds, so the solve ends where progress stalls, not at
//! the end of a round. It also reports every iteration to the progress
//! callback.

use super::report::StopReason;
use crate::spacetime::progress::{Progress, ProgressEvent};
use argmin::core::{
    Error, KV, Problem as ArgminProblem, Solver, State, TerminationReason, TerminationStatus,
};
use std::cell::{Cell, RefCell};

/// The stall rule of one round, and what it shares with the rounds before
/// and after it.
pub(super) struct Stall<'h> {
    /// Iterations done in earlier rounds.
    pub start: u64,
    pub window: u64,
    pub tolerance: f64,
    /// (iteration, best energy) after every iteration so far.
    pub history: &'h RefCell<Vec<(u64, f64)>>,
    /// Set when the stall rule ends the round, so the report can say so
    /// (argmin's own reason is only text): (iterations looked back, tolerance).
    pub stalled: &'h Cell<Option<(u64, f64)>>,
    /// Told of every iteration, out of `max_iters`.
    pub progress: &'h Progress,
    pub max_iters: u64,
}

/// A solver run under the stall rule (see the module docs).
pub(super) struct StallAware<'h, S> {
    pub inner: S,
    pub rule: Stall<'h>,
}

impl<O, I, S> Solver<O, I> for StallAware<'_, S>
where
    I: State<Float = f64>,
    S: Solver<O, I>,
{
    fn name(&self) -> &str {
        self.inner.name()
    }

    fn init(&mut self, problem: &mut ArgminProblem<O>, state: I) -> Result<(I, Option<KV>), Error> {
        self.inner.init(problem, state)
    }

    fn next_iter(
        &mut self,
        problem: &mut ArgminProblem<O>,
        state: I,
    ) -> Result<(I, Option<KV>), Error> {
        let iteration = self.rule.start + state.get_iter() + 1;
        let out = self.inner.next_iter(problem, state)?;
        self.rule.progress.report(ProgressEvent::Iteration {
            iteration,
            max: self.rule.max_iters,
        });
        Ok(out)
    }

    fn terminate(&mut self, state: &I) -> TerminationStatus {
        let status = self.inner.terminate(state);
        if status.terminated() {
            return status;
        }
        let rule = &self.rule;
        let now = rule.start + state.get_iter();
        let e = state.get_best_cost();
        if !e.is_finite() {
            // before the run's first evaluation
            return TerminationStatus::NotTerminated;
        }
        let mut history = rule.history.borrow_mut();
        history.push((now, e));
        let then = history
            .iter()
            .rev()
            .find(|(t, _)| *t + rule.window <= now)
            .copied();
        match then {
            Some((t, e_then)) if e_then - e < rule.tolerance * e.abs() => {
                rule.stalled.set(Some((now - t, rule.tolerance)));
                TerminationStatus::Terminated(TerminationReason::SolverExit("stalled".into()))
            }
            _ => TerminationStatus::NotTerminated,
        }
    }
}

/// Why a round ended: the stall rule if it fired, else argmin's status.
pub(super) fn stop_reason(status: &TerminationStatus, stalled: Option<(u64, f64)>) -> StopReason {
    if let Some((iterations, tolerance)) = stalled {
        return StopReason::Stalled {
            iterations,
            tolerance,
        };
    }
    match status {
        TerminationStatus::Terminated(TerminationReason::SolverConverged) => StopReason::Converged,
        TerminationStatus::Terminated(TerminationReason::MaxItersReached) => {
            StopReason::IterationLimit
        }
        TerminationStatus::Terminated(r) => StopReason::Other(r.text().to_string()),
        TerminationStatus::NotTerminated => StopReason::Other("not terminated".into()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_stall_rule_names_itself_before_argmins_status() {
        let max = TerminationStatus::Terminated(TerminationReason::MaxItersReached);
        assert_eq!(stop_reason(&max, None), StopReason::IterationLimit);
        assert_eq!(
            stop_reason(&max, Some((25, 1e-3))),
            StopReason::Stalled {
                iterations: 25,
                tolerance: 1e-3
            }
        );
        let done = TerminationStatus::Terminated(TerminationReason::SolverConverged);
        assert_eq!(stop_reason(&done, None), StopReason::Converged);
    }
}
