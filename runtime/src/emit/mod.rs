//! Emitters: where executed blocks go. An emitter writes one line per block in a dialect; the kernel
//! decides what the block means, the emitter only how it is spelled.

pub mod format;
pub mod literal;

use fmsvm_block::{Block, Stop};

/// What the emitter needs to know about the state the block runs in.
#[derive(Clone, Copy, Debug)]
pub struct Context {
    /// Inch units (G20) are active for this block.
    pub inch: bool,
}

/// Receives the executed blocks of one program and writes them out.
pub trait Emitter {
    /// Starts the program: tape start and program number.
    fn begin(&mut self, number: Option<u32>, title: &str) -> Result<(), Stop>;
    /// One executed block.
    fn block(&mut self, block: &Block<'_>, ctx: &Context) -> Result<(), Stop>;
    /// Ends the program (tape end) and flushes.
    fn end(&mut self) -> Result<(), Stop>;
    /// A `#3006` message stop: the flat program stops there with the message (M00 and a comment).
    fn message(&mut self, number: u32, text: &str) -> Result<(), Stop>;
}
