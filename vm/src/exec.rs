//! The run-time services both engines share: the block being built, emission to the Machine, calls
//! (M98, G65, G66, M97) and returns, DPRNT/BPRNT, system and indirect variables, limits. An engine only
//! runs the ops of one activation; everything that crosses activations is here, once.
//!
//! Calls are real calls: `call` runs the callee through the engine (`Engine::exec`) recursively, which
//! Fanuc's nesting limits (4 macro levels, 4 subprogram levels) keep shallow.

use crate::gate::BlockGate;
use fmsvm_block::alarms::{NO_FANUC_NUMBER, TOO_MANY_DIGITS};
use fmsvm_block::{
    Alarm, Block, Code, Flow, Letter, LimitKind, Machine, Stop, VACANT, Word, is_vacant,
};
use fmsvm_ir::{
    CallKind, CommonRanges, Function, GotoDest, LOCALS, PrintItem, Program, Span, VarClass, alarm,
};

use crate::calls::{self, MAX_MACRO_LEVELS, MAX_SUB_DEPTH};
use crate::print::{Port, bprnt_value, dprnt_value, iso_parity};
use crate::{RunOptions, Stats};

/// Steps between looks at the clock when a wall-time limit is set.
const CHECK_EVERY: u64 = 1 << 16;

/// 0115 VARIABLE NO. OUT OF RANGE.
pub const VARIABLE_RANGE: u32 = 115;
/// 0116 WRITE PROTECTED VARIABLE.
pub const WRITE_PROTECTED: u32 = 116;
/// 0128 ILLEGAL MACRO SEQUENCE NUMBER.
pub const SEQUENCE_NUMBER: u32 = 128;

/// How an activation (or a service) ended.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Status {
    /// Go on with the next op.
    Next,
    /// M99 (or the end of a called program): back to the caller, or to its block `Nn` (M99 Pn).
    Return(Option<u32>),
    /// The program ended (M02, M30, or the end of the main program).
    End,
    /// Stopped: the reason is in `Ctx::error`.
    Error,
}

/// Runs the ops of one activation of a function.
pub trait Engine<M: Machine> {
    /// Runs function `func` on `regs` from op `pc` until it returns, ends or fails.
    fn exec(&self, ctx: &mut Ctx<'_, M>, func: usize, regs: &mut [f64], pc: usize) -> Status;
}

/// A G66 (or G66.1) modal call in force.
struct ModalCall {
    func: usize,
    args: Box<[f64; LOCALS + 1]>,
    count: u32,
    level: u8,
    /// G66.1: every NC block of this level calls the macro, its words the arguments (instead of the
    /// block running).
    each_block: bool,
}

/// Everything a run shares across activations.
pub struct Ctx<'p, M: Machine> {
    /// The program.
    pub program: &'p Program,
    /// The machine blocks go to.
    pub machine: &'p mut M,
    port: &'p mut dyn Port,
    /// Common variables.
    pub commons: &'p mut [f64],
    /// Options and limits.
    pub options: RunOptions,
    /// The step count at which `checkpoint` runs next (the JIT compares against it inline).
    pub(crate) step_check: u64,
    max_steps: u64,
    /// The block and wall-time limits, and the blocks handed.
    gate: BlockGate,
    /// Work done.
    pub stats: Stats,
    /// The block being built by Word ops.
    pub block: Block<'p>,
    rest: Block<'p>,
    record: Vec<u8>,
    pool: Vec<Vec<f64>>,
    modal: Vec<ModalCall>,
    port_open: bool,
    level: u8,
    sub_depth: u8,
    /// Why the run stopped, and where (the span is filled in by the innermost activation).
    pub error: Option<(Stop, Option<Span>)>,
    /// A panic caught at the JIT's ABI boundary, to resume once the native code has returned.
    #[cfg_attr(not(feature = "jit"), allow(dead_code))]
    pub(crate) panic: Option<Box<dyn std::any::Any + Send>>,
}

impl<M: Machine> Ctx<'_, M> {
    /// Macro and subprogram levels in force (0 in the main program).
    pub(crate) fn depth(&self) -> u8 {
        self.level.saturating_add(self.sub_depth)
    }
}

/// The start of the block with sequence number `n` in `f` (for M99 P, M97 P).
pub fn label_pc(f: &Function, n: u32) -> Option<usize> {
    f.labels
        .binary_search_by_key(&n, |e| e.0)
        .ok()
        .map(|i| f.blocks[f.labels[i].1 as usize] as usize)
}

/// The variable an indirect address `#[v]` names (rounded to the nearest integer), among the
/// control's `commons` (V4: a common number the control does not have is alarm 0115).
pub fn indirect(v: f64, commons: &CommonRanges) -> Result<VarClass, Alarm> {
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
    commons.classify(n as u32).ok_or_else(|| {
        Alarm::new(
            VARIABLE_RANGE,
            format!(
                "there is no variable #{n} (from #[{v}]; the commons are {})",
                commons.describe()
            ),
        )
    })
}

/// The block a computed `GOTO v` goes to through `goto_tables[table]` (L5: rounded, 1–99999).
pub fn goto(f: &Function, table: u32, v: f64) -> Result<u32, Alarm> {
    let n = if is_vacant(v) { 0.0 } else { v.round() };
    let found = if (1.0..=99_999.0).contains(&n) {
        f.goto_tables[table as usize].find(n as u32)
    } else {
        None
    };
    match found {
        Some(GotoDest::Block(b)) => Ok(b),
        Some(GotoDest::IntoLoop) => Err(Alarm::new(
            SEQUENCE_NUMBER,
            format!("GOTO{n} jumps into a DO range from outside it"),
        )),
        None => Err(Alarm::new(
            SEQUENCE_NUMBER,
            format!("sequence number N{n} not found (GOTO of {v})"),
        )),
    }
}

fn code(w: &Word) -> Option<Code> {
    Code::of(w.value)
}

impl<'p, M: Machine> Ctx<'p, M> {
    /// A context for one run.
    pub fn new(
        program: &'p Program,
        machine: &'p mut M,
        port: &'p mut dyn Port,
        commons: &'p mut [f64],
        options: RunOptions,
    ) -> Self {
        let l = options.limits;
        let max_steps = if l.max_steps == 0 {
            u64::MAX
        } else {
            l.max_steps
        };
        let gate = BlockGate::new(&l);
        Ctx {
            step_check: if gate.deadline().is_some() {
                CHECK_EVERY.min(max_steps)
            } else {
                max_steps
            },
            gate,
            program,
            machine,
            port,
            commons,
            options,
            max_steps,
            stats: Stats::default(),
            block: Block::new(),
            rest: Block::new(),
            record: Vec::with_capacity(128),
            pool: Vec::new(),
            modal: Vec::new(),
            port_open: false,
            level: 0,
            sub_depth: 0,
            error: None,
            panic: None,
        }
    }

    /// Records why the run stops; returns `Status::Error`.
    pub fn fail(&mut self, stop: impl Into<Stop>) -> Status {
        if self.error.is_none() {
            self.error = Some((stop.into(), None));
        }
        Status::Error
    }

    /// Counts a branch taken against the limits.
    #[inline(always)]
    pub fn step(&mut self) -> Status {
        self.stats.steps += 1;
        if self.stats.steps > self.step_check {
            return self.checkpoint();
        }
        Status::Next
    }

    /// Past `step_check`: the step limit, then the wall-time limit (looked at every `CHECK_EVERY`
    /// steps, so a runaway loop without output stops too).
    pub fn checkpoint(&mut self) -> Status {
        if self.stats.steps > self.max_steps {
            let limit = self.max_steps;
            return self.fail(Stop::Limit {
                kind: LimitKind::Steps,
                limit,
            });
        }
        if self.gate.deadline().is_some() {
            if let Some(stop) = self.gate.out_of_time() {
                return self.fail(stop);
            }
            self.step_check = self
                .stats
                .steps
                .saturating_add(CHECK_EVERY)
                .min(self.max_steps);
        }
        Status::Next
    }

    /// Fresh registers for function `fi`: vacant, with its constants.
    fn registers(&mut self, fi: usize) -> Vec<f64> {
        let g = &self.program.functions[fi];
        let mut r = self.pool.pop().unwrap_or_default();
        r.clear();
        r.resize(g.n_slots as usize, VACANT);
        for &(s, v) in &g.slot_consts {
            r[s as usize] = v;
        }
        r
    }

    /// Appends a word to the block being built (a vacant value drops the word, V6).
    #[inline(always)]
    pub fn word(&mut self, word: Word) {
        if !is_vacant(word.value) {
            self.block.push(word);
        }
    }

    /// `LiteralBlock`: adds the words packed at byte `at` of the function's literals to the block
    /// being built, then hands it over as `emit` does.
    pub fn literal_block<E: Engine<M>>(&mut self, engine: &E, fi: usize, at: u32) -> Status {
        let program = self.program;
        let f = &program.functions[fi];
        let Some(block) = fmsvm_ir::literal::block(&f.literals, at) else {
            panic!("fmsvm bug: no literal block at byte {at} of {}", f.name());
        };
        let info = block.info;
        for w in block {
            match w {
                Some(w) => self.word(w),
                None => panic!(
                    "fmsvm bug: literal block at byte {at} of {} is cut",
                    f.name()
                ),
            }
        }
        self.emit(engine, fi, info)
    }

    fn hand(&mut self, which_rest: bool, fi: usize, info: u32) -> Result<Flow, Status> {
        let f = &self.program.functions[fi];
        let info = f.infos[info as usize];
        let b = if which_rest {
            &mut self.rest
        } else {
            &mut self.block
        };
        b.line = info.line;
        b.file = info.file;
        b.column = info.column;
        b.block_delete = info.block_delete;
        b.comment = self.program.string(info.comment);
        // The gate's rule: a block counts once the machine has taken it.
        let r = self.gate.hand(
            &mut *self.machine,
            if which_rest { &self.rest } else { &self.block },
        );
        self.stats.blocks = self.gate.blocks;
        match r {
            Ok(Flow::End) => Err(Status::End),
            Ok(flow) => Ok(flow),
            Err(e) => Err(self.fail(e)),
        }
    }

    /// `EmitBlock`: hands the built block to the Machine; after a move block, a G66 of this level
    /// calls its macro (C12).
    pub fn emit<E: Engine<M>>(&mut self, engine: &E, fi: usize, info: u32) -> Status {
        // G66.1: the block does not run; its words are the arguments of a call (NCT 2000M/99M manual
        // 20: "the macro will be called in entering each block, treating the addresses of the
        // particular block as arguments"; Fanuc's each-block modal call).
        let level = self.level;
        if let Some(mc) = self
            .modal
            .iter()
            .rev()
            .find(|m| m.level == level && m.each_block)
        {
            let (callee, count) = (mc.func, mc.count);
            let mut args = [VACANT; LOCALS + 1];
            self.rest.clear();
            for w in self.block.words() {
                if !matches!(
                    w.letter,
                    Letter::G | Letter::L | Letter::N | Letter::O | Letter::P
                ) {
                    self.rest.push(*w);
                }
            }
            self.block.clear();
            if self.rest.is_empty() {
                return Status::Next;
            }
            if let Err(e) = calls::assign(self.rest.words(), &mut args[..], &*self.machine) {
                return self.fail(e);
            }
            return self.modal_call(engine, fi, callee, count, &args);
        }
        let flow = match self.hand(false, fi, info) {
            Ok(f) => f,
            Err(s) => return s,
        };
        self.block.clear();
        if flow == Flow::Moved {
            let level = self.level;
            if let Some(mc) = self.modal.iter().rev().find(|m| m.level == level) {
                let (callee, count, args) = (mc.func, mc.count, *mc.args);
                return self.modal_call(engine, fi, callee, count, &args[..]);
            }
        }
        Status::Next
    }

    /// `Call`: M98 / G65 / G66 / M97 with the words of the block being built.
    pub fn call<E: Engine<M>>(
        &mut self,
        engine: &E,
        fi: usize,
        regs: &mut [f64],
        kind: CallKind,
        info: u32,
    ) -> Status {
        let (mut p, mut l) = (None, None);
        self.rest.clear();
        let mut each_block = false;
        for w in self.block.words() {
            match w.letter {
                Letter::P if p.is_none() => p = Some(w.value),
                Letter::L if l.is_none() => l = Some(w.value),
                Letter::G if kind == CallKind::Modal && code(w) == Some(Code::G66_1) => {
                    each_block = true
                }
                Letter::G
                    if matches!(kind, CallKind::Macro | CallKind::Modal)
                        && matches!(code(w), Some(Code::G65 | Code::G66)) => {}
                Letter::M if kind == CallKind::Sub && code(w) == Some(Code::M98) => {}
                Letter::M if kind == CallKind::Local && code(w) == Some(Code::M97) => {}
                _ => {
                    self.rest.push(*w);
                }
            }
        }
        self.block.clear();
        let Some(p) = p.map(f64::round) else {
            return self.fail(Alarm::new(
                calls::PROGRAM_NOT_FOUND,
                "a call without P (the program to call)",
            ));
        };
        let l = l.map(f64::round);
        // The program number and the repeat count are never negative (alarm 0006, as for any word).
        for (letter, v) in [("P", Some(p)), ("L", l)] {
            if let Some(v) = v.filter(|v| *v < 0.0) {
                return self.fail(Alarm::new(
                    alarm::MINUS_SIGN,
                    format!("illegal use of minus sign: {letter}{v}"),
                ));
            }
        }
        let (number, count) = kind.target(p, l);
        if count > 9999 {
            return self.fail(Alarm::new(
                TOO_MANY_DIGITS,
                format!("too many digits: L{count} (at most 9999 repeats)"),
            ));
        }
        if matches!(kind, CallKind::Sub | CallKind::Local)
            && self.rest.words().iter().any(|w| w.letter != Letter::N)
        {
            // The block's own NC words run before the call.
            if let Err(s) = self.hand(true, fi, info) {
                return s;
            }
        }
        if count == 0 {
            return Status::Next;
        }
        match kind {
            CallKind::Local => {
                let Some(start) = label_pc(&self.program.functions[fi], number) else {
                    return self.fail(Alarm::new(
                        SEQUENCE_NUMBER,
                        format!("M97 P{number}: sequence number N{number} not found"),
                    ));
                };
                self.enter(
                    engine,
                    fi,
                    Some(regs),
                    fi,
                    CallKind::Local,
                    count,
                    start,
                    &[],
                )
            }
            _ => {
                let Some(callee) = self.program.find(number) else {
                    return self.fail(Alarm::new(
                        calls::PROGRAM_NOT_FOUND,
                        format!("program not found: O{number:04}"),
                    ));
                };
                if kind == CallKind::Sub {
                    let mut locals = [VACANT; LOCALS + 1];
                    locals.copy_from_slice(&regs[..=LOCALS]);
                    return self.enter(
                        engine,
                        fi,
                        Some(regs),
                        callee,
                        CallKind::Sub,
                        count,
                        0,
                        &locals,
                    );
                }
                let mut args = [VACANT; LOCALS + 1];
                if let Err(e) = calls::assign(self.rest.words(), &mut args[..], &*self.machine) {
                    return self.fail(e);
                }
                if kind == CallKind::Modal {
                    let level = self.level;
                    self.modal.push(ModalCall {
                        func: callee,
                        args: Box::new(args),
                        count,
                        level,
                        each_block,
                    });
                    if each_block {
                        // The G66.1 block itself calls the macro with its arguments (inferred
                        // from the each-block rule; docs/semantics.md).
                        return self.modal_call(engine, fi, callee, count, &args);
                    }
                    return Status::Next;
                }
                self.enter(engine, fi, None, callee, CallKind::Macro, count, 0, &args)
            }
        }
    }

    /// A G66/G66.1 modal macro's call: `callee` with the arguments it was set up with.
    fn modal_call<E: Engine<M>>(
        &mut self,
        engine: &E,
        fi: usize,
        callee: usize,
        count: u32,
        args: &[f64],
    ) -> Status {
        self.enter(engine, fi, None, callee, CallKind::Modal, count, 0, args)
    }

    /// Runs `callee` `count` times as a `kind` call. `locals` are the callee's #1–#33 (index 0 unused);
    /// `caller` is the caller's registers, which M98 shares and M97 reuses.
    #[allow(clippy::too_many_arguments)]
    fn enter<E: Engine<M>>(
        &mut self,
        engine: &E,
        caller_fi: usize,
        caller: Option<&mut [f64]>,
        callee: usize,
        kind: CallKind,
        count: u32,
        start: usize,
        locals: &[f64],
    ) -> Status {
        match kind {
            CallKind::Macro | CallKind::Modal => {
                if self.level >= MAX_MACRO_LEVELS {
                    return self.fail(Alarm::new(
                        calls::MACRO_NESTING,
                        "too many macro nesting: a fifth G65/G66 level",
                    ));
                }
                self.level += 1;
            }
            CallKind::Sub | CallKind::Local => {
                if self.sub_depth >= self.options.max_sub_depth.clamp(1, MAX_SUB_DEPTH) {
                    return self.fail(Alarm::new(
                        calls::SUB_NESTING,
                        "too many sub, macro nesting: a fifth nested subprogram",
                    ));
                }
                self.sub_depth += 1;
            }
        }
        let mut status = Status::Next;
        let mut runs_left = count;
        if kind == CallKind::Local {
            // M97 runs in the caller's own registers.
            if let Some(regs) = caller {
                status = self.repeat(engine, callee, regs, start, &mut runs_left);
            }
        } else {
            let mut regs = self.registers(callee);
            if !locals.is_empty() {
                regs[1..=LOCALS].copy_from_slice(&locals[1..=LOCALS]);
            }
            status = self.repeat(engine, callee, &mut regs, start, &mut runs_left);
            if kind == CallKind::Sub {
                // M98 shares the caller's locals (V12).
                if let Some(c) = caller {
                    c[1..=LOCALS].copy_from_slice(&regs[1..=LOCALS]);
                }
            }
            self.pool.push(regs);
        }
        match kind {
            CallKind::Macro | CallKind::Modal => self.level -= 1,
            CallKind::Sub | CallKind::Local => self.sub_depth -= 1,
        }
        match status {
            Status::Return(Some(n)) => match label_pc(&self.program.functions[caller_fi], n) {
                // M99 Pn: back to block Nn of the caller (C9).
                Some(_) => Status::Return(Some(n)),
                None => self.fail(Alarm::new(
                    SEQUENCE_NUMBER,
                    format!("M99 P{n}: sequence number N{n} not found in the caller"),
                )),
            },
            Status::Return(None) => Status::Next,
            s => s,
        }
    }

    /// Runs an activation `runs_left` times (L repeats start again with the locals the last run left,
    /// C10); returns how the last run ended.
    fn repeat<E: Engine<M>>(
        &mut self,
        engine: &E,
        fi: usize,
        regs: &mut [f64],
        start: usize,
        runs_left: &mut u32,
    ) -> Status {
        loop {
            let st = engine.exec(self, fi, regs, start);
            *runs_left -= 1;
            match st {
                Status::Return(None) | Status::Next if *runs_left > 0 => {
                    if self.step() == Status::Error {
                        return Status::Error;
                    }
                }
                Status::Next => return Status::Return(None),
                s => return s,
            }
        }
    }

    /// `Return` (M99 [P]): emits the block's other words, then ends the activation.
    pub fn ret(&mut self, fi: usize, info: u32) -> Status {
        let is_main = self.level == 0 && self.sub_depth == 0;
        let mut seq = None;
        self.rest.clear();
        for w in self.block.words() {
            match w.letter {
                Letter::P if seq.is_none() => seq = Some(w.value.round().max(0.0) as u32),
                Letter::M if code(w) == Some(Code::M99) => {}
                _ => {
                    self.rest.push(*w);
                }
            }
        }
        self.block.clear();
        if self.rest.words().iter().any(|w| w.letter != Letter::N)
            && let Err(s) = self.hand(true, fi, info)
        {
            return s;
        }
        if is_main && self.options.main_m99_ends && seq.is_none() {
            // Keep the M99 in the flat program: the control repeats it.
            self.rest.clear();
            self.rest.push(Word {
                letter: Letter::M,
                flags: Default::default(),
                value: 99.0,
            });
            if let Err(s) = self.hand(true, fi, info) {
                return s;
            }
            return Status::End;
        }
        Status::Return(seq)
    }

    /// `G67`.
    pub fn cancel_modal(&mut self) {
        self.modal.pop();
    }

    /// `Print`: one DPRNT/BPRNT record.
    pub fn print(&mut self, fi: usize, regs: &[f64], print: u32) -> Status {
        let pi = &self.program.functions[fi].prints[print as usize];
        if !self.port_open && !self.options.print_without_popen {
            let what = if pi.binary { "BPRNT" } else { "DPRNT" };
            return self.fail(Alarm::new(
                NO_FANUC_NUMBER,
                format!("{what} before POPEN: the port is not open"),
            ));
        }
        self.record.clear();
        for item in &pi.items {
            match *item {
                PrintItem::Text(t) => {
                    let text = self.program.string(t).as_bytes();
                    if pi.binary {
                        self.record.extend(text.iter().map(|&c| iso_parity(c)));
                    } else {
                        self.record.extend_from_slice(text);
                    }
                }
                PrintItem::Value { slot, whole, frac } => {
                    let v = regs[slot as usize];
                    if pi.binary {
                        bprnt_value(&mut self.record, v, frac);
                    } else {
                        dprnt_value(&mut self.record, v, whole, frac);
                    }
                }
            }
        }
        self.record.push(b'\n');
        match self.port.write(&self.record) {
            Ok(()) => Status::Next,
            Err(e) => self.fail(e),
        }
    }

    /// `POPEN` (`open`) and `PCLOS`.
    pub fn port(&mut self, open: bool) -> Status {
        let r = if open {
            self.port.open()
        } else {
            self.port.close()
        };
        match r {
            Ok(()) => {
                self.port_open = open;
                Status::Next
            }
            Err(e) => self.fail(e),
        }
    }

    /// `#3006 = v (message)`.
    pub fn message(&mut self, v: f64, message: u32) -> Status {
        let n = if is_vacant(v) {
            0
        } else {
            v.round().clamp(0.0, 9999.0) as u32
        };
        let text = self.program.string(message);
        let text = if text.trim().is_empty() {
            "(no message)"
        } else {
            text
        };
        match self.machine.message(n, text) {
            Ok(()) => Status::Next,
            Err(e) => self.fail(e),
        }
    }

    /// `#3000 = v (message)`: always stops.
    pub fn macro_alarm(&mut self, v: f64, message: u32) -> Status {
        let n = if is_vacant(v) { 0.0 } else { v.round() };
        if !(0.0..=999.0).contains(&n) {
            return self.fail(Alarm::new(
                VARIABLE_RANGE,
                format!("#3000 = {v}: a macro alarm number is 0 to 999"),
            ));
        }
        let text = self.program.string(message);
        // `#3000=5` without a comment: the control shows the number alone; say so.
        let text = if text.trim().is_empty() {
            "macro alarm (no message)".to_string()
        } else {
            text.to_string()
        };
        self.fail(Alarm::new(3000 + n as u32, text))
    }

    /// `#[addr]` read.
    pub fn load_indirect(&mut self, regs: &[f64], addr: f64) -> Result<f64, Status> {
        match indirect(addr, &self.program.commons) {
            Ok(VarClass::Vacant) => Ok(VACANT),
            Ok(VarClass::Local(n)) => Ok(regs[n as usize]),
            Ok(VarClass::Common(i)) => Ok(self.commons[i as usize]),
            Ok(VarClass::System(n)) => self.machine.read_system(n).map_err(|e| self.fail(e)),
            Err(e) => Err(self.fail(e)),
        }
    }

    /// `#[addr] = v`.
    pub fn store_indirect(&mut self, regs: &mut [f64], addr: f64, v: f64) -> Status {
        match indirect(addr, &self.program.commons) {
            Ok(VarClass::Vacant) => self.fail(Alarm::new(
                WRITE_PROTECTED,
                "#0 is always vacant and cannot be assigned (indirect #[…] gave 0)",
            )),
            Ok(VarClass::Local(n)) => {
                regs[n as usize] = v;
                Status::Next
            }
            Ok(VarClass::Common(i)) => {
                self.commons[i as usize] = v;
                Status::Next
            }
            Ok(VarClass::System(n)) => match self.machine.write_system(n, v) {
                Ok(()) => Status::Next,
                Err(e) => self.fail(e),
            },
            Err(e) => self.fail(e),
        }
    }

    /// Runs the main program to its end: M99 there restarts it (C9) unless `main_m99_ends`.
    pub fn run_main<E: Engine<M>>(&mut self, engine: &E) -> Status {
        let mut regs = self.registers(0);
        let mut pc = 0;
        loop {
            match engine.exec(self, 0, &mut regs, pc) {
                Status::Return(Some(n)) => match label_pc(&self.program.functions[0], n) {
                    Some(p) => {
                        if self.step() == Status::Error {
                            return Status::Error;
                        }
                        pc = p;
                    }
                    None => {
                        return self.fail(Alarm::new(
                            SEQUENCE_NUMBER,
                            format!("M99 P{n}: sequence number N{n} not found"),
                        ));
                    }
                },
                Status::Return(None) => {
                    // Locals are vacant again after M99 (V2); commons keep their values.
                    if self.step() == Status::Error {
                        return Status::Error;
                    }
                    regs[1..=LOCALS].fill(VACANT);
                    pc = 0;
                }
                Status::Next | Status::End => return Status::End,
                Status::Error => return Status::Error,
            }
        }
    }
}
