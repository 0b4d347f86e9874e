//! fmsvm-ir: the bytecode IR and its verifier, the one front-end crate the VM depends on.
//!
//! The fmsvm bytecode IR: per program (O number) a [`Function`] of basic blocks over numbered `f64`
//! slots; `Display` prints it (`fmsvm ir`).
//!
//! Shape, chosen to translate 1:1 into Cranelift IR:
//! - A function's **slots** are its registers: slot 0 is `#0` (always vacant), slots 1–33 are the locals
//!   `#1`–`#33` of the current local level, then constant slots (filled when the function starts, never
//!   written), then temporaries. Common variables (#100–#999, as the control's ranges allow) are one global array reached by
//!   `LoadCommon`/`StoreCommon` with a direct index; system variables (#1000 and up) go to the Machine.
//! - **Vacant** is NaN (see `fmsvm_block::VACANT`): the engines keep every non-vacant value finite.
//! - Ops are a fixed 8-byte `Copy` enum. Each basic block is a run of ops ending in exactly one
//!   terminator (`Jump`, `Branch`, `Goto`, `Alarm`, `End`); `Branch` falls through to the next block in
//!   layout order when its condition does not hold.
//! - NC blocks are built by `Word`/`WordConst` ops (vacant words are dropped, macro-b-rules V6) and handed
//!   to the Machine by `EmitBlock`; a block of literal words only is one `LiteralBlock` op, its words
//!   packed in a byte stream ([`literal`]).
//! - Spans live in a side table parallel to the ops, read only to report an alarm.
#![deny(missing_docs)]
#![forbid(unsafe_code)]

use std::fmt;

use fmsvm_block::{Letter, WordFlags};

pub mod literal;
mod ops;
pub mod span;
pub mod verify;
pub use ops::{BinOp, CmpOp, Func};

/// Where an op came from (the span table), for reporting an alarm.
pub use crate::span::{FileId, SourceMap, Span};

/// Fanuc alarm numbers the compiler and VM use (macro-b-rules A1, A2).
pub mod alarm {
    /// 0003 TOO MANY DIGIT.
    pub const TOO_MANY_DIGITS: u32 = 3;
    /// 0006 ILLEGAL USE OF MINUS SIGN.
    pub const MINUS_SIGN: u32 = 6;
    /// 0007 ILLEGAL USE OF DECIMAL POINT.
    pub const DECIMAL_POINT: u32 = 7;
    /// 0110 OVERFLOW: INTEGER.
    pub const INTEGER_OVERFLOW: u32 = 110;
    /// 0111 OVERFLOW: FLOATING.
    pub const FLOAT_OVERFLOW: u32 = 111;
    /// 0112 ZERO DIVIDE.
    pub const ZERO_DIVIDE: u32 = 112;
    /// 0114 ILLEGAL EXPRESSION FORMAT (format error in macro).
    pub const FORMAT: u32 = 114;
    /// 0115 VARIABLE NO. OUT OF RANGE.
    pub const VARIABLE_RANGE: u32 = 115;
    /// 0116 WRITE PROTECTED VARIABLE.
    pub const WRITE_PROTECTED: u32 = 116;
    /// 0118 TOO MANY BRACKET NESTING.
    pub const BRACKET_NESTING: u32 = 118;
    /// 0119 ARGUMENT VALUE OUT OF RANGE.
    pub const ARGUMENT_RANGE: u32 = 119;
    /// 0124 MISSING END STATEMENT.
    pub const MISSING_END: u32 = 124;
    /// 0125 MACRO STATEMENT FORMAT ERROR.
    pub const STATEMENT_FORMAT: u32 = 125;
    /// 0126 ILLEGAL LOOP NUMBER.
    pub const LOOP_NUMBER: u32 = 126;
    /// 0127 DUPLICATE NC, MACRO STATEMENT.
    pub const NC_AND_MACRO: u32 = 127;
    /// 0128 ILLEGAL MACRO SEQUENCE NUMBER (GOTO target not found).
    pub const SEQUENCE_NUMBER: u32 = 128;
}

/// A slot (register) number within a function.
pub type Slot = u16;
/// A basic block number within a function.
pub type BlockId = u32;

/// Slot of `#0`.
pub const VACANT_SLOT: Slot = 0;
/// Number of local variables (#1–#33), in slots 1..=33.
pub const LOCALS: usize = 33;
/// Number of common-variable places: every number #100–#999 has one; which of them a control has is
/// its [`CommonRanges`].
pub const COMMONS: usize = 900;

/// The index of common variable `#n` in the common array, if `n` can be one (#100–#999).
pub fn common_index(n: u32) -> Option<u16> {
    match n {
        100..=999 => Some((n - 100) as u16),
        _ => None,
    }
}

/// The variable number of common index `i`.
pub fn common_number(i: u16) -> u32 {
    100 + i as u32
}

/// The common variables a control has (macro-b-rules V4, S6): a volatile range, vacant at the start of
/// every run, and a retained range, kept between runs (`--vars`, `--dump-vars`). Both inclusive,
/// inside #100–#999, not overlapping; None: the control has none of that kind. Fanuc: #100–#199
/// and #500–#999 (the default); NCT 99M: #500–#599 retained; Yaskawa LX3: #100–#149 and #500–#549.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CommonRanges {
    /// The volatile commons (#100–#199).
    pub volatile: Option<(u32, u32)>,
    /// The retained commons (#500–#999).
    pub retained: Option<(u32, u32)>,
}

impl Default for CommonRanges {
    fn default() -> Self {
        CommonRanges {
            volatile: Some((100, 199)),
            retained: Some((500, 999)),
        }
    }
}

impl CommonRanges {
    /// Whether `#n` is a volatile common.
    pub fn is_volatile(&self, n: u32) -> bool {
        self.volatile.is_some_and(|(a, b)| (a..=b).contains(&n))
    }

    /// Whether `#n` is a retained common.
    pub fn is_retained(&self, n: u32) -> bool {
        self.retained.is_some_and(|(a, b)| (a..=b).contains(&n))
    }

    /// Whether `#n` is a common variable of this control.
    pub fn contains(&self, n: u32) -> bool {
        self.is_volatile(n) || self.is_retained(n)
    }

    /// The ranges in words: `#100–#199 and #500–#999`.
    pub fn describe(&self) -> String {
        let range = |r: Option<(u32, u32)>| r.map(|(a, b)| format!("#{a}–#{b}"));
        match (range(self.volatile), range(self.retained)) {
            (Some(v), Some(r)) => format!("{v} and {r}"),
            (Some(x), None) | (None, Some(x)) => x,
            (None, None) => "none".to_string(),
        }
    }

    /// Checks the ranges: inside #100–#999, first ≤ last, not overlapping.
    pub fn check(&self) -> Result<(), String> {
        for (name, r) in [("volatile", self.volatile), ("retained", self.retained)] {
            if let Some((a, b)) = r
                && (!(100..=999).contains(&a) || !(100..=999).contains(&b) || a > b)
            {
                return Err(format!(
                    "the {name} commons #{a}–#{b} are not a range inside #100–#999"
                ));
            }
        }
        if let (Some((a, b)), Some((c, d))) = (self.volatile, self.retained)
            && a <= d
            && c <= b
        {
            return Err(format!(
                "the volatile commons #{a}–#{b} and the retained #{c}–#{d} overlap"
            ));
        }
        Ok(())
    }

    /// What `#n` refers to for this control: as [`classify`], but a common outside the ranges is none.
    pub fn classify(&self, n: u32) -> Option<VarClass> {
        match classify(n) {
            Some(VarClass::Common(_)) if !self.contains(n) => None,
            c => c,
        }
    }
}

/// What a variable number refers to (macro-b-rules V1–V4, S6).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum VarClass {
    /// `#0`, always vacant.
    Vacant,
    /// `#1`–`#33`.
    Local(u16),
    /// `#100`–`#999` (those of the control's [`CommonRanges`]): index into the common array.
    Common(u16),
    /// `#1000` and up: answered by the Machine.
    System(u32),
}

/// Classifies a variable number, or None when no variable has that number.
pub fn classify(n: u32) -> Option<VarClass> {
    match n {
        0 => Some(VarClass::Vacant),
        1..=33 => Some(VarClass::Local(n as u16)),
        1000..=99_999_999 => Some(VarClass::System(n)),
        _ => common_index(n).map(VarClass::Common),
    }
}

/// What kind of call a `Call` op makes.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum CallKind {
    /// `M98 P… L…`: subprogram; shares the caller's locals (V12).
    Sub,
    /// `G65 P… L… args`: macro call; a new local level with the arguments (C2–C4, C10).
    Macro,
    /// `G66 P… L… args`: registers a modal macro call made after each move block (C12).
    Modal,
    /// `M97 P…`: Haas local subprogram: the sequence number P in the same program.
    Local,
}

impl CallKind {
    /// Every kind, in declaration order.
    pub const ALL: [CallKind; 4] = [
        CallKind::Sub,
        CallKind::Macro,
        CallKind::Modal,
        CallKind::Local,
    ];

    /// The program (or, for M97, the sequence number) a call names and how many times it runs, from
    /// its P and L values — the one definition the library lookup and both engines use. P and L are
    /// integer addresses: rounded half away from zero (V10), so `G65 P9010.6` calls O9011. An M98
    /// without L whose P has more than four digits carries the count in the digits left of the last
    /// four (C8: `M98 P51000` runs O1000 five times). The caller has refused negative values (0006).
    pub fn target(self, p: f64, l: Option<f64>) -> (u32, u32) {
        let p = p.round().max(0.0);
        match (self, l) {
            (CallKind::Sub, None) if p > 9999.0 => {
                ((p % 10_000.0) as u32, (p / 10_000.0).trunc() as u32)
            }
            _ => (p as u32, l.map_or(1.0, f64::round).max(0.0) as u32),
        }
    }
}

/// One piece of a DPRNT/BPRNT record.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum PrintItem {
    /// Literal text (`Program::strings` index).
    Text(u32),
    /// A value: DPRNT `[whole frac]`, BPRNT `[frac]`.
    Value {
        /// Where the value is.
        slot: Slot,
        /// Whole digits.
        whole: u8,
        /// Fraction digits (BPRNT: the scale exponent).
        frac: u8,
    },
}

/// A DPRNT (`binary` false) or BPRNT record.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PrintInfo {
    /// BPRNT.
    pub binary: bool,
    /// Its pieces in order.
    pub items: Vec<PrintItem>,
}

/// One instruction.
#[allow(missing_docs)]
#[derive(Clone, Copy, PartialEq, Debug)]
pub enum Op {
    /// `dst = consts[k]`.
    Const { dst: Slot, k: u32 },
    /// `dst = src`, vacancy kept (V5: `#2=#1` with #1 vacant leaves #2 vacant).
    Copy { dst: Slot, src: Slot },
    /// `dst = -src`; a vacant operand stays vacant (the sign of an address word, E8).
    Neg { dst: Slot, src: Slot },
    /// Arithmetic or logic; vacant operands act as 0 (V5).
    Bin {
        op: BinOp,
        dst: Slot,
        a: Slot,
        b: Slot,
    },
    /// Comparison, 1.0 or 0.0 (V7 for vacant operands).
    Cmp {
        op: CmpOp,
        dst: Slot,
        a: Slot,
        b: Slot,
    },
    /// One-argument function.
    Func1 { f: Func, dst: Slot, a: Slot },
    /// Two-argument function (ATAN2, POW).
    Func2 {
        f: Func,
        dst: Slot,
        a: Slot,
        b: Slot,
    },
    /// `ROUND` inside an address: round to that address's least increment (E3).
    RoundAddr {
        letter: Letter,
        dst: Slot,
        src: Slot,
    },
    /// `dst = commons[index]`.
    LoadCommon { dst: Slot, index: u16 },
    /// `commons[index] = src`.
    StoreCommon { index: u16, src: Slot },
    /// `dst = #number` from the Machine.
    LoadSystem { dst: Slot, number: u32 },
    /// `#number = src` to the Machine.
    StoreSystem { number: u32, src: Slot },
    /// `dst = #[addr]`.
    LoadIndirect { dst: Slot, addr: Slot },
    /// `#[addr] = src`.
    StoreIndirect { addr: Slot, src: Slot },
    /// Appends word `letter src` to the block being built, unless `src` is vacant.
    Word {
        letter: Letter,
        flags: WordFlags,
        src: Slot,
    },
    /// Appends word `letter consts[k]`.
    WordConst {
        letter: Letter,
        flags: WordFlags,
        k: u32,
    },
    /// Hands the block being built to the Machine (`infos[info]` says where it is from), then clears it.
    EmitBlock { info: u32 },
    /// Adds the literal words packed at byte `at` of `literals` to the block being built and hands it
    /// to the Machine as `EmitBlock` does (the packed block holds its info index; [`literal`]).
    LiteralBlock { at: u32 },
    /// `#3000 = src (message)`: macro alarm 3000 + src with `strings[message]`.
    MacroAlarm { src: Slot, message: u32 },
    /// `#3006 = src (message)`: message stop.
    Message { src: Slot, message: u32 },
    /// A call; its words (P, L, arguments) are in the block being built. Execution goes on after it.
    Call { kind: CallKind, info: u32 },
    /// `M99 [P…]`: return (or restart, in the main program); other words of the block are emitted first.
    Return { info: u32 },
    /// `G67`: cancel the most recent G66.
    CancelModal,
    /// `DPRNT`/`BPRNT` with `prints[print]`.
    Print { print: u32 },
    /// `POPEN`.
    Popen,
    /// `PCLOS`.
    Pclos,
    /// Terminator: go to `target`.
    Jump { target: BlockId },
    /// Terminator: go to `target` if `(cond != 0) == when`, else to the next block.
    Branch {
        cond: Slot,
        when: bool,
        target: BlockId,
    },
    /// Terminator: computed `GOTO src` through `goto_tables[table]`.
    Goto { src: Slot, table: u32 },
    /// Terminator: raise alarm `number` with `strings[message]`.
    Alarm { number: u16, message: u32 },
    /// Terminator: end of the program.
    End,
}

const _: () = assert!(std::mem::size_of::<Op>() == 8);

impl Op {
    /// True for the ops that end a basic block.
    pub fn is_terminator(&self) -> bool {
        matches!(
            self,
            Op::Jump { .. } | Op::Branch { .. } | Op::Goto { .. } | Op::Alarm { .. } | Op::End
        )
    }

    /// Rewrites every slot the op reads or writes through `f` (the lowerer renumbers temporaries
    /// once it knows how many constant slots a function has).
    pub fn map_slots(&mut self, f: impl Fn(Slot) -> Slot) {
        match self {
            Op::Const { dst, .. } | Op::LoadCommon { dst, .. } | Op::LoadSystem { dst, .. } => {
                *dst = f(*dst)
            }
            Op::Copy { dst, src } | Op::Neg { dst, src } | Op::RoundAddr { dst, src, .. } => {
                *dst = f(*dst);
                *src = f(*src);
            }
            Op::Bin { dst, a, b, .. } | Op::Cmp { dst, a, b, .. } | Op::Func2 { dst, a, b, .. } => {
                *dst = f(*dst);
                *a = f(*a);
                *b = f(*b);
            }
            Op::Func1 { dst, a, .. } => {
                *dst = f(*dst);
                *a = f(*a);
            }
            Op::LoadIndirect { dst, addr } => {
                *dst = f(*dst);
                *addr = f(*addr);
            }
            Op::StoreIndirect { addr, src } => {
                *addr = f(*addr);
                *src = f(*src);
            }
            Op::StoreCommon { src, .. }
            | Op::StoreSystem { src, .. }
            | Op::Word { src, .. }
            | Op::MacroAlarm { src, .. }
            | Op::Message { src, .. }
            | Op::Goto { src, .. } => *src = f(*src),
            Op::Branch { cond, .. } => *cond = f(*cond),
            Op::WordConst { .. }
            | Op::EmitBlock { .. }
            | Op::LiteralBlock { .. }
            | Op::Call { .. }
            | Op::Return { .. }
            | Op::CancelModal
            | Op::Print { .. }
            | Op::Popen
            | Op::Pclos
            | Op::Jump { .. }
            | Op::Alarm { .. }
            | Op::End => {}
        }
    }
}

/// Where one `EmitBlock` comes from.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct BlockInfo {
    /// The source file (its id in the compile's source map).
    pub file: u16,
    /// 1-based source line.
    pub line: u32,
    /// 1-based column (in characters) of the block's first word.
    pub column: u16,
    /// The block starts with `/`.
    pub block_delete: bool,
    /// Index into `Program::strings` of the block's comment text, or `u32::MAX`.
    pub comment: u32,
}

/// Where a computed GOTO may land.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum GotoDest {
    /// The basic block that starts at the labelled line.
    Block(BlockId),
    /// The label is inside a DO range that does not contain the GOTO (an alarm when taken, L3).
    IntoLoop,
}

/// The sequence numbers one computed `GOTO` can reach, sorted by number.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GotoTable {
    /// `(N number, destination)`, sorted, first occurrence of each number.
    pub entries: Vec<(u32, GotoDest)>,
}

impl GotoTable {
    /// The destination of `GOTO n`, if label `n` exists.
    pub fn find(&self, n: u32) -> Option<GotoDest> {
        self.entries
            .binary_search_by_key(&n, |e| e.0)
            .ok()
            .map(|i| self.entries[i].1)
    }
}

/// One program (O number) compiled.
#[derive(Clone, Debug, Default)]
pub struct Function {
    /// The O number (None for a file without one).
    pub number: Option<u32>,
    /// Index into `Program::strings` of the program's title comment, or `u32::MAX`.
    pub title: u32,
    /// Slots the function needs.
    pub n_slots: u16,
    /// Constant slots and their values, set when the function starts.
    pub slot_consts: Vec<(Slot, f64)>,
    /// Constant pool of `Const` and `WordConst`.
    pub consts: Vec<f64>,
    /// The ops of all basic blocks, in layout order.
    pub ops: Vec<Op>,
    /// The source span of each op.
    pub spans: crate::span::OpSpans,
    /// The first op of each basic block.
    pub blocks: Vec<u32>,
    /// Tables of computed GOTOs.
    pub goto_tables: Vec<GotoTable>,
    /// The words of `LiteralBlock`s, packed ([`literal`]).
    pub literals: Vec<u8>,
    /// Source information of `EmitBlock`s.
    pub infos: Vec<BlockInfo>,
    /// Sequence numbers and the blocks they begin (for `M99 P`), sorted; empty unless needed.
    pub labels: Vec<(u32, BlockId)>,
    /// DPRNT/BPRNT records.
    pub prints: Vec<PrintInfo>,
}

impl Function {
    /// The ops of basic block `b`.
    pub fn block_ops(&self, b: BlockId) -> &[Op] {
        let start = self.blocks[b as usize] as usize;
        let end = self
            .blocks
            .get(b as usize + 1)
            .map_or(self.ops.len(), |&e| e as usize);
        &self.ops[start..end]
    }

    /// The name as written: `O1234`, or `(main)`.
    pub fn name(&self) -> String {
        match self.number {
            Some(n) => format!("O{n:04}"),
            None => "(main)".to_string(),
        }
    }
}

/// A compiled file: the main program first, then the other programs it holds.
#[derive(Clone, Debug, Default)]
pub struct Program {
    /// The programs; `functions[0]` is the main program.
    pub functions: Vec<Function>,
    /// Comments and messages.
    pub strings: Vec<String>,
    /// The common variables the control has (an indirect `#[…]` outside them is alarm 0115).
    pub commons: CommonRanges,
}

impl Program {
    /// Checks every index and structural rule the engines rely on (see [`crate::verify`]).
    pub fn verify(&self) -> Result<(), crate::verify::VerifyError> {
        crate::verify::verify(self)
    }

    /// True when the program may read or write system variable `n` (directly, or through `#[…]`).
    pub fn may_access(&self, numbers: &[u32]) -> bool {
        self.functions
            .iter()
            .flat_map(|f| f.ops.iter())
            .any(|op| match *op {
                Op::LoadSystem { number, .. } | Op::StoreSystem { number, .. } => {
                    numbers.contains(&number)
                }
                Op::LoadIndirect { .. } | Op::StoreIndirect { .. } => true,
                _ => false,
            })
    }

    /// Whether the program may write printed output (DPRNT, BPRNT, POPEN, PCLOS).
    pub fn may_print(&self) -> bool {
        self.functions
            .iter()
            .flat_map(|f| f.ops.iter())
            .any(|op| matches!(op, Op::Print { .. } | Op::Popen | Op::Pclos))
    }

    /// The function of program number `number`.
    pub fn find(&self, number: u32) -> Option<usize> {
        self.functions.iter().position(|f| f.number == Some(number))
    }

    /// The string with index `i`, or "" for `u32::MAX`.
    pub fn string(&self, i: u32) -> &str {
        self.strings.get(i as usize).map_or("", |s| s.as_str())
    }
}

fn slot_name(f: &Function, s: Slot) -> String {
    if s == VACANT_SLOT {
        "#0".to_string()
    } else if (s as usize) <= LOCALS {
        format!("#{s}")
    } else if let Some((_, v)) = f.slot_consts.iter().find(|(c, _)| *c == s) {
        format!("{v:?}")
    } else {
        format!("t{s}")
    }
}

fn flags(fl: WordFlags) -> &'static str {
    if fl.has(WordFlags::NO_POINT) {
        " (no point)"
    } else {
        ""
    }
}

impl fmt::Display for Program {
    fn fmt(&self, out: &mut fmt::Formatter<'_>) -> fmt::Result {
        for f in &self.functions {
            writeln!(
                out,
                "function {} slots={} consts={}",
                f.name(),
                f.n_slots,
                f.slot_consts.len()
            )?;
            for b in 0..f.blocks.len() as BlockId {
                writeln!(out, "  b{b}:")?;
                let start = f.blocks[b as usize];
                for (i, op) in f.block_ops(b).iter().enumerate() {
                    let s = |x: Slot| slot_name(f, x);
                    let pc = start as usize + i;
                    write!(out, "    {pc:5}  ")?;
                    match *op {
                        Op::Const { dst, k } => {
                            write!(out, "{} = {:?}", s(dst), f.consts[k as usize])
                        }
                        Op::Copy { dst, src } => write!(out, "{} = {}", s(dst), s(src)),
                        Op::Neg { dst, src } => write!(out, "{} = -{}", s(dst), s(src)),
                        Op::Bin { op, dst, a, b } => {
                            write!(out, "{} = {} {:?} {}", s(dst), s(a), op, s(b))
                        }
                        Op::Cmp { op, dst, a, b } => {
                            write!(out, "{} = {} {:?} {}", s(dst), s(a), op, s(b))
                        }
                        Op::Func1 { f: fu, dst, a } => {
                            write!(out, "{} = {}[{}]", s(dst), fu.name(), s(a))
                        }
                        Op::Func2 { f: fu, dst, a, b } => {
                            write!(out, "{} = {}[{}, {}]", s(dst), fu.name(), s(a), s(b))
                        }
                        Op::RoundAddr { letter, dst, src } => {
                            write!(out, "{} = ROUND.{}[{}]", s(dst), letter, s(src))
                        }
                        Op::LoadCommon { dst, index } => {
                            write!(out, "{} = #{}", s(dst), common_number(index))
                        }
                        Op::StoreCommon { index, src } => {
                            write!(out, "#{} = {}", common_number(index), s(src))
                        }
                        Op::LoadSystem { dst, number } => write!(out, "{} = #{}", s(dst), number),
                        Op::StoreSystem { number, src } => write!(out, "#{} = {}", number, s(src)),
                        Op::LoadIndirect { dst, addr } => {
                            write!(out, "{} = #[{}]", s(dst), s(addr))
                        }
                        Op::StoreIndirect { addr, src } => {
                            write!(out, "#[{}] = {}", s(addr), s(src))
                        }
                        Op::Word {
                            letter,
                            flags: fl,
                            src,
                        } => {
                            write!(out, "word {}{}{}", letter, s(src), flags(fl))
                        }
                        Op::WordConst {
                            letter,
                            flags: fl,
                            k,
                        } => {
                            write!(
                                out,
                                "word {}{:?}{}",
                                letter,
                                f.consts[k as usize],
                                flags(fl)
                            )
                        }
                        Op::EmitBlock { info } => {
                            write!(out, "emit block (line {})", f.infos[info as usize].line)
                        }
                        Op::LiteralBlock { at } => match literal::block(&f.literals, at) {
                            Some(b) => {
                                let line = f.infos.get(b.info as usize).map_or(0, |i| i.line);
                                write!(out, "emit literal block (line {line})")?;
                                for w in b {
                                    match w {
                                        // As written: `M30` without a point, `X10.0` with one.
                                        Some(w) if w.flags.has(WordFlags::NO_POINT) => {
                                            write!(out, " {}{}", w.letter, w.value)?
                                        }
                                        Some(w) => write!(out, " {}{:?}", w.letter, w.value)?,
                                        None => write!(out, " <bad>")?,
                                    }
                                }
                                Ok(())
                            }
                            None => write!(out, "emit literal block <bad {at}>"),
                        },
                        Op::MacroAlarm { src, message } => {
                            write!(out, "alarm 3000+{} {:?}", s(src), self.string(message))
                        }
                        Op::Message { src, message } => {
                            write!(out, "message 3006={} {:?}", s(src), self.string(message))
                        }
                        Op::Call { kind, info } => write!(
                            out,
                            "call {kind:?} with the block (line {})",
                            f.infos[info as usize].line
                        ),
                        Op::Return { info } => {
                            write!(out, "return (M99, line {})", f.infos[info as usize].line)
                        }
                        Op::CancelModal => write!(out, "cancel modal call (G67)"),
                        Op::Print { print } => {
                            let p = &f.prints[print as usize];
                            write!(out, "{}", if p.binary { "bprnt" } else { "dprnt" })?;
                            for it in &p.items {
                                match *it {
                                    PrintItem::Text(t) => write!(out, " {:?}", self.string(t))?,
                                    PrintItem::Value { slot, whole, frac } => {
                                        write!(out, " {}[{whole}{frac}]", s(slot))?
                                    }
                                }
                            }
                            Ok(())
                        }
                        Op::Popen => write!(out, "popen"),
                        Op::Pclos => write!(out, "pclos"),
                        Op::Jump { target } => write!(out, "jump b{target}"),
                        Op::Branch { cond, when, target } => write!(
                            out,
                            "branch b{target} if {} is {}",
                            s(cond),
                            if when { "true" } else { "false" }
                        ),
                        Op::Goto { src, table } => {
                            let t = &f.goto_tables[table as usize];
                            write!(out, "goto N[{}] among {} labels", s(src), t.entries.len())
                        }
                        Op::Alarm { number, message } => {
                            write!(out, "alarm {number} {:?}", self.string(message))
                        }
                        Op::End => write!(out, "end"),
                    }?;
                    writeln!(out)?;
                }
            }
        }
        Ok(())
    }
}
