//! SIGINT, SIGTERM, SIGHUP and SIGQUIT: remove the temporary output files, say what was stopped, and
//! exit with 128 + the signal number. The handler runs on its own thread (signal-hook), so it may lock,
//! delete files and print; a commit in progress finishes first (it holds the registry).

use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};

use signal_hook::consts::{SIGHUP, SIGINT, SIGQUIT, SIGTERM};
use signal_hook::iterator::Signals;

use fmsvm_driver::output::TEMPORARIES;

/// What the run is doing, for the message (`expanding part.nc`).
static DOING: Mutex<String> = Mutex::new(String::new());

/// Says what the run is doing now.
pub fn doing(what: String) {
    *DOING.lock().unwrap_or_else(|p| p.into_inner()) = what;
}

/// While set (`fmsvm dnc` sending), the first signal does not end the process: it is recorded for the
/// DNC writer, which stops between two characters, sends the trailer and reports. A second signal ends
/// the process as usual.
static DEFER: AtomicBool = AtomicBool::new(false);
/// The signal recorded while deferred (0 = none).
static REQUESTED: AtomicI32 = AtomicI32::new(0);

/// Defers the first signal to the DNC writer (`requested`), or no longer.
#[cfg_attr(not(feature = "dnc"), allow(dead_code))]
pub fn defer(on: bool) {
    DEFER.store(on, Ordering::SeqCst);
}

/// The signal that asked the DNC writer to stop, if one did.
#[cfg_attr(not(feature = "dnc"), allow(dead_code))]
pub fn requested() -> Option<i32> {
    match REQUESTED.load(Ordering::Relaxed) {
        0 => None,
        n => Some(n),
    }
}

/// Installs the handler. Without it (the system refused) signals keep their default action.
pub fn install() {
    let Ok(mut signals) = Signals::new([SIGINT, SIGTERM, SIGHUP, SIGQUIT]) else {
        return;
    };
    let _ = std::thread::Builder::new()
        .name("signals".into())
        .spawn(move || {
            for n in signals.forever() {
                if DEFER.load(Ordering::SeqCst) && REQUESTED.swap(n, Ordering::SeqCst) == 0 {
                    continue;
                }
                stop(n);
            }
        });
}

fn stop(n: i32) -> ! {
    // Held until the process ends: no temporary file can appear after this.
    let temps = TEMPORARIES.lock().unwrap_or_else(|p| p.into_inner());
    let mut removed = 0;
    for p in temps.iter() {
        if std::fs::remove_file(p).is_ok() {
            removed += 1;
        }
    }
    let name = name(n);
    let doing = DOING.lock().map(|d| d.clone()).unwrap_or_default();
    let doing = if doing.is_empty() {
        String::new()
    } else {
        format!(" while {doing}")
    };
    let what = match removed {
        _ if fmsvm_driver::output::COMMITTED.load(std::sync::atomic::Ordering::SeqCst) => {
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
