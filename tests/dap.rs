//! `fmsvm dap` driven as an editor's debugger would: a conditional breakpoint in a loop, the stack
//! and locals there, a step into the G65 macro (its X argument in #24), a step out, evaluate, and
//! the flat program when the run ends (the same as `fmsvm run`'s).
#![cfg(feature = "lsp")]

use crate::cli_support;
use crate::framed;

use std::process::Command;

use serde_json::{Value, json};

/// An editor's end of `fmsvm dap`.
struct Adapter {
    server: framed::Framed,
    seq: i64,
    /// Events seen while waiting for responses.
    events: Vec<Value>,
}

impl Adapter {
    fn start() -> Adapter {
        Adapter {
            server: framed::Framed::start("dap"),
            seq: 0,
            events: Vec::new(),
        }
    }

    fn receive(&mut self) -> Value {
        self.server.receive()
    }

    /// Sends a request and waits for its response (events meanwhile kept).
    fn exchange(&mut self, command: &str, arguments: Value) -> Value {
        self.seq += 1;
        self.server.send(
            &json!({"seq": self.seq, "type": "request", "command": command, "arguments": arguments}),
        );
        loop {
            let m = self.receive();
            if m["type"] == "response" && m["request_seq"] == self.seq {
                return m;
            }
            self.events.push(m);
        }
    }

    /// A request the adapter refuses: its message.
    fn refused(&mut self, command: &str, arguments: Value) -> String {
        let m = self.exchange(command, arguments);
        assert_eq!(m["success"], false, "{command}: {m}");
        m["message"].as_str().unwrap_or("").to_string()
    }

    fn request(&mut self, command: &str, arguments: Value) -> Value {
        let m = self.exchange(command, arguments);
        assert_eq!(m["success"], true, "{command}: {m}");
        m["body"].clone()
    }

    /// The next event named `name` (earlier ones seen while waiting included).
    fn event(&mut self, name: &str) -> Value {
        if let Some(i) = self.events.iter().position(|e| e["event"] == name) {
            return self.events.remove(i);
        }
        loop {
            let m = self.receive();
            if m["event"] == name {
                return m;
            }
            self.events.push(m);
        }
    }

    fn top(&mut self) -> Value {
        let s = self.request("stackTrace", json!({"threadId": 1}));
        s["stackFrames"][0].clone()
    }

    fn local(&mut self, frame: u64, name: &str) -> String {
        let vars = self.request("variables", json!({"variablesReference": 1000 + frame}));
        vars["variables"]
            .as_array()
            .and_then(|a| a.iter().find(|v| v["name"] == name))
            .map(|v| v["value"].as_str().unwrap_or("").to_string())
            .unwrap_or_default()
    }
}

const PROGRAM: &str = "O1000
#1=0
WHILE[#1LT3]DO1
G65 P2000 X#1
#1=#1+1
END1
M30
O2000
#2=#24*2
G1 X#2 F100
M99
";

#[test]
fn a_breakpoint_a_step_into_the_macro_and_out_and_the_flat_program() {
    let d = cli_support::Dir::new();
    let program = d.file("loop.nc", PROGRAM);
    let path = std::fs::canonicalize(&program)
        .expect("path")
        .display()
        .to_string();
    let mut a = Adapter::start();
    let caps = a.request("initialize", json!({"adapterID": "fmsvm"}));
    assert_eq!(caps["supportsConditionalBreakpoints"], true);
    a.event("initialized");
    a.request("launch", json!({"program": path, "args": []}));
    let b = a.request(
        "setBreakpoints",
        json!({"source": {"path": path}, "breakpoints": [{"line": 4, "condition": "#1 EQ 2"}]}),
    );
    assert_eq!(b["breakpoints"][0]["verified"], true);
    a.request("configurationDone", json!({}));

    // The breakpoint holds only when #1 is 2 (the third pass).
    let s = a.event("stopped");
    assert_eq!(s["body"]["reason"], "breakpoint", "{s}");
    let top = a.top();
    assert_eq!(
        (top["line"].as_u64(), top["name"].as_str()),
        (Some(4), Some("O1000")),
        "{top}"
    );
    assert_eq!(a.local(0, "#1 (A)"), "2");

    // Into the macro: O2000's first line, #24 (X) = 2, two frames.
    a.request("stepIn", json!({"threadId": 1}));
    assert_eq!(a.event("stopped")["body"]["reason"], "step");
    let s = a.request("stackTrace", json!({"threadId": 1}));
    assert_eq!(s["totalFrames"], 2, "{s}");
    assert_eq!(s["stackFrames"][0]["name"], "O2000");
    assert_eq!(s["stackFrames"][0]["line"], 9);
    assert_eq!(a.local(1, "#24 (X)"), "2");
    let e = a.request("evaluate", json!({"expression": "#24 GT 1", "frameId": 1}));
    assert_eq!(e["result"], "1");
    // Any Macro B expression, on the paused values: the compiler and the VM evaluate it.
    let e = a.request(
        "evaluate",
        json!({"expression": "[#24+1]*2+SQRT[#24*8]", "frameId": 1}),
    );
    assert_eq!(e["result"], "10");
    let e = a.request("evaluate", json!({"expression": "#1*10", "frameId": 0}));
    assert_eq!(e["result"], "20");
    // An expression that fails says why, as the run would.
    let why = a.refused("evaluate", json!({"expression": "1/[#1-2]", "frameId": 0}));
    assert!(why.contains("alarm 0112: zero divide"), "{why}");

    // Over one line, then out: back in the main program after the call.
    a.request("next", json!({"threadId": 1}));
    a.event("stopped");
    assert_eq!(a.top()["line"], 10);
    a.request("stepOut", json!({"threadId": 1}));
    a.event("stopped");
    let top = a.top();
    assert_eq!(
        (top["line"].as_u64(), top["name"].as_str()),
        (Some(5), Some("O1000")),
        "{top}"
    );

    // To the end: the flat program, as `fmsvm run` writes it (in pieces, as written).
    a.request("continue", json!({"threadId": 1}));
    a.event("terminated");
    let out: String = a
        .events
        .iter()
        .filter(|e| e["event"] == "output" && e["body"]["category"] == "stdout")
        .map(|e| e["body"]["output"].as_str().unwrap_or("").to_string())
        .collect();
    let run = Command::new(env!("CARGO_BIN_EXE_fmsvm"))
        .args(["run", "-q", &path])
        .output()
        .expect("fmsvm run");
    assert_eq!(
        out,
        String::from_utf8_lossy(&run.stdout),
        "the debugger's run is the run"
    );
    assert!(out.contains("G1 X4. F100."), "{out}");
    a.request("disconnect", json!({}));
    assert!(a.server.child.wait().expect("exits").success());

    // A program that does not compile: the run says so and ends.
    let broken = d.file("broken.nc", "O1\n#1=[1+\nM30\n");
    let mut a = Adapter::start();
    a.request("initialize", json!({"adapterID": "fmsvm"}));
    a.request("launch", json!({"program": broken.display().to_string()}));
    a.request("configurationDone", json!({}));
    a.event("terminated");
    let exited = a
        .events
        .iter()
        .find(|e| e["event"] == "exited")
        .cloned()
        .unwrap_or_default();
    assert_eq!(exited["body"]["exitCode"], 3, "{:?}", a.events);
    a.request("disconnect", json!({}));
    assert!(a.server.child.wait().expect("exits").success());
}

/// Broken frames (not JSON, a negative length, a length of 10¹⁴) are said to the client as output
/// and passed by; the adapter answers the next request.
#[test]
fn broken_frames_are_said_and_passed_by() {
    let mut a = Adapter::start();
    a.server.send_raw(b"Content-Length: 9\r\n\r\nnot json!");
    a.server.send_raw(b"Content-Length: -5\r\n\r\n");
    let init = a.request("initialize", json!({"adapterID": "fmsvm"}));
    assert_eq!(init["supportsTerminateRequest"], true, "{init}");
    let said: Vec<String> = a
        .events
        .iter()
        .filter(|e| e["event"] == "output")
        .map(|e| e["body"]["output"].as_str().unwrap_or("").to_string())
        .collect();
    assert!(
        said.iter().any(|s| s.contains("not JSON")) && said.iter().any(|s| s.contains("`-5`")),
        "{said:?}"
    );
    a.server
        .send_raw(b"Content-Length: 100000000000000\r\n\r\n{}");
    a.server.close();
    let status = a.server.child.wait().expect("the adapter exits");
    assert!(status.code().is_some(), "ended by a signal: {status}");
}

/// Starts a session on `file` with `breakpoints` and lets it run; the breakpoints' answer.
fn launched(a: &mut Adapter, file: &str, breakpoints: Value) -> Value {
    a.request("initialize", json!({"adapterID": "fmsvm"}));
    a.event("initialized");
    a.request("launch", json!({"program": file, "args": []}));
    let b = a.request(
        "setBreakpoints",
        json!({"source": {"path": file}, "breakpoints": breakpoints}),
    );
    a.request("configurationDone", json!({}));
    b
}

/// The stderr output events seen, joined.
fn said(a: &Adapter) -> String {
    a.events
        .iter()
        .filter(|e| e["event"] == "output" && e["body"]["category"] == "stderr")
        .map(|e| e["body"]["output"].as_str().unwrap_or("").to_string())
        .collect()
}

/// A running endless loop is paused by `pause` (where it is), and `terminate` ends it at once,
/// paused or running.
#[test]
fn a_running_program_pauses_and_terminates_at_once() {
    let d = cli_support::Dir::new();
    let program = d.file(
        "endless.nc",
        "O1\n#1=0\nWHILE[1EQ1]DO1\n#1=#1+1\nEND1\nM30\n",
    );
    let file = program.display().to_string();
    let mut a = Adapter::start();
    launched(&mut a, &file, json!([]));
    std::thread::sleep(std::time::Duration::from_millis(200));
    a.request("pause", json!({"threadId": 1}));
    let s = a.event("stopped");
    assert_eq!(s["body"]["reason"], "pause", "{s}");
    let line = a.top()["line"].as_u64().unwrap_or(0);
    assert!((3..=5).contains(&line), "paused at line {line}");
    a.request("continue", json!({"threadId": 1}));
    std::thread::sleep(std::time::Duration::from_millis(100));
    // Running again: terminate stops it within a fraction of a second.
    let started = std::time::Instant::now();
    a.request("terminate", json!({}));
    a.event("terminated");
    assert!(
        started.elapsed() < std::time::Duration::from_secs(2),
        "{:?}",
        started.elapsed()
    );
}

/// Breakpoints on lines the file does not have are not verified; a program that does not compile
/// is said error by error at its line and column, and one that cannot be read (a FIFO) is said
/// too, not waited on; a run's alarm is said at line and column, not at a byte offset.
#[test]
fn what_the_adapter_cannot_do_it_says_at_its_line() {
    let d = cli_support::Dir::new();
    let program = d.file(
        "alarm.nc",
        "O1\n#1=1\nG0 X#1\n    #3000=7 (NO STOCK)\nM30\n",
    );
    let file = program.display().to_string();
    let mut a = Adapter::start();
    let b = launched(
        &mut a,
        &file,
        json!([{"line": 0}, {"line": -5}, {"line": 4294967296u64}, {"line": 6}, {"line": 4}]),
    );
    let verified: Vec<bool> = b["breakpoints"]
        .as_array()
        .expect("breakpoints")
        .iter()
        .map(|b| b["verified"] == true)
        .collect();
    assert_eq!(verified, [false, false, false, false, true], "{b}");
    assert_eq!(a.event("stopped")["body"]["reason"], "breakpoint");
    a.request("continue", json!({"threadId": 1}));
    let exited = a.event("exited");
    assert_eq!(exited["body"]["exitCode"], 4, "{exited}");
    a.event("terminated");
    assert!(said(&a).contains("alarm.nc:4:5: "), "{}", said(&a));

    let bad = d.file("bad.nc", "O1\n#1=[1+\nM30\n");
    let mut a = Adapter::start();
    launched(&mut a, &bad.display().to_string(), json!([]));
    let exited = a.event("exited");
    assert_eq!(exited["body"]["exitCode"], 3, "{exited}");
    assert!(said(&a).contains("bad.nc:2:"), "{}", said(&a));

    let fifo = d.fifo("wait.nc");
    let mut a = Adapter::start();
    launched(&mut a, &fifo.display().to_string(), json!([]));
    let exited = a.event("exited");
    assert_eq!(exited["body"]["exitCode"], 6, "{exited}");
    assert!(said(&a).contains("not a regular file"), "{}", said(&a));
}
