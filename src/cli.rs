//! The command line (clap): the subcommands and their flags over the run's (`fmsvm-flags`). `Args`
//! is the raw command line; it does no I/O.

use std::path::PathBuf;

use clap::{Parser, Subcommand};
use fmsvm_driver::request::Control;
pub use fmsvm_flags::{InputArgs, RunArgs, text_flag_used};
use fmsvm_flags::{choice, for_screen, hide_text_flags, parse_size_nonzero};

/// fmsvm expands Fanuc Custom Macro B programs (variables, WHILE loops, IF/GOTO) into flat G-code for
/// controls that cannot run macros.
#[derive(Parser, Debug)]
#[command(name = "fmsvm", version, about, long_about = None, after_help = EXAMPLES)]
pub struct Args {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Compile and run a program; write the flat G-code.
    #[command(after_help = RUN_SHORT, after_long_help = RUN_HELP, mut_args(for_screen))]
    Run(Box<RunArgs>),
    /// Compile only and report every error and warning.
    #[command(after_help = EXIT_CODES)]
    Check(CheckArgs),
    /// Print the compiled IR.
    Ir(InputArgs),
    /// Run a program and report its motion: moves, lengths, extents, estimated time, tool changes.
    #[command(after_help = STATS_HELP)]
    Stats(Box<StatsArgs>),
    /// Print the effective control parameters (`--control`, `--params`) as a file to start from.
    Params(ParamsArgs),
    /// Expand a program and drip-feed it to a control over a serial port or a serial device server.
    #[cfg(feature = "dnc")]
    #[command(after_help = fmsvm_dnc::HELP)]
    Dnc(Box<fmsvm_dnc::DncArgs>),
    /// Run a program and draw its tool path to an SVG or PNG picture.
    #[cfg(feature = "plot")]
    #[command(after_help = PLOT_HELP)]
    Plot(Box<PlotArgs>),
    /// The turning library's postprocessor: its `input.tmp` (the neutral language) to `output.tmp`
    /// in the control's words beside it; prints `OK` or the errors.
    #[command(after_help = POST_HELP)]
    Post(fmsvm_post::PostArgs),
    /// List the output dialects, or print one as a profile to start from (`--show NAME`).
    #[command(after_help = DIALECTS_HELP)]
    Dialects(DialectsArgs),
    /// The language server for editors, over standard input and output (the workspace's
    /// `fmsvm.toml` gives `check`'s options: `args = ["--lib", "lib"]`).
    #[cfg(feature = "lsp")]
    Lsp,
    /// The macro debugger for editors, a Debug Adapter Protocol server over standard input and
    /// output (launch arguments `program` and `args`, `run`'s options).
    #[cfg(feature = "lsp")]
    Dap,
}

const POST_HELP: &str = "\
Examples:
  fmsvm post --dialect mayak600t \"%TEMP%\\TEMP CNC\\<session>\\input.tmp\"
  fmsvm dialects --cycles mayak600t           the control's BEGIN_MACHINE_CYCLES block
  fmsvm dialects --launcher mayak600t > fmsvm_post_mayak600t.py   its launcher, for the library

Controls: mayak600t, nc31, fanuc0itd, sinumerik802d, fagor8035t, iso (or --dialect-file).
Prints exactly OK (output.tmp and path.tmp written beside the input) or one located error a line
(neither written). Exit codes: 0, 2 (usage or a malformed input), 6 (a file), 7 (--verify found a
difference). docs/postprocessor.md";

const DIALECTS_HELP: &str = "\
Examples:
  fmsvm dialects                              every dialect, one line each
  fmsvm dialects --show fms3000 > my.toml     a profile to start from (edit, then --dialect-file)
  fmsvm dialects --show my.toml               a profile of your own with every key it implies
  fmsvm run part.nc --dialect fms3000 -o part.txt --verify";

/// Arguments of `dialects`.
#[derive(clap::Args, Debug)]
pub struct DialectsArgs {
    /// Print this dialect (a name, or a profile file) with every key.
    #[arg(long, value_name = "NAME|FILE")]
    pub show: Option<String>,
    /// Print this dialect's machine cycles as the turning library's BEGIN_MACHINE_CYCLES block.
    #[arg(long, value_name = "NAME|FILE", conflicts_with = "show")]
    pub cycles: Option<String>,
    /// Print the turning library's launcher script for this control: a Python file for its
    /// POSTPROCESSORS folder that runs `fmsvm post` and carries the control's machine cycles.
    #[arg(long, value_name = "NAME", conflicts_with_all = ["show", "cycles"])]
    pub launcher: Option<String>,
}

const EXAMPLES: &str = "\
Examples:
  fmsvm run part.nc -o part-flat.nc        expand part.nc into a flat program
  fmsvm run part.nc --lib macros/ --stats  with called programs from macros/, and a summary
  fmsvm check part.nc --deny-warnings      compile only; warnings fail too
  fmsvm ir part.nc                         show the compiled bytecode

Exit codes: 0 success, 1 internal error, 2 usage, 3 compile error, 4 alarm, 5 limit, 6 file error,
7 --verify found a difference, 10-12 dnc (link not opened, lost, held), 128+N stopped by signal N
(SIGINT 130, SIGTERM 143).";

const RUN_SHORT: &str = "\
--help: every flag, grouped (macro rules, output, dialect, kernel, machine model, limits,
variables, printing), with examples and the exit codes.";

const RUN_HELP: &str = "\
Examples:
  fmsvm run part.nc -o part-flat.nc                  write the flat program (atomically)
  fmsvm run part.nc -o - | less                      to standard output
  fmsvm run part.nc -o out.nc --print probe.txt      DPRNT records to probe.txt
  fmsvm run part.nc --vars store.txt --dump-vars store.txt
                                                     retained commons #500-#999 kept between runs
  fmsvm run part.nc --encoding cp1251 -o out.nc      comments in CP1251 (Windows Cyrillic)

Exit codes: 0 success, 1 internal error, 2 usage, 3 compile error (nothing ran), 4 alarm while
running, 5 limit reached, 6 file could not be read or written, 7 --verify: the output does not move
as the program does (it is removed), 128+N stopped by signal N. After exits 3-7 and signals no output
file is committed (--keep-partial keeps what was expanded).";

const STATS_HELP: &str = "\
Examples:
  fmsvm stats part.nc                       moves, lengths, extents, time, tool changes
  fmsvm stats part.nc --json --rapid 24000  the same as JSON, rapids at 24 m/min

Time: feed moves at their F, rapids at --rapid, dwells; G95 moves need S (without it they are
counted as not timed). A tool change is an M6; in a program without M6, each T that changes the tool.";

#[cfg(feature = "plot")]
const PLOT_HELP: &str = "\
Examples:
  fmsvm plot part.nc -o part.svg                             the XY view, 1200x900
  fmsvm plot part.nc -o part.png --view iso --size 1600x1200

Feeds are solid, rapids dashed; the extents of the shown axes and a scale bar are written on it.";

const EXIT_CODES: &str = "\
Exit codes: 0 no errors (warnings allowed unless --deny-warnings), 1 internal error, 2 usage,
3 errors (or warnings with --deny-warnings), 5 the input is larger than --max-input, 6 file error.";

/// Flags of `fmsvm check`.
#[derive(clap::Args, Debug)]
pub struct CheckArgs {
    /// The program.
    #[command(flatten)]
    pub input: InputArgs,
    /// More programs, each checked on its own with the same flags (`fmsvm check *.nc`).
    #[arg(value_name = "MORE")]
    pub more: Vec<PathBuf>,
    /// Warnings count as errors (exit 3).
    #[arg(long)]
    pub deny_warnings: bool,
}

/// Flags of `fmsvm stats`: `run`'s, less those about the flat program's text.
#[derive(clap::Args, Debug)]
#[command(
    mut_arg("output", |a| a.help("Write the report here (default: standard output)")),
    mut_args(hide_text_flags),
)]
pub struct StatsArgs {
    /// The program and everything `run` takes (`-o` is where the report goes, standard output by
    /// default; `--rapid` times the rapids).
    #[command(flatten)]
    pub run: RunArgs,
    /// Write the report as JSON.
    #[arg(help_heading = "Report", long)]
    pub json: bool,
}

/// Flags of `fmsvm params`.
#[derive(clap::Args, Debug)]
pub struct ParamsArgs {
    /// Print the parameters (the only action; the flag says what the command does).
    #[arg(long)]
    pub show: bool,
    /// A control's built-in parameters to start from.
    #[arg(long, value_parser = choice::<Control>(), value_name = "NAME")]
    pub control: Option<Control>,
    /// A parameter file over the profile.
    #[arg(long, value_name = "FILE")]
    pub params: Option<PathBuf>,
    /// Refuse a parameter file larger than this.
    #[arg(long, value_name = "BYTES", default_value = "256M", value_parser = parse_size_nonzero)]
    pub max_input: u64,
}

/// Flags of `fmsvm plot`: `run`'s, less those about the flat program's text.
#[cfg(feature = "plot")]
#[derive(clap::Args, Debug)]
#[command(
    mut_arg("output", |a| a.help("Write the picture here: SVG or PNG by its extension")),
    mut_args(hide_text_flags),
)]
pub struct PlotArgs {
    /// The program and everything `run` takes; `-o` is the picture, SVG or PNG by its extension
    /// (written atomically).
    #[command(flatten)]
    pub run: RunArgs,
    /// Which way to look: `xy` (from above; a mill's default), `xz` (from the front), `yz` (from
    /// the side), `iso`, or `zx` (a lathe's default: Z right, X the radius up).
    #[arg(help_heading = "Picture", long, value_parser = choice::<fmsvm_plot::View>())]
    pub view: Option<fmsvm_plot::View>,
    /// How feed moves are coloured: `depth` (Z along a ramp, the default), `tool` (a colour for
    /// each T) or `motion` (one colour; rapids are dashed in every mode).
    #[arg(help_heading = "Picture", long, value_parser = choice::<fmsvm_plot::Colour>(), default_value = "depth")]
    pub colour: fmsvm_plot::Colour,
    /// The picture's size in pixels, WIDTHxHEIGHT (each 200 to 8192).
    #[arg(help_heading = "Picture", long, value_name = "WxH", default_value = "1200x900", value_parser = parse_picture_size)]
    pub size: (u32, u32),
}

/// `WIDTHxHEIGHT` in pixels, each side 200 to 8192.
#[cfg(feature = "plot")]
fn parse_picture_size(s: &str) -> Result<(u32, u32), String> {
    let bad = || format!("`{s}` is not a size: give WIDTHxHEIGHT in pixels, each 200 to 8192");
    let (w, h) = s.trim().split_once(['x', 'X']).ok_or_else(bad)?;
    let side = |t: &str| {
        t.trim()
            .parse::<u32>()
            .ok()
            .filter(|v| (200..=fmsvm_plot::MAX_SIDE).contains(v))
            .ok_or_else(bad)
    };
    Ok((side(w)?, side(h)?))
}

/// Parses the command line (exits with code 2 on a usage error).
pub fn parse() -> Args {
    Args::parse()
}

#[cfg(test)]
mod tests {
    use super::*;
    use fmsvm_driver::request::DEFAULT_RAPID;
    use fmsvm_flags::TEXT_FLAGS;

    #[test]
    fn every_text_flag_is_seen_where_stats_refuses_it() {
        // One list: each flag TEXT_FLAGS hides is the one `text_flag_used` names when given.
        let given: [&[&str]; 12] = [
            &["--verify"],
            &["--verify-file", "x.nc"],
            &["--tape"],
            &["--renumber", "10"],
            &["--compact"],
            &["--no-comments"],
            &["--n33-g18", "iso"],
            &["--n33-brake-step", "500"],
            &["--n33-tape-length", "150"],
            &["--split-tapes"],
            &["--keep-partial"],
            &["--travel", "X1000 Y400 Z150"],
        ];
        assert_eq!(given.len(), TEXT_FLAGS.len());
        for (flag, (id, _)) in given.iter().zip(TEXT_FLAGS) {
            let mut argv = vec!["fmsvm", "stats", "p.nc"];
            argv.extend_from_slice(flag);
            let a = Args::try_parse_from(&argv).expect("parses");
            let Command::Stats(s) = a.command else {
                panic!("not stats")
            };
            assert_eq!(text_flag_used(&s.run).as_deref(), Some(flag[0]), "{id}");
        }
        let a = Args::try_parse_from(["fmsvm", "stats", "p.nc"]).expect("parses");
        let Command::Stats(s) = a.command else {
            panic!("not stats")
        };
        assert_eq!(text_flag_used(&s.run), None);
    }

    #[test]
    fn stats_and_plot_flags() {
        let a = Args::try_parse_from(["fmsvm", "stats", "p.nc", "--json"]).expect("parses");
        let Command::Stats(s) = a.command else {
            panic!("not stats")
        };
        assert!(s.json && s.run.rapid == DEFAULT_RAPID && !s.run.input.quiet);
        let a = Args::try_parse_from(["fmsvm", "plot", "p.nc", "-o", "p.svg"]).expect("parses");
        let Command::Plot(p) = a.command else {
            panic!("not plot")
        };
        assert_eq!((p.view, p.size), (None, (1200, 900)));
        assert_eq!(p.run.output, Some(PathBuf::from("p.svg")));
        let a = Args::try_parse_from([
            "fmsvm", "plot", "p.nc", "-o", "p.PNG", "--view", "iso", "--size", "640x480", "--lib",
            "m",
        ])
        .expect("parses");
        let Command::Plot(p) = a.command else {
            panic!("not plot")
        };
        assert_eq!((p.view, p.size), (Some(fmsvm_plot::View::Iso), (640, 480)));
        // Sizes are bounded (the picture's name is checked when the command starts: tests/cli.rs).
        for bad in ["100x100", "1200", "1200x9000", "axb", "1200x"] {
            assert!(parse_picture_size(bad).is_err(), "{bad}");
        }
        assert_eq!(parse_picture_size(" 8192X200 "), Ok((8192, 200)));
        assert!(Args::try_parse_from(["fmsvm", "stats", "p.nc", "--rapid", "0"]).is_err());
    }
}
