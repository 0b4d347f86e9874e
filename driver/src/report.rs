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

    /// A run's warning about the output, located as errors are: `FILE:LINE:COL: warning: …` (a
    /// warning about the program as a whole: `warning: …`).
    pub fn run_warning(&self, w: &fmsvm_canon::Warning) -> String {
        let at = self.locate(w);
        if at.line > 0 {
            format!(
                "{}:{}:{}: warning: {}",
                at.file,
                at.line,
                at.column.max(1),
                at.text
            )
        } else {
            format!("warning: {}", at.text)
        }
    }

    /// A run's warning with its block's file as the sources name it (line 0: no block).
    pub fn locate(&self, w: &fmsvm_canon::Warning) -> RunWarning {
        let file = self.sources.files().get(usize::from(w.at.file));
        RunWarning {
            file: file.map(|f| f.name.to_string()).unwrap_or_default(),
            line: if file.is_some() { w.at.line } else { 0 },
            column: u32::from(w.at.column),
            text: w.text.to_string(),
        }
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
        let (shown, caret_col, width) = window(text, col as usize, width as usize);
        let message = if message.trim().is_empty() {
            "(no message text)"
        } else {
            message
        };
        let mut out = format!(
            "{severity}{code}: {message}\n{pad}--> {}:{line}:{col}\n{pad} |\n{line} | {shown}\n{pad} | {}{} {label}\n",
            file.name,
            " ".repeat(caret_col - 1),
            "^".repeat(width),
        );
        for n in notes.iter().filter(|n| !n.trim().is_empty()) {
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

/// Errors shown of one compilation; the rest are counted in one line.
pub const MAX_ERRORS: usize = 50;

/// `1 error`, `2 errors`: a count with its noun in the right number.
pub fn count(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// Characters of a source line shown at most; a longer line is cut around the error.
pub const MAX_SHOWN: usize = 100;

/// The part of `text` shown for an error at 1-based character column `col` spanning `width`
/// characters: tabs as spaces, a line longer than [`MAX_SHOWN`] cut to a window around the column with
/// `…` where text was left out. Returns the shown text, the caret's 1-based column in it and the
/// caret's width (at least 1, never past the shown text).
pub fn window(text: &str, col: usize, width: usize) -> (String, usize, usize) {
    let chars: Vec<char> = text
        .chars()
        .map(|c| if c == '\t' { ' ' } else { c })
        .collect();
    let col = col.max(1);
    let width = width.max(1);
    if chars.len() <= MAX_SHOWN {
        return (chars.into_iter().collect(), col, width);
    }
    // A third of the window before the error, the rest after it.
    let start = (col - 1).saturating_sub(MAX_SHOWN / 3);
    let start = start.min(chars.len().saturating_sub(MAX_SHOWN));
    let end = (start + MAX_SHOWN).min(chars.len());
    let mut shown = String::new();
    let mut caret = col - start;
    if start > 0 {
        shown.push('…');
        caret += 1;
    }
    shown.extend(&chars[start..end]);
    if end < chars.len() {
        shown.push('…');
    }
    let room = (end + 1).saturating_sub(col).max(1);
    (shown, caret, width.min(room))
}

/// Says `message` on standard error as it is (a summary, a note).
pub fn info(message: &str) {
    let _ = writeln!(io::stderr(), "{message}");
}

/// A plain error with no source position (files, flags).
pub fn plain(message: &str) {
    let mut err = io::stderr().lock();
    let _ = writeln!(err, "error: {message}");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_lines_are_shown_whole() {
        assert_eq!(window("G1\tX1", 4, 2), ("G1 X1".to_string(), 4, 2));
    }

    #[test]
    fn long_lines_are_cut_with_the_caret_on_its_character() {
        // 300 characters, two bytes each; the error at character 200.
        let text: String = (0..300).map(|i| if i == 199 { '$' } else { 'é' }).collect();
        let (shown, caret, width) = window(&text, 200, 5);
        assert!(shown.starts_with('…') && shown.ends_with('…'));
        assert_eq!(shown.chars().count(), MAX_SHOWN + 2);
        assert_eq!(shown.chars().nth(caret - 1), Some('$'));
        assert_eq!(width, 5);
        // At the end of a long line the caret may sit just past its last character.
        let (shown, caret, width) = window(&text, 301, 9);
        assert!(shown.starts_with('…') && !shown.ends_with('…'));
        assert_eq!(caret, shown.chars().count() + 1);
        assert_eq!(width, 1);
    }

    #[test]
    fn counts_agree_with_their_noun() {
        assert_eq!(count(1, "error", "errors"), "1 error");
        assert_eq!(count(0, "error", "errors"), "0 errors");
        assert_eq!(count(2, "error", "errors"), "2 errors");
    }
}

/// A warning a run said at a block.
#[derive(Clone, Debug, PartialEq)]
pub struct RunWarning {
    /// The block's file, as the run's sources name it (empty when it has none).
    pub file: String,
    /// Its line and column, from 1 (line 0: no block).
    pub line: u32,
    pub column: u32,
    pub text: String,
}
