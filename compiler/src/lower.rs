//! Lowers checked lines, one at a time, to an IR [`Function`]: variables to slots, WHILE/IF/GOTO to
//! jumps to labels (basic blocks are cut at the end, `Draft::layout`), NC words to `Word` ops and one
//! `EmitBlock` per NC block, a block of literal words to one `LiteralBlock`.

use std::collections::HashMap;

use fmsvm_block::{Code, Letter, Word, WordFlags};

use crate::ast::{Expr, GotoTarget, Line, Stmt, VarRef, WordAst};
use crate::check::{SeqTable, Structure, seq_number};
use crate::diag::{Diagnostic, alarm};
use crate::ir::{
    BinOp, BlockId, BlockInfo, CallKind, Func, Function, GotoDest, GotoTable, LOCALS, Op,
    PrintInfo, PrintItem, Slot, VACANT_SLOT, VarClass, classify, literal as packed,
};
use crate::print::{PrintPiece, parse_body};
use crate::span::{SourceMap, Span};

/// A jump target before block numbers are final.
type Label = u32;

/// A computed-GOTO table before blocks are cut: (table, entries (N, op position, or None = into a
/// loop)).
type PendingTable = (u32, Vec<(u32, Option<u32>)>);

/// The first line with a sequence number: where its ops begin, and its span (a jump that falls into
/// it gets that span).
#[derive(Clone, Copy, Debug)]
struct SeqLine {
    n: u32,
    pos: u32,
    span: Span,
}

/// A map keyed by an f64's bits (the constant pools): hashed with a 64-bit finalizer (SplitMix64's)
/// instead of SipHash, which was 7 % of compiling a long program. Every bit of the key reaches the low
/// bits the table indexes by, so `1.0, 2.0, 3.0 …` (low mantissa bits all zero) do not collide.
type BitsMap<V> = HashMap<u64, V, std::hash::BuildHasherDefault<BitsHasher>>;

#[derive(Default)]
struct BitsHasher(u64);

impl std::hash::Hasher for BitsHasher {
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = self.0.rotate_left(8) ^ u64::from(b);
        }
    }

    fn write_u64(&mut self, x: u64) {
        self.0 ^= x;
    }

    fn finish(&self) -> u64 {
        let mut x = self.0;
        x = (x ^ (x >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        x = (x ^ (x >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        x ^ (x >> 31)
    }
}

/// A label not yet bound to an op.
const UNBOUND: u32 = u32::MAX;

/// The string table of a compilation: comments and messages, each stored once.
#[derive(Default)]
pub struct Strings {
    /// The strings, by index (they become [`crate::Program::strings`]).
    pub list: Vec<String>,
    ids: HashMap<String, u32>,
}

impl Strings {
    /// The index of `s`, added if new.
    fn intern(&mut self, s: String) -> u32 {
        if let Some(&i) = self.ids.get(&s) {
            return i;
        }
        self.list.push(s.clone());
        let i = (self.list.len() - 1) as u32;
        self.ids.insert(s, i);
        i
    }
}

/// Lowers one program line by line as it is checked: ops are appended in source order, jump targets
/// are labels bound to op positions, constants get slots on first use. [`Lowerer::finish`] resolves the
/// GOTOs once the program's sequence numbers and DO ranges are known; [`Draft::layout`] then cuts the
/// ops into basic blocks.
pub struct Lowerer<'a> {
    src: &'a SourceMap,
    strings: Strings,
    f: Function,
    /// The op position each label is bound to (`UNBOUND` until then) and the span a fall-through jump
    /// to it gets.
    label_pos: Vec<u32>,
    label_span: Vec<Span>,
    /// The first line with each sequence number, in source order, and by number its index there.
    seq_lines: Vec<SeqLine>,
    seq_first: SeqTable,
    /// GOTOs to a literal sequence number, resolved at the end: (label, line, n, span of n).
    sites: Vec<(Label, usize, u32, Span)>,
    /// Computed GOTOs: (table, line).
    tables: Vec<(u32, usize)>,
    terminated: bool,
    /// Where the last line number was found in the file's line index.
    line_cursor: usize,
    /// The positions of the jumps and branches, and those after each terminator.
    jumps: Vec<u32>,
    after_terminators: Vec<u32>,
    const_slots: BitsMap<Slot>,
    /// Constants beyond the registers already loaded into a temporary on this stretch of straight
    /// code (one line, up to a label or a branch): (bits, temporary).
    loaded: Vec<(u64, Slot)>,
    /// The next free constant slot.
    next_const: u32,
    pool: BitsMap<u32>,
    next_temp: u32,
    max_temp: u32,
    /// Where a statement first needed a temporary past the last slot.
    temps_overflow: Option<Span>,
    loops: Vec<(Label, Label)>,
    /// The address letter while lowering a word's value (for ROUND, E3).
    address: Option<Letter>,
    /// The words of a literal block being packed.
    scratch: Vec<Word>,
    span: Span,
    /// The codes the parameters bind to programs.
    /// The codes bound to calls, when any is.
    calls: Option<crate::CodeCalls>,
    /// The number of the program being lowered.
    number: Option<u32>,
    /// Haas: M99 Pn branches within the program.
    haas: bool,
    /// M97 is a local call (Haas).
    m97: bool,
}

/// A lowered function whose ops are not yet cut into basic blocks: jump targets are labels.
pub struct Draft {
    f: Function,
    label_pos: Vec<u32>,
    label_span: Vec<Span>,
    seq_lines: Vec<SeqLine>,
    /// Computed-GOTO tables with their destinations as op positions.
    tables: Vec<PendingTable>,
    computed_goto: bool,
    /// The positions of the jumps and branches, and those after each terminator.
    jumps: Vec<u32>,
    after_terminators: Vec<u32>,
}

/// The value of a literal: `10`, `-10`, `[10]` (the last is an expression, so it is "with point").
fn literal(e: &Expr) -> Option<(f64, bool)> {
    match e {
        Expr::Num(n, _) => Some((n.value, !n.point)),
        Expr::Neg(x, _) => literal(x).map(|(v, np)| (-v, np)),
        Expr::Group(x, _) => literal(x).map(|(v, _)| (v, false)),
        _ => None,
    }
}

/// The call or flow code a line's words hold, as a literal: G65 G66 G67 M97 M98 M99.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum FlowCode {
    /// G65 / G66 / M98 / M97.
    Call(CallKind),
    /// M99.
    Return,
}

/// The G or M code of a literal word.
pub fn code_of(w: &WordAst) -> Option<Code> {
    match (&w.letter, literal(&w.value)) {
        (Letter::G | Letter::M, Some((v, _))) => Code::of(v),
        _ => None,
    }
}

/// Haas: the block dwells (G04), so its P written with a decimal point is seconds (`G04 P200.`),
/// without one milliseconds (docs/semantics.md).
pub fn haas_dwell_block(words: &[WordAst]) -> bool {
    words
        .iter()
        .any(|w| w.letter == Letter::G && code_of(w) == Some(Code::G4))
}

/// Finds the call/return code of a line (M97 only when `m97` is on).
pub fn flow_code(words: &[WordAst], m97: bool) -> Option<FlowCode> {
    words.iter().find_map(|w| match (w.letter, code_of(w)) {
        (Letter::G, Some(Code::G65)) => Some(FlowCode::Call(CallKind::Macro)),
        (Letter::G, Some(Code::G66 | Code::G66_1)) => Some(FlowCode::Call(CallKind::Modal)),
        (Letter::M, Some(Code::M98)) => Some(FlowCode::Call(CallKind::Sub)),
        (Letter::M, Some(Code::M97)) if m97 => Some(FlowCode::Call(CallKind::Local)),
        (Letter::M, Some(Code::M99)) => Some(FlowCode::Return),
        _ => None,
    })
}

/// Where the G65/G66 word of a macro call stands when G codes come before it (`G57 G65 P160003
/// X160.`): the words before it (a leading N aside) are G codes, which run as a block of their own
/// before the call.
pub fn codes_before_call(words: &[WordAst], flow: Option<FlowCode>) -> Option<usize> {
    if !matches!(
        flow,
        Some(FlowCode::Call(CallKind::Macro | CallKind::Modal))
    ) {
        return None;
    }
    let at = words.iter().position(|w| {
        w.letter == Letter::G && matches!(code_of(w), Some(Code::G65 | Code::G66 | Code::G66_1))
    })?;
    let before = &words[..at];
    let codes = before.iter().filter(|w| w.letter != Letter::N);
    (codes.clone().count() > 0 && codes.clone().all(|w| w.letter == Letter::G)).then_some(at)
}

/// A block that calls by a bound code: the kind of call, the program, and which word is the code.
pub struct CodeCall {
    /// Macro (with arguments) or subprogram.
    pub kind: CallKind,
    /// O9000–O9029.
    pub program: u32,
    /// The index of the calling word in the block (left out of the block and of the arguments).
    pub word: usize,
    /// The common variable the calling word's value goes to first: #149 (T), #147 (S), #146 (the
    /// second auxiliary function); None for G and M.
    pub store: Option<u32>,
}

/// The call a block makes by a G, M, T, S or second-auxiliary code the parameters bind (the first
/// such word), unless the block is in one of the called programs: there the codes are ordinary codes
/// (Fanuc: "a G code specified in a macro called by a G code is treated as an ordinary G code",
/// likewise M, T, S and B; docs/params.md).
pub fn code_call(
    words: &[WordAst],
    calls: &crate::CodeCalls,
    program: Option<u32>,
) -> Option<CodeCall> {
    if !calls.any() || program.is_some_and(|p| calls.programs().contains(&p)) {
        return None;
    }
    words.iter().enumerate().find_map(|(i, w)| {
        let found = |kind, program, store| {
            Some(CodeCall {
                kind,
                program,
                word: i,
                store,
            })
        };
        match w.letter {
            Letter::G => {
                let c = code_of(w)?;
                let k = calls.g_macro.iter().position(|&g| g == Some(c))?;
                found(CallKind::Macro, 9010 + k as u32, None)
            }
            Letter::M => {
                let (v, _) = literal(&w.value)?;
                let m = v as u32;
                if v.fract() != 0.0 || v < 0.0 {
                    return None;
                }
                if let Some(k) = calls.m_macro.iter().position(|c| *c == Some(m)) {
                    return found(CallKind::Macro, 9020 + k as u32, None);
                }
                let k = calls.m_sub.iter().position(|c| *c == Some(m))?;
                found(CallKind::Sub, 9001 + k as u32, None)
            }
            Letter::T if calls.t_sub => found(CallKind::Sub, 9000, Some(149)),
            Letter::S if calls.s_sub => found(CallKind::Sub, 9029, Some(147)),
            l if calls.b_sub == Some(l) => found(CallKind::Sub, 9028, Some(146)),
            _ => None,
        }
    })
}

/// True for a literal `G67` word.
pub fn is_g67(w: &WordAst) -> bool {
    w.letter == Letter::G && code_of(w) == Some(Code::G67)
}

/// Registers for constants at most (the rest of 65 535 slots is for temporaries).
const CONST_SLOTS: u32 = 16_384;

/// Where temporaries are numbered from while a function is lowered; they move down next to the
/// constant slots once the number of those is known.
const TEMP_BASE: u32 = CONST_SLOTS + 1;

impl<'a> Lowerer<'a> {
    /// Starts lowering program `number` (its O line at `span`, `title` its comments).
    pub fn new(
        src: &'a SourceMap,
        options: &crate::Options,
        number: Option<u32>,
        span: Span,
        title: &[Span],
        strings: Strings,
    ) -> Self {
        let mut lw = Lowerer {
            src,
            strings,
            f: Function {
                number,
                title: u32::MAX,
                spans: crate::span::OpSpans::new(span.file),
                ..Function::default()
            },
            label_pos: Vec::new(),
            label_span: Vec::new(),
            seq_lines: Vec::new(),
            seq_first: SeqTable::default(),
            sites: Vec::new(),
            tables: Vec::new(),
            terminated: false,
            line_cursor: 0,
            jumps: Vec::new(),
            after_terminators: Vec::new(),
            const_slots: BitsMap::default(),
            loaded: Vec::new(),
            next_const: LOCALS as u32 + 1,
            pool: BitsMap::default(),
            next_temp: TEMP_BASE,
            max_temp: TEMP_BASE,
            temps_overflow: None,
            loops: Vec::new(),
            address: None,
            scratch: Vec::new(),
            span,
            calls: options.calls.any().then(|| options.calls.clone()),
            number,
            haas: options.syntax.haas,
            m97: options.syntax.m97,
        };
        if !title.is_empty() {
            let t = lw.comment_text(title);
            lw.f.title = lw.string(t);
        }
        lw
    }

    /// Lowers line `i` of the program (lines are numbered from 0, in order), checked without error;
    /// `flow` is its [`flow_code`].
    pub fn line(&mut self, i: usize, line: &Line, flow: Option<FlowCode>) {
        self.begin_line(line.span, seq_number(line));
        self.lower_line(i, line, flow);
    }

    /// Lowers a line of the plain subset, decoded with no tree: `seq` is its sequence number. A lone
    /// N word is no block; the rest is one literal block (or, when a value does not pack, a
    /// `WordConst` op a word), as `line` makes of the same text. (In that last case the ops carry the
    /// line's span where `line` gives each its word's; a `WordConst` never raises an alarm, so no
    /// message can show the difference.)
    pub fn plain_line(&mut self, seq: Option<u32>, p: &crate::lexer::PlainLine<'_>) {
        self.begin_line(p.span, seq);
        if p.sequence_only {
            return;
        }
        let info = self.block_info(p.span, false, p.comment.as_slice());
        let words = p.block.words();
        if let Ok(at) = u32::try_from(self.f.literals.len())
            && packed::pack(&mut self.f.literals, info, words)
        {
            self.emit(Op::LiteralBlock { at });
            return;
        }
        for w in words {
            let k = self.pool(w.value);
            self.emit(Op::WordConst {
                letter: w.letter,
                flags: w.flags,
                k,
            });
        }
        self.emit(Op::EmitBlock { info });
    }

    /// Ends the program: binds each GOTO to its line or to an alarm stub after the body, and moves
    /// the temporaries down next to the constant slots. `st` is the checker's view of the program.
    /// None (with a diagnostic) when it needs more slots than a function has.
    pub fn finish(
        mut self,
        st: &Structure,
        diags: &mut Vec<Diagnostic>,
    ) -> (Option<Draft>, Strings) {
        if !self.terminated {
            self.emit(Op::End);
        }
        let name = match self.number {
            Some(n) => format!("O{n:04}"),
            None => "the program".to_string(),
        };
        // GOTO n (macro-b-rules L3, L5): to the first line numbered n, unless that enters a DO range
        // from outside; else alarm 128 when the jump is taken.
        for (l, from, n, span) in std::mem::take(&mut self.sites) {
            let to = st.labels.get(n).map(|t| {
                (
                    st.jumps_into_loop(from, t as usize).is_none(),
                    self.seq_first.get(n),
                )
            });
            let message = match to {
                Some((true, Some(k))) => {
                    let seq = self.seq_lines[k as usize];
                    self.label_pos[l as usize] = seq.pos;
                    self.label_span[l as usize] = seq.span;
                    continue;
                }
                Some((false, _)) => format!("GOTO{n} jumps into a DO range from outside it"),
                _ => format!("sequence number N{n} not found in {name}"),
            };
            self.span = span;
            self.start_block(Some(l));
            let m = self.string(message);
            self.emit(Op::Alarm {
                number: alarm::SEQUENCE_NUMBER as u16,
                message: m,
            });
        }
        let mut tables = Vec::new();
        for (table, from) in std::mem::take(&mut self.tables) {
            let mut entries: Vec<(u32, Option<u32>)> = self
                .seq_lines
                .iter()
                .map(|seq| {
                    let inside = st
                        .labels
                        .get(seq.n)
                        .is_some_and(|t| st.jumps_into_loop(from, t as usize).is_some());
                    (seq.n, (!inside).then_some(seq.pos))
                })
                .collect();
            entries.sort_unstable_by_key(|e| e.0);
            tables.push((table, entries));
        }
        // Temporaries were numbered from TEMP_BASE; they follow the constant slots used.
        let shift = (TEMP_BASE - self.next_const) as Slot;
        let slots = self.max_temp - u32::from(shift);
        if let Some(at) = self.temps_overflow {
            diags.push(
                Diagnostic::error(
                    at,
                    None,
                    format!(
                        "this statement needs more than {} intermediate values",
                        Slot::MAX as u32 - TEMP_BASE
                    ),
                )
                .note("split it into several statements"),
            );
            return (None, self.strings);
        }
        let down = |s: Slot| {
            if u32::from(s) >= TEMP_BASE {
                s - shift
            } else {
                s
            }
        };
        if shift > 0 {
            for op in &mut self.f.ops {
                op.map_slots(down);
            }
            for p in &mut self.f.prints {
                for item in &mut p.items {
                    if let PrintItem::Value { slot, .. } = item {
                        *slot = down(*slot);
                    }
                }
            }
        }
        self.f.n_slots = slots as Slot;
        let draft = Draft {
            f: self.f,
            label_pos: self.label_pos,
            label_span: self.label_span,
            seq_lines: self.seq_lines,
            tables,
            computed_goto: st.computed_goto,
            jumps: self.jumps,
            after_terminators: self.after_terminators,
        };
        (Some(draft), self.strings)
    }
}

impl Draft {
    /// Cuts the ops into basic blocks and makes every jump target a block: a block begins at op 0,
    /// after every terminator and at every label a jump uses (at every sequence number's first line
    /// too when the program has a computed GOTO, whose table lists them all, or `all_labels`: some
    /// program of the compilation returns to a sequence number with `M99 P`, and the function's label
    /// table lists them). Where a block begins
    /// after an op that falls through, a jump to it is inserted; the ops move in place.
    pub fn layout(self, all_labels: bool) -> Function {
        let Draft {
            mut f,
            label_pos,
            label_span,
            seq_lines,
            tables,
            computed_goto,
            jumps,
            after_terminators,
        } = self;
        let n = f.ops.len();
        let mut starts: Vec<(u32, Span)> = vec![(0, Span::default())];
        // A computed GOTO's table lists every sequence number: each of them begins a block.
        if computed_goto || all_labels {
            for seq in seq_lines.iter().filter(|s| (s.pos as usize) < n) {
                starts.push((seq.pos, seq.span));
            }
        }
        for &at in &jumps {
            if let Op::Jump { target } | Op::Branch { target, .. } = f.ops[at as usize] {
                let pos = label_pos[target as usize];
                if pos != UNBOUND && (pos as usize) < n {
                    starts.push((pos, label_span[target as usize]));
                }
            }
        }
        for &at in after_terminators.iter().filter(|&&at| (at as usize) < n) {
            starts.push((at, Span::default()));
        }
        starts.sort_by_key(|s| s.0);
        starts.dedup_by_key(|s| s.0);
        let block_at = |pos: u32| starts.partition_point(|s| s.0 < pos) as BlockId;
        for &at in &jumps {
            if let Op::Jump { target } | Op::Branch { target, .. } = &mut f.ops[at as usize] {
                *target = block_at(label_pos.get(*target as usize).copied().unwrap_or(0));
            }
        }
        for (table, entries) in tables {
            f.goto_tables[table as usize].entries = entries
                .into_iter()
                .map(|(n, pos)| {
                    (
                        n,
                        match pos {
                            Some(pos) => GotoDest::Block(block_at(pos)),
                            None => GotoDest::IntoLoop,
                        },
                    )
                })
                .collect();
        }
        if all_labels {
            let mut labels: Vec<(u32, BlockId)> =
                seq_lines.iter().map(|s| (s.n, block_at(s.pos))).collect();
            labels.sort_unstable();
            f.labels = labels;
        }
        // A block that the op before falls into gets a jump to it at the end of that op's block.
        let falls = |pos: u32| pos > 0 && !f.ops[pos as usize - 1].is_terminator();
        let inserts: Vec<(u32, Span)> = starts.iter().filter(|s| falls(s.0)).copied().collect();
        let jumps = inserts.len();
        let mut blocks = Vec::with_capacity(starts.len());
        let mut before = 0;
        for s in &starts {
            before += usize::from(falls(s.0));
            blocks.push(s.0 + before as u32);
        }
        f.spans.insert_many(&inserts);
        f.ops.resize(n + jumps, Op::End);
        let mut ins = jumps;
        let mut next = starts.len();
        for i in (0..n).rev() {
            if ins == 0 {
                break;
            }
            f.ops[i + ins] = f.ops[i];
            if next > 0 && starts[next - 1].0 as usize == i {
                next -= 1;
                if i > 0 && !f.ops[i - 1].is_terminator() {
                    ins -= 1;
                    f.ops[i + ins] = Op::Jump {
                        target: next as BlockId,
                    };
                }
            }
        }
        f.blocks = blocks;
        f
    }
}

impl Lowerer<'_> {
    /// A line at `span` begins: its spans' anchor, free temporaries, and its sequence number if it has
    /// one.
    fn begin_line(&mut self, span: Span, seq: Option<u32>) {
        self.span = span;
        self.f.spans.line(span.start);
        self.reset_temps();
        if let Some(n) = seq {
            self.sequence(n);
        }
    }

    /// A line with sequence number `n` begins here; the first one is its target.
    fn sequence(&mut self, n: u32) {
        if self.seq_first.insert_first(n, self.seq_lines.len() as u32) {
            self.seq_lines.push(SeqLine {
                n,
                pos: self.f.ops.len() as u32,
                span: self.span,
            });
        }
        // Code after it is reachable (by a jump to it).
        self.terminated = false;
    }

    fn new_label(&mut self) -> Label {
        self.label_pos.push(UNBOUND);
        self.label_span.push(self.span);
        (self.label_pos.len() - 1) as Label
    }

    fn string(&mut self, s: String) -> u32 {
        self.strings.intern(s)
    }

    /// The strings back, when the lowerer is dropped unfinished (an error stopped it).
    pub fn into_strings(self) -> Strings {
        self.strings
    }

    /// A program fmsvm cannot read (a library file with an error): its body raises alarm `number`
    /// with `message` when it is called, as a control alarms where it cannot read.
    pub fn unreadable(&mut self, number: u32, message: String) {
        let m = self.string(message);
        self.emit(Op::Alarm {
            number: number.min(u32::from(u16::MAX)) as u16,
            message: m,
        });
    }

    fn comment_text(&self, comments: &[Span]) -> String {
        comments
            .iter()
            .map(|&c| self.src.text(c))
            .collect::<Vec<_>>()
            .join(" ")
    }

    fn line_no(&mut self, span: Span) -> u32 {
        self.src
            .file(span.file)
            .line_at(span.start, &mut self.line_cursor)
    }

    /// Binds `label` (or a fresh one) to the next op: a block begins there if the label is used.
    fn start_block(&mut self, label: Option<Label>) -> Label {
        let label = label.unwrap_or_else(|| self.new_label());
        // Code may come here from elsewhere: what was loaded before is not known to be there.
        self.loaded.clear();
        self.label_pos[label as usize] = self.f.ops.len() as u32;
        self.label_span[label as usize] = self.span;
        self.terminated = false;
        label
    }

    fn emit(&mut self, op: Op) {
        self.terminated = op.is_terminator();
        if self.terminated {
            self.loaded.clear();
            if matches!(op, Op::Jump { .. } | Op::Branch { .. }) {
                self.jumps.push(self.f.ops.len() as u32);
            }
            self.after_terminators.push(self.f.ops.len() as u32 + 1);
        }
        self.f.ops.push(op);
        self.f.spans.push(self.span);
    }

    fn jump(&mut self, target: Label) {
        self.emit(Op::Jump { target });
    }

    fn branch(&mut self, cond: Slot, when: bool, target: Label) {
        self.emit(Op::Branch { cond, when, target });
        // The next op is the fall-through successor; what follows runs only on one way.
        self.terminated = false;
        self.loaded.clear();
    }

    fn temp(&mut self) -> Slot {
        let t = self.next_temp;
        self.next_temp += 1;
        self.max_temp = self.max_temp.max(self.next_temp);
        if t >= Slot::MAX as u32 && self.temps_overflow.is_none() {
            self.temps_overflow = Some(self.span);
        }
        t.min(Slot::MAX as u32) as Slot
    }

    fn pool(&mut self, v: f64) -> u32 {
        if let Some(&k) = self.pool.get(&v.to_bits()) {
            return k;
        }
        self.f.consts.push(v);
        let k = (self.f.consts.len() - 1) as u32;
        self.pool.insert(v.to_bits(), k);
        k
    }

    /// The slot holding constant `v`: the first CONST_SLOTS distinct constants get a register filled
    /// at entry (the JIT makes them immediates); any beyond that are loaded into a temporary where
    /// they are used, so a program may hold any number of them.
    fn const_slot(&mut self, v: f64) -> Slot {
        if let Some(&s) = self.const_slots.get(&v.to_bits()) {
            return s;
        }
        if self.next_const < TEMP_BASE {
            let s = self.next_const as Slot;
            self.next_const += 1;
            self.const_slots.insert(v.to_bits(), s);
            self.f.slot_consts.push((s, v));
            return s;
        }
        let bits = v.to_bits();
        if let Some(&(_, t)) = self.loaded.iter().find(|l| l.0 == bits) {
            return t;
        }
        let t = self.temp();
        let k = self.pool(v);
        self.emit(Op::Const { dst: t, k });
        self.loaded.push((bits, t));
        t
    }

    /// Temporaries are free again (a new statement), and so no loaded constant is kept.
    fn reset_temps(&mut self) {
        self.next_temp = TEMP_BASE;
        self.loaded.clear();
    }

    fn lower_line(&mut self, i: usize, line: &Line, mut flow: Option<FlowCode>) {
        // Haas's `IF [cond] <NC block>`: the block runs when the condition holds.
        if let Some((cond, block)) = line.guarded() {
            self.span = line.span;
            let c = self.cond(cond);
            let after = self.new_label();
            self.branch(c, false, after);
            self.reset_temps();
            let block_flow = flow_code(&block.words, self.m97);
            self.lower_line(i, &block, block_flow);
            self.start_block(Some(after));
            return;
        }
        match line.stmt.as_deref() {
            Some((stmt, span)) => {
                self.span = *span;
                self.stmt(i, stmt, line);
            }
            None => {
                let words = if seq_number(line).is_some() && line.words.len() == 1 {
                    // A lone N word is no block.
                    &line.words[..0]
                } else {
                    &line.words[..]
                };
                if words.is_empty() && line.comments.is_empty() {
                    return;
                }
                let by_code = match &self.calls {
                    Some(calls) if flow.is_none() => code_call(words, calls, self.number),
                    _ => None,
                };
                if let Some(c) = &by_code {
                    flow = Some(FlowCode::Call(c.kind));
                    if let Some(n) = c.store {
                        // T calls O9000 with the T value in #149, S O9029 with S in #147, the second
                        // auxiliary function O9028 with its value in #146.
                        let t = &words[c.word];
                        let target = VarRef::Direct {
                            number: crate::lexer::Num {
                                value: n as f64,
                                point: false,
                            },
                            span: t.span,
                        };
                        self.assign(&target, &t.value, line);
                    }
                    self.span = words[c.word].span;
                    let k = self.pool(c.program as f64);
                    self.emit(Op::WordConst {
                        letter: Letter::P,
                        flags: WordFlags(0),
                        k,
                    });
                }
                // Haas: M99 Pn is a branch to Nn of this program (C9): the block's other words run,
                // then the jump.
                let haas_branch = if self.haas {
                    crate::check::haas_m99_target(line)
                } else {
                    None
                };
                if haas_branch.is_some() {
                    flow = None;
                }
                // Haas: a dwell's P written with a decimal point is seconds (`G04 P200.`), and is
                // handed on as the milliseconds the kernel reads a dwell's P in.
                let haas_dwell = self.haas
                    && haas_dwell_block(words)
                    && words.iter().any(|w| {
                        w.letter == Letter::P && literal(&w.value).is_some_and(|(_, np)| !np)
                    });
                if flow.is_none()
                    && by_code.is_none()
                    && haas_branch.is_none()
                    && !haas_dwell
                    && self.literal_block(words, line)
                {
                    return;
                }
                // G codes before G65/G66 are no arguments ("G65 must be specified before any
                // argument"): they run as a block of their own, then the call (docs/semantics.md).
                let words = match codes_before_call(words, flow) {
                    Some(c) => {
                        for w in &words[..c] {
                            self.word(w);
                        }
                        self.span = line.span;
                        let info = self.block_info(line.span, line.block_delete, &[]);
                        self.emit(Op::EmitBlock { info });
                        &words[c..]
                    }
                    None => words,
                };
                let mut cancel = false;
                for (j, w) in words.iter().enumerate() {
                    if by_code.as_ref().is_some_and(|c| c.word == j) {
                        continue;
                    }
                    if is_g67(w) {
                        cancel = true;
                        continue;
                    }
                    if haas_branch.is_some()
                        && (w.letter == Letter::P || code_of(w) == Some(Code::M99))
                    {
                        continue;
                    }
                    if haas_dwell
                        && w.letter == Letter::P
                        && let Some((seconds, false)) = literal(&w.value)
                    {
                        self.span = w.span;
                        let k = self.pool((seconds * 1000.0).round());
                        self.emit(Op::WordConst {
                            letter: Letter::P,
                            flags: WordFlags(WordFlags::NO_POINT),
                            k,
                        });
                        continue;
                    }
                    self.word(w);
                }
                self.span = line.span;
                let info = self.block_info(line.span, line.block_delete, &line.comments);
                if cancel {
                    self.emit(Op::CancelModal);
                }
                match flow {
                    Some(FlowCode::Call(kind)) => self.emit(Op::Call { kind, info }),
                    Some(FlowCode::Return) => self.emit(Op::Return { info }),
                    None => self.emit(Op::EmitBlock { info }),
                }
                if let Some(target) = haas_branch {
                    self.goto(i, &target, None);
                }
            }
        }
    }

    /// One address word of a block.
    fn word(&mut self, w: &WordAst) {
        self.span = w.span;
        self.address = Some(w.letter);
        let incremental = if w.incremental {
            WordFlags::INCREMENTAL
        } else {
            0
        };
        match literal(&w.value) {
            Some((v, no_point)) => {
                let k = self.pool(v);
                let flags = WordFlags(if no_point { WordFlags::NO_POINT } else { 0 } | incremental);
                self.emit(Op::WordConst {
                    letter: w.letter,
                    flags,
                    k,
                });
            }
            None => {
                let s = self.expr(&w.value, None);
                self.emit(Op::Word {
                    letter: w.letter,
                    flags: WordFlags(incremental),
                    src: s,
                });
            }
        }
        self.address = None;
    }

    /// The source information of the block on `line`.
    fn block_info(&mut self, span: Span, block_delete: bool, comments: &[Span]) -> u32 {
        let comment = if comments.is_empty() {
            u32::MAX
        } else {
            let t = self.comment_text(comments);
            self.string(t)
        };
        // The column of the block's first character past its indentation.
        let file = self.src.file(span.file);
        let line = file
            .text
            .get(span.start as usize..span.end as usize)
            .unwrap_or("");
        let indent = line.len() - line.trim_start().len();
        let (_, column) = file.line_col(span.start + indent as u32);
        let info = BlockInfo {
            file: span.file.0,
            line: self.line_no(span),
            column: u16::try_from(column).unwrap_or(u16::MAX),
            block_delete,
            comment,
        };
        self.f.infos.push(info);
        (self.f.infos.len() - 1) as u32
    }

    /// A block of literal words only (a CAM file's line): one `LiteralBlock` op, its words packed.
    /// False, with nothing emitted, when a word is not a literal, is incremental or G67, or a value
    /// does not pack.
    fn literal_block(&mut self, words: &[WordAst], line: &Line) -> bool {
        self.scratch.clear();
        for w in words {
            let Some((value, no_point)) = literal(&w.value) else {
                return false;
            };
            if w.incremental || is_g67(w) {
                return false;
            }
            self.scratch.push(Word {
                letter: w.letter,
                flags: WordFlags(if no_point { WordFlags::NO_POINT } else { 0 }),
                value,
            });
        }
        let Ok(at) = u32::try_from(self.f.literals.len()) else {
            return false;
        };
        self.span = line.span;
        let info = self.block_info(line.span, line.block_delete, &line.comments);
        if !packed::pack(&mut self.f.literals, info, &self.scratch) {
            self.f.infos.pop();
            return false;
        }
        self.emit(Op::LiteralBlock { at });
        true
    }

    fn goto(&mut self, from: usize, target: &GotoTarget, cond: Option<Slot>) {
        match target {
            GotoTarget::Seq(n, span) => {
                // Bound by `finish`, to line Nn or to an alarm stub.
                let l = self.new_label();
                self.sites.push((l, from, *n, *span));
                match cond {
                    Some(c) => self.branch(c, true, l),
                    None => self.jump(l),
                }
            }
            GotoTarget::Computed(e) => {
                let after = cond.map(|c| {
                    let after = self.new_label();
                    self.branch(c, false, after);
                    after
                });
                let s = self.expr(e, None);
                self.f.goto_tables.push(GotoTable::default());
                let table = (self.f.goto_tables.len() - 1) as u32;
                self.tables.push((table, from));
                self.emit(Op::Goto { src: s, table });
                if let Some(after) = after {
                    self.start_block(Some(after));
                }
            }
        }
    }

    fn stmt(&mut self, i: usize, stmt: &Stmt, line: &Line) {
        match stmt {
            Stmt::Assign { target, value } => self.assign(target, value, line),
            Stmt::While { cond, .. } => {
                let head = self.start_block(None);
                let exit = self.new_label();
                let c = self.cond(cond);
                self.branch(c, false, exit);
                self.loops.push((head, exit));
            }
            Stmt::Do { .. } => {
                let head = self.start_block(None);
                let exit = self.new_label();
                self.loops.push((head, exit));
            }
            Stmt::End { .. } => {
                if let Some((head, exit)) = self.loops.pop() {
                    self.jump(head);
                    self.start_block(Some(exit));
                }
            }
            Stmt::IfGoto { cond, target } => {
                let c = self.cond(cond);
                self.goto(i, target, Some(c));
            }
            Stmt::Goto(target) => self.goto(i, target, None),
            Stmt::IfThen { cond, then, .. } => {
                let c = self.cond(cond);
                let after = self.new_label();
                self.branch(c, false, after);
                self.reset_temps();
                self.stmt(i, then, line);
                self.start_block(Some(after));
            }
            Stmt::Print { binary, body } => {
                let text = &self.src.file(body.file).text;
                let mut scratch = Vec::new();
                let Some(pieces) = parse_body(body.file, text, *body, *binary, &mut scratch) else {
                    return;
                };
                let mut items = Vec::new();
                for piece in pieces {
                    match piece {
                        PrintPiece::Text(t) => items.push(PrintItem::Text(self.string(t))),
                        PrintPiece::Value { var, whole, frac } => {
                            let slot = self.expr(&Expr::Var(var), None);
                            items.push(PrintItem::Value { slot, whole, frac });
                        }
                    }
                }
                self.f.prints.push(PrintInfo {
                    binary: *binary,
                    items,
                });
                let print = (self.f.prints.len() - 1) as u32;
                self.emit(Op::Print { print });
            }
            Stmt::Popen(_) => self.emit(Op::Popen),
            Stmt::Pclos(_) => self.emit(Op::Pclos),
            Stmt::IfThenWords { .. } | Stmt::IfBlock { .. } => {}
        }
    }

    fn assign(&mut self, target: &VarRef, value: &Expr, line: &Line) {
        let lit = literal(value).map(|(v, _)| v);
        match target {
            VarRef::Direct { number, .. } => match classify(number.value as u32) {
                Some(VarClass::Local(n)) => match lit {
                    Some(v) => {
                        let k = self.pool(v);
                        self.emit(Op::Const { dst: n, k });
                    }
                    None => {
                        let s = self.expr(value, Some(n));
                        if s != n {
                            self.emit(Op::Copy { dst: n, src: s });
                        }
                    }
                },
                Some(VarClass::Common(index)) => {
                    let s = self.value(value, lit);
                    self.emit(Op::StoreCommon { index, src: s });
                }
                Some(VarClass::System(n @ (3000 | 3006))) => {
                    let s = self.value(value, lit);
                    // Each comment without its parentheses: `(A)(B)` is the message `A B`.
                    let msg = line
                        .comments
                        .iter()
                        .map(|&c| {
                            let t = self.src.text(c);
                            let t = t.strip_prefix('(').unwrap_or(t);
                            t.strip_suffix(')').unwrap_or(t).trim()
                        })
                        .filter(|t| !t.is_empty())
                        .collect::<Vec<_>>()
                        .join(" ");
                    let message = self.string(msg);
                    self.emit(if n == 3000 {
                        Op::MacroAlarm { src: s, message }
                    } else {
                        Op::Message { src: s, message }
                    });
                }
                Some(VarClass::System(number)) => {
                    let s = self.value(value, lit);
                    self.emit(Op::StoreSystem { number, src: s });
                }
                // Rejected by the checker.
                Some(VarClass::Vacant) | None => {}
            },
            VarRef::Indirect { addr, .. } => {
                let a = self.expr(addr, None);
                let s = self.value(value, lit);
                self.emit(Op::StoreIndirect { addr: a, src: s });
            }
        }
    }

    /// A whole value into some slot (a literal through the pool).
    fn value(&mut self, value: &Expr, lit: Option<f64>) -> Slot {
        match lit {
            Some(v) => {
                let t = self.temp();
                let k = self.pool(v);
                self.emit(Op::Const { dst: t, k });
                t
            }
            None => self.expr(value, None),
        }
    }

    /// A condition into a slot that is non-zero when it holds. A plain value (Haas, E9) counts as true
    /// when it is not 0, vacant counting as 0.
    fn cond(&mut self, e: &Expr) -> Slot {
        let s = self.expr(e, None);
        if crate::check::is_condition(e) {
            return s;
        }
        let zero = self.const_slot(0.0);
        let t = self.temp();
        self.emit(Op::Bin {
            op: BinOp::Add,
            dst: t,
            a: s,
            b: zero,
        });
        t
    }

    /// Lowers `e`; the result is in the returned slot (`dst` when given and an op was needed). Ops are
    /// marked with the span of the sub-expression they compute, so an alarm points at it.
    fn expr(&mut self, e: &Expr, dst: Option<Slot>) -> Slot {
        let saved = std::mem::replace(&mut self.span, e.span());
        let r = self.expr_inner(e, dst);
        self.span = saved;
        r
    }

    fn expr_inner(&mut self, e: &Expr, dst: Option<Slot>) -> Slot {
        // `-5`, `[5]`: a constant too.
        if matches!(e, Expr::Neg(..) | Expr::Group(..))
            && let Some((v, _)) = literal(e)
        {
            return self.const_slot(v);
        }
        match e {
            Expr::Num(n, _) => self.const_slot(n.value),
            Expr::Var(VarRef::Direct { number, .. }) => match classify(number.value as u32) {
                Some(VarClass::Local(n)) => n,
                Some(VarClass::Common(index)) => {
                    let d = dst.unwrap_or_else(|| self.temp());
                    self.emit(Op::LoadCommon { dst: d, index });
                    d
                }
                Some(VarClass::System(number)) => {
                    let d = dst.unwrap_or_else(|| self.temp());
                    self.emit(Op::LoadSystem { dst: d, number });
                    d
                }
                Some(VarClass::Vacant) | None => VACANT_SLOT,
            },
            Expr::Var(VarRef::Indirect { addr, .. }) => {
                let a = self.expr(addr, None);
                let d = dst.unwrap_or_else(|| self.temp());
                self.emit(Op::LoadIndirect { dst: d, addr: a });
                d
            }
            Expr::Neg(x, _) => {
                let s = self.expr(x, None);
                let d = dst.unwrap_or_else(|| self.temp());
                self.emit(Op::Neg { dst: d, src: s });
                d
            }
            Expr::Group(x, _) => self.expr(x, dst),
            Expr::Bin(op, ab, _) => {
                let sa = self.expr(&ab[0], None);
                let sb = self.expr(&ab[1], None);
                let d = dst.unwrap_or_else(|| self.temp());
                self.emit(Op::Bin {
                    op: *op,
                    dst: d,
                    a: sa,
                    b: sb,
                });
                d
            }
            Expr::Cmp(op, ab, _) => {
                let sa = self.expr(&ab[0], None);
                let sb = self.expr(&ab[1], None);
                let d = dst.unwrap_or_else(|| self.temp());
                self.emit(Op::Cmp {
                    op: *op,
                    dst: d,
                    a: sa,
                    b: sb,
                });
                d
            }
            Expr::Call(f, args, _) => {
                let sa = self.expr(&args[0], None);
                let d = dst.unwrap_or_else(|| self.temp());
                match (*f, args.get(1), self.address) {
                    (Func::Round, None, Some(letter)) => self.emit(Op::RoundAddr {
                        letter,
                        dst: d,
                        src: sa,
                    }),
                    (f, None, _) => self.emit(Op::Func1 { f, dst: d, a: sa }),
                    (f, Some(b), _) => {
                        let sb = self.expr(b, None);
                        self.emit(Op::Func2 {
                            f,
                            dst: d,
                            a: sa,
                            b: sb,
                        });
                    }
                }
                d
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use std::hash::{BuildHasher, BuildHasherDefault};

    use super::BitsHasher;
    use crate::ir::{GotoDest, Op};
    use crate::{Options, compile_str};

    /// The layout pass, worked by hand: a block begins at op 0, at each label a jump uses (the
    /// backward GOTO10, lowered after its target, and the forward GOTO20), after each terminator;
    /// an unused sequence number (N15) begins none of its own, and a jump is inserted where a block
    /// would be fallen into.
    #[test]
    fn blocks_are_cut_where_jumps_land() {
        let src = "#1=0\nN10 #1=#1+1\nIF[#1 LT 3] GOTO10\nGOTO20\nN15 #2=1\nN20 #3=2\nM30\n";
        let (p, d, _) = compile_str(src, &Options::default());
        let p = p.unwrap_or_else(|| panic!("{d:?}"));
        let f = &p.functions[0];
        assert_eq!(f.blocks, [0, 2, 5, 6, 8]);
        assert!(matches!(f.ops[0], Op::Const { dst: 1, .. }));
        assert_eq!(f.ops[1], Op::Jump { target: 1 });
        assert!(matches!(f.ops[2], Op::Bin { dst: 1, .. }));
        assert!(matches!(f.ops[3], Op::Cmp { .. }));
        assert!(matches!(
            f.ops[4],
            Op::Branch {
                when: true,
                target: 1,
                ..
            }
        ));
        assert_eq!(f.ops[5], Op::Jump { target: 4 });
        assert!(matches!(f.ops[6], Op::Const { dst: 2, .. }));
        assert_eq!(f.ops[7], Op::Jump { target: 4 });
        assert!(matches!(f.ops[8], Op::Const { dst: 3, .. }));
        assert!(matches!(f.ops[9], Op::LiteralBlock { .. }));
        assert_eq!(f.ops[10], Op::End);
        assert_eq!(f.spans.len(), f.ops.len());
        assert!(p.verify().is_ok());
    }

    /// A constant beyond the 16 384 registers is loaded into a temporary once on a stretch of straight
    /// code: three uses in one line, one load; after a branch, loaded again.
    #[test]
    fn a_loaded_constant_is_reused_on_its_line() {
        let mut src = String::new();
        for i in 0..16_400u32 {
            src.push_str(&format!("#1=#1+{i}.5\n"));
        }
        src.push_str("#2=[0.125+0.125]*0.125\nIF[#2 GT 0] THEN #2=#2+0.125\nM30\n");
        let (p, d, _) = compile_str(&src, &Options::default());
        let p = p.unwrap_or_else(|| panic!("{d:?}"));
        let f = &p.functions[0];
        let loads = f
            .ops
            .iter()
            .filter(|op| matches!(op, Op::Const { k, .. } if f.consts[*k as usize] == 0.125))
            .count();
        assert_eq!(loads, 2);
        assert!(!f.slot_consts.iter().any(|c| c.1 == 0.125));
        assert!(p.verify().is_ok());
    }

    /// A statement that needs more temporaries than a function has slots is refused where it is,
    /// with the limit; one just under it compiles.
    #[test]
    fn a_statement_past_the_temporaries_is_refused_where_it_is() {
        let print = |n: usize| format!("#100=1\nDPRNT[{}]\nM30\n", "#100[53]".repeat(n));
        let (p, d, _) = compile_str(&print(49_000), &Options::default());
        assert!(p.is_some(), "{:?}", d.first());
        let (p, d, _) = compile_str(&print(50_000), &Options::default());
        assert!(p.is_none());
        let e = d.iter().find(|d| d.is_error()).expect("an error");
        assert!(
            e.message.contains("more than 49150 intermediate values"),
            "{}",
            e.message
        );
        // At the item where the limit is passed, on the DPRNT line.
        assert!(
            e.span.start > 7 && e.span.end as usize <= 7 + 7 + 8 * 50_000,
            "{:?}",
            e.span
        );
    }

    /// GOTOs bound at the program's end: one into a DO range and one to a missing number go to alarm
    /// stubs after the body, in source order; a computed GOTO's table lists every sequence number,
    /// the one inside the range as a way into it, and each listed line begins a block.
    #[test]
    fn gotos_resolve_at_the_end_of_the_program() {
        let src = "GOTO5\nWHILE[#1 LT 2]DO1\nN5 #1=#1+1\nEND1\nIF[#1 EQ 9]GOTO7\nN8 GOTO#1\nM30\n";
        let (p, d, _) = compile_str(src, &Options::default());
        let p = p.unwrap_or_else(|| panic!("{d:?}"));
        assert_eq!(
            d.iter().filter(|d| d.alarm == Some(128)).count(),
            2,
            "{d:?}"
        );
        let f = &p.functions[0];
        let alarms: Vec<&str> = f
            .ops
            .iter()
            .filter_map(|op| match *op {
                Op::Alarm {
                    number: 128,
                    message,
                } => Some(p.string(message)),
                _ => None,
            })
            .collect();
        assert_eq!(
            alarms,
            [
                "GOTO5 jumps into a DO range from outside it",
                "sequence number N7 not found in the program"
            ]
        );
        let table = &f.goto_tables[0].entries;
        assert_eq!(table.len(), 2);
        assert_eq!(table[0], (5, GotoDest::IntoLoop));
        let GotoDest::Block(b8) = table[1].1 else {
            panic!("{table:?}")
        };
        assert_eq!(table[1].0, 8);
        assert!(matches!(
            f.block_ops(b8)[0],
            Op::LoadCommon { .. } | Op::Goto { .. }
        ));
        assert!(p.verify().is_ok());
    }

    /// Whole numbers and short decimals (the constants of real programs) spread over the low bits the
    /// table indexes by: a weak hash here would make every constant pool a list.
    #[test]
    fn constant_bits_spread_over_the_low_bits() {
        let h = BuildHasherDefault::<BitsHasher>::default();
        for values in [
            (1..=65_536).map(f64::from).collect::<Vec<_>>(),
            (1..=65_536).map(|i| f64::from(i) / 1000.0).collect(),
        ] {
            let mut seen = std::collections::HashSet::new();
            for v in &values {
                seen.insert(h.hash_one(v.to_bits()) & 0xFFFF);
            }
            // A random function fills about 63 % of 65 536 buckets with 65 536 keys.
            assert!(seen.len() > 40_000, "{} distinct low words", seen.len());
        }
    }
}
