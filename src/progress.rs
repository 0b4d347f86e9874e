//! The terminal's progress of a run writing its output file: a spinner on standard error with the
//! bytes written, their rate and the time, shown only when standard error is a terminal and the run
//! is not quiet (never in a pipe).

use std::io::IsTerminal;
use std::sync::Arc;

use fmsvm_driver::output::Progress;

/// A spinner of the bytes written.
struct Spinner(indicatif::ProgressBar);

impl Progress for Spinner {
    fn written(&self, bytes: u64) {
        self.0.inc(bytes);
    }
    fn done(&self) {
        self.0.finish_and_clear();
    }
}

/// The progress to show for a run, if any: on a terminal, unless `quiet`.
pub fn on_terminal(quiet: bool) -> Option<Arc<dyn Progress>> {
    if quiet || !std::io::stderr().is_terminal() {
        return None;
    }
    let bar = indicatif::ProgressBar::new_spinner();
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{spinner} {bytes} written ({bytes_per_sec}) {elapsed}",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_spinner()),
    );
    Some(Arc::new(Spinner(bar)))
}
