//! The resolved emitter: canonical operations written as flat motion — G0/G1/G2/G3 in G90 (with G4, F,
//! S, T, M and comments), every offset, transform, cycle and compensation already applied — in the
//! dialect's number format. What `ncmotion` compares against LinuxCNC's trace.
//!
//! Rules: the first block sets the frame (`G90` with the plane and units); a motion G code is written
//! when it changes, an axis word when its rounded value changes (arcs always carry their plane's two
//! axes and the centre as I J K from the start), F on the first feed move after it changes; a move
//! that rounds to no motion is left out. Arcs in another plane are preceded by G17/G18/G19. The
//! dialect says how numbers, blocks and comments are spelled, and how arcs (I J K, R, chords),
//! helices (the axis word, or G10 with a pitch) and dwells (P ms, P s, X s, E tenths) are written;
//! a dialect without inch mode gets inch programs in mm.

use fmsvm_block::alarms::{IMPROPER_G, NO_FANUC_NUMBER, TOO_MANY_DIGITS};
use std::io::Write;

use fmsvm_block::{Alarm, Code, Letter, Stop};

use crate::dialect::{
    AddressKind, ArcForm, ClampForm, CommentStyle, CssForm, CycleForm, Dialect, DwellForm,
    HelixForm, MillThread, ReferenceForm, SkipForm, ThreadForm,
};
use crate::format::{Prefix, push_code_word, push_formatted, push_padded, push_u64, push_word_as};
use crate::lines::Lines;
use crate::literal::Options;
use fmsvm_canon::AXES;
use fmsvm_canon::Emitter;
use fmsvm_canon::modal::CodeSystem;
use fmsvm_canon::{Arc, Canon, Corners, Origin, Plane, Pose, Warning};

/// The centre letters of the axes X Y Z.
const CENTRE_LETTERS: [Letter; 3] = [Letter::I, Letter::J, Letter::K];

/// How an arc block says its centre.
#[derive(Clone, Copy, Debug)]
enum Centre {
    /// I J K: the centre from the start point (first, second plane axis).
    Offsets([f64; 2]),
    /// I J K: the centre itself, in the output's coordinates (FMS-3000 N3021 = 1, or 2 in G90).
    Absolute([f64; 2]),
    /// R, negative over half a turn.
    Radius(f64),
}

/// The words of an arc block besides its end point.
#[derive(Clone, Copy, Debug)]
struct ArcWords {
    plane: Plane,
    centre: Centre,
    /// The arc's radius.
    radius: f64,
    /// The helix pitch word (FMS-3000 G10): its letter and the rise per revolution.
    pitch: Option<(Letter, f64)>,
}

/// What the run's thread checks, for the pipelined emitter, to know that a rapid or feed move or a
/// feed rate cannot fail in `canon`: the values each axis and the feed rate write without an alarm
/// in the units in force, the most bytes of a move's line, and that nothing else is due before the
/// next move (`Pipelined`, "Resolved output").
#[derive(Clone, Copy, Debug)]
pub struct Offload {
    /// Per axis (X … C): values below this in magnitude, in the program's units, are written.
    hi: [f64; 6],
    /// The same for the feed rate.
    hi_feed: f64,
    /// The most bytes of a move's line, its end included.
    bound: u32,
    /// The feed rate a feed move may write next is in its range (or none is due).
    feed_safe: bool,
    /// The last operation was a move or a feed rate: a move has nothing else to write first (a
    /// cycle to close, offset codes, a changed unit).
    steady: bool,
}

impl Offload {
    /// The most bytes `op`'s line takes, when `op` is a move or a feed rate that cannot fail; None
    /// otherwise.
    #[inline]
    pub(crate) fn takes(&mut self, op: &Canon<'_>) -> Option<u32> {
        if !self.steady {
            return None;
        }
        match *op {
            Canon::Rapid(to) | Canon::Feed(to) if self.feed_safe => {
                for (v, hi) in to.iter().zip(&self.hi) {
                    if !(v.is_nan() || v.abs() < *hi) {
                        return None;
                    }
                }
                Some(self.bound)
            }
            Canon::FeedRate(f) if f.abs() < self.hi_feed => {
                self.feed_safe = true;
                Some(0)
            }
            _ => None,
        }
    }

    /// The safe range of axis `i` (for the tests of the bound).
    #[cfg(test)]
    pub(crate) fn hi_for_tests(&self, i: usize) -> f64 {
        self.hi[i]
    }

    /// The safe range of the feed rate (for the tests of the bound).
    #[cfg(test)]
    pub(crate) fn hi_feed_for_tests(&self) -> f64 {
        self.hi_feed
    }

    /// These checks after `op` ran on the run's thread.
    pub(crate) fn after(self, op: &Canon<'_>) -> Self {
        Offload {
            steady: matches!(op, Canon::Rapid(_) | Canon::Feed(_) | Canon::FeedRate(_)),
            ..self
        }
    }
}

/// Writes canonical operations as flat motion.
pub struct ResolvedEmitter<W: Write> {
    lines: Lines<W>,
    dialect: Dialect,
    options: Options,
    /// Renumbered output's block numbers.
    numbers: Option<crate::dialect::BlockNumbers>,
    number: Option<u32>,
    /// Lengths are in inch in the output (G20).
    inch: bool,
    /// The program's lengths are inch but the dialect has no inch mode: ×25.4 on the way out.
    scale: f64,
    /// Exact position of the tool (output frame).
    at: Pose,
    /// The span of the moves against the machine's travels.
    travel: crate::travel::Travel,
    /// The next motion line stops exactly at its end (G09 on the control).
    exact_once: bool,
    /// The corner mode as last written.
    corner_mode: Option<Corners>,
    /// The lathe tool the output last changed to (LinuxCNC's `T1 M6`).
    lathe_tool_loaded: Option<u32>,
    /// The skip code the motion line being written carries after its motion code (G31, G32).
    skip_code: Option<Code>,
    /// Rounded position as last written, in least increments (None: never written).
    written: [Option<i64>; 6],
    /// Motion G code ×10 in effect in the output, if any yet.
    motion: Option<Code>,
    plane: Plane,
    /// The frame line went out.
    started: bool,
    /// Between `Canon::Cycle` and `Canon::CycleEnd`.
    in_cycle: bool,
    /// A native cycle is in effect in the output (G80 due before anything else).
    cycle_open: bool,
    /// The last thing written ended the program (M2, M30).
    ended: bool,
    /// What the run should be told (an end of program written for it).
    warnings: Vec<Warning>,
    /// The open native cycle's last block said a dwell (FMS-3000's E, which stays in force for the
    /// next block of the same cycle and has no "none": §4.1).
    cycle_dwell: bool,
    /// The unit the output last said (G20 true, G21 false), if any yet.
    units: Option<bool>,
    /// The feed rate programmed, and whether the output still has to say it.
    feed: f64,
    feed_due: bool,
    /// Each letter's prefix alone and after the separator (None: longer than a prefix takes).
    prefixes: [[Option<Prefix>; 2]; Letter::COUNT],
    /// The letter's numbers are in Fanuc's format.
    fanuc: [bool; Letter::COUNT],
    /// What the output's X word is of the kernel's X (2 on a diameter lathe, else 1).
    x_scale: f64,
    /// The spindle under a turning program.
    spindle: Spindle,
    /// The control's work system the output said last (1–6: G54–G59; 0: none yet, where the
    /// control's own is taken as G54), where the kernel leaves work offsets to the control; and one
    /// selected that no block has said yet.
    work_system: u8,
    work_due: Option<u8>,
    /// The control's length offset selected that no block has said yet (G43/G44 H, G49).
    length_due: Option<(Code, u16)>,
}

/// The spindle's state as a turning program's output has it (docs/lathe.md).
#[derive(Clone, Copy, Debug, Default)]
struct Spindle {
    /// Constant surface speed in force (m/min or ft/min).
    css: Option<f64>,
    /// The speed limit, rpm.
    clamp: Option<f64>,
    /// The rpm last written (a control without CSS).
    rpm: Option<i64>,
    /// The feed mode last written (feed per revolution: true).
    per_rev: Option<bool>,
}

impl<W: Write> ResolvedEmitter<W> {
    /// What the run should be told about the output (an end of program written for the control).
    pub fn warnings(&self) -> Vec<Warning> {
        let mut all = self.warnings.clone();
        all.extend(
            self.numbers
                .as_ref()
                .and_then(|n| n.warning(&self.dialect.name))
                .map(Warning::program),
        );
        all.extend(self.lines.comment_warnings(&self.dialect.name));
        all
    }

    /// The bytes written so far (for the tests of the bound).
    #[cfg(test)]
    pub(crate) fn output_for_tests(&self) -> &[u8] {
        &self.lines.buf
    }

    /// The byte budget the lines are spent from.
    pub(crate) fn budget(&self) -> &fmsvm_block::OutputBudget {
        &self.options.budget
    }

    /// The checks that let the pipelined emitter hand moves to a writer thread, worked out from
    /// the units in force; None for a turning dialect (its moves may write a spindle speed), a
    /// machine with declared travels (a running span, [`crate::travel`]) or where a move's
    /// longest line passes the dialect's length.
    pub(crate) fn offload(&self) -> Option<Offload> {
        let d = &self.dialect;
        // The travels are a running span, checked on one thread in the order of the moves.
        if d.turning().is_some() || self.travel.limited() {
            return None;
        }
        let inch = self.inch;
        let word = |l: Letter| {
            let prefix = d.separator.len() + l.as_str().len();
            prefix
                + 3
                + d.max_digits as usize
                + d.numbers[l.index()].width as usize
                + d.digits(l, inch) as usize
        };
        // `least_increments`: |v × 10^digits| below the limit; a margin of 2^-40 covers the
        // product's rounding.
        let hi = |l: Letter, scale: f64| {
            d.increments_limit() / Dialect::increments_per_unit(d.digits(l, inch))
                * (1.0 - 2f64.powi(-40))
                / scale
        };
        let mut limits = [0.0; 6];
        for (i, limit) in limits.iter_mut().enumerate() {
            let l = AXES[i];
            let linear = matches!(d.kind(l), AddressKind::Linear | AddressKind::Feed);
            let scale =
                if linear { self.scale } else { 1.0 } * if i == 0 { self.x_scale } else { 1.0 };
            *limit = hi(l, scale);
        }
        let hi_feed = hi(Letter::F, self.scale);
        // `/`, N, two codes, six axes, F and the line's end.
        let n = 2 + d.separator.len() + (d.number_width as usize).max(10);
        let code = d.separator.len() + 7 + d.numbers[Letter::G.index()].width as usize;
        let bound = 1
            + n
            + 2 * code
            + AXES.iter().map(|&l| word(l)).sum::<usize>()
            + word(Letter::F)
            + d.eol.len();
        if d.max_block.is_some_and(|m| bound > m) {
            return None;
        }
        Some(Offload {
            hi: limits,
            hi_feed,
            bound: u32::try_from(bound).ok()?,
            feed_safe: !self.feed_due || self.feed.abs() < hi_feed,
            steady: false,
        })
    }

    /// Each line goes to the writer as it ends, not in 64 KiB pieces: for `--verify`'s reader
    /// beside the writer.
    pub fn line_by_line(mut self) -> Self {
        self.lines.line_by_line();
        self
    }

    /// An emitter writing to `out`.
    pub fn new(out: W, dialect: Dialect, options: Options) -> Self {
        ResolvedEmitter {
            lines: Lines::new(out, &dialect.eol, dialect.max_block, options.budget.clone()),
            prefixes: crate::literal::prefixes(&dialect.separator),
            fanuc: dialect.fanuc_formats(),
            numbers: dialect.block_numbers(options.renumber),
            number: None,
            travel: crate::travel::Travel::new(dialect.travel),
            exact_once: false,
            corner_mode: None,
            dialect,
            options,
            inch: false,
            scale: 1.0,
            at: [0.0; 6],
            written: [None; 6],
            motion: None,
            plane: Plane::XY,
            units: None,
            started: false,
            in_cycle: false,
            cycle_open: false,
            cycle_dwell: false,
            ended: false,
            warnings: Vec::new(),
            feed: 0.0,
            feed_due: false,
            lathe_tool_loaded: None,
            skip_code: None,
            x_scale: 1.0,
            spindle: Spindle::default(),
            work_system: 0,
            work_due: None,
            length_due: None,
        }
        .turning()
    }

    /// Set up for a turning program (the dialect's `turning`): X in diameter where the control
    /// reads it so, the ZX plane.
    fn turning(mut self) -> Self {
        if let Some(l) = self.dialect.turning() {
            self.x_scale = if l.diameter { 2.0 } else { 1.0 };
            self.plane = Plane::ZX;
        }
        self
    }

    /// Axis `i`'s output value of kernel coordinate `v` (a lathe's X in diameter).
    #[inline(always)]
    fn axis_value(&self, i: usize, v: f64) -> f64 {
        if i == 0 { v * self.x_scale } else { v }
    }

    fn start_line(&mut self, origin: Origin) {
        self.ended = false;
        if origin.block_delete && self.dialect.block_delete {
            self.lines.buf.push(b'/');
        }
        if let Some(numbers) = &mut self.numbers {
            let n = numbers.take();
            self.lines.buf.push(b'N');
            push_padded(&mut self.lines.buf, n as u64, self.dialect.number_width);
            self.lines
                .buf
                .extend_from_slice(self.dialect.separator.as_bytes());
        }
    }

    /// The separator before the next word, unless the line has nothing yet.
    fn separate(&mut self) {
        let sep = self.dialect.separator.as_bytes();
        if !self.lines.line_is_empty() && !sep.is_empty() && !self.lines.buf.ends_with(sep) {
            self.lines.buf.extend_from_slice(sep);
        }
    }

    /// Each known axis of `to` in least increments (0 where the axis is unknown, NaN).
    fn quantize_pose(&self, to: &Pose) -> Result<[i64; 6], Alarm> {
        let mut q = [0i64; 6];
        for i in (0..6).filter(|&i| !to[i].is_nan()) {
            q[i] = self.quantize(AXES[i], self.axis_value(i, to[i]))?;
        }
        Ok(q)
    }

    /// `value` of `letter` in least increments, or alarm 0003 when it does not fit the dialect.
    fn quantize(&self, letter: Letter, value: f64) -> Result<i64, Alarm> {
        self.quantize_in(letter, value, false)
    }

    /// A thread's lead in `letter`, quantized: a length a revolution, so F's per-revolution
    /// digits whatever the feed mode.
    fn quantize_lead(&self, letter: Letter, lead: f64) -> Result<i64, Alarm> {
        self.quantize_in(letter, lead, true)
    }

    fn quantize_in(&self, letter: Letter, value: f64, lead: bool) -> Result<i64, Alarm> {
        let value = match self.dialect.kind(letter) {
            AddressKind::Linear | AddressKind::Feed => value * self.scale,
            _ => value,
        };
        self.dialect
            .least_increments(value, self.digits(letter, lead))
            .ok_or_else(|| self.dialect.too_many_digits(letter, value))
    }

    /// Decimals of `letter` here: a feed's by the feed mode and units in force (`lead`: a
    /// thread's lead, always per revolution).
    fn digits(&self, letter: Letter, lead: bool) -> u32 {
        if letter == Letter::F {
            let per_rev = lead || self.spindle.per_rev == Some(true);
            self.dialect.feed_digits(per_rev, self.inch)
        } else {
            self.dialect.digits(letter, self.inch)
        }
    }

    /// The separator and `letter` before the next word (the separator as `separate` writes it), as
    /// a prefix of the number's store, or written here when too long for one.
    #[inline]
    fn prefix(&mut self, letter: Letter) -> Prefix {
        let sep = self.dialect.separator.as_bytes();
        let buf = &self.lines.buf;
        let ends_with_sep = match sep {
            [b] => buf.last() == Some(b),
            _ => buf.ends_with(sep),
        };
        let need = !self.lines.line_is_empty() && !sep.is_empty() && !ends_with_sep;
        match self.prefixes[letter.index()][need as usize] {
            Some(p) => p,
            None => {
                self.separate();
                self.lines.buf.extend_from_slice(letter.as_str().as_bytes());
                Prefix::NONE
            }
        }
    }

    fn push_number(&mut self, letter: Letter, q: i64) {
        self.push_number_as(letter, letter, q);
    }

    /// The word `letter` with a value quantized and formatted as address `like`'s (FMS-3000's H,
    /// a feed in G82).
    fn push_number_as(&mut self, letter: Letter, like: Letter, q: i64) {
        let digits = self.digits(like, false);
        self.push_number_in(letter, like, q, digits);
    }

    /// A thread's lead `q` (`quantize_lead`) in `letter`.
    fn push_lead(&mut self, letter: Letter, q: i64) {
        let digits = self.digits(letter, true);
        self.push_number_in(letter, letter, q, digits);
    }

    /// The word `letter` with `q` in `digits` decimals, formatted as address `like`'s.
    fn push_number_in(&mut self, letter: Letter, like: Letter, q: i64, digits: u32) {
        let prefix = self.prefix(letter);
        let i = like.index();
        let (fanuc, format) = (self.fanuc[i], &self.dialect.numbers[i]);
        push_word_as(&mut self.lines.buf, prefix, q, digits, fanuc, format);
    }

    /// A G code word (×10): the meaning `code`, as the control numbers it.
    fn push_code(&mut self, code: Code) {
        let code = match self.dialect.turning() {
            Some(l) => l.codes.written(code),
            None => code,
        };
        let prefix = self.prefix(Letter::G);
        let width = self.dialect.format(Letter::G).width;
        push_code_word(&mut self.lines.buf, prefix, code, width);
    }

    /// A skip move in the control's own touch-stop block (`[motion] skip`), or refused: a plain
    /// feed to the programmed end would drive the probe through the surface.
    fn skip(&mut self, to: &Pose, origin: Origin) -> Result<(), Stop> {
        let (motion, with) = match self.dialect.skip {
            SkipForm::None => {
                return Err(Alarm::new(
                    NO_FANUC_NUMBER,
                    format!(
                        "G31 (a skip move): the {} dialect has no touch-stop block ([motion] skip), and a plain feed to the programmed end would drive the probe through the surface",
                        self.dialect.name
                    ),
                )
                .into());
            }
            SkipForm::G31 => (Code::G1, Some(Code::G31)),
            SkipForm::G01G32 => (Code::G1, Some(Code::G32)),
            SkipForm::G38_3 => (Code::from_tenths(383), None),
        };
        self.skip_code = with;
        // The block is written whatever it repeats: the probe moves until it touches.
        let always: Vec<usize> = (0..6)
            .filter(|&i| !to[i].is_nan() && self.at[i] != to[i])
            .collect();
        let done = self.motion_line(motion, to, &always, None, origin);
        self.skip_code = None;
        if self.dialect.skip == SkipForm::G38_3 {
            // G38.3 stays in force as the motion code: the next move says its own.
            self.motion = None;
        }
        done
    }

    /// One motion line: its G code, the axis words that change (and `always`), the arc's words,
    /// then F when it is due.
    fn motion_line(
        &mut self,
        code: Code,
        to: &Pose,
        always: &[usize],
        arc: Option<&ArcWords>,
        origin: Origin,
    ) -> Result<(), Stop> {
        let q = self.quantize_pose(to)?;
        let mut change = [false; 6];
        for i in 0..6 {
            // An axis the kernel does not know is not moved by this block: never written.
            if to[i].is_nan() {
                continue;
            }
            change[i] = self.written[i] != Some(q[i]) || always.contains(&i);
        }
        if change[1] {
            self.lathe_y()?;
        }
        let exact_once = std::mem::take(&mut self.exact_once);
        if arc.is_none() && !change.iter().any(|&c| c) {
            self.at = *to;
            return Ok(());
        }
        self.start_line(origin);
        self.push_offset_codes();
        if let (true, Some([once, ..])) = (exact_once, self.dialect.corners) {
            self.push_code(once);
        }
        if let Some(w) = arc
            && w.plane != self.plane
        {
            self.push_code(w.plane.code());
            self.plane = w.plane;
        }
        if self.motion != Some(code) {
            self.push_code(code);
            self.motion = Some(code);
        }
        if let Some(c) = self.skip_code {
            self.push_code(c);
        }
        if let Some(ArcWords { pitch: Some(_), .. }) = arc {
            self.push_code(Code::G10);
        }
        for i in 0..6 {
            if change[i] {
                self.push_number(AXES[i], q[i]);
                self.written[i] = Some(q[i]);
            }
        }
        if let Some(w) = arc {
            match w.centre {
                Centre::Offsets(offsets) | Centre::Absolute(offsets) => {
                    let (a, b, _) = w.plane.axes();
                    for (axis, c) in [(a, offsets[0]), (b, offsets[1])] {
                        let letter = CENTRE_LETTERS[axis];
                        let v = self.quantize(letter, c)?;
                        self.push_number(letter, v);
                    }
                }
                Centre::Radius(r) => {
                    let v = self.quantize(Letter::R, r)?;
                    self.push_number(Letter::R, v);
                }
            }
            if let Some((letter, pitch)) = w.pitch {
                let v = self.quantize(letter, pitch)?;
                self.push_number(letter, v);
            }
        }
        self.push_length_register();
        // A pitch helix's F is the feed along the helix (FMS-3000 §1.4.5.3), Fanuc's the feed
        // along the arc in the plane: F·√((2πR)² + K²)/2πR, said in every helix block and again
        // in the block after it.
        let along_helix = arc.and_then(|w| {
            let (_, k) = w.pitch?;
            let turn = std::f64::consts::TAU * w.radius;
            (turn > 0.0).then(|| turn.hypot(k) / turn)
        });
        if code != Code::G0 && (self.feed_due || along_helix.is_some()) {
            let f = self.quantize(Letter::F, self.feed * along_helix.unwrap_or(1.0))?;
            self.push_number(Letter::F, f);
            self.feed_due = along_helix.is_some();
        }
        self.at = *to;
        self.lines.end_line()
    }

    /// The control's work system and length offset codes selected since the last block (`G55`,
    /// `G43`), at the start of a block.
    fn push_offset_codes(&mut self) {
        if let Some(n) = self.work_due.take() {
            self.push_code(work_system_code(n));
            self.work_system = n;
        }
        if let Some((code, _)) = self.length_due {
            // The kernel's length is on Z; the FMS-3000 takes it on the normal of the plane in
            // force (§3.3, Table 7): G43/G44/G49 are said in G17.
            if self.plane != Plane::XY {
                self.push_code(Plane::XY.code());
                self.plane = Plane::XY;
            }
            self.push_code(code);
        }
    }

    /// The H word of a length offset put in force in this block (after its axis words, as
    /// `G43 Z50. H1`).
    fn push_length_register(&mut self) {
        if let Some((code, h)) = self.length_due.take()
            && code != Code::G49
        {
            let prefix = self.prefix(Letter::H);
            push_code_word(
                &mut self.lines.buf,
                prefix,
                Code::from_tenths(u32::from(h) * 10),
                0,
            );
        }
    }

    /// The offset codes still due, in a block of their own, before a block that is not a move.
    fn flush_offset_codes(&mut self, origin: Origin) -> Result<(), Stop> {
        if self.work_due.is_none() && self.length_due.is_none() {
            return Ok(());
        }
        self.start_line(origin);
        self.push_offset_codes();
        self.push_length_register();
        self.lines.end_line()
    }

    /// The tool stands at `to` on the axes of `axes` (bit 0 X … bit 5 C) with nothing written: a
    /// known axis counts as written there (a move restates it only when it changes), an unknown
    /// one is written when a move first gives it.
    fn stand_at(&mut self, axes: u8, to: &Pose) -> Result<(), Alarm> {
        for i in (0..6).filter(|i| axes & (1 << i) != 0) {
            self.written[i] = if to[i].is_nan() {
                None
            } else {
                Some(self.quantize(AXES[i], self.axis_value(i, to[i]))?)
            };
            self.at[i] = to[i];
        }
        Ok(())
    }

    /// A return to reference position `number` on `axes`, as the dialect says one (`G91 G28 Z0`
    /// then `G90`; the FMS-3000's `G28 Z0`), or as a rapid to it where the dialect has no return
    /// code and the position is known; otherwise alarm 0224.
    fn reference(&mut self, number: u8, axes: u8, to: &Pose, origin: Origin) -> Result<(), Stop> {
        let returned = || (0..6).filter(move |i| axes & (1 << i) != 0);
        if axes & 0b10 != 0 {
            self.lathe_y()?;
        }
        let code = match (self.dialect.reference, number) {
            (ReferenceForm::Incremental, 1) | (ReferenceForm::MachineZero, 1) => Some(Code::G28),
            (ReferenceForm::Incremental, _) => Some(Code::G30),
            _ => None,
        };
        let Some(code) = code else {
            if let Some(i) = returned().find(|&i| to[i].is_nan()) {
                return Err(fmsvm_canon::unknown_axis(
                    i,
                    &format!(
                        "{} in the {} dialect (it has no such return: the move is written to the reference position, which --offsets [reference] gives)",
                        if number == 1 { "G28".to_string() } else { format!("G30 P{number}") },
                        self.dialect.name
                    ),
                )
                .into());
            }
            return self.motion_line(Code::G0, to, &[], None, origin);
        };
        // A lathe in G-code system A says the increment with U, V and W: `G28 U0. W0.` (no G91).
        let lathe_a = self.dialect.turning().map(|l| l.codes) == Some(CodeSystem::LatheA);
        let incremental = self.dialect.reference == ReferenceForm::Incremental && !lathe_a;
        self.start_line(origin);
        if incremental {
            self.push_code(Code::G91);
        }
        self.push_code(code);
        if code == Code::G30 && number > 2 {
            // P is an integer word (`P3`, never `P3.`).
            let prefix = self.prefix(Letter::P);
            push_code_word(
                &mut self.lines.buf,
                prefix,
                Code::from_tenths(u32::from(number) * 10),
                0,
            );
        }
        for i in returned() {
            let letter = match i {
                0 if lathe_a => Letter::U,
                1 if lathe_a => Letter::V,
                2 if lathe_a => Letter::W,
                _ => AXES[i],
            };
            self.push_number(letter, 0);
        }
        self.lines.end_line()?;
        if incremental {
            self.start_line(origin);
            self.push_code(Code::G90);
            self.lines.end_line()?;
        }
        Ok(self.stand_at(axes, to)?)
    }

    /// G53 in the dialect's own form: `G53 G0 Z-5.` (Fanuc, ISO, LinuxCNC: one block), or the
    /// FMS-3000's modal `G53 G00 Z-5` and `G54` after it (§2.15.5). A dialect without G53 gets the
    /// move in the output frame, which assumes the control's G54 is the one fmsvm was given.
    fn machine(&mut self, axes: u8, machine: &Pose, to: &Pose, origin: Origin) -> Result<(), Stop> {
        if axes & 0b10 != 0 {
            self.lathe_y()?;
        }
        if self.dialect.reference == ReferenceForm::None {
            return self.motion_line(Code::G0, to, &[], None, origin);
        }
        self.start_line(origin);
        self.push_code(Code::G53);
        self.push_code(Code::G0);
        self.motion = Some(Code::G0);
        for i in (0..6).filter(|i| axes & (1 << i) != 0) {
            let q = self.quantize(AXES[i], self.axis_value(i, machine[i]))?;
            self.push_number(AXES[i], q);
        }
        self.lines.end_line()?;
        if self.dialect.reference == ReferenceForm::MachineZero {
            self.start_line(origin);
            self.push_code(work_system_code(self.work_system));
            self.lines.end_line()?;
        }
        Ok(self.stand_at(axes, to)?)
    }

    /// An arc as the dialect writes it: whole, in pieces, or as chords.
    fn arc(&mut self, arc: &Arc, origin: Origin) -> Result<(), Stop> {
        let from = self.at;
        let (a, b, n) = arc.plane.axes();
        let code = if arc.clockwise { Code::G2 } else { Code::G3 };
        // An arc of less than half a turn whose end rounds onto its start is no motion at the
        // output's resolution: written, its I J K form would be a full circle.
        if arc.sweep(&from).1 < std::f64::consts::PI {
            let mut same = true;
            for i in [a, b, n] {
                if !(arc.to[i].is_nan() && from[i].is_nan()) {
                    same &= self.quantize(AXES[i], self.axis_value(i, arc.to[i]))?
                        == self.quantize(AXES[i], self.axis_value(i, from[i]))?;
                }
            }
            if same {
                self.at = arc.to;
                return Ok(());
            }
        }
        // An unknown normal axis (NaN at both ends) does not move: no helix.
        let helix = !arc.to[n].is_nan()
            && !from[n].is_nan()
            && self.quantize(AXES[n], self.axis_value(n, arc.to[n]))?
                != self.quantize(AXES[n], self.axis_value(n, from[n]))?;
        let form = if helix {
            match self.dialect.helix {
                HelixForm::Linearize => ArcForm::Linearize,
                _ => self.dialect.arcs,
            }
        } else {
            self.dialect.arcs
        };
        if form == ArcForm::Linearize {
            let tolerance = self.options.arc_tolerance;
            return fmsvm_canon::arcs::chords(&from, arc, tolerance, &mut |p| {
                self.motion_line(Code::G1, &p, &[], None, origin)
            });
        }
        let (r, sweep) = arc.sweep(&from);
        let pitch = (helix && self.dialect.helix == HelixForm::Pitch).then(|| {
            let rise = arc.to[n] - from[n];
            (CENTRE_LETTERS[n], rise * std::f64::consts::TAU / sweep)
        });
        // Fanuc's I J K arcs take a full circle in one block (end = start) and have no turn count: a
        // multi-turn arc is its whole turns, then the rest. R cannot say a full circle, nor can a
        // pitch block (FMS-3000 reads a full circle from the missing axis words): at most half a turn
        // a block there.
        let full_turn = form == ArcForm::Ijk && pitch.is_none();
        let pieces = if full_turn {
            arc.turns as usize + 1
        } else if sweep > std::f64::consts::PI + 1e-9
            && (form == ArcForm::Radius || pitch.is_some())
        {
            // Half a turn at most a block, a 270° helix in two (docs/dialects.md).
            (sweep / std::f64::consts::PI - 1e-9).ceil() as usize
        } else {
            1
        };
        let [cx, cy] = arc.centre;
        let a0 = (from[b] - cy).atan2(from[a] - cx);
        let dir = if arc.clockwise { -1.0 } else { 1.0 };
        for k in 1..=pieces {
            let t = if full_turn {
                if k == pieces {
                    1.0
                } else {
                    k as f64 * std::f64::consts::TAU / sweep
                }
            } else {
                k as f64 / pieces as f64
            };
            let to = if k == pieces {
                arc.to
            } else {
                let mut p: Pose = std::array::from_fn(|i| from[i] + (arc.to[i] - from[i]) * t);
                if !full_turn {
                    let ang = a0 + dir * sweep * t;
                    p[a] = cx + r * ang.cos();
                    p[b] = cy + r * ang.sin();
                } else {
                    p[a] = from[a];
                    p[b] = from[b];
                }
                p
            };
            let start = self.at;
            let piece_sweep = if full_turn && k < pieces {
                std::f64::consts::TAU
            } else if full_turn {
                sweep - (pieces - 1) as f64 * std::f64::consts::TAU
            } else {
                sweep / pieces as f64
            };
            let centre = match form {
                ArcForm::Radius => {
                    // Over half a turn the radius is negative (the long way round).
                    let r = if piece_sweep > std::f64::consts::PI + 1e-9 {
                        -r
                    } else {
                        r
                    };
                    Centre::Radius(r)
                }
                _ if self.dialect.centre_absolute => Centre::Absolute([cx, cy]),
                _ => Centre::Offsets([cx - start[a], cy - start[b]]),
            };
            let words = ArcWords {
                plane: arc.plane,
                centre,
                radius: r,
                pitch,
            };
            // A whole turn in the plane: its end point said (Fanuc), or only its centre, the
            // plane's axis words left out where the output already stands there (FMS-3000
            // §2.4.3: I J K without X Y Z is a full circle).
            let whole = full_turn && piece_sweep >= std::f64::consts::TAU - 1e-9;
            let always: &[usize] = if whole && self.dialect.circle_by_centre {
                &[]
            } else {
                &[a, b]
            };
            self.motion_line(code, &to, always, Some(&words), origin)?;
        }
        Ok(())
    }

    /// G80 after native cycles, before anything else is written (a cycle would repeat at the next
    /// positioning block).
    fn close_cycle(&mut self, origin: Origin) -> Result<(), Stop> {
        if !self.cycle_open {
            return Ok(());
        }
        self.cycle_open = false;
        self.start_line(origin);
        self.push_code(Code::G80);
        self.motion = None;
        // G80 cancels the cycle's F with it (FMS-3000 §4.3): the next feed move says its F.
        self.feed_due = true;
        self.lines.end_line()
    }

    /// One hole of a native cycle as the dialect writes it; the cycle's moves that follow are only
    /// followed.
    fn cycle(&mut self, c: &fmsvm_canon::CycleOp, origin: Origin) -> Result<(), Stop> {
        let x = self.quantize(Letter::X, c.hole[0])?;
        let y = self.quantize(Letter::Y, c.hole[1])?;
        let z = self.quantize(Letter::Z, c.bottom)?;
        let r = self.quantize(Letter::R, c.r)?;
        let end = self.quantize(Letter::Z, c.end)?;
        let f = self.quantize(Letter::F, self.feed)?;
        let tenths = (c.dwell * 10.0).round() as u64;
        // FMS-3000 §4.1: a cycle block without its optional words keeps the last block's; E has no
        // value for "no dwell" (1–65535), so the cycle is cancelled (G80) before a hole without one.
        if self.dialect.cycle_form == CycleForm::Fms3000
            && self.cycle_open
            && self.cycle_dwell
            && tenths == 0
        {
            self.close_cycle(origin)?;
        }
        self.start_line(origin);
        // The cycle drills along Z: the plane is G17 whatever the last arc left.
        if self.plane != Plane::XY {
            self.push_code(Plane::XY.code());
            self.plane = Plane::XY;
        }
        match self.dialect.cycle_form {
            CycleForm::Fanuc => {
                let initial = (c.end - c.initial).abs() < 1e-9;
                self.push_code(if initial { Code::G98 } else { Code::G99 });
                self.push_code(c.code);
                self.push_number(Letter::X, x);
                self.push_number(Letter::Y, y);
                self.push_number(Letter::Z, z);
                self.push_number(Letter::R, r);
                // P is sticky in the cycle mode: always said, so that no earlier P carries over.
                if matches!(c.code, Code::G82 | Code::G89) {
                    self.separate();
                    self.lines.buf.push(b'P');
                    if self.dialect.dwell == DwellForm::PSeconds {
                        let q = (c.dwell * 1000.0).round() as i64;
                        push_formatted(&mut self.lines.buf, q, 3, self.dialect.format(Letter::X));
                    } else {
                        push_u64(&mut self.lines.buf, (c.dwell * 1000.0).round() as u64);
                    }
                }
                self.push_number(Letter::F, f);
            }
            CycleForm::Fms3000 => {
                // §4.1: other words before the cycle code, its parameters after.
                self.push_code(Code::G0);
                self.push_number(Letter::X, x);
                self.push_number(Letter::Y, y);
                let exit_feed = matches!(c.code, Code::G85 | Code::G89);
                self.push_code(if exit_feed { Code::G82 } else { Code::G81 });
                self.push_number(Letter::U, r);
                self.push_number(Letter::Z, z);
                // I (point 4, the exit level) is optional and stays in force from the block before
                // (§4.1): always said, so that no earlier exit level carries over.
                self.push_number(Letter::I, end);
                self.push_number(Letter::F, f);
                if exit_feed {
                    // H is the feed on section 2–3 in mm/min (FMS-3000 Tables 11 and 14): the
                    // feed's value in the feed's format, not a corrector number's.
                    self.push_number_as(Letter::H, Letter::F, f);
                }
                if tenths > 0 {
                    self.separate();
                    self.lines.buf.push(b'E');
                    push_u64(&mut self.lines.buf, tenths.min(65_535));
                }
                self.cycle_dwell = tenths > 0;
            }
        }
        self.lines.end_line()?;
        self.feed_due = false;
        self.written[0] = Some(x);
        self.written[1] = Some(y);
        self.written[2] = Some(end);
        self.motion = Some(c.code);
        self.in_cycle = true;
        self.cycle_open = true;
        Ok(())
    }

    /// A milling thread in one block, `G01 X Y Z G33 F<lead>` (FMS-3000 §2.7: G33 acts on its
    /// block alone, the motion G01's, F the lead per revolution there): the next feed move says
    /// its own F again.
    fn mill_thread(&mut self, to: &Pose, lead: f64, origin: Origin) -> Result<(), Stop> {
        let lead_q = self.quantize_lead(Letter::F, lead)?;
        let q = self.quantize_pose(to)?;
        self.start_line(origin);
        if self.motion != Some(Code::G1) {
            self.push_code(Code::G1);
            self.motion = Some(Code::G1);
        }
        for i in 0..6 {
            if !to[i].is_nan() && self.written[i] != Some(q[i]) {
                self.push_number(AXES[i], q[i]);
                self.written[i] = Some(q[i]);
            }
        }
        self.push_code(Code::G33);
        self.push_lead(Letter::F, lead_q);
        self.feed_due = true;
        self.at = *to;
        self.lines.end_line()
    }

    /// A dwell of `seconds` as the dialect writes it.
    fn dwell(&mut self, seconds: f64, origin: Origin) -> Result<(), Stop> {
        let form = self.dialect.dwell;
        let mut units = (seconds.max(0.0) * form.units_per_second()).round() as u64;
        // A form with a most a block (FMS-3000's 65535 tenths) takes several; a dwell of none is
        // still one block where the form has no most (`G4 P0`).
        let most = form.most_a_block().unwrap_or(u64::MAX);
        if units == 0 && seconds > 0.0 && form.most_a_block().is_some() {
            // Below half the form's unit (FMS-3000: 0.05 s of its tenths): no block can say it.
            self.warnings.push(Warning::at(
                origin,
                format!(
                    "a dwell of {seconds} s is under half of the {} dialect's least dwell: not written",
                    self.dialect.name
                ),
            ));
        }
        loop {
            let here = units.min(most);
            units -= here;
            if here == 0 && form.most_a_block().is_some() {
                return Ok(());
            }
            self.start_line(origin);
            self.push_code(Code::G4);
            self.separate();
            self.lines
                .buf
                .extend_from_slice(form.letter().as_str().as_bytes());
            if form.whole_units() {
                push_u64(&mut self.lines.buf, here);
            } else {
                push_formatted(
                    &mut self.lines.buf,
                    here as i64,
                    3,
                    self.dialect.format(Letter::X),
                );
            }
            self.lines.end_line()?;
            if units == 0 {
                return Ok(());
            }
        }
    }

    /// A Y move is written: refused on a lathe dialect whose control has no Y axis.
    fn lathe_y(&self) -> Result<(), Alarm> {
        match self.dialect.turning() {
            Some(l) if !l.y_axis => Err(Alarm::new(
                IMPROPER_G,
                format!(
                    "a Y move: the {} dialect writes a lathe of X and Z ([lathe] y_axis = false): a turning centre's Y has no word there",
                    self.dialect.name
                ),
            )),
            _ => Ok(()),
        }
    }

    /// A lathe's turning form, or alarm 0010 naming what needs it (a mill dialect).
    fn lathe_form(&self, what: &str) -> Result<crate::dialect::LatheForm, Stop> {
        self.dialect.turning().cloned().ok_or_else(|| {
            Alarm::new(
                IMPROPER_G,
                format!(
                    "{what} is a lathe's: the {} dialect writes for a mill",
                    self.dialect.name
                ),
            )
            .into()
        })
    }

    /// S in rpm; on a lathe it ends constant surface speed (`G97 S`).
    fn speed(&mut self, s: f64, origin: Origin) -> Result<(), Stop> {
        let Some(l) = self.dialect.turning().cloned() else {
            return self.word_line(Letter::S, s, origin);
        };
        let was_css = self.spindle.css.take().is_some();
        self.spindle.rpm = None;
        if l.css == CssForm::Native && was_css {
            self.start_line(origin);
            self.push_code(Code::G97);
            self.push_integer(Letter::S, s)?;
            return self.lines.end_line();
        }
        self.word_line(Letter::S, s, origin)
    }

    /// G96 S: the control's own, or remembered for the rpm of each move (`rpm_for`).
    fn surface_speed(&mut self, v: f64, origin: Origin) -> Result<(), Stop> {
        let l = self.lathe_form("G96 constant surface speed")?;
        self.spindle.css = Some(v);
        if l.css == CssForm::Rpm {
            self.spindle.rpm = None;
            return Ok(());
        }
        self.start_line(origin);
        self.push_code(Code::G96);
        if l.clamp == ClampForm::D
            && let Some(c) = self.spindle.clamp
        {
            // LinuxCNC's D here is the speed limit in rev/min: a spindle speed's range, not a
            // corrector number's.
            self.push_integer_as(Letter::D, Letter::S, c)?;
        }
        self.push_integer(Letter::S, v)?;
        self.lines.end_line()
    }

    /// The spindle clamp (G50 S) in the control's form.
    fn clamp(&mut self, s: f64, origin: Origin) -> Result<(), Stop> {
        let l = self.lathe_form("G50 S spindle speed clamp")?;
        self.spindle.clamp = Some(s);
        if l.css == CssForm::Rpm {
            // Applied to the rpm written per move.
            self.spindle.rpm = None;
            return Ok(());
        }
        match l.clamp {
            ClampForm::G50 | ClampForm::G92 => {
                self.start_line(origin);
                // G50 (system A) and G92 (B) are the same meaning: coordinate setting.
                self.push_code(Code::G92);
                self.push_integer(Letter::S, s)?;
                self.lines.end_line()
            }
            ClampForm::D => match self.spindle.css {
                // LinuxCNC takes the clamp on the G96 block: say it again with it.
                Some(v) => self.surface_speed(v, origin),
                None => Ok(()),
            },
            ClampForm::Lims => {
                self.start_line(origin);
                self.lines.buf.extend_from_slice(b"LIMS=");
                push_u64(&mut self.lines.buf, s.round().max(0.0) as u64);
                self.lines.end_line()
            }
        }
    }

    /// On a control without constant surface speed: the rpm a move under G96 needs, written when
    /// it changes: 1000·V/(π·D) at the larger diameter of the move's two ends (so the surface speed
    /// never exceeds V along it), clamped (docs/lathe.md).
    fn rpm_for(&mut self, to: &Pose, origin: Origin) -> Result<(), Stop> {
        let Some(v) = self.spindle.css else {
            return Ok(());
        };
        if self.dialect.turning().map(|l| l.css) != Some(CssForm::Rpm) {
            return Ok(());
        }
        let radius = to[0].abs().max(if self.at[0].is_nan() {
            0.0
        } else {
            self.at[0].abs()
        });
        let radius_mm = if self.inch { radius * 25.4 } else { radius };
        let free = fmsvm_canon::surface_speed_constant(v, self.inch) / radius_mm;
        let rpm = match self.spindle.clamp {
            Some(c) => free.min(c),
            None if free.is_finite() => free,
            None => {
                return Err(Alarm::new(
                    NO_FANUC_NUMBER,
                    format!(
                        "G96 at X0 on the {} dialect, which has no constant surface speed: the rpm there is infinite without a clamp (G50 S)",
                        self.dialect.name
                    ),
                )
                .into());
            }
        };
        let rpm = rpm.round() as i64;
        if self.spindle.rpm != Some(rpm) {
            self.spindle.rpm = Some(rpm);
            self.word_line(Letter::S, rpm as f64, origin)?;
        }
        Ok(())
    }

    /// Before M3/M4 under G96 on a control without CSS: the rpm where the tool stands (clamped),
    /// so the spindle does not start at whatever S the control had.
    fn spindle_start(&mut self, origin: Origin) -> Result<(), Stop> {
        let css_as_rpm = self.dialect.turning().map(|l| l.css) == Some(CssForm::Rpm);
        if self.spindle.css.is_none() || !css_as_rpm {
            return Ok(());
        }
        if self.at[0].is_nan() {
            let Some(c) = self.spindle.clamp else {
                return Err(Alarm::new(
                    NO_FANUC_NUMBER,
                    format!(
                        "M3/M4 under G96 on the {} dialect (no constant surface speed) before the tool's X is known: give G50 S (the spindle starts at it) or position X first",
                        self.dialect.name
                    ),
                )
                .into());
            };
            let rpm = c.round() as i64;
            self.spindle.rpm = Some(rpm);
            return self.word_line(Letter::S, rpm as f64, origin);
        }
        let at = self.at;
        self.rpm_for(&at, origin)
    }

    /// A thread to `to`, `lead` per revolution: G32 (system A) or G33 with F or K.
    fn thread(&mut self, to: &Pose, lead: f64, origin: Origin) -> Result<(), Stop> {
        if self.dialect.turning().is_none() && self.dialect.mill_thread == MillThread::G1G33F {
            return self.mill_thread(to, lead, origin);
        }
        let l = self.lathe_form("G32 thread cutting")?;
        let from = [self.at[0], self.at[2]];
        let letter = match l.thread_letter(from, [to[0], to[2]]) {
            Some(letter) => letter,
            None if l.thread == ThreadForm::None => {
                return Err(Alarm::new(
                    IMPROPER_G,
                    format!(
                        "a thread (G32) has no known form on the {} dialect: no single-block thread is known for that control (docs/lathe.md)",
                        self.dialect.name
                    ),
                )
                .into());
            }
            None => {
                return Err(Alarm::new(
                    IMPROPER_G,
                    format!(
                        "a thread at 45° or steeper to the Z axis: the {} dialect's G33 K gives the lead along Z only",
                        self.dialect.name
                    ),
                )
                .into());
            }
        };
        let lead_q = self.quantize_lead(letter, lead)?;
        let q = self.quantize_pose(to)?;
        self.start_line(origin);
        self.push_code(Code::G33);
        self.motion = Some(Code::G33);
        for i in 0..6 {
            // Both ends of a thread are written: its start is the previous block's end.
            if !to[i].is_nan() && (self.written[i] != Some(q[i]) || i == 2) {
                self.push_number(AXES[i], q[i]);
                self.written[i] = Some(q[i]);
            }
        }
        self.push_lead(letter, lead_q);
        if letter == Letter::F {
            // F is now the lead: the next feed move says its own F again.
            self.feed_due = true;
        }
        self.at = *to;
        self.lines.end_line()
    }

    /// `letter` with a whole value (S, D): rounded.
    fn push_integer(&mut self, letter: Letter, v: f64) -> Result<(), Stop> {
        self.push_integer_as(letter, letter, v)
    }

    /// `letter` with a whole value in the range of address `like` (LinuxCNC's G96 D, a speed).
    fn push_integer_as(&mut self, letter: Letter, like: Letter, v: f64) -> Result<(), Stop> {
        let n = crate::literal::integer(letter, v, self.dialect.integer_max(like))?;
        self.separate();
        self.lines.buf.extend_from_slice(letter.as_str().as_bytes());
        push_u64(&mut self.lines.buf, n);
        Ok(())
    }

    /// A lathe's tool call `T0101` in the control's words (`LatheForm::tool_call`, docs/lathe.md,
    /// "Lathe output").
    fn lathe_tool(
        &mut self,
        l: &crate::dialect::LatheForm,
        t: f64,
        origin: Origin,
    ) -> Result<(), Stop> {
        let (text, tool) = l
            .tool_call(t, self.lathe_tool_loaded)
            .map_err(|m| Alarm::new(TOO_MANY_DIGITS, m))?;
        self.start_line(origin);
        self.lathe_tool_loaded = Some(tool);
        self.lines.buf.extend_from_slice(text.as_bytes());
        self.lines.end_line()
    }

    /// Holds the span of the moves (a native cycle's too: the machine makes them) to the machine's
    /// travels; a frame moved under the tool is no motion.
    fn within_travel(&mut self, op: &Canon<'_>) -> Result<(), Stop> {
        let mm = if self.units == Some(true) { 25.4 } else { 1.0 };
        match *op {
            Canon::Rapid(to) | Canon::Feed(to) | Canon::Skip(to) => self.travel.reach(&to, mm)?,
            Canon::Arc(ref arc) => self.travel.reach_arc(&self.at, arc, mm)?,
            Canon::Start(p) if self.started => self.travel.reframe(&self.at, &p, mm),
            Canon::Start(p) => self.travel.reach(&p, mm)?,
            _ => {}
        }
        Ok(())
    }

    fn word_line(&mut self, letter: Letter, value: f64, origin: Origin) -> Result<(), Stop> {
        // An integer address (S, T, M …) within the control's range (FMS-3000: S and T to 9999).
        if let AddressKind::Integer { max } = self.dialect.kind(letter)
            && (value - value.round()).abs() < 1e-9
        {
            crate::literal::integer(letter, value, max)?;
        }
        self.start_line(origin);
        self.lines.buf.extend_from_slice(letter.as_str().as_bytes());
        let r = value.round();
        if (value - r).abs() < 1e-9 && r >= 0.0 {
            let width = self.dialect.format(letter).width;
            push_padded(&mut self.lines.buf, r as u64, width);
        } else {
            let digits = self.dialect.mm_digits;
            let q = self
                .dialect
                .least_increments(value, digits)
                .ok_or_else(|| {
                    Alarm::new(TOO_MANY_DIGITS, format!("too many digits: {letter}{value}"))
                })?;
            push_formatted(
                &mut self.lines.buf,
                q,
                digits,
                self.dialect.format(Letter::X),
            );
        }
        self.lines.end_line()
    }
}

impl<W: Write> Emitter for ResolvedEmitter<W> {
    const CANON: bool = true;

    fn begin(&mut self, number: Option<u32>, title: &str) -> Result<(), Stop> {
        self.number = number;
        self.lines
            .tape_start(&self.dialect, number, title, &self.options.source)
    }

    fn native_cycle(&self, code: Code) -> bool {
        self.dialect.native_cycles.contains(&code)
    }

    fn corners(&self) -> bool {
        self.dialect.corners.is_some()
    }

    fn canon(&mut self, op: &Canon<'_>, origin: Origin) -> Result<(), Stop> {
        if self.travel.limited() {
            self.within_travel(op)?;
        }
        // The moves of a native cycle are the control's to make: followed, not written.
        if self.in_cycle {
            match *op {
                Canon::Rapid(to) | Canon::Feed(to) | Canon::Skip(to) => {
                    self.at = to;
                    return Ok(());
                }
                Canon::CycleEnd => {
                    self.in_cycle = false;
                    return Ok(());
                }
                Canon::Dwell(_) => return Ok(()),
                _ => {}
            }
        }
        match *op {
            Canon::Cycle(_) | Canon::CycleEnd | Canon::FeedRate(_) | Canon::Start(_) => {}
            _ => self.close_cycle(origin)?,
        }
        match *op {
            Canon::Rapid(_)
            | Canon::Feed(_)
            | Canon::Skip(_)
            | Canon::Arc(_)
            | Canon::FeedRate(_)
            | Canon::Start(_)
            | Canon::WorkSystem(_)
            | Canon::ToolLength { .. }
            | Canon::Comment(_) => {}
            _ => self.flush_offset_codes(origin)?,
        }
        match *op {
            Canon::Cycle(c) => self.cycle(&c, origin),
            Canon::CycleEnd => Ok(()),
            Canon::Corners(Corners::ExactStopOnce) => {
                self.exact_once = true;
                Ok(())
            }
            Canon::Corners(mode) => {
                let Some([_, exact, cutting]) = self.dialect.corners else {
                    return Ok(());
                };
                if self.corner_mode == Some(mode) {
                    return Ok(());
                }
                self.corner_mode = Some(mode);
                self.start_line(origin);
                self.push_code(if mode == Corners::ExactStop {
                    exact
                } else {
                    cutting
                });
                self.lines.end_line()
            }
            Canon::Start(p) => {
                // The tool is there (at the start, or after the output frame moved): an axis whose
                // position is known counts as written, so a move names only the axes that change;
                // an unknown one is written when a move first gives it.
                // After the output frame moved (a later Start) the known X Y Z are spelled on the
                // next move: a reader of the flat program cannot know their new coordinates.
                self.stand_at(0b11_1111, &p)?;
                if self.started {
                    self.written[0] = None;
                    self.written[2] = None;
                    // A lathe's Y is never written unless it has one.
                    if self.dialect.turning().is_none_or(|l| l.y_axis) {
                        self.written[1] = None;
                    }
                }
                if self.started {
                    return Ok(());
                }
                self.started = true;
                if let Some(l) = self.dialect.turning() {
                    let frame = l.frame.clone();
                    self.lines.buf.extend_from_slice(frame.as_bytes());
                    return self.lines.end_line();
                }
                self.push_code(Code::G90);
                self.push_code(Code::G17);
                for code in self.dialect.start_modes.clone() {
                    self.push_code(code);
                    if code.tenths() % 10 == 0 && (54..=59).contains(&code.whole()) {
                        self.work_system = (code.whole() - 53) as u8;
                    }
                }
                self.lines.end_line()
            }
            Canon::Units(inch) => {
                // Written at the start and where the unit changes; a repeated G21 says nothing.
                if self.units == Some(inch) {
                    return Ok(());
                }
                if !self.dialect.inch {
                    // No inch mode on the control: inch lengths go out in mm (the positions
                    // written so far are mm already).
                    self.units = Some(inch);
                    self.scale = if inch { 25.4 } else { 1.0 };
                    return Ok(());
                }
                let changed = self.units.is_some() && inch != self.inch;
                if changed {
                    // The tool stays where it is: its coordinates change unit.
                    let k = if inch { 1.0 / 25.4 } else { 25.4 };
                    for v in &mut self.at[..3] {
                        *v *= k;
                    }
                }
                self.units = Some(inch);
                self.inch = inch;
                self.start_line(origin);
                match self.dialect.turning() {
                    // A lathe's own unit words (G71 metric on a SINUMERIK or a FAGOR).
                    Some(l) => {
                        let words = if inch {
                            l.inch.clone()
                        } else {
                            l.metric.clone()
                        };
                        if words.is_empty() {
                            return Err(Alarm::new(
                                IMPROPER_G,
                                format!(
                                    "{}: the {} dialect knows no word for it ([lathe] {})",
                                    if inch { "G20 (inch)" } else { "G21 (mm)" },
                                    self.dialect.name,
                                    if inch { "inch" } else { "metric" }
                                ),
                            )
                            .into());
                        }
                        self.separate();
                        self.lines.buf.extend_from_slice(words.as_bytes());
                    }
                    None => self.push_code(if inch { Code::G20 } else { Code::G21 }),
                }
                // The tool has not moved: what is written counts as the position in the new unit
                // (a block that does not name an axis does not restate it); angles are not lengths.
                if changed {
                    let at = self.at;
                    self.stand_at(0b111, &at)?;
                }
                self.lines.end_line()
            }
            Canon::FeedPerRev(per_rev) => {
                // A turning program's output says its feed mode at the start, then where it changes.
                let said = self.spindle.per_rev == Some(per_rev);
                self.spindle.per_rev = Some(per_rev);
                if said && self.dialect.turning().is_some() {
                    return Ok(());
                }
                self.start_line(origin);
                self.push_code(if per_rev { Code::G95 } else { Code::G94 });
                self.feed_due = true;
                self.lines.end_line()
            }
            Canon::Reference { number, axes, to } => self.reference(number, axes, &to, origin),
            Canon::Machine { axes, machine, to } => self.machine(axes, &machine, &to, origin),
            Canon::Rapid(to) => self.motion_line(Code::G0, &to, &[], None, origin),
            Canon::Feed(to) => {
                if self.spindle.css.is_some() {
                    self.rpm_for(&to, origin)?;
                }
                self.motion_line(Code::G1, &to, &[], None, origin)
            }
            Canon::Skip(to) => self.skip(&to, origin),
            Canon::Arc(arc) => {
                if self.spindle.css.is_some() {
                    self.rpm_for(&arc.to, origin)?;
                }
                self.arc(&arc, origin)
            }
            Canon::Dwell(seconds) => self.dwell(seconds, origin),
            Canon::FeedRate(f) => {
                if f != self.feed {
                    self.feed = f;
                    self.feed_due = true;
                }
                Ok(())
            }
            Canon::Speed(s) => self.speed(s, origin),
            Canon::SurfaceSpeed(v) => self.surface_speed(v, origin),
            Canon::SpindleClamp(s) => self.clamp(s, origin),
            Canon::Thread { to, lead } => self.thread(&to, lead, origin),
            Canon::Tool(t) => match self.dialect.turning().cloned() {
                Some(l) => self.lathe_tool(&l, t, origin),
                _ => self.word_line(Letter::T, t, origin),
            },
            Canon::MCode(m) => {
                if m == 3.0 || m == 4.0 {
                    self.spindle_start(origin)?;
                }
                // The main program's M99 (`--main-m99 end`) is no end of program to a control
                // that requires M2 or M30: it ends with M30.
                let m = if m == 99.0 && self.dialect.end_required {
                    self.warnings.push(Warning::at(
                        origin,
                        format!(
                            "the main program's M99 is written as M30: the {} ends a program with M2 or M30",
                            self.dialect.name
                        ),
                    ));
                    30.0
                } else {
                    m
                };
                self.word_line(Letter::M, m, origin)?;
                self.ended = m == 2.0 || m == 30.0;
                Ok(())
            }
            Canon::AuxCode(letter, code) => self.word_line(letter, code, origin),
            Canon::WorkSystem(n) => {
                // Said with the next block (`G55 G00 X0 Y0`); a Start follows with where the tool
                // is in the new system.
                self.work_due = (n != self.work_system || self.work_due.is_some()).then_some(n);
                Ok(())
            }
            Canon::ToolLength { code, register } => {
                // The register within the control's range (FMS-3000 §1.2.3 Table 3, H 1–255).
                if code != Code::G49
                    && let AddressKind::Integer { max } = self.dialect.kind(Letter::H)
                {
                    crate::literal::integer(Letter::H, f64::from(register), max)?;
                }
                // The control takes the length on (or off) at the next block that moves the
                // axis (FMS-3000 §3.3): that block must spell it.
                self.length_due = Some((code, register));
                self.written[2] = None;
                Ok(())
            }
            Canon::Comment(text) => {
                if !self.options.comments {
                    return Ok(());
                }
                if self.dialect.comments == CommentStyle::None {
                    self.lines.leave_out_comment();
                    return Ok(());
                }
                self.start_line(origin);
                self.lines.push_block_comments(
                    self.dialect.comments,
                    &self.dialect.active_comments,
                    text,
                );
                self.lines.end_line()
            }
        }
    }

    fn message(&mut self, number: u32, text: &str) -> Result<(), Stop> {
        self.lines.message(&self.dialect, number, text)
    }

    fn written(&self) -> u64 {
        self.lines.written()
    }

    fn end(&mut self) -> Result<(), Stop> {
        self.close_cycle(Origin::default())?;
        self.flush_offset_codes(Origin::default())?;
        if self.dialect.end_required && !self.ended {
            self.warnings.push(Warning::program(format!(
                "the program ends without M2 or M30, which the {} refuses: M30 written at its end",
                self.dialect.name
            )));
            self.word_line(Letter::M, 30.0, Origin::default())?;
        }
        self.lines.tape_end(&self.dialect, self.number)
    }
}

/// The G code of the control's work system `n` (1–6: G54–G59).
fn work_system_code(n: u8) -> Code {
    Code::from_tenths(530 + 10 * u32::from(n.clamp(1, 6)))
}
