//! IR → Cranelift IR, one method per op kind: slots are memory in the register array (constant slots
//! immediates), IR blocks are Cranelift blocks entered through one dispatch switch, services are calls
//! to the `abi` entry points.

use std::collections::HashMap;

use cranelift_codegen::ir::condcodes::{FloatCC, IntCC};
use cranelift_codegen::ir::{
    AbiParam, Block, FuncRef, InstBuilder, MemFlagsData, Signature, Value, types,
};
use cranelift_codegen::isa::TargetFrontendConfig;
use cranelift_frontend::{FunctionBuilder, FunctionBuilderContext, Switch};
use cranelift_jit::JITModule;
use cranelift_module::{FuncId, Linkage, Module};
use fmsvm_block::Machine;
use fmsvm_ir::{BinOp, CmpOp, Func, Function, Op, Program, Slot, VACANT_SLOT};

use super::{JitError, err};
use crate::Stats;
use crate::abi::{self, Helper, NEXT, Ty};
use crate::exec::Ctx;

fn clif(t: Ty, ptr: types::Type) -> types::Type {
    match t {
        Ty::Ptr => ptr,
        Ty::I32 => types::I32,
        Ty::I64 => types::I64,
        Ty::F64 => types::F64,
    }
}

/// The native signature: (ctx, engine, regs_view, regs, commons, start_block) -> status.
fn signature(module: &JITModule) -> Signature {
    let ptr = module.target_config().pointer_type();
    let mut sig = module.make_signature();
    for _ in 0..5 {
        sig.params.push(AbiParam::new(ptr));
    }
    sig.params.push(AbiParam::new(types::I32));
    sig.returns.push(AbiParam::new(types::I64));
    sig
}

/// Compiles every function; returns their ids in program order.
pub fn compile_all<'a, M: Machine + 'a>(
    module: &mut JITModule,
    program: &Program,
) -> Result<Vec<FuncId>, JitError> {
    let ptr = module.target_config().pointer_type();
    let mut helper_ids = Vec::new();
    for &h in Helper::ALL {
        let mut sig = module.make_signature();
        for &p in h.params() {
            sig.params.push(AbiParam::new(clif(p, ptr)));
        }
        sig.returns.push(AbiParam::new(clif(h.ret(), ptr)));
        let id = module
            .declare_function(h.name(), Linkage::Import, &sig)
            .map_err(err)?;
        helper_ids.push(id);
    }
    let steps_at =
        (std::mem::offset_of!(Ctx<'a, M>, stats) + std::mem::offset_of!(Stats, steps)) as i32;
    let max_at = std::mem::offset_of!(Ctx<'a, M>, step_check) as i32;
    let sig = signature(module);
    let mut ctx = module.make_context();
    let mut fctx = FunctionBuilderContext::new();
    let mut ids = Vec::new();
    for (fi, f) in program.functions.iter().enumerate() {
        let id = module
            .declare_function(&format!("fmsvm_f{fi}"), Linkage::Local, &sig)
            .map_err(err)?;
        ctx.func.signature = sig.clone();
        {
            let refs = helper_ids
                .iter()
                .map(|&hid| module.declare_func_in_func(hid, &mut ctx.func))
                .collect();
            let builder = FunctionBuilder::new(&mut ctx.func, &mut fctx);
            Translator::new(builder, refs, f, fi as u32, steps_at, max_at)
                .function(module.target_config());
        }
        module.define_function(id, &mut ctx).map_err(err)?;
        module.clear_context(&mut ctx);
        ids.push(id);
    }
    Ok(ids)
}

/// The IR blocks inside a loop: between a backward `Jump`/`Branch` and its target (WHILE/DO
/// loops, backward GOTOs). Only a hint for speed (a computed GOTO's cycles are not seen), never for
/// meaning.
fn looped_blocks(f: &Function) -> Vec<bool> {
    let n = f.blocks.len();
    let mut depth = vec![0i32; n + 1];
    for (bi, &start) in f.blocks.iter().enumerate() {
        let end = f.blocks.get(bi + 1).map_or(f.ops.len(), |&e| e as usize);
        if let Some(Op::Jump { target } | Op::Branch { target, .. }) =
            f.ops[start as usize..end].last().copied()
            && (target as usize) <= bi
        {
            depth[target as usize] += 1;
            depth[bi + 1] -= 1;
        }
    }
    let mut inside = 0;
    depth[..n]
        .iter()
        .map(|d| {
            inside += d;
            inside > 0
        })
        .collect()
}

/// The inline operations whose refusal goes to a shared path: the helper refuses exactly the operands
/// the inline test sends there, so the run always stops on it and nothing comes back to the op.
#[derive(Clone, Copy)]
enum Refusal {
    /// `+ - * /` with a result that is not finite (`binary`'s `finite`, or its zero divisor).
    Overflow,
    /// SQRT of `num(x) < 0` (`func1`'s range alarm).
    Range,
}

impl Refusal {
    fn helper(self) -> Helper {
        match self {
            Refusal::Overflow => Helper::h_binary,
            Refusal::Range => Helper::h_func1,
        }
    }

    fn operands(self) -> usize {
        match self {
            Refusal::Overflow => 2,
            Refusal::Range => 1,
        }
    }
}

/// Lowering state of one function.
struct Translator<'a> {
    b: FunctionBuilder<'a>,
    /// Indexed by `Helper as usize`.
    /// Indexed by `Helper as usize`.
    refs: Vec<FuncRef>,
    f: &'a Function,
    fi: u32,
    consts: HashMap<Slot, f64>,
    blocks: Vec<Block>,
    dispatch: Block,
    /// The one slow path of every service (params: the op's pc, the status): `h_after`, then go on at
    /// the block it names or leave with the status. Shared, so a service costs one block, not four.
    after: Block,
    /// The shared path past the step limit (params: the op's pc, the IR block the branch goes to).
    limit: Block,
    /// The shared refusal paths, by `Refusal`, made on first use.
    refusals: [Option<Block>; 2],
    steps_at: i32,
    max_at: i32,
    /// Loads and stores of registers, commons and the step counter: aligned, never trapping.
    mem: MemFlagsData,
    // Function parameters.
    ctx: Value,
    engine: Value,
    regs_view: Value,
    regs: Value,
    commons: Value,
}

impl<'a> Translator<'a> {
    fn new(
        mut b: FunctionBuilder<'a>,
        refs: Vec<FuncRef>,
        f: &'a Function,
        fi: u32,
        steps_at: i32,
        max_at: i32,
    ) -> Self {
        let mem = MemFlagsData::trusted();
        let entry = b.create_block();
        b.append_block_params_for_function_params(entry);
        b.switch_to_block(entry);
        let p = b.block_params(entry).to_vec();
        let dispatch = b.create_block();
        b.append_block_param(dispatch, types::I32);
        let after = b.create_block();
        b.append_block_param(after, types::I32);
        b.append_block_param(after, types::I64);
        let limit = b.create_block();
        b.append_block_param(limit, types::I32);
        b.append_block_param(limit, types::I32);
        let blocks = (0..f.blocks.len()).map(|_| b.create_block()).collect();
        b.ins().jump(dispatch, &[p[5].into()]);
        Translator {
            b,
            refs,
            f,
            fi,
            consts: f.slot_consts.iter().copied().collect(),
            blocks,
            dispatch,
            after,
            limit,
            refusals: [None; 2],
            steps_at,
            max_at,
            mem,
            ctx: p[0],
            engine: p[1],
            regs_view: p[2],
            regs: p[3],
            commons: p[4],
        }
    }

    fn function(mut self, config: TargetFrontendConfig) {
        // The dispatch switch: where an activation starts (0, a label of M97/M99 P, a repeat).
        self.b.switch_to_block(self.dispatch);
        let which = self.b.block_params(self.dispatch)[0];
        let mut sw = Switch::new();
        for (i, &blk) in self.blocks.iter().enumerate() {
            sw.set_entry(i as u128, blk);
        }
        let bad = self.b.create_block();
        sw.emit(&mut self.b, which, bad);
        self.b.switch_to_block(bad);
        // Unreachable for a verified program: the helper reports the bug.
        let fi = self.i32(self.fi);
        let e = self.call(Helper::h_bad_block, &[self.ctx, fi, which]);
        self.b.ins().return_(&[e]);
        // The shared path past the step limit: a checkpoint (NEXT) goes on at the branch's target
        // through the dispatch; a stop goes the way of every service's.
        self.b.switch_to_block(self.limit);
        let (pc, target) = {
            let p = self.b.block_params(self.limit);
            (p[0], p[1])
        };
        let st = self.call(Helper::h_step_limit, &[self.ctx]);
        let next = self.b.ins().icmp_imm_s(IntCC::Equal, st, NEXT as i64);
        self.b.ins().brif(
            next,
            self.dispatch,
            &[target.into()],
            self.after,
            &[pc.into(), st.into()],
        );
        // The shared slow path of `check`.
        self.b.switch_to_block(self.after);
        let (pc, st) = {
            let p = self.b.block_params(self.after);
            (p[0], p[1])
        };
        let fi = self.i32(self.fi);
        let r = self.call(Helper::h_after, &[self.ctx, fi, pc, st]);
        let resume = self.b.create_block();
        let leave = self.b.create_block();
        let neg = self.b.ins().icmp_imm_s(IntCC::SignedLessThan, r, 0);
        self.b.ins().brif(neg, leave, &[], resume, &[]);
        self.b.switch_to_block(resume);
        let blk = self.b.ins().ireduce(types::I32, r);
        self.b.ins().jump(self.dispatch, &[blk.into()]);
        self.b.switch_to_block(leave);
        // r = -(status + 1)
        let m = self.b.ins().ineg(r);
        let status = self.b.ins().iadd_imm_s(m, -1);
        self.b.ins().return_(&[status]);
        let looped = looped_blocks(self.f);
        for (bi, &in_loop) in looped.iter().enumerate() {
            self.b.switch_to_block(self.blocks[bi]);
            let start = self.f.blocks[bi] as usize;
            let end = self
                .f
                .blocks
                .get(bi + 1)
                .map_or(self.f.ops.len(), |&e| e as usize);
            let mut pc = start;
            while pc < end {
                // Outside loops a run of words (a block's words, usually) is one call: `h_words`
                // reads their values from the registers, where every slot is kept. Fewer calls make
                // the compile shorter; inside loops one `h_word` call a word runs faster.
                let run = if in_loop {
                    0
                } else {
                    self.f.ops[pc..end]
                        .iter()
                        .take_while(|op| matches!(op, Op::Word { .. } | Op::WordConst { .. }))
                        .count()
                };
                if run >= 2 {
                    self.words(pc, run);
                    pc += run;
                } else {
                    self.op(pc, bi);
                    pc += 1;
                }
            }
        }
        self.refusal_paths();
        self.b.seal_all_blocks();
        self.b.finalize(config);
    }

    /// The shared refusal paths the function's ops use: each calls its helper on the operands (params
    /// after the pc and the code), which raises the alarm, and leaves through `after`.
    fn refusal_paths(&mut self) {
        for r in [Refusal::Overflow, Refusal::Range] {
            let Some(blk) = self.refusals[r as usize] else {
                continue;
            };
            self.b.switch_to_block(blk);
            let p = self.b.block_params(blk).to_vec();
            let mut args = vec![self.ctx];
            args.extend_from_slice(&p[1..]);
            // The helper writes nothing when it refuses; slot 0 is only a valid address for it.
            args.push(self.slot_addr(VACANT_SLOT));
            let st = self.call(r.helper(), &args);
            self.b.ins().jump(self.after, &[p[0].into(), st.into()]);
        }
    }

    /// The shared refusal block `r` (params: the op's pc, the operator's or function's code, the
    /// operands), made on first use.
    fn refusal_block(&mut self, r: Refusal) -> Block {
        if let Some(blk) = self.refusals[r as usize] {
            return blk;
        }
        let blk = self.b.create_block();
        self.b.append_block_param(blk, types::I32);
        self.b.append_block_param(blk, types::I32);
        for _ in 0..r.operands() {
            self.b.append_block_param(blk, types::F64);
        }
        self.refusals[r as usize] = Some(blk);
        blk
    }

    /// Ops after a return in the same IR block (the code after an M99) go to a block of their own,
    /// which nothing reaches.
    fn unreachable(&mut self) {
        let dead = self.b.create_block();
        self.b.switch_to_block(dead);
    }

    /// Calls a helper that returns a status, and handles anything but NEXT (`check`).
    fn service(&mut self, h: Helper, args: &[Value], pc: usize) {
        let st = self.call(h, args);
        self.check(st, pc);
    }

    /// Calls a helper; every helper returns one value.
    fn call(&mut self, h: Helper, args: &[Value]) -> Value {
        let r = self.refs[h as usize];
        let inst = self.b.ins().call(r, args);
        self.b.inst_results(inst)[0]
    }

    fn i32(&mut self, v: u32) -> Value {
        self.b.ins().iconst(types::I32, v as i64)
    }

    fn load(&mut self, s: Slot) -> Value {
        match self.consts.get(&s) {
            Some(&v) => self.b.ins().f64const(v),
            None => self
                .b
                .ins()
                .load(types::F64, self.mem, self.regs, s as i32 * 8),
        }
    }

    fn store(&mut self, s: Slot, v: Value) {
        self.b.ins().store(self.mem, v, self.regs, s as i32 * 8);
    }

    fn slot_addr(&mut self, s: Slot) -> Value {
        self.b.ins().iadd_imm_s(self.regs, s as i64 * 8)
    }

    /// Vacant (NaN) as 0 (V5).
    fn num(&mut self, v: Value) -> Value {
        let nan = self.b.ins().fcmp(FloatCC::Unordered, v, v);
        let zero = self.b.ins().f64const(0.0);
        self.b.ins().select(nan, zero, v)
    }

    /// After a service that returned `st` at op `pc`: on NEXT go on; else return it, or go on at the
    /// block of M99 Pn.
    fn check(&mut self, st: Value, pc: usize) {
        let cont = self.b.create_block();
        let ok = self.b.ins().icmp_imm_s(IntCC::Equal, st, NEXT as i64);
        let p = self.i32(pc as u32);
        self.b
            .ins()
            .brif(ok, cont, &[], self.after, &[p.into(), st.into()]);
        self.b.switch_to_block(cont);
    }

    /// Counts a branch taken to IR block `target`; past the limit, checks in (and stops, or goes on
    /// there).
    fn step(&mut self, pc: usize, target: Value) {
        let n = self
            .b
            .ins()
            .load(types::I64, self.mem, self.ctx, self.steps_at);
        let n1 = self.b.ins().iadd_imm_s(n, 1);
        self.b.ins().store(self.mem, n1, self.ctx, self.steps_at);
        let max = self
            .b
            .ins()
            .load(types::I64, self.mem, self.ctx, self.max_at);
        let over = self.b.ins().icmp(IntCC::UnsignedGreaterThan, n1, max);
        let cont = self.b.create_block();
        let p = self.i32(pc as u32);
        self.b
            .ins()
            .brif(over, self.limit, &[p.into(), target.into()], cont, &[]);
        self.b.switch_to_block(cont);
    }

    fn jump_to(&mut self, target: u32, pc: usize) {
        let t = self.i32(target);
        self.step(pc, t);
        let t = self.blocks[target as usize];
        self.b.ins().jump(t, &[]);
    }

    fn binary(&mut self, op: BinOp, dst: Slot, a: Slot, b: Slot, pc: usize) {
        let (x, y) = (self.load(a), self.load(b));
        let inline = matches!(op, BinOp::Add | BinOp::Sub | BinOp::Mul | BinOp::Div);
        if !inline {
            let code = self.i32(abi::bin_index(op));
            let out = self.slot_addr(dst);
            self.service(Helper::h_binary, &[self.ctx, code, x, y, out], pc);
            return;
        }
        let (nx, ny) = (self.num(x), self.num(y));
        let r = match op {
            BinOp::Add => self.b.ins().fadd(nx, ny),
            BinOp::Sub => self.b.ins().fsub(nx, ny),
            BinOp::Mul => self.b.ins().fmul(nx, ny),
            _ => self.b.ins().fdiv(nx, ny),
        };
        // A non-finite result (overflow, or a zero divisor) goes to the shared path for its alarm.
        let d = self.b.ins().fsub(r, r);
        let bad = self.b.ins().fcmp(FloatCC::Unordered, d, d);
        let fast = self.b.create_block();
        let (p, code) = (self.i32(pc as u32), self.i32(abi::bin_index(op)));
        let overflow = self.refusal_block(Refusal::Overflow);
        self.b.ins().brif(
            bad,
            overflow,
            &[p.into(), code.into(), x.into(), y.into()],
            fast,
            &[],
        );
        self.b.switch_to_block(fast);
        self.store(dst, r);
    }

    /// `h_words` for ops `pc..pc + n`. Like `h_word` it cannot fail (a bug is stashed and raised
    /// when the function returns), so its status is not looked at.
    fn words(&mut self, pc: usize, n: usize) {
        let (fi, p, n) = (self.i32(self.fi), self.i32(pc as u32), self.i32(n as u32));
        self.call(Helper::h_words, &[self.ctx, self.regs, fi, p, n]);
    }

    /// The functions whose result is one machine instruction on `num(x)`, as `value::func1` computes
    /// them: SQRT (negative: the shared range path), ABS, FIX (truncate), FUP (away from zero).
    fn func1_inline(&mut self, f: Func, dst: Slot, a: Slot, pc: usize) {
        let x = self.load(a);
        let nx = self.num(x);
        let r = match f {
            Func::Sqrt => {
                let zero = self.b.ins().f64const(0.0);
                let neg = self.b.ins().fcmp(FloatCC::LessThan, nx, zero);
                let ok = self.b.create_block();
                let (p, code) = (self.i32(pc as u32), self.i32(abi::func_index(f)));
                let range = self.refusal_block(Refusal::Range);
                self.b
                    .ins()
                    .brif(neg, range, &[p.into(), code.into(), x.into()], ok, &[]);
                self.b.switch_to_block(ok);
                self.b.ins().sqrt(nx)
            }
            Func::Abs => self.b.ins().fabs(nx),
            Func::Fix => self.b.ins().trunc(nx),
            _ => {
                let zero = self.b.ins().f64const(0.0);
                let up = self.b.ins().fcmp(FloatCC::GreaterThanOrEqual, nx, zero);
                let c = self.b.ins().ceil(nx);
                let fl = self.b.ins().floor(nx);
                self.b.ins().select(up, c, fl)
            }
        };
        self.store(dst, r);
    }

    fn compare(&mut self, op: CmpOp, dst: Slot, a: Slot, b: Slot) {
        let (x, y) = (self.load(a), self.load(b));
        let t = match op {
            CmpOp::Eq | CmpOp::Ne => {
                // V7: EQ/NE tell vacant from 0.
                let xn = self.b.ins().fcmp(FloatCC::Unordered, x, x);
                let yn = self.b.ins().fcmp(FloatCC::Unordered, y, y);
                let both = self.b.ins().band(xn, yn);
                let eq = self.b.ins().fcmp(FloatCC::Equal, x, y);
                let eq = self.b.ins().bor(both, eq);
                if op == CmpOp::Eq {
                    eq
                } else {
                    self.b.ins().bxor_imm_s(eq, 1)
                }
            }
            _ => {
                let (nx, ny) = (self.num(x), self.num(y));
                let cc = match op {
                    CmpOp::Gt => FloatCC::GreaterThan,
                    CmpOp::Ge => FloatCC::GreaterThanOrEqual,
                    CmpOp::Lt => FloatCC::LessThan,
                    _ => FloatCC::LessThanOrEqual,
                };
                self.b.ins().fcmp(cc, nx, ny)
            }
        };
        let one = self.b.ins().f64const(1.0);
        let zero = self.b.ins().f64const(0.0);
        let v = self.b.ins().select(t, one, zero);
        self.store(dst, v);
    }

    /// Lowers one op: the JIT's table, one arm per op beside the interpreter's. Long on purpose (about
    /// 200 lines): each arm is a few Cranelift instructions, and one match keeps the table readable
    /// against `interp.rs` arm by arm; what an arm shares with others is a helper above.
    fn op(&mut self, pc: usize, bi: usize) {
        let op = self.f.ops[pc];
        match op {
            Op::Const { dst, k } => {
                let v = self.b.ins().f64const(self.f.consts[k as usize]);
                self.store(dst, v);
            }
            Op::Copy { dst, src } => {
                let v = self.load(src);
                self.store(dst, v);
            }
            Op::Neg { dst, src } => {
                let v = self.load(src);
                let n = self.b.ins().fneg(v);
                self.store(dst, n);
            }
            Op::Bin { op, dst, a, b } => self.binary(op, dst, a, b, pc),
            Op::Cmp { op, dst, a, b } => self.compare(op, dst, a, b),
            Op::Func1 { f, dst, a }
                if matches!(f, Func::Sqrt | Func::Abs | Func::Fix | Func::Fup) =>
            {
                self.func1_inline(f, dst, a, pc)
            }
            Op::Func1 { f, dst, a } => {
                let x = self.load(a);
                let code = self.i32(abi::func_index(f));
                let out = self.slot_addr(dst);
                self.service(Helper::h_func1, &[self.ctx, code, x, out], pc);
            }
            Op::Func2 { f, dst, a, b } => {
                let (x, y) = (self.load(a), self.load(b));
                let code = self.i32(abi::func_index(f));
                let out = self.slot_addr(dst);
                self.service(Helper::h_func2, &[self.ctx, code, x, y, out], pc);
            }
            Op::RoundAddr { letter, dst, src } => {
                let x = self.load(src);
                let l = self.i32(letter.index() as u32);
                let out = self.slot_addr(dst);
                self.service(Helper::h_round_addr, &[self.ctx, l, x, out], pc);
            }
            Op::LoadCommon { dst, index } => {
                let v = self
                    .b
                    .ins()
                    .load(types::F64, self.mem, self.commons, index as i32 * 8);
                self.store(dst, v);
            }
            Op::StoreCommon { index, src } => {
                let v = self.load(src);
                self.b
                    .ins()
                    .store(self.mem, v, self.commons, index as i32 * 8);
            }
            Op::LoadSystem { dst, number } => {
                let n = self.i32(number);
                let out = self.slot_addr(dst);
                self.service(Helper::h_load_system, &[self.ctx, n, out], pc);
            }
            Op::StoreSystem { number, src } => {
                let v = self.load(src);
                let n = self.i32(number);
                self.service(Helper::h_store_system, &[self.ctx, n, v], pc);
            }
            Op::LoadIndirect { dst, addr } => {
                let a = self.load(addr);
                let out = self.slot_addr(dst);
                self.service(
                    Helper::h_load_indirect,
                    &[self.ctx, self.regs_view, a, out],
                    pc,
                );
            }
            Op::StoreIndirect { addr, src } => {
                let (a, v) = (self.load(addr), self.load(src));
                self.service(
                    Helper::h_store_indirect,
                    &[self.ctx, self.regs_view, a, v],
                    pc,
                );
            }
            // `h_word` cannot fail: its only refusal is a letter index no `Letter` has, and this one
            // comes from a `Letter`. So its status is not looked at (no block, no branch per word).
            Op::Word { letter, flags, src } => {
                let v = self.load(src);
                let lf = self.i32(letter.index() as u32 | (flags.0 as u32) << 8);
                self.call(Helper::h_word, &[self.ctx, lf, v]);
            }
            Op::WordConst { letter, flags, k } => {
                let v = self.b.ins().f64const(self.f.consts[k as usize]);
                let lf = self.i32(letter.index() as u32 | (flags.0 as u32) << 8);
                self.call(Helper::h_word, &[self.ctx, lf, v]);
            }
            Op::EmitBlock { info } => {
                let (fi, i) = (self.i32(self.fi), self.i32(info));
                self.service(Helper::h_emit, &[self.ctx, self.engine, fi, i], pc);
            }
            Op::LiteralBlock { at } => {
                let (fi, a) = (self.i32(self.fi), self.i32(at));
                self.service(Helper::h_literal_block, &[self.ctx, self.engine, fi, a], pc);
            }
            Op::Call { kind, info } => {
                let (fi, k, i) = (
                    self.i32(self.fi),
                    self.i32(abi::kind_index(kind)),
                    self.i32(info),
                );
                self.service(
                    Helper::h_call,
                    &[self.ctx, self.engine, self.regs_view, fi, k, i],
                    pc,
                );
            }
            Op::Return { info } => {
                let (fi, i) = (self.i32(self.fi), self.i32(info));
                let st = self.call(Helper::h_return, &[self.ctx, fi, i]);
                // The status goes back to the caller as it is; an error is marked here first.
                let mark = self.b.create_block();
                let leave = self.b.create_block();
                let err = self.b.ins().icmp_imm_s(IntCC::Equal, st, abi::ERROR as i64);
                self.b.ins().brif(err, mark, &[], leave, &[]);
                self.b.switch_to_block(mark);
                let p = self.i32(pc as u32);
                self.call(Helper::h_after, &[self.ctx, fi, p, st]);
                self.b.ins().jump(leave, &[]);
                self.b.switch_to_block(leave);
                self.b.ins().return_(&[st]);
                self.unreachable();
            }
            Op::CancelModal => {
                self.service(Helper::h_cancel_modal, &[self.ctx], pc);
            }
            Op::Print { print } => {
                let (fi, p) = (self.i32(self.fi), self.i32(print));
                self.service(Helper::h_print, &[self.ctx, self.regs_view, fi, p], pc);
            }
            Op::Popen | Op::Pclos => {
                let open = self.i32(u32::from(op == Op::Popen));
                self.service(Helper::h_port, &[self.ctx, open], pc);
            }
            Op::Message { src, message } => {
                let v = self.load(src);
                let m = self.i32(message);
                self.service(Helper::h_message, &[self.ctx, v, m], pc);
            }
            Op::MacroAlarm { src, message } => {
                let v = self.load(src);
                let m = self.i32(message);
                self.service(Helper::h_macro_alarm, &[self.ctx, v, m], pc);
                let e = self.b.ins().iconst(types::I64, abi::ERROR as i64);
                self.b.ins().return_(&[e]);
                self.unreachable();
            }
            Op::Jump { target } => self.jump_to(target, pc),
            Op::Branch { cond, when, target } => {
                let v = self.load(cond);
                let zero = self.b.ins().f64const(0.0);
                // `!=` is true for NaN, exactly as the interpreter's `v != 0.0`.
                let ne = self.b.ins().fcmp(FloatCC::NotEqual, v, zero);
                let taken = self.b.create_block();
                let next = self.blocks[bi + 1];
                if when {
                    self.b.ins().brif(ne, taken, &[], next, &[]);
                } else {
                    self.b.ins().brif(ne, next, &[], taken, &[]);
                }
                self.b.switch_to_block(taken);
                self.jump_to(target, pc);
            }
            Op::Goto { src, table } => {
                let v = self.load(src);
                let (fi, t) = (self.i32(self.fi), self.i32(table));
                let r = self.call(Helper::h_goto, &[self.ctx, fi, t, v]);
                let ok = self.b.create_block();
                let bad = self.b.create_block();
                let neg = self.b.ins().icmp_imm_s(IntCC::SignedLessThan, r, 0);
                self.b.ins().brif(neg, bad, &[], ok, &[]);
                self.b.switch_to_block(bad);
                let e = self.b.ins().iconst(types::I64, abi::ERROR as i64);
                self.check(e, pc);
                self.b.ins().return_(&[e]);
                self.b.switch_to_block(ok);
                let blk = self.b.ins().ireduce(types::I32, r);
                self.step(pc, blk);
                self.b.ins().jump(self.dispatch, &[blk.into()]);
            }
            Op::Alarm { number, message } => {
                let (n, m) = (self.i32(number as u32), self.i32(message));
                self.service(Helper::h_alarm, &[self.ctx, n, m], pc);
                // `service` has left on the error; this return only ends the block.
                let e = self.b.ins().iconst(types::I64, abi::ERROR as i64);
                self.b.ins().return_(&[e]);
            }
            Op::End => {
                let next = self.b.ins().iconst(types::I64, NEXT as i64);
                self.b.ins().return_(&[next]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use fmsvm_block::{Letter, WordFlags};
    use fmsvm_ir::{Function, Op};

    use super::looped_blocks;

    #[test]
    fn the_blocks_of_a_loop_are_looped_and_the_rest_not() {
        // b0: words before the loop; b1: the WHILE test; b2: the body, back to b1; b3: after it.
        let word = Op::WordConst {
            letter: Letter::X,
            flags: WordFlags(0),
            k: 0,
        };
        let f = Function {
            ops: vec![
                word,
                Op::Jump { target: 1 },
                Op::Branch {
                    cond: 1,
                    when: false,
                    target: 3,
                },
                word,
                Op::Jump { target: 1 },
                word,
                Op::End,
            ],
            blocks: vec![0, 2, 3, 5],
            ..Function::default()
        };
        assert_eq!(looped_blocks(&f), [false, true, true, false]);
    }
}
