//! Renders diagnostics and alarms for people (ariadne): `file:line:col`, the source line, a caret under
//! the offending text, the Fanuc alarm number. The only place that formats messages.

use std::io::{self, IsTerminal, Write};
use std::ops::Range;

use ariadne::{CharSet, Color, Config, IndexType, Label, Report, ReportKind, Source};
use fmsvm_compiler::{Diagnostic, Severity, SourceMap, Span};

/// Writes messages to standard error.
pub struct Reporter<'a> {
    sources: &'a SourceMap,
    color: bool,
}

impl<'a> Reporter<'a> {
    /// A reporter over `sources`; colour only on a terminal.
    pub fn new(sources: &'a SourceMap) -> Self {
        Reporter {
            sources,
            color: io::stderr().is_terminal() && std::env::var_os("NO_COLOR").is_none(),
        }
    }

    fn config(&self) -> Config {
        Config::default()
            .with_index_type(IndexType::Byte)
            .with_color(self.color)
            .with_char_set(if self.color {
                CharSet::Unicode
            } else {
                CharSet::Ascii
            })
    }

    fn range(&self, span: Span) -> Range<usize> {
        let len = self.sources.file(span.file).text.len();
        let start = (span.start as usize).min(len);
        let end = (span.end as usize).clamp(start, len);
        // A zero-width span (end of file) still needs a caret.
        if start == end && end < len {
            start..end + 1
        } else {
            start..end
        }
    }

    /// Renders one message with its location.
    fn render(
        &self,
        kind: ReportKind<'_>,
        code: Option<String>,
        span: Span,
        message: &str,
        label: &str,
        notes: &[String],
    ) {
        let file = self.sources.file(span.file);
        let name = file.name.clone();
        let range = self.range(span);
        let (line, col) = file.line_col(span.start);
        let mut report = Report::build(kind, (name.clone(), range.clone()))
            .with_config(self.config())
            .with_message(format!("{name}:{line}:{col}: {message}"))
            .with_label(
                Label::new((name.clone(), range))
                    .with_message(label)
                    .with_color(Color::Red),
            );
        if let Some(c) = code {
            report = report.with_code(c);
        }
        for n in notes {
            report = report.with_note(n);
        }
        let mut err = io::stderr().lock();
        let _ = report
            .finish()
            .write((name, Source::from(file.text.as_str())), &mut err);
        let _ = err.flush();
    }

    /// Renders a compiler diagnostic.
    pub fn diagnostic(&self, d: &Diagnostic) {
        let kind = match d.severity {
            Severity::Error => ReportKind::Error,
            Severity::Warning => ReportKind::Warning,
        };
        let label = if d.is_error() { "here" } else { "this" };
        self.render(
            kind,
            d.alarm.map(|a| format!("alarm {a:04}")),
            d.span,
            &d.message,
            label,
            &d.notes,
        );
    }

    /// Renders a run-time stop (alarm, limit) at the statement that raised it.
    pub fn stop(&self, what: &str, code: Option<u32>, span: Span, notes: &[String]) {
        self.render(
            ReportKind::Error,
            code.map(|a| format!("alarm {a:04}")),
            span,
            what,
            "raised while running this statement",
            notes,
        );
    }
}

/// A plain error with no source position (files, flags).
pub fn plain(message: &str) {
    let mut err = io::stderr().lock();
    let _ = writeln!(err, "error: {message}");
}
