//! The `Emitter` trait: where executed blocks go. A literal emitter takes each decoded block as
//! programmed; a resolved emitter (and `stats`, `plot`) the canonical operations the kernel makes of
//! them. The kernel decides what a block means, the emitter only how it is spelled.

use fmsvm_block::{Code, Stop};

use crate::canon::{Canon, Origin};
use crate::decode::Decoded;

/// What the emitter needs to know about the state the block runs in.
#[derive(Clone, Copy, Debug)]
pub struct Context {
    /// Inch units (G20) are active for this block.
    pub inch: bool,
    /// Axis words of this block are absolute (G90).
    pub absolute: bool,
    /// The motion G code in effect for this block (G0 G1 G2 G3, or a canned cycle's).
    pub motion: Code,
    /// P and Q are whole numbers as written (a lathe's G70–G76: sequence numbers, or lengths in
    /// least increments): written without a point.
    pub pq_integers: bool,
    /// The block's F is per revolution (G95, a lathe's G99) or a thread's lead (G32 G33 G76 G92):
    /// written with the finer decimals of a feed per revolution.
    pub per_rev: bool,
}

/// Receives the executed blocks of one program and writes them out.
pub trait Emitter {
    /// Whether the emitter consumes canonical operations (the kernel makes none otherwise: arcs,
    /// cycles and compensation are then only followed for the positions).
    const CANON: bool;
    /// Starts the program: tape start and program number (nothing, for an emitter that writes no
    /// text: `stats`, `plot`).
    fn begin(&mut self, number: Option<u32>, title: &str) -> Result<(), Stop> {
        let _ = (number, title);
        Ok(())
    }
    /// One executed block as programmed, its words decoded (literal emitters).
    fn block(&mut self, block: &Decoded<'_, '_>, ctx: &Context) -> Result<(), Stop> {
        let _ = (block, ctx);
        Ok(())
    }
    /// One canonical operation (resolved emitters), with the block it came from.
    fn canon(&mut self, op: &Canon<'_>, origin: Origin) -> Result<(), Stop> {
        let _ = (op, origin);
        Ok(())
    }
    /// Whether the emitter writes canned cycle `code` (G code ×10) as the control's own cycle block:
    /// the kernel then brackets the cycle's moves with `Canon::Cycle` and `Canon::CycleEnd`.
    fn native_cycle(&self, code: Code) -> bool {
        let _ = code;
        false
    }
    /// Whether the emitter writes `Canon::Corners` (exact stop and cutting mode) in the control's
    /// words: the kernel then sends them, and says nothing about leaving them out.
    fn corners(&self) -> bool {
        false
    }
    /// Bytes of complete lines written so far.
    fn written(&self) -> u64 {
        0
    }
    /// Ends the program (tape end) and flushes.
    fn end(&mut self) -> Result<(), Stop> {
        Ok(())
    }
    /// Finishes writing what the emitter has taken, after a stop that did not come from it: the
    /// output error it met on the way, if any, which is then the run's stop (an emitter that
    /// writes each block as it comes reports that at the block itself).
    fn settle(&mut self) -> Result<(), Stop> {
        Ok(())
    }
    /// A `#3006` message stop: the flat program stops there with the message (M00 and a comment).
    fn message(&mut self, number: u32, text: &str) -> Result<(), Stop> {
        let _ = (number, text);
        Ok(())
    }
}
