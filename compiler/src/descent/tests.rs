use super::*;
use crate::grammar::LineParser;
use crate::lexer::{self, LexError};

/// Every line of `text`: the descent's tree (when it gives one) against the grammar's, by their
/// debug text (every node and span). Returns the number of lines, the number the descent took, and
/// the lines the grammar accepted and the descent left to it.
fn compare(text: &str) -> (usize, usize, Vec<String>) {
    let parser = LineParser::new();
    let file = FileId(0);
    let mut diags = Vec::new();
    let (mut lines, mut taken, mut declined) = (0, 0, Vec::new());
    lexer::lex_with(file, text, &mut diags, &mut |ll, _| {
        if ll.tokens.is_empty() {
            return;
        }
        lines += 1;
        let reference = parser.parse(file, ll.tokens.iter().copied().map(Ok::<_, LexError>));
        let src = &text[ll.span.start as usize..ll.span.end as usize];
        match (line(file, &ll.tokens), reference) {
            (Some(tree), Ok(r)) => {
                taken += 1;
                assert_eq!(format!("{tree:?}"), format!("{r:?}"), "line {src:?}");
            }
            (Some(_), Err(e)) => {
                panic!("the descent took {src:?}, the grammar refused it: {e:?}")
            }
            (None, Ok(_)) => declined.push(src.to_string()),
            (None, Err(_)) => {}
        }
    });
    (lines, taken, declined)
}

/// The forms the descent hands to the generated parser on purpose.
fn handed_on(line: &str) -> bool {
    let l = line.to_ascii_uppercase();
    ["DPRNT", "BPRNT", "POPEN", "PCLOS"]
        .iter()
        .any(|k| l.contains(k))
        || l.split("THEN").skip(1).any(|rest| {
            rest.trim_start()
                .bytes()
                .next()
                .is_some_and(|b| b.is_ascii_alphabetic() || b == b',' || b == b':')
                && !["IF", "GOTO", "WHILE", "DO", "END"]
                    .iter()
                    .any(|k| rest.trim_start().starts_with(k))
        })
}

struct Rng(u64);

impl Rng {
    fn below(&mut self, n: usize) -> usize {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 % n as u64) as usize
    }

    fn pick<'a>(&mut self, xs: &[&'a str]) -> &'a str {
        xs[self.below(xs.len())]
    }
}

fn number(r: &mut Rng) -> String {
    r.pick(&[
        "0", "1", "12", "2.5", ".5", "10.", "007", "3.14159", "100000",
    ])
    .to_string()
}

fn var(r: &mut Rng, depth: u32) -> String {
    if depth > 3 || r.below(4) > 0 {
        format!(
            "#{}",
            r.pick(&["1", "2", "24", "100", "500", "5001", "1.5"])
        )
    } else {
        format!("#[{}]", expr(r, depth + 1))
    }
}

fn primary(r: &mut Rng, depth: u32) -> String {
    let leaf = depth > 3;
    match r.below(if leaf { 2 } else { 8 }) {
        0 => number(r),
        1 => var(r, depth),
        2 => format!("[{}]", cond(r, depth + 1)),
        3 => format!(
            "{}{}",
            r.pick(&[
                "SIN", "COS", "SQRT", "ABS", "FIX", "FUP", "ROUND", "SQR", "ATAN"
            ]),
            primary(r, depth + 1)
        ),
        4 => format!("ATAN[{}]/[{}]", expr(r, depth + 1), expr(r, depth + 1)),
        5 => format!("ATAN[{},{}]", expr(r, depth + 1), expr(r, depth + 1)),
        6 => format!("POW[{},{}]", expr(r, depth + 1), expr(r, depth + 1)),
        _ => format!("-{}", primary(r, depth + 1)),
    }
}

fn expr(r: &mut Rng, depth: u32) -> String {
    let mut s = primary(r, depth);
    for _ in 0..r.below(4) {
        let op = r.pick(&["+", "-", "*", "/", " AND ", " OR ", " XOR ", " MOD ", "/-"]);
        s = format!("{s}{op}{}", primary(r, depth));
    }
    s
}

fn cond(r: &mut Rng, depth: u32) -> String {
    if r.below(3) == 0 {
        let op = r.pick(&[" EQ ", " NE ", " GT ", " GE ", " LT ", " LE "]);
        format!("{}{op}{}", expr(r, depth), expr(r, depth))
    } else {
        expr(r, depth)
    }
}

fn word(r: &mut Rng) -> String {
    let letter = r.pick(&[
        "G", "X", "Y", "z", "F", "N", "M", "P", "XI", ",R", ",C", "H",
    ]);
    let value = match r.below(5) {
        0 => number(r),
        1 => format!("-{}", number(r)),
        2 => var(r, 0),
        3 => format!("-{}", var(r, 0)),
        _ => format!("[{}]", cond(r, 1)),
    };
    format!("{letter}{value}")
}

fn target(r: &mut Rng) -> String {
    match r.below(4) {
        0 => var(r, 1),
        1 => format!("[{}]", expr(r, 1)),
        2 => "2.5".into(),
        _ => r.pick(&["10", "200", "0"]).into(),
    }
}

fn statement(r: &mut Rng, depth: u32) -> String {
    match r.below(if depth > 1 { 7 } else { 9 }) {
        0 | 1 => format!("{}={}", var(r, 0), cond(r, 0)),
        2 => format!("WHILE[{}]DO{}", cond(r, 0), r.pick(&["1", "2", "3"])),
        3 => format!("END{}", r.pick(&["1", "2", "3"])),
        4 => format!("DO{}", r.pick(&["1", "2"])),
        5 => format!("GOTO{}", target(r)),
        6 => "DPRNT[X#1[43]]".to_string(),
        7 => format!("IF[{}]GOTO{}", cond(r, 0), target(r)),
        _ => match r.below(3) {
            0 => format!("IF[{}]THEN{}", cond(r, 0), statement(r, depth + 1)),
            1 => format!("IF[{}]{}={}", cond(r, 0), var(r, 0), expr(r, 0)),
            _ => format!("IF[{}]THEN G1 X{}", cond(r, 0), number(r)),
        },
    }
}

#[test]
fn the_same_tree_as_the_grammar_on_every_shipped_program() {
    let (mut files, mut lines, mut taken) = (0, 0, 0);
    for path in crate::test_programs(&["nc", "ngc"]) {
        let text = std::fs::read(&path).unwrap_or_default();
        let (l, t, declined) = compare(&String::from_utf8_lossy(&text));
        files += 1;
        lines += l;
        taken += t;
        for d in declined {
            assert!(
                handed_on(&d),
                "{}: the descent declined {d:?}",
                path.display()
            );
        }
    }
    assert!(files > 50, "only {files} programs found");
    // Nearly every line of a real program is taken by the descent (the rest: DPRNT, POPEN…).
    assert!(taken * 10 > lines * 9, "{taken} of {lines} lines");
}

/// `n` generated lines: a block delete, words, a statement.
fn generated_lines(r: &mut Rng, n: usize) -> String {
    let mut text = String::new();
    for _ in 0..n {
        if r.below(4) == 0 {
            text.push('/');
            if r.below(2) == 0 {
                text.push('1');
            }
        }
        for _ in 0..r.below(4) {
            text.push_str(&word(r));
            if r.below(2) == 0 {
                text.push(' ');
            }
        }
        if r.below(3) > 0 {
            text.push_str(&statement(r, 0));
        }
        text.push('\n');
    }
    text
}

#[test]
fn the_same_tree_as_the_grammar_on_random_lines() {
    let mut r = Rng(0x9e37_79b9_7f4a_7c15);
    let text = generated_lines(&mut r, 20_000);
    let (lines, taken, declined) = compare(&text);
    assert!(lines > 15_000 && taken > 10_000, "{taken} of {lines}");
    // Every line the grammar accepts is taken, but for the forms handed on on purpose.
    for d in &declined {
        assert!(handed_on(d), "the descent declined {d:?}");
    }
}

/// The equivalence as a property: the lines generated from any seed (proptest draws new ones
/// each run) parse to the grammar's tree, or are handed on as designed.
#[test]
fn the_same_tree_as_the_grammar_for_any_seed() {
    use proptest::prelude::*;
    proptest!(ProptestConfig::with_cases(64), |(seed in any::<u64>())| {
        let mut r = Rng(seed | 1);
        let (lines, _, declined) = compare(&generated_lines(&mut r, 200));
        prop_assert!(lines > 100);
        for d in &declined {
            prop_assert!(handed_on(d), "seed {}: the descent declined {:?}", seed, d);
        }
    });
}

#[test]
fn random_token_soup_is_never_taken_wrongly() {
    const VOCABULARY: [&str; 34] = [
        "G", "X", "XI", "#", "1", "2.5", "[", "]", "+", "-", "*", "/", "=", ",", ":", "EQ", "LT",
        "AND", "OR", "MOD", "SIN", "ATAN", "POW", "IF", "THEN", "GOTO", "WHILE", "DO", "END", " ",
        "R", ",R", "DPRNT[X]", "%",
    ];
    let mut r = Rng(12345);
    let mut text = String::new();
    for _ in 0..30_000 {
        for _ in 0..1 + r.below(9) {
            text.push_str(r.pick(&VOCABULARY));
        }
        text.push('\n');
    }
    let (lines, taken, declined) = compare(&text.replace('%', ""));
    assert!(lines > 20_000 && taken > 100, "{taken} of {lines}");
    for d in &declined {
        assert!(handed_on(d), "the descent declined {d:?}");
    }
}
