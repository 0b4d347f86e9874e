//! The Н33-2М tape read back into moves (the text form or the parity tape, told apart by the `%`),
//! for `--verify`: the dialect's format is `emit::n33`'s.

use std::io::BufRead;

use super::{Motion, Move, ReadError, Reader};
use fmsvm_canon::{Plane, Pose};
use fmsvm_emit::n33::{RAPID, decode_feed, radius};

/// Reads an Н33-2М tape (the text form or the parity tape, told apart by the `%`) back into moves.
pub struct N33Reader<R: BufRead> {
    input: R,
    /// Lines read so far (the next is `line + 1`).
    line: u32,
    /// Parity tape (Some(true)), text (Some(false)), not known before `%`.
    tape: Option<bool>,
    /// A B C and the start, for the moves.
    start: Pose,
    /// Absolute position, discretes.
    pos: [i64; 3],
    motion: u8,
    plane: Option<Plane>,
    feed: Option<u16>,
    g18_ccw_is_iso: bool,
    ended: bool,
    raw: Vec<u8>,
}

/// A block as read: the words present (I J K and X Y Z indexed by axis).
#[derive(Default, Debug)]
struct Words {
    g: Option<u8>,
    ijk: [Option<i64>; 3],
    xyz: [Option<i64>; 3],
    m: Option<u8>,
    f: Option<u16>,
}

impl<R: BufRead> N33Reader<R> {
    /// A reader of `input`, the tool standing at `start` (mm) when the tape begins.
    pub fn new(input: R, start: Pose) -> Self {
        N33Reader {
            input,
            line: 0,
            tape: None,
            start,
            pos: [
                (start[0] * 100.0).round() as i64,
                (start[1] * 100.0).round() as i64,
                (start[2] * 100.0).round() as i64,
            ],
            motion: 1,
            plane: None,
            feed: None,
            g18_ccw_is_iso: true,
            ended: false,
            raw: Vec::new(),
        }
    }

    /// The G18 sense the tape was written with ([`N33Options::g18_ccw_is_iso`]).
    pub fn g18_ccw_is_iso(mut self, iso: bool) -> Self {
        self.g18_ccw_is_iso = iso;
        self
    }

    fn error(&self, message: String) -> ReadError {
        ReadError {
            line: self.line,
            message,
        }
    }

    /// The next line's characters, parity checked and stripped, NUL and DEL left out; None at the end.
    fn next_line(&mut self) -> Result<Option<Vec<u8>>, ReadError> {
        self.raw.clear();
        let n = self
            .input
            .read_until(b'\n', &mut self.raw)
            .map_err(|e| ReadError {
                line: self.line + 1,
                message: format!("cannot read the tape: {e}"),
            })?;
        if n == 0 {
            return Ok(None);
        }
        self.line += 1;
        let mut text = Vec::with_capacity(self.raw.len());
        for (col, &byte) in self.raw.iter().enumerate() {
            if self.tape.is_none() && byte != 0 {
                self.tape = match byte {
                    0xa5 => Some(true),
                    b'%' => Some(false),
                    other => {
                        return Err(self.error(format!(
                            "the tape must start with % (§5.1.3), found byte 0x{other:02x}"
                        )));
                    }
                };
            }
            let c = if self.tape == Some(true) {
                if byte.count_ones() % 2 != 0 {
                    return Err(self.error(format!(
                        "byte 0x{byte:02x} in column {} has odd parity: a tape row must have an even number of holes (§5.1.2)",
                        col + 1
                    )));
                }
                byte & 0x7f
            } else {
                if byte >= 0x80 {
                    return Err(self.error(format!(
                        "byte 0x{byte:02x} in column {}: the text form is ISO 7-bit",
                        col + 1
                    )));
                }
                byte
            };
            match c {
                0 | 0x7f | b'\n' => {}
                b'\r' => {
                    return Err(self.error("CR: a block ends with LF alone (A.4)".into()));
                }
                c => text.push(c),
            }
        }
        Ok(Some(text))
    }

    /// After M02: the end, or the next tape of a program split over several (§5.2.1), which
    /// starts with `%` and, the control having ended the last, says its plane, G and F again.
    fn next_tape(&mut self) -> Result<bool, ReadError> {
        loop {
            let Some(text) = self.next_line()? else {
                return Ok(false);
            };
            match text.as_slice() {
                [] => continue,
                b"%" => {
                    self.ended = false;
                    self.motion = 1;
                    self.plane = None;
                    self.feed = None;
                    return Ok(true);
                }
                _ => {
                    return Err(self.error(format!(
                        "`{}` after M02: a tape ends there; a next tape starts with % (§5.1.3)",
                        String::from_utf8_lossy(&text)
                    )));
                }
            }
        }
    }

    /// The words of a block, strictly in the order N G I J K X Y Z M F with fixed widths (§5.1.1).
    fn words(&self, text: &[u8]) -> Result<Words, ReadError> {
        const ORDER: &[u8] = b"NGIJKXYZMF";
        let mut w = Words::default();
        let mut at = 0;
        let mut last: Option<usize> = None;
        while at < text.len() {
            let letter = text[at];
            let end = text[at + 1..]
                .iter()
                .position(|c| c.is_ascii_uppercase())
                .map_or(text.len(), |p| at + 1 + p);
            let word = String::from_utf8_lossy(&text[at..end]).into_owned();
            let body = &text[at + 1..end];
            let Some(rank) = ORDER.iter().position(|&c| c == letter) else {
                return Err(self.error(match letter {
                    b'S' | b'T' => {
                        format!("word {word}: S and T are not used on the 6Р13Ф3-37 (§5.2.18)")
                    }
                    b'L' => format!(
                        "word {word}: correction L words are not modelled by this reader (§5.2.8)"
                    ),
                    _ => format!("word {word}: no such address on the Н33-2М (Table 3)"),
                }));
            };
            if at == 0 && letter != b'N' {
                return Err(self.error(format!(
                    "word {word}: a block starts with its number N (§5.2.1)"
                )));
            }
            if last.is_some_and(|l| rank <= l) {
                return Err(self.error(format!(
                    "word {word}: out of order or repeated; the order is N G I J K X Y Z M F (§5.2.18)"
                )));
            }
            last = Some(rank);
            let digits = |n: usize, signed: bool, plus_only: bool| -> Result<i64, ReadError> {
                let (sign, ds) = if signed {
                    match body.first() {
                        Some(b'+') => (1, &body[1..]),
                        Some(b'-') if !plus_only => (-1, &body[1..]),
                        _ => {
                            return Err(self.error(format!(
                                "word {word}: {} takes a sign{} and {n} digits (§5.1.1)",
                                letter as char,
                                if plus_only { " +" } else { "" }
                            )));
                        }
                    }
                } else {
                    (1, body)
                };
                if ds.len() != n || !ds.iter().all(u8::is_ascii_digit) {
                    return Err(self.error(format!(
                        "word {word}: {} takes {}{n} digits, it has {} (§5.1.1: the control counts the rows)",
                        letter as char,
                        if signed { "a sign and " } else { "" },
                        ds.len()
                    )));
                }
                let v = ds.iter().fold(0i64, |v, d| v * 10 + (d - b'0') as i64);
                Ok(sign * v)
            };
            match letter {
                b'N' => {
                    digits(3, false, false)?;
                }
                b'G' => w.g = Some(digits(2, false, false)? as u8),
                b'I' | b'J' | b'K' => {
                    w.ijk[(letter - b'I') as usize] = Some(digits(6, true, true)?)
                }
                b'X' | b'Y' | b'Z' => {
                    w.xyz[(letter - b'X') as usize] = Some(digits(6, true, false)?)
                }
                b'M' => w.m = Some(digits(2, false, false)? as u8),
                _ => w.f = Some(digits(4, false, false)? as u16),
            }
            at = end;
        }
        Ok(w)
    }

    fn pose(&self) -> Pose {
        let mut p = self.start;
        for (v, &d) in p.iter_mut().zip(&self.pos) {
            *v = d as f64 / 100.0;
        }
        p
    }

    fn feed_mm(&self) -> f64 {
        self.feed.and_then(decode_feed).unwrap_or(f64::NAN)
    }

    /// The arc of one block: the start relative to the centre, its signs inferred from the direction
    /// and the increment signs (one quadrant, A.12), radii within one discrete (§5.2.11).
    fn arc(&self, w: &Words, g: u8, plane: Plane) -> Result<Motion, ReadError> {
        let (a, b, n) = plane.axes();
        if w.xyz[n].is_some_and(|v| v != 0) || w.ijk[n].is_some() {
            return Err(self.error(format!(
                "G{g:02} with a word of the axis normal to its plane: no helix on the Н33-2М (§5.2.18)"
            )));
        }
        let mag = [w.ijk[a].unwrap_or(0), w.ijk[b].unwrap_or(0)];
        if mag == [0, 0] {
            return Err(self.error(format!(
                "G{g:02} with no I J K: the arc's start relative to its centre is missing (A.12)"
            )));
        }
        let d = [w.xyz[a].unwrap_or(0), w.xyz[b].unwrap_or(0)];
        let iso_cw = g == 2;
        let clockwise = if plane == Plane::ZX && !self.g18_ccw_is_iso {
            !iso_cw
        } else {
            iso_cw
        };
        let mut best: Option<([i64; 2], f64)> = None;
        for sa in [1i64, -1] {
            for sb in [1i64, -1] {
                if (sa < 0 && mag[0] == 0) || (sb < 0 && mag[1] == 0) {
                    continue;
                }
                let s = [sa * mag[0], sb * mag[1]];
                let e = [s[0] + d[0], s[1] + d[1]];
                let cross = s[0] as i128 * e[1] as i128 - s[1] as i128 * e[0] as i128;
                let turns = if clockwise { cross < 0 } else { cross > 0 };
                if s[0] * e[0] < 0 || s[1] * e[1] < 0 || !turns {
                    continue;
                }
                let mismatch = (radius(s, [0, 0]) - radius(e, [0, 0])).abs();
                if best.is_none_or(|(_, m)| mismatch < m) {
                    best = Some((s, mismatch));
                }
            }
        }
        let Some((s, mismatch)) = best else {
            return Err(self.error(format!(
                "G{g:02}: no quadrant holds an arc with these I J K and increments (A.12)"
            )));
        };
        if mismatch > 1.0 {
            return Err(self.error(format!(
                "G{g:02}: the start and end radii differ by {:.2} discretes, more than one: the control stops (§5.2.11)",
                mismatch
            )));
        }
        Ok(Motion::Arc {
            centre: [
                (self.pos[a] - s[0]) as f64 / 100.0,
                (self.pos[b] - s[1]) as f64 / 100.0,
            ],
            plane,
            clockwise,
        })
    }
}

impl<R: BufRead> Reader for N33Reader<R> {
    fn start(&mut self, p: Pose) {
        self.start = p;
        self.pos = [
            (p[0] * 100.0).round() as i64,
            (p[1] * 100.0).round() as i64,
            (p[2] * 100.0).round() as i64,
        ];
    }

    fn next_move(&mut self) -> Result<Option<Move>, ReadError> {
        loop {
            if self.ended && !self.next_tape()? {
                return Ok(None);
            }
            let Some(text) = self.next_line()? else {
                return Err(self.error(if self.tape.is_none() {
                    "an empty tape: no % (§5.1.3)".into()
                } else {
                    "the tape ends without M02 (A.4)".into()
                }));
            };
            if text.is_empty() || text == b"%" {
                continue;
            }
            let w = self.words(&text)?;
            if let Some(f) = w.f {
                if decode_feed(f).is_none() {
                    return Err(
                        self.error(format!("word F{f:04}: not a feed code of Table 6 (§5.2.3)"))
                    );
                }
                self.feed = Some(f);
            }
            match w.g {
                None => {}
                Some(17) => self.plane = Some(Plane::XY),
                Some(18) => self.plane = Some(Plane::ZX),
                Some(19) => self.plane = Some(Plane::YZ),
                Some(g @ 1..=4) => self.motion = g,
                Some(g) => {
                    return Err(self.error(format!(
                        "word G{g:02}: not modelled by this reader (the Н33-2М's G40–G53 are corrections, §5.2.2)"
                    )));
                }
            }
            if let Some(m) = w.m
                && !matches!(m, 0 | 1 | 2 | 3 | 5 | 13)
            {
                return Err(self.error(format!(
                    "word M{m:02}: the Н33-2М knows only M00 M01 M02 M03 M05 M13 (A.8)"
                )));
            }
            let moves = w.xyz.iter().any(|v| v.is_some_and(|v| v != 0));
            let result = if !moves {
                None
            } else if self.motion == 4 {
                if w.xyz[1].is_some() || w.xyz[2].is_some() {
                    return Err(self
                        .error("G04 with Y or Z: a dwell is a fictitious X move (§5.2.7)".into()));
                }
                let feed = self.feed_mm();
                if feed.is_nan() {
                    return Err(self.error("G04 with no feed: its time is X / F (§5.2.7)".into()));
                }
                let pulses = w.xyz[0].unwrap_or(0).abs() as f64;
                // Pulses at 0.01 mm at F mm/min: F·100/60 per second.
                Some(Move {
                    motion: Motion::Dwell(pulses * 0.6 / feed),
                    to: self.pose(),
                    feed,
                    per_rev: false,
                    line: self.line,
                })
            } else {
                let motion = if self.motion == 1 {
                    if self.feed.is_some_and(|f| f % 1000 == RAPID) {
                        Motion::Rapid
                    } else {
                        Motion::Feed
                    }
                } else {
                    let Some(plane) = self.plane else {
                        return Err(self.error(format!(
                            "G{:02} with no plane: G17, G18 or G19 must come first (§5.2.9)",
                            self.motion
                        )));
                    };
                    self.arc(&w, self.motion, plane)?
                };
                for i in 0..3 {
                    self.pos[i] += w.xyz[i].unwrap_or(0);
                }
                Some(Move {
                    motion,
                    to: self.pose(),
                    feed: self.feed_mm(),
                    per_rev: false,
                    line: self.line,
                })
            };
            if w.m == Some(2) {
                self.ended = true;
            }
            if result.is_some() {
                return Ok(result);
            }
        }
    }
}
