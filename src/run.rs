//! The pipeline behind each subcommand: load, compile, report, run, write; returns the exit code.

use std::io;
use std::time::Instant;

use fmsvm_block::Stop;
use fmsvm_compiler::{Options, Program, SourceMap};
use fmsvm_runtime::Kernel;
use fmsvm_runtime::dialect::Dialect;
use fmsvm_runtime::emit::literal::{self, LiteralEmitter};
use fmsvm_vm::{Limits, Variables};

use crate::cli::{Args, Command, DecimalInput, InputArgs, RunArgs};
use crate::exit::Exit;
use crate::output::{Sink, read_input, write_atomic};
use crate::report::{Reporter, plain};

/// Runs one command.
pub fn main(args: Args) -> Exit {
    match args.command {
        Command::Check(a) => match compile(&a) {
            Ok(_) => Exit::Success,
            Err(e) => e,
        },
        Command::Ir(a) => match compile(&a) {
            Ok((p, _)) => {
                use std::io::Write;
                let mut out = io::stdout().lock();
                match write!(out, "{p}") {
                    Ok(()) => Exit::Success,
                    Err(e) if e.kind() == io::ErrorKind::BrokenPipe => Exit::Success,
                    Err(e) => {
                        plain(&format!("writing the IR: {e}"));
                        Exit::Io
                    }
                }
            }
            Err(e) => e,
        },
        Command::Run(a) => run(&a),
    }
}

/// Loads and compiles; renders every diagnostic.
fn compile(a: &InputArgs) -> Result<(Program, SourceMap), Exit> {
    let (name, bytes) = match read_input(&a.file) {
        Ok(x) => x,
        Err(e) => {
            plain(&format!("cannot read {}: {e}", a.file.display()));
            return Err(Exit::Io);
        }
    };
    let text = match String::from_utf8(bytes) {
        Ok(t) => t,
        Err(e) => {
            let at = e.utf8_error().valid_up_to();
            plain(&format!(
                "{name}: not a text file: byte {at} is not ASCII/UTF-8 (an EIA-coded or binary file?)"
            ));
            return Err(Exit::Compile);
        }
    };
    let mut sources = SourceMap::new();
    let id = sources.add(name, text);
    let options = Options {
        block_delete: a.block_delete,
    };
    let (program, diags) = fmsvm_compiler::compile(&sources, id, &options);
    let reporter = Reporter::new(&sources);
    for d in &diags {
        if d.is_error() || !a.quiet {
            reporter.diagnostic(d);
        }
    }
    match program {
        Some(p) => Ok((p, sources)),
        None => {
            let n = diags.iter().filter(|d| d.is_error()).count();
            plain(&format!(
                "{n} error{} in {}; nothing was run",
                if n == 1 { "" } else { "s" },
                sources.file(id).name
            ));
            Err(Exit::Compile)
        }
    }
}

fn run(a: &RunArgs) -> Exit {
    let (program, sources) = match compile(&a.input) {
        Ok(x) => x,
        Err(e) => return e,
    };
    let mut vars = Variables::default();
    if let Some(path) = &a.vars {
        match std::fs::read_to_string(path) {
            Ok(text) => {
                if let Err(e) = crate::vars::parse(&path.display().to_string(), &text, &mut vars) {
                    plain(&e);
                    return Exit::Compile;
                }
            }
            Err(e) => {
                plain(&format!("cannot read {}: {e}", path.display()));
                return Exit::Io;
            }
        }
    }
    let mut sink = match Sink::open(a.output.as_deref()) {
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
    let options = literal::Options {
        comments: a.comments,
        renumber: a.renumber,
        max_bytes: a.max_bytes,
        decimal_input: match a.decimal_input {
            DecimalInput::Calculator => literal::DecimalInput::Calculator,
            DecimalInput::Increment => literal::DecimalInput::Increment,
        },
        ..literal::Options::default()
    };
    let limits = Limits {
        max_steps: a.max_steps,
        max_blocks: a.max_blocks,
    };
    let started = Instant::now();
    let main = &program.functions[0];
    let outcome = {
        let writer = sink.writer();
        let emitter = LiteralEmitter::new(writer, Dialect::fanuc(), options.clone());
        let mut kernel = Kernel::new(emitter, Dialect::fanuc(), options.decimal_input);
        let result = kernel
            .begin(main.number, program.string(main.title))
            .map_err(|stop| (stop, None))
            .and_then(|()| {
                fmsvm_vm::run(&program, &mut kernel, &mut vars, &limits)
                    .map_err(|e| (e.stop, Some((e.span, e.stats))))
            })
            .and_then(|stats| kernel.end().map(|()| stats).map_err(|s| (s, None)));
        let bytes = kernel.emitter().written();
        result.map(|s| (s, bytes))
    };
    match outcome {
        Ok((stats, bytes)) => {
            if let Err(e) = sink.commit() {
                return io_failure(a, e);
            }
            if let Some(path) = &a.dump_vars
                && let Err(e) = write_atomic(path, &crate::vars::dump(&vars))
            {
                plain(&format!("cannot write {}: {e}", path.display()));
                return Exit::Io;
            }
            if a.stats {
                let t = started.elapsed();
                plain_info(&format!(
                    "{} blocks, {} bytes, {} steps in {:.3} s ({:.1} M blocks/s)",
                    stats.blocks,
                    bytes,
                    stats.steps,
                    t.as_secs_f64(),
                    stats.blocks as f64 / t.as_secs_f64().max(1e-9) / 1e6
                ));
            }
            Exit::Success
        }
        Err((stop, at)) => {
            // The temporary output is dropped (deleted) here: no partial program under the final name.
            drop(sink);
            let reporter = Reporter::new(&sources);
            let note_kept = if a.output.is_some() {
                "no output file was written"
            } else {
                "the output above is incomplete"
            };
            match stop {
                Stop::Io(e) if e.kind() == io::ErrorKind::BrokenPipe && a.output.is_none() => {
                    Exit::Success
                }
                Stop::Io(e) => io_failure(a, e),
                Stop::Alarm(alarm) => {
                    let msg = alarm.message.to_string();
                    match at {
                        Some((span, stats)) => reporter.stop(
                            &msg,
                            Some(alarm.number),
                            span,
                            &[format!(
                                "stopped after {} blocks; {note_kept}",
                                stats.blocks
                            )],
                        ),
                        None => plain(&format!("alarm {:04}: {msg}", alarm.number)),
                    }
                    Exit::Alarm
                }
                limit @ Stop::Limit { .. } => {
                    let msg = format!("{limit}");
                    let hint = "raise it with --max-steps / --max-blocks / --max-bytes (0 = no limit) if the program is meant to run this long".to_string();
                    match at {
                        Some((span, _)) => {
                            reporter.stop(&msg, None, span, &[hint, note_kept.to_string()])
                        }
                        None => plain(&format!("{msg}; {hint}")),
                    }
                    Exit::Limit
                }
            }
        }
    }
}

fn io_failure(a: &RunArgs, e: io::Error) -> Exit {
    let what = a
        .output
        .as_deref()
        .map_or("standard output".into(), |p| p.display().to_string());
    plain(&format!(
        "writing {what} failed: {e}; no output file was written"
    ));
    Exit::Io
}

fn plain_info(message: &str) {
    use std::io::Write;
    let _ = writeln!(io::stderr(), "{message}");
}
