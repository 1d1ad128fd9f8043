//! A progress bar on stderr for built-ins that may run long (SP, cyclify):
//! invisible for the first half second, so quick calls print nothing, and
//! never drawn when stderr is not a terminal (scripts piped to files, tests).

use std::io::IsTerminal;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// How long a call runs before its bar appears.
pub const SHOW_AFTER: Duration = Duration::from_millis(500);

pub struct Busy {
    bar: ProgressBar,
    done: Arc<AtomicBool>,
    watcher: Option<JoinHandle<()>>,
}

impl Busy {
    /// Start timing `what`; `template` is an indicatif template (`{msg}`, `{bar}`, `{pos}`, `{len}`…).
    pub fn start(what: &str, template: &str) -> Self {
        let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::hidden());
        bar.set_style(
            ProgressStyle::with_template(template)
                .unwrap_or_else(|_| ProgressStyle::default_spinner()),
        );
        bar.set_prefix(what.to_string());
        let done = Arc::new(AtomicBool::new(false));
        let watcher = std::io::stderr().is_terminal().then(|| {
            let (bar, done) = (bar.clone(), done.clone());
            std::thread::spawn(move || {
                let t0 = Instant::now();
                while t0.elapsed() < SHOW_AFTER {
                    if done.load(Ordering::SeqCst) {
                        return;
                    }
                    std::thread::sleep(Duration::from_millis(20));
                }
                if !done.load(Ordering::SeqCst) {
                    bar.set_draw_target(ProgressDrawTarget::stderr());
                    bar.enable_steady_tick(Duration::from_millis(100));
                }
            })
        });
        Busy { bar, done, watcher }
    }

    /// The bar, to set its length, position and message from any thread.
    pub fn bar(&self) -> &ProgressBar {
        &self.bar
    }
}

impl Drop for Busy {
    fn drop(&mut self) {
        self.done.store(true, Ordering::SeqCst);
        if let Some(w) = self.watcher.take() {
            let _ = w.join();
        }
        self.bar.finish_and_clear();
    }
}
