//! Progress of long runs on stderr: one line per job, updated in place, shown only on a terminal
//! so pipes and logs stay clean.

use std::io::{IsTerminal, Write};
use std::time::Instant;

/// A percentage counter for `total` steps of the job named `label`.
pub struct Progress {
    label: String,
    total: usize,
    shown_percent: Option<usize>,
    started: Instant,
    enabled: bool,
}

impl Progress {
    /// Starts counting; draws nothing unless stderr is a terminal.
    pub fn new(label: impl Into<String>, total: usize) -> Self {
        Self {
            label: label.into(),
            total: total.max(1),
            shown_percent: None,
            started: Instant::now(),
            enabled: std::io::stderr().is_terminal(),
        }
    }

    /// Records that `done` steps are finished; redraws when the whole percentage changes.
    pub fn update(&mut self, done: usize) {
        if !self.enabled {
            return;
        }
        let percent = (100 * done.min(self.total)) / self.total;
        if self.shown_percent == Some(percent) {
            return;
        }
        self.shown_percent = Some(percent);
        let elapsed = self.started.elapsed().as_secs_f64();
        let mut err = std::io::stderr().lock();
        let _ = write!(err, "\r{}: {percent:>3}% ({elapsed:.1} s)", self.label);
        let _ = err.flush();
    }

    /// Ends the line (the job finished or stopped).
    pub fn finish(&mut self) {
        if self.enabled && self.shown_percent.is_some() {
            eprintln!();
            self.shown_percent = None;
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.finish();
    }
}
