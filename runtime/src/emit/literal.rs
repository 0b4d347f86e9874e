//! The literal emitter: each executed block's words as programmed (macros expanded, values rounded to
//! the least increment, no geometry resolved), in the dialect's number format.
//!
//! Format rules (default dialect "fanuc"): dimensional addresses always carry a decimal point (`X10.`:
//! on many controls `X10` means 10 µm), integer addresses never; trailing zeros trimmed; never `-0.`;
//! comments only when asked (the O line's program name always); `/` kept on block-delete blocks; `%` and
//! the O number at the ends.

use std::io::Write;

use fmsvm_block::{Alarm, Block, ByteBudget, Letter, Stop, Word};

use super::format::{push_fixed, push_gcode, push_u64};
use super::{Context, Emitter};
pub use crate::decode::DecimalInput;
use crate::decode::input_value;
use crate::dialect::{AddressKind, Dialect};

/// Output options.
#[derive(Clone, Debug)]
pub struct Options {
    /// Keep comments.
    pub comments: bool,
    /// Renumber blocks: first N and step.
    pub renumber: Option<(u32, u32)>,
    /// Line end.
    pub eol: &'static str,
    /// The bytes the run may write (shared with the printed output).
    pub budget: ByteBudget,
    /// How literals without a point are read.
    pub decimal_input: DecimalInput,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            comments: false,
            renumber: None,
            eol: "\n",
            budget: ByteBudget::default(),
            decimal_input: DecimalInput::Calculator,
        }
    }
}

/// Output goes to the writer in pieces of this size.
const CHUNK: usize = 1 << 16;

/// Powers of ten for the digits of an address.
const POW10: [f64; 10] = [1.0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9];

/// Rounds half away from zero without a libm call (|x| < 2^52, which the digit check guarantees).
#[inline(always)]
fn round_away(x: f64) -> i64 {
    let t = x as i64;
    let f = x - t as f64;
    if f >= 0.5 {
        t + 1
    } else if f <= -0.5 {
        t - 1
    } else {
        t
    }
}

/// 0003 TOO MANY DIGIT.
const TOO_MANY_DIGITS: u32 = 3;

/// Rounds an integer-address value half away from zero and checks its range (V10).
pub fn integer(letter: Letter, value: f64, max: u64) -> Result<u64, Alarm> {
    let r = value.round();
    if r < 0.0 {
        return Err(Alarm::new(
            6,
            format!("illegal use of minus sign: {letter}{value}"),
        ));
    }
    if r > max as f64 {
        return Err(Alarm::new(
            TOO_MANY_DIGITS,
            format!("too many digits: {letter}{value} (at most {letter}{max})"),
        ));
    }
    Ok(r as u64)
}

/// Writes blocks as programmed. Lines are formatted straight into one large buffer that goes to the
/// writer in 64 KiB pieces; only complete lines ever reach the writer (also when dropped after a stop).
pub struct LiteralEmitter<W: Write> {
    out: W,
    buf: Vec<u8>,
    /// Where the line being formatted starts in `buf`.
    line_start: usize,
    dialect: Dialect,
    options: Options,
    next_n: u32,
    written: u64,
}

impl<W: Write> LiteralEmitter<W> {
    /// An emitter writing to `out`.
    pub fn new(out: W, dialect: Dialect, options: Options) -> Self {
        let next_n = options.renumber.map_or(0, |r| r.0);
        LiteralEmitter {
            out,
            buf: Vec::with_capacity(CHUNK + 1024),
            line_start: 0,
            dialect,
            options,
            next_n,
            written: 0,
        }
    }

    /// Bytes written so far.
    pub fn written(&self) -> u64 {
        self.written
    }

    fn flush_line(&mut self) -> Result<(), Stop> {
        self.buf.extend_from_slice(self.options.eol.as_bytes());
        let len = (self.buf.len() - self.line_start) as u64;
        if let Err(stop) = self.options.budget.spend(len) {
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

    fn push_word(&mut self, w: &Word, inch: bool) -> Result<(), Alarm> {
        let v = input_value(&self.dialect, self.options.decimal_input, w, inch);
        if !v.is_finite() {
            return Err(Alarm::new(
                111,
                format!("{}: value is not a finite number", w.letter),
            ));
        }
        for &b in w.letter.as_str().as_bytes() {
            self.buf.push(b);
        }
        match self.dialect.kind(w.letter) {
            // The kernel checked the code against the G-code table before the block came here.
            AddressKind::GCode => push_gcode(&mut self.buf, fmsvm_block::code10(v).unwrap_or(0)),
            AddressKind::Integer { max } => push_u64(&mut self.buf, integer(w.letter, v, max)?),
            AddressKind::Linear | AddressKind::Angular | AddressKind::Feed => {
                let digits = self.dialect.digits(w.letter, inch);
                let q = v * POW10[digits as usize];
                let max = POW10[self.dialect.max_digits as usize] - 0.5;
                if q.is_nan() || q.abs() >= max {
                    return Err(Alarm::new(
                        TOO_MANY_DIGITS,
                        format!(
                            "too many digits: {}{v} does not fit {} digit{}",
                            w.letter,
                            self.dialect.max_digits,
                            if self.dialect.max_digits == 1 {
                                ""
                            } else {
                                "s"
                            }
                        ),
                    ));
                }
                push_fixed(&mut self.buf, round_away(q), digits);
            }
        }
        Ok(())
    }
}

impl<W: Write> Emitter for LiteralEmitter<W> {
    fn begin(&mut self, number: Option<u32>, title: &str) -> Result<(), Stop> {
        self.buf.push(b'%');
        self.flush_line()?;
        if let Some(n) = number {
            self.buf.push(b'O');
            let s = format!("{n:04}");
            self.buf.extend_from_slice(s.as_bytes());
            // The program name comment is always kept: the control lists it in its directory.
            let name = comment_words(title);
            if !name.is_empty() {
                self.buf.extend_from_slice(b" (");
                self.buf.extend_from_slice(name.as_bytes());
                self.buf.push(b')');
            }
            self.flush_line()?;
        }
        Ok(())
    }

    fn block(&mut self, block: &Block<'_>, ctx: &Context) -> Result<(), Stop> {
        let has_words = block.words().iter().any(|w| w.letter != Letter::N);
        let comment = self.options.comments && !block.comment.is_empty();
        if !has_words && !comment {
            return Ok(());
        }
        if block.block_delete {
            self.buf.push(b'/');
        }
        let mut first = true;
        if has_words && let Some((start, step)) = self.options.renumber {
            self.buf.push(b'N');
            push_u64(&mut self.buf, self.next_n as u64);
            first = false;
            self.next_n = self.next_n.saturating_add(step);
            if self.next_n > 99_999 {
                self.next_n = start;
            }
        }
        for w in block.words() {
            if w.letter == Letter::N && self.options.renumber.is_some() {
                continue;
            }
            if !first {
                self.buf.push(b' ');
            }
            first = false;
            if let Err(e) = self.push_word(w, ctx.inch) {
                // Nothing of a block that fails reaches the output.
                self.buf.truncate(self.line_start);
                return Err(e.into());
            }
        }
        if comment {
            if !first {
                self.buf.push(b' ');
            }
            push_comments(&mut self.buf, block.comment);
        }
        self.flush_line()
    }

    fn message(&mut self, number: u32, text: &str) -> Result<(), Stop> {
        // Parentheses inside the text would end the comment early.
        let clean: String = text
            .chars()
            .map(|c| if c == '(' || c == ')' { ' ' } else { c })
            .collect();
        let line = format!("M0 (MESSAGE {number}: {})", clean.trim());
        self.buf.extend_from_slice(line.as_bytes());
        self.flush_line()
    }

    fn end(&mut self) -> Result<(), Stop> {
        self.buf.push(b'%');
        self.flush_line()?;
        self.out.write_all(&self.buf)?;
        self.buf.clear();
        self.line_start = 0;
        self.out.flush()?;
        Ok(())
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
fn push_comments(buf: &mut Vec<u8>, text: &str) {
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

impl<W: Write> Drop for LiteralEmitter<W> {
    /// After a stop, the complete lines formatted so far still reach the writer (for `--keep-partial`).
    fn drop(&mut self) {
        if self.line_start > 0 {
            let _ = self.out.write_all(&self.buf[..self.line_start]);
            let _ = self.out.flush();
        }
    }
}
