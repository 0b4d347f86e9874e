//! The native ceilings of the fine hemisphere raster, written by hand in Rust with the VM's float
//! arithmetic, so that they make the VM's bytes (`tests/ceiling.rs` checks them):
//!
//! - [`hemisphere`] drives the same kernel and literal emitter as the VM (the VM's overhead alone);
//! - [`hemisphere_bytes`] has no VM and no kernel: the raster's lines written straight into a buffer
//!   with the best formatter (each row's `N220 G1 X…` formatted once, the Y and Z words through
//!   `push_fixed_word`, one store a word), the fastest Rust for the same bytes.
//!
//! The JIT's throughput is reported as a ratio of these (`benches/expand.rs`).

use std::io::{self, Write};

use fmsvm_block::{Block, Flow, Letter, Machine, Word, WordFlags};
use fmsvm_emit::format::{Prefix, push_fixed_word};

const LIT: WordFlags = WordFlags(WordFlags::NO_POINT);
const VAL: WordFlags = WordFlags(0);

fn block<M: Machine>(
    m: &mut M,
    b: &mut Block<'_>,
    line: u32,
    words: &[(Letter, f64, WordFlags)],
) -> Flow {
    b.clear();
    b.line = line;
    for &(letter, value, flags) in words {
        b.push(Word {
            letter,
            flags,
            value,
        });
    }
    m.block(b).expect("the ceiling's blocks are valid")
}

/// `003-hemisphere.nc` with raster step `step` (the corpus program has 1), as the macro computes it.
pub fn hemisphere<M: Machine>(m: &mut M, step: f64) {
    use Letter::*;
    let mut b = Block::new();
    block(m, &mut b, 3, &[(N, 100.0, LIT), (T, 1.0, LIT)]);
    block(
        m,
        &mut b,
        4,
        &[
            (N, 110.0, LIT),
            (G, 54.0, LIT),
            (G, 0.0, LIT),
            (X, 0.0, LIT),
            (Y, 0.0, LIT),
        ],
    );
    block(
        m,
        &mut b,
        5,
        &[
            (N, 120.0, LIT),
            (G, 43.0, LIT),
            (Z, 50.0, LIT),
            (H, 1.0, LIT),
        ],
    );
    block(
        m,
        &mut b,
        6,
        &[
            (N, 130.0, LIT),
            (S, 1000.0, LIT),
            (M, 3.0, LIT),
            (M, 8.0, LIT),
        ],
    );
    block(
        m,
        &mut b,
        7,
        &[
            (N, 140.0, LIT),
            (G, 0.0, LIT),
            (X, -50.0, LIT),
            (Y, -50.0, LIT),
            (Z, 0.0, LIT),
        ],
    );
    let z = |x: f64, y: f64| {
        if x * x + y * y > 1600.0 {
            0.0
        } else {
            (1600.0 - x * x - y * y).sqrt()
        }
    };
    let mut x: f64 = -50.0;
    while x <= 50.0 {
        let mut y: f64 = -50.0;
        while y <= 50.0 {
            block(
                m,
                &mut b,
                16,
                &[
                    (N, 220.0, LIT),
                    (G, 1.0, LIT),
                    (X, x, VAL),
                    (Y, y, VAL),
                    (Z, z(x, y), VAL),
                    (F, 1000.0, LIT),
                ],
            );
            y += step;
        }
        x += step;
        // N260 IF[#1GE50] GOTO370: to END1, whose WHILE test decides.
        if x >= 50.0 {
            continue;
        }
        let mut y: f64 = 50.0;
        while y >= -50.0 {
            block(
                m,
                &mut b,
                26,
                &[
                    (N, 320.0, LIT),
                    (G, 1.0, LIT),
                    (X, x, VAL),
                    (Y, y, VAL),
                    (Z, z(x, y), VAL),
                ],
            );
            y -= step;
        }
        x += step;
    }
    block(m, &mut b, 31, &[(N, 380.0, LIT), (M, 30.0, LIT)]);
}

/// `x` in 0.001 mm, rounded half away from zero (what `Dialect::least_increments` makes of it).
#[inline(always)]
fn micrometres(x: f64) -> i64 {
    let q = x * 1000.0;
    let t = q as i64;
    let f = q - t as f64;
    t + (f >= 0.5) as i64 - (f <= -0.5) as i64
}

/// The bytes `fmsvm run` writes for `003-hemisphere.nc` at raster step `step`, the program's lines
/// and the raster's float arithmetic written by hand, into `out` in 64 KiB pieces.
pub fn hemisphere_bytes<W: Write>(out: &mut W, title: &str, step: f64) -> io::Result<()> {
    const CHUNK: usize = 1 << 16;
    let mut buf: Vec<u8> = Vec::with_capacity(CHUNK + 256);
    buf.extend_from_slice(b"%\nO7118");
    if !title.is_empty() {
        buf.extend_from_slice(b" ");
        buf.extend_from_slice(title.as_bytes());
    }
    buf.extend_from_slice(
        b"\nN100 T1\nN110 G54 G0 X0. Y0.\nN120 G43 Z50. H1\nN130 S1000 M3 M8\nN140 G0 X-50. Y-50. Z0.\n",
    );
    let (y, z) = (
        Prefix::new(b" Y").expect("fits"),
        Prefix::new(b" Z").expect("fits"),
    );
    let x_prefix = Prefix::new(b" X").expect("fits");
    // The start of each row's lines (`N220 G1 X-49.95`), formatted once a row.
    let mut row: Vec<u8> = Vec::with_capacity(64);
    // Its length; the row is padded to 32 bytes for the fixed-size copy.
    let start_row = |row: &mut Vec<u8>, n: &[u8; 7], x: f64| {
        row.clear();
        row.extend_from_slice(n);
        push_fixed_word(row, x_prefix, micrometres(x), 3);
        let len = row.len();
        row.resize(32, 0);
        len
    };
    let line = |buf: &mut Vec<u8>, row: &[u8], n: usize, x: f64, yv: f64, feed: bool| {
        // One fixed-size copy of the row's start, cut to its length.
        let len = buf.len();
        buf.extend_from_slice(&row[..32]);
        buf.truncate(len + n);
        push_fixed_word(buf, y, micrometres(yv), 3);
        let zv = if x * x + yv * yv > 1600.0 {
            0.0
        } else {
            (1600.0 - x * x - yv * yv).sqrt()
        };
        push_fixed_word(buf, z, micrometres(zv), 3);
        if feed {
            buf.extend_from_slice(b" F1000.\n");
        } else {
            buf.push(b'\n');
        }
    };
    let mut x: f64 = -50.0;
    while x <= 50.0 {
        let n = start_row(&mut row, b"N220 G1", x);
        let mut yv: f64 = -50.0;
        while yv <= 50.0 {
            line(&mut buf, &row, n, x, yv, true);
            if buf.len() >= CHUNK {
                out.write_all(&buf)?;
                buf.clear();
            }
            yv += step;
        }
        x += step;
        if x >= 50.0 {
            continue;
        }
        let n = start_row(&mut row, b"N320 G1", x);
        let mut yv: f64 = 50.0;
        while yv >= -50.0 {
            line(&mut buf, &row, n, x, yv, false);
            if buf.len() >= CHUNK {
                out.write_all(&buf)?;
                buf.clear();
            }
            yv -= step;
        }
        x += step;
    }
    buf.extend_from_slice(b"N380 M30\n%\n");
    out.write_all(&buf)?;
    out.flush()
}
