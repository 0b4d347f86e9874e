//! The `fmsvm` command line as a library for the binary (`main.rs`): the subcommands' flags
//! (`cli`, over the run's flags of `fmsvm-flags`), each subcommand run through the driver or its
//! front end (`commands`), and the process's signals (`signals`). The front ends are crates of
//! their own: `fmsvm-editor` (language server and debugger), `fmsvm-dnc`, `fmsvm-post`,
//! `fmsvm-plot`; the pipeline is `fmsvm-driver`.
#![forbid(unsafe_code)]

pub mod cli;
pub mod commands;
mod progress;
mod signals;
