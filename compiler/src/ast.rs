//! The syntax tree of a Macro B program: one [`Line`] per NC block, every node with its [`Span`]; no
//! meaning is attached here (that is `check` and `lower`).

use fmsvm_block::Letter;

pub use crate::ir::{BinOp, CmpOp, Func};
use crate::lexer::Num;
use crate::span::Span;

/// A variable reference `#n` or `#[expr]`.
#[derive(Clone, Debug)]
pub enum VarRef {
    /// `#n` with n as written (checked to be an integer in range by `check`).
    Direct {
        /// The number as written.
        number: Num,
        /// `#n`.
        span: Span,
    },
    /// `#[expr]`.
    Indirect {
        /// The address expression.
        addr: Box<Expr>,
        /// `#[…]`.
        span: Span,
    },
}

impl VarRef {
    /// Where it is.
    pub fn span(&self) -> Span {
        match self {
            VarRef::Direct { span, .. } | VarRef::Indirect { span, .. } => *span,
        }
    }
}

/// An expression.
#[derive(Clone, Debug)]
pub enum Expr {
    /// A number literal.
    Num(Num, Span),
    /// A variable.
    Var(VarRef),
    /// Unary minus.
    Neg(Box<Expr>, Span),
    /// Arithmetic or logic: the operator and its two operands (one allocation for both).
    Bin(BinOp, Box<[Expr; 2]>, Span),
    /// A comparison (only as the condition of IF/WHILE, E9).
    Cmp(CmpOp, Box<[Expr; 2]>, Span),
    /// A function call; `args` has one element except for ATAN2 and POW.
    Call(Func, Vec<Expr>, Span),
    /// `[ expr ]`.
    Group(Box<Expr>, Span),
}

impl Expr {
    /// Where it is.
    pub fn span(&self) -> Span {
        match self {
            Expr::Num(_, s)
            | Expr::Neg(_, s)
            | Expr::Bin(_, _, s)
            | Expr::Cmp(_, _, s)
            | Expr::Call(_, _, s)
            | Expr::Group(_, s) => *s,
            Expr::Var(v) => v.span(),
        }
    }
}

/// Builds `l / r`, taking `ATAN[a]/[b]` as the two-argument arctangent (macro-b-rules E5) rather than a
/// division: the ATAN may be the whole left operand or the right end of a multiplicative chain.
pub fn divide(l: Expr, r: Expr, span: Span) -> Expr {
    fn is_atan1(e: &Expr) -> bool {
        matches!(e, Expr::Call(Func::Atan, a, _) if a.len() == 1 && matches!(a[0], Expr::Group(..)))
    }
    if !matches!(r, Expr::Group(..)) {
        return Expr::Bin(BinOp::Div, Box::new([l, r]), span);
    }
    match l {
        Expr::Call(Func::Atan, mut args, s)
            if args.len() == 1 && matches!(args[0], Expr::Group(..)) =>
        {
            args.push(r);
            Expr::Call(Func::Atan2, args, s.to(span))
        }
        Expr::Neg(inner, s) if is_atan1(&inner) => {
            let e = divide(*inner, r, span);
            Expr::Neg(Box::new(e), s.to(span))
        }
        Expr::Bin(op @ (BinOp::Mul | BinOp::Div | BinOp::And | BinOp::Mod), ab, s)
            if is_atan1(&ab[1]) || matches!(&ab[1], Expr::Neg(i, _) if is_atan1(i)) =>
        {
            let [a, b] = *ab;
            let e = divide(b, r, span);
            Expr::Bin(op, Box::new([a, e]), s.to(span))
        }
        l => Expr::Bin(BinOp::Div, Box::new([l, r]), span),
    }
}

/// One address word as written: `X#1`, `G01`, `,R5.`, `Z[50-#1]`.
#[derive(Clone, Debug)]
pub struct WordAst {
    /// The address.
    pub letter: Letter,
    /// Its value.
    pub value: Expr,
    /// The whole word.
    pub span: Span,
    /// Written with NCT's incremental operator (`XI10`).
    pub incremental: bool,
}

/// Where a GOTO goes.
#[derive(Clone, Debug)]
pub enum GotoTarget {
    /// `GOTOn` with a literal n.
    Seq(u32, Span),
    /// `GOTO#n`, `GOTO[expr]`: computed when it runs.
    Computed(Expr),
}

/// A macro statement (everything that is not NC words).
#[derive(Clone, Debug)]
pub enum Stmt {
    /// `#n=expr`, `#[e]=expr`.
    Assign {
        /// Left side.
        target: VarRef,
        /// Right side.
        value: Expr,
    },
    /// `WHILE[cond]DOm`.
    While {
        /// Condition.
        cond: Expr,
        /// Loop number m as written.
        number: Num,
        /// Span of `DOm`.
        do_span: Span,
    },
    /// `DOm` without WHILE: an endless loop.
    Do {
        /// m as written.
        number: Num,
        /// Span of `DOm`.
        do_span: Span,
    },
    /// `ENDm`.
    End {
        /// m as written.
        number: Num,
        /// Span of `ENDm`.
        span: Span,
    },
    /// `IF[cond]GOTOn`.
    IfGoto {
        /// Condition.
        cond: Expr,
        /// Where to go.
        target: GotoTarget,
    },
    /// `IF[cond]THEN stmt`, or Haas's `IF[cond] #n=…` without THEN (`bare`, macro-b-rules L2).
    IfThen {
        /// Condition.
        cond: Expr,
        /// The one statement.
        then: Box<Stmt>,
        /// Written without THEN.
        bare: bool,
    },
    /// Haas's `IF [cond] <NC block>` without THEN (`IF [#598 NE 1.] G65 P9725`): the block runs
    /// when the condition holds. Fanuc refuses it (macro-b-rules L6).
    IfBlock {
        /// Condition.
        cond: Expr,
        /// The block's words.
        words: Vec<WordAst>,
    },
    /// `IF[cond]THEN` followed by NC words: not allowed (macro-b-rules L6); kept to report it well.
    IfThenWords {
        /// Span of the words.
        span: Span,
    },
    /// `GOTOn`, `GOTO#n`.
    Goto(GotoTarget),
    /// `DPRNT[…]` (`binary` false) or `BPRNT[…]`; `body` is the text between the brackets.
    Print {
        /// BPRNT.
        binary: bool,
        /// Span of the text between the brackets.
        body: Span,
    },
    /// `POPEN`, with NCT's channel number (`POPEN31`) where one is written.
    Popen(Option<Span>),
    /// `PCLOS`, likewise.
    Pclos(Option<Span>),
}

/// The expressions of a statement, written once for the shared and the mutable walk: an indirect
/// target's address, then the value (flagged as an assignment's whole right side), conditions, computed
/// GOTO targets, and the statement after THEN.
macro_rules! walk_exprs {
    ($stmt:expr, $f:expr, $recurse:ident, $($mut:tt)?) => {
        match $stmt {
            Stmt::Assign { target, value } => {
                if let VarRef::Indirect { addr, .. } = target {
                    $f(&$($mut)? **addr, false);
                }
                $f(value, true);
            }
            Stmt::While { cond, .. } => $f(cond, false),
            Stmt::IfGoto { cond, target } => {
                $f(cond, false);
                if let GotoTarget::Computed(e) = target {
                    $f(e, false);
                }
            }
            Stmt::IfBlock { cond, words } => {
                $f(cond, false);
                for w in words {
                    $f(&$($mut)? w.value, false);
                }
            }
            Stmt::IfThen { cond, then, .. } => {
                $f(cond, false);
                then.$recurse($f);
            }
            Stmt::Goto(GotoTarget::Computed(e)) => $f(e, false),
            _ => {}
        }
    };
}

impl Stmt {
    /// Calls `f` on every expression of the statement; the flag says the expression is an
    /// assignment's whole right side.
    pub fn for_each_expr(&self, f: &mut impl FnMut(&Expr, bool)) {
        walk_exprs!(self, f, for_each_expr,);
    }

    /// `for_each_expr` with the expressions open to change.
    pub fn for_each_expr_mut(&mut self, f: &mut impl FnMut(&mut Expr, bool)) {
        walk_exprs!(self, f, for_each_expr_mut, mut);
    }
}

impl Line {
    /// Haas's `IF [cond] <NC block>`: the condition, and the block as a line of its own (the
    /// line's N first, then the words after the condition).
    pub fn guarded(&self) -> Option<(&Expr, Line)> {
        let (Stmt::IfBlock { cond, words }, _) = &**self.stmt.as_ref()? else {
            return None;
        };
        let mut all = self.words.clone();
        all.extend(words.iter().cloned());
        Some((
            cond,
            Line {
                span: self.span,
                block_delete: self.block_delete,
                words: all,
                stmt: None,
                comments: self.comments.clone(),
            },
        ))
    }
}

/// One source line: an NC block, a macro statement, or a program start.
#[derive(Clone, Debug)]
pub struct Line {
    /// The whole line.
    pub span: Span,
    /// Starts with `/`.
    pub block_delete: bool,
    /// NC words (the N word included, first), in order.
    pub words: Vec<WordAst>,
    /// The macro statement, if any.
    /// (Boxed: most lines of a long program are words only, and a program's lines are all held while
    /// it is checked.)
    pub stmt: Option<Box<(Stmt, Span)>>,
    /// Comment spans (parentheses included).
    pub comments: Vec<Span>,
}
