//! Where AND, OR and XOR bind (macro-b-rules E7). The grammar parses the Fanuc/NCT grouping (AND with
//! `* / MOD`, OR and XOR with `+ -`); for the controls that rank them otherwise the binary chains of an
//! expression are taken apart in their written order and grouped again with that control's levels.

use crate::ast::{BinOp, Expr, Line, VarRef};

/// The level of the logic operators.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub enum LogicLevel {
    /// Fanuc/NCT: AND with `* / MOD`, OR and XOR with `+ -` (`2+3 AND 1` = 3).
    #[default]
    Fanuc,
    /// Rockwell 8520: only `* / MOD` above the rest; AND, OR, XOR with `+ -`, left to right (`2+3 AND 1` = 1).
    Additive,
    /// zappettini, LinuxCNC, Tormach: AND, OR, XOR below `+ -` (`4 OR 1 AND 2` = 0 read left to right).
    Lowest,
}

fn level(op: BinOp, logic: LogicLevel) -> u8 {
    use BinOp::*;
    match (op, logic) {
        (Mul | Div | Mod, _) => 3,
        (And, LogicLevel::Fanuc) => 3,
        (Add | Sub, _) => 2,
        (Or | Xor, LogicLevel::Fanuc) => 2,
        (And | Or | Xor, LogicLevel::Additive) => 2,
        (And | Or | Xor, LogicLevel::Lowest) => 1,
    }
}

/// Regroups every expression of a line.
pub fn regroup_line(line: &mut Line, logic: LogicLevel) {
    if logic == LogicLevel::Fanuc {
        return;
    }
    for w in &mut line.words {
        regroup_in_place(&mut w.value, logic);
    }
    if let Some((s, _)) = line.stmt.as_deref_mut() {
        s.for_each_expr_mut(&mut |e, _| regroup_in_place(e, logic));
    }
}

fn regroup_var(v: &mut VarRef, logic: LogicLevel) {
    if let VarRef::Indirect { addr, .. } = v {
        regroup_in_place(addr, logic);
    }
}

fn regroup_in_place(e: &mut Expr, logic: LogicLevel) {
    let taken = std::mem::replace(
        e,
        Expr::Num(
            crate::lexer::Num {
                value: 0.0,
                point: false,
            },
            e.span(),
        ),
    );
    *e = regroup(taken, logic);
}

/// The expression with its binary chains grouped by `logic`'s levels, inner expressions too.
pub fn regroup(e: Expr, logic: LogicLevel) -> Expr {
    let mut atoms = Vec::new();
    let mut ops = Vec::new();
    flatten(e, logic, &mut atoms, &mut ops);
    let mut atoms = atoms.into_iter();
    let first = atoms.next().unwrap_or(Expr::Num(
        crate::lexer::Num {
            value: 0.0,
            point: false,
        },
        Default::default(),
    ));
    let mut rest: Vec<(BinOp, Expr)> = ops.into_iter().zip(atoms).collect();
    rest.reverse();
    climb(first, &mut rest, 0, logic)
}

/// The written order of a chain: its operands (regrouped inside) and the operators between them.
fn flatten(e: Expr, logic: LogicLevel, atoms: &mut Vec<Expr>, ops: &mut Vec<BinOp>) {
    match e {
        Expr::Bin(op, lr, _) => {
            let [l, r] = *lr;
            flatten(l, logic, atoms, ops);
            ops.push(op);
            flatten(r, logic, atoms, ops);
        }
        other => atoms.push(inner(other, logic)),
    }
}

/// Regroups inside an operand.
fn inner(e: Expr, logic: LogicLevel) -> Expr {
    match e {
        Expr::Group(x, s) => Expr::Group(Box::new(regroup(*x, logic)), s),
        Expr::Neg(x, s) => Expr::Neg(Box::new(inner(*x, logic)), s),
        Expr::Call(f, args, s) => {
            Expr::Call(f, args.into_iter().map(|a| regroup(a, logic)).collect(), s)
        }
        Expr::Cmp(op, ab, s) => {
            let [a, b] = *ab;
            Expr::Cmp(op, Box::new([regroup(a, logic), regroup(b, logic)]), s)
        }
        Expr::Var(mut v) => {
            regroup_var(&mut v, logic);
            Expr::Var(v)
        }
        n @ Expr::Num(..) => n,
        b @ Expr::Bin(..) => regroup(b, logic),
    }
}

/// Precedence climbing over `rest` (reversed: the next operator last), left-associative.
fn climb(mut left: Expr, rest: &mut Vec<(BinOp, Expr)>, min: u8, logic: LogicLevel) -> Expr {
    while let Some(&(op, _)) = rest.last() {
        let l = level(op, logic);
        if l < min {
            break;
        }
        let Some((op, mut right)) = rest.pop() else {
            break;
        };
        while let Some(&(next, _)) = rest.last() {
            if level(next, logic) > l {
                right = climb(right, rest, l + 1, logic);
            } else {
                break;
            }
        }
        let span = left.span().to(right.span());
        left = Expr::Bin(op, Box::new([left, right]), span);
    }
    left
}
