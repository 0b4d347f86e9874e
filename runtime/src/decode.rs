//! What a block's words mean in the program's language, before any output: the decimal-point input rule
//! (V11), which G codes exist, vacant stores. The kernel decodes with these; emitters only format.

use fmsvm_block::{Alarm, Word, WordFlags, is_exact_code};

use crate::dialect::{AddressKind, Dialect};

/// 0010 IMPROPER G-CODE.
const IMPROPER_G: u32 = 10;

/// How a literal without a decimal point is read (macro-b-rules V11).
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub enum DecimalInput {
    /// `X10` = 10 mm (calculator type, Fanuc parameter; what the textbook programs and LinuxCNC assume).
    #[default]
    Calculator,
    /// `X10` = 10 least increments = 0.010 mm (Fanuc decimal-point input type I).
    Increment,
}

/// The value a word stands for, after the decimal-point input rule.
#[inline(always)]
pub fn input_value(dialect: &Dialect, decimal: DecimalInput, w: &Word, inch: bool) -> f64 {
    if decimal == DecimalInput::Increment && w.flags.has(WordFlags::NO_POINT) {
        match dialect.kind(w.letter) {
            AddressKind::Linear | AddressKind::Angular => {
                return w.value * dialect.increment(w.letter, inch);
            }
            _ => {}
        }
    }
    w.value
}

/// Rounds a G-code value to its ×10 code and checks it exists.
pub fn gcode(value: f64) -> Result<u16, Alarm> {
    match fmsvm_block::code10(value) {
        Some(c) if is_exact_code(value, c) && crate::modal::group(c).is_some() => Ok(c),
        _ => Err(Alarm::new(IMPROPER_G, format!("improper G-code: G{value}"))),
    }
}

/// Vacant written to a numeric store counts as 0.
pub fn vacant_as_zero(v: f64) -> f64 {
    if fmsvm_block::is_vacant(v) { 0.0 } else { v }
}
