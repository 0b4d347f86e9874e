//! fmsvm-emit: the emitters, where executed blocks go. The literal emitter writes each decoded block
//! as programmed ([`literal`], and [`pipelined`] on a second thread); the resolved emitter writes the
//! canonical operations in a control's [`dialect`] ([`resolved`], numbers by [`format`], lines by
//! [`lines`]); [`n33`] punches the Н33-2М tape; [`stats`] measures the motion instead of writing it; [`travel`]
//! holds the output's moves to the machine's travels.
#![deny(missing_docs)]
#![forbid(unsafe_code)]

pub mod dialect;
pub mod format;
pub mod lines;
pub mod literal;
pub mod n33;
pub mod pipelined;
pub mod resolved;
pub mod stats;
pub mod travel;
