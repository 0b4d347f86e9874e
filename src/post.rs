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
    /// The control (a built-in dialect with machine cycles: `mayak600t`).
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
                "{}: the dialect declares no machine cycles ([[cycle]]); `fmsvm post` writes for the controls that have a catalogue (mayak600t)",
                profile.dialect.name
            )],
            Exit::Usage,
        ));
    }
    let bytes = crate::input::read_bounded(&a.input, MAX_INPUT)
        .map_err(|e| (vec![format!("{}: {e}", a.input.display())], Exit::Io))?;
    // The library writes in the Windows code page of its users when not in UTF-8.
    let text = match crate::input::decode(bytes.clone(), Some(crate::input::Charset::Utf8)) {
        Ok(d) => d.text,
        Err(_) => crate::input::decode(bytes, Some(crate::input::Charset::Cp1251))
            .map(|d| d.text)
            .map_err(|e| {
                (
                    vec![format!("{name}:{}:{}: {}", e.line, e.column, e.message)],
                    Exit::MALFORMED_INPUT,
                )
            })?,
    };
    let located = |errors: Vec<Error>| -> Failure {
        (
            errors.iter().map(|e| format!("{name}:{e}")).collect(),
            Exit::MALFORMED_INPUT,
        )
    };
    let blocks = neutral::parse(&text).map_err(located)?;
    write_program(&blocks, &profile.cycles).map_err(located)
}

/// The control's blocks: ordinary blocks as written, each cycle record as the control's cycle
/// block (its profile and G80 dropped), numbered anew from the first block's N in its width.
fn write_program(blocks: &[Block], cycles: &[MachineCycle]) -> Result<String, Vec<Error>> {
    let mut errors = Vec::new();
    let mut lines: Vec<String> = Vec::with_capacity(blocks.len());
    for b in blocks {
        match b {
            Block::Plain(p) => match plain(p) {
                Ok(l) => lines.push(l),
                Err(e) => errors.push(e),
            },
            Block::Cycle(c) => match native(c, cycles) {
                Ok(l) => lines.push(l),
                Err(e) => errors.extend(e),
            },
        }
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    let first_n = blocks.iter().find_map(|b| match b {
        Block::Plain(p) => p.n,
        Block::Cycle(c) => c.n,
    });
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

/// An ordinary block's words as written.
fn plain(p: &Plain) -> Result<String, Error> {
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
        .map(|w| format!("{}{}", w.letter, w.text))
        .collect::<Vec<_>>()
        .join(" "))
}

/// A cycle record as the control's block.
fn native(c: &Cycle, cycles: &[MachineCycle]) -> Result<String, Vec<Error>> {
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
    if !errors.is_empty() {
        return Err(errors);
    }
    let mut words = Vec::new();
    for token in m.block.split_whitespace() {
        match fill(token, c, m) {
            Ok(Some(w)) => words.push(w),
            Ok(None) => {}
            Err(what) => errors.push(Error { at, what }),
        }
    }
    if errors.is_empty() {
        Ok(words.join(" "))
    } else {
        Err(errors)
    }
}

/// One word of a cycle's block with its `{NAME}` filled: None when the parameter is not given (a
/// free parameter left empty).
fn fill(token: &str, c: &Cycle, m: &MachineCycle) -> Result<Option<String>, String> {
    let Some((head, rest)) = token.split_once('{') else {
        return Ok(Some(token.to_string()));
    };
    let Some((name, tail)) = rest.split_once('}') else {
        return Err(format!(
            "CYCLE {}: `{token}` in the dialect's block: a {{NAME}} is not closed",
            c.number
        ));
    };
    let value = match c.param(name) {
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
    };
    Ok(value.map(|v| format!("{head}{v}{tail}")))
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

/// Writes `output.tmp` whole or not at all.
fn write_output(path: &Path, text: &[u8]) -> std::io::Result<()> {
    let target = crate::output::Target::plan(path).map_err(std::io::Error::other)?;
    let sink = crate::output::write_text(&target, text)?;
    crate::output::commit_all(vec![sink])
}
