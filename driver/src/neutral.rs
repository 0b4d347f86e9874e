//! The turning library's neutral language (docs/postprocessor.md): `input.tmp` read into blocks and
//! `CYCLE` records, every error located at its line and column.
//!
//! A block is `N### [words]`: ISO words (G00 X156.31 F1.2 …) or a cycle record `CYCLE nn` with its
//! parameters as `NAME=value`, in the order main, additional, environment (`_L1 _FEED …`), then the
//! figure (`_Xbegin _Zbegin _Xend _Zend`). A turning cycle's record is followed by its profile in
//! elementary moves up to a `G80` block; a drilling or threading record (it has `_D`, `_Angle` or
//! `_FEED`) is not. `;` or `(` starts a comment to the end of the line (the library's listings
//! annotate blocks so).

use std::fmt;

/// Where something is in the input: line and column, from 1.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct At {
    /// Line.
    pub line: u32,
    /// Column (characters).
    pub col: u32,
}

/// A located error.
#[derive(Clone, Debug, PartialEq)]
pub struct Error {
    /// Where.
    pub at: At,
    /// What.
    pub what: String,
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}: {}", self.at.line, self.at.col, self.what)
    }
}

/// An address word as written (`X156.31`).
#[derive(Clone, Debug, PartialEq)]
pub struct Word {
    /// The address letter.
    pub letter: char,
    /// The number as written (`156.31`, `00`).
    pub text: String,
    /// Its value.
    pub value: f64,
    /// Where the word starts.
    pub at: At,
}

/// An ordinary block: its sequence number and words.
#[derive(Clone, Debug, PartialEq)]
pub struct Plain {
    /// The block's line.
    pub line: u32,
    /// N, if written.
    pub n: Option<u32>,
    /// The words after N, in order.
    pub words: Vec<Word>,
}

impl Plain {
    /// The value of the word of `letter`, if the block has one.
    pub fn get(&self, letter: char) -> Option<f64> {
        self.words
            .iter()
            .find(|w| w.letter == letter)
            .map(|w| w.value)
    }

    /// Whether the block has G code `g`.
    pub fn has_g(&self, g: f64) -> bool {
        self.words.iter().any(|w| w.letter == 'G' && w.value == g)
    }
}

/// A parameter of a cycle record (`I=5`, `_Xend=156.31`).
#[derive(Clone, Debug, PartialEq)]
pub struct Param {
    /// The designation, as written (`I`, `VP`, `P1`, `_Xend`).
    pub name: String,
    /// The value as written.
    pub text: String,
    /// Its number.
    pub value: f64,
    /// Where the parameter starts.
    pub at: At,
}

/// What kind of machine cycle a record is (its environment variables say).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A turning cycle: a profile up to G80 follows.
    Turning,
    /// A drilling cycle (`_D`, `_Angle`): no profile.
    Drilling,
    /// A threading cycle (`_FEED`): no profile.
    Threading,
}

/// A `CYCLE nn` record with what belongs to it.
#[derive(Clone, Debug, PartialEq)]
pub struct Cycle {
    /// The record's line.
    pub line: u32,
    /// N, if written.
    pub n: Option<u32>,
    /// The cycle's number (`72`).
    pub number: u32,
    /// Its parameters in order.
    pub params: Vec<Param>,
    /// Turning, drilling or threading.
    pub kind: Kind,
    /// A turning cycle's profile blocks (the `G80` block not included).
    pub profile: Vec<Plain>,
}

impl Cycle {
    /// The parameter called `name`, if given.
    pub fn param(&self, name: &str) -> Option<&Param> {
        self.params.iter().find(|p| p.name == name)
    }
}

/// A block of the neutral program.
#[derive(Clone, Debug, PartialEq)]
pub enum Block {
    /// An ordinary block.
    Plain(Plain),
    /// A cycle record (with its profile).
    Cycle(Cycle),
}

/// The letters of the neutral language's words (B.3: G M S F T, the axes X Z, arcs I K R, P).
const LETTERS: &str = "GMSFTXZIKRP";
/// The G codes of the neutral language.
const G_CODES: [u32; 15] = [0, 1, 2, 3, 4, 8, 9, 40, 41, 42, 66, 80, 90, 96, 97];
/// The M codes of the neutral language.
const M_CODES: [u32; 6] = [3, 4, 5, 8, 9, 30];

/// The most blocks a neutral program may have (a bound on time and memory; the library's programs
/// have hundreds).
pub const MAX_BLOCKS: usize = 200_000;

/// The most words (or parameters) in one block.
pub const MAX_WORDS: usize = 64;

/// The environment variables the library gives a cycle record (its manual, §4.1 and §4.3).
pub const ENVIRONMENT: [&str; 14] = [
    "_L1",
    "_L2",
    "_FEED",
    "_DEPTH",
    "_ALFA",
    "_DIRECT",
    "_NTHREADS",
    "_D",
    "_Depth",
    "_Angle",
    "_Xbegin",
    "_Zbegin",
    "_Xend",
    "_Zend",
];

/// The words a profile block may have: a profile is elementary moves.
const PROFILE_LETTERS: &str = "GXZIKR";

/// Reads a neutral program whose records' kinds their environment variables say (`_FEED` a
/// thread, `_D` or `_Angle` a hole, else turning with a profile).
#[cfg(test)]
pub fn parse(text: &str) -> Result<Vec<Block>, Vec<Error>> {
    parse_for(text, &|_| None)
}

/// Reads a neutral program for a control whose catalogue gives each cycle's kind (its `TYPE`):
/// `kind_of(number)` decides whether a record has a profile up to G80; the environment variables
/// only where the catalogue has no such cycle.
pub fn parse_for(
    text: &str,
    kind_of: &dyn Fn(u32) -> Option<Kind>,
) -> Result<Vec<Block>, Vec<Error>> {
    let mut blocks = Vec::new();
    let mut errors = Vec::new();
    let mut open: Option<Cycle> = None;
    let mut count = 0usize;
    for (i, raw) in text.lines().enumerate() {
        let line = u32::try_from(i + 1).unwrap_or(u32::MAX);
        let code = strip_comment(raw);
        if code.trim().is_empty() {
            continue;
        }
        count += 1;
        if count > MAX_BLOCKS {
            errors.push(Error {
                at: At { line, col: 1 },
                what: format!(
                    "more than {MAX_BLOCKS} blocks: the program is too long for fmsvm post"
                ),
            });
            break;
        }
        if errors.len() >= 100 {
            break;
        }
        match parse_line(code, line, kind_of) {
            Err(e) => errors.push(e),
            Ok(Line::Cycle(c)) => {
                if let Some(prev) = open.take() {
                    errors.push(Error {
                        at: At { line, col: 1 },
                        what: format!(
                            "CYCLE {} before the G80 that ends the profile of CYCLE {} (line {})",
                            c.number, prev.number, prev.line
                        ),
                    });
                }
                if c.kind == Kind::Turning {
                    open = Some(c);
                } else {
                    blocks.push(Block::Cycle(c));
                }
            }
            Ok(Line::Plain(p)) => {
                if open.is_some() && p.has_g(80.0) {
                    if p.words.len() > 1 {
                        errors.push(Error {
                            at: At { line, col: 1 },
                            what: "the G80 that ends a cycle's profile stands alone in its block"
                                .into(),
                        });
                    }
                    if let Some(c) = open.take() {
                        blocks.push(Block::Cycle(c));
                    }
                } else if let Some(c) = open.as_mut() {
                    // A profile is moves: a word that does something else would be lost in it.
                    if let Some(w) = p.words.iter().find(|w| !PROFILE_LETTERS.contains(w.letter)) {
                        errors.push(Error {
                            at: w.at,
                            what: format!(
                                "{}{}: a cycle's profile is moves (G00–G03 X Z I K R): put it before the cycle or after its G80",
                                w.letter, w.text
                            ),
                        });
                    } else if let Some(w) =
                        p.words.iter().find(|w| w.letter == 'G' && w.value > 3.0)
                    {
                        errors.push(Error {
                            at: w.at,
                            what: format!(
                                "G{}: a cycle's profile is moves (G00–G03 X Z I K R)",
                                w.text
                            ),
                        });
                    }
                    c.profile.push(p);
                } else {
                    blocks.push(Block::Plain(p));
                }
            }
        }
    }
    if let Some(c) = open {
        errors.push(Error {
            at: At {
                line: c.line,
                col: 1,
            },
            what: format!(
                "CYCLE {}: its profile has no G80 (the program ends inside it)",
                c.number
            ),
        });
    }
    if errors.is_empty() {
        Ok(blocks)
    } else {
        Err(errors)
    }
}

/// The text of a line before its comment.
fn strip_comment(raw: &str) -> &str {
    let end = raw.find([';', '(']).unwrap_or(raw.len());
    &raw[..end]
}

enum Line {
    Plain(Plain),
    Cycle(Cycle),
}

/// The line's tokens: (column, text), split on blanks.
fn tokens(code: &str) -> Vec<(u32, &str)> {
    let mut out = Vec::new();
    let mut col = 0u32;
    let mut start: Option<(u32, usize)> = None;
    for (byte, ch) in code.char_indices() {
        col += 1;
        if ch.is_whitespace() {
            if let Some((c, b)) = start.take() {
                out.push((c, &code[b..byte]));
            }
        } else if start.is_none() {
            start = Some((col, byte));
        }
    }
    if let Some((c, b)) = start {
        out.push((c, &code[b..]));
    }
    out
}

fn parse_line(code: &str, line: u32, kind_of: &dyn Fn(u32) -> Option<Kind>) -> Result<Line, Error> {
    let toks = tokens(code);
    let err = |col: u32, what: String| Error {
        at: At { line, col },
        what,
    };
    let mut rest = &toks[..];
    let mut n = None;
    if let Some(&(col, t)) = rest.first()
        && let Some(digits) = t.strip_prefix('N')
    {
        n = Some(
            digits
                .parse::<u32>()
                .map_err(|_| err(col, format!("`{t}`: N is a block number of digits")))?,
        );
        rest = &rest[1..];
    }
    if let Some(&(col, "CYCLE")) = rest.first() {
        let Some(&(ncol, num)) = rest.get(1) else {
            return Err(err(col, "CYCLE without its number".into()));
        };
        let cycle_number = num
            .parse::<u32>()
            .map_err(|_| err(ncol, format!("CYCLE `{num}`: the cycle's number is digits")))?;
        let mut params: Vec<Param> = Vec::new();
        if rest.len() > MAX_WORDS + 2 {
            return Err(err(
                col,
                format!("more than {MAX_WORDS} parameters in one record"),
            ));
        }
        for &(pcol, t) in &rest[2..] {
            let Some((name, value)) = t.split_once('=') else {
                return Err(err(pcol, format!("`{t}`: a cycle parameter is NAME=value")));
            };
            let good_name = name
                .chars()
                .next()
                .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
                && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
            if !good_name {
                return Err(err(pcol, format!("`{name}`: not a parameter's name")));
            }
            let v = number(value).ok_or_else(|| {
                err(
                    pcol + name.chars().count() as u32 + 1,
                    format!("{name}=`{value}`: the value of {name} is not a number"),
                )
            })?;
            if params.iter().any(|p| p.name == name) {
                return Err(err(pcol, format!("{name} is given twice")));
            }
            if name.starts_with('_') && !ENVIRONMENT.contains(&name) {
                return Err(err(
                    pcol,
                    format!(
                        "{name}: not one of the library's environment variables ({})",
                        ENVIRONMENT.join(" ")
                    ),
                ));
            }
            params.push(Param {
                name: name.to_string(),
                text: value.to_string(),
                value: v,
                at: At { line, col: pcol },
            });
        }
        let has = |n: &str| params.iter().any(|p| p.name == n);
        let kind = if let Some(k) = kind_of(cycle_number) {
            k
        } else if has("_FEED") {
            Kind::Threading
        } else if has("_D") || has("_Angle") {
            Kind::Drilling
        } else {
            Kind::Turning
        };
        return Ok(Line::Cycle(Cycle {
            line,
            n,
            number: cycle_number,
            params,
            kind,
            profile: Vec::new(),
        }));
    }
    if rest.len() > MAX_WORDS {
        return Err(err(1, format!("more than {MAX_WORDS} words in one block")));
    }
    let mut words: Vec<Word> = Vec::with_capacity(rest.len());
    for &(col, t) in rest {
        let mut chars = t.chars();
        let letter = chars.next().unwrap_or(' ');
        let digits = chars.as_str();
        if !LETTERS.contains(letter) || !letter.is_ascii_uppercase() {
            return Err(err(
                col,
                format!("`{t}`: not a word of the neutral language (G M S F T X Z I K R P)"),
            ));
        }
        let value = number(digits)
            .ok_or_else(|| err(col + 1, format!("{letter}`{digits}`: not a number")))?;
        let known =
            |codes: &[u32]| value.fract() == 0.0 && value >= 0.0 && codes.contains(&(value as u32));
        if (letter == 'G' && !known(&G_CODES)) || (letter == 'M' && !known(&M_CODES)) {
            return Err(err(
                col,
                format!("{letter}{digits}: not a code of the neutral language"),
            ));
        }
        // One word of each letter (the language's block is `[G..] [X.. Z..] [S..] [F..] [T..]
        // [M..]`); two G codes only of different kinds (G00 G40, not G01 G00).
        let motion = |v: f64| v <= 3.0;
        if let Some(prev) = words
            .iter()
            .find(|w| w.letter == letter && (letter != 'G' || (motion(w.value) && motion(value))))
        {
            return Err(err(
                col,
                format!(
                    "{letter}{digits}: the block already has {}{} (one word of each letter)",
                    prev.letter, prev.text
                ),
            ));
        }
        words.push(Word {
            letter,
            text: digits.to_string(),
            value,
            at: At { line, col },
        });
    }
    Ok(Line::Plain(Plain { line, n, words }))
}

/// A number as the library writes them: `156.31`, `-136.98`, `2.`, `.5`, `05`.
fn number(s: &str) -> Option<f64> {
    let body = s.strip_prefix(['-', '+']).unwrap_or(s);
    let ok = !body.is_empty()
        && body.chars().all(|c| c.is_ascii_digit() || c == '.')
        && body.chars().filter(|&c| c == '.').count() <= 1
        && body.chars().any(|c| c.is_ascii_digit());
    if !ok {
        return None;
    }
    s.parse::<f64>().ok().filter(|v| v.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The seed's Маяк-600Т input (B.5), with its annotations.
    const MAYAK: &str = include_str!("../../tests/post/mayak-input.txt");

    #[test]
    fn the_seeds_records_read() {
        let blocks = parse(MAYAK).expect("reads");
        assert_eq!(blocks.len(), 4);
        let Block::Cycle(c) = &blocks[2] else {
            panic!("{:?}", blocks[2]);
        };
        assert_eq!((c.n, c.number, c.kind), (Some(8), 72, Kind::Turning));
        assert_eq!(c.params.len(), 11);
        assert_eq!(c.param("_Zend").map(|p| p.value), Some(-136.98));
        assert_eq!(c.profile.len(), 2);
        assert_eq!(c.profile[0].get('Z'), Some(-136.98));
        // НЦ-31's drilling and threading records: no profile follows them.
        let nc31 = "N049 G00 X0 Z-22.40\nN050 CYCLE 73 P=10 _D=8 _L1=0 _L2=1 _Angle=118 _Zbegin=-22.40 _Zend=-47.29\n\
                    N051 G00 X0 Z-22.40\nN145 CYCLE 31 P2=0.5 _FEED=2. _NTHREADS=1 _DEPTH=1.62 _L1=6 _L2=5.5 _Xbegin=32.75 _Zbegin=-0.5 _Xend=32.75 _Zend=-35.5\n\
                    N146 G00 X36 Z-0.5\nN165 CYCLE 33 S=1 _FEED=1.5 _NTHREADS=1 _L1=3 _L2=3 _Zbegin=-3.5 _Zend=-27\nN166 M03\n";
        let blocks = parse(nc31).expect("reads");
        let kinds: Vec<Kind> = blocks
            .iter()
            .filter_map(|b| match b {
                Block::Cycle(c) => Some(c.kind),
                Block::Plain(_) => None,
            })
            .collect();
        assert_eq!(kinds, [Kind::Drilling, Kind::Threading, Kind::Threading]);
        assert_eq!(blocks.len(), 7);
    }

    #[test]
    fn a_malformed_record_is_located_and_named() {
        let e = parse("N008 CYCLE 77 P1=2?5 W=1 _L1=1.5\nN009 G80\n").unwrap_err();
        assert_eq!(e[0].at, At { line: 1, col: 18 });
        assert!(e[0].what.contains("P1=`2?5`: the value of P1"), "{}", e[0]);
        let e = parse("N001 G00 X10 Y5\n").unwrap_err();
        assert_eq!(e[0].at, At { line: 1, col: 14 });
        let e = parse("N001 G65 X10\n").unwrap_err();
        assert!(e[0].what.contains("G65: not a code"), "{}", e[0]);
        let e = parse("N008 CYCLE 72 I=5\nN009 Z-10\n").unwrap_err();
        assert!(e[0].what.contains("has no G80"), "{}", e[0]);
        let e = parse("N008 CYCLE 72 I=5 I=6\n").unwrap_err();
        assert!(e[0].what.contains("I is given twice"), "{}", e[0]);
    }
}
