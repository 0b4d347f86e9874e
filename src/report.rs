//! Renders diagnostics and alarms for people, in the shape compilers use:
//!
//! ```text
//! error[alarm 0114]: format error: unexpected `]`
//!   --> part.nc:12:9
//!    |
//! 12 | #1=[2+3]]
//!    |         ^ here
//!    = note: …
//! ```
//!
//! `file:line:column`, the source line, a caret under the offending text, the Fanuc alarm number.
//! The only place that formats messages for the terminal.

use std::io::{self, Write};

use fmsvm_compiler::{Diagnostic, Severity, SourceMap, Span};

/// Writes messages to standard error.
pub struct Reporter<'a> {
    sources: &'a SourceMap,
}

impl<'a> Reporter<'a> {
    /// A reporter over `sources`.
    pub fn new(sources: &'a SourceMap) -> Self {
        Reporter { sources }
    }

    /// Renders one message with its location into a string.
    pub fn format(
        &self,
        severity: &str,
        alarm: Option<u32>,
        span: Span,
        message: &str,
        label: &str,
        notes: &[String],
    ) -> String {
        let file = self.sources.file(span.file);
        let (line, col) = file.line_col(span.start);
        let text = file.line_text(line);
        let code = alarm.map_or(String::new(), |a| format!("[alarm {a:04}]"));
        let gutter = line.to_string().len();
        let pad = " ".repeat(gutter);
        // The caret runs under the span's characters on its first line (at least one).
        let (end_line, end_col) = file.line_col(span.end.max(span.start));
        let width = if end_line == line && end_col > col {
            end_col - col
        } else {
            1
        };
        let shown: String = text
            .chars()
            .map(|c| if c == '\t' { ' ' } else { c })
            .collect();
        let mut out = format!(
            "{severity}{code}: {message}\n{pad}--> {}:{line}:{col}\n{pad} |\n{line} | {shown}\n{pad} | {}{} {label}\n",
            file.name,
            " ".repeat(col as usize - 1),
            "^".repeat(width as usize),
        );
        for n in notes {
            out.push_str(&format!("{pad} = note: {n}\n"));
        }
        out
    }

    fn write(&self, s: &str) {
        let mut err = io::stderr().lock();
        let _ = err.write_all(s.as_bytes());
        let _ = err.flush();
    }

    /// Renders a compiler diagnostic.
    pub fn diagnostic(&self, d: &Diagnostic) {
        let (severity, label) = match d.severity {
            Severity::Error => ("error", "here"),
            Severity::Warning => ("warning", "this"),
        };
        self.write(&self.format(severity, d.alarm, d.span, &d.message, label, &d.notes));
    }

    /// Renders a run-time stop (alarm, limit) at the statement that raised it.
    pub fn stop(&self, what: &str, code: Option<u32>, span: Span, notes: &[String]) {
        self.write(&self.format(
            "error",
            code,
            span,
            what,
            "raised while running this",
            notes,
        ));
    }
}

/// A plain error with no source position (files, flags).
pub fn plain(message: &str) {
    let mut err = io::stderr().lock();
    let _ = writeln!(err, "error: {message}");
}
