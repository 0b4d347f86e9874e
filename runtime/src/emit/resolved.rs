//! The resolved emitter: canonical operations written as flat motion — G0/G1/G2/G3 in G90 (with G4, F,
//! S, T, M and comments), every offset, transform, cycle and compensation already applied — in the
//! dialect's number format. What `ncmotion` compares against LinuxCNC's trace.
//!
//! Rules: the first block sets the frame (`G90` with the plane and units); a motion G code is written
//! when it changes, an axis word when its rounded value changes (arcs always carry their plane's two
//! axes and the centre as I J K from the start), F on the first feed move after it changes; a move
//! that rounds to no motion is left out. Arcs in another plane are preceded by G17/G18/G19. Dwells are
//! `G4 P<ms>`.

use std::io::Write;

use fmsvm_block::{Alarm, Letter, Stop};

use super::Emitter;
use super::format::{push_fixed, push_u64};
use super::lines::{Lines, push_comments};
use super::literal::Options;
use crate::canon::{Arc, Canon, Origin, Plane, Pose};
use crate::dialect::Dialect;
use crate::kernel::AXES;

/// Writes canonical operations as flat motion.
pub struct ResolvedEmitter<W: Write> {
    lines: Lines<W>,
    dialect: Dialect,
    options: Options,
    next_n: u32,
    inch: bool,
    /// Exact position of the tool (output frame).
    at: Pose,
    /// Rounded position as last written, in least increments (None: never written).
    written: [Option<i64>; 6],
    /// Motion G code ×10 in effect in the output, if any yet.
    motion: Option<u16>,
    plane: Plane,
    /// The frame line went out.
    started: bool,
    /// The unit the output last said (G20 true, G21 false), if any yet.
    units: Option<bool>,
    /// The feed rate programmed, and whether the output still has to say it.
    feed: f64,
    feed_due: bool,
}

impl<W: Write> ResolvedEmitter<W> {
    /// An emitter writing to `out`.
    pub fn new(out: W, dialect: Dialect, options: Options) -> Self {
        let next_n = options.renumber.map_or(0, |r| r.0);
        ResolvedEmitter {
            lines: Lines::new(out, options.eol, options.budget.clone()),
            dialect,
            options,
            next_n,
            inch: false,
            at: [0.0; 6],
            written: [None; 6],
            motion: None,
            plane: Plane::XY,
            units: None,
            started: false,
            feed: 0.0,
            feed_due: false,
        }
    }

    fn start_line(&mut self, origin: Origin) {
        if origin.block_delete {
            self.lines.buf.push(b'/');
        }
        if let Some((start, step)) = self.options.renumber {
            self.lines.buf.push(b'N');
            push_u64(&mut self.lines.buf, self.next_n as u64);
            self.lines.buf.push(b' ');
            self.next_n = self.next_n.saturating_add(step);
            if self.next_n > 99_999 {
                self.next_n = start;
            }
        }
    }

    /// `value` of `letter` in least increments, or alarm 0003 when it does not fit the dialect.
    fn quantize(&self, letter: Letter, value: f64) -> Result<i64, Alarm> {
        self.dialect
            .least_increments(value, self.dialect.digits(letter, self.inch))
            .ok_or_else(|| {
                Alarm::new(
                    3,
                    format!(
                        "too many digits: the resolved {letter}{value} does not fit {} digits",
                        self.dialect.max_digits
                    ),
                )
            })
    }

    fn push_number(&mut self, letter: Letter, q: i64) {
        if !self.lines.line_is_empty() && !self.lines.buf.ends_with(b" ") {
            self.lines.buf.push(b' ');
        }
        self.lines.buf.extend_from_slice(letter.as_str().as_bytes());
        push_fixed(
            &mut self.lines.buf,
            q,
            self.dialect.digits(letter, self.inch),
        );
    }

    fn push_code(&mut self, letter: u8, code: u16) {
        if !self.lines.line_is_empty() && !self.lines.buf.ends_with(b" ") {
            self.lines.buf.push(b' ');
        }
        self.lines.buf.push(letter);
        push_u64(&mut self.lines.buf, (code / 10) as u64);
        if !code.is_multiple_of(10) {
            self.lines.buf.push(b'.');
            push_u64(&mut self.lines.buf, (code % 10) as u64);
        }
    }

    /// One motion line: its G code, the axis words that change (and `always`), then the extra words.
    fn motion_line(
        &mut self,
        code: u16,
        to: &Pose,
        always: &[usize],
        centre: Option<(&Arc, &Pose)>,
        origin: Origin,
    ) -> Result<(), Stop> {
        let mut q = [0i64; 6];
        let mut change = [false; 6];
        for i in 0..6 {
            q[i] = self.quantize(AXES[i], to[i])?;
            change[i] = self.written[i] != Some(q[i]) || always.contains(&i);
        }
        if centre.is_none() && !change.iter().any(|&c| c) {
            self.at = *to;
            return Ok(());
        }
        self.start_line(origin);
        if let Some((arc, _)) = centre
            && arc.plane != self.plane
        {
            self.push_code(b'G', arc.plane.code());
            self.plane = arc.plane;
        }
        if self.motion != Some(code) {
            self.push_code(b'G', code);
            self.motion = Some(code);
        }
        for i in 0..6 {
            if change[i] {
                self.push_number(AXES[i], q[i]);
                self.written[i] = Some(q[i]);
            }
        }
        if let Some((arc, from)) = centre {
            let (a, b, _) = arc.plane.axes();
            let offsets = [Letter::I, Letter::J, Letter::K];
            for (axis, c) in [(a, arc.centre[0]), (b, arc.centre[1])] {
                let letter = offsets[axis];
                let v = self.quantize(letter, c - from[axis])?;
                self.push_number(letter, v);
            }
        }
        if code != 0 && self.feed_due {
            let f = self.quantize(Letter::F, self.feed)?;
            self.push_number(Letter::F, f);
            self.feed_due = false;
        }
        self.at = *to;
        self.lines.end_line()
    }

    fn word_line(&mut self, letter: Letter, value: f64, origin: Origin) -> Result<(), Stop> {
        self.start_line(origin);
        self.lines.buf.extend_from_slice(letter.as_str().as_bytes());
        let r = value.round();
        if (value - r).abs() < 1e-9 && r >= 0.0 {
            push_u64(&mut self.lines.buf, r as u64);
        } else {
            let q = self.quantize(Letter::X, value)?;
            push_fixed(
                &mut self.lines.buf,
                q,
                self.dialect.digits(Letter::X, self.inch),
            );
        }
        self.lines.end_line()
    }
}

impl<W: Write> Emitter for ResolvedEmitter<W> {
    const CANON: bool = true;

    fn begin(&mut self, number: Option<u32>, title: &str) -> Result<(), Stop> {
        self.lines.tape_start(number, title)
    }

    fn canon(&mut self, op: &Canon<'_>, origin: Origin) -> Result<(), Stop> {
        match *op {
            Canon::Start(p) => {
                // The tool is there (at the start, or after the output frame moved). The next move
                // spells X Y Z in full (a reader of the flat program cannot know where the tool
                // stood); A B C only when they move.
                self.at = p;
                for i in 0..6 {
                    self.written[i] = if i < 3 {
                        None
                    } else {
                        Some(self.quantize(AXES[i], p[i])?)
                    };
                }
                if self.started {
                    return Ok(());
                }
                self.started = true;
                self.lines.buf.extend_from_slice(b"G90 G17");
                self.lines.end_line()
            }
            Canon::Units(inch) => {
                // Written at the start and where the unit changes; a repeated G21 says nothing.
                if self.units == Some(inch) {
                    return Ok(());
                }
                let changed = self.units.is_some() && inch != self.inch;
                self.units = Some(inch);
                self.inch = inch;
                self.start_line(origin);
                self.push_code(b'G', if inch { 200 } else { 210 });
                // Lengths are spelled anew in a new unit; angles (A B C) are not lengths.
                if changed {
                    self.written[..3].fill(None);
                }
                self.lines.end_line()
            }
            Canon::FeedPerRev(per_rev) => {
                self.start_line(origin);
                self.push_code(b'G', if per_rev { 950 } else { 940 });
                self.feed_due = true;
                self.lines.end_line()
            }
            Canon::Rapid(to) => self.motion_line(0, &to, &[], None, origin),
            Canon::Feed(to) => self.motion_line(10, &to, &[], None, origin),
            Canon::Arc(arc) => {
                let from = self.at;
                let (a, b, _) = arc.plane.axes();
                let code = if arc.clockwise { 20 } else { 30 };
                for turn in 0..arc.turns {
                    // Whole turns first (Fanuc has no turn count): full circles rising their share.
                    let mut p = from;
                    let (_, sweep) = arc.sweep(&from);
                    let (_, _, n) = arc.plane.axes();
                    let t = (turn + 1) as f64 * std::f64::consts::TAU / sweep;
                    p[n] = from[n] + (arc.to[n] - from[n]) * t;
                    let full = Arc {
                        to: p,
                        turns: 0,
                        ..arc
                    };
                    let start = self.at;
                    self.motion_line(code, &p, &[a, b], Some((&full, &start)), origin)?;
                }
                let start = self.at;
                self.motion_line(code, &arc.to, &[a, b], Some((&arc, &start)), origin)
            }
            Canon::Dwell(seconds) => {
                self.start_line(origin);
                self.lines.buf.extend_from_slice(b"G4 P");
                push_u64(
                    &mut self.lines.buf,
                    (seconds * 1000.0).round().max(0.0) as u64,
                );
                self.lines.end_line()
            }
            Canon::FeedRate(f) => {
                if f != self.feed {
                    self.feed = f;
                    self.feed_due = true;
                }
                Ok(())
            }
            Canon::Speed(s) => self.word_line(Letter::S, s, origin),
            Canon::Tool(t) => self.word_line(Letter::T, t, origin),
            Canon::MCode(m) => self.word_line(Letter::M, m, origin),
            Canon::Comment(text) => {
                if self.options.comments {
                    self.start_line(origin);
                    push_comments(&mut self.lines.buf, text);
                    self.lines.end_line()?;
                }
                Ok(())
            }
        }
    }

    fn message(&mut self, number: u32, text: &str) -> Result<(), Stop> {
        self.lines.message(number, text)
    }

    fn written(&self) -> u64 {
        self.lines.written()
    }

    fn end(&mut self) -> Result<(), Stop> {
        self.lines.tape_end()
    }
}
