//! `fmsvm post`: the turning library's postprocessor contract (docs/postprocessor.md). It reads the
//! library's `input.tmp` (the neutral language), writes `output.tmp` beside it in the control's
//! words (its machine cycles as its own blocks, from the dialect's `[[cycle]]` catalogue), and prints
//! exactly `OK`, or the errors one a line (`input.tmp:8:21: …`) and no `output.tmp`.
//!
//! Bounded: the input is at most 16 MiB and every step is linear in it, so a program the library
//! writes converts in well under its 10 seconds (the `post` tests time the largest).

mod cycle_moves;
mod post_blocks;
mod post_verify;
mod post_words;

use std::io::Write as _;
use std::path::{Path, PathBuf};

use crate::cycle_moves::Move;
use crate::post_words::MoveWords;
use fmsvm_driver::catalogue::{MachineCycle, Scheme};
use fmsvm_driver::exit::Exit;
use fmsvm_driver::neutral::{self, At, Block, Cycle, Error, Plain};

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
    /// The control: a built-in lathe dialect with machine cycles (`mayak600t`, `nc31`, `fanuc0itd`, `sinumerik802d`, `fagor8035t`, `iso`).
    #[arg(long, value_name = "NAME", conflicts_with = "dialect_file")]
    pub dialect: Option<String>,
    /// A dialect profile of your own (its `[[cycle]]` tables the control's machine cycles).
    #[arg(long, value_name = "FILE")]
    pub dialect_file: Option<PathBuf>,
    /// Every cycle in elementary moves, even those the control has.
    #[arg(long)]
    pub moves: bool,
    /// Read output.tmp back and compare its moves with the neutral program's: the default
    /// (docs/postprocessor.md); kept for the launchers of earlier versions.
    #[arg(long, hide = true, conflicts_with = "no_verify")]
    pub verify: bool,
    /// Do not read output.tmp back (nothing then checks that it moves as the library's program).
    #[arg(long)]
    pub no_verify: bool,
    /// The machine's highest spindle speed (rpm): the clamp written before constant surface speed
    /// (G96), which the neutral program cannot give. Without it (or the profile's `[lathe]
    /// max_rpm`) a G96 is refused on a control that does not clamp at power-on.
    #[arg(long, value_name = "RPM", value_parser = max_rpm)]
    pub max_rpm: Option<f64>,
}

/// `--max-rpm`: a spindle speed from 1 to 99999.
fn max_rpm(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && (1.0..=99_999.0).contains(&v) => Ok(v),
        _ => Err(format!("{s}: a spindle speed from 1 to 99999 rpm")),
    }
}

/// Runs `post`: prints `OK` or the errors on standard output.
pub fn main(a: &PostArgs) -> Exit {
    let name = a
        .input
        .file_name()
        .map_or_else(|| "input".into(), |n| n.to_string_lossy().into_owned());
    let output = a.input.with_file_name("output.tmp");
    let path_file = a.input.with_file_name("path.tmp");
    let mut out = std::io::stdout().lock();
    // The files post writes are its own to name: never its input (by name, or by a link to one
    // of them), and written as new files in the folder: the last program's are removed first, so
    // that nothing stale is left for this program's if it stops (an error, a signal) and a link
    // there is replaced, not written through.
    if let Err(e) = clear_outputs(&a.input, &[&output, &path_file]) {
        let _ = writeln!(out, "{e}");
        return Exit::Usage;
    }
    let result = convert(a, &name).and_then(|done| {
        if !a.no_verify {
            crate::post_verify::verify(&done, &name).map_err(|e| (vec![e], Exit::Verify))?;
        }
        Ok(done)
    });
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
#[derive(Clone, Debug)]
pub struct Converted {
    /// output.tmp's text (its lines ending as the input's).
    pub output: String,
    /// path.tmp's text, when the path inside every cycle is known.
    pub path: Option<String>,
    /// The neutral program's motion: its own moves and each cycle's path (X as a radius).
    pub motion: Vec<Move>,
    /// The control's profile.
    pub profile: fmsvm_driver::dialects::Profile,
    /// A cycle written as the control's own block (its motion is the control's to make).
    pub native: Option<u32>,
    /// output.tmp as `--verify` reads it where a cycle block is one fmsvm does not model (the
    /// Маяк-600Т's G72): that block's lines in its elementary moves, the rest as written. The
    /// block itself is written only for a record whose shape its words state exactly
    /// (`exact_native`).
    pub readable: Option<String>,
    /// The lines (from 0) holding such a block, and the words (address, value) the record makes
    /// it state: `--verify` reads them back from output.tmp.
    pub stated: Vec<(usize, Vec<(String, f64)>)>,
}

/// The control's program for the neutral program in `a.input`.
pub(crate) fn convert(a: &PostArgs, name: &str) -> Result<Converted, Failure> {
    let profile = match (&a.dialect, &a.dialect_file) {
        (Some(d), _) => fmsvm_driver::dialects::builtin(d),
        (None, Some(f)) => fmsvm_driver::input::read_bounded(f, 1 << 20)
            .map_err(|e| format!("{}: {e}", f.display()))
            .and_then(|b| {
                String::from_utf8(b).map_err(|_| format!("{}: not UTF-8 text", f.display()))
            })
            .and_then(|t| fmsvm_driver::dialects::load(&f.display().to_string(), &t)),
        (None, None) => Err("give the control: --dialect NAME or --dialect-file FILE".into()),
    }
    .map_err(|e| (vec![e], Exit::Usage))?;
    if profile.offered().is_empty() {
        return Err((
            vec![format!(
                "{}: the dialect declares no machine cycles ([[cycle]]); `fmsvm post` writes for the controls that have a catalogue (`fmsvm dialects` marks them)",
                profile.dialect.name
            )],
            Exit::Usage,
        ));
    }
    let bytes = fmsvm_driver::input::read_bounded(&a.input, MAX_INPUT).map_err(|e| {
        let what = match e {
            fmsvm_driver::input::ReadError::TooBig(_) => format!(
                "it is larger than {}, the most fmsvm post reads",
                fmsvm_driver::input::human(MAX_INPUT)
            ),
            e => e.to_string(),
        };
        (vec![format!("{}: {what}", a.input.display())], Exit::Io)
    })?;
    // The library writes in the Windows code page of its users when not in UTF-8.
    let charset = if std::str::from_utf8(&bytes).is_ok() {
        fmsvm_driver::input::Charset::Utf8
    } else {
        fmsvm_driver::input::Charset::Cp1251
    };
    let text = fmsvm_driver::input::decode(bytes, Some(charset))
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
    // The catalogue's TYPE decides whether a record has a profile, not the words it happens to have.
    let kind_of = |number: u32| {
        profile
            .cycles
            .iter()
            .find(|m| m.number == number)
            .map(|m| match m.kind.as_str() {
                "Drilling" => neutral::Kind::Drilling,
                "Threading" => neutral::Kind::Threading,
                _ => neutral::Kind::Turning,
            })
    };
    let blocks = neutral::parse_for(&text, &kind_of).map_err(located)?;
    let words = crate::post_blocks::Translator::new(&profile.dialect, a.max_rpm)
        .map_err(|e| (vec![e], Exit::Usage))?;
    let mut w = Writer::new(&profile, words, a.moves);
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
    let readable = w.readable;
    Ok(Converted {
        output,
        readable,
        stated: w.stated,
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
}

/// The program as the control's blocks, the paths inside its cycles, and the neutral program's
/// motion, made in one pass over the blocks.
struct Writer<'p> {
    profile: &'p fmsvm_driver::dialects::Profile,
    spell: Spelling,
    /// The control's table for ordinary blocks.
    words: crate::post_blocks::Translator<'p>,
    /// For each line of `lines` that `--verify` reads otherwise (an unmodelled native cycle's):
    /// its index and the lines read instead.
    readable_lines: Vec<(usize, Vec<String>)>,
    /// For each line of `lines` holding such a cycle's block: the words the record makes it state.
    stated: Vec<(usize, Vec<(String, f64)>)>,
    readable: Option<String>,
    /// The program's start words (`Translator::start`), until the first block takes them.
    pending_start: Option<String>,
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
    /// The neutral program's F in force (per revolution), as its last F word.
    feed: Option<fmsvm_driver::neutral::Word>,
    /// That F, to be written again on the next block after a cycle that fed at its own.
    pending_feed: Option<fmsvm_driver::neutral::Word>,
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
    fn new(
        profile: &'p fmsvm_driver::dialects::Profile,
        words: crate::post_blocks::Translator<'p>,
        all_moves: bool,
    ) -> Self {
        Writer {
            profile,
            words,
            readable_lines: Vec::new(),
            stated: Vec::new(),
            readable: None,
            pending_start: None,
            spell: Spelling {
                point_always: profile.dialect.format(fmsvm_block::Letter::X).point
                    == fmsvm_emit::dialect::Point::Always,
            },
            all_moves,
            lines: Vec::new(),
            first_n: None,
            at: [None, None],
            motion: 0,
            spindle: None,
            feed: None,
            pending_feed: None,
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
        let start = self.words.start().join(" ");
        match blocks.first() {
            Some(Block::Cycle(_)) => self.lines.push(start),
            Some(Block::Plain(_)) => self.pending_start = Some(start),
            None => {}
        }
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
        // Numbered on from the first block's N; past the control's largest N (the Маяк-600Т's
        // 999) the numbers start again at its first, as its profile says.
        let d = &self.profile.dialect;
        let most = d.integer_max(fmsvm_block::Letter::N).max(1) as usize;
        let restart = match d.line_numbers {
            fmsvm_emit::dialect::LineNumbers::Renumber { start, .. } => start as usize,
            _ => 1,
        };
        let mut n = self.first_n.map(|n| n as usize);
        let mut text = String::new();
        let mut readable = (!self.readable_lines.is_empty()).then(String::new);
        let mut replaced = self.readable_lines.iter().peekable();
        for (k, l) in self.lines.iter().enumerate() {
            let number = n.map(|v| format!("N{v:03} "));
            if let Some(number) = &number {
                text.push_str(number);
            }
            text.push_str(l);
            text.push('\n');
            if let Some(r) = readable.as_mut() {
                match replaced.peek() {
                    Some((i, instead)) if *i == k => {
                        for l in instead {
                            r.push_str(number.as_deref().unwrap_or(""));
                            r.push_str(l);
                            r.push('\n');
                        }
                        replaced.next();
                    }
                    _ => {
                        r.push_str(number.as_deref().unwrap_or(""));
                        r.push_str(l);
                        r.push('\n');
                    }
                }
            }
            n = n.map(|v| if v + 1 > most { restart } else { v + 1 });
        }
        self.text = text;
        self.readable = readable;
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

    /// An ordinary block: in the control's words (`post_blocks`); its move and spindle followed.
    fn plain_block(&mut self, p: &Plain) -> Result<(), Vec<Error>> {
        // The program's F again after a cycle's own, on the block after it (the library's return
        // to the cycle's start) unless that block says its own.
        let with_feed;
        let p = match self.pending_feed.take() {
            Some(f) if p.get('F').is_none() => {
                let mut q = p.clone();
                q.words.push(f);
                with_feed = q;
                &with_feed
            }
            _ => p,
        };
        let located = |what: String| {
            vec![Error {
                at: At {
                    line: p.line,
                    col: 1,
                },
                what,
            }]
        };
        for w in &p.words {
            match (w.letter, w.value as u32) {
                ('G', g @ 0..=3) if w.value.fract() == 0.0 => self.motion = g as u8,
                ('M', 3) => self.spindle = Some(3),
                ('M', 4) => self.spindle = Some(4),
                ('M', 5 | 30) => self.spindle = None,
                ('F', _) => self.feed = Some(w.clone()),
                _ => {}
            }
        }
        let feed = self.feed.as_ref().map(|w| w.value);
        let (x, z) = (p.get('X'), p.get('Z'));
        let mut mv = None;
        let mut arc = None;
        if !p.has_g(4.0) && (x.is_some() || z.is_some()) {
            // A dwell's X is its time.
            let from = self.at;
            if let Some(x) = x {
                self.at[0] = Some(x / 2.0);
            }
            if let Some(z) = z {
                self.at[1] = Some(z);
            }
            if let [Some(tx), Some(tz)] = self.at {
                let to = [tx, tz];
                mv = Some(match self.motion {
                    0 => Move::Rapid(to),
                    1 => Move::Feed(to, feed),
                    m => {
                        let (Some(fx), Some(fz)) = (from[0], from[1]) else {
                            return Err(located(
                                "an arc before the tool's X and Z are known".into(),
                            ));
                        };
                        let centre = arc_centre(p, [fx, fz], to, m == 2).map_err(located)?;
                        arc = Some(([fx, fz], centre));
                        Move::Arc {
                            to,
                            centre,
                            cw: m == 2,
                            f: feed,
                        }
                    }
                });
            }
        }
        let mut lines = self.words.block(p, arc).map_err(|e| vec![e])?;
        if let Some(start) = self.pending_start.take() {
            match lines.first_mut() {
                Some(first) => {
                    // A word the start already says (the library's G90) is not said twice.
                    let said: Vec<&str> = start.split_whitespace().collect();
                    let rest: Vec<&str> = first
                        .split_whitespace()
                        .filter(|w| !said.contains(w))
                        .collect();
                    *first = std::iter::once(start.as_str())
                        .chain(rest)
                        .collect::<Vec<_>>()
                        .join(" ");
                }
                None => lines.push(start),
            }
        }
        self.lines.append(&mut lines);
        if let Some(mv) = mv {
            self.motion_moves.push(mv);
        }
        Ok(())
    }

    /// A cycle record: the control's block, or elementary moves; its path kept for path.tmp.
    fn cycle(&mut self, c: &Cycle) -> Result<(), Vec<Error>> {
        self.feed_before_cycle(c).map_err(|e| vec![e])?;
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
                self.profile
                    .offered()
                    .iter()
                    .map(|m| m.number.to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            )));
        };
        if let Some(why) = self.profile.withheld(m, self.all_moves) {
            return Err(located(format!(
                "CYCLE {}: the control cannot take it: {why}",
                c.number
            )));
        }
        check_parameters(c, m)?;
        // Threads are cut at constant rpm: the lead follows the spindle, and a surface speed
        // would change the rpm along a cone or a face.
        if matches!(m.moves, Some(Scheme::Threading | Scheme::Tapping)) && self.words.css() {
            return Err(located(format!(
                "CYCLE {}: a thread under G96 (constant surface speed): threads are cut at constant rpm; have the library write G97 S… before it",
                c.number
            )));
        }
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
                return Err(located(unknown_start(c)));
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
            let mut lines = self.elementary(c, s, &moves).map_err(located)?;
            self.lines.append(&mut lines);
            self.keep_path(c, s, &moves);
            self.spindle = spindle_after(&moves, self.spindle);
            self.restore_feed(&moves);
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
                return Err(located(unknown_start(c)));
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
        let mut l = native(
            c,
            m,
            self.spell,
            base,
            side,
            (&mut self.words, start, self.motion),
        )?;
        // A cycle block fmsvm does not model (the Маяк-600Т's: not a Fanuc's, which --verify
        // expands) is written only for a record its words state exactly, and --verify reads its
        // elementary moves in its place.
        let modelled = crate::post_verify::expands_own_cycles(&self.profile.dialect);
        // (A block of a shop's profile with no model at all, `moves` unset, has no path: the
        // verification then refuses the output, unless it is turned off.)
        if !modelled && m.moves.is_some() {
            if !matches!(m.moves, Some(Scheme::Turning | Scheme::Facing)) {
                return Err(located(format!(
                    "CYCLE {}: the control's own block for it is not modelled by fmsvm, which cannot check that it states this record exactly: choose the elementary moves (--moves)",
                    c.number
                )));
            }
            trapezoid(c, m).map_err(located)?;
            let (Some(s), Some(moves)) = (start, moves.as_ref()) else {
                return Err(located(unknown_start(c)));
            };
            let instead = self.elementary(c, s, moves).map_err(located)?;
            let first = self.lines.len();
            for (k, words) in stated_words(c, m).map_err(located)?.into_iter().enumerate() {
                self.stated.push((first + k, words));
            }
            self.readable_lines.push((first, instead));
            for k in 1..l.len() {
                self.readable_lines.push((first + k, Vec::new()));
            }
        }
        self.lines.append(&mut l);
        self.native.get_or_insert(c.number);
        match (start, moves) {
            (Some(s), Some(moves)) => {
                self.keep_path(c, s, &moves);
                self.restore_feed(&moves);
            }
            _ => self.paths = None,
        }
        Ok(())
    }

    /// The neutral program's F again after a cycle that fed at its own (the record's F): the
    /// library's next block without an F means the feed it set before the cycle, and the
    /// control would keep the cycle's. Written on the next block (`pending_feed`).
    fn restore_feed(&mut self, moves: &[Move]) {
        let Some(f) = self.feed.clone() else {
            return;
        };
        let own = moves.iter().any(|m| match m {
            Move::Feed(_, Some(v)) | Move::Arc { f: Some(v), .. } => (v - f.value).abs() > 1e-9,
            _ => false,
        });
        if own {
            self.pending_feed = Some(f);
        }
    }

    /// The F a cycle left pending when another cycle follows at once: a block of its own.
    fn feed_before_cycle(&mut self, c: &Cycle) -> Result<(), Error> {
        if let Some(f) = self.pending_feed.take() {
            let block = fmsvm_driver::neutral::Plain {
                line: c.line,
                n: None,
                words: vec![f],
            };
            let mut lines = self.words.block(&block, None)?;
            self.lines.append(&mut lines);
        }
        Ok(())
    }

    /// A cycle's moves from `start` as the control's blocks, then the neutral program's motion code
    /// again where the moves left another in force (a later block without a G code moves as the
    /// library meant it to).
    fn elementary(
        &self,
        c: &Cycle,
        start: [f64; 2],
        moves: &[Move],
    ) -> Result<Vec<String>, String> {
        let mut words = MoveWords::control(&self.profile.dialect, start);
        let mut lines = Vec::new();
        for mv in moves {
            if let Some(l) = words
                .line(mv)
                .map_err(|e| format!("CYCLE {}: {e}", c.number))?
            {
                lines.push(l);
            }
        }
        lines.extend(words.restore(self.motion));
        Ok(lines)
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

/// A cycle whose start point is not known.
fn unknown_start(c: &Cycle) -> String {
    format!(
        "CYCLE {}: the tool's X and Z are not known before it (its start point): move there first (G00 X… Z…)",
        c.number
    )
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
        // The thread's hand: the library's manual names it (§4.3, "_DIRECT hand (right/left)")
        // but not how its value says which, and the hand a lathe cuts follows the spindle's
        // direction and the tool's side, which fmsvm takes from the program. A value it cannot
        // read is refused rather than ignored: the program's M03/M04 says the hand.
        if p.name == "_DIRECT" {
            errors.push(Error {
                at: p.at,
                what: format!(
                    "CYCLE {}: _DIRECT (the thread's hand): how its value says right or left is not in the library's manual, and fmsvm cuts the hand the program's spindle direction (M03/M04) gives; leave _DIRECT out of the record",
                    c.number
                ),
            });
            continue;
        }
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
    (words, start, motion): (
        &mut crate::post_blocks::Translator<'_>,
        Option<[f64; 2]>,
        u8,
    ),
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
        let pocket_entry = if infeed.is_none() {
            pocket_entry(c, m)
        } else {
            None
        };
        out.extend(infeed);
        // The profile's blocks in the control's words, followed from the figure's begin (where
        // the infeed leaves the tool) so that each arc's centre is known.
        let mut at = profile_start(c, m, start);
        let mut motion = motion;
        for (k, p) in c.profile.iter().enumerate() {
            let p = match (&pocket_entry, k) {
                (Some(entry), 0) => entry,
                _ => p,
            };
            let mut arc = None;
            if let Some(g) = p.words.iter().find(|w| w.letter == 'G' && w.value <= 3.0) {
                motion = g.value as u8;
            }
            let to = at.map(|a| {
                [
                    p.get('X').map_or(a[0], |x| x / 2.0),
                    p.get('Z').unwrap_or(a[1]),
                ]
            });
            if motion >= 2
                && let (Some(from), Some(to)) = (at, to)
            {
                match arc_centre(p, from, to, motion == 2) {
                    Ok(centre) => arc = Some((from, centre)),
                    Err(what) => errors.push(Error {
                        at: At {
                            line: p.line,
                            col: 1,
                        },
                        what,
                    }),
                }
            }
            at = to;
            match words.block(p, arc) {
                Ok(mut l) => out.append(&mut l),
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

/// A profile with pockets (type II) whose own first block is the infeed along the level axis: that
/// block with the other axis named too (at the figure's begin, where the tool already is), as the
/// control's type II needs.
fn pocket_entry(c: &Cycle, m: &MachineCycle) -> Option<fmsvm_driver::neutral::Plain> {
    if !crate::cycle_moves::type_two(c, m) {
        return None;
    }
    let first = c.profile.first()?;
    let (letter, name) = if m.moves == Some(Scheme::Facing) {
        ('X', "_Xbegin")
    } else {
        ('Z', "_Zbegin")
    };
    if first.get(letter).is_some() {
        return None;
    }
    let begin = c.param(name)?;
    let mut entry = first.clone();
    entry.words.push(fmsvm_driver::neutral::Word {
        letter,
        text: begin.text.clone(),
        value: begin.value,
        at: begin.at,
    });
    Some(entry)
}

/// Where a kept profile's first block starts: the cycle's start moved to the figure's begin along
/// the level axis (X for turning, Z for facing), where the infeed leaves the tool.
fn profile_start(c: &Cycle, m: &MachineCycle, start: Option<[f64; 2]>) -> Option<[f64; 2]> {
    let mut at = start?;
    match m.moves {
        Some(Scheme::Facing) => at[1] = c.param("_Zbegin")?.value,
        Some(Scheme::Turning | Scheme::Pattern) => at[0] = c.param("_Xbegin")?.value / 2.0,
        _ => {}
    }
    Some(at)
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
    let spelled = |text: &str| {
        if spell.point_always {
            pointed(text)
        } else {
            text.to_string()
        }
    };
    // A profile with pockets (type II) names both axes in its first block: the infeed, or the
    // profile's own first block (`pocket_entry`).
    if crate::cycle_moves::type_two(c, m) {
        if already {
            return Ok(None);
        }
        let other_name = if letter == 'X' { "_Zbegin" } else { "_Xbegin" };
        let Some(o) = c.param(other_name) else {
            return Err(format!(
                "CYCLE {}: the record has no {other_name}, where the control's profile starts",
                c.number
            ));
        };
        let (x, z) = if letter == 'X' {
            (begin, o)
        } else {
            (o, begin)
        };
        return Ok(Some(format!(
            "G00 X{} Z{}",
            spelled(&x.text),
            spelled(&z.text)
        )));
    }
    if already {
        return Ok(None);
    }
    Ok(Some(format!("G00 {letter}{}", spelled(&begin.text))))
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
            Some(p) if p.kind == "A" => automatic(name, c, m)?,
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

/// The words (address, value) each line of a cycle's block states for record `c`, from the
/// catalogue's block and the record's values (K computed from the figure), not from the text
/// written: what `--verify` reads back from a block it cannot expand. A word whose parameter is
/// not given and has no default is not written, and so not stated.
fn stated_words(c: &Cycle, m: &MachineCycle) -> Result<Vec<Vec<(String, f64)>>, String> {
    let mut lines = Vec::new();
    for line in m.block.as_deref().unwrap_or_default().lines() {
        let mut words = Vec::new();
        for token in line.split_whitespace() {
            let Some((address, rest)) = token.split_once('{') else {
                continue;
            };
            let name = rest.split(['}', ':']).next().unwrap_or_default();
            let kind = m.parameters.iter().find(|p| p.name == name);
            let value = match (c.param(name), kind) {
                (Some(p), _) => Some(p.value),
                (None, Some(p)) if p.kind == "A" && name == "K" => Some(trapezoid(c, m)?),
                (None, Some(p)) => p.default.as_deref().and_then(|d| d.parse::<f64>().ok()),
                (None, None) => None,
            };
            if let Some(v) = value {
                words.push((address.to_string(), v));
            }
        }
        lines.push(words);
    }
    Ok(lines)
}

/// An automatic parameter the library leaves to the postprocessor ("A": "computed by the library
/// … or by the postprocessor", shown as `auto`): K, the taper, from the figure (`trapezoid`).
fn automatic(name: &str, c: &Cycle, m: &MachineCycle) -> Result<Option<String>, String> {
    match name {
        "K" => {
            let k = trapezoid(c, m)?;
            let t = format!("{k:.4}");
            let t = t.trim_end_matches('0').trim_end_matches('.');
            Ok(Some(if t == "-0" || t.is_empty() {
                "0".into()
            } else {
                t.to_string()
            }))
        }
        _ => Ok(None),
    }
}

/// The taper K of a trapezoid figure (the catalogue's PROFIL_DEMANDS `TrapecG1`–`4` for turning,
/// `TrapecV1`–`4` for facing), or why the record's profile is not one: the one shape a
/// longitudinal (facing) cycle block with its end point and a taper states exactly. Judged by the
/// motion, not the words: from the figure's begin, one straight move along Z (facing: along X),
/// which may change the other axis too (a cone), then one straight move along X only (facing: Z
/// only) to the figure's end. K is the cone's конусность as ГОСТ 25548 defines it, (D − d)/L: the
/// change of diameter over the length, signed as the diameter grows from the begin towards the
/// end; 0 for a cylinder (the library's listing: `K0`). A facing figure's cone is refused (how the
/// control counts a face's taper is not in the sources).
fn trapezoid(c: &Cycle, m: &MachineCycle) -> Result<f64, String> {
    let facing = m.moves == Some(Scheme::Facing);
    let refuse = |why: String| {
        format!(
            "CYCLE {}: the control's block states a trapezoid ({}), and this figure is not one: {why}; choose the elementary moves for it (--moves)",
            c.number,
            if facing {
                "TrapecV1–4"
            } else {
                "TrapecG1–4"
            }
        )
    };
    let get = |name: &str| {
        c.param(name)
            .map(|p| p.value)
            .ok_or_else(|| refuse(format!("the record has no {name}")))
    };
    let mut at = [get("_Xbegin")?, get("_Zbegin")?];
    let end = [get("_Xend")?, get("_Zend")?];
    // The moves that move, as points (X a diameter).
    let mut points = Vec::new();
    for b in &c.profile {
        if b.words
            .iter()
            .any(|w| w.letter == 'G' && (w.value == 2.0 || w.value == 3.0))
            || b.get('R').is_some()
            || b.get('I').is_some()
            || b.get('K').is_some()
        {
            return Err(refuse(format!("line {} is an arc", b.line)));
        }
        let to = [b.get('X').unwrap_or(at[0]), b.get('Z').unwrap_or(at[1])];
        if (to[0] - at[0]).abs() > 0.005 || (to[1] - at[1]).abs() > 0.005 {
            points.push((b.line, to));
            at = to;
        }
    }
    // `cut`: the axis the first move runs along (Z turning, X facing); `level` the other.
    let (cut, level) = if facing { (0, 1) } else { (1, 0) };
    let [(_, corner), (line, last)] = points[..] else {
        return Err(refuse(format!(
            "its profile makes {} moves, where a trapezoid makes two",
            points.len()
        )));
    };
    let begin = [get("_Xbegin")?, get("_Zbegin")?];
    if (last[cut] - corner[cut]).abs() > 0.005 || (last[level] - corner[level]).abs() < 0.005 {
        return Err(refuse(format!(
            "line {line}: its second move is not square to the cut (along {} only)",
            if facing { "Z" } else { "X" }
        )));
    }
    if (last[0] - end[0]).abs() > 0.005 || (last[1] - end[1]).abs() > 0.005 {
        return Err(refuse(format!(
            "line {line}: the profile ends at X{} Z{}, not at the figure's end _Xend _Zend",
            last[0], last[1]
        )));
    }
    let length = (corner[cut] - begin[cut]).abs();
    let rise = corner[level] - begin[level];
    if length < 0.005 {
        return Err(refuse("its first move does not run along the cut".into()));
    }
    if rise.abs() <= 0.005 {
        return Ok(0.0);
    }
    if facing {
        return Err(refuse("its face is a cone".into()));
    }
    Ok(rise / length)
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
            fmsvm_driver::catalogue::specs_named()
        )),
    }
}

/// Before `post` runs: refuses an input that is one of `outputs` (by name, or the same file through
/// a link), and removes the outputs of an earlier run (a link itself, never what it points to); a
/// folder, a FIFO or a device there is refused, not removed.
fn clear_outputs(input: &Path, outputs: &[&Path]) -> Result<(), String> {
    let input_id = fmsvm_driver::output::identity(input);
    for &o in outputs {
        let Ok(meta) = std::fs::symlink_metadata(o) else {
            continue;
        };
        if o == input || (input_id.is_some() && fmsvm_driver::output::identity(o) == input_id) {
            return Err(format!(
                "{}: post writes {} itself; give the neutral program another name",
                input.display(),
                o.display()
            ));
        }
        let t = meta.file_type();
        if !(t.is_file() || t.is_symlink()) {
            return Err(format!(
                "{} is not a file post may replace (a folder, a FIFO or a device); move it away",
                o.display()
            ));
        }
        std::fs::remove_file(o).map_err(|e| format!("{}: {e}", o.display()))?;
    }
    Ok(())
}

/// Writes `output.tmp` (and `path.tmp` when the paths are known) whole or not at all; a path.tmp
/// of an earlier run is removed when this one has none.
fn write_outputs(output: &Path, path: &Path, done: &Converted) -> std::io::Result<()> {
    // `post` installs no signal handler: its temporary files are its own to list.
    let temps = std::sync::Arc::default();
    let mut sinks = Vec::new();
    let target =
        fmsvm_driver::output::Target::plan(output, &temps).map_err(std::io::Error::other)?;
    sinks.push(fmsvm_driver::output::write_text(
        &target,
        done.output.as_bytes(),
    )?);
    match &done.path {
        Some(text) => {
            let target =
                fmsvm_driver::output::Target::plan(path, &temps).map_err(std::io::Error::other)?;
            sinks.push(fmsvm_driver::output::write_text(&target, text.as_bytes())?);
        }
        None => {
            let _ = std::fs::remove_file(path);
        }
    }
    fmsvm_driver::output::commit_all(sinks)
}

/// The launcher script of `control` (post/launcher.py): the library's Python postprocessor that runs
/// `fmsvm post --dialect CONTROL`, with the control's machine cycles in its header comment.
pub fn launcher(
    control: &str,
    profile: &fmsvm_driver::dialects::Profile,
) -> Result<String, String> {
    // The name and the summary go into the script's comments, its docstring and a string: text
    // that could end one of them (a quote, a backslash, a line break) is refused, not escaped.
    for (what, text) in [
        ("name", control),
        ("summary", profile.dialect.summary.as_str()),
    ] {
        if text
            .chars()
            .any(|c| matches!(c, '"' | '\\') || c.is_control())
        {
            return Err(format!(
                "the launcher's {what} {text:?} has a double quote, a backslash or a control character, which the script cannot hold as text"
            ));
        }
    }
    Ok(include_str!("../../../post/launcher.py")
        .replace(
            "{CATALOGUE}",
            &fmsvm_driver::catalogue::machine_cycles_block(&profile.offered()),
        )
        .replace("{CONTROL}", control)
        .replace("{SUMMARY}", &profile.dialect.summary))
}
