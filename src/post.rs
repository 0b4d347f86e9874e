//! `fmsvm post`: the turning library's postprocessor contract (docs/postprocessor.md). It reads the
//! library's `input.tmp` (the neutral language), writes `output.tmp` beside it in the control's
//! words (its machine cycles as its own blocks, from the dialect's `[[cycle]]` catalogue), and prints
//! exactly `OK`, or the errors one a line (`input.tmp:8:21: …`) and no `output.tmp`.
//!
//! Bounded: the input is at most 16 MiB and every step is linear in it, so a program the library
//! writes converts in well under its 10 seconds (the `post` tests time the largest).

use std::io::Write as _;
use std::path::{Path, PathBuf};

use crate::catalogue::{MachineCycle, Scheme};
use crate::cycle_moves::{self, Move};
use crate::exit::Exit;
use crate::neutral::{self, At, Block, Cycle, Error, Plain};
use crate::post_words::MoveWords;

/// The most `input.tmp` may hold.
pub const MAX_INPUT: u64 = 16 << 20;

/// The most blocks `output.tmp` and `path.tmp` may hold together (cycles in elementary moves
/// included): a bound on the time and memory of any input.
pub const MAX_BLOCKS: usize = 250_000;

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
    /// Every cycle in elementary moves, even those the control has.
    #[arg(long)]
    pub moves: bool,
    /// Read output.tmp back and compare its moves with the neutral program's (docs/postprocessor.md).
    #[arg(long)]
    pub verify: bool,
}

/// Runs `post`: prints `OK` or the errors on standard output.
pub fn main(a: &PostArgs) -> Exit {
    let name = a
        .input
        .file_name()
        .map_or_else(|| "input".into(), |n| n.to_string_lossy().into_owned());
    let output = a.input.with_file_name("output.tmp");
    let path_file = a.input.with_file_name("path.tmp");
    let result = convert(a, &name).and_then(|done| {
        if a.verify {
            crate::post_verify::verify(&done, &name).map_err(|e| (vec![e], Exit::Verify))?;
        }
        Ok(done)
    });
    let mut out = std::io::stdout().lock();
    match result {
        Ok(done) => match write_outputs(&output, &path_file, &done) {
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
            // A stale output.tmp (or path.tmp) must not pass for this program's.
            let _ = std::fs::remove_file(&output);
            let _ = std::fs::remove_file(&path_file);
            for l in lines {
                let _ = writeln!(out, "{l}");
            }
            code
        }
    }
}

type Failure = (Vec<String>, Exit);

/// What `post` made of a neutral program.
pub struct Converted {
    /// output.tmp's text (its lines ending as the input's).
    pub output: String,
    /// path.tmp's text, when the path inside every cycle is known.
    pub path: Option<String>,
    /// The neutral program's motion: its own moves and each cycle's path (X as a radius).
    pub motion: Vec<Move>,
    /// The control's profile.
    pub profile: crate::dialects::Profile,
    /// A cycle written as the control's own block (its motion is the control's to make).
    pub native: Option<u32>,
}

/// The control's program for the neutral program in `a.input`.
fn convert(a: &PostArgs, name: &str) -> Result<Converted, Failure> {
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
                "{}: the dialect declares no machine cycles ([[cycle]]); `fmsvm post` writes for the controls that have a catalogue (`fmsvm dialects` marks them)",
                profile.dialect.name
            )],
            Exit::Usage,
        ));
    }
    let bytes = crate::input::read_bounded(&a.input, MAX_INPUT).map_err(|e| {
        let what = match e {
            crate::input::ReadError::TooBig(_) => format!(
                "it is larger than {}, the most fmsvm post reads",
                crate::input::human(MAX_INPUT)
            ),
            e => e.to_string(),
        };
        (vec![format!("{}: {what}", a.input.display())], Exit::Io)
    })?;
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
    let mut w = Writer::new(&profile, a.moves);
    w.program(&blocks).map_err(located)?;
    // The library runs on Windows: its lines end as the input's do.
    let crlf = |t: String| {
        if text.contains("\r\n") {
            t.replace('\n', "\r\n")
        } else {
            t
        }
    };
    let output = crlf(w.text);
    let path = w.path.map(crlf);
    Ok(Converted {
        output,
        path,
        motion: w.all_motion,
        native: w.native,
        profile,
    })
}

/// How the control's words are spelled where the library's may differ.
#[derive(Clone, Copy)]
struct Spelling {
    /// The control reads a number without a point as least increments (a Fanuc: `X68` is 68 µm):
    /// a length or a feed the library wrote without one gets it (`X68.`).
    point_always: bool,
    /// The control has constant surface speed (G96 S in m/min, G97 S in rpm).
    css: bool,
    /// How the control writes a dwell.
    dwell: fmsvm_emit::dialect::DwellForm,
    /// The digits of a G code (`G04` or `G4`).
    g_width: usize,
}

/// The letters whose numbers are lengths or feeds.
const LENGTHS: &str = "XZIKRFUW";

/// The program as the control's blocks, the paths inside its cycles, and the neutral program's
/// motion, made in one pass over the blocks.
struct Writer<'p> {
    profile: &'p crate::dialects::Profile,
    spell: Spelling,
    /// Every cycle in elementary moves.
    all_moves: bool,
    /// The control's lines, without N.
    lines: Vec<String>,
    /// The first block's N: the output is numbered from it.
    first_n: Option<u32>,
    /// Where the tool is (X radius, Z), once a block has said both.
    at: [Option<f64>; 2],
    /// The motion G code in force (0–3).
    motion: u8,
    /// The spindle's direction (3, 4) while it turns.
    spindle: Option<u8>,
    /// The paths of the cycles, in the neutral language (None once one is unknown).
    paths: Option<Vec<String>>,
    /// The neutral program's motion.
    motion_moves: Vec<Move>,
    /// The first cycle written as the control's own block.
    native: Option<u32>,
    // Results.
    text: String,
    path: Option<String>,
    all_motion: Vec<Move>,
}

impl<'p> Writer<'p> {
    fn new(profile: &'p crate::dialects::Profile, all_moves: bool) -> Self {
        Writer {
            profile,
            spell: Spelling {
                point_always: profile.dialect.format(fmsvm_block::Letter::X).point
                    == fmsvm_emit::dialect::Point::Always,
                css: profile
                    .dialect
                    .lathe
                    .as_ref()
                    .is_some_and(|l| l.css == fmsvm_emit::dialect::CssForm::Native),
                dwell: profile.dialect.dwell,
                g_width: usize::from(profile.dialect.format(fmsvm_block::Letter::G).width),
            },
            all_moves,
            lines: Vec::new(),
            first_n: None,
            at: [None, None],
            motion: 0,
            spindle: None,
            paths: Some(Vec::new()),
            motion_moves: Vec::new(),
            native: None,
            text: String::new(),
            path: None,
            all_motion: Vec::new(),
        }
    }

    /// The control's blocks: ordinary blocks as written (with a point where the control needs
    /// one), each cycle record as the control's cycle block (its profile kept or dropped as the
    /// catalogue says, the G80 dropped) or in elementary moves, numbered anew from the first
    /// block's N in three digits.
    fn program(&mut self, blocks: &[Block]) -> Result<(), Vec<Error>> {
        let mut errors = Vec::new();
        self.first_n = blocks.iter().find_map(|b| match b {
            Block::Plain(p) => p.n,
            Block::Cycle(c) => c.n,
        });
        for b in blocks {
            let (done, line) = match b {
                Block::Plain(p) => (self.plain_block(p), p.line),
                Block::Cycle(c) => (self.cycle(c), c.line),
            };
            if let Err(e) = done {
                errors.extend(e);
            }
            if self.lines.len() + self.paths.as_ref().map_or(0, Vec::len) > MAX_BLOCKS {
                errors.push(Error {
                    at: At { line, col: 1 },
                    what: format!(
                        "output.tmp and path.tmp would hold more than {MAX_BLOCKS} blocks from here on"
                    ),
                });
                break;
            }
        }
        if !errors.is_empty() {
            return Err(errors);
        }
        let mut text = String::new();
        for (k, l) in self.lines.iter().enumerate() {
            if let Some(n0) = self.first_n {
                text.push_str(&format!("N{:03} ", n0 as usize + k));
            }
            text.push_str(l);
            text.push('\n');
        }
        self.text = text;
        self.path = self.paths.take().filter(|p| !p.is_empty()).map(|lines| {
            let mut n = 0;
            lines
                .iter()
                .map(|l| {
                    if l.starts_with(';') {
                        format!("{l}\n")
                    } else {
                        n += 1;
                        format!("N{n:03} {l}\n")
                    }
                })
                .collect()
        });
        self.all_motion = std::mem::take(&mut self.motion_moves);
        Ok(())
    }

    /// An ordinary block: written as it is; its move and spindle followed.
    fn plain_block(&mut self, p: &Plain) -> Result<(), Vec<Error>> {
        let line = plain(p, self.spell).map_err(|e| vec![e])?;
        if !line.is_empty() {
            self.lines.push(line);
        }
        for w in &p.words {
            match (w.letter, w.value as u32) {
                ('G', g @ 0..=3) if w.value.fract() == 0.0 => self.motion = g as u8,
                ('M', 3) => self.spindle = Some(3),
                ('M', 4) => self.spindle = Some(4),
                ('M', 5 | 30) => self.spindle = None,
                _ => {}
            }
        }
        if p.has_g(4.0) {
            // A dwell's X is its time.
            return Ok(());
        }
        let (x, z) = (p.get('X'), p.get('Z'));
        if x.is_none() && z.is_none() {
            return Ok(());
        }
        let from = self.at;
        if let Some(x) = x {
            self.at[0] = Some(x / 2.0);
        }
        if let Some(z) = z {
            self.at[1] = Some(z);
        }
        let [Some(tx), Some(tz)] = self.at else {
            return Ok(());
        };
        let to = [tx, tz];
        let mv = match self.motion {
            0 => Move::Rapid(to),
            1 => Move::Feed(to, p.get('F')),
            m => {
                let (Some(fx), Some(fz)) = (from[0], from[1]) else {
                    return Err(vec![Error {
                        at: At {
                            line: p.line,
                            col: 1,
                        },
                        what: "an arc before the tool's X and Z are known".into(),
                    }]);
                };
                let centre = arc_centre(p, [fx, fz], to, m == 2).map_err(|what| {
                    vec![Error {
                        at: At {
                            line: p.line,
                            col: 1,
                        },
                        what,
                    }]
                })?;
                Move::Arc {
                    to,
                    centre,
                    cw: m == 2,
                    f: p.get('F'),
                }
            }
        };
        self.motion_moves.push(mv);
        Ok(())
    }

    /// A cycle record: the control's block, or elementary moves; its path kept for path.tmp.
    fn cycle(&mut self, c: &Cycle) -> Result<(), Vec<Error>> {
        let cycles = &self.profile.cycles;
        let at = At {
            line: c.line,
            col: 1,
        };
        let located = |what: String| vec![Error { at, what }];
        let Some(m) = cycles.iter().find(|m| m.number == c.number) else {
            return Err(located(format!(
                "CYCLE {}: not one of the control's machine cycles ({})",
                c.number,
                cycles
                    .iter()
                    .map(|m| m.number.to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            )));
        };
        check_parameters(c, m)?;
        let start = match self.at {
            [Some(x), Some(z)] => Some([x, z]),
            _ => None,
        };
        let path = match start {
            Some(s) if m.moves.is_some() => Some(cycle_moves::path(c, m, s, self.spindle)),
            _ => None,
        };
        let elementary = self.all_moves || m.block.is_none();
        if elementary {
            let Some(s) = start else {
                return Err(located(format!(
                    "CYCLE {}: the tool's X and Z are not known before it (its start point): move there first (G00 X… Z…)",
                    c.number
                )));
            };
            let moves = match path {
                Some(p) => p.map_err(located)?,
                None => {
                    return Err(located(format!(
                        "CYCLE {}: the catalogue does not say how to write it in elementary moves (moves = …)",
                        c.number
                    )));
                }
            };
            let mut words = MoveWords::control(&self.profile.dialect, s);
            for mv in &moves {
                if let Some(l) = words
                    .line(mv)
                    .map_err(|e| located(format!("CYCLE {}: {e}", c.number)))?
                {
                    self.lines.push(l);
                }
            }
            // The control's motion code in force as the neutral program's was before the cycle:
            // a later block without a G code moves as the library meant it to.
            if let Some(l) = words.restore(self.motion) {
                self.lines.push(l);
            }
            self.keep_path(c, s, &moves);
            self.spindle = spindle_after(&moves, self.spindle);
            return Ok(());
        }
        // The control's own cycle is checked by fmsvm's model of it first: a record the model
        // refuses (a profile it cannot cut, a start inside the stock, a thread of several starts,
        // words out of range) is refused here too, before the control meets it.
        let moves = match (start, path) {
            (Some(_), Some(Ok(moves))) => Some(moves),
            (_, Some(Err(e))) => {
                return Err(located(format!(
                    "{e} (the control's own cycle is checked by fmsvm's model of it)"
                )));
            }
            (None, _) if m.moves.is_some() => {
                return Err(located(format!(
                    "CYCLE {}: the tool's X and Z are not known before it (its start point): move there first (G00 X… Z…)",
                    c.number
                )));
            }
            _ => None,
        };
        // A control's own drilling or tapping cycle starts where the tool stands: the tool goes to
        // the hole's start at feed (`_Zbegin`, the approach included) first, as the elementary
        // moves do.
        if matches!(m.moves, Some(Scheme::Drilling | Scheme::Tapping))
            && let (Some(zb), Some(s)) = (c.param("_Zbegin"), start)
            && (zb.value - s[1]).abs() > 1e-9
        {
            let z = if self.spell.point_always {
                pointed(&zb.text)
            } else {
                zb.text.clone()
            };
            self.lines.push(format!("G00 Z{z}"));
        }
        // The N the profile's first and last blocks get, when they are kept.
        let base = self.first_n.unwrap_or(0) as usize + self.lines.len();
        let side = start.and_then(|st| cycle_moves::stock_side(c, m, st));
        let mut l = native(c, m, self.spell, base, side)?;
        self.lines.append(&mut l);
        self.native.get_or_insert(c.number);
        match (start, moves) {
            (Some(s), Some(moves)) => self.keep_path(c, s, &moves),
            _ => self.paths = None,
        }
        Ok(())
    }

    /// A cycle's path: into path.tmp (from a point at its start) and the program's motion.
    fn keep_path(&mut self, c: &Cycle, start: [f64; 2], moves: &[Move]) {
        if let Some(paths) = &mut self.paths {
            let mut words = MoveWords::neutral(start);
            let n = c.n.map_or_else(String::new, |n| format!(" N{n:03}"));
            paths.push(format!("; CYCLE {}{n}", c.number));
            paths.push(words.point(start));
            for mv in moves {
                if let Ok(Some(l)) = words.line(mv) {
                    paths.push(l);
                }
            }
        }
        self.motion_moves.extend_from_slice(moves);
    }
}

/// The spindle's direction after a cycle's moves.
fn spindle_after(moves: &[Move], before: Option<u8>) -> Option<u8> {
    moves
        .iter()
        .rev()
        .find_map(|m| match m {
            Move::Spindle(d) => Some(Some(*d)),
            _ => None,
        })
        .unwrap_or(before)
}

/// The centre of a neutral arc block from `from` to `to` (X radius): its I K (I a radius, from the
/// start, as Fanuc's lathe) or its R.
fn arc_centre(p: &Plain, from: [f64; 2], to: [f64; 2], cw: bool) -> Result<[f64; 2], String> {
    let words = match (p.get('R'), p.get('I'), p.get('K')) {
        (Some(r), _, _) => fmsvm_canon::arcs::CentreWords::Radius(r),
        (None, None, None) => return Err("an arc without I K or R".into()),
        (None, i, k) => {
            fmsvm_canon::arcs::CentreWords::Offsets([i.unwrap_or(0.0), 0.0, k.unwrap_or(0.0)])
        }
    };
    let pose = |q: [f64; 2]| -> fmsvm_canon::Pose { [q[0], 0.0, q[1], 0.0, 0.0, 0.0] };
    match fmsvm_canon::arcs::arc(
        &pose(from),
        &pose(to),
        fmsvm_canon::Plane::ZX,
        cw,
        words,
        0.01,
    ) {
        Ok(Some(a)) => Ok([a.centre[1], a.centre[0]]),
        Ok(None) => Err("an arc that does not move".into()),
        Err(a) => Err(a.message.to_string()),
    }
}

/// Obligatory parameters given, and no parameter the cycle does not declare.
fn check_parameters(c: &Cycle, m: &MachineCycle) -> Result<(), Vec<Error>> {
    let at = At {
        line: c.line,
        col: 1,
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
    if errors.is_empty() {
        Ok(())
    } else {
        Err(errors)
    }
}

/// The neutral codes fmsvm does not convert (yet): G66 (the spindle's zero, not Fanuc's macro
/// call), G08/G09 (acceleration and deceleration: Fanuc's G08 is look-ahead control, its G09 an
/// exact stop in one block).
const NOT_YET: [(f64, &str); 3] = [
    (8.0, "G08 (acceleration)"),
    (9.0, "G09 (deceleration)"),
    (66.0, "G66 (synchronisation with the spindle's zero)"),
];

/// An ordinary block's words as written (a point added where the control needs one). G96 S
/// (m/min) and G97 S (rpm) are the same words on a control with constant surface speed
/// (`[lathe] css = "native"`); a control without it is refused G96, and G97 (its only way) is left
/// out.
fn plain(p: &Plain, spell: Spelling) -> Result<String, Error> {
    for w in p.words.iter().filter(|w| w.letter == 'G') {
        let what = NOT_YET
            .iter()
            .find(|(g, _)| *g == w.value)
            .map(|(_, t)| format!("{t}: not yet converted for this control"));
        let what = what.or_else(|| {
            (w.value == 96.0 && !spell.css).then(|| {
                "G96 (constant surface speed): this control has none known ([lathe] css = \"rpm\"): have the library write the spindle speed in rpm (G97)".to_string()
            })
        });
        if let Some(what) = what {
            return Err(Error { at: w.at, what });
        }
    }
    let dwell = p.has_g(4.0);
    if dwell && let Some(w) = p.words.iter().find(|w| w.letter == 'P') {
        return Err(Error {
            at: w.at,
            what: "G04 P: the unit of a dwell's P is not documented for the neutral language (seconds or milliseconds): fmsvm reads G04 X<seconds>".into(),
        });
    }
    let mut out = Vec::with_capacity(p.words.len());
    for w in &p.words {
        if w.letter == 'G' && w.value == 97.0 && !spell.css {
            continue;
        }
        if dwell && w.letter == 'X' {
            // The dwell's time, in seconds, as the control writes a dwell.
            if w.value < 0.0 {
                return Err(Error {
                    at: w.at,
                    what: format!("G04 X{}: a dwell's time is not negative", w.text),
                });
            }
            out.push(dwell_word(w.value, spell.dwell));
            continue;
        }
        if dwell && w.letter == 'G' && w.value == 4.0 {
            out.push(format!("G{:0width$}", 4, width = spell.g_width));
            continue;
        }
        out.push(if spell.point_always && LENGTHS.contains(w.letter) {
            format!("{}{}", w.letter, pointed(&w.text))
        } else {
            format!("{}{}", w.letter, w.text)
        });
    }
    Ok(out.join(" "))
}

/// A dwell of `seconds` as the control writes it (the dialect's `[motion] dwell`).
fn dwell_word(seconds: f64, form: fmsvm_emit::dialect::DwellForm) -> String {
    let units = (seconds.max(0.0) * form.units_per_second()).round();
    let value = if form.whole_units() {
        format!("{units}")
    } else {
        // Seconds, to the millisecond, trailing zeros off (`P1.5`, `X2.`).
        let t = format!("{:.3}", units / form.units_per_second());
        t.trim_end_matches('0').to_string()
    };
    format!("{}{value}", form.letter())
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
    m: &MachineCycle,
    spell: Spelling,
    base: usize,
    side: Option<[f64; 2]>,
) -> Result<Vec<String>, Vec<Error>> {
    let at = At {
        line: c.line,
        col: 1,
    };
    let mut errors = Vec::new();
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
    let block = m.block.as_deref().unwrap_or_default();
    let block_lines: Vec<&str> = block.lines().collect();
    let infeed = if m.keep_profile {
        infeed(c, m, spell).map_err(|what| vec![Error { at, what }])?
    } else {
        None
    };
    let ns = base + block_lines.len();
    let nf = ns + c.profile.len() + usize::from(infeed.is_some()) - 1;
    let mut out = Vec::new();
    for line in block_lines {
        let mut words = Vec::new();
        for token in line.split_whitespace() {
            match fill(token, c, m, spell, (ns, nf), side) {
                Ok(Some(w)) => words.push(w),
                Ok(None) => {}
                Err(what) => errors.push(Error { at, what }),
            }
        }
        out.push(words.join(" "));
    }
    if m.keep_profile {
        out.extend(infeed);
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

/// The move from the cycle's start to the figure's begin that a kept profile must start with (Fanuc's
/// A to A'), when the library's profile does not: the library's profile starts at `_Xbegin`
/// `_Zbegin` (B.5: `N009 Z-136.98` after `_Xbegin=118`), the control's from its start point.
fn infeed(c: &Cycle, m: &MachineCycle, spell: Spelling) -> Result<Option<String>, String> {
    let (letter, name) = match m.moves {
        Some(Scheme::Facing) => ('Z', "_Zbegin"),
        Some(Scheme::Turning | Scheme::Pattern) => ('X', "_Xbegin"),
        _ => return Ok(None),
    };
    let Some(begin) = c.param(name) else {
        return Err(format!(
            "CYCLE {}: the record has no {name}, where the control's profile starts",
            c.number
        ));
    };
    let already = c.profile.first().is_some_and(|b| {
        b.get(letter)
            .is_some_and(|v| (v - begin.value).abs() < 0.005)
            && b.get(if letter == 'X' { 'Z' } else { 'X' }).is_none()
    });
    if already {
        return Ok(None);
    }
    let v = if spell.point_always {
        pointed(&begin.text)
    } else {
        begin.text.clone()
    };
    Ok(Some(format!("G00 {letter}{v}")))
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
    side: Option<[f64; 2]>,
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
        out.push_str(&formatted(&v, spec, spell, name, c, side)?);
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
    side: Option<[f64; 2]>,
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
        "as" => Ok(v.to_string()),
        "um" => {
            let um = (number()? * 1000.0).round();
            if um < 1.0 {
                return Err(format!(
                    "CYCLE {}: {name} = {v}: at least 0.001 mm here (the control's word counts micrometres)",
                    c.number
                ));
            }
            Ok(format!("{}", um as i64))
        }
        "xside" | "zside" => {
            // A finishing allowance written with the sign of the stock's side (Fanuc's U and W:
            // negative for a bore), from its size as the library gives it.
            let n = number()?;
            let k = usize::from(spec == "zside");
            let Some(side) = side else {
                return Err(format!(
                    "CYCLE {}: {name}: the side of the stock is not known (the cycle's start and figure)",
                    c.number
                ));
            };
            let w = n.abs() * side[k];
            let t = format!("{w}");
            Ok(if spell.point_always { pointed(&t) } else { t })
        }
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
            "CYCLE {}: {{{name}:{other}}} in the dialect's block: the formats are {}",
            c.number,
            crate::catalogue::specs_named()
        )),
    }
}

/// Writes `output.tmp` (and `path.tmp` when the paths are known) whole or not at all; a path.tmp
/// of an earlier run is removed when this one has none.
fn write_outputs(output: &Path, path: &Path, done: &Converted) -> std::io::Result<()> {
    let mut sinks = Vec::new();
    let target = crate::output::Target::plan(output).map_err(std::io::Error::other)?;
    sinks.push(crate::output::write_text(&target, done.output.as_bytes())?);
    match &done.path {
        Some(text) => {
            let target = crate::output::Target::plan(path).map_err(std::io::Error::other)?;
            sinks.push(crate::output::write_text(&target, text.as_bytes())?);
        }
        None => {
            let _ = std::fs::remove_file(path);
        }
    }
    crate::output::commit_all(sinks)
}

/// The launcher script of `control` (post/launcher.py): the library's Python postprocessor that runs
/// `fmsvm post --dialect CONTROL`, with the control's machine cycles in its header comment.
pub fn launcher(control: &str, profile: &crate::dialects::Profile) -> String {
    include_str!("../post/launcher.py")
        .replace(
            "{CATALOGUE}",
            &crate::catalogue::machine_cycles_block(&profile.cycles),
        )
        .replace("{CONTROL}", control)
        .replace("{SUMMARY}", &profile.dialect.summary)
}
