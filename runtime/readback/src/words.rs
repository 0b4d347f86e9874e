//! The reader of word-address dialects (Fanuc, ISO, LinuxCNC, FMS-3000, the lathe controls): the
//! resolved output's blocks read back as the dialect's profile says they are spelled — comments,
//! number formats (a number without a point is least increments where the dialect always writes
//! one), block ends, G0–G3 with I J K or R, the FMS-3000 helix pitch, every dwell form, inch.

use std::io::BufRead;

use fmsvm_block::{Code, Letter};

use super::{Motion, Move, OffsetState, ReadError, Reader};
use fmsvm_canon::{Plane, Pose};
use fmsvm_emit::dialect::{CommentStyle, Dialect, DwellForm, HelixForm, Point, SkipForm};

/// One block's words by address.
struct Fields {
    g: Vec<Code>,
    axes: [Option<f64>; 6],
    ijk: [Option<f64>; 3],
    r: Option<f64>,
    p: Option<f64>,
    e: Option<f64>,
    f: Option<f64>,
    u: Option<f64>,
    /// A lathe's V (Y's increment in system A: `G28 V0.`).
    v: Option<f64>,
    h: Option<f64>,
    w: Option<f64>,
}

/// The address of each capital letter (`A` first), None for a letter that is none.
const LETTER_OF: [Option<Letter>; 26] = {
    let mut t = [None; 26];
    let mut i = 0;
    while i < Letter::ALL.len() {
        let name = Letter::ALL[i].as_str().as_bytes();
        if name.len() == 1 && name[0].is_ascii_uppercase() {
            t[(name[0] - b'A') as usize] = Some(Letter::ALL[i]);
        }
        i += 1;
    }
    t
};

/// Reads the resolved output of a word-address dialect.
pub struct WordReader<R: BufRead> {
    input: R,
    dialect: Dialect,
    line: u32,
    text: String,
    /// Where the tool is (NaN: never said).
    at: Pose,
    motion: Code,
    plane: Plane,
    inch: bool,
    feed: f64,
    /// Feed per revolution is in force (G95, a lathe's G99).
    per_rev: bool,
    /// The input is at its end.
    done: bool,
    /// Moves of a cycle block still to be returned.
    pending: std::collections::VecDeque<Move>,
    /// The canned cycle in effect (G code ×10), G99 (return to R), the mode's initial level.
    cycle: Option<Code>,
    to_r: bool,
    initial: f64,
    /// The second auxiliary function's address (`InputRules::second_aux`): a line of only its code
    /// (and N), as resolved output writes one, is a code, not motion.
    pub second_aux: Option<Letter>,
    /// The control's own offsets the output has selected (where the dialect leaves them to it).
    offsets: OffsetState,
    /// The current line's words, and its G codes (buffers kept from line to line).
    words: Vec<(Letter, f64)>,
    g: Vec<Code>,
}

impl<R: BufRead> WordReader<R> {
    /// A reader of `input`, written in `dialect`.
    pub fn new(input: R, dialect: Dialect) -> Self {
        let turning = dialect.turning().is_some();
        WordReader {
            input,
            dialect,
            line: 0,
            text: String::new(),
            at: [f64::NAN; 6],
            motion: Code::G0,
            plane: if turning { Plane::ZX } else { Plane::XY },
            inch: false,
            feed: f64::NAN,
            per_rev: turning,
            done: false,
            pending: std::collections::VecDeque::new(),
            cycle: None,
            to_r: false,
            initial: f64::NAN,
            second_aux: None,
            offsets: OffsetState::default(),
            words: Vec::new(),
            g: Vec::new(),
        }
    }

    fn error(&self, message: String) -> ReadError {
        ReadError {
            line: self.line,
            message: format!("`{}`: {message}", self.text.trim_end()),
        }
    }

    /// The words of the current line (letter, value) into `words`.
    fn words(&self, words: &mut Vec<(Letter, f64)>) -> Result<(), ReadError> {
        words.clear();
        let line = self.text.trim_end_matches(['\r', '\n']);
        // Comments become blanks (a copy only for a line that has one).
        let uncommented;
        let s = match self.dialect.comments {
            CommentStyle::Paren if line.contains('(') => {
                let mut s = line.to_string();
                while let Some(i) = s.find('(') {
                    let j = s[i..].find(')').map_or(s.len(), |j| i + j + 1);
                    s.replace_range(i..j, " ");
                }
                uncommented = s;
                uncommented.as_str()
            }
            CommentStyle::Semicolon => line.split_once(';').map_or(line, |(s, _)| s),
            _ => line,
        };
        let b = s.as_bytes();
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
            let letter = LETTER_OF[(c - b'A') as usize]
                .ok_or_else(|| self.error(format!("no address {}", c as char)))?;
            i += 1;
            let start = i;
            let negative = b.get(i) == Some(&b'-');
            if matches!(b.get(i), Some(b'-' | b'+')) {
                i += 1;
            }
            // Digits and one point converted as they are read (`exact_decimal`); anything else
            // (a sign inside, a second point, a long number) by `str::parse`.
            let (mut mant, mut digits, mut frac) = (0u64, 0u32, 0u32);
            let (mut point, mut plain, mut any_digit) = (false, true, false);
            while i < b.len() && (b[i].is_ascii_digit() || b"+-.".contains(&b[i])) {
                match b[i] {
                    b'.' => {
                        plain &= !point;
                        point = true;
                    }
                    d @ b'0'..=b'9' => {
                        if digits < 16 {
                            mant = mant * 10 + u64::from(d - b'0');
                        }
                        digits += u32::from(mant > 0);
                        frac += u32::from(point);
                        any_digit = true;
                    }
                    _ => plain = false,
                }
                i += 1;
            }
            let num = &s[start..i];
            let exact = (plain && any_digit)
                .then(|| fmsvm_block::exact_decimal(mant, digits, frac))
                .flatten();
            let value: f64 = match exact {
                Some(v) if negative => -v,
                Some(v) => v,
                None => num
                    .parse()
                    .map_err(|_| self.error(format!("{letter}{num} is not a number")))?,
            };
            let value = if point {
                value
            } else {
                self.without_point(letter, value)
            };
            words.push((letter, value));
        }
        Ok(())
    }

    /// A value written without a point: least increments where the dialect writes a point on every
    /// such number (Fanuc reads `X10` as 10 µm), implied decimals for `never`, else as written.
    fn without_point(&self, letter: Letter, v: f64) -> f64 {
        let f = self.dialect.format(letter);
        let digits = self.dialect.digits(letter, self.inch);
        use fmsvm_emit::dialect::AddressKind::{Angular, Feed, Linear};
        if matches!(self.dialect.kind(letter), Linear | Angular | Feed)
            && matches!(f.point, Point::Always | Point::Never)
        {
            v / 10f64.powi(digits as i32)
        } else {
            v
        }
    }

    fn mm(&self, v: f64) -> f64 {
        if self.inch { v * 25.4 } else { v }
    }

    /// The arc of a G2/G3 block from `from` to `to` (R, or I J K from the start; G10's pitch checked
    /// against the rise under the FMS-3000's helix form); None for an arc that is no motion.
    fn arc_motion(
        &self,
        from: &Pose,
        to: &Pose,
        r: Option<f64>,
        ijk: &[Option<f64>; 3],
        helix_pitch: bool,
    ) -> Result<Option<(Motion, f64)>, ReadError> {
        let (a, b, n) = self.plane.axes();
        if from[a].is_nan() || from[b].is_nan() {
            return Err(self.error("an arc before the tool's position was said".into()));
        }
        let letters = [Letter::I, Letter::J, Letter::K];
        // The centre from the words by the read-back's own rule (`centre.rs`), not the kernel's.
        let (s, e) = ([from[a], from[b]], [to[a], to[b]]);
        let clockwise = self.motion == Code::G2;
        let found = match r {
            // An arc by R that ends where it starts moves nothing (Fanuc).
            Some(_) if s == e => return Ok(None),
            Some(r) => crate::centre::from_radius(s, e, self.mm(r), clockwise, 0.01),
            None => {
                let mut o = [0.0; 2];
                for (j, k) in [a, b].into_iter().enumerate() {
                    o[j] = self.mm(ijk[k]
                        .ok_or_else(|| self.error(format!("an arc without {}", letters[k])))?);
                    // The centre itself (FMS-3000 N3021 = 1, or 2 in G90): its offset from the
                    // start point.
                    if self.dialect.centre_absolute {
                        o[j] -= from[k];
                    }
                }
                crate::centre::from_offsets(s, e, o, 0.01)
            }
        };
        let centre = found.map_err(|e| self.error(e))?;
        let arc = fmsvm_canon::Arc {
            to: *to,
            centre,
            plane: self.plane,
            clockwise,
            turns: 0,
        };
        // The block's F in the plane's feed: 1, or below 1 for a pitch helix, whose F is the feed
        // along the helix (FMS-3000 §1.4.5.3: F_arc = F·2πR/√((2πR)² + K²)).
        let mut in_plane = 1.0;
        if helix_pitch {
            let pitch = ijk[n]
                .map(|v| self.mm(v))
                .ok_or_else(|| self.error(format!("G10 without its pitch {}", letters[n])))?;
            let (_, sweep) = arc.sweep(from);
            let rise = to[n] - from[n];
            let said = pitch * sweep / std::f64::consts::TAU;
            if (said - rise).abs() > 0.002 + rise.abs() * 1e-6 {
                return Err(self.error(format!(
                    "the pitch {pitch} over this arc rises {said:.4}, the axis word {rise:.4}"
                )));
            }
            let turn =
                std::f64::consts::TAU * (from[a] - arc.centre[0]).hypot(from[b] - arc.centre[1]);
            if turn > 0.0 {
                in_plane = turn / turn.hypot(pitch);
            }
        }
        Ok(Some((
            Motion::Arc {
                centre: arc.centre,
                plane: self.plane,
                clockwise: self.motion == Code::G2,
            },
            in_plane,
        )))
    }

    /// A G53 block (with G00, when `with_g0`): the axes it names go to machine coordinates, which
    /// the output frame's origin does not say here (they are unknown to the reader after it).
    fn machine_block(&mut self, axes: &[Option<f64>; 6], with_g0: bool) -> Result<Move, ReadError> {
        let mut at = [f64::NAN; 6];
        let mut mask = 0u8;
        for (i, v) in axes.iter().enumerate() {
            if let Some(v) = v {
                at[i] = if i < 3 { self.mm(*v) } else { *v };
                mask |= 1 << i;
                self.at[i] = f64::NAN;
            }
        }
        if mask == 0 {
            return Err(self.error("G53 without an axis".into()));
        }
        if with_g0 {
            self.motion = Code::G0;
        }
        Ok(Move {
            motion: Motion::Machine {
                axes: mask,
                machine: at,
            },
            to: self.at,
            feed: self.feed,
            per_rev: self.per_rev,
            line: self.line,
        })
    }

    /// What G code `code` of a turning program's output means (its code system read back), or
    /// an error for a code the output does not write.
    fn lathe_meaning(&self, code: Code) -> Result<Code, ReadError> {
        let Some(l) = self.dialect.turning() else {
            return Ok(code);
        };
        // The lathe's own unit words (G71 metric on a SINUMERIK or a FAGOR, `[lathe] metric`).
        let names = |words: &str| g_word(words) == Some(code);
        if names(&l.metric) {
            return Ok(Code::G21);
        }
        if names(&l.inch) {
            return Ok(Code::G20);
        }
        // LinuxCNC's G7 (diameter mode) on the first line.
        if l.codes == fmsvm_canon::modal::CodeSystem::Mill && code.tenths() == 70 {
            return Ok(Code::G7);
        }
        l.codes
            .meaning(code)
            .ok_or_else(|| self.error(format!("G{code} is not in the dialect's resolved output")))
    }

    /// G`v` is a word of the lathe's first line (`[lathe] frame`) that its code system does not
    /// read: a mode the output states and the reader assumes (diameter programming).
    fn frame_only(&self, v: f64) -> bool {
        let Some(l) = self.dialect.turning() else {
            return false;
        };
        let Some(code) = Code::of(v) else {
            return false;
        };
        l.codes.meaning(code).is_none()
            && l.frame.split_whitespace().any(|w| g_word(w) == Some(code))
    }

    /// A block's words by address (X halved on a diameter lathe; G codes read as their meanings).
    fn fields(
        &self,
        words: &[(Letter, f64)],
        diameter: bool,
        mut g: Vec<Code>,
    ) -> Result<Fields, ReadError> {
        g.clear();
        let mut axes: [Option<f64>; 6] = [None; 6];
        let mut ijk: [Option<f64>; 3] = [None; 3];
        let (mut r, mut p, mut e, mut f) = (None, None, None, None);
        let (mut u, mut h, mut w, mut v_word) = (None, None, None, None);
        for &(l, v) in words {
            match l {
                // A lathe's frame word that only states what the reader assumes (FAGOR's G151,
                // diameter programming) is no motion.
                Letter::G if self.frame_only(v) => {}
                Letter::G => match Code::of(v) {
                    Some(code) => g.push(self.lathe_meaning(code)?),
                    None => {
                        return Err(
                            self.error(format!("G{v} is not in the dialect's resolved output"))
                        );
                    }
                },
                Letter::X => axes[0] = Some(if diameter { v / 2.0 } else { v }),
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
                Letter::U => u = Some(v),
                Letter::V => v_word = Some(v),
                Letter::W => w = Some(v),
                Letter::H => h = Some(v),
                _ => {}
            }
        }
        Ok(Fields {
            g,
            axes,
            ijk,
            r,
            p,
            e,
            f,
            u,
            v: v_word,
            h,
            w,
        })
    }

    /// The move of the current block, if it has one.
    fn block(&mut self) -> Result<Option<Move>, ReadError> {
        let turning = self.dialect.turning().cloned();
        // Sinumerik's spindle limit `LIMS=…` is no motion.
        if turning.is_some() && self.text.contains("LIMS=") {
            return Ok(None);
        }
        // Sinumerik's diameter programming `DIAMON` is no motion (the reader's X is a diameter).
        if turning.is_some() && self.text.contains("DIAMON") {
            self.text = self.text.replace("DIAMON", " ");
        }
        // The line's words and G codes in buffers kept from line to line.
        let mut words = std::mem::take(&mut self.words);
        let read = self.words(&mut words);
        let m = read.and_then(|()| self.block_of(&words, turning));
        self.words = words;
        m
    }

    /// The move of the current block, its words read.
    fn block_of(
        &mut self,
        words: &[(Letter, f64)],
        turning: Option<fmsvm_emit::dialect::LatheForm>,
    ) -> Result<Option<Move>, ReadError> {
        if let Some(aux) = self.second_aux
            && words.iter().any(|&(l, _)| l == aux)
            && words.iter().all(|&(l, _)| l == aux || l == Letter::N)
        {
            return Ok(None);
        }
        let diameter = turning.as_ref().is_some_and(|l| l.diameter);
        let g_buffer = std::mem::take(&mut self.g);
        let Fields {
            g,
            mut axes,
            ijk,
            r,
            p,
            e,
            f,
            u,
            v,
            h,
            w,
        } = self.fields(words, diameter, g_buffer)?;
        let mut helix_pitch = false;
        let mut dwell = false;
        let mut cycle_code = None;
        let mut incremental = false;
        let mut machine = false;
        let mut reference = None;
        let mut thread = false;
        let mut skip = false;
        for &code in &g {
            match code {
                // A turning program's frame and spindle codes: no motion.
                // The tool's offsets (LinuxCNC's `T1 M6 G43`): the control's, no motion.
                Code::G7 | Code::G96 | Code::G97 | Code::G43 | Code::G49 if turning.is_some() => {}
                Code::G92 if turning.is_some() && axes.iter().all(Option::is_none) => {}
                Code::G33
                    if turning.is_some()
                        || self.dialect.mill_thread == fmsvm_emit::dialect::MillThread::G1G33F =>
                {
                    thread = true
                }
                Code::G91 => incremental = true,
                Code::G53 => machine = true,
                Code::G28 => reference = Some(1u8),
                Code::G30 => reference = Some(p.map_or(2, |p| p.round().clamp(2.0, 4.0) as u8)),
                Code::G0 | Code::G1 | Code::G2 | Code::G3 => self.motion = code,
                // The dialect's touch-stop (`[motion] skip`): this block a skip move; LinuxCNC's
                // G38.3 a motion code in force until another.
                Code::G31 if self.dialect.skip == SkipForm::G31 => skip = true,
                Code::G32 if self.dialect.skip == SkipForm::G01G32 && turning.is_none() => {
                    skip = true
                }
                c if c.tenths() == 383 && self.dialect.skip == SkipForm::G38_3 => self.motion = c,
                Code::G81 | Code::G82 | Code::G85 | Code::G89 => cycle_code = Some(code),
                Code::G80 => self.cycle = None,
                Code::G98 => self.to_r = false,
                Code::G99 => self.to_r = true,
                Code::G4 => dwell = true,
                Code::G10 if self.dialect.helix == HelixForm::Pitch => helix_pitch = true,
                Code::G17 | Code::G18 | Code::G19 => self.plane = Plane::from_code(code),
                Code::G20 => self.inch = true,
                Code::G21 => self.inch = false,
                Code::G94 => self.per_rev = false,
                Code::G95 => self.per_rev = true,
                // The control's work systems: where the tool is in a newly selected one is
                // not said until a move says it.
                Code::G54 | Code::G55 | Code::G56 | Code::G57 | Code::G58 | Code::G59
                    if self.dialect.control_work =>
                {
                    let n = (code.whole() - 53) as u8;
                    if self.offsets.work != 0 && self.offsets.work != n {
                        self.at = [f64::NAN; 6];
                    }
                    self.offsets.work = n;
                }
                // The control's length offsets (the positions stay the tool tip's).
                Code::G43 | Code::G44 if self.dialect.control_length => {
                    let Some(h) = h.filter(|h| h.fract() == 0.0 && (1.0..=999.0).contains(h))
                    else {
                        return Err(self.error(format!("G{code} without its register H1–H999")));
                    };
                    let h = h as i32;
                    self.offsets.length = if code == Code::G43 { h } else { -h };
                    // On the normal of the plane in force, this block's G17–G19 included.
                    let plane = g
                        .iter()
                        .rev()
                        .find(|c| matches!(**c, Code::G17 | Code::G18 | Code::G19))
                        .map_or(self.plane, |&c| Plane::from_code(c));
                    self.offsets.length_plane = plane.code().whole() as u8;
                }
                Code::G49 if self.dialect.control_length => {
                    self.offsets.length = 0;
                    self.offsets.length_plane = 0;
                }
                Code::G90 | Code::G54 => {}
                // Exact stop and cutting mode (`[motion] corners`): how corners are taken, no
                // motion.
                c if self.dialect.corners.is_some_and(|k| k.contains(&c)) => {}
                // The modes the first block states (`[motion] start_modes`): no motion.
                c if self.dialect.start_modes.contains(&c) => {}
                _ => {
                    return Err(
                        self.error(format!("G{code} is not in the dialect's resolved output"))
                    );
                }
            }
        }
        let with_g0 = g.contains(&Code::G0);
        self.g = g;
        if machine {
            return self.machine_block(&axes, with_g0).map(Some);
        }
        if let Some(number) = reference {
            // A lathe in system A returns with U, V and W (the increments of X, Y and Z), no G91.
            let lathe_a =
                turning.as_ref().map(|l| l.codes) == Some(fmsvm_canon::modal::CodeSystem::LatheA);
            if lathe_a && (u.is_some() || v.is_some() || w.is_some()) {
                axes[0] = u;
                axes[1] = v;
                axes[2] = w;
                incremental = true;
            }
            return self.reference_block(number, incremental, &axes).map(Some);
        }
        if incremental {
            return Err(self.error(
                "G91 outside a return to a reference position: resolved output is absolute".into(),
            ));
        }
        if dwell {
            let form = self.dialect.dwell;
            let word = match form.letter() {
                Letter::P => p,
                // X of a dwell is its time, whatever a lathe's X is (diameter): its word as written.
                Letter::X => words
                    .iter()
                    .rev()
                    .find(|&&(l, _)| l == Letter::X)
                    .map(|&(_, v)| v),
                Letter::F => f,
                Letter::E => e,
                Letter::K => ijk[2],
                _ => None,
            };
            let seconds = word
                .map(|v| form.seconds(v))
                .ok_or_else(|| self.error("a dwell without its time".into()))?;
            return Ok(Some(Move {
                motion: Motion::Dwell(seconds),
                to: self.at,
                feed: self.feed,
                per_rev: self.per_rev,
                line: self.line,
            }));
        }
        if thread {
            return self.thread_block(&axes, f, ijk[0], ijk[2]).map(Some);
        }
        if let Some(f) = f {
            self.feed = self.mm(f);
        }
        if let Some(code) = cycle_code.or(self
            .cycle
            .filter(|_| axes[0].is_some() || axes[1].is_some()))
        {
            return self.cycle_block(code, &axes, r, u, h, p, e, ijk[0]);
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
        // I J K without an axis word is a full circle (Fanuc; FMS-3000 §2.4.3 "in any centre
        // mode"): it ends where it starts.
        let circle = matches!(self.motion, Code::G2 | Code::G3) && ijk.iter().any(Option::is_some);
        if !moved && !circle {
            return Ok(None);
        }
        self.at = to;
        let (motion, in_plane) = match self.motion {
            _ if skip => (Motion::Skip, 1.0),
            c if c.tenths() == 383 => (Motion::Skip, 1.0),
            Code::G0 => (Motion::Rapid, 1.0),
            Code::G1 => (Motion::Feed, 1.0),
            _ => match self.arc_motion(&from, &to, r, &ijk, helix_pitch)? {
                Some(m) => m,
                None => return Ok(None),
            },
        };
        Ok(Some(Move {
            motion,
            to,
            feed: self.feed * in_plane,
            per_rev: self.per_rev,
            line: self.line,
        }))
    }
}

/// The code of a profile's G word (`G71`, `G151`), if `word` is one.
fn g_word(word: &str) -> Option<Code> {
    word.strip_prefix('G')
        .and_then(|t| t.parse::<f64>().ok())
        .and_then(Code::of)
}

impl<R: BufRead> WordReader<R> {
    /// A thread block (G32 with F, G33 with F or K: the dialect's `thread`): a straight move with
    /// its lead; F here is the lead, not the feed.
    fn thread_block(
        &mut self,
        axes: &[Option<f64>; 6],
        f: Option<f64>,
        i: Option<f64>,
        k: Option<f64>,
    ) -> Result<Move, ReadError> {
        use fmsvm_emit::dialect::{MillThread, ThreadForm};
        // A milling thread (FMS-3000 §2.7) is `G01 … G33 F<lead>`: G33 acts on its block alone.
        let mill =
            self.dialect.turning().is_none() && self.dialect.mill_thread == MillThread::G1G33F;
        let form = if mill {
            Some(ThreadForm::F)
        } else {
            self.dialect.turning().map(|l| l.thread)
        };
        let mut to = self.at;
        for (n, v) in axes.iter().enumerate() {
            if let Some(v) = v {
                to[n] = if n < 3 { self.mm(*v) } else { *v };
            }
        }
        // The lead's letter must be the one the control reads for this thread's slope (DIN
        // 66025: K along Z below 45°, I along X at 45° and above); a K on a steep thread is read
        // by the control as the lead along Z, another thread.
        let steep = (to[0] - self.at[0]).abs() >= (to[2] - self.at[2]).abs();
        let lead = match form {
            Some(ThreadForm::F) => f,
            Some(ThreadForm::K) if !steep => k,
            Some(ThreadForm::Din) if steep => i,
            Some(ThreadForm::Din) => k,
            _ => None,
        }
        .ok_or_else(|| {
            self.error(if steep && (k.is_some() || i.is_some()) {
                "a thread at 45° or steeper to Z with its lead in the wrong letter (I along X for a DIN 66025 control; none for K along Z)".into()
            } else {
                "a thread without its lead".into()
            })
        })?;
        self.at = to;
        self.motion = if mill { Code::G1 } else { Code::G33 };
        Ok(Move {
            motion: Motion::Thread {
                lead: self.mm(lead),
            },
            to,
            feed: self.feed,
            per_rev: self.per_rev,
            line: self.line,
        })
    }

    /// `G91 G28 Z0` (Fanuc, ISO, LinuxCNC) or `G28 Z0` (FMS-3000: the letters select axes): the
    /// axes named go to a reference position the reader does not know (NaN until a move says
    /// them again).
    fn reference_block(
        &mut self,
        number: u8,
        incremental: bool,
        axes: &[Option<f64>; 6],
    ) -> Result<Move, ReadError> {
        use fmsvm_emit::dialect::ReferenceForm;
        match self.dialect.reference {
            ReferenceForm::Incremental if !incremental => {
                return Err(self.error(
                    "G28/G30 without G91: in G90 its words are an intermediate point".into(),
                ));
            }
            ReferenceForm::Incremental => {}
            ReferenceForm::MachineZero if number == 1 && !incremental => {}
            _ => {
                return Err(self.error(format!(
                    "G{} is not in the dialect's resolved output",
                    if number == 1 { 28 } else { 30 }
                )));
            }
        }
        let mut mask = 0u8;
        for (i, v) in axes.iter().enumerate() {
            if let Some(v) = v {
                if self.dialect.reference == ReferenceForm::Incremental && *v != 0.0 {
                    return Err(self.error(format!(
                        "G91 G28 with a non-zero word: the output returns without an intermediate point ({v})"
                    )));
                }
                mask |= 1 << i;
                self.at[i] = f64::NAN;
            }
        }
        if mask == 0 {
            return Err(self.error("a reference return without an axis".into()));
        }
        Ok(Move {
            motion: Motion::Reference { number, axes: mask },
            to: self.at,
            feed: self.feed,
            per_rev: self.per_rev,
            line: self.line,
        })
    }

    /// A canned-cycle block, its moves queued: Fanuc's `G98 G81 X Y Z R [P] F` (modal), or the
    /// FMS-3000's `G00 X Y G81 U Z [I] F [H] [E]` (§4.1: the other words first, then the cycle).
    #[allow(clippy::too_many_arguments)]
    fn cycle_block(
        &mut self,
        code: Code,
        axes: &[Option<f64>; 6],
        r: Option<f64>,
        u: Option<f64>,
        h: Option<f64>,
        p: Option<f64>,
        e: Option<f64>,
        i: Option<f64>,
    ) -> Result<Option<Move>, ReadError> {
        let fms = self.dialect.cycle_form == fmsvm_emit::dialect::CycleForm::Fms3000;
        let start = self.at;
        if self.cycle.is_none() {
            self.initial = start[2];
        }
        if !fms {
            self.cycle = Some(code);
        }
        let mut at = start;
        let line = self.line;
        let feed = self.feed;
        let push = |q: &mut std::collections::VecDeque<Move>, motion, to: Pose, at: &mut Pose| {
            if motion == Motion::Rapid || motion == Motion::Feed {
                // Axes never said (NaN) are the same on both sides.
                let same = |a: &f64, b: &f64| (a.is_nan() && b.is_nan()) || (a - b).abs() < 1e-9;
                if to.iter().zip(at.iter()).all(|(a, b)| same(a, b)) {
                    return;
                }
                *at = to;
            }
            q.push_back(Move {
                motion,
                to,
                feed,
                per_rev: self.per_rev,
                line,
            });
        };
        let mut q = std::mem::take(&mut self.pending);
        let mut hole = at;
        if let Some(x) = axes[0] {
            hole[0] = self.mm(x);
        }
        if let Some(y) = axes[1] {
            hole[1] = self.mm(y);
        }
        push(&mut q, Motion::Rapid, hole, &mut at);
        let level = |v: Option<f64>, what: &str, me: &Self| {
            v.map(|v| me.mm(v))
                .ok_or_else(|| me.error(format!("a cycle without {what}")))
        };
        let (r_level, bottom) = if fms {
            (level(u, "U", self)?, level(axes[2], "Z", self)?)
        } else {
            (level(r, "R", self)?, level(axes[2], "Z", self)?)
        };
        let mut p_r = hole;
        p_r[2] = r_level;
        let mut p_bottom = hole;
        p_bottom[2] = bottom;
        push(&mut q, Motion::Rapid, p_r, &mut at);
        push(&mut q, Motion::Feed, p_bottom, &mut at);
        let dwell = if fms {
            e.map_or(0.0, |e| e / 10.0)
        } else if matches!(code, Code::G82 | Code::G89) {
            match self.dialect.dwell {
                DwellForm::PSeconds => p.unwrap_or(0.0),
                _ => p.map_or(0.0, |p| p / 1000.0),
            }
        } else {
            0.0
        };
        if dwell > 0.0 {
            q.push_back(Move {
                motion: Motion::Dwell(dwell),
                to: at,
                feed,
                per_rev: self.per_rev,
                line,
            });
        }
        let feed_out = if fms {
            code == Code::G82 && h.is_some()
        } else {
            matches!(code, Code::G85 | Code::G89)
        };
        let before = q.len();
        push(
            &mut q,
            if feed_out {
                Motion::Feed
            } else {
                Motion::Rapid
            },
            p_r,
            &mut at,
        );
        // FMS-3000: G82's H is the feed of the way out (mm/min, Tables 11 and 14).
        if fms
            && feed_out
            && q.len() > before
            && let (Some(h), Some(out)) = (h, q.back_mut())
        {
            out.feed = self.mm(h);
        }
        let end = if fms {
            i.map(|v| self.mm(v))
        } else if self.to_r {
            None
        } else {
            Some(self.initial)
        };
        if let Some(end) = end {
            let mut p_end = hole;
            p_end[2] = end;
            push(&mut q, Motion::Rapid, p_end, &mut at);
        }
        self.at = at;
        let first = q.pop_front();
        self.pending = q;
        Ok(first)
    }
}

impl<R: BufRead> Reader for WordReader<R> {
    fn offsets(&self) -> OffsetState {
        self.offsets
    }

    fn next_move(&mut self) -> Result<Option<Move>, ReadError> {
        if let Some(m) = self.pending.pop_front() {
            return Ok(Some(m));
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    fn moves(text: &str, dialect: Dialect) -> Vec<Move> {
        let mut r = WordReader::new(text.as_bytes(), dialect);
        let mut v = Vec::new();
        while let Some(m) = r.next_move().unwrap() {
            v.push(m);
        }
        v
    }

    #[test]
    fn a_fanuc_cycle_block_reads_as_its_moves() {
        let mut d = Dialect::fanuc();
        d.numbers = [fmsvm_emit::dialect::NumberFormat {
            point: Point::WhenFractional,
            ..fmsvm_emit::dialect::NumberFormat::FANUC
        }; Letter::COUNT];
        let v = moves("G0 X0 Y0 Z10\nG98 G81 X10 Y10 Z-5 R2 F120\nG80\n", d);
        let z: Vec<(Motion, f64)> = v.iter().map(|m| (m.motion, m.to[2])).collect();
        assert_eq!(
            z,
            vec![
                (Motion::Rapid, 10.0),
                (Motion::Rapid, 10.0),
                (Motion::Rapid, 2.0),
                (Motion::Feed, -5.0),
                (Motion::Rapid, 2.0),
                (Motion::Rapid, 10.0)
            ]
        );
    }
}
