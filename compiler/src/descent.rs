//! A recursive-descent parser for one line, building exactly the tree the LALRPOP grammar
//! (`grammar.lalrpop`) builds: the same nodes, the same spans, `ast::divide` for `/`.
//!
//! It is the fast path, not a second grammar: it answers `None` for anything it is not sure of (an
//! error, DPRNT/BPRNT/POPEN/PCLOS, `IF[…]THEN` before words, very deep nesting), and then the
//! generated parser parses the line again and reports what is wrong. The grammar is LR(1) and so
//! unambiguous: a derivation found here is the derivation.
//!
//! **Its scope:** lines of NC words (letters, `,R` `,C`, NCT's `XI`), numbers, variables, `[…]`
//! expressions with every operator and function, assignments, WHILE/DO/END, GOTO, `IF[…]GOTO` and
//! `IF[…]THEN` with a statement after it. **Its proof:** the tests below compare the two trees on
//! every shipped program, on 20 000 generated lines from a fixed seed, on token soup, and, as a
//! property test (proptest, new seeds every run, in CI with the rest), on generated lines from any
//! seed; a line is either the grammar's tree to the span or handed on. A syntax change is an edit to
//! `grammar.lalrpop`, and to this file only where the change falls in its scope (a new token the
//! descent does not know makes it hand the line on, so the grammar alone is never wrong).

use fmsvm_block::Letter;

use crate::ast::{BinOp, CmpOp, Expr, Func, GotoTarget, Stmt, VarRef, WordAst, divide};
use crate::lexer::{Num, Spanned, Token};
use crate::span::{FileId, Span};

/// What the grammar's `Line` rule returns: block delete, the words, the macro statement.
pub type LineTree = (bool, Vec<WordAst>, Option<(Stmt, Span)>);

/// Deeper than this (brackets, unary signs, functions, IF…THEN) is left to the generated parser,
/// whose stack is on the heap.
const MAX_DEPTH: u32 = 64;

/// The tree of a line the grammar accepts, or None (the caller then runs the generated parser).
pub fn line(file: FileId, tokens: &[Spanned]) -> Option<LineTree> {
    let mut p = Descent {
        file,
        t: tokens,
        i: 0,
        depth: 0,
    };
    let mut block_delete = false;
    if p.peek() == Some(Token::Slash) {
        p.i += 1;
        block_delete = true;
        if let Some(Token::Number(_)) = p.peek() {
            p.i += 1;
        }
    }
    // One place per address letter (a long program holds every line's words at once).
    let letters = tokens
        .iter()
        .filter(|(_, t, _)| matches!(t, Token::Letter(_) | Token::IncLetter(_) | Token::Colon))
        .count();
    let mut words = Vec::with_capacity(letters);
    while let Some(t) = p.peek() {
        let l = p.start();
        let (letter, incremental) = match t {
            Token::Letter(c) => {
                p.i += 1;
                (Letter::from_ascii(c)?, false)
            }
            Token::IncLetter(c) => {
                p.i += 1;
                (Letter::from_ascii(c)?, true)
            }
            Token::Comma => {
                p.i += 1;
                let Some(Token::Letter(c)) = p.peek() else {
                    return None;
                };
                p.i += 1;
                (Letter::comma(c)?, false)
            }
            Token::Colon => {
                p.i += 1;
                let value = p.number()?;
                words.push(WordAst {
                    letter: Letter::O,
                    value,
                    span: p.span(l),
                    incremental: false,
                });
                continue;
            }
            _ => break,
        };
        let value = p.word_value()?;
        words.push(WordAst {
            letter,
            value,
            span: p.span(l),
            incremental,
        });
    }
    let stmt = if p.i < p.t.len() {
        let l = p.start();
        let s = p.statement()?;
        Some((s, p.span(l)))
    } else {
        None
    };
    (p.i == p.t.len()).then_some((block_delete, words, stmt))
}

struct Descent<'a> {
    file: FileId,
    t: &'a [Spanned],
    i: usize,
    depth: u32,
}

impl Descent<'_> {
    fn peek(&self) -> Option<Token> {
        self.t.get(self.i).map(|&(_, t, _)| t)
    }

    /// Where the next token starts (the grammar's `@L`).
    fn start(&self) -> usize {
        self.t.get(self.i).map_or(0, |&(l, _, _)| l)
    }

    /// From `l` to the end of the last token taken (the grammar's `@R`).
    fn span(&self, l: usize) -> Span {
        let r = self.i.checked_sub(1).map_or(l, |j| self.t[j].2);
        Span::new(self.file, l, r)
    }

    /// Takes the next token if it is `t`.
    fn eat(&mut self, t: Token) -> Option<()> {
        (self.peek() == Some(t)).then(|| self.i += 1)
    }

    /// Counts one level of nesting; None past `MAX_DEPTH`.
    fn deeper(&mut self) -> Option<()> {
        self.depth += 1;
        (self.depth <= MAX_DEPTH).then_some(())
    }

    fn num(&mut self) -> Option<(Num, Span)> {
        let &(l, Token::Number(n), r) = self.t.get(self.i)? else {
            return None;
        };
        self.i += 1;
        Some((n, Span::new(self.file, l, r)))
    }

    /// `NumLit`.
    fn number(&mut self) -> Option<Expr> {
        let (n, s) = self.num()?;
        Some(Expr::Num(n, s))
    }

    /// `WordValue`: `Unsigned`, `-Unsigned`, `+Unsigned`.
    fn word_value(&mut self) -> Option<Expr> {
        let l = self.start();
        match self.peek()? {
            Token::Minus => {
                self.i += 1;
                let e = self.unsigned()?;
                Some(Expr::Neg(Box::new(e), self.span(l)))
            }
            Token::Plus => {
                self.i += 1;
                self.unsigned()
            }
            _ => self.unsigned(),
        }
    }

    /// `Unsigned`: a number, a variable, `[Cond]`.
    fn unsigned(&mut self) -> Option<Expr> {
        match self.peek()? {
            Token::Number(_) => self.number(),
            Token::Hash => Some(Expr::Var(self.var()?)),
            Token::LBracket => self.group(),
            _ => None,
        }
    }

    /// `[Cond]`.
    fn group(&mut self) -> Option<Expr> {
        self.deeper()?;
        let l = self.start();
        self.eat(Token::LBracket)?;
        let e = self.cond()?;
        self.eat(Token::RBracket)?;
        self.depth -= 1;
        Some(Expr::Group(Box::new(e), self.span(l)))
    }

    /// `Var`: `#n`, `#[Expr]`.
    fn var(&mut self) -> Option<VarRef> {
        let l = self.start();
        self.eat(Token::Hash)?;
        if let Some((number, _)) = self.num() {
            return Some(VarRef::Direct {
                number,
                span: self.span(l),
            });
        }
        self.deeper()?;
        let gl = self.start();
        self.eat(Token::LBracket)?;
        let e = self.expr()?;
        self.eat(Token::RBracket)?;
        self.depth -= 1;
        let addr = Box::new(Expr::Group(Box::new(e), self.span(gl)));
        Some(VarRef::Indirect {
            addr,
            span: self.span(l),
        })
    }

    /// `Cond`: `Expr RelOp Expr` or `Expr`.
    fn cond(&mut self) -> Option<Expr> {
        let l = self.start();
        let a = self.expr()?;
        let op = match self.peek() {
            Some(Token::Eq) => CmpOp::Eq,
            Some(Token::Ne) => CmpOp::Ne,
            Some(Token::Gt) => CmpOp::Gt,
            Some(Token::Ge) => CmpOp::Ge,
            Some(Token::Lt) => CmpOp::Lt,
            Some(Token::Le) => CmpOp::Le,
            _ => return Some(a),
        };
        self.i += 1;
        let b = self.expr()?;
        Some(Expr::Cmp(op, Box::new([a, b]), self.span(l)))
    }

    /// `Expr`: terms joined by `+ - OR XOR`, left to right.
    fn expr(&mut self) -> Option<Expr> {
        let l = self.start();
        let mut a = self.term()?;
        loop {
            let op = match self.peek() {
                Some(Token::Plus) => BinOp::Add,
                Some(Token::Minus) => BinOp::Sub,
                Some(Token::Or) => BinOp::Or,
                Some(Token::Xor) => BinOp::Xor,
                _ => return Some(a),
            };
            self.i += 1;
            let b = self.term()?;
            a = Expr::Bin(op, Box::new([a, b]), self.span(l));
        }
    }

    /// `Term`: unary operands joined by `* / AND MOD`, left to right (`/` through `divide`).
    fn term(&mut self) -> Option<Expr> {
        let l = self.start();
        let mut a = self.unary()?;
        loop {
            let op = match self.peek() {
                Some(Token::Slash) => None,
                Some(Token::Star) => Some(BinOp::Mul),
                Some(Token::And) => Some(BinOp::And),
                Some(Token::Mod) => Some(BinOp::Mod),
                _ => return Some(a),
            };
            self.i += 1;
            let b = self.unary()?;
            let span = self.span(l);
            a = match op {
                None => divide(a, b, span),
                Some(op) => Expr::Bin(op, Box::new([a, b]), span),
            };
        }
    }

    /// `Unary`: `-Unary`, `+Unary`, `Primary`.
    fn unary(&mut self) -> Option<Expr> {
        let l = self.start();
        match self.peek()? {
            Token::Minus => {
                self.i += 1;
                self.deeper()?;
                let e = self.unary()?;
                self.depth -= 1;
                Some(Expr::Neg(Box::new(e), self.span(l)))
            }
            Token::Plus => {
                self.i += 1;
                self.deeper()?;
                let e = self.unary();
                self.depth -= 1;
                e
            }
            _ => self.primary(),
        }
    }

    /// `Primary`: a number, a variable, `[Cond]`, a function of a primary, ATAN's and POW's forms.
    fn primary(&mut self) -> Option<Expr> {
        let l = self.start();
        match self.peek()? {
            Token::Number(_) => self.number(),
            Token::Hash => Some(Expr::Var(self.var()?)),
            Token::LBracket => self.group(),
            Token::Func(f) => {
                self.i += 1;
                self.deeper()?;
                let a = self.primary()?;
                self.depth -= 1;
                Some(Expr::Call(f, vec![a], self.span(l)))
            }
            Token::Atan => {
                self.i += 1;
                if self.peek() != Some(Token::LBracket) {
                    self.deeper()?;
                    let a = self.primary()?;
                    self.depth -= 1;
                    return Some(Expr::Call(Func::Atan, vec![a], self.span(l)));
                }
                // `ATAN[Cond]` (a primary) or `ATAN[Expr,Expr]`: the token after the first operand
                // decides, as the LR(1) parser's look-ahead does.
                self.deeper()?;
                let gl = self.start();
                self.i += 1;
                let a = self.cond()?;
                let e = match self.peek()? {
                    Token::RBracket => {
                        self.i += 1;
                        let g = Expr::Group(Box::new(a), self.span(gl));
                        Expr::Call(Func::Atan, vec![g], self.span(l))
                    }
                    Token::Comma if !matches!(a, Expr::Cmp(..)) => {
                        self.i += 1;
                        let b = self.expr()?;
                        self.eat(Token::RBracket)?;
                        Expr::Call(Func::Atan2, vec![a, b], self.span(l))
                    }
                    _ => return None,
                };
                self.depth -= 1;
                Some(e)
            }
            Token::Pow => {
                self.i += 1;
                self.deeper()?;
                self.eat(Token::LBracket)?;
                let a = self.expr()?;
                self.eat(Token::Comma)?;
                let b = self.expr()?;
                self.eat(Token::RBracket)?;
                self.depth -= 1;
                Some(Expr::Call(Func::Pow, vec![a, b], self.span(l)))
            }
            _ => None,
        }
    }

    /// `Target` of a GOTO: a whole number, a variable, `[Expr]`.
    fn target(&mut self) -> Option<GotoTarget> {
        match self.peek()? {
            Token::Number(n) => {
                if n.point
                    || n.value.fract() != 0.0
                    || n.value.is_nan()
                    || n.value > u32::MAX as f64
                {
                    return None;
                }
                let (_, s) = self.num()?;
                Some(GotoTarget::Seq(n.value as u32, s))
            }
            Token::Hash => Some(GotoTarget::Computed(Expr::Var(self.var()?))),
            Token::LBracket => {
                self.deeper()?;
                let l = self.start();
                self.i += 1;
                let e = self.expr()?;
                self.eat(Token::RBracket)?;
                self.depth -= 1;
                Some(GotoTarget::Computed(Expr::Group(Box::new(e), self.span(l))))
            }
            _ => None,
        }
    }

    /// `#n=…`, then the rest of an assignment.
    fn assign(&mut self) -> Option<Stmt> {
        let target = self.var()?;
        self.eat(Token::Assign)?;
        let value = self.cond()?;
        Some(Stmt::Assign { target, value })
    }

    /// `[Cond]` of IF and WHILE (the brackets are the statement's, not a group).
    fn condition(&mut self) -> Option<Expr> {
        self.eat(Token::LBracket)?;
        let c = self.cond()?;
        self.eat(Token::RBracket)?;
        Some(c)
    }

    /// `Macro`: every statement but DPRNT/BPRNT/POPEN/PCLOS and `IF[…]THEN` before words.
    fn statement(&mut self) -> Option<Stmt> {
        match self.peek()? {
            Token::Hash => self.assign(),
            Token::While => {
                self.i += 1;
                let cond = self.condition()?;
                let l = self.start();
                self.eat(Token::Do)?;
                let (number, _) = self.num()?;
                Some(Stmt::While {
                    cond,
                    number,
                    do_span: self.span(l),
                })
            }
            Token::Do => {
                let l = self.start();
                self.i += 1;
                let (number, _) = self.num()?;
                Some(Stmt::Do {
                    number,
                    do_span: self.span(l),
                })
            }
            Token::End => {
                let l = self.start();
                self.i += 1;
                let (number, _) = self.num()?;
                Some(Stmt::End {
                    number,
                    span: self.span(l),
                })
            }
            Token::If => {
                self.i += 1;
                self.deeper()?;
                let cond = self.condition()?;
                let s = match self.peek()? {
                    Token::Goto => {
                        self.i += 1;
                        let target = self.target()?;
                        Stmt::IfGoto { cond, target }
                    }
                    Token::Then => {
                        self.i += 1;
                        let then = Box::new(self.statement()?);
                        Stmt::IfThen {
                            cond,
                            then,
                            bare: false,
                        }
                    }
                    Token::Hash => {
                        let then = Box::new(self.assign()?);
                        Stmt::IfThen {
                            cond,
                            then,
                            bare: true,
                        }
                    }
                    _ => return None,
                };
                self.depth -= 1;
                Some(s)
            }
            Token::Goto => {
                self.i += 1;
                Some(Stmt::Goto(self.target()?))
            }
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests;
