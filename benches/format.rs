//! The number formatter alone (`runtime/emit/src/format.rs`), on the words of the hemisphere raster at
//! step 0.5 (40 401 blocks `N220 G1 X… Y… Z… F1000.`, the fine hemisphere's mix of values): the values
//! are rounded to increments once, outside the loop, so only formatting is measured, into a line
//! buffer handed to a sink every 64 KiB as `Lines` does.
//!
//! - `format/raster/<dialect>`: whole lines in Fanuc's format, FMS-3000's (point when fractional, G
//!   two digits) and a fixed-width tape format (no point, sign always, six digits);
//! - `format/raster/fanuc-prefixed`: the Fanuc lines with the separator and letter as each number's
//!   prefix (`push_*_word`), as the emitters write them;
//! - `format/xyz/fixed`: the X Y Z numbers alone through `push_fixed`.
//!
//! `FORMAT_ONCE=1 <bench binary>` (`=prefixed`: the prefixed lines) formats the Fanuc raster once and
//! exits, for `valgrind --tool=callgrind` (instructions per word: the inclusive cost of `lines` or
//! `words_prefixed` over the words).

use std::hint::black_box;

use criterion::{Criterion, Throughput};
use fmsvm_emit::dialect::{Dialect, NumberFormat, Point};
use fmsvm_emit::format::{
    Prefix, push_code_word, push_fixed, push_fixed_word, push_formatted, push_padded,
    push_padded_word,
};

/// The X Y Z of each raster block in increments (0.001 mm), zigzag as the program runs.
fn raster(step: f64) -> Vec<[i64; 3]> {
    let d = Dialect::fanuc();
    let q = |v: f64| d.least_increments(v, 3).expect("fits");
    let z = |x: f64, y: f64| {
        if x * x + y * y > 1600.0 {
            0.0
        } else {
            (1600.0 - x * x - y * y).sqrt()
        }
    };
    let mut out = Vec::new();
    let mut x: f64 = -50.0;
    let mut up = true;
    while x <= 50.0 {
        let mut y: f64 = if up { -50.0 } else { 50.0 };
        while (-50.0..=50.0).contains(&y) {
            out.push([q(x), q(y), q(z(x, y))]);
            y += if up { step } else { -step };
        }
        up = !up;
        x += step;
    }
    out
}

/// How one dialect spells the raster's words.
struct Style {
    g_width: u8,
    number: NumberFormat,
    digits: u32,
    separator: &'static [u8],
}

const FANUC: Style = Style {
    g_width: 0,
    number: NumberFormat::FANUC,
    digits: 3,
    separator: b" ",
};

const FMS3000: Style = Style {
    g_width: 2,
    number: NumberFormat {
        point: Point::WhenFractional,
        ..NumberFormat::FANUC
    },
    digits: 3,
    separator: b" ",
};

const TAPE: Style = Style {
    g_width: 2,
    number: NumberFormat {
        point: Point::Never,
        plus: true,
        width: 6,
        ..NumberFormat::FANUC
    },
    digits: 3,
    separator: b"",
};

/// Formats every block as the literal emitter does (N, G, X, Y, Z, F on every other block), handing
/// the buffer on every 64 KiB; returns the bytes written.
#[inline(never)]
fn lines(blocks: &[[i64; 3]], s: &Style, buf: &mut Vec<u8>) -> usize {
    let mut total = 0;
    for (i, b) in blocks.iter().enumerate() {
        buf.push(b'N');
        push_padded(buf, 220, 0);
        buf.extend_from_slice(s.separator);
        buf.push(b'G');
        push_padded(buf, 1, s.g_width);
        for (letter, &q) in [b'X', b'Y', b'Z'].iter().zip(b) {
            buf.extend_from_slice(s.separator);
            buf.push(*letter);
            push_formatted(buf, q, s.digits, &s.number);
        }
        if i % 2 == 0 {
            buf.extend_from_slice(s.separator);
            buf.push(b'F');
            push_formatted(buf, 1_000_000, s.digits, &s.number);
        }
        buf.push(b'\n');
        if buf.len() >= 1 << 16 {
            total += buf.len();
            black_box(&buf[..]);
            buf.clear();
        }
    }
    total + buf.len()
}

/// `lines` in Fanuc's format as the emitters write it since the SWAR formatter: the separator and
/// letter as each word's prefix, one store a word.
#[inline(never)]
fn words_prefixed(blocks: &[[i64; 3]], buf: &mut Vec<u8>) -> usize {
    let p = |t: &[u8]| Prefix::new(t).expect("fits");
    let (n, g, f) = (p(b"N"), p(b" G"), p(b" F"));
    let xyz = [p(b" X"), p(b" Y"), p(b" Z")];
    let mut total = 0;
    for (i, b) in blocks.iter().enumerate() {
        push_padded_word(buf, n, 220, 0);
        push_code_word(buf, g, fmsvm_block::Code::G1, 0);
        for (&prefix, &q) in xyz.iter().zip(b) {
            push_fixed_word(buf, prefix, q, 3);
        }
        if i % 2 == 0 {
            push_fixed_word(buf, f, 1_000_000, 3);
        }
        buf.push(b'\n');
        if buf.len() >= 1 << 16 {
            total += buf.len();
            black_box(&buf[..]);
            buf.clear();
        }
    }
    total + buf.len()
}

#[inline(never)]
fn xyz(blocks: &[[i64; 3]], buf: &mut Vec<u8>) -> usize {
    let mut total = 0;
    for b in blocks {
        for &q in b {
            push_fixed(buf, q, 3);
        }
        if buf.len() >= 1 << 16 {
            total += buf.len();
            black_box(&buf[..]);
            buf.clear();
        }
    }
    total + buf.len()
}

/// Words of `lines`: N G X Y Z on every block, F on every other one.
fn words(blocks: &[[i64; 3]]) -> u64 {
    5 * blocks.len() as u64 + blocks.len().div_ceil(2) as u64
}

fn benches(c: &mut Criterion) {
    let blocks = raster(0.5);
    let mut buf = Vec::with_capacity((1 << 16) + 1024);
    let mut g = c.benchmark_group("format");
    g.throughput(Throughput::Elements(words(&blocks)));
    for (name, style) in [("fanuc", &FANUC), ("fms3000", &FMS3000), ("tape", &TAPE)] {
        g.bench_function(format!("raster/{name}"), |b| {
            b.iter(|| {
                buf.clear();
                lines(black_box(&blocks), style, &mut buf)
            })
        });
    }
    g.bench_function("raster/fanuc-prefixed", |b| {
        b.iter(|| {
            buf.clear();
            words_prefixed(black_box(&blocks), &mut buf)
        })
    });
    g.throughput(Throughput::Elements(3 * blocks.len() as u64));
    g.bench_function("xyz/fixed", |b| {
        b.iter(|| {
            buf.clear();
            xyz(black_box(&blocks), &mut buf)
        })
    });
    g.finish();
}

fn main() {
    if std::env::var_os("FORMAT_ONCE").is_some() {
        let blocks = raster(0.5);
        let mut buf = Vec::with_capacity((1 << 16) + 1024);
        let bytes = if std::env::var_os("FORMAT_ONCE").is_some_and(|v| v == "prefixed") {
            words_prefixed(black_box(&blocks), &mut buf)
        } else {
            lines(black_box(&blocks), &FANUC, &mut buf)
        };
        println!(
            "{} blocks, {} words, {bytes} bytes",
            blocks.len(),
            words(&blocks)
        );
        return;
    }
    let mut c = Criterion::default().configure_from_args();
    benches(&mut c);
    c.final_summary();
}
