//! The fmsvm pipeline as a library, for every front end (the command line, the editor, the
//! debugger, DNC, `post`, `plot`): a `Request` (plain data) is checked and its files read into a
//! configuration (`run::configure`), and a run writes its outputs and hands back its `Outcome`.
//! No command-line parser, no terminal code and no process exit here: what a request names and
//! cannot be loaded comes back as an `exit::Failure` (its exit code and message, for the front end
//! to render); a run's other errors come back as its exit code, their messages said through
//! `report` as they happen.
//!
//! A front end fills a request, runs it into a consumer and reads the outcome:
//!
//! ```
//! use fmsvm_driver::exit::Exit;
//! use fmsvm_driver::request::{Input, Request};
//! use fmsvm_driver::run::{Consumer, Hooks, expand};
//!
//! // The program as an editor holds it: `part.nc` only names it.
//! let input = Input {
//!     text: Some("O1\n#1=2.5\nG0 X#1 Y[#1*2]\nM30\n".into()),
//!     quiet: true,
//!     ..Input::new("part.nc")
//! };
//! let mut flat = Vec::new();
//! let outcome = expand(&Request::new(input), Consumer::Into(Box::new(&mut flat)), Hooks::default());
//! assert_eq!(outcome.exit, Exit::Success);
//! assert!(String::from_utf8_lossy(&flat).contains("G0 X2.5 Y5.\n"));
//! ```
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
