//! The logos lexer for Macro B text and the adapter that splits it into lines (NC blocks) of
//! `(start, Token, end)` triples for the generated parser.
//!
//! Bad input never makes the lexer fail: an unknown character becomes [`Token::Error`] and the line that
//! holds it gets one diagnostic. Comments are not given to the parser; they go to the line's side list,
//! because `#3000=1(MSG)` and the flat output use their text. `DPRNT[…]`/`BPRNT[…]` bodies are free text
//! (`*` is a space, `X#1[53]` a format), so the lexer takes the whole bracketed body as one token.
//! Reading stops at the `%` that closes the program (macro-b-rules L4). A line of the plain subset can
//! be handed on decoded instead of as tokens (`lex_lines`, [`crate::plain`]).

use logos::Logos;

use crate::ast::Func;
use crate::diag::{Diagnostic, alarm};
use crate::span::{FileId, Span};

/// A number as written: its value and whether it had a decimal point.
#[derive(Clone, Copy, PartialEq, Debug)]
pub struct Num {
    /// The value.
    pub value: f64,
    /// Written with a decimal point (`10.`, `.5`).
    pub point: bool,
}

/// The error type the lexer and the grammar's fallible actions share. Lexing errors never reach the
/// parser (they become [`Token::Error`]); the grammar uses it for checks with a message and position.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct LexError {
    /// What is wrong.
    pub message: &'static str,
    /// First byte.
    pub start: usize,
    /// One past the last byte.
    pub end: usize,
}

fn number(lex: &mut logos::Lexer<Token>) -> Num {
    number_value(lex.slice())
}

pub use fmsvm_block::exact_decimal;

/// The value of a number token (`[0-9]+\.?[0-9]*|\.[0-9]+`), bit-identical to `str::parse`
/// (`exact_decimal`, else the parse).
fn number_value(s: &str) -> Num {
    let (mut mant, mut digits, mut frac, mut point) = (0u64, 0u32, 0u32, false);
    for &b in s.as_bytes() {
        if b == b'.' {
            point = true;
            continue;
        }
        if digits < 16 {
            mant = mant * 10 + u64::from(b - b'0');
        }
        if mant > 0 {
            digits += 1;
        }
        frac += u32::from(point);
    }
    let value = exact_decimal(mant, digits, frac)
        .unwrap_or_else(|| s.parse::<f64>().unwrap_or(f64::INFINITY));
    Num { value, point }
}

fn letter(lex: &mut logos::Lexer<Token>) -> u8 {
    lex.slice().as_bytes()[0].to_ascii_uppercase()
}

/// Consumes the bracketed body after `DPRNT`/`BPRNT`, up to its matching `]` on the same line.
fn print_body(lex: &mut logos::Lexer<Token>) -> bool {
    let rest = lex.remainder().as_bytes();
    let mut i = 0;
    while i < rest.len() && (rest[i] == b' ' || rest[i] == b'\t') {
        i += 1;
    }
    if rest.get(i) != Some(&b'[') {
        return false;
    }
    let mut depth = 0usize;
    while i < rest.len() {
        match rest[i] {
            b'[' => depth += 1,
            b']' => {
                depth -= 1;
                if depth == 0 {
                    lex.bump(i + 1);
                    return true;
                }
            }
            b'\n' | b'\r' => break,
            _ => {}
        }
        i += 1;
    }
    false
}

/// The macro words a Fanuc takes by their first two letters, and those words (docs/semantics.md,
/// "Abbreviated macro words"), in capitals only (a lower-case pair is two letters). BIN's `BI` is
/// not among them here: it is NCT's incremental B.
const ABBREVIATED: [(&str, &str); 23] = [
    ("WH", "WHILE"),
    ("GO", "GOTO"),
    ("TH", "THEN"),
    ("EN", "END"),
    ("AN", "AND"),
    ("XO", "XOR"),
    ("SI", "SIN"),
    ("CO", "COS"),
    ("TA", "TAN"),
    ("AS", "ASIN"),
    ("AC", "ACOS"),
    ("AT", "ATAN"),
    ("SQ", "SQRT"),
    ("AB", "ABS"),
    ("RO", "ROUND"),
    ("FI", "FIX"),
    ("FU", "FUP"),
    ("EX", "EXP"),
    ("BC", "BCD"),
    ("DP", "DPRNT"),
    ("BP", "BPRNT"),
    ("PO", "POPEN"),
    ("PC", "PCLOS"),
];

/// The full word a keyword token abbreviates (its text is two letters of it), if it does.
fn abbreviation(tok: Token, slice: &str) -> Option<&'static str> {
    let keyword = matches!(
        tok,
        Token::While
            | Token::Goto
            | Token::Then
            | Token::End
            | Token::And
            | Token::Xor
            | Token::Func(_)
            | Token::Atan
            | Token::Dprnt
            | Token::Bprnt
            | Token::Popen
            | Token::Pclos
    );
    if !keyword || slice.len() < 2 {
        return None;
    }
    let head = slice.get(..2)?.to_ascii_uppercase();
    let (_, full) = ABBREVIATED.iter().find(|(a, _)| *a == head)?;
    // The word written out in full is no abbreviation.
    let written = slice.get(..full.len()).map(str::to_ascii_uppercase);
    (written.as_deref() != Some(*full)).then_some(*full)
}

/// One token of Macro B text. Punctuation and keyword variants are named after what they match.
#[allow(missing_docs)]
#[derive(Logos, Clone, Copy, PartialEq, Debug)]
#[logos(skip r"[ \t\x0c]+")]
#[logos(error = LexError)]
pub enum Token {
    /// End of block: a line end, or `;` as Fanuc prints it.
    #[regex(r"\r\n|\n|\r|;")]
    Eob,
    /// Tape start/end marker.
    #[token("%")]
    Percent,
    /// `( … )` comment (diverted to the side list).
    #[regex(r"\([^)\r\n]*\)")]
    Comment,
    /// `(` without `)` on its line.
    #[regex(r"\([^)\r\n]*", priority = 1)]
    UnclosedComment,
    /// A number literal.
    #[regex(r"[0-9]+\.?[0-9]*|\.[0-9]+", number)]
    Number(Num),
    /// An address letter (upper-cased).
    #[regex(r"[A-Za-z]", letter)]
    Letter(u8),
    /// An address letter with NCT's incremental operator right after it (`XI10`): the letter,
    /// upper-cased. Never Fanuc syntax (check.rs refuses it outside `--input nct`).
    #[regex(r"[XYZABCRUVWxyzabcruvw][Ii]", letter)]
    IncLetter(u8),
    #[token("#")]
    Hash,
    #[token("[")]
    LBracket,
    #[token("]")]
    RBracket,
    #[token(",")]
    Comma,
    #[token("=")]
    Assign,
    #[token("+")]
    Plus,
    #[token("-")]
    Minus,
    #[token("*")]
    Star,
    #[token("/")]
    Slash,
    #[token(":")]
    Colon,
    #[token("EQ", ignore(ascii_case))]
    Eq,
    #[token("NE", ignore(ascii_case))]
    Ne,
    #[token("GT", ignore(ascii_case))]
    Gt,
    #[token("GE", ignore(ascii_case))]
    Ge,
    #[token("LT", ignore(ascii_case))]
    Lt,
    #[token("LE", ignore(ascii_case))]
    Le,
    #[token("MOD", ignore(ascii_case))]
    Mod,
    #[token("AND", ignore(ascii_case))]
    #[token("AN")]
    And,
    #[token("OR", ignore(ascii_case))]
    Or,
    #[token("XOR", ignore(ascii_case))]
    #[token("XO")]
    Xor,
    /// A one-argument function name.
    #[token("SIN", |_| Func::Sin, ignore(ascii_case))]
    #[token("SI", |_| Func::Sin)]
    #[token("COS", |_| Func::Cos, ignore(ascii_case))]
    #[token("CO", |_| Func::Cos)]
    #[token("TAN", |_| Func::Tan, ignore(ascii_case))]
    #[token("TA", |_| Func::Tan)]
    #[token("ASIN", |_| Func::Asin, ignore(ascii_case))]
    #[token("AS", |_| Func::Asin)]
    #[token("ACOS", |_| Func::Acos, ignore(ascii_case))]
    #[token("AC", |_| Func::Acos)]
    #[token("SQRT", |_| Func::Sqrt, ignore(ascii_case))]
    #[token("SQ", |_| Func::Sqrt)]
    #[token("SQR", |_| Func::Sqrt, ignore(ascii_case))]
    #[token("ABS", |_| Func::Abs, ignore(ascii_case))]
    #[token("AB", |_| Func::Abs)]
    #[token("ROUND", |_| Func::Round, ignore(ascii_case))]
    #[token("RO", |_| Func::Round)]
    #[token("RND", |_| Func::Round, ignore(ascii_case))]
    #[token("FIX", |_| Func::Fix, ignore(ascii_case))]
    #[token("FI", |_| Func::Fix)]
    #[token("FUP", |_| Func::Fup, ignore(ascii_case))]
    #[token("FU", |_| Func::Fup)]
    #[token("LN", |_| Func::Ln, ignore(ascii_case))]
    #[token("EXP", |_| Func::Exp, ignore(ascii_case))]
    #[token("EX", |_| Func::Exp)]
    #[token("ADP", |_| Func::Adp, ignore(ascii_case))]
    #[token("BIN", |_| Func::Bin, ignore(ascii_case))]
    #[token("BCD", |_| Func::Bcd, ignore(ascii_case))]
    #[token("BC", |_| Func::Bcd)]
    Func(Func),
    #[token("ATAN", ignore(ascii_case))]
    #[token("AT")]
    #[token("ATN", ignore(ascii_case))]
    Atan,
    #[token("POW", ignore(ascii_case))]
    Pow,
    #[token("WHILE", ignore(ascii_case))]
    #[token("WH")]
    While,
    #[token("DO", ignore(ascii_case))]
    Do,
    #[token("END", ignore(ascii_case))]
    #[token("EN")]
    End,
    #[token("IF", ignore(ascii_case))]
    If,
    #[token("GOTO", ignore(ascii_case))]
    #[token("GO")]
    Goto,
    #[token("THEN", ignore(ascii_case))]
    #[token("TH")]
    Then,
    /// `DPRNT[…]` with its whole body.
    #[token("DPRNT", print_body, ignore(ascii_case))]
    #[token("DP", print_body)]
    Dprnt,
    /// `BPRNT[…]` with its whole body.
    #[token("BPRNT", print_body, ignore(ascii_case))]
    #[token("BP", print_body)]
    Bprnt,
    #[token("POPEN", ignore(ascii_case))]
    #[token("PO")]
    Popen,
    #[token("PCLOS", ignore(ascii_case))]
    #[token("PC")]
    Pclos,
    /// Text the lexer does not know.
    Error,
}

impl std::fmt::Display for Token {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let s = match self {
            Token::Eob => "end of block",
            Token::Percent => "%",
            Token::Comment | Token::UnclosedComment => "comment",
            Token::Number(_) => "number",
            Token::Letter(_) => "address",
            Token::IncLetter(_) => "incremental address",
            Token::Hash => "#",
            Token::LBracket => "[",
            Token::RBracket => "]",
            Token::Comma => ",",
            Token::Assign => "=",
            Token::Plus => "+",
            Token::Minus => "-",
            Token::Star => "*",
            Token::Slash => "/",
            Token::Colon => ":",
            Token::Eq => "EQ",
            Token::Ne => "NE",
            Token::Gt => "GT",
            Token::Ge => "GE",
            Token::Lt => "LT",
            Token::Le => "LE",
            Token::Mod => "MOD",
            Token::And => "AND",
            Token::Or => "OR",
            Token::Xor => "XOR",
            Token::Func(_) => "function",
            Token::Atan => "ATAN",
            Token::Pow => "POW",
            Token::While => "WHILE",
            Token::Do => "DO",
            Token::End => "END",
            Token::If => "IF",
            Token::Goto => "GOTO",
            Token::Then => "THEN",
            Token::Dprnt => "DPRNT",
            Token::Bprnt => "BPRNT",
            Token::Popen => "POPEN",
            Token::Pclos => "PCLOS",
            Token::Error => "unknown character",
        };
        f.write_str(s)
    }
}

/// A `(start, token, end)` triple as the generated parser takes it.
pub type Spanned = (usize, Token, usize);

/// One source line (one NC block) as tokens, with its comments set aside.
#[derive(Debug)]
pub struct LexLine {
    /// The tokens, without comments and without the end of block.
    pub tokens: Vec<Spanned>,
    /// Spans of the comments, parentheses included.
    pub comments: Vec<Span>,
    /// The whole line, for messages.
    pub span: Span,
}

/// The lines of one file.
#[derive(Debug, Default)]
pub struct Lexed {
    /// Lines between the opening and the closing `%` (or the whole file).
    pub lines: Vec<LexLine>,
}

/// Nesting far beyond anything legal (Fanuc allows 5 bracket levels, E1) is refused before parsing,
/// so that no input can make the recursive passes overflow the stack.
const MAX_NESTING: usize = 32;

/// Tokens one line may have (an operator chain this long is also a tree this deep).
const MAX_TOKENS: usize = 2000;

/// A diagnostic when a line nests brackets, or chains signs and functions, deeper than `MAX_NESTING`.
fn too_deep(file: FileId, tokens: &[Spanned]) -> Option<Diagnostic> {
    let (mut depth, mut run) = (0usize, 0usize);
    for &(l, t, r) in tokens {
        match t {
            Token::LBracket => depth += 1,
            Token::RBracket => depth = depth.saturating_sub(1),
            _ => {}
        }
        run = match t {
            Token::Minus | Token::Plus | Token::Func(_) | Token::Atan | Token::Hash => run + 1,
            _ => 0,
        };
        if depth > MAX_NESTING {
            return Some(
                Diagnostic::error(
                    Span::new(file, l, r),
                    Some(alarm::BRACKET_NESTING),
                    format!("brackets nested more than {MAX_NESTING} deep"),
                )
                .note("docs/semantics.md, row E1: at most 5 levels"),
            );
        }
        if run > MAX_NESTING {
            return Some(Diagnostic::error(
                Span::new(file, l, r),
                Some(alarm::FORMAT),
                format!("more than {MAX_NESTING} signs or functions in a row"),
            ));
        }
    }
    if tokens.len() > MAX_TOKENS {
        let (l, _, _) = tokens[0];
        let (_, _, r) = tokens[tokens.len() - 1];
        return Some(
            Diagnostic::error(
                Span::new(file, l, r),
                Some(alarm::FORMAT),
                format!(
                    "a block of {} tokens; at most {MAX_TOKENS} are read",
                    tokens.len()
                ),
            )
            .note("split the expression over several assignments"),
        );
    }
    None
}

/// The message for a `%` that shares its line with NC text.
const PERCENT_INSIDE: &str = "`%` inside a block: the tape marker stands on a line of its own";

/// True when the rest of a line (up to its end of block) holds text other than spaces and comments.
fn text_after(rest: &str) -> bool {
    let mut in_comment = false;
    for c in rest.chars() {
        match c {
            '\n' | '\r' => return false,
            ';' if !in_comment => return false,
            '(' => in_comment = true,
            ')' => in_comment = false,
            c if in_comment || c.is_whitespace() => {}
            _ => return true,
        }
    }
    false
}

/// Splits `text` into lines of tokens. Lexical errors are reported in `diags`; their lines are dropped.
pub fn lex(file: FileId, text: &str, diags: &mut Vec<Diagnostic>) -> Lexed {
    let mut out = Lexed::default();
    lex_with(file, text, diags, &mut |line, _| {
        out.lines.push(LexLine {
            tokens: line.tokens.clone(),
            comments: std::mem::take(&mut line.comments),
            span: line.span,
        })
    });
    out
}

/// Lexes `text` line by line, handing each line to `on_line` as soon as it is complete (so a large
/// file is never held as tokens all at once). The line is lent: its token vector is reused for the next
/// line (one allocation for the whole file); `on_line` may take the comments.
pub fn lex_with(
    file: FileId,
    text: &str,
    diags: &mut Vec<Diagnostic>,
    on_line: &mut dyn FnMut(&mut LexLine, &mut Vec<Diagnostic>),
) {
    lex_lines(file, text, false, diags, &mut |event, diags| {
        if let LexEvent::Tokens(line) = event {
            on_line(line, diags);
        }
    });
}

/// A line as [`lex_lines`] hands it on.
pub enum LexEvent<'a> {
    /// The tokens of a line, lent as `lex_with` lends them.
    Tokens(&'a mut LexLine),
    /// A line of the plain subset, decoded from the text with no tokens.
    Plain(PlainLine<'a>),
}

/// A line in the plain subset ([`crate::plain`]): words only, with at most one comment.
pub struct PlainLine<'a> {
    /// The whole line.
    pub span: Span,
    /// Its words, in order (at least one).
    pub block: &'a fmsvm_block::Block<'static>,
    /// Its comment, parentheses included.
    pub comment: Option<Span>,
    /// A lone N word: a sequence number, no block.
    pub sequence_only: bool,
}

/// The plain line starting at byte `at`, if the line there is one (with a word, no `/`): its end,
/// comment and whether it is a lone N word. Its words are left in `block`.
fn plain_at(
    file: FileId,
    bytes: &[u8],
    at: usize,
    block: &mut fmsvm_block::Block<'static>,
) -> Option<(usize, Option<Span>, bool)> {
    let rest = bytes.get(at..)?;
    // A macro statement (`#`), `%`, `/` and the like are never taken here: no need to find the end.
    if !rest
        .first()
        .is_some_and(|&b| b.is_ascii_uppercase() || matches!(b, b'(' | b' ' | b'\t' | 0x0c))
    {
        return None;
    }
    let end = at + memchr::memchr2(b'\n', b'\r', rest).unwrap_or(rest.len());
    match crate::plain::line(&bytes[at..end], block)? {
        crate::plain::Line::Sequence => Some((end, None, true)),
        crate::plain::Line::Block {
            block_delete: false,
            comment,
        } if !block.is_empty() => Some((
            end,
            comment.map(|(a, b)| Span::new(file, at + a, at + b)),
            false,
        )),
        _ => None,
    }
}

/// The diagnostic for text no token matches: a DPRNT/BPRNT without its bracketed body, or a
/// character the language does not have.
fn not_allowed(file: FileId, text: &str, r: std::ops::Range<usize>) -> Diagnostic {
    let bad = &text[r.clone()];
    let (msg, note) = if bad.to_ascii_uppercase().ends_with("PRNT") {
        (
            "DPRNT/BPRNT needs a bracketed body closed on the same line",
            "write DPRNT[TEXT*#1[53]]",
        )
    } else {
        (
            "character not allowed in a Macro B program",
            "remove it, or put it inside a comment ( )",
        )
    };
    Diagnostic::error(
        Span::new(file, r.start, r.end),
        None,
        format!("{msg}: `{}`", bad.escape_debug()),
    )
    .note(note)
}

/// `lex_with`, and with `plain` on, a line of the plain subset (a CAM file's line) is decoded
/// straight from the text ([`crate::plain::line`]) and handed on as [`LexEvent::Plain`], skipping the
/// tokens.
pub fn lex_lines(
    file: FileId,
    text: &str,
    plain: bool,
    diags: &mut Vec<Diagnostic>,
    on_line: &mut dyn FnMut(LexEvent<'_>, &mut Vec<Diagnostic>),
) {
    let bytes = text.as_bytes();
    let mut block = fmsvm_block::Block::new();
    let mut line_start = plain;
    let mut lexer = Token::lexer(text);
    let mut line = LexLine {
        tokens: Vec::new(),
        comments: Vec::new(),
        span: Span::new(file, 0, 0),
    };
    let mut line_bad = false;
    let mut seen_content = false;
    // The opening `%` of the current line, until the line ends.
    let mut opening: Option<Span> = None;
    let finish = |line: &mut LexLine,
                  bad: &mut bool,
                  end: usize,
                  on_line: &mut dyn FnMut(LexEvent<'_>, &mut Vec<Diagnostic>),
                  diags: &mut Vec<Diagnostic>| {
        if !*bad
            && !line.tokens.is_empty()
            && let Some(d) = too_deep(file, &line.tokens)
        {
            diags.push(d);
            *bad = true;
        }
        line.span.end = end as u32;
        if !*bad && (!line.tokens.is_empty() || !line.comments.is_empty()) {
            on_line(LexEvent::Tokens(line), diags);
        }
        line.tokens.clear();
        line.comments.clear();
        line.span = Span::new(file, end, end);
        *bad = false;
    };
    loop {
        if line_start {
            line_start = false;
            let at = line.span.start as usize;
            if let Some((end, comment, sequence_only)) = plain_at(file, bytes, at, &mut block) {
                seen_content = true;
                on_line(
                    LexEvent::Plain(PlainLine {
                        span: Span::new(file, at, end),
                        block: &block,
                        comment,
                        sequence_only,
                    }),
                    diags,
                );
                // The line's end is the next token.
                lexer.bump(end - at);
            }
        }
        let Some(tok) = lexer.next() else {
            break;
        };
        let r = lexer.span();
        let tok = tok.unwrap_or(Token::Error);
        if let Some(full) = abbreviation(tok, lexer.slice()) {
            diags.push(Diagnostic::warning(
                Span::new(file, r.start, r.start + 2),
                None,
                format!(
                    "`{}` is read as {full}: a Fanuc control takes the first two letters of a macro word for the word",
                    &text[r.start..r.start + 2]
                ),
            ).fix(full));
        }
        match tok {
            Token::Eob => {
                opening = None;
                finish(&mut line, &mut line_bad, r.start, on_line, diags);
                line.span = Span::new(file, r.end, r.end);
                line_start = plain;
            }
            Token::Percent => {
                let here = Span::new(file, r.start, r.end);
                if !seen_content && line.tokens.is_empty() {
                    // The opening tape marker: read on (text after it on its line is an error).
                    seen_content = true;
                    opening = Some(here);
                    line.comments.clear();
                    continue;
                }
                // The closing `%`: nothing after it is read (macro-b-rules L4). It stands on a line
                // of its own; NC text before or after it on that line would be dropped unseen.
                let after = text_after(&text[r.end..]);
                if !line_bad && (!line.tokens.is_empty() || after) {
                    let note = if after {
                        "`%` ends the program: the text after it on this line would not be read"
                    } else {
                        "put `%` on a line of its own after the last block"
                    };
                    diags.push(Diagnostic::error(here, None, PERCENT_INSIDE).note(note));
                    line_bad = true;
                }
                finish(&mut line, &mut line_bad, r.start, on_line, diags);
                return;
            }
            Token::Comment => {
                seen_content = true;
                line.comments.push(Span::new(file, r.start, r.end));
            }
            Token::UnclosedComment => {
                if !line_bad {
                    diags.push(
                        Diagnostic::error(
                            Span::new(file, r.start, r.end),
                            Some(alarm::FORMAT),
                            "comment is not closed: `(` without `)` on this line",
                        )
                        .note("close the comment with `)` before the end of the block"),
                    );
                }
                line_bad = true;
            }
            Token::Error => {
                seen_content = true;
                if !line_bad {
                    diags.push(not_allowed(file, text, r));
                }
                line_bad = true;
            }
            _ => {
                seen_content = true;
                if let Some(at) = opening.take()
                    && !line_bad
                {
                    diags.push(
                        Diagnostic::error(at, None, PERCENT_INSIDE)
                            .note("the opening `%` is followed by NC text on its line; start the program on the next line"),
                    );
                    line_bad = true;
                }
                line.tokens.push((r.start, tok, r.end));
            }
        }
    }
    finish(&mut line, &mut line_bad, text.len(), on_line, diags);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The fast number conversion against `str::parse` on every shape a number token has: 1 to 24
    /// digits, the point anywhere or nowhere, leading and trailing zeros, rounding cases.
    #[test]
    fn number_values_are_the_parse_values() {
        let mut x = 0x2545_f491_4f6c_dd1du64;
        let mut next = |n: u64| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x % n
        };
        let mut texts: Vec<String> = [
            "0",
            "0.",
            ".0",
            "00.000",
            "1",
            "10.",
            ".5",
            "0.1",
            "0.3",
            "123456789012345",
            "1234567890123456",
            "999999999999999.9",
            "0.000000000000001",
            ".0000000000000001",
            "9007199254740993",
            "3.14159265358979323846",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        for _ in 0..200_000 {
            let len = 1 + next(24) as usize;
            let mut t: String = (0..len)
                .map(|_| match next(4) {
                    0 => '0',
                    _ => char::from(b'0' + next(10) as u8),
                })
                .collect();
            if next(3) > 0 {
                t.insert(next(len as u64 + 1) as usize, '.');
            }
            texts.push(t);
        }
        for t in &texts {
            let n = number_value(t);
            let want: f64 = t.parse().expect("a number");
            assert_eq!(n.value.to_bits(), want.to_bits(), "{t}");
            assert_eq!(n.point, t.contains('.'), "{t}");
        }
    }

    fn toks(s: &str) -> Vec<Token> {
        let mut d = Vec::new();
        let l = lex(FileId(0), s, &mut d);
        assert!(d.is_empty(), "{d:?}");
        l.lines
            .into_iter()
            .flat_map(|l| l.tokens.into_iter().map(|t| t.1))
            .collect()
    }

    #[test]
    fn words_without_spaces() {
        let t = toks("G1X#1Y-#2");
        assert_eq!(t.len(), 9);
        assert_eq!(t[0], Token::Letter(b'G'));
        assert!(matches!(
            t[1],
            Token::Number(Num {
                value: 1.0,
                point: false
            })
        ));
        assert_eq!(t[3], Token::Hash);
        assert_eq!(t[6], Token::Minus);
    }

    #[test]
    fn keywords_any_case_and_glued() {
        let t = toks("if[#1le360]goto220");
        assert_eq!(t[0], Token::If);
        assert_eq!(t[4], Token::Le);
        assert_eq!(t[7], Token::Goto);
        let t = toks("WHILE[#2GE-50]DO2");
        assert_eq!(t[4], Token::Ge);
        assert_eq!(t[8], Token::Do);
    }

    #[test]
    fn comments_go_aside_and_percent_ends() {
        let mut d = Vec::new();
        let l = lex(FileId(0), "%\nO1(HEAD)\nG0X1;G1X2\n%\nGARBAGE ä\n", &mut d);
        assert!(d.is_empty());
        assert_eq!(l.lines.len(), 3);
        assert_eq!(l.lines[0].comments.len(), 1);
        assert_eq!(l.lines[0].tokens.len(), 2);
    }

    #[test]
    fn dprnt_body_is_one_token() {
        let t = toks("DPRNT[G1*X#1[53]*Y#2[53]]");
        assert_eq!(t, vec![Token::Dprnt]);
    }

    #[test]
    fn bad_character_is_one_diagnostic() {
        let mut d = Vec::new();
        let l = lex(FileId(0), "G1 X1 ä ö\nG0 X2\n", &mut d);
        assert_eq!(d.len(), 1);
        assert_eq!(l.lines.len(), 1);
    }
}
