//! The interpreter engine: one `match` over [`Op`] in a loop over one activation's ops and registers.
//! Everything that crosses activations (blocks, calls, printing, system variables) is a service of
//! [`Ctx`]; no allocation per op or per block.

use fmsvm_block::alarms::NO_FANUC_NUMBER;
use fmsvm_block::{Machine, Word};
use fmsvm_ir::{BinOp, Op};

use crate::exec::{Ctx, Engine, SEQUENCE_NUMBER, Status, label_pc};
use crate::value::{binary, compare, func1, func2, num, round_to};
use fmsvm_block::Alarm;

/// Runs IR ops one by one. With a `tier`, a program that turns out to loop long (more than
/// `TIER_UP_STEPS` branches) goes on in JIT code from the next loop head: both engines share the
/// registers and the context, so the activation simply continues natively (on-stack replacement).
/// With `DEBUG` the loop tells the debugger of every op; without it that code is not compiled in.
pub struct Interpreter<'t, M: Machine, const DEBUG: bool = false> {
    /// The lazily compiled JIT to move to, for `--engine auto`.
    #[cfg_attr(not(feature = "jit"), allow(dead_code))]
    pub tier: Option<Tier<'t, M>>,
    /// The debugger told of every op (`crate::debug`).
    pub debugger: Option<&'t dyn crate::debug::Debugger>,
}

/// What the interpreter can move to: the lazily compiled JIT.
#[cfg(feature = "jit")]
pub type Tier<'t, M> = &'t crate::jit::Lazy<'t, M>;
/// What the interpreter can move to: nothing, in a build without the JIT.
#[cfg(not(feature = "jit"))]
pub type Tier<'t, M> = std::marker::PhantomData<&'t M>;

/// Branches after which `auto` compiles and moves to the JIT (about 2 ms of interpretation, the
/// JIT's compile time for a corpus program).
pub const TIER_UP_STEPS: u64 = 100_000;

impl<M: Machine, const DEBUG: bool> Engine<M> for Interpreter<'_, M, DEBUG> {
    /// The dispatch loop (clox's `run`): one arm per op in one `match`. Long on purpose (about 180
    /// lines): the program counter, the registers and the op slices stay in locals the compiler
    /// keeps in registers, which a call per arm would spill; anything rare calls out to `Ctx`.
    fn exec(&self, ctx: &mut Ctx<'_, M>, fi: usize, vec: &mut [f64], start: usize) -> Status {
        let program = ctx.program;
        let f = &program.functions[fi];
        // The ops, constants and registers as slices held in locals (a `Vec` would be read through
        // its header at every access); the register vector itself only for a call and the tier-up.
        let (ops, consts, blocks) = (&f.ops[..], &f.consts[..], &f.blocks[..]);
        let mut regs: &mut [f64] = &mut vec[..];
        let mut pc = start;
        // Runs a service; on anything but Next, leaves (after marking where it failed).
        macro_rules! service {
            ($e:expr) => {
                match $e {
                    Status::Next => {}
                    Status::Return(Some(n)) => match label_pc(f, n) {
                        // M99 Pn of a callee: on at block Nn of this program.
                        Some(p) => pc = p,
                        None => fail!(Alarm::new(
                            SEQUENCE_NUMBER,
                            format!("M99 P{n}: N{n} not found")
                        )),
                    },
                    Status::Error => {
                        mark(ctx, f.spans.get(pc - 1));
                        return Status::Error;
                    }
                    s => return s,
                }
            };
        }
        macro_rules! fail {
            ($e:expr) => {{
                ctx.fail($e);
                mark(ctx, f.spans.get(pc - 1));
                return Status::Error;
            }};
        }
        macro_rules! value {
            ($e:expr) => {
                match $e {
                    Ok(v) => v,
                    Err(e) => fail!(e),
                }
            };
        }
        macro_rules! jump {
            ($target:expr) => {{
                if ctx.step() == Status::Error {
                    mark(ctx, f.spans.get(pc - 1));
                    return Status::Error;
                }
                pc = blocks[$target as usize] as usize;
                #[cfg(feature = "jit")]
                if let Some(tier) = self.tier {
                    if ctx.stats.steps >= TIER_UP_STEPS {
                        if let Some(jit) = tier.get() {
                            return jit.exec(ctx, fi, vec, pc);
                        }
                    }
                }
            }};
        }
        let debugger = self.debugger;
        loop {
            if DEBUG && let Some(d) = debugger {
                let depth = ctx.depth();
                let machine = &mut *ctx.machine;
                let mut system = |n: u32| machine.read_system(n).ok();
                let go_on = d.before(&mut crate::debug::Stop {
                    span: f.spans.get(pc),
                    program: f.number,
                    depth,
                    locals: regs.get(..=fmsvm_ir::LOCALS).unwrap_or(&[]),
                    commons: ctx.commons,
                    system: &mut system,
                });
                if !go_on {
                    ctx.fail(Alarm::new(NO_FANUC_NUMBER, "stopped by the debugger"));
                    mark(ctx, f.spans.get(pc));
                    return Status::Error;
                }
            }
            let op = ops[pc];
            pc += 1;
            match op {
                Op::Const { dst, k } => regs[dst as usize] = consts[k as usize],
                Op::Copy { dst, src } => regs[dst as usize] = regs[src as usize],
                Op::Neg { dst, src } => regs[dst as usize] = -regs[src as usize],
                Op::Bin { op, dst, a, b } => {
                    let (x, y) = (regs[a as usize], regs[b as usize]);
                    // + - * / inline: `binary` gives the same finite result, and is called for the
                    // rest (the other operators; an overflow or a zero divisor, whose quotient is not
                    // finite, to report).
                    let r = match op {
                        BinOp::Add => num(x) + num(y),
                        BinOp::Sub => num(x) - num(y),
                        BinOp::Mul => num(x) * num(y),
                        BinOp::Div => num(x) / num(y),
                        _ => f64::NAN,
                    };
                    regs[dst as usize] = if r.is_finite() {
                        r
                    } else {
                        value!(binary(op, x, y, ctx.options.semantics))
                    }
                }
                Op::Cmp { op, dst, a, b } => {
                    regs[dst as usize] =
                        compare(op, regs[a as usize], regs[b as usize]) as u8 as f64
                }
                Op::Func1 { f: func, dst, a } => {
                    regs[dst as usize] =
                        value!(func1(func, regs[a as usize], ctx.options.semantics))
                }
                Op::Func2 { f: func, dst, a, b } => {
                    regs[dst as usize] = value!(func2(
                        func,
                        regs[a as usize],
                        regs[b as usize],
                        ctx.options.semantics
                    ))
                }
                Op::RoundAddr { letter, dst, src } => {
                    regs[dst as usize] = round_to(regs[src as usize], ctx.machine.increment(letter))
                }
                Op::LoadCommon { dst, index } => regs[dst as usize] = ctx.commons[index as usize],
                Op::StoreCommon { index, src } => ctx.commons[index as usize] = regs[src as usize],
                Op::LoadSystem { dst, number } => {
                    regs[dst as usize] = value!(ctx.machine.read_system(number))
                }
                Op::StoreSystem { number, src } => {
                    value!(ctx.machine.write_system(number, regs[src as usize]))
                }
                Op::LoadIndirect { dst, addr } => {
                    match ctx.load_indirect(regs, regs[addr as usize]) {
                        Ok(v) => regs[dst as usize] = v,
                        Err(s) => service!(s),
                    }
                }
                Op::StoreIndirect { addr, src } => {
                    let (a, v) = (regs[addr as usize], regs[src as usize]);
                    service!(ctx.store_indirect(regs, a, v))
                }
                Op::Word { letter, flags, src } => ctx.word(Word {
                    letter,
                    flags,
                    value: regs[src as usize],
                }),
                Op::WordConst { letter, flags, k } => ctx.word(Word {
                    letter,
                    flags,
                    value: consts[k as usize],
                }),
                Op::EmitBlock { info } => service!(ctx.emit(self, fi, info)),
                Op::LiteralBlock { at } => service!(ctx.literal_block(self, fi, at)),
                Op::Call { kind, info } => {
                    let status = ctx.call(self, fi, vec, kind, info);
                    regs = &mut vec[..];
                    service!(status)
                }
                Op::Return { info } => {
                    return match ctx.ret(fi, info) {
                        Status::Error => {
                            mark(ctx, f.spans.get(pc - 1));
                            Status::Error
                        }
                        s => s,
                    };
                }
                Op::CancelModal => ctx.cancel_modal(),
                Op::Print { print } => service!(ctx.print(fi, regs, print)),
                Op::Popen => service!(ctx.port(true)),
                Op::Pclos => service!(ctx.port(false)),
                Op::Message { src, message } => service!(ctx.message(regs[src as usize], message)),
                Op::MacroAlarm { src, message } => {
                    service!(ctx.macro_alarm(regs[src as usize], message))
                }
                Op::Jump { target } => jump!(target),
                Op::Branch { cond, when, target } => {
                    if (regs[cond as usize] != 0.0) == when {
                        jump!(target);
                    }
                }
                Op::Goto { src, table } => match crate::exec::goto(f, table, regs[src as usize]) {
                    Ok(b) => jump!(b),
                    Err(e) => fail!(e),
                },
                Op::Alarm { number, message } => {
                    fail!(Alarm::new(
                        number as u32,
                        program.string(message).to_string()
                    ))
                }
                // The end of the program text: the main program ends, a called one returns (`repeat`).
                Op::End => return Status::Next,
            }
        }
    }
}

/// Marks where a failure happened (the innermost activation's op wins).
fn mark<M: Machine>(ctx: &mut Ctx<'_, M>, span: fmsvm_ir::Span) {
    if let Some((_, at @ None)) = &mut ctx.error {
        *at = Some(span);
    }
}
