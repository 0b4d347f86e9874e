//! `fmsvm post`: the turning library's postprocessor contract (docs/postprocessor.md). It reads the
//! library's `input.tmp` (the neutral language), writes `output.tmp` beside it in the control's
//! words (its machine cycles as its own blocks, from the dialect's `[[cycle]]` catalogue), and prints
//! exactly `OK`, or the errors one a line (`input.tmp:8:21: …`) and no `output.tmp`.
//!
//! Bounded: the input is at most 16 MiB and every step is linear in it, so a program the library
//! writes converts in well under its 10 seconds (the `post` tests time the largest).

use std::io::Write as _;
use std::path::{Path, PathBuf};

use crate::catalogue::MachineCycle;
use crate::exit::Exit;
use crate::neutral::{self, At, Block, Cycle, Error, Plain};

/// The most `input.tmp` may hold.
pub const MAX_INPUT: u64 = 16 << 20;

/// Arguments of `post`.
#[derive(clap::Args, Debug)]
pub struct PostArgs {
    /// The library's `input.tmp` (the neutral language); `output.tmp` is written beside it.
    pub input: PathBuf,
    /// The control (a built-in dialect with machine cycles: `fanuc0itd`, `mayak600t`).
    #[arg(long, value_name = "NAME", conflicts_with = "dialect_file")]
    pub dialect: Option<String>,
    /// A dialect profile of your own (its `[[cycle]]` tables the control's machine cycles).
    #[arg(long, value_name = "FILE")]
    pub dialect_file: Option<PathBuf>,
}

/// Runs `post`: prints `OK` or the errors on standard output.
pub fn main(a: &PostArgs) -> Exit {
    let name = a
        .input
        .file_name()
        .map_or_else(|| "input".into(), |n| n.to_string_lossy().into_owned());
    let output = a.input.with_file_name("output.tmp");
    let result = convert(a, &name);
    let mut out = std::io::stdout().lock();
    match result {
        Ok(text) => match write_output(&output, text.as_bytes()) {
            Ok(()) => {
                let _ = writeln!(out, "OK");
                Exit::Success
            }
            Err(e) => {
                let _ = writeln!(out, "{}: {e}", output.display());
                Exit::Io
            }
        },
        Err((lines, code)) => {
            // A stale output.tmp must not pass for this program's.
            let _ = std::fs::remove_file(&output);
            for l in lines {
                let _ = writeln!(out, "{l}");
            }
            code
        }
    }
}

type Failure = (Vec<String>, Exit);

/// The control's program for the neutral program in `a.input`.
fn convert(a: &PostArgs, name: &str) -> Result<String, Failure> {
    let profile = match (&a.dialect, &a.dialect_file) {
        (Some(d), _) => crate::dialects::builtin(d),
        (None, Some(f)) => crate::input::read_bounded(f, 1 << 20)
            .map_err(|e| format!("{}: {e}", f.display()))
            .and_then(|b| {
                String::from_utf8(b).map_err(|_| format!("{}: not UTF-8 text", f.display()))
            })
            .and_then(|t| crate::dialects::load(&f.display().to_string(), &t)),
        (None, None) => Err("give the control: --dialect NAME or --dialect-file FILE".into()),
    }
    .map_err(|e| (vec![e], Exit::Usage))?;
    if profile.cycles.is_empty() {
        return Err((
            vec![format!(
                "{}: the dialect declares no machine cycles ([[cycle]]); `fmsvm post` writes for the controls that have a catalogue (fanuc0itd, mayak600t)",
                profile.dialect.name
            )],
            Exit::Usage,
        ));
    }
    let bytes = crate::input::read_bounded(&a.input, MAX_INPUT)
        .map_err(|e| (vec![format!("{}: {e}", a.input.display())], Exit::Io))?;
    // The library writes in the Windows code page of its users when not in UTF-8.
    let charset = if std::str::from_utf8(&bytes).is_ok() {
        crate::input::Charset::Utf8
    } else {
        crate::input::Charset::Cp1251
    };
    let text = crate::input::decode(bytes, Some(charset))
        .map(|d| d.text)
        .map_err(|e| {
            (
                vec![format!("{name}:{}:{}: {}", e.line, e.column, e.message)],
                Exit::MALFORMED_INPUT,
            )
        })?;
    let located = |errors: Vec<Error>| -> Failure {
        (
            errors.iter().map(|e| format!("{name}:{e}")).collect(),
            Exit::MALFORMED_INPUT,
        )
    };
    let blocks = neutral::parse(&text).map_err(located)?;
    let spell = Spelling {
        point_always: profile.dialect.format(fmsvm_block::Letter::X).point
            == fmsvm_emit::dialect::Point::Always,
    };
    let program = write_program(&blocks, &profile.cycles, spell).map_err(located)?;
    // The library runs on Windows: its lines end as the input's do.
    Ok(if text.contains("\r\n") {
        program.replace('\n', "\r\n")
    } else {
        program
    })
}

/// How the control's words are spelled where the library's may differ.
#[derive(Clone, Copy)]
struct Spelling {
    /// The control reads a number without a point as least increments (a Fanuc: `X68` is 68 µm):
    /// a length or a feed the library wrote without one gets it (`X68.`).
    point_always: bool,
}

/// The letters whose numbers are lengths or feeds.
const LENGTHS: &str = "XZIKRFUW";

/// The control's blocks: ordinary blocks as written (with a point where the control needs one),
/// each cycle record as the control's cycle block (its profile kept or dropped as the catalogue
/// says, the G80 dropped), numbered anew from the first block's N in three digits.
fn write_program(
    blocks: &[Block],
    cycles: &[MachineCycle],
    spell: Spelling,
) -> Result<String, Vec<Error>> {
    let mut errors = Vec::new();
    let mut lines: Vec<String> = Vec::with_capacity(blocks.len());
    let first_n = blocks.iter().find_map(|b| match b {
        Block::Plain(p) => p.n,
        Block::Cycle(c) => c.n,
    });
    for b in blocks {
        match b {
            Block::Plain(p) => match plain(p, spell) {
                Ok(l) => lines.push(l),
                Err(e) => errors.push(e),
            },
            Block::Cycle(c) => {
                // The N the profile's first and last blocks get, when they are kept.
                let base = first_n.unwrap_or(0) as usize + lines.len();
                match native(c, cycles, spell, base) {
                    Ok(mut l) => lines.append(&mut l),
                    Err(e) => errors.extend(e),
                }
            }
        }
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    let mut text = String::new();
    for (k, l) in lines.iter().enumerate() {
        if let Some(n0) = first_n {
            text.push_str(&format!("N{:03} ", n0 as usize + k));
        }
        text.push_str(l);
        text.push('\n');
    }
    Ok(text)
}

/// The neutral codes the control's words do not spell as the neutral language does (or fmsvm does
/// not convert yet): G66 (the spindle's zero, not Fanuc's macro call), G08/G09, G96/G97.
const NOT_YET: [(f64, &str); 5] = [
    (8.0, "G08 (acceleration)"),
    (9.0, "G09 (deceleration)"),
    (66.0, "G66 (synchronisation with the spindle's zero)"),
    (96.0, "G96 (constant surface speed)"),
    (97.0, "G97"),
];

/// An ordinary block's words as written (a point added where the control needs one).
fn plain(p: &Plain, spell: Spelling) -> Result<String, Error> {
    if let Some(w) = p
        .words
        .iter()
        .find(|w| w.letter == 'G' && NOT_YET.iter().any(|(g, _)| *g == w.value))
    {
        let what = NOT_YET
            .iter()
            .find(|(g, _)| *g == w.value)
            .map_or("", |(_, t)| t);
        return Err(Error {
            at: w.at,
            what: format!("{what}: not yet converted for this control"),
        });
    }
    Ok(p.words
        .iter()
        .map(|w| {
            if spell.point_always && LENGTHS.contains(w.letter) {
                format!("{}{}", w.letter, pointed(&w.text))
            } else {
                format!("{}{}", w.letter, w.text)
            }
        })
        .collect::<Vec<_>>()
        .join(" "))
}

/// A number with a decimal point (`68` → `68.`).
fn pointed(text: &str) -> String {
    if text.contains('.') {
        text.to_string()
    } else {
        format!("{text}.")
    }
}

/// A cycle record as the control's block lines (and its profile's, when the catalogue keeps it);
/// `base` is the N the first of them gets.
fn native(
    c: &Cycle,
    cycles: &[MachineCycle],
    spell: Spelling,
    base: usize,
) -> Result<Vec<String>, Vec<Error>> {
    let at = At {
        line: c.line,
        col: 1,
    };
    let Some(m) = cycles.iter().find(|m| m.number == c.number) else {
        return Err(vec![Error {
            at,
            what: format!(
                "CYCLE {}: not one of the control's machine cycles ({}); elementary moves are not yet written by fmsvm post",
                c.number,
                cycles
                    .iter()
                    .map(|m| m.number.to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        }]);
    };
    let mut errors = Vec::new();
    for p in m.parameters.iter().filter(|p| p.obligatory()) {
        if c.param(&p.name).is_none() && p.default.is_none() {
            errors.push(Error {
                at,
                what: format!(
                    "CYCLE {}: the obligatory parameter {} ({}) is not given",
                    c.number, p.name, p.text
                ),
            });
        }
    }
    for p in &c.params {
        let known = p.name.starts_with('_') || m.parameters.iter().any(|q| q.name == p.name);
        if !known {
            errors.push(Error {
                at: p.at,
                what: format!(
                    "CYCLE {}: {} is not a parameter of this cycle",
                    c.number, p.name
                ),
            });
        }
    }
    if m.keep_profile && c.profile.is_empty() {
        errors.push(Error {
            at,
            what: format!(
                "CYCLE {}: the control's cycle needs its profile, and none follows",
                c.number
            ),
        });
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    let block_lines: Vec<&str> = m.block.lines().collect();
    let ns = base + block_lines.len();
    let nf = ns + c.profile.len().saturating_sub(1);
    let mut out = Vec::new();
    for line in block_lines {
        let mut words = Vec::new();
        for token in line.split_whitespace() {
            match fill(token, c, m, spell, (ns, nf)) {
                Ok(Some(w)) => words.push(w),
                Ok(None) => {}
                Err(what) => errors.push(Error { at, what }),
            }
        }
        out.push(words.join(" "));
    }
    if m.keep_profile {
        for p in &c.profile {
            match plain(p, spell) {
                Ok(l) => out.push(l),
                Err(e) => errors.push(e),
            }
        }
    }
    if errors.is_empty() {
        Ok(out)
    } else {
        Err(errors)
    }
}

/// One word of a cycle's block with its `{NAME}` filled: None when the parameter is not given (a
/// free parameter left empty). `{ns}` and `{nf}` are the kept profile's first and last N;
/// `{NAME:02}` writes a whole number in two digits, `{NAME:int}` a whole number, `{NAME:um}` a
/// length in micrometres (as
/// Fanuc's G74–G76 take P and Q); any other number gets a point where the control needs one.
fn fill(
    token: &str,
    c: &Cycle,
    m: &MachineCycle,
    spell: Spelling,
    (ns, nf): (usize, usize),
) -> Result<Option<String>, String> {
    let mut out = String::new();
    let mut rest = token;
    while let Some((head, after)) = rest.split_once('{') {
        out.push_str(head);
        let Some((field, tail)) = after.split_once('}') else {
            return Err(format!(
                "CYCLE {}: `{token}` in the dialect's block: a {{NAME}} is not closed",
                c.number
            ));
        };
        let (name, spec) = field.split_once(':').unwrap_or((field, ""));
        let value = match name {
            "ns" => Some(ns.to_string()),
            "nf" => Some(nf.to_string()),
            _ => value_of(name, c, m)?,
        };
        let Some(v) = value else {
            return Ok(None);
        };
        out.push_str(&formatted(&v, spec, spell, name, c)?);
        rest = tail;
    }
    out.push_str(rest);
    Ok(Some(out))
}

/// A parameter's value as written: the record's, an automatic one, or the catalogue's default.
fn value_of(name: &str, c: &Cycle, m: &MachineCycle) -> Result<Option<String>, String> {
    Ok(match c.param(name) {
        Some(p) => Some(p.text.clone()),
        None => match m.parameters.iter().find(|p| p.name == name) {
            Some(p) if p.kind == "A" => automatic(name, c)?,
            Some(p) => p.default.clone(),
            None if name.starts_with('_') => {
                return Err(format!(
                    "CYCLE {}: the record has no {name}, which the control's block needs",
                    c.number
                ));
            }
            None => None,
        },
    })
}

/// An automatic parameter the library leaves to the postprocessor: K, the taper, is 0 when the
/// profile's first move runs along Z only (a cylinder, as the seed's listing writes K0 for its
/// figure); a cone's K is not computed yet (which way and in what unit the control counts it is not
/// in the sources): give K.
fn automatic(name: &str, c: &Cycle) -> Result<Option<String>, String> {
    match name {
        "K" => match c.profile.first() {
            Some(b) if b.get('X').is_some() && b.get('Z').is_some() => Err(format!(
                "CYCLE {}: the figure is a cone (its first move changes X and Z): its K (the taper) is not yet computed by fmsvm; give K in the record",
                c.number
            )),
            _ => Ok(Some("0".into())),
        },
        _ => Ok(None),
    }
}

/// A value written by the block's spec.
fn formatted(
    v: &str,
    spec: &str,
    spell: Spelling,
    name: &str,
    c: &Cycle,
) -> Result<String, String> {
    let number = || {
        v.parse::<f64>()
            .map_err(|_| format!("CYCLE {}: {name} = {v} is not a number", c.number))
    };
    match spec {
        "" if name == "ns" || name == "nf" || !spell.point_always => Ok(v.to_string()),
        "" => Ok(pointed(v)),
        "02" => {
            let n = number()?;
            if n.fract() != 0.0 || !(0.0..100.0).contains(&n) {
                return Err(format!(
                    "CYCLE {}: {name} = {v}: a whole number from 0 to 99 here",
                    c.number
                ));
            }
            Ok(format!("{:02}", n as u32))
        }
        "um" => Ok(format!("{}", (number()? * 1000.0).round() as i64)),
        "int" => {
            let n = number()?;
            if n.fract() != 0.0 {
                return Err(format!(
                    "CYCLE {}: {name} = {v}: a whole number here",
                    c.number
                ));
            }
            Ok(format!("{}", n as i64))
        }
        other => Err(format!(
            "CYCLE {}: {{{name}:{other}}} in the dialect's block: the formats are :02, :int and :um",
            c.number
        )),
    }
}

/// Writes `output.tmp` whole or not at all.
fn write_output(path: &Path, text: &[u8]) -> std::io::Result<()> {
    let target = crate::output::Target::plan(path).map_err(std::io::Error::other)?;
    let sink = crate::output::write_text(&target, text)?;
    crate::output::commit_all(vec![sink])
}
