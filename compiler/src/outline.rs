//! The outline of a program text, for an editor: its programs, sequence numbers, jumps, loops,
//! calls, codes and variables, each with its span. It reads the text with the same parser as
//! `compile` (every line as a tree), so what it finds is what the compiler sees; a line that does
//! not parse gives nothing.

use fmsvm_block::Letter;

use crate::ast::{Expr, GotoTarget, Line, Stmt, VarRef, WordAst};
use crate::diag::Diagnostic;
use crate::lower::{self, FlowCode};
use crate::parse::{self, Event};
use crate::span::{FileId, Span};

/// One thing of the text an editor can point at.
#[derive(Clone, Debug, PartialEq)]
pub enum Item {
    /// A program: its O number (None for lines before the first O word), its O line, and the
    /// whole program (to its last line).
    Program {
        /// O number.
        number: Option<u32>,
        /// The O line.
        span: Span,
        /// The O line to the end of the program's last line.
        whole: Span,
    },
    /// `Nn` first in a block: a sequence number GOTO can jump to.
    Label {
        /// n.
        number: u32,
        /// The N word.
        span: Span,
    },
    /// `GOTOn` (also in `IF[…]GOTOn`), or Haas's `M99 Pn` branch.
    Goto {
        /// n.
        number: u32,
        /// The target as written.
        span: Span,
    },
    /// `DOm` … `ENDm`: a loop, the END where one closes it.
    Loop {
        /// m.
        number: u32,
        /// `DOm` (with its WHILE, the whole statement).
        head: Span,
        /// `ENDm`.
        end: Option<Span>,
    },
    /// A call of program `program` (M98 P, G65 P, G66 P with a literal P, or a code the
    /// parameters bind: G100 → O9010).
    Call {
        /// The program called.
        program: u32,
        /// The calling word (P, or the bound code).
        span: Span,
    },
    /// A G or M code word with a literal value.
    Code {
        /// G or M.
        letter: Letter,
        /// The code as written (`1`, `43.4`).
        value: f64,
        /// The word.
        span: Span,
    },
    /// A function call (`SIN[…]`).
    Function {
        /// The function.
        func: crate::ir::Func,
        /// The call.
        span: Span,
    },
    /// `#n` with a literal n.
    Var {
        /// n.
        number: u32,
        /// `#n`.
        span: Span,
        /// The variable is assigned here.
        write: bool,
    },
}

impl Item {
    /// Where the item is (a program: its O line).
    pub fn span(&self) -> Span {
        match self {
            Item::Program { span, .. }
            | Item::Label { span, .. }
            | Item::Goto { span, .. }
            | Item::Call { span, .. }
            | Item::Code { span, .. }
            | Item::Function { span, .. }
            | Item::Var { span, .. } => *span,
            Item::Loop { head, .. } => *head,
        }
    }
}

/// The items of `text` (file `file`), in source order; the diagnostics of the parse are dropped
/// (the compiler's own check gives them).
pub fn outline(file: FileId, text: &str, options: &crate::Options) -> Vec<Item> {
    let mut items = Vec::new();
    let mut open: Vec<usize> = Vec::new();
    let mut program: Option<(usize, Option<u32>)> = None;
    let mut diags: Vec<Diagnostic> = Vec::new();
    let close = |items: &mut Vec<Item>, program: Option<(usize, Option<u32>)>, end: u32| {
        if let Some((at, _)) = program
            && let Some(Item::Program { whole, .. }) = items.get_mut(at)
        {
            whole.end = whole.end.max(end);
        }
    };
    parse::parse_stream(file, text, false, &mut diags, &mut |event, _| match event {
        Event::Program { number, span, .. } => {
            let end = items.last().map_or(span.end, |i: &Item| i.span().end);
            close(&mut items, program, end);
            open.clear();
            program = Some((items.len(), number));
            items.push(Item::Program {
                number,
                span,
                whole: span,
            });
        }
        Event::Line(line) => {
            let number = program.and_then(|(_, n)| n);
            line_items(&line, options, number, &mut items, &mut open);
            close(&mut items, program, line.span.end);
        }
        Event::Plain(_) => {}
    });
    items
}

/// The items of one line; `open` holds the loops not yet closed (indices into `items`).
fn line_items(
    line: &Line,
    options: &crate::Options,
    program: Option<u32>,
    items: &mut Vec<Item>,
    open: &mut Vec<usize>,
) {
    if let Some(n) = line.words.first().filter(|w| w.letter == Letter::N)
        && let Expr::Num(v, _) = &n.value
        && v.value >= 0.0
        && v.value.fract() == 0.0
    {
        items.push(Item::Label {
            number: v.value as u32,
            span: n.span,
        });
    }
    words_items(&line.words, items);
    let flow = lower::flow_code(&line.words, options.syntax.m97);
    if let Some(callee) = crate::static_callee(line, flow) {
        let p = line.words.iter().find(|w| w.letter == Letter::P);
        items.push(Item::Call {
            program: callee,
            span: p.map_or(line.span, |w| w.span),
        });
    } else if flow.is_none()
        && let Some(c) = lower::code_call(&line.words, &options.calls, program)
    {
        items.push(Item::Call {
            program: c.program,
            span: line.words[c.word].span,
        });
    }
    if options.syntax.haas
        && matches!(flow, Some(FlowCode::Return))
        && let Some(crate::ast::GotoTarget::Seq(n, span)) = crate::check::haas_m99_target(line)
    {
        items.push(Item::Goto { number: n, span });
    }
    let Some(stmt) = line.stmt.as_deref() else {
        return;
    };
    stmt_items(&stmt.0, stmt.1, items, open);
}

fn words_items(words: &[WordAst], items: &mut Vec<Item>) {
    for w in words {
        if matches!(w.letter, Letter::G | Letter::M)
            && let Expr::Num(v, _) = &w.value
        {
            items.push(Item::Code {
                letter: w.letter,
                value: v.value,
                span: w.span,
            });
        }
        expr_vars(&w.value, items);
    }
}

fn stmt_items(stmt: &Stmt, span: Span, items: &mut Vec<Item>, open: &mut Vec<usize>) {
    match stmt {
        Stmt::Assign { target, value } => {
            match target {
                VarRef::Direct { number, span } => {
                    if number.value >= 0.0 && number.value.fract() == 0.0 {
                        items.push(Item::Var {
                            number: number.value as u32,
                            span: *span,
                            write: true,
                        });
                    }
                }
                VarRef::Indirect { addr, .. } => expr_vars(addr, items),
            }
            expr_vars(value, items);
        }
        Stmt::While { number, .. } | Stmt::Do { number, .. } => {
            if let Stmt::While { cond, .. } = stmt {
                expr_vars(cond, items);
            }
            open.push(items.len());
            items.push(Item::Loop {
                number: number.value as u32,
                head: span,
                end: None,
            });
        }
        Stmt::End { number, span } => {
            let m = number.value as u32;
            if let Some(k) = open
                .iter()
                .rposition(|&i| matches!(items[i], Item::Loop { number, .. } if number == m))
            {
                let i = open.remove(k);
                if let Item::Loop { end, .. } = &mut items[i] {
                    *end = Some(*span);
                }
            }
        }
        Stmt::IfGoto { cond, target } => {
            expr_vars(cond, items);
            goto_items(target, items);
        }
        Stmt::Goto(target) => goto_items(target, items),
        Stmt::IfThen { cond, then, .. } => {
            expr_vars(cond, items);
            stmt_items(then, span, items, open);
        }
        Stmt::IfBlock { cond, words } => {
            expr_vars(cond, items);
            words_items(words, items);
        }
        Stmt::IfThenWords { .. } | Stmt::Print { .. } | Stmt::Popen(_) | Stmt::Pclos(_) => {}
    }
}

fn goto_items(target: &GotoTarget, items: &mut Vec<Item>) {
    match target {
        GotoTarget::Seq(n, span) => items.push(Item::Goto {
            number: *n,
            span: *span,
        }),
        GotoTarget::Computed(e) => expr_vars(e, items),
    }
}

/// The variables `e` reads.
fn expr_vars(e: &Expr, items: &mut Vec<Item>) {
    match e {
        Expr::Num(..) => {}
        Expr::Var(VarRef::Direct { number, span }) => {
            if number.value >= 0.0 && number.value.fract() == 0.0 {
                items.push(Item::Var {
                    number: number.value as u32,
                    span: *span,
                    write: false,
                });
            }
        }
        Expr::Var(VarRef::Indirect { addr, .. }) => expr_vars(addr, items),
        Expr::Neg(a, _) | Expr::Group(a, _) => expr_vars(a, items),
        Expr::Bin(_, ab, _) | Expr::Cmp(_, ab, _) => {
            expr_vars(&ab[0], items);
            expr_vars(&ab[1], items);
        }
        Expr::Call(func, args, span) => {
            items.push(Item::Function {
                func: *func,
                span: *span,
            });
            for a in args {
                expr_vars(a, items);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn items(text: &str) -> Vec<Item> {
        outline(FileId(0), text, &crate::Options::default())
    }

    fn at(text: &str, span: Span) -> &str {
        &text[span.start as usize..span.end as usize]
    }

    #[test]
    fn finds_programs_labels_jumps_loops_calls_codes_and_variables() {
        let text = "O1000 (MAIN)\nN10 #1=0\nWHILE[#1LT3]DO1\nG65 P2000 A#1\n#1=#1+1\nEND1\nIF[#1EQ3]GOTO10\nM30\nO2000\nN5 G1 X#1\nM99\n";
        let it = items(text);
        let programs: Vec<(Option<u32>, &str)> = it
            .iter()
            .filter_map(|i| match i {
                Item::Program { number, whole, .. } => Some((*number, at(text, *whole))),
                _ => None,
            })
            .collect();
        assert_eq!(programs[0].0, Some(1000));
        assert!(programs[0].1.starts_with("O1000") && programs[0].1.ends_with("M30"));
        assert_eq!(programs[1].0, Some(2000));
        assert!(programs[1].1.ends_with("M99"));
        assert!(it.contains(&Item::Label {
            number: 10,
            span: Span::new(FileId(0), 13, 16)
        }));
        let goto = it.iter().find_map(|i| match i {
            Item::Goto { number, span } => Some((*number, at(text, *span))),
            _ => None,
        });
        assert_eq!(goto, Some((10, "10")));
        let lp = it.iter().find_map(|i| match i {
            Item::Loop { number, head, end } => {
                Some((*number, at(text, *head), end.map(|e| at(text, e))))
            }
            _ => None,
        });
        assert_eq!(lp, Some((1, "WHILE[#1LT3]DO1", Some("END1"))));
        let call = it.iter().find_map(|i| match i {
            Item::Call { program, span } => Some((*program, at(text, *span))),
            _ => None,
        });
        assert_eq!(call, Some((2000, "P2000")));
        let writes = it
            .iter()
            .filter(|i| {
                matches!(
                    i,
                    Item::Var {
                        number: 1,
                        write: true,
                        ..
                    }
                )
            })
            .count();
        let reads = it
            .iter()
            .filter(|i| {
                matches!(
                    i,
                    Item::Var {
                        number: 1,
                        write: false,
                        ..
                    }
                )
            })
            .count();
        assert_eq!((writes, reads), (2, 5));
        assert!(it.iter().any(|i| matches!(
            i,
            Item::Code {
                letter: Letter::M,
                value: 30.0,
                ..
            }
        )));
    }

    #[test]
    fn nested_loops_pair_each_end_with_its_do_and_broken_lines_give_nothing() {
        let text = "DO1\nDO2\nEND2\nEND1\nG1 X[[\n";
        let loops: Vec<(u32, Option<Span>)> = items(text)
            .into_iter()
            .filter_map(|i| match i {
                Item::Loop { number, end, .. } => Some((number, end)),
                _ => None,
            })
            .collect();
        assert_eq!(loops.len(), 2);
        assert_eq!(at(text, loops[0].1.expect("END1")), "END1");
        assert_eq!(at(text, loops[1].1.expect("END2")), "END2");
    }
}
