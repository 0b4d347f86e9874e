//! The end of a run: the outputs committed and the success said, or the stop reported at its block
//! with its exit code.

use std::io;
use std::path::{Path, PathBuf};
use std::time::Instant;

use fmsvm_block::Stop;
use fmsvm_compiler::{Program, SourceMap};
use fmsvm_vm::Variables;

use fmsvm_block::LimitKind;

use crate::exit::Exit;
use crate::output::{Target, commit_all, write_text};
use crate::port::PrintPort;
use crate::report::{Reporter, plain};
use crate::request::{MainM99, Request};

use super::*;

/// What writing the flat program did besides its result.
pub(super) struct Written {
    /// The plain blocks were written by a second thread.
    pub(super) second_thread: bool,
    /// What `--verify`'s reader beside the writer found: the moves read back, or the first
    /// difference (None: not checked in the pass, a second expansion checks the output).
    pub(super) verdict: Option<Result<u64, String>>,
}

/// What a finished run says besides its output: where the printed output went, and with `--stats`
/// the counts, the speed and the estimated machining time.
pub(super) fn report_success(
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
pub(super) struct Open {
    pub(super) outputs: Outputs,
    pub(super) sink: crate::output::Sink,
    pub(super) port: PrintPort,
    /// The program goes out as it is made (`run`); `stats` and `plot` write theirs at the end.
    pub(super) streams: bool,
}

/// A finished run's outputs, every one complete, committed together (or none): the flat program,
/// the printed output, `--dump-vars`. Gives where the printed output went.
pub(super) fn commit(
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
pub(super) fn report_stop(
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
        sink,
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
    let kept = keep_partial(a, &outputs.program, sink, streams, code, &headline);
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
        notes.extend(limit_notes(a, &stop, program));
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

pub(super) fn io_failure(a: &Request, target: &Target, e: io::Error) -> Exit {
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
pub(super) fn incomplete(target: &Target) -> &'static str {
    match target {
        Target::File { .. } => "no output file was written",
        Target::Direct { .. } | Target::Stdout => "what was written there is incomplete",
    }
}

/// What became of the output of a stopped run, for the report: kept as `.PARTIAL` with a marker
/// (`--keep-partial`), dropped, or written already (a device, standard output).
fn keep_partial(
    a: &Request,
    program: &Target,
    mut sink: crate::output::Sink,
    streams: bool,
    code: Option<u32>,
    headline: &str,
) -> String {
    // Without --keep-partial the temporary output is dropped (deleted): nothing partial remains.
    match (program, a.keep_partial) {
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
    }
}

/// The notes of a run stopped by a limit: the flag that raises it, and M99's restart.
fn limit_notes(a: &Request, stop: &Stop, program: &Program) -> Vec<String> {
    let mut notes = Vec::new();
    let flag = match stop {
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
    notes
}
