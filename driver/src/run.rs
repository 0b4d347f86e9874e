//! The pipeline behind each subcommand: load, compile, report, run, write; returns the exit code.

use std::io;
use std::path::{Path, PathBuf};
use std::time::{Instant, SystemTime, UNIX_EPOCH};

use fmsvm_block::Stop;
use fmsvm_canon::Emitter;
use fmsvm_canon::decode::InputRules;
use fmsvm_compiler::{Options, Program, SourceMap};
use fmsvm_emit::literal::{self, LiteralEmitter};
use fmsvm_emit::pipelined::Pipelined;
use fmsvm_emit::resolved::ResolvedEmitter;
use fmsvm_kernel::probe::ProbeModel;
use fmsvm_kernel::{Kernel, OutputFrame, Settings};
use fmsvm_vm::{Limits, RunOptions, Variables};

use fmsvm_block::{LimitKind, OutputBudget};

use crate::exit::Exit;
use crate::input::{Charset, Encode, ReadError, decode, read_bounded};
use crate::library::Folders;
use crate::output::{Named, Target, check_distinct, commit_all, write_text};
use crate::port::PrintPort;
use crate::report::{Reporter, plain};
use crate::request::{
    Control, DecimalInput, FastPath, GCodeSystem, Input, InputSyntax, LatheX, Logic, Machine,
    MacroDialect, MainM99, N33G18, Request,
};
use fmsvm_compiler::precedence::LogicLevel;

/// The output dialect: a profile file (`--dialect-file FILE` over its base; the flag that named it
/// beside it), or the built-in `--dialect NAME`.
pub fn load_dialect(
    name: Option<&str>,
    file: Option<(&str, &Path)>,
    max: u64,
) -> Result<crate::dialects::Profile, Exit> {
    match file {
        Some((flag, path)) => {
            let bytes = read_file(flag, path, max)?;
            let Ok(text) = String::from_utf8(bytes) else {
                plain(&format!(
                    "{}: a dialect profile is UTF-8 text",
                    path.display()
                ));
                return Err(Exit::MALFORMED_INPUT);
            };
            crate::dialects::load(&path.display().to_string(), &text).map_err(|e| {
                plain(&e);
                Exit::MALFORMED_INPUT
            })
        }
        None => crate::dialects::builtin(name.unwrap_or("fanuc")).map_err(|e| {
            plain(&e);
            Exit::Usage
        }),
    }
}

/// What consumes the run's output: the flat program, or its canonical operations for a report or a
/// picture.
pub enum Consumer<'a> {
    /// `run`: the flat program (literal, or resolved with `--resolve`) into the request's output.
    Flat,
    /// `dnc`: the flat program into this writer (the link) instead of the output file.
    Into(Box<dyn io::Write + Send + 'a>),
    /// `stats`: the motion report.
    Stats { json: bool },
    /// A front end's own record of the canonical operations (`plot`'s picture), rendered into the
    /// request's output when the run ends.
    Render(&'a mut dyn Render),
}

/// A front end's consumer of the canonical operations: told the run's setting, given every
/// operation, and asked at the end for the bytes of the output file.
pub trait Render {
    /// The run is configured: where the stock is, what the output may take, how far the dialect
    /// reaches, and whether it turns.
    fn start(&mut self, run: RenderStart);
    /// One canonical operation, with the block it came from.
    fn canon(
        &mut self,
        op: &fmsvm_canon::Canon<'_>,
        origin: fmsvm_canon::Origin,
    ) -> Result<(), Stop>;
    /// The output file's bytes, once the run has ended well.
    fn render(&mut self) -> Result<Vec<u8>, String>;
}

/// What a `Render` is told when the run starts.
pub struct RenderStart {
    /// `--stock` in the kernel's terms (a lathe's X as a radius).
    pub stock: Option<[[f64; 3]; 2]>,
    pub budget: OutputBudget,
    pub reach: fmsvm_emit::dialect::Reach,
    /// A turning program: depth is along X.
    pub lathe: bool,
}

/// A `Render` as the kernel's emitter.
struct Rendering<'a>(&'a mut dyn Render);

impl Emitter for Rendering<'_> {
    const CANON: bool = true;

    fn canon(
        &mut self,
        op: &fmsvm_canon::Canon<'_>,
        origin: fmsvm_canon::Origin,
    ) -> Result<(), Stop> {
        self.0.canon(op, origin)
    }
}

/// An error a consumer's own writer stopped the run with, having reported it itself (the DNC link
/// lost, an XOFF held too long, a signal): the run says nothing more and exits with `Exit::Io`.
#[derive(Debug)]
pub struct WriterStop;

impl std::fmt::Display for WriterStop {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("the link stopped the run")
    }
}

impl std::error::Error for WriterStop {}

impl WriterStop {
    /// Whether `e` is a `WriterStop`.
    pub fn is(e: &io::Error) -> bool {
        e.get_ref().is_some_and(|i| i.is::<WriterStop>())
    }
}

/// A compiled program with what was learnt reading it.
struct Compiled {
    /// The program file's name in messages (`<stdin>` for `-`).
    name: String,
    program: Program,
    sources: SourceMap,
    /// Warnings reported.
    warnings: usize,
    /// The character set the program was read in.
    charset: Charset,
    /// The control's parameters the program was compiled under (profile, file, flags not applied).
    params: crate::params::Params,
    /// An NC-only program that runs straight from its file (`flat`): then `program` is only its O
    /// number and name, and `sources` does not hold its text.
    flat: Option<crate::flat::FlatProgram>,
}

/// The control's parameters: `--control`'s profile, then `--params FILE` over it.
pub fn load_params(
    control: Option<Control>,
    file: Option<&Path>,
    max_input: u64,
) -> Result<crate::params::Params, Exit> {
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
fn haas_program(a: &Input, params: &crate::params::Params) -> bool {
    a.macro_dialect.or(params.dialect) == Some(MacroDialect::Haas)
}

/// Whether the program may run without compiling (`flat`): a file (not standard input), Fanuc syntax
/// with Fanuc's macro rules, no code bound to a call. The file's lines decide the rest.
fn flat_candidate(a: &Input, params: &crate::params::Params) -> bool {
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

/// The flags that name a settings file: a regular file of at most `MAX_SETTINGS`.
const SETTINGS_FLAGS: [&str; 7] = [
    "--dialect-file",
    "--params",
    "--offsets",
    "--probe-points",
    "dialects --show",
    "dialects --cycles",
    "dialects --launcher",
];

/// Reads an input file of `flag` within the bound; the error is reported and mapped to its exit code.
/// A settings file is a regular file of at most `MAX_SETTINGS` bytes.
fn read_file(flag: &str, path: &Path, max: u64) -> Result<Vec<u8>, Exit> {
    let settings = SETTINGS_FLAGS.contains(&flag);
    let read = if settings {
        crate::input::read_regular(path, max.min(crate::input::MAX_SETTINGS))
    } else {
        read_bounded(path, max)
    };
    read.map_err(|e| {
        let flag = if flag.is_empty() {
            String::new()
        } else {
            format!("{flag} ")
        };
        let what = match &e {
            ReadError::TooBig(_) if settings => format!(
                "it is larger than {}, the most a settings file may hold",
                crate::input::human(crate::input::MAX_SETTINGS)
            ),
            e => e.to_string(),
        };
        plain(&format!("cannot read {flag}{}: {what}", path.display()));
        match e {
            ReadError::TooBig(_) => Exit::Limit,
            ReadError::Io(_) => Exit::Io,
        }
    })
}

/// An input file a flag names, read (bounded) and parsed by `parse(name, text)`: a file that cannot
/// be read is `read_file`'s error, one that does not parse is reported with
/// `Exit::MALFORMED_INPUT`, the code of every malformed input file.
fn parse_input<T>(
    flag: &str,
    path: &Path,
    max: u64,
    parse: impl FnOnce(&str, &str) -> Result<T, String>,
) -> Result<T, Exit> {
    let bytes = read_file(flag, path, max)?;
    parse(
        &path.display().to_string(),
        &String::from_utf8_lossy(&bytes),
    )
    .map_err(|e| {
        plain(&e);
        Exit::MALFORMED_INPUT
    })
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
fn unmodelled_variables(c: &Compiled, quiet: bool) -> usize {
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
        logic: match a.logic_level.or(params.logic_level).unwrap_or(Logic::Fanuc) {
            Logic::Fanuc => LogicLevel::Fanuc,
            Logic::Additive => LogicLevel::Additive,
            Logic::Lowest => LogicLevel::Lowest,
        },
        // Tests that hold the flat path to the compiler take the compiler's full grammar too.
        parse_every_line: a.without.contains(&FastPath::Flat),
    }
}

/// The program compiled (`fmsvm ir`): every diagnostic rendered.
pub fn compile_program(a: &Input) -> Result<Program, Exit> {
    compile(a, false).map(|c| c.program)
}

/// Loads and compiles (with the library folders); renders every diagnostic.
fn compile(a: &Input, allow_flat: bool) -> Result<Compiled, Exit> {
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
    let params = load_params(a.control, a.params.as_deref(), a.max_input)?;
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
            None => read_file("", &a.file, a.max_input)?,
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

/// Whether the literal emitter's plain blocks are formatted and written by a second thread
/// (`emit::pipelined`): the machine has two cores or more, the program prints nothing (the printed
/// output shares the byte budget, which one thread spends at a time), and `--without pipeline` is
/// not given. The output is the same either way (tests/pipelined.rs).
fn pipelined(a: &Input, program: &fmsvm_compiler::ir::Program) -> bool {
    !a.without.contains(&FastPath::Pipeline)
        && std::thread::available_parallelism().is_ok_and(|n| n.get() >= 2)
        && !program.may_print()
}

/// `OUT` with `.PARTIAL` before its extension.
fn partial_name(out: &Path) -> PathBuf {
    let stem = out
        .file_stem()
        .map_or("out".into(), |s| s.to_string_lossy().into_owned());
    let name = match out.extension() {
        Some(e) => format!("{stem}.PARTIAL.{}", e.to_string_lossy()),
        None => format!("{stem}.PARTIAL"),
    };
    out.with_file_name(name)
}

/// The date and time #3011/#3012 read: the flags, else SOURCE_DATE_EPOCH, else now (UTC).
pub fn clock(a: &Request) -> (u32, u32) {
    let secs = std::env::var("SOURCE_DATE_EPOCH")
        .ok()
        .and_then(|s| s.parse::<u64>().ok())
        .unwrap_or_else(|| {
            SystemTime::now()
                .duration_since(UNIX_EPOCH)
                .map_or(0, |d| d.as_secs())
        });
    let days = (secs / 86_400) as i64;
    // Civil date from days since 1970-01-01 (Howard Hinnant's algorithm).
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    let s = secs % 86_400;
    let date = (y * 10_000 + m * 100 + d) as u32;
    let time = ((s / 3600) * 10_000 + (s / 60 % 60) * 100 + s % 60) as u32;
    (a.date.unwrap_or(date), a.time.unwrap_or(time))
}

/// Where the outputs of a run go, decided before anything runs.
struct Outputs {
    program: Target,
    print: Target,
    dump: Option<Target>,
}

/// Plans every output and refuses a run that would write over an input or write one file twice.
fn plan_outputs(a: &Request) -> Result<Outputs, Exit> {
    let plan = |flag: &str, p: &Path| {
        Target::plan(p).map_err(|e| {
            plain(&format!("{flag}: {e}"));
            Exit::Io
        })
    };
    let program = match &a.output {
        Some(p) => plan("-o", p)?,
        None => Target::Stdout,
    };
    let print = match (&a.print, &program) {
        (Some(p), _) => plan("--print", p)?,
        // Beside the output, else beside the input.
        (None, Target::File { path, .. }) => plan("--print", &path.with_extension("prn"))?,
        (None, _) if a.input.file.as_os_str() == "-" => plan("--print", Path::new("stdin.prn"))?,
        (None, _) => plan("--print", &a.input.file.with_extension("prn"))?,
    };
    let dump = match &a.dump_vars {
        Some(p) => Some(plan("--dump-vars", p)?),
        None => None,
    };
    let mut inputs: Vec<(&str, PathBuf)> = Vec::new();
    if a.input.file.as_os_str() != "-" {
        inputs.push(("the program", a.input.file.clone()));
    }
    if let Some(v) = &a.vars {
        inputs.push(("--vars", v.clone()));
    }
    if let Some(p) = &a.probe_points {
        inputs.push(("--probe-points", p.clone()));
    }
    if let Some(p) = &a.offsets {
        inputs.push(("--offsets", p.clone()));
    }
    if let Some(p) = &a.input.params {
        inputs.push(("--params", p.clone()));
    }
    if let Some(p) = &a.dialect_file {
        inputs.push(("--dialect-file", p.clone()));
    }
    if let Some(p) = &a.verify_file {
        // Read back whole: a regular file (a FIFO would hold the run, a device never end).
        if let Err(e) = crate::input::require_regular(p) {
            plain(&format!("cannot read --verify-file {}: {e}", p.display()));
            return Err(Exit::Io);
        }
        inputs.push(("--verify-file", p.clone()));
    }
    for f in Folders::files(&a.input.libs) {
        inputs.push(("--lib", f));
    }
    let mut named = vec![
        Named {
            flag: "-o",
            target: &program,
        },
        Named {
            flag: "--print",
            target: &print,
        },
    ];
    if let Some(d) = &dump {
        named.push(Named {
            flag: "--dump-vars",
            target: d,
        });
    }
    // The variable store may be updated in place: it is read whole before the run and replaced
    // atomically after it.
    check_distinct(&inputs, &named, &[("--dump-vars", "--vars")]).map_err(|e| {
        plain(&e);
        Exit::Usage
    })?;
    Ok(Outputs {
        program,
        print,
        dump,
    })
}

/// Everything a run takes from its arguments and input files, read and merged in one place: the
/// outputs planned, the dialect profile, the compiled program, the starting variables, offsets and
/// probe model, and the emitter's, the kernel's and the VM's settings.
struct Config {
    outputs: Outputs,
    profile: crate::dialects::Profile,
    /// The output is resolved motion (asked for, or the dialect is not a literal one).
    resolve: bool,
    program: Program,
    sources: SourceMap,
    params: crate::params::Params,
    flat: Option<crate::flat::FlatProgram>,
    out_charset: Charset,
    vars: Variables,
    options: literal::Options,
    rules: InputRules,
    settings: Settings,
    frames: fmsvm_kernel::frames::Frames,
    run_options: RunOptions,
    date: u32,
    time: u32,
    probe: ProbeModel,
}

/// What the run adds to the kernel: tolerances, the output frame, the compensation style, the
/// power-on state, the start point, the cycle parameters (flags over `--params`).
fn kernel_settings(
    a: &Request,
    params: &crate::params::Params,
    plain_paths: bool,
    lathe: Option<fmsvm_kernel::Lathe>,
    power_on: fmsvm_canon::modal::ModalState,
) -> Settings {
    Settings {
        lathe,
        arc_tolerance: a.arc_tolerance,
        linearize: a.linearize,
        frame: a.frame,
        comp_style: a.comp_style,
        power_on,
        start_point: a
            .start_point
            .or(params.start_point)
            .unwrap_or([f64::NAN; 6]),
        strict_axes: a.strict_axes,
        arc_intersections: a.input.input_syntax.or(params.input) == Some(InputSyntax::Nct),
        plain_moves: plain_paths,
        variables: params.variables.clone(),
        arc_centre: params.arc_centre.unwrap_or_default(),
        mill_threads: false,
        control_offsets: fmsvm_kernel::ControlOffsets::default(),
        tool_tip: false,
        // G51's P I J K without a point: Fanuc's least increment of magnification (0.001 unless
        // the parameters say 0.00001); the NCT textbook writes the factor itself (`P2`: ×2).
        scaling_unit: if a.input.input_syntax.or(params.input) == Some(InputSyntax::Nct) {
            0.0
        } else {
            params.scaling_unit.unwrap_or(0.001)
        },
        haas_codes: haas_program(&a.input, params),
        // Set where the dialect is known (`configure`).
        haas_output: false,
        // The run's own, set where it is made (`configure`).
        budget: fmsvm_block::OutputBudget::default(),
        cycles: {
            let mut c = fmsvm_kernel::cycles::CycleParams::default();
            if let Some(v) = params.g73_retract {
                c.g73_retract = v;
            }
            if let Some(v) = params.g83_clearance {
                c.g83_clearance = v;
            }
            c.stock_retract = params.haas_setting_73;
            c.thread_allowance = params.haas_setting_86;
            c.thread_least = params.haas_setting_99;
            c.thread_chamfer = params.haas_setting_95;
            c
        },
    }
}

/// How the VM runs: the engine, the limits, the print and M99 rules, the arithmetic's options
/// (flags over `--params`).
fn run_options(a: &Request, params: &crate::params::Params) -> RunOptions {
    RunOptions {
        engine: a.engine,
        limits: Limits {
            max_steps: a.max_steps,
            max_blocks: a.max_blocks,
            // Bounded when parsed (MAX_SECONDS), so the conversion cannot fail.
            max_time: a
                .max_seconds
                .and_then(|s| std::time::Duration::try_from_secs_f64(s).ok()),
        },
        print_without_popen: a.print_without_popen || haas_program(&a.input, params),
        main_m99_ends: a.main_m99 == MainM99::End,
        max_sub_depth: a.sub_depth,
        semantics: fmsvm_vm::value::Semantics {
            nat: a.nat || params.nat.unwrap_or(false),
            mod_integers: a.mod_integers || params.mod_integers.unwrap_or(false),
        },
    }
}

/// The machine the program is for (`--machine`, else the parameters', else the dialect's: a
/// lathe-only dialect makes a lathe) and its power-on modal state (`--modal` read in its codes);
/// the dialect is told when it writes a turning program. A lathe program for a milling dialect, or
/// the reverse, is a usage error.
fn machine(
    a: &Request,
    params: &crate::params::Params,
    profile: &mut crate::dialects::Profile,
) -> Result<(Option<fmsvm_kernel::Lathe>, fmsvm_canon::modal::ModalState), Exit> {
    use fmsvm_canon::modal::{CodeSystem, ModalState};
    use fmsvm_emit::dialect::MachineKind;
    let asked = a.machine.or(params.machine);
    if asked == Some(Machine::Lathe) && a.dialect.is_none() && a.dialect_file.is_none() {
        // A turning program without a dialect named: Fanuc's lathe, or a Haas's for a Haas
        // program (`--control haas-lathe`).
        let name = if haas_program(&a.input, params) {
            "haaslathe"
        } else {
            "fanuc0itd"
        };
        *profile = load_dialect(Some(name), None, a.input.max_input)?;
        if a.resolve {
            profile.dialect.native_cycles.clear();
        }
    }
    let d = &mut profile.dialect;
    let machine = asked.unwrap_or(match d.machine {
        MachineKind::Lathe => Machine::Lathe,
        _ => Machine::Mill,
    });
    let lathe = machine == Machine::Lathe;
    match (lathe, d.machine) {
        (true, MachineKind::Mill) => {
            plain(&format!(
                "the {} dialect writes for a milling machine, and this is a turning program (--machine lathe): choose a lathe dialect (fanuc0itd, haaslathe, mayak600t, nc31, sinumerik802d, fagor8035t) or linuxcnc or iso",
                d.name
            ));
            return Err(Exit::Usage);
        }
        (false, MachineKind::Lathe) => {
            plain(&format!(
                "the {} dialect writes for a lathe, and this is a milling program: say --machine lathe (or --control fanuc-0i-t) for a turning program",
                d.name
            ));
            return Err(Exit::Usage);
        }
        _ => {}
    }
    if lathe && a.renumber.is_some() && !a.resolve && d.literal {
        plain(
            "--renumber with literal output of a turning program: G70–G73 name their profile by its N numbers; resolve it (--resolve) or keep the numbers",
        );
        return Err(Exit::Usage);
    }
    if lathe && a.compact {
        plain("--compact is not yet written for turning programs");
        return Err(Exit::Usage);
    }
    if lathe && (d.control_work || d.control_length) {
        plain(&format!(
            "the {} profile leaves work offsets or tool lengths to the control ([motion] work_offsets, tool_length = \"control\"): that is a milling rule; a lathe's offsets are its tool offsets by T",
            d.name
        ));
        return Err(Exit::Usage);
    }
    if d.control_work && a.frame == OutputFrame::Machine {
        plain(&format!(
            "--frame machine writes machine coordinates, and the {} profile leaves work offsets to the control ([motion] work_offsets = \"control\"): choose one",
            d.name
        ));
        return Err(Exit::Usage);
    }
    d.turning = lathe;
    if !lathe && (a.gcode_system.is_some() || a.lathe_x.is_some()) {
        plain(
            "--gcode-system and --lathe-x are a lathe's: say --machine lathe (or --control fanuc-0i-t)",
        );
        return Err(Exit::Usage);
    }
    let system = match (lathe, a.gcode_system.or(params.gcode_system)) {
        (false, _) => CodeSystem::Mill,
        (true, Some(GCodeSystem::B)) => CodeSystem::LatheB,
        (true, _) => CodeSystem::LatheA,
    };
    // A Fanuc lathe's output is in the G-code system the control is set to (the program's).
    if let Some(l) = d.lathe.as_mut()
        && lathe
        && l.codes != CodeSystem::Mill
    {
        l.codes = system;
    }
    let power_on = match &a.modal {
        None => ModalState::power_on(system),
        Some(text) => ModalState::parse_in(system, text).map_err(|e| {
            plain(&format!("--modal: {e}"));
            Exit::Usage
        })?,
    };
    let diameter = a.lathe_x.or(params.lathe_x) != Some(LatheX::Radius);
    Ok((
        lathe.then_some(fmsvm_kernel::Lathe {
            diameter,
            max_rpm: params.max_rpm,
            y_axis: params.y_axis,
        }),
        power_on,
    ))
}

/// Reads and merges a run's configuration (stage one of `run`); a usage, compile or file error
/// is reported here, with its exit code.
fn configure(a: &Request) -> Result<Config, Exit> {
    let outputs = plan_outputs(a)?;
    let mut profile = load_dialect(
        a.dialect.as_deref(),
        a.dialect_file.as_deref().map(|p| ("--dialect-file", p)),
        a.input.max_input,
    )?;
    // Asked to resolve: the cycles too.
    if a.resolve {
        profile.dialect.native_cycles.clear();
    }
    if let Some(travel) = a.travel {
        profile.dialect.travel = travel;
    }
    // Output in machine coordinates selects no work system at its start: the positions are the
    // machine's, and a G54 would add its offset to every one of them.
    if a.frame == OutputFrame::Machine {
        profile
            .dialect
            .start_modes
            .retain(|c| !(54..=59).contains(&c.whole()));
    }
    // A control that does not read Fanuc's language gets the motion.
    let resolve = a.resolve || !profile.dialect.literal;
    if a.tape && profile.kind != crate::dialects::Kind::N33 {
        plain("--tape writes the Н33-2М punched tape: it goes with --dialect n33");
        return Err(Exit::Usage);
    }
    if a.verify && !matches!(outputs.program, Target::File { .. }) {
        plain("--verify reads the output back: give it as a file with -o FILE");
        return Err(Exit::Usage);
    }
    let Compiled {
        program,
        sources,
        charset: input_charset,
        params,
        flat,
        ..
    } = compile(&a.input, true)?;
    let out_charset = a
        .output_encoding
        .or(profile.charset)
        .unwrap_or(input_charset);
    let mut vars = Variables::default();
    if let Some(path) = &a.vars {
        parse_input("--vars", path, a.input.max_input, |name, text| {
            crate::vars::parse(name, text, &mut vars, &params.commons)
        })?;
    }
    // The tests compare the plain paths with the general ones (tests/plain.rs).
    let plain_paths = !a.input.without.contains(&FastPath::Plain);
    let run_options = run_options(a, &params);
    // The blocks and the clock are looked at as lines are made too: one cycle or arc in chords
    // can be many lines.
    let budget = OutputBudget::with_limits(a.max_bytes, a.max_blocks, run_options.limits.max_time);
    let options = literal::Options {
        comments: a.comments,
        renumber: a.renumber,
        compact: a.compact || profile.dialect.compact,
        source: a.input.file.display().to_string(),
        arc_tolerance: a.linearize.unwrap_or(0.001),
        budget,
        plain_path: plain_paths,
        second_aux: params.calls.b_sub,
    };
    let rules = InputRules {
        decimal: match a
            .decimal_input
            .or(params.decimal_input)
            .unwrap_or(DecimalInput::Calculator)
        {
            DecimalInput::Calculator => fmsvm_canon::decode::DecimalInput::Calculator,
            DecimalInput::Increment => fmsvm_canon::decode::DecimalInput::Increment,
        },
        second_aux: params.calls.b_sub,
        ..InputRules::default()
    };
    let (lathe, power_on) = machine(a, &params, &mut profile)?;
    // A dialect whose lathes may have a Y axis writes Y only for a machine that declares one (the
    // kernel's Y of a lathe without one is the spindle's plane, never written).
    if let Some(l) = &mut profile.dialect.lathe {
        l.y_axis &= lathe.is_some_and(|l| l.y_axis);
    }
    let mut settings = kernel_settings(a, &params, plain_paths, lathe, power_on);
    settings.budget = options.budget.clone();
    // A milling thread is applied where the output can write it (FMS-3000 §2.7).
    settings.mill_threads = settings.lathe.is_none()
        && profile.dialect.mill_thread != fmsvm_emit::dialect::MillThread::None;
    settings.control_offsets = fmsvm_kernel::ControlOffsets {
        work: profile.dialect.control_work,
        length: profile.dialect.control_length,
    };
    // Literal output for a Haas keeps the Haas's own forms as written.
    settings.haas_output = profile.dialect.haas && !resolve;
    let mut frames = match &a.offsets {
        None => fmsvm_kernel::frames::Frames::default(),
        Some(path) => parse_input("--offsets", path, a.input.max_input, crate::offsets::parse)?,
    };
    // Every X a user gives on a diameter lathe is a diameter, as the program's X is (docs/lathe.md):
    // the start point and the reference positions; the kernel keeps radii.
    if let Some(l) = settings.lathe {
        let k = l.radius_per_x_word();
        settings.start_point[0] *= k;
        for r in &mut frames.reference {
            r[0] *= k;
        }
    }
    let (date, time) = clock(a);
    let probe = match (stock_box(a, settings.lathe), &a.probe_points) {
        (Some([min, max]), _) => ProbeModel::Stock {
            min,
            max,
            radius: a.probe_radius,
        },
        (None, Some(path)) => ProbeModel::Points {
            points: parse_input("--probe-points", path, a.input.max_input, parse_points)?,
            next: 0,
        },
        (None, None) => ProbeModel::None,
    };
    Ok(Config {
        outputs,
        profile,
        resolve,
        program,
        sources,
        params,
        flat,
        out_charset,
        vars,
        options,
        rules,
        settings,
        frames,
        run_options,
        date,
        time,
        probe,
    })
}

pub fn run(a: &Request, consumer: Consumer<'_>) -> Exit {
    run_into(a, consumer, &mut None)
}

/// What one run ended with: its exit, and where it stopped when it stopped at a block (for a
/// front end that shows the stop at its line: the editor, the debugger).
pub struct Outcome {
    pub exit: Exit,
    pub stop: Option<RunStop>,
}

/// `run`, its stop handed back rather than only reported.
pub fn expand(a: &Request, consumer: Consumer<'_>) -> Outcome {
    let mut stop = None;
    let exit = run_into(a, consumer, &mut stop);
    Outcome { exit, stop }
}

/// `run`, the stop at a block (if any) put in `stop`.
fn run_into(a: &Request, consumer: Consumer<'_>, stop: &mut Option<RunStop>) -> Exit {
    let Config {
        outputs,
        profile,
        resolve,
        program,
        sources,
        params,
        flat,
        out_charset,
        mut vars,
        options,
        rules,
        settings,
        frames,
        run_options,
        date,
        time,
        probe,
    } = match configure(a) {
        Ok(c) => c,
        Err(e) => return e,
    };
    // A picture and the motion report show where the tool's tip goes (the same extents in both):
    // the tool lengths of --offsets are taken off.
    let tool_tip = matches!(consumer, Consumer::Stats { .. } | Consumer::Render(_));
    let settings = Settings {
        tool_tip,
        ..settings
    };
    let mut sink = match outputs.program.open() {
        Ok(s) => s,
        Err(e) => {
            let what = a
                .output
                .as_deref()
                .map_or("standard output".into(), |p| p.display().to_string());
            plain(&format!("cannot create {what}: {e}"));
            return Exit::Io;
        }
    };
    let mut port = PrintPort::new(
        outputs.print.clone(),
        !a.no_dc_codes,
        out_charset,
        options.budget.clone(),
        a.max_print_bytes,
    );
    let started = Instant::now();
    // What a second expansion for --verify starts from.
    let again = a.verify.then(|| (vars.clone(), probe.clone()));
    let job = Job {
        a,
        quiet: false,
        flat: flat.as_ref(),
        program: &program,
        run: &run_options,
        date,
        time,
        frames: &frames,
        rules: &rules,
        settings: &settings,
        sources: &sources,
    };
    if let Some(out) = &a.verify_file {
        drop(sink);
        let again = Again {
            profile: &profile,
            resolve,
        };
        return verify(&job, &again, out, probe, &mut vars);
    }
    let to_file = matches!(consumer, Consumer::Flat);
    let to_writer = matches!(consumer, Consumer::Into(_));
    // The plain blocks were written by a second thread (`--stats` says so).
    let mut second_thread = false;
    // What --verify's reader beside the writer found.
    let mut verdict = None;
    let outcome = match consumer {
        consumer @ (Consumer::Flat | Consumer::Into(_)) => {
            let show = a.output.is_some()
                && !a.input.quiet
                && std::io::IsTerminal::is_terminal(&io::stderr());
            let mut to: Box<dyn io::Write + Send + '_> = match consumer {
                Consumer::Into(w) => w,
                _ => Box::new(crate::output::Progress::new(sink.writer(), show)),
            };
            // --verify of a text dialect's resolved output reads each line back as it is written.
            let mut beside = None;
            if again.is_some() && resolve && profile.kind == crate::dialects::Kind::Text {
                let (echo, echoed) = fmsvm_readback::beside::echo(io::BufWriter::new(to));
                to = Box::new(echo);
                beside = Some(echoed);
            }
            let writer = Encode::new(to, out_charset);
            let text = Text {
                profile: &profile,
                resolve,
                options: &options,
                pipeline: to_file && pipelined(&a.input, &program),
            };
            let (result, threaded) = text.write(&job, writer, probe, &mut port, &mut vars, beside);
            second_thread = threaded.second_thread;
            verdict = threaded.verdict;
            result
        }
        Consumer::Stats { json } => {
            let mut stats = fmsvm_emit::stats::Stats::default()
                .within(options.budget.clone(), profile.dialect.reach());
            if let Some(l) = job.settings.lathe {
                stats = stats.turning(l.diameter);
            }
            let (result, stats) = job.expand(stats, probe, &mut port, &mut vars);
            result.and_then(|done| {
                let mut text = Vec::new();
                crate::stats::report(&stats.finish(a.rapid), json, &mut text)
                    .and_then(|()| write_all(&mut sink, &text))
                    .map(|()| done)
                    .map_err(|e| (Stop::Io(e), None))
            })
        }
        Consumer::Render(render) => {
            render.start(RenderStart {
                stock: stock_box(a, job.settings.lathe),
                budget: options.budget.clone(),
                reach: profile.dialect.reach(),
                lathe: job.settings.lathe.is_some(),
            });
            let (result, rendering) = job.expand(Rendering(render), probe, &mut port, &mut vars);
            result.and_then(|done| {
                let bytes = rendering
                    .0
                    .render()
                    .map_err(|e| (Stop::Io(io::Error::other(e)), None))?;
                write_all(&mut sink, &bytes)
                    .map(|()| done)
                    .map_err(|e| (Stop::Io(e), None))
            })
        }
    };
    let open = Open {
        outputs,
        sink,
        port,
        streams: to_file || to_writer,
    };
    match outcome {
        Ok(done) => {
            let written = open.outputs.program.path().map(Path::to_path_buf);
            let printed = match commit(a, open, &vars, &params.commons) {
                Ok(p) => p,
                Err(e) => return e,
            };
            report_success(a, printed, done, started, second_thread);
            if let (Some(checked), Some(out)) = (verdict, written.as_deref()) {
                return verified(&job, &profile, out, checked);
            }
            if let Some((mut vars, probe)) = again
                && let Some(out) = written.as_deref()
            {
                let again = Again {
                    profile: &profile,
                    resolve,
                };
                return verify(&job, &again, out, probe, &mut vars);
            }
            Exit::Success
        }
        Err(stopped) => report_stop(a, open, &program, sources, flat.as_ref(), stopped, stop),
    }
}

/// How the flat program is written: the dialect's profile, literal or resolved, and whether plain
/// blocks may go to a second thread.
struct Text<'a> {
    profile: &'a crate::dialects::Profile,
    resolve: bool,
    options: &'a fmsvm_emit::literal::Options,
    pipeline: bool,
}

impl Text<'_> {
    /// Expands the program into `writer` with the emitter the profile asks for: the Н33-2М tape,
    /// resolved motion (read back beside the writer from `beside`, for `--verify`), or the literal
    /// blocks (their plain blocks on a second thread when it may); also says whether the second
    /// thread wrote, and what the read-back found.
    fn write<W: io::Write + Send>(
        &self,
        job: &Job<'_>,
        writer: W,
        probe: ProbeModel,
        port: &mut PrintPort,
        vars: &mut Variables,
        beside: Option<fmsvm_readback::beside::Echoed>,
    ) -> (Result<Expanded, Stopped>, Written) {
        let threaded = |second_thread| Written {
            second_thread,
            verdict: None,
        };
        let (a, profile, options) = (job.a, self.profile, self.options);
        if profile.kind == crate::dialects::Kind::N33 {
            let n33 = fmsvm_emit::n33::N33Options {
                tape: a.tape,
                g18_ccw_is_iso: a.n33_g18 == N33G18::Iso,
                brake_step: a.n33_brake_step,
                max_tape_m: a.n33_tape_length,
                travel: a.travel.unwrap_or(fmsvm_emit::n33::TRAVEL_MM),
                split_tapes: a.split_tapes,
                arc_tolerance: a.linearize.unwrap_or(0.01),
                budget: options.budget.clone(),
                ..Default::default()
            };
            let emitter = fmsvm_emit::n33::N33Emitter::new(writer, n33);
            let (result, emitter) = job.expand(emitter, probe, port, vars);
            job.say(emitter.warnings());
            return (result, threaded(false));
        }
        let said = |warnings: Vec<fmsvm_canon::Warning>| job.say(&warnings);
        if self.resolve {
            let emitter = ResolvedEmitter::new(writer, profile.dialect.clone(), options.clone());
            if let Some(echoed) = beside {
                let input = io::BufReader::new(echoed);
                let check = text_verifier(job, &profile.dialect, input);
                let emitter =
                    fmsvm_readback::beside::ReadBeside::new(emitter.line_by_line(), check);
                let (result, emitter) = job.expand(emitter, probe, port, vars);
                said(emitter.emitter().warnings());
                let written = Written {
                    second_thread: false,
                    verdict: emitter.verdict(),
                };
                return (result, written);
            }
            if !self.pipeline {
                let (result, emitter) = job.expand(emitter, probe, port, vars);
                said(emitter.warnings());
                return (result, threaded(false));
            }
            // Moves are formatted and written by a second thread.
            return std::thread::scope(|scope| {
                match Pipelined::new(scope, emitter, &job.rules.table()) {
                    Ok(emitter) => {
                        let (result, mut emitter) = job.expand(emitter, probe, port, vars);
                        said(emitter.warnings());
                        (result, threaded(true))
                    }
                    Err(emitter) => {
                        let (result, emitter) = job.expand(*emitter, probe, port, vars);
                        said(emitter.warnings());
                        (result, threaded(false))
                    }
                }
            });
        }
        let emitter = LiteralEmitter::new(writer, profile.dialect.clone(), options.clone());
        // What the literal emitter has to say (renumbering that started again); a pipelined
        // emitter does not renumber.
        if !self.pipeline {
            let (result, emitter) = job.expand(emitter, probe, port, vars);
            said(emitter.warnings());
            return (result, threaded(false));
        }
        // Plain blocks are formatted and written by a second thread.
        std::thread::scope(
            |scope| match Pipelined::new(scope, emitter, &job.rules.table()) {
                Ok(emitter) => (job.expand(emitter, probe, port, vars).0, threaded(true)),
                Err(emitter) => {
                    let (result, emitter) = job.expand(*emitter, probe, port, vars);
                    said(emitter.warnings());
                    (result, threaded(false))
                }
            },
        )
    }
}

/// What writing the flat program did besides its result.
struct Written {
    /// The plain blocks were written by a second thread.
    second_thread: bool,
    /// What `--verify`'s reader beside the writer found: the moves read back, or the first
    /// difference (None: not checked in the pass, a second expansion checks the output).
    verdict: Option<Result<u64, String>>,
}

/// What a finished run says besides its output: where the printed output went, and with `--stats`
/// the counts, the speed and the estimated machining time.
fn report_success(
    a: &Request,
    printed: Option<PathBuf>,
    (stats, bytes, machining): Expanded,
    started: Instant,
    second_thread: bool,
) {
    if let Some(p) = printed
        && !a.input.quiet
    {
        plain_info(&format!(
            "printed output (DPRNT/BPRNT) written to {}",
            p.display()
        ));
    }
    if a.stats {
        let t = started.elapsed();
        plain_info(&format!(
            "{}, {}, {} in {:.3} s ({:.1} M blocks/s{}); estimated machining time {:.1} min",
            crate::report::count(stats.blocks as usize, "block", "blocks"),
            crate::report::count(bytes as usize, "byte", "bytes"),
            crate::report::count(stats.steps as usize, "step", "steps"),
            t.as_secs_f64(),
            stats.blocks as f64 / t.as_secs_f64().max(1e-9) / 1e6,
            if second_thread {
                ", written by a second thread"
            } else {
                ""
            },
            machining / 60.0
        ));
    }
}

/// What a run has open while it expands: the planned outputs, the flat program's sink and the
/// DPRNT/BPRNT port.
struct Open {
    outputs: Outputs,
    sink: crate::output::Sink,
    port: PrintPort,
    /// The program goes out as it is made (`run`); `stats` and `plot` write theirs at the end.
    streams: bool,
}

/// A finished run's outputs, every one complete, committed together (or none): the flat program,
/// the printed output, `--dump-vars`. Gives where the printed output went.
fn commit(
    a: &Request,
    open: Open,
    vars: &Variables,
    commons: &fmsvm_compiler::ir::CommonRanges,
) -> Result<Option<PathBuf>, Exit> {
    let Open {
        outputs,
        sink,
        port,
        ..
    } = open;
    // Every output is complete: commit them together, or none.
    let mut sinks = vec![sink];
    let printed = match port.finish() {
        Ok(Some(s)) => {
            sinks.push(s);
            outputs.print.path().map(Path::to_path_buf)
        }
        Ok(None) => None,
        Err(e) => {
            plain(&format!(
                "writing the printed output failed: {e}; no output file was written"
            ));
            return Err(Exit::Io);
        }
    };
    if let Some(t) = &outputs.dump {
        match write_text(t, crate::vars::dump(vars, commons).as_bytes()) {
            Ok(s) => sinks.push(s),
            Err(e) => {
                plain(&format!(
                    "cannot write --dump-vars {}: {e}; no output file was written",
                    t.path().map_or("-".into(), |p| p.display().to_string())
                ));
                return Err(Exit::Io);
            }
        }
    }
    if let Err(e) = commit_all(sinks) {
        return Err(io_failure(a, &outputs.program, e));
    }
    Ok(printed)
}

/// A run that stopped: what is kept of its outputs (`--keep-partial`), the message at the block
/// that stopped it, and the exit code.
fn report_stop(
    a: &Request,
    open: Open,
    program: &Program,
    sources: SourceMap,
    flat: Option<&crate::flat::FlatProgram>,
    (stop, at): Stopped,
    stopped_at: &mut Option<RunStop>,
) -> Exit {
    let Open {
        outputs,
        mut sink,
        port,
        streams,
    } = open;
    let (exit, headline, code) = match &stop {
        // The program's own file, read as it runs (a program with no macro statement).
        Stop::Io(e) if let Some(r) = crate::flat::read_failure(e) => {
            drop(sink);
            drop(port);
            plain(&format!("{r}; {}", incomplete(&outputs.program)));
            return Exit::Io;
        }
        Stop::Io(e) if e.kind() == io::ErrorKind::BrokenPipe && a.output.is_none() => {
            return Exit::Success;
        }
        // The DNC session reports its own stop (link lost, XOFF timeout, signal).
        Stop::Io(e) if WriterStop::is(e) => return Exit::Io,
        Stop::Io(e) => {
            drop(sink);
            drop(port);
            return io_failure(a, &outputs.program, io::Error::new(e.kind(), e.to_string()));
        }
        // Alarm 0 has no Fanuc number (an fmsvm stop such as DPRNT before POPEN).
        Stop::Alarm(alarm) => (
            Exit::Alarm,
            alarm.message.to_string(),
            (alarm.number != 0).then_some(alarm.number),
        ),
        Stop::Limit { .. } => (Exit::Limit, stop.to_string(), None),
    };
    // Without --keep-partial the temporary output is dropped (deleted): nothing partial remains.
    let kept = match (&outputs.program, a.keep_partial) {
        (Target::File { path, resolved, .. }, true) => {
            let name = partial_name(resolved);
            let shown = partial_name(path);
            let marker = format!(
                "(INCOMPLETE: {} {}: EXPANSION STOPPED HERE)\n",
                code.map_or("LIMIT".to_string(), |c| format!("ALARM {c:04}")),
                headline.to_ascii_uppercase().replace(['(', ')'], " ")
            );
            let r = {
                use std::io::Write;
                let mut w = sink.writer();
                w.write_all(marker.as_bytes()).and_then(|()| w.flush())
            };
            match r.and_then(|()| sink.commit_as(&name)) {
                Ok(()) => format!(
                    "the blocks expanded so far are in {} (incomplete)",
                    shown.display()
                ),
                Err(e) => format!("keeping the partial output failed: {e}"),
            }
        }
        (Target::File { .. }, false) => {
            drop(sink);
            "no output file was written (--keep-partial keeps what was expanded)".to_string()
        }
        (Target::Direct { path }, _) => {
            format!("what was written to {} is incomplete", path.display())
        }
        (Target::Stdout, _) if streams => "the output above is incomplete".to_string(),
        (Target::Stdout, _) => "nothing was written".to_string(),
    };
    if a.keep_partial
        && let Target::File { resolved, .. } = &outputs.print
        && let Ok(Some(s)) = port.finish()
    {
        let _ = s.commit_as(&partial_name(resolved));
    }
    let mut notes = Vec::new();
    if let Some((_, stats)) = at {
        let s = if stats.blocks == 1 { "" } else { "s" };
        notes.push(format!("stopped after {} block{s}; {kept}", stats.blocks));
    } else {
        notes.push(kept);
    }
    if exit == Exit::Limit {
        let flag = match &stop {
            Stop::Limit { kind, .. } => match kind {
                LimitKind::Steps => "--max-steps",
                LimitKind::Blocks => "--max-blocks",
                LimitKind::OutputBytes => "--max-bytes",
                LimitKind::PrintBytes => "--max-print-bytes",
                LimitKind::WallTime => "--max-seconds",
                LimitKind::CallDepth => "--sub-depth",
            },
            _ => "its flag",
        };
        let none = if flag == "--sub-depth" {
            ""
        } else {
            " (0 = none)"
        };
        notes.push(format!(
            "raise the limit with {flag}{none} if the program is meant to run this long"
        ));
        let main_has_m99 = program.functions[0]
            .ops
            .iter()
            .any(|op| matches!(op, fmsvm_compiler::ir::Op::Return { .. }));
        if a.main_m99 == MainM99::Restart && main_has_m99 {
            notes.push("a main program ending in M99 restarts forever: --main-m99 end writes the M99 and stops".into());
        }
    }
    // A flat program's text was never held: read it now, for the report.
    let mut sources = sources;
    let at = match (at, &flat) {
        (Some((At::FlatFile { start, end }, st)), Some(f)) => {
            let text = std::fs::read(&f.path)
                .map(|b| String::from_utf8_lossy(&b).into_owned())
                .unwrap_or_default();
            let id = sources.add(a.input.file.display().to_string(), text);
            // Spans are 32-bit: a stop past 4 GiB points at the last place they can say.
            let offset = |b: u64| b.min(u64::from(u32::MAX)) as usize;
            Some((
                fmsvm_compiler::Span::new(id, offset(start), offset(end)),
                st,
            ))
        }
        (Some((At::Span(span), st)), _) => Some((span, st)),
        (Some((At::FlatFile { .. }, _)), None) | (None, _) => None,
    };
    if let Some((span, _)) = at {
        let file = &sources.file(span.file).name;
        *stopped_at = Some(RunStop {
            file: file.clone(),
            start: span.start,
            end: span.end,
            message: headline.clone(),
            alarm: code,
            notes: notes.clone(),
        });
    }
    let reporter = Reporter::new(&sources);
    match at {
        Some((span, _)) => reporter.stop(&headline, code, span, &notes),
        None => {
            plain(&headline);
            for n in &notes {
                plain_info(&format!("  note: {n}"));
            }
        }
    }
    exit
}

/// Touch points: one `X… Y… Z…` line each (missing axes are 0); `(…)` comments and blank lines skipped.
pub fn parse_points(name: &str, text: &str) -> Result<Vec<[f64; 3]>, String> {
    let mut out = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let mut line = String::new();
        let mut depth = 0;
        for c in raw.chars() {
            match c {
                '(' => depth += 1,
                ')' => depth = 0.max(depth - 1),
                _ if depth == 0 => line.push(c.to_ascii_uppercase()),
                _ => {}
            }
        }
        let line = line.trim();
        if line.is_empty() {
            continue;
        }
        let mut p = [0.0; 3];
        for word in line.split_whitespace() {
            let axis_len = word.chars().next().map_or(0, char::len_utf8);
            let (axis, value) = word.split_at(axis_len);
            let k = match axis {
                "X" => 0,
                "Y" => 1,
                "Z" => 2,
                _ => return Err(format!("{name}:{}: expected X Y Z words: `{raw}`", i + 1)),
            };
            p[k] = value
                .parse()
                .map_err(|_| format!("{name}:{}: `{word}` is not a number", i + 1))?;
        }
        out.push(p);
    }
    Ok(out)
}

fn io_failure(a: &Request, target: &Target, e: io::Error) -> Exit {
    let what = a
        .output
        .as_deref()
        .map_or("standard output".into(), |p| p.display().to_string());
    plain(&format!(
        "writing {what} failed: {e}; {}",
        incomplete(target)
    ));
    Exit::Io
}

/// What a failed run left at its output.
fn incomplete(target: &Target) -> &'static str {
    match target {
        Target::File { .. } => "no output file was written",
        Target::Direct { .. } | Target::Stdout => "what was written there is incomplete",
    }
}

fn plain_info(message: &str) {
    crate::report::info(message);
}

/// Writes a whole report or picture to the output.
fn write_all(sink: &mut crate::output::Sink, bytes: &[u8]) -> io::Result<()> {
    use std::io::Write;
    let mut w = sink.writer();
    w.write_all(bytes)?;
    w.flush()
}

/// A print port that keeps nothing (the second expansion of `--verify` prints nothing again).
struct Discard;

impl fmsvm_vm::print::Port for Discard {
    fn open(&mut self) -> Result<(), Stop> {
        Ok(())
    }
    fn write(&mut self, _: &[u8]) -> Result<(), Stop> {
        Ok(())
    }
    fn close(&mut self) -> Result<(), Stop> {
        Ok(())
    }
}

/// What a second expansion for `--verify` runs with.
struct Again<'a> {
    profile: &'a crate::dialects::Profile,
    resolve: bool,
}

/// `--verify` and `--verify-file`: `out` read back and checked, the outcome reported.
fn verify(
    job: &Job<'_>,
    again: &Again<'_>,
    out: &Path,
    probe: ProbeModel,
    vars: &mut Variables,
) -> Exit {
    let checked = if again.resolve {
        verify_resolved(job, again, out, probe, vars)
    } else {
        verify_literal(
            job.a,
            out,
            job.rules.second_aux,
            job.settings.lathe.is_some(),
        )
    };
    verified(job, again.profile, out, checked)
}

/// The outcome of `--verify` or `--verify-file` on `out` reported: the moves read back, or the
/// first difference (the output then removed, or kept as a partial file).
fn verified(
    job: &Job<'_>,
    profile: &crate::dialects::Profile,
    out: &Path,
    checked: Result<u64, String>,
) -> Exit {
    match checked {
        Ok(moves) => {
            if !job.a.input.quiet {
                plain_info(&format!(
                    "verified: {} of {} read back match the kernel's within the {} dialect's resolution",
                    crate::report::count(moves as usize, "move", "moves"),
                    out.display(),
                    profile.dialect.name
                ));
            }
            Exit::Success
        }
        Err(e) => {
            plain(&format!(
                "--verify: {} does not move as the program does: {e}",
                out.display()
            ));
            // A file that failed its check is not left under the name a user sends to the machine:
            // removed, or kept as OUT.PARTIAL.ext with --keep-partial (`--verify-file` names a file
            // written before: it is the user's, left alone).
            if job.a.verify && job.a.verify_file.is_none() {
                if job.a.keep_partial {
                    let kept = partial_name(out);
                    match std::fs::rename(out, &kept) {
                        Ok(()) => {
                            plain_info(&format!("note: the output is kept as {}", kept.display()))
                        }
                        Err(e) => plain_info(&format!(
                            "note: {} could not be renamed: {e}",
                            out.display()
                        )),
                    }
                } else if let Err(e) = std::fs::remove_file(out) {
                    plain_info(&format!(
                        "note: {} could not be removed: {e}",
                        out.display()
                    ));
                } else {
                    plain_info(&format!("note: {} was removed", out.display()));
                }
            }
            Exit::Verify
        }
    }
}

/// `--verify` of resolved output: the program expanded again, each canonical operation checked
/// against what the dialect's reader reads back from `out`. The number of moves read, or the first
/// difference.
fn verify_resolved(
    job: &Job<'_>,
    again: &Again<'_>,
    out: &Path,
    probe: ProbeModel,
    vars: &mut Variables,
) -> Result<u64, String> {
    use fmsvm_readback::Verifier;
    let file = std::fs::File::open(out).map_err(|e| format!("cannot read it back: {e}"))?;
    let input = io::BufReader::new(file);
    let dialect = &again.profile.dialect;
    match again.profile.kind {
        crate::dialects::Kind::Text => {
            let v = text_verifier(job, dialect, input);
            check_against(job, v, probe, vars)
        }
        crate::dialects::Kind::N33 => {
            let reader = fmsvm_readback::n33::N33Reader::new(input, [0.0; 6])
                .g18_ccw_is_iso(job.a.n33_g18 == N33G18::Iso);
            // The tape has no reference return: one is written as a move.
            let mut d = dialect.clone();
            d.reference = fmsvm_emit::dialect::ReferenceForm::None;
            let mut v = Verifier::new(reader, d, job.a.linearize.unwrap_or(0.01));
            v.rapid_as_feed = true;
            v.rapid_feed = Some(fmsvm_emit::n33::RAPID_MM_PER_MIN);
            v.dwell_units = 100.0;
            v.respell_after_frame_move = false;
            v.unknown_counted_from_start = true;
            v.zero_dwells_written = false;
            // Two significant digits: half a step of the code is under 5 %.
            v.feed_tolerance = 0.05;
            check_against(job, v, probe, vars)
        }
    }
}

/// The verifier of a text dialect's output read from `input`.
fn text_verifier<R: io::BufRead>(
    job: &Job<'_>,
    dialect: &fmsvm_emit::dialect::Dialect,
    input: R,
) -> fmsvm_readback::Verifier<fmsvm_readback::words::WordReader<R>> {
    let mut reader = fmsvm_readback::words::WordReader::new(input, dialect.clone());
    reader.second_aux = job.rules.second_aux;
    fmsvm_readback::Verifier::new(reader, dialect.clone(), job.a.linearize.unwrap_or(0.001))
}

/// The program expanded once more, quietly, each canonical operation checked by `v` against what
/// its reader reads back: the moves read, or the first difference.
fn check_against<R: fmsvm_readback::Reader>(
    job: &Job<'_>,
    v: fmsvm_readback::Verifier<R>,
    probe: ProbeModel,
    vars: &mut Variables,
) -> Result<u64, String> {
    let quiet_job = Job {
        quiet: true,
        ..*job
    };
    let (result, v) = quiet_job.expand(v, probe, &mut Discard, vars);
    match (result, v.mismatch.clone()) {
        (_, Some(m)) => Err(m),
        (Ok(_), None) => Ok(v.moves()),
        (Err((stop, _)), None) => Err(format!("the second expansion stopped: {stop}")),
    }
}

/// `--verify` of literal (Fanuc) output: the program and the output, each resolved into a
/// temporary file, read back move by move; they must be the same.
fn verify_literal(
    a: &Request,
    out: &Path,
    second_aux: Option<fmsvm_block::Letter>,
    turning: bool,
) -> Result<u64, String> {
    // Both resolved in Fanuc's own dialect: the mill's, or the lathe's for a turning program.
    let fanuc = if turning { "fanuc0itd" } else { "fanuc" };
    let mut reading = crate::dialects::builtin(fanuc)
        .map_err(|e| format!("the {fanuc} dialect: {e}"))?
        .dialect;
    reading.turning = turning;
    use fmsvm_readback::{Motion, Reader, words::WordReader};
    let dir = tempfile::tempdir().map_err(|e| format!("cannot make a temporary folder: {e}"))?;
    let resolve_into = |input: &Path, name: &str| -> Result<PathBuf, String> {
        let mut b = a.clone();
        if input != a.input.file {
            // The output, read from its file (the program may be an editor's text).
            b.input.text = None;
        }
        b.input.file = input.to_path_buf();
        b.input.quiet = true;
        b.output = Some(dir.path().join(name));
        b.print = Some(dir.path().join(format!("{name}.prn")));
        b.dump_vars = None;
        b.resolve = true;
        b.verify = false;
        b.verify_file = None;
        b.stats = false;
        b.compact = false;
        b.renumber = None;
        b.comments = false;
        b.dialect = Some(fanuc.into());
        if turning {
            b.machine = Some(Machine::Lathe);
        }
        b.dialect_file = None;
        match run(&b, Consumer::Flat) {
            Exit::Success => Ok(dir.path().join(name)),
            e => Err(format!(
                "resolving {} for the comparison failed (exit {})",
                input.display(),
                e as u8
            )),
        }
    };
    let program = resolve_into(&a.input.file, "program.nc")?;
    let output = resolve_into(out, "output.nc")?;
    let open = |p: &Path| -> Result<WordReader<io::BufReader<std::fs::File>>, String> {
        let f = std::fs::File::open(p).map_err(|e| format!("cannot read {}: {e}", p.display()))?;
        let mut r = WordReader::new(io::BufReader::new(f), reading.clone());
        r.second_aux = second_aux;
        Ok(r)
    };
    let (mut want, mut got) = (open(&program)?, open(&output)?);
    let mut moves = 0u64;
    loop {
        let w = want.next_move().map_err(|e| e.to_string())?;
        let g = got.next_move().map_err(|e| e.to_string())?;
        match (w, g) {
            (None, None) => return Ok(moves),
            (Some(w), Some(g)) => {
                // A feed move's F means per minute or per revolution (G94/G95, a lathe's G98/G99):
                // the same number in the other mode is another speed.
                let cuts = matches!(w.motion, Motion::Feed | Motion::Arc { .. });
                let same_feed = ((w.feed.is_nan() && g.feed.is_nan()) || w.feed == g.feed)
                    && (!cuts || w.per_rev == g.per_rev);
                let same = w.motion.same(&g.motion)
                    && w.to
                        .iter()
                        .zip(&g.to)
                        .all(|(x, y)| (x.is_nan() && y.is_nan()) || (x - y).abs() < 1e-9);
                if !same || !same_feed {
                    // The feeds are named where they differ (the positions may be the same).
                    let feeds_differ = !same_feed;
                    let at = |f: f64, per_rev: bool| match (feeds_differ, f.is_nan()) {
                        (false, _) => String::new(),
                        (true, true) => " with no feed".to_string(),
                        (true, false) if per_rev => format!(" at F{f} per revolution"),
                        (true, false) => format!(" at F{f} per minute"),
                    };
                    return Err(format!(
                        "move {}: the program resolves to {} to {}{}, the output to {} to {}{}",
                        moves + 1,
                        w.motion.describe(),
                        fmsvm_canon::describe_pose(&w.to),
                        at(w.feed, w.per_rev),
                        g.motion.describe(),
                        fmsvm_canon::describe_pose(&g.to),
                        at(g.feed, g.per_rev)
                    ));
                }
                moves += 1;
            }
            (Some(_), None) => {
                return Err(format!(
                    "the output ends after {moves} moves; the program goes on"
                ));
            }
            (None, Some(_)) => {
                return Err(format!(
                    "the output moves on after the program's {moves} moves"
                ));
            }
        }
    }
}

/// What one expansion needs besides its kernel (shared by the literal and the resolved output).
#[derive(Clone, Copy)]
struct Job<'a> {
    a: &'a Request,
    /// Print no warnings (the second expansion of `--verify`).
    quiet: bool,
    /// The program runs straight from its file.
    flat: Option<&'a crate::flat::FlatProgram>,
    program: &'a Program,
    run: &'a RunOptions,
    date: u32,
    time: u32,
    frames: &'a fmsvm_kernel::frames::Frames,
    /// How the program's numbers are read, and what the run adds to the kernel.
    rules: &'a InputRules,
    settings: &'a Settings,
    /// The compiled sources, to name the file a warning's block comes from.
    sources: &'a SourceMap,
}

/// Blocks, bytes written and the estimated machining time of a finished run.
type Expanded = (fmsvm_vm::Stats, u64, f64);
/// Why a run stopped, and where (with what it did up to there).
type Stopped = (Stop, Option<(At, fmsvm_vm::Stats)>);

/// Where the last run in this process stopped, as its report says it: for the language server,
/// which runs programs in its own process and shows the stop at its block.
#[derive(Clone, Debug)]
pub struct RunStop {
    /// The file of the block (its name as the run's sources have it).
    pub file: String,
    /// Its byte range there.
    pub start: u32,
    pub end: u32,
    /// The headline and the alarm number.
    pub message: String,
    pub alarm: Option<u32>,
    pub notes: Vec<String>,
}

/// Where a run stopped: an op's span in the compiled sources, or a byte range of a flat program's
/// file (whose text was never held: the report reads it again).
#[derive(Clone, Copy, Debug)]
enum At {
    Span(fmsvm_compiler::Span),
    FlatFile { start: u64, end: u64 },
}

impl Job<'_> {
    /// Says the run's warnings about the output, each at its source block, unless quiet.
    fn say(&self, warnings: &[fmsvm_canon::Warning]) {
        if self.a.input.quiet || self.quiet {
            return;
        }
        let reporter = Reporter::new(self.sources);
        for w in warnings {
            plain_info(&reporter.run_warning(w));
        }
    }

    /// Runs the program through a kernel to `emitter`; reports the kernel's warnings and messages.
    fn expand<E: Emitter>(
        &self,
        emitter: E,
        probe: ProbeModel,
        port: &mut dyn fmsvm_vm::print::Port,
        vars: &mut Variables,
    ) -> (Result<Expanded, Stopped>, E) {
        let (a, program) = (self.a, self.program);
        let main = &program.functions[0];
        let mut kernel = Kernel::with_settings(emitter, self.rules.clone(), self.settings.clone());
        *kernel.frames_mut() = self.frames.clone();
        kernel.set_clock(self.date, self.time);
        kernel.set_rapid_rate(a.rapid);
        kernel.set_timing(a.stats || program.may_access(&[3001, 3002]));
        kernel.set_probe(probe);
        let result = kernel
            .begin(main.number, program.string(main.title))
            .map_err(|stop| (stop, None))
            .and_then(|()| match self.flat {
                None => fmsvm_vm::run(program, &mut kernel, port, vars, self.run)
                    .map_err(|e| (e.stop, Some((At::Span(e.span), e.stats)))),
                Some(f) => {
                    let limits = crate::flat::FlatLimits {
                        limits: self.run.limits,
                        block_delete: a.input.block_delete,
                    };
                    crate::flat::run(f, &mut kernel, &limits).map_err(|e| {
                        let span = At::FlatFile {
                            start: e.start,
                            end: e.end,
                        };
                        let stats = fmsvm_vm::Stats {
                            steps: e.blocks,
                            blocks: e.blocks,
                        };
                        (e.stop, Some((span, stats)))
                    })
                }
            });
        self.say(kernel.warnings());
        for (n, text) in kernel.messages() {
            plain_info(&format!(
                "message {n}: {text} (#3006: the control stops here; the flat program has M0)"
            ));
        }
        let result = match result {
            Ok(stats) => kernel.end().map(|()| stats).map_err(|s| (s, None)),
            // An output error the second thread met before this stop (an alarm, a limit, the
            // program's file failing to read) is what stopped the run first: report it as one
            // thread would.
            Err((stop, at)) if !matches!(&stop, Stop::Io(e) if crate::flat::read_failure(e).is_none()) => {
                match kernel.settle_output() {
                    Err(io @ Stop::Io(_)) => Err((io, at)),
                    _ => Err((stop, at)),
                }
            }
            Err(e) => Err(e),
        };
        let [f3003, f3004] = kernel.flags_3003_3004();
        if !a.input.quiet && (f3003 != 0.0 || f3004 != 0.0) {
            plain_info(&format!(
                "warning: the program ends with #3003={f3003} #3004={f3004}: single-block/feed-hold suppression left on"
            ));
        }
        let bytes = kernel.emitter().written();
        let machining = kernel.machining_seconds();
        (result.map(|s| (s, bytes, machining)), kernel.into_emitter())
    }
}

/// `--stock` as least and greatest X Y Z in the kernel's terms: on a lathe its X is read as the
/// program's X (a diameter on a diameter lathe), so it is halved there.
fn stock_box(a: &Request, lathe: Option<fmsvm_kernel::Lathe>) -> Option<[[f64; 3]; 2]> {
    let b = a.stock?;
    let k = lathe.map_or(1.0, |l| l.radius_per_x_word());
    Some([[b[0] * k, b[1], b[2]], [b[3] * k, b[4], b[5]]])
}
