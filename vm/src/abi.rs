//! The narrow ABI between JIT code and the run-time services: `extern "C"` entry points that JIT code
//! calls, and the status encoding both sides use. Every entry point forwards to the same `Ctx` service
//! the interpreter calls, so the two engines share one definition of everything but the op loop.
//!
//! Pointers passed in are the ones `Jit::exec` handed to the native function: `ctx` is the run's
//! `Ctx<M>`, `engine` the `Jit<M>`, `regs_vec` the activation's register vector, valid for the call.

use fmsvm_block::{Letter, Machine, Word, WordFlags};
use fmsvm_compiler::ast::{BinOp, Func};
use fmsvm_compiler::ir::CallKind;

use crate::exec::{Ctx, SEQUENCE_NUMBER, Status, label_pc};
use crate::jit::Jit;
use crate::value::{binary, func1, func2, round_to};

/// Status: go on.
pub const NEXT: u64 = 0;
/// Status: M99 (back to the caller).
pub const RETURN: u64 = 1;
/// Status: M99 Pn; n in the bits above 8.
pub const RETURN_SEQ: u64 = 2;
/// Status: end of program.
pub const END: u64 = 3;
/// Status: stopped; the reason is in the context.
pub const ERROR: u64 = 4;

/// Encodes a status for JIT code.
pub fn encode(s: Status) -> u64 {
    match s {
        Status::Next => NEXT,
        Status::Return(None) => RETURN,
        Status::Return(Some(n)) => RETURN_SEQ | ((n as u64) << 8),
        Status::End => END,
        Status::Error => ERROR,
    }
}

/// Decodes a status from JIT code.
pub fn decode(s: u64) -> Status {
    match s & 0xFF {
        NEXT => Status::Next,
        RETURN => Status::Return(None),
        RETURN_SEQ => Status::Return(Some((s >> 8) as u32)),
        END => Status::End,
        _ => Status::Error,
    }
}

/// # Safety
/// `ctx` must point to the live `Ctx<M>` of the run (see the module doc).
unsafe fn ctx<'a, M: Machine + 'a>(p: *mut u8) -> &'a mut Ctx<'a, M> {
    // SAFETY: the caller passes the pointer Jit::exec created from `&mut Ctx<M>`.
    unsafe { &mut *(p as *mut Ctx<'a, M>) }
}

fn bin_op(op: u32) -> BinOp {
    [
        BinOp::Add,
        BinOp::Sub,
        BinOp::Mul,
        BinOp::Div,
        BinOp::Mod,
        BinOp::And,
        BinOp::Or,
        BinOp::Xor,
    ][op as usize & 7]
}

/// The index of a binary operator in `bin_op`.
pub fn bin_index(op: BinOp) -> u32 {
    match op {
        BinOp::Add => 0,
        BinOp::Sub => 1,
        BinOp::Mul => 2,
        BinOp::Div => 3,
        BinOp::Mod => 4,
        BinOp::And => 5,
        BinOp::Or => 6,
        BinOp::Xor => 7,
    }
}

const FUNCS: [Func; 18] = [
    Func::Sin,
    Func::Cos,
    Func::Tan,
    Func::Asin,
    Func::Acos,
    Func::Atan,
    Func::Atan2,
    Func::Sqrt,
    Func::Abs,
    Func::Round,
    Func::Fix,
    Func::Fup,
    Func::Ln,
    Func::Exp,
    Func::Pow,
    Func::Adp,
    Func::Bin,
    Func::Bcd,
];

/// The index of a function in `FUNCS`.
pub fn func_index(f: Func) -> u32 {
    FUNCS.iter().position(|&g| g == f).unwrap_or(0) as u32
}

fn kind_of(k: u32) -> CallKind {
    match k {
        0 => CallKind::Sub,
        1 => CallKind::Macro,
        2 => CallKind::Modal,
        _ => CallKind::Local,
    }
}

/// The index of a call kind for `kind_of`.
pub fn kind_index(k: CallKind) -> u32 {
    match k {
        CallKind::Sub => 0,
        CallKind::Macro => 1,
        CallKind::Modal => 2,
        CallKind::Local => 3,
    }
}

/// Binary operator with alarms (the JIT inlines the common cases and comes here for the rest).
///
/// # Safety
/// `ctx` as in the module doc; `out` points to a register.
pub unsafe extern "C" fn h_binary<M: Machine>(
    c: *mut u8,
    op: u32,
    a: f64,
    b: f64,
    out: *mut f64,
) -> u64 {
    // SAFETY: see the function's contract.
    let c = unsafe { ctx::<M>(c) };
    match binary(bin_op(op), a, b, c.options.semantics) {
        Ok(v) => {
            // SAFETY: `out` is a register of the running activation.
            unsafe { *out = v };
            NEXT
        }
        Err(e) => encode(c.fail(e)),
    }
}

/// One-argument function.
///
/// # Safety
/// As `h_binary`.
pub unsafe extern "C" fn h_func1<M: Machine>(c: *mut u8, f: u32, a: f64, out: *mut f64) -> u64 {
    // SAFETY: see the function's contract.
    let c = unsafe { ctx::<M>(c) };
    match func1(FUNCS[f as usize % FUNCS.len()], a, c.options.semantics) {
        Ok(v) => {
            // SAFETY: as above.
            unsafe { *out = v };
            NEXT
        }
        Err(e) => encode(c.fail(e)),
    }
}

/// Two-argument function.
///
/// # Safety
/// As `h_binary`.
pub unsafe extern "C" fn h_func2<M: Machine>(
    c: *mut u8,
    f: u32,
    a: f64,
    b: f64,
    out: *mut f64,
) -> u64 {
    // SAFETY: see the function's contract.
    let c = unsafe { ctx::<M>(c) };
    match func2(FUNCS[f as usize % FUNCS.len()], a, b, c.options.semantics) {
        Ok(v) => {
            // SAFETY: as above.
            unsafe { *out = v };
            NEXT
        }
        Err(e) => encode(c.fail(e)),
    }
}

/// `ROUND` inside an address.
///
/// # Safety
/// `ctx` as in the module doc.
pub unsafe extern "C" fn h_round_addr<M: Machine>(c: *mut u8, letter: u32, v: f64) -> f64 {
    // SAFETY: see the function's contract.
    let c = unsafe { ctx::<M>(c) };
    let l = Letter::from_index(letter as u8).unwrap_or(Letter::X);
    round_to(v, c.machine.increment(l))
}

/// System variable read.
///
/// # Safety
/// As `h_binary`.
pub unsafe extern "C" fn h_load_system<M: Machine>(c: *mut u8, n: u32, out: *mut f64) -> u64 {
    // SAFETY: see the function's contract.
    let c = unsafe { ctx::<M>(c) };
    match c.machine.read_system(n) {
        Ok(v) => {
            // SAFETY: as above.
            unsafe { *out = v };
            NEXT
        }
        Err(e) => encode(c.fail(e)),
    }
}

/// System variable write.
///
/// # Safety
/// `ctx` as in the module doc.
pub unsafe extern "C" fn h_store_system<M: Machine>(c: *mut u8, n: u32, v: f64) -> u64 {
    // SAFETY: see the function's contract.
    let c = unsafe { ctx::<M>(c) };
    match c.machine.write_system(n, v) {
        Ok(()) => NEXT,
        Err(e) => encode(c.fail(e)),
    }
}

/// `#[addr]` read.
///
/// # Safety
/// As `h_binary`; `regs` is the activation's register vector.
pub unsafe extern "C" fn h_load_indirect<M: Machine>(
    c: *mut u8,
    regs: *mut Vec<f64>,
    addr: f64,
    out: *mut f64,
) -> u64 {
    // SAFETY: see the function's contract.
    let (c, r) = unsafe { (ctx::<M>(c), &*regs) };
    match c.load_indirect(r, addr) {
        Ok(v) => {
            // SAFETY: as above.
            unsafe { *out = v };
            NEXT
        }
        Err(s) => encode(s),
    }
}

/// `#[addr] = v`.
///
/// # Safety
/// As `h_load_indirect`.
pub unsafe extern "C" fn h_store_indirect<M: Machine>(
    c: *mut u8,
    regs: *mut Vec<f64>,
    addr: f64,
    v: f64,
) -> u64 {
    // SAFETY: see the function's contract.
    let (c, r) = unsafe { (ctx::<M>(c), &mut *regs) };
    encode(c.store_indirect(r, addr, v))
}

/// A word for the block being built.
///
/// # Safety
/// `ctx` as in the module doc.
pub unsafe extern "C" fn h_word<M: Machine>(c: *mut u8, letter_flags: u32, v: f64) {
    // SAFETY: see the function's contract.
    let c = unsafe { ctx::<M>(c) };
    let letter = Letter::from_index((letter_flags & 0xFF) as u8).unwrap_or(Letter::X);
    c.word(Word {
        letter,
        flags: WordFlags((letter_flags >> 8) as u8),
        value: v,
    });
}

/// `EmitBlock`.
///
/// # Safety
/// `ctx`, `engine` as in the module doc.
pub unsafe extern "C" fn h_emit<M: Machine>(
    c: *mut u8,
    engine: *const u8,
    fi: u32,
    info: u32,
) -> u64 {
    // SAFETY: see the function's contract.
    let (c, e) = unsafe { (ctx::<M>(c), &*(engine as *const Jit<M>)) };
    encode(c.emit(e, fi as usize, info))
}

/// `Call`.
///
/// # Safety
/// As `h_emit`; `regs` is the activation's register vector.
pub unsafe extern "C" fn h_call<M: Machine>(
    c: *mut u8,
    engine: *const u8,
    regs: *mut Vec<f64>,
    fi: u32,
    kind: u32,
    info: u32,
) -> u64 {
    // SAFETY: see the function's contract.
    let (c, e, r) = unsafe { (ctx::<M>(c), &*(engine as *const Jit<M>), &mut *regs) };
    encode(c.call(e, fi as usize, r, kind_of(kind), info))
}

/// `Return` (M99).
///
/// # Safety
/// `ctx` as in the module doc.
pub unsafe extern "C" fn h_return<M: Machine>(c: *mut u8, fi: u32, info: u32) -> u64 {
    // SAFETY: see the function's contract.
    let c = unsafe { ctx::<M>(c) };
    encode(c.ret(fi as usize, info))
}

/// `G67`.
///
/// # Safety
/// `ctx` as in the module doc.
pub unsafe extern "C" fn h_cancel_modal<M: Machine>(c: *mut u8) {
    // SAFETY: see the function's contract.
    unsafe { ctx::<M>(c) }.cancel_modal();
}

/// DPRNT/BPRNT.
///
/// # Safety
/// As `h_load_indirect`.
pub unsafe extern "C" fn h_print<M: Machine>(
    c: *mut u8,
    regs: *mut Vec<f64>,
    fi: u32,
    print: u32,
) -> u64 {
    // SAFETY: see the function's contract.
    let (c, r) = unsafe { (ctx::<M>(c), &*regs) };
    encode(c.print(fi as usize, r, print))
}

/// POPEN (1) / PCLOS (0).
///
/// # Safety
/// `ctx` as in the module doc.
pub unsafe extern "C" fn h_port<M: Machine>(c: *mut u8, open: u32) -> u64 {
    // SAFETY: see the function's contract.
    encode(unsafe { ctx::<M>(c) }.port(open != 0))
}

/// `#3006`.
///
/// # Safety
/// `ctx` as in the module doc.
pub unsafe extern "C" fn h_message<M: Machine>(c: *mut u8, v: f64, message: u32) -> u64 {
    // SAFETY: see the function's contract.
    encode(unsafe { ctx::<M>(c) }.message(v, message))
}

/// `#3000`.
///
/// # Safety
/// `ctx` as in the module doc.
pub unsafe extern "C" fn h_macro_alarm<M: Machine>(c: *mut u8, v: f64, message: u32) -> u64 {
    // SAFETY: see the function's contract.
    encode(unsafe { ctx::<M>(c) }.macro_alarm(v, message))
}

/// The step limit was passed.
///
/// # Safety
/// `ctx` as in the module doc.
pub unsafe extern "C" fn h_step_limit<M: Machine>(c: *mut u8) -> u64 {
    // SAFETY: see the function's contract.
    let c = unsafe { ctx::<M>(c) };
    encode(c.checkpoint())
}

/// Computed GOTO: the block, or -1 after an alarm.
///
/// # Safety
/// `ctx` as in the module doc.
pub unsafe extern "C" fn h_goto<M: Machine>(c: *mut u8, fi: u32, table: u32, v: f64) -> i64 {
    // SAFETY: see the function's contract.
    let c = unsafe { ctx::<M>(c) };
    let f = &c.program.functions[fi as usize];
    match crate::exec::goto(f, table, v) {
        Ok(b) => b as i64,
        Err(e) => {
            c.fail(e);
            -1
        }
    }
}

/// A static alarm (`Alarm` op).
///
/// # Safety
/// `ctx` as in the module doc.
pub unsafe extern "C" fn h_alarm<M: Machine>(c: *mut u8, number: u32, message: u32) -> u64 {
    // SAFETY: see the function's contract.
    let c = unsafe { ctx::<M>(c) };
    let text = c.program.string(message).to_string();
    encode(c.fail(fmsvm_block::Alarm::new(number, text)))
}

/// After a service returned something other than NEXT at op `pc`: for M99 Pn of a callee, the block
/// to go on at (≥ 0); otherwise `-(status + 1)` with the status the activation returns, after marking
/// where an error happened.
///
/// # Safety
/// `ctx` as in the module doc.
pub unsafe extern "C" fn h_after<M: Machine>(c: *mut u8, fi: u32, pc: u32, status: u64) -> i64 {
    // SAFETY: see the function's contract.
    let c = unsafe { ctx::<M>(c) };
    let f = &c.program.functions[fi as usize];
    let mut status = decode(status);
    if let Status::Return(Some(n)) = status {
        match label_pc(f, n) {
            Some(p) => return f.blocks.binary_search(&(p as u32)).map_or(-1, |b| b as i64),
            None => {
                c.fail(fmsvm_block::Alarm::new(
                    SEQUENCE_NUMBER,
                    format!("M99 P{n}: N{n} not found"),
                ));
                status = Status::Error;
            }
        }
    }
    if status == Status::Error {
        let span = f.spans[pc as usize];
        if let Some((_, at @ None)) = &mut c.error {
            *at = Some(span);
        }
    }
    -(encode(status) as i64) - 1
}
