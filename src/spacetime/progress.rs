//! Progress of a whole-motion SP, reported to whoever shows it (the
//! language's progress bar): how many gap groups there are, each group that
//! finishes, and within a group each solve of the prior's continuation, each
//! quasi-Newton iteration and each objective evaluation (so a long single
//! group still shows where it is). The library itself draws nothing.

use std::fmt;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

/// What happened.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProgressEvent {
    /// SP split the gaps into this many independent groups.
    Groups(usize),
    /// One group was solved.
    GroupDone,
    /// A group's solve starts: step `step` (from 1) of at most `steps` of
    /// the continuation that lowers the prior (1 of 1 without a prior). A
    /// group whose example could not undercut Hermite runs the steps twice.
    Step { step: usize, steps: usize },
    /// A quasi-Newton iteration of the current solve ended: `iteration`
    /// (from 1, across its rounds) of at most `max`.
    Iteration { iteration: u64, max: u64 },
    /// One evaluation of a transition's objective (cost and gradient).
    Evaluation,
}

type Callback = dyn Fn(ProgressEvent) + Send + Sync;

/// An optional callback; the default reports to no one. Called from the
/// solver's worker threads, so it must be `Send + Sync` and cheap.
#[derive(Clone, Default)]
pub struct Progress(Option<Arc<Callback>>);

impl Progress {
    pub fn new(f: impl Fn(ProgressEvent) + Send + Sync + 'static) -> Self {
        Progress(Some(Arc::new(f)))
    }

    pub fn report(&self, e: ProgressEvent) {
        if let Some(f) = &self.0 {
            f(e);
        }
    }
}

impl fmt::Debug for Progress {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(if self.0.is_some() {
            "Progress(callback)"
        } else {
            "Progress(none)"
        })
    }
}

/// Evaluations between two refreshes of [`Tally::record`]'s caller (an
/// evaluation can take well under a millisecond).
const EVALUATIONS_PER_REFRESH: u64 = 16;

/// The events so far, summed into one line for a progress bar, e.g. "group
/// 1 of 1, solve 2 of ≤5, iteration 37 of ≤300, 412 objective evaluations".
/// Groups run in parallel: the step and iteration are the latest reported.
/// Lock-free (atomics), so the solver's threads only pay for a few stores.
#[derive(Debug, Default)]
pub struct Tally {
    groups: AtomicU64,
    done: AtomicU64,
    step: AtomicU64,
    steps: AtomicU64,
    iteration: AtomicU64,
    max_iterations: AtomicU64,
    evaluations: AtomicU64,
}

impl Tally {
    /// Counts `e`; true when the line changed enough to be redrawn.
    pub fn record(&self, e: ProgressEvent) -> bool {
        let set = |a: &AtomicU64, v: u64| a.store(v, Ordering::Relaxed);
        match e {
            ProgressEvent::Groups(n) => set(&self.groups, n as u64),
            ProgressEvent::GroupDone => {
                self.done.fetch_add(1, Ordering::Relaxed);
            }
            ProgressEvent::Step { step, steps } => {
                set(&self.step, step as u64);
                set(&self.steps, steps as u64);
                set(&self.iteration, 0);
            }
            ProgressEvent::Iteration { iteration, max } => {
                set(&self.iteration, iteration);
                set(&self.max_iterations, max);
            }
            ProgressEvent::Evaluation => {
                let k = self.evaluations.fetch_add(1, Ordering::Relaxed) + 1;
                return k.is_multiple_of(EVALUATIONS_PER_REFRESH);
            }
        }
        true
    }

    /// Groups solved so far.
    pub fn done(&self) -> u64 {
        self.done.load(Ordering::Relaxed)
    }

    /// The progress line (see the type's docs); parts not reported yet are left out.
    pub fn message(&self) -> String {
        let get = |a: &AtomicU64| a.load(Ordering::Relaxed);
        let mut parts = vec![];
        let groups = get(&self.groups);
        if groups > 0 {
            let current = (get(&self.done) + 1).min(groups);
            parts.push(format!("group {current} of {groups}"));
        }
        if get(&self.step) > 0 {
            parts.push(format!(
                "solve {} of ≤{}",
                get(&self.step),
                get(&self.steps)
            ));
        }
        if get(&self.iteration) > 0 {
            parts.push(format!(
                "iteration {} of ≤{}",
                get(&self.iteration),
                get(&self.max_iterations)
            ));
        }
        parts.push(format!("{} objective evaluations", get(&self.evaluations)));
        parts.join(", ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    #[test]
    fn the_callback_sees_every_event_and_the_default_is_silent() {
        let n = Arc::new(AtomicUsize::new(0));
        let m = n.clone();
        let p = Progress::new(move |_| {
            m.fetch_add(1, Ordering::SeqCst);
        });
        p.clone().report(ProgressEvent::Groups(2));
        p.report(ProgressEvent::Evaluation);
        assert_eq!(n.load(Ordering::SeqCst), 2);
        Progress::default().report(ProgressEvent::GroupDone);
    }

    #[test]
    fn the_tally_reads_group_solve_iteration_and_evaluations() {
        let t = Tally::default();
        assert_eq!(t.message(), "0 objective evaluations");
        assert!(t.record(ProgressEvent::Groups(2)));
        assert!(t.record(ProgressEvent::Step { step: 2, steps: 5 }));
        assert!(t.record(ProgressEvent::Iteration {
            iteration: 37,
            max: 300
        }));
        let redraws = (0..412)
            .filter(|_| t.record(ProgressEvent::Evaluation))
            .count();
        assert_eq!(redraws, 412 / 16);
        assert_eq!(
            t.message(),
            "group 1 of 2, solve 2 of ≤5, iteration 37 of ≤300, 412 objective evaluations"
        );
        // a new solve starts its iterations afresh; the last group stays the last
        t.record(ProgressEvent::GroupDone);
        t.record(ProgressEvent::Step { step: 1, steps: 5 });
        t.record(ProgressEvent::GroupDone);
        assert_eq!(t.done(), 2);
        assert_eq!(
            t.message(),
            "group 2 of 2, solve 1 of ≤5, 412 objective evaluations"
        );
    }
}
