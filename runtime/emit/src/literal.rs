//! The literal emitter: each executed block's words as programmed (macros expanded, values rounded to
//! the least increment, no geometry resolved), in the dialect's number format.
//!
//! Format rules (default dialect "fanuc"): dimensional addresses always carry a decimal point (`X10.`:
//! on many controls `X10` means 10 µm), integer addresses never; trailing zeros trimmed; never `-0.`;
//! comments only when asked (the O line's program name always); `/` kept on block-delete blocks; `%` and
//! the O number at the ends.

use fmsvm_block::alarms::{MINUS_SIGN, TOO_MANY_DIGITS};
use std::io::Write;

use fmsvm_block::{Alarm, Code, Letter, OutputBudget, Stop};

use crate::dialect::{AddressKind, CommentStyle, Dialect, LineNumbers, NumberFormat, round_away};
use crate::format::{
    Prefix, Text, code_word_text, fixed_word_text, padded_word_text, push_code_word, push_padded,
    push_padded_word, push_word_as,
};
use crate::lines::Lines;
pub use crate::lines::comment_words;
use fmsvm_canon::decode::{DecodeTable, Decoded};
use fmsvm_canon::modal::{self, Group};
use fmsvm_canon::{Context, Emitter, Warning};

/// Output options.
#[derive(Clone, Debug)]
pub struct Options {
    /// Keep comments.
    pub comments: bool,
    /// Renumber blocks: first N and step (over the dialect's own numbering).
    pub renumber: Option<(u32, u32)>,
    /// Modal suppression: words that repeat the modal state are left out (`--compact`).
    pub compact: bool,
    /// The source file's name, for the header comment.
    pub source: String,
    /// How far chords may stray from an arc the dialect cannot write as one (mm).
    pub arc_tolerance: f64,
    /// The bytes the run may write (shared with the printed output).
    pub budget: OutputBudget,
    /// The plain path (`plain_block`) for blocks that may take it; off, every block takes the
    /// general one (the tests compare the two).
    pub plain_path: bool,
    /// The second auxiliary function's address (`InputRules::second_aux`): `--compact` keeps its
    /// codes and forgets what it knew at one (the code may index a table), as at a T.
    pub second_aux: Option<Letter>,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            comments: false,
            renumber: None,
            compact: false,
            source: String::new(),
            arc_tolerance: 0.001,
            budget: OutputBudget::default(),
            plain_path: true,
            second_aux: None,
        }
    }
}

/// Rounds an integer-address value half away from zero and checks its range (V10).
#[inline]
pub fn integer(letter: Letter, value: f64, max: u64) -> Result<u64, Alarm> {
    // Half away from zero without the libm call, where that is exact (0 ≤ value < 2^52).
    if (0.0..4_503_599_627_370_496.0).contains(&value) {
        let t = value as u64;
        let r = t + (value - t as f64 >= 0.5) as u64;
        if r <= max {
            return Ok(r);
        }
    }
    integer_slow(letter, value, max)
}

#[cold]
fn integer_slow(letter: Letter, value: f64, max: u64) -> Result<u64, Alarm> {
    let r = value.round();
    if r < 0.0 {
        return Err(Alarm::new(
            MINUS_SIGN,
            format!("illegal use of minus sign: {letter}{value}"),
        ));
    }
    if r > max as f64 {
        return Err(Alarm::new(
            TOO_MANY_DIGITS,
            format!("too many digits: {letter}{value} (at most {letter}{max})"),
        ));
    }
    Ok(r as u64)
}

/// `--compact`: what the output has said, so that words repeating the modal state can be left out
/// (G codes of the motion, plane, distance, feed-mode and unit groups, F, and axis words of plain
/// G0/G1 moves in G90 that repeat the position). Any other G code, a canned cycle, G91 or an arc
/// forgets the positions: only what is known for certain is dropped.
#[derive(Default)]
struct Compact {
    /// The code in effect in the output, per tracked group: motion, plane, distance, feed mode, units.
    groups: [Option<Code>; TRACKED.len()],
    /// F as last written (least increments).
    feed: Option<i64>,
    /// X Y Z A B C as last written in G90 (least increments).
    at: [Option<i64>; 6],
    /// A canned cycle is in effect (its blocks' words are parameters).
    cycle: bool,
}

/// The modal groups `--compact` follows.
const TRACKED: [Group; 5] = [
    Group::Motion,
    Group::Plane,
    Group::Distance,
    Group::FeedMode,
    Group::Units,
];

/// Where `code`'s group stands in `TRACKED`. G33 (a thread's words are its own) and G93 (an
/// inverse-time F belongs to its block) are never left out, so they are not followed.
fn tracked(code: Code) -> Option<usize> {
    if matches!(code, Code::G33 | Code::G93) {
        return None;
    }
    let group = modal::group(code)?;
    TRACKED.iter().position(|&g| g == group)
}

impl Compact {
    /// Which words of the block to write (bit i: word i), updating the state.
    fn keep(
        &mut self,
        decoded: &Decoded<'_, '_>,
        dialect: &Dialect,
        ctx: &Context,
        second_aux: Option<Letter>,
    ) -> u64 {
        let inch = ctx.inch;
        let mut keep = u64::MAX;
        if decoded.block.block_delete {
            // The control may skip it (the switch is the operator's): nothing of it is known, and
            // nothing after it may lean on it. A cycle code in it leaves the cycle state unknown.
            let cycle_code = decoded.words().any(|(w, v)| {
                w.letter == Letter::G
                    && Code::of(v).and_then(modal::group) == Some(Group::CannedCycle)
            });
            *self = Compact {
                cycle: self.cycle || cycle_code,
                ..Compact::default()
            };
            return keep;
        }
        let mut plain = true;
        // A tool change, a stop or another machine function may move the tool or change modes (a
        // builder's M6 macro, the operator jogging after M0): what the output said is forgotten.
        let mut forget = false;
        for (w, v) in decoded.words() {
            if w.letter == Letter::T
                || Some(w.letter) == second_aux
                || (w.letter == Letter::M
                    && !matches!(
                        Code::of_integer(v),
                        Some(Code::M3 | Code::M4 | Code::M5 | Code::M7 | Code::M8 | Code::M9)
                    ))
            {
                forget = true;
            }
        }
        for (w, v) in decoded.words() {
            if w.letter == Letter::G {
                let code = Code::of(v).unwrap_or_default();
                if code == Code::G80 {
                    self.cycle = false;
                } else if modal::group(code) == Some(Group::CannedCycle) {
                    self.cycle = true;
                }
                if tracked(code).is_none() {
                    plain = false;
                }
            }
        }
        let old = self.groups;
        for (i, (w, v)) in decoded.words().enumerate() {
            if w.letter == Letter::G {
                let code = Code::of(v).unwrap_or_default();
                if let Some(g) = tracked(code) {
                    if old[g] == Some(code) && plain && !self.cycle {
                        keep &= !(1 << i);
                    }
                    if old[g] != Some(code) {
                        // New units: positions and feed are numbers of another unit. A new feed
                        // mode: F means something else.
                        match TRACKED[g] {
                            Group::Units => {
                                self.at = [None; 6];
                                self.feed = None;
                            }
                            Group::FeedMode => self.feed = None,
                            _ => {}
                        }
                    }
                    self.groups[g] = Some(code);
                }
            }
        }
        // The kernel knows the modes in effect (power-on ones too).
        let axes =
            plain && !self.cycle && matches!(ctx.motion, Code::G0 | Code::G1) && ctx.absolute;
        let mut moved = [None; 6];
        for (i, (w, v)) in decoded.words().enumerate() {
            let axis = fmsvm_canon::axis_index(w.letter, second_aux);
            let digits = if w.letter == Letter::F {
                dialect.feed_digits(ctx.per_rev, inch)
            } else {
                dialect.digits(w.letter, inch)
            };
            let q = dialect.least_increments(v, digits);
            if let Some(k) = axis {
                if axes && q.is_some() && self.at[k] == q {
                    keep &= !(1 << i);
                }
                moved[k] = q;
            } else if w.letter == Letter::F {
                if plain && q.is_some() && self.feed == q {
                    keep &= !(1 << i);
                }
                self.feed = q;
            } else if !matches!(
                w.letter,
                Letter::G | Letter::N | Letter::S | Letter::T | Letter::M
            ) && Some(w.letter) != second_aux
            {
                // I J K R P Q L …: not a plain move.
                if axes {
                    keep = u64::MAX;
                }
                self.at = [None; 6];
                return keep;
            }
        }
        if axes {
            for (at, m) in self.at.iter_mut().zip(moved) {
                if m.is_some() {
                    *at = m;
                }
            }
        } else {
            self.at = [None; 6];
        }
        if forget {
            *self = Compact {
                cycle: self.cycle,
                ..Compact::default()
            };
        }
        keep
    }
}

/// Writes blocks as programmed.
pub struct LiteralEmitter<W: Write> {
    lines: Lines<W>,
    dialect: Dialect,
    options: Options,
    /// Renumbered output's block numbers (the option's start and step, else the dialect's).
    numbers: Option<crate::dialect::BlockNumbers>,
    number: Option<u32>,
    compact: Option<Compact>,
    /// Each letter's prefix alone and after the separator (None: longer than a prefix takes).
    prefixes: [[Option<Prefix>; 2]; Letter::COUNT],
    /// The letter's numbers are in Fanuc's format.
    fanuc: [bool; Letter::COUNT],
    /// The letter's decimals in mm (0) and inch (1): `Dialect::digits` once, not per word.
    digits: [[u32; 2]; Letter::COUNT],
    /// How each letter's words are spelled on the plain path (`plain_block`).
    spells: [Spell; Letter::COUNT],
    /// Every word is written as programmed, N included (no `--compact`, no renumbering): the block
    /// may take the plain path.
    plain: bool,
    /// `Dialect::increments_limit`.
    limit: f64,
    /// Each letter's last word on the plain path, at the block's start (0) and after the separator
    /// (1), with the bits of the value it was made from: a word that repeats (N, G, F, X along a
    /// raster's row) costs one store.
    texts: [[(u64, Text); 2]; Letter::COUNT],
    /// The units `texts` were made in.
    texts_inch: bool,
}

/// How a letter's words are spelled on the plain path: worked out once per run from the dialect.
#[derive(Clone, Copy)]
struct Spell {
    /// The word's prefix at the block's start (0) and after the separator (1).
    prefix: [Prefix; 2],
    how: How,
}

#[derive(Clone, Copy)]
enum How {
    /// A number in Fanuc's format: increments per unit and decimals, in mm (0) and inch (1).
    Fanuc { scale: [f64; 2], digits: [u32; 2] },
    /// A G code `width` digits wide.
    Code { width: u8 },
    /// A whole number up to `max`, zero-padded to `width`.
    Integer { max: u64, width: u8 },
    /// Anything else (another number format, a prefix too long): `push_word`.
    General,
}

/// Each letter's `Spell` in `dialect`.
fn spells(dialect: &Dialect) -> [Spell; Letter::COUNT] {
    let prefixes = prefixes(&dialect.separator);
    std::array::from_fn(|i| {
        let l = Letter::ALL[i];
        let [Some(first), Some(after)] = prefixes[i] else {
            return Spell {
                prefix: [Prefix::NONE; 2],
                how: How::General,
            };
        };
        let width = dialect.numbers[i].width;
        let digits = [dialect.digits(l, false), dialect.digits(l, true)];
        Spell {
            prefix: [first, after],
            how: match dialect.kinds[i] {
                AddressKind::GCode => How::Code { width },
                AddressKind::Integer { max } => How::Integer { max, width },
                _ if dialect.numbers[i] == NumberFormat::FANUC
                    && digits.iter().all(|&d| d <= 9) =>
                {
                    How::Fanuc {
                        scale: digits.map(Dialect::increments_per_unit),
                        digits,
                    }
                }
                _ => How::General,
            },
        }
    })
}

/// Each letter's word prefix, alone and after `separator`.
pub(crate) fn prefixes(separator: &str) -> [[Option<Prefix>; 2]; Letter::COUNT] {
    std::array::from_fn(|i| {
        let letter = Letter::ALL[i].as_str().as_bytes();
        let joined = [separator.as_bytes(), letter].concat();
        [Prefix::new(letter), Prefix::new(&joined)]
    })
}

impl<W: Write> LiteralEmitter<W> {
    /// What the run should be told about the output (renumbering that started again).
    pub fn warnings(&self) -> Vec<Warning> {
        self.numbers
            .as_ref()
            .and_then(|n| n.warning(&self.dialect.name))
            .map(Warning::program)
            .into_iter()
            .chain(self.lines.comment_warnings(&self.dialect.name))
            .collect()
    }

    /// An emitter writing to `out`.
    pub fn new(out: W, dialect: Dialect, options: Options) -> Self {
        let numbers = dialect.block_numbers(options.renumber);
        LiteralEmitter {
            lines: Lines::new(out, &dialect.eol, dialect.max_block, options.budget.clone()),
            compact: options.compact.then(Compact::default),
            prefixes: prefixes(&dialect.separator),
            fanuc: dialect.fanuc_formats(),
            digits: std::array::from_fn(|i| {
                let l = Letter::ALL[i];
                [dialect.digits(l, false), dialect.digits(l, true)]
            }),
            spells: spells(&dialect),
            plain: options.plain_path
                && !options.compact
                && numbers.is_none()
                && dialect.line_numbers != LineNumbers::Off,
            numbers,
            limit: dialect.increments_limit(),
            texts: [[(0, Text::default()); 2]; Letter::COUNT],
            texts_inch: false,
            dialect,
            options,
            number: None,
        }
    }

    /// Writes the word (after the separator unless `first`).
    #[inline(always)]
    /// `letter` with the whole number `raw` as the program wrote it (a lathe cycle's P and Q).
    fn push_whole(&mut self, letter: Letter, raw: f64, first: bool) -> Result<(), Alarm> {
        if !first {
            self.lines
                .buf
                .extend_from_slice(self.dialect.separator.as_bytes());
        }
        self.lines.buf.extend_from_slice(letter.as_str().as_bytes());
        let whole = integer(letter, raw, 99_999_999)?;
        push_padded_word(&mut self.lines.buf, Prefix::NONE, whole, 0);
        Ok(())
    }

    /// The separator (unless `first`) and `letter` before a word: written here, or as the prefix
    /// of the number's store.
    fn word_prefix(&mut self, letter: Letter, first: bool) -> Prefix {
        if let Some(p) = self.prefixes[letter.index()][!first as usize] {
            return p;
        }
        if !first {
            self.lines
                .buf
                .extend_from_slice(self.dialect.separator.as_bytes());
        }
        self.lines.buf.extend_from_slice(letter.as_str().as_bytes());
        Prefix::NONE
    }

    fn push_word(&mut self, letter: Letter, v: f64, inch: bool, first: bool) -> Result<(), Alarm> {
        let i = letter.index();
        match self.dialect.kinds[i] {
            // The kernel checked the code against the G-code table before the block came here.
            AddressKind::GCode => {
                let prefix = self.word_prefix(letter, first);
                let width = self.dialect.numbers[i].width;
                push_code_word(
                    &mut self.lines.buf,
                    prefix,
                    Code::of(v).unwrap_or_default(),
                    width,
                );
            }
            AddressKind::Integer { max } => {
                let whole = integer(letter, v, max)?;
                let prefix = self.word_prefix(letter, first);
                let width = self.dialect.numbers[i].width;
                push_padded_word(&mut self.lines.buf, prefix, whole, width);
            }
            AddressKind::Linear | AddressKind::Angular | AddressKind::Feed => {
                let digits = self.digits[i][inch as usize];
                return self.push_number(letter, v, digits, first);
            }
        }
        Ok(())
    }

    /// A number word of `letter` with `digits` decimals (a length, an angle, a feed).
    fn push_number(
        &mut self,
        letter: Letter,
        v: f64,
        digits: u32,
        first: bool,
    ) -> Result<(), Alarm> {
        let i = letter.index();
        let Some(q) = self.dialect.least_increments(v, digits) else {
            return Err(Alarm::new(
                TOO_MANY_DIGITS,
                format!(
                    "too many digits: {}{v} does not fit {} digit{}",
                    letter,
                    self.dialect.max_digits,
                    if self.dialect.max_digits == 1 {
                        ""
                    } else {
                        "s"
                    }
                ),
            ));
        };
        let prefix = self.word_prefix(letter, first);
        let (fanuc, format) = (self.fanuc[i], &self.dialect.numbers[i]);
        push_word_as(&mut self.lines.buf, prefix, q, digits, fanuc, format);
        Ok(())
    }
}

impl<W: Write> LiteralEmitter<W> {
    /// A block whose every word is written, with no comment: `block` in fewer steps, each letter's
    /// spelling looked up once.
    #[inline]
    fn plain_block(&mut self, decoded: &Decoded<'_, '_>, ctx: &Context) -> Result<(), Stop> {
        let (words, values) = (decoded.block.words(), decoded.values());
        self.plain_words(
            words.len().min(values.len()),
            |i| words[i].letter,
            |i| values[i],
            decoded.block.block_delete,
            ctx.inch,
        )
    }

    /// A plain block whose `n` words are `letter(i)`, `value(i)` (decoded): `plain_block`'s body,
    /// shared with the pipelined emitter's writer thread, which has the words but not the block.
    #[inline(always)]
    fn plain_words(
        &mut self,
        n: usize,
        letter: impl Fn(usize) -> Letter,
        value: impl Fn(usize) -> f64,
        block_delete: bool,
        inch: bool,
    ) -> Result<(), Stop> {
        if block_delete && self.dialect.block_delete {
            self.lines.buf.push(b'/');
        }
        let unit = inch as usize;
        if inch != self.texts_inch {
            self.texts = [[(0, Text::default()); 2]; Letter::COUNT];
            self.texts_inch = inch;
        }
        // 0 for the block's first word, then 1 (the prefix with the separator).
        let mut after = 0;
        let mut any = false;
        for i in 0..n {
            let (l, v) = (letter(i), value(i));
            any |= l != Letter::N;
            let bits = v.to_bits();
            let (seen, text) = self.texts[l.index()][after];
            if seen == bits && !text.is_empty() {
                text.push(&mut self.lines.buf);
                after = 1;
                continue;
            }
            let spell = &self.spells[l.index()];
            let prefix = spell.prefix[after];
            // Ok(None): the general word (another format, or a value the fast path does not take).
            let fast = match spell.how {
                How::Fanuc { scale, digits } => {
                    let q = v * scale[unit];
                    // `Dialect::least_increments` (a NaN is not below the limit either).
                    Ok(if q.abs() < self.limit {
                        fixed_word_text(prefix, round_away(q), digits[unit])
                    } else {
                        None
                    })
                }
                How::Code { width } => Ok(code_word_text(
                    prefix,
                    Code::of(v).unwrap_or_default(),
                    width,
                )),
                How::Integer { max, width } => {
                    integer(l, v, max).map(|n| padded_word_text(prefix, n, width))
                }
                How::General => Ok(None),
            };
            let done = match fast {
                Ok(Some(text)) => {
                    text.push(&mut self.lines.buf);
                    self.texts[l.index()][after] = (bits, text);
                    Ok(())
                }
                Ok(None) => self.push_word(l, v, inch, after == 0),
                Err(e) => Err(e),
            };
            if let Err(e) = done {
                // Nothing of a block that fails reaches the output.
                self.lines.cancel_line();
                return Err(e.into());
            }
            after = 1;
        }
        if !any {
            // A block of only N (or nothing) writes nothing, as in `block`.
            self.lines.cancel_line();
            return Ok(());
        }
        self.lines.end_line()
    }
}

/// What the run's thread checks, for the pipelined emitter, to know that a block takes
/// `plain_block` and that nothing in it can fail there: each letter's values that format without an
/// alarm, and the most bytes such a word takes.
#[derive(Clone)]
pub struct Offload {
    /// `Options::comments`: a block with a comment does not take the plain path then.
    pub(crate) comments: bool,
    /// Per units (mm, inch): every value the kernel's decoding lets through formats without an
    /// alarm, whatever its letter (the usual case: the dialect's digits are the language's), so
    /// no word needs a look.
    pub(crate) all_safe: [bool; 2],
    /// Per units and letter: the lowest value that formats without an alarm.
    pub(crate) lo: [[f64; Letter::COUNT]; 2],
    /// Per units and letter: the values below this (and from `lo`) format without an alarm.
    pub(crate) hi: [[f64; Letter::COUNT]; 2],
    /// Per units and letter: the most bytes of a word, the separator included.
    pub(crate) len: [[u8; Letter::COUNT]; 2],
    /// The most bytes of any word.
    pub(crate) longest: u32,
    /// The bytes a line may take besides its words: `/` and the line end.
    pub(crate) fixed: u32,
    /// Most bytes of a line, its end included (`Dialect::max_block`).
    pub(crate) max_line: u32,
}

impl Offload {
    /// The most bytes the block's line takes, when every word is in its safe range and the line
    /// fits the dialect's length; None otherwise (and for a block that does not take the plain path).
    #[inline(always)]
    pub fn bound(&self, decoded: &Decoded<'_, '_>, inch: bool) -> Option<u32> {
        let block = decoded.block;
        if self.comments && !block.comment.is_empty() {
            return None;
        }
        let unit = inch as usize;
        let words = block.words();
        // An NCT incremental word was made absolute after decoding (`XI0.2` from X99999.9): its
        // value was never checked against the limits, so it takes the look.
        let rewritten = block.any_flags().has(fmsvm_block::WordFlags::INCREMENTAL);
        let len = if self.all_safe[unit] && !rewritten {
            self.fixed + words.len() as u32 * self.longest
        } else {
            let (lo, hi, lens) = (&self.lo[unit], &self.hi[unit], &self.len[unit]);
            let mut ok = true;
            let mut len = self.fixed;
            for (w, &v) in words.iter().zip(decoded.values()) {
                let i = w.letter.index();
                ok &= v >= lo[i] && v < hi[i];
                len += lens[i] as u32;
            }
            if !ok {
                return None;
            }
            len
        };
        (len <= self.max_line).then_some(len)
    }
}

impl<W: Write> LiteralEmitter<W> {
    /// The byte budget the lines are spent from.
    pub(crate) fn budget(&self) -> &OutputBudget {
        &self.options.budget
    }

    /// The checks that let the pipelined emitter hand blocks to a writer thread, or None when no
    /// block takes the plain path (`--compact`, renumbering).
    pub(crate) fn offload(&self, decode: &DecodeTable) -> Option<Offload> {
        if !self.plain {
            return None;
        }
        let d = &self.dialect;
        let mut offload = Offload {
            comments: self.options.comments,
            all_safe: [true; 2],
            lo: [[0.0; Letter::COUNT]; 2],
            hi: [[0.0; Letter::COUNT]; 2],
            len: [[0; Letter::COUNT]; 2],
            longest: 0,
            fixed: (1 + d.eol.len()) as u32,
            max_line: d
                .max_block
                .map_or(u32::MAX, |m| m.min(u32::MAX as usize) as u32),
        };
        for (unit, inch) in [false, true].into_iter().enumerate() {
            for (i, &l) in Letter::ALL.iter().enumerate() {
                // The separator and the letter, written by hand when longer than a prefix.
                let prefix = (d.separator.len() + l.as_str().len()) as u32;
                let width = d.numbers[i].width as u32;
                let digits = d.digits(l, inch);
                let (lo, hi, len) = match d.kinds[i] {
                    // Any value: the kernel checked the code; `Code::of` of anything is a code.
                    AddressKind::GCode => (f64::NEG_INFINITY, f64::INFINITY, prefix + 6 + width),
                    // `integer`: rounds half away from zero, refuses what passes `max`.
                    AddressKind::Integer { max } => (
                        f64::from_bits((-0.5f64).to_bits() - 1),
                        max as f64 + 0.5,
                        prefix + (max.max(1).ilog10() + 1).max(width),
                    ),
                    // `least_increments`: |v × 10^digits| below the limit; a margin of 2^-40
                    // covers the product's rounding. Sign, digits, padding, point, and a leading 0.
                    AddressKind::Linear | AddressKind::Angular | AddressKind::Feed => {
                        let hi = d.increments_limit() / Dialect::increments_per_unit(digits)
                            * (1.0 - 2f64.powi(-40));
                        (-hi, hi, prefix + 3 + d.max_digits + width + digits)
                    }
                };
                offload.lo[unit][i] = lo;
                offload.hi[unit][i] = hi;
                // A word that long sends its block to the run's thread (`max_line` of 0).
                offload.len[unit][i] = len.min(255) as u8;
                offload.longest = offload.longest.max(len);
                if len > 255 {
                    offload.max_line = 0;
                }
                // What decoding lets through, an open interval: its extremes pass the emitter's
                // own test (which is monotone on each side of 0), or this letter needs a look.
                let (low, high) = decode.bounds(l, inch);
                let accepts = |v: f64| match d.kinds[i] {
                    AddressKind::GCode => true,
                    AddressKind::Integer { max } => v.is_finite() && integer(l, v, max).is_ok(),
                    _ => d.least_increments(v, digits).is_some(),
                };
                if !(accepts(low.next_up()) && accepts(high.next_down())) {
                    offload.all_safe[unit] = false;
                }
            }
        }
        Some(offload)
    }

    /// `plain_block` of words handed over by the pipelined emitter (`letters[i]`, `values[i]`).
    #[inline]
    pub(crate) fn plain_handed(
        &mut self,
        letters: &[Letter],
        values: &[f64],
        block_delete: bool,
        inch: bool,
    ) -> Result<(), Stop> {
        let n = letters.len().min(values.len());
        self.plain_words(n, |i| letters[i], |i| values[i], block_delete, inch)
    }
}

impl<W: Write> Emitter for LiteralEmitter<W> {
    const CANON: bool = false;

    fn begin(&mut self, number: Option<u32>, title: &str) -> Result<(), Stop> {
        self.number = number;
        self.lines
            .tape_start(&self.dialect, number, title, &self.options.source)
    }

    fn block(&mut self, decoded: &Decoded<'_, '_>, ctx: &Context) -> Result<(), Stop> {
        let block = decoded.block;
        if self.plain
            && !ctx.pq_integers
            && !ctx.per_rev
            && (block.comment.is_empty() || !self.options.comments)
        {
            return self.plain_block(decoded, ctx);
        }
        let keep = match &mut self.compact {
            Some(c) => c.keep(decoded, &self.dialect, ctx, self.options.second_aux),
            None => u64::MAX,
        };
        let has_words = block
            .words()
            .iter()
            .enumerate()
            .any(|(i, w)| w.letter != Letter::N && keep & (1 << i) != 0);
        let wanted = self.options.comments && !block.comment.is_empty();
        let comment = wanted && self.dialect.comments != CommentStyle::None;
        if wanted && !comment {
            self.lines.leave_out_comment();
        }
        if !has_words && !comment {
            return Ok(());
        }
        if block.block_delete && self.dialect.block_delete {
            self.lines.buf.push(b'/');
        }
        let mut first = true;
        if has_words && let Some(numbers) = &mut self.numbers {
            let n = numbers.take();
            self.lines.buf.push(b'N');
            push_padded(&mut self.lines.buf, n as u64, self.dialect.number_width);
            first = false;
        }
        let drop_n = self.numbers.is_some() || self.dialect.line_numbers == LineNumbers::Off;
        for (i, (w, v)) in decoded.words().enumerate() {
            if (w.letter == Letter::N && drop_n) || keep & (1 << i) == 0 {
                continue;
            }
            let at_start = first;
            first = false;
            let pushed = if ctx.pq_integers && matches!(w.letter, Letter::P | Letter::Q) {
                self.push_whole(w.letter, w.value, at_start)
            } else if w.letter == Letter::F && ctx.per_rev {
                let digits = self.dialect.feed_digits(true, ctx.inch);
                self.push_number(w.letter, v, digits, at_start)
            } else {
                self.push_word(w.letter, v, ctx.inch, at_start)
            };
            if let Err(e) = pushed {
                // Nothing of a block that fails reaches the output.
                self.lines.cancel_line();
                return Err(e.into());
            }
        }
        if comment {
            if !first {
                self.lines.buf.push(b' ');
            }
            self.lines.push_block_comments(
                self.dialect.comments,
                &self.dialect.active_comments,
                block.comment,
            );
        }
        self.lines.end_line()
    }

    fn message(&mut self, number: u32, text: &str) -> Result<(), Stop> {
        self.lines.message(&self.dialect, number, text)
    }

    fn written(&self) -> u64 {
        self.lines.written()
    }

    fn end(&mut self) -> Result<(), Stop> {
        self.lines.tape_end(&self.dialect, self.number)
    }
}
