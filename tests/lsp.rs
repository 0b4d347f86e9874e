//! `fmsvm lsp` driven over standard input and output as an editor would: initialize, open a file
//! with an error, the diagnostic (alarm number, note, quick fix), the fix applied, hover, go to
//! definition (a GOTO, a loop's END, a program in a library folder), references, symbols, folding,
//! the flat program, and input a server must survive; then shutdown and exit.
#![cfg(feature = "lsp")]

use crate::cli_support;
use crate::framed;

use serde_json::{Value, json};

/// An editor's end of `fmsvm lsp`: requests numbered from 1.
struct Client {
    server: framed::Framed,
    next: i64,
}

impl Client {
    fn start() -> Client {
        Client {
            server: framed::Framed::start("lsp"),
            next: 1,
        }
    }

    fn send(&mut self, v: &Value) {
        self.server.send(v);
    }

    fn receive(&mut self) -> Value {
        self.server.receive()
    }

    fn notify(&mut self, method: &str, params: Value) {
        self.send(&json!({"jsonrpc": "2.0", "method": method, "params": params}));
    }

    /// Sends a request and returns its result (notifications before it are kept aside).
    fn request(&mut self, method: &str, params: Value) -> Value {
        let id = self.next;
        self.next += 1;
        self.send(&json!({"jsonrpc": "2.0", "id": id, "method": method, "params": params}));
        loop {
            let m = self.receive();
            if m.get("id") == Some(&json!(id)) {
                assert!(m.get("error").is_none(), "{method}: {m}");
                return m["result"].clone();
            }
        }
    }

    /// `initialize` with `root` as the workspace, then `initialized`: the server's capabilities.
    fn initialize(&mut self, root: &std::path::Path) -> Value {
        let init = self.request(
            "initialize",
            json!({"processId": null, "rootUri": uri(root), "capabilities": {}}),
        );
        self.notify("initialized", json!({}));
        init
    }

    /// `didOpen` of document `uri` with `text` (version 1).
    fn open(&mut self, uri: &str, text: &str) {
        self.notify(
            "textDocument/didOpen",
            json!({"textDocument": {"uri": uri, "languageId": "fanuc-macro", "version": 1, "text": text}}),
        );
    }

    /// `didSave` of `uri`: the run on save starts.
    fn save(&mut self, uri: &str) {
        self.notify(
            "textDocument/didSave",
            json!({"textDocument": {"uri": uri}}),
        );
    }

    /// `shutdown` (answered with null), `exit`, and the server's exit with success.
    fn shut_down(&mut self) {
        let r = self.request("shutdown", Value::Null);
        assert!(r.is_null(), "{r}");
        self.notify("exit", Value::Null);
        let status = self.server.child.wait().expect("the server exits");
        assert!(status.success(), "{status}");
    }

    /// The next diagnostics published for `uri`.
    fn diagnostics(&mut self, uri: &str) -> Vec<Value> {
        loop {
            let m = self.receive();
            if m["method"] == "textDocument/publishDiagnostics" && m["params"]["uri"] == uri {
                return m["params"]["diagnostics"]
                    .as_array()
                    .cloned()
                    .unwrap_or_default();
            }
        }
    }
}

/// A workspace whose `fmsvm.toml` gives `args` (TOML) and `run_args` with a stock (a block X 0–100
/// Y 0–100 Z −20–0) and T1 a 6 mm flat end mill.
fn stock_workspace(d: &cli_support::Dir, args: &str) {
    d.file(
        "fmsvm.toml",
        &format!(
            "args = {args}\nrun_args = [\"--stock\", \"0,0,-20,100,100,0\", \"--offsets\", \"tools.toml\"]\n"
        ),
    );
    d.file(
        "tools.toml",
        "[tool.1]\ntype = \"flat\"\ndiameter = 6.0\n\n[work.G54]\nX = 0.0\nY = 0.0\nZ = 0.0\n",
    );
}

fn uri(p: &std::path::Path) -> String {
    format!("file://{}", p.display())
}

fn at(uri: &str, line: u32, character: u32) -> Value {
    json!({"textDocument": {"uri": uri}, "position": {"line": line, "character": character}})
}

const MAIN: &str = "O1000 (MAIN)
N10 #1=0
WHILE[#1LTE3]DO1
G65 P2000 X#1
#1=#1+1
END1
G43 H1 Z50.
IF[#1LT3]GOTO10
M30
";

#[test]
fn an_editor_sees_diagnostics_hovers_jumps_and_fixes() {
    let d = cli_support::Dir::new();
    d.file("fmsvm.toml", "args = [\"--lib\", \"lib\"]\n");
    std::fs::create_dir_all(d.path("lib")).expect("lib");
    d.file("lib/O2000.nc", "O2000\nG1 X#24 F100\nM99\n");
    let main = d.file("main.nc", MAIN);
    let main_uri = uri(&main);
    let mut c = Client::start();
    let init = c.initialize(&d.path(""));
    assert_eq!(init["capabilities"]["hoverProvider"], true, "{init}");

    // The error as the compiler gives it: where, the alarm, the note, and the fix.
    c.open(&main_uri, MAIN);
    // The WHILE line does not parse, so END1 has no DO1 before it: both, as `check` says.
    let diags = c.diagnostics(&main_uri);
    assert_eq!(diags.len(), 2, "{diags:?}");
    assert_eq!(diags[1]["code"], "0126", "{diags:?}");
    let e = &diags[0];
    assert_eq!(e["code"], "0114", "{e}");
    assert_eq!(e["severity"], 1);
    assert_eq!(
        e["range"]["start"],
        json!({"line": 2, "character": 8}),
        "{e}"
    );
    assert!(
        e["message"]
            .as_str()
            .unwrap_or("")
            .contains("did you mean `LE`"),
        "{e}"
    );
    assert!(
        e["relatedInformation"][0]["message"]
            .as_str()
            .unwrap_or("")
            .contains("EQ NE GT GE LT LE"),
        "{e}"
    );
    let actions = c.request(
        "textDocument/codeAction",
        json!({"textDocument": {"uri": main_uri}, "range": e["range"], "context": {"diagnostics": [e]}}),
    );
    let edit = &actions[0]["edit"]["changes"][&main_uri][0];
    assert_eq!(edit["newText"], "LE", "{actions}");
    assert_eq!(edit["range"], e["range"]);

    // Fixed, it has none.
    let fixed = MAIN.replace("LTE3", "LE3");
    c.notify(
        "textDocument/didChange",
        json!({"textDocument": {"uri": main_uri, "version": 2}, "contentChanges": [{"text": fixed}]}),
    );
    assert_eq!(c.diagnostics(&main_uri), Vec::<Value>::new());

    // Hover: a macro argument, a G code of the kernel's tables.
    let h = c.request("textDocument/hover", at(&main_uri, 3, 12));
    assert!(
        h["contents"]["value"]
            .as_str()
            .unwrap_or("")
            .starts_with("#1: a local variable; in a macro called with G65/G66, its argument A"),
        "{h}"
    );
    // A function: what it does.
    let doc2 = "O1\n#1=SQRT[#2]\nM30\n";
    let fn_uri = uri(&d.file("fn.nc", doc2));
    c.open(&fn_uri, doc2);
    let h = c.request("textDocument/hover", at(&fn_uri, 1, 4));
    assert_eq!(
        h["contents"]["value"], "SQRT[x]: the square root of x; alarm 0119 below 0",
        "{h}"
    );
    let h = c.request("textDocument/hover", at(&main_uri, 6, 1));
    assert_eq!(
        h["contents"]["value"], "G43: group 08, tool length offset (G43 G44 G49)",
        "{h}"
    );

    // Definition: GOTO10 → N10; END1 → its DO; P2000 → the library's file.
    let g = c.request("textDocument/definition", at(&main_uri, 7, 14));
    assert_eq!(
        g["range"]["start"],
        json!({"line": 1, "character": 0}),
        "{g}"
    );
    let g = c.request("textDocument/definition", at(&main_uri, 5, 1));
    assert_eq!(g["range"]["start"]["line"], 2, "{g}");
    let g = c.request("textDocument/definition", at(&main_uri, 3, 5));
    assert_eq!(g["uri"], uri(&d.path("lib/O2000.nc")), "{g}");

    // References of #1: every read and write in the program.
    let r = c.request(
        "textDocument/references",
        json!({"textDocument": {"uri": main_uri}, "position": {"line": 1, "character": 5}, "context": {"includeDeclaration": true}}),
    );
    assert_eq!(r.as_array().map(Vec::len), Some(6), "{r}");

    // The outline: O1000 with N10 and its loop; the loop folds.
    let s = c.request(
        "textDocument/documentSymbol",
        json!({"textDocument": {"uri": main_uri}}),
    );
    assert_eq!(s[0]["name"], "O1000", "{s}");
    let children: Vec<&str> = s[0]["children"]
        .as_array()
        .map(|a| a.iter().filter_map(|c| c["name"].as_str()).collect())
        .unwrap_or_default();
    assert_eq!(children, ["N10", "DO1"], "{s}");
    let f = c.request(
        "textDocument/foldingRange",
        json!({"textDocument": {"uri": main_uri}}),
    );
    assert!(
        f.as_array()
            .is_some_and(|a| a.iter().any(|r| r["startLine"] == 2 && r["endLine"] == 5)),
        "{f}"
    );

    // The flat program, as `run` writes it with the workspace's --lib.
    let x = c.request(
        "workspace/executeCommand",
        json!({"command": "fmsvm.expand", "arguments": [main_uri]}),
    );
    let flat = x["flat"].as_str().unwrap_or("");
    assert!(flat.contains("G1 X0. F100.") && flat.contains("X3."), "{x}");
    // And its statistics, as `fmsvm stats --json` gives them: five feed moves (X0 to X3, and
    // `G43 H1 Z50.` under the G1 in force), X0 to X3.
    assert_eq!(x["stats"]["counts"]["feed"], 5, "{x}");
    assert_eq!(x["stats"]["extents"]["max"]["x"], 3.0, "{x}");

    // On save the program runs: a zero divide at run time is shown at its block, with its alarm.
    let alarm = d.file("alarm.nc", "O3000\n#1=0\n#2=1/#1\nM30\n");
    let alarm_uri = uri(&alarm);
    c.open(&alarm_uri, "O3000\n#1=0\n#2=1/#1\nM30\n");
    assert_eq!(
        c.diagnostics(&alarm_uri),
        Vec::<Value>::new(),
        "it compiles"
    );
    c.save(&alarm_uri);
    let run = c.diagnostics(&alarm_uri);
    assert_eq!(run.len(), 1, "{run:?}");
    assert_eq!(run[0]["code"], "0112", "{run:?}");
    assert_eq!(run[0]["source"], "fmsvm run");
    assert_eq!(run[0]["range"]["start"]["line"], 2, "{run:?}");
    // Hover then tells what #1 was when the run reached that line.
    let h = c.request("textDocument/hover", at(&alarm_uri, 2, 6));
    assert!(
        h["contents"]["value"]
            .as_str()
            .unwrap_or("")
            .ends_with("In the last run (on save): #1 = 0 when this line last began"),
        "{h}"
    );

    // What a server must survive: binary text, positions past the end, unknown methods.
    let junk = "\u{0}\u{1}[[[[#####\u{fffd}\nWHILE[DO\n".repeat(50);
    c.notify(
        "textDocument/didChange",
        json!({"textDocument": {"uri": main_uri, "version": 3}, "contentChanges": [{"text": junk}]}),
    );
    assert!(!c.diagnostics(&main_uri).is_empty());
    let h = c.request("textDocument/hover", at(&main_uri, 100_000, 100_000));
    assert!(h.is_null(), "{h}");
    let id = 999;
    c.send(&json!({"jsonrpc": "2.0", "id": id, "method": "fmsvm/nothing", "params": {}}));
    loop {
        let m = c.receive();
        if m["id"] == id {
            assert_eq!(m["error"]["code"], -32601, "{m}");
            break;
        }
    }

    c.shut_down();
}

/// Frames a server must survive: a body that is not JSON, JSON that is no message, a negative
/// length, a header ended by LF alone, a lone UTF-16 surrogate in a document (as JavaScript writes
/// one), a length of 10¹⁴ bytes. Each broken one is answered with JSON-RPC's parse error (-32700)
/// or invalid request (-32600) and the server goes on; the huge one is passed by, not allocated.
#[test]
fn broken_frames_are_answered_and_the_server_goes_on() {
    let d = cli_support::Dir::new();
    let main = d.file("main.nc", "O1\nG0 X0\nM30\n");
    let main_uri = uri(&main);
    let mut c = Client::start();
    c.initialize(&d.path(""));
    let error = |c: &mut Client| loop {
        let m = c.receive();
        if m.get("error").is_some() && m["id"].is_null() {
            return m["error"]["code"].as_i64().unwrap_or(0);
        }
    };
    c.server.send_raw(b"Content-Length: 9\r\n\r\nnot json!");
    assert_eq!(error(&mut c), -32700);
    c.server.send_raw(b"Content-Length: 7\r\n\r\n[1,2,3]");
    assert_eq!(error(&mut c), -32600);
    c.server.send_raw(b"Content-Length: -5\r\n\r\n");
    assert_eq!(error(&mut c), -32700);
    // A request framed with LF alone is read as any other.
    let body = json!({"jsonrpc": "2.0", "id": 77, "method": "textDocument/hover",
        "params": at(&main_uri, 0, 0)})
    .to_string();
    c.server
        .send_raw(format!("Content-Length: {}\n\n{body}", body.len()).as_bytes());
    loop {
        let m = c.receive();
        if m["id"] == 77 {
            assert!(m.get("error").is_none(), "{m}");
            break;
        }
    }
    // The document's text with a lone surrogate: opened, checked, its diagnostics published.
    let open = format!(
        r#"{{"jsonrpc":"2.0","method":"textDocument/didOpen","params":{{"textDocument":{{"uri":"{main_uri}","languageId":"nc","version":1,"text":"O1\nG0 X0 (a\ud800b)\nWHILE[\n"}}}}}}"#
    );
    c.server
        .send_raw(format!("Content-Length: {}\r\n\r\n{open}", open.len()).as_bytes());
    assert!(!c.diagnostics(&main_uri).is_empty());
    let r = c.request("shutdown", Value::Null);
    assert!(r.is_null());
    // A length no server can hold, and the input ends: no allocation of it, an exit that says why.
    c.server
        .send_raw(b"Content-Length: 100000000000000\r\n\r\n{\"jsonrpc\":\"2.0\"}");
    c.server.close();
    let status = c.server.child.wait().expect("the server exits");
    // The shutdown came before the input ended: 0, the protocol's rule.
    assert_eq!(status.code(), Some(0), "{status}");
    // Without a shutdown the end of the input is exit 1.
    let mut c = Client::start();
    c.initialize(&d.path(""));
    c.server
        .send_raw(b"Content-Length: 100000000000000\r\n\r\n{}");
    c.server.close();
    let status = c.server.child.wait().expect("the server exits");
    assert_eq!(status.code(), Some(1), "{status}");
}

/// The run on save goes on a thread of its own: while an endless loop runs (up to the on-save
/// run's 10 s), a hover is answered, before the run's diagnostics come.
#[test]
fn the_server_answers_while_a_save_runs() {
    let d = cli_support::Dir::new();
    let text = "O1\n#1=0\nWHILE[1EQ1]DO1\n#1=#1+1\nEND1\nM30\n";
    let main_uri = uri(&d.file("main.nc", text));
    let mut c = Client::start();
    c.initialize(&d.path(""));
    c.open(&main_uri, text);
    assert_eq!(c.diagnostics(&main_uri), Vec::<Value>::new());
    c.save(&main_uri);
    c.send(
        &json!({"jsonrpc": "2.0", "id": 500, "method": "textDocument/hover",
        "params": at(&main_uri, 1, 1)}),
    );
    loop {
        let m = c.receive();
        assert_ne!(
            m["method"], "textDocument/publishDiagnostics",
            "the run's diagnostics came before the hover's answer: {m}"
        );
        if m["id"] == 500 {
            assert!(m.get("error").is_none(), "{m}");
            break;
        }
    }
    c.shut_down();
}

#[test]
fn the_clients_settings_give_checks_options() {
    // No fmsvm.toml: the client says the options, at start or later.
    let d = cli_support::Dir::new();
    d.file("lib/O2000.nc", "O2000\nM99\n");
    let text = "O1\nM98 P2000\nM30\n";
    let main_uri = uri(&d.file("main.nc", text));
    let lib = d.path("lib").display().to_string();
    let mut c = Client::start();
    c.initialize(&d.path(""));
    c.open(&main_uri, text);
    // Without the library the call finds nothing: the compiler's warning, and no definition.
    let diags = c.diagnostics(&main_uri);
    assert!(
        diags
            .iter()
            .any(|d| d["message"].as_str().unwrap_or("").contains("O2000")),
        "{diags:?}"
    );
    assert!(
        c.request("textDocument/definition", at(&main_uri, 1, 5))
            .is_null()
    );
    c.notify(
        "workspace/didChangeConfiguration",
        json!({"settings": {"fmsvm": {"args": ["--lib", lib]}}}),
    );
    assert_eq!(c.diagnostics(&main_uri), Vec::<Value>::new());
    let g = c.request("textDocument/definition", at(&main_uri, 1, 5));
    assert_eq!(g["uri"], uri(&d.path("lib/O2000.nc")), "{g}");
    // A bad option is said as the editor's, not fmsvm.toml's; a parameters file that does not
    // parse says why.
    let said = |c: &mut Client| {
        c.diagnostics(&main_uri)
            .iter()
            .map(|d| d["message"].as_str().unwrap_or("").to_string())
            .collect::<String>()
    };
    c.notify(
        "workspace/didChangeConfiguration",
        json!({"settings": {"fmsvm": {"args": ["--no-such-option"]}}}),
    );
    let m = said(&mut c);
    assert!(m.contains("the editor's settings (fmsvm.args)"), "{m}");
    d.file(
        "p.toml",
        "[macro]
no_such_key = 1
",
    );
    let params = d.path("p.toml").display().to_string();
    c.notify(
        "workspace/didChangeConfiguration",
        json!({"settings": {"fmsvm": {"args": ["--params", params]}}}),
    );
    let m = said(&mut c);
    assert!(
        m.contains("cannot be read") && m.contains("no_such_key"),
        "{m}"
    );
    c.shut_down();
}

/// The editor's diagnostics, its expand and its on-save run take one configuration: the
/// workspace's options all reach the run (here the block-delete switch and AND's binding, which
/// the run once did not get), and hover reads codes as the workspace's control does (a lathe's
/// G50 is the spindle clamp, not the mill's scaling cancel). By hand: with AND bound below + -
/// (`lowest`), `1 AND 3 + 1` is 1 AND 4 = 0 (Fanuc's binding would give 2); the `/` block is
/// skipped.
#[test]
fn the_editor_runs_with_the_workspaces_options_and_its_controls_codes() {
    let d = cli_support::Dir::new();
    d.file(
        "fmsvm.toml",
        "args = [\"--block-delete\", \"--logic-level\", \"lowest\"]\n",
    );
    let text = "O1\n#1=1 AND 3 + 1\nG0 X#1\n/G0 X5.\nM30\n";
    let main = d.file("main.nc", text);
    let main_uri = uri(&main);
    let mut c = Client::start();
    c.initialize(&d.path(""));
    c.open(&main_uri, text);
    let x = c.request(
        "workspace/executeCommand",
        json!({"command": "fmsvm.expand", "arguments": [main_uri]}),
    );
    let flat = x["flat"].as_str().unwrap_or("");
    assert!(flat.contains("G0 X0.\n"), "{x}");
    assert!(!flat.contains("X5."), "{x}");

    // A lathe workspace: G50 and G71 as the 0i-TD reads them (G-code system A).
    let lathe = cli_support::Dir::new();
    lathe.file("fmsvm.toml", "args = [\"--control\", \"fanuc-0i-t\"]\n");
    let text = "O2\nG50 S2000\nG71 U1. R0.5\nG99\nM30\n";
    let prog = lathe.file("t.nc", text);
    let prog_uri = uri(&prog);
    let mut c = Client::start();
    c.initialize(&lathe.path(""));
    c.open(&prog_uri, text);
    for (line, want) in [
        (
            1,
            "G50: coordinate system setting, or with S the spindle speed clamp (group 00",
        ),
        (2, "G71: stock removal in turning (group 00"),
        (3, "G99: group 05, feed mode (G98 G99)"),
    ] {
        let h = c.request("textDocument/hover", at(&prog_uri, line, 1));
        let value = h["contents"]["value"].as_str().unwrap_or("");
        assert!(value.starts_with(want), "line {line}: {h}");
    }
}

/// The editor runs the buffer it holds, not the file on disk: an unsaved edit is what expands, and
/// nothing is written beside the document.
#[test]
fn the_editor_runs_its_buffer_not_the_file() {
    let d = cli_support::Dir::new();
    let main = d.file("main.nc", "O1\nG0 X1.\nM30\n");
    let main_uri = uri(&main);
    let mut c = Client::start();
    c.initialize(&d.path(""));
    c.open(&main_uri, "O1\nG0 X2.\nM30\n");
    let x = c.request(
        "workspace/executeCommand",
        json!({"command": "fmsvm.expand", "arguments": [main_uri]}),
    );
    let flat = x["flat"].as_str().unwrap_or("");
    assert!(flat.contains("G0 X2.\n"), "{x}");
    assert!(!flat.contains("X1."), "{x}");
    assert_eq!(d.names(), ["main.nc"]);
}

/// Hover on a variable says what it is under the workspace's parameters: a common the control's
/// parameters narrow away, a variable they declare with its value, a range they add, an alias.
#[test]
fn hover_reads_variables_as_the_workspaces_parameters_declare_them() {
    let d = cli_support::Dir::new();
    d.file(
        "p.toml",
        "[macro]\ncommon_retained = [500, 599]\n[variables]\nranges = [[100000, 100009]]\nvalues = { 3901 = 41 }\nalias = { 4012 = 4014 }\n",
    );
    d.file("fmsvm.toml", "args = [\"--params\", \"p.toml\"]\n");
    let text = "O1\n#1=#700\n#2=#3901\n#3=#100005\n#4=#4012\n#5=#550\nM30\n";
    let prog = d.file("v.nc", text);
    let u = uri(&prog);
    let mut c = Client::start();
    c.initialize(&d.path(""));
    c.open(&u, text);
    for (line, want) in [
        (1, "#700: not a common variable of this control"),
        (
            2,
            "#3901: a variable the control holds, declared in --params (it starts at 41)",
        ),
        (3, "#100005: a common variable declared in --params"),
        (4, "#4012: read and written as #4014"),
        (5, "#550: a common variable, kept at power-off"),
    ] {
        let h = c.request("textDocument/hover", at(&u, line, 4));
        let value = h["contents"]["value"].as_str().unwrap_or("");
        assert!(value.starts_with(want), "line {line}: {h}");
    }
}

/// A workspace whose `fmsvm.toml` gives `run_args` with a stock: on save the program runs as
/// `stats` with it, and the stock's findings are shown at their lines, as warnings.
#[test]
fn on_save_the_stock_s_findings_are_shown_at_their_lines() {
    let d = cli_support::Dir::new();
    stock_workspace(&d, "[]");
    let text = "T1 M6\nG0 G90 X50 Y50 Z5\nG0 Z-1\nG1 Z5 F300\nM30\n";
    let main_uri = uri(&d.file("main.nc", text));
    let mut c = Client::start();
    c.initialize(&d.path(""));
    c.open(&main_uri, text);
    assert_eq!(c.diagnostics(&main_uri), Vec::<Value>::new());
    c.save(&main_uri);
    let run = c.diagnostics(&main_uri);
    let found: Vec<&Value> = run
        .iter()
        .filter(|d| {
            d["message"].as_str().unwrap_or("").contains(
                "a rapid (G0) into the stock: the cutter goes 1.000 below the material's top",
            )
        })
        .collect();
    assert_eq!(found.len(), 1, "{run:?}");
    assert_eq!(found[0]["range"]["start"]["line"], 2, "{run:?}");
    assert_eq!(found[0]["severity"], 2, "{run:?}");
    assert_eq!(found[0]["source"], "fmsvm run");
    c.shut_down();
}

/// A run's finding in a library program open in the editor is published with that program's own
/// diagnostics, not in their place (publishing replaces a file's whole list).
#[test]
fn a_run_s_finding_in_an_open_library_program_keeps_its_own_diagnostics() {
    let d = cli_support::Dir::new();
    stock_workspace(&d, "[\"--lib\", \"lib\"]");
    std::fs::create_dir_all(d.path("lib")).expect("lib");
    // Its own warning: a call to a program nowhere (on a branch the run does not take).
    let lib_text = "O2000\nIF[#1EQ5]GOTO10\nM98 P3000\nN10 G0 Z-1\nG0 Z5\nM99\n";
    let lib_uri = uri(&d.file("lib/O2000.nc", lib_text));
    let main_text = "T1 M6\nG0 G90 X50 Y50 Z5\n#1=5\nM98 P2000\nM30\n";
    let main_uri = uri(&d.file("main.nc", main_text));
    let mut c = Client::start();
    c.initialize(&d.path(""));
    c.open(&lib_uri, lib_text);
    let own = c.diagnostics(&lib_uri);
    let is_own = |d: &Value| d["code"] == "0076" && d["range"]["start"]["line"] == 2;
    assert!(own.iter().any(is_own), "{own:?}");
    c.open(&main_uri, main_text);
    c.save(&main_uri);
    // The run's finding, at the library program's line 4, with the program's own warning.
    let is_run = |d: &Value| {
        d["source"] == "fmsvm run"
            && d["range"]["start"]["line"] == 3
            && d["message"]
                .as_str()
                .unwrap_or("")
                .contains("a rapid (G0) into the stock: the cutter goes 1.000 below")
    };
    let published = loop {
        let list = c.diagnostics(&lib_uri);
        if list.iter().any(is_run) {
            break list;
        }
    };
    assert!(published.iter().any(is_own), "{published:?}");
    c.shut_down();
}
