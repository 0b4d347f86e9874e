//! The alarm numbers fmsvm raises from more than one place, each named once: Fanuc's where the
//! control has the alarm (its operator's manual's alarm list), 0 where it has none.

/// fmsvm's own refusal: no Fanuc alarm says it (shown without a number's meaning).
pub const NO_FANUC_NUMBER: u32 = 0;
/// 0003 TOO MANY DIGIT: a number that does not fit the address's digits.
pub const TOO_MANY_DIGITS: u32 = 3;
/// 0006 ILLEGAL USE OF MINUS SIGN.
pub const MINUS_SIGN: u32 = 6;
/// 0010 IMPROPER G-CODE: a code the control does not have, or cannot take here.
pub const IMPROPER_G: u32 = 10;
/// 0114 FORMAT ERROR: the block's words.
pub const FORMAT: u32 = 114;
