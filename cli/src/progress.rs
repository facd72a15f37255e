//! A one-line progress bar on stderr, drawn only when stderr is a terminal
//! (so piped output and the integration tests see no control characters).
//!
//! Hand-written rather than `indicatif`: a bar that counts steps needs a
//! dozen lines, not a dependency tree.
use std::io::{IsTerminal, Write};
use std::time::{Duration, Instant};

/// Width of the bar in characters.
const BAR_WIDTH: u64 = 30;
/// Least time between two redraws (a redraw per step would cost more than
/// a small scene's step).
const REDRAW_EVERY: Duration = Duration::from_millis(50);

/// A progress bar counting up to `total`.
pub struct Progress {
    label: String,
    total: u64,
    done: u64,
    start: Instant,
    last_draw: Option<Instant>,
    enabled: bool,
}

impl Progress {
    /// A bar labelled `label` for `total` units of work.
    pub fn new(label: &str, total: u64) -> Progress {
        Progress {
            label: label.to_owned(),
            total: total.max(1),
            done: 0,
            start: Instant::now(),
            last_draw: None,
            enabled: std::io::stderr().is_terminal(),
        }
    }

    /// Changes the label (e.g. the scene a benchmark is on) and redraws.
    pub fn set_label(&mut self, label: &str) {
        label.clone_into(&mut self.label);
        self.last_draw = None;
        self.draw_if_due();
    }

    /// Counts `n` more units done.
    pub fn inc(&mut self, n: u64) {
        self.done = self.done.saturating_add(n).min(self.total);
        self.draw_if_due();
    }

    /// Draws the full bar and ends its line.
    pub fn finish(&mut self) {
        if self.enabled {
            self.done = self.total;
            self.draw();
            eprintln!();
            self.enabled = false;
        }
    }

    fn draw_if_due(&mut self) {
        if !self.enabled {
            return;
        }
        let now = Instant::now();
        if self
            .last_draw
            .is_none_or(|t| now.duration_since(t) >= REDRAW_EVERY)
        {
            self.last_draw = Some(now);
            self.draw();
        }
    }

    fn draw(&self) {
        let filled = self.done * BAR_WIDTH / self.total;
        let bar: String = (0..BAR_WIDTH)
            .map(|i| if i < filled { '#' } else { '-' })
            .collect();
        let mut err = std::io::stderr().lock();
        // \r and "erase line": the bar redraws in place.
        let _ = write!(
            err,
            "\r\x1b[2K{} [{bar}] {}/{} {:.1} s",
            self.label,
            self.done,
            self.total,
            self.start.elapsed().as_secs_f64()
        );
        let _ = err.flush();
    }
}

impl Drop for Progress {
    /// An unfinished bar (an error mid-run) still ends its line, so the
    /// error message starts on a fresh one.
    fn drop(&mut self) {
        if self.enabled && self.done < self.total {
            eprintln!();
        }
    }
}
