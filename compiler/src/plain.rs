//! The plain subset of NC lines: `[/] [N<digits>] {<LETTER><number>}` with a comment, the lines of a
//! CAM file. One decoder, used twice: the flat path (a file of plain lines only runs without compiling)
//! and the compiler (a plain line skips the lexer, the parser and the checks and is packed as a
//! literal block at once). Whatever the decoder accepts, the full grammar reads the same way, with no
//! diagnostic; `tests/flat.rs` and this module's tests hold it to that.

use fmsvm_block::{AddressClass, Block, Code, Letter, MAX_WORDS, Word, WordFlags};

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
///
/// Long on purpose (about 190 lines): one pass over the bytes with its state in locals, the path every
/// line of a CAM file takes (millions a second); split into calls, the state would go through memory.
pub fn line(text: &[u8], block: &mut Block<'_>) -> Option<Line> {
    let mut i = 0;
    // A CR ends a block for the compiler (and ends a comment's text): only a last one, the line's end,
    // is this path's; any other is a byte no rule below accepts.
    let n = text.len() - usize::from(text.last() == Some(&b'\r'));
    let skip = |i: &mut usize| {
        while *i < n && matches!(text[*i], b' ' | b'\t' | 0x0c) {
            *i += 1;
        }
    };
    block.clear();
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
            let close = text[i + 1..n].iter().position(|&b| b == b')')? + i + 1;
            if text[i + 1..close].iter().any(|&b| b == b'(' || b == b'\r') {
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
        // The digits: the mantissa of the first 19 (wrapping beyond, when the count of significant
        // digits already sends the number to the exact parse), the significant ones counted.
        let (mut mant, mut digits) = (0u64, 0u32);
        let mut run = |i: &mut usize| {
            while *i < n && text[*i].is_ascii_digit() {
                mant = mant
                    .wrapping_mul(10)
                    .wrapping_add(u64::from(text[*i] - b'0'));
                digits += u32::from(mant != 0);
                *i += 1;
            }
        };
        run(&mut i);
        let point = i < n && text[i] == b'.';
        let mut frac = 0;
        if point {
            i += 1;
            let at = i;
            run(&mut i);
            frac = (i - at) as u32;
        }
        if digits > 15 {
            digits = u32::MAX;
        }
        let body = &text[start..i];
        if body.is_empty() || body == b"." {
            return None;
        }
        // After a number: a separator, a comment, the next letter, or the end.
        if i < n && !matches!(text[i], b' ' | b'\t' | 0x0c | b'(') && !text[i].is_ascii_uppercase()
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
                let rest = &text[i..n];
                let title = if rest.is_empty() {
                    (i, i)
                } else if rest[0] == b'('
                    && rest.ends_with(b")")
                    && !rest[1..rest.len() - 1]
                        .iter()
                        .any(|&b| matches!(b, b'(' | b')' | b'\r'))
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
                if matches!(
                    Code::of(value),
                    Some(Code::G65 | Code::G66 | Code::G66_1 | Code::G67)
                ) {
                    return None;
                }
                seq_only = false;
            }
            Letter::M => {
                if matches!(Code::of(value), Some(Code::M97 | Code::M98 | Code::M99)) {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ir::{Op, literal};
    use crate::{Options, compile_str};

    /// An O line ends with CR LF in a DOS file: the CR is the line's end, and the title stops before it.
    #[test]
    fn an_o_line_before_a_cr_is_a_program_number() {
        let mut block = Block::new();
        assert!(matches!(
            line(b"O1000\r", &mut block),
            Some(Line::Number(1000, _))
        ));
        let text = b"O12 (A B)\r";
        let Some(Line::Number(12, (a, b))) = line(text, &mut block) else {
            panic!("not an O line");
        };
        assert_eq!(&text[a..b], b"(A B)");
        assert!(line(b"O12 (A\rB)\r", &mut block).is_none());
    }

    /// The codes and numbers the subset leaves to the compiler: calls and their cancel, the return,
    /// a sequence number past N99999, a program number past O9999, a point or a sign where the
    /// compiler refuses one; and their neighbours, which it takes.
    #[test]
    fn calls_and_out_of_range_numbers_are_left_to_the_compiler() {
        let mut block = Block::new();
        for refused in [
            "G65 P1",
            "G66 P1",
            "G66.1 P1",
            "G67",
            "M98 P1",
            "M99",
            "M97 P1",
            "G1 M99",
            "N100000 G1",
            "O10000",
            "G1 N10",
            "M-3",
            "N-1",
            "S10.5",
            "X1.2.3",
            "x5",
            "G1 ;",
            "G1 X1 (A)(B)",
        ] {
            assert!(line(refused.as_bytes(), &mut block).is_none(), "{refused}");
        }
        for taken in [
            "G64 X1",
            "G68 X1",
            "M96",
            "N99999 G1",
            "G1 X-1.5",
            "M30",
            "O9999",
        ] {
            assert!(line(taken.as_bytes(), &mut block).is_some(), "{taken}");
        }
    }

    /// A random line near the subset's edges: words with and without signs, points, leading zeros and
    /// long digit runs, blanks, tabs, a CR here and there, comments, `/`, `%`, bytes outside it.
    fn random_line(seed: &mut u64) -> Vec<u8> {
        let mut next = || {
            *seed ^= *seed << 13;
            *seed ^= *seed >> 7;
            *seed ^= *seed << 17;
            *seed
        };
        let mut s = Vec::new();
        for _ in 0..1 + next() % 5 {
            match next() % 16 {
                0 => s.push(b' '),
                1 => s.push(b"\t\r(/%;#[.-x"[(next() % 11) as usize]),
                2 => s.extend_from_slice(b"(CUT) "),
                _ => {
                    s.push(b"GXYZFNMSRIJPTLOA"[(next() % 16) as usize]);
                    if next() % 4 == 0 {
                        s.push(b'-');
                    }
                    let digits = match next() % 8 {
                        0 => 17 + next() % 8,
                        1 => 0,
                        _ => 1 + next() % 5,
                    };
                    for k in 0..digits {
                        if k > 0 && next() % 5 == 0 {
                            s.push(b'.');
                        }
                        s.push(b'0' + (next() % 10) as u8);
                    }
                    if next() % 6 == 0 {
                        s.push(b'.');
                    }
                }
            }
        }
        s
    }

    /// What the plain decoder makes of a line is what the full grammar makes of it: for every line it
    /// takes, the compiler (every line parsed) reports no error and builds the same words, bit for
    /// bit, with the same comment.
    #[test]
    fn random_lines_read_as_the_grammar_reads_them() {
        let full = Options {
            parse_every_line: true,
            ..Options::default()
        };
        let mut seed = 0x9E37_79B9_7F4A_7C15;
        let (mut taken, mut blocks) = (0, 0);
        for _ in 0..40_000 {
            let text = random_line(&mut seed);
            let mut block = Block::new();
            let Some(kind) = line(&text, &mut block) else {
                continue;
            };
            let Line::Block { comment, .. } = kind else {
                continue;
            };
            if block.is_empty() && comment.is_none() {
                // `/` alone, `/N10`: no block either way.
                continue;
            }
            let Ok(src) = std::str::from_utf8(&text) else {
                continue;
            };
            taken += 1;
            let program = format!("{src}\n#1=1\n");
            let (p, diags, _) = compile_str(&program, &full);
            let Some(p) = p else {
                panic!("{src:?}: the decoder takes it, the compiler refuses it: {diags:?}");
            };
            let f = &p.functions[0];
            let mut words = Vec::new();
            let mut info = None;
            for op in &f.ops {
                match *op {
                    Op::WordConst { letter, flags, k } => words.push(fmsvm_block::Word {
                        letter,
                        flags,
                        value: f.consts[k as usize],
                    }),
                    Op::EmitBlock { info: i } => info = Some(i),
                    Op::LiteralBlock { at } => {
                        let b = literal::block(&f.literals, at).expect("decodes");
                        info = Some(b.info);
                        words.extend(b.map(|w| w.expect("decodes")));
                    }
                    _ => {}
                }
                if info.is_some() {
                    break;
                }
            }
            let Some(info) = info else {
                panic!("{src:?}: the compiler makes no block of it");
            };
            blocks += 1;
            let same = words.len() == block.words().len()
                && words.iter().zip(block.words()).all(|(a, b)| {
                    a.letter == b.letter
                        && a.flags == b.flags
                        && a.value.to_bits() == b.value.to_bits()
                });
            assert!(same, "{src:?}: {words:?} against {:?}", block.words());
            let want = comment.map_or("", |(a, b)| &src[a..b]);
            assert_eq!(p.string(f.infos[info as usize].comment), want, "{src:?}");
        }
        assert!(
            taken > 5_000 && blocks > 5_000,
            "{taken} lines taken, {blocks} blocks"
        );
    }
}
