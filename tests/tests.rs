//! The integration tests, one binary (each file beside this one is a module of it): the tests of the
//! `fmsvm` binary run it as a process, the others call the crates in-process.

mod cli_support;
mod common;
#[cfg(feature = "lsp")]
mod framed;

mod calls;
mod ceiling;
mod cli;
mod comments;
mod corpus;
mod dap;
mod dialects;
#[cfg(unix)]
mod dnc;
mod engines;
mod errors;
mod flat;
mod format;
mod haas_lathe;
#[cfg(unix)]
mod hostile;
mod hostile2;
mod kernel;
mod lathe;
mod lsp;
mod m98m99;
mod messages;
mod milling_controls;
mod motion_cli;
mod neovim;
mod params;
mod pipelined;
mod plain;
mod post;
mod post_words;
#[cfg(unix)]
mod progress;
mod properties;
mod realworld;
mod rules;
mod safety;
mod stock;
mod textbook;
