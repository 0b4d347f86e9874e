//! `fmsvm lsp`: the language server over standard input and output (the Language Server Protocol,
//! with `lsp-server` and `lsp-types`): the compiler's diagnostics as a file changes, hover for
//! variables and G codes, go to definition and references for sequence numbers, loops, called
//! programs and variables, document symbols, folding, quick fixes, and the flat program of a file
//! (`fmsvm.expand`). A workspace's `fmsvm.toml` gives the options `check` would take.

use std::cell::RefCell;
use std::collections::HashMap;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::rc::Rc;

use lsp_server::{Connection, ErrorCode, Message, Notification, Request, Response};
use lsp_types as lsp;
use serde_json::{Value, json};

use fmsvm_compiler::outline::{self, Item};
use fmsvm_compiler::{FileId, Severity, SourceMap};

use fmsvm_driver::request::{Control, GCodeSystem, Input, Machine};

use fmsvm_driver::exit::Exit;
use fmsvm_driver::library::Folders;

/// The command that returns a file's flat program.
pub const EXPAND: &str = "fmsvm.expand";

/// The largest document the server takes (a part program is rarely above a few MB): what one
/// frame may carry.
const MAX_DOCUMENT: usize = crate::frame::MAX_BODY;

/// `fmsvm lsp`: serves one client until it says exit; the exit code is 0 after a shutdown, 1
/// without one (the protocol's rule), 6 when the connection failed.
pub fn main() -> Exit {
    let (connection, client) = Connection::memory();
    let out = std::sync::Arc::new(std::sync::Mutex::new(std::io::stdout()));
    // The writer: what the server says, framed, in order.
    let writer = {
        let out = out.clone();
        std::thread::spawn(move || {
            for msg in client.receiver {
                let mut o = out
                    .lock()
                    .unwrap_or_else(std::sync::PoisonError::into_inner);
                if msg.write(&mut *o).is_err() {
                    break;
                }
            }
        })
    };
    // The reader: frames from the client, each bounded; a broken one is answered and passed by.
    let to_server = client.sender;
    // The runner's way to tell the server a run ended: a message among the client's.
    let inject = to_server.clone();
    std::thread::spawn(move || {
        let mut input = std::io::BufReader::new(std::io::stdin());
        let answer = |code: i32, why: String| {
            let body = json!({"jsonrpc": "2.0", "id": Value::Null,
                "error": {"code": code, "message": why}})
            .to_string();
            let mut o = out
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            let _ = write!(o, "Content-Length: {}\r\n\r\n{body}", body.len());
            let _ = o.flush();
        };
        loop {
            let msg = match crate::frame::read(&mut input) {
                crate::frame::Frame::Body(body) => match crate::frame::json(&body) {
                    Err(e) => {
                        answer(-32700, format!("parse error: {e}"));
                        continue;
                    }
                    Ok(v) => match serde_json::from_value::<Message>(v) {
                        Ok(m) => m,
                        Err(e) => {
                            answer(-32600, format!("invalid request: {e}"));
                            continue;
                        }
                    },
                },
                crate::frame::Frame::Bad(why) => {
                    answer(-32700, format!("parse error: {why}"));
                    continue;
                }
                crate::frame::Frame::End => break,
                crate::frame::Frame::Failed(e) => {
                    eprintln!("fmsvm lsp: reading the client failed: {e}");
                    break;
                }
            };
            if to_server.send(msg).is_err() {
                break;
            }
        }
        // The runner holds a sender too: the server is told that the input ended.
        let ended = Notification::new(INPUT_ENDED.into(), Value::Null);
        let _ = to_server.send(Message::Notification(ended));
    });
    let exit = match serve(&connection, inject) {
        Ok(true) => Exit::Success,
        Ok(false) => {
            eprintln!("fmsvm lsp: the client's input ended without shutdown and exit");
            Exit::Internal
        }
        Err(e) => {
            eprintln!("fmsvm lsp: {e}");
            Exit::Io
        }
    };
    drop(connection);
    let _ = writer.join();
    exit
}

/// The capabilities fmsvm serves.
fn capabilities() -> lsp::ServerCapabilities {
    lsp::ServerCapabilities {
        position_encoding: Some(lsp::PositionEncodingKind::UTF16),
        text_document_sync: Some(lsp::TextDocumentSyncCapability::Options(
            lsp::TextDocumentSyncOptions {
                open_close: Some(true),
                change: Some(lsp::TextDocumentSyncKind::FULL),
                save: Some(lsp::TextDocumentSyncSaveOptions::Supported(true)),
                ..Default::default()
            },
        )),
        hover_provider: Some(lsp::HoverProviderCapability::Simple(true)),
        definition_provider: Some(lsp::OneOf::Left(true)),
        references_provider: Some(lsp::OneOf::Left(true)),
        document_symbol_provider: Some(lsp::OneOf::Left(true)),
        folding_range_provider: Some(lsp::FoldingRangeProviderCapability::Simple(true)),
        code_action_provider: Some(lsp::CodeActionProviderCapability::Simple(true)),
        execute_command_provider: Some(lsp::ExecuteCommandOptions {
            commands: vec![EXPAND.into()],
            ..Default::default()
        }),
        ..Default::default()
    }
}

/// Serves until `exit` (true when a `shutdown` came first) or the end of the input.
fn serve(
    connection: &Connection,
    inject: crossbeam_channel::Sender<Message>,
) -> Result<bool, String> {
    let caps = serde_json::to_value(capabilities()).map_err(|e| e.to_string())?;
    let init = connection.initialize(caps).map_err(|e| e.to_string())?;
    let params: lsp::InitializeParams = serde_json::from_value(init).unwrap_or_default();
    let mut server = Server::new(workspace_root(&params), Runner::start(inject));
    server.workspace.client_args = params.initialization_options.as_ref().and_then(client_args);
    // After `shutdown` only `exit` is awaited; a second shutdown (Neovim sends one as it quits)
    // is answered again.
    let mut shut = false;
    for msg in &connection.receiver {
        match msg {
            Message::Request(req) => {
                let resp = if req.method == "shutdown" {
                    shut = true;
                    Response::new_ok(req.id, Value::Null)
                } else {
                    server.request(req)
                };
                connection
                    .sender
                    .send(Message::Response(resp))
                    .map_err(|e| e.to_string())?;
            }
            Message::Notification(n) if n.method == "exit" || n.method == INPUT_ENDED => {
                return Ok(shut);
            }
            Message::Notification(n) => {
                for out in server.notification(n) {
                    connection
                        .sender
                        .send(Message::Notification(out))
                        .map_err(|e| e.to_string())?;
                }
            }
            Message::Response(_) => {}
        }
    }
    Ok(shut)
}

/// The workspace's folder, if the client named one.
fn workspace_root(p: &lsp::InitializeParams) -> Option<PathBuf> {
    if let Some(f) = p.workspace_folders.as_ref().and_then(|f| f.first()) {
        return path_of(&f.uri);
    }
    #[allow(deprecated)]
    p.root_uri.as_ref().and_then(path_of)
}

/// The file a `file:` URI names.
fn path_of(uri: &lsp::Uri) -> Option<PathBuf> {
    let s = uri.as_str().strip_prefix("file://")?;
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%'
            && let Some(v) = s
                .get(i + 1..i + 3)
                .and_then(|h| u8::from_str_radix(h, 16).ok())
        {
            out.push(v);
            i += 3;
            continue;
        }
        out.push(bytes[i]);
        i += 1;
    }
    String::from_utf8(out).ok().map(PathBuf::from)
}

/// The `file:` URI of a path.
fn uri_of(path: &Path) -> Option<lsp::Uri> {
    let mut s = String::from("file://");
    for b in path.to_string_lossy().bytes() {
        if b.is_ascii_alphanumeric() || b"/-_.~".contains(&b) {
            s.push(b as char);
        } else {
            s.push_str(&format!("%{b:02X}"));
        }
    }
    s.parse().ok()
}

/// Byte offsets of a text and LSP positions (UTF-16 columns), both ways.
struct Lines<'a> {
    text: &'a str,
    starts: Vec<usize>,
}

impl<'a> Lines<'a> {
    fn new(text: &'a str) -> Self {
        let mut starts = vec![0];
        for (i, b) in text.bytes().enumerate() {
            if b == b'\n' {
                starts.push(i + 1);
            }
        }
        Lines { text, starts }
    }

    fn position(&self, offset: usize) -> lsp::Position {
        let offset = offset.min(self.text.len());
        let line = self.starts.partition_point(|&s| s <= offset) - 1;
        let start = self.starts[line];
        let col: usize = self
            .text
            .get(start..offset)
            .map_or(0, |t| t.chars().map(char::len_utf16).sum());
        lsp::Position::new(line as u32, col as u32)
    }

    fn range(&self, start: u32, end: u32) -> lsp::Range {
        lsp::Range::new(self.position(start as usize), self.position(end as usize))
    }

    fn offset(&self, p: lsp::Position) -> usize {
        let Some(&start) = self.starts.get(p.line as usize) else {
            return self.text.len();
        };
        let mut units = 0u32;
        for (i, c) in self.text[start..].char_indices() {
            if units >= p.character || c == '\n' {
                return start + i;
            }
            units += c.len_utf16() as u32;
        }
        self.text.len()
    }
}

/// An open document.
struct Document {
    text: String,
    /// Its outline (made on demand, dropped when the text changes).
    outline: Option<Vec<Item>>,
    /// The values the variables of each line had when the line last began, in the last run on
    /// save (kept until the next save's run).
    last_run: Seen,
}

/// The server's state: the open documents and the workspace's options.
struct Server {
    workspace: Workspace,
    documents: HashMap<String, Document>,
    /// The runs on save, on a thread of their own.
    runner: Runner,
}

/// Where `check`'s options for a file come from.
#[derive(Clone, Default)]
struct Workspace {
    root: Option<PathBuf>,
    /// The client's settings (`initializationOptions.args`, or `fmsvm.args` of
    /// `workspace/didChangeConfiguration`): they replace `fmsvm.toml`'s.
    client_args: Option<Vec<String>>,
}

/// The `args` of a client's settings (`{"args": [...]}` or `{"fmsvm": {"args": [...]}}`).
fn client_args(v: &Value) -> Option<Vec<String>> {
    let a = v.get("args").or_else(|| v.get("fmsvm")?.get("args"))?;
    a.as_array()?
        .iter()
        .map(|x| x.as_str().map(str::to_string))
        .collect()
}

impl Server {
    fn new(root: Option<PathBuf>, runner: Runner) -> Self {
        Server {
            workspace: Workspace {
                root,
                client_args: None,
            },
            documents: HashMap::new(),
            runner,
        }
    }

    fn input_args(&self, path: &Path) -> Result<Input, String> {
        self.workspace.input_args(path)
    }

    /// The document's control parameters (a Fanuc 0i's where its options cannot be read: the
    /// diagnostics say why).
    fn params(&self, uri: &lsp::Uri) -> fmsvm_driver::params::Params {
        path_of(uri)
            .and_then(|p| self.input_args(&p).ok())
            .and_then(|a| workspace_params(&a).ok())
            .unwrap_or_else(|| fmsvm_driver::params::profile(Control::Fanuc0i))
    }
}

/// `check`'s flags, as the workspace's `fmsvm.toml` `args` or the editor's settings give them.
#[derive(clap::Parser)]
#[command(name = "fmsvm", bin_name = "fmsvm check")]
struct CheckFlags {
    #[command(flatten)]
    input: fmsvm_flags::InputArgs,
    /// Warnings count as errors (`check`'s; the editor shows them as warnings).
    #[arg(long = "deny-warnings")]
    _deny_warnings: bool,
}

/// `stats`'s flags, as the workspace's `fmsvm.toml` `args` and `run_args` give them.
#[derive(clap::Parser)]
#[command(name = "fmsvm", bin_name = "fmsvm stats")]
struct StatsFlags {
    #[command(flatten)]
    run: fmsvm_flags::RunArgs,
    /// `check`'s, in `args` (the editor shows warnings as warnings).
    #[arg(long = "deny-warnings")]
    _deny_warnings: bool,
}

impl Workspace {
    /// The run on save of file `path` when the workspace's `fmsvm.toml` gives `run_args` (flags of
    /// `stats` beyond `check`'s, such as `--stock` and `--offsets`; the files it reads relative to
    /// the root, none written): a `stats` run of them after the workspace's `check` options,
    /// whose warnings (the stock's findings, the kernel's) the editor shows at their lines. None:
    /// no `run_args`, and the run on save is `run`'s.
    fn stock_run(
        &self,
        path: &Path,
        input: &Input,
    ) -> Option<Result<fmsvm_driver::request::Request, String>> {
        use clap::Parser as _;
        let root = self.root.as_ref()?;
        let more = match self.listed("run_args")? {
            Ok(more) => more,
            Err(e) => return Some(Err(e)),
        };
        let mut argv: Vec<String> = vec!["fmsvm stats".into()];
        // The check's options from where `input_args` takes them: the editor's, else the file's.
        match self
            .client_args
            .clone()
            .map(Ok)
            .or_else(|| self.listed("args"))
        {
            Some(Ok(args)) => argv.extend(args),
            Some(Err(e)) => return Some(Err(e)),
            None => {}
        }
        argv.extend(more);
        let from = "fmsvm.toml: run_args";
        argv.push(path.to_string_lossy().into_owned());
        let flags = match StatsFlags::try_parse_from(&argv) {
            Ok(f) => f,
            Err(e) => {
                return Some(Err(format!(
                    "{from}: {}",
                    e.to_string().lines().next().unwrap_or("")
                )));
            }
        };
        let mut run = flags.run.request();
        // The input as `check` takes it here (its paths made the root's), the files the run reads
        // the root's too, and nothing written but the report in a temporary folder.
        run.input = input.clone();
        for p in [
            &mut run.offsets,
            &mut run.vars,
            &mut run.probe_points,
            &mut run.dialect_file,
        ] {
            if let Some(p) = p.as_mut().filter(|p| p.is_relative()) {
                *p = root.join(&*p);
            }
        }
        run.print = None;
        run.dump_vars = None;
        run.verify_file = None;
        Some(Ok(run))
    }

    /// The list of strings `key` of the workspace's `fmsvm.toml`, when it has the file and the key.
    fn listed(&self, key: &str) -> Option<Result<Vec<String>, String>> {
        let file = self.root.as_ref()?.join("fmsvm.toml");
        let text = std::fs::read_to_string(&file).ok()?;
        let doc: toml::Table = match text.parse() {
            Ok(d) => d,
            Err(e) => return Some(Err(format!("{}: {e}", file.display()))),
        };
        let list = doc.get(key)?;
        let bad = || format!("{}: {key}: every item is a string", file.display());
        Some(list.as_array().ok_or_else(bad).and_then(|l| {
            l.iter()
                .map(|a| a.as_str().map(String::from).ok_or_else(bad))
                .collect()
        }))
    }

    /// The options `check` takes in this workspace for file `path`: the `args` of `fmsvm.toml` at the
    /// workspace's root (paths in them relative to it), else the defaults.
    fn input_args(&self, path: &Path) -> Result<Input, String> {
        use clap::Parser as _;
        let mut argv: Vec<String> = vec!["fmsvm check".into()];
        if let Some(args) = &self.client_args {
            argv.extend(args.iter().cloned());
        } else if let Some(args) = self.listed("args") {
            argv.extend(args?);
        }
        argv.push(path.to_string_lossy().into_owned());
        // Where the options came from, for a message about them.
        let from = if self.client_args.is_some() {
            "the editor's settings (fmsvm.args)"
        } else {
            "fmsvm.toml: args"
        };
        let c = CheckFlags::try_parse_from(&argv)
            .map_err(|e| format!("{from}: {}", e.to_string().lines().next().unwrap_or("")))?;
        let mut a = c.input.input();
        if let Some(root) = &self.root {
            for l in &mut a.libs {
                if l.is_relative() {
                    *l = root.join(&*l);
                }
            }
            if let Some(p) = a.params.as_mut().filter(|p| p.is_relative()) {
                *p = root.join(&*p);
            }
        }
        Ok(a)
    }
}

impl Server {
    fn notification(&mut self, n: Notification) -> Vec<Notification> {
        use lsp::notification::{
            DidChangeTextDocument, DidCloseTextDocument, DidOpenTextDocument, DidSaveTextDocument,
            Notification as _,
        };
        let uri = match n.method.as_str() {
            DidOpenTextDocument::METHOD => {
                let Ok(p) = serde_json::from_value::<lsp::DidOpenTextDocumentParams>(n.params)
                else {
                    return Vec::new();
                };
                self.open(&p.text_document.uri, p.text_document.text);
                p.text_document.uri
            }
            DidChangeTextDocument::METHOD => {
                let Ok(p) = serde_json::from_value::<lsp::DidChangeTextDocumentParams>(n.params)
                else {
                    return Vec::new();
                };
                // Full sync: the last change is the whole text.
                let Some(c) = p.content_changes.into_iter().last() else {
                    return Vec::new();
                };
                self.open(&p.text_document.uri, c.text);
                p.text_document.uri
            }
            DidSaveTextDocument::METHOD => {
                let Ok(p) = serde_json::from_value::<lsp::DidSaveTextDocumentParams>(n.params)
                else {
                    return Vec::new();
                };
                // On save the program runs too, on the runner's thread (the server answers other
                // requests meanwhile): its alarm, at the block that raised it, when it ends.
                // The diagnostics go out once, with the run's alarm, when it ends.
                return match self.run_job(&p.text_document.uri) {
                    Some(job) => {
                        self.runner.run(job);
                        Vec::new()
                    }
                    None => self.diagnostics(&p.text_document.uri),
                };
            }
            RAN => {
                let done = self.runner.take();
                return done.into_iter().flat_map(|d| self.ran(d)).collect();
            }
            "workspace/didChangeConfiguration" => {
                if let Some(args) = n.params.get("settings").and_then(client_args) {
                    self.workspace.client_args = Some(args);
                    for d in self.documents.values_mut() {
                        d.outline = None;
                    }
                }
                let uris: Vec<String> = self.documents.keys().cloned().collect();
                return uris
                    .iter()
                    .filter_map(|u| u.parse::<lsp::Uri>().ok())
                    .flat_map(|u| self.diagnostics(&u))
                    .collect();
            }
            DidCloseTextDocument::METHOD => {
                let Ok(p) = serde_json::from_value::<lsp::DidCloseTextDocumentParams>(n.params)
                else {
                    return Vec::new();
                };
                self.documents.remove(p.text_document.uri.as_str());
                // The closed file's diagnostics are cleared.
                return vec![publish(p.text_document.uri, Vec::new())];
            }
            _ => return Vec::new(),
        };
        self.diagnostics(&uri)
    }

    fn open(&mut self, uri: &lsp::Uri, mut text: String) {
        if text.len() > MAX_DOCUMENT {
            let mut cut = MAX_DOCUMENT;
            while !text.is_char_boundary(cut) {
                cut -= 1;
            }
            text.truncate(cut);
        }
        let last_run = self
            .documents
            .remove(uri.as_str())
            .map(|d| d.last_run)
            .unwrap_or_default();
        self.documents.insert(
            uri.as_str().to_string(),
            Document {
                text,
                outline: None,
                last_run,
            },
        );
    }

    /// The compiler's diagnostics of document `uri`, as notifications (one per file they are in).
    fn diagnostics(&self, uri: &lsp::Uri) -> Vec<Notification> {
        let Some(doc) = self.documents.get(uri.as_str()) else {
            return Vec::new();
        };
        let path = path_of(uri).unwrap_or_else(|| PathBuf::from(uri.as_str()));
        let lines = Lines::new(&doc.text);
        let a = match self.input_args(&path) {
            Ok(a) => a,
            Err(e) => {
                let d = lsp::Diagnostic {
                    range: lsp::Range::default(),
                    severity: Some(lsp::DiagnosticSeverity::ERROR),
                    source: Some("fmsvm".into()),
                    message: e,
                    ..Default::default()
                };
                return vec![publish(uri.clone(), vec![d])];
            }
        };
        let (found, sources, main) = compile_text(&a, &path, &doc.text);
        let mut by_file: HashMap<FileId, Vec<lsp::Diagnostic>> = HashMap::new();
        by_file.insert(main, Vec::new());
        for d in found {
            let file = d.span.file;
            let other;
            let l = if file == main {
                &lines
            } else {
                other = Lines::new(&sources.file(file).text);
                &other
            };
            let range = l.range(d.span.start, d.span.end);
            let related: Vec<lsp::DiagnosticRelatedInformation> = d
                .notes
                .iter()
                .map(|n| lsp::DiagnosticRelatedInformation {
                    location: lsp::Location::new(uri.clone(), range),
                    message: n.clone(),
                })
                .collect();
            by_file.entry(file).or_default().push(lsp::Diagnostic {
                range,
                severity: Some(match d.severity {
                    Severity::Error => lsp::DiagnosticSeverity::ERROR,
                    Severity::Warning => lsp::DiagnosticSeverity::WARNING,
                }),
                code: d
                    .alarm
                    .map(|n| lsp::NumberOrString::String(format!("{n:04}"))),
                source: Some("fmsvm".into()),
                message: d.message.clone(),
                related_information: (!related.is_empty()).then_some(related),
                data: d.fix.as_ref().map(|f| json!({ "fix": f })),
                ..Default::default()
            });
        }
        by_file
            .into_iter()
            .filter_map(|(file, ds)| {
                let u = if file == main {
                    uri.clone()
                } else {
                    uri_of(Path::new(&sources.file(file).name))?
                };
                Some(publish(u, ds))
            })
            .collect()
    }

    /// The run of document `uri` on save, as a job for the runner thread (`Runner`): what it
    /// needs to run the text and note, as each line begins, the values of the variables it names.
    fn run_job(&mut self, uri: &lsp::Uri) -> Option<RunJob> {
        let path = path_of(uri).unwrap_or_else(|| PathBuf::from("program.nc"));
        let args = self.input_args(&path).ok()?;
        let stock = self.workspace.stock_run(&path, &args).and_then(Result::ok);
        let (text, items) = self.outlined(uri)?;
        let lines = Lines::new(text);
        let mut watch: HashMap<u32, Vec<u32>> = HashMap::new();
        for i in items {
            if let Item::Var { number, span, .. } = i {
                let l = lines.position(span.start as usize).line;
                let v = watch.entry(l).or_default();
                if !v.contains(number) {
                    v.push(*number);
                }
            }
        }
        Some(RunJob {
            uri: uri.clone(),
            args,
            stock,
            path,
            text: text.to_string(),
            starts: lines.starts.clone(),
            watch,
        })
    }

    /// A run on save has ended (`runner::RAN`): its values for hover, and the alarm it stopped
    /// with added to the diagnostics of the file that holds its block (the document itself, or a
    /// library program). A run of a text the document no longer has is dropped.
    fn ran(&mut self, done: RunDone) -> Vec<Notification> {
        let uri = done.uri;
        let Some(doc) = self.documents.get_mut(uri.as_str()) else {
            return Vec::new();
        };
        if doc.text != done.text {
            return Vec::new();
        }
        doc.last_run = done.values;
        let mut out = self.diagnostics(&uri);
        let Some(doc) = self.documents.get(uri.as_str()) else {
            return out;
        };
        for w in done.warnings.iter().filter(|w| w.line > 0) {
            let Some((target, text)) = block_text(&uri, &doc.text, &done.name, &w.file) else {
                continue;
            };
            let lines = Lines::new(&text);
            let line = w.line as usize - 1;
            let Some(&start) = lines.starts.get(line) else {
                continue;
            };
            let end = lines
                .starts
                .get(line + 1)
                .map_or(text.len(), |&e| e.saturating_sub(1));
            let start = (start + (w.column as usize).saturating_sub(1)).min(end);
            let d = lsp::Diagnostic {
                range: lines.range(start as u32, end as u32),
                severity: Some(lsp::DiagnosticSeverity::WARNING),
                source: Some("fmsvm run".into()),
                message: w.text.clone(),
                ..Default::default()
            };
            add_diagnostic(&mut out, target, d);
        }
        let Ok(Ran {
            stop: Some((stop, name)),
            ..
        }) = done.ran
        else {
            return out;
        };
        let Some((target, text)) = block_text(&uri, &doc.text, &name, &stop.file) else {
            return out;
        };
        let lines = Lines::new(&text);
        let d = lsp::Diagnostic {
            range: lines.range(stop.start, stop.end),
            severity: Some(lsp::DiagnosticSeverity::ERROR),
            code: stop
                .alarm
                .map(|n| lsp::NumberOrString::String(format!("{n:04}"))),
            source: Some("fmsvm run".into()),
            message: format!("{} (raised while running this block)", stop.message),
            related_information: (!stop.notes.is_empty()).then(|| {
                stop.notes
                    .iter()
                    .map(|n| lsp::DiagnosticRelatedInformation {
                        location: lsp::Location::new(
                            target.clone(),
                            lines.range(stop.start, stop.end),
                        ),
                        message: n.clone(),
                    })
                    .collect()
            }),
            ..Default::default()
        };
        add_diagnostic(&mut out, target, d);
        out
    }

    fn request(&mut self, req: Request) -> Response {
        use lsp::request::{
            CodeActionRequest, DocumentSymbolRequest, ExecuteCommand, FoldingRangeRequest,
            GotoDefinition, HoverRequest, References, Request as _,
        };
        let id = req.id.clone();
        let result = match req.method.as_str() {
            HoverRequest::METHOD => parse(req).map(|p| json!(self.hover(p))),
            GotoDefinition::METHOD => parse(req).map(|p| json!(self.definition(p))),
            References::METHOD => parse(req).map(|p| json!(self.references(p))),
            DocumentSymbolRequest::METHOD => parse(req).map(|p| json!(self.symbols(p))),
            FoldingRangeRequest::METHOD => parse(req).map(|p| json!(self.folding(p))),
            CodeActionRequest::METHOD => parse(req).map(|p| json!(self.actions(p))),
            ExecuteCommand::METHOD => parse(req).and_then(|p| self.execute(p)),
            _ => Err((
                ErrorCode::MethodNotFound,
                format!("no method {}", req.method),
            )),
        };
        match result {
            Ok(v) => Response::new_ok(id, v),
            Err((code, message)) => Response::new_err(id, code as i32, message),
        }
    }

    /// Document `uri`'s text and outline.
    fn outlined(&mut self, uri: &lsp::Uri) -> Option<(&str, &[Item])> {
        let doc = self.documents.get_mut(uri.as_str())?;
        if doc.outline.is_none() {
            let options = path_of(uri)
                .and_then(|p| self.workspace.input_args(&p).ok())
                .map(|a| outline_options(&a))
                .unwrap_or_default();
            doc.outline = Some(outline::outline(FileId(0), &doc.text, &options));
        }
        Some((&doc.text, doc.outline.as_deref().unwrap_or(&[])))
    }

    fn hover(&mut self, p: lsp::HoverParams) -> Option<lsp::Hover> {
        let at = p.text_document_position_params;
        let last = self
            .documents
            .get(at.text_document.uri.as_str())
            .map(|d| d.last_run.clone())
            .unwrap_or_default();
        let params = self.params(&at.text_document.uri);
        let system = code_system(&params);
        let (text, items) = self.outlined(&at.text_document.uri)?;
        let lines = Lines::new(text);
        let offset = lines.offset(at.position) as u32;
        let item = item_at(items, offset)?;
        let line = lines.position(item.span().start as usize).line;
        let value = match item {
            Item::Var { number, .. } => {
                let mut v = describe_variable(*number, &params);
                if let Some(seen) = last
                    .get(&line)
                    .and_then(|l| l.iter().find(|(n, _)| n == number))
                {
                    let shown = if seen.1.is_nan() {
                        "vacant".to_string()
                    } else {
                        format!("{}", seen.1)
                    };
                    v.push_str(&format!(
                        "\nIn the last run (on save): #{number} = {shown} when this line last began"
                    ));
                }
                v
            }
            Item::Code { letter, value, .. } => describe_code(*letter, *value, system)?,
            Item::Call { program, .. } => format!("calls O{program}"),
            Item::Function { func, .. } => func.describe().to_string(),
            Item::Goto { number, .. } => format!("jumps to N{number}"),
            Item::Label { number, .. } => format!("sequence number N{number}"),
            Item::Loop { number, .. } => format!("loop {number} (DO{number} … END{number})"),
            Item::Program { number, .. } => number
                .map_or("the lines before the first O word".into(), |n| {
                    format!("program O{n}")
                }),
        };
        let span = item.span();
        Some(lsp::Hover {
            contents: lsp::HoverContents::Markup(lsp::MarkupContent {
                kind: lsp::MarkupKind::PlainText,
                value,
            }),
            range: Some(lines.range(span.start, span.end)),
        })
    }

    fn definition(&mut self, p: lsp::GotoDefinitionParams) -> Option<lsp::GotoDefinitionResponse> {
        let at = p.text_document_position_params;
        let uri = at.text_document.uri.clone();
        let workspace = self.workspace.clone();
        let (text, items) = self.outlined(&uri)?;
        let lines = Lines::new(text);
        let offset = lines.offset(at.position) as u32;
        let item = item_at(items, offset)?;
        let program = program_at(items, offset);
        let here = |s: fmsvm_compiler::Span| {
            lsp::GotoDefinitionResponse::Scalar(lsp::Location::new(
                uri.clone(),
                lines.range(s.start, s.end),
            ))
        };
        match item {
            Item::Goto { number, .. } => {
                let target = label_in(items, program, *number)?;
                Some(here(target))
            }
            Item::Loop { head, end, .. } => {
                // From DO to END and back.
                let to = match end {
                    Some(e) if offset < head.end => *e,
                    _ => *head,
                };
                Some(here(to))
            }
            Item::Call {
                program: callee, ..
            } => {
                if let Some(s) = items.iter().find_map(|i| match i {
                    Item::Program {
                        number: Some(n),
                        span,
                        ..
                    } if n == callee => Some(*span),
                    _ => None,
                }) {
                    return Some(here(s));
                }
                // In a library folder.
                let path = path_of(&uri)?;
                let a = workspace.input_args(&path).ok()?;
                let file = Folders::files(&a.libs)
                    .into_iter()
                    .find(|f| holds_program(f, *callee))?;
                Some(lsp::GotoDefinitionResponse::Scalar(lsp::Location::new(
                    uri_of(&file)?,
                    lsp::Range::default(),
                )))
            }
            _ => None,
        }
    }

    fn references(&mut self, p: lsp::ReferenceParams) -> Option<Vec<lsp::Location>> {
        let at = p.text_document_position;
        let uri = at.text_document.uri.clone();
        let (text, items) = self.outlined(&uri)?;
        let lines = Lines::new(text);
        let offset = lines.offset(at.position) as u32;
        let item = item_at(items, offset)?;
        let programs = Programs::of(items);
        let program = programs.at(offset);
        let same: Vec<fmsvm_compiler::Span> = match item {
            Item::Var { number, .. } => items
                .iter()
                .filter_map(|i| match i {
                    // Locals are each program's own; the others are shared.
                    Item::Var {
                        number: n, span, ..
                    } if n == number && (*n > 33 || programs.at(span.start) == program) => {
                        Some(*span)
                    }
                    _ => None,
                })
                .collect(),
            Item::Label { number, .. } | Item::Goto { number, .. } => items
                .iter()
                .filter_map(|i| match i {
                    Item::Label { number: n, span } | Item::Goto { number: n, span }
                        if n == number && programs.at(span.start) == program =>
                    {
                        Some(*span)
                    }
                    _ => None,
                })
                .collect(),
            Item::Call {
                program: callee, ..
            } => items
                .iter()
                .filter_map(|i| match i {
                    Item::Call { program: c, span } if c == callee => Some(*span),
                    Item::Program {
                        number: Some(n),
                        span,
                        ..
                    } if n == callee => Some(*span),
                    _ => None,
                })
                .collect(),
            _ => return None,
        };
        Some(
            same.into_iter()
                .map(|s| lsp::Location::new(uri.clone(), lines.range(s.start, s.end)))
                .collect(),
        )
    }

    #[allow(deprecated)]
    fn symbols(&mut self, p: lsp::DocumentSymbolParams) -> Option<lsp::DocumentSymbolResponse> {
        let (text, items) = self.outlined(&p.text_document.uri)?;
        let lines = Lines::new(text);
        let symbol = |name: String, kind, whole: lsp::Range, at: lsp::Range| lsp::DocumentSymbol {
            name,
            detail: None,
            kind,
            tags: None,
            deprecated: None,
            range: whole,
            selection_range: at,
            children: Some(Vec::new()),
        };
        let mut programs: Vec<lsp::DocumentSymbol> = Vec::new();
        for i in items {
            let s = i.span();
            let at = lines.range(s.start, s.end);
            match i {
                Item::Program { number, whole, .. } => programs.push(symbol(
                    number.map_or("(before O)".into(), |n| format!("O{n}")),
                    lsp::SymbolKind::FUNCTION,
                    lines.range(whole.start, whole.end),
                    at,
                )),
                Item::Label { number, .. } => {
                    if let Some(p) = programs.last_mut() {
                        p.children.get_or_insert_with(Vec::new).push(symbol(
                            format!("N{number}"),
                            lsp::SymbolKind::KEY,
                            at,
                            at,
                        ));
                    }
                }
                Item::Loop { number, head, end } => {
                    let whole = lines.range(head.start, end.map_or(head.end, |e| e.end));
                    if let Some(p) = programs.last_mut() {
                        p.children.get_or_insert_with(Vec::new).push(symbol(
                            format!("DO{number}"),
                            lsp::SymbolKind::NAMESPACE,
                            whole,
                            at,
                        ));
                    }
                }
                _ => {}
            }
        }
        Some(lsp::DocumentSymbolResponse::Nested(programs))
    }

    fn folding(&mut self, p: lsp::FoldingRangeParams) -> Option<Vec<lsp::FoldingRange>> {
        let (text, items) = self.outlined(&p.text_document.uri)?;
        let lines = Lines::new(text);
        let fold = |start: u32, end: u32| {
            let (a, b) = (lines.position(start as usize), lines.position(end as usize));
            (b.line > a.line).then(|| lsp::FoldingRange {
                start_line: a.line,
                end_line: b.line,
                kind: Some(lsp::FoldingRangeKind::Region),
                ..Default::default()
            })
        };
        Some(
            items
                .iter()
                .filter_map(|i| match i {
                    Item::Loop {
                        head, end: Some(e), ..
                    } => fold(head.start, e.end),
                    Item::Program { whole, .. } => fold(whole.start, whole.end),
                    _ => None,
                })
                .collect(),
        )
    }

    /// The quick fixes of the diagnostics the client sends back (their `data.fix`).
    fn actions(&mut self, p: lsp::CodeActionParams) -> Vec<lsp::CodeActionOrCommand> {
        p.context
            .diagnostics
            .into_iter()
            .filter_map(|d| {
                let fix = d.data.as_ref()?.get("fix")?.as_str()?.to_string();
                let edit = lsp::TextEdit::new(d.range, fix.clone());
                // lsp-types keys the edit by URI (its parsed form caches, hence clippy's lint).
                #[allow(clippy::mutable_key_type)]
                let mut changes = HashMap::new();
                changes.insert(p.text_document.uri.clone(), vec![edit]);
                Some(lsp::CodeActionOrCommand::CodeAction(lsp::CodeAction {
                    title: format!("Write `{fix}`"),
                    kind: Some(lsp::CodeActionKind::QUICKFIX),
                    diagnostics: Some(vec![d]),
                    edit: Some(lsp::WorkspaceEdit::new(changes)),
                    is_preferred: Some(true),
                    ..Default::default()
                }))
            })
            .collect()
    }

    /// `fmsvm.expand` with the document's URI: its flat program and its statistics, from a run
    /// with the workspace's options (into a temporary folder).
    fn execute(&mut self, p: lsp::ExecuteCommandParams) -> Result<Value, (ErrorCode, String)> {
        if p.command != EXPAND {
            return Err((
                ErrorCode::InvalidParams,
                format!("no command {}", p.command),
            ));
        }
        let uri: lsp::Uri = p
            .arguments
            .first()
            .and_then(|v| serde_json::from_value(v.clone()).ok())
            .ok_or((ErrorCode::InvalidParams, "give the document's URI".into()))?;
        let doc = self
            .documents
            .get(uri.as_str())
            .ok_or((ErrorCode::InvalidParams, "the document is not open".into()))?;
        let path = path_of(&uri).unwrap_or_else(|| PathBuf::from("program.nc"));
        let a = self
            .input_args(&path)
            .map_err(|e| (ErrorCode::InvalidParams, e))?;
        expand(&a, &path, &doc.text).map_err(|e| (ErrorCode::RequestFailed, e))
    }
}

fn parse<T: serde::de::DeserializeOwned>(req: Request) -> Result<T, (ErrorCode, String)> {
    serde_json::from_value(req.params).map_err(|e| (ErrorCode::InvalidParams, e.to_string()))
}

/// The document or file a run's block lies in, and its text: the document `uri` (its text
/// `doc`) when `file` is the name the run gave it (`name`), else the file as it is on disk.
fn block_text(uri: &lsp::Uri, doc: &str, name: &str, file: &str) -> Option<(lsp::Uri, String)> {
    if file == name {
        return Some((uri.clone(), doc.to_string()));
    }
    let u = uri_of(Path::new(file))?;
    Some((u, std::fs::read_to_string(file).unwrap_or_default()))
}

/// `d` added to the diagnostics `out` publishes for `target`, or published for it.
fn add_diagnostic(out: &mut Vec<Notification>, target: lsp::Uri, d: lsp::Diagnostic) {
    let target_str = target.as_str().to_string();
    for n in out.iter_mut() {
        if n.params["uri"] == target_str
            && let Some(list) = n.params["diagnostics"].as_array_mut()
            && let Ok(v) = serde_json::to_value(&d)
        {
            list.push(v);
            return;
        }
    }
    out.push(publish(target, vec![d]));
}

fn publish(uri: lsp::Uri, diagnostics: Vec<lsp::Diagnostic>) -> Notification {
    use lsp::notification::{Notification as _, PublishDiagnostics};
    Notification::new(
        PublishDiagnostics::METHOD.into(),
        lsp::PublishDiagnosticsParams::new(uri, diagnostics, None),
    )
}

/// The outline's options: the input syntax and the bound codes of `a`.
fn outline_options(a: &Input) -> fmsvm_compiler::Options {
    match workspace_params(a) {
        Ok(params) => fmsvm_driver::run::compile_options(a, &params),
        Err(_) => fmsvm_compiler::Options::default(),
    }
}

/// The control's parameters as `check` reads them with `a`, the reason said when they cannot be.
fn workspace_params(a: &Input) -> Result<fmsvm_driver::params::Params, String> {
    fmsvm_driver::run::load_params(a.control, a.params.as_deref(), a.max_input)
        .map_err(|f| f.message)
}

/// How the program's control numbers its G codes: a lathe's system (A unless the parameters say
/// B), or the mill's.
fn code_system(p: &fmsvm_driver::params::Params) -> fmsvm_canon::modal::CodeSystem {
    use fmsvm_canon::modal::CodeSystem;
    match (p.machine, p.gcode_system) {
        (Some(Machine::Lathe), Some(GCodeSystem::B)) => CodeSystem::LatheB,
        (Some(Machine::Lathe), _) => CodeSystem::LatheA,
        _ => CodeSystem::Mill,
    }
}

/// Compiles `text` (file `path`) as `check` would with `a`: the diagnostics, the sources they
/// point into, and the main file's id.
pub(crate) fn compile_text(
    a: &Input,
    path: &Path,
    text: &str,
) -> (Vec<fmsvm_compiler::Diagnostic>, SourceMap, FileId) {
    let mut sources = SourceMap::new();
    let main = sources.add(path.to_string_lossy().into_owned(), text.to_string());
    let params = match workspace_params(a) {
        Ok(p) => p,
        Err(why) => {
            let d = fmsvm_compiler::Diagnostic::error(
                fmsvm_compiler::Span::new(main, 0, 0),
                None,
                format!("the control's parameters (--params) cannot be read: {why}"),
            );
            return (vec![d], sources, main);
        }
    };
    let options = fmsvm_driver::run::compile_options(a, &params);
    let mut library = Folders::new(a.libs.clone(), None, a.max_input);
    let (_, diags) = fmsvm_compiler::compile(&mut sources, main, &options, &mut library);
    (diags, sources, main)
}

/// By 0-based line: the variables the line names and their values as the run reached it.
type Seen = HashMap<u32, Vec<(u32, f64)>>;

/// Notes, as a run reaches each line of the document (file 0), the values of the variables the
/// line names: for hover's "in the last run".
struct LastRun {
    starts: Vec<usize>,
    watch: HashMap<u32, Vec<u32>>,
    /// The line last seen, and the values by line.
    values: RefCell<(u32, Seen)>,
}

impl fmsvm_vm::debug::Debugger for LastRun {
    fn before(&self, at: &mut fmsvm_vm::debug::Stop<'_>) -> bool {
        if at.span.file != FileId(0) {
            return true;
        }
        let line = (self
            .starts
            .partition_point(|&s| s <= at.span.start as usize)
            - 1) as u32;
        let mut v = self.values.borrow_mut();
        if v.0 == line {
            return true;
        }
        v.0 = line;
        let Some(names) = self.watch.get(&line) else {
            return true;
        };
        let seen: Vec<(u32, f64)> = names
            .iter()
            .map(|&n| {
                let value = match n {
                    0 => f64::NAN,
                    1..=33 => at.locals.get(n as usize).copied().unwrap_or(f64::NAN),
                    _ => match fmsvm_compiler::ir::common_index(n) {
                        Some(i) => at.commons.get(usize::from(i)).copied().unwrap_or(f64::NAN),
                        None => (at.system)(n).unwrap_or(f64::NAN),
                    },
                };
                (n, value)
            })
            .collect();
        v.1.insert(line, seen);
        true
    }
}

/// What a run of a document gave: its flat program, or where it stopped.
/// The notification the runner puts among the client's when a run on save has ended.
const RAN: &str = "fmsvm/ran";
/// The notification the reader puts last, when the client's input has ended.
const INPUT_ENDED: &str = "fmsvm/input-ended";

/// A run on save to make.
struct RunJob {
    uri: lsp::Uri,
    args: Input,
    /// The workspace's `stats` run with the stock, when it gives one.
    stock: Option<fmsvm_driver::request::Request>,
    path: PathBuf,
    text: String,
    starts: Vec<usize>,
    watch: HashMap<u32, Vec<u32>>,
}

/// A run on save made.
struct RunDone {
    uri: lsp::Uri,
    /// The text it ran (a document changed since is not given its results).
    text: String,
    values: Seen,
    ran: Result<Ran, String>,
    /// What the run said at its blocks (the stock's findings, the kernel's warnings).
    warnings: Vec<fmsvm_driver::run::RunWarning>,
    /// The name the run gave the document (its sources' name of the main file).
    name: String,
}

/// The runs on save, one at a time on a thread of their own, so that the server answers other
/// requests while one runs (up to `run_request`'s 10 s); each result waits here for the server,
/// which a [`RAN`] notification wakes.
struct Runner {
    jobs: std::sync::mpsc::Sender<RunJob>,
    done: std::sync::Arc<std::sync::Mutex<Vec<RunDone>>>,
}

impl Runner {
    fn start(inject: crossbeam_channel::Sender<Message>) -> Runner {
        let (jobs, queue) = std::sync::mpsc::channel::<RunJob>();
        let done = std::sync::Arc::new(std::sync::Mutex::new(Vec::new()));
        let results = std::sync::Arc::clone(&done);
        std::thread::spawn(move || {
            for job in queue {
                let recorder = Rc::new(LastRun {
                    starts: job.starts,
                    watch: job.watch,
                    values: RefCell::new((u32::MAX, HashMap::new())),
                });
                let heard = Rc::new(RefCell::new(Vec::new()));
                let hooks = fmsvm_driver::run::Hooks {
                    debugger: Some(recorder.clone()),
                    warnings: Some(heard.clone()),
                    ..Default::default()
                };
                let ran = match &job.stock {
                    Some(stock) => run_stock(stock, &job.path, &job.text, hooks),
                    None => run_text(&job.args, &job.path, &job.text, false, hooks),
                };
                let values = std::mem::take(&mut recorder.values.borrow_mut().1);
                let warnings = std::mem::take(&mut *heard.borrow_mut());
                if let Ok(mut d) = results.lock() {
                    d.push(RunDone {
                        uri: job.uri,
                        text: job.text,
                        values,
                        ran,
                        warnings,
                        name: job.path.display().to_string(),
                    });
                }
                let note = Notification::new(RAN.into(), Value::Null);
                if inject.send(Message::Notification(note)).is_err() {
                    break;
                }
            }
        });
        Runner { jobs, done }
    }

    fn run(&self, job: RunJob) {
        let _ = self.jobs.send(job);
    }

    /// The runs that have ended since the last look.
    fn take(&self) -> Vec<RunDone> {
        self.done
            .lock()
            .map(|mut d| std::mem::take(&mut *d))
            .unwrap_or_default()
    }
}

struct Ran {
    flat: Result<String, String>,
    /// The stop at a block, and the name the run's sources gave the document.
    stop: Option<(fmsvm_driver::run::RunStop, String)>,
    /// `stats --json`'s report, where asked.
    stats: Option<Value>,
}

/// The run of the document `path` as the editor holds it (`text`) into `output` with every input
/// option of `a` (the workspace's, the same the diagnostics are compiled with), quietly, for at most
/// 10 s.
fn run_request(
    a: &Input,
    path: &Path,
    text: &std::sync::Arc<str>,
    output: &Path,
) -> fmsvm_driver::request::Request {
    on_save(
        fmsvm_driver::request::Request::new(a.clone()),
        path,
        text,
        output,
    )
}

/// `run` made the run of the document `path` as the editor holds it (`text`) into `output`,
/// quietly, for at most 10 s.
fn on_save(
    mut run: fmsvm_driver::request::Request,
    path: &Path,
    text: &std::sync::Arc<str>,
    output: &Path,
) -> fmsvm_driver::request::Request {
    run.input.file = path.to_path_buf();
    run.input.text = Some(text.clone());
    run.input.quiet = true;
    run.max_seconds = Some(10.0);
    run.output = Some(output.to_path_buf());
    run
}

/// Runs `text` (the buffer of file `path`, not the file) as `fmsvm run` with the options of `a`, its
/// outputs in a temporary folder; with `stats`, `fmsvm stats --json` too.
fn run_text(
    a: &Input,
    path: &Path,
    text: &str,
    stats: bool,
    hooks: fmsvm_driver::run::Hooks,
) -> Result<Ran, String> {
    let dir = tempfile::tempdir().map_err(|e| e.to_string())?;
    let text: std::sync::Arc<str> = text.into();
    let output = dir.path().join("flat.out");
    let run = run_request(a, path, &text, &output);
    let outcome = fmsvm_driver::run::expand(&run, fmsvm_driver::run::Consumer::Flat, hooks);
    let exit = outcome.exit;
    let stop = outcome.stop.map(|s| (s, path.display().to_string()));
    let flat = match exit {
        Exit::Success => std::fs::read_to_string(&output).map_err(|e| e.to_string()),
        e => Err(match &stop {
            Some((s, _)) => s.message.clone(),
            None => format!("the run stopped (exit {})", e as u8),
        }),
    };
    let mut report = None;
    if stats && flat.is_ok() {
        let json = dir.path().join("stats.json");
        let run = run_request(a, path, &text, &json);
        if fmsvm_driver::run::run(&run, fmsvm_driver::run::Consumer::Stats { json: true })
            == Exit::Success
        {
            report = std::fs::read_to_string(&json)
                .ok()
                .and_then(|t| serde_json::from_str(&t).ok());
        }
    }
    Ok(Ran {
        flat,
        stop,
        stats: report,
    })
}

/// Runs `text` (the buffer of file `path`) as the workspace's `stats` run with the stock (`run`'s
/// flags and `run_args`), quietly, for at most 10 s, its report in a temporary folder.
fn run_stock(
    stock: &fmsvm_driver::request::Request,
    path: &Path,
    text: &str,
    hooks: fmsvm_driver::run::Hooks,
) -> Result<Ran, String> {
    let dir = tempfile::tempdir().map_err(|e| e.to_string())?;
    let json = dir.path().join("stats.json");
    let run = on_save(stock.clone(), path, &text.into(), &json);
    let outcome = fmsvm_driver::run::expand(
        &run,
        fmsvm_driver::run::Consumer::Stats { json: true },
        hooks,
    );
    let stop = outcome.stop.map(|s| (s, path.display().to_string()));
    let stats = (outcome.exit == Exit::Success)
        .then(|| std::fs::read_to_string(&json).ok())
        .flatten()
        .and_then(|t| serde_json::from_str(&t).ok());
    Ok(Ran {
        flat: Err("the run on save with the stock writes no flat program".into()),
        stop,
        stats,
    })
}

/// The flat program of `text`, its size and its statistics (`fmsvm stats --json`).
fn expand(a: &Input, path: &Path, text: &str) -> Result<Value, String> {
    let ran = run_text(a, path, text, true, fmsvm_driver::run::Hooks::default())?;
    let flat = ran.flat?;
    Ok(json!({
        "flat": flat,
        "blocks": flat.lines().count(),
        "stats": ran.stats,
    }))
}

/// Whether file `f` holds program `n` (named `O1234…`, or an `O1234` line in it).
fn holds_program(f: &Path, n: u32) -> bool {
    let stem = f
        .file_stem()
        .map(|s| s.to_string_lossy().to_ascii_uppercase());
    if stem
        .as_deref()
        .and_then(|s| s.strip_prefix('O'))
        .and_then(|d| d.parse::<u32>().ok())
        == Some(n)
    {
        return true;
    }
    std::fs::read_to_string(f).is_ok_and(|t| {
        t.lines().any(|l| {
            let l = l.trim_start();
            (l.starts_with('O') || l.starts_with(':'))
                && l[1..]
                    .split(|c: char| !c.is_ascii_digit())
                    .next()
                    .and_then(|d| d.parse::<u32>().ok())
                    == Some(n)
        })
    })
}

/// The innermost item whose span holds `offset` (a program only where nothing else does).
fn item_at(items: &[Item], offset: u32) -> Option<&Item> {
    items
        .iter()
        .filter(|i| !matches!(i, Item::Program { .. }) || i.span().start <= offset)
        .filter(|i| {
            let s = i.span();
            s.start <= offset && offset <= s.end
        })
        .min_by_key(|i| i.span().end - i.span().start)
        .or_else(|| {
            items.iter().find(|i| match i {
                Item::Loop { end: Some(e), .. } => e.start <= offset && offset <= e.end,
                _ => false,
            })
        })
}

/// Where each program (its O number) of a document starts: made in one pass, looked up by a
/// binary search, so that a request over every item of a long document stays linear.
struct Programs(Vec<(u32, Option<u32>)>);

impl Programs {
    fn of(items: &[Item]) -> Programs {
        let mut starts: Vec<(u32, Option<u32>)> = items
            .iter()
            .filter_map(|i| match i {
                Item::Program { number, whole, .. } => Some((whole.start, *number)),
                _ => None,
            })
            .collect();
        // The last program to start at or before an offset holds it (a later one of the same
        // start wins, as in the outline's order).
        starts.sort_by_key(|&(start, _)| start);
        Programs(starts)
    }

    /// The program the text at `offset` belongs to (None before the first).
    fn at(&self, offset: u32) -> Option<Option<u32>> {
        let k = self.0.partition_point(|&(start, _)| start <= offset);
        k.checked_sub(1).map(|k| self.0[k].1)
    }
}

/// The program (its O number) the text at `offset` belongs to.
fn program_at(items: &[Item], offset: u32) -> Option<Option<u32>> {
    Programs::of(items).at(offset)
}

/// Sequence number `n` in program `program`.
fn label_in(items: &[Item], program: Option<Option<u32>>, n: u32) -> Option<fmsvm_compiler::Span> {
    let programs = Programs::of(items);
    items.iter().find_map(|i| match i {
        Item::Label { number, span } if *number == n && programs.at(span.start) == program => {
            Some(*span)
        }
        _ => None,
    })
}

/// What variable `#n` is.
pub fn describe_variable(n: u32, params: &fmsvm_driver::params::Params) -> String {
    let to = params.variables.alias(n);
    if to != n {
        // One step: the number it is read as, described without its own alias.
        return format!(
            "#{n}: read and written as #{to} (--params [variables] aliases): {}",
            describe_number(to, params)
        );
    }
    describe_number(n, params)
}

/// What `#n` is under the parameters, its aliases aside.
fn describe_number(n: u32, params: &fmsvm_driver::params::Params) -> String {
    let declared = &params.variables;
    if let Some(v) = declared.values.get(&n) {
        return format!(
            "#{n}: a variable the control holds, declared in --params (it starts at {v})"
        );
    }
    if declared.in_range(n) {
        return format!("#{n}: a common variable declared in --params ([variables] ranges)");
    }
    let commons = &params.commons;
    match n {
        _ if commons.is_volatile(n) => format!("#{n}: a common variable, cleared at power-off"),
        _ if commons.is_retained(n) => format!("#{n}: a common variable, kept at power-off"),
        100..=199 | 500..=999 => format!(
            "#{n}: not a common variable of this control (its parameters narrow the commons): alarm 0115"
        ),
        0 => "#0: always vacant (null); read only".into(),
        1..=33 => {
            let letter = fmsvm_block::Letter::ALL
                .iter()
                .find(|&&l| fmsvm_vm::spec_i(l) == Some(n as usize));
            match letter {
                Some(l) => format!(
                    "#{n}: a local variable; in a macro called with G65/G66, its argument {l} (specification I)"
                ),
                None => format!(
                    "#{n}: a local variable; in a macro called with G65/G66, an argument of specification II (I J K sets)"
                ),
            }
        }
        _ => fmsvm_kernel::describe_variable(n)
            .unwrap_or_else(|| format!("#{n}: a system variable fmsvm does not model (alarm 0115 if read; declare it in --params)")),
    }
}

/// What G or M code `value` means on a mill (the kernel's tables).
pub fn describe_code(
    letter: fmsvm_block::Letter,
    value: f64,
    system: fmsvm_canon::modal::CodeSystem,
) -> Option<String> {
    use fmsvm_canon::modal;
    let code = fmsvm_block::Code::of(value)?;
    if letter != fmsvm_block::Letter::G {
        return Some(format!("M{code}"));
    }
    // What the code means on this control (a lathe's G50 is not the mill's scaling cancel).
    let Some(meaning) = system.meaning(code) else {
        return Some(format!("G{code}: not a code of {}", system.name()));
    };
    let group = modal::group(meaning)?;
    // The group's other codes as this control writes them.
    let members: Vec<String> = group
        .codes()
        .chain(modal::lathe_meanings_of(group).filter(|_| system.lathe()))
        .filter(|&m| system.meaning(system.written(m)) == Some(m))
        .map(|m| format!("G{}", system.written(m)))
        .collect();
    let number = system.group_number(group).unwrap_or(group as u8);
    let title = match modal::lathe_title(meaning).filter(|_| system.lathe()) {
        Some(t) => format!("{t} (group {number:02}, {})", group.title()),
        None => format!("group {number:02}, {}", group.title()),
    };
    Some(format!(
        "G{code}: {title}{}",
        if members.len() > 1 {
            format!(" ({})", members.join(" "))
        } else {
            String::new()
        }
    ))
}
