//! The terminal's progress of a run: a spinner on standard error with what the run has done (the
//! bytes of the output file, or the operations a report or a picture has taken), their rate and
//! the time, shown only when standard error is a terminal and the run is not quiet (never in a
//! pipe).

use std::io::IsTerminal;
use std::sync::Arc;

use fmsvm_driver::output::Progress;

/// What the spinner counts.
#[derive(Clone, Copy, Debug)]
pub enum Counted {
    /// The output file's bytes (`run -o`).
    Bytes,
    /// Canonical operations (`stats`, `plot`).
    Operations,
}

/// A spinner of what the run has done, drawn from the first count on (what the compiler says
/// before it is not interleaved with it).
struct Spinner(indicatif::ProgressBar, std::sync::Once);

impl Spinner {
    fn count(&self, n: u64) {
        // Drawn every tenth of a second even while nothing is counted (a long loop without output).
        self.1.call_once(|| {
            self.0
                .enable_steady_tick(std::time::Duration::from_millis(100))
        });
        self.0.inc(n);
    }
}

impl Progress for Spinner {
    fn written(&self, bytes: u64) {
        self.count(bytes);
    }
    fn operations(&self, operations: u64) {
        self.count(operations);
    }
    fn done(&self) {
        self.0.finish_and_clear();
    }
    fn aside(&self, print: &mut dyn FnMut()) {
        self.0.suspend(print);
    }
}

/// The progress to show for a run, if any: on a terminal, unless `quiet`.
pub fn on_terminal(quiet: bool, counted: Counted) -> Option<Arc<dyn Progress>> {
    if quiet || !std::io::stderr().is_terminal() {
        return None;
    }
    let template = match counted {
        Counted::Bytes => "{spinner} {bytes} written ({bytes_per_sec}), {elapsed}",
        Counted::Operations => "{spinner} {human_pos} operations, {elapsed}",
    };
    // Cleared, not left, when the run ends before it says so (a request refused early).
    let bar =
        indicatif::ProgressBar::new_spinner().with_finish(indicatif::ProgressFinish::AndClear);
    bar.set_style(
        indicatif::ProgressStyle::with_template(template)
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_spinner()),
    );
    Some(Arc::new(Spinner(bar, std::sync::Once::new())))
}
