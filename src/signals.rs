//! SIGINT, SIGTERM, SIGHUP and SIGQUIT (Windows: Ctrl-C as SIGINT, and SIGTERM): remove the
//! temporary output files, say what was stopped, and exit with 128 + the signal number. The handler
//! runs on its own thread (signal-hook), so it may lock, delete files and print; a commit in progress
//! finishes first (it holds the run's `Temporaries`). The command makes one `Handler` and installs
//! it; the handler thread and the run share it.

use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};
use std::sync::{Arc, Mutex};

use fmsvm_driver::output::Temporaries;
#[cfg(unix)]
use signal_hook::consts::{SIGHUP, SIGQUIT};
use signal_hook::consts::{SIGINT, SIGTERM};

/// What the handler shares with the run: the temporary files to remove, what the run is doing (for
/// the message), and the DNC writer's deferral of the first signal.
#[derive(Default)]
pub struct Handler {
    /// The run's temporary files.
    pub temporaries: Arc<Temporaries>,
    doing: Mutex<String>,
    /// While set (`fmsvm dnc` sending), the first signal does not end the process: it is recorded
    /// for the DNC writer, which stops between two characters, sends the trailer and reports. A
    /// second signal ends the process as usual.
    defer: AtomicBool,
    /// The signal recorded while deferred (0 = none).
    requested: AtomicI32,
}

impl Handler {
    /// Says what the run is doing now.
    pub fn doing(&self, what: String) {
        *self.doing.lock().unwrap_or_else(|p| p.into_inner()) = what;
    }
}

#[cfg(feature = "dnc")]
impl fmsvm_dnc::Signals for Handler {
    fn temporaries(&self) -> Arc<Temporaries> {
        Arc::clone(&self.temporaries)
    }
    fn doing(&self, what: String) {
        Handler::doing(self, what);
    }
    fn defer(&self, on: bool) {
        self.defer.store(on, Ordering::SeqCst);
    }
    fn requested(&self) -> Option<i32> {
        match self.requested.load(Ordering::Relaxed) {
            0 => None,
            n => Some(n),
        }
    }
    fn name(&self, n: i32) -> &'static str {
        name(n)
    }
}

/// Installs `handler` for the process (once: a command installs it before it runs). Where the
/// system refuses, signals keep their default action.
#[cfg(unix)]
pub fn install(handler: &Arc<Handler>) {
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP, SIGQUIT])
    else {
        return;
    };
    let shared = Arc::clone(handler);
    let _ = std::thread::Builder::new()
        .name("signals".into())
        .spawn(move || {
            for n in signals.forever() {
                on_signal(&shared, n);
            }
        });
}

/// Installs `handler` where signals cannot be read from a pipe (Windows): `polled`.
#[cfg(not(unix))]
pub fn install(handler: &Arc<Handler>) {
    polled::install(handler, &[SIGINT, SIGTERM]);
}

/// What a signal does: recorded for the DNC writer when it defers the first one, else the end.
fn on_signal(handler: &Handler, n: i32) {
    if handler.defer.load(Ordering::SeqCst) && handler.requested.swap(n, Ordering::SeqCst) == 0 {
        return;
    }
    stop(handler, n);
}

/// Delivery by flags signal-hook sets, each looked at every 50 ms by the handler's thread: the way
/// on Windows (whose C runtime has `signal` but no pipe to read them from); compiled and tested on
/// unix too.
#[cfg_attr(unix, allow(dead_code))]
mod polled {
    use super::*;

    /// Sets a flag for each of `signals` and watches them on a thread of its own.
    pub fn install(handler: &Arc<Handler>, signals: &[i32]) {
        let flags = register(signals);
        let shared = Arc::clone(handler);
        let _ = std::thread::Builder::new()
            .name("signals".into())
            .spawn(move || {
                loop {
                    match take_raised(&flags) {
                        Some(n) => on_signal(&shared, n),
                        None => std::thread::sleep(std::time::Duration::from_millis(50)),
                    }
                }
            });
    }

    /// A flag for each signal the system lets us catch.
    pub fn register(signals: &[i32]) -> Vec<(i32, Arc<AtomicBool>)> {
        signals
            .iter()
            .filter_map(|&n| {
                let flag = Arc::new(AtomicBool::new(false));
                signal_hook::flag::register(n, Arc::clone(&flag))
                    .ok()
                    .map(|_| (n, flag))
            })
            .collect()
    }

    /// The first signal raised since the last look, its flag cleared.
    pub fn take_raised(flags: &[(i32, Arc<AtomicBool>)]) -> Option<i32> {
        flags
            .iter()
            .find(|(_, f)| f.swap(false, Ordering::SeqCst))
            .map(|(n, _)| *n)
    }

    #[cfg(all(test, unix))]
    mod tests {
        use super::*;
        use signal_hook::consts::SIGUSR2;

        #[test]
        fn a_raised_signal_is_taken_once() {
            let flags = register(&[SIGUSR2]);
            assert_eq!(flags.len(), 1);
            assert_eq!(take_raised(&flags), None);
            signal_hook::low_level::raise(SIGUSR2).expect("raised");
            assert_eq!(take_raised(&flags), Some(SIGUSR2));
            assert_eq!(take_raised(&flags), None);
        }
    }
}

fn stop(handler: &Handler, n: i32) -> ! {
    // Held until the process ends: no temporary file can appear after this.
    let temps = handler.temporaries.lock();
    let mut removed = 0;
    for p in temps.iter() {
        if std::fs::remove_file(p).is_ok() {
            removed += 1;
        }
    }
    let name = name(n);
    let doing = handler.doing.lock().map(|d| d.clone()).unwrap_or_default();
    let doing = if doing.is_empty() {
        String::new()
    } else {
        format!(" while {doing}")
    };
    let what = match removed {
        _ if handler.temporaries.committed() => {
            "the outputs were already complete and committed".to_string()
        }
        0 => "no output file was committed".to_string(),
        1 => "no output file was committed (1 temporary file removed)".to_string(),
        k => format!("no output file was committed ({k} temporary files removed)"),
    };
    eprintln!("error: stopped by {name}{doing}; {what}");
    std::process::exit(128 + n)
}

/// A signal's name in messages.
pub fn name(n: i32) -> &'static str {
    match n {
        SIGINT => "SIGINT (interrupt)",
        SIGTERM => "SIGTERM",
        #[cfg(unix)]
        SIGHUP => "SIGHUP (hang-up)",
        #[cfg(unix)]
        SIGQUIT => "SIGQUIT",
        _ => "a signal",
    }
}
