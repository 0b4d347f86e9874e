//! The fmsvm pipeline as a library, for every front end (the command line, the editor, the
//! debugger, DNC, `post`, `plot`): a `Request` (plain data) is checked and its files read into a
//! configuration (`run::configure`), and a run writes its outputs and hands back its `Outcome`.
//! No command-line parser and no process exit here: errors come back as exit codes with their
//! messages said through `report`.
#![deny(unsafe_code)]

pub mod catalogue;
pub mod dialects;
pub mod exit;
mod flat;
pub mod input;
pub mod library;
pub mod neutral;
pub mod offsets;
pub mod output;
pub mod params;
mod port;
pub mod report;
pub mod request;
pub mod run;
pub mod stats;
pub mod tomlfile;
pub mod vars;
