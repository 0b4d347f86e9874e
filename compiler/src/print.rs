//! The free text of `DPRNT[…]` and `BPRNT[…]`: literal characters (`*` is a space) and values
//! `#n[ab]` / `#[expr][ab]` (a whole digits, b fraction digits; BPRNT `#n[d]`), macro-b-rules O1–O4.

use crate::ast::{Expr, VarRef};
use crate::diag::{Diagnostic, alarm};
use crate::grammar::ExpressionParser;
use crate::lexer::{self, LexError, Num};
use crate::span::{FileId, Span};

/// One piece of a print statement.
#[derive(Clone, Debug)]
pub enum PrintPiece {
    /// Literal text, `*` already turned into spaces.
    Text(String),
    /// A value with its format.
    Value {
        /// The variable.
        var: VarRef,
        /// DPRNT: whole digits; BPRNT: unused.
        whole: u8,
        /// DPRNT: fraction digits; BPRNT: the scale exponent d.
        frac: u8,
    },
}

/// Parses the body of a DPRNT/BPRNT statement whose token spans `token` (from `DPRNT` to `]`).
pub fn parse_body(
    file: FileId,
    text: &str,
    token: Span,
    binary: bool,
    diags: &mut Vec<Diagnostic>,
) -> Option<Vec<PrintPiece>> {
    let whole_tok = &text[token.start as usize..token.end as usize];
    let open = whole_tok.find('[')?;
    let base = token.start as usize + open + 1;
    let body = &text[base..token.end as usize - 1];
    let b = body.as_bytes();
    let mut pieces = Vec::new();
    let mut lit = String::new();
    let mut i = 0;
    let err = |diags: &mut Vec<Diagnostic>, s: usize, e: usize, msg: String| {
        diags.push(Diagnostic::error(
            Span::new(file, base + s, base + e),
            Some(alarm::FORMAT),
            msg,
        ));
    };
    while i < b.len() {
        match b[i] {
            b'#' => {
                if !lit.is_empty() {
                    pieces.push(PrintPiece::Text(std::mem::take(&mut lit)));
                }
                let start = i;
                i += 1;
                let var = if b.get(i) == Some(&b'[') {
                    let close = matching(b, i)?;
                    let inner_start = base + i + 1;
                    let inner = &text[inner_start..base + close];
                    let e = parse_expr(file, text, inner_start, inner.len(), diags)?;
                    i = close + 1;
                    VarRef::Indirect {
                        addr: Box::new(Expr::Group(
                            Box::new(e),
                            Span::new(file, base + start + 1, base + i),
                        )),
                        span: Span::new(file, base + start, base + i),
                    }
                } else {
                    let d0 = i;
                    while i < b.len() && b[i].is_ascii_digit() {
                        i += 1;
                    }
                    if d0 == i {
                        err(
                            diags,
                            start,
                            i.max(start + 1),
                            "`#` in DPRNT must be followed by a variable number".into(),
                        );
                        return None;
                    }
                    let n: f64 = body[d0..i].parse().ok()?;
                    VarRef::Direct {
                        number: Num {
                            value: n,
                            point: false,
                        },
                        span: Span::new(file, base + start, base + i),
                    }
                };
                // The format [ab] (DPRNT) or [d] (BPRNT).
                if b.get(i) != Some(&b'[') {
                    err(
                        diags,
                        start,
                        i,
                        format!(
                            "{} needs a format after the variable, e.g. #1[53]",
                            if binary { "BPRNT" } else { "DPRNT" }
                        ),
                    );
                    return None;
                }
                let close = matching(b, i)?;
                let digits = &body[i + 1..close];
                let ok_digits = digits.bytes().all(|c| c.is_ascii_digit());
                let (whole, frac) = match (binary, digits.len()) {
                    (false, 2) if ok_digits => {
                        (digits.as_bytes()[0] - b'0', digits.as_bytes()[1] - b'0')
                    }
                    (true, 1) if ok_digits => (0, digits.as_bytes()[0] - b'0'),
                    _ => {
                        err(
                            diags,
                            i,
                            close + 1,
                            format!(
                                "format `[{digits}]`: DPRNT takes [ab] (two digits), BPRNT [d] (one digit)"
                            ),
                        );
                        return None;
                    }
                };
                // O3: a + b from 1 to 8.
                if !binary && !(1..=8).contains(&(whole + frac)) {
                    err(
                        diags,
                        i,
                        close + 1,
                        format!(
                            "format `[{digits}]`: the digits a + b must be 1 to 8 (docs/semantics.md, row O3)"
                        ),
                    );
                    return None;
                }
                i = close + 1;
                pieces.push(PrintPiece::Value { var, whole, frac });
            }
            b'*' => {
                lit.push(' ');
                i += 1;
            }
            _ => {
                // One character (ASCII letters upper-cased, as the control prints them; others as written).
                let c = body[i..].chars().next().unwrap_or(' ');
                lit.push(c.to_ascii_uppercase());
                i += c.len_utf8();
            }
        }
    }
    if !lit.is_empty() {
        pieces.push(PrintPiece::Text(lit));
    }
    Some(pieces)
}

fn matching(b: &[u8], open: usize) -> Option<usize> {
    let mut depth = 0;
    for (k, &c) in b.iter().enumerate().skip(open) {
        match c {
            b'[' => depth += 1,
            b']' => {
                depth -= 1;
                if depth == 0 {
                    return Some(k);
                }
            }
            _ => {}
        }
    }
    None
}

fn parse_expr(
    file: FileId,
    text: &str,
    start: usize,
    len: usize,
    diags: &mut Vec<Diagnostic>,
) -> Option<Expr> {
    let mut lex_diags = Vec::new();
    let slice = &text[start..start + len];
    let lexed = lexer::lex(file, slice, &mut lex_diags);
    if !lex_diags.is_empty() || lexed.lines.len() != 1 {
        diags.push(Diagnostic::error(
            Span::new(file, start, start + len),
            Some(alarm::FORMAT),
            "bad expression in DPRNT",
        ));
        return None;
    }
    let tokens = lexed.lines.into_iter().next()?.tokens;
    let shifted = tokens
        .into_iter()
        .map(|(l, t, r)| Ok::<_, LexError>((l + start, t, r + start)));
    match ExpressionParser::new().parse(file, shifted) {
        Ok(e) => Some(e),
        Err(_) => {
            diags.push(Diagnostic::error(
                Span::new(file, start, start + len),
                Some(alarm::FORMAT),
                "bad expression in DPRNT",
            ));
            None
        }
    }
}
