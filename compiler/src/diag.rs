//! Diagnostics: what the compiler found wrong, where, and the Fanuc alarm number where one exists.

use fmsvm_ir::span::Span;

/// How bad a diagnostic is.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Severity {
    /// The program cannot run.
    Error,
    /// The program runs, but probably not as meant.
    Warning,
}

/// One finding of the compiler.
#[derive(Clone, Debug)]
pub struct Diagnostic {
    /// Error or warning.
    pub severity: Severity,
    /// Where.
    pub span: Span,
    /// The Fanuc alarm a control would raise for the same text (114 format error, 118 bracket nesting …).
    pub alarm: Option<u32>,
    /// What is wrong, in one sentence.
    pub message: String,
    /// Extra lines: what to do, or where the other half of a pair is.
    pub notes: Vec<String>,
    /// The text that would replace the span to mend it (`LE` for `LTE`), where one is known: an
    /// editor's quick fix.
    pub fix: Option<String>,
}

/// `error: message (alarm 0114)`: the finding without its place (the renderer adds file:line:column).
impl std::fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let kind = if self.is_error() { "error" } else { "warning" };
        write!(f, "{kind}: {}", self.message)?;
        if let Some(n) = self.alarm {
            write!(f, " (alarm {n:04})")?;
        }
        Ok(())
    }
}

impl std::error::Error for Diagnostic {}

impl Diagnostic {
    /// The error as a warning, with `note` saying why it does not stop the run.
    pub fn demote(&mut self, note: String) {
        self.severity = Severity::Warning;
        self.notes.push(note);
    }

    /// An error with an alarm number.
    pub fn error(span: Span, alarm: Option<u32>, message: impl Into<String>) -> Diagnostic {
        Diagnostic {
            severity: Severity::Error,
            span,
            alarm,
            message: message.into(),
            notes: Vec::new(),
            fix: None,
        }
    }

    /// A warning.
    pub fn warning(span: Span, alarm: Option<u32>, message: impl Into<String>) -> Diagnostic {
        Diagnostic {
            severity: Severity::Warning,
            span,
            alarm,
            message: message.into(),
            notes: Vec::new(),
            fix: None,
        }
    }

    /// With the text that mends the span.
    pub fn fix(mut self, with: impl Into<String>) -> Diagnostic {
        self.fix = Some(with.into());
        self
    }

    /// Adds a note.
    pub fn note(mut self, note: impl Into<String>) -> Diagnostic {
        self.notes.push(note.into());
        self
    }

    /// True for errors.
    pub fn is_error(&self) -> bool {
        self.severity == Severity::Error
    }
}

/// Fanuc alarm numbers the compiler and VM use (macro-b-rules A1, A2).
pub use fmsvm_ir::alarm;
