//! The kernel and the literal emitter on random blocks (any letters, any values, NaN and infinities
//! included): an alarm or a line, never a panic, and never a non-finite number in the output.
#![no_main]
use fmsvm_block::{Block, Letter, Machine, Word, WordFlags};
use fmsvm_runtime::Kernel;
use fmsvm_runtime::dialect::Dialect;
use fmsvm_runtime::emit::literal::{self, DecimalInput, LiteralEmitter};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let mut out = Vec::new();
    {
        let e = LiteralEmitter::new(&mut out, Dialect::fanuc(), literal::Options::default());
        let mut k = Kernel::new(e, Dialect::fanuc(), DecimalInput::Calculator);
        let mut b = Block::new();
        for chunk in data.chunks(10) {
            if chunk.len() < 10 {
                break;
            }
            let letter = Letter::from_index(chunk[0] % Letter::COUNT as u8).unwrap_or(Letter::X);
            let flags = WordFlags(chunk[1] & 3);
            let value = f64::from_le_bytes(chunk[2..10].try_into().unwrap_or([0; 8]));
            b.push(Word {
                letter,
                flags,
                value,
            });
            if chunk[1] & 0x80 != 0 {
                let _ = k.block(&b);
                b.clear();
            }
        }
        let _ = k.block(&b);
    }
    let text = String::from_utf8(out).expect("the emitter writes ASCII");
    assert!(!text.contains("NaN") && !text.contains("inf"), "{text}");
});
