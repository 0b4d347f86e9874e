//! Property tests: random well-formed macro programs (expressions with vacant values and alarms, loops,
//! forward GOTOs, words) run on both engines, which must agree (`common::expand` compares them), and
//! random expressions are checked against a tiny direct evaluator written here from the rules.

mod common;

use common::{Failure, expand_with};
use fmsvm_compiler::Options;
use fmsvm_runtime::emit::literal;
use fmsvm_vm::Limits;
use proptest::prelude::*;

/// An expression as the test knows it.
#[derive(Clone, Debug)]
enum E {
    Num(f64),
    /// `#n`: #1 = 3.5, #2 = -2, #3 = 0, #4 vacant, #0 vacant.
    Var(u8),
    Neg(Box<E>),
    Bin(char, Box<E>, Box<E>),
    F(&'static str, Box<E>),
}

fn var_value(n: u8) -> Option<f64> {
    match n {
        1 => Some(3.5),
        2 => Some(-2.0),
        3 => Some(0.0),
        _ => None,
    }
}

/// The direct evaluator: vacant is None; Err is an alarm number.
fn eval(e: &E) -> Result<Option<f64>, u32> {
    let num = |v: Option<f64>| v.unwrap_or(0.0);
    let finite = |r: f64| if r.is_finite() { Ok(Some(r)) } else { Err(111) };
    match e {
        E::Num(v) => Ok(Some(*v)),
        E::Var(n) => Ok(var_value(*n)),
        E::Neg(x) => Ok(eval(x)?.map(|v| -v)),
        E::Bin(op, a, b) => {
            let (x, y) = (num(eval(a)?), num(eval(b)?));
            match op {
                '+' => finite(x + y),
                '-' => finite(x - y),
                '*' => finite(x * y),
                _ => {
                    if y == 0.0 {
                        Err(112)
                    } else {
                        finite(x / y)
                    }
                }
            }
        }
        E::F(f, x) => {
            let v = num(eval(x)?);
            Ok(Some(match *f {
                "ABS" => v.abs(),
                "FIX" => v.trunc(),
                "FUP" => {
                    if v >= 0.0 {
                        v.ceil()
                    } else {
                        v.floor()
                    }
                }
                "ROUND" => v.round(),
                "SIN" => v.to_radians().sin(),
                _ => v.to_radians().cos(),
            }))
        }
    }
}

/// The expression as Macro B text; binary operations bracketed, so depth ≤ 4 stays within E1's five.
fn text(e: &E) -> String {
    match e {
        E::Num(v) => format!("{v}"),
        E::Var(n) => format!("#{n}"),
        E::Neg(x) => format!("-{}", text(x)),
        E::Bin(op, a, b) => format!("[{}{op}{}]", text(a), text(b)),
        E::F(f, x) => format!("{f}[{}]", text(x)),
    }
}

fn expr() -> impl Strategy<Value = E> {
    let leaf = prop_oneof![
        (-20i32..20).prop_map(|i| E::Num(i as f64)),
        (-2000i32..2000).prop_map(|i| E::Num(i as f64 / 100.0)),
        (0u8..5).prop_map(E::Var),
    ];
    leaf.prop_recursive(3, 12, 2, |inner| {
        prop_oneof![
            inner.clone().prop_map(|x| E::Neg(Box::new(x))),
            (
                prop::sample::select(vec!['+', '-', '*', '/']),
                inner.clone(),
                inner.clone()
            )
                .prop_map(|(o, a, b)| E::Bin(o, Box::new(a), Box::new(b))),
            (
                prop::sample::select(vec!["ABS", "FIX", "FUP", "ROUND", "SIN", "COS"]),
                inner
            )
                .prop_map(|(f, x)| E::F(f, Box::new(x))),
        ]
    })
}

const SETUP: &str = "#1=3.5\n#2=-2\n#3=0\n";

fn small() -> Limits {
    Limits {
        max_steps: 20_000,
        max_blocks: 5_000,
        ..Default::default()
    }
}

fn run(src: &str) -> Result<common::Expansion, Failure> {
    expand_with(
        src,
        literal::Options::default(),
        small(),
        Options::default(),
    )
}

/// A statement of a random program (rendered with its own line numbers).
#[derive(Clone, Debug)]
enum S {
    Assign(u8, E),
    Words(E, u8),
    /// IF [a LT b] GOTO to the label that many statements ahead.
    IfSkip(E, E, u8),
    /// A counted WHILE loop with a body.
    Loop(u8, Vec<S>),
}

fn stmt() -> impl Strategy<Value = S> {
    let simple = prop_oneof![
        ((1u8..5), expr()).prop_map(|(v, e)| S::Assign(v, e)),
        (expr(), 0u8..5).prop_map(|(e, v)| S::Words(e, v)),
        (expr(), expr(), 1u8..3).prop_map(|(a, b, k)| S::IfSkip(a, b, k)),
    ];
    simple.prop_recursive(2, 16, 4, |inner| {
        ((1u8..4), prop::collection::vec(inner, 1..4)).prop_map(|(n, body)| S::Loop(n, body))
    })
}

fn render(stmts: &[S], depth: u8, next_label: &mut u32, out: &mut Vec<String>) {
    for (i, s) in stmts.iter().enumerate() {
        match s {
            S::Assign(v, e) => out.push(format!("#{v}={}", text(e))),
            S::Words(e, v) => out.push(format!("G1 X{} Y#{v}", text(e))),
            S::IfSkip(a, b, k) => {
                // Forward to a label after `k` more statements of this list (or its end).
                let target = *next_label;
                *next_label += 1;
                out.push(format!("IF[{} LT {}]GOTO{target}", text(a), text(b)));
                let rest = &stmts[i + 1..];
                let (skipped, after) = rest.split_at((*k as usize).min(rest.len()));
                render(skipped, depth, next_label, out);
                out.push(format!("N{target} #9=#9+1"));
                render(after, depth, next_label, out);
                return;
            }
            S::Loop(n, body) => {
                let d = depth + 1;
                let c = 20 + d;
                out.push(format!("#{c}=0"));
                out.push(format!("WHILE[#{c} LT {n}]DO{d}"));
                render(body, d, next_label, out);
                out.push(format!("#{c}=#{c}+1"));
                out.push(format!("END{d}"));
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, .. ProptestConfig::default() })]

    #[test]
    fn expressions_match_the_direct_evaluator(e in expr()) {
        let src = format!("{SETUP}#100={}\n", text(&e));
        let got = run(&src);
        match eval(&e) {
            Ok(None) => prop_assert!(got.as_ref().is_ok_and(|x| x.var(100).is_none()), "{src}: {:?}", got.map(|x| x.var(100))),
            Ok(Some(want)) => {
                let v = got.as_ref().ok().and_then(|x| x.var(100));
                prop_assert!(v.is_some_and(|v| (v - want).abs() <= 1e-9 * want.abs().max(1.0)), "{src}: got {v:?}, want {want}");
            }
            Err(alarm) => prop_assert!(matches!(got, Err(Failure::Alarm(n, ..)) if n == alarm), "{src}: want alarm {alarm}, got {:?}", got.map(|x| x.text)),
        }
    }

    #[test]
    fn random_programs_run_alike_on_both_engines(stmts in prop::collection::vec(stmt(), 1..8)) {
        let mut lines = vec![SETUP.trim_end().to_string(), "#9=0".to_string()];
        let mut label = 100;
        render(&stmts, 0, &mut label, &mut lines);
        lines.push("M30".into());
        let src = lines.join("\n");
        // `run` panics if the engines differ; any outcome (output, alarm, limit) is otherwise fine.
        let _ = run(&src);
    }
}
