//! What a front end asks of the pipeline: the program and its input rules (`Input`), and a run with
//! its outputs, limits and machine model (`Request`). Plain data: the command line, the editor, the
//! debugger, DNC and `post` each fill one; `run::configure` checks it and reads the files it names.
//!
//! The choices among named values (`Choice`) carry their names once, for the command line and for
//! the settings files alike.

use std::path::PathBuf;

pub use crate::input::Charset;
pub use fmsvm_canon::decode::DecimalInput;
pub use fmsvm_compiler::precedence::LogicLevel;
pub use fmsvm_kernel::{CompStyle, OutputFrame};
pub use fmsvm_vm::EngineKind;

/// One named value of a choice: its name, other names it is known by, and a line of help.
pub struct Named<T: 'static> {
    pub value: T,
    pub name: &'static str,
    pub aliases: &'static [&'static str],
    pub help: &'static str,
}

impl<T> Named<T> {
    /// `value` called `name`, with no other name.
    pub const fn new(value: T, name: &'static str, help: &'static str) -> Named<T> {
        Named {
            value,
            name,
            aliases: &[],
            help,
        }
    }
}

/// A value chosen by name on the command line or in a settings file: every value with its names.
pub trait Choice: Copy + PartialEq + Sized + 'static {
    /// Every value, in the order the help lists them.
    const NAMES: &'static [Named<Self>];

    /// The value called `name` (or one of its aliases).
    fn named(name: &str) -> Option<Self> {
        Self::NAMES
            .iter()
            .find(|n| n.name == name || n.aliases.contains(&name))
            .map(|n| n.value)
    }

    /// The value's name.
    fn name(self) -> &'static str {
        Self::NAMES
            .iter()
            .find(|n| n.value == self)
            .map_or("", |n| n.name)
    }
}

/// Reads a choice by name in a settings file (serde's `deserialize_with`), with serde's own message
/// for a name it does not have.
pub fn by_name<'de, D, T>(d: D) -> Result<Option<T>, D::Error>
where
    D: serde::Deserializer<'de>,
    T: Choice,
{
    let name = <String as serde::Deserialize>::deserialize(d)?;
    T::named(&name).map(Some).ok_or_else(|| {
        let quoted: Vec<String> = T::NAMES.iter().map(|n| format!("`{}`", n.name)).collect();
        let expected = match quoted.as_slice() {
            [one] => one.clone(),
            [a, b] => format!("{a} or {b}"),
            all => format!("one of {}", all.join(", ")),
        };
        serde::de::Error::custom(format!("unknown variant `{name}`, expected {expected}"))
    })
}

/// `Named` without the ceremony: `named!(Value, "name", ["alias"], "help")`.
macro_rules! named {
    ($value:expr, $name:literal, [$($alias:literal),*], $help:literal) => {
        Named { value: $value, name: $name, aliases: &[$($alias),*], help: $help }
    };
}

/// The program to read and how to read it.
#[derive(Clone, Debug, PartialEq)]
pub struct Input {
    /// The macro program (`-` reads standard input); its name in messages.
    pub file: PathBuf,
    /// The program's text as a front end holds it (an editor's buffer, unsaved): read instead of
    /// `file`, which then only names it. None: `file` is read.
    pub text: Option<std::sync::Arc<str>>,
    /// The program's character set (None: UTF-8, or a Cyrillic set guessed with a warning).
    pub encoding: Option<Charset>,
    /// The most bytes any input file may hold.
    pub max_input: u64,
    /// Skip blocks that start with `/`.
    pub block_delete: bool,
    /// Say no warnings.
    pub quiet: bool,
    /// Folders of called programs.
    pub libs: Vec<PathBuf>,
    /// `M97 P…` calls a local subprogram (Haas).
    pub m97: bool,
    /// A control's built-in parameters.
    pub control: Option<Control>,
    /// Where AND, OR and XOR bind (None: the parameters', else Fanuc's).
    pub logic_level: Option<LogicLevel>,
    /// Whose macro syntax the program is in (None: the parameters', else Fanuc's).
    pub macro_dialect: Option<MacroDialect>,
    /// Which control's program text this is (None: the parameters', else Fanuc's).
    pub input_syntax: Option<InputSyntax>,
    /// The control's parameters file.
    pub params: Option<PathBuf>,
    /// Fast paths turned off (the tests hold each to the general one).
    pub without: Vec<FastPath>,
}

impl Input {
    /// `file` read with every rule at its default.
    pub fn new(file: impl Into<PathBuf>) -> Input {
        Input {
            file: file.into(),
            text: None,
            encoding: None,
            max_input: crate::input::DEFAULT_MAX_INPUT,
            block_delete: false,
            quiet: false,
            libs: Vec::new(),
            m97: false,
            control: None,
            logic_level: None,
            macro_dialect: None,
            input_syntax: None,
            params: None,
            without: Vec::new(),
        }
    }
}

/// A run: the program, its outputs, limits, macro rules and machine model.
#[derive(Clone, Debug, PartialEq)]
pub struct Request {
    pub input: Input,
    /// The flat program's file (None or `-`: standard output).
    pub output: Option<PathBuf>,
    /// The character set of the outputs (None: the dialect's, else the program's).
    pub output_encoding: Option<Charset>,
    /// Branches taken before the run stops; 0 = no limit.
    pub max_steps: u64,
    /// NC blocks run or written before the run stops; 0 = no limit.
    pub max_blocks: u64,
    /// Wall time before the run stops, seconds (at most `MAX_SECONDS`).
    pub max_seconds: Option<f64>,
    /// Fanuc parameter NAT.
    pub nat: bool,
    /// MOD of integers (the 30i's rule).
    pub mod_integers: bool,
    /// Subprogram nesting allowed, 1 to 10.
    pub sub_depth: u8,
    /// The most bytes the flat program and the printed output may take together; 0 = no limit.
    pub max_bytes: u64,
    /// The most bytes DPRNT/BPRNT may print; 0 = no limit.
    pub max_print_bytes: u64,
    /// Keep the program's comments in the output where the dialect has a comment syntax (default).
    pub comments: bool,
    /// The output dialect's built-in name.
    pub dialect: Option<String>,
    /// A dialect profile file.
    pub dialect_file: Option<PathBuf>,
    /// Leave out the words that repeat the modal state.
    pub compact: bool,
    /// Read the output back and prove its motion.
    pub verify: bool,
    /// Verify this earlier output instead of writing one.
    pub verify_file: Option<PathBuf>,
    /// Н33-2М: the punched tape itself.
    pub tape: bool,
    /// Н33-2М: the sense of G02/G03 in G18.
    pub n33_g18: N33G18,
    /// Н33-2М: the velocity step that brakes, mm/min.
    pub n33_brake_step: f64,
    /// Н33-2М: the longest tape, metres.
    pub n33_tape_length: f64,
    /// The machine's travel on each axis (NaN: none given).
    pub travel: Option<[f64; 6]>,
    /// Н33-2М: a long program on several tapes.
    pub split_tapes: bool,
    /// Renumber the output blocks: (start, step).
    pub renumber: Option<(u32, u32)>,
    /// How a literal without a decimal point is read (None: the parameters', else calculator).
    pub decimal_input: Option<DecimalInput>,
    /// Retained commons to start from.
    pub vars: Option<PathBuf>,
    /// Where the commons go at the end.
    pub dump_vars: Option<PathBuf>,
    /// The engine that runs the program.
    pub engine: EngineKind,
    /// Say what the run did.
    pub stats: bool,
    /// Where DPRNT/BPRNT records go.
    pub print: Option<PathBuf>,
    /// DPRNT/BPRNT without POPEN (Haas).
    pub print_without_popen: bool,
    /// No DC2/DC4 for POPEN/PCLOS.
    pub no_dc_codes: bool,
    /// Write the motion instead of the words.
    pub resolve: bool,
    /// The frame of resolved output.
    pub frame: OutputFrame,
    /// Arcs as chords within this tolerance.
    pub linearize: Option<f64>,
    /// How far an arc's end may lie off its circle (Fanuc parameter 3410).
    pub arc_tolerance: f64,
    /// The cutter compensation rules.
    pub comp_style: CompStyle,
    /// Where the tool stands at the start (NaN: unknown).
    pub start_point: Option<[f64; 6]>,
    /// A move the block does not name stops the run instead of a warning.
    pub strict_axes: bool,
    /// The power-on modal state, as G codes in the machine's numbering.
    pub modal: Option<String>,
    /// The machine the program is for.
    pub machine: Option<Machine>,
    /// A lathe's X words.
    pub lathe_x: Option<LatheX>,
    /// A lathe's G-code system.
    pub gcode_system: Option<GCodeSystem>,
    /// Work offsets, tool registers and reference positions file.
    pub offsets: Option<PathBuf>,
    /// Keep what was expanded before an alarm.
    pub keep_partial: bool,
    /// What M99 in the main program does.
    pub main_m99: MainM99,
    /// The date #3011 reads, YYYYMMDD.
    pub date: Option<u32>,
    /// The time #3012 reads, HHMMSS.
    pub time: Option<u32>,
    /// A box of stock: XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX.
    pub stock: Option<[f64; 6]>,
    /// The stock is the cylinder inscribed in `stock`'s X Y, axis along Z (a mill's round blank).
    pub stock_round: bool,
    /// The side of the stock's cells for the material simulation (`stats`); None: 0.1 on a mill,
    /// 0.05 on a lathe.
    pub stock_cell: Option<f64>,
    /// The stock's findings stop the run at their block.
    pub strict_stock: bool,
    /// The probe's stylus radius.
    pub probe_radius: f64,
    /// Planned G31 touch points.
    pub probe_points: Option<PathBuf>,
    /// The rapid rate of the time estimates, mm/min.
    pub rapid: f64,
}

impl Request {
    /// A run of `input` with every other setting at its default (the command line's defaults).
    pub fn new(input: Input) -> Request {
        Request {
            input,
            output: None,
            output_encoding: None,
            max_steps: 1_000_000_000,
            max_blocks: 10_000_000,
            max_seconds: None,
            nat: false,
            mod_integers: false,
            sub_depth: 4,
            max_bytes: 1 << 30,
            max_print_bytes: 64 << 20,
            comments: true,
            dialect: None,
            dialect_file: None,
            compact: false,
            verify: false,
            verify_file: None,
            tape: false,
            n33_g18: N33G18::Manual,
            n33_brake_step: fmsvm_emit::n33::BRAKE_STEP,
            n33_tape_length: fmsvm_emit::n33::MAX_TAPE_M,
            travel: None,
            split_tapes: false,
            renumber: None,
            decimal_input: None,
            vars: None,
            dump_vars: None,
            engine: EngineKind::Auto,
            stats: false,
            print: None,
            print_without_popen: false,
            no_dc_codes: false,
            resolve: false,
            frame: OutputFrame::G54,
            linearize: None,
            arc_tolerance: 0.005,
            comp_style: CompStyle::Fanuc,
            start_point: None,
            strict_axes: false,
            modal: None,
            machine: None,
            lathe_x: None,
            gcode_system: None,
            offsets: None,
            keep_partial: false,
            main_m99: MainM99::Restart,
            date: None,
            time: None,
            stock: None,
            stock_round: false,
            stock_cell: None,
            strict_stock: false,
            probe_radius: 0.0,
            probe_points: None,
            rapid: DEFAULT_RAPID,
        }
    }
}

/// The rapid rate of the time estimates when none is given, mm/min.
pub const DEFAULT_RAPID: f64 = 10_000.0;

/// At most about 31 years: any larger wall-time limit is no limit, and `Duration` must hold it.
pub const MAX_SECONDS: f64 = 1e9;

/// The run's fast paths, each with a general path that gives the same output.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FastPath {
    Flat,
    Pipeline,
    Plain,
}

impl Choice for FastPath {
    const NAMES: &'static [Named<Self>] = &[
        named!(FastPath::Flat, "flat", [], ""),
        named!(FastPath::Pipeline, "pipeline", [], ""),
        named!(FastPath::Plain, "plain", [], ""),
    ];
}

impl Choice for Charset {
    const NAMES: &'static [Named<Self>] = &[
        named!(
            Charset::Utf8,
            "utf-8",
            ["utf8"],
            "UTF-8 (a byte-order mark is accepted)"
        ),
        named!(
            Charset::Cp1251,
            "cp1251",
            [],
            "Windows-1251 (Cyrillic, Windows)"
        ),
        named!(Charset::Cp866, "cp866", [], "IBM866 (Cyrillic, DOS)"),
        named!(
            Charset::Koi8R,
            "koi8-r",
            ["koi8r"],
            "KOI8-R (Cyrillic, Unix)"
        ),
        named!(
            Charset::Latin1,
            "latin1",
            ["iso-8859-1"],
            "ISO 8859-1 (Western European)"
        ),
        named!(
            Charset::Ascii,
            "ascii",
            [],
            "7-bit ASCII (other characters become `?`)"
        ),
    ];
}

impl Choice for LogicLevel {
    const NAMES: &'static [Named<Self>] = &[
        named!(
            LogicLevel::Fanuc,
            "fanuc",
            [],
            "AND with `* / MOD`, OR and XOR with `+ -`"
        ),
        named!(
            LogicLevel::Additive,
            "additive",
            [],
            "AND, OR, XOR with `+ -`"
        ),
        named!(LogicLevel::Lowest, "lowest", [], "AND, OR, XOR below `+ -`"),
    ];
}

/// The macro syntax of the input.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MacroDialect {
    Fanuc,
    Haas,
}

impl Choice for MacroDialect {
    const NAMES: &'static [Named<Self>] = &[
        named!(
            MacroDialect::Fanuc,
            "fanuc",
            [],
            "Fanuc Custom Macro B (docs/semantics.md)"
        ),
        named!(
            MacroDialect::Haas,
            "haas",
            [],
            "Haas: the Fanuc language with Haas's IF without THEN, M99 Pn branching within the program, DPRNT without POPEN, and M97 (docs/semantics.md, rows L2, C9, O5)"
        ),
    ];
}

/// A control with built-in parameters (`--control`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Control {
    Fanuc0i,
    Haas,
    Nct,
    Fms3000,
    Fanuc0iT,
    Fanuc30i,
    HaasLathe,
}

impl Choice for Control {
    const NAMES: &'static [Named<Self>] = &[
        named!(
            Control::Fanuc0i,
            "fanuc-0i",
            [],
            "Fanuc 0i-MF set for calculator-type decimal input (parameter 3401#0 DPI = 1, as shops commonly set it): X10 is 10 mm. The factory setting reads X10 as 0.010 mm: `--decimal-input increment`"
        ),
        named!(Control::Haas, "haas", [], "Haas: its macro syntax and M97"),
        named!(
            Control::Nct,
            "nct",
            [],
            "NCT 100M/2000M/99M: NCT syntax, its automatic geometry, its commons"
        ),
        named!(
            Control::Fms3000,
            "fms3000",
            [],
            "FMS-3000: numbers without a point are mm (§1.3.2), I J K from the start point (N3021 = 0)"
        ),
        named!(
            Control::Fanuc0iT,
            "fanuc-0i-t",
            [],
            "Fanuc 0i-TF/0i-TD lathe: a turning program, X a diameter, G-code system A"
        ),
        named!(
            Control::Fanuc30i,
            "fanuc-30i",
            [],
            "Fanuc 30i/31i/32i: the additional common variables #100000–#199999 and #500000–#999999"
        ),
        named!(
            Control::HaasLathe,
            "haas-lathe",
            [],
            "Haas lathe: its macro syntax and M97, a turning program with X a diameter, its one-block G71–G76 (`--control haas --machine lathe` is the same)"
        ),
    ];
}

/// The kind of machine a program is for (`--machine`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Machine {
    Mill,
    Lathe,
}

impl Choice for Machine {
    const NAMES: &'static [Named<Self>] = &[
        named!(
            Machine::Mill,
            "mill",
            [],
            "A machining centre: X Y Z, G17, Fanuc M-series codes"
        ),
        named!(
            Machine::Lathe,
            "lathe",
            [],
            "A lathe: X (diameter) and Z, G18, the lathe's codes (docs/lathe.md)"
        ),
    ];
}

/// How a lathe reads X (Fanuc parameter 1006#3 DIAx).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LatheX {
    Diameter,
    Radius,
}

impl Choice for LatheX {
    const NAMES: &'static [Named<Self>] = &[
        named!(
            LatheX::Diameter,
            "diameter",
            [],
            "X and U are diameters (the lathe's habit; 1006#3 = 1)"
        ),
        named!(LatheX::Radius, "radius", [], "X and U are radii"),
    ];
}

/// A lathe's G-code system (Fanuc parameter 3401#6 GSB).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize)]
pub enum GCodeSystem {
    #[serde(rename = "A")]
    A,
    #[serde(rename = "B")]
    B,
}

impl Choice for GCodeSystem {
    const NAMES: &'static [Named<Self>] = &[
        named!(
            GCodeSystem::A,
            "a",
            [],
            "System A: G90/G92/G94 are the single cycles, G50 the coordinate setting, G98/G99 the feed modes, U and W incremental"
        ),
        named!(
            GCodeSystem::B,
            "b",
            [],
            "System B: G90/G91 absolute/incremental, G92 the coordinate setting, G94/G95 the feed modes, G77/G78/G79 the single cycles"
        ),
    ];
}

/// The input's syntax.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum InputSyntax {
    Fanuc,
    Nct,
}

impl Choice for InputSyntax {
    const NAMES: &'static [Named<Self>] = &[
        named!(InputSyntax::Fanuc, "fanuc", [], "Fanuc Custom Macro B"),
        named!(
            InputSyntax::Nct,
            "nct",
            [],
            "The NCT milling controls: Fanuc's language with NCT words"
        ),
    ];
}

impl Choice for OutputFrame {
    const NAMES: &'static [Named<Self>] = &[
        named!(
            OutputFrame::G54,
            "g54",
            [],
            "G54 (with the external offset) as the program leaves it"
        ),
        named!(OutputFrame::Machine, "machine", [], "Machine coordinates"),
    ];
}

impl Choice for CompStyle {
    const NAMES: &'static [Named<Self>] = &[
        named!(CompStyle::Fanuc, "fanuc", [], "Fanuc's compensation C"),
        named!(CompStyle::LinuxCnc, "linuxcnc", [], "LinuxCNC's"),
    ];
}

impl Choice for EngineKind {
    const NAMES: &'static [Named<Self>] = &[
        named!(EngineKind::Interp, "interp", [], "The interpreter"),
        named!(EngineKind::Jit, "jit", [], "The Cranelift JIT"),
        named!(
            EngineKind::Auto,
            "auto",
            [],
            "Interpret, and move to the JIT at a loop head once the program has taken 100 000 branches"
        ),
    ];
}

/// What `M99` does in the main program.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MainM99 {
    Restart,
    End,
}

impl Choice for MainM99 {
    const NAMES: &'static [Named<Self>] = &[
        named!(
            MainM99::Restart,
            "restart",
            [],
            "Start the program again (as a control does), until a limit stops it"
        ),
        named!(
            MainM99::End,
            "end",
            [],
            "Write `M99` and end the expansion: the control repeats the flat program"
        ),
    ];
}

impl Choice for DecimalInput {
    const NAMES: &'static [Named<Self>] = &[
        named!(
            DecimalInput::Calculator,
            "calculator",
            [],
            "`X10` is 10 mm (calculator type)"
        ),
        named!(
            DecimalInput::Increment,
            "increment",
            [],
            "`X10` is 10 least increments, 0.010 mm (Fanuc decimal-point input type I)"
        ),
    ];
}

/// The sense of the Н33-2М's G02/G03 in G18 (`--n33-g18`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum N33G18 {
    Manual,
    Iso,
}

impl Choice for N33G18 {
    const NAMES: &'static [Named<Self>] = &[
        named!(
            N33G18::Manual,
            "manual",
            [],
            "The manual's XZ example (Fig. 23): G03 is counter-clockwise with X right and Z up"
        ),
        named!(
            N33G18::Iso,
            "iso",
            [],
            "ISO 6983: G03 is counter-clockwise seen from +Y (Z right, X up)"
        ),
    ];
}

/// `XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX`: a box of stock, work coordinates. The one reader of a stock box,
/// for `--stock` and the parameters file's `[machine] stock`.
pub fn parse_stock_box(s: &str) -> Result<[f64; 6], String> {
    let b: [f64; 6] = lengths(s, "six numbers: XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX")?;
    if (0..3).any(|i| b[i] > b[i + 3]) {
        return Err("each minimum must be at most its maximum".into());
    }
    Ok(b)
}

/// `X,Y,D,ZMIN,ZMAX`: a round blank on a mill, its axis along Z at X Y, of diameter D.
pub fn parse_stock_cylinder(s: &str) -> Result<[f64; 5], String> {
    let c: [f64; 5] = lengths(s, "five numbers: X,Y,DIAMETER,ZMIN,ZMAX")?;
    if c[2] <= 0.0 || c[3] > c[4] {
        return Err("the diameter is above 0 and ZMIN at most ZMAX".into());
    }
    Ok(c)
}

/// `N` comma-separated lengths, each finite and within ±1e6 (`what`: the numbers, as the error
/// asks for them).
fn lengths<const N: usize>(s: &str, what: &str) -> Result<[f64; N], String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|t| {
            t.trim()
                .parse::<f64>()
                .map_err(|_| format!("`{t}` is not a number"))
        })
        .collect::<Result<_, _>>()?;
    let b: [f64; N] = v.try_into().map_err(|_| format!("give {what}"))?;
    if let Some(x) = b.iter().find(|x| !x.is_finite() || x.abs() > 1e6) {
        return Err(format!("{x}: each value is a finite length within ±1e6"));
    }
    Ok(b)
}

/// The box a round blank stands in (`--stock`'s form).
pub fn cylinder_box(c: [f64; 5]) -> [f64; 6] {
    let r = c[2] / 2.0;
    [c[0] - r, c[1] - r, c[3], c[0] + r, c[1] + r, c[4]]
}

/// `X0 Y0 Z100`: axis words (X Y Z A B C, each at most once, spaces optional) to a pose with NaN on
/// the axes not given. The one reader of a start point, for the flag and the parameters file.
pub fn parse_start_point(s: &str) -> Result<[f64; 6], String> {
    let mut p = [f64::NAN; 6];
    let mut rest = s.trim();
    if rest.is_empty() {
        return Err("give axis words, e.g. `X0 Y0 Z100`".into());
    }
    while !rest.is_empty() {
        let mut chars = rest.chars();
        let letter = chars.next().unwrap_or(' ').to_ascii_uppercase();
        let Some(i) = fmsvm_canon::AXES
            .iter()
            .position(|l| l.as_str().chars().eq([letter]))
        else {
            return Err(format!(
                "`{}`: a start point is axis words X Y Z A B C",
                rest.split_whitespace().next().unwrap_or(rest)
            ));
        };
        let tail = chars.as_str();
        let end = tail
            .find(|c: char| c.is_ascii_alphabetic() || c.is_whitespace())
            .unwrap_or(tail.len());
        let v: f64 = tail[..end]
            .parse()
            .map_err(|_| format!("`{letter}{}` is not a number", &tail[..end]))?;
        if !v.is_finite() || v.abs() > 1e6 {
            return Err(format!("{letter}{v}: out of range (±1000000)"));
        }
        if !p[i].is_nan() {
            return Err(format!("{letter} is given twice"));
        }
        p[i] = v;
        rest = tail[end..].trim_start();
    }
    Ok(p)
}

/// A start point as the words `parse_start_point` reads.
pub fn start_point_text(p: &[f64; 6]) -> String {
    let mut t = String::new();
    for (i, v) in p.iter().enumerate() {
        if !v.is_nan() {
            if !t.is_empty() {
                t.push(' ');
            }
            t.push_str(&format!("{}{v}", fmsvm_canon::AXES[i]));
        }
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    fn round_trip<T: Choice + std::fmt::Debug>() {
        for n in T::NAMES {
            assert_eq!(T::named(n.name), Some(n.value), "{}", n.name);
            assert_eq!(n.value.name(), n.name);
            for a in n.aliases {
                assert_eq!(T::named(a), Some(n.value), "{a}");
            }
        }
        assert_eq!(T::named("no such name"), None);
    }

    #[test]
    fn every_name_and_alias_reads_back_its_value() {
        round_trip::<FastPath>();
        round_trip::<Charset>();
        round_trip::<LogicLevel>();
        round_trip::<MacroDialect>();
        round_trip::<Control>();
        round_trip::<Machine>();
        round_trip::<LatheX>();
        round_trip::<GCodeSystem>();
        round_trip::<InputSyntax>();
        round_trip::<OutputFrame>();
        round_trip::<CompStyle>();
        round_trip::<EngineKind>();
        round_trip::<MainM99>();
        round_trip::<DecimalInput>();
        round_trip::<N33G18>();
    }

    #[test]
    fn a_request_defaults_as_the_command_line_does() {
        let r = Request::new(Input::new("part.nc"));
        assert_eq!(r.max_bytes, 1 << 30);
        assert_eq!(r.max_print_bytes, 64 << 20);
        assert_eq!(r.input.max_input, 256 << 20);
        assert_eq!(r.engine, EngineKind::Auto);
        assert_eq!(r.rapid, 10_000.0);
    }
}
