//! Literal blocks: an NC block whose words are all literal numbers (a CAM file's `G1 X12.5 Y-3.25
//! F800`) is one `LiteralBlock` op whose words are packed in the function's byte stream, about four
//! bytes a word, instead of a `WordConst` op and a pooled constant per word (fourteen bytes and a
//! hash-table entry each, and a CAM file's coordinates are nearly all distinct).
//!
//! A block at byte `at` of [`crate::Function::literals`]: its info index and its word count as
//! LEB128 varints, then each word as a head byte (letter index in bits 0–4, `NO_POINT` in bit 5, a
//! minus sign in bit 6), a byte of decimals `frac`, and the mantissa `mant` as a varint; the value is
//! `mant / 10^frac`, the division the lexer itself makes of a number's digits, so the same bits.
//! A value that is not such a quotient is not packed: the block stays `WordConst` ops.

use fmsvm_block::{Letter, Word, WordFlags};

/// Most decimals tried when packing a value: as many as the lexer's own division takes.
const MAX_FRAC: u32 = 15;

/// Powers of ten that are exact in an f64 (and in a u64).
const POW10: [f64; 16] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
];

fn put_varint(out: &mut Vec<u8>, mut v: u64) {
    while v >= 0x80 {
        out.push((v as u8) | 0x80);
        v >>= 7;
    }
    out.push(v as u8);
}

fn get_varint(bytes: &[u8], at: &mut usize) -> Option<u64> {
    let mut v = 0u64;
    for shift in (0..64).step_by(7) {
        let b = *bytes.get(*at)?;
        *at += 1;
        v |= u64::from(b & 0x7F) << shift;
        if b < 0x80 {
            return Some(v);
        }
    }
    None
}

/// `mant / 10^frac`, the division the lexer makes of a number's digits (`lexer::exact_decimal`:
/// both operands exact in an f64), or None outside its range.
#[inline]
fn quotient(mant: u64, frac: u32) -> Option<f64> {
    (mant < 1_000_000_000_000_000 && frac < 16).then(|| mant as f64 / POW10[frac as usize])
}

/// The packed form of `value`: (negative, decimals, mantissa) with `mant / 10^frac` exactly `|value|`,
/// bit for bit. None for a value no such quotient gives (NaN, infinities, too many digits).
fn pack_value(value: f64) -> Option<(bool, u32, u64)> {
    let negative = value.is_sign_negative();
    let v = value.abs();
    if v.is_nan() || v >= 1e15 {
        return None;
    }
    for frac in 0..=MAX_FRAC {
        let x = v * POW10[frac as usize];
        if x >= 1e15 {
            return None;
        }
        // The nearest whole number (x is not negative); the comparison below decides.
        let mant = (x + 0.5) as u64;
        if quotient(mant, frac).is_some_and(|q| q.to_bits() == v.to_bits()) {
            return Some((negative, frac, mant));
        }
    }
    None
}

/// Appends a block of `words` with info `info` to `out`; false (and `out` as it was) when a value
/// cannot be packed or a word carries a flag other than `NO_POINT`.
pub fn pack(out: &mut Vec<u8>, info: u32, words: &[Word]) -> bool {
    let mark = out.len();
    // A head, a decimals byte and up to 8 mantissa bytes a word, and the two counts.
    out.reserve(10 + 10 * words.len());
    put_varint(out, u64::from(info));
    put_varint(out, words.len() as u64);
    for w in words {
        let packed = pack_value(w.value);
        let (Some((negative, frac, mant)), true) = (packed, w.flags.0 & !WordFlags::NO_POINT == 0)
        else {
            out.truncate(mark);
            return false;
        };
        out.push(
            w.letter.index() as u8
                | if w.flags.has(WordFlags::NO_POINT) {
                    0x20
                } else {
                    0
                }
                | if negative { 0x40 } else { 0 },
        );
        out.push(frac as u8);
        put_varint(out, mant);
    }
    true
}

/// A packed block: its info index and its words.
pub struct LiteralBlock<'a> {
    /// The `BlockInfo` index.
    pub info: u32,
    bytes: &'a [u8],
    at: usize,
    left: u64,
}

/// Reads the block at byte `at` of `bytes`; None when it is not well formed there.
pub fn block(bytes: &[u8], at: u32) -> Option<LiteralBlock<'_>> {
    let mut i = at as usize;
    let info = u32::try_from(get_varint(bytes, &mut i)?).ok()?;
    let left = get_varint(bytes, &mut i)?;
    Some(LiteralBlock {
        info,
        bytes,
        at: i,
        left,
    })
}

impl Iterator for LiteralBlock<'_> {
    /// A word, or None inside when the bytes are not well formed.
    type Item = Option<Word>;

    fn next(&mut self) -> Option<Option<Word>> {
        if self.left == 0 {
            return None;
        }
        self.left -= 1;
        Some(self.word())
    }
}

impl LiteralBlock<'_> {
    fn word(&mut self) -> Option<Word> {
        let head = *self.bytes.get(self.at)?;
        let frac = u32::from(*self.bytes.get(self.at + 1)?);
        self.at += 2;
        let mant = get_varint(self.bytes, &mut self.at)?;
        let letter = Letter::from_index(head & 0x1F)?;
        let v = quotient(mant, frac)?;
        Some(Word {
            letter,
            flags: WordFlags(if head & 0x20 != 0 {
                WordFlags::NO_POINT
            } else {
                0
            }),
            value: if head & 0x40 != 0 { -v } else { v },
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn round_trip(words: &[Word]) -> Option<Vec<Word>> {
        let mut out = vec![0xAA];
        if !pack(&mut out, 7, words) {
            assert_eq!(out, [0xAA], "a refused block leaves nothing");
            return None;
        }
        let b = block(&out, 1)?;
        assert_eq!(b.info, 7);
        b.collect()
    }

    fn word(letter: Letter, value: f64, no_point: bool) -> Word {
        Word {
            letter,
            flags: WordFlags(if no_point { WordFlags::NO_POINT } else { 0 }),
            value,
        }
    }

    /// Every value the lexer makes of a short decimal comes back bit for bit: the lexer's division
    /// (`exact_decimal`) of every mantissa up to 6 digits at every scale up to 6 decimals, signed.
    #[test]
    fn short_decimals_come_back_bit_for_bit() {
        for frac in 0..=6u32 {
            for mant in (0..1_000_000u64).step_by(7).chain([999_999, 1, 10, 100]) {
                let digits = if mant == 0 { 0 } else { mant.ilog10() + 1 };
                // The lexer's division (`lexer::exact_decimal`): by an exact power of ten.
                let _ = digits;
                let v = mant as f64 / 10f64.powi(frac as i32);
                for v in [v, -v] {
                    let w = [word(Letter::X, v, frac == 0)];
                    let back = round_trip(&w).unwrap_or_default();
                    assert_eq!(back.len(), 1, "{v:?} was not packed");
                    assert_eq!(back[0].value.to_bits(), v.to_bits(), "{v:?}");
                    assert_eq!(back[0].flags, w[0].flags);
                }
            }
        }
    }

    #[test]
    fn a_block_keeps_its_letters_flags_and_order() {
        let w = [
            word(Letter::G, 1.0, true),
            word(Letter::X, -12.345, false),
            word(Letter::Y, 0.5, false),
            word(Letter::Z, -0.0, false),
            word(Letter::F, 1000.0, true),
        ];
        let back = round_trip(&w).unwrap_or_default();
        assert_eq!(back.len(), 5);
        for (a, b) in w.iter().zip(&back) {
            assert_eq!((a.letter, a.flags), (b.letter, b.flags));
            assert_eq!(a.value.to_bits(), b.value.to_bits());
        }
    }

    #[test]
    fn values_that_are_no_short_quotient_stay_unpacked() {
        for v in [
            f64::NAN,
            f64::INFINITY,
            1.0 / 3.0,
            std::f64::consts::PI,
            1e300,
        ] {
            assert!(round_trip(&[word(Letter::X, v, false)]).is_none(), "{v:?}");
        }
        let incremental = Word {
            letter: Letter::X,
            flags: WordFlags(WordFlags::INCREMENTAL),
            value: 1.0,
        };
        assert!(round_trip(&[incremental]).is_none());
    }

    #[test]
    fn truncated_bytes_are_not_a_block() {
        let mut out = Vec::new();
        assert!(pack(&mut out, 3, &[word(Letter::X, 123.456, false)]));
        for cut in 0..out.len() {
            let ok = block(&out[..cut], 0).and_then(|b| b.collect::<Option<Vec<_>>>());
            assert!(ok.is_none(), "cut at {cut}");
        }
    }
}
