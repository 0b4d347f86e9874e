//! fmsvm-compiler: Fanuc Custom Macro B text → checked syntax tree → bytecode IR.
//!
//! `compile` never stops at the first problem: it returns every diagnostic it found, and a program
//! only when none of them is an error (the rust-analyzer rule: broken input is normal, not an exception).
//! The crate does no I/O; the caller loads the text into a [`SourceMap`].
#![deny(missing_docs)]
#![forbid(unsafe_code)]

mod ast;
mod check;
mod descent;
mod diag;
mod foreign;
/// The IR the compiler lowers to (its own crate, `fmsvm-ir`, the VM's only front-end dependency).
pub use fmsvm_ir as ir;
mod lexer;
mod lower;
pub mod outline;
mod parse;
pub mod plain;
pub mod precedence;
mod print;
pub use fmsvm_ir::span;

#[allow(clippy::all, missing_docs, unused)]
mod grammar {
    include!(concat!(env!("OUT_DIR"), "/grammar.rs"));
}

/// The repository's own programs, for tests that run the front end over all of them.
#[cfg(test)]
pub(crate) fn test_programs(extensions: &[&str]) -> Vec<std::path::PathBuf> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut dirs = vec![root.join("tests"), root.join("samples")];
    let mut found = Vec::new();
    while let Some(d) = dirs.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries.flatten() {
            let path = e.path();
            if path.is_dir() {
                dirs.push(path);
            } else if path
                .extension()
                .is_some_and(|x| extensions.iter().any(|e| x == *e))
            {
                found.push(path);
            }
        }
    }
    found.sort();
    found
}

pub use diag::{Diagnostic, Severity};
pub use ir::Program;
pub use span::{FileId, SourceMap, Span};

/// Compile-time options.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// The block-delete switch is on: lines starting with `/` are skipped entirely.
    pub block_delete: bool,
    /// Where AND, OR and XOR bind (macro-b-rules E7).
    pub logic: precedence::LogicLevel,
    /// Which control's program text this is.
    pub syntax: Syntax,
    /// The codes the control's parameters bind to programs (G100 → O9010 …).
    pub calls: CodeCalls,
    /// The common variables the control has (#100–#199 and #500–#999 unless its parameters say
    /// otherwise); a number outside them is alarm 0115.
    pub commons: ir::CommonRanges,
    /// Read every line with the full grammar: a line of the plain subset (words only, a CAM file's
    /// line) is otherwise decoded straight from the text ([`plain`]) and packed as a literal block,
    /// with the same result. For tests that hold the two ways to the same program.
    pub parse_every_line: bool,
}

/// Macro and subprogram calls by G, M, T, S and second-auxiliary-function codes: the control's
/// parameters 6050–6059, 6071–6079, 6080–6089 and 6001#5 (Fanuc 0i-MF operator's manual B-64604EN,
/// "Custom macro": "Macro call using a G code", "using an M code", "Subprogram call using an M code",
/// "using a T code"), the S and B code calls (docs/params.md gives their sources).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct CodeCalls {
    /// 6050–6059: the G code that calls O9010–O9019 as G65 does, with arguments.
    pub g_macro: [Option<fmsvm_block::Code>; 10],
    /// 6080–6089: the M code that calls O9020–O9029 as a macro, with arguments. Bound M codes are
    /// whole numbers of up to eight digits (the parameters' range), so they are kept as integers.
    pub m_macro: [Option<u32>; 10],
    /// 6071–6079: the M code that calls O9001–O9009 as a subprogram (as M98).
    pub m_sub: [Option<u32>; 9],
    /// 6001#5: a T code calls O9000 as a subprogram, the T value in #149.
    pub t_sub: bool,
    /// An S code calls O9029 as a subprogram, the S value in #147.
    pub s_sub: bool,
    /// The second auxiliary function's address (B, unless the control moves it): its code calls O9028
    /// as a subprogram, the value in #146. None: the address is an ordinary word (an axis).
    pub b_sub: Option<fmsvm_block::Letter>,
}

impl CodeCalls {
    /// Whether any code is bound.
    pub fn any(&self) -> bool {
        self.t_sub
            || self.s_sub
            || self.b_sub.is_some()
            || self.g_macro.iter().any(Option::is_some)
            || self.m_macro.iter().any(Option::is_some)
            || self.m_sub.iter().any(Option::is_some)
    }

    /// The programs the codes call.
    pub fn programs(&self) -> Vec<u32> {
        let mut v = Vec::new();
        if self.t_sub {
            v.push(9000);
        }
        for (k, c) in self.m_sub.iter().enumerate() {
            if c.is_some() {
                v.push(9001 + k as u32);
            }
        }
        for (k, c) in self.g_macro.iter().enumerate() {
            if c.is_some() {
                v.push(9010 + k as u32);
            }
        }
        for (k, c) in self.m_macro.iter().enumerate() {
            if c.is_some() {
                v.push(9020 + k as u32);
            }
        }
        if self.b_sub.is_some() {
            v.push(9028);
        }
        if self.s_sub {
            v.push(9029);
        }
        v
    }
}

/// The input's syntax: what the program text of a control allows beyond Fanuc Custom Macro B. One
/// description per input dialect (`Syntax::FANUC`, `HAAS`, `NCT`), each feature a field.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Syntax {
    /// Haas macro syntax: `IF [..] #n=..` without THEN (L2), comparisons as values (E9), `M99 Pn` in a
    /// subprogram branching to Nn of that program instead of returning (C9).
    pub haas: bool,
    /// `M97 P…` calls the local subprogram at sequence number P (Haas); off, M97 is an ordinary word.
    pub m97: bool,
    /// NCT words: the incremental operator after an address (`XI10`: incremental in that block, for
    /// that address), a channel number after POPEN and PCLOS (`POPEN31`).
    pub nct: bool,
}

impl Syntax {
    /// Fanuc Custom Macro B.
    pub const FANUC: Syntax = Syntax {
        haas: false,
        m97: false,
        nct: false,
    };
    /// Haas (its macro rules and M97).
    pub const HAAS: Syntax = Syntax {
        haas: true,
        m97: true,
        nct: false,
    };
    /// The NCT milling controls (100M/2000M/99M): Fanuc's macro language with NCT words.
    pub const NCT: Syntax = Syntax {
        haas: false,
        m97: false,
        nct: true,
    };
}

/// Where programs that the file calls but does not hold are found (a library search path). The
/// compiler asks; the caller does the I/O.
pub trait Library {
    /// The file holding program `number`: its name and text.
    fn find(&mut self, number: u32) -> Option<(String, String)>;
}

/// A library with nothing in it.
pub struct NoLibrary;

impl Library for NoLibrary {
    fn find(&mut self, _: u32) -> Option<(String, String)> {
        None
    }
}

/// The program numbers a line calls with a literal P (M98, G65, G66), decoding `M98 P00051000`
/// (count in the digits left of the last four, macro-b-rules C8).
fn static_callee(line: &ast::Line, flow: Option<lower::FlowCode>) -> Option<u32> {
    use lower::FlowCode;
    let kind = match flow? {
        FlowCode::Call(k) => k,
        FlowCode::Return => return None,
    };
    let p = line
        .words
        .iter()
        .find(|w| w.letter == fmsvm_block::Letter::P)?;
    let ast::Expr::Num(n, _) = &p.value else {
        return None;
    };
    // A literal L keeps P whole (C8); a computed L is not known here, and cannot split P either.
    let l = line
        .words
        .iter()
        .find(|w| w.letter == fmsvm_block::Letter::L)
        .map(|w| match &w.value {
            ast::Expr::Num(n, _) => n.value,
            _ => 1.0,
        });
    match kind {
        ir::CallKind::Local => None,
        k => Some(k.target(n.value, l).0),
    }
}

/// Compiles file `main` of `sources`; programs it calls with a literal P that the file does not hold
/// are asked of `library` and added to `sources`. Returns the program (None if any diagnostic is an
/// error) and all diagnostics, in source order. `functions[0]` is the main program.
///
/// The compilation streams: each line is lexed, parsed, checked and lowered as soon as it is read,
/// and its tree dropped, so no file is ever held as a tree (ARCHITECTURE.md, "Compiling a long
/// program"). Lowering stops at the first error; the checks go on to the end.
pub fn compile(
    sources: &mut SourceMap,
    main: FileId,
    options: &Options,
    library: &mut dyn Library,
) -> (Option<Program>, Vec<Diagnostic>) {
    // A program in another control's language is named at its first telling line.
    if let Some(d) = foreign::detect(main, &sources.file(main).text) {
        return (None, vec![d]);
    }
    let mut diags = Vec::new();
    let mut cx = Compilation {
        options,
        drafts: Vec::new(),
        strings: lower::Strings::default(),
        defined: std::collections::HashSet::new(),
        wanted: Vec::new(),
        all_labels: false,
        any_block: false,
        lowering: true,
        seen: 0,
        code_calls: options.calls.any(),
        file_start: 0,
        file_programs: Vec::new(),
    };
    cx.file(sources, main, true, &mut diags);
    if !cx.any_block && diags.is_empty() {
        // Comment lines alone are no program either (they would expand to an empty tape).
        diags.push(Diagnostic::error(
            Span::new(main, 0, 0),
            None,
            "the file holds no program (it is empty, or only `%` and comments)",
        ));
    }
    // Load called programs from the library until nothing new is called.
    let mut asked = std::collections::HashSet::new();
    let mut i = 0;
    while i < cx.wanted.len() {
        let (n, span) = cx.wanted[i];
        i += 1;
        if cx.defined.contains(&n) || !asked.insert(n) {
            continue;
        }
        match library.find(n) {
            Some((name, text)) => {
                let id = sources.add(name, text);
                cx.library_file(sources, id, &mut diags);
            }
            None => diags.push(
                Diagnostic::warning(span, Some(76), format!("program O{n:04} is not in this file nor in the library"))
                    .note("alarm 0076 PROGRAM NOT FOUND is raised if the call runs; give its folder with --lib"),
            ),
        }
    }
    let mut program = None;
    if cx.lowering && !diags.iter().any(Diagnostic::is_error) {
        let all_labels = cx.all_labels;
        program = Some(Program {
            functions: cx
                .drafts
                .into_iter()
                .map(|d| d.layout(all_labels))
                .collect(),
            strings: cx.strings.list,
            commons: options.commons,
        });
    }
    diags.sort_by_key(|d| (d.span.file.0, d.span.start));
    (program, diags)
}

/// What a compilation keeps from line to line and file to file.
struct Compilation<'o> {
    options: &'o Options,
    /// The programs lowered so far, in order (the main program first).
    drafts: Vec<lower::Draft>,
    strings: lower::Strings,
    /// Program numbers seen in any file.
    defined: std::collections::HashSet<u32>,
    /// Programs called with a literal P: (number, calling line).
    wanted: Vec<(u32, Span)>,
    /// Some program returns to a sequence number (`M99 P`) or calls one (`M97`): every labelled line
    /// of every program begins a block (macro-b-rules C9).
    all_labels: bool,
    /// The main file holds a program number or a line with words or a statement.
    any_block: bool,
    /// No error so far: lines are lowered (after one, only checked).
    lowering: bool,
    /// Diagnostics looked at for errors.
    seen: usize,
    /// Some code is bound to a call (`CodeCalls::any`, once).
    code_calls: bool,
    /// Where the drafts of the file being read begin (an error drops those only).
    file_start: usize,
    /// The programs the file being read defines.
    file_programs: Vec<(u32, Span)>,
}

/// The program being read: its checker and (while lowering) its lowerer.
struct Current<'s> {
    checker: check::Checker<'s>,
    lowerer: Option<lower::Lowerer<'s>>,
    number: Option<u32>,
    line: usize,
}

impl Compilation<'_> {
    /// True while no error has been reported (looking only at diagnostics new since the last call).
    fn still_lowering(&mut self, diags: &[Diagnostic]) -> bool {
        if self.lowering && diags[self.seen..].iter().any(Diagnostic::is_error) {
            self.lowering = false;
            self.drafts.truncate(self.file_start);
        }
        self.seen = diags.len();
        self.lowering
    }

    /// Compiles a library file. A file with an error does not stop the run (a control reads a
    /// program only when it is called): its errors become warnings, and each of its programs
    /// raises the first error's alarm when it is called (docs/semantics.md, "Library programs").
    fn library_file(&mut self, sources: &SourceMap, id: FileId, diags: &mut Vec<Diagnostic>) {
        if !self.lowering {
            // The main file has an error already: check this one as it is.
            self.file(sources, id, false, diags);
            return;
        }
        let mut own = Vec::new();
        self.file_start = self.drafts.len();
        self.file_programs.clear();
        self.seen = 0;
        self.file(sources, id, false, &mut own);
        if let Some(first) = own.iter().find(|d| d.is_error()).cloned() {
            self.drafts.truncate(self.file_start);
            self.lowering = true;
            let file = sources.file(id);
            let (line, col) = file.line_col(first.span.start);
            let alarm = first.alarm.unwrap_or(ir::alarm::FORMAT);
            let programs = std::mem::take(&mut self.file_programs);
            let names: Vec<String> = programs.iter().map(|(n, _)| format!("O{n:04}")).collect();
            for d in &mut own {
                if d.is_error() {
                    d.demote(format!(
                        "{} cannot be read, and a control alarms only where it reaches this line: fmsvm raises the alarm when {} is called",
                        file.name,
                        names.join(", ")
                    ));
                }
            }
            for (n, span) in programs {
                let strings = std::mem::take(&mut self.strings);
                let mut lw =
                    lower::Lowerer::new(sources, self.options, Some(n), span, &[], strings);
                lw.unreadable(
                    alarm,
                    format!(
                        "O{n:04} cannot be read: {}:{line}:{col}: {}",
                        file.name, first.message
                    ),
                );
                let st = check::Checker::new(
                    format!("O{n:04}"),
                    file,
                    self.options.syntax,
                    self.options.commons,
                )
                .finish(&mut Vec::new());
                let (draft, strings) = lw.finish(&st, &mut Vec::new());
                self.strings = strings;
                if let Some(d) = draft {
                    self.drafts.push(d);
                }
            }
        }
        diags.extend(own);
        self.file_start = 0;
        self.seen = diags.len();
    }

    /// Compiles every program of file `id` (`main`: the file the user named), line by line.
    fn file(&mut self, sources: &SourceMap, id: FileId, main: bool, diags: &mut Vec<Diagnostic>) {
        let file = sources.file(id);
        let mut current: Option<Current> = None;
        // Codes bound to calls turn words into calls: such lines need the whole tree.
        let plain = !self.options.parse_every_line && !self.options.calls.any();
        parse::parse_stream(
            id,
            &file.text,
            plain,
            diags,
            &mut |event, diags| match event {
                parse::Event::Program {
                    number,
                    span,
                    title,
                } => {
                    if let Some(c) = current.take() {
                        self.finish(c, diags);
                    }
                    if main {
                        self.any_block |= number.is_some();
                    }
                    let duplicate = number.is_some_and(|n| !self.defined.insert(n));
                    if let Some(n) = number.filter(|_| !duplicate) {
                        self.file_programs.push((n, span));
                    }
                    if duplicate {
                        diags.push(Diagnostic::warning(
                            span,
                            None,
                            format!(
                                "program O{:04} is defined twice; the first one is used",
                                number.unwrap_or(0)
                            ),
                        ));
                    }
                    let name = number.map_or("the program".to_string(), |n| format!("O{n:04}"));
                    let lowerer = (self.still_lowering(diags) && !duplicate).then(|| {
                        let strings = std::mem::take(&mut self.strings);
                        lower::Lowerer::new(sources, self.options, number, span, &title, strings)
                    });
                    current = Some(Current {
                        checker: check::Checker::new(
                            name,
                            file,
                            self.options.syntax,
                            self.options.commons,
                        ),
                        lowerer,
                        number,
                        line: 0,
                    });
                }
                parse::Event::Line(mut line) => {
                    let Some(c) = current.as_mut() else {
                        return;
                    };
                    self.line(c, &mut line, main, diags);
                }
                parse::Event::Plain(p) => {
                    let Some(c) = current.as_mut() else {
                        return;
                    };
                    self.any_block |= main;
                    let seq = p
                        .block
                        .words()
                        .first()
                        .filter(|w| w.letter == fmsvm_block::Letter::N)
                        .map(|w| w.value as u32);
                    c.checker.plain_line(c.line, seq);
                    if let Some(lw) = self.lowerer(c, diags) {
                        lw.plain_line(seq, &p);
                    }
                    c.line += 1;
                }
            },
        );
        if let Some(c) = current.take() {
            self.finish(c, diags);
        }
    }

    /// One line of the program `c`: the calls it makes, precedence, block delete, checks, lowering.
    fn line(
        &mut self,
        c: &mut Current,
        line: &mut ast::Line,
        main: bool,
        diags: &mut Vec<Diagnostic>,
    ) {
        let options = self.options;
        if main {
            self.any_block |= !line.words.is_empty() || line.stmt.is_some();
        }
        let mut flow = lower::flow_code(&line.words, options.syntax.m97);
        // Haas's `IF [cond] G65 P…`: the guarded block's call is wanted as any other.
        if let Some((_, block)) = line.guarded() {
            let f = lower::flow_code(&block.words, options.syntax.m97);
            if let Some(n) = static_callee(&block, f) {
                self.wanted.push((n, line.span));
            }
        }
        if let Some(n) = static_callee(line, flow).or_else(|| {
            self.code_calls
                .then(|| lower::code_call(&line.words, &options.calls, c.number))
                .flatten()
                .map(|call| call.program)
        }) {
            self.wanted.push((n, line.span));
        }
        precedence::regroup_line(line, options.logic);
        if options.block_delete && line.block_delete {
            // Keep a lone N word so that GOTO targets stay where they were.
            line.words
                .truncate(usize::from(check::seq_number(line).is_some()));
            line.stmt = None;
            line.comments.clear();
            flow = None;
        }
        // `M99 P…` returns to a sequence number of the caller: then every labelled line is a target.
        self.all_labels |= flow == Some(lower::FlowCode::Call(ir::CallKind::Local))
            || (flow == Some(lower::FlowCode::Return)
                && line
                    .words
                    .iter()
                    .any(|w| w.letter == fmsvm_block::Letter::P));
        // M97 is Haas's local subprogram call: elsewhere it is an M code the control's machine
        // builder defines, and a Haas program's bolt circle would silently be missing.
        if !options.syntax.m97
            && let Some(w) = line.words.iter().find(|w| {
                w.letter == fmsvm_block::Letter::M
                    && lower::code_of(w) == Some(fmsvm_block::Code::M97)
            })
        {
            diags.push(
                Diagnostic::warning(
                    w.span,
                    None,
                    "M97 is written as a plain M code: on a Haas it calls the sequence number P of this program",
                )
                .note("a Haas program: give --control haas (or --macro-dialect haas with [macro] m97 = true)"),
            );
        }
        let i = c.line;
        c.checker.line(i, line, diags);
        if let Some(lw) = self.lowerer(c, diags) {
            lw.line(i, line, flow);
        }
        c.line += 1;
    }

    /// The lowerer of program `c`, unless an error has been reported (then it is dropped).
    fn lowerer<'c, 's>(
        &mut self,
        c: &'c mut Current<'s>,
        diags: &[Diagnostic],
    ) -> Option<&'c mut lower::Lowerer<'s>> {
        if !self.still_lowering(diags)
            && let Some(lw) = c.lowerer.take()
        {
            self.strings = lw.into_strings();
        }
        c.lowerer.as_mut()
    }

    /// Ends program `c`: its whole-program checks, then its draft.
    fn finish(&mut self, c: Current, diags: &mut Vec<Diagnostic>) {
        let st = c.checker.finish(diags);
        let Some(lw) = c.lowerer else {
            return;
        };
        if !self.still_lowering(diags) {
            self.strings = lw.into_strings();
            return;
        }
        let (draft, strings) = lw.finish(&st, diags);
        self.strings = strings;
        if let Some(d) = draft {
            self.drafts.push(d);
        }
    }
}

/// Compiles a program given as text (for tests and tools).
pub fn compile_str(text: &str, options: &Options) -> (Option<Program>, Vec<Diagnostic>, SourceMap) {
    let mut sources = SourceMap::new();
    let id = sources.add("<input>", text);
    let (p, d) = compile(&mut sources, id, options, &mut NoLibrary);
    (p, d, sources)
}

#[cfg(test)]
mod verify_compiled {
    use crate::{Options, compile_str};

    /// Every `.nc` file under the repository's `tests/` and `samples/` that compiles gives a program
    /// that verifies.
    #[test]
    fn every_compiled_test_program_verifies() {
        let mut compiled = 0;
        for path in crate::test_programs(&["nc"]) {
            let Ok(text) = std::fs::read_to_string(&path) else {
                continue;
            };
            for options in [
                Options::default(),
                Options {
                    syntax: crate::Syntax::HAAS,
                    ..Options::default()
                },
            ] {
                if let (Some(p), ..) = compile_str(&text, &options) {
                    compiled += 1;
                    if let Err(e) = p.verify() {
                        panic!("{}: {e}", path.display());
                    }
                }
            }
        }
        assert!(compiled > 20, "only {compiled} test programs compiled");
    }
}
