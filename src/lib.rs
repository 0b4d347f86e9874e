//! The `fmsvm` application: flags, files, the pipeline's glue, messages and exit codes, as a library
//! for the binary (`main.rs`) and the fuzz targets (the settings files' readers).
// Two calls are unsafe, each allowed where it is: a socket's send queue and its reset on close
// (`dnc::link`).
#![deny(unsafe_code)]

mod catalogue;
pub mod cli;
mod cycle_moves;
#[cfg(feature = "lsp")]
mod dap;
pub mod dialects;
#[cfg(feature = "dnc")]
mod dnc;
pub mod exit;
mod flat;
pub mod frame;
mod input;
mod library;
#[cfg(feature = "lsp")]
mod lsp;
pub mod neutral;
pub mod offsets;
mod output;
pub mod params;
#[cfg(feature = "plot")]
mod plot;
mod port;
mod post;
/// The launcher script of a control (`dialects --launcher`), for the fuzz target that writes it.
pub use post::launcher;
mod post_blocks;
mod post_verify;
mod post_words;
mod report;
pub mod run;
mod signals;
mod stats;
mod tomlfile;
pub mod vars;
