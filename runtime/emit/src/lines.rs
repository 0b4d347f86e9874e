//! The output buffer every emitter writes through: lines formatted in place into one large buffer
//! that goes to the writer in 64 KiB pieces, the output budget (bytes, blocks, time) spent per line, and only complete lines
//! ever reaching the writer (also when dropped after a stop, for `--keep-partial`).

use std::io::Write;

use fmsvm_block::alarms::FORMAT;
use fmsvm_block::{Alarm, OutputBudget, Stop};

use crate::dialect::{CommentStyle, Dialect};
use crate::format::Text;

/// Output goes to the writer in pieces of this size.
const CHUNK: usize = 1 << 16;

/// A line-oriented output buffer.
pub struct Lines<W: Write> {
    out: W,
    /// The bytes not yet written; the line being formatted is `buf[line_start..]`.
    pub buf: Vec<u8>,
    line_start: usize,
    eol: String,
    /// `eol` in a register, when it fits one (it always does in the built-in dialects).
    eol_text: Option<Text>,
    /// Most bytes of a line, its end included.
    max_line: usize,
    budget: OutputBudget,
    written: u64,
    /// The writer gets what is buffered once it reaches this many bytes (`CHUNK`; 0: every line).
    chunk: usize,
    /// Comments the run asked for that the control has no syntax for (left out).
    left_out_comments: u64,
    /// Comments cut to fit the dialect's line length.
    cut_comments: u64,
    /// Comments the control would act on, made inert.
    inert_comments: u64,
}

impl<W: Write> Lines<W> {
    /// Lines ending in `eol` going to `out`, within `budget`.
    pub fn new(out: W, eol: &str, max_line: Option<usize>, budget: OutputBudget) -> Self {
        Lines {
            out,
            buf: Vec::with_capacity(CHUNK + 1024),
            line_start: 0,
            eol: eol.to_string(),
            eol_text: Text::from_bytes(eol.as_bytes()),
            max_line: max_line.unwrap_or(usize::MAX),
            budget,
            written: 0,
            chunk: CHUNK,
            left_out_comments: 0,
            cut_comments: 0,
            inert_comments: 0,
        }
    }

    /// A comment the run asked for is left out: the control has no comment syntax.
    pub fn leave_out_comment(&mut self) {
        self.left_out_comments += 1;
    }

    /// What the run is told, once each, when comments were left out because the control has no
    /// comment syntax, or cut to fit its line length (`control`: the dialect's name).
    pub fn comment_warnings(&self, control: &str) -> Vec<fmsvm_canon::Warning> {
        let plural = |n: u64| if n == 1 { "comment is" } else { "comments are" };
        let mut said = Vec::new();
        let n = self.left_out_comments;
        if n > 0 {
            said.push(fmsvm_canon::Warning::program(format!(
                "{control} has no comments: the program's {n} {} left out of the output (--no-comments leaves them out without this note)",
                plural(n)
            )));
        }
        let n = self.cut_comments;
        if n > 0 {
            said.push(fmsvm_canon::Warning::program(format!(
                "{n} {} cut to fit {control}'s line of {} characters",
                plural(n),
                self.max_line
            )));
        }
        let n = self.inert_comments;
        if n > 0 {
            said.push(fmsvm_canon::Warning::program(format!(
                "{n} {} written with a `-` before the word {control} would act on (`(MSG,`, `(LOGOPEN,`, …): in the program they are only comments",
                plural(n)
            )));
        }
        said
    }

    /// Writes a block's comments in `style` on the line being formatted (`push_block_comments`),
    /// cut where the line would pass the dialect's length: a comment is for the operator, and a
    /// line too long is refused by the control.
    pub fn push_block_comments(&mut self, style: CommentStyle, active: &[String], text: &str) {
        let start = self.buf.len();
        push_block_comments(&mut self.buf, style, text);
        if style == CommentStyle::Paren && !active.is_empty() {
            self.inert_comments += make_inert(&mut self.buf, start, active);
        }
        let eol = self.eol.len();
        let room = self
            .max_line
            .saturating_sub(eol + (start - self.line_start));
        if self.buf.len() - start <= room {
            return;
        }
        self.cut_comments += 1;
        // Room for the closing parenthesis; the cut is at a character's start.
        let close = usize::from(style == CommentStyle::Paren);
        let mut end = start + room.saturating_sub(close);
        while end > start && !is_char_start(self.buf[end]) {
            end -= 1;
        }
        self.buf.truncate(end);
        let open = self.buf[start..].iter().filter(|&&b| b == b'(').count()
            > self.buf[start..].iter().filter(|&&b| b == b')').count();
        if open {
            self.buf.push(b')');
        }
        // Nothing of the comment fits: not even the separating space stays.
        if self.buf.len() - start <= close {
            self.buf.truncate(start);
            while self.buf.len() > self.line_start && self.buf.last() == Some(&b' ') {
                self.buf.pop();
            }
        }
    }

    /// Every line goes to the writer as it ends (for a reader beside the writer).
    pub fn line_by_line(&mut self) {
        self.chunk = 0;
    }

    /// Bytes of complete lines so far.
    pub fn written(&self) -> u64 {
        self.written
    }

    /// Whether the line being formatted is still empty.
    pub fn line_is_empty(&self) -> bool {
        self.buf.len() == self.line_start
    }

    /// Drops the line being formatted (nothing of a block that fails reaches the output).
    pub fn cancel_line(&mut self) {
        self.buf.truncate(self.line_start);
    }

    /// Ends the line being formatted: one block of the flat program.
    #[inline]
    pub fn end_line(&mut self) -> Result<(), Stop> {
        self.close_line(true)
    }

    /// Ends a line of the tape's start or end (`%`, the program number, a footer): bytes, not a
    /// block.
    fn end_tape_line(&mut self) -> Result<(), Stop> {
        self.close_line(false)
    }

    /// Ends the line being formatted, spent as a block or as bytes only.
    #[inline]
    fn close_line(&mut self, block: bool) -> Result<(), Stop> {
        match self.eol_text {
            Some(t) => t.push(&mut self.buf),
            None => self.buf.extend_from_slice(self.eol.as_bytes()),
        }
        let len = (self.buf.len() - self.line_start) as u64;
        if len as usize > self.max_line {
            let text = String::from_utf8_lossy(&self.buf[self.line_start..])
                .trim_end()
                .to_string();
            self.buf.truncate(self.line_start);
            return Err(Alarm::new(
                FORMAT,
                format!(
                    "the block `{text}` has {len} characters with its end; the dialect takes at most {}",
                    self.max_line
                ),
            )
            .into());
        }
        let spent = if block {
            self.budget.spend_line(len)
        } else {
            self.budget.spend(len)
        };
        if let Err(stop) = spent {
            self.buf.truncate(self.line_start);
            return Err(stop);
        }
        self.written += len;
        self.line_start = self.buf.len();
        if self.buf.len() >= self.chunk {
            self.out.write_all(&self.buf)?;
            self.buf.clear();
            self.line_start = 0;
        }
        Ok(())
    }

    /// Writes every complete line and flushes the writer.
    pub fn finish(&mut self) -> Result<(), Stop> {
        self.out.write_all(&self.buf[..self.line_start])?;
        self.buf.clear();
        self.line_start = 0;
        self.out.flush()?;
        Ok(())
    }
}

impl<W: Write> Lines<W> {
    /// The program's start as the dialect spells it: the header lines (`%`), the program-number
    /// line (`O0001`, with the program's name as a comment where the dialect has comments: the
    /// control lists it in its directory), and the optional header comment naming fmsvm.
    pub fn tape_start(
        &mut self,
        dialect: &Dialect,
        number: Option<u32>,
        title: &str,
        source: &str,
    ) -> Result<(), Stop> {
        let name = comment_words(title);
        for t in &dialect.header {
            let line = Dialect::expand_template(t, number, &name, source);
            self.buf.extend_from_slice(line.as_bytes());
            self.end_tape_line()?;
        }
        if let Some(n) = number
            && !dialect.program_number.is_empty()
        {
            let line = Dialect::expand_template(&dialect.program_number, Some(n), &name, source);
            self.buf.extend_from_slice(line.as_bytes());
            if !name.is_empty() && dialect.comments != CommentStyle::None {
                self.buf.push(b' ');
                push_comment(&mut self.buf, dialect.comments, &name);
            }
            self.end_tape_line()?;
        }
        if dialect.header_comment && dialect.comments != CommentStyle::None {
            let text = format!(
                "written by fmsvm {} from {}",
                env!("CARGO_PKG_VERSION"),
                comment_words(source)
            );
            push_comment(&mut self.buf, dialect.comments, &text);
            self.end_tape_line()?;
        }
        Ok(())
    }

    /// A `#3006` message stop: `M0 (MESSAGE n: text)` (the comment as the dialect has them).
    pub fn message(&mut self, dialect: &Dialect, number: u32, text: &str) -> Result<(), Stop> {
        self.buf.extend_from_slice(b"M0");
        if dialect.comments != CommentStyle::None {
            self.buf.push(b' ');
            let text = format!("MESSAGE {number}: {}", comment_words(text));
            push_comment(&mut self.buf, dialect.comments, &text);
        }
        self.end_line()
    }

    /// The program's end (the footer lines, `%`), and everything out.
    pub fn tape_end(&mut self, dialect: &Dialect, number: Option<u32>) -> Result<(), Stop> {
        for t in &dialect.footer {
            let line = Dialect::expand_template(t, number, "", "");
            self.buf.extend_from_slice(line.as_bytes());
            self.end_tape_line()?;
        }
        self.finish()
    }
}

/// Puts a `-` at the start of each comment in `buf[start..]` whose text begins (whitespace left
/// out, any case) with one of the `active` words (upper case), so that the control does not act on
/// it; how many.
fn make_inert(buf: &mut Vec<u8>, start: usize, active: &[String]) -> u64 {
    let mut made = 0;
    let mut at = start;
    while let Some(open) = buf[at..].iter().position(|&b| b == b'(').map(|p| at + p) {
        let end = buf[open..]
            .iter()
            .position(|&b| b == b')')
            .map_or(buf.len(), |p| open + p);
        let compact: Vec<u8> = buf[open + 1..end]
            .iter()
            .filter(|b| !b.is_ascii_whitespace())
            .map(u8::to_ascii_uppercase)
            .collect();
        at = end;
        if active.iter().any(|w| compact.starts_with(w.as_bytes())) {
            buf.insert(open + 1, b'-');
            made += 1;
            at += 1;
        }
    }
    made
}

/// Whether `b` starts a UTF-8 character (is not a continuation byte).
fn is_char_start(b: u8) -> bool {
    b & 0xC0 != 0x80
}

/// Writes one comment of plain words (no parentheses in `text`) in `style`.
pub fn push_comment(buf: &mut Vec<u8>, style: CommentStyle, text: &str) {
    match style {
        CommentStyle::Paren => {
            buf.push(b'(');
            buf.extend_from_slice(text.as_bytes());
            buf.push(b')');
        }
        CommentStyle::Semicolon => {
            buf.extend_from_slice(b"; ");
            buf.extend_from_slice(text.as_bytes());
        }
        CommentStyle::None => {}
    }
}

/// Writes a block's comments in `style`: as `(A) (B)` (see `push_comments`), or their words after `;`.
pub fn push_block_comments(buf: &mut Vec<u8>, style: CommentStyle, text: &str) {
    match style {
        CommentStyle::Paren => push_comments(buf, text),
        CommentStyle::Semicolon => push_comment(buf, style, &comment_words(text)),
        CommentStyle::None => {}
    }
}

/// The words of comment text `(A) (B (C)`, without parentheses: `A B C`. Written inside one pair of
/// parentheses it can never end the comment early nor nest one. A `%` is a space: it is the end of
/// record on a tape or a serial line, where the control would stop reading the program (Fanuc, ISO
/// 6983's EOR), in a comment or not.
pub fn comment_words(text: &str) -> String {
    text.split(['(', ')', '%'])
        .flat_map(str::split_whitespace)
        .collect::<Vec<_>>()
        .join(" ")
}

/// Writes comments as `(A) (B)`: a `(` inside one (`(A (B)` is one comment) becomes a space, so that
/// no comment nests another.
pub fn push_comments(buf: &mut Vec<u8>, text: &str) {
    let mut open = false;
    for c in text.chars() {
        match c {
            '(' if open => buf.push(b' '),
            '(' => {
                open = true;
                buf.push(b'(');
            }
            ')' if open => {
                open = false;
                buf.push(b')');
            }
            ')' => buf.push(b' '),
            // The end of record (see `comment_words`).
            '%' => buf.push(b' '),
            c => {
                let mut b = [0u8; 4];
                buf.extend_from_slice(c.encode_utf8(&mut b).as_bytes());
            }
        }
    }
    if open {
        buf.push(b')');
    }
}

impl<W: Write> Drop for Lines<W> {
    /// After a stop, the complete lines formatted so far still reach the writer.
    fn drop(&mut self) {
        if self.line_start > 0 {
            let _ = self.out.write_all(&self.buf[..self.line_start]);
            let _ = self.out.flush();
        }
    }
}
