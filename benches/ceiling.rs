//! The native ceiling: the fine hemisphere raster written by hand in Rust, driving the same kernel and
//! emitter as the VM with the same float arithmetic, so it produces the same bytes. The JIT's throughput
//! is reported as a ratio of this (`benches/expand.rs`); `tests/ceiling.rs` checks the bytes are equal.

use fmsvm_block::{Block, Flow, Letter, Machine, Word, WordFlags};

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
