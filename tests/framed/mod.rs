//! A server started as an editor starts it (`fmsvm lsp`, `fmsvm dap`): JSON messages over its
//! standard input and output, each after a `Content-Length` header (both protocols frame so).
#![allow(dead_code)]

use std::io::{BufRead, BufReader, Read, Write};
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};

use serde_json::Value;

pub struct Framed {
    pub child: Child,
    input: Option<ChildStdin>,
    output: BufReader<ChildStdout>,
}

impl Framed {
    /// `fmsvm <command>`, its standard error dropped.
    pub fn start(command: &str) -> Framed {
        let mut child = Command::new(env!("CARGO_BIN_EXE_fmsvm"))
            .arg(command)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap_or_else(|e| panic!("fmsvm {command} starts: {e}"));
        let input = child.stdin.take().expect("stdin");
        let output = BufReader::new(child.stdout.take().expect("stdout"));
        Framed {
            child,
            input: Some(input),
            output,
        }
    }

    pub fn send(&mut self, v: &Value) {
        let body = v.to_string();
        self.send_raw(format!("Content-Length: {}\r\n\r\n{body}", body.len()).as_bytes());
    }

    /// Sends bytes as they are (a frame the test breaks on purpose).
    pub fn send_raw(&mut self, bytes: &[u8]) {
        let input = self.input.as_mut().expect("the input is open");
        input.write_all(bytes).expect("written");
        input.flush().expect("flushed");
    }

    /// Closes the server's input.
    pub fn close(&mut self) {
        self.input = None;
    }

    pub fn receive(&mut self) -> Value {
        let mut length = 0usize;
        loop {
            let mut line = String::new();
            let n = self.output.read_line(&mut line).expect("a header");
            assert!(n > 0, "the server closed its output");
            let line = line.trim_end();
            if line.is_empty() {
                break;
            }
            if let Some(v) = line.strip_prefix("Content-Length: ") {
                length = v.parse().expect("a length");
            }
        }
        let mut body = vec![0u8; length];
        self.output.read_exact(&mut body).expect("the body");
        serde_json::from_slice(&body).expect("JSON")
    }
}
