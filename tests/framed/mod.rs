//! A server started as an editor starts it (`fmsvm lsp`, `fmsvm dap`): JSON messages over its
//! standard input and output, each after a `Content-Length` header (both protocols frame so).

use std::io::{BufRead, BufReader, Read, Write};
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};

use serde_json::Value;

pub struct Framed {
    pub child: Child,
    input: ChildStdin,
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
            input,
            output,
        }
    }

    pub fn send(&mut self, v: &Value) {
        let body = v.to_string();
        write!(self.input, "Content-Length: {}\r\n\r\n{body}", body.len()).expect("written");
        self.input.flush().expect("flushed");
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
