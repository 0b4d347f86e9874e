//! `fmsvm`: compile a Fanuc Custom Macro B program and expand it into flat G-code.
//!
//! This binary is glue: it parses flags into the driver's requests, runs the subcommand and maps
//! the outcome to an exit code (the library `fmsvm`, `lib.rs`).
#![forbid(unsafe_code)]

use std::process::ExitCode;

use fmsvm::{cli, commands};
use fmsvm_driver::exit;

fn main() -> ExitCode {
    let args = cli::parse();
    // A panic is a bug in fmsvm: report it with its own exit code, never as a success.
    let code = std::panic::catch_unwind(|| commands::main(args)).unwrap_or(exit::Exit::Internal);
    ExitCode::from(code as u8)
}
