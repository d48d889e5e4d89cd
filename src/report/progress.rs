//! A progress bar on standard error for long bootstraps (indicatif).

use crate::stats::bootstrap::Progress;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;

/// Work (resamples x measurement rows) above which a bar is worth showing:
/// about a second on a current machine.
pub(crate) const SHOW_ABOVE: u64 = 200_000_000;

/// A bar of resamples done, drawn only when standard error is a terminal.
pub(crate) struct TerminalProgress {
    bar: ProgressBar,
}

impl TerminalProgress {
    /// A bar that shows when `quiet` is off, standard error is a terminal and
    /// the expected work (`resamples * rows`) exceeds [`SHOW_ABOVE`].
    pub(crate) fn new(quiet: bool, resamples: usize, rows: usize) -> TerminalProgress {
        let work = (resamples as u64).saturating_mul(rows as u64);
        let visible = !quiet && std::io::stderr().is_terminal() && work > SHOW_ABOVE;
        let target = if visible {
            ProgressDrawTarget::stderr()
        } else {
            ProgressDrawTarget::hidden()
        };
        let bar = ProgressBar::with_draw_target(Some(0), target);
        if let Ok(style) =
            ProgressStyle::with_template("bootstrap {bar:30} {pos}/{len} resamples ({eta} left)")
        {
            bar.set_style(style);
        }
        TerminalProgress { bar }
    }

    /// Removes the bar from the terminal.
    pub(crate) fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

impl Progress for TerminalProgress {
    fn start(&self, total: u64) {
        self.bar.set_length(total);
    }

    fn advance(&self, done: u64) {
        self.bar.inc(done);
    }
}
