//! DPRNT/BPRNT records (macro-b-rules O1–O5) and the [`Port`] they go to, which the caller provides
//! (a file, standard output). The VM formats; the port only moves bytes.

use fmsvm_block::{Stop, is_vacant};

/// Where POPEN/DPRNT/BPRNT/PCLOS go. A port may stop the run: a write error, or a limit on the bytes
/// printed.
pub trait Port {
    /// `POPEN`.
    fn open(&mut self) -> Result<(), Stop>;
    /// One record (its end of record included).
    fn write(&mut self, record: &[u8]) -> Result<(), Stop>;
    /// `PCLOS`.
    fn close(&mut self) -> Result<(), Stop>;
}

/// A port that takes everything and keeps it (tests, and runs without print output).
#[derive(Default, Debug)]
pub struct MemoryPort {
    /// Everything written, POPEN/PCLOS included as DC2/DC4.
    pub bytes: Vec<u8>,
}

impl Port for MemoryPort {
    fn open(&mut self) -> Result<(), Stop> {
        self.bytes.push(DC2);
        Ok(())
    }
    fn write(&mut self, record: &[u8]) -> Result<(), Stop> {
        self.bytes.extend_from_slice(record);
        Ok(())
    }
    fn close(&mut self) -> Result<(), Stop> {
        self.bytes.push(DC4);
        Ok(())
    }
}

/// DC2, sent by POPEN (O5, Haas).
pub const DC2: u8 = 0x12;
/// DC4, sent by PCLOS.
pub const DC4: u8 = 0x14;

fn push_digits(buf: &mut Vec<u8>, mut v: u64, min: usize) {
    let mut tmp = [b'0'; 20];
    let mut i = tmp.len();
    loop {
        i -= 1;
        tmp[i] = b'0' + (v % 10) as u8;
        v /= 10;
        if v == 0 && tmp.len() - i >= min {
            break;
        }
    }
    buf.extend_from_slice(&tmp[i..]);
}

/// A DPRNT value `#v[ab]` (O1, O3): the whole part right-aligned in `a` places (the field grows when it
/// has more digits), a sign place before the digits (a space when positive, `-` when negative), then
/// `.` and exactly `b` rounded fraction digits; `b = 0` prints the whole part only, the fraction dropped.
/// Vacant prints as 0.
pub fn dprnt_value(buf: &mut Vec<u8>, v: f64, whole: u8, frac: u8) {
    let x = if is_vacant(v) { 0.0 } else { v };
    let scale = 10u64.pow(frac as u32);
    let (int, fr) = if frac == 0 {
        (x.abs().trunc().min(1e18) as u64, 0)
    } else {
        let q = (x.abs() * scale as f64).round().min(1e18) as u64;
        (q / scale, q % scale)
    };
    let negative = x < 0.0 && (int != 0 || fr != 0);
    let digits = if int == 0 {
        1
    } else {
        int.ilog10() as usize + 1
    };
    for _ in digits..whole as usize {
        buf.push(b' ');
    }
    buf.push(if negative { b'-' } else { b' ' });
    push_digits(buf, int, 1);
    if frac > 0 {
        buf.push(b'.');
        push_digits(buf, fr, frac as usize);
    }
}

/// ISO code with even parity on bit 7 (BPRNT text, O4: `*` goes out as A0h).
pub fn iso_parity(c: u8) -> u8 {
    let c = c & 0x7F;
    if c.count_ones() % 2 == 1 { c | 0x80 } else { c }
}

/// A BPRNT value `#v[d]` (O4): round(v × 10^d) as a 32-bit integer, most significant byte first;
/// vacant is 0. Values beyond 32 bits are clamped.
pub fn bprnt_value(buf: &mut Vec<u8>, v: f64, d: u8) {
    let x = if is_vacant(v) { 0.0 } else { v };
    let q = (x * 10f64.powi(d as i32))
        .round()
        .clamp(i32::MIN as f64, i32::MAX as f64) as i32;
    buf.extend_from_slice(&q.to_be_bytes());
}

#[cfg(test)]
mod tests {
    use super::*;

    fn d(v: f64, a: u8, b: u8) -> String {
        let mut buf = Vec::new();
        dprnt_value(&mut buf, v, a, b);
        String::from_utf8(buf).unwrap()
    }

    #[test]
    fn dprnt_formats() {
        assert_eq!(d(1.5436, 4, 4), "    1.5436");
        assert_eq!(d(1.5436, 0, 3), " 1.544");
        assert_eq!(d(1.5436, 4, 0), "    1");
        assert_eq!(d(-50.0, 5, 3), "   -50.000");
        assert_eq!(d(123456.0, 2, 0), " 123456");
        assert_eq!(d(-0.0004, 1, 3), " 0.000");
        assert_eq!(d(f64::NAN, 1, 1), " 0.0");
        assert_eq!(d(12.3456, 5, 3), "    12.346");
    }

    #[test]
    fn bprnt_values_from_the_rule_table() {
        for (v, dd, want) in [
            (258.647673, 3, [0x00, 0x03, 0xF2, 0x58]),
            (318.49362, 3, [0x00, 0x04, 0xDC, 0x1E]),
            (0.723415, 3, [0x00, 0x00, 0x02, 0xD3]),
            (23.9, 0, [0x00, 0x00, 0x00, 0x18]),
            (f64::NAN, 3, [0, 0, 0, 0]),
        ] {
            let mut buf = Vec::new();
            bprnt_value(&mut buf, v, dd);
            assert_eq!(buf, want, "{v}");
        }
        assert_eq!(iso_parity(b' '), 0xA0);
        assert_eq!(iso_parity(b'\n'), 0x0A);
    }
}
