//! Arbitrary IR built by hand (bytes → functions, ops, tables): the verifier never panics, and a
//! program it accepts runs on the interpreter and the JIT with small limits without crashing, to the
//! same bytes, variables and stop.
#![no_main]
use libfuzzer_sys::fuzz_target;

use fmsvm_block::{Letter, WordFlags};
use fmsvm_compiler::ir::{
    BinOp, BlockInfo, CallKind, CmpOp, Func, Function, GotoDest, GotoTable, Op, PrintInfo,
    PrintItem, Program, Span,
};

#[path = "common.rs"]
#[allow(dead_code)] // `compile`: this target builds its programs itself
mod common;

/// The input, read from the front; zeros once it runs out.
struct Bytes<'a>(&'a [u8]);

impl Bytes<'_> {
    fn u8(&mut self) -> u8 {
        match self.0.split_first() {
            Some((&b, rest)) => {
                self.0 = rest;
                b
            }
            None => 0,
        }
    }
    fn below(&mut self, n: usize) -> usize {
        if n == 0 { 0 } else { self.u8() as usize % n }
    }
    fn u16(&mut self) -> u16 {
        u16::from_le_bytes([self.u8(), self.u8()])
    }
    fn u32(&mut self) -> u32 {
        u32::from_le_bytes([self.u8(), self.u8(), self.u8(), self.u8()])
    }
    fn pick<T: Copy>(&mut self, from: &[T]) -> T {
        from[self.below(from.len())]
    }
    /// Mostly a small index below `n` (valid), sometimes anything (invalid).
    fn index(&mut self, n: usize) -> u32 {
        if self.u8() < 240 {
            self.below(n.max(1)) as u32
        } else {
            self.u32()
        }
    }
    fn bool(&mut self) -> bool {
        self.u8() & 1 == 1
    }
}

const VALUES: [f64; 12] = [
    0.0,
    1.0,
    -1.0,
    2.0,
    3.0,
    2.5,
    -7.25,
    100.0,
    1e9,
    1e300,
    f64::NAN,
    f64::INFINITY,
];
/// System variables the kernel knows, and some it does not.
const SYSTEM: [u32; 6] = [3001, 4001, 5001, 5221, 4109, 77_777];

fn function(b: &mut Bytes, fi: usize, strings: usize) -> Function {
    let n_slots = if b.u8() < 250 {
        34 + b.below(16) as u16
    } else {
        b.u16()
    };
    let slots = n_slots as usize + 2;
    let slot = |b: &mut Bytes| b.index(slots) as u16;
    let mut f = Function {
        number: Some(if fi == 0 { 1 } else { 8999 + fi as u32 }),
        title: b.index(strings),
        n_slots,
        ..Function::default()
    };
    for _ in 0..b.below(4) {
        let s = 34 + b.below(16) as u16;
        let v = b.pick(&VALUES);
        f.slot_consts.push((s, v));
    }
    for _ in 0..b.below(6) {
        f.consts.push(b.pick(&VALUES));
    }
    // Packed literal blocks as raw bytes: the verifier must refuse any that do not decode.
    for _ in 0..b.below(24) {
        f.literals.push(b.u8());
    }
    for _ in 0..1 + b.below(3) {
        f.infos.push(BlockInfo {
            file: 0,
            line: b.below(100) as u32,
            column: 1,
            block_delete: b.bool(),
            comment: if b.bool() { u32::MAX } else { b.index(strings) },
        });
    }
    for _ in 0..b.below(3) {
        let mut items = Vec::new();
        for _ in 0..b.below(4) {
            items.push(if b.bool() {
                PrintItem::Text(b.index(strings))
            } else {
                PrintItem::Value {
                    slot: slot(b),
                    whole: b.below(11) as u8,
                    frac: b.below(11) as u8,
                }
            });
        }
        f.prints.push(PrintInfo {
            binary: b.bool(),
            items,
        });
    }
    let n_ops = 1 + b.below(40);
    // Blocks are cut after each terminator, so the structure is mostly valid.
    let n_blocks_guess = 1 + n_ops / 3;
    for _ in 0..b.below(3) {
        let mut entries = Vec::new();
        for n in 1..=b.below(4) as u32 {
            let d = if b.u8() < 20 {
                GotoDest::IntoLoop
            } else {
                GotoDest::Block(b.index(n_blocks_guess))
            };
            entries.push((n * 10, d));
        }
        f.goto_tables.push(GotoTable { entries });
    }
    for n in 1..=b.below(4) as u32 {
        f.labels.push((n * 10, b.index(n_blocks_guess)));
    }
    let goto_tables = f.goto_tables.len();
    let (consts, infos, prints) = (f.consts.len(), f.infos.len(), f.prints.len());
    let literals = f.literals.len() + 2;
    f.blocks.push(0);
    for pc in 0..n_ops {
        let last = pc + 1 == n_ops;
        let op = if last {
            // End the function with a terminator (mostly).
            match b.below(8) {
                0 => Op::Jump {
                    target: b.index(n_blocks_guess),
                },
                1 => Op::Alarm {
                    number: b.u16(),
                    message: b.index(strings),
                },
                _ => Op::End,
            }
        } else {
            match b.below(31) {
                0 => Op::Const {
                    dst: slot(b),
                    k: b.index(consts),
                },
                1 => Op::Copy {
                    dst: slot(b),
                    src: slot(b),
                },
                2 => Op::Neg {
                    dst: slot(b),
                    src: slot(b),
                },
                3 => Op::Bin {
                    op: b.pick(&BinOp::ALL),
                    dst: slot(b),
                    a: slot(b),
                    b: slot(b),
                },
                4 => Op::Cmp {
                    op: b.pick(&CmpOp::ALL),
                    dst: slot(b),
                    a: slot(b),
                    b: slot(b),
                },
                5 => Op::Func1 {
                    f: b.pick(&Func::ALL),
                    dst: slot(b),
                    a: slot(b),
                },
                6 => Op::Func2 {
                    f: b.pick(&Func::ALL),
                    dst: slot(b),
                    a: slot(b),
                    b: slot(b),
                },
                7 => Op::RoundAddr {
                    letter: b.pick(&Letter::ALL),
                    dst: slot(b),
                    src: slot(b),
                },
                8 => Op::LoadCommon {
                    dst: slot(b),
                    index: b.index(610) as u16,
                },
                9 => Op::StoreCommon {
                    index: b.index(610) as u16,
                    src: slot(b),
                },
                10 => Op::LoadSystem {
                    dst: slot(b),
                    number: b.pick(&SYSTEM),
                },
                11 => Op::StoreSystem {
                    number: b.pick(&SYSTEM),
                    src: slot(b),
                },
                12 => Op::LoadIndirect {
                    dst: slot(b),
                    addr: slot(b),
                },
                13 => Op::StoreIndirect {
                    addr: slot(b),
                    src: slot(b),
                },
                14 | 15 => Op::Word {
                    letter: b.pick(&Letter::ALL),
                    flags: WordFlags(b.u8() & 3),
                    src: slot(b),
                },
                16 | 17 => Op::WordConst {
                    letter: b.pick(&Letter::ALL),
                    flags: WordFlags(b.u8() & 3),
                    k: b.index(consts),
                },
                18 => Op::EmitBlock {
                    info: b.index(infos),
                },
                19 => Op::LiteralBlock {
                    at: b.index(literals),
                },
                20 => Op::MacroAlarm {
                    src: slot(b),
                    message: b.index(strings),
                },
                21 => Op::Message {
                    src: slot(b),
                    message: b.index(strings),
                },
                22 => Op::Call {
                    kind: b.pick(&CallKind::ALL),
                    info: b.index(infos),
                },
                23 => Op::Return {
                    info: b.index(infos),
                },
                24 => Op::CancelModal,
                25 => Op::Print {
                    print: b.index(prints),
                },
                26 => Op::Popen,
                27 => Op::Pclos,
                28 => Op::Jump {
                    target: b.index(n_blocks_guess),
                },
                29 => Op::Branch {
                    cond: slot(b),
                    when: b.bool(),
                    target: b.index(n_blocks_guess),
                },
                _ => Op::Goto {
                    src: slot(b),
                    table: b.index(goto_tables),
                },
            }
        };
        f.ops.push(op);
        f.spans.push(Span::default());
        if op.is_terminator() && !last {
            f.blocks.push(pc as u32 + 1);
        }
    }
    if b.u8() > 250 {
        // A broken block list now and then.
        let i = b.below(f.blocks.len());
        f.blocks[i] = b.u32();
    }
    f
}

fn program(data: &[u8]) -> Program {
    let mut b = Bytes(data);
    let strings: Vec<String> = (0..b.below(4)).map(|i| format!("s{i}")).collect();
    let n = 1 + b.below(3);
    let functions = (0..n)
        .map(|fi| function(&mut b, fi, strings.len()))
        .collect();
    Program {
        functions,
        strings,
        ..Program::default()
    }
}

fuzz_target!(|data: &[u8]| {
    let p = program(data);
    if p.verify().is_ok() {
        let a = common::expand(&p, fmsvm_vm::EngineKind::Interp);
        let b = common::expand(&p, fmsvm_vm::EngineKind::Jit);
        assert_eq!(a, b, "engines differ on {p:?}");
    }
});
