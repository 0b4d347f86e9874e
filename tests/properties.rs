//! Property tests: random well-formed macro programs (expressions with vacant values and alarms, every
//! operator and comparison, indirect `#[…]` reads and writes, loops, forward GOTOs, words, G65 macro
//! calls with arguments and M98 subprogram calls into O-programs of the same file) run on both engines,
//! which must agree (`common::expand` compares them), and random expressions are checked against a tiny
//! direct evaluator written here from the rules.

use crate::common;

use common::{Failure, expand_with};
use fmsvm_compiler::Options;
use fmsvm_emit::literal;
use fmsvm_vm::Limits;
use proptest::prelude::*;

/// An expression as the test knows it.
#[derive(Clone, Debug)]
enum E {
    Num(f64),
    /// `#n`: #1 = 3.5, #2 = -2, #3 = 0, #4 vacant, #0 vacant.
    Var(u8),
    Neg(Box<E>),
    /// `+ - * /`, and `%` MOD, `&` AND, `|` OR, `^` XOR.
    Bin(char, Box<E>, Box<E>),
    F(&'static str, Box<E>),
    /// `#[e]` (only in random programs: the evaluator knows no variables but #1-#4).
    Ind(Box<E>),
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
            // E13: AND/OR/XOR on the 32-bit integer parts.
            let int = |v: f64| -> Result<i64, u32> {
                let t = v.trunc();
                if (-2_147_483_648.0..=4_294_967_295.0).contains(&t) {
                    Ok(t as i64)
                } else {
                    Err(110)
                }
            };
            match op {
                '+' => finite(x + y),
                '-' => finite(x - y),
                '*' => finite(x * y),
                '%' => {
                    if y == 0.0 {
                        Err(112)
                    } else {
                        finite(x % y)
                    }
                }
                '&' => Ok(Some((int(x)? & int(y)?) as f64)),
                '|' => Ok(Some((int(x)? | int(y)?) as f64)),
                '^' => Ok(Some((int(x)? ^ int(y)?) as f64)),
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
            if *f == "SQRT" {
                // Alarm 119: argument out of range.
                return if v < 0.0 {
                    Err(119)
                } else {
                    Ok(Some(v.sqrt()))
                };
            }
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
        E::Ind(_) => unreachable!("the evaluator's expressions have no #[…]"),
    }
}

fn op_text(op: char) -> String {
    match op {
        '%' => " MOD ".into(),
        '&' => " AND ".into(),
        '|' => " OR ".into(),
        '^' => " XOR ".into(),
        c => c.to_string(),
    }
}

/// The expression as Macro B text; binary operations bracketed, so depth ≤ 4 stays within E1's five.
fn text(e: &E) -> String {
    match e {
        E::Num(v) => format!("{v}"),
        E::Var(n) => format!("#{n}"),
        E::Neg(x) => format!("-{}", text(x)),
        E::Bin(op, a, b) => format!("[{}{}{}]", text(a), op_text(*op), text(b)),
        E::F(f, x) => format!("{f}[{}]", text(x)),
        // `#[a+b]`, not `#[[a+b]]`: bracket depth is limited (E1).
        E::Ind(a) => match &**a {
            E::Bin(op, x, y) => format!("#[{}{}{}]", text(x), op_text(*op), text(y)),
            a => format!("#[{}]", text(a)),
        },
    }
}

/// The operators, `+ - *` more often (MOD and `/` by a random operand often divide by zero).
const OPS: [char; 11] = ['+', '-', '*', '+', '-', '*', '/', '%', '&', '|', '^'];

/// An indirect address: mostly a variable that exists (locals, commons), sometimes one that does not.
fn address() -> impl Strategy<Value = E> {
    let base = |b: Vec<f64>| prop::sample::select(b).prop_map(E::Num);
    prop_oneof![
        6 => base(vec![1.0, 2.0, 5.0, 9.0, 26.0, 100.0, 101.0, 500.0]),
        // #1 = 3.5 and #3 = 0 (#4 vacant counts as 0): an address that is rounded.
        3 => (base(vec![1.0, 9.0, 100.0, 500.0]), prop::sample::select(vec![1u8, 3, 4]))
            .prop_map(|(b, v)| E::Bin('+', Box::new(b), Box::new(E::Var(v)))),
        // #40 does not exist, #[100 + #2] is #98, which does not either: alarm 115.
        1 => prop_oneof![
            Just(E::Num(40.0)),
            Just(E::Bin('+', Box::new(E::Num(100.0)), Box::new(E::Var(2)))),
        ],
    ]
}

/// Expressions: every operator and the common functions; with `indirect`, `#[…]` reads too.
/// The bracket levels of an expression's text.
fn levels(e: &E) -> usize {
    match e {
        E::Num(_) | E::Var(_) => 0,
        E::Neg(x) => levels(x),
        E::Bin(_, a, b) => 1 + levels(a).max(levels(b)),
        E::F(_, x) => 1 + levels(x),
        E::Ind(a) => match &**a {
            E::Bin(_, x, y) => 1 + levels(x).max(levels(y)),
            a => 1 + levels(a),
        },
    }
}

/// Expressions of at most `max` bracket levels (brackets nest at most five deep, E1; the context of
/// an expression takes some of them).
fn expr_with(indirect: bool, max: usize) -> BoxedStrategy<E> {
    let mut leaves = vec![
        (-20i32..20).prop_map(|i| E::Num(i as f64)).boxed(),
        (-2000i32..2000)
            .prop_map(|i| E::Num(i as f64 / 100.0))
            .boxed(),
        (0u8..5).prop_map(E::Var).boxed(),
    ];
    if indirect {
        leaves.push(address().prop_map(|a| E::Ind(Box::new(a))).boxed());
    }
    let leaf = prop::strategy::Union::new(leaves);
    leaf.prop_recursive(3, 12, 2, |inner| {
        prop_oneof![
            inner.clone().prop_map(|x| E::Neg(Box::new(x))),
            (
                prop::sample::select(OPS.to_vec()),
                inner.clone(),
                inner.clone()
            )
                .prop_map(|(o, a, b)| E::Bin(o, Box::new(a), Box::new(b))),
            (
                prop::sample::select(vec!["ABS", "FIX", "FUP", "ROUND", "SIN", "COS"]),
                inner.clone()
            )
                .prop_map(|(f, x)| E::F(f, Box::new(x))),
            // SQRT of a negative number is alarm 119 (tests/messages.rs): mostly of an ABS here, so
            // that most programs still run to their end.
            (inner, 0..4u8).prop_map(|(x, k)| {
                let x = if k == 0 { x } else { E::F("ABS", Box::new(x)) };
                E::F("SQRT", Box::new(x))
            }),
        ]
    })
    .prop_filter("brackets nest too deep", move |e| levels(e) <= max)
    .boxed()
}

/// Expressions for the evaluator (the whole right side of an assignment: five levels).
fn expr() -> BoxedStrategy<E> {
    expr_with(false, 5)
}

/// Expressions inside one bracket (a word's value, an argument, one side of a comparison).
fn inner_expr() -> BoxedStrategy<E> {
    expr_with(false, 4)
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

/// A condition of an IF: one comparison, or two joined by AND/OR/XOR (logical, E13).
#[derive(Clone, Debug)]
enum Cond {
    Rel(&'static str, E, E),
    Logic(&'static str, Box<Cond>, Box<Cond>),
}

fn cond() -> impl Strategy<Value = Cond> {
    let rel = |depth| {
        (
            prop::sample::select(vec!["EQ", "NE", "GT", "GE", "LT", "LE"]),
            pexpr(depth),
            pexpr(depth),
        )
            .prop_map(|(op, a, b)| Cond::Rel(op, a, b))
    };
    prop_oneof![
        3 => rel(4),
        // Two comparisons add a bracket level: shallower operands.
        1 => (prop::sample::select(vec!["AND", "OR", "XOR"]), rel(3), rel(3))
            .prop_map(|(op, a, b)| Cond::Logic(op, Box::new(a), Box::new(b))),
    ]
}

fn cond_text(c: &Cond) -> String {
    match c {
        Cond::Rel(op, a, b) => format!("[{} {op} {}]", text(a), text(b)),
        Cond::Logic(op, a, b) => format!("[{} {op} {}]", cond_text(a), cond_text(b)),
    }
}

/// Program expressions: with `#[…]` reads, at most `max` bracket levels.
fn pexpr(max: usize) -> BoxedStrategy<E> {
    expr_with(true, max)
}

/// A statement of a random program (rendered with its own line numbers).
#[derive(Clone, Debug)]
enum S {
    Assign(u32, E),
    /// `#[addr] = e`.
    AssignInd(E, E),
    Words(E, u8),
    /// IF [cond] GOTO to the label that many statements ahead.
    IfSkip(Cond, u8),
    /// A counted WHILE loop with a body.
    Loop(u8, Vec<S>),
    /// `G65 P… L… A[…] …`: a macro call (the callee chosen at render time) with arguments.
    Macro(u8, u8, Vec<(char, E)>),
    /// `M98 P… L…`: a subprogram call.
    Sub(u8, u8),
}

fn stmt() -> impl Strategy<Value = S> {
    let simple = prop_oneof![
        (
            prop::sample::select(vec![1, 2, 3, 4, 5, 100, 101, 500]),
            pexpr(5)
        )
            .prop_map(|(v, e)| S::Assign(v, e)),
        (address(), pexpr(5)).prop_map(|(a, e)| S::AssignInd(a, e)),
        (pexpr(4), 0u8..5).prop_map(|(e, v)| S::Words(e, v)),
        (cond(), 1u8..3).prop_map(|(c, k)| S::IfSkip(c, k)),
        (
            0u8..2,
            1u8..3,
            prop::collection::vec(
                (
                    prop::sample::select(vec!['A', 'B', 'C', 'I', 'J', 'K', 'X', 'Z']),
                    inner_expr()
                ),
                0..4
            )
        )
            .prop_map(|(p, l, args)| S::Macro(p, l, args)),
        (0u8..2, 1u8..3).prop_map(|(p, l)| S::Sub(p, l)),
    ];
    simple.prop_recursive(2, 16, 4, |inner| {
        ((1u8..4), prop::collection::vec(inner, 1..4)).prop_map(|(n, body)| S::Loop(n, body))
    })
}

/// Where a program is rendered: its loop counters, and the programs it may call.
#[derive(Clone, Copy)]
struct At {
    /// The loop counter of depth d is `#(counters + d)`.
    counters: u8,
    /// This program's index among the O-programs (None: the main program); it calls only later ones,
    /// so calls never recurse.
    program: Option<usize>,
    /// How many O-programs the file has.
    programs: usize,
}

impl At {
    /// The program number a call with choice `p` goes to, if there is one to call.
    fn callee(self, p: u8) -> Option<usize> {
        let first = self.program.map_or(0, |i| i + 1);
        let left = self.programs.checked_sub(first).filter(|&n| n > 0)?;
        Some(9001 + first + p as usize % left)
    }
}

fn render(stmts: &[S], depth: u8, at: At, next_label: &mut u32, out: &mut Vec<String>) {
    for (i, s) in stmts.iter().enumerate() {
        match s {
            S::Assign(v, e) => out.push(format!("#{v}={}", text(e))),
            S::AssignInd(a, e) => out.push(format!("#[{}]={}", text(a), text(e))),
            S::Words(e, v) => out.push(format!("G1 X[{}] Y#{v}", text(e))),
            S::IfSkip(c, k) => {
                // Forward to a label after `k` more statements of this list (or its end).
                let target = *next_label;
                *next_label += 1;
                out.push(format!("IF{}GOTO{target}", cond_text(c)));
                let rest = &stmts[i + 1..];
                let (skipped, after) = rest.split_at((*k as usize).min(rest.len()));
                render(skipped, depth, at, next_label, out);
                out.push(format!("N{target} #9=#9+1"));
                render(after, depth, at, next_label, out);
                return;
            }
            S::Loop(n, body) => {
                let d = depth + 1;
                let c = at.counters + d;
                out.push(format!("#{c}=0"));
                out.push(format!("WHILE[#{c} LT {n}]DO{d}"));
                render(body, d, at, next_label, out);
                out.push(format!("#{c}=#{c}+1"));
                out.push(format!("END{d}"));
            }
            S::Macro(p, l, args) => {
                if let Some(o) = at.callee(*p) {
                    let args: String = args
                        .iter()
                        .map(|(letter, e)| format!(" {letter}[{}]", text(e)))
                        .collect();
                    out.push(format!("G65 P{o} L{l}{args}"));
                }
            }
            S::Sub(p, l) => {
                if let Some(o) = at.callee(*p) {
                    out.push(format!("M98 P{o} L{l}"));
                }
            }
        }
    }
}

/// A file: the main program, then O9001, O9002… (each ends with M99 and may call the later ones).
fn program_text(main: &[S], subs: &[Vec<S>]) -> String {
    let mut lines = vec![
        "%".to_string(),
        "O1".to_string(),
        SETUP.trim_end().to_string(),
        "#9=0".to_string(),
    ];
    let mut label = 100;
    let main_at = At {
        counters: 20,
        program: None,
        programs: subs.len(),
    };
    render(main, 0, main_at, &mut label, &mut lines);
    lines.push("M30".into());
    for (i, body) in subs.iter().enumerate() {
        lines.push(format!("O{}", 9001 + i));
        // Counters of their own: M98 shares the caller's locals.
        let at = At {
            counters: 26,
            program: Some(i),
            programs: subs.len(),
        };
        render(body, 0, at, &mut label, &mut lines);
        lines.push("M99".into());
    }
    lines.push("%".into());
    lines.join("\n")
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
}

proptest! {
    // Fewer cases: each program compiles up to three functions with the JIT, slow in a debug build.
    #![proptest_config(ProptestConfig { cases: 80, .. ProptestConfig::default() })]

    #[test]
    fn random_programs_run_alike_on_both_engines(
        main in prop::collection::vec(stmt(), 1..8),
        subs in prop::collection::vec(prop::collection::vec(stmt(), 1..5), 0..3),
    ) {
        let src = program_text(&main, &subs);
        // `run` panics if the engines differ; any outcome (output, alarm, limit) is otherwise fine.
        let _ = run(&src);
    }
}

/// The generator reaches what it claims to: a fixed sample of programs holds every operator,
/// comparison, `#[…]` read and write, G65 with arguments and M98 into the file's O-programs, and they
/// expand on both engines.
#[test]
fn random_programs_cover_every_construct() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
    let mut runner = TestRunner::new_with_rng(
        Config::default(),
        TestRng::from_seed(RngAlgorithm::ChaCha, &[7; 32]),
    );
    let file = (
        prop::collection::vec(stmt(), 1..8),
        prop::collection::vec(prop::collection::vec(stmt(), 1..5), 1..3),
    );
    const N: usize = 40;
    let (mut all, mut ran, mut broken) = (String::new(), 0, 0);
    for _ in 0..N {
        let (main, subs) = file.new_tree(&mut runner).expect("a value").current();
        let src = program_text(&main, &subs);
        match run(&src) {
            Ok(_) => ran += 1,
            Err(Failure::Compile(d)) => {
                eprintln!("does not compile: {d:?}\n{src}");
                broken += 1;
            }
            Err(_) => {}
        }
        all.push_str(&src);
    }
    for needle in [
        " EQ ",
        " NE ",
        " GT ",
        " GE ",
        " LT ",
        " LE ",
        " MOD ",
        " AND ",
        " OR ",
        " XOR ",
        "#[",
        "\n#[",
        "G65 P9001 L",
        "G65 P9002",
        "M98 P9001",
        "M98 P9002",
        "O9002",
    ] {
        assert!(all.contains(needle), "no program has {needle:?}");
    }
    assert!(
        all.contains(" A[") || all.contains(" X["),
        "no G65 arguments"
    );
    assert!(ran > N / 3, "only {ran} of {N} programs ran to their end");
    assert_eq!(broken, 0, "every generated program compiles");
}
