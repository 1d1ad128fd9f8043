//! Progress of a whole-motion SP, reported to whoever shows it (the
//! language's progress bar): how many gap groups there are, each group that
//! finishes, and each objective evaluation (so a long single group still
//! shows life). The library itself draws nothing.

use std::fmt;
use std::sync::Arc;

/// What happened.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProgressEvent {
    /// SP split the gaps into this many independent groups.
    Groups(usize),
    /// One group was solved.
    GroupDone,
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
}
