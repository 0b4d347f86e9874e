//! Number formatting into a reused byte buffer, with integer arithmetic on least increments: no
//! float-to-string, no allocation.

use fmsvm_block::Code;

use crate::dialect::{NumberFormat, Point};

/// Up to four bytes written before a number in the same store: a separator and an address letter.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Prefix {
    /// The bytes, first in the lowest byte.
    bytes: u64,
    len: u32,
}

impl Prefix {
    /// Nothing before the number.
    pub const NONE: Prefix = Prefix { bytes: 0, len: 0 };

    /// `text` as a prefix, or None when it is longer than four bytes (the caller writes it itself).
    pub fn new(text: &[u8]) -> Option<Prefix> {
        if text.len() > 4 {
            return None;
        }
        let mut b = [0u8; 8];
        b[..text.len()].copy_from_slice(text);
        Some(Prefix {
            bytes: u64::from_le_bytes(b),
            len: text.len() as u32,
        })
    }

    /// Appends the prefix's bytes.
    #[inline]
    fn push(self, buf: &mut Vec<u8>) {
        buf.extend_from_slice(&self.bytes.to_le_bytes()[..self.len as usize]);
    }
}

/// Powers of ten that fit a u64.
const POW10: [u64; 20] = {
    let mut t = [1u64; 20];
    let mut i = 1;
    while i < 20 {
        t[i] = t[i - 1] * 10;
        i += 1;
    }
    t
};

/// '0' in every byte.
const ASCII: u64 = 0x3030_3030_3030_3030;

/// Two values below 10^4 (in the lanes at bits 0 and 32) to their four decimal digits each (0–9 a
/// byte, the most significant first in memory), all lanes at once (SWAR): /100 and /10 as
/// multiplications by reciprocals, exact below 10^4.
#[inline(always)]
fn lanes4(x: u64) -> u64 {
    let q = ((x * 10_486) >> 20) & 0x0000_007F_0000_007F;
    let x = ((x - q * 100) << 16) | q;
    let q = ((x * 103) >> 10) & 0x000F_000F_000F_000F;
    ((x - q * 10) << 8) | q
}

/// The eight decimal digits of `v` < 10^8 (0–9 a byte, the most significant first in memory).
#[inline(always)]
fn raw8(v: u64) -> u64 {
    if v < 10_000 {
        return lanes4(v) << 32;
    }
    let hi = v / 10_000;
    lanes4(hi | ((v - hi * 10_000) << 32))
}

/// Appends the first `n` (≤ 16) bytes of `w` with one capacity check and one store.
#[inline(always)]
fn put16(buf: &mut Vec<u8>, w: u128, n: u32) {
    let len = buf.len();
    buf.extend_from_slice(&w.to_le_bytes());
    buf.truncate(len + n as usize);
}

/// Appends the decimal digits of `v`.
#[inline]
pub fn push_u64(buf: &mut Vec<u8>, v: u64) {
    push_padded(buf, v, 0);
}

/// Appends `v` zero-padded to at least `width` digits (`M02`, `N006`).
#[inline]
pub fn push_padded(buf: &mut Vec<u8>, v: u64, pad: u8) {
    push_padded_word(buf, Prefix::NONE, v, pad)
}

/// Appends `prefix` and `v` zero-padded to at least `width` digits: an integer address's word.
#[inline]
pub fn push_padded_word(buf: &mut Vec<u8>, prefix: Prefix, v: u64, pad: u8) {
    match padded_word_text(prefix, v, pad) {
        Some(t) => t.push(buf),
        None => {
            prefix.push(buf);
            slow_padded(buf, v, pad);
        }
    }
}

/// Appends `q × 10^-digits` with a decimal point, trailing zeros trimmed, never `-0.`:
/// (10000, 3) → `10.`, (-1500, 3) → `-1.5`, (0, 3) → `0.`, (5, 3) → `0.005`.
#[inline]
pub fn push_fixed(buf: &mut Vec<u8>, q: i64, digits: u32) {
    push_word(buf, Prefix::NONE, q, digits, &NumberFormat::FANUC)
}

/// Appends `prefix` and `q × 10^-digits` in Fanuc's format (`push_fixed`), inlined into the caller:
/// the emitters' word for a length in Fanuc's format.
#[inline(always)]
pub fn push_fixed_word(buf: &mut Vec<u8>, prefix: Prefix, q: i64, digits: u32) {
    match fixed_word_text(prefix, q, digits) {
        Some(t) => t.push(buf),
        None => {
            prefix.push(buf);
            slow(buf, q, digits, &NumberFormat::FANUC);
        }
    }
}

/// Appends `prefix` and a G code ×10 in a word `width` digits wide: `G1`, `G54.1`, `G01`.
#[inline(always)]
pub fn push_code_word(buf: &mut Vec<u8>, prefix: Prefix, code: Code, width: u8) {
    match code_word_text(prefix, code, width) {
        Some(t) => t.push(buf),
        None => {
            prefix.push(buf);
            slow(buf, i64::from(code.tenths()), 1, &gcode_format(width));
        }
    }
}

/// Appends `q × 10^-digits` as `f` says.
#[inline]
pub fn push_formatted(buf: &mut Vec<u8>, q: i64, digits: u32, f: &NumberFormat) {
    push_word(buf, Prefix::NONE, q, digits, f)
}

/// `push_word` where whether `f` is Fanuc's format is known already (`Dialect::fanuc_formats`, once
/// a run): the emitters' word writer.
#[inline]
pub fn push_word_as(
    buf: &mut Vec<u8>,
    prefix: Prefix,
    q: i64,
    digits: u32,
    fanuc: bool,
    f: &NumberFormat,
) {
    if fanuc {
        push_fixed_word(buf, prefix, q, digits);
    } else {
        push_word(buf, prefix, q, digits, f);
    }
}

/// Appends `prefix` and `q × 10^-digits` as `f` says: a whole word in one store when it fits 16
/// bytes (any value of fewer than 8 integer digits with at most 7 decimals), else digit by digit.
/// `Point::Never` reads `q` as an integer (the increments).
#[inline]
pub fn push_word(buf: &mut Vec<u8>, prefix: Prefix, q: i64, digits: u32, f: &NumberFormat) {
    // Fanuc's format has its own copy, the rules and divisors constant.
    if *f == NumberFormat::FANUC {
        return push_fixed_word(buf, prefix, q, digits);
    }
    let done = match digits {
        1 => word(buf, prefix, q, 1, 10, f),
        3 => word(buf, prefix, q, 3, 1000, f),
        d @ 0..=7 => word(buf, prefix, q, d, POW10[d as usize], f),
        _ => false,
    };
    if !done {
        prefix.push(buf);
        slow(buf, q, digits, f);
    }
}

/// The word in registers, appended in one store; false (nothing written) when it does not fit: an
/// integer part of 8 digits or more, a prefix, sign and integer part over 8 bytes, more than 7
/// decimals.
#[inline(always)]
fn word(
    buf: &mut Vec<u8>,
    prefix: Prefix,
    q: i64,
    digits: u32,
    scale: u64,
    f: &NumberFormat,
) -> bool {
    match word_text(prefix, q, digits, scale, f) {
        Some(t) => {
            t.push(buf);
            true
        }
        None => false,
    }
}

/// A whole word's bytes in a register: what `word` appends.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Text {
    /// The bytes, first in the lowest byte; those past `len` are not part of it.
    bytes: u128,
    len: u32,
}

impl Text {
    /// Appends the word with one capacity check and one store.
    #[inline(always)]
    pub fn push(self, buf: &mut Vec<u8>) {
        put16(buf, self.bytes, self.len);
    }

    /// `bytes` as a text, or None when it is longer than 16 bytes.
    pub fn from_bytes(bytes: &[u8]) -> Option<Text> {
        let mut b = [0u8; 16];
        b.get_mut(..bytes.len())?.copy_from_slice(bytes);
        Some(Text {
            bytes: u128::from_le_bytes(b),
            len: bytes.len() as u32,
        })
    }

    /// Whether there are no bytes.
    #[inline(always)]
    pub fn is_empty(self) -> bool {
        self.len == 0
    }
}

/// `push_fixed_word`'s word as a `Text`, or None where it takes the digit-by-digit path.
#[inline(always)]
pub fn fixed_word_text(prefix: Prefix, q: i64, digits: u32) -> Option<Text> {
    let f = &NumberFormat::FANUC;
    match digits {
        3 => word_text(prefix, q, 3, 1000, f),
        4 => word_text(prefix, q, 4, 10_000, f),
        d @ 0..=7 => word_text(prefix, q, d, POW10[d as usize], f),
        _ => None,
    }
}

/// `push_code_word`'s word as a `Text`, or None where it takes the digit-by-digit path.
#[inline(always)]
pub fn code_word_text(prefix: Prefix, code: Code, width: u8) -> Option<Text> {
    word_text(
        prefix,
        i64::from(code.tenths()),
        1,
        10,
        &gcode_format(width),
    )
}

/// `push_padded_word`'s word as a `Text`, or None where it takes the digit-by-digit path.
#[inline(always)]
pub fn padded_word_text(prefix: Prefix, v: u64, pad: u8) -> Option<Text> {
    if v >= POW10[8] {
        return None;
    }
    let f = NumberFormat {
        point: Point::Never,
        width: pad,
        ..NumberFormat::FANUC
    };
    word_text(prefix, v as i64, 0, 1, &f)
}

/// The word in registers; None when it does not fit (see `word`).
#[inline(always)]
fn word_text(prefix: Prefix, q: i64, digits: u32, scale: u64, f: &NumberFormat) -> Option<Text> {
    let neg = q < 0;
    let a = q.unsigned_abs();
    let (int, frac) = if f.point == Point::Never {
        (a, 0)
    } else {
        (a / scale, a % scale)
    };
    if int >= POW10[8] || digits > 7 {
        return None;
    }
    let point = match f.point {
        Point::Always => true,
        Point::WhenFractional => frac != 0 || (f.trailing_zeros && digits > 0),
        Point::Never => false,
    };
    // The digits of the integer part and of the fraction (as 8 decimals), most significant first.
    let (ri, rf) = if int < 10_000 && digits <= 4 {
        let x = lanes4(int | ((frac * POW10[4 - digits as usize]) << 32));
        (x << 32, x >> 32)
    } else {
        (raw8(int), raw8(frac * POW10[8 - digits as usize]))
    };
    let width = f.width as u32;
    // `-.5` without a leading zero, unless padded.
    let shown = int != 0 || frac == 0 || f.leading_zero || width > 0;
    let ni = if shown {
        (8 - ri.trailing_zeros() / 8).max(width).max(1)
    } else {
        0
    };
    let ns = (neg || f.plus) as u32;
    let nh = prefix.len + ns + ni;
    if nh > 8 {
        return None;
    }
    let nf = if !point {
        0
    } else if f.trailing_zeros {
        digits
    } else {
        8 - rf.leading_zeros() / 8
    };
    let sign = (if neg { b'-' } else { b'+' }) as u64 * ns as u64;
    let int_text = if ni == 0 {
        0
    } else {
        (ri | ASCII) >> (64 - 8 * ni)
    };
    let head = prefix.bytes | sign << (8 * prefix.len) | int_text << (8 * (prefix.len + ns));
    // The point and the decimals; what follows the word's end is cut off by `put16`.
    let tail = b'.' as u64 | (rf | ASCII) << 8;
    Some(Text {
        bytes: head as u128 | (tail as u128) << (8 * nh),
        len: nh + point as u32 + nf,
    })
}

/// Two ASCII digits for each value 0–99.
const PAIRS: [u8; 200] = {
    let mut t = [0u8; 200];
    let mut i = 0;
    while i < 100 {
        t[2 * i] = b'0' + (i / 10) as u8;
        t[2 * i + 1] = b'0' + (i % 10) as u8;
        i += 1;
    }
    t
};

/// Appends the digits of `v`, two at a time (any u64).
fn slow_u64(buf: &mut Vec<u8>, mut v: u64) {
    let mut tmp = [0u8; 20];
    let mut end = tmp.len();
    while v >= 100 {
        let p = (v % 100) as usize * 2;
        v /= 100;
        end -= 2;
        tmp[end] = PAIRS[p];
        tmp[end + 1] = PAIRS[p + 1];
    }
    if v >= 10 {
        let p = v as usize * 2;
        end -= 2;
        tmp[end] = PAIRS[p];
        tmp[end + 1] = PAIRS[p + 1];
    } else {
        end -= 1;
        tmp[end] = b'0' + v as u8;
    }
    buf.extend_from_slice(&tmp[end..]);
}

/// Number of decimal digits of `v` (1 for 0).
fn width(v: u64) -> usize {
    v.checked_ilog10().map_or(1, |l| l as usize + 1)
}

#[cold]
fn slow_padded(buf: &mut Vec<u8>, v: u64, pad: u8) {
    for _ in width(v)..pad as usize {
        buf.push(b'0');
    }
    slow_u64(buf, v);
}

/// Any word `word` does not take: digit by digit.
#[cold]
fn slow(buf: &mut Vec<u8>, q: i64, digits: u32, f: &NumberFormat) {
    let a = q.unsigned_abs();
    if q < 0 {
        buf.push(b'-');
    } else if f.plus {
        buf.push(b'+');
    }
    if f.point == Point::Never {
        return slow_padded(buf, a, f.width);
    }
    let scale = 10u64.pow(digits);
    let (int, frac) = (a / scale, a % scale);
    let point = f.point == Point::Always || frac != 0 || (f.trailing_zeros && digits > 0);
    if int != 0 || frac == 0 || f.leading_zero || !point || f.width > 0 {
        slow_padded(buf, int, f.width);
    }
    if !point {
        return;
    }
    buf.push(b'.');
    if f.trailing_zeros {
        // Every decimal, none when there are none (`X5.` at 0 decimals).
        if digits > 0 {
            slow_padded(buf, frac, digits as u8);
        }
    } else if frac != 0 {
        let (mut frac, mut d) = (frac, digits as u8);
        while frac.is_multiple_of(10) {
            frac /= 10;
            d -= 1;
        }
        slow_padded(buf, frac, d);
    }
}

/// The format of a G code ×10 in a word `width` digits wide: `G1`, `G54.1`, `G01`.
#[inline(always)]
pub fn gcode_format(width: u8) -> NumberFormat {
    NumberFormat {
        point: Point::WhenFractional,
        width,
        ..NumberFormat::FANUC
    }
}

/// Appends a G code ×10: 10 → `1`, 541 → `54.1`.
pub fn push_gcode(buf: &mut Vec<u8>, code: u16) {
    push_word(buf, Prefix::NONE, code as i64, 1, &gcode_format(0));
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fixed(q: i64, d: u32) -> String {
        let mut b = Vec::new();
        push_fixed(&mut b, q, d);
        String::from_utf8(b).unwrap()
    }

    #[test]
    fn fixed_point() {
        assert_eq!(fixed(10_000, 3), "10.");
        assert_eq!(fixed(-1_500, 3), "-1.5");
        assert_eq!(fixed(0, 3), "0.");
        assert_eq!(fixed(5, 3), "0.005");
        assert_eq!(fixed(-50, 3), "-0.05");
        assert_eq!(fixed(12_369, 3), "12.369");
        assert_eq!(fixed(20_067, 4), "2.0067");
        assert_eq!(fixed(99_999_999, 3), "99999.999");
        assert_eq!(fixed(1_000_001, 3), "1000.001");
    }

    fn formatted(q: i64, d: u32, f: NumberFormat) -> String {
        let mut b = Vec::new();
        push_formatted(&mut b, q, d, &f);
        String::from_utf8(b).unwrap()
    }

    #[test]
    fn formats() {
        let when = NumberFormat {
            point: Point::WhenFractional,
            ..NumberFormat::FANUC
        };
        assert_eq!(formatted(10_000, 3, when), "10");
        assert_eq!(formatted(-1_500, 3, when), "-1.5");
        assert_eq!(formatted(0, 3, when), "0");
        assert_eq!(formatted(5, 3, when), "0.005");
        let bare = NumberFormat {
            leading_zero: false,
            ..NumberFormat::FANUC
        };
        assert_eq!(formatted(-500, 3, bare), "-.5");
        assert_eq!(formatted(0, 3, bare), "0.");
        let full = NumberFormat {
            trailing_zeros: true,
            ..NumberFormat::FANUC
        };
        assert_eq!(formatted(10_500, 3, full), "10.500");
        assert_eq!(formatted(-5, 3, full), "-0.005");
        let tape = NumberFormat {
            point: Point::Never,
            plus: true,
            width: 6,
            ..NumberFormat::FANUC
        };
        assert_eq!(formatted(8_000, 2, tape), "+008000");
        assert_eq!(formatted(-21_759, 2, tape), "-021759");
        assert_eq!(formatted(0, 2, tape), "+000000");
        let mut b = Vec::new();
        push_padded(&mut b, 6, 3);
        push_padded(&mut b, 1234, 2);
        assert_eq!(b, b"0061234");
    }

    #[test]
    fn codes() {
        let mut b = Vec::new();
        push_gcode(&mut b, 541);
        b.push(b' ');
        push_gcode(&mut b, 10);
        b.push(b' ');
        push_gcode(&mut b, 0);
        assert_eq!(b, b"54.1 1 0");
    }
}
