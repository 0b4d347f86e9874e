//! The boundary between the macro VM and the geometry kernel: a [`Block`] of address words, the
//! [`Machine`] that executes blocks, and the [`Stop`] reasons a run can end with.
//!
//! This crate is the one type both sides of the pipeline share (ripgrep's `grep-matcher` pattern): the VM
//! produces Blocks and calls a `Machine`; the runtime implements `Machine`. It depends on std only, and a
//! `Block` never allocates.
//!
//! Values are `f64` everywhere. A **vacant** value (Fanuc `#0`, "null") is any NaN: the VM guarantees that
//! every non-vacant value it stores is finite (arithmetic that would give NaN or infinity raises an alarm),
//! so NaN is free to mean vacant, in the interpreter and in JIT code alike (`x != x`).
#![deny(missing_docs)]
#![forbid(unsafe_code)]

pub mod alarms;
mod code;
pub use code::{AXES_ARE_DATA, Code};

use std::borrow::Cow;
use std::fmt;

/// The vacant value (`#0`). Test with [`is_vacant`], never with `==`.
pub const VACANT: f64 = f64::NAN;

/// True when `v` is vacant (macro-b-rules V1).
#[inline(always)]
pub fn is_vacant(v: f64) -> bool {
    v.is_nan()
}

/// An address letter of an NC word. `A`..`Z` are the plain addresses; `CommaA`, `CommaC`, `CommaR` are the
/// comma words of corner chamfering/rounding (`,C2.`, `,R5.`) and angle (`,A30.`).
#[allow(missing_docs)]
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug)]
#[repr(u8)]
pub enum Letter {
    A,
    B,
    C,
    D,
    E,
    F,
    G,
    H,
    I,
    J,
    K,
    L,
    M,
    N,
    O,
    P,
    Q,
    R,
    S,
    T,
    U,
    V,
    W,
    X,
    Y,
    Z,
    CommaA,
    CommaC,
    CommaR,
}

/// What the value of an address is in the language (Fanuc Custom Macro B), the same on every control;
/// how many digits each takes is the output dialect's business.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum AddressClass {
    /// G: a code with at most one decimal (`G54.1`).
    GCode,
    /// D H L M N O P S T: a whole number (a literal point is 0007, a sign on N O M G is 0006; V10, E8).
    Integer,
    /// X Y Z I J K Q R U V W E and `,C` `,R`: a length.
    Linear,
    /// A B C and `,A`: an angle.
    Angular,
    /// F: a feed.
    Feed,
}

impl Letter {
    /// The class of the address (the one definition of which addresses are integers).
    pub const fn class(self) -> AddressClass {
        match self {
            Letter::G => AddressClass::GCode,
            Letter::D
            | Letter::H
            | Letter::L
            | Letter::M
            | Letter::N
            | Letter::O
            | Letter::P
            | Letter::S
            | Letter::T => AddressClass::Integer,
            Letter::A | Letter::B | Letter::C | Letter::CommaA => AddressClass::Angular,
            Letter::F => AddressClass::Feed,
            _ => AddressClass::Linear,
        }
    }

    /// Number of letters (the size of a per-letter table).
    pub const COUNT: usize = 29;

    /// Every letter in table order.
    pub const ALL: [Letter; Letter::COUNT] = {
        let mut all = [Letter::A; Letter::COUNT];
        let mut i = 0;
        while i < Letter::COUNT {
            all[i] = match Letter::from_index(i as u8) {
                Some(l) => l,
                None => Letter::A,
            };
            i += 1;
        }
        all
    };

    /// The letter for an upper- or lower-case ASCII letter.
    pub const fn from_ascii(c: u8) -> Option<Letter> {
        let u = c.to_ascii_uppercase();
        if u.is_ascii_uppercase() {
            Letter::from_index(u - b'A')
        } else {
            None
        }
    }

    /// The comma word for a letter (`,A` `,C` `,R`), if there is one.
    pub const fn comma(c: u8) -> Option<Letter> {
        match c.to_ascii_uppercase() {
            b'A' => Some(Letter::CommaA),
            b'C' => Some(Letter::CommaC),
            b'R' => Some(Letter::CommaR),
            _ => None,
        }
    }

    /// The letter with table index `i`.
    pub const fn from_index(i: u8) -> Option<Letter> {
        if (i as usize) < Letter::COUNT {
            // SAFETY-free: repr(u8) enum with contiguous discriminants 0..COUNT; checked above.
            Some(match i {
                0 => Letter::A,
                1 => Letter::B,
                2 => Letter::C,
                3 => Letter::D,
                4 => Letter::E,
                5 => Letter::F,
                6 => Letter::G,
                7 => Letter::H,
                8 => Letter::I,
                9 => Letter::J,
                10 => Letter::K,
                11 => Letter::L,
                12 => Letter::M,
                13 => Letter::N,
                14 => Letter::O,
                15 => Letter::P,
                16 => Letter::Q,
                17 => Letter::R,
                18 => Letter::S,
                19 => Letter::T,
                20 => Letter::U,
                21 => Letter::V,
                22 => Letter::W,
                23 => Letter::X,
                24 => Letter::Y,
                25 => Letter::Z,
                26 => Letter::CommaA,
                27 => Letter::CommaC,
                _ => Letter::CommaR,
            })
        } else {
            None
        }
    }

    /// Table index of the letter (0 = A).
    #[inline(always)]
    pub const fn index(self) -> usize {
        self as usize
    }

    /// The letter as written in a program (`X`, `,R`).
    pub const fn as_str(self) -> &'static str {
        const NAMES: [&str; Letter::COUNT] = [
            "A", "B", "C", "D", "E", "F", "G", "H", "I", "J", "K", "L", "M", "N", "O", "P", "Q",
            "R", "S", "T", "U", "V", "W", "X", "Y", "Z", ",A", ",C", ",R",
        ];
        NAMES[self as usize]
    }
}

impl fmt::Display for Letter {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Flags of a word, set by the compiler from how the word was written.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct WordFlags(pub u8);

impl WordFlags {
    /// The value is a literal written without a decimal point (`X10`, not `X10.` nor `X#1`): under
    /// decimal-point input type I it counts least increments (macro-b-rules V11).
    pub const NO_POINT: u8 = 1;
    /// NCT incremental operator (`XI10`): this address is incremental in this block only.
    pub const INCREMENTAL: u8 = 2;

    /// True when `flag` is set.
    #[inline(always)]
    pub fn has(self, flag: u8) -> bool {
        self.0 & flag != 0
    }
}

/// One address word of an evaluated block: a letter and its value (never vacant: a vacant word is
/// dropped before it reaches a block, macro-b-rules V6).
#[derive(Clone, Copy, PartialEq, Debug)]
pub struct Word {
    /// The address.
    pub letter: Letter,
    /// How the word was written.
    pub flags: WordFlags,
    /// The value as evaluated, not yet rounded to the address's unit.
    pub value: f64,
}

/// The most words one block can carry. The compiler rejects blocks with more.
pub const MAX_WORDS: usize = 48;

/// One executed NC block: its words in programmed order (several G and M codes allowed), with where it
/// came from. Built by the VM in place and handed to [`Machine::block`]; never allocates.
#[derive(Clone, Debug)]
pub struct Block<'p> {
    words: [Word; MAX_WORDS],
    len: usize,
    /// Every word's flags or'ed together.
    flags: u8,
    /// Source line (1-based) of the block, for messages.
    pub line: u32,
    /// The source file of the block (its id in the run's source map; 0 the program's own file).
    pub file: u16,
    /// Column (1-based, in characters) of the block's first word.
    pub column: u16,
    /// The block began with `/` (block delete) and the switch was off, so it runs.
    pub block_delete: bool,
    /// The block's comments, joined, or "" when it has none.
    pub comment: &'p str,
}

impl Default for Block<'_> {
    fn default() -> Self {
        Block::new()
    }
}

impl<'p> Block<'p> {
    /// An empty block.
    pub const fn new() -> Self {
        Block {
            words: [Word {
                letter: Letter::A,
                flags: WordFlags(0),
                value: 0.0,
            }; MAX_WORDS],
            len: 0,
            flags: 0,
            line: 0,
            file: 0,
            column: 0,
            block_delete: false,
            comment: "",
        }
    }

    /// Appends a word. Returns false (and drops the word) when the block is full; the compiler
    /// guarantees that never happens for a compiled program.
    #[inline(always)]
    pub fn push(&mut self, word: Word) -> bool {
        if self.len < MAX_WORDS {
            self.words[self.len] = word;
            self.len += 1;
            self.flags |= word.flags.0;
            true
        } else {
            false
        }
    }

    /// Removes all words and resets the source information.
    #[inline(always)]
    pub fn clear(&mut self) {
        self.len = 0;
        self.flags = 0;
        self.block_delete = false;
        self.comment = "";
    }

    /// The flags of all its words or'ed together (`WordFlags` bits): whether any word has one.
    #[inline(always)]
    pub fn any_flags(&self) -> WordFlags {
        WordFlags(self.flags)
    }

    /// The words in programmed order.
    #[inline(always)]
    pub fn words(&self) -> &[Word] {
        &self.words[..self.len]
    }

    /// Every word slot, the block's words first (those past them are left from earlier blocks).
    #[inline(always)]
    pub fn word_slots(&self) -> &[Word; MAX_WORDS] {
        &self.words
    }

    /// The first word with `letter`, if any.
    pub fn get(&self, letter: Letter) -> Option<f64> {
        self.words()
            .iter()
            .find(|w| w.letter == letter)
            .map(|w| w.value)
    }

    /// True when the block has no words.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
}

/// What the VM does after a block ran.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Flow {
    /// Go on with the next statement.
    Continue,
    /// Go on; the block commanded axis motion (a G66 modal call runs after it, macro-b-rules C12).
    Moved,
    /// The block ended the program (M02, M30).
    End,
}

/// A Fanuc-style alarm: the control stops with a number and a message.
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct Alarm {
    /// Alarm number as the control shows it (112 = zero divide; 3000+n for `#3000=n`).
    pub number: u32,
    /// What happened, in words, with the values involved.
    pub message: Cow<'static, str>,
}

impl Alarm {
    /// An alarm with a number and message.
    pub fn new(number: u32, message: impl Into<Cow<'static, str>>) -> Self {
        Alarm {
            number,
            message: message.into(),
        }
    }
}

impl fmt::Display for Alarm {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "alarm {:04}: {}", self.number, self.message)
    }
}

/// Which configured limit a run reached.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum LimitKind {
    /// Branches taken (loop iterations and jumps).
    Steps,
    /// NC blocks written.
    Blocks,
    /// Bytes of output written (the flat program and the printed output together).
    OutputBytes,
    /// Bytes of printed output (DPRNT/BPRNT) written.
    PrintBytes,
    /// Nested calls.
    CallDepth,
    /// Wall-clock seconds.
    WallTime,
}

/// What a run may still write across its outputs: bytes (`--max-bytes`), blocks of the flat program
/// (`--max-blocks`) and wall time (`--max-seconds`), looked at as each line is made, so that one
/// block that becomes many lines (a canned cycle, an arc in chords) is bounded too. The emitter and
/// the DPRNT port share the bytes, so printing counts as much as the program; blocks are the
/// emitter's lines. Cloning shares it; the default has no limit. One thread spends at a time (the
/// pipelined emitter's writer thread spends only while the run's thread cannot: a program that
/// prints is not pipelined), so a spend is a plain load and store, not a locked read-modify-write.
#[derive(Clone, Debug, Default)]
pub struct OutputBudget(Option<std::sync::Arc<Spent>>);

/// The shared state of an [`OutputBudget`].
#[derive(Debug)]
struct Spent {
    bytes: std::sync::atomic::AtomicU64,
    max_bytes: u64,
    lines: std::sync::atomic::AtomicU64,
    max_lines: u64,
    deadline: Option<(std::time::Instant, u64)>,
}

/// How many lines go by between two looks at the clock.
const LINES_PER_LOOK: u64 = 4096;

impl OutputBudget {
    /// A budget of `limit` bytes; 0 = no limit.
    pub fn new(limit: u64) -> Self {
        Self::with_limits(limit, 0, None)
    }

    /// A budget of `max_bytes` bytes and `max_lines` lines (0 = no limit), and the wall time left
    /// from now.
    pub fn with_limits(
        max_bytes: u64,
        max_lines: u64,
        max_time: Option<std::time::Duration>,
    ) -> Self {
        if max_bytes == 0 && max_lines == 0 && max_time.is_none() {
            return OutputBudget(None);
        }
        let deadline = max_time.map(|t| {
            (
                std::time::Instant::now() + t,
                u64::try_from(t.as_millis()).unwrap_or(u64::MAX),
            )
        });
        OutputBudget(Some(std::sync::Arc::new(Spent {
            bytes: std::sync::atomic::AtomicU64::new(0),
            max_bytes: if max_bytes == 0 { u64::MAX } else { max_bytes },
            lines: std::sync::atomic::AtomicU64::new(0),
            max_lines: if max_lines == 0 { u64::MAX } else { max_lines },
            deadline,
        })))
    }

    /// Spends `n` bytes, or says the limit would be passed (nothing is spent then).
    #[inline]
    pub fn spend(&self, n: u64) -> Result<(), Stop> {
        use std::sync::atomic::Ordering::Relaxed;
        if let Some(b) = &self.0 {
            let used = b.bytes.load(Relaxed) + n;
            if used > b.max_bytes {
                return Err(Stop::Limit {
                    kind: LimitKind::OutputBytes,
                    limit: b.max_bytes,
                });
            }
            b.bytes.store(used, Relaxed);
        }
        Ok(())
    }

    /// Spends one block of `n` bytes: the block limit, the byte limit and (every
    /// [`LINES_PER_LOOK`] lines) the clock, or says which would be passed (nothing is spent then).
    #[inline]
    pub fn spend_line(&self, n: u64) -> Result<(), Stop> {
        use std::sync::atomic::Ordering::Relaxed;
        if let Some(b) = &self.0 {
            let lines = b.lines.load(Relaxed);
            if lines >= b.max_lines {
                return Err(Stop::Limit {
                    kind: LimitKind::Blocks,
                    limit: b.max_lines,
                });
            }
            if lines % LINES_PER_LOOK == LINES_PER_LOOK - 1
                && let Some((deadline, ms)) = b.deadline
                && std::time::Instant::now() >= deadline
            {
                return Err(Stop::Limit {
                    kind: LimitKind::WallTime,
                    limit: ms,
                });
            }
            self.spend(n)?;
            b.lines.store(lines + 1, Relaxed);
        }
        Ok(())
    }

    /// The wall-time limit, looked at now: for work that makes no line for a long time (a cycle's
    /// passes worked out before the first is written).
    pub fn clock(&self) -> Result<(), Stop> {
        if let Some(b) = &self.0
            && let Some((deadline, ms)) = b.deadline
            && std::time::Instant::now() >= deadline
        {
            return Err(Stop::Limit {
                kind: LimitKind::WallTime,
                limit: ms,
            });
        }
        Ok(())
    }

    /// The byte limit, or None when there is none.
    pub fn limit(&self) -> Option<u64> {
        self.0
            .as_ref()
            .map(|b| b.max_bytes)
            .filter(|&m| m != u64::MAX)
    }

    /// The block (line) limit, or None when there is none.
    pub fn line_limit(&self) -> Option<u64> {
        self.0
            .as_ref()
            .map(|b| b.max_lines)
            .filter(|&m| m != u64::MAX)
    }

    /// The blocks (lines) spent so far.
    pub fn lines(&self) -> u64 {
        self.0
            .as_ref()
            .map_or(0, |b| b.lines.load(std::sync::atomic::Ordering::Relaxed))
    }

    /// The bytes spent so far.
    pub fn used(&self) -> u64 {
        self.0
            .as_ref()
            .map_or(0, |b| b.bytes.load(std::sync::atomic::Ordering::Relaxed))
    }
}

/// Why a run stopped before its end.
#[derive(Debug)]
pub enum Stop {
    /// The program raised an alarm (a real control would have stopped too).
    Alarm(Alarm),
    /// A configured limit was reached (a runaway loop, an output bigger than allowed).
    Limit {
        /// Which limit.
        kind: LimitKind,
        /// Its value.
        limit: u64,
    },
    /// Writing the output failed.
    Io(std::io::Error),
}

impl std::error::Error for Alarm {}

impl std::error::Error for Stop {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Stop::Alarm(a) => Some(a),
            Stop::Io(e) => Some(e),
            Stop::Limit { .. } => None,
        }
    }
}

impl From<Alarm> for Stop {
    fn from(a: Alarm) -> Self {
        Stop::Alarm(a)
    }
}

impl From<std::io::Error> for Stop {
    fn from(e: std::io::Error) -> Self {
        Stop::Io(e)
    }
}

impl fmt::Display for Stop {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Stop::Alarm(a) => a.fmt(f),
            Stop::Limit {
                kind: LimitKind::WallTime,
                limit,
            } => {
                let seconds = *limit as f64 / 1000.0;
                let noun = if seconds == 1.0 { "second" } else { "seconds" };
                write!(f, "limit of {seconds} {noun} of wall time reached")
            }
            Stop::Limit { kind, limit } => {
                let (one, many) = match kind {
                    LimitKind::Steps => ("step (branch taken)", "steps (branches taken)"),
                    LimitKind::Blocks => ("output block", "output blocks"),
                    LimitKind::OutputBytes => ("output byte", "output bytes"),
                    LimitKind::PrintBytes => {
                        ("printed byte (DPRNT/BPRNT)", "printed bytes (DPRNT/BPRNT)")
                    }
                    LimitKind::CallDepth => ("call level", "call levels"),
                    LimitKind::WallTime => ("second of wall time", "seconds of wall time"),
                };
                let what = if *limit == 1 { one } else { many };
                write!(f, "limit of {limit} {what} reached")
            }
            Stop::Io(e) => write!(f, "output error: {e}"),
        }
    }
}

/// The machine a program runs on: it executes NC blocks and answers system variables. The runtime's
/// kernel implements it; the VM drives it.
pub trait Machine {
    /// Executes one NC block (its words evaluated, vacant words already dropped).
    fn block(&mut self, block: &Block<'_>) -> Result<Flow, Stop>;

    /// Reads system variable `number` (#1000 and up); unknown numbers are alarm 115.
    fn read_system(&mut self, number: u32) -> Result<f64, Stop>;

    /// Writes system variable `number`; read-only ones are alarm 116, unknown ones 115.
    fn write_system(&mut self, number: u32, value: f64) -> Result<(), Stop>;

    /// The least increment of `letter` in the current units, for `ROUND` inside an address
    /// (macro-b-rules E3): 0.001 for mm, 0.0001 for inch, 1 for integer addresses.
    fn increment(&self, letter: Letter) -> f64;

    /// The value a G65/G66 argument word stands for: a literal without a decimal point may count
    /// least increments (macro-b-rules C5, V11). The default takes the value as written.
    fn argument(&self, word: &Word) -> f64 {
        word.value
    }

    /// `#3006 = n (MSG)`: the control stops with a message until cycle start. The default ignores it.
    fn message(&mut self, number: u32, text: &str) -> Result<(), Stop> {
        let _ = (number, text);
        Ok(())
    }
}

/// Powers of ten exact in an f64.
const POW10: [f64; 16] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
];

/// The decimal number `mant / 10^frac` written with `digits` significant digits, when that is one
/// correctly rounded division (both operands exact in an f64: at most 15 digits and 15 decimals), and
/// so bit-identical to `str::parse` of its text; None for a longer number (parse its text). The
/// compiler's lexer, the flat path and the read-back convert their numbers with it.
#[inline]
pub fn exact_decimal(mant: u64, digits: u32, frac: u32) -> Option<f64> {
    (digits <= 15 && frac <= 15).then(|| mant as f64 / POW10[frac as usize])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_say_one_in_the_singular() {
        let limit = |kind, limit| Stop::Limit { kind, limit }.to_string();
        assert_eq!(
            limit(LimitKind::WallTime, 1000),
            "limit of 1 second of wall time reached"
        );
        assert_eq!(
            limit(LimitKind::WallTime, 200),
            "limit of 0.2 seconds of wall time reached"
        );
        assert_eq!(
            limit(LimitKind::Steps, 1),
            "limit of 1 step (branch taken) reached"
        );
        assert_eq!(
            limit(LimitKind::Blocks, 2),
            "limit of 2 output blocks reached"
        );
        assert_eq!(
            limit(LimitKind::OutputBytes, 1),
            "limit of 1 output byte reached"
        );
        assert_eq!(
            limit(LimitKind::CallDepth, 1),
            "limit of 1 call level reached"
        );
    }

    #[test]
    fn letters_round_trip() {
        for (i, l) in Letter::ALL.iter().enumerate() {
            assert_eq!(l.index(), i);
            assert_eq!(Letter::from_index(i as u8), Some(*l));
        }
        assert_eq!(Letter::from_ascii(b'x'), Some(Letter::X));
        assert_eq!(Letter::from_ascii(b'1'), None);
        assert_eq!(Letter::CommaR.as_str(), ",R");
    }

    #[test]
    fn block_push_and_clear() {
        let mut b = Block::new();
        assert!(b.push(Word {
            letter: Letter::X,
            flags: WordFlags(0),
            value: 1.0
        }));
        assert_eq!(b.get(Letter::X), Some(1.0));
        b.clear();
        assert!(b.is_empty());
        for _ in 0..MAX_WORDS {
            assert!(b.push(Word {
                letter: Letter::G,
                flags: WordFlags(0),
                value: 1.0
            }));
        }
        assert!(!b.push(Word {
            letter: Letter::G,
            flags: WordFlags(0),
            value: 1.0
        }));
    }

    #[test]
    fn vacant_is_nan() {
        assert!(is_vacant(VACANT));
        assert!(!is_vacant(0.0));
    }
}
