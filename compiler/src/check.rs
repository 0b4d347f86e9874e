//! The checks before anything runs: line shapes (NC words versus macro statements), variable numbers,
//! bracket depth, comparisons only in conditions (line by line, as each is read), DO/END pairing and
//! depth, GOTO targets (at the program's end). The result, a [`Structure`], is what `lower` resolves
//! the jumps by.

use fmsvm_block::{Code, Letter, MAX_WORDS};

use crate::ast::{BinOp, Expr, Func, GotoTarget, Line, Stmt, VarRef, WordAst};
use crate::diag::{Diagnostic, alarm};
use crate::ir::VarClass;
use crate::lexer::Num;
#[cfg(test)]
use crate::parse::ProgramAst;
use crate::span::{SourceFile, Span};

/// Maximum bracket nesting (macro-b-rules E1: 5 levels including function brackets).
pub const MAX_BRACKET_DEPTH: usize = 5;
/// Loop numbers run 1..=3 (macro-b-rules L1, L7).
pub const MAX_LOOP_NUMBER: u32 = 3;

/// Addresses whose value is an integer code or count: a decimal point in a literal is illegal
/// (macro-b-rules V10), and so is a sign on N O M G (E8).
pub fn is_integer_address(l: Letter) -> bool {
    l.class() == fmsvm_block::AddressClass::Integer
}

/// A DO range: from its WHILE/DO line to its END line (indexes into the program's lines).
#[derive(Clone, Copy, Debug)]
pub struct LoopRange {
    /// Line of WHILE…DOm / DOm.
    pub do_line: usize,
    /// Line of ENDm.
    pub end_line: usize,
    /// The whole DO line (for messages).
    pub do_span: Span,
}

impl LoopRange {
    /// A jump target inside the range (the DO line itself is its entry, not inside).
    pub fn holds_target(&self, line: usize) -> bool {
        self.do_line < line && line <= self.end_line
    }
    /// A jump source inside the range.
    pub fn holds_source(&self, line: usize) -> bool {
        self.do_line < line && line < self.end_line
    }
}

/// A value for each sequence number N0–N99999 that has one: a table indexed by the number (400 KB
/// once a program has a sequence number), so a program numbered on every line costs nothing per line.
#[derive(Clone, Debug, Default)]
pub struct SeqTable(Vec<u32>);

impl SeqTable {
    /// The value for `n`.
    pub fn get(&self, n: u32) -> Option<u32> {
        self.0.get(n as usize).copied().filter(|&v| v != u32::MAX)
    }

    /// Sets the value for `n` unless it has one; false when it had.
    pub fn insert_first(&mut self, n: u32, value: u32) -> bool {
        if self.0.is_empty() {
            self.0 = vec![u32::MAX; MAX_SEQUENCE as usize + 1];
        }
        match self.0.get_mut(n as usize) {
            Some(v) if *v == u32::MAX => {
                *v = value;
                true
            }
            _ => false,
        }
    }
}

/// The largest sequence number (macro-b-rules L5).
pub const MAX_SEQUENCE: u32 = 99_999;

/// The control structure of one program, as `lower` needs it to resolve its jumps.
#[derive(Debug, Default)]
pub struct Structure {
    /// Loop ranges, sorted by DO line.
    pub loops: Vec<LoopRange>,
    /// Sequence number → first line with it.
    pub labels: SeqTable,
    /// The program has a computed GOTO (every labelled line is then a target).
    pub computed_goto: bool,
}

impl Structure {
    /// True when a jump from `source` to `target` enters a DO range from outside (L3, L7).
    pub fn jumps_into_loop(&self, source: usize, target: usize) -> Option<&LoopRange> {
        self.loops
            .iter()
            .find(|r| r.holds_target(target) && !r.holds_source(source))
    }
}

/// Checks one program line by line as it is parsed (`line`), then what needs the whole program:
/// unclosed DO ranges and GOTO targets (`finish`). Diagnostics go to the `diags` each call is given.
pub struct Checker<'a> {
    name: String,
    file: &'a SourceFile,
    syntax: crate::Syntax,
    commons: crate::ir::CommonRanges,
    /// Open DO ranges: (m, DO line, `DOm` span, whole line).
    stack: Vec<(u32, usize, Span, Span)>,
    st: Structure,
    /// GOTOs with a literal target: (line, n, span of n).
    gotos: Vec<(usize, u32, Span)>,
}

impl<'a> Checker<'a> {
    /// A checker for the program called `name` in messages.
    pub fn new(
        name: String,
        file: &'a SourceFile,
        syntax: crate::Syntax,
        commons: crate::ir::CommonRanges,
    ) -> Self {
        Checker {
            name,
            file,
            syntax,
            commons,
            stack: Vec::new(),
            st: Structure::default(),
            gotos: Vec::new(),
        }
    }

    fn describe(&self, span: Span) -> String {
        format!("line {}", self.file.line_col(span.start).0)
    }

    /// Checks line `i` of the program (lines are numbered from 0, in order).
    pub fn line(&mut self, i: usize, line: &Line, diags: &mut Vec<Diagnostic>) {
        let haas = self.syntax.haas;
        let commons = self.commons;
        let mut cx = Cx {
            diags,
            haas,
            commons,
        };
        check_line_shape(line, &mut cx);
        // Haas's `IF [cond] <NC block>`: the block is checked as a block.
        if haas && let Some((_, block)) = line.guarded() {
            check_line_shape(&block, &mut cx);
        }
        let diags = cx.diags;
        check_nct_words(line, self.syntax, &self.file.text, diags);
        if let Some(n) = seq_number(line) {
            self.st.labels.insert_first(n, i as u32);
        }
        let haas_branch = haas.then(|| haas_m99_target(line)).flatten();
        let target = match (line.stmt.as_deref(), &haas_branch) {
            (Some((Stmt::Goto(t), _)), _) | (Some((Stmt::IfGoto { target: t, .. }, _)), _) => {
                Some(t)
            }
            (None, Some(t)) => Some(t),
            _ => None,
        };
        match target {
            Some(GotoTarget::Computed(_)) => self.st.computed_goto = true,
            Some(GotoTarget::Seq(n, span)) => self.gotos.push((i, *n, *span)),
            None => {}
        }
        let Some((stmt, _)) = line.stmt.as_deref() else {
            return;
        };
        if let Stmt::IfThen {
            bare: true, cond, ..
        } = stmt
            && !haas
        {
            diags.push(
                Diagnostic::error(cond.span(), Some(alarm::STATEMENT_FORMAT), "IF without THEN or GOTO")
                    .note("docs/semantics.md, row L2: `IF [..] #n=..` is Haas syntax; write THEN, or run with --macro-dialect haas"),
            );
        }
        check_stmt(
            stmt,
            &self.file.text,
            &mut Cx {
                diags,
                haas,
                commons,
            },
        );
        match stmt {
            Stmt::While {
                number, do_span, ..
            }
            | Stmt::Do { number, do_span } => {
                let Some(m) = loop_number(number, *do_span, diags) else {
                    return;
                };
                if let Some(open) = self.stack.iter().find(|o| o.0 == m) {
                    diags.push(
                        Diagnostic::error(
                            *do_span,
                            Some(alarm::LOOP_NUMBER),
                            format!("DO{m} is opened again inside its own range"),
                        )
                        .note(format!(
                            "DO{m} is open since {}; nested loops need different numbers (1 to 3)",
                            self.describe(open.2)
                        )),
                    );
                } else {
                    self.stack.push((m, i, *do_span, line.span));
                }
            }
            Stmt::End { number, span } => {
                let Some(m) = loop_number(number, *span, diags) else {
                    return;
                };
                match self.stack.iter().rposition(|o| o.0 == m) {
                    Some(pos) if pos + 1 == self.stack.len() => {
                        if let Some((_, do_line, _, do_span)) = self.stack.pop() {
                            self.st.loops.push(LoopRange {
                                do_line,
                                end_line: i,
                                do_span,
                            });
                        }
                    }
                    Some(pos) => {
                        let inner = self.stack[self.stack.len() - 1];
                        diags.push(
                            Diagnostic::error(
                                *span,
                                Some(alarm::LOOP_NUMBER),
                                format!("END{m} closes DO{m} while DO{} inside it is still open: DO ranges overlap", inner.0),
                            )
                            .note(format!("DO{} opened at {}, DO{m} at {}", inner.0, self.describe(inner.2), self.describe(self.stack[pos].2))),
                        );
                        self.stack.truncate(pos);
                    }
                    None => diags.push(Diagnostic::error(
                        *span,
                        Some(alarm::LOOP_NUMBER),
                        format!("END{m} without a DO{m} before it"),
                    )),
                }
            }
            _ => {}
        }
    }

    /// Checks line `i`, a line of the plain subset (nothing in it can be wrong): its sequence number.
    pub fn plain_line(&mut self, i: usize, seq: Option<u32>) {
        if let Some(n) = seq {
            self.st.labels.insert_first(n, i as u32);
        }
    }

    /// Ends the program: DO ranges left open, and each GOTO's target (macro-b-rules L3, L5: searched
    /// when the jump runs, so a missing one or one into a DO range is a warning now).
    pub fn finish(mut self, diags: &mut Vec<Diagnostic>) -> Structure {
        let name = &self.name;
        for &(m, _, span, _) in &self.stack {
            diags.push(
                Diagnostic::error(
                    span,
                    Some(alarm::MISSING_END),
                    format!("DO{m} has no END{m} in {name}"),
                )
                .note(format!("close the loop with END{m}")),
            );
        }
        self.st.loops.sort_by_key(|l| l.do_line);
        for &(i, n, span) in &self.gotos {
            match self.st.labels.get(n).map(|t| t as usize) {
                None => diags.push(
                    Diagnostic::warning(
                        span,
                        Some(alarm::SEQUENCE_NUMBER),
                        format!("GOTO{n}: there is no N{n} in {name}"),
                    )
                    .note("the program runs; alarm 128 is raised only if this jump is taken (docs/semantics.md, row L3)"),
                ),
                Some(t) => {
                    if let Some(r) = self.st.jumps_into_loop(i, t) {
                        diags.push(
                            Diagnostic::warning(
                                span,
                                Some(alarm::SEQUENCE_NUMBER),
                                format!("GOTO{n} jumps into a DO range from outside it"),
                            )
                            .note(format!(
                                "the range begins at {}; alarm 128 is raised if this jump is taken (docs/semantics.md, row L3)",
                                self.describe(r.do_span)
                            )),
                        );
                    }
                }
            }
        }
        self.st
    }
}

/// Checks one whole program (the tree at once: for tests).
#[cfg(test)]
pub fn check_program(
    p: &ProgramAst,
    name: &str,
    file: &SourceFile,
    syntax: crate::Syntax,
    commons: &crate::ir::CommonRanges,
    diags: &mut Vec<Diagnostic>,
) -> Structure {
    let mut c = Checker::new(name.to_string(), file, syntax, *commons);
    for (i, line) in p.lines.iter().enumerate() {
        c.line(i, line, diags);
    }
    c.finish(diags)
}

/// Haas: `M99 Pn` branches to Nn of the same program (macro-b-rules C9); the jump it stands for.
pub fn haas_m99_target(line: &Line) -> Option<GotoTarget> {
    if !matches!(
        crate::lower::flow_code(&line.words, false),
        Some(crate::lower::FlowCode::Return)
    ) {
        return None;
    }
    let p = line.words.iter().find(|w| w.letter == Letter::P)?;
    Some(match &p.value {
        Expr::Num(n, s) if !n.point && n.value >= 0.0 && n.value.fract() == 0.0 => {
            GotoTarget::Seq(n.value as u32, *s)
        }
        e => GotoTarget::Computed(e.clone()),
    })
}

/// NCT words outside `--input nct`: the incremental operator (`XI10`) and a POPEN/PCLOS channel
/// number are located errors that name the option; in NCT syntax the operator is refused where it
/// means nothing (integer addresses, G, M).
fn check_nct_words(line: &Line, syntax: crate::Syntax, text: &str, diags: &mut Vec<Diagnostic>) {
    for w in line.words.iter().filter(|w| w.incremental) {
        let l = w.letter;
        if !syntax.nct {
            let written = text
                .get(w.span.start as usize..w.span.end as usize)
                .unwrap_or("");
            let value = written.get(2..).filter(|v| !v.is_empty()).unwrap_or("…");
            diags.push(
                Diagnostic::error(
                    w.span,
                    Some(alarm::FORMAT),
                    format!("`{l}I{value}` is NCT's incremental operator, not Fanuc syntax"),
                )
                .note(format!(
                    "run with --input nct to read NCT programs; in Fanuc syntax the increment is written G91 {l}{value}"
                )),
            );
        } else if !matches!(
            l.class(),
            fmsvm_block::AddressClass::Linear | fmsvm_block::AddressClass::Angular
        ) {
            diags.push(Diagnostic::error(
                w.span,
                Some(alarm::FORMAT),
                format!("`{l}I` is no incremental word: {l} is not a dimension"),
            ));
        }
    }
    if let Some((Stmt::Popen(Some(c)) | Stmt::Pclos(Some(c)), _)) = line.stmt.as_deref()
        && !syntax.nct
    {
        diags.push(
            Diagnostic::error(
                *c,
                Some(alarm::FORMAT),
                "a channel number after POPEN/PCLOS is NCT syntax".to_string(),
            )
            .note("run with --input nct, or write POPEN alone (Fanuc)"),
        );
    }
}

/// The sequence number of a line (its first word, `N` with a literal).
pub fn seq_number(line: &Line) -> Option<u32> {
    match line.words.first() {
        Some(WordAst {
            letter: Letter::N,
            value: Expr::Num(n, _),
            ..
        }) if !n.point && n.value >= 0.0 && n.value <= MAX_SEQUENCE as f64 => Some(n.value as u32),
        _ => None,
    }
}

fn loop_number(n: &Num, span: Span, diags: &mut Vec<Diagnostic>) -> Option<u32> {
    if n.point || n.value.fract() != 0.0 || n.value < 1.0 || n.value > MAX_LOOP_NUMBER as f64 {
        diags.push(
            Diagnostic::error(
                span,
                Some(alarm::LOOP_NUMBER),
                format!("illegal loop number {}: DO and END take 1, 2 or 3", n.value),
            )
            .note("docs/semantics.md, row L7: up to three nested DO ranges, numbered 1 to 3"),
        );
        None
    } else {
        Some(n.value as u32)
    }
}

fn check_line_shape(line: &Line, cx: &mut Cx) {
    let is_call = line.words.iter().any(|w| {
        w.letter == Letter::G && matches!(crate::lower::code_of(w), Some(Code::G65 | Code::G66))
    });
    let haas_dwell = cx.haas && crate::lower::haas_dwell_block(&line.words);
    // A Haas lathe's one-block cycles give D as a length with a point (`G71 P1 Q2 … D0.2`: the
    // depth of cut; G76's first depth): a value there, not a register number.
    let haas_cycle = cx.haas
        && line.words.iter().any(|w| {
            w.letter == Letter::G
                && matches!(crate::lower::code_of(w), Some(c) if (71..=76).contains(&c.whole()) && c.tenths() % 10 == 0)
        });
    for (k, w) in line.words.iter().enumerate() {
        let value = (haas_dwell && w.letter == Letter::P) || (haas_cycle && w.letter == Letter::D);
        check_word(w, k, is_call || value, cx);
    }
    if let Some((_, stmt_span)) = line.stmt.as_deref() {
        let nc: Vec<&WordAst> = line
            .words
            .iter()
            .filter(|w| w.letter != Letter::N)
            .collect();
        if let Some(first) = nc.first() {
            cx.diags.push(
                Diagnostic::error(
                    first.span.to(*stmt_span),
                    Some(alarm::NC_AND_MACRO),
                    "NC words and a macro statement in one block",
                )
                .note("put the macro statement on its own line"),
            );
        }
    }
    // G65/G66 arguments: G is no argument (0129), O and N neither (C2). G codes before the call
    // word are no arguments: they run as their own block first (lower::codes_before_call).
    if is_call {
        let first = crate::lower::codes_before_call(
            &line.words,
            Some(crate::lower::FlowCode::Call(crate::ir::CallKind::Macro)),
        )
        .unwrap_or(0);
        if first > 0 {
            cx.diags.push(
                Diagnostic::warning(
                    line.words[0].span.to(line.words[first - 1].span),
                    None,
                    "the G codes before G65/G66 run as a block of their own, then the call",
                )
                .note("G65 must come before its arguments: a word before it is none (docs/semantics.md)"),
            );
        }
        for (k, w) in line.words.iter().enumerate().skip(first) {
            let call = matches!(crate::lower::code_of(w), Some(Code::G65 | Code::G66))
                && w.letter == Letter::G;
            if call || (k == 0 && w.letter == Letter::N) {
                continue;
            }
            match w.letter {
                Letter::G => cx.diags.push(
                    Diagnostic::error(w.span, Some(129), "G cannot be an argument of G65/G66")
                        .note("docs/semantics.md, row C12, alarm 0129: G is an argument only in G66.1"),
                ),
                Letter::O | Letter::N => cx.diags.push(Diagnostic::error(
                    w.span,
                    Some(alarm::FORMAT),
                    format!(
                        "{} cannot be an argument of G65/G66 (docs/semantics.md, row C2)",
                        w.letter
                    ),
                )),
                _ => {}
            }
        }
    }
    if line.words.len() > MAX_WORDS {
        cx.diags.push(Diagnostic::error(
            line.span,
            Some(alarm::FORMAT),
            format!(
                "{} words in one block; at most {MAX_WORDS} are allowed",
                line.words.len()
            ),
        ));
    }
}

fn check_word(w: &WordAst, position: usize, is_call: bool, cx: &mut Cx) {
    let mut depth = 0;
    if check_expr(&w.value, 0, &mut depth, cx) == Ty::Bool {
        cx.typing(Diagnostic::error(
            w.value.span(),
            Some(alarm::FORMAT),
            "a comparison cannot be the value of an address (docs/semantics.md, row E9)",
        ));
    }
    let (lit, negative) = match &w.value {
        Expr::Num(n, _) => (Some(n), false),
        Expr::Neg(inner, _) => match &**inner {
            Expr::Num(n, _) => (Some(n), true),
            _ => (None, true),
        },
        _ => (None, false),
    };
    // In a call block (G65, G66) M is argument #13, a value like any other (C2): it may be negative.
    if negative
        && (matches!(w.letter, Letter::N | Letter::O | Letter::G)
            || (w.letter == Letter::M && !is_call))
    {
        cx.diags.push(
            Diagnostic::error(
                w.span,
                Some(alarm::MINUS_SIGN),
                format!("illegal use of minus sign: {} takes no sign", w.letter),
            )
            .note("docs/semantics.md, row E8"),
        );
    } else if negative && lit.is_some() && matches!(w.letter, Letter::P | Letter::L) {
        // A program number, sequence number, dwell or repeat count is never negative; a literal one is
        // refused now rather than when the block runs.
        cx.diags.push(
            Diagnostic::error(
                w.span,
                Some(alarm::MINUS_SIGN),
                format!("illegal use of minus sign: {} takes no sign", w.letter),
            )
            .note(
                "P and L (program and sequence numbers, dwell, repeat counts) are never negative",
            ),
        );
    }
    if let Some(n) = lit {
        // G65/G66 arguments are values, not codes: `D5.` is an argument (C5).
        if is_integer_address(w.letter) && n.point && !is_call {
            cx.diags.push(
                Diagnostic::error(
                    w.span,
                    Some(alarm::DECIMAL_POINT),
                    format!(
                        "illegal use of decimal point: {} takes a whole number",
                        w.letter
                    ),
                )
                .note(format!(
                    "write {}{} (docs/semantics.md, row V10; `{}[{}]` is accepted and rounded)",
                    w.letter, n.value as i64, w.letter, n.value
                )),
            );
        }
        if !n.value.is_finite() {
            cx.diags.push(Diagnostic::error(
                w.span,
                Some(alarm::TOO_MANY_DIGITS),
                "number too large",
            ));
        }
    }
    match w.letter {
        Letter::N if position != 0 => cx.diags.push(Diagnostic::error(
            w.span,
            Some(alarm::FORMAT),
            "a sequence number N must begin the block",
        )),
        Letter::N if lit.is_none() => cx.diags.push(Diagnostic::error(
            w.span,
            Some(alarm::FORMAT),
            "a sequence number must be a literal whole number (N1 to N99999)",
        )),
        Letter::N if lit.is_some_and(|n| n.value > 99_999.0) => cx.diags.push(
            Diagnostic::error(
                w.span,
                Some(alarm::TOO_MANY_DIGITS),
                "a sequence number has more than five digits",
            )
            .note("docs/semantics.md, row L5: N1 to N99999"),
        ),
        Letter::O => cx.diags.push(Diagnostic::error(
            w.span,
            Some(alarm::FORMAT),
            "a program number O must stand alone on its line",
        )),
        _ => {}
    }
}

/// What the line checks report to, and whether Haas rules apply (E9: every expression has a truth
/// value there, so comparisons are values and values are conditions).
struct Cx<'a> {
    diags: &'a mut Vec<Diagnostic>,
    haas: bool,
    /// The control's common variables (V4).
    commons: crate::ir::CommonRanges,
}

impl Cx<'_> {
    /// Reports a comparison used as a value or a value used as a condition: an error on Fanuc (E9),
    /// nothing on Haas, where comparisons are 1 or 0.
    fn typing(&mut self, d: Diagnostic) {
        if !self.haas {
            self.diags.push(d);
        }
    }
}

/// True when `e` is a truth value (a comparison, or AND/OR/XOR of comparisons).
pub fn is_condition(e: &Expr) -> bool {
    ty(e) == Ty::Bool
}

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Ty {
    Num,
    Bool,
    Bad,
}

/// The type of an expression: a number, or the truth value of a comparison (E9).
fn ty(e: &Expr) -> Ty {
    match e {
        Expr::Cmp(..) => Ty::Bool,
        Expr::Group(x, _) => ty(x),
        Expr::Bin(BinOp::And | BinOp::Or | BinOp::Xor, ab, _) => match (ty(&ab[0]), ty(&ab[1])) {
            (Ty::Num, Ty::Num) => Ty::Num,
            (Ty::Bool, Ty::Bool) => Ty::Bool,
            _ => Ty::Bad,
        },
        _ => Ty::Num,
    }
}

fn check_stmt(stmt: &Stmt, text: &str, cx: &mut Cx) {
    match stmt {
        Stmt::Assign { target, value } => {
            check_var(target, true, cx);
            check_value(value, cx);
        }
        Stmt::While { cond, .. } => check_cond(cond, cx),
        Stmt::IfGoto { cond, target } => {
            check_cond(cond, cx);
            if let GotoTarget::Computed(e) = target {
                check_value(e, cx);
            }
        }
        Stmt::Goto(GotoTarget::Computed(e)) => check_value(e, cx),
        Stmt::IfThen { cond, then, .. } => {
            check_cond(cond, cx);
            match &**then {
                Stmt::Assign { .. } => check_stmt(then, text, cx),
                _ => cx.diags.push(
                    Diagnostic::error(
                        cond.span(),
                        Some(alarm::STATEMENT_FORMAT),
                        "IF … THEN takes exactly one assignment",
                    )
                    .note("docs/semantics.md, row L6: write IF[…]GOTOn for a jump"),
                ),
            }
        }
        Stmt::Print { binary, body } => {
            let _ = crate::print::parse_body(body.file, text, *body, *binary, cx.diags);
        }
        Stmt::Popen(_) | Stmt::Pclos(_) => {}
        Stmt::IfBlock { cond, words } => {
            check_cond(cond, cx);
            let (Some(first), Some(last)) = (words.first(), words.last()) else {
                return;
            };
            let span = first.span.to(last.span);
            if !cx.haas {
                cx.diags.push(
                    Diagnostic::error(
                        span,
                        Some(alarm::STATEMENT_FORMAT),
                        "an NC block after IF without THEN is Haas's (IF [cond] G65 P…)",
                    )
                    .note("docs/semantics.md, row L6: on a Fanuc jump over the block with IF[…]GOTOn; a Haas program: --control haas"),
                );
            }
        }
        Stmt::IfThenWords { span } => cx.diags.push(
            Diagnostic::error(
                *span,
                Some(alarm::STATEMENT_FORMAT),
                "NC words cannot follow THEN",
            )
            .note("docs/semantics.md, row L6: only one macro statement may follow THEN; jump over the NC block with IF[…]GOTOn instead"),
        ),
        _ => {}
    }
}

fn check_cond(cond: &Expr, cx: &mut Cx) {
    let mut depth = 0;
    // The IF/WHILE bracket itself is the first level.
    match check_expr(cond, 1, &mut depth, cx) {
        Ty::Bool => {}
        _ => cx.typing(
            Diagnostic::error(
                cond.span(),
                Some(alarm::FORMAT),
                "the condition must be a comparison (EQ NE GT GE LT LE)",
            )
            .note("write IF[#1 NE 0] rather than IF[#1]"),
        ),
    }
}

fn check_value(e: &Expr, cx: &mut Cx) {
    let mut depth = 0;
    if check_expr(e, 0, &mut depth, cx) != Ty::Num {
        cx.typing(
            Diagnostic::error(
                e.span(),
                Some(alarm::FORMAT),
                "a comparison is not a value: it can only be the condition of IF or WHILE",
            )
            .note("docs/semantics.md, row E9"),
        );
    }
}

fn check_var(v: &VarRef, is_target: bool, cx: &mut Cx) {
    match v {
        VarRef::Direct { number, span } => {
            if number.point || number.value.fract() != 0.0 {
                let d = Diagnostic::error(
                    *span,
                    Some(alarm::VARIABLE_RANGE),
                    "a variable number is a whole number",
                );
                // Haas NGC reads its settings as #20000 + n and its parameters as #30000 + n; a
                // number with a fraction there (`#30001.116`) appears in vendor macros, but no
                // source at hand says what it reads, so it is refused rather than guessed.
                let d = if cx.haas && (20_000.0..40_000.0).contains(&number.value) {
                    d.note("on the Haas NGC #20000–#29999 read settings and #30000–#39999 parameters; what a fraction after the number selects is not documented in the Haas manuals fmsvm follows, so the read is refused, not guessed: declare the value the program should see as a plain variable (--params [variables] values)")
                } else {
                    d
                };
                cx.diags.push(d);
                return;
            }
            let n = number.value;
            match (n >= 0.0 && n <= u32::MAX as f64)
                .then(|| cx.commons.classify(n as u32))
                .flatten()
            {
                None => {
                    let note = format!(
                        "locals are #1–#33, commons {} (the control's parameters, docs/semantics.md, row V4), system variables #1000 and up",
                        cx.commons.describe()
                    );
                    cx.diags.push(
                        Diagnostic::error(
                            *span,
                            Some(alarm::VARIABLE_RANGE),
                            format!("there is no variable #{n}"),
                        )
                        .note(note),
                    )
                }
                Some(VarClass::Vacant) if is_target => cx.diags.push(
                    Diagnostic::error(
                        *span,
                        Some(alarm::WRITE_PROTECTED),
                        "#0 is always vacant and cannot be assigned",
                    )
                    .note("docs/semantics.md, row V1"),
                ),
                _ => {}
            }
        }
        VarRef::Indirect { addr, .. } => check_value(addr, cx),
    }
}

/// Checks `e` and returns its type (`ty`'s, found in the same walk).
fn check_expr(e: &Expr, level: usize, max: &mut usize, cx: &mut Cx) -> Ty {
    let level_here = match e {
        Expr::Group(..) => level + 1,
        Expr::Call(Func::Atan2 | Func::Pow, args, _) if !matches!(args[0], Expr::Group(..)) => {
            level + 1
        }
        _ => level,
    };
    if level_here > MAX_BRACKET_DEPTH && level <= MAX_BRACKET_DEPTH {
        cx.diags.push(
            Diagnostic::error(
                e.span(),
                Some(alarm::BRACKET_NESTING),
                format!("brackets nested {level_here} deep; at most {MAX_BRACKET_DEPTH} levels are allowed"),
            )
            .note("docs/semantics.md, row E1: function brackets count; split the expression with a variable"),
        );
    }
    *max = (*max).max(level_here);
    match e {
        Expr::Num(n, s) => {
            if !n.value.is_finite() {
                cx.diags.push(Diagnostic::error(
                    *s,
                    Some(alarm::FLOAT_OVERFLOW),
                    "number too large",
                ));
            }
            Ty::Num
        }
        Expr::Var(v) => {
            if let VarRef::Indirect { addr, .. } = v {
                check_expr(addr, level_here, max, cx);
            } else {
                check_var(v, false, cx);
            }
            Ty::Num
        }
        Expr::Neg(x, _) => {
            if check_expr(x, level_here, max, cx) != Ty::Num {
                cx.typing(Diagnostic::error(
                    x.span(),
                    Some(alarm::FORMAT),
                    "a comparison cannot be negated",
                ));
            }
            Ty::Num
        }
        Expr::Bin(op, ab, s) => {
            let ta = check_expr(&ab[0], level_here, max, cx);
            let tb = check_expr(&ab[1], level_here, max, cx);
            let logic = matches!(op, BinOp::And | BinOp::Or | BinOp::Xor);
            let t = match (logic, ta, tb) {
                (false, ..) | (true, Ty::Num, Ty::Num) => Ty::Num,
                (true, Ty::Bool, Ty::Bool) => Ty::Bool,
                _ => Ty::Bad,
            };
            if t == Ty::Bad || (!logic && (ta != Ty::Num || tb != Ty::Num)) {
                cx.typing(Diagnostic::error(
                    *s,
                    Some(alarm::FORMAT),
                    "a comparison cannot be used in arithmetic",
                ));
            }
            t
        }
        Expr::Cmp(_, ab, s) => {
            let ta = check_expr(&ab[0], level_here, max, cx);
            let tb = check_expr(&ab[1], level_here, max, cx);
            if ta != Ty::Num || tb != Ty::Num {
                cx.typing(Diagnostic::error(
                    *s,
                    Some(alarm::FORMAT),
                    "comparisons cannot be chained",
                ));
            }
            Ty::Bool
        }
        Expr::Call(_, args, s) => {
            for a in args {
                if check_expr(a, level_here, max, cx) != Ty::Num {
                    cx.typing(Diagnostic::error(
                        *s,
                        Some(alarm::FORMAT),
                        "a comparison is not a function argument",
                    ));
                }
            }
            Ty::Num
        }
        Expr::Group(x, _) => check_expr(x, level_here, max, cx),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parse::parse_file;
    use crate::span::FileId;

    fn diags(src: &str) -> Vec<Diagnostic> {
        let mut d = Vec::new();
        let p = parse_file(FileId(0), src, &mut d);
        let f = SourceFile::new("t", src);
        for prog in &p {
            check_program(
                prog,
                "O1",
                &f,
                crate::Syntax::FANUC,
                &Default::default(),
                &mut d,
            );
        }
        d
    }

    fn alarms(src: &str) -> Vec<(bool, Option<u32>)> {
        diags(src).iter().map(|d| (d.is_error(), d.alarm)).collect()
    }

    #[test]
    fn bracket_depth_five_ok_six_is_118() {
        assert!(alarms("#1=[[[[[1]]]]]").is_empty());
        assert_eq!(alarms("#1=[[[[[[1]]]]]]"), vec![(true, Some(118))]);
        // Function brackets count (E1): SIN[ is a level.
        assert_eq!(alarms("#1=SIN[[[[[1]]]]]"), vec![]);
        assert_eq!(alarms("#1=SIN[[[[[[1]]]]]]"), vec![(true, Some(118))]);
        // The IF bracket counts too.
        assert_eq!(alarms("IF[[[[[1]]]] EQ 1]GOTO1\nN1"), vec![]);
        assert_eq!(
            alarms("IF[[[[[[1]]]]] EQ 1]GOTO1\nN1"),
            vec![(true, Some(118))]
        );
    }

    #[test]
    fn loops_pair_up() {
        assert!(alarms("WHILE[1 EQ 1]DO1\nDO2\nEND2\nEND1").is_empty());
        assert_eq!(alarms("WHILE[1 EQ 1]DO1\n"), vec![(true, Some(124))]);
        assert_eq!(alarms("END1\n"), vec![(true, Some(126))]);
        assert_eq!(
            alarms("WHILE[1 EQ 1]DO4\nEND4"),
            vec![(true, Some(126)), (true, Some(126))]
        );
        assert_eq!(
            alarms("DO1\nDO2\nEND1\nEND2"),
            vec![(true, Some(126)), (true, Some(126))]
        );
        assert_eq!(
            alarms("DO1\nDO1\nEND1\nEND1"),
            vec![(true, Some(126)), (true, Some(126))]
        );
        // A number may be used again after its END (L7).
        assert!(alarms("DO1\nEND1\nDO1\nEND1").is_empty());
    }

    #[test]
    fn goto_checks_are_warnings() {
        assert_eq!(alarms("GOTO5\n"), vec![(false, Some(128))]);
        assert_eq!(
            alarms("GOTO5\nWHILE[1 EQ 1]DO1\nN5 G0 X1\nEND1"),
            vec![(false, Some(128))]
        );
        // Out of a loop, and to the loop's own END from inside: fine.
        assert!(alarms("WHILE[1 EQ 1]DO1\nGOTO5\nN5 END1").is_empty());
        assert!(alarms("WHILE[1 EQ 1]DO1\nGOTO5\nEND1\nN5 M30").is_empty());
    }

    #[test]
    fn line_shapes() {
        assert_eq!(alarms("G0 X1 #1=2"), vec![(true, Some(127))]);
        assert!(alarms("N10 #1=2").is_empty());
        assert_eq!(alarms("M3.0"), vec![(true, Some(7))]);
        assert!(alarms("M[3.0]").is_empty());
        assert_eq!(alarms("N-10 G0"), vec![(true, Some(6))]);
        assert_eq!(alarms("M-3"), vec![(true, Some(6))]);
        assert_eq!(alarms("#34=1"), vec![(true, Some(115))]);
        assert_eq!(alarms("#0=1"), vec![(true, Some(116))]);
        assert_eq!(alarms("#2=[1 LT 2]"), vec![(true, Some(114))]);
        assert_eq!(alarms("IF[#1]GOTO1\nN1"), vec![(true, Some(114))]);
        assert_eq!(alarms("IF[#1 EQ 2]THEN G00 X5.0"), vec![(true, Some(125))]);
        assert!(alarms("IF[#1 EQ 2]THEN #100=#100+1").is_empty());
        assert!(alarms("IF[[#7 NE #0] AND [#7 GE 0]]GOTO1\nN1").is_empty());
    }
}
