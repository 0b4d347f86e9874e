//! Lowers a checked program to an IR [`Function`]: variables to slots, WHILE/IF/GOTO to basic blocks and
//! jumps, NC words to `Word` ops and one `EmitBlock` per NC block.

use std::collections::HashMap;

use fmsvm_block::{Letter, WordFlags};

use crate::ast::{Expr, GotoTarget, Line, Stmt, VarRef, WordAst};
use crate::check::{Structure, seq_number};
use crate::diag::{Diagnostic, alarm};
use crate::ir::{
    BinOp, BlockId, BlockInfo, CallKind, Func, Function, GotoDest, GotoTable, LOCALS, Op,
    PrintInfo, PrintItem, Slot, VACANT_SLOT, VarClass, classify,
};
use crate::parse::ProgramAst;
use crate::print::{PrintPiece, parse_body};
use crate::span::{SourceMap, Span};

/// A jump target before block numbers are final.
type Label = u32;

/// A computed-GOTO table while its destinations are still labels: (N, label or None = into a loop).
type PendingTable = (u32, Vec<(u32, Option<Label>)>);

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

/// Lowering state of one function.
struct Lowerer<'a> {
    src: &'a SourceMap,
    strings: &'a mut Vec<String>,
    string_ids: HashMap<String, u32>,
    f: Function,
    /// Targets of ops, as labels, patched to block ids at the end: (op index, label).
    fixups: Vec<(usize, Label)>,
    /// Block bound to each label.
    labels: Vec<Option<BlockId>>,
    /// Label of each target line.
    line_labels: HashMap<usize, Label>,
    /// Computed-GOTO tables still in labels: (table, entries).
    goto_fixups: Vec<PendingTable>,
    /// Alarm stubs emitted after the body: (label, alarm, message, span).
    stubs: Vec<(Label, u16, String, Span)>,
    terminated: bool,
    const_slots: BitsMap<Slot>,
    pool: BitsMap<u32>,
    temp_base: u32,
    next_temp: u32,
    max_temp: u32,
    loops: Vec<(Label, Label)>,
    /// The address letter while lowering a word's value (for ROUND, E3).
    address: Option<Letter>,
    span: Span,
    /// M97 is a local subprogram call (Haas).
    m97: bool,
    /// The codes the parameters bind to programs.
    calls: crate::CodeCalls,
    /// The number of the program being lowered.
    number: Option<u32>,
    /// Haas: M99 Pn branches within the program.
    haas: bool,
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

/// The G or M code ×10 of a literal word.
pub fn code_of(w: &WordAst) -> Option<u32> {
    match (&w.letter, literal(&w.value)) {
        (Letter::G | Letter::M, Some((v, _))) => fmsvm_block::code10(v).map(u32::from),
        _ => None,
    }
}

/// Finds the call/return code of a line (M97 only when `m97` is on).
pub fn flow_code(words: &[WordAst], m97: bool) -> Option<FlowCode> {
    words.iter().find_map(|w| match (w.letter, code_of(w)) {
        (Letter::G, Some(650)) => Some(FlowCode::Call(CallKind::Macro)),
        (Letter::G, Some(660 | 661)) => Some(FlowCode::Call(CallKind::Modal)),
        (Letter::M, Some(980)) => Some(FlowCode::Call(CallKind::Sub)),
        (Letter::M, Some(970)) if m97 => Some(FlowCode::Call(CallKind::Local)),
        (Letter::M, Some(990)) => Some(FlowCode::Return),
        _ => None,
    })
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
                let k = calls
                    .g_macro
                    .iter()
                    .position(|g| g.map(u32::from) == Some(c))?;
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
    w.letter == Letter::G && code_of(w) == Some(670)
}

/// Collects the constants that need a slot (operands inside expressions).
fn collect_consts(e: &Expr, out: &mut Vec<f64>) {
    if let Some((v, _)) = literal(e) {
        out.push(v);
        return;
    }
    match e {
        Expr::Num(..) => {}
        Expr::Var(VarRef::Indirect { addr, .. }) => collect_consts(addr, out),
        Expr::Var(_) => {}
        Expr::Neg(x, _) | Expr::Group(x, _) => collect_consts(x, out),
        Expr::Bin(_, a, b, _) | Expr::Cmp(_, a, b, _) => {
            collect_consts(a, out);
            collect_consts(b, out);
        }
        Expr::Call(_, args, _) => args.iter().for_each(|a| collect_consts(a, out)),
    }
}

/// Constants of a value that is used whole (an assignment's right side, a word): a plain literal needs
/// no slot.
fn collect_value_consts(e: &Expr, out: &mut Vec<f64>) {
    if literal(e).is_none() {
        collect_consts(e, out);
    }
}

/// Registers for constants at most (the rest of 65 535 slots is for temporaries).
const CONST_SLOTS: u32 = 16_384;

/// Lowers one checked program.
pub fn lower_program(
    p: &ProgramAst,
    st: &Structure,
    src: &SourceMap,
    options: &crate::Options,
    strings: &mut Vec<String>,
    diags: &mut Vec<Diagnostic>,
) -> Option<Function> {
    // Constant slots first, after #0 and the locals.
    let mut consts = Vec::new();
    for line in &p.lines {
        for w in &line.words {
            collect_value_consts(&w.value, &mut consts);
        }
        if let Some((s, _)) = line.stmt.as_deref() {
            s.for_each_expr(&mut |e, whole| {
                if whole {
                    collect_value_consts(e, &mut consts)
                } else {
                    collect_consts(e, &mut consts)
                }
            });
        }
    }
    let mut f = Function {
        number: p.number,
        title: u32::MAX,
        ..Function::default()
    };
    let mut const_slots = BitsMap::default();
    let mut next = LOCALS as u32 + 1;
    // The first CONST_SLOTS distinct constants get a register filled at entry (the JIT makes them
    // immediates); any beyond that are loaded into a temporary where they are used (`const_slot`), so
    // a program may hold any number of them.
    for v in consts {
        if next > CONST_SLOTS {
            break;
        }
        if let std::collections::hash_map::Entry::Vacant(e) = const_slots.entry(v.to_bits()) {
            e.insert(next as Slot);
            f.slot_consts.push((next as Slot, v));
            next += 1;
        }
    }
    let mut lw = Lowerer {
        src,
        strings,
        string_ids: HashMap::new(),
        f,
        fixups: Vec::new(),
        labels: Vec::new(),
        line_labels: HashMap::new(),
        goto_fixups: Vec::new(),
        stubs: Vec::new(),
        terminated: false,
        const_slots,
        pool: BitsMap::default(),
        temp_base: next,
        next_temp: next,
        max_temp: next,
        loops: Vec::new(),
        address: None,
        span: p.span,
        m97: options.syntax.m97,
        calls: options.calls.clone(),
        number: p.number,
        haas: options.syntax.haas,
    };
    lw.f.blocks.push(0);
    if !p.title.is_empty() {
        let t = lw.comment_text(&p.title);
        lw.f.title = lw.string(t);
    }
    for &t in &st.targets {
        let l = lw.new_label();
        lw.line_labels.insert(t, l);
    }
    for (i, line) in p.lines.iter().enumerate() {
        lw.span = line.span;
        lw.next_temp = lw.temp_base;
        if let Some(&l) = lw.line_labels.get(&i) {
            lw.start_block(Some(l));
        }
        lw.line(i, line, st, p);
    }
    if !lw.terminated {
        lw.emit(Op::End);
    }
    let stubs = std::mem::take(&mut lw.stubs);
    for (label, number, message, span) in stubs {
        lw.span = span;
        lw.start_block(Some(label));
        let m = lw.string(message);
        lw.emit(Op::Alarm { number, message: m });
    }
    if lw.max_temp > Slot::MAX as u32 {
        diags.push(Diagnostic::error(
            p.span,
            None,
            "program needs more than 65535 value slots",
        ));
        return None;
    }
    lw.f.n_slots = lw.max_temp as Slot;
    lw.finish();
    if st.all_labels {
        let mut labels: Vec<(u32, BlockId)> = st
            .labels
            .iter()
            .filter_map(|(&n, line)| {
                let l = lw.line_labels.get(line)?;
                Some((n, lw.labels[*l as usize]?))
            })
            .collect();
        labels.sort_unstable();
        lw.f.labels = labels;
    }
    Some(lw.f)
}

impl Lowerer<'_> {
    fn new_label(&mut self) -> Label {
        self.labels.push(None);
        (self.labels.len() - 1) as Label
    }

    fn string(&mut self, s: String) -> u32 {
        if let Some(&i) = self.string_ids.get(&s) {
            return i;
        }
        self.strings.push(s.clone());
        let i = (self.strings.len() - 1) as u32;
        self.string_ids.insert(s, i);
        i
    }

    fn comment_text(&self, comments: &[Span]) -> String {
        comments
            .iter()
            .map(|&c| self.src.text(c))
            .collect::<Vec<_>>()
            .join(" ")
    }

    fn line_no(&self, span: Span) -> u32 {
        self.src.file(span.file).line_col(span.start).0
    }

    /// Binds `label` (or a fresh one) to a new block, closing the current one with a jump if needed.
    fn start_block(&mut self, label: Option<Label>) -> Label {
        let label = label.unwrap_or_else(|| self.new_label());
        let current = (self.f.blocks.len() - 1) as BlockId;
        let empty = *self.f.blocks.last().unwrap_or(&0) as usize == self.f.ops.len();
        if empty && !self.terminated {
            self.labels[label as usize] = Some(current);
            return label;
        }
        if !self.terminated {
            self.jump(label);
        }
        self.f.blocks.push(self.f.ops.len() as u32);
        self.labels[label as usize] = Some((self.f.blocks.len() - 1) as BlockId);
        self.terminated = false;
        label
    }

    fn emit(&mut self, op: Op) {
        if self.terminated {
            // Code after a jump: unreachable unless labelled, but it still needs a block.
            self.f.blocks.push(self.f.ops.len() as u32);
            self.terminated = false;
        }
        self.terminated = op.is_terminator();
        self.f.ops.push(op);
        self.f.spans.push(self.span);
    }

    fn jump(&mut self, target: Label) {
        if self.terminated {
            self.f.blocks.push(self.f.ops.len() as u32);
            self.terminated = false;
        }
        self.fixups.push((self.f.ops.len(), target));
        self.emit(Op::Jump { target: 0 });
    }

    fn branch(&mut self, cond: Slot, when: bool, target: Label) {
        if self.terminated {
            self.f.blocks.push(self.f.ops.len() as u32);
            self.terminated = false;
        }
        self.fixups.push((self.f.ops.len(), target));
        self.emit(Op::Branch {
            cond,
            when,
            target: 0,
        });
        // The fall-through successor.
        self.start_block(None);
    }

    fn temp(&mut self) -> Slot {
        let t = self.next_temp;
        self.next_temp += 1;
        self.max_temp = self.max_temp.max(self.next_temp);
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

    fn const_slot(&mut self, v: f64) -> Slot {
        match self.const_slots.get(&v.to_bits()) {
            Some(&s) => s,
            None => {
                // Beyond the constant registers: load it into a temporary.
                let t = self.temp();
                let k = self.pool(v);
                self.emit(Op::Const { dst: t, k });
                t
            }
        }
    }

    fn finish(&mut self) {
        for &(at, label) in &self.fixups {
            let b = self.labels[label as usize].unwrap_or(0);
            match &mut self.f.ops[at] {
                Op::Jump { target } | Op::Branch { target, .. } => *target = b,
                _ => {}
            }
        }
        for (table, entries) in std::mem::take(&mut self.goto_fixups) {
            self.f.goto_tables[table as usize].entries = entries
                .into_iter()
                .map(|(n, l)| {
                    (
                        n,
                        match l {
                            Some(l) => GotoDest::Block(self.labels[l as usize].unwrap_or(0)),
                            None => GotoDest::IntoLoop,
                        },
                    )
                })
                .collect();
        }
    }

    fn line(&mut self, i: usize, line: &Line, st: &Structure, p: &ProgramAst) {
        match line.stmt.as_deref() {
            Some((stmt, span)) => {
                self.span = *span;
                self.stmt(i, stmt, line, st, p);
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
                let mut flow = flow_code(words, self.m97);
                let by_code = if flow.is_none() {
                    code_call(words, &self.calls, self.number)
                } else {
                    None
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
                let mut cancel = false;
                for (j, w) in words.iter().enumerate() {
                    if by_code.as_ref().is_some_and(|c| c.word == j) {
                        continue;
                    }
                    if is_g67(w) {
                        cancel = true;
                        continue;
                    }
                    if haas_branch.is_some() && (w.letter == Letter::P || code_of(w) == Some(990)) {
                        continue;
                    }
                    self.span = w.span;
                    self.address = Some(w.letter);
                    match literal(&w.value) {
                        Some((v, no_point)) => {
                            let k = self.pool(v);
                            let flags = WordFlags(
                                if no_point { WordFlags::NO_POINT } else { 0 }
                                    | if w.incremental {
                                        WordFlags::INCREMENTAL
                                    } else {
                                        0
                                    },
                            );
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
                                flags: WordFlags(if w.incremental {
                                    WordFlags::INCREMENTAL
                                } else {
                                    0
                                }),
                                src: s,
                            });
                        }
                    }
                    self.address = None;
                }
                self.span = line.span;
                let comment = if line.comments.is_empty() {
                    u32::MAX
                } else {
                    let t = self.comment_text(&line.comments);
                    self.string(t)
                };
                let info = BlockInfo {
                    line: self.line_no(line.span),
                    block_delete: line.block_delete,
                    comment,
                };
                self.f.infos.push(info);
                let info = (self.f.infos.len() - 1) as u32;
                if cancel {
                    self.emit(Op::CancelModal);
                }
                match flow {
                    Some(FlowCode::Call(kind)) => self.emit(Op::Call { kind, info }),
                    Some(FlowCode::Return) => self.emit(Op::Return { info }),
                    None => self.emit(Op::EmitBlock { info }),
                }
                if let Some(target) = haas_branch {
                    self.goto(i, &target, None, st, p);
                }
            }
        }
    }

    fn goto_label(
        &mut self,
        from: usize,
        n: u32,
        span: Span,
        st: &Structure,
        p: &ProgramAst,
    ) -> Label {
        let name = match p.number {
            Some(n) => format!("O{n:04}"),
            None => "the program".to_string(),
        };
        match st.labels.get(&n) {
            Some(&t) if st.jumps_into_loop(from, t).is_none() => {
                self.line_labels.get(&t).copied().unwrap_or(0)
            }
            Some(_) => {
                let l = self.new_label();
                self.stubs.push((
                    l,
                    alarm::SEQUENCE_NUMBER as u16,
                    format!("GOTO{n} jumps into a DO range from outside it"),
                    span,
                ));
                l
            }
            None => {
                let l = self.new_label();
                self.stubs.push((
                    l,
                    alarm::SEQUENCE_NUMBER as u16,
                    format!("sequence number N{n} not found in {name}"),
                    span,
                ));
                l
            }
        }
    }

    fn goto(
        &mut self,
        from: usize,
        target: &GotoTarget,
        cond: Option<Slot>,
        st: &Structure,
        p: &ProgramAst,
    ) {
        match target {
            GotoTarget::Seq(n, span) => {
                let l = self.goto_label(from, *n, *span, st, p);
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
                let mut entries: Vec<(u32, Option<Label>)> = st
                    .labels
                    .iter()
                    .map(|(&n, &t)| {
                        let ok = st.jumps_into_loop(from, t).is_none();
                        (
                            n,
                            ok.then(|| self.line_labels.get(&t).copied().unwrap_or(0)),
                        )
                    })
                    .collect();
                entries.sort_by_key(|e| e.0);
                self.f.goto_tables.push(GotoTable::default());
                let table = (self.f.goto_tables.len() - 1) as u32;
                self.goto_fixups.push((table, entries));
                self.emit(Op::Goto { src: s, table });
                if let Some(after) = after {
                    self.start_block(Some(after));
                }
            }
        }
    }

    fn stmt(&mut self, i: usize, stmt: &Stmt, line: &Line, st: &Structure, p: &ProgramAst) {
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
                self.goto(i, target, Some(c), st, p);
            }
            Stmt::Goto(target) => self.goto(i, target, None, st, p),
            Stmt::IfThen { cond, then, .. } => {
                let c = self.cond(cond);
                let after = self.new_label();
                self.branch(c, false, after);
                self.next_temp = self.temp_base;
                self.stmt(i, then, line, st, p);
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
            Stmt::IfThenWords { .. } => {}
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
        if let Some((v, _)) = literal(e) {
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
            Expr::Bin(op, a, b, _) => {
                let sa = self.expr(a, None);
                let sb = self.expr(b, None);
                let d = dst.unwrap_or_else(|| self.temp());
                self.emit(Op::Bin {
                    op: *op,
                    dst: d,
                    a: sa,
                    b: sb,
                });
                d
            }
            Expr::Cmp(op, a, b, _) => {
                let sa = self.expr(a, None);
                let sb = self.expr(b, None);
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
