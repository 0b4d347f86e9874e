//! The narrow ABI between JIT code and the run-time services: `extern "C"` entry points that JIT code
//! calls, declared once in the `helpers!` table (which gives each its Rust function, its Cranelift
//! signature, its symbol name and its address), and the status encoding both sides use. Every entry
//! point forwards to the same `Ctx` service the interpreter calls, so the two engines share one
//! definition of everything but the op loop.
//!
//! Pointers passed in are the ones `Jit::exec` handed to the native function: `ctx` is the run's
//! `Ctx<M>`, `engine` the `Jit<M>`, `regs_view` the activation's registers as a [`Registers`] (a
//! pointer and a length: a fixed slice, never the vector that owns it), valid for the call.
//!
//! **Panics.** A panic must not unwind into native code (it would abort the process). Each entry point
//! runs its body under `catch_unwind`; a panic is stashed in `Ctx::panic` and the entry point returns
//! an error status, which makes the native code return at once; `Jit::exec` then resumes the unwind,
//! so a panic under the JIT ends the run exactly as one under the interpreter.

use std::any::Any;
use std::panic::{AssertUnwindSafe, catch_unwind};

use fmsvm_block::{Letter, Machine, Word, WordFlags};
use fmsvm_ir::{BinOp, CallKind, Func, Op};

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
/// Status: stopped; the reason is in the context (or a panic is in `Ctx::panic`).
pub const ERROR: u64 = 4;

/// The activation's registers as native code and the entry points see them: the slice's start and
/// length. No entry point can reach the `Vec` that owns them, so none can resize it (and so move
/// the buffer native code indexes through its own copy of `ptr`) while native code runs.
#[repr(C)]
pub struct Registers {
    ptr: *mut f64,
    len: usize,
}

impl Registers {
    /// A view of `regs` for a native call; it must not outlive the borrow it was made from.
    pub fn of(regs: &mut [f64]) -> Registers {
        Registers {
            ptr: regs.as_mut_ptr(),
            len: regs.len(),
        }
    }

    /// Where the registers start, for the native code's own indexing.
    pub fn ptr(&self) -> *mut f64 {
        self.ptr
    }

    /// The registers again.
    ///
    /// # Safety
    /// `view` is a `Registers` made by [`Registers::of`] whose borrow is still live, and no other
    /// reference to the registers is used while the slice is.
    unsafe fn slice<'a>(view: *mut Registers) -> &'a mut [f64] {
        // SAFETY: the caller's contract; `ptr` and `len` describe one live slice.
        unsafe {
            let v = &*view;
            std::slice::from_raw_parts_mut(v.ptr, v.len)
        }
    }
}

/// `h_after`'s answer for a status to return: `-(status + 1)`.
const fn leave(status: u64) -> i64 {
    -(status as i64) - 1
}

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
        ERROR => Status::Error,
        other => panic!("fmsvm bug: JIT code returned the unknown status {other}"),
    }
}

/// # Safety
/// `ctx` must point to the live `Ctx<M>` of the run (see the module doc).
unsafe fn ctx<'a, M: Machine + 'a>(p: *mut u8) -> &'a mut Ctx<'a, M> {
    // SAFETY: the caller passes the pointer Jit::exec created from `&mut Ctx<M>`.
    unsafe { &mut *(p as *mut Ctx<'a, M>) }
}

/// Runs an entry point's body; a panic in it is kept in `Ctx::panic` (the first one wins) and
/// `on_panic` returned instead, a status that makes the native code return at once.
///
/// # Safety
/// As `ctx`.
unsafe fn guard<'a, M: Machine + 'a, R>(
    p: *mut u8,
    on_panic: R,
    body: impl FnOnce(&'a mut Ctx<'a, M>) -> R,
) -> R {
    // SAFETY: the function's contract.
    match catch_unwind(AssertUnwindSafe(|| body(unsafe { ctx::<M>(p) }))) {
        Ok(r) => r,
        Err(payload) => {
            // SAFETY: the body's borrow of the context ended when it unwound.
            stash(unsafe { ctx::<M>(p) }, payload);
            on_panic
        }
    }
}

/// Gives an entry point's body (a closure) its parameter type.
fn typed<'a, M: Machine + 'a, R>(
    body: impl FnOnce(&'a mut Ctx<'a, M>) -> R,
) -> impl FnOnce(&'a mut Ctx<'a, M>) -> R {
    body
}

/// A letter code no lowering makes: reported as a caught panic would be (kept out of line, so the
/// hot `h_word` stays short).
#[cold]
#[inline(never)]
fn bad_letter<M: Machine>(c: &mut Ctx<'_, M>, code: u32) -> u64 {
    stash(
        c,
        Box::new(format!("fmsvm bug: JIT code passed letter code {code}")),
    );
    ERROR
}

/// `h_words` asked for ops that are not a run of words: reported as a caught panic would be.
#[cold]
#[inline(never)]
fn bad_words<M: Machine>(c: &mut Ctx<'_, M>, fi: u32, pc: u32) -> u64 {
    stash(
        c,
        Box::new(format!(
            "fmsvm bug: JIT code passed ops at {pc} of function {fi} as words"
        )),
    );
    ERROR
}

fn stash<M: Machine>(c: &mut Ctx<'_, M>, payload: Box<dyn Any + Send>) {
    if c.panic.is_none() {
        c.panic = Some(payload);
    }
}

/// The codes of an enum that crosses the ABI as its declaration index: `as u32` encodes; the enum's
/// `ALL` list decodes (a compile-time check keeps that list in declaration order).
macro_rules! code_table {
    ($table:ident: $t:ty = $all:expr; $(#[$doc:meta])* $enc:ident, $dec:ident) => {
        const $table: &[$t] = &$all;
        const _: () = {
            let mut i = 0;
            while i < $table.len() {
                assert!($table[i] as usize == i, "the table is not in declaration order");
                i += 1;
            }
        };
        $(#[$doc])*
        pub fn $enc(x: $t) -> u32 {
            x as u32
        }
        fn $dec(i: u32) -> $t {
            match $table.get(i as usize) {
                Some(&x) => x,
                None => panic!(
                    "fmsvm bug: JIT code passed {} code {i}",
                    stringify!($t)
                ),
            }
        }
    };
}

code_table!(BIN_OPS: BinOp = BinOp::ALL; /// The code of a binary operator.
bin_index, bin_op);

code_table!(FUNCS: Func = Func::ALL; /// The code of a function.
func_index, func_of);

code_table!(KINDS: CallKind = CallKind::ALL; /// The code of a call kind.
kind_index, kind_of);

fn letter_of(i: u32) -> Letter {
    match Letter::from_index((i & 0xFF) as u8) {
        Some(l) => l,
        None => unknown_letter(i),
    }
}

#[cold]
#[inline(never)]
fn unknown_letter(i: u32) -> ! {
    panic!("fmsvm bug: JIT code passed letter code {i}")
}

/// A value type that crosses the ABI.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ty {
    /// A pointer.
    Ptr,
    /// `u32`.
    I32,
    /// `u64`, `i64`.
    I64,
    /// `f64`.
    F64,
}

/// The ABI type of a Rust parameter or result type.
pub trait AbiType {
    /// Its type.
    const TY: Ty;
}

macro_rules! abi_types {
    ($($t:ty => $ty:ident),* $(,)?) => {
        $(impl AbiType for $t {
            const TY: Ty = Ty::$ty;
        })*
    };
}

abi_types!(
    *mut u8 => Ptr,
    *const u8 => Ptr,
    *mut f64 => Ptr,
    *mut Registers => Ptr,
    u32 => I32,
    u64 => I64,
    i64 => I64,
    f64 => F64,
);

/// Declares the entry points, once each: `fn name(ctx, params…) -> ret [panic: value] { body }`.
/// Gives the `extern "C"` function (its body guarded, `ctx` a `&mut Ctx<M>` in it) and the `Helper`
/// enum the lowering calls them by, with each one's name, signature and address: a signature cannot
/// differ between the Rust function and the Cranelift declaration.
/// How an entry point runs its body: `panic: STATUS` under [`guard`]; `panic-free` directly, for the
/// hottest entry points whose bodies cannot panic (no indexing, no unwrap, no call that can panic; a
/// bug is reported by stashing a payload, as a caught panic would be). The guard costs about ten
/// instructions a call.
macro_rules! body_under {
    ($m:ident, $r:ty, $c:ident, $body:ident, panic: $on_panic:expr) => {
        // SAFETY: the function's contract.
        unsafe { guard::<$m, $r>($c, $on_panic, $body) }
    };
    ($m:ident, $r:ty, $c:ident, $body:ident, panic-free) => {
        // SAFETY: the function's contract.
        $body(unsafe { ctx::<$m>($c) })
    };
}

macro_rules! helpers {
    ($(
        $(#[doc = $doc:literal])*
        fn $name:ident($c:ident $(, $p:ident: $t:ty)* $(,)?) -> $r:ty [$($mode:tt)*] $body:block
    )*) => {
        $(
            $(#[doc = $doc])*
            ///
            /// # Safety
            /// The pointers are the ones `Jit::exec` passed to the native code (see the module doc).
            pub unsafe extern "C" fn $name<M: Machine>($c: *mut u8 $(, $p: $t)*) -> $r {
                let body = typed::<M, $r>(move |$c| $body);
                body_under!(M, $r, $c, body, $($mode)*)
            }
        )*

        /// The entry points JIT code calls.
        #[allow(non_camel_case_types)]
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        pub enum Helper {
            $(
                #[doc = concat!("`", stringify!($name), "`")]
                $name,
            )*
        }

        impl Helper {
            /// Every entry point, in declaration order (`Helper as usize` indexes it).
            pub const ALL: &[Helper] = &[$(Helper::$name),*];

            /// The symbol name.
            pub fn name(self) -> &'static str {
                match self {
                    $(Helper::$name => stringify!($name),)*
                }
            }

            /// The parameter types (the context pointer first).
            pub fn params(self) -> &'static [Ty] {
                match self {
                    $(Helper::$name => const { &[Ty::Ptr $(, <$t as AbiType>::TY)*] },)*
                }
            }

            /// The result type.
            pub fn ret(self) -> Ty {
                match self {
                    $(Helper::$name => <$r as AbiType>::TY,)*
                }
            }

            /// The address of the entry point for machines of type `M`.
            pub fn address<M: Machine>(self) -> *const u8 {
                match self {
                    $(Helper::$name => $name::<M> as *const u8,)*
                }
            }
        }
    };
}

/// Writes a service's value to a register, or fails.
fn put<M: Machine>(
    c: &mut Ctx<'_, M>,
    out: *mut f64,
    r: Result<f64, impl Into<fmsvm_block::Stop>>,
) -> u64 {
    match r {
        Ok(v) => {
            // SAFETY: `out` is a register of the running activation (the lowering passes the address
            // of a slot the verifier checked).
            unsafe { *out = v };
            NEXT
        }
        Err(e) => encode(c.fail(e)),
    }
}

helpers! {
    /// Binary operator with alarms (the JIT inlines the common cases and comes here for the rest).
    fn h_binary(c, op: u32, a: f64, b: f64, out: *mut f64) -> u64 [panic: ERROR] {
        let r = binary(bin_op(op), a, b, c.options.semantics);
        put(c, out, r)
    }

    /// One-argument function.
    fn h_func1(c, f: u32, a: f64, out: *mut f64) -> u64 [panic: ERROR] {
        let r = func1(func_of(f), a, c.options.semantics);
        put(c, out, r)
    }

    /// Two-argument function.
    fn h_func2(c, f: u32, a: f64, b: f64, out: *mut f64) -> u64 [panic: ERROR] {
        let r = func2(func_of(f), a, b, c.options.semantics);
        put(c, out, r)
    }

    /// `ROUND` inside an address.
    fn h_round_addr(c, letter: u32, v: f64, out: *mut f64) -> u64 [panic: ERROR] {
        let r = round_to(v, c.machine.increment(letter_of(letter)));
        put(c, out, Ok::<_, fmsvm_block::Stop>(r))
    }

    /// System variable read.
    fn h_load_system(c, n: u32, out: *mut f64) -> u64 [panic: ERROR] {
        let r = c.machine.read_system(n);
        put(c, out, r)
    }

    /// System variable write.
    fn h_store_system(c, n: u32, v: f64) -> u64 [panic: ERROR] {
        match c.machine.write_system(n, v) {
            Ok(()) => NEXT,
            Err(e) => encode(c.fail(e)),
        }
    }

    /// `#[addr]` read; `regs` is the activation's registers.
    fn h_load_indirect(c, regs: *mut Registers, addr: f64, out: *mut f64) -> u64 [panic: ERROR] {
        // SAFETY: `regs` is the running activation's registers (module doc).
        let r = unsafe { Registers::slice(regs) };
        match c.load_indirect(r, addr) {
            Ok(v) => put(c, out, Ok::<_, fmsvm_block::Stop>(v)),
            Err(s) => encode(s),
        }
    }

    /// `#[addr] = v`.
    fn h_store_indirect(c, regs: *mut Registers, addr: f64, v: f64) -> u64 [panic: ERROR] {
        // SAFETY: as `h_load_indirect`.
        let r = unsafe { Registers::slice(regs) };
        encode(c.store_indirect(r, addr, v))
    }

    /// The words of ops `pc..pc + n` of function `fi` (a run of `Word`/`WordConst` ops, nothing
    /// between them) for the block being built, in order: one call for a block's words. A `Word`'s
    /// value is read from the activation's registers `regs`, where the JIT keeps every slot, a
    /// `WordConst`'s from the function's constants.
    fn h_words(c, regs: *mut f64, fi: u32, pc: u32, n: u32) -> u64 [panic-free] {
        let ops = c
            .program
            .functions
            .get(fi as usize)
            .and_then(|f| Some((f.ops.get(pc as usize..pc.saturating_add(n) as usize)?, &f.consts)));
        let Some((ops, consts)) = ops else {
            return bad_words(c, fi, pc);
        };
        for &op in ops {
            let word = match op {
                Op::Word { letter, flags, src } => Word {
                    letter,
                    flags,
                    // SAFETY: `src` is a slot of the function (the verifier checked it) and `regs`
                    // its activation's registers (module doc).
                    value: unsafe { *regs.add(src as usize) },
                },
                Op::WordConst { letter, flags, k } => match consts.get(k as usize) {
                    Some(&value) => Word {
                        letter,
                        flags,
                        value,
                    },
                    None => return bad_words(c, fi, pc),
                },
                _ => return bad_words(c, fi, pc),
            };
            c.word(word);
        }
        NEXT
    }

    /// A word for the block being built.
    fn h_word(c, letter_flags: u32, v: f64) -> u64 [panic-free] {
        match Letter::from_index((letter_flags & 0xFF) as u8) {
            Some(letter) => {
                c.word(Word {
                    letter,
                    flags: WordFlags((letter_flags >> 8) as u8),
                    value: v,
                });
                NEXT
            }
            None => bad_letter(c, letter_flags),
        }
    }

    /// `EmitBlock`.
    fn h_emit(c, engine: *const u8, fi: u32, info: u32) -> u64 [panic: ERROR] {
        // SAFETY: `engine` is the running `Jit<M>` (module doc).
        let e = unsafe { &*(engine as *const Jit<M>) };
        encode(c.emit(e, fi as usize, info))
    }

    /// `LiteralBlock`.
    fn h_literal_block(c, engine: *const u8, fi: u32, at: u32) -> u64 [panic: ERROR] {
        // SAFETY: as `h_emit`.
        let e = unsafe { &*(engine as *const Jit<M>) };
        encode(c.literal_block(e, fi as usize, at))
    }

    /// `Call`; `regs` is the activation's registers.
    fn h_call(
        c,
        engine: *const u8,
        regs: *mut Registers,
        fi: u32,
        kind: u32,
        info: u32,
    ) -> u64 [panic: ERROR] {
        // SAFETY: as `h_emit` and `h_load_indirect`.
        let (e, r) = unsafe { (&*(engine as *const Jit<M>), Registers::slice(regs)) };
        encode(c.call(e, fi as usize, r, kind_of(kind), info))
    }

    /// `Return` (M99).
    fn h_return(c, fi: u32, info: u32) -> u64 [panic: ERROR] {
        encode(c.ret(fi as usize, info))
    }

    /// `G67`.
    fn h_cancel_modal(c) -> u64 [panic: ERROR] {
        c.cancel_modal();
        NEXT
    }

    /// DPRNT/BPRNT.
    fn h_print(c, regs: *mut Registers, fi: u32, print: u32) -> u64 [panic: ERROR] {
        // SAFETY: as `h_load_indirect`.
        let r = unsafe { Registers::slice(regs) };
        encode(c.print(fi as usize, r, print))
    }

    /// POPEN (1) / PCLOS (0).
    fn h_port(c, open: u32) -> u64 [panic: ERROR] {
        encode(c.port(open != 0))
    }

    /// `#3006`.
    fn h_message(c, v: f64, message: u32) -> u64 [panic: ERROR] {
        encode(c.message(v, message))
    }

    /// `#3000`.
    fn h_macro_alarm(c, v: f64, message: u32) -> u64 [panic: ERROR] {
        encode(c.macro_alarm(v, message))
    }

    /// The step limit was passed.
    fn h_step_limit(c) -> u64 [panic: ERROR] {
        encode(c.checkpoint())
    }

    /// Computed GOTO: the block, or -1 after an alarm.
    fn h_goto(c, fi: u32, table: u32, v: f64) -> i64 [panic: -1] {
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
    fn h_alarm(c, number: u32, message: u32) -> u64 [panic: ERROR] {
        let text = c.program.string(message).to_string();
        encode(c.fail(fmsvm_block::Alarm::new(number, text)))
    }

    /// After a service returned something other than NEXT at op `pc`: for M99 Pn of a callee, the
    /// block to go on at (≥ 0); otherwise `-(status + 1)` with the status the activation returns,
    /// after marking where an error happened.
    fn h_after(c, fi: u32, pc: u32, status: u64) -> i64 [panic: leave(ERROR)] {
        let f = &c.program.functions[fi as usize];
        let mut status = decode(status);
        if let Status::Return(Some(n)) = status {
            match label_pc(f, n) {
                Some(p) => match f.blocks.binary_search(&(p as u32)) {
                    Ok(b) => return b as i64,
                    Err(_) => panic!("fmsvm bug: label N{n} of {} starts no block", f.name()),
                },
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
            let span = f.spans.get(pc as usize);
            if let Some((_, at @ None)) = &mut c.error {
                *at = Some(span);
            }
        }
        leave(encode(status))
    }

    /// The entry switch was asked for a block the function does not have: a bug (the verifier and
    /// `Jit::exec` rule it out), reported as a panic.
    fn h_bad_block(c, fi: u32, block: u32) -> u64 [panic: ERROR] {
        let name = c.program.functions.get(fi as usize).map(|f| f.name());
        panic!("fmsvm bug: JIT code entered block {block} of function {fi} ({name:?}), which it does not have")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Native code indexes the registers through its own copy of their start: every engine, and
    /// every entry point native code calls, takes them as a slice or a [`Registers`] view, never
    /// the vector that owns them (which could be resized, moving the buffer). A signature with a
    /// `&mut Vec<f64>` does not compile here.
    #[test]
    fn registers_reach_the_engines_as_a_fixed_slice() {
        use crate::exec::{Engine, Status};
        type Exec<E, M> =
            for<'a, 'c, 'r> fn(&'a E, &'c mut Ctx<'_, M>, usize, &'r mut [f64], usize) -> Status;
        fn takes<M: Machine + 'static>() {
            let _: Exec<Jit<M>, M> = <Jit<M> as Engine<M>>::exec;
            let _: Exec<crate::interp::Interpreter<'static, M>, M> =
                <crate::interp::Interpreter<'static, M> as Engine<M>>::exec;
            let _: unsafe fn(*mut Registers) -> &'static mut [f64] = Registers::slice;
        }
        struct Still;
        impl Machine for Still {
            fn block(
                &mut self,
                _: &fmsvm_block::Block<'_>,
            ) -> Result<fmsvm_block::Flow, fmsvm_block::Stop> {
                Ok(fmsvm_block::Flow::Continue)
            }
            fn read_system(&mut self, _: u32) -> Result<f64, fmsvm_block::Stop> {
                Ok(0.0)
            }
            fn write_system(&mut self, _: u32, _: f64) -> Result<(), fmsvm_block::Stop> {
                Ok(())
            }
            fn increment(&self, _: Letter) -> f64 {
                0.001
            }
        }
        takes::<Still>();
        let mut regs = [1.0, 2.0, 3.0];
        let mut view = Registers::of(&mut regs);
        // SAFETY: `view` was made from `regs`, whose borrow is live, and nothing else uses it.
        let again = unsafe { Registers::slice(&mut view) };
        again[2] = 7.0;
        assert_eq!(again.len(), 3);
        assert_eq!(regs, [1.0, 2.0, 7.0]);
    }

    #[test]
    fn codes_decode_to_what_they_encode() {
        for &op in BIN_OPS {
            assert_eq!(bin_op(bin_index(op)), op);
        }
        for &f in FUNCS {
            assert_eq!(func_of(func_index(f)), f);
        }
        for &k in KINDS {
            assert_eq!(kind_of(kind_index(k)), k);
        }
        // The last variants, so an appended one shows up here.
        assert_eq!(func_index(Func::Bcd) as usize, FUNCS.len() - 1);
        assert_eq!(bin_index(BinOp::Xor) as usize, BIN_OPS.len() - 1);
        assert_eq!(kind_index(CallKind::Local) as usize, KINDS.len() - 1);
    }

    #[test]
    fn helper_table_is_in_declaration_order() {
        for (i, h) in Helper::ALL.iter().enumerate() {
            assert_eq!(*h as usize, i);
            assert_eq!(
                h.params()[0],
                Ty::Ptr,
                "{} takes the context first",
                h.name()
            );
        }
        assert_eq!(Helper::h_binary.params().len(), 5);
        assert_eq!(Helper::h_goto.ret(), Ty::I64);
    }

    #[test]
    fn statuses_round_trip() {
        for s in [
            Status::Next,
            Status::Return(None),
            Status::Return(Some(1234)),
            Status::End,
            Status::Error,
        ] {
            assert_eq!(decode(encode(s)), s);
        }
        assert_eq!(leave(ERROR), -5);
    }
}
