//! The interpreter: one `match` over [`Op`] in a loop, registers in a flat slot array, no allocation
//! per op or per block.

use fmsvm_block::{Alarm, Block, Flow, LimitKind, Machine, Stop, Word, is_vacant};
use fmsvm_compiler::check::{VarClass, classify};
use fmsvm_compiler::ir::{GotoDest, Op, Program};

use crate::value::{binary, compare, func1, func2, round_to};
use crate::{Limits, RunError, Stats, Variables};

/// 0115 VARIABLE NO. OUT OF RANGE.
const VARIABLE_RANGE: u32 = 115;
/// 0116 WRITE PROTECTED VARIABLE.
const WRITE_PROTECTED: u32 = 116;
/// 0128 ILLEGAL MACRO SEQUENCE NUMBER.
const SEQUENCE_NUMBER: u32 = 128;

/// The variable an indirect address `#[v]` names (rounded to the nearest integer).
fn indirect(v: f64) -> Result<VarClass, Alarm> {
    if is_vacant(v) {
        return Ok(VarClass::Vacant);
    }
    let n = v.round();
    if n < 0.0 || n > u32::MAX as f64 {
        return Err(Alarm::new(
            VARIABLE_RANGE,
            format!("variable number #[{v}] out of range"),
        ));
    }
    classify(n as u32).ok_or_else(|| {
        Alarm::new(
            VARIABLE_RANGE,
            format!("there is no variable #{n} (from #[{v}])"),
        )
    })
}

pub(crate) fn run<M: Machine>(
    program: &Program,
    machine: &mut M,
    vars: &mut Variables,
    limits: &Limits,
) -> Result<Stats, RunError> {
    let Some(f) = program.functions.first() else {
        return Ok(Stats::default());
    };
    let mut regs = vec![fmsvm_block::VACANT; f.n_slots as usize];
    for &(s, v) in &f.slot_consts {
        regs[s as usize] = v;
    }
    let ops = &f.ops[..];
    let consts = &f.consts[..];
    let blocks = &f.blocks[..];
    let commons = &mut vars.commons[..];
    let max_steps = if limits.max_steps == 0 {
        u64::MAX
    } else {
        limits.max_steps
    };
    let max_blocks = if limits.max_blocks == 0 {
        u64::MAX
    } else {
        limits.max_blocks
    };
    let mut stats = Stats::default();
    let mut block = Block::new();
    let mut pc = 0usize;

    macro_rules! fail {
        ($stop:expr) => {
            return Err(RunError {
                stop: Stop::from($stop),
                span: f.spans[pc - 1],
                stats,
            })
        };
    }
    macro_rules! jump {
        ($target:expr) => {{
            stats.steps += 1;
            if stats.steps > max_steps {
                fail!(Stop::Limit {
                    kind: LimitKind::Steps,
                    limit: max_steps
                });
            }
            pc = blocks[$target as usize] as usize;
        }};
    }

    loop {
        let op = ops[pc];
        pc += 1;
        match op {
            Op::Const { dst, k } => regs[dst as usize] = consts[k as usize],
            Op::Copy { dst, src } => regs[dst as usize] = regs[src as usize],
            Op::Neg { dst, src } => regs[dst as usize] = -regs[src as usize],
            Op::Bin { op, dst, a, b } => match binary(op, regs[a as usize], regs[b as usize]) {
                Ok(v) => regs[dst as usize] = v,
                Err(e) => fail!(e),
            },
            Op::Cmp { op, dst, a, b } => {
                regs[dst as usize] = compare(op, regs[a as usize], regs[b as usize]) as u8 as f64
            }
            Op::Func1 { f: func, dst, a } => match func1(func, regs[a as usize]) {
                Ok(v) => regs[dst as usize] = v,
                Err(e) => fail!(e),
            },
            Op::Func2 { f: func, dst, a, b } => {
                match func2(func, regs[a as usize], regs[b as usize]) {
                    Ok(v) => regs[dst as usize] = v,
                    Err(e) => fail!(e),
                }
            }
            Op::RoundAddr { letter, dst, src } => {
                regs[dst as usize] = round_to(regs[src as usize], machine.increment(letter))
            }
            Op::LoadCommon { dst, index } => regs[dst as usize] = commons[index as usize],
            Op::StoreCommon { index, src } => commons[index as usize] = regs[src as usize],
            Op::LoadSystem { dst, number } => match machine.read_system(number) {
                Ok(v) => regs[dst as usize] = v,
                Err(e) => fail!(e),
            },
            Op::StoreSystem { number, src } => {
                if let Err(e) = machine.write_system(number, regs[src as usize]) {
                    fail!(e)
                }
            }
            Op::LoadIndirect { dst, addr } => {
                regs[dst as usize] = match indirect(regs[addr as usize]) {
                    Ok(VarClass::Vacant) => fmsvm_block::VACANT,
                    Ok(VarClass::Local(n)) => regs[n as usize],
                    Ok(VarClass::Common(i)) => commons[i as usize],
                    Ok(VarClass::System(n)) => match machine.read_system(n) {
                        Ok(v) => v,
                        Err(e) => fail!(e),
                    },
                    Err(e) => fail!(e),
                }
            }
            Op::StoreIndirect { addr, src } => {
                let v = regs[src as usize];
                match indirect(regs[addr as usize]) {
                    Ok(VarClass::Vacant) => fail!(Alarm::new(
                        WRITE_PROTECTED,
                        "#0 is always vacant and cannot be assigned (indirect #[…] gave 0)"
                    )),
                    Ok(VarClass::Local(n)) => regs[n as usize] = v,
                    Ok(VarClass::Common(i)) => commons[i as usize] = v,
                    Ok(VarClass::System(n)) => {
                        if let Err(e) = machine.write_system(n, v) {
                            fail!(e)
                        }
                    }
                    Err(e) => fail!(e),
                }
            }
            Op::Word { letter, flags, src } => {
                let value = regs[src as usize];
                if !is_vacant(value) {
                    block.push(Word {
                        letter,
                        flags,
                        value,
                    });
                }
            }
            Op::WordConst { letter, flags, k } => {
                block.push(Word {
                    letter,
                    flags,
                    value: consts[k as usize],
                });
            }
            Op::EmitBlock { info } => {
                let info = f.infos[info as usize];
                stats.blocks += 1;
                if stats.blocks > max_blocks {
                    fail!(Stop::Limit {
                        kind: LimitKind::Blocks,
                        limit: max_blocks
                    });
                }
                block.line = info.line;
                block.block_delete = info.block_delete;
                block.comment = program.string(info.comment);
                match machine.block(&block) {
                    Ok(Flow::Continue) => block.clear(),
                    Ok(Flow::End) => return Ok(stats),
                    Err(e) => fail!(e),
                }
            }
            Op::MacroAlarm { src, message } => {
                let v = regs[src as usize];
                let n = if is_vacant(v) { 0.0 } else { v.round() };
                if !(0.0..=999.0).contains(&n) {
                    fail!(Alarm::new(
                        VARIABLE_RANGE,
                        format!("#3000 = {v}: a macro alarm number is 0 to 999")
                    ));
                }
                fail!(Alarm::new(
                    3000 + n as u32,
                    program.string(message).to_string()
                ));
            }
            Op::Jump { target } => jump!(target),
            Op::Branch { cond, when, target } => {
                if (regs[cond as usize] != 0.0) == when {
                    jump!(target);
                }
            }
            Op::Goto { src, table } => {
                let v = regs[src as usize];
                let n = if is_vacant(v) { 0.0 } else { v.round() };
                let found = if (1.0..=99_999.0).contains(&n) {
                    f.goto_tables[table as usize].find(n as u32)
                } else {
                    None
                };
                match found {
                    Some(GotoDest::Block(b)) => jump!(b),
                    Some(GotoDest::IntoLoop) => fail!(Alarm::new(
                        SEQUENCE_NUMBER,
                        format!("GOTO{n} jumps into a DO range from outside it")
                    )),
                    None => fail!(Alarm::new(
                        SEQUENCE_NUMBER,
                        format!("sequence number N{n} not found (GOTO of {v})")
                    )),
                }
            }
            Op::Alarm { number, message } => {
                fail!(Alarm::new(
                    number as u32,
                    program.string(message).to_string()
                ))
            }
            Op::End => return Ok(stats),
        }
    }
}
