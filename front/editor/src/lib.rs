//! The editor's front ends over the driver: the language server (`fmsvm lsp`) and the macro
//! debugger (`fmsvm dap`), both over the base protocol's frames (`frame`).
// A server's lines are read on a thread of their own; nothing here is unsafe.
#![deny(unsafe_code)]

mod dap;
pub mod frame;
mod lsp;

pub use dap::main as dap;
pub use lsp::main as lsp;
