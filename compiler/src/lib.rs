//! fmsvm-compiler: Fanuc Custom Macro B text → checked syntax tree → bytecode IR.
//!
//! `compile` never stops at the first problem: it returns every diagnostic it found, and a program
//! only when none of them is an error (the rust-analyzer rule: broken input is normal, not an exception).
//! The crate does no I/O; the caller loads the text into a [`SourceMap`].
#![deny(missing_docs)]

pub mod ast;
pub mod check;
pub mod diag;
pub mod ir;
pub mod lexer;
pub mod lower;
pub mod parse;
pub mod span;

#[allow(clippy::all, missing_docs, unused)]
mod grammar {
    include!(concat!(env!("OUT_DIR"), "/grammar.rs"));
}

pub use diag::{Diagnostic, Severity};
pub use ir::Program;
pub use span::{FileId, SourceMap, Span};

/// Compile-time options.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// The block-delete switch is on: lines starting with `/` are skipped entirely.
    pub block_delete: bool,
}

/// Compiles file `main` of `sources`. Returns the program (None if any diagnostic is an error) and all
/// diagnostics, in source order.
pub fn compile(
    sources: &SourceMap,
    main: FileId,
    options: &Options,
) -> (Option<Program>, Vec<Diagnostic>) {
    let mut diags = Vec::new();
    let file = sources.file(main);
    let mut programs = parse::parse_file(main, &file.text, &mut diags);
    if programs.is_empty() && diags.is_empty() {
        diags.push(Diagnostic::error(
            Span::new(main, 0, 0),
            None,
            "the file holds no program (it is empty, or only `%` and comments)",
        ));
    }
    if options.block_delete {
        for p in &mut programs {
            for line in &mut p.lines {
                if line.block_delete {
                    // Keep a lone N word so that GOTO targets stay where they were.
                    line.words
                        .truncate(usize::from(check::seq_number(line).is_some()));
                    line.stmt = None;
                    line.comments.clear();
                }
            }
        }
    }
    let mut structures = Vec::new();
    for p in &programs {
        let name = p
            .number
            .map_or("the program".to_string(), |n| format!("O{n:04}"));
        structures.push(check::check_program(p, &name, file, &mut diags));
    }
    let mut program = None;
    if !diags.iter().any(Diagnostic::is_error) {
        let mut prog = Program::default();
        for (p, st) in programs.iter().zip(&structures) {
            if let Some(f) = lower::lower_program(p, st, sources, &mut prog.strings, &mut diags) {
                prog.functions.push(f);
            }
        }
        if !diags.iter().any(Diagnostic::is_error) {
            program = Some(prog);
        }
    }
    diags.sort_by_key(|d| (d.span.file.0, d.span.start));
    (program, diags)
}

/// Compiles a program given as text (for tests and tools).
pub fn compile_str(text: &str, options: &Options) -> (Option<Program>, Vec<Diagnostic>, SourceMap) {
    let mut sources = SourceMap::new();
    let id = sources.add("<input>", text);
    let (p, d) = compile(&sources, id, options);
    (p, d, sources)
}
