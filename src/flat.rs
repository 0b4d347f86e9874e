//! NC-only programs straight from the file to the kernel: a program with no macro statement,
//! variable, call or subprogram (a CAM file) is read a line at a time into one reused `Block`, with
//! no tree and no IR — flat memory and the file's own speed, whatever its length.
//!
//! `scan` decides, by reading the file once, whether every line is in the plain subset whose meaning
//! the compiler would give exactly the same way (see `line`); any other line, anywhere, sends the
//! whole program to the compiler, so diagnostics and behaviour never depend on this path. `run` then
//! reads the file again and hands each block to the machine as the VM would.

use std::fs::File;
use std::io::{self, BufRead, BufReader};
use std::path::{Path, PathBuf};

use fmsvm_block::{
    AddressClass, Block, Flow, Letter, LimitKind, MAX_WORDS, Machine, Stop, Word, WordFlags,
};
use fmsvm_compiler::lexer::exact_decimal;

/// A program that runs without compiling.
#[derive(Clone, Debug)]
pub struct FlatProgram {
    /// The file.
    pub path: PathBuf,
    /// Its O number, if it has one.
    pub number: Option<u32>,
    /// The comments of the O line, as the compiler keeps them (`(NAME)`).
    pub title: String,
    /// The line of the closing `%`, where reading stops (None: the end of the file).
    pub end_line: Option<u32>,
}

/// Where a flat run stopped: the stop, the byte range of the block in the file, the blocks run.
pub struct FlatStop {
    /// Why.
    pub stop: Stop,
    /// First byte of the block.
    pub start: u64,
    /// One past its last byte.
    pub end: u64,
    /// Blocks handed to the machine.
    pub blocks: u64,
}

/// The limits a flat run keeps (the VM's, as far as they apply: a flat program has no branches).
#[derive(Clone, Copy, Debug)]
pub struct FlatLimits {
    /// Most blocks (0: no limit). A flat program takes no branch, so the VM's step and time limits,
    /// which it checks at branches, never stop one either.
    pub max_blocks: u64,
    /// The block-delete switch is on: `/` blocks are skipped.
    pub block_delete: bool,
}

/// What one line is.
enum Line {
    /// Nothing to run: a blank line.
    Nothing,
    /// A lone N word: no block, but the line is part of the program.
    Sequence,
    /// `%`.
    Percent,
    /// `O1234 (NAME)`.
    Number(u32, (usize, usize)),
    /// A block: its words are in the block; `/`; the comment's byte range in the line.
    Block {
        block_delete: bool,
        comment: Option<(usize, usize)>,
    },
}

/// Reads `line` (without its end) into `block`; None when it is not in the plain subset.
///
/// The subset: `[/] [N<digits>] {<LETTER><number>}` with comments `( … )` between words, where a
/// number is `[-]digits[.digits]` or `[-].digits`; a sign only on addresses the compiler takes it on
/// (not N O G M P L), a point only on those that are not whole numbers (G excepted: G54.1); no
/// lower case, no `;`, no comma words, no `#`, `[`, keyword or call (G65 G66 G66.1 G67 M98 M99),
/// at most `MAX_WORDS` words, and an O word only alone on the first line of the program.
fn line(text: &[u8], block: &mut Block<'_>) -> Option<Line> {
    let mut i = 0;
    let n = text.len();
    let skip = |i: &mut usize| {
        while *i < n && matches!(text[*i], b' ' | b'\t' | 0x0c | b'\r') {
            *i += 1;
        }
    };
    block.clear();
    // A CR inside a line ends a block for the compiler (and ends a comment's text): not this path's.
    if text[..n.saturating_sub(1)].contains(&b'\r') {
        return None;
    }
    skip(&mut i);
    if i == n {
        return Some(Line::Nothing);
    }
    if text[i] == b'%' {
        i += 1;
        skip(&mut i);
        return (i == n).then_some(Line::Percent);
    }
    let mut block_delete = false;
    if text[i] == b'/' {
        if text.get(i + 1).is_some_and(u8::is_ascii_digit) {
            return None;
        }
        block_delete = true;
        i += 1;
    }
    let mut comment: Option<(usize, usize)> = None;
    let mut first = true;
    let mut seq_only = true;
    loop {
        skip(&mut i);
        if i == n {
            break;
        }
        let c = text[i];
        if c == b'(' {
            let close = text[i + 1..].iter().position(|&b| b == b')')? + i + 1;
            if text[i + 1..close].contains(&b'(') {
                return None;
            }
            // Several comments are joined by a space, as the compiler joins them.
            comment = Some(match comment {
                None => (i, close + 1),
                Some(_) => return None,
            });
            i = close + 1;
            continue;
        }
        if !c.is_ascii_uppercase() {
            return None;
        }
        let letter = Letter::ALL[(c - b'A') as usize];
        i += 1;
        let negative = text.get(i) == Some(&b'-');
        if negative {
            i += 1;
        }
        let start = i;
        let (mut mant, mut digits, mut frac, mut point) = (0u64, 0u32, 0u32, false);
        while i < n {
            match text[i] {
                b'0'..=b'9' => {
                    if digits < 18 {
                        mant = mant * 10 + (text[i] - b'0') as u64;
                        if point {
                            frac += 1;
                        }
                        if mant > 0 {
                            digits += 1;
                        }
                    } else {
                        // Too long for the fast conversion: the exact parse below.
                        digits = u32::MAX;
                    }
                }
                b'.' if !point => point = true,
                _ => break,
            }
            i += 1;
        }
        let body = &text[start..i];
        if body.is_empty() || body == b"." {
            return None;
        }
        // After a number: a separator, a comment, the next letter, or the end.
        if i < n
            && !matches!(text[i], b' ' | b'\t' | 0x0c | b'\r' | b'(')
            && !text[i].is_ascii_uppercase()
        {
            return None;
        }
        let mut value = match exact_decimal(mant, digits, frac) {
            Some(v) => v,
            None => std::str::from_utf8(body).ok()?.parse::<f64>().ok()?,
        };
        if !value.is_finite() {
            return None;
        }
        if negative {
            value = -value;
        }
        let integer = letter.class() == AddressClass::Integer;
        if negative
            && matches!(
                letter,
                Letter::N | Letter::O | Letter::G | Letter::M | Letter::P | Letter::L
            )
        {
            return None;
        }
        if point && integer {
            return None;
        }
        match letter {
            Letter::O => {
                // Alone on its line (the caller checks that it is the program's first).
                skip(&mut i);
                let rest = &text[i..];
                let title = if rest.is_empty() {
                    (i, i)
                } else if rest[0] == b'('
                    && rest.ends_with(b")")
                    && !rest[1..rest.len() - 1].contains(&b'(')
                    && !rest[1..rest.len() - 1].contains(&b')')
                {
                    (i, n)
                } else {
                    return None;
                };
                if !first || block_delete || negative || value > 9999.0 {
                    return None;
                }
                return Some(Line::Number(value as u32, title));
            }
            Letter::N => {
                if !first || value > 99_999.0 {
                    return None;
                }
            }
            Letter::G => {
                if matches!(fmsvm_block::code10(value), Some(650 | 660 | 661 | 670)) {
                    return None;
                }
                seq_only = false;
            }
            Letter::M => {
                if matches!(fmsvm_block::code10(value), Some(970 | 980 | 990)) {
                    return None;
                }
                seq_only = false;
            }
            _ => seq_only = false,
        }
        first = false;
        let flags = WordFlags(if point { 0 } else { WordFlags::NO_POINT });
        if !block.push(Word {
            letter,
            flags,
            value,
        }) {
            return None;
        }
    }
    if block.words().len() > MAX_WORDS {
        return None;
    }
    if seq_only && !block.is_empty() && comment.is_some() {
        // `N10 (TEXT)`: the comment is the block; a lone N word is not written.
        block.clear();
    }
    if seq_only && comment.is_none() && !block_delete {
        // A lone N word is no block.
        return Some(if block.is_empty() {
            Line::Nothing
        } else {
            Line::Sequence
        });
    }
    if seq_only && comment.is_none() {
        // `/` (and an N): content to the lexer, no block to the compiler.
        block.clear();
    }
    Some(Line::Block {
        block_delete,
        comment,
    })
}

/// The file a line at a time: the line's bytes without its end, and the offset where it starts.
struct Lines {
    input: BufReader<File>,
    buf: Vec<u8>,
    offset: u64,
    number: u32,
}

impl Lines {
    fn open(path: &Path) -> io::Result<Lines> {
        Ok(Lines {
            input: BufReader::with_capacity(1 << 18, File::open(path)?),
            buf: Vec::with_capacity(256),
            offset: 0,
            number: 0,
        })
    }

    /// The next line (None at the end), with its start offset.
    fn next(&mut self) -> io::Result<Option<u64>> {
        self.buf.clear();
        let start = self.offset;
        let got = self.input.read_until(b'\n', &mut self.buf)?;
        if got == 0 {
            return Ok(None);
        }
        self.offset += got as u64;
        self.number += 1;
        if self.buf.last() == Some(&b'\n') {
            self.buf.pop();
        }
        Ok(Some(start))
    }
}

/// Reads `path` once: the program when every line is in the plain subset, else None (the compiler
/// takes it). Files that are not ASCII go to the compiler too (their character set is its to read),
/// also after the closing `%`.
pub fn scan(path: &Path) -> io::Result<Option<FlatProgram>> {
    let mut lines = Lines::open(path)?;
    let mut block = Block::new();
    let mut number = None;
    let mut title = String::new();
    // As the lexer counts it: a line with anything but blanks (a comment, `/`, N) before a `%`
    // makes that `%` the closing one.
    let mut seen = false;
    let mut opened = false;
    // Words (or an O line): a program. Comment lines before the first of them are the tape's
    // leader, which the compiler drops when an O line follows.
    let mut program = false;
    let mut leader = false;
    let mut end_line = None;
    while lines.next()?.is_some() {
        if !lines.buf.is_ascii() {
            return Ok(None);
        }
        match line(&lines.buf, &mut block) {
            None => return Ok(None),
            Some(Line::Nothing) => {}
            Some(Line::Percent) => {
                if seen || opened {
                    // The closing tape mark: nothing after it is read (but it is decoded).
                    end_line = Some(lines.number);
                    break;
                }
                opened = true;
            }
            Some(Line::Number(n, (a, b))) => {
                if program || leader {
                    return Ok(None);
                }
                seen = true;
                program = true;
                number = Some(n);
                title = String::from_utf8_lossy(&lines.buf[a..b]).into_owned();
            }
            Some(Line::Sequence) => {
                seen = true;
                program = true;
            }
            Some(Line::Block { .. }) => {
                seen = true;
                if block.is_empty() {
                    leader |= !program;
                } else {
                    program = true;
                }
            }
        }
    }
    if end_line.is_some() {
        while lines.next()?.is_some() {
            if !lines.buf.is_ascii() {
                return Ok(None);
            }
        }
    }
    if !program {
        // No program in it (a comment is none): the compiler says so.
        return Ok(None);
    }
    Ok(Some(FlatProgram {
        path: path.to_path_buf(),
        number,
        title,
        end_line,
    }))
}

/// Runs `program` on `machine`: each block as the VM hands it over; M02/M30 end it.
pub fn run<M: Machine>(
    program: &FlatProgram,
    machine: &mut M,
    limits: &FlatLimits,
) -> Result<fmsvm_vm::Stats, FlatStop> {
    let io_stop = |e: io::Error, blocks: u64| FlatStop {
        stop: Stop::Io(e),
        start: 0,
        end: 0,
        blocks,
    };
    let mut lines = Lines::open(&program.path).map_err(|e| io_stop(e, 0))?;
    let mut blocks = 0u64;
    let max_blocks = if limits.max_blocks == 0 {
        u64::MAX
    } else {
        limits.max_blocks
    };
    // One block for every line without a comment (the common case: no 1 KiB block per line);
    // a line with a comment gets a block that borrows its text.
    let mut plain: Block<'static> = Block::new();
    loop {
        let start = match lines.next() {
            Ok(Some(s)) => s,
            Ok(None) => break,
            Err(e) => return Err(io_stop(e, blocks)),
        };
        if Some(lines.number) == program.end_line {
            break;
        }
        let text = std::mem::take(&mut lines.buf);
        let parsed = line(&text, &mut plain);
        let at = |stop: Stop, blocks: u64| FlatStop {
            stop,
            start,
            end: start + text.len() as u64 - u64::from(text.last() == Some(&b'\r')),
            blocks,
        };
        match parsed {
            // The opening `%` (the scan found the closing one).
            Some(Line::Percent) => {}
            Some(Line::Number(..)) => {}
            Some(Line::Block {
                block_delete,
                comment,
            }) => {
                if (block_delete && limits.block_delete) || (plain.is_empty() && comment.is_none())
                {
                    lines.buf = text;
                    continue;
                }
                if blocks >= max_blocks {
                    let limit = limits.max_blocks;
                    return Err(at(
                        Stop::Limit {
                            kind: LimitKind::Blocks,
                            limit,
                        },
                        blocks,
                    ));
                }
                let result = match comment {
                    None => {
                        plain.line = lines.number;
                        plain.block_delete = block_delete;
                        machine.block(&plain)
                    }
                    Some((a, b)) => {
                        let mut block = Block::new();
                        for w in plain.words() {
                            block.push(*w);
                        }
                        block.line = lines.number;
                        block.block_delete = block_delete;
                        // ASCII: checked by the scan.
                        block.comment = std::str::from_utf8(&text[a..b]).unwrap_or("");
                        machine.block(&block)
                    }
                };
                match result {
                    Ok(Flow::End) => {
                        blocks += 1;
                        break;
                    }
                    Ok(_) => blocks += 1,
                    Err(stop) => return Err(at(stop, blocks)),
                }
            }
            Some(Line::Nothing | Line::Sequence) => {}
            // The scan read every line; a file changed since is an error, not a guess.
            None => {
                return Err(at(
                    Stop::Io(io::Error::other("the program changed while it ran")),
                    blocks,
                ));
            }
        }
        lines.buf = text;
    }
    // No branch is taken in a flat program: no step, as the VM counts them.
    Ok(fmsvm_vm::Stats { steps: 0, blocks })
}
