//! The IR verifier: checks every index and every structural rule the engines rely on, so that a
//! `Program` built by hand (or by a bug) is refused with a message instead of trusted by the JIT.
//!
//! The engines index registers, commons, constants, tables and blocks without checks (the JIT turns
//! a slot into a raw offset), so each rule here is one the interpreter or the JIT assumes:
//!
//! - at least one function; per function at least one op, fewer than `u32::MAX`, one span per op;
//! - `n_slots` > `LOCALS` (calls copy #1–#33, `#[n]` reads them); every slot an op, a print item or
//!   `slot_consts` names is below `n_slots`;
//! - constant slots are above the locals, given once, and never written; no op writes slot 0 (`#0`);
//! - constants (`consts`, `slot_consts`) are finite or vacant;
//! - common indices are below `COMMONS`; `consts`, `infos`, `prints`, `goto_tables` indices in range;
//!   string indices are in range or `u32::MAX` (none);
//! - `blocks` starts at 0 and is strictly increasing within the ops; every block ends with exactly one
//!   terminator and holds no other; a `Branch` has a next block to fall through to;
//! - jump, branch, GOTO-table and label targets are blocks; GOTO tables and labels are sorted by
//!   number without repeats (the engines binary-search them);
//! - `Func1` names a one-argument function, `Func2` ATAN2 or POW; DPRNT/BPRNT digits are 0–9.

use std::fmt;

use crate::{COMMONS, Func, Function, GotoDest, LOCALS, Op, PrintItem, Program, Slot, VACANT_SLOT};

/// Why a program was refused: where, and what is wrong.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct VerifyError {
    /// The function's index in `Program::functions`.
    pub function: usize,
    /// The op, when the problem is in one.
    pub pc: Option<usize>,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for VerifyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "invalid IR in function {}", self.function)?;
        if let Some(pc) = self.pc {
            write!(f, " at op {pc}")?;
        }
        write!(f, ": {}", self.message)
    }
}

impl std::error::Error for VerifyError {}

/// Checks `program` against every rule of the module doc.
pub fn verify(program: &Program) -> Result<(), VerifyError> {
    if program.functions.is_empty() {
        return Err(VerifyError {
            function: 0,
            pc: None,
            message: "the program has no function (the main program is function 0)".into(),
        });
    }
    for (fi, f) in program.functions.iter().enumerate() {
        let v = Verifier {
            program,
            f,
            fi,
            is_const: const_map(f),
        };
        v.function()?;
    }
    Ok(())
}

/// Which slots are constant slots (for the "never written" rule); slots out of range are left out
/// (the function check reports them).
fn const_map(f: &Function) -> Vec<bool> {
    let mut m = vec![false; f.n_slots as usize];
    for &(s, _) in &f.slot_consts {
        if let Some(c) = m.get_mut(s as usize) {
            *c = true;
        }
    }
    m
}

struct Verifier<'a> {
    program: &'a Program,
    f: &'a Function,
    fi: usize,
    is_const: Vec<bool>,
}

type Check = Result<(), String>;

fn finite_or_vacant(v: f64) -> bool {
    v.is_finite() || v.is_nan()
}

impl Verifier<'_> {
    fn error(&self, pc: Option<usize>, message: String) -> VerifyError {
        VerifyError {
            function: self.fi,
            pc,
            message,
        }
    }

    fn function(&self) -> Result<(), VerifyError> {
        self.sizes().map_err(|m| self.error(None, m))?;
        self.structure()?;
        self.tables().map_err(|m| self.error(None, m))?;
        for (pc, op) in self.f.ops.iter().enumerate() {
            self.op(op)
                .map_err(|m| self.error(Some(pc), format!("{op:?}: {m}")))?;
        }
        Ok(())
    }

    /// The sizes: slots, ops, spans.
    fn sizes(&self) -> Check {
        let f = self.f;
        if (f.n_slots as usize) <= LOCALS {
            return Err(format!(
                "{} slots: a function needs at least {} (#0 and the locals #1-#{LOCALS})",
                f.n_slots,
                LOCALS + 1
            ));
        }
        if f.ops.is_empty() {
            return Err("the function has no ops".into());
        }
        if f.ops.len() >= u32::MAX as usize {
            return Err(format!("{} ops: more than a u32 can number", f.ops.len()));
        }
        if f.spans.len() != f.ops.len() {
            return Err(format!(
                "{} spans for {} ops (one span per op)",
                f.spans.len(),
                f.ops.len()
            ));
        }
        Ok(())
    }

    /// Everything that is not an op: constants, tables, labels, infos, prints.
    fn tables(&self) -> Check {
        let f = self.f;
        self.string(f.title).map_err(|m| format!("title: {m}"))?;
        let mut seen = vec![false; f.n_slots as usize];
        for &(s, v) in &f.slot_consts {
            self.slot(s).map_err(|m| format!("constant slot: {m}"))?;
            if (s as usize) <= LOCALS {
                return Err(format!(
                    "constant slot {s} is #0 or a local (#1-#{LOCALS}); constants come after them"
                ));
            }
            if std::mem::replace(&mut seen[s as usize], true) {
                return Err(format!("constant slot {s} is given twice"));
            }
            if !finite_or_vacant(v) {
                return Err(format!("constant slot {s} holds {v}, not a finite value"));
            }
        }
        if let Some(v) = f.consts.iter().find(|v| !finite_or_vacant(**v)) {
            return Err(format!("constant pool holds {v}, not a finite value"));
        }
        for (i, info) in f.infos.iter().enumerate() {
            self.string(info.comment)
                .map_err(|m| format!("block info {i} comment: {m}"))?;
        }
        for (i, p) in f.prints.iter().enumerate() {
            for item in &p.items {
                let check = match *item {
                    PrintItem::Text(t) => self.string(t),
                    PrintItem::Value { whole, frac, .. } if whole > 9 || frac > 9 => {
                        Err(format!("format [{whole} {frac}]: digits are 0 to 9"))
                    }
                    PrintItem::Value { slot, .. } => self.slot(slot),
                };
                check.map_err(|m| format!("print {i}: {m}"))?;
            }
        }
        for (i, t) in f.goto_tables.iter().enumerate() {
            if let Some(w) = t.entries.windows(2).find(|w| w[0].0 >= w[1].0) {
                return Err(format!(
                    "GOTO table {i}: N{} then N{}, not sorted without repeats",
                    w[0].0, w[1].0
                ));
            }
            for &(n, d) in &t.entries {
                if let GotoDest::Block(b) = d {
                    self.block(b)
                        .map_err(|m| format!("GOTO table {i}, N{n}: {m}"))?;
                }
            }
        }
        if let Some(w) = f.labels.windows(2).find(|w| w[0].0 >= w[1].0) {
            return Err(format!(
                "labels: N{} then N{}, not sorted without repeats",
                w[0].0, w[1].0
            ));
        }
        for &(n, b) in &f.labels {
            self.block(b).map_err(|m| format!("label N{n}: {m}"))?;
        }
        Ok(())
    }

    /// Blocks: where they start, and that each ends with its one terminator.
    fn structure(&self) -> Result<(), VerifyError> {
        let f = self.f;
        if f.blocks.first() != Some(&0) {
            return Err(self.error(
                None,
                format!(
                    "the first block starts at {:?}, not at op 0",
                    f.blocks.first()
                ),
            ));
        }
        for (bi, w) in f.blocks.windows(2).enumerate() {
            if w[0] >= w[1] {
                return Err(self.error(
                    None,
                    format!(
                        "block {} starts at op {}, not after block {bi} (at op {})",
                        bi + 1,
                        w[1],
                        w[0]
                    ),
                ));
            }
        }
        let last = f.blocks[f.blocks.len() - 1] as usize;
        if last >= f.ops.len() {
            return Err(self.error(
                None,
                format!(
                    "block {} starts at op {last}, past the {} ops",
                    f.blocks.len() - 1,
                    f.ops.len()
                ),
            ));
        }
        for bi in 0..f.blocks.len() {
            let start = f.blocks[bi] as usize;
            let end = f.blocks.get(bi + 1).map_or(f.ops.len(), |&e| e as usize);
            for (pc, op) in f.ops.iter().enumerate().take(end).skip(start) {
                let is_last = pc + 1 == end;
                if op.is_terminator() != is_last {
                    let m = if is_last {
                        format!("block {bi} does not end with a terminator ({op:?})")
                    } else {
                        format!("{op:?} ends block {bi} before its end (op {end})")
                    };
                    return Err(self.error(Some(pc), m));
                }
                if matches!(op, Op::Branch { .. }) && bi + 1 >= f.blocks.len() {
                    return Err(self.error(
                        Some(pc),
                        format!("{op:?} in the last block has no next block to fall through to"),
                    ));
                }
            }
        }
        Ok(())
    }

    fn slot(&self, s: Slot) -> Check {
        if (s as usize) < self.f.n_slots as usize {
            Ok(())
        } else {
            Err(format!(
                "slot {s} out of range (the function has {} slots)",
                self.f.n_slots
            ))
        }
    }

    /// A slot an op writes: in range, not `#0`, not a constant.
    fn dst(&self, s: Slot) -> Check {
        self.slot(s)?;
        if s == VACANT_SLOT {
            return Err("writes slot 0 (#0 is always vacant)".into());
        }
        if self.is_const[s as usize] {
            return Err(format!("writes constant slot {s}"));
        }
        Ok(())
    }

    fn block(&self, b: u32) -> Check {
        if (b as usize) < self.f.blocks.len() {
            Ok(())
        } else {
            Err(format!(
                "block {b} out of range (the function has {} blocks)",
                self.f.blocks.len()
            ))
        }
    }

    fn string(&self, i: u32) -> Check {
        if i == u32::MAX || (i as usize) < self.program.strings.len() {
            Ok(())
        } else {
            Err(format!(
                "string {i} out of range (the program has {} strings)",
                self.program.strings.len()
            ))
        }
    }

    fn index(what: &str, i: u32, len: usize) -> Check {
        if (i as usize) < len {
            Ok(())
        } else {
            Err(format!("{what} {i} out of range (there are {len})"))
        }
    }

    fn konst(&self, k: u32) -> Check {
        Self::index("constant", k, self.f.consts.len())
    }

    fn info(&self, i: u32) -> Check {
        Self::index("block info", i, self.f.infos.len())
    }

    fn op(&self, op: &Op) -> Check {
        match *op {
            Op::Const { dst, k } => {
                self.dst(dst)?;
                self.konst(k)
            }
            Op::Copy { dst, src } | Op::Neg { dst, src } | Op::RoundAddr { dst, src, .. } => {
                self.dst(dst)?;
                self.slot(src)
            }
            Op::Bin { dst, a, b, .. } | Op::Cmp { dst, a, b, .. } => {
                self.dst(dst)?;
                self.slot(a)?;
                self.slot(b)
            }
            Op::Func1 { f, dst, a } => {
                if matches!(f, Func::Atan2 | Func::Pow) {
                    return Err(format!("{} takes two arguments", f.name()));
                }
                self.dst(dst)?;
                self.slot(a)
            }
            Op::Func2 { f, dst, a, b } => {
                if !matches!(f, Func::Atan2 | Func::Pow) {
                    return Err(format!("{} takes one argument", f.name()));
                }
                self.dst(dst)?;
                self.slot(a)?;
                self.slot(b)
            }
            Op::LoadCommon { dst, index } => {
                self.dst(dst)?;
                Self::index("common", index as u32, COMMONS)
            }
            Op::StoreCommon { index, src } => {
                Self::index("common", index as u32, COMMONS)?;
                self.slot(src)
            }
            Op::LoadSystem { dst, .. } => self.dst(dst),
            Op::StoreSystem { src, .. } => self.slot(src),
            Op::LoadIndirect { dst, addr } => {
                self.dst(dst)?;
                self.slot(addr)
            }
            Op::StoreIndirect { addr, src } => {
                self.slot(addr)?;
                self.slot(src)
            }
            Op::Word { src, .. } => self.slot(src),
            Op::WordConst { k, .. } => self.konst(k),
            Op::EmitBlock { info } | Op::Call { info, .. } | Op::Return { info } => self.info(info),
            Op::LiteralBlock { at } => {
                let bad = || format!("literal block at byte {at} is not well formed");
                let b = crate::literal::block(&self.f.literals, at).ok_or_else(bad)?;
                self.info(b.info)?;
                let mut n = 0;
                for w in b {
                    w.ok_or_else(bad)?;
                    n += 1;
                }
                if n > fmsvm_block::MAX_WORDS {
                    return Err(format!("literal block at byte {at} has {n} words"));
                }
                Ok(())
            }
            Op::MacroAlarm { src, message } | Op::Message { src, message } => {
                self.slot(src)?;
                self.string(message)
            }
            Op::Print { print } => Self::index("print", print, self.f.prints.len()),
            Op::CancelModal | Op::Popen | Op::Pclos | Op::End => Ok(()),
            Op::Jump { target } => self.block(target),
            Op::Branch { cond, target, .. } => {
                self.slot(cond)?;
                self.block(target)
            }
            Op::Goto { src, table } => {
                self.slot(src)?;
                Self::index("GOTO table", table, self.f.goto_tables.len())
            }
            Op::Alarm { message, .. } => self.string(message),
        }
    }
}

#[cfg(test)]
mod tests;
