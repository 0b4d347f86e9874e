//! Number formatting into a reused byte buffer, with integer arithmetic on least increments: no
//! float-to-string, no allocation.

/// Appends the decimal digits of `v` (byte pushes: no memcpy call for a few digits).
#[inline]
pub fn push_u64(buf: &mut Vec<u8>, v: u64) {
    if v < 10 {
        buf.push(b'0' + v as u8);
        return;
    }
    let mut tmp = [0u8; 20];
    let mut i = tmp.len();
    let mut v = v;
    while v > 0 {
        i -= 1;
        tmp[i] = b'0' + (v % 10) as u8;
        v /= 10;
    }
    for &b in &tmp[i..] {
        buf.push(b);
    }
}

/// Appends `q × 10^-digits` with a decimal point, trailing zeros trimmed, never `-0.`:
/// (10000, 3) → `10.`, (-1500, 3) → `-1.5`, (0, 3) → `0.`, (5, 3) → `.005` is written `0.005`.
pub fn push_fixed(buf: &mut Vec<u8>, q: i64, digits: u32) {
    if q < 0 {
        buf.push(b'-');
    }
    let a = q.unsigned_abs();
    let scale = 10u64.pow(digits);
    push_u64(buf, a / scale);
    buf.push(b'.');
    let mut frac = a % scale;
    if frac != 0 {
        let mut tmp = [b'0'; 20];
        let d = digits as usize;
        for slot in tmp[..d].iter_mut().rev() {
            *slot = b'0' + (frac % 10) as u8;
            frac /= 10;
        }
        let mut last = d;
        while last > 0 && tmp[last - 1] == b'0' {
            last -= 1;
        }
        for &b in &tmp[..last] {
            buf.push(b);
        }
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
