//! The plain subset of NC lines: `[/] [N<digits>] {<LETTER><number>}` with a comment, the lines of a
//! CAM file. One decoder, used twice: the flat path (a file of plain lines only runs without compiling)
//! and the compiler (a plain line skips the lexer, the parser and the checks and is packed as a
//! literal block at once). Whatever the decoder accepts, the full grammar reads the same way, with no
//! diagnostic; `tests/flat.rs` holds both to that.

use fmsvm_block::{AddressClass, Block, Letter, MAX_WORDS, Word, WordFlags};

use crate::lexer::exact_decimal;

/// What one line is.
pub enum Line {
    /// Nothing to run: a blank line.
    Nothing,
    /// A lone N word: no block, but the line is part of the program.
    Sequence,
    /// `%`.
    Percent,
    /// `O1234 (NAME)`.
    Number(u32, (usize, usize)),
    /// A block: its words are in the block.
    Block {
        /// The line begins with `/`.
        block_delete: bool,
        /// The comment's byte range in the line.
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
pub fn line(text: &[u8], block: &mut Block<'_>) -> Option<Line> {
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
