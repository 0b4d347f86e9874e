//! fmsvm-kernel: the geometry kernel. [`Kernel`] implements `fmsvm_block::Machine`: it keeps the
//! modal state, frames and positions, answers system variables, resolves transforms, arcs, canned
//! cycles and cutter compensation, and hands each block to an `fmsvm_canon::Emitter`: as decoded
//! words (literal output) or as canonical operations (resolved output, stats, plot).
#![deny(missing_docs)]
#![forbid(unsafe_code)]

mod comp;
mod contour;
pub mod cycles;
pub mod frames;
mod kernel;
mod pockets;
pub mod probe;
mod sysvars;
mod timing;
mod transform;
pub mod turning;

pub use kernel::lathe::imaginary_tip;
pub use kernel::{ArcCentre, CompStyle, ControlOffsets, Kernel, Lathe, OutputFrame, Settings};
pub use sysvars::{ControlVariables, describe as describe_variable};

use fmsvm_block::Alarm;

/// Whether `alarm` says a system variable is not modelled (what `check` warns about before a run).
pub fn is_not_modelled(alarm: &Alarm) -> bool {
    alarm.number == 115 && alarm.message.contains("is not available in fmsvm")
}

/// An alarm for a system variable fmsvm does not model.
fn not_modelled(number: u32) -> Alarm {
    Alarm::new(
        115,
        format!(
            "system variable #{number} is not available in fmsvm: if the control has it, declare it in --params: [variables] values = {{ {number} = … }} (a value the control holds) or ranges = [[first, last]] (common variables) (docs/params.md)"
        ),
    )
}
