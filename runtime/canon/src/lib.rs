//! fmsvm-canon: what a block means once the kernel has decided it, and the vocabulary every later
//! stage speaks. The canonical operations ([`Canon`]: the tool's motion with every frame, transform,
//! cycle and compensation applied, as rs274ngc's canon), the [`Emitter`] trait that receives them (or
//! the decoded words, for literal output), and the rules both sides read the same way: the modal
//! groups ([`modal`]), the value of a word ([`decode`]), arc centres and chords ([`arcs`]) and plane
//! geometry under one tolerance ([`geom`]).
#![deny(missing_docs)]
#![forbid(unsafe_code)]

pub mod arcs;
mod canon;
pub mod decode;
mod emitter;
pub mod geom;
pub mod modal;

pub use canon::*;
pub use emitter::{Context, Emitter};
