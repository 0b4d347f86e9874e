//! `fmsvm dap`: the macro debugger, a Debug Adapter Protocol server over standard input and output.
//! It runs the program as `fmsvm run` does (launch arguments `program` and `args`, `run`'s options
//! as strings) on the interpreter with a `fmsvm_vm::debug::Debugger` that pauses at source lines:
//! breakpoints (with conditions such as `#1 GT 10`), continue, step over, into and out of G65, M98
//! and code-called macros; the call stack, locals #1–#33 with their argument letters, commons and
//! system variables; evaluate; the flat program as output when the run ends.

use fmsvm_block::alarms::NO_FANUC_NUMBER;
use std::collections::HashMap;
use std::io::{self, BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::sync::mpsc::{Receiver, Sender, channel};
use std::sync::{Arc, Mutex};

use serde_json::{Value, json};

use fmsvm_vm::debug::{Debugger, Stop};

use fmsvm_driver::exit::Exit;

/// The system variables the debugger shows: the modal state, the last F S T H D, the position, the
/// G54 work offset.
const SYSTEM: [(u32, &str); 20] = [
    (4001, "#4001 motion (G group 01)"),
    (4002, "#4002 plane (02)"),
    (4003, "#4003 absolute/incremental (03)"),
    (4006, "#4006 inch/metric (06)"),
    (4007, "#4007 cutter compensation (07)"),
    (4008, "#4008 tool length offset (08)"),
    (4009, "#4009 canned cycle (09)"),
    (4014, "#4014 work offset (14)"),
    (4109, "#4109 F"),
    (4111, "#4111 H"),
    (4107, "#4107 D"),
    (4119, "#4119 S"),
    (4120, "#4120 T"),
    (5001, "#5001 X (work)"),
    (5002, "#5002 Y (work)"),
    (5003, "#5003 Z (work)"),
    (5021, "#5021 X (machine)"),
    (5221, "#5221 G54 X offset"),
    (5222, "#5222 G54 Y offset"),
    (5223, "#5223 G54 Z offset"),
];

/// How the run goes on after a pause.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Mode {
    /// To the next breakpoint.
    Continue,
    /// To the next line at this depth or above.
    Over(u8),
    /// To the next line anywhere.
    Into,
    /// To the next line above this depth.
    Out(u8),
    /// Stop the run.
    Stop,
}

/// One frame of a pause.
#[derive(Clone, Debug)]
struct Frame {
    program: Option<u32>,
    file: String,
    line: u32,
    column: u32,
    locals: Vec<f64>,
}

/// What the front end knows of a pause.
#[derive(Clone, Debug, Default)]
struct Paused {
    frames: Vec<Frame>,
    commons: Vec<f64>,
    system: Vec<(String, Option<f64>)>,
}

/// What the protocol thread asks of a run that is not paused (read before every op).
const RUNNING: u8 = 0;
const PAUSE: u8 = 1;
const STOP: u8 = 2;

/// State shared between the protocol thread and the run.
#[derive(Default)]
struct Shared {
    /// Breakpoints by file: line (1-based) and condition.
    breakpoints: HashMap<String, Vec<(u32, Option<String>)>>,
    paused: Option<Paused>,
}

/// Writes protocol messages (the run's thread sends events too).
#[derive(Clone)]
struct Out(Arc<Mutex<(io::Stdout, i64)>>);

impl Out {
    fn send(&self, mut v: Value) {
        let Ok(mut g) = self.0.lock() else {
            return;
        };
        g.1 += 1;
        v["seq"] = json!(g.1);
        let body = v.to_string();
        let _ = write!(g.0, "Content-Length: {}\r\n\r\n{body}", body.len());
        let _ = g.0.flush();
    }

    fn event(&self, event: &str, body: Value) {
        self.send(json!({"type": "event", "event": event, "body": body}));
    }

    fn respond(&self, req: &Value, body: Value) {
        self.send(
            json!({"type": "response", "request_seq": req["seq"], "success": true,
            "command": req["command"], "body": body}),
        );
    }

    fn refuse(&self, req: &Value, message: &str) {
        self.send(
            json!({"type": "response", "request_seq": req["seq"], "success": false,
            "command": req["command"], "message": message}),
        );
    }
}

/// Reads one message (`Content-Length` framing, bounded: `frame.rs`); None at the end of the
/// input. A broken frame, or a body that is not JSON, is said to the client as output and passed
/// by.
fn read_message(input: &mut impl BufRead, out: &Out) -> Option<Value> {
    loop {
        let why = match crate::frame::read(input) {
            crate::frame::Frame::Body(body) => match crate::frame::json(&body) {
                Ok(v) => return Some(v),
                Err(e) => format!("a message that is not JSON ({e})"),
            },
            crate::frame::Frame::Bad(why) => why,
            crate::frame::Frame::End => return None,
            crate::frame::Frame::Failed(e) => {
                eprintln!("fmsvm dap: reading the client failed: {e}");
                return None;
            }
        };
        out.event(
            "output",
            json!({"category": "stderr", "output": format!("fmsvm dap: {why}: passed by\n")}),
        );
    }
}

/// `fmsvm dap`: serves one debugging session.
pub fn main() -> Exit {
    let out = Out(Arc::new(Mutex::new((io::stdout(), 0))));
    let shared = Arc::new(Mutex::new(Shared::default()));
    let mut input = BufReader::new(io::stdin());
    let mut launch: Option<Value> = None;
    let mut resume: Option<Sender<Mode>> = None;
    let interrupt = Arc::new(std::sync::atomic::AtomicU8::new(RUNNING));
    let mut worker: Option<std::thread::JoinHandle<()>> = None;
    while let Some(req) = read_message(&mut input, &out) {
        let command = req["command"].as_str().unwrap_or("").to_string();
        let args = &req["arguments"];
        match command.as_str() {
            "initialize" => {
                out.respond(
                    &req,
                    json!({"supportsConfigurationDoneRequest": true,
                        "supportsConditionalBreakpoints": true,
                        "supportsEvaluateForHovers": true,
                        "supportsTerminateRequest": true}),
                );
                out.event("initialized", json!({}));
            }
            "launch" => {
                launch = Some(args.clone());
                out.respond(&req, json!({}));
            }
            "setBreakpoints" => out.respond(&req, set_breakpoints(args, &shared)),
            "configurationDone" => {
                out.respond(&req, json!({}));
                let Some(l) = launch.clone() else {
                    out.event(
                        "output",
                        json!({"category": "stderr", "output": "no launch request came\n"}),
                    );
                    continue;
                };
                let (tx, rx) = channel();
                resume = Some(tx);
                let (out2, shared2, interrupt2) =
                    (out.clone(), Arc::clone(&shared), Arc::clone(&interrupt));
                worker = Some(std::thread::spawn(move || {
                    session(&l, rx, interrupt2, &out2, &shared2)
                }));
            }
            "threads" => out.respond(&req, json!({"threads": [{"id": 1, "name": "program"}]})),
            "stackTrace" => out.respond(&req, stack_trace(&shared)),
            "scopes" => {
                let frame = args["frameId"].as_u64().unwrap_or(0);
                out.respond(
                    &req,
                    json!({"scopes": [
                        {"name": "Locals #1–#33", "variablesReference": 1000 + frame, "expensive": false},
                        {"name": "Commons", "variablesReference": 2, "expensive": false},
                        {"name": "System", "variablesReference": 3, "expensive": false}]}),
                );
            }
            "variables" => {
                let r = args["variablesReference"].as_u64().unwrap_or(0);
                let vars = paused(&shared)
                    .map(|p| variables(&p, r))
                    .unwrap_or_default();
                out.respond(&req, json!({"variables": vars}));
            }
            "evaluate" => {
                let p = paused(&shared).unwrap_or_default();
                let frame = args["frameId"]
                    .as_u64()
                    .unwrap_or(p.frames.len().saturating_sub(1) as u64);
                let expr = args["expression"].as_str().unwrap_or("");
                match evaluate(expr, &p, frame as usize) {
                    Ok(v) => out.respond(&req, json!({"result": show(v), "variablesReference": 0})),
                    Err(e) => out.refuse(&req, &format!("`{expr}`: {e}")),
                }
            }
            "continue" | "next" | "stepIn" | "stepOut" => {
                let depth = paused(&shared)
                    .and_then(|p| p.frames.len().checked_sub(1))
                    .unwrap_or(0) as u8;
                let mode = match command.as_str() {
                    "continue" => Mode::Continue,
                    "next" => Mode::Over(depth),
                    "stepIn" => Mode::Into,
                    _ => Mode::Out(depth),
                };
                out.respond(&req, json!({"allThreadsContinued": true}));
                if let Some(tx) = &resume {
                    let _ = tx.send(mode);
                }
            }
            "pause" => {
                interrupt.store(PAUSE, std::sync::atomic::Ordering::Relaxed);
                out.respond(&req, json!({}));
            }
            "disconnect" | "terminate" => {
                // A running program stops at its next op; a paused one when it is resumed so.
                interrupt.store(STOP, std::sync::atomic::Ordering::Relaxed);
                if let Some(tx) = &resume {
                    let _ = tx.send(Mode::Stop);
                }
                out.respond(&req, json!({}));
                if command == "disconnect" {
                    break;
                }
            }
            _ => out.refuse(&req, &format!("fmsvm dap has no `{command}`")),
        }
    }
    drop(resume);
    if let Some(w) = worker {
        let _ = w.join();
    }
    Exit::Success
}

fn paused(shared: &Arc<Mutex<Shared>>) -> Option<Paused> {
    shared.lock().ok().and_then(|s| s.paused.clone())
}

/// A path as breakpoints and stops compare it.
fn canonical(path: &str) -> String {
    std::fs::canonicalize(path).map_or(path.to_string(), |p| p.display().to_string())
}

/// A value as the debugger shows it (`vacant` for #0's value).
fn show(v: f64) -> String {
    if v.is_nan() {
        "vacant".into()
    } else {
        format!("{v}")
    }
}

fn variables(p: &Paused, r: u64) -> Vec<Value> {
    let var =
        |name: String, v: f64| json!({"name": name, "value": show(v), "variablesReference": 0});
    match r {
        // Every common the run holds that is not vacant (the control's ranges decide which exist).
        2 => p
            .commons
            .iter()
            .enumerate()
            .filter(|(_, v)| !v.is_nan())
            .filter_map(|(i, &v)| {
                let n = fmsvm_compiler::ir::common_number(u16::try_from(i).ok()?);
                Some(var(format!("#{n}"), v))
            })
            .collect(),
        3 => p
            .system
            .iter()
            .map(|(n, v)| var(n.clone(), v.unwrap_or(f64::NAN)))
            .collect(),
        r if r >= 1000 => {
            let Some(f) = p.frames.get((r - 1000) as usize) else {
                return Vec::new();
            };
            (1..=33)
                .map(|n| {
                    let letter = fmsvm_block::Letter::ALL
                        .iter()
                        .find(|&&l| fmsvm_vm::spec_i(l) == Some(n))
                        .map_or(String::new(), |l| format!(" ({l})"));
                    var(
                        format!("#{n}{letter}"),
                        f.locals.get(n).copied().unwrap_or(f64::NAN),
                    )
                })
                .collect()
        }
        _ => Vec::new(),
    }
}

/// A Macro B expression (`[#1+#2]*COS[#3]`) or condition (`#1 GT 10`, `[#1 EQ 2] AND [#2 LT 5]`)
/// at a pause: every variable it reads is replaced by its value in frame `frame` (locals), the
/// commons and the system variables shown, then the compiler and the VM evaluate it; a condition
/// gives 1 or 0.
fn evaluate(expr: &str, p: &Paused, frame: usize) -> Result<f64, String> {
    if expr.contains(['\n', '\r', ';', '(']) {
        return Err("one expression, on one line".into());
    }
    // First as a value, then as a condition.
    let forms = [
        format!("#100=[{expr}]\n"),
        format!("#100=0\nIF[{expr}]THEN#100=1\n"),
    ];
    // A value that does not compile may be a condition; one that fails as it runs (a zero
    // divide) says so.
    match evaluate_text(&forms[0], p, frame) {
        Ok(v) => Ok(v),
        Err(Failed::Running(e)) => Err(e),
        Err(Failed::Compiling(e)) => match evaluate_text(&forms[1], p, frame) {
            Ok(v) => Ok(v),
            Err(Failed::Running(why)) => Err(why),
            Err(Failed::Compiling(_)) => Err(e),
        },
    }
}

/// Why an expression has no value: it does not compile, or it fails as it runs.
enum Failed {
    Compiling(String),
    Running(String),
}

/// Runs `text` (which sets #100) with the paused values put in for the variables it reads.
fn evaluate_text(text: &str, p: &Paused, frame: usize) -> Result<f64, Failed> {
    use fmsvm_compiler::outline::{Item, outline};
    let options = fmsvm_compiler::Options::default();
    let mut reads: Vec<(usize, usize, u32)> = outline(fmsvm_compiler::FileId(0), text, &options)
        .into_iter()
        .filter_map(|i| match i {
            Item::Var {
                number,
                span,
                write: false,
            } => Some((span.start as usize, span.end as usize, number)),
            _ => None,
        })
        .collect();
    reads.sort_by_key(|r| std::cmp::Reverse(r.0));
    let mut text = text.to_string();
    for (start, end, n) in reads {
        let v = match n {
            0 => f64::NAN,
            100 => continue,
            1..=33 => p
                .frames
                .get(frame)
                .and_then(|f| f.locals.get(n as usize).copied())
                .unwrap_or(f64::NAN),
            _ => match fmsvm_compiler::ir::common_index(n) {
                Some(i) => p.commons.get(usize::from(i)).copied().unwrap_or(f64::NAN),
                None => p
                    .system
                    .iter()
                    .find(|(name, _)| name.starts_with(&format!("#{n} ")))
                    .and_then(|(_, v)| *v)
                    .ok_or_else(|| {
                        Failed::Running(format!(
                            "#{n} is not among the variables the debugger shows"
                        ))
                    })?,
            },
        };
        let literal = if v.is_nan() {
            "#0".to_string()
        } else {
            format!("[{v:?}]")
        };
        text.replace_range(start..end, &literal);
    }
    let (program, diags, _) = fmsvm_compiler::compile_str(&text, &options);
    let Some(program) = program else {
        return Err(Failed::Compiling(
            diags
                .iter()
                .find(|d| d.is_error())
                .map_or("not an expression".into(), |d| d.message.clone()),
        ));
    };
    let mut vars = fmsvm_vm::Variables::default();
    let mut port = fmsvm_vm::MemoryPort::default();
    // A breakpoint's condition is evaluated inside the run being debugged: not by its debugger.
    fmsvm_vm::debug::without_debugger(|| {
        fmsvm_vm::run(
            &program,
            &mut Values,
            &mut port,
            &mut vars,
            &fmsvm_vm::RunOptions::default(),
        )
    })
    .map_err(|e| Failed::Running(e.to_string()))?;
    let i = fmsvm_compiler::ir::common_index(100).map_or(0, usize::from);
    Ok(vars.commons[i])
}

/// The machine an expression runs on: it has no blocks and no system variables (they were put in
/// as values).
struct Values;

impl fmsvm_block::Machine for Values {
    fn block(
        &mut self,
        _: &fmsvm_block::Block<'_>,
    ) -> Result<fmsvm_block::Flow, fmsvm_block::Stop> {
        Err(fmsvm_block::Alarm::new(NO_FANUC_NUMBER, "an expression has no NC words").into())
    }

    fn read_system(&mut self, n: u32) -> Result<f64, fmsvm_block::Stop> {
        Err(fmsvm_block::Alarm::new(115, format!("#{n} is not known here")).into())
    }

    fn write_system(&mut self, n: u32, _: f64) -> Result<(), fmsvm_block::Stop> {
        Err(fmsvm_block::Alarm::new(116, format!("#{n} cannot be written here")).into())
    }

    fn increment(&self, _: fmsvm_block::Letter) -> f64 {
        0.001
    }
}

/// The debugger on the run's thread: where each op is, and the pauses.
struct Session {
    /// The run's files as it compiles them (the same library, so the same file numbers), and
    /// their names as breakpoints say them.
    sources: fmsvm_compiler::SourceMap,
    names: Vec<String>,
    /// The run's folder (its output is written there as it goes) and the bytes of it sent so far.
    dir: PathBuf,
    sent: std::cell::Cell<usize>,
    shared: Arc<Mutex<Shared>>,
    out: Out,
    resume: Receiver<Mode>,
    /// `pause`, `terminate` or `disconnect` while the run goes on ([`RUNNING`], [`PAUSE`], [`STOP`]).
    interrupt: Arc<std::sync::atomic::AtomicU8>,
    state: std::cell::RefCell<Walk>,
}

/// Where the run is, line by line.
struct Walk {
    mode: Mode,
    /// The last (file, line) seen at each depth, and the frames' locals.
    frames: Vec<Frame>,
    last: Option<(u8, u32, u32)>,
    entry: bool,
}

impl Session {
    /// The flat program written since the last output event (what the run's writer has flushed:
    /// the output file, or its temporary file while the run goes on).
    fn output(&self) {
        let Ok(entries) = std::fs::read_dir(&self.dir) else {
            return;
        };
        let newest = entries
            .flatten()
            .filter(|e| e.path().extension().is_none_or(|x| x != "nc"))
            .filter_map(|e| Some((e.metadata().ok()?.modified().ok()?, e.path())))
            .max()
            .map(|(_, p)| p);
        let Some(text) = newest.and_then(|p| std::fs::read(p).ok()) else {
            return;
        };
        let from = self.sent.get();
        if text.len() > from {
            self.out.event(
                "output",
                json!({"category": "stdout", "output": String::from_utf8_lossy(&text[from..])}),
            );
            self.sent.set(text.len());
        }
    }

    /// The file and 1-based line and column of a span.
    fn place(&self, span: fmsvm_compiler::Span) -> Option<(usize, u32, u32)> {
        let i = span.file.0 as usize;
        let (line, col) = self.sources.files().get(i)?.line_col(span.start);
        Some((i, line, col))
    }

    fn breakpoint(&self, file: usize, line: u32, p: &Paused) -> bool {
        let Ok(s) = self.shared.lock() else {
            return false;
        };
        let name = &self.names[file];
        let Some(list) = s.breakpoints.get(name) else {
            return false;
        };
        list.iter().any(|(l, cond)| {
            *l == line
                && cond
                    .as_deref()
                    .is_none_or(|c| evaluate(c, p, p.frames.len().saturating_sub(1)) == Ok(1.0))
        })
    }
}

impl Debugger for Session {
    fn before(&self, at: &mut Stop<'_>) -> bool {
        use std::sync::atomic::Ordering::Relaxed;
        // A terminate or disconnect stops a running program at its next op; a pause pauses it
        // at its next op.
        let interrupt = self.interrupt.load(Relaxed);
        if interrupt == STOP {
            return false;
        }
        let Some((file, line, column)) = self.place(at.span) else {
            return true;
        };
        let mut w = self.state.borrow_mut();
        let here = (at.depth, file as u32, line);
        if w.last == Some(here) && interrupt == RUNNING {
            return true;
        }
        let depth = at.depth;
        w.last = Some(here);
        let d = usize::from(depth);
        w.frames.truncate(d + 1);
        while w.frames.len() <= d {
            w.frames.push(Frame {
                program: None,
                file: String::new(),
                line: 0,
                column: 0,
                locals: Vec::new(),
            });
        }
        w.frames[d] = Frame {
            program: at.program,
            file: self.names[file].clone(),
            line,
            column,
            locals: at.locals.to_vec(),
        };
        let snapshot = |w: &Walk, at: &mut Stop<'_>| Paused {
            frames: w.frames.clone(),
            commons: at.commons.to_vec(),
            system: SYSTEM
                .iter()
                .map(|&(n, name)| (name.to_string(), (at.system)(n)))
                .collect(),
        };
        let p = snapshot(&w, at);
        let reason = match w.mode {
            _ if w.entry => Some("entry"),
            Mode::Stop => return false,
            _ if interrupt == PAUSE => {
                self.interrupt.store(RUNNING, Relaxed);
                Some("pause")
            }
            Mode::Into => Some("step"),
            Mode::Over(k) if depth <= k => Some("step"),
            Mode::Out(k) if depth < k => Some("step"),
            _ if self.breakpoint(file, line, &p) => Some("breakpoint"),
            _ => None,
        };
        let Some(reason) = reason else {
            return true;
        };
        w.entry = false;
        if let Ok(mut s) = self.shared.lock() {
            s.paused = Some(p);
        }
        self.output();
        self.out.event(
            "stopped",
            json!({"reason": reason, "threadId": 1, "allThreadsStopped": true}),
        );
        let mode = self.resume.recv().unwrap_or(Mode::Stop);
        w.mode = mode;
        if let Ok(mut s) = self.shared.lock() {
            s.paused = None;
        }
        mode != Mode::Stop
    }
}

/// `setBreakpoints`: the breakpoints kept for the session, each said verified or not (a line the file
/// does not have is said so).
fn set_breakpoints(args: &Value, shared: &Arc<Mutex<Shared>>) -> Value {
    let path = args["source"]["path"].as_str().unwrap_or("").to_string();
    // A breakpoint is on a line the file has (1 to its last); any other is said so.
    let lines = fmsvm_driver::input::read_regular(Path::new(&path), crate::frame::MAX_BODY as u64)
        .map(|b| {
            let n = b.iter().filter(|&&c| c == b'\n').count();
            n + usize::from(b.last().is_some_and(|&c| c != b'\n'))
        })
        .map_err(|e| format!("cannot read {path}: {e}"));
    let mut wanted: Vec<(u32, Option<String>)> = Vec::new();
    let mut body: Vec<Value> = Vec::new();
    for b in args["breakpoints"].as_array().into_iter().flatten() {
        let line = b["line"]
            .as_i64()
            .filter(|&l| {
                lines
                    .as_ref()
                    .is_ok_and(|&n| l >= 1 && l as u64 <= n as u64)
            })
            .and_then(|l| u32::try_from(l).ok());
        match (line, &lines) {
            (Some(l), _) => {
                wanted.push((l, b["condition"].as_str().map(str::to_string)));
                body.push(json!({"verified": true, "line": l}));
            }
            (None, Ok(n)) => body.push(json!({"verified": false, "line": b["line"],
                    "message": format!("not a line of {path} (it has lines 1 to {n})")})),
            (None, Err(why)) => body.push(json!({"verified": false, "line": b["line"],
                    "message": why})),
        }
    }
    if let Ok(mut s) = shared.lock() {
        s.breakpoints.insert(canonical(&path), wanted);
    }
    json!({"breakpoints": body})
}

/// `stackTrace`: the paused run's programs, innermost first.
fn stack_trace(shared: &Arc<Mutex<Shared>>) -> Value {
    let frames = paused(shared).map(|p| p.frames).unwrap_or_default();
    let list: Vec<Value> = frames
        .iter()
        .enumerate()
        .rev()
        .map(|(i, f)| {
            json!({"id": i, "name": f.program.map_or("(main)".to_string(), |n| format!("O{n}")),
                "source": {"path": f.file, "name": Path::new(&f.file).file_name().map(|n| n.to_string_lossy().into_owned())},
                "line": f.line, "column": f.column})
        })
        .collect();
    json!({"stackFrames": list, "totalFrames": frames.len()})
}

/// `run`'s flags, as the launch arguments give them.
#[derive(clap::Parser)]
#[command(name = "fmsvm", bin_name = "fmsvm run")]
struct RunFlags {
    #[command(flatten)]
    run: fmsvm_flags::RunArgs,
}

/// The run: `run`'s options from the launch arguments, the program into a temporary folder, the
/// debugger installed; its report and flat program as output, then `terminated`.
fn session(
    launch: &Value,
    resume: Receiver<Mode>,
    interrupt: Arc<std::sync::atomic::AtomicU8>,
    out: &Out,
    shared: &Arc<Mutex<Shared>>,
) {
    use clap::Parser as _;
    let program = launch["program"].as_str().unwrap_or("").to_string();
    let stop_on_entry = launch["stopOnEntry"].as_bool().unwrap_or(false);
    let extra: Vec<String> = launch["args"]
        .as_array()
        .map(|a| {
            a.iter()
                .filter_map(|v| v.as_str().map(str::to_string))
                .collect()
        })
        .unwrap_or_default();
    let Ok(dir) = tempfile::tempdir() else {
        out.event("terminated", json!({}));
        return;
    };
    let flat = dir.path().join("flat.out");
    let folder = dir.path().to_path_buf();
    let mut argv: Vec<std::ffi::OsString> = vec!["fmsvm run".into(), "-q".into()];
    argv.extend(extra.iter().map(Into::into));
    argv.extend([
        "-o".into(),
        flat.clone().into_os_string(),
        program.clone().into(),
    ]);
    let args = match RunFlags::try_parse_from(&argv) {
        Ok(a) => a,
        Err(e) => {
            out.event(
                "output",
                json!({"category": "stderr", "output": format!("{e}\n")}),
            );
            out.event("terminated", json!({}));
            return;
        }
    };
    let run = args.run.request();
    let say = |text: String| {
        out.event("output", json!({"category": "stderr", "output": text}));
    };
    let end = |exit: Exit| {
        out.event("exited", json!({"exitCode": exit as u8}));
        out.event("terminated", json!({}));
    };
    // The program as the run reads it: a regular file, within --max-input.
    let path = PathBuf::from(&program);
    let text = match fmsvm_driver::input::read_regular(&path, run.input.max_input) {
        Ok(bytes) => String::from_utf8_lossy(&bytes).into_owned(),
        Err(e) => {
            say(format!("cannot read {program}: {e}\n"));
            return end(match e {
                fmsvm_driver::input::ReadError::TooBig(_) => Exit::Limit,
                fmsvm_driver::input::ReadError::Io(_) => Exit::Io,
            });
        }
    };
    // The files as the run compiles them (the same library, so the same file numbers); a program
    // that does not compile is said error by error, each at its line and column, and not run.
    let (diags, sources, _) = crate::lsp::compile_text(&run.input, &path, &text);
    let errors: Vec<String> = diags
        .iter()
        .filter(|d| d.is_error())
        .map(|d| {
            let file = sources.file(d.span.file);
            let (line, col) = file.line_col(d.span.start);
            let alarm = d.alarm.map_or(String::new(), |a| format!("[alarm {a:04}]"));
            let notes: String = d.notes.iter().map(|n| format!("  = note: {n}\n")).collect();
            format!(
                "{}:{line}:{col}: error{alarm}: {}\n{notes}",
                file.name, d.message
            )
        })
        .collect();
    if !errors.is_empty() {
        for e in errors {
            say(e);
        }
        return end(Exit::Compile);
    }
    let names = sources.files().iter().map(|f| canonical(&f.name)).collect();
    let debugger = Rc::new(Session {
        sources,
        names,
        dir: folder,
        sent: std::cell::Cell::new(0),
        shared: Arc::clone(shared),
        out: out.clone(),
        resume,
        interrupt,
        state: std::cell::RefCell::new(Walk {
            mode: Mode::Continue,
            frames: Vec::new(),
            last: None,
            entry: stop_on_entry,
        }),
    });
    // Whatever happens in the run, the session ends with `terminated`.
    let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        let hooks = fmsvm_driver::run::Hooks {
            debugger: Some(debugger.clone()),
            ..Default::default()
        };
        fmsvm_driver::run::expand(&run, fmsvm_driver::run::Consumer::Flat, hooks)
    }));
    let (exit, stop) = match outcome {
        Ok(o) => (o.exit, o.stop),
        Err(_) => (Exit::Internal, None),
    };
    if let Some(s) = stop {
        // Where the run stopped, as line and column of its file.
        let place = debugger
            .sources
            .files()
            .iter()
            .find(|f| f.name == s.file)
            .map(|f| f.line_col(s.start));
        let at = match place {
            Some((line, col)) => format!("{}:{line}:{col}", s.file),
            None => s.file.clone(),
        };
        say(format!("{at}: {}\n", s.message));
    }
    if flat.exists() {
        debugger.output();
    }
    end(exit);
}
