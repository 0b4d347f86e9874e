//! `fmsvm`: compile a Fanuc Custom Macro B program and expand it into flat G-code.
//!
//! This binary is glue: it parses flags, loads files, plugs the compiler, the VM and the runtime
//! together, renders messages and maps the outcome to an exit code (see `exit`).
// One call is unsafe: the socket's send queue (`dnc::link::send_queue`), allowed there alone.
#![deny(unsafe_code)]

mod catalogue;
mod cli;
mod cycle_moves;
mod dialects;
#[cfg(feature = "dnc")]
mod dnc;
mod exit;
mod flat;
mod input;
mod library;
mod neutral;
mod offsets;
mod output;
mod params;
#[cfg(feature = "plot")]
mod plot;
mod port;
mod post;
mod post_verify;
mod post_words;
mod report;
mod run;
mod signals;
mod stats;
mod tomlfile;
mod vars;

use std::process::ExitCode;

fn main() -> ExitCode {
    let args = cli::parse();
    // A panic is a bug in fmsvm: report it with its own exit code, never as a success.
    let code = std::panic::catch_unwind(|| run::main(args)).unwrap_or(exit::Exit::Internal);
    ExitCode::from(code as u8)
}
