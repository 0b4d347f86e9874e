//! The stock a program cuts: a mill's box as a height field (`mill`), a lathe's bar as its
//! half-section (`lathe`), the cutters (`cutter`), and `Simulated`, which cuts it beside any
//! consumer of canonical operations and says where a move hits material it must not.

pub mod cutter;
pub mod lathe;
pub mod mill;
pub mod quarters;
mod simulate;

pub use cutter::{Cutter, Shape};
pub use lathe::{HalfSection, Nose};
pub use mill::HeightField;
pub use simulate::{Report, Simulated, Stock, Tool, ToolTotals};

/// Cells a stock may have at most (8 bytes each for a mill, 1 for a lathe): 5 × 10⁷.
pub const MAX_CELLS: u64 = 50_000_000;

#[cfg(test)]
mod tests;
