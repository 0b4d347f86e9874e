//! Diagnostics: what the compiler found wrong, where, and the Fanuc alarm number where one exists.

use crate::span::Span;

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
}

impl Diagnostic {
    /// An error with an alarm number.
    pub fn error(span: Span, alarm: Option<u32>, message: impl Into<String>) -> Diagnostic {
        Diagnostic {
            severity: Severity::Error,
            span,
            alarm,
            message: message.into(),
            notes: Vec::new(),
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
        }
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
pub mod alarm {
    /// 0003 TOO MANY DIGIT.
    pub const TOO_MANY_DIGITS: u32 = 3;
    /// 0006 ILLEGAL USE OF MINUS SIGN.
    pub const MINUS_SIGN: u32 = 6;
    /// 0007 ILLEGAL USE OF DECIMAL POINT.
    pub const DECIMAL_POINT: u32 = 7;
    /// 0110 OVERFLOW: INTEGER.
    pub const INTEGER_OVERFLOW: u32 = 110;
    /// 0111 OVERFLOW: FLOATING.
    pub const FLOAT_OVERFLOW: u32 = 111;
    /// 0112 ZERO DIVIDE.
    pub const ZERO_DIVIDE: u32 = 112;
    /// 0114 ILLEGAL EXPRESSION FORMAT (format error in macro).
    pub const FORMAT: u32 = 114;
    /// 0115 VARIABLE NO. OUT OF RANGE.
    pub const VARIABLE_RANGE: u32 = 115;
    /// 0116 WRITE PROTECTED VARIABLE.
    pub const WRITE_PROTECTED: u32 = 116;
    /// 0118 TOO MANY BRACKET NESTING.
    pub const BRACKET_NESTING: u32 = 118;
    /// 0119 ARGUMENT VALUE OUT OF RANGE.
    pub const ARGUMENT_RANGE: u32 = 119;
    /// 0124 MISSING END STATEMENT.
    pub const MISSING_END: u32 = 124;
    /// 0125 MACRO STATEMENT FORMAT ERROR.
    pub const STATEMENT_FORMAT: u32 = 125;
    /// 0126 ILLEGAL LOOP NUMBER.
    pub const LOOP_NUMBER: u32 = 126;
    /// 0127 DUPLICATE NC, MACRO STATEMENT.
    pub const NC_AND_MACRO: u32 = 127;
    /// 0128 ILLEGAL MACRO SEQUENCE NUMBER (GOTO target not found).
    pub const SEQUENCE_NUMBER: u32 = 128;
}
