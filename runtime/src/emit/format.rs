//! Number formatting into a reused byte buffer, with integer arithmetic on least increments: no
//! float-to-string, no allocation.

use crate::dialect::{NumberFormat, Point};

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

/// Writes the digits of `v` so that they end just before `tmp[end]`.
#[inline(always)]
fn digits_into(tmp: &mut [u8; 32], mut end: usize, mut v: u64) {
    while v >= 100 {
        let p = (v % 100) as usize * 2;
        v /= 100;
        end -= 2;
        tmp[end] = PAIRS[p];
        tmp[end + 1] = PAIRS[p + 1];
    }
    if v >= 10 {
        let p = v as usize * 2;
        tmp[end - 2] = PAIRS[p];
        tmp[end - 1] = PAIRS[p + 1];
    } else {
        tmp[end - 1] = b'0' + v as u8;
    }
}

/// Number of decimal digits of `v` (1 for 0).
#[inline(always)]
fn width(v: u64) -> usize {
    v.checked_ilog10().map_or(1, |l| l as usize + 1)
}

/// Appends the first `n` bytes of `tmp` (a fixed-size copy, then a cut: no call per word).
#[inline(always)]
fn put(buf: &mut Vec<u8>, tmp: &[u8; 32], n: usize) {
    let len = buf.len();
    buf.extend_from_slice(tmp);
    buf.truncate(len + n);
}

/// Appends the decimal digits of `v`.
#[inline]
pub fn push_u64(buf: &mut Vec<u8>, v: u64) {
    if v < 10 {
        buf.push(b'0' + v as u8);
        return;
    }
    let mut tmp = [0u8; 32];
    let n = width(v);
    digits_into(&mut tmp, n, v);
    put(buf, &tmp, n);
}

/// Appends `q × 10^-digits` with a decimal point, trailing zeros trimmed, never `-0.`:
/// (10000, 3) → `10.`, (-1500, 3) → `-1.5`, (0, 3) → `0.`, (5, 3) → `0.005`.
#[inline]
pub fn push_fixed(buf: &mut Vec<u8>, q: i64, digits: u32) {
    // Constant divisors for the usual increments, so the splits are multiplications.
    match digits {
        3 => fixed::<1000>(buf, q, 3),
        4 => fixed::<10_000>(buf, q, 4),
        _ => fixed_any(buf, q, digits),
    }
}

#[inline(always)]
fn fixed<const SCALE: u64>(buf: &mut Vec<u8>, q: i64, digits: usize) {
    let a = q.unsigned_abs();
    write_fixed(buf, q < 0, a / SCALE, a % SCALE, digits);
}

fn fixed_any(buf: &mut Vec<u8>, q: i64, digits: u32) {
    let a = q.unsigned_abs();
    let scale = 10u64.pow(digits);
    write_fixed(buf, q < 0, a / scale, a % scale, digits as usize);
}

#[inline(always)]
fn write_fixed(buf: &mut Vec<u8>, negative: bool, int: u64, mut frac: u64, digits: usize) {
    let mut tmp = [b'0'; 32];
    let mut pos = 0;
    if negative {
        tmp[0] = b'-';
        pos = 1;
    }
    pos += width(int);
    digits_into(&mut tmp, pos, int);
    tmp[pos] = b'.';
    pos += 1;
    if frac != 0 {
        let mut d = digits;
        while frac.is_multiple_of(10) {
            frac /= 10;
            d -= 1;
        }
        // `tmp` is '0'-filled, so the fraction's leading zeros are already there.
        pos += d;
        digits_into(&mut tmp, pos, frac);
    }
    put(buf, &tmp, pos);
}

/// Appends `v` zero-padded to at least `width` digits (`M02`, `N006`).
#[inline]
pub fn push_padded(buf: &mut Vec<u8>, v: u64, pad: u8) {
    for _ in width(v)..pad as usize {
        buf.push(b'0');
    }
    push_u64(buf, v);
}

/// Appends `q × 10^-digits` as `f` says. Fanuc's format (the common case) is `push_fixed`.
#[inline]
pub fn push_formatted(buf: &mut Vec<u8>, q: i64, digits: u32, f: &NumberFormat) {
    if *f == NumberFormat::FANUC {
        return push_fixed(buf, q, digits);
    }
    let a = q.unsigned_abs();
    if q < 0 {
        buf.push(b'-');
    } else if f.plus {
        buf.push(b'+');
    }
    if f.point == Point::Never {
        return push_padded(buf, a, f.width);
    }
    let scale = 10u64.pow(digits);
    let (int, frac) = (a / scale, a % scale);
    let point = f.point == Point::Always || frac != 0 || (f.trailing_zeros && digits > 0);
    if int != 0 || frac == 0 || f.leading_zero || !point || f.width > 0 {
        push_padded(buf, int, f.width);
    }
    if !point {
        return;
    }
    buf.push(b'.');
    if f.trailing_zeros {
        // Every decimal, none when there are none (`X5.` at 0 decimals).
        if digits > 0 {
            push_padded(buf, frac, digits as u8);
        }
    } else if frac != 0 {
        let (mut frac, mut d) = (frac, digits as u8);
        while frac.is_multiple_of(10) {
            frac /= 10;
            d -= 1;
        }
        push_padded(buf, frac, d);
    }
}

/// Appends a G code ×10: 10 → `1`, 541 → `54.1`.
pub fn push_gcode(buf: &mut Vec<u8>, code: u16) {
    push_u64(buf, (code / 10) as u64);
    if !code.is_multiple_of(10) {
        buf.push(b'.');
        push_u64(buf, (code % 10) as u64);
    }
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
