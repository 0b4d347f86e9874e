//! The reader of word-address dialects (Fanuc, ISO, LinuxCNC, FMS-3000, the lathe controls): the
//! resolved output's blocks read back as the dialect's profile says they are spelled — comments,
//! number formats (a number without a point is least increments where the dialect always writes
//! one), block ends, G0–G3 with I J K or R, the FMS-3000 helix pitch, every dwell form, inch.

use std::io::BufRead;

use fmsvm_block::Letter;

use super::{Motion, Move, ReadError, Reader};
use crate::arcs::{self, CentreWords};
use crate::canon::{Plane, Pose};
use crate::dialect::{CommentStyle, Dialect, DwellForm, HelixForm, Point};

/// Reads the resolved output of a word-address dialect.
pub struct WordReader<R: BufRead> {
    input: R,
    dialect: Dialect,
    line: u32,
    text: String,
    /// Where the tool is (NaN: never said).
    at: Pose,
    motion: u16,
    plane: Plane,
    inch: bool,
    feed: f64,
    /// A move of a block waiting to be returned (an arc block and its dwell never share one).
    done: bool,
}

impl<R: BufRead> WordReader<R> {
    /// A reader of `input`, written in `dialect`.
    pub fn new(input: R, dialect: Dialect) -> Self {
        WordReader {
            input,
            dialect,
            line: 0,
            text: String::new(),
            at: [f64::NAN; 6],
            motion: 0,
            plane: Plane::XY,
            inch: false,
            feed: f64::NAN,
            done: false,
        }
    }

    fn error(&self, message: String) -> ReadError {
        ReadError {
            line: self.line,
            message: format!("`{}`: {message}", self.text.trim_end()),
        }
    }

    /// The words of the current line: (letter, value as written, had a point).
    fn words(&self) -> Result<Vec<(Letter, f64)>, ReadError> {
        let mut s = self.text.trim_end_matches(['\r', '\n']).to_string();
        match self.dialect.comments {
            CommentStyle::Paren => {
                while let Some(i) = s.find('(') {
                    let j = s[i..].find(')').map_or(s.len(), |j| i + j + 1);
                    s.replace_range(i..j, " ");
                }
            }
            CommentStyle::Semicolon => {
                if let Some(i) = s.find(';') {
                    s.truncate(i);
                }
            }
            CommentStyle::None => {}
        }
        let b = s.as_bytes();
        let mut out = Vec::new();
        let mut i = 0;
        if b.first() == Some(&b'/') {
            i = 1;
        }
        while i < b.len() {
            let c = b[i];
            if c == b' ' || c == b'\t' {
                i += 1;
                continue;
            }
            if !c.is_ascii_uppercase() {
                return Err(self.error(format!("`{}` is not an address", c as char)));
            }
            let letter = Letter::ALL
                .iter()
                .copied()
                .find(|l| l.as_str().as_bytes() == [c])
                .ok_or_else(|| self.error(format!("no address {}", c as char)))?;
            i += 1;
            let start = i;
            while i < b.len() && (b[i].is_ascii_digit() || b"+-.".contains(&b[i])) {
                i += 1;
            }
            let num = &s[start..i];
            let value: f64 = num
                .parse()
                .map_err(|_| self.error(format!("{letter}{num} is not a number")))?;
            let value = if num.contains('.') {
                value
            } else {
                self.without_point(letter, value)
            };
            out.push((letter, value));
        }
        Ok(out)
    }

    /// A value written without a point: least increments where the dialect writes a point on every
    /// such number (Fanuc reads `X10` as 10 µm), implied decimals for `never`, else as written.
    fn without_point(&self, letter: Letter, v: f64) -> f64 {
        let f = self.dialect.format(letter);
        let digits = self.dialect.digits(letter, self.inch);
        match (self.dialect.kind(letter), f.point) {
            (crate::dialect::AddressKind::Linear, Point::Always | Point::Never)
            | (crate::dialect::AddressKind::Angular, Point::Always | Point::Never)
            | (crate::dialect::AddressKind::Feed, Point::Always | Point::Never) => {
                v / 10f64.powi(digits as i32)
            }
            _ => v,
        }
    }

    fn mm(&self, v: f64) -> f64 {
        if self.inch { v * 25.4 } else { v }
    }

    /// The move of the current block, if it has one.
    fn block(&mut self) -> Result<Option<Move>, ReadError> {
        let words = self.words()?;
        let mut g = Vec::new();
        let mut axes: [Option<f64>; 6] = [None; 6];
        let mut ijk: [Option<f64>; 3] = [None; 3];
        let (mut r, mut p, mut e, mut f) = (None, None, None, None);
        for &(l, v) in &words {
            match l {
                Letter::G => g.push((v * 10.0).round() as u16),
                Letter::X => axes[0] = Some(v),
                Letter::Y => axes[1] = Some(v),
                Letter::Z => axes[2] = Some(v),
                Letter::A => axes[3] = Some(v),
                Letter::B => axes[4] = Some(v),
                Letter::C => axes[5] = Some(v),
                Letter::I => ijk[0] = Some(v),
                Letter::J => ijk[1] = Some(v),
                Letter::K => ijk[2] = Some(v),
                Letter::R => r = Some(v),
                Letter::P => p = Some(v),
                Letter::E => e = Some(v),
                Letter::F => f = Some(v),
                _ => {}
            }
        }
        let mut helix_pitch = false;
        let mut dwell = false;
        for &code in &g {
            match code {
                0 | 10 | 20 | 30 => self.motion = code,
                40 => dwell = true,
                100 if self.dialect.helix == HelixForm::Pitch => helix_pitch = true,
                170 | 180 | 190 => self.plane = Plane::from_code(code),
                200 => self.inch = true,
                210 => self.inch = false,
                900 | 940 | 950 | 540 => {}
                _ => {
                    return Err(self.error(format!(
                        "G{} is not in the dialect's resolved output",
                        code as f64 / 10.0
                    )));
                }
            }
        }
        if dwell {
            let seconds = match self.dialect.dwell {
                DwellForm::Milliseconds => p.map(|v| v / 1000.0),
                DwellForm::PSeconds => p,
                DwellForm::XSeconds => axes[0],
                DwellForm::FSeconds => f,
                DwellForm::ETenths => e.map(|v| v / 10.0),
            }
            .ok_or_else(|| self.error("a dwell without its time".into()))?;
            return Ok(Some(Move {
                motion: Motion::Dwell(seconds),
                to: self.at,
                feed: self.feed,
                line: self.line,
            }));
        }
        if let Some(f) = f {
            self.feed = self.mm(f);
        }
        let angular = |i: usize| i >= 3;
        let from = self.at;
        let mut to = self.at;
        for (i, v) in axes.iter().enumerate() {
            if let Some(v) = v {
                to[i] = if angular(i) { *v } else { self.mm(*v) };
            }
        }
        let moved = axes.iter().any(Option::is_some);
        if !moved {
            return Ok(None);
        }
        self.at = to;
        let motion = match self.motion {
            0 => Motion::Rapid,
            10 => Motion::Feed,
            _ => {
                let (a, b, n) = self.plane.axes();
                if from[a].is_nan() || from[b].is_nan() {
                    return Err(self.error("an arc before the tool's position was said".into()));
                }
                let letters = [Letter::I, Letter::J, Letter::K];
                let centre = match r {
                    Some(r) => CentreWords::Radius(self.mm(r)),
                    None => {
                        let mut o = [0.0; 3];
                        for k in [a, b] {
                            o[k] = self.mm(ijk[k].ok_or_else(|| {
                                self.error(format!("an arc without {}", letters[k]))
                            })?);
                        }
                        CentreWords::Offsets(o)
                    }
                };
                let arc = arcs::arc(&from, &to, self.plane, self.motion == 20, centre, 0.01)
                    .map_err(|e| self.error(e.message.to_string()))?;
                let Some(arc) = arc else {
                    return Ok(None);
                };
                if helix_pitch {
                    let pitch = ijk[n].map(|v| self.mm(v)).ok_or_else(|| {
                        self.error(format!("G10 without its pitch {}", letters[n]))
                    })?;
                    let (_, sweep) = arc.sweep(&from);
                    let rise = to[n] - from[n];
                    let said = pitch * sweep / std::f64::consts::TAU;
                    if (said - rise).abs() > 0.002 + rise.abs() * 1e-6 {
                        return Err(self.error(format!(
                            "the pitch {pitch} over this arc rises {said:.4}, the axis word {rise:.4}"
                        )));
                    }
                }
                Motion::Arc {
                    centre: arc.centre,
                    plane: self.plane,
                    clockwise: self.motion == 20,
                }
            }
        };
        Ok(Some(Move {
            motion,
            to,
            feed: self.feed,
            line: self.line,
        }))
    }
}

impl<R: BufRead> Reader for WordReader<R> {
    fn next_move(&mut self) -> Result<Option<Move>, ReadError> {
        if self.done {
            return Ok(None);
        }
        loop {
            self.text.clear();
            let n = self
                .input
                .read_line(&mut self.text)
                .map_err(|e| ReadError {
                    line: self.line + 1,
                    message: format!("cannot read the output: {e}"),
                })?;
            if n == 0 {
                self.done = true;
                return Ok(None);
            }
            self.line += 1;
            let t = self.text.trim();
            // The envelope: tape marks, the program number, header comments.
            if t.is_empty() || t.starts_with('%') || (t.starts_with('O') && self.line <= 3) {
                continue;
            }
            if let Some(m) = self.block()? {
                return Ok(Some(m));
            }
        }
    }
}
