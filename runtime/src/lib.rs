//! fmsvm-runtime: the kernel side of the pipeline. [`Kernel`] implements `fmsvm_block::Machine`: it
//! keeps the modal state, frames and positions, answers system variables, resolves transforms, arcs,
//! canned cycles and cutter compensation, and hands each block to an [`emit::Emitter`]: as decoded
//! words (literal output) or as [`canon::Canon`] operations (resolved output, stats, plot).
#![deny(missing_docs)]
#![forbid(unsafe_code)]

mod arcs;
pub mod canon;
mod comp;
mod contour;
pub mod cycles;
pub mod decode;
pub mod dialect;
pub mod emit;
pub mod frames;
mod geom;
pub mod kernel;
pub mod modal;
pub mod probe;
pub mod readback;
pub mod stats;
mod sysvars;
mod timing;
mod transform;

pub use kernel::{AXES, Kernel, OutputFrame, Settings};

use fmsvm_block::Alarm;

/// An alarm for a system variable fmsvm does not model.
fn not_modelled(number: u32) -> Alarm {
    Alarm::new(
        115,
        format!("system variable #{number} is not available in fmsvm"),
    )
}
