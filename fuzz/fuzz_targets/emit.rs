//! The kernel and an emitter on random blocks (any letters, any values, NaN and infinities included):
//! an alarm or a line, never a panic, and never a non-finite number in the output. The first byte
//! chooses the emitter: literal, or resolved (the whole geometry kernel: frames, transforms, cycles,
//! compensation) from a known start point.
#![no_main]
use fmsvm_block::{Block, Letter, Machine, Word, WordFlags};
use fmsvm_canon::Emitter;
use fmsvm_canon::decode::InputRules;
use fmsvm_emit::dialect::Dialect;
use fmsvm_emit::literal::{self, LiteralEmitter};
use fmsvm_emit::resolved::ResolvedEmitter;
use fmsvm_kernel::{Kernel, Settings};
use libfuzzer_sys::fuzz_target;

fn feed<E: Emitter>(k: &mut Kernel<E>, data: &[u8]) {
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

fuzz_target!(|data: &[u8]| {
    let Some((&choice, data)) = data.split_first() else {
        return;
    };
    let mut out = Vec::new();
    if choice & 1 == 0 {
        let e = LiteralEmitter::new(&mut out, Dialect::fanuc(), literal::Options::default());
        feed(&mut Kernel::new(e, InputRules::default()), data);
    } else {
        let e = ResolvedEmitter::new(&mut out, Dialect::fanuc(), literal::Options::default());
        let settings = Settings {
            start_point: [0.0; 6],
            ..Settings::default()
        };
        feed(
            &mut Kernel::with_settings(e, InputRules::default(), settings),
            data,
        );
    }
    let text = String::from_utf8(out).expect("the emitter writes ASCII");
    assert!(!text.contains("NaN") && !text.contains("inf"), "{text}");
});
