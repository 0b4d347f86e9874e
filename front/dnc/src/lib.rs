//! `fmsvm dnc`: expand a program and drip-feed it to a control over a serial line or a serial device
//! server, while it expands (docs/dnc.md).
//!
//! Two passes: a counting pass expands the whole program into a `Counter` first (so that an alarm or a
//! limit stops before anything reaches the control, the progress bar knows the total, and `--start-at`
//! is checked and its preamble made); the sending pass expands it again into a `DncWriter` over the
//! link. Nothing holds the whole program: memory stays bounded however long it is.
// Two calls are unsafe, each allowed where it is: a socket's send queue and its reset on close
// (`link`).
#![deny(unsafe_code)]

mod link;
mod resume;
mod writer;

use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::Duration;

use fmsvm_driver::exit::Exit;
use fmsvm_driver::report::plain;
use fmsvm_driver::run::{Consumer, Hooks, clock, expand};
use fmsvm_flags::RunArgs;

pub use link::{Flow, Framing};
use writer::{Counter, Plan, Session, Why};

/// `fmsvm dnc --help`'s tail.
pub const HELP: &str = "\
Examples:
  fmsvm dnc part.nc --port /dev/ttyUSB0 --baud 9600 --data 7E2     XON/XOFF, 50 NULs each end
  fmsvm dnc part.nc --tcp 10.0.0.5:4001 --baud 19200               through a serial device server
  fmsvm dnc part.nc --port /dev/ttyS0 --start-at 1234              resume at block 1234

The program is expanded twice: once to check and count it (nothing is sent if it raises an alarm),
once while it is sent. Ctrl-C stops between two characters, sends the trailer and names the block to
resume from with --start-at (docs/dnc.md).

Exit codes: 0 sent, 2 usage (or a --start-at that cannot be resumed safely), 3 compile error, 4 alarm,
5 limit (nothing sent after 3-5), 10 the link could not be opened (nothing sent), 11 the link was lost
while sending or its queue stopped emptying at the end, 12 the control held XOFF longer than --hold-timeout, 128+N stopped by signal N (SIGINT
130).";

/// Flags of `fmsvm dnc`.
#[derive(clap::Args, Debug)]
pub struct DncArgs {
    /// The program and everything `run` takes (except `-o`: the program goes over the link).
    #[command(flatten)]
    pub run: RunArgs,
    /// The serial port the control is on (`/dev/ttyS0`, `/dev/ttyUSB0`).
    #[arg(
        help_heading = "Link",
        long,
        value_name = "DEVICE",
        required_unless_present = "tcp",
        conflicts_with = "tcp"
    )]
    pub port: Option<String>,
    /// A serial device server's TCP port instead (raw TCP, as `10.0.0.5:4001`); `--baud` and `--data`
    /// are then its serial side's, for the pacing and the time estimate.
    #[arg(help_heading = "Link", long, value_name = "HOST:PORT")]
    pub tcp: Option<String>,
    /// The line's speed in bits per second.
    #[arg(help_heading = "Link", long, default_value_t = 9600, value_parser = parse_baud)]
    pub baud: u32,
    /// Data bits, parity and stop bits: `8N1`, `7E1`, `7E2`, `7O1` …
    #[arg(help_heading = "Link", long, value_name = "FRAMING", default_value = "8N1", value_parser = link::parse_framing)]
    pub data: Framing,
    /// Flow control: `xonxoff` (the control's DC3 stops the sending within a character, DC1 resumes
    /// it), `rtscts` (the CTS line; serial ports only) or `none`.
    #[arg(help_heading = "Link", long, value_enum, default_value_t = Flow::Xonxoff)]
    pub flow: Flow,
    /// NUL characters sent before the program (tape leader).
    #[arg(help_heading = "Link", long, value_name = "N", default_value_t = 50, value_parser = clap::value_parser!(u32).range(0..=100_000))]
    pub leader: u32,
    /// NUL characters sent after the program (tape trailer).
    #[arg(help_heading = "Link", long, value_name = "N", default_value_t = 50, value_parser = clap::value_parser!(u32).range(0..=100_000))]
    pub trailer: u32,
    /// Resume at this block (line) of the flat program, 1-based, as the progress bar and an interrupted
    /// run name it: the modal state of the blocks before it is restored first (docs/dnc.md).
    #[arg(help_heading = "Link", long, value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u64).range(1..))]
    pub start_at: u64,
    /// Give up when the control holds XOFF (or CTS off) this long, in seconds; 0 = wait for ever (a
    /// control holds XOFF through an M0 stop for as long as the operator takes).
    #[arg(help_heading = "Link", long, value_name = "SECONDS", default_value_t = 0.0, value_parser = parse_hold)]
    pub hold_timeout: f64,
}

/// Standard and old rates alike: 50 to 4 000 000 bits per second.
fn parse_baud(s: &str) -> Result<u32, String> {
    match s.trim().parse::<u32>() {
        Ok(v) if (50..=4_000_000).contains(&v) => Ok(v),
        _ => Err(format!(
            "`{s}` is not a baud rate: give bits per second, 50 to 4000000"
        )),
    }
}

fn parse_hold(s: &str) -> Result<f64, String> {
    // A timeout is at least a millisecond: a shorter one would round to none, which is "for ever".
    match s.trim().parse::<f64>() {
        Ok(v) if v == 0.0 || (0.001..=1e6).contains(&v) => Ok(v),
        _ => Err(format!(
            "`{s}` is not a number of seconds: 0 (for ever), or from 0.001 to 1000000"
        )),
    }
}

fn info(text: &str) {
    eprintln!("{text}");
}

/// The flags `dnc` cannot use, before anything runs.
fn check_usage(a: &DncArgs) -> Result<(), Exit> {
    if let Some(o) = &a.run.output {
        plain(&format!(
            "fmsvm dnc sends the program over the link; -o {} is not used (`fmsvm run -o` writes a file)",
            o.display()
        ));
        return Err(Exit::Usage);
    }
    if a.run.input.file.as_os_str() == "-" {
        plain("fmsvm dnc expands the program twice (a counting pass first); give a file, not -");
        return Err(Exit::Usage);
    }
    if a.tcp.is_some() && a.flow == Flow::Rtscts {
        plain("--flow rtscts needs a serial port (--port); a TCP link has no CTS line");
        return Err(Exit::Usage);
    }
    Ok(())
}

/// What the counting pass found that stops the send before it starts: nothing to send (a success),
/// `--start-at` past the end, 8-bit characters on a 7-bit line.
fn check_counted(a: &DncArgs, counter: &Counter, name: &str) -> Result<(), Exit> {
    if counter.lines == 0 {
        plain(&format!("{name} expands to nothing; nothing was sent"));
        return Err(Exit::Success);
    }
    if a.start_at > counter.lines {
        plain(&format!(
            "--start-at {}: the flat program has {} blocks; nothing was sent",
            a.start_at, counter.lines
        ));
        return Err(Exit::Usage);
    }
    if a.data.data == 7
        && let Some(b) = counter.high_byte_block
    {
        plain(&format!(
            "block {b} has characters above 127 (a comment in a Cyrillic set?) and --data {} sends 7 bits; use --data 8N1, or leave the comments out; nothing was sent",
            a.data
        ));
        return Err(Exit::Usage);
    }
    Ok(())
}

/// The blocks sent before block `--start-at` to restore the modal state the program had there
/// (none from the start); refused for the Н33-2М tape, which cannot say where the tool is.
fn resume_preamble(a: &DncArgs, counter: &Counter, eol: &[u8]) -> Result<Vec<u8>, Exit> {
    let quiet = a.run.input.quiet;
    let mut preamble = Vec::new();
    if a.start_at > 1 {
        // The Н33-2М tape is incremental and has no rapid code: a block of the middle of it says
        // nothing of where the tool is, and the preamble's words are not its dialect (a `G0` it
        // does not have, absolute values it would read as increments). Refused.
        let n33 = a.run.tape
            || fmsvm_driver::run::load_dialect(
                a.run.dialect.as_deref(),
                a.run.dialect_file.as_deref().map(|p| ("--dialect-file", p)),
                a.run.input.max_input,
            )
            .is_ok_and(|p| p.kind == fmsvm_driver::dialects::Kind::N33);
        if n33 {
            plain(&format!(
                "--start-at {}: the Н33-2М tape is incremental, and a resume preamble cannot be written in its dialect (no G00, no absolute position); send the tape from its start, or position the tool by hand and expand the rest as its own program; nothing was sent",
                a.start_at
            ));
            return Err(Exit::Usage);
        }
        // A turning program's preamble would need the lathe's codes (G90 is a cycle there).
        let turning = a.run.machine == Some(fmsvm_driver::request::Machine::Lathe)
            || matches!(
                a.run.input.control,
                Some(
                    fmsvm_driver::request::Control::Fanuc0iT
                        | fmsvm_driver::request::Control::HaasLathe
                )
            )
            || fmsvm_driver::run::load_dialect(
                a.run.dialect.as_deref(),
                a.run.dialect_file.as_deref().map(|p| ("--dialect-file", p)),
                a.run.input.max_input,
            )
            .is_ok_and(|p| p.dialect.machine == fmsvm_emit::dialect::MachineKind::Lathe);
        if turning {
            plain(&format!(
                "--start-at {}: a resume preamble is not yet written for turning programs (their G codes are a lathe's); send the program from its start; nothing was sent",
                a.start_at
            ));
            return Err(Exit::Usage);
        }
        let p = match counter.modal.preamble(a.start_at) {
            Ok(p) => p,
            Err(e) => {
                plain(&format!("--start-at {}: {e}; nothing was sent", a.start_at));
                return Err(Exit::Usage);
            }
        };
        if counter.modal.starts_with_percent {
            preamble.extend_from_slice(b"%");
            preamble.extend_from_slice(eol);
        }
        for l in &p.lines {
            preamble.extend_from_slice(l.as_bytes());
            preamble.extend_from_slice(eol);
        }
        if !quiet {
            info(&format!(
                "resuming at block {} of {}; the restoring blocks sent first: {}",
                a.start_at,
                counter.lines,
                if p.lines.is_empty() {
                    "none".to_string()
                } else {
                    p.lines.join(" / ")
                }
            ));
            for n in &p.notes {
                info(&format!("  note: {n}"));
            }
        }
    }
    Ok(preamble)
}

/// The process's signal handling, which a session uses: only a process has signals, so the binary
/// installs the handler and hands it in. The run's temporary files are listed where the handler
/// removes them; it is told what is being done; the first signal is deferred to the writer while
/// it sends.
pub trait Signals: Send + Sync {
    /// Where the run lists its temporary files.
    fn temporaries(&self) -> std::sync::Arc<fmsvm_driver::output::Temporaries>;
    /// What the process is doing, for the handler's message.
    fn doing(&self, what: String);
    /// Defers the first signal to the writer, or no longer.
    fn defer(&self, on: bool);
    /// The signal deferred, if one came.
    fn requested(&self) -> Option<i32>;
    /// A signal's name in messages.
    fn name(&self, n: i32) -> &'static str;
}

/// `fmsvm dnc`.
pub fn main(mut a: DncArgs, signals: std::sync::Arc<dyn Signals>) -> Exit {
    if let Err(e) = check_usage(&a) {
        return e;
    }
    signals.doing(format!("expanding {}", a.run.input.file.display()));
    // Both passes read the same clock (#3011, #3012).
    let (date, time) = clock(&a.run.request());
    a.run.date = Some(date);
    a.run.time = Some(time);
    let quiet = a.run.input.quiet;
    let name = a.run.input.file.display().to_string();

    // The counting pass: reports every warning and alarm; writes --print, not --dump-vars.
    let dump = a.run.dump_vars.take();
    let mut counter = Counter::new(a.start_at);
    // The FMS-3000's cycle blocks are whole (`G81 U Z I`, §4.1): a resume inside a cycle needs
    // no cycle mode restored.
    counter.modal.self_contained_cycles = fmsvm_driver::run::load_dialect(
        a.run.dialect.as_deref(),
        a.run.dialect_file.as_deref().map(|p| ("--dialect-file", p)),
        a.run.input.max_input,
    )
    .is_ok_and(|p| p.dialect.cycle_form == fmsvm_emit::dialect::CycleForm::Fms3000);
    let hooks = Hooks {
        temporaries: Some(signals.temporaries()),
        ..Hooks::default()
    };
    let exit = expand(
        &a.run.request(),
        Consumer::Into(Box::new(&mut counter)),
        hooks.clone(),
    )
    .exit;
    if exit != Exit::Success {
        plain("nothing was sent to the control");
        return exit;
    }
    if let Err(e) = check_counted(&a, &counter, &name) {
        return e;
    }
    let eol: &[u8] = if counter.crlf { b"\r\n" } else { b"\n" };
    let preamble = match resume_preamble(&a, &counter, eol) {
        Ok(p) => p,
        Err(e) => return e,
    };
    let bits = a.data.bits();
    let char_time = Duration::from_secs_f64(f64::from(bits) / f64::from(a.baud));
    let to_send = u64::from(a.leader)
        + preamble.len() as u64
        + (counter.bytes - counter.bytes_before)
        + u64::from(a.trailer);
    let plan = Plan {
        start_at: a.start_at,
        preamble,
        leader: a.leader,
        trailer: a.trailer,
        blocks: counter.lines,
        to_send,
        flow: a.flow,
        hold_timeout: Duration::from_secs_f64(a.hold_timeout),
        char_time,
        checkpoints: std::mem::take(&mut counter.checkpoints),
    };

    let endpoint = match (&a.port, &a.tcp) {
        (Some(p), _) => link::Endpoint::Serial {
            path: p,
            baud: a.baud,
            framing: a.data,
        },
        (None, Some(t)) => link::Endpoint::Tcp { address: t },
        (None, None) => {
            plain("give the link: --port DEVICE or --tcp HOST:PORT");
            return Exit::Usage;
        }
    };
    let link = match link::Link::open(&endpoint, a.flow) {
        Ok(l) => l,
        Err(e) => {
            plain(&format!("{e}; nothing was sent"));
            return Exit::LinkOpen;
        }
    };
    if !quiet {
        let secs = to_send as f64 * char_time.as_secs_f64();
        info(&format!(
            "sending {name} to {} at {} baud {} ({} blocks, {} bytes: {} at the line's rate)",
            link.name,
            a.baud,
            a.data,
            counter.lines - (a.start_at - 1),
            to_send,
            duration(secs)
        ));
    }
    // From here a signal stops the sending between two characters; this function reports it.
    signals.doing(format!("sending {name} to {}", link.name));
    signals.defer(true);
    let show = !quiet && std::io::stderr().is_terminal();
    let mut session = Session::new(link, plan, show, std::sync::Arc::clone(&signals));

    // The sending pass: quiet (the counting pass reported), no wall-time limit (the line is slow),
    // --print already written, --dump-vars now.
    let outcome = if session.leader() {
        a.run.input.quiet = true;
        a.run.stats = false;
        a.run.max_seconds = None;
        a.run.print = Some(PathBuf::from("/dev/null"));
        a.run.dump_vars = dump;
        expand(
            &a.run.request(),
            Consumer::Into(Box::new(session.writer())),
            hooks,
        )
        .exit
    } else {
        Exit::Io
    };
    finish(session, outcome, &name, &counter, quiet, &*signals)
}

/// Ends the session: the trailer, the link closed, the report and the exit code.
/// What was written, for the report: the blocks (their range when resumed), the bytes with leader
/// and trailer, a block cut short, and what the link has passed on of it.
fn sent_summary(s: &Session, stuck: Option<u64>) -> String {
    let block = s.block();
    let done = s.done_lines;
    let out = s.out_lines;
    let first = s.plan().start_at;
    let sent_blocks = done.saturating_sub(first - 1);
    let blocks = fmsvm_driver::report::count(sent_blocks as usize, "block", "blocks");
    let range = if first > 1 && sent_blocks > 0 {
        format!(" ({first} to {done})")
    } else {
        String::new()
    };
    let cut = if s.line_bytes > 0 {
        format!(
            "; block {block} was cut after {} without its end of block (the control does not run it)",
            fmsvm_driver::report::count(s.line_bytes as usize, "character", "characters")
        )
    } else {
        String::new()
    };
    let taken = if !s.knows_out() {
        "; a pseudo-terminal does not tell what its other end has read".to_string()
    } else if out < done {
        format!(
            "; of those, the link has passed on blocks up to {out} only{}",
            stuck.map_or(String::new(), |q| format!(
                " ({} still in its queue)",
                fmsvm_driver::report::count(q as usize, "byte", "bytes")
            ))
        )
    } else {
        String::new()
    };
    format!(
        "{blocks}{range} written ({} with leader and trailer){cut}{taken}",
        fmsvm_driver::report::count(s.sent as usize, "byte", "bytes")
    )
}

fn finish(
    mut s: Session,
    outcome: Exit,
    name: &str,
    counter: &Counter,
    quiet: bool,
    signals: &dyn Signals,
) -> Exit {
    let complete = s.why.is_none() && outcome == Exit::Success;
    if complete && (s.program_bytes != counter.bytes || s.digest != counter.digest) {
        // The last chunk was held back: it does not go out.
        s.why = Some(Why::Differs(s.block()));
    } else if complete && s.send_pending().is_err() {
        // The link stopped while the last chunk went out: `why` says how.
    }
    let why = s.why.clone();
    let complete = complete && why.is_none();
    if let Some(Why::Differs(at)) = why {
        s.hide();
        let sent = s.done_lines.saturating_sub(s.plan().start_at - 1);
        plain(&format!(
            "the sending pass expanded other bytes than the counting pass by block {at}: the program's output is not the same twice (it reads something that changes?); nothing of it was sent past block {} ({} sent); the trailer was sent",
            s.done_lines,
            fmsvm_driver::report::count(sent as usize, "block", "blocks")
        ));
        let _ = s.trailer(true);
        let _ = s.close();
        return Exit::Internal;
    }
    let trailer = match &why {
        None => s.trailer(false),
        Some(Why::Signal(_)) => s.trailer(true),
        Some(_) => false,
    };
    // A stop while the trailer was going out: the program itself is complete.
    let trailer_stop = if complete { s.why.clone() } else { None };
    // Nothing counts as sent before it has left: the whole program waits for the link's queue to
    // empty (while it keeps emptying); after a stop, a short look names the block to resume at. A
    // lost link's queue is not waited for: what it last said has left is all that is known.
    let patience = match s.plan().hold_timeout {
        d if d.is_zero() => DRAIN_PATIENCE,
        d => d,
    };
    let stuck = match &why {
        None if complete => s.drain(patience, true).err(),
        Some(Why::Lost(_)) => None,
        _ => s.drain(Duration::from_secs(2), false).err(),
    };
    if stuck.is_some() || matches!(why, Some(Why::Lost(_))) {
        s.discard();
    }
    s.hide();
    let block = s.block();
    let out = s.out_lines;
    let resume = out + 1;
    let sent = sent_summary(&s, stuck);
    let link = s.link_name().to_string();
    let secs = s.elapsed();
    let rate = s.sent as f64 / secs.max(1e-3);
    let total = s.plan().blocks;
    let closed = s.close();
    match why {
        None if complete && out < total => {
            plain(&format!(
                "the link to {link} took nothing more for {} at the end: {sent}; resume with --start-at {resume}",
                duration(patience.as_secs_f64())
            ));
            Exit::LinkLost
        }
        None if complete => {
            if let Err(e) = closed {
                plain(&format!(
                    "the link to {link} failed at the end: {e}; all {total} blocks had left, the trailer may not have"
                ));
                return Exit::LinkLost;
            }
            if !trailer || stuck.is_some() {
                let why = match trailer_stop {
                    Some(Why::Signal(n)) => format!("stopped by {}", signals.name(n)),
                    Some(Why::Lost(e)) => format!("the link was lost: {e}"),
                    Some(Why::Held { what, secs }) => {
                        format!("the control held {what} for {secs} s")
                    }
                    Some(Why::Differs(_)) | None if stuck.is_some() => {
                        "it is still in the link's queue".into()
                    }
                    Some(Why::Differs(_)) | None => "stopped".into(),
                };
                info(&format!(
                    "warning: the whole program was sent to {link}, but not all of the trailer ({why})"
                ));
            }
            signals.defer(false);
            if !quiet {
                info(&format!(
                    "sent {name} to {link}: {sent} in {} ({rate:.0} bytes/s)",
                    duration(secs)
                ));
            }
            Exit::Success
        }
        None => {
            // The expansion stopped (run reported it); what was sent is incomplete.
            plain(&format!(
                "{sent}; the program sent to {link} is incomplete; resume with --start-at {resume}"
            ));
            outcome
        }
        Some(Why::Signal(n)) => {
            let trail = if trailer {
                "trailer sent"
            } else {
                "trailer not sent (the control held XOFF)"
            };
            plain(&format!(
                "stopped by {} while sending {name} to {link}: {sent}; {trail}; resume with --start-at {resume}",
                signals.name(n)
            ));
            std::process::exit(128 + n)
        }
        Some(Why::Lost(e)) => {
            plain(&format!(
                "the link to {link} was lost: {e}; {sent}; resume with --start-at {resume} when it is back"
            ));
            Exit::LinkLost
        }
        Some(Why::Held { what, secs }) => {
            plain(&format!(
                "the control held {what} for {secs} s (--hold-timeout) at block {block}; {sent}; resume with --start-at {resume}"
            ));
            Exit::LinkHeld
        }
        // Reported above, before the trailer.
        Some(Why::Differs(_)) => Exit::Internal,
    }
}

/// How long the end of a session waits for the link's queue to shrink before it counts the link as
/// taking nothing more (`--hold-timeout` when given): as long as a write may block.
const DRAIN_PATIENCE: Duration = Duration::from_secs(30);

/// A time for people: `12.3 s`, `4 min 05 s`, `2 h 03 min`.
fn duration(secs: f64) -> String {
    if secs < 60.0 {
        format!("{secs:.1} s")
    } else if secs < 3600.0 {
        let s = secs.round() as u64;
        format!("{} min {:02} s", s / 60, s % 60)
    } else {
        let m = (secs / 60.0).round() as u64;
        format!("{} h {:02} min", m / 60, m % 60)
    }
}
