//! SIGINT, SIGTERM, SIGHUP and SIGQUIT: remove the temporary output files, say what was stopped, and
//! exit with 128 + the signal number. The handler runs on its own thread (signal-hook), so it may lock,
//! delete files and print; a commit in progress finishes first (it holds the run's `Temporaries`).
//! The command makes one `Handler` and installs it; the handler thread and the run share it.

use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};
use std::sync::{Arc, Mutex};

use fmsvm_driver::output::Temporaries;
use signal_hook::consts::{SIGHUP, SIGINT, SIGQUIT, SIGTERM};
use signal_hook::iterator::Signals;

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
pub fn install(handler: &Arc<Handler>) {
    let Ok(mut signals) = Signals::new([SIGINT, SIGTERM, SIGHUP, SIGQUIT]) else {
        return;
    };
    let shared = Arc::clone(handler);
    let _ = std::thread::Builder::new()
        .name("signals".into())
        .spawn(move || {
            for n in signals.forever() {
                if shared.defer.load(Ordering::SeqCst)
                    && shared.requested.swap(n, Ordering::SeqCst) == 0
                {
                    continue;
                }
                stop(&shared, n);
            }
        });
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
        SIGHUP => "SIGHUP (hang-up)",
        SIGQUIT => "SIGQUIT",
        _ => "a signal",
    }
}
