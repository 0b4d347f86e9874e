//! The program read and compiled (or found to run straight from its file) under the control's
//! parameters; `check`'s report of one program.

use std::path::Path;

use fmsvm_canon::decode::InputRules;
use fmsvm_compiler::{Options, Program, SourceMap};
use fmsvm_kernel::{Kernel, Settings};

use crate::exit::{Exit, Failure};
use crate::input::{Charset, ReadError, decode};
use crate::library::Folders;
use crate::report::{Reporter, plain};
use crate::request::{Control, FastPath, Input, InputSyntax, LatheX, Machine, MacroDialect};

use super::*;

/// A compiled program with what was learnt reading it.
pub(super) struct Compiled {
    /// The program file's name in messages (`<stdin>` for `-`).
    pub(super) name: String,
    pub(super) program: Program,
    pub(super) sources: SourceMap,
    /// Warnings reported.
    pub(super) warnings: usize,
    /// The character set the program was read in.
    pub(super) charset: Charset,
    /// The control's parameters the program was compiled under (profile, file, flags not applied).
    pub(super) params: crate::params::Params,
    /// An NC-only program that runs straight from its file (`flat`): then `program` is only its O
    /// number and name, and `sources` does not hold its text.
    pub(super) flat: Option<crate::flat::FlatProgram>,
}

/// The control's parameters: `--control`'s profile, then `--params FILE` over it.
pub fn load_params(
    control: Option<Control>,
    file: Option<&Path>,
    max_input: u64,
) -> Result<crate::params::Params, Failure> {
    let base = crate::params::profile(control.unwrap_or(Control::Fanuc0i));
    let Some(path) = file else {
        return Ok(base);
    };
    parse_input("--params", path, max_input, |name, text| {
        crate::params::parse(name, text, base)
    })
}

/// Whether the program is a Haas's (`--control haas`, `haas-lathe`, `--macro-dialect haas`): its
/// macro syntax, its codes, and on a lathe its own output dialect.
pub(super) fn haas_program(a: &Input, params: &crate::params::Params) -> bool {
    a.macro_dialect.or(params.dialect) == Some(MacroDialect::Haas)
}

/// Whether the program may run without compiling (`flat`): a file (not standard input), Fanuc syntax
/// with Fanuc's macro rules, no code bound to a call. The file's lines decide the rest.
pub(super) fn flat_candidate(a: &Input, params: &crate::params::Params) -> bool {
    a.file.as_os_str() != "-"
        && a.macro_dialect
            .or(params.dialect)
            .unwrap_or(MacroDialect::Fanuc)
            == MacroDialect::Fanuc
        && a.input_syntax
            .or(params.input)
            .unwrap_or(InputSyntax::Fanuc)
            == InputSyntax::Fanuc
        && !(a.m97 || params.m97.unwrap_or(false))
        && !params.calls.any()
        && !a.without.contains(&FastPath::Flat)
}

/// `check` of one program: its exit and its warnings.
pub fn check_one(input: &Input, deny_warnings: bool) -> (Exit, usize) {
    match compile(input, false) {
        Ok(c) => {
            let name = &c.name;
            let n = c.program.functions.len();
            let w = c.warnings + unmodelled_variables(&c, input.quiet);
            let ws = if w == 1 { "" } else { "s" };
            let ps = if n == 1 { "" } else { "s" };
            if deny_warnings && w > 0 {
                plain(&format!(
                    "{name}: {w} warning{ws}, denied by --deny-warnings; no errors"
                ));
                return (Exit::Compile, w);
            }
            if !input.quiet {
                plain_info(&format!(
                    "{name}: no errors, {w} warning{ws}; {n} program{ps} compiled"
                ));
            }
            (Exit::Success, w)
        }
        Err(e) => (e, 0),
    }
}

/// `check`'s warnings for the system variables the program names that fmsvm does not model (nor
/// the parameters declare): a run stops where it reads or writes one (alarm 0115). One warning a
/// variable and program; returns how many were given.
pub(super) fn unmodelled_variables(c: &Compiled, quiet: bool) -> usize {
    use fmsvm_block::Machine as _;
    use fmsvm_compiler::ir::Op;
    let settings = Settings {
        variables: c.params.variables.clone(),
        lathe: (c.params.machine == Some(Machine::Lathe)).then_some(fmsvm_kernel::Lathe {
            diameter: c.params.lathe_x != Some(LatheX::Radius),
            max_rpm: c.params.max_rpm,
            y_axis: c.params.y_axis,
        }),
        ..Settings::default()
    };
    let probe = || {
        Kernel::with_settings(
            fmsvm_emit::stats::Stats::new([f64::NAN; 6]),
            InputRules::default(),
            settings.clone(),
        )
    };
    let reporter = Reporter::new(&c.sources);
    // Each variable is asked of the kernel once, reading and writing, whatever the programs.
    let mut verdicts: std::collections::HashMap<(u32, bool), bool> = Default::default();
    let mut count = 0;
    for f in &c.program.functions {
        let mut seen = std::collections::HashSet::new();
        for (i, op) in f.ops.iter().enumerate() {
            let (number, write) = match *op {
                Op::LoadSystem { number, .. } => (number, false),
                Op::StoreSystem { number, .. } => (number, true),
                _ => continue,
            };
            if seen.contains(&number) {
                continue;
            }
            let unmodelled = *verdicts.entry((number, write)).or_insert_with(|| {
                let result = if write {
                    probe().write_system(number, 0.0)
                } else {
                    probe().read_system(number).map(|_| ())
                };
                matches!(result, Err(fmsvm_block::Stop::Alarm(a)) if fmsvm_kernel::is_not_modelled(&a))
            });
            if !unmodelled {
                continue;
            }
            seen.insert(number);
            count += 1;
            if !quiet {
                reporter.diagnostic(
                    &fmsvm_compiler::Diagnostic::warning(
                        f.spans.get(i),
                        Some(115),
                        format!("fmsvm does not model #{number}: a run stops here (alarm 0115)"),
                    )
                    .note(
                        "if the control has it, declare it in --params: [variables] values or ranges (docs/params.md)",
                    ),
                );
            }
        }
    }
    count
}

/// The compiler's options for a program read with `a` and the control's parameters `params`:
/// the macro dialect and input syntax, M97, block delete, bound codes, commons and the logic level
/// (`check`, `run` and the language server read programs so).
pub fn compile_options(a: &Input, params: &crate::params::Params) -> Options {
    let dialect = a
        .macro_dialect
        .or(params.dialect)
        .unwrap_or(MacroDialect::Fanuc);
    let input = a
        .input_syntax
        .or(params.input)
        .unwrap_or(InputSyntax::Fanuc);
    let mut syntax = match (dialect, input) {
        (MacroDialect::Haas, _) => fmsvm_compiler::Syntax::HAAS,
        (_, InputSyntax::Nct) => fmsvm_compiler::Syntax::NCT,
        _ => fmsvm_compiler::Syntax::FANUC,
    };
    syntax.m97 |= a.m97 || params.m97.unwrap_or(false);
    Options {
        block_delete: a.block_delete,
        syntax,
        calls: params.calls.clone(),
        commons: params.commons,
        logic: a.logic_level.or(params.logic_level).unwrap_or_default(),
        // Tests that hold the flat path to the compiler take the compiler's full grammar too.
        parse_every_line: a.without.contains(&FastPath::Flat),
    }
}

/// The program compiled (`fmsvm ir`): every diagnostic rendered.
pub fn compile_program(a: &Input) -> Result<Program, Exit> {
    compile(a, false).map(|c| c.program)
}

/// Loads and compiles (with the library folders); renders every diagnostic.
pub(super) fn compile(a: &Input, allow_flat: bool) -> Result<Compiled, Exit> {
    use crate::report::{MAX_ERRORS, count};
    let name = if a.file.as_os_str() == "-" {
        "<stdin>".to_string()
    } else {
        a.file.display().to_string()
    };
    if let Err(e) = Folders::check(&a.libs) {
        plain(&e);
        return Err(Exit::Io);
    }
    let params = load_params(a.control, a.params.as_deref(), a.max_input).map_err(Failure::say)?;
    let flat = if allow_flat && a.text.is_none() && flat_candidate(a, &params) {
        match std::fs::metadata(&a.file) {
            Ok(m) if m.is_file() && m.len() <= a.max_input => {
                crate::flat::scan(&a.file).ok().flatten()
            }
            _ => None,
        }
    } else {
        None
    };
    // An NC-only program is not compiled: a stub holds its number and name.
    let bytes = match &flat {
        Some(f) => match f.number {
            Some(n) => format!("O{n} {}\nM30\n", f.title).into_bytes(),
            None => b"M30\n".to_vec(),
        },
        None => match &a.text {
            Some(text) if text.len() as u64 > a.max_input => {
                plain(&format!(
                    "cannot read {name}: {}",
                    ReadError::TooBig(a.max_input)
                ));
                return Err(Exit::Limit);
            }
            Some(text) => text.as_bytes().to_vec(),
            None => read_file("", &a.file, a.max_input).map_err(Failure::say)?,
        },
    };
    let decoded = match decode(bytes, a.encoding) {
        Ok(d) => d,
        Err(e) => {
            plain(&format!("{name}:{}:{}: {}", e.line, e.column, e.message));
            return Err(Exit::Compile);
        }
    };
    if let Some(w) = &decoded.guessed
        && !a.quiet
    {
        plain_info(&format!("warning: {name}: {w}"));
    }
    let text = decoded.text;
    let mut sources = SourceMap::new();
    let id = sources.add(name.clone(), text);
    let options = compile_options(a, &params);
    let mut library = Folders::new(a.libs.clone(), a.encoding, a.max_input);
    let (program, diags) = fmsvm_compiler::compile(&mut sources, id, &options, &mut library);
    for s in &library.skipped {
        plain(&format!("library: {s}"));
    }
    if !a.quiet {
        for w in &library.warnings {
            plain_info(&format!("warning: {w}"));
        }
    }
    let reporter = Reporter::new(&sources);
    // The first MAX_ERRORS errors are shown (with the warnings among them); one line counts the rest.
    let (mut shown, mut hidden_errors, mut hidden_warnings) = (0usize, 0usize, 0usize);
    for d in &diags {
        if !d.is_error() && a.quiet {
            continue;
        }
        if shown >= MAX_ERRORS {
            if d.is_error() {
                hidden_errors += 1;
            } else {
                hidden_warnings += 1;
            }
            continue;
        }
        reporter.diagnostic(d);
        shown += usize::from(d.is_error());
    }
    if hidden_errors + hidden_warnings > 0 {
        let mut what = count(hidden_errors, "more error", "more errors");
        if hidden_warnings > 0 {
            what = format!(
                "{what} and {}",
                count(hidden_warnings, "warning", "warnings")
            );
        }
        plain(&format!(
            "{what} not shown (only the first {MAX_ERRORS} errors are)"
        ));
    }
    let warnings = diags.iter().filter(|d| !d.is_error()).count();
    match program {
        Some(p) => Ok(Compiled {
            name,
            program: p,
            sources,
            warnings,
            charset: decoded.charset,
            params,
            flat,
        }),
        None => {
            let n = diags.iter().filter(|d| d.is_error()).count();
            // Name the files that hold the errors (a library program's errors are in its own file).
            let mut files: Vec<&str> = Vec::new();
            for d in diags.iter().filter(|d| d.is_error()) {
                let name = sources.file(d.span.file).name.as_str();
                if !files.contains(&name) {
                    files.push(name);
                }
            }
            if files.is_empty() {
                files.push(sources.file(id).name.as_str());
            }
            plain(&format!(
                "{} in {}; nothing was run",
                count(n, "error", "errors"),
                files.join(", ")
            ));
            Err(Exit::Compile)
        }
    }
}
