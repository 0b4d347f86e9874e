//! Elementary moves as words: in the control's (output.tmp: its number formats, its thread block)
//! or in the neutral language (path.tmp: G00 G01 G02 G03, a thread as G01 at its lead).

use fmsvm_block::{Code, Letter};
use fmsvm_emit::dialect::{Dialect, NumberFormat, Point, ThreadForm};
use fmsvm_emit::format::{Prefix, push_word};

use crate::cycle_moves::Move;

/// The neutral language's numbers: a point where there is a fraction, at most three decimals.
const NEUTRAL: NumberFormat = NumberFormat {
    point: Point::WhenFractional,
    trailing_zeros: false,
    leading_zero: true,
    plus: false,
    width: 0,
};

/// Writes moves one block each, modally: a G code or an axis only where it changes.
/// The word `letter` `value` (a length or a feed, in mm) in the control's number format, or the
/// message of alarm 0003 when it does not fit the control's digits: the one number check of `post`,
/// the same rule as `run`'s (`Dialect::least_increments`).
pub fn number_word(d: &Dialect, letter: Letter, value: f64) -> Result<String, String> {
    let digits = d.digits(letter, false);
    let Some(q) = d.least_increments(value, digits) else {
        return Err(d.too_many_digits(letter, value).to_string());
    };
    let mut buf = Vec::with_capacity(16);
    let name = letter.to_string();
    push_word(
        &mut buf,
        Prefix::new(name.as_bytes()).unwrap_or(Prefix::NONE),
        q,
        digits,
        d.format(letter),
    );
    Ok(String::from_utf8_lossy(&buf).into_owned())
}

pub struct MoveWords<'d> {
    /// The control's dialect (None: the neutral language).
    dialect: Option<&'d Dialect>,
    /// The motion code in force as written (0–3, or the thread's code).
    g: Option<u32>,
    /// The feed in force.
    f: Option<f64>,
    /// Where the tool is (X radius, Z).
    at: [f64; 2],
}

impl<'d> MoveWords<'d> {
    /// In the control's words, from `at`.
    pub fn control(dialect: &'d Dialect, at: [f64; 2]) -> Self {
        MoveWords {
            dialect: Some(dialect),
            g: None,
            f: None,
            at,
        }
    }

    /// In the neutral language, from `at`.
    pub fn neutral(at: [f64; 2]) -> MoveWords<'static> {
        MoveWords {
            dialect: None,
            g: None,
            f: None,
            at,
        }
    }

    /// The decimals and format of `letter`.
    fn format(&self, letter: Letter) -> (u32, NumberFormat) {
        match self.dialect {
            Some(d) => (d.digits(letter, false), *d.format(letter)),
            None => (3, NEUTRAL),
        }
    }

    /// `v` in least increments of `letter`.
    fn q(&self, letter: Letter, v: f64) -> i64 {
        let (digits, _) = self.format(letter);
        (v * 10f64.powi(digits as i32)).round() as i64
    }

    /// The word `letter` `v`.
    fn word(&self, letter: Letter, v: f64) -> String {
        match self.dialect {
            Some(d) => number_word(d, letter, v).unwrap_or_else(|e| e),
            None => {
                let (digits, f) = self.format(letter);
                let mut buf = Vec::with_capacity(16);
                let name = letter.to_string();
                push_word(
                    &mut buf,
                    Prefix::new(name.as_bytes()).unwrap_or(Prefix::NONE),
                    self.q(letter, v),
                    digits,
                    &f,
                );
                String::from_utf8_lossy(&buf).into_owned()
            }
        }
    }

    /// The control's words of a move to `to` are within its digits (alarm 0003 otherwise), as
    /// `run` refuses them.
    fn fits(&self, to: [f64; 2], others: &[(Letter, f64)]) -> Result<(), String> {
        let Some(d) = self.dialect else {
            return Ok(());
        };
        number_word(d, Letter::X, to[0] * self.x_scale())?;
        number_word(d, Letter::Z, to[1])?;
        for &(l, v) in others {
            number_word(d, l, v)?;
        }
        Ok(())
    }

    /// A G or M code as the control pads it (`G00`, `M3`).
    fn code(&self, letter: Letter, n: u32) -> String {
        let width = match self.dialect {
            Some(d) => usize::from(d.format(letter).width),
            None => 2,
        };
        format!("{letter}{n:0width$}")
    }

    /// X is written on the diameter (the neutral language's, and a diameter lathe's).
    fn x_scale(&self) -> f64 {
        match self.dialect.and_then(|d| d.lathe.as_ref()) {
            Some(l) if !l.diameter => 1.0,
            _ => 2.0,
        }
    }

    /// The axis words of a move to `to` that changes them.
    fn axes(&self, to: [f64; 2]) -> Vec<String> {
        let s = self.x_scale();
        let mut w = Vec::new();
        if self.q(Letter::X, to[0] * s) != self.q(Letter::X, self.at[0] * s) {
            w.push(self.word(Letter::X, to[0] * s));
        }
        if self.q(Letter::Z, to[1]) != self.q(Letter::Z, self.at[1]) {
            w.push(self.word(Letter::Z, to[1]));
        }
        w
    }

    /// `G code` when it is not in force.
    fn motion(&mut self, g: u32, words: &mut Vec<String>) {
        if self.g != Some(g) {
            words.push(self.code(Letter::G, g));
            self.g = Some(g);
        }
    }

    /// A point at `at` (G00 X Z), where a cycle's path starts.
    pub fn point(&mut self, at: [f64; 2]) -> String {
        let s = self.x_scale();
        self.g = Some(0);
        self.at = at;
        format!(
            "{} {} {}",
            self.code(Letter::G, 0),
            self.word(Letter::X, at[0] * s),
            self.word(Letter::Z, at[1])
        )
    }

    /// The block of one move (None: it does not move the tool).
    pub fn line(&mut self, mv: &Move) -> Result<Option<String>, String> {
        let mut words = Vec::new();
        match *mv {
            Move::Spindle(d) => return Ok(Some(self.code(Letter::M, u32::from(d)))),
            // A cycle's elementary moves carry no profile codes (`cycle_moves`).
            Move::Codes { .. } => return Ok(None),
            Move::Rapid(to) => {
                self.fits(to, &[])?;
                let axes = self.axes(to);
                if axes.is_empty() {
                    return Ok(None);
                }
                self.motion(0, &mut words);
                words.extend(axes);
                self.at = to;
            }
            Move::Feed(to, f) => {
                self.fits(to, &[(Letter::F, f.unwrap_or(0.0))])?;
                let axes = self.axes(to);
                if axes.is_empty() {
                    return Ok(None);
                }
                self.motion(1, &mut words);
                words.extend(axes);
                self.feed(f, &mut words);
                self.at = to;
            }
            Move::Arc { to, centre, cw, f } => {
                self.fits(
                    to,
                    &[
                        (Letter::I, centre[0] - self.at[0]),
                        (Letter::K, centre[1] - self.at[1]),
                        (Letter::F, f.unwrap_or(0.0)),
                    ],
                )?;
                let axes = self.axes(to);
                if axes.is_empty() {
                    return Ok(None);
                }
                self.motion(if cw { 2 } else { 3 }, &mut words);
                words.extend(axes);
                words.push(self.word(Letter::I, centre[0] - self.at[0]));
                words.push(self.word(Letter::K, centre[1] - self.at[1]));
                self.feed(f, &mut words);
                self.at = to;
            }
            Move::Thread(to, lead) => {
                self.fits(to, &[(Letter::F, lead)])?;
                let axes = self.axes(to);
                if axes.is_empty() {
                    return Ok(None);
                }
                let (g, letter) = self.thread(to)?;
                words.push(self.code(Letter::G, g));
                self.g = Some(g);
                words.extend(axes);
                words.push(self.word(letter, lead));
                // The lead is not a feed: the next feed move writes its F again.
                self.f = None;
                self.at = to;
            }
        }
        Ok(Some(words.join(" ")))
    }

    /// F when it changes.
    fn feed(&mut self, f: Option<f64>, words: &mut Vec<String>) {
        if let Some(f) = f
            && self.f != Some(f)
        {
            words.push(self.word(Letter::F, f));
            self.f = Some(f);
        }
    }

    /// The thread's code and the letter of its lead to `to`: the dialect's `[lathe] thread` (G32 F
    /// in Fanuc's system A, G33 F, K, or K and I by the slope: `LatheForm::thread_letter`), G33 K
    /// where the profile has no lathe (ISO 6983: G33 thread cutting, constant lead); in path.tmp
    /// a G01 at the lead.
    fn thread(&self, to: [f64; 2]) -> Result<(u32, Letter), String> {
        let Some(d) = self.dialect else {
            return Ok((1, Letter::F));
        };
        let Some(l) = &d.lathe else {
            return Ok((33, Letter::K));
        };
        let g = l.codes.written(Code::G33).tenths() / 10;
        match l.thread_letter(self.at, to) {
            Some(letter) => Ok((g, letter)),
            None if l.thread == ThreadForm::None => Err(format!(
                "a thread cannot be written for {}: no single-block thread is known for it ([lathe] thread = \"none\"); a profile of your own that knows the machine's thread block sets [lathe] thread = \"F\", \"K\" or \"din\", or gives the cycle's own block",
                d.name
            )),
            None => Err(format!(
                "a thread at 45° or steeper to Z cannot be written for {}: its G33 K gives the lead along Z only",
                d.name
            )),
        }
    }

    /// A block with the neutral program's motion code `g` when the moves left another in force.
    pub fn restore(&mut self, g: u8) -> Option<String> {
        match self.g {
            Some(now) if now != u32::from(g) => {
                self.g = Some(u32::from(g));
                Some(self.code(Letter::G, u32::from(g)))
            }
            _ => None,
        }
    }
}
