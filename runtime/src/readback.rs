//! The motion a flat program describes, read back from its text: the vocabulary every dialect's reader
//! speaks, and what `--verify` compares with the kernel's canonical operations.
//!
//! A reader turns the bytes an emitter wrote (in any dialect: decimal words, fixed-width increments,
//! parity tape) into a stream of [`Move`]s in absolute millimetres and degrees, in the output frame,
//! one per motion block the control would execute (an arc split into quadrants gives one move per
//! piece). Readers stream: they hold one block at a time, never the program.

use crate::canon::{Plane, Pose};

/// What one block makes the tool do.
#[derive(Clone, Copy, PartialEq, Debug)]
pub enum Motion {
    /// Straight at rapid traverse.
    Rapid,
    /// Straight at the feed rate.
    Feed,
    /// An arc (or helix: the normal axis moves with it) about `centre`, the plane coordinates of the
    /// centre in absolute mm.
    Arc {
        /// Centre (first, second plane axis), absolute.
        centre: [f64; 2],
        /// The plane.
        plane: Plane,
        /// G2 (true) or G3.
        clockwise: bool,
    },
    /// A dwell of this many seconds (no motion).
    Dwell(f64),
}

/// One move read back.
#[derive(Clone, Copy, PartialEq, Debug)]
pub struct Move {
    /// What the block does.
    pub motion: Motion,
    /// Where the tool stands after it (absolute, mm and degrees, axes X Y Z A B C).
    pub to: Pose,
    /// The feed rate in effect, mm/min (or mm/rev under G95) as the dialect encodes it; NaN when the
    /// program never said one.
    pub feed: f64,
    /// The output line (1-based) the move was read from.
    pub line: u32,
}

/// A block the reader cannot read: the output is not what the dialect's rules say.
#[derive(Clone, PartialEq, Debug)]
pub struct ReadError {
    /// Output line (1-based).
    pub line: u32,
    /// What is wrong, naming the offending text.
    pub message: String,
}

impl std::fmt::Display for ReadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "output line {}: {}", self.line, self.message)
    }
}

impl std::error::Error for ReadError {}

/// A dialect's reader: the moves of a flat program, one at a time.
pub trait Reader {
    /// The next move, or None at the end of the program.
    fn next_move(&mut self) -> Result<Option<Move>, ReadError>;
}
