//! The interpreter: one `match` over [`Op`] in a loop. The running function's registers are one
//! `Vec<f64>`; calls save the caller's (function, pc, registers) in a frame and take a register vector
//! from a pool, so nothing is allocated per op, per block, or (after the first) per call.

use fmsvm_block::{Alarm, Block, Flow, Letter, LimitKind, Machine, Stop, VACANT, Word, is_vacant};
use fmsvm_compiler::check::{VarClass, classify};
use fmsvm_compiler::ir::{CallKind, Function, GotoDest, LOCALS, Op, PrintItem, Program};

use crate::calls::{self, MAX_MACRO_LEVELS, MAX_SUB_DEPTH};
use crate::print::{Port, bprnt_value, dprnt_value, iso_parity};
use crate::value::{binary, compare, func1, func2, round_to};
use crate::{RunError, RunOptions, Stats, Variables};

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

/// The saved state of a caller.
struct Frame {
    func: usize,
    pc: usize,
    /// The caller's registers (empty for M97, which shares the caller's).
    regs: Vec<f64>,
    /// How the callee was called, and the caller's own call state.
    callee_kind: CallKind,
    caller_kind: Option<CallKind>,
    caller_repeats: u32,
    caller_entry: usize,
}

/// A G66 modal call in force.
struct ModalCall {
    func: usize,
    args: Box<[f64; LOCALS + 1]>,
    count: u32,
    level: u8,
}

/// The start of the block with sequence number `n` in `f` (for M99 P, M97 P).
fn label_pc(f: &Function, n: u32) -> Option<usize> {
    f.labels
        .binary_search_by_key(&n, |e| e.0)
        .ok()
        .map(|i| f.blocks[f.labels[i].1 as usize] as usize)
}

fn code(w: &Word) -> u32 {
    (w.value * 10.0).round() as u32
}

pub(crate) fn run<M: Machine>(
    program: &Program,
    machine: &mut M,
    port: &mut dyn Port,
    vars: &mut Variables,
    options: &RunOptions,
) -> Result<Stats, RunError> {
    if program.functions.is_empty() {
        return Ok(Stats::default());
    }
    let limits = &options.limits;
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
    let commons = &mut vars.commons[..];
    let mut stats = Stats::default();
    let mut block = Block::new();
    let mut rest = Block::new();
    let mut record: Vec<u8> = Vec::with_capacity(128);
    let mut frames: Vec<Frame> = Vec::with_capacity(16);
    let mut pool: Vec<Vec<f64>> = Vec::new();
    let mut modal: Vec<ModalCall> = Vec::new();
    let mut port_open = false;

    // The running activation.
    let mut fi = 0usize;
    let mut f = &program.functions[0];
    let mut regs = vec![VACANT; f.n_slots as usize];
    for &(s, v) in &f.slot_consts {
        regs[s as usize] = v;
    }
    let mut pc = 0usize;
    let mut kind: Option<CallKind> = None; // None = main program
    let mut repeats = 0u32; // runs left after this one
    let mut entry = 0usize; // where a repeat starts
    let mut level = 0u8; // local level (G65/G66 nesting)
    let mut sub_depth = 0u8; // M98/M97 nesting

    macro_rules! fail {
        ($stop:expr) => {
            return Err(RunError {
                stop: Stop::from($stop),
                span: f.spans[pc - 1],
                stats,
            })
        };
    }
    macro_rules! step {
        () => {{
            stats.steps += 1;
            if stats.steps > max_steps {
                fail!(Stop::Limit {
                    kind: LimitKind::Steps,
                    limit: max_steps
                });
            }
        }};
    }
    macro_rules! jump {
        ($target:expr) => {{
            step!();
            pc = f.blocks[$target as usize] as usize;
        }};
    }
    // Hands `$b` to the machine; returns from `run` at the end of the program.
    macro_rules! emit {
        ($b:expr, $info:expr) => {{
            let info = f.infos[$info as usize];
            stats.blocks += 1;
            if stats.blocks > max_blocks {
                fail!(Stop::Limit {
                    kind: LimitKind::Blocks,
                    limit: max_blocks
                });
            }
            $b.line = info.line;
            $b.block_delete = info.block_delete;
            $b.comment = program.string(info.comment);
            match machine.block(&$b) {
                Ok(Flow::End) => return Ok(stats),
                Ok(flow) => flow,
                Err(e) => fail!(e),
            }
        }};
    }
    // Enters function `$callee` (called as `$k`, `$count` runs) at `$start`, with `$locals` set up by
    // `$init` on the new registers.
    macro_rules! enter {
        ($callee:expr, $k:expr, $count:expr, $start:expr, |$r:ident| $init:block) => {{
            let callee: usize = $callee;
            let k: CallKind = $k;
            let shared = k == CallKind::Local;
            let new_regs = if shared {
                Vec::new()
            } else {
                let g = &program.functions[callee];
                let mut $r = pool.pop().unwrap_or_default();
                $r.clear();
                $r.resize(g.n_slots as usize, VACANT);
                for &(s, v) in &g.slot_consts {
                    $r[s as usize] = v;
                }
                $init
                $r
            };
            let caller_regs = if shared { Vec::new() } else { std::mem::replace(&mut regs, new_regs) };
            frames.push(Frame {
                func: fi,
                pc,
                regs: caller_regs,
                callee_kind: k,
                caller_kind: kind,
                caller_repeats: repeats,
                caller_entry: entry,
            });
            match k {
                CallKind::Macro | CallKind::Modal => level += 1,
                CallKind::Sub | CallKind::Local => sub_depth += 1,
            }
            fi = callee;
            f = &program.functions[fi];
            kind = Some(k);
            repeats = $count - 1;
            entry = $start;
            pc = $start;
        }};
    }
    // Leaves the running callee (M99 or its end); `$seq` is M99's P.
    macro_rules! leave {
        ($seq:expr) => {{
            let seq: Option<u32> = $seq;
            match frames.pop() {
                None => {
                    // M99 in the main program: to Nn, or back to the start (C9), locals vacant (V2).
                    match seq {
                        Some(n) => match label_pc(f, n) {
                            Some(p) => {
                                step!();
                                pc = p;
                            }
                            None => fail!(Alarm::new(SEQUENCE_NUMBER, format!("M99 P{n}: sequence number N{n} not found"))),
                        },
                        None => {
                            if options.main_m99_ends {
                                return Ok(stats);
                            }
                            step!();
                            regs[1..=LOCALS].fill(VACANT);
                            pc = 0;
                        }
                    }
                }
                Some(frame) => {
                    if repeats > 0 && seq.is_none() {
                        // The next run of an L repeat starts with the locals the last one left (C10).
                        frames.push(frame);
                        repeats -= 1;
                        step!();
                        pc = entry;
                    } else {
                        match frame.callee_kind {
                            CallKind::Macro | CallKind::Modal => level -= 1,
                            CallKind::Sub | CallKind::Local => sub_depth -= 1,
                        }
                        if frame.callee_kind != CallKind::Local {
                            let mut done = std::mem::replace(&mut regs, frame.regs);
                            if frame.callee_kind == CallKind::Sub {
                                // M98 shares the caller's locals (V12).
                                regs[1..=LOCALS].copy_from_slice(&done[1..=LOCALS]);
                            }
                            done.clear();
                            pool.push(done);
                        }
                        fi = frame.func;
                        f = &program.functions[fi];
                        kind = frame.caller_kind;
                        repeats = frame.caller_repeats;
                        entry = frame.caller_entry;
                        pc = frame.pc;
                        if let Some(n) = seq {
                            match label_pc(f, n) {
                                Some(p) => pc = p,
                                None => fail!(Alarm::new(SEQUENCE_NUMBER, format!("M99 P{n}: sequence number N{n} not found in the caller"))),
                            }
                        }
                    }
                }
            }
        }};
    }

    loop {
        let op = f.ops[pc];
        pc += 1;
        match op {
            Op::Const { dst, k } => regs[dst as usize] = f.consts[k as usize],
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
                    Ok(VarClass::Vacant) => VACANT,
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
                    value: f.consts[k as usize],
                });
            }
            Op::EmitBlock { info } => {
                let flow = emit!(block, info);
                block.clear();
                // C12: a G66 of this level calls its macro after each move block.
                if flow == Flow::Moved
                    && let Some(mc) = modal.iter().rev().find(|m| m.level == level)
                {
                    if level >= MAX_MACRO_LEVELS {
                        fail!(Alarm::new(
                            calls::MACRO_NESTING,
                            "too many macro nesting: a fifth G65/G66 level"
                        ));
                    }
                    let (callee, count) = (mc.func, mc.count);
                    let args = mc.args.clone();
                    enter!(callee, CallKind::Modal, count, 0, |r| {
                        r[1..=LOCALS].copy_from_slice(&args[1..=LOCALS]);
                    });
                }
            }
            Op::Call { kind: k, info } => {
                let (mut p, mut l) = (None, None);
                rest.clear();
                for w in block.words() {
                    match w.letter {
                        Letter::P if p.is_none() => p = Some(w.value),
                        Letter::L if l.is_none() => l = Some(w.value),
                        Letter::G
                            if matches!(k, CallKind::Macro | CallKind::Modal)
                                && matches!(code(w), 650 | 660) => {}
                        Letter::M if k == CallKind::Sub && code(w) == 980 => {}
                        Letter::M if k == CallKind::Local && code(w) == 970 => {}
                        _ => {
                            rest.push(*w);
                        }
                    }
                }
                block.clear();
                let Some(p) = p.map(f64::round) else {
                    fail!(Alarm::new(
                        calls::PROGRAM_NOT_FOUND,
                        "a call without P (the program to call)"
                    ));
                };
                let l = l.map(f64::round);
                // C8: M98 P with more than four digits carries the count in the digits left of them.
                let (number, count) = match (k, l) {
                    (CallKind::Sub, None) if p > 9999.0 => {
                        ((p % 10_000.0) as u32, (p / 10_000.0).trunc() as u32)
                    }
                    _ => (p.max(0.0) as u32, l.unwrap_or(1.0).max(0.0) as u32),
                };
                if count > 9999 {
                    fail!(Alarm::new(
                        3,
                        format!("too many digits: L{count} (at most 9999 repeats)")
                    ));
                }
                if matches!(k, CallKind::Sub | CallKind::Local)
                    && rest.words().iter().any(|w| w.letter != Letter::N)
                {
                    // The block's own NC words run before the call.
                    emit!(rest, info);
                }
                if count == 0 {
                    continue;
                }
                match k {
                    CallKind::Local => {
                        let Some(start) = label_pc(f, number) else {
                            fail!(Alarm::new(
                                SEQUENCE_NUMBER,
                                format!("M97 P{number}: sequence number N{number} not found")
                            ));
                        };
                        if sub_depth >= MAX_SUB_DEPTH {
                            fail!(Alarm::new(
                                calls::SUB_NESTING,
                                "too many sub, macro nesting: a fifth nested subprogram"
                            ));
                        }
                        enter!(fi, CallKind::Local, count, start, |r| {});
                    }
                    _ => {
                        let Some(callee) = program.find(number) else {
                            fail!(Alarm::new(
                                calls::PROGRAM_NOT_FOUND,
                                format!("program not found: O{number:04}")
                            ));
                        };
                        match k {
                            CallKind::Sub => {
                                if sub_depth >= MAX_SUB_DEPTH {
                                    fail!(Alarm::new(
                                        calls::SUB_NESTING,
                                        "too many sub, macro nesting: a fifth nested M98"
                                    ));
                                }
                                let mut locals = [VACANT; LOCALS + 1];
                                locals[1..=LOCALS].copy_from_slice(&regs[1..=LOCALS]);
                                enter!(callee, CallKind::Sub, count, 0, |r| {
                                    r[1..=LOCALS].copy_from_slice(&locals[1..=LOCALS]);
                                });
                            }
                            _ => {
                                let mut args = Box::new([VACANT; LOCALS + 1]);
                                let words: &[Word] = rest.words();
                                if let Err(e) = calls::assign(words, &mut args[..], machine) {
                                    fail!(e);
                                }
                                if k == CallKind::Modal {
                                    modal.push(ModalCall {
                                        func: callee,
                                        args,
                                        count,
                                        level,
                                    });
                                    continue;
                                }
                                if level >= MAX_MACRO_LEVELS {
                                    fail!(Alarm::new(
                                        calls::MACRO_NESTING,
                                        "too many macro nesting: a fifth G65/G66 level"
                                    ));
                                }
                                enter!(callee, CallKind::Macro, count, 0, |r| {
                                    r[1..=LOCALS].copy_from_slice(&args[1..=LOCALS]);
                                });
                            }
                        }
                    }
                }
            }
            Op::Return { info } => {
                let mut seq = None;
                rest.clear();
                for w in block.words() {
                    match w.letter {
                        Letter::P if seq.is_none() => seq = Some(w.value.round().max(0.0) as u32),
                        Letter::M if code(w) == 990 => {}
                        _ => {
                            rest.push(*w);
                        }
                    }
                }
                block.clear();
                if rest.words().iter().any(|w| w.letter != Letter::N) {
                    emit!(rest, info);
                }
                if frames.is_empty() && options.main_m99_ends && seq.is_none() {
                    // Keep the M99 in the flat program: the control repeats it.
                    rest.clear();
                    rest.push(Word {
                        letter: Letter::M,
                        flags: Default::default(),
                        value: 99.0,
                    });
                    emit!(rest, info);
                }
                leave!(seq);
            }
            Op::CancelModal => {
                modal.pop();
            }
            Op::Print { print } => {
                let pi = &f.prints[print as usize];
                if !port_open && !options.print_without_popen {
                    fail!(Alarm::new(
                        0,
                        format!(
                            "{} before POPEN: the port is not open",
                            if pi.binary { "BPRNT" } else { "DPRNT" }
                        )
                    ));
                }
                record.clear();
                for item in &pi.items {
                    match *item {
                        PrintItem::Text(t) => {
                            let text = program.string(t).as_bytes();
                            if pi.binary {
                                record.extend(text.iter().map(|&c| iso_parity(c)));
                            } else {
                                record.extend_from_slice(text);
                            }
                        }
                        PrintItem::Value { slot, whole, frac } => {
                            let v = regs[slot as usize];
                            if pi.binary {
                                bprnt_value(&mut record, v, frac);
                            } else {
                                dprnt_value(&mut record, v, whole, frac);
                            }
                        }
                    }
                }
                record.push(b'\n');
                if let Err(e) = port.write(&record) {
                    fail!(e);
                }
            }
            Op::Popen => {
                if let Err(e) = port.open() {
                    fail!(e);
                }
                port_open = true;
            }
            Op::Pclos => {
                if let Err(e) = port.close() {
                    fail!(e);
                }
                port_open = false;
            }
            Op::Message { src, message } => {
                let v = regs[src as usize];
                let n = if is_vacant(v) {
                    0
                } else {
                    v.round().clamp(0.0, 9999.0) as u32
                };
                if let Err(e) = machine.message(n, program.string(message)) {
                    fail!(e);
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
                    Some(GotoDest::IntoLoop) => {
                        fail!(Alarm::new(
                            SEQUENCE_NUMBER,
                            format!("GOTO{n} jumps into a DO range from outside it")
                        ))
                    }
                    None => fail!(Alarm::new(
                        SEQUENCE_NUMBER,
                        format!("sequence number N{n} not found (GOTO of {v})")
                    )),
                }
            }
            Op::Alarm { number, message } => fail!(Alarm::new(
                number as u32,
                program.string(message).to_string()
            )),
            Op::End => {
                if frames.is_empty() {
                    return Ok(stats);
                }
                // A called program that ends without M99 returns as if it had one.
                leave!(None);
            }
        }
    }
}
