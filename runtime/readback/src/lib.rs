//! The motion a flat program describes, read back from its text: the vocabulary every dialect's reader
//! speaks, and what `--verify` compares with the kernel's canonical operations.
//!
//! A reader turns the bytes an emitter wrote (in any dialect: decimal words, fixed-width increments,
//! parity tape) into a stream of [`Move`]s in absolute millimetres and degrees, in the output frame,
//! one per motion block the control would execute (an arc split into quadrants gives one move per
//! piece). Readers stream: they hold one block at a time, never the program.
#![deny(missing_docs)]
#![forbid(unsafe_code)]

use fmsvm_canon::{Plane, Pose, describe_pose};

/// What one block makes the tool do.
#[derive(Clone, Copy, PartialEq, Debug)]
pub enum Motion {
    /// Straight at rapid traverse.
    Rapid,
    /// Straight at the feed rate.
    Feed,
    /// A skip move (the control's touch-stop: G31, the FMS-3000's G01 G32, LinuxCNC's G38.3):
    /// towards its end at the feed rate, stopped where the probe touches.
    Skip,
    /// An arc (or helix: the normal axis moves with it) about `centre`, the plane coordinates of the
    /// centre in absolute mm.
    Arc {
        /// Centre (first, second plane axis), absolute.
        centre: [f64; 2],
        /// The plane.
        plane: Plane,
        /// G2 (true) or G3.
        clockwise: bool,
    },
    /// A dwell of this many seconds (no motion).
    Dwell(f64),
    /// A thread: straight, synchronised with the spindle, `lead` mm a revolution.
    Thread {
        /// The lead.
        lead: f64,
    },
    /// G53: a rapid to machine coordinates `machine` on the axes of `axes`; the reader does not know
    /// the output frame's origin, so `to` is NaN on them.
    Machine {
        /// The axes moved.
        axes: u8,
        /// Their machine coordinates (NaN elsewhere).
        machine: [f64; 6],
    },
    /// A return to reference position `number` (1: G28) on the axes of `axes` (bit 0 X … bit 5 C):
    /// the reader does not know where that is, so `to` is NaN on them.
    Reference {
        /// 1 for G28, 2–4 for G30 P2–P4.
        number: u8,
        /// The axes returned.
        axes: u8,
    },
}

impl Motion {
    /// The same motion, an axis not known on both sides (NaN) counting as the same.
    pub fn same(&self, other: &Motion) -> bool {
        match (self, other) {
            (
                Motion::Machine {
                    axes: a,
                    machine: m,
                },
                Motion::Machine {
                    axes: b,
                    machine: n,
                },
            ) => {
                a == b
                    && m.iter()
                        .zip(n)
                        .all(|(x, y)| x == y || (x.is_nan() && y.is_nan()))
            }
            _ => self == other,
        }
    }

    /// What the motion is, for a message.
    pub fn describe(&self) -> String {
        match self {
            Motion::Machine { machine, .. } => format!("G53 to {}", describe_pose(machine)),
            Motion::Reference { number, .. } => format!("a return to reference position {number}"),
            other => format!("{other:?}"),
        }
    }
}

/// One move read back.
#[derive(Clone, Copy, PartialEq, Debug)]
pub struct Move {
    /// What the block does.
    pub motion: Motion,
    /// Where the tool stands after it (absolute, mm and degrees, axes X Y Z A B C).
    pub to: Pose,
    /// The feed rate in effect, mm/min (or mm/rev under G95) as the dialect encodes it; NaN when the
    /// program never said one.
    pub feed: f64,
    /// Feed per revolution is in force (G95; a lathe's G99).
    pub per_rev: bool,
    /// The output line (1-based) the move was read from.
    pub line: u32,
}

/// A block the reader cannot read: the output is not what the dialect's rules say.
#[derive(Clone, PartialEq, Debug)]
pub struct ReadError {
    /// Output line (1-based).
    pub line: u32,
    /// What is wrong, naming the offending text.
    pub message: String,
}

impl std::fmt::Display for ReadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "output line {}: {}", self.line, self.message)
    }
}

impl std::error::Error for ReadError {}

/// The control's own offsets a flat program has selected so far, where it leaves them to the
/// control (a profile's `work_offsets`/`tool_length = "control"`).
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct OffsetState {
    /// The work system, 1–6 for G54–G59 (0: none said).
    pub work: u8,
    /// The length offset: +H under G43, −H under G44, 0 cancelled (G49) or never said.
    pub length: i32,
    /// The plane the length offset was taken on in (17, 18, 19; 0 with none): the FMS-3000 puts
    /// it on the plane's normal axis (§3.3, Table 7), the kernel on Z, so the output must say
    /// G43 in G17.
    pub length_plane: u8,
}

impl OffsetState {
    /// As a program says it (`G55 G43 H1`).
    pub fn describe(&self) -> String {
        let work = match self.work {
            0 => "no work system".to_string(),
            n => format!("G{}", 53 + n),
        };
        let plane = match self.length_plane {
            0 | 17 => String::new(),
            18 => " in G18 (on Y)".to_string(),
            19 => " in G19 (on X)".to_string(),
            p => format!(" in G{p}"),
        };
        let length = match self.length {
            0 => "no length offset (G49)".to_string(),
            h if h > 0 => format!("G43 H{h}{plane}"),
            h => format!("G44 H{}{plane}", -h),
        };
        format!("{work}, {length}")
    }
}

/// A dialect's reader: the moves of a flat program, one at a time.
pub trait Reader {
    /// The next move, or None at the end of the program.
    fn next_move(&mut self) -> Result<Option<Move>, ReadError>;
    /// The control's offsets in force at the last move read.
    fn offsets(&self) -> OffsetState {
        OffsetState::default()
    }
    /// The tool stands at `p` (mm) before the moves that follow: the start of the program, or the
    /// output frame moved under it. Readers of absolute words need nothing; an incremental tape
    /// counts from there.
    fn start(&mut self, p: Pose) {
        let _ = p;
    }
}

pub mod beside;
pub mod centre;
pub mod n33;
pub mod words;

use fmsvm_block::{Alarm, Code, Stop};

use fmsvm_canon::Emitter;
use fmsvm_canon::{Arc, Canon, Origin};
use fmsvm_emit::dialect::Dialect;

/// A verification mismatch is fmsvm's own finding: no Fanuc alarm.
const MISMATCH: u32 = fmsvm_block::alarms::NO_FANUC_NUMBER;

/// Runs beside a second expansion of the program: takes the kernel's canonical operations and, for
/// each motion, the moves the reader reads back from the written output, and stops at the first
/// that differs by more than the dialect's resolution (half a least increment; chords and arc pieces
/// must lie on the kernel's arc).
pub struct Verifier<R: Reader> {
    reader: R,
    /// Half a least increment of a length, mm (angles: of a degree).
    tolerance: f64,
    angle_tolerance: f64,
    /// How far chords may stray from an arc.
    chord_tolerance: f64,
    /// The output's dwell units a second (1000: milliseconds; 10: FMS-3000's tenths; 100: the
    /// Н33-2М's hundredths): a dwell of s seconds is written as round(s·units), as its emitter
    /// writes it.
    pub dwell_units: f64,
    dialect: Dialect,
    /// The kernel's tool position (output frame, program units) and its unit.
    at: Pose,
    inch: bool,
    feed: f64,
    /// The kernel's feed per revolution (G95) is in force.
    per_rev: bool,
    /// Where the output's last move read back ended.
    read_at: Pose,
    /// A move read ahead and not yet matched (after a dwell of no time that the output may or may
    /// not write).
    held: Option<Move>,
    /// X Y Z said since the last Start (the output spells them in full on the next move).
    said: bool,
    moves: u64,
    /// Rapids may read back as feed moves.
    pub rapid_as_feed: bool,
    /// A feed move at this rate (mm/min) or above may read back as a rapid: the Н33-2М's rapid is
    /// its feed code F0748, 4800 mm/min (A.7), the same tape as `G01 F4800`.
    pub rapid_feed: Option<f64>,
    /// A dwell of no time is still a block (`G4 P0`); not in tenths (FMS-3000) nor on the Н33-2М.
    pub zero_dwells_written: bool,
    /// The output spells X Y Z on the first move after the output frame moved (text dialects);
    /// an incremental tape does not.
    pub respell_after_frame_move: bool,
    /// A Start came already.
    started: bool,
    /// The control's offsets the kernel has put in force (checked at each move where the dialect
    /// leaves offsets to the control).
    offsets: OffsetState,
    /// Relative resolution of the feed code (1e-9 for a decimal feed; Н33-2М: two digits).
    pub feed_tolerance: f64,
    /// The reader counts every axis from its start (an incremental tape): an axis the kernel does
    /// not know reads as wherever the count is, and is not a difference (the tape writes no
    /// increment on it).
    pub unknown_counted_from_start: bool,
    /// The first mismatch, for the caller.
    pub mismatch: Option<String>,
}

impl<R: Reader> Verifier<R> {
    /// A verifier reading the output through `reader`, written in `dialect`; `chord_tolerance` is the
    /// run's chord tolerance (arcs the dialect writes as chords).
    pub fn new(reader: R, dialect: Dialect, chord_tolerance: f64) -> Self {
        let tenths_off = dialect.dwell.most_a_block().is_none();
        let half = |d: u32| 0.5 * 10f64.powi(-(d as i32)) + 1e-9;
        Verifier {
            reader,
            tolerance: half(dialect.mm_digits),
            angle_tolerance: half(dialect.angle_digits),
            chord_tolerance,
            dwell_units: dialect.dwell.units_per_second(),
            dialect,
            at: [0.0; 6],
            inch: false,
            feed: f64::NAN,
            per_rev: false,
            said: false,
            read_at: [f64::NAN; 6],
            held: None,
            moves: 0,
            rapid_as_feed: false,
            rapid_feed: None,
            zero_dwells_written: tenths_off,
            feed_tolerance: 1e-9,
            unknown_counted_from_start: false,
            respell_after_frame_move: true,
            started: false,
            offsets: OffsetState::default(),
            mismatch: None,
        }
    }

    /// A dwell of `seconds` in the output's dwell units, as its emitter rounds them.
    fn dwell_in_units(&self, seconds: f64) -> f64 {
        (seconds.max(0.0) * self.dwell_units).round()
    }

    /// Moves read back and checked.
    pub fn moves(&self) -> u64 {
        self.moves
    }

    fn mm(&self, p: &Pose) -> Pose {
        let k = if self.inch { 25.4 } else { 1.0 };
        std::array::from_fn(|i| if i < 3 { p[i] * k } else { p[i] })
    }

    /// The tolerance of a length in the output: half an increment of the output's unit.
    fn length_tolerance(&self) -> f64 {
        if self.inch && self.dialect.inch {
            (0.5 * 10f64.powi(-(self.dialect.inch_digits as i32)) + 1e-9) * 25.4
        } else {
            self.tolerance
        }
    }

    fn fail(&mut self, origin: Origin, what: String) -> Stop {
        let text = format!(
            "{what} (the kernel's move from source line {})",
            origin.line
        );
        self.mismatch = Some(text.clone());
        Stop::Alarm(Alarm::new(MISMATCH, text))
    }

    fn next(&mut self, origin: Origin) -> Result<Move, Stop> {
        if let Some(m) = self.held.take() {
            self.moves += 1;
            return Ok(m);
        }
        match self.reader.next_move() {
            Ok(Some(m)) => {
                self.moves += 1;
                let read = self.reader.offsets();
                if (self.dialect.control_work || self.dialect.control_length)
                    && read != self.offsets
                {
                    return Err(self.fail(
                        origin,
                        format!(
                            "output line {}: the control's offsets there are {}, the kernel's {}",
                            m.line,
                            read.describe(),
                            self.offsets.describe()
                        ),
                    ));
                }
                Ok(m)
            }
            Ok(None) => Err(self.fail(
                origin,
                "the output ends before the kernel's motion does".into(),
            )),
            Err(e) => Err(self.fail(origin, e.to_string())),
        }
    }

    /// Whether `a` and `b` agree within the output's resolution (axes the output never said: NaN).
    fn same(&self, a: &Pose, b: &Pose, extra: f64) -> bool {
        let t = self.length_tolerance() + extra;
        (0..6).all(|i| {
            let tol = if i < 3 {
                t
            } else {
                self.angle_tolerance + extra
            };
            b[i].is_nan()
                || (a[i] - b[i]).abs() <= tol
                || (a[i].is_nan() && self.unknown_counted_from_start)
        })
    }

    /// Whether the output's rounded position would not change going from `self.at` to `to`: the
    /// emitter leaves such a move out.
    fn rounds_away(&self, to: &Pose) -> bool {
        if !self.said {
            return false;
        }
        let from = self.mm(&self.at);
        let to = self.mm(to);
        let q = |v: f64, d: u32| (v * 10f64.powi(d as i32)).round();
        (0..6).all(|i| {
            let d = if i < 3 {
                self.dialect.mm_digits
            } else {
                self.dialect.angle_digits
            };
            q(from[i], d) == q(to[i], d) || (from[i].is_nan() && to[i].is_nan())
        })
    }

    /// Whether `p` lies on the straight line from where the output stands to `want`, short of it.
    fn on_the_way(&self, want: &Pose, p: &Pose) -> bool {
        let from = self.read_at;
        if from[..3].iter().chain(&p[..3]).any(|v| v.is_nan()) {
            return false;
        }
        // Axes the output never said (NaN) do not move.
        let axis = |v: &Pose, i: usize| if v[i].is_nan() { 0.0 } else { v[i] };
        let (from, p, want): (Pose, Pose, Pose) = (
            std::array::from_fn(|i| axis(&from, i)),
            std::array::from_fn(|i| axis(p, i)),
            std::array::from_fn(|i| {
                if from[i].is_nan() || p[i].is_nan() {
                    0.0
                } else {
                    want[i]
                }
            }),
        );
        let (p, want) = (&p, &want);
        let d: Vec<f64> = (0..6).map(|i| want[i] - from[i]).collect();
        let len2: f64 = d.iter().map(|v| v * v).sum();
        if len2 == 0.0 {
            return false;
        }
        let t: f64 = (0..6).map(|i| (p[i] - from[i]) * d[i]).sum::<f64>() / len2;
        if !(0.0..1.0).contains(&t) {
            return false;
        }
        let off: f64 = (0..6)
            .map(|i| (from[i] + t * d[i] - p[i]).powi(2))
            .sum::<f64>()
            .sqrt();
        off <= self.length_tolerance() * 2.0
    }

    /// The safety check: the output block `m` read back moves no axis its source block must leave
    /// where it is (`Origin::fixed`: neither named nor coupled), and writes none of them first.
    fn check_fixed(&mut self, m: &Move, origin: Origin) -> Result<(), Stop> {
        let t = self.length_tolerance();
        // From where the kernel's tool stands (the output agreed with it so far).
        let start = self.mm(&self.at);
        for (i, letter) in fmsvm_canon::AXES.iter().enumerate() {
            if origin.fixed & (1 << i) == 0 || m.to[i].is_nan() {
                continue;
            }
            let tol = if i < 3 { t } else { self.angle_tolerance };
            let from = start[i];
            if from.is_nan() && self.unknown_counted_from_start {
                continue;
            }
            if from.is_nan() || (m.to[i] - from).abs() > tol {
                return Err(self.fail(
                    origin,
                    format!(
                        "output line {}: moves {letter}, which its source block neither names nor couples",
                        m.line
                    ),
                ));
            }
        }
        Ok(())
    }

    fn describe(p: &Pose) -> String {
        describe_pose(p)
    }

    /// A skip move: read back as the control's touch-stop block to the same end, nothing else
    /// (a plain feed there would drive the probe through the surface).
    fn skip(&mut self, to: Pose, origin: Origin) -> Result<(), Stop> {
        if self.rounds_away(&to) {
            self.at = to;
            return Ok(());
        }
        let want = self.mm(&to);
        let m = self.next(origin)?;
        if m.motion != Motion::Skip || !self.same(&want, &m.to, 0.0) {
            return Err(self.fail(
                origin,
                format!(
                    "output line {}: {:?} to {}, the kernel: a skip move (G31) to {}",
                    m.line,
                    m.motion,
                    Self::describe(&m.to),
                    Self::describe(&want)
                ),
            ));
        }
        self.check_fixed(&m, origin)?;
        self.read_at = m.to;
        self.at = to;
        Ok(())
    }

    fn straight(&mut self, to: Pose, rapid: bool, origin: Origin) -> Result<(), Stop> {
        if self.rounds_away(&to) {
            self.at = to;
            return Ok(());
        }
        let want = self.mm(&to);
        let mut m = self.next(origin)?;
        loop {
            // A control without a rapid word (the Н33-2М) moves short rapids at a working feed.
            let kind_ok = matches!(
                (m.motion, rapid),
                (Motion::Rapid, true) | (Motion::Feed, false)
            ) || (rapid && self.rapid_as_feed && m.motion == Motion::Feed)
                || (!rapid
                    && m.motion == Motion::Rapid
                    && self.rapid_feed.is_some_and(|r| {
                        let f = if self.inch {
                            self.feed * 25.4
                        } else {
                            self.feed
                        };
                        f >= r * (1.0 - self.feed_tolerance)
                    }));
            if kind_ok && self.same(&want, &m.to, 0.0) {
                self.check_fixed(&m, origin)?;
                break;
            }
            // The same straight move in pieces (a long move split, a cycle's exit by way of R).
            if kind_ok && self.on_the_way(&want, &m.to) {
                self.check_fixed(&m, origin)?;
                self.read_at = m.to;
                m = self.next(origin)?;
                continue;
            }
            return Err(self.fail(
                origin,
                format!(
                    "output line {}: {:?} to {}, the kernel: {} to {}",
                    m.line,
                    m.motion,
                    Self::describe(&m.to),
                    if rapid { "rapid" } else { "feed" },
                    Self::describe(&want)
                ),
            ));
        }
        self.read_at = m.to;
        if !rapid {
            self.check_feed_mode(&m, origin)?;
        }
        if !rapid && !self.feed.is_nan() && self.feed_tolerance.is_finite() {
            let f = if self.inch {
                self.feed * 25.4
            } else {
                self.feed
            };
            let step = 10f64.powi(-(self.dialect.digits(fmsvm_block::Letter::F, self.inch) as i32));
            let unit = if self.inch && self.dialect.inch {
                25.4
            } else {
                1.0
            };
            let t = (0.5 * step * unit + 1e-9).max(f.abs() * self.feed_tolerance);
            if (m.feed - f).abs() > t {
                return Err(self.fail(
                    origin,
                    format!(
                        "output line {}: feed {} where the kernel feeds at {f}",
                        m.line, m.feed
                    ),
                ));
            }
        }
        self.at = to;
        self.said = true;
        Ok(())
    }

    /// A thread: one block to the kernel's end with its lead (within the lead's resolution).
    fn thread(&mut self, to: Pose, lead: f64, origin: Origin) -> Result<(), Stop> {
        let want = self.mm(&to);
        let m = self.next(origin)?;
        let k = if self.inch { 25.4 } else { 1.0 };
        let ok = match m.motion {
            Motion::Thread { lead: read } => {
                (read - lead * k).abs() <= self.length_tolerance() && self.same(&want, &m.to, 0.0)
            }
            _ => false,
        };
        if !ok {
            return Err(self.fail(
                origin,
                format!(
                    "output line {}: {:?} to {}, the kernel: a thread of lead {lead} to {}",
                    m.line,
                    m.motion,
                    Self::describe(&m.to),
                    Self::describe(&want)
                ),
            ));
        }
        self.check_fixed(&m, origin)?;
        self.read_at = m.to;
        self.at = to;
        self.said = true;
        Ok(())
    }

    /// A feed move read back under the kernel's feed mode (per minute or per revolution).
    fn check_feed_mode(&mut self, m: &Move, origin: Origin) -> Result<(), Stop> {
        if m.per_rev == self.per_rev {
            return Ok(());
        }
        let mode = |r: bool| {
            if r {
                "feed per revolution"
            } else {
                "feed per minute"
            }
        };
        Err(self.fail(
            origin,
            format!(
                "output line {}: the feed is read as {}, the kernel's is {}",
                m.line,
                mode(m.per_rev),
                mode(self.per_rev)
            ),
        ))
    }

    fn arc(&mut self, arc: &Arc, origin: Origin) -> Result<(), Stop> {
        let from = self.at;
        // Less than half a turn ending where it starts at the output's resolution: not written.
        if arc.sweep(&from).1 < std::f64::consts::PI && self.rounds_away(&arc.to) {
            self.at = arc.to;
            return Ok(());
        }
        let want_end = self.mm(&arc.to);
        let k = if self.inch { 25.4 } else { 1.0 };
        let centre = [arc.centre[0] * k, arc.centre[1] * k];
        let (a, b, _) = arc.plane.axes();
        let start = self.mm(&from);
        let r = (start[a] - centre[0]).hypot(start[b] - centre[1]);
        let (_, total) = arc.sweep(&from);
        let mut swept = 0.0;
        let mut at = start;
        loop {
            let m = self.next(origin)?;
            self.check_feed_mode(&m, origin)?;
            let on_circle = |p: &Pose, extra: f64| {
                ((p[a] - centre[0]).hypot(p[b] - centre[1]) - r).abs()
                    <= self.length_tolerance() * 2.0 + extra
            };
            match m.motion {
                Motion::Arc {
                    centre: c,
                    plane,
                    clockwise,
                } => {
                    let t = self.length_tolerance() * 2.0;
                    if plane != arc.plane
                        || clockwise != arc.clockwise
                        || (c[0] - centre[0]).abs() > t
                        || (c[1] - centre[1]).abs() > t
                        || !on_circle(&m.to, 0.0)
                    {
                        return Err(self.fail(
                            origin,
                            format!(
                                "output line {}: the arc about {:.4} {:.4} is not the kernel's {} arc about {:.4} {:.4}",
                                m.line,
                                c[0],
                                c[1],
                                if arc.clockwise { "G2" } else { "G3" },
                                centre[0],
                                centre[1]
                            ),
                        ));
                    }
                    let piece = Arc {
                        to: m.to,
                        centre: c,
                        plane,
                        clockwise,
                        turns: 0,
                    };
                    swept += piece.sweep(&at).1;
                }
                Motion::Feed => {
                    if !on_circle(&m.to, self.chord_tolerance) {
                        return Err(self.fail(
                            origin,
                            format!(
                                "output line {}: the chord end {} is off the kernel's arc",
                                m.line,
                                Self::describe(&m.to)
                            ),
                        ));
                    }
                    let a0 = (at[b] - centre[1]).atan2(at[a] - centre[0]);
                    let a1 = (m.to[b] - centre[1]).atan2(m.to[a] - centre[0]);
                    let mut d = if arc.clockwise { a0 - a1 } else { a1 - a0 };
                    if d < -1e-9 {
                        d += std::f64::consts::TAU;
                    }
                    swept += d;
                }
                other => {
                    return Err(self.fail(
                        origin,
                        format!(
                            "output line {}: {other:?} where the kernel has an arc",
                            m.line
                        ),
                    ));
                }
            }
            at = m.to;
            // The pieces start from rounded points: their sweep may fall short of the kernel's by
            // the angle a few increments make on this radius.
            let slack = 1e-3 + 4.0 * self.length_tolerance() / r.max(1e-9);
            if self.same(&want_end, &m.to, 0.0) && swept >= total - slack {
                break;
            }
            if swept > total + 0.1 {
                return Err(self.fail(
                    origin,
                    format!(
                        "output line {}: the arc goes past the kernel's end {}",
                        m.line,
                        Self::describe(&want_end)
                    ),
                ));
            }
        }
        self.at = arc.to;
        Ok(())
    }
}

impl<R: Reader> Emitter for Verifier<R> {
    const CANON: bool = true;

    fn canon(&mut self, op: &Canon<'_>, origin: Origin) -> Result<(), Stop> {
        match *op {
            Canon::Start(p) => {
                self.at = p;
                // At the start, where the tool stands counts as said on every axis the kernel
                // knows (a move there is left out; an unknown axis is never equal to anything).
                // After the frame moved, a text dialect spells X Y Z again on the next move; an
                // incremental tape counts from there.
                self.said = !self.started || !self.respell_after_frame_move;
                self.started = true;
                let mm = self.mm(&p);
                self.reader.start(mm);
                Ok(())
            }
            Canon::Units(inch) => {
                // The tool stays where it is: its coordinates change unit.
                if inch != self.inch {
                    let k = if inch { 1.0 / 25.4 } else { 25.4 };
                    for v in &mut self.at[..3] {
                        *v *= k;
                    }
                }
                self.inch = inch;
                Ok(())
            }
            Canon::FeedRate(f) => {
                self.feed = f;
                Ok(())
            }
            Canon::FeedPerRev(on) => {
                self.per_rev = on;
                Ok(())
            }
            Canon::Reference { number, axes, to } => {
                if self.dialect.reference == fmsvm_emit::dialect::ReferenceForm::None
                    || (self.dialect.reference == fmsvm_emit::dialect::ReferenceForm::MachineZero
                        && number != 1)
                {
                    // Written as a move to a known position.
                    return self.straight(to, true, origin);
                }
                let m = self.next(origin)?;
                if m.motion != (Motion::Reference { number, axes }) {
                    return Err(self.fail(
                        origin,
                        format!(
                            "output line {}: {} where the kernel returns to reference position {number} (axes {axes:#08b})",
                            m.line,
                            m.motion.describe()
                        ),
                    ));
                }
                self.read_at = m.to;
                self.at = to;
                Ok(())
            }
            Canon::Machine { axes, machine, to } => {
                if self.dialect.reference == fmsvm_emit::dialect::ReferenceForm::None {
                    return self.straight(to, true, origin);
                }
                let m = self.next(origin)?;
                let (want, t) = (self.mm(&machine), self.length_tolerance());
                let same = match m.motion {
                    Motion::Machine {
                        axes: a,
                        machine: read,
                    } => {
                        a == axes
                            && (0..6)
                                .all(|i| axes & (1 << i) == 0 || (read[i] - want[i]).abs() <= t)
                    }
                    _ => false,
                };
                if !same {
                    return Err(self.fail(
                        origin,
                        format!(
                            "output line {}: {} where the kernel moves to machine coordinates {}",
                            m.line,
                            m.motion.describe(),
                            Self::describe(&machine)
                        ),
                    ));
                }
                self.read_at = m.to;
                self.at = to;
                Ok(())
            }
            Canon::WorkSystem(n) => {
                self.offsets.work = n;
                Ok(())
            }
            Canon::ToolLength { code, register } => {
                let h = i32::from(register);
                self.offsets.length = match code {
                    Code::G43 => h,
                    Code::G44 => -h,
                    _ => 0,
                };
                // The kernel's length is on Z: said in G17.
                self.offsets.length_plane = if self.offsets.length == 0 { 0 } else { 17 };
                Ok(())
            }
            Canon::Rapid(to) => self.straight(to, true, origin),
            Canon::Feed(to) => self.straight(to, false, origin),
            Canon::Skip(to) => self.skip(to, origin),
            Canon::Thread { to, lead } => self.thread(to, lead, origin),
            Canon::Arc(arc) => self.arc(&arc, origin),
            Canon::Dwell(s) => {
                // The output holds round(s·units) of its dwell units, in one block or several
                // (FMS-3000: 65535 tenths a block; Н33-2М: 999999 hundredths); a dwell that rounds
                // to none is no block, but where `G4 P0` is written.
                let mut left = self.dwell_in_units(s);
                if left == 0.0 {
                    if !self.zero_dwells_written {
                        return Ok(());
                    }
                    // A dwell of no time: a `G4 P0` block, or none (a cycle's P0).
                    let m = match self.held.take() {
                        Some(m) => Some(m),
                        None => match self.reader.next_move() {
                            Ok(m) => m,
                            Err(e) => return Err(self.fail(origin, e.to_string())),
                        },
                    };
                    if let Some(m) = m {
                        if matches!(m.motion, Motion::Dwell(d) if self.dwell_in_units(d) == 0.0) {
                            self.moves += 1;
                        } else {
                            self.held = Some(m);
                        }
                    }
                    return Ok(());
                }
                while left > 0.0 {
                    let m = self.next(origin)?;
                    let units = match m.motion {
                        Motion::Dwell(d) => self.dwell_in_units(d),
                        _ => 0.0,
                    };
                    match m.motion {
                        Motion::Dwell(_) if units > 0.0 && units <= left => left -= units,
                        other => {
                            return Err(self.fail(
                                origin,
                                format!(
                                    "output line {}: {other:?} where the kernel dwells {s} s",
                                    m.line
                                ),
                            ));
                        }
                    }
                }
                Ok(())
            }
            _ => Ok(()),
        }
    }

    fn end(&mut self) -> Result<(), Stop> {
        if let Some(m) = self.held.take() {
            return Err(self.fail(
                Origin::default(),
                format!(
                    "output line {}: motion after the kernel's last move",
                    m.line
                ),
            ));
        }
        match self.reader.next_move() {
            Ok(None) => Ok(()),
            Ok(Some(m)) => Err(self.fail(
                Origin::default(),
                format!(
                    "output line {}: motion after the kernel's last move",
                    m.line
                ),
            )),
            Err(e) => Err(self.fail(Origin::default(), e.to_string())),
        }
    }
}

#[cfg(test)]
mod n33_tests;
#[cfg(test)]
mod tests {
    use super::*;
    use fmsvm_canon::Emitter;

    /// The safety check fires on a move of an axis the block must leave (here Z of a block that
    /// names X only) even when the output agrees with the kernel, and not on one it frees.
    #[test]
    fn a_move_of_a_fixed_axis_fails_the_check() {
        let text = "G90 G17\nG0 X0. Y0. Z50.\nX10. Z60.\n";
        let run = |fixed: u8| {
            let reader = words::WordReader::new(text.as_bytes(), Dialect::fanuc());
            let mut v = Verifier::new(reader, Dialect::fanuc(), 0.001);
            let o = |fixed| Origin {
                line: 2,
                block_delete: false,
                fixed,
                ..Origin::default()
            };
            v.canon(&Canon::Start([f64::NAN; 6]), o(0))?;
            v.canon(
                &Canon::Rapid([0.0, 0.0, 50.0, f64::NAN, f64::NAN, f64::NAN]),
                o(0),
            )?;
            v.canon(
                &Canon::Rapid([10.0, 0.0, 60.0, f64::NAN, f64::NAN, f64::NAN]),
                o(fixed),
            )
        };
        let Err(Stop::Alarm(a)) = run(0b000100) else {
            panic!("Z moved in a block that fixes it, and the check let it pass");
        };
        assert!(
            a.message.contains("output line 3: moves Z"),
            "{}",
            a.message
        );
        assert!(run(0b110000).is_ok());
    }

    /// The read-back finds an arc's centre by its own rule (`centre.rs`): a kernel whose R rule
    /// put the centre on the wrong side of the chord (the mirror, (5, +√75) for `G2 X10. Y0 R10.`
    /// from the origin, where it is (5, −√75)) is caught by its own output's check.
    #[test]
    fn a_centre_on_the_wrong_side_is_caught() {
        let text = "G90 G17\nG0 X0. Y0. Z0.\nG2 X10. Y0. R10. F100.\n";
        let h = 75f64.sqrt();
        let run = |cy: f64| {
            let reader = words::WordReader::new(text.as_bytes(), Dialect::fanuc());
            let mut v = Verifier::new(reader, Dialect::fanuc(), 0.001);
            let o = Origin {
                line: 2,
                ..Origin::default()
            };
            v.canon(&Canon::Start([f64::NAN; 6]), o)?;
            v.canon(
                &Canon::Rapid([0.0, 0.0, 0.0, f64::NAN, f64::NAN, f64::NAN]),
                o,
            )?;
            v.canon(&Canon::FeedRate(100.0), o)?;
            v.canon(
                &Canon::Arc(fmsvm_canon::Arc {
                    to: [10.0, 0.0, 0.0, f64::NAN, f64::NAN, f64::NAN],
                    centre: [5.0, cy],
                    plane: fmsvm_canon::Plane::XY,
                    clockwise: true,
                    turns: 0,
                }),
                o,
            )
        };
        assert!(run(-h).is_ok(), "{:?}", run(-h));
        assert!(run(h).is_err(), "the mirrored centre passed");
    }
}
