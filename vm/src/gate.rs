//! Handing blocks to the Machine under the run's limits, once for every way a block can come: the
//! engines (`Ctx`) and a flat program run straight from its file (the CLI's flat path). A block
//! counts once the Machine has taken it ("stopped after n blocks" is what was written); the block
//! limit stops the run before the block past it; and the wall-time limit is looked at every
//! [`TIME_EVERY`] blocks, so a program that takes no branch (a CAM file) is bounded too.

use std::time::{Duration, Instant};

use fmsvm_block::{Block, Flow, LimitKind, Machine, Stop};

use crate::Limits;

/// How many blocks go by between two looks at the clock.
pub const TIME_EVERY: u64 = 4096;

/// The block and wall-time limits of one run, and the blocks handed so far.
#[derive(Clone, Debug)]
pub struct BlockGate {
    /// The block limit (`u64::MAX`: none).
    max_blocks: u64,
    /// When the run must stop, if it has a wall-time limit.
    deadline: Option<Instant>,
    /// The wall-time limit as configured, for the message.
    max_time: Option<Duration>,
    /// The block count at which the clock is looked at next.
    next_look: u64,
    /// Blocks the Machine has taken.
    pub blocks: u64,
}

impl BlockGate {
    /// The gate of a run starting now.
    pub fn new(limits: &Limits) -> BlockGate {
        let deadline = limits.max_time.map(|t| Instant::now() + t);
        BlockGate {
            max_blocks: if limits.max_blocks == 0 {
                u64::MAX
            } else {
                limits.max_blocks
            },
            deadline,
            max_time: limits.max_time,
            next_look: if deadline.is_some() { 0 } else { u64::MAX },
            blocks: 0,
        }
    }

    /// When the run must stop (the engines look at it on their branches too).
    pub fn deadline(&self) -> Option<Instant> {
        self.deadline
    }

    /// The wall-time stop, if the deadline has passed.
    pub fn out_of_time(&self) -> Option<Stop> {
        let d = self.deadline?;
        (Instant::now() >= d).then(|| Stop::Limit {
            kind: LimitKind::WallTime,
            limit: self.max_time.map_or(0, |t| t.as_millis() as u64),
        })
    }

    /// Hands `block` to `machine`, unless a limit stops the run first.
    #[inline(always)]
    pub fn hand<M: Machine + ?Sized>(
        &mut self,
        machine: &mut M,
        block: &Block<'_>,
    ) -> Result<Flow, Stop> {
        if self.blocks >= self.max_blocks {
            return Err(Stop::Limit {
                kind: LimitKind::Blocks,
                limit: self.max_blocks,
            });
        }
        if self.blocks >= self.next_look {
            if let Some(stop) = self.out_of_time() {
                return Err(stop);
            }
            self.next_look = self.blocks + TIME_EVERY;
        }
        let flow = machine.block(block)?;
        self.blocks += 1;
        Ok(flow)
    }
}
