//! A run: a request configured, expanded into its consumer, verified, and its outcome reported.

mod compile;
mod config;
mod files;
mod finish;
mod ticking;
mod verify;

use compile::*;
pub use compile::{check_one, compile_options, compile_program, load_params};
pub use config::clock;
use config::*;
use files::*;
pub use files::{load_dialect, parse_points};
use finish::*;
use verify::*;

use std::io;
use std::path::Path;
use std::time::Instant;

use fmsvm_block::Stop;
use fmsvm_canon::Emitter;
use fmsvm_canon::decode::InputRules;
use fmsvm_compiler::{Program, SourceMap};
use fmsvm_emit::literal::LiteralEmitter;
use fmsvm_emit::pipelined::Pipelined;
use fmsvm_emit::resolved::ResolvedEmitter;
use fmsvm_kernel::probe::ProbeModel;
use fmsvm_kernel::{Kernel, Settings};
use fmsvm_vm::{RunOptions, Variables};

use fmsvm_block::OutputBudget;

use crate::exit::Exit;
use crate::input::Encode;
use crate::port::PrintPort;
use crate::report::{Reporter, plain};
use crate::request::{FastPath, Input, N33G18, Request};

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
    /// The stock the run cut (`--stock`) and what it saw, before `render`.
    fn stock(&mut self, stock: fmsvm_stock::Stock, report: fmsvm_stock::Report) {
        let _ = (stock, report);
    }
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

/// Whether the literal emitter's plain blocks are formatted and written by a second thread
/// (`emit::pipelined`): the machine has two cores or more, the program prints nothing (the printed
/// output shares the byte budget, which one thread spends at a time), and `--without pipeline` is
/// not given. The output is the same either way (tests/pipelined.rs).
fn pipelined(a: &Input, program: &fmsvm_compiler::ir::Program) -> bool {
    !a.without.contains(&FastPath::Pipeline)
        && std::thread::available_parallelism().is_ok_and(|n| n.get() >= 2)
        && !program.may_print()
}

pub fn run(a: &Request, consumer: Consumer<'_>) -> Exit {
    expand(a, consumer, Hooks::default()).exit
}

/// What one run ended with: its exit, and where it stopped when it stopped at a block (for a
/// front end that shows the stop at its line: the editor, the debugger).
pub struct Outcome {
    pub exit: Exit,
    pub stop: Option<RunStop>,
}

/// What a front end hooks into a run.
#[derive(Clone, Default)]
pub struct Hooks {
    /// Called before every op (the editor's debugger, the on-save run's value recorder): the run
    /// interprets, and the debugger is on this thread for this run only.
    pub debugger: Option<std::rc::Rc<dyn fmsvm_vm::debug::Debugger>>,
    /// Told the bytes written to the output file as the run goes, or the operations a report or a
    /// picture takes (a terminal's spinner); not used for standard output or a consumer's own
    /// writer.
    pub progress: Option<std::sync::Arc<dyn crate::output::Progress>>,
    /// Where the run lists its temporary files (shared with a signal handler that removes them);
    /// None: a list of the run's own.
    pub temporaries: Option<std::sync::Arc<crate::output::Temporaries>>,
    /// Where the run's warnings go besides the screen, each at its block (the language server's
    /// on-save run, which is quiet): what the kernel and the stock say.
    pub warnings: Option<std::rc::Rc<std::cell::RefCell<Vec<RunWarning>>>>,
}

pub use crate::report::RunWarning;

/// `run` with `hooks`, its stop handed back rather than only reported.
pub fn expand(a: &Request, consumer: Consumer<'_>, hooks: Hooks) -> Outcome {
    let mut stop = None;
    let exit = match hooks.debugger.clone() {
        Some(d) => fmsvm_vm::debug::with_debugger(d, || run_into(a, consumer, hooks, &mut stop)),
        None => run_into(a, consumer, hooks, &mut stop),
    };
    Outcome { exit, stop }
}

/// `run`, the stop at a block (if any) put in `stop`.
fn run_into(a: &Request, consumer: Consumer<'_>, hooks: Hooks, stop: &mut Option<RunStop>) -> Exit {
    let temps = hooks.temporaries.unwrap_or_default();
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
        stock,
    } = match configure(
        a,
        &temps,
        match consumer {
            Consumer::Stats { .. } | Consumer::Render(_) => true,
            Consumer::Flat | Consumer::Into(_) => a.verify || a.verify_file.is_some(),
        },
    ) {
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
    let Some(mut sink) = open_output(a, &outputs.program) else {
        return Exit::Io;
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
    // And the stock's pass after it (`--verify --stock`).
    let (stock, stock_pass) = match stock {
        Some(s) if matches!(consumer, Consumer::Flat | Consumer::Into(_)) => {
            (None, Some((s, vars.clone(), probe.clone())))
        }
        other => (other, None),
    };
    let shown = hooks.progress.clone();
    let heard = hooks.warnings.clone();
    let job = Job {
        a,
        quiet: false,
        progress: shown.as_deref(),
        heard: heard.as_deref(),
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
        let exit = verify(&job, &again, out, probe, &mut vars);
        return stock_after_verify(&job, exit, out, false, stock_pass);
    }
    let to_file = matches!(consumer, Consumer::Flat);
    let to_writer = matches!(consumer, Consumer::Into(_));
    // The plain blocks were written by a second thread (`--stats` says so).
    let mut second_thread = false;
    // What --verify's reader beside the writer found.
    let mut verdict = None;
    let outcome = match consumer {
        consumer @ (Consumer::Flat | Consumer::Into(_)) => {
            // Progress is shown for an output file only.
            let progress = hooks.progress.filter(|_| a.output.is_some());
            let mut to: Box<dyn io::Write + Send + '_> = match consumer {
                Consumer::Into(w) => w,
                _ => Box::new(crate::output::Counted::new(sink.writer(), progress)),
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
            let report = Report {
                budget: &options.budget,
                profile: &profile,
                sink: &mut sink,
                progress: hooks.progress,
            };
            report.stats(&job, json, stock, probe, &mut port, &mut vars)
        }
        Consumer::Render(render) => {
            let report = Report {
                budget: &options.budget,
                profile: &profile,
                sink: &mut sink,
                progress: hooks.progress,
            };
            report.render(&job, render, stock, probe, &mut port, &mut vars)
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
                let exit = verified(&job, &profile, out, checked);
                return stock_after_verify(&job, exit, out, true, stock_pass);
            }
            if let Some((mut vars, probe)) = again
                && let Some(out) = written.as_deref()
            {
                let again = Again {
                    profile: &profile,
                    resolve,
                };
                let exit = verify(&job, &again, out, probe, &mut vars);
                return stock_after_verify(&job, exit, out, true, stock_pass);
            }
            Exit::Success
        }
        Err(stopped) => report_stop(a, open, &program, sources, flat.as_ref(), stopped, stop),
    }
}

/// The output opened (its temporary file made), or the error said.
fn open_output(a: &Request, program: &crate::output::Target) -> Option<crate::output::Sink> {
    program
        .open()
        .map_err(|e| {
            let what = a
                .output
                .as_deref()
                .map_or("standard output".into(), |p| p.display().to_string());
            plain(&format!("cannot create {what}: {e}"));
        })
        .ok()
}

/// Where a report or a picture of the run goes: the output file, within the run's budget and the
/// dialect's reach.
struct Report<'a> {
    budget: &'a OutputBudget,
    profile: &'a crate::dialects::Profile,
    sink: &'a mut crate::output::Sink,
    /// Told the operations taken.
    progress: Option<std::sync::Arc<dyn crate::output::Progress>>,
}

impl Report<'_> {
    /// `stats`: the motion report written when the run has ended.
    fn stats(
        self,
        job: &Job<'_>,
        json: bool,
        stock: Option<Stocked>,
        probe: ProbeModel,
        port: &mut PrintPort,
        vars: &mut Variables,
    ) -> Result<Expanded, Stopped> {
        let mut stats = fmsvm_emit::stats::Stats::default()
            .within(self.budget.clone(), self.profile.dialect.reach());
        if let Some(l) = job.settings.lathe {
            stats = stats.turning(l.diameter);
        }
        let (result, stats, stocked) = match stock {
            None => {
                let ticking = ticking::Ticking::new(stats, self.progress);
                let (result, ticking) = job.expand(ticking, probe, port, vars);
                (result, ticking.into_inner(), None)
            }
            Some(stocked) => {
                let strict = job.a.strict_stock;
                let cut = Cutting {
                    job,
                    progress: self.progress,
                };
                let (result, stats, _, report) =
                    cut.expand(stats, stocked, strict, probe, port, vars);
                (result, stats, Some(report))
            }
        };
        result.and_then(|done| {
            let mut text = Vec::new();
            crate::stats::report(
                &stats.finish(job.a.rapid),
                stocked.as_ref(),
                json,
                &mut text,
            )
            .and_then(|()| write_all(self.sink, &text))
            .map(|()| done)
            .map_err(|e| (Stop::Io(e), None))
        })
    }

    /// A front end's `Render`: told the run's setting, fed the operations, its bytes written.
    fn render(
        self,
        job: &Job<'_>,
        render: &mut dyn Render,
        stock: Option<Stocked>,
        probe: ProbeModel,
        port: &mut PrintPort,
        vars: &mut Variables,
    ) -> Result<Expanded, Stopped> {
        render.start(RenderStart {
            stock: stock_box(job.a, job.settings.lathe),
            budget: self.budget.clone(),
            reach: self.profile.dialect.reach(),
            lathe: job.settings.lathe.is_some(),
        });
        let (result, rendering) = match stock {
            None => {
                let ticking = ticking::Ticking::new(Rendering(render), self.progress);
                let (result, ticking) = job.expand(ticking, probe, port, vars);
                (result, ticking.into_inner())
            }
            Some(stocked) => {
                let strict = job.a.strict_stock;
                let cut = Cutting {
                    job,
                    progress: self.progress,
                };
                let (result, rendering, stock, report) =
                    cut.expand(Rendering(render), stocked, strict, probe, port, vars);
                rendering.0.stock(stock, report);
                (result, rendering)
            }
        };
        result.and_then(|done| {
            let bytes = rendering
                .0
                .render()
                .map_err(|e| (Stop::Io(io::Error::other(e)), None))?;
            write_all(self.sink, &bytes)
                .map(|()| done)
                .map_err(|e| (Stop::Io(e), None))
        })
    }
}

/// A run that cuts the stock beside its consumer (`stats`, `plot`, the pass after `--verify`).
struct Cutting<'a, 'j> {
    job: &'a Job<'j>,
    progress: Option<std::sync::Arc<dyn crate::output::Progress>>,
}

impl Cutting<'_, '_> {
    /// Expands the program into `inner` with `stocked` cut beside it (`strict`: the first finding
    /// stops the run); the findings said at their lines. The run's result, `inner`, the stock and
    /// its report.
    #[allow(clippy::type_complexity)]
    fn expand<E: Emitter>(
        self,
        inner: E,
        stocked: Stocked,
        strict: bool,
        probe: ProbeModel,
        port: &mut dyn fmsvm_vm::print::Port,
        vars: &mut Variables,
    ) -> (
        Result<Expanded, Stopped>,
        E,
        fmsvm_stock::Stock,
        fmsvm_stock::Report,
    ) {
        let Stocked { stock, tools } = stocked;
        let simulated = fmsvm_stock::Simulated::new(inner, stock, tools, strict);
        let ticking = ticking::Ticking::new(simulated, self.progress);
        let (result, ticking) = self.job.expand(ticking, probe, port, vars);
        let mut simulated = ticking.into_inner();
        simulated.stopped();
        self.job.say_anyway(simulated.warnings());
        let (inner, stock, report) = simulated.finish();
        (result, inner, stock, report)
    }
}

/// How the flat program is written: the dialect's profile, literal or resolved, and whether plain
/// blocks may go to a second thread.
struct Text<'a> {
    pub(super) profile: &'a crate::dialects::Profile,
    pub(super) resolve: bool,
    pub(super) options: &'a fmsvm_emit::literal::Options,
    pub(super) pipeline: bool,
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
                comments: options.comments,
                ..Default::default()
            };
            let emitter = fmsvm_emit::n33::N33Emitter::new(writer, n33);
            let (result, emitter) = job.expand(emitter, probe, port, vars);
            job.say(&emitter.warnings());
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
            },
        )
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

/// What one expansion needs besides its kernel (shared by the literal and the resolved output).
#[derive(Clone, Copy)]
struct Job<'a> {
    pub(super) a: &'a Request,
    /// Print no warnings (the second expansion of `--verify`).
    pub(super) quiet: bool,
    /// The front end's progress, put aside while a warning is said.
    pub(super) progress: Option<&'a dyn crate::output::Progress>,
    /// Where the warnings said go besides (`Hooks::warnings`).
    pub(super) heard: Option<&'a std::cell::RefCell<Vec<RunWarning>>>,
    /// The program runs straight from its file.
    pub(super) flat: Option<&'a crate::flat::FlatProgram>,
    pub(super) program: &'a Program,
    pub(super) run: &'a RunOptions,
    pub(super) date: u32,
    pub(super) time: u32,
    pub(super) frames: &'a fmsvm_kernel::frames::Frames,
    /// How the program's numbers are read, and what the run adds to the kernel.
    pub(super) rules: &'a InputRules,
    pub(super) settings: &'a Settings,
    /// The compiled sources, to name the file a warning's block comes from.
    pub(super) sources: &'a SourceMap,
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
        if self.quiet {
            return;
        }
        self.say_anyway(warnings);
    }

    /// Says `warnings` unless `-q`, also in a quiet expansion (the stock's pass after `--verify`,
    /// whose other warnings the first expansion said).
    fn say_anyway(&self, warnings: &[fmsvm_canon::Warning]) {
        let reporter = Reporter::new(self.sources);
        if let Some(heard) = self.heard {
            heard
                .borrow_mut()
                .extend(warnings.iter().map(|w| reporter.locate(w)));
        }
        if self.a.input.quiet {
            return;
        }
        self.aside(&mut || {
            for w in warnings {
                plain_info(&reporter.run_warning(w));
            }
        });
    }

    /// Runs `print` with the front end's progress off the screen.
    fn aside(&self, print: &mut dyn FnMut()) {
        match self.progress {
            Some(p) => p.aside(print),
            None => print(),
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
        self.aside(&mut || {
            for (n, text) in kernel.messages() {
                plain_info(&format!(
                    "message {n}: {text} (#3006: the control stops here; the flat program has M0)"
                ));
            }
        });
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
            self.aside(&mut || plain_info(&format!(
                "warning: the program ends with #3003={f3003} #3004={f3004}: single-block/feed-hold suppression left on"
            )));
        }
        let bytes = kernel.emitter().written();
        let machining = kernel.machining_seconds();
        (result.map(|s| (s, bytes, machining)), kernel.into_emitter())
    }
}
