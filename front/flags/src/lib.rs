//! The command line's spelling of a run: the flags of `run` (and of every subcommand that runs a
//! program: `stats`, `plot`, `dnc`, the debugger's launch arguments, the editor's workspace `args`),
//! each value checked when parsed, made into the driver's `Request` field by field.

use std::path::PathBuf;

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use fmsvm_driver::request::{
    Charset, Choice, CompStyle, Control, DEFAULT_RAPID, DecimalInput, EngineKind, FastPath,
    GCodeSystem, Input, InputSyntax, LatheX, LogicLevel, MAX_SECONDS, Machine, MacroDialect,
    MainM99, N33G18, OutputFrame, Request,
};

/// The program to read.
#[derive(clap::Args, Debug, Clone)]
pub struct InputArgs {
    /// The macro program (`-` reads standard input).
    pub file: PathBuf,
    /// The character set of the program and library files; default: UTF-8, or a Cyrillic set guessed
    /// (with a warning) when only comments hold bytes that are not UTF-8.
    #[arg(help_heading = "Input", long, value_parser = choice::<Charset>(), value_name = "CHARSET")]
    pub encoding: Option<Charset>,
    /// Refuse any input file (program, library, --vars, --probe-points) larger than this; K M G
    /// suffixes (powers of 1024).
    #[arg(help_heading = "Input", long, value_name = "BYTES", default_value = "256M", value_parser = parse_size_nonzero)]
    pub max_input: u64,
    /// Skip blocks that start with `/` (the block-delete switch is on).
    #[arg(help_heading = "Input", long)]
    pub block_delete: bool,
    /// Do not print warnings.
    #[arg(help_heading = "Input", short, long)]
    pub quiet: bool,
    /// A folder of called programs (`O9010.nc`, or any .nc file whose first line is `O9010`); repeatable.
    #[arg(help_heading = "Input", long = "lib", value_name = "DIR")]
    pub libs: Vec<PathBuf>,
    /// `M97 P…` calls the local subprogram at sequence number P (Haas).
    #[arg(help_heading = "Macro rules", long)]
    pub m97: bool,
    /// A control's built-in parameters: `fanuc-0i` (the default), `haas`, `nct`, `fms3000`; `--params`
    /// and the flags override them.
    #[arg(help_heading = "Macro rules", long, value_parser = choice::<Control>(), value_name = "NAME")]
    pub control: Option<Control>,
    /// Where AND, OR and XOR bind: `fanuc` (AND with * /, OR XOR with + -), `additive` (all three with
    /// + -, Rockwell) or `lowest` (below + -, as LinuxCNC). Default: the parameters', else fanuc.
    #[arg(help_heading = "Macro rules", long, value_parser = choice::<LogicLevel>())]
    pub logic_level: Option<LogicLevel>,
    /// Whose macro syntax the program is written in: `fanuc`, or `haas` (IF without THEN, M99 Pn
    /// branching within the program, M97, DPRNT without POPEN). Default: the parameters', else fanuc.
    #[arg(help_heading = "Macro rules", long, value_parser = choice::<MacroDialect>())]
    pub macro_dialect: Option<MacroDialect>,
    /// Which control's program text this is: `fanuc` (default) or `nct` (the incremental operator
    /// `XI10`, POPEN/PCLOS channel numbers).
    #[arg(
        help_heading = "Macro rules",
        long = "input",
        value_parser = choice::<InputSyntax>(),
        value_name = "SYNTAX"
    )]
    pub input_syntax: Option<InputSyntax>,
    /// The control's parameters from a TOML file: the G, M and T codes that call macros and
    /// subprograms (docs/params.md).
    #[arg(help_heading = "Macro rules", long, value_name = "FILE")]
    pub params: Option<PathBuf>,
    /// A fast path turned off (the tests hold each to the general one; the output is the same):
    /// `flat` (the file run without compiling it), `pipeline` (plain blocks written by a second
    /// thread), `plain` (the kernel's and the emitter's plain-block paths). Repeatable.
    #[arg(long, value_parser = choice::<FastPath>(), value_name = "PATH", hide = true)]
    pub without: Vec<FastPath>,
}

/// The value parser of a request's choice (`--engine`, `--control`, …): its names, aliases and
/// help from the driver's table, the one place they are written.
pub fn choice<T: Choice + Send + Sync + Clone>() -> ChoiceParser<T> {
    ChoiceParser(std::marker::PhantomData)
}

/// The value parser `choice` makes.
#[derive(Clone)]
pub struct ChoiceParser<T>(std::marker::PhantomData<T>);

impl<T: Choice> ChoiceParser<T> {
    /// Each value as clap shows and reads it: its name, aliases and help.
    fn values() -> impl Iterator<Item = PossibleValue> {
        T::NAMES.iter().map(|n| {
            PossibleValue::new(n.name)
                .aliases(n.aliases.iter().copied())
                .help(n.help)
        })
    }

    fn names() -> PossibleValuesParser {
        PossibleValuesParser::new(Self::values())
    }
}

impl<T: Choice + Send + Sync + Clone> TypedValueParser for ChoiceParser<T> {
    type Value = T;

    fn parse_ref(
        &self,
        cmd: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &std::ffi::OsStr,
    ) -> Result<T, clap::Error> {
        let name = Self::names().parse_ref(cmd, arg, value)?;
        T::named(&name).ok_or_else(|| clap::Error::new(clap::error::ErrorKind::InvalidValue))
    }

    fn possible_values(&self) -> Option<Box<dyn Iterator<Item = PossibleValue> + '_>> {
        Some(Box::new(Self::values()))
    }
}

/// A distance tolerance: positive, at most 10.
fn parse_tolerance(s: &str) -> Result<f64, String> {
    let v: f64 = s.parse().map_err(|_| format!("`{s}` is not a number"))?;
    if v > 0.0 && v <= 10.0 {
        Ok(v)
    } else {
        Err(format!("the tolerance is above 0 and at most 10, not {s}"))
    }
}

/// The power-on modal state from a list of G codes.
fn parse_modal(s: &str) -> Result<String, String> {
    // Read in the machine's codes once the machine is known; here only the words are checked.
    for word in s.split(|c: char| c.is_whitespace() || c == ',') {
        if !word.is_empty()
            && word
                .strip_prefix(['G', 'g'])
                .and_then(|v| v.parse::<f64>().ok())
                .is_none()
        {
            return Err(format!("`{word}` is not a G code"));
        }
    }
    Ok(s.to_string())
}

/// Flags of `fmsvm run`.
#[derive(clap::Args, Debug, Clone)]
pub struct RunArgs {
    /// The program.
    #[command(flatten)]
    pub input: InputArgs,
    /// Write the flat program here (atomically; `-` = standard output, the default). A FIFO or a
    /// character device is written directly; a symbolic link's target is replaced.
    #[arg(help_heading = "Output", short, long, value_name = "OUT")]
    pub output: Option<PathBuf>,
    /// The character set of comments and printed text in the outputs (default: the program's).
    #[arg(help_heading = "Output", long, value_parser = choice::<Charset>(), value_name = "CHARSET")]
    pub output_encoding: Option<Charset>,
    /// Stop after this many branches taken (loop iterations, GOTOs); 0 = no limit.
    #[arg(
        help_heading = "Limits",
        long,
        default_value_t = 1_000_000_000,
        value_name = "N"
    )]
    pub max_steps: u64,
    /// Stop after this many NC blocks, run or written (a canned cycle's moves and an arc's chords
    /// count one each); 0 = no limit.
    #[arg(
        help_heading = "Limits",
        long,
        default_value_t = 10_000_000,
        value_name = "N"
    )]
    pub max_blocks: u64,
    /// Stop after this many seconds of wall time (a runaway loop without output stops too).
    #[arg(help_heading = "Limits", long, value_name = "SECONDS", value_parser = parse_seconds)]
    pub max_seconds: Option<f64>,
    /// Fanuc parameter NAT: ATAN gives −180…180 and ASIN −90…90 (default 0…360 and 270…90).
    #[arg(help_heading = "Macro rules", long)]
    pub nat: bool,
    /// MOD rounds both operands to integers first (the 30i rule; default: remainder of the values).
    #[arg(help_heading = "Macro rules", long)]
    pub mod_integers: bool,
    /// Subprogram (M98/M97) nesting allowed, 1 to 10 (Fanuc default 4; the fifth is alarm 0077).
    #[arg(help_heading = "Limits", long, default_value_t = 4, value_parser = clap::value_parser!(u8).range(1..=10))]
    pub sub_depth: u8,
    /// Stop when the flat program and the printed output together would exceed this many bytes
    /// (K M G suffixes); 0 = no limit.
    #[arg(help_heading = "Limits", long, default_value = "1G", value_name = "BYTES", value_parser = parse_size)]
    pub max_bytes: u64,
    /// Stop when the printed output (DPRNT/BPRNT) would exceed this many bytes (K M G); 0 = no limit.
    #[arg(help_heading = "Limits", long, default_value = "64M", value_name = "BYTES", value_parser = parse_size)]
    pub max_print_bytes: u64,
    /// Leave the program's comments out of the output. By default they are kept wherever the
    /// dialect has a comment syntax (the FMS-3000, the Маяк-600Т, the НЦ-31 and the Н33-2М tape have
    /// none: there the run says once that they were left out).
    #[arg(help_heading = "Output", long)]
    pub no_comments: bool,
    /// Keep the comments (the default; accepted for scripts written when it was not).
    #[arg(long, hide = true, conflicts_with = "no_comments")]
    pub comments: bool,
    /// The control the output is for (`fmsvm dialects` lists them; default `fanuc`, or `fanuc0itd`
    /// for a turning program). Dialects other than Fanuc's get resolved motion (as --resolve).
    #[arg(help_heading = "Dialect", long, value_name = "NAME")]
    pub dialect: Option<String>,
    /// A dialect profile (TOML) over the built-in one it names as `base` (see `fmsvm dialects --show`).
    #[arg(
        help_heading = "Dialect",
        long,
        value_name = "FILE",
        conflicts_with = "dialect"
    )]
    pub dialect_file: Option<PathBuf>,
    /// Leave out the words that repeat the modal state (G, F and unchanged axis words), as CAM
    /// postprocessors do.
    #[arg(help_heading = "Output", long)]
    pub compact: bool,
    /// After writing, read the output back with the dialect's reader and prove its motion equals
    /// the kernel's within the dialect's resolution (exit code 7 on a mismatch).
    #[arg(help_heading = "Verification", long)]
    pub verify: bool,
    /// Write nothing: verify FILE, an output written before in this dialect, against the program
    /// (exit code 7 when it does not move as the program does).
    #[arg(
        help_heading = "Verification",
        long,
        value_name = "FILE",
        conflicts_with = "verify"
    )]
    pub verify_file: Option<PathBuf>,
    /// Н33-2М: write the punched tape itself (ISO 7-bit, even parity in bit 8, NUL leader, gaps
    /// and trailer) instead of its text.
    #[arg(help_heading = "Dialect", long)]
    pub tape: bool,
    /// Н33-2М: the sense of G02/G03 in the XZ plane (G18): `manual` (the default: the manual's XZ
    /// example, counter-clockwise drawn with X right and Z up) or `iso` (ISO 6983: seen from +Y,
    /// Z right and X up). Check it on the machine.
    #[arg(
        help_heading = "Dialect",
        long,
        value_parser = choice::<N33G18>(),
        value_name = "SENSE",
        default_value = "manual"
    )]
    pub n33_g18: N33G18,
    /// Н33-2М: brake (feed code F4…, decelerate to 240 mm/min at the block's end) where a corner
    /// would change the velocity by more than this many mm/min (the feed × 2·sin(turn/2)); 1000
    /// brakes a 90° corner from 710 mm/min up. `inf` never brakes.
    #[arg(
        help_heading = "Dialect",
        long,
        value_name = "MM_PER_MIN",
        default_value_t = fmsvm_emit::n33::BRAKE_STEP,
        value_parser = parse_brake_step
    )]
    pub n33_brake_step: f64,
    /// Н33-2М: the longest tape the machine's reader takes, metres (§5.1: 30 with the ФСУ-2
    /// photo-reader, the default; 150 the tape itself). A longer tape is refused at the block that
    /// passes it, 2.54 mm a row with the leader, gaps and trailer.
    #[arg(
        help_heading = "Dialect",
        long,
        value_name = "M",
        default_value_t = fmsvm_emit::n33::MAX_TAPE_M,
        value_parser = parse_tape_length
    )]
    pub n33_tape_length: f64,
    /// The machine's travel on each axis, mm: `X1000 Y400 Z150`, or `none`. A program whose moves
    /// on an axis span more cannot run wherever the part is clamped: refused (alarm 0500) at the
    /// block that passes it. Replaces the dialect profile's `[motion] travel` and the Н33-2М's own
    /// (the 6Р13Ф3-37: X1000 Y400 Z150, A.2).
    #[arg(
        help_heading = "Dialect",
        long,
        value_name = "TRAVELS",
        value_parser = fmsvm_emit::travel::parse
    )]
    pub travel: Option<[f64; 6]>,
    /// Н33-2М: a program over 999 blocks goes on several tapes, one after another in the output:
    /// each ends after a rapid with M02, the next starts with its own leader and % where the last
    /// left the tool (§5.2.1). Without it such a program is refused.
    #[arg(help_heading = "Dialect", long)]
    pub split_tapes: bool,
    /// Renumber the output blocks: `--renumber 10` gives N10 N20 …; `--renumber 100,5` starts at N100.
    #[arg(help_heading = "Output", long, value_name = "STEP|START,STEP", value_parser = parse_renumber)]
    pub renumber: Option<(u32, u32)>,
    /// How a literal without a decimal point is read (`X10`).
    /// Default: the parameters', else calculator.
    #[arg(help_heading = "Macro rules", long, value_parser = choice::<DecimalInput>())]
    pub decimal_input: Option<DecimalInput>,
    /// Load retained common variables #500–#999 from this file (`#500=1.25` lines).
    #[arg(help_heading = "Variables", long, value_name = "FILE")]
    pub vars: Option<PathBuf>,
    /// Write the common variables #100–#199 and #500–#999 to this file at the end.
    #[arg(help_heading = "Variables", long, value_name = "FILE")]
    pub dump_vars: Option<PathBuf>,
    /// Which engine runs the program: the interpreter, the Cranelift JIT, or `auto` (interpret, and
    /// move to the JIT at a loop head once the program has taken 100 000 branches). All three give
    /// identical output.
    #[arg(help_heading = "Run", long, value_parser = choice::<EngineKind>(), default_value = "auto")]
    pub engine: EngineKind,
    /// Print what the run did (blocks, steps, time) to standard error.
    #[arg(help_heading = "Run", long)]
    pub stats: bool,
    /// Where DPRNT/BPRNT records go (`-` = standard output); default: beside the output file with
    /// extension .prn, or beside the input (input.prn) when the output is not a file. Written only if
    /// something was printed.
    #[arg(help_heading = "Printing (DPRNT/BPRNT)", long, value_name = "FILE")]
    pub print: Option<PathBuf>,
    /// DPRNT/BPRNT work without POPEN (Haas) instead of stopping with an alarm.
    #[arg(help_heading = "Printing (DPRNT/BPRNT)", long)]
    pub print_without_popen: bool,
    /// Do not send DC2/DC4 for POPEN/PCLOS.
    #[arg(help_heading = "Printing (DPRNT/BPRNT)", long)]
    pub no_dc_codes: bool,
    /// Write the motion instead of the words: only G0 G1 G2 G3 (with G4, F, S, T, M and comments) in
    /// G90, every work offset, G52/G92 shift, rotation, scaling, mirror, canned cycle and cutter
    /// compensation applied.
    #[arg(help_heading = "Kernel", long)]
    pub resolve: bool,
    /// The frame resolved output is written in: G54 as the program leaves it, or machine coordinates.
    #[arg(help_heading = "Kernel", long, value_parser = choice::<OutputFrame>(), default_value = "g54")]
    pub frame: OutputFrame,
    /// Write arcs as straight chords that stay within this distance of the arc (mm or inch).
    #[arg(help_heading = "Kernel", long, value_name = "TOL", value_parser = parse_tolerance)]
    pub linearize: Option<f64>,
    /// How far an arc's end point may lie off its circle before alarm 0020 (Fanuc parameter 3410).
    #[arg(help_heading = "Kernel", long, value_name = "TOL", default_value_t = 0.005, value_parser = parse_tolerance)]
    pub arc_tolerance: f64,
    /// Cutter compensation rules: Fanuc's (convex corners joined at the intersection) or LinuxCNC's
    /// (convex corners rolled round on an arc of the tool radius).
    #[arg(help_heading = "Kernel", long, value_parser = choice::<CompStyle>(), default_value = "fanuc")]
    pub comp_style: CompStyle,
    /// Where the tool stands when the program starts, as axis words in the work coordinates of the
    /// power-on work offset (`X0 Y0 Z100`; any of X Y Z A B C). Without it no position is assumed:
    /// each axis is unknown until the program positions it (docs/kernel.md).
    #[arg(help_heading = "Machine model", long, value_name = "WORDS", value_parser = fmsvm_driver::request::parse_start_point)]
    pub start_point: Option<[f64; 6]>,
    /// An output move of an axis its block does not name (a changed length offset, …), and a cutter
    /// or length register the program and --offsets never set, stop the run instead of a warning.
    #[arg(help_heading = "Kernel", long)]
    pub strict_axes: bool,
    /// The modal state at power-on, as G codes in the machine's numbering (default: a mill's
    /// G17 G90 G94 G21 G40 G49 G80 G98 G0; a lathe's G18 G99 G21 G40 G97 G67 in system A).
    #[arg(help_heading = "Machine model", long, value_name = "CODES", value_parser = parse_modal)]
    pub modal: Option<String>,
    /// The machine the program is for (default: the --control profile's, else the dialect's: a
    /// lathe dialect makes it a lathe, else a mill).
    #[arg(help_heading = "Machine model", long, value_parser = choice::<Machine>())]
    pub machine: Option<Machine>,
    /// A lathe's X words: diameters or radii (Fanuc parameter 1006#3; default diameter).
    #[arg(help_heading = "Machine model", long, value_parser = choice::<LatheX>())]
    pub lathe_x: Option<LatheX>,
    /// A lathe's G-code system (Fanuc parameter 3401#6; default A).
    #[arg(help_heading = "Machine model", long, value_parser = choice::<GCodeSystem>())]
    pub gcode_system: Option<GCodeSystem>,
    /// Work offsets, tool registers and reference positions from a TOML file (docs/offsets.md).
    #[arg(help_heading = "Machine model", long, value_name = "FILE")]
    pub offsets: Option<PathBuf>,
    /// After an alarm or a limit, keep what was expanded in OUT's name with `.PARTIAL` before the extension.
    #[arg(help_heading = "Output", long)]
    pub keep_partial: bool,
    /// What `M99` in the main program does.
    #[arg(help_heading = "Macro rules", long, value_parser = choice::<MainM99>(), default_value = "restart")]
    pub main_m99: MainM99,
    /// The date #3011 reads, YYYYMMDD (default: today, or SOURCE_DATE_EPOCH).
    #[arg(help_heading = "Machine model", long, value_name = "YYYYMMDD", value_parser = parse_date)]
    pub date: Option<u32>,
    /// The time #3012 reads, HHMMSS (default: now, or SOURCE_DATE_EPOCH).
    #[arg(help_heading = "Machine model", long, value_name = "HHMMSS", value_parser = parse_time)]
    pub time: Option<u32>,
    /// A box of stock for G31 probing, `plot`'s outline and the material `stats`, `plot` and a
    /// verified `run` cut: XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX (work coordinates; on a lathe X as the
    /// program writes it, a diameter on a diameter lathe, the bar).
    #[arg(help_heading = "Machine model", long, value_name = "BOX", value_parser = fmsvm_driver::request::parse_stock_box, conflicts_with_all = ["probe_points", "stock_cylinder"])]
    pub stock: Option<[f64; 6]>,
    /// A mill's round blank standing on Z: X,Y,DIAMETER,ZMIN,ZMAX (its axis at X Y, work
    /// coordinates), the material `stats`, `plot` and a verified `run` cut.
    #[arg(help_heading = "Machine model", long, value_name = "X,Y,D,ZMIN,ZMAX", value_parser = fmsvm_driver::request::parse_stock_cylinder, conflicts_with = "probe_points")]
    pub stock_cylinder: Option<[f64; 5]>,
    /// The side of the stock's cells for the material `stats` simulates with --stock (mm or inch;
    /// default 0.1 on a mill, 0.05 on a lathe): each move cuts exactly at each cell's centre.
    #[arg(help_heading = "Machine model", long, value_name = "SIDE", value_parser = parse_tolerance)]
    pub stock_cell: Option<f64>,
    /// What the stock finds (a rapid into material, a cut below its floor, a shank that rubs, a
    /// plunge with a tool that cannot) stops the run at its block instead of a warning.
    #[arg(help_heading = "Machine model", long)]
    pub strict_stock: bool,
    /// Radius of the probe's stylus ball (with --stock).
    #[arg(
        help_heading = "Machine model",
        long,
        default_value_t = 0.0,
        value_name = "R",
        value_parser = parse_radius
    )]
    pub probe_radius: f64,
    /// Planned touch points for G31, one `X… Y… Z…` line per G31 in order.
    #[arg(help_heading = "Machine model", long, value_name = "FILE")]
    pub probe_points: Option<PathBuf>,
    /// Rapid traverse rate in mm/min for the machining-time estimate behind #3001/#3002.
    #[arg(
        help_heading = "Machine model",
        long,
        default_value_t = DEFAULT_RAPID,
        value_name = "MM_PER_MIN",
        value_parser = parse_rate
    )]
    pub rapid: f64,
}

impl InputArgs {
    /// The driver's input: these flags as they are.
    pub fn input(&self) -> Input {
        Input {
            file: self.file.clone(),
            text: None,
            encoding: self.encoding,
            max_input: self.max_input,
            block_delete: self.block_delete,
            quiet: self.quiet,
            libs: self.libs.clone(),
            m97: self.m97,
            control: self.control,
            logic_level: self.logic_level,
            macro_dialect: self.macro_dialect,
            input_syntax: self.input_syntax,
            params: self.params.clone(),
            without: self.without.clone(),
        }
    }
}

impl RunArgs {
    /// The driver's request: these flags as they are.
    pub fn request(&self) -> Request {
        Request {
            input: self.input.input(),
            output: self.output.clone(),
            output_encoding: self.output_encoding,
            max_steps: self.max_steps,
            max_blocks: self.max_blocks,
            max_seconds: self.max_seconds,
            nat: self.nat,
            mod_integers: self.mod_integers,
            sub_depth: self.sub_depth,
            max_bytes: self.max_bytes,
            max_print_bytes: self.max_print_bytes,
            comments: !self.no_comments,
            dialect: self.dialect.clone(),
            dialect_file: self.dialect_file.clone(),
            compact: self.compact,
            verify: self.verify,
            verify_file: self.verify_file.clone(),
            tape: self.tape,
            n33_g18: self.n33_g18,
            n33_brake_step: self.n33_brake_step,
            n33_tape_length: self.n33_tape_length,
            travel: self.travel,
            split_tapes: self.split_tapes,
            renumber: self.renumber,
            decimal_input: self.decimal_input,
            vars: self.vars.clone(),
            dump_vars: self.dump_vars.clone(),
            engine: self.engine,
            stats: self.stats,
            print: self.print.clone(),
            print_without_popen: self.print_without_popen,
            no_dc_codes: self.no_dc_codes,
            resolve: self.resolve,
            frame: self.frame,
            linearize: self.linearize,
            arc_tolerance: self.arc_tolerance,
            comp_style: self.comp_style,
            start_point: self.start_point,
            strict_axes: self.strict_axes,
            modal: self.modal.clone(),
            machine: self.machine,
            lathe_x: self.lathe_x,
            gcode_system: self.gcode_system,
            offsets: self.offsets.clone(),
            keep_partial: self.keep_partial,
            main_m99: self.main_m99,
            date: self.date,
            time: self.time,
            stock: self
                .stock
                .or(self.stock_cylinder.map(fmsvm_driver::request::cylinder_box)),
            stock_round: self.stock_cylinder.is_some(),
            stock_cell: self.stock_cell,
            strict_stock: self.strict_stock,
            probe_radius: self.probe_radius,
            probe_points: self.probe_points.clone(),
            rapid: self.rapid,
        }
    }
}

/// The flags of `run` about the flat program's text, by id, each with whether a run's arguments
/// use it: `stats` and `plot` write none, hide them in their help and refuse them
/// (`text_flag_used`).
pub const TEXT_FLAGS: [(&str, UsedBy); 12] = [
    ("verify", |a| a.verify),
    ("verify_file", |a| a.verify_file.is_some()),
    ("tape", |a| a.tape),
    ("renumber", |a| a.renumber.is_some()),
    ("compact", |a| a.compact),
    ("no_comments", |a| a.no_comments),
    ("n33_g18", |a| a.n33_g18 != N33G18::Manual),
    ("n33_brake_step", |a| {
        a.n33_brake_step != fmsvm_emit::n33::BRAKE_STEP
    }),
    ("n33_tape_length", |a| {
        a.n33_tape_length != fmsvm_emit::n33::MAX_TAPE_M
    }),
    ("split_tapes", |a| a.split_tapes),
    ("keep_partial", |a| a.keep_partial),
    ("travel", |a| a.travel.is_some()),
];

/// Whether a run's arguments use a flag.
pub type UsedBy = fn(&RunArgs) -> bool;

/// The first of the `TEXT_FLAGS` that `a` uses, as the command line spells it (`--verify-file`).
pub fn text_flag_used(a: &RunArgs) -> Option<String> {
    TEXT_FLAGS
        .iter()
        .find(|(_, used)| used(a))
        .map(|(id, _)| format!("--{}", id.replace('_', "-")))
}

/// The flags `-h` shows, each with its help in a line: what most runs need. `--help` shows every
/// flag under its heading with its whole help; `for_screen` makes the difference.
pub const ON_SCREEN: [(&str, &str); 12] = [
    ("quiet", "Do not print warnings"),
    (
        "libs",
        "A folder of called programs (`O9010.nc`); repeatable",
    ),
    (
        "control",
        "The control's built-in parameters (default fanuc-0i)",
    ),
    (
        "params",
        "The control's parameters from a TOML file (docs/params.md)",
    ),
    (
        "output",
        "Write the flat program here (default: standard output)",
    ),
    ("no_comments", "Leave the program's comments out"),
    ("renumber", "Renumber the output blocks: 10 gives N10 N20 …"),
    (
        "dialect",
        "The control the output is for (`fmsvm dialects` lists them)",
    ),
    (
        "verify",
        "Read the output back and prove it moves as the program does",
    ),
    (
        "resolve",
        "Write the motion: every offset, transform and cycle applied",
    ),
    (
        "offsets",
        "Work offsets, tool registers and reference positions (TOML)",
    ),
    (
        "start_point",
        "Where the tool stands at the start (`X0 Y0 Z100`)",
    ),
];

/// `arg` as `-h` and `--help` show it: the `ON_SCREEN` flags with their line under `-h` and their
/// whole help (the values listed) under `--help`; every other flag under `--help` only.
pub fn for_screen(arg: clap::Arg) -> clap::Arg {
    let id = arg.get_id().as_str().to_string();
    let Some((_, line)) = ON_SCREEN.iter().find(|(n, _)| *n == id) else {
        return if arg.is_positional() {
            arg
        } else {
            arg.hide_short_help(true)
        };
    };
    let mut whole = arg
        .get_long_help()
        .or(arg.get_help())
        .map(|h| h.to_string())
        .unwrap_or_default();
    let values: Vec<String> = arg
        .get_possible_values()
        .iter()
        .filter(|v| !v.is_hide_set())
        .map(|v| match v.get_help() {
            Some(h) => format!("- {}: {h}", v.get_name()),
            None => format!("- {}", v.get_name()),
        })
        .collect();
    if values.is_empty() || !arg.get_action().takes_values() {
        return arg.help(*line).long_help(whole);
    }
    whole.push_str("\n\nPossible values:\n");
    whole.push_str(&values.join("\n"));
    arg.help(*line).long_help(whole).hide_possible_values(true)
}

/// `arg` hidden from the help when it is one of the `TEXT_FLAGS`.
pub fn hide_text_flags(arg: clap::Arg) -> clap::Arg {
    let id = arg.get_id().as_str();
    let hide = TEXT_FLAGS.iter().any(|(t, _)| *t == id) || arg.is_hide_set();
    arg.hide(hide)
}

fn parse_seconds(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v > 0.0 && v <= MAX_SECONDS => Ok(v),
        _ => Err(format!(
            "`{s}` is not a number of seconds from 0.001 to 1e9"
        )),
    }
}

/// A rapid rate in mm/min: more than 0, at most 1 000 000 (over 16 m/s; no machine is faster).
fn parse_rate(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v > 0.0 && v <= 1e6 => Ok(v),
        _ => Err(format!(
            "`{s}` is not a rapid rate: give mm/min, more than 0 and at most 1000000"
        )),
    }
}

fn parse_radius(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if (0.0..=1e4).contains(&v) => Ok(v),
        _ => Err(format!(
            "`{s}` is not a stylus radius: give mm, from 0 to 10000"
        )),
    }
}

/// A byte count with an optional K, M or G suffix (powers of 1024); 0 allowed (no limit).
pub fn parse_size(s: &str) -> Result<u64, String> {
    let t = s.trim();
    let (digits, shift) = match t.char_indices().last() {
        Some((i, c)) if c.eq_ignore_ascii_case(&'k') => (&t[..i], 10),
        Some((i, c)) if c.eq_ignore_ascii_case(&'m') => (&t[..i], 20),
        Some((i, c)) if c.eq_ignore_ascii_case(&'g') => (&t[..i], 30),
        _ => (t, 0),
    };
    digits
        .parse::<u64>()
        .ok()
        .and_then(|n| n.checked_mul(1u64 << shift))
        .ok_or_else(|| {
            format!("`{s}` is not a byte count (a whole number, optionally with K, M or G)")
        })
}

pub fn parse_size_nonzero(s: &str) -> Result<u64, String> {
    match parse_size(s)? {
        0 => Err("the input bound must be at least 1 byte".into()),
        n => Ok(n),
    }
}

fn digits(s: &str, n: usize, what: &str) -> Result<u32, String> {
    let t = s.trim();
    if t.len() != n || !t.bytes().all(|b| b.is_ascii_digit()) {
        return Err(format!("`{s}` is not {what}"));
    }
    t.parse().map_err(|_| format!("`{s}` is not {what}"))
}

/// `YYYYMMDD`, a real calendar day (years 1900 to 9999, as #3011 holds eight digits).
fn parse_date(s: &str) -> Result<u32, String> {
    let v = digits(s, 8, "a date YYYYMMDD")?;
    let (y, m, d) = (v / 10_000, v / 100 % 100, v % 100);
    let leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
    let days = match m {
        1 | 3 | 5 | 7 | 8 | 10 | 12 => 31,
        4 | 6 | 9 | 11 => 30,
        2 if leap => 29,
        2 => 28,
        _ => return Err(format!("`{s}`: month {m} does not exist (01 to 12)")),
    };
    if y < 1900 {
        return Err(format!("`{s}`: the year must be 1900 or later"));
    }
    if d == 0 || d > days {
        return Err(format!(
            "`{s}`: day {d} does not exist in month {m:02} of {y}"
        ));
    }
    Ok(v)
}

/// `HHMMSS` on a 24-hour clock.
fn parse_time(s: &str) -> Result<u32, String> {
    let v = digits(s, 6, "a time HHMMSS")?;
    let (h, m, sec) = (v / 10_000, v / 100 % 100, v % 100);
    if h > 23 || m > 59 || sec > 59 {
        return Err(format!(
            "`{s}` is not a time of day (hours 00-23, minutes and seconds 00-59)"
        ));
    }
    Ok(v)
}

fn parse_renumber(s: &str) -> Result<(u32, u32), String> {
    let parse = |t: &str| {
        t.trim()
            .parse::<u32>()
            .map_err(|_| format!("`{t}` is not a whole number"))
    };
    let (start, step) = match s.split_once(',') {
        Some((a, b)) => (parse(a)?, parse(b)?),
        None => {
            let step = parse(s)?;
            (step, step)
        }
    };
    if step == 0 || start == 0 || start > 99_999 {
        return Err("start and step must be 1 to 99999".into());
    }
    Ok((start, step))
}

/// `--n33-tape-length`: metres of tape, above 0 and at most the 150 m a tape is (§5.1).
fn parse_tape_length(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v > 0.0 && v <= 150.0 => Ok(v),
        _ => Err(format!(
            "`{s}` is not a tape length in metres (above 0, at most 150: the tape, §5.1)"
        )),
    }
}

/// `--n33-brake-step`: a velocity step in mm/min, 0 or more (`inf`: never).
fn parse_brake_step(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v >= 0.0 => Ok(v),
        _ => Err(format!(
            "`{s}` is not a velocity step in mm/min (0 or more, or inf)"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(Parser)]
    struct Run {
        #[command(flatten)]
        run: RunArgs,
    }

    /// The flags' defaults are the request's: a run with no flag is `Request::new`.
    #[test]
    fn no_flag_is_the_default_request() {
        let r = Run::try_parse_from(["fmsvm", "part.nc"]).expect("parses");
        assert_eq!(r.run.request(), Request::new(Input::new("part.nc")));
    }

    /// Each choice reads its names and aliases from the driver's table.
    #[test]
    fn choices_read_their_names_and_aliases() {
        let r = Run::try_parse_from([
            "fmsvm",
            "p.nc",
            "--encoding",
            "utf8",
            "--engine",
            "jit",
            "--frame",
            "machine",
            "--comp-style",
            "linuxcnc",
            "--control",
            "haas-lathe",
            "--gcode-system",
            "b",
        ])
        .expect("parses");
        let q = r.run.request();
        assert_eq!(q.input.encoding, Some(Charset::Utf8));
        assert_eq!(q.engine, EngineKind::Jit);
        assert_eq!(q.frame, OutputFrame::Machine);
        assert_eq!(q.comp_style, CompStyle::LinuxCnc);
        assert_eq!(q.input.control, Some(Control::HaasLathe));
        assert_eq!(q.gcode_system, Some(GCodeSystem::B));
        let e = Run::try_parse_from(["fmsvm", "p.nc", "--engine", "fast"])
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default();
        assert!(
            e.contains("invalid value 'fast'") && e.contains("interp, jit, auto"),
            "{e}"
        );
    }
}
