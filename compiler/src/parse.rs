//! Parses a file a line at a time: lexes it, parses each line (by recursive descent, and what that is
//! unsure of with the generated parser, which reports every error: one bad line gives one diagnostic
//! and the rest still parses), and hands on each line and each program start (`O`/`:` numbers) as an
//! [`Event`] as soon as it is read; `parse_file` collects them into programs of [`Line`]s.

use fmsvm_block::Letter;
use lalrpop_util::ParseError;

use crate::ast::{Expr, Line};
use crate::descent;
use crate::diag::{Diagnostic, alarm};
use crate::grammar::LineParser;
use crate::lexer::{self, LexError, Token};
use crate::span::{FileId, Span};

/// One program of a file: `O1234` and the lines up to the next program number (tests).
#[cfg(test)]
#[derive(Debug)]
pub struct ProgramAst {
    /// The O number, or None for lines before the first O word.
    pub number: Option<u32>,
    /// The `O` line (or the first line).
    #[allow(dead_code)]
    pub span: Span,
    /// Comments of the O line (the program's title).
    pub title: Vec<Span>,
    /// The lines after the O line.
    pub lines: Vec<Line>,
}

/// What the parser hands on, in file order: a program starts, or one of its lines.
pub enum Event<'a> {
    /// `O1234` (or, for lines before the first O word, a program without a number).
    Program {
        /// The O number.
        number: Option<u32>,
        /// The `O` line (or the first line).
        span: Span,
        /// Comments of the O line (the program's title).
        title: Vec<Span>,
    },
    /// A line of the program last started.
    Line(Line),
    /// A plain line of the program last started, decoded with no tree (only when asked for).
    Plain(lexer::PlainLine<'a>),
}

/// Parses one file, handing each program start and each line to `on` as soon as it is parsed, so a
/// long file is never held as a tree. Diagnostics go to `diags`; lines with errors are left out.
/// Comment lines before the first O number are the tape's leader, not a program: they are held back
/// until a line shows whether a program without a number begins there. With `plain` on, a line of the
/// plain subset comes as [`Event::Plain`], never parsed ([`lexer::lex_lines`]).
pub fn parse_stream(
    file: FileId,
    text: &str,
    plain: bool,
    diags: &mut Vec<Diagnostic>,
    on: &mut dyn FnMut(Event<'_>, &mut Vec<Diagnostic>),
) {
    let parser = LineParser::new();
    let mut started = false;
    let mut leader: Vec<Line> = Vec::new();
    // Each line is parsed as soon as it is lexed: the tokens of a large file never pile up.
    lexer::lex_lines(file, text, plain, diags, &mut |event, diags| {
        let ll = match event {
            lexer::LexEvent::Tokens(ll) => ll,
            lexer::LexEvent::Plain(p) => {
                if !started {
                    start_unnumbered(&mut leader, p.span, on, diags);
                    started = true;
                }
                on(Event::Plain(p), diags);
                return;
            }
        };
        let tree = if ll.tokens.is_empty() {
            (false, Vec::new(), None)
        } else if let Some(tree) = descent::line(file, &ll.tokens) {
            // Nearly every line the grammar accepts, by recursive descent: the same tree.
            tree
        } else {
            let end = ll.span.end as usize;
            match parser.parse(file, ll.tokens.iter().copied().map(Ok::<_, LexError>)) {
                Ok(tree) => tree,
                Err(e) => {
                    diags.push(line_error(file, text, &ll.tokens, e, end));
                    return;
                }
            }
        };
        let (block_delete, words, stmt) = tree;
        let line = Line {
            span: ll.span,
            block_delete,
            words,
            stmt: stmt.map(Box::new),
            comments: std::mem::take(&mut ll.comments),
        };
        if let Some(number) = program_number(&line) {
            leader.clear();
            started = true;
            on(
                Event::Program {
                    number: Some(number),
                    span: line.span,
                    title: line.comments,
                },
                diags,
            );
            return;
        }
        if !started {
            if line.words.is_empty() && line.stmt.is_none() {
                leader.push(line);
                return;
            }
            start_unnumbered(&mut leader, line.span, on, diags);
            started = true;
        }
        on(Event::Line(line), diags);
    });
    if !started && !leader.is_empty() {
        let span = leader[0].span;
        start_unnumbered(&mut leader, span, on, diags);
    }
}

/// Starts the program without a number that lines before the first O word make, with the comment
/// lines held back before it.
fn start_unnumbered(
    leader: &mut Vec<Line>,
    span: Span,
    on: &mut dyn FnMut(Event<'_>, &mut Vec<Diagnostic>),
    diags: &mut Vec<Diagnostic>,
) {
    let span = leader.first().map_or(span, |l| l.span);
    on(
        Event::Program {
            number: None,
            span,
            title: Vec::new(),
        },
        diags,
    );
    for l in leader.drain(..) {
        on(Event::Line(l), diags);
    }
}

/// Parses one file into its programs (the whole tree at once: for tests).
#[cfg(test)]
pub fn parse_file(file: FileId, text: &str, diags: &mut Vec<Diagnostic>) -> Vec<ProgramAst> {
    let mut programs: Vec<ProgramAst> = Vec::new();
    parse_stream(file, text, false, diags, &mut |event, _| match event {
        Event::Program {
            number,
            span,
            title,
        } => programs.push(ProgramAst {
            number,
            span,
            title,
            lines: Vec::new(),
        }),
        Event::Line(line) => {
            if let Some(p) = programs.last_mut() {
                p.lines.push(line);
            }
        }
        Event::Plain(_) => {}
    });
    programs
}

/// The program number of an `O1234` / `:1234` line (a line with only that word).
fn program_number(line: &Line) -> Option<u32> {
    if line.stmt.is_some() || line.words.len() != 1 {
        return None;
    }
    let w = &line.words[0];
    match (&w.letter, &w.value) {
        (Letter::O, Expr::Num(n, _)) if !n.point && n.value >= 0.0 && n.value <= 99_999_999.0 => {
            Some(n.value as u32)
        }
        _ => None,
    }
}

fn token_name(t: &str) -> String {
    match t {
        "num" => "a number".into(),
        "letter" => "an address".into(),
        "func" => "a function".into(),
        _ => format!("`{}`", t.trim_matches('"')),
    }
}

fn describe(t: &Token) -> String {
    match t {
        Token::Number(n) => format!("number {}", n.value),
        Token::Letter(c) => format!("address `{}`", *c as char),
        Token::Func(f) => format!("function {}", f.name()),
        _ => format!("`{t}`"),
    }
}

/// The relational operators (macro-b-rules E2).
const RELATIONAL: [&str; 6] = ["EQ", "NE", "GT", "GE", "LT", "LE"];

/// What a word that starts like a relational operator was probably meant to be: `LTE` → `LE`.
fn meant_operator(word: &str) -> Option<&'static str> {
    let w = word.to_ascii_uppercase();
    let known = match w.as_str() {
        "LTE" | "LTEQ" | "LEQ" => Some("LE"),
        "GTE" | "GTEQ" | "GEQ" => Some("GE"),
        "NEQ" | "NEQU" => Some("NE"),
        "EQU" | "EQL" | "EQUAL" | "EQQ" => Some("EQ"),
        _ => None,
    };
    known.or_else(|| RELATIONAL.iter().copied().find(|op| w.starts_with(op)))
}

/// The diagnostic for a line the grammar refused, with what the text suggests was meant.
fn line_error(
    file: FileId,
    text: &str,
    tokens: &[lexer::Spanned],
    e: ParseError<usize, Token, LexError>,
    end: usize,
) -> Diagnostic {
    let eof = matches!(e, ParseError::UnrecognizedEof { .. });
    let mut d = parse_error(file, e, end);
    let bytes = text.as_bytes();
    let at = d.span.start as usize;
    let before = |i: usize| i.checked_sub(1).and_then(|j| bytes.get(j)).copied();
    // `LTE`: a run of letters that begins with a relational operator, refused at a later letter.
    if !eof && bytes.get(at).is_some_and(u8::is_ascii_alphabetic) {
        let mut start = at;
        while before(start).is_some_and(|b| b.is_ascii_alphabetic()) {
            start -= 1;
        }
        let mut stop = at;
        while bytes.get(stop).is_some_and(u8::is_ascii_alphabetic) {
            stop += 1;
        }
        let word = &text[start..stop];
        let op_first = tokens.iter().any(|&(l, t, r)| {
            l == start
                && r <= at
                && matches!(
                    t,
                    Token::Eq | Token::Ne | Token::Gt | Token::Ge | Token::Lt | Token::Le
                )
        });
        if op_first
            && word.len() >= 3
            && let Some(op) = meant_operator(word)
        {
            return Diagnostic::error(
                Span::new(file, start, stop),
                Some(alarm::FORMAT),
                format!(
                    "format error: `{}` is not an operator; did you mean `{op}`?",
                    word.to_ascii_uppercase()
                ),
            )
            .note("the relational operators are EQ NE GT GE LT LE (docs/semantics.md, row E2)")
            .fix(op);
        }
    }
    // An unclosed `[`: point at the bracket the block failed to match.
    let limit = if eof { end } else { at };
    let mut open: Vec<usize> = Vec::new();
    for &(l, t, _) in tokens.iter().take_while(|&&(l, _, _)| l < limit) {
        match t {
            Token::LBracket => open.push(l),
            Token::RBracket => {
                open.pop();
            }
            _ => {}
        }
    }
    if !eof
        && open.is_empty()
        && tokens
            .iter()
            .any(|&(l, t, _)| l == at && t == Token::RBracket)
    {
        d = d.note("no `[` is open here: this `]` closes nothing");
    }
    if let Some(&bracket) = open.last() {
        let wanted_close = d.notes.iter().any(|n| n.contains("`]`"));
        if eof {
            let mut notes = std::mem::take(&mut d.notes);
            notes.insert(
                0,
                "brackets close on the same line: write the `]` that ends this one".into(),
            );
            return Diagnostic {
                notes,
                ..Diagnostic::error(
                    Span::new(file, bracket, bracket + 1),
                    Some(alarm::FORMAT),
                    "format error: `[` is not closed: the block ends before its `]`",
                )
            };
        }
        if wanted_close {
            let line_start = text[..bracket].rfind(['\n', '\r']).map_or(0, |i| i + 1);
            let col = text[line_start..bracket].chars().count() + 1;
            d = d.note(format!("the `[` at column {col} is not closed"));
        }
    }
    // `XI10`: NCT's incremental operator, `I` right after an axis address letter.
    let prev = before(at);
    if matches!(bytes.get(at), Some(b'I' | b'i'))
        && let Some(axis) = prev.filter(|b| b"XYZABCUVWxyzabcuvw".contains(b))
        && !before(at - 1).is_some_and(|b| b.is_ascii_alphabetic())
    {
        let axis = axis.to_ascii_uppercase() as char;
        let digits: String = text[at + 1..]
            .chars()
            .take_while(|c| c.is_ascii_digit() || matches!(c, '.' | '-' | '+'))
            .collect();
        let value = if digits.is_empty() { "…" } else { &digits };
        d = d.note(format!(
            "`{axis}I{digits}` is NCT's incremental operator; fmsvm reads Fanuc syntax, where the increment is written G91 {axis}{value}"
        ));
    }
    d
}

fn parse_error(file: FileId, e: ParseError<usize, Token, LexError>, line_end: usize) -> Diagnostic {
    // LALRPOP lists no token when only the end of the block may follow.
    let expected_note = |expected: &[String]| {
        let mut names: Vec<String> = expected.iter().map(|t| token_name(t)).collect();
        names.sort();
        names.dedup();
        if names.is_empty() {
            "this cannot continue the block: a block holds NC words or one macro statement"
                .to_string()
        } else {
            format!("expected {}", names.join(", "))
        }
    };
    match e {
        ParseError::UnrecognizedToken {
            token: (l, t, r),
            expected,
        } => Diagnostic::error(
            Span::new(file, l, r),
            Some(alarm::FORMAT),
            format!("format error: unexpected {}", describe(&t)),
        )
        .note(expected_note(&expected)),
        ParseError::UnrecognizedEof { location, expected } => Diagnostic::error(
            Span::new(file, location.min(line_end).saturating_sub(1), line_end),
            Some(alarm::FORMAT),
            "format error: the block ends too early",
        )
        .note(expected_note(&expected)),
        ParseError::User { error } => Diagnostic::error(
            Span::new(file, error.start, error.end),
            Some(alarm::FORMAT),
            format!("format error: {}", error.message),
        ),
        ParseError::ExtraToken { token: (l, t, r) } => Diagnostic::error(
            Span::new(file, l, r),
            Some(alarm::FORMAT),
            format!("format error: unexpected {}", describe(&t)),
        )
        .note(expected_note(&[])),
        ParseError::InvalidToken { location } => Diagnostic::error(
            Span::new(file, location, location + 1),
            Some(alarm::FORMAT),
            "format error: invalid token",
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ast::{BinOp, Func, Stmt};

    fn one(src: &str) -> Line {
        let mut d = Vec::new();
        let mut p = parse_file(FileId(0), src, &mut d);
        assert!(d.is_empty(), "{d:?}");
        p.remove(0).lines.remove(0)
    }

    #[test]
    fn precedence_groups_and_before_plus() {
        // E7: `2+3 AND 1` is 2+[3 AND 1].
        let l = one("#1=2+3 AND 1");
        let Some((Stmt::Assign { value, .. }, _)) = l.stmt.map(|s| *s) else {
            panic!()
        };
        let Expr::Bin(BinOp::Add, ab, _) = value else {
            panic!("{value:?}")
        };
        assert!(matches!(ab[1], Expr::Bin(BinOp::And, ..)));
    }

    #[test]
    fn atan_slash_form_is_two_argument() {
        let l = one("#1=ATAN[1]/[-1]");
        let Some((Stmt::Assign { value, .. }, _)) = l.stmt.map(|s| *s) else {
            panic!()
        };
        assert!(matches!(value, Expr::Call(Func::Atan2, ref a, _) if a.len() == 2));
        let l = one("#1=2*ATAN[1]/[2]");
        let Some((Stmt::Assign { value, .. }, _)) = l.stmt.map(|s| *s) else {
            panic!()
        };
        let Expr::Bin(BinOp::Mul, ab, _) = value else {
            panic!()
        };
        assert!(matches!(ab[1], Expr::Call(Func::Atan2, ..)));
        // A plain bracket division stays a division.
        let l = one("#1=[1]/[2]");
        let Some((Stmt::Assign { value, .. }, _)) = l.stmt.map(|s| *s) else {
            panic!()
        };
        assert!(matches!(value, Expr::Bin(BinOp::Div, ..)));
    }

    #[test]
    fn programs_split_at_o_numbers() {
        let mut d = Vec::new();
        let p = parse_file(
            FileId(0),
            "%\nO1(MAIN)\nG0X1\nM30\nO1000\nG1X2\nM99\n%\n",
            &mut d,
        );
        assert!(d.is_empty());
        assert_eq!(p.len(), 2);
        assert_eq!(p[0].number, Some(1));
        assert_eq!(p[0].title.len(), 1);
        assert_eq!(p[1].lines.len(), 2);
    }

    #[test]
    fn nct_incremental_operator_is_one_word() {
        // `XI10` is X with NCT's incremental operator (check.rs decides whether the syntax allows it).
        let mut d = Vec::new();
        let p = parse_file(FileId(0), "G81 XI10 Y50\n", &mut d);
        assert!(d.is_empty(), "{d:?}");
        let w = &p[0].lines[0].words;
        assert_eq!(w[1].letter, Letter::X);
        assert!(w[1].incremental && !w[2].incremental);
    }

    #[test]
    fn one_diagnostic_per_bad_line() {
        let mut d = Vec::new();
        let p = parse_file(FileId(0), "G1 X\n#1=[2+\nG0 X1\n", &mut d);
        assert_eq!(d.len(), 2);
        assert_eq!(p[0].lines.len(), 1);
        assert_eq!(d[0].alarm, Some(114));
    }
}
