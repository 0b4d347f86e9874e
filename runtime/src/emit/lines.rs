//! The output buffer every emitter writes through: lines formatted in place into one large buffer
//! that goes to the writer in 64 KiB pieces, the byte budget spent per line, and only complete lines
//! ever reaching the writer (also when dropped after a stop, for `--keep-partial`).

use std::io::Write;

use fmsvm_block::{ByteBudget, Stop};

/// Output goes to the writer in pieces of this size.
const CHUNK: usize = 1 << 16;

/// A line-oriented output buffer.
pub struct Lines<W: Write> {
    out: W,
    /// The bytes not yet written; the line being formatted is `buf[line_start..]`.
    pub buf: Vec<u8>,
    line_start: usize,
    eol: &'static str,
    budget: ByteBudget,
    written: u64,
}

impl<W: Write> Lines<W> {
    /// Lines ending in `eol` going to `out`, within `budget`.
    pub fn new(out: W, eol: &'static str, budget: ByteBudget) -> Self {
        Lines {
            out,
            buf: Vec::with_capacity(CHUNK + 1024),
            line_start: 0,
            eol,
            budget,
            written: 0,
        }
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

    /// Ends the line being formatted.
    #[inline]
    pub fn end_line(&mut self) -> Result<(), Stop> {
        self.buf.extend_from_slice(self.eol.as_bytes());
        let len = (self.buf.len() - self.line_start) as u64;
        if let Err(stop) = self.budget.spend(len) {
            self.buf.truncate(self.line_start);
            return Err(stop);
        }
        self.written += len;
        self.line_start = self.buf.len();
        if self.buf.len() >= CHUNK {
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
    /// The tape start `%` and the O line with the program's name as one flat comment (always kept:
    /// the control lists it in its directory).
    pub fn tape_start(&mut self, number: Option<u32>, title: &str) -> Result<(), Stop> {
        self.buf.push(b'%');
        self.end_line()?;
        if let Some(n) = number {
            self.buf.push(b'O');
            let s = format!("{n:04}");
            self.buf.extend_from_slice(s.as_bytes());
            let name = comment_words(title);
            if !name.is_empty() {
                self.buf.extend_from_slice(b" (");
                self.buf.extend_from_slice(name.as_bytes());
                self.buf.push(b')');
            }
            self.end_line()?;
        }
        Ok(())
    }

    /// A `#3006` message stop: `M0 (MESSAGE n: text)`.
    pub fn message(&mut self, number: u32, text: &str) -> Result<(), Stop> {
        // Parentheses inside the text would end the comment early.
        let clean: String = text
            .chars()
            .map(|c| if c == '(' || c == ')' { ' ' } else { c })
            .collect();
        let line = format!("M0 (MESSAGE {number}: {})", clean.trim());
        self.buf.extend_from_slice(line.as_bytes());
        self.end_line()
    }

    /// The tape end `%`, and everything out.
    pub fn tape_end(&mut self) -> Result<(), Stop> {
        self.buf.push(b'%');
        self.end_line()?;
        self.finish()
    }
}

/// The words of comment text `(A) (B (C)`, without parentheses: `A B C`. Written inside one pair of
/// parentheses it can never end the comment early nor nest one.
pub fn comment_words(text: &str) -> String {
    text.split(['(', ')'])
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
