//! The `fmsvm` application's front ends over the driver (`fmsvm-driver`): the command line's flags
//! and subcommands, the editor's language server and debugger, DNC, `post` and `plot`, as a
//! library for the binary (`main.rs`) and the fuzz targets.
// Two calls are unsafe, each allowed where it is: a socket's send queue and its reset on close
// (`dnc::link`).
#![deny(unsafe_code)]

pub mod cli;
pub mod commands;
mod cycle_moves;
#[cfg(feature = "lsp")]
mod dap;
#[cfg(feature = "dnc")]
mod dnc;
pub mod frame;
#[cfg(feature = "lsp")]
mod lsp;
#[cfg(feature = "plot")]
mod plot;
mod post;
/// The launcher script of a control (`dialects --launcher`), for the fuzz target that writes it.
pub use post::launcher;
mod post_blocks;
mod post_verify;
mod post_words;
mod signals;

// The driver's modules, under the names the front ends use.
pub use fmsvm_driver::{
    catalogue, dialects, exit, input, library, neutral, offsets, output, params, report, run,
    stats, vars,
};
