//! The Н33-2М punched-tape dialect (6Р13Ф3-37 milling machine): canonical operations as fixed-width incremental blocks in 0.01 mm discretes (`readback::n33` reads such a tape back).
//!
//! Sections (§5.1.1, A.7 …) are those of the Н33-2М programming manual; "inferred" marks a rule of ours.
//!
//! What the emitter refuses (a [`Stop::Alarm`] numbered [`ALARM`], naming the cause): A B C motion,
//! G95, M04 and every M code the machine lacks, a feed move with no feed, more than 999 blocks.
//! What it changes, with a warning ([`N33Emitter::warnings`]): inch input (converted to mm), feeds
//! outside 0.1–4800 mm/min (clamped), S and T (dropped; S names the nearest of the 18 spindle steps),
//! M06 (an M00 stop for a manual tool change), M08/M09 (folded into M13/M05), `#3006` messages (M00).

use std::io::Write;

use fmsvm_block::{Alarm, Code, OutputBudget, Stop};

use crate::lines::Lines;
use fmsvm_canon::Emitter;
use fmsvm_canon::{Arc, Canon, Origin, Plane, Pose, Warning};

/// The alarm number of everything the Н33-2М cannot do (fmsvm's own number: the control has none).
pub const ALARM: u32 = 3300;
/// Blocks per tape: N001–N999 (§5.2.1).
pub const MAX_BLOCKS: u32 = 999;
/// The largest X Y Z I J K word, in discretes (§5.1.1: sign and 6 digits).
pub const MAX_WORD: i64 = 999_999;
/// Rapid traverse, 4800 mm/min (A.7: there is no G00).
pub const RAPID: u16 = 748;
/// The rate of `RAPID`, mm/min.
pub const RAPID_MM_PER_MIN: f64 = 4800.0;
/// The fastest working feed, 2000 mm/min (A.2), for rapids too short for rapid traverse.
pub const FASTEST_WORKING: u16 = 720;
/// 240 mm/min, for blocks with a stopping technological command (§5.2.3).
pub const STOP_FEED: u16 = 624;
/// The braking mode d1 = 4 of a feed code: decelerate to 240 mm/min at the end of the block, one
/// block only (§5.2.3).
pub const BRAKE: u16 = 4000;
/// The fixed speed a braking block decelerates to, mm/min: only a faster feed brakes (§5.2.3).
pub const BRAKE_FEED_MM: f64 = 240.0;
/// The velocity step at a corner, mm/min, above which a block brakes (`--n33-brake-step`). The
/// manual asks for braking "at sharp corners", none at tangent junctions (Fig. 8, Fig. 9), and
/// leaves the measure open; its examples brake a 90° corner at 1200 mm/min (Ex. 17 N017, step
/// 1697) and reversals at rapid (Ex. 4 N013), and not a 90° corner at 500 mm/min (Ex. 12, step
/// 707). 1000 mm/min lies between: a 90° corner brakes from 710 mm/min up, a reversal from 500,
/// and nothing at or under 240 does (docs/dialects.md).
pub const BRAKE_STEP: f64 = 1000.0;
/// The longest program the ФСУ-2 photo-reader takes, m (§5.1).
pub const MAX_TAPE_M: f64 = 30.0;

/// The 6Р13Ф3-37's travels, mm (A.2): X (longitudinal) 1000, Y (cross) 400, the ram (Z) 150 down
/// from its top (§4).
pub const TRAVEL_MM: [f64; 6] = [
    1000.0,
    400.0,
    150.0,
    f64::INFINITY,
    f64::INFINITY,
    f64::INFINITY,
];
/// A punched tape's row pitch, mm: ten rows an inch.
const ROW_MM: f64 = 2.54;
/// 60 mm/min, the dwell feed: one discrete is 0.01 s (§5.2.7).
pub const DWELL_FEED: u16 = 560;
/// The 18 spindle steps, rpm (A.2): set by hand.
pub const SPINDLE_STEPS: [f64; 18] = [
    40.0, 50.0, 63.0, 80.0, 100.0, 125.0, 160.0, 200.0, 250.0, 315.0, 400.0, 500.0, 630.0, 800.0,
    1000.0, 1250.0, 1600.0, 2000.0,
];

/// How the Н33-2М tape is written.
#[derive(Clone, Debug)]
pub struct N33Options {
    /// Punched-tape image: ISO 7-bit with even parity in bit 8, a NUL leader, NUL gaps after every
    /// block and a NUL trailer (§5.1.2, A.4). Otherwise the text form (`%`, blocks, LF).
    pub tape: bool,
    /// Chord tolerance, mm, where an arc must be linearised (a helix; an arc the grid cannot hold).
    pub arc_tolerance: f64,
    /// Rapids shorter than this (mm) go at the fastest working feed F0720 (A.7: 200 mm).
    pub rapid_min_length: f64,
    /// In G18 a tape G03 is ISO's counter-clockwise (seen from +Y, Z right, X up). False: the
    /// manual's XZ example's sense (counter-clockwise with X right, Z up), G02/G03 swapped (A.12).
    pub g18_ccw_is_iso: bool,
    /// NUL rows before `%` (tape), room for the hand-written name (§5.1.3).
    pub leader: usize,
    /// NUL rows after each block (tape): 1–2 are mandatory (A.4).
    pub gap: usize,
    /// NUL rows after the program (tape).
    pub trailer: usize,
    /// A feed or rapid block whose corner into the next move would change the velocity by more
    /// than this (mm/min: the feed × 2·sin(turn/2)) ends with the braking code `F4…`, decelerating
    /// to 240 mm/min at its end (§5.2.3, Fig. 8); infinite: never.
    pub brake_step: f64,
    /// A program over 999 blocks goes on several tapes, each ending after a rapid with M02 and
    /// the next starting where it left the tool (§5.2.1); otherwise it is refused.
    pub split_tapes: bool,
    /// The longest tape the reader takes, m: 30 with the domestic photo-reader ФСУ-2, 150 the
    /// tape itself (§5.1). Ten rows an inch (2.54 mm a character, the leader, gaps and trailer
    /// included).
    pub max_tape_m: f64,
    /// The machine's travels, mm ([`TRAVEL_MM`]; infinite: unchecked).
    pub travel: [f64; 6],
    /// The run's output budget.
    pub budget: OutputBudget,
    /// The run asked for the program's comments (the tape has none: it is told so once).
    pub comments: bool,
}

impl Default for N33Options {
    fn default() -> Self {
        N33Options {
            tape: false,
            arc_tolerance: 0.01,
            rapid_min_length: 200.0,
            g18_ccw_is_iso: true,
            leader: 100,
            gap: 2,
            trailer: 100,
            brake_step: BRAKE_STEP,
            split_tapes: false,
            max_tape_m: MAX_TAPE_M,
            travel: TRAVEL_MM,
            budget: OutputBudget::default(),
            comments: false,
        }
    }
}

/// A tape position in discretes as a pose.
fn discretes(q: [i64; 3]) -> Pose {
    [q[0] as f64, q[1] as f64, q[2] as f64, 0.0, 0.0, 0.0]
}

/// `b` with bit 8 set when needed to make its number of ones even (§5.1.2).
pub const fn with_parity(b: u8) -> u8 {
    let b = b & 0x7f;
    if b.count_ones() % 2 == 1 { b | 0x80 } else { b }
}

/// The feed code `d1 d2 d3 d4` (d1 = 0) nearest `feed` mm/min, as the number `d2d3d4`: d2 = 3 + the
/// integer digits of the feed, d3 d4 its first two significant digits, rounded half up; below
/// 1 mm/min the step is 0.1 (§5.2.3, Table 6). None outside 0.1–4800 mm/min.
pub fn encode_feed(feed: f64) -> Option<u16> {
    if !feed.is_finite() || feed <= 0.0 {
        return None;
    }
    if feed < 1.0 {
        let tenths = (feed * 10.0).round() as u16;
        return match tenths {
            0 => None,
            1..=9 => Some(300 + tenths * 10),
            _ => Some(410),
        };
    }
    let mut digits = 1u32;
    while digits < 6 && feed >= 10f64.powi(digits as i32) {
        digits += 1;
    }
    let mut m = if digits <= 2 {
        (feed * 10f64.powi(2 - digits as i32)).round()
    } else {
        (feed / 10f64.powi(digits as i32 - 2)).round()
    } as u16;
    if m >= 100 {
        m = 10;
        digits += 1;
    }
    let d2 = 3 + digits as u16;
    (d2 < 7 || (d2 == 7 && m <= 48)).then_some(d2 * 100 + m)
}

/// The feed, mm/min, of feed code `d1d2d3d4` (d1 0 or 4: 4 decelerates to 240 at the block end,
/// the feed is the same): 0.d3d4 × 10^(d2−3); d2 = 3 drops d4 (§5.2.3, Table 6). None for a code
/// that is not on the grid.
pub fn decode_feed(code: u16) -> Option<f64> {
    let (d1, d2, m) = (code / 1000, (code / 100) % 10, code % 100);
    if !(d1 == 0 || d1 == 4) || !(3..=7).contains(&d2) || m < 10 || (d2 == 7 && m > 48) {
        return None;
    }
    Some(match d2 {
        3 => (m / 10) as f64 / 10.0,
        4 => m as f64 / 10.0,
        5 => m as f64,
        6 => m as f64 * 10.0,
        _ => m as f64 * 100.0,
    })
}

/// The spindle step nearest `rpm` (by ratio: the steps are geometric), A.2.
pub fn nearest_spindle_step(rpm: f64) -> f64 {
    let mut best = SPINDLE_STEPS[0];
    for &s in &SPINDLE_STEPS {
        if (rpm.max(1.0) / s).ln().abs() < (rpm.max(1.0) / best).ln().abs() {
            best = s;
        }
    }
    best
}

fn alarm(message: String) -> Stop {
    Stop::Alarm(Alarm::new(ALARM, message))
}

fn push_digits(buf: &mut Vec<u8>, v: u64, width: u32) {
    for i in (0..width).rev() {
        buf.push(b'0' + ((v / 10u64.pow(i)) % 10) as u8);
    }
}

/// One block as it goes on the tape (words in the order of §5.2.18: N G I J K X Y Z M F).
#[derive(Clone, Copy, Default, Debug)]
struct Block {
    g: Option<u8>,
    /// I J K: magnitudes, discretes (indexed by axis X Y Z).
    ijk: [Option<i64>; 3],
    /// X Y Z increments, discretes.
    xyz: [Option<i64>; 3],
    m: Option<u8>,
    f: Option<u16>,
    /// The path's direction where the block starts and where it ends (unit vectors in X Y Z;
    /// zero in a block that does not move).
    entry: [f64; 3],
    exit: [f64; 3],
    /// A rapid: the tool is clear of the work where it ends (a tape may end there).
    rapid: bool,
}

impl Block {
    fn moves(&self) -> bool {
        self.entry != [0.0; 3]
    }

    /// The characters `render` punches for it, its end of block included: N and three digits, G
    /// and two, a sign and six digits an I J K X Y Z, M and two, F and four (§5.1.1).
    fn chars(&self) -> usize {
        let words = self
            .ijk
            .iter()
            .chain(&self.xyz)
            .filter(|v| v.is_some())
            .count();
        4 + 3 * usize::from(self.g.is_some())
            + 8 * words
            + 3 * usize::from(self.m.is_some())
            + 5 * usize::from(self.f.is_some())
            + 1
    }
}

/// The unit vector along `v` (zero for zero).
fn unit(v: [f64; 3]) -> [f64; 3] {
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if n > 0.0 {
        [v[0] / n, v[1] / n, v[2] / n]
    } else {
        [0.0; 3]
    }
}

/// How much the velocity changes, mm/min, where a path at `feed` turns from direction `a` to `b`
/// (unit vectors) without slowing: feed × |b − a| = feed × 2·sin(turn/2).
fn corner_step(feed: f64, a: [f64; 3], b: [f64; 3]) -> f64 {
    feed * ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2) + (b[2] - a[2]).powi(2)).sqrt()
}

/// What a tape has put in force by a block: what the next tape must say again after M02.
#[derive(Clone, Copy, Default, Debug)]
struct TapeState {
    /// G01–G04.
    motion: Option<u8>,
    /// G17–G19.
    plane: Option<u8>,
    /// The feed code (braking is one block: the code without d1).
    feed: Option<u16>,
    /// M03, M13 or M05.
    spindle: Option<u8>,
}

impl TapeState {
    fn after(mut self, b: &Block) -> TapeState {
        match b.g {
            Some(g @ 17..=19) => self.plane = Some(g),
            Some(g @ 1..=4) => self.motion = Some(g),
            _ => {}
        }
        if let Some(f) = b.f {
            self.feed = Some(f % 1000);
        }
        if let Some(m @ (3 | 5 | 13)) = b.m {
            self.spindle = Some(m);
        }
        self
    }
}

/// A block of the tape being gathered (`split_tapes`): the block, its origin, what is in force after
/// it, and whether it restates that at a tape's start.
#[derive(Clone, Copy, Debug)]
struct Gathered {
    block: Block,
    origin: Origin,
    state: TapeState,
    restated: bool,
}

/// Spindle and coolant, as M03/M05/M13 can set them (A.8).
#[derive(Clone, Copy, PartialEq, Eq, Default, Debug)]
struct Spindle {
    on: bool,
    coolant: bool,
}

/// Writes canonical operations as an Н33-2М tape.
pub struct N33Emitter<W: Write> {
    lines: Lines<W>,
    options: N33Options,
    /// Blocks written (the next is N = blocks + 1).
    blocks: u32,
    /// `%` (and the leader) went out.
    started: bool,
    /// M02 went out.
    ended: bool,
    /// Canon values are inch (converted: 2540 discretes per unit).
    inch: bool,
    /// The exact canon position (program units, output frame).
    at: Pose,
    /// The tape position: absolute, discretes, as the increments written so far add up.
    q: [i64; 3],
    /// Where the tape started, discretes (for the closure warning).
    origin: [i64; 3],
    /// Motion G on the tape (1 2 3 4), if any yet.
    motion: Option<u8>,
    /// Plane G on the tape.
    plane: Option<Plane>,
    /// Feed code on the tape.
    tape_feed: Option<u16>,
    /// The programmed feed as a code (None: none programmed).
    feed: Option<u16>,
    /// Spindle and coolant: as programmed, and as the tape has them.
    want: Spindle,
    tape: Spindle,
    /// Programmed T (for the M06 warning).
    tool: Option<f64>,
    warnings: Vec<Warning>,
    /// The last moving block, not yet on the tape: whether it brakes depends on the next (with its
    /// origin and the feed code in force in it).
    held: Option<(Block, Origin, u16)>,
    /// Plane blocks that came after the held block (written after it).
    between: Vec<(Block, Origin)>,
    /// With `split_tapes`: the current tape's blocks, numbered and written when the tape is full or
    /// the program ends; the state in force after the last block gathered; tapes finished; a tape
    /// just started whose first moving block must restate G and F.
    gathered: Vec<Gathered>,
    running: TapeState,
    tapes: u32,
    /// Rows punched on the current tape so far (its length at 2.54 mm a row).
    tape_rows: usize,
    /// With `split_tapes`: the rows of the blocks gathered for the current tape.
    gathered_rows: usize,
    fresh: bool,
    /// The span of the tape's moves against the machine's travels.
    travel: crate::travel::Travel,
}

impl<W: Write> N33Emitter<W> {
    /// An emitter writing to `out`.
    pub fn new(out: W, options: N33Options) -> Self {
        N33Emitter {
            lines: Lines::new(out, "", None, options.budget.clone()),
            travel: crate::travel::Travel::new(options.travel),
            options,
            blocks: 0,
            started: false,
            ended: false,
            inch: false,
            at: [0.0; 6],
            q: [0; 3],
            origin: [0; 3],
            motion: None,
            plane: None,
            tape_feed: None,
            feed: None,
            want: Spindle::default(),
            tape: Spindle::default(),
            tool: None,
            warnings: Vec::new(),
            held: None,
            between: Vec::new(),
            gathered: Vec::new(),
            running: TapeState::default(),
            tapes: 1,
            tape_rows: 0,
            gathered_rows: 0,
            fresh: false,
        }
    }

    /// What the emitter changed or dropped, once each.
    pub fn warnings(&self) -> Vec<Warning> {
        let mut all = self.warnings.clone();
        all.extend(self.lines.comment_warnings("the Н33-2М tape (A.4)"));
        all
    }

    /// Blocks numbered so far (those waiting for the next move's corner included).
    pub fn blocks(&self) -> u32 {
        self.blocks
            + self.gathered.len() as u32
            + u32::from(self.held.is_some())
            + self.between.len() as u32
    }

    /// The tapes the program takes (more than one only with `split_tapes`).
    pub fn tapes(&self) -> u32 {
        self.tapes
    }

    /// Says `text` once, at the first block it is about (a note on the machine: M05 with the
    /// coolant, a feed rate's grid, said again and again otherwise).
    fn warn(&mut self, at: Origin, text: String) {
        if !self.warnings.iter().any(|w| w.text == text) {
            self.warn_each(at, text);
        }
    }

    /// Says `text` about the block at `at`, once for that block (an arc written as chords).
    fn warn_each(&mut self, at: Origin, text: String) {
        let w = Warning::at(Origin { fixed: 0, ..at }, text);
        if !self.warnings.contains(&w) {
            self.warnings.push(w);
        }
    }

    /// Discretes per program unit: 0.01 mm (§5.1.1), inch converted (inferred: no inch mode).
    fn scale(&self) -> f64 {
        if self.inch { 2540.0 } else { 100.0 }
    }

    /// `v` (program units) on the 0.01 mm grid, rounded half away from zero (inferred, A.14 §2).
    fn quantise(&self, v: f64) -> i64 {
        (v * self.scale()).round() as i64
    }

    fn quantise_pose(&self, p: &Pose) -> [i64; 3] {
        [
            self.quantise(p[0]),
            self.quantise(p[1]),
            self.quantise(p[2]),
        ]
    }

    /// The target of a move as an increment can say it: an axis the kernel does not know stays
    /// where it is (it was unknown before: increment 0); an axis that becomes known from an unknown
    /// start has no increment, and the tape cannot say an absolute position (alarm 0224).
    fn known_target(&self, to: &Pose) -> Result<Pose, Stop> {
        let mut t = *to;
        for (i, (v, &at)) in t.iter_mut().zip(&self.at).enumerate() {
            if v.is_nan() {
                *v = at;
            } else if at.is_nan() {
                return Err(fmsvm_canon::unknown_axis(
                    i,
                    "the Н33-2М tape (incremental only: every move is from where the tool starts, which --start-point declares)",
                )
                .into());
            }
        }
        Ok(t)
    }

    /// A B C must stay where they are: the machine has X Y Z only (A.2).
    fn check_abc(&self, to: &Pose) -> Result<(), Stop> {
        for (i, name) in [(3, 'A'), (4, 'B'), (5, 'C')] {
            let moved = match (to[i].is_nan(), self.at[i].is_nan()) {
                (true, true) => false,
                (false, false) => (to[i] - self.at[i]).abs() > 1e-9,
                _ => true,
            };
            if moved {
                return Err(alarm(format!(
                    "{name}{}: the 6Р13Ф3-37 has the axes X Y Z only (A.2), a move of {name} cannot go on the Н33-2М tape",
                    to[i]
                )));
            }
        }
        Ok(())
    }

    /// Leader and `%` (§5.1.3).
    fn ensure_started(&mut self) -> Result<(), Stop> {
        if self.started {
            return Ok(());
        }
        self.started = true;
        // The leader, % and its end of block.
        self.tape_rows = self.options.leader + 2;
        let buf = &mut self.lines.buf;
        if self.options.tape {
            buf.extend(std::iter::repeat_n(0u8, self.options.leader));
            buf.push(with_parity(b'%'));
            buf.push(with_parity(b'\n'));
        } else {
            buf.extend_from_slice(b"%\n");
        }
        self.lines.end_line()
    }

    /// Writes `b` as the next block. Its modal words count at once; a block that moves waits for
    /// the next, which decides whether it brakes (§5.2.3).
    fn write(&mut self, b: &Block, origin: Origin) -> Result<(), Stop> {
        if self.ended {
            return Ok(());
        }
        // A plane block between two moves is no stop: the corner is across it.
        let plane_only =
            matches!(b.g, Some(17..=19)) && b.m.is_none() && b.f.is_none() && b.xyz == [None; 3];
        if plane_only && self.held.is_some() {
            self.plane = match b.g {
                Some(17) => Some(Plane::XY),
                Some(18) => Some(Plane::ZX),
                _ => Some(Plane::YZ),
            };
            self.between.push((*b, origin));
            return Ok(());
        }
        if b.moves() && self.travel.limited() {
            // Where the block takes the tool, 0.01 mm a discrete (a frame change is no motion:
            // `Canon::Start`).
            let to: [i64; 3] = std::array::from_fn(|i| self.q[i] + b.xyz[i].unwrap_or(0));
            for p in [self.q, to] {
                self.travel.reach(&discretes(p), 0.01)?;
            }
        }
        if let Some((mut h, at, feed)) = self.held.take() {
            // With d1 = 0 the control already slows at the block's end to the next block's feed
            // ("deceleration … so that the next block's speed is reached by the block end",
            // §5.2.3): the corner is taken at the slower of the two, and braking (to 240 mm/min)
            // is for a corner still too sharp at that speed.
            let next = b.f.and_then(|c| decode_feed(c % BRAKE));
            let brakes = b.moves()
                && decode_feed(feed).is_some_and(|f| {
                    let at_corner = next.map_or(f, |n| f.min(n));
                    at_corner > BRAKE_FEED_MM
                        && corner_step(at_corner, h.exit, b.entry) > self.options.brake_step
                });
            if brakes {
                h.f = Some(BRAKE + feed);
            }
            self.put(&h, at)?;
            for (p, at) in std::mem::take(&mut self.between) {
                self.put(&p, at)?;
            }
        }
        if let Some(g) = b.g {
            match g {
                17 => self.plane = Some(Plane::XY),
                18 => self.plane = Some(Plane::ZX),
                19 => self.plane = Some(Plane::YZ),
                _ => self.motion = Some(g),
            }
        }
        if b.f.is_some() {
            self.tape_feed = b.f;
        }
        if b.moves() {
            self.held = Some((*b, origin, self.tape_feed.unwrap_or(0)));
            return Ok(());
        }
        self.put(b, origin)
    }

    /// Puts `b` on the tape as the next block: at once, or stops at block 1000 before any of it is
    /// written (§5.2.1); with `split_tapes`, gathered into the current tape.
    fn put(&mut self, b: &Block, origin: Origin) -> Result<(), Stop> {
        if !self.options.split_tapes {
            return self.render(b, origin);
        }
        // Block 999 is the tape's M02; and a tape is no longer than the reader takes (§5.1), its
        // leader, M02 and trailer included.
        let gap = self.options.gap;
        let rows = |b: &Block| b.chars() + gap;
        let m02 = Block {
            m: Some(2),
            ..Block::default()
        };
        let longest = (self.options.max_tape_m * 1000.0 / ROW_MM) as usize;
        let fixed = self.options.leader + 2 + rows(&m02) + self.options.trailer;
        let full = self.gathered.len() as u32 >= MAX_BLOCKS - 1
            || fixed + self.gathered_rows + rows(b) > longest;
        if full && b.m != Some(2) {
            self.split_tape(origin)?;
            self.gathered_rows = self.gathered.iter().map(|g| rows(&g.block)).sum();
        }
        let mut b = *b;
        self.restate_after_split(&mut b, self.running);
        self.gathered_rows += rows(&b);
        self.running = self.running.after(&b);
        self.gathered.push(Gathered {
            block: b,
            origin,
            state: self.running,
            restated: false,
        });
        Ok(())
    }

    /// The first block of a tape that moves or dwells says G and F again (`before`: in force
    /// before it), as after M02 the control has neither.
    fn restate_after_split(&mut self, b: &mut Block, before: TapeState) {
        if !self.fresh || b.xyz == [None; 3] {
            return;
        }
        self.fresh = false;
        b.g = b.g.or(before.motion);
        b.f = b.f.or(before.feed);
    }

    /// The gathered tape is full: it ends after its last rapid (the tool clear of the work) with
    /// M02, and a new tape starts there, saying again the plane and the spindle in force.
    fn split_tape(&mut self, origin: Origin) -> Result<(), Stop> {
        let Some(k) = self
            .gathered
            .iter()
            .rposition(|g| g.block.rapid && !g.restated)
        else {
            let first = self.gathered.iter().map(|g| g.origin.line).find(|&l| l > 0);
            return Err(alarm(format!(
                "tape {} (from source line {}) is full (at most 999 blocks, §5.2.1, and {} m, §5.1) and has no rapid after which it could end with the tool clear of the work; the block that does not fit comes from source line {}",
                self.tapes,
                first.unwrap_or(0),
                self.options.max_tape_m,
                origin.line
            )));
        };
        let rest = self.gathered.split_off(k + 1);
        let at_end = self.gathered[k].state;
        for g in std::mem::take(&mut self.gathered) {
            self.render(&g.block, g.origin)?;
        }
        self.render(
            &Block {
                m: Some(2),
                ..Block::default()
            },
            origin,
        )?;
        // The next tape: its leader and %, numbered from N001.
        if self.options.tape {
            self.lines
                .buf
                .extend(std::iter::repeat_n(0u8, self.options.trailer));
        }
        self.started = false;
        self.ensure_started()?;
        self.blocks = 0;
        self.tapes += 1;
        let restated = |block| Gathered {
            block,
            origin,
            state: at_end,
            restated: true,
        };
        if let Some(p) = at_end.plane {
            self.gathered.push(restated(Block {
                g: Some(p),
                ..Block::default()
            }));
        }
        if let Some(m @ (3 | 13)) = at_end.spindle {
            self.gathered.push(restated(Block {
                m: Some(m),
                f: Some(STOP_FEED),
                ..Block::default()
            }));
        }
        self.fresh = true;
        let mut before = at_end;
        for mut g in rest {
            self.restate_after_split(&mut g.block, before);
            before = g.state;
            self.gathered.push(g);
        }
        Ok(())
    }

    /// The gathered blocks on the tape (at its end).
    fn render_gathered(&mut self) -> Result<(), Stop> {
        for g in std::mem::take(&mut self.gathered) {
            self.render(&g.block, g.origin)?;
        }
        Ok(())
    }

    /// Writes `b` as the tape's next block, or stops at block 1000 before any of it is written
    /// (§5.2.1).
    fn render(&mut self, b: &Block, origin: Origin) -> Result<(), Stop> {
        self.ensure_started()?;
        if self.blocks >= MAX_BLOCKS {
            let from = if origin.line > 0 {
                format!("block 1000 comes from source line {}", origin.line)
            } else {
                "block 1000 is the program end".to_string()
            };
            return Err(alarm(format!(
                "the Н33-2М takes at most 999 blocks per tape; this program needs more than that: {from}; split it over several tapes (§5.2.1)"
            )));
        }
        let start = self.lines.buf.len();
        let buf = &mut self.lines.buf;
        buf.push(b'N');
        push_digits(buf, self.blocks as u64 + 1, 3);
        if let Some(g) = b.g {
            buf.push(b'G');
            push_digits(buf, g as u64, 2);
        }
        for (i, letter) in [b'I', b'J', b'K'].into_iter().enumerate() {
            if let Some(v) = b.ijk[i] {
                buf.push(letter);
                buf.push(b'+');
                push_digits(buf, v.unsigned_abs(), 6);
            }
        }
        for (i, letter) in [b'X', b'Y', b'Z'].into_iter().enumerate() {
            if let Some(v) = b.xyz[i] {
                buf.push(letter);
                buf.push(if v < 0 { b'-' } else { b'+' });
                push_digits(buf, v.unsigned_abs(), 6);
            }
        }
        if let Some(m) = b.m {
            buf.push(b'M');
            push_digits(buf, m as u64, 2);
        }
        if let Some(f) = b.f {
            buf.push(b'F');
            push_digits(buf, f as u64, 4);
        }
        buf.push(b'\n');
        debug_assert_eq!(buf.len() - start, b.chars());
        let rows = b.chars() + self.options.gap;
        if self.options.tape {
            for byte in &mut buf[start..] {
                *byte = with_parity(*byte);
            }
            buf.extend(std::iter::repeat_n(0u8, self.options.gap));
        }
        // The tape's length with this block and the trailer, punched as `--tape` punches it.
        self.tape_rows += rows;
        let metres = (self.tape_rows + self.options.trailer) as f64 * ROW_MM / 1000.0;
        if metres > self.options.max_tape_m {
            return Err(alarm(format!(
                "the tape reaches {metres:.1} m at block {} (source line {}), where the reader takes {} m (§5.1: 30 m with the ФСУ-2 photo-reader, 150 m the tape; 2.54 mm a row): shorten the program or split it (--split-tapes)",
                self.blocks + 1,
                origin.line,
                self.options.max_tape_m
            )));
        }
        self.lines.end_line()?;
        self.blocks += 1;
        Ok(())
    }

    /// The motion G when it changes (§5.2.2 group II; after G04 it must be re-stated).
    fn motion_word(&self, g: u8) -> Option<u8> {
        (self.motion != Some(g)).then_some(g)
    }

    /// The F word when the code changes (A.7: F is modal).
    fn feed_word(&self, code: u16) -> Option<u16> {
        (self.tape_feed != Some(code)).then_some(code)
    }

    /// The programmed feed's code, or a stop when none was programmed.
    fn cutting_feed(&self, origin: Origin) -> Result<u16, Stop> {
        self.feed.ok_or_else(|| {
            alarm(format!(
                "a feed move with no feed rate (source line {}): the Н33-2М needs an F code (§5.2.3)",
                origin.line
            ))
        })
    }

    /// A straight move to `to` (discretes) at feed code `f`: left out when it is zero; split into
    /// equal pieces on the grid above 999999 discretes an axis (§5.1.1; splitting inferred).
    fn line(&mut self, to: [i64; 3], f: u16, rapid: bool, origin: Origin) -> Result<(), Stop> {
        let d = [to[0] - self.q[0], to[1] - self.q[1], to[2] - self.q[2]];
        let longest = d.iter().map(|v| v.abs()).max().unwrap_or(0);
        if longest == 0 {
            return Ok(());
        }
        let n = (longest + MAX_WORD - 1) / MAX_WORD;
        let from = self.q;
        for k in 1..=n {
            let mut p = [0i64; 3];
            for i in 0..3 {
                // Rounded k/n of the move, exactly `to` at k = n.
                p[i] = from[i] + div_round(d[i] * k, n);
            }
            let along = unit(std::array::from_fn(|i| (p[i] - self.q[i]) as f64));
            let mut b = Block {
                g: self.motion_word(1),
                f: self.feed_word(f),
                entry: along,
                exit: along,
                rapid,
                ..Block::default()
            };
            for ((w, &to), &at) in b.xyz.iter_mut().zip(&p).zip(&self.q) {
                if to != at {
                    *w = Some(to - at);
                }
            }
            self.write(&b, origin)?;
            self.q = p;
        }
        Ok(())
    }

    /// The spindle and coolant as programmed, on the tape: M13 both on, M03 spindle, M05 both off
    /// (A.8); an M block at F0624 (§5.2.3).
    fn flush_spindle(&mut self, origin: Origin) -> Result<(), Stop> {
        if self.want == self.tape {
            return Ok(());
        }
        let m = match (self.want.on, self.want.coolant) {
            (true, true) => 13,
            (true, false) if self.tape.coolant && self.tape.on => {
                self.warn(origin, "M09 with the spindle running: the Н33-2М has no coolant-off without a spindle stop (A.8); the coolant stays on until M05".into());
                self.want.coolant = true;
                return Ok(());
            }
            (true, false) => 3,
            (false, coolant) if !self.tape.on => {
                // The coolant is only remembered: it comes on with the next M03, as M13.
                if coolant && !self.tape.coolant {
                    self.warn(origin, "M08 with the spindle stopped: the Н33-2М switches the coolant only with the spindle (M13, A.8); it comes on with the next M03".into());
                }
                self.tape.coolant = coolant;
                return Ok(());
            }
            (false, coolant) => {
                if coolant {
                    self.warn(
                        origin,
                        "M05 stops the coolant too on the Н33-2М (A.8); it comes back with the next M03 (as M13)".into(),
                    );
                }
                5
            }
        };
        self.m_block(m, origin)?;
        self.tape = match m {
            13 => Spindle {
                on: true,
                coolant: true,
            },
            3 => Spindle {
                on: true,
                coolant: false,
            },
            // M05 stops both; coolant still wanted comes back with the next M03.
            _ => Spindle {
                on: false,
                coolant: self.want.coolant,
            },
        };
        Ok(())
    }

    /// An M code in its own block (one M per block, A.8), at F0624 unless it is M02 (§5.2.3; M02
    /// bare as in every example, inferred).
    fn m_block(&mut self, m: u8, origin: Origin) -> Result<(), Stop> {
        let f = if m == 2 {
            None
        } else {
            self.feed_word(STOP_FEED)
        };
        self.write(
            &Block {
                m: Some(m),
                f,
                ..Block::default()
            },
            origin,
        )
    }

    /// An M00 or M01 stop. "An M command holds until the next M" (A.8): the stop takes the place
    /// of the M03/M13 in force, so the spindle (and coolant) the program wants is said again before
    /// the next move, as after the first tool's stop.
    fn stop_block(&mut self, m: u8, origin: Origin) -> Result<(), Stop> {
        self.flush_spindle(origin)?;
        self.m_block(m, origin)?;
        self.tape = Spindle::default();
        Ok(())
    }

    fn mcode(&mut self, m: f64, origin: Origin) -> Result<(), Stop> {
        let code = m.round();
        if (m - code).abs() > 1e-9 {
            return Err(alarm(format!(
                "M{m}: the Н33-2М knows only M00 M01 M02 M03 M05 M13 (A.8)"
            )));
        }
        match Code::of_integer(m) {
            Some(Code::M3) => self.want.on = true,
            Some(Code::M5) => self.want.on = false,
            Some(Code::M8) => self.want.coolant = true,
            Some(Code::M9) => self.want.coolant = false,
            Some(Code::M4) => {
                return Err(alarm(
                    "M04: the Н33-2М has no reverse spindle command; the direction is set by switch S1 on the cabinet (A.8)".into(),
                ));
            }
            Some(stop @ (Code::M0 | Code::M1)) => self.stop_block(stop.whole() as u8, origin)?,
            Some(Code::M6) => {
                let t = self
                    .tool
                    .map_or(String::new(), |t| format!(" to T{}", t.round() as i64));
                self.warn(origin, format!(
                    "M06{t}: no automatic tool change on the 6Р13Ф3-37; an M00 stop for a manual change"
                ));
                self.stop_block(0, origin)?;
            }
            Some(end @ (Code::M2 | Code::M30)) => {
                if end == Code::M30 {
                    self.warn(
                        origin,
                        "M30 written as M02 (the Н33-2М has no M30, A.8; rewind is on the tape)"
                            .into(),
                    );
                }
                self.finish_program(origin)?;
            }
            _ => {
                return Err(alarm(format!(
                    "M{:02}: the Н33-2М knows only M00 M01 M02 M03 M05 M13 (A.8)",
                    code as i64
                )));
            }
        }
        Ok(())
    }

    /// M02 in its own block (A.4, A.8), once.
    fn finish_program(&mut self, origin: Origin) -> Result<(), Stop> {
        if self.ended {
            return Ok(());
        }
        self.ensure_started()?;
        self.flush_spindle(origin)?;
        if self.q != self.origin {
            let d: Vec<String> = (0..3)
                .map(|i| format!("{:+.2}", (self.q[i] - self.origin[i]) as f64 / 100.0))
                .collect();
            self.warn(origin, format!(
                "the program ends X{} Y{} Z{} mm from its start point: the next program on this machine starts there (A.14 §2)",
                d[0], d[1], d[2]
            ));
        }
        self.m_block(2, origin)?;
        self.ended = true;
        Ok(())
    }

    /// The G code on the tape for `clockwise` (canon sense) in `plane` (A.12).
    fn arc_g(&self, plane: Plane, clockwise: bool) -> u8 {
        let cw = if plane == Plane::ZX && !self.options.g18_ccw_is_iso {
            !clockwise
        } else {
            clockwise
        };
        if cw { 2 } else { 3 }
    }

    fn arc(&mut self, arc: &Arc, origin: Origin) -> Result<(), Stop> {
        self.check_abc(&arc.to)?;
        let f = self.cutting_feed(origin)?;
        let to = self.quantise_pose(&arc.to);
        let (a, b, n) = arc.plane.axes();
        let (r_true, sweep) = arc.sweep(&self.at);
        let pieces = if to[n] != self.q[n] {
            // No helix on this machine (§5.2.18): chords.
            None
        } else {
            let s = [self.q[a], self.q[b]];
            let e = [to[a], to[b]];
            let c = [arc.centre[0] * self.scale(), arc.centre[1] * self.scale()];
            quadrant_pieces(s, e, c, r_true * self.scale(), sweep, arc.clockwise)
        };
        let Some((centre, points)) = pieces else {
            let text = if to[n] == self.q[n] {
                format!(
                    "an arc the 0.01 mm grid cannot hold within one discrete of radius: written as chords within {} mm (A.12, inferred)",
                    self.options.arc_tolerance
                )
            } else {
                format!(
                    "a helix: no helix on the Н33-2М (§5.2.18), written as chords within {} mm",
                    self.options.arc_tolerance
                )
            };
            self.warn_each(origin, text);
            return self.chords(arc, sweep, f, origin);
        };
        let g = self.arc_g(arc.plane, arc.clockwise);
        if self.plane != Some(arc.plane) {
            let code = match arc.plane {
                Plane::XY => 17,
                Plane::ZX => 18,
                Plane::YZ => 19,
            };
            self.write(
                &Block {
                    g: Some(code),
                    ..Block::default()
                },
                origin,
            )?;
        }
        for p in points {
            let from = [self.q[a], self.q[b]];
            let d = [p[0] - from[0], p[1] - from[1]];
            if d == [0, 0] {
                continue;
            }
            let mut target = self.q;
            target[a] = p[0];
            target[b] = p[1];
            if d[0] == 0 || d[1] == 0 {
                // A piece along one axis is a step of a discrete or two at an axis crossing: the
                // quadrant would be ambiguous, the chord is the arc (inferred).
                self.line(target, f, false, origin)?;
                continue;
            }
            let mut blk = Block {
                g: self.motion_word(g),
                f: self.feed_word(f),
                ..Block::default()
            };
            let r = [from[0] - centre[0], from[1] - centre[1]];
            if r[0] != 0 {
                blk.ijk[a] = Some(r[0].abs());
            }
            if r[1] != 0 {
                blk.ijk[b] = Some(r[1].abs());
            }
            blk.xyz[a] = Some(d[0]);
            blk.xyz[b] = Some(d[1]);
            // The tangents at the piece's ends: the radius turned a quarter, with the arc.
            let tangent = |p: [i64; 2]| {
                let r = [(p[0] - centre[0]) as f64, (p[1] - centre[1]) as f64];
                let t = if arc.clockwise {
                    [r[1], -r[0]]
                } else {
                    [-r[1], r[0]]
                };
                let mut v = [0.0; 3];
                v[a] = t[0];
                v[b] = t[1];
                unit(v)
            };
            blk.entry = tangent(from);
            blk.exit = tangent(p);
            self.write(&blk, origin)?;
            self.q = target;
        }
        Ok(())
    }

    /// The arc (or helix) from the tool as chords within `arc_tolerance` (A.12: no helix).
    fn chords(&mut self, arc: &Arc, sweep: f64, f: u16, origin: Origin) -> Result<(), Stop> {
        let (a, b, n) = arc.plane.axes();
        let from = self.at;
        let [cx, cy] = arc.centre;
        let r0 = (from[a] - cx).hypot(from[b] - cy);
        let r1 = (arc.to[a] - cx).hypot(arc.to[b] - cy);
        let a0 = (from[b] - cy).atan2(from[a] - cx);
        let tol =
            (self.options.arc_tolerance / self.scale() * 100.0).max(0.005 / self.scale() * 100.0);
        let r = r0.max(r1);
        let step = if tol >= r {
            std::f64::consts::FRAC_PI_2
        } else {
            (2.0 * (1.0 - tol / r).acos()).min(std::f64::consts::FRAC_PI_2)
        };
        let count = ((sweep / step).ceil() as i64).max(1);
        let dir = if arc.clockwise { -1.0 } else { 1.0 };
        for k in 1..=count {
            let t = k as f64 / count as f64;
            let mut p = arc.to;
            if k < count {
                let ang = a0 + dir * sweep * t;
                let rr = r0 + (r1 - r0) * t;
                p[a] = cx + rr * ang.cos();
                p[b] = cy + rr * ang.sin();
                p[n] = from[n] + (arc.to[n] - from[n]) * t;
            }
            let q = self.quantise_pose(&p);
            self.line(q, f, false, origin)?;
        }
        Ok(())
    }

    /// A dwell: G04 with X the pause in hundredths of a second at F0560, split above 999999
    /// (§5.2.7); the next move re-states G and F (it differs from G04 F0560).
    fn dwell(&mut self, seconds: f64, origin: Origin) -> Result<(), Stop> {
        let mut left = (seconds * 100.0).round().max(0.0) as i64;
        while left > 0 {
            let x = left.min(MAX_WORD);
            self.write(
                &Block {
                    g: self.motion_word(4),
                    xyz: [Some(x), None, None],
                    f: self.feed_word(DWELL_FEED),
                    ..Block::default()
                },
                origin,
            )?;
            left -= x;
        }
        Ok(())
    }

    fn feed_rate(&mut self, f: f64, origin: Origin) {
        if !f.is_finite() || f <= 0.0 {
            self.feed = None;
            return;
        }
        let mm = if self.inch { f * 25.4 } else { f };
        let clamped = if mm > RAPID_MM_PER_MIN {
            self.warn(
                origin,
                format!("F{f}: above the Н33-2М's 4800 mm/min, written as 4800 (F0748, A.7)"),
            );
            RAPID_MM_PER_MIN
        } else if mm < 0.1 {
            self.warn(
                origin,
                format!("F{f}: below the Н33-2М's 0.1 mm/min, written as 0.1 (F0310, A.7)"),
            );
            0.1
        } else {
            mm
        };
        if !(10.0..=2000.0).contains(&clamped) {
            self.warn(
                origin,
                format!("F{f}: outside the 6Р13Ф3-37's working feeds 10–2000 mm/min (A.2)"),
            );
        }
        self.feed = encode_feed(clamped);
        if let (Some(code), Some(exact)) = (self.feed, self.feed.and_then(decode_feed))
            && (exact - clamped).abs() > 1e-9 * clamped.max(1.0)
        {
            self.warn(origin, format!(
                "F{f}: the Н33-2М feed grid has 2 significant digits; written as F{code:04} ({exact} mm/min, §5.2.3)"
            ));
        }
    }
}

/// `n / d` rounded half away from zero (d > 0).
fn div_round(n: i64, d: i64) -> i64 {
    let q = n.div_euclid(d);
    let r = n.rem_euclid(d);
    if 2 * r >= d { q + 1 } else { q }
}

fn dist(p: [i64; 2], c: [f64; 2]) -> f64 {
    (p[0] as f64 - c[0]).hypot(p[1] as f64 - c[1])
}

/// The distance of a point from a centre, both in increments (the Н33-2М reader checks arcs by it).
pub fn radius(p: [i64; 2], c: [i64; 2]) -> f64 {
    ((p[0] - c[0]) as f64).hypot((p[1] - c[1]) as f64)
}

/// The quadrant pieces of the arc from grid point `s` to grid point `e` about the true centre `c`
/// (discretes), of true radius `r_true`, sweeping about `sweep` radians: a grid centre near `c` for which every piece's start
/// and end radius agree within one discrete (§5.2.11), and the piece end points, on the axes of that
/// centre where the arc crosses them (A.12). Of the grid centres within two discretes of `c` that
/// will do, the one whose centre and split points stray least from the true circle (inferred). None
/// when none will do, or the radius does not fit I J K (the caller then writes chords).
fn quadrant_pieces(
    s: [i64; 2],
    e: [i64; 2],
    c: [f64; 2],
    r_true: f64,
    sweep: f64,
    clockwise: bool,
) -> Option<([i64; 2], Vec<[i64; 2]>)> {
    let base = [c[0].round() as i64, c[1].round() as i64];
    let mut best: Option<([i64; 2], Vec<[i64; 2]>, f64)> = None;
    for dx in -2..=2 {
        for dy in -2..=2 {
            let cg = [base[0] + dx, base[1] + dy];
            let Some((points, err)) = pieces_about(s, e, c, r_true, cg, sweep, clockwise) else {
                continue;
            };
            if best.as_ref().is_none_or(|b| err < b.2 - 1e-12) {
                best = Some((cg, points, err));
            }
        }
    }
    best.map(|(cg, points, _)| (cg, points))
}

/// The pieces about grid centre `cg`, and how far the centre and the split points stray from the
/// true circle (discretes); None when a piece's radii would differ by more than one discrete.
fn pieces_about(
    s: [i64; 2],
    e: [i64; 2],
    c: [f64; 2],
    r_true: f64,
    cg: [i64; 2],
    sweep: f64,
    clockwise: bool,
) -> Option<(Vec<[i64; 2]>, f64)> {
    use std::f64::consts::{FRAC_PI_2, PI, TAU};
    let (rs, re) = (radius(s, cg), radius(e, cg));
    if rs < 1.0 || (rs - re).abs() > 1.0 || rs.max(re) > (MAX_WORD - 1) as f64 {
        return None;
    }
    let angle = |p: [i64; 2]| ((p[1] - cg[1]) as f64).atan2((p[0] - cg[0]) as f64);
    let a0 = angle(s);
    let raw = if clockwise {
        a0 - angle(e)
    } else {
        angle(e) - a0
    };
    let mut d = if s == e { 0.0 } else { raw.rem_euclid(TAU) };
    // The sweep about the grid centre nearest the true one (a full circle stays one).
    while d + PI <= sweep {
        d += TAU;
    }
    let offset = dist(cg, c);
    if d <= 0.0 {
        return Some((Vec::new(), offset));
    }
    // The axis crossings, in the order the arc meets them.
    let eps = 1e-9;
    let mut axes = Vec::new();
    let q = a0 / FRAC_PI_2;
    let mut k = if clockwise {
        (q - eps).ceil() as i64 - 1
    } else {
        (q + eps).floor() as i64 + 1
    };
    loop {
        let theta = k as f64 * FRAC_PI_2;
        let gone = if clockwise { a0 - theta } else { theta - a0 };
        if gone >= d - eps {
            break;
        }
        axes.push(match k.rem_euclid(4) {
            0 => [1, 0],
            1 => [0, 1],
            2 => [-1, 0],
            _ => [0, -1],
        });
        k += if clockwise { -1 } else { 1 };
    }
    // The split radii: on each axis, the integer radius nearest the true circle that keeps every
    // piece's two radii within one discrete (from the start radius, to the end radius).
    let n = axes.len() as i64;
    let mut points = Vec::with_capacity(axes.len() + 1);
    let mut err = offset;
    let mut prev: Option<i64> = None;
    for (i, u) in axes.into_iter().enumerate() {
        let i = i as i64;
        let lo = ((rs - 1.0).ceil() as i64 - i).max((re - 1.0).ceil() as i64 - (n - 1 - i));
        let hi = ((rs + 1.0).floor() as i64 + i).min((re + 1.0).floor() as i64 + (n - 1 - i));
        let (lo, hi) = match prev {
            Some(m) => (lo.max(m - 1), hi.min(m + 1)),
            None => (lo, hi),
        };
        if lo > hi {
            return None;
        }
        let along = (cg[0] as f64 - c[0]) * u[0] as f64 + (cg[1] as f64 - c[1]) * u[1] as f64;
        let m = ((r_true - along).round() as i64).clamp(lo, hi);
        prev = Some(m);
        let p = [cg[0] + u[0] * m, cg[1] + u[1] * m];
        err = err.max((dist(p, c) - r_true).abs());
        points.push(p);
    }
    points.push(e);
    // Every piece within one discrete of radius (the control stops otherwise, §5.2.11).
    let mut from = s;
    for &p in &points {
        if (radius(from, cg) - radius(p, cg)).abs() > 1.0 {
            return None;
        }
        from = p;
    }
    Some((points, err))
}

impl<W: Write> Emitter for N33Emitter<W> {
    const CANON: bool = true;

    fn begin(&mut self, _number: Option<u32>, _title: &str) -> Result<(), Stop> {
        // The tape has no program number nor name (no comments, A.4): only the leader and `%`.
        self.ensure_started()
    }

    fn canon(&mut self, op: &Canon<'_>, origin: Origin) -> Result<(), Stop> {
        if self.ended {
            return Ok(());
        }
        match *op {
            Canon::Start(p) => {
                // The tool stands there; the tape is incremental, its origin is where it starts.
                // A later Start (the frame moved under the tool) moves the start point with it.
                self.at = p;
                let q = self.quantise_pose(&p);
                self.travel.reframe(&discretes(self.q), &discretes(q), 0.01);
                for ((o, &new), &old) in self.origin.iter_mut().zip(&q).zip(&self.q) {
                    *o += new - old;
                }
                if self.blocks == 0 {
                    self.origin = q;
                }
                self.q = q;
                Ok(())
            }
            Canon::Units(inch) => {
                if inch {
                    self.warn(origin, "inch input converted to mm: the Н33-2М has no inch mode (inferred)".into());
                }
                if inch != self.inch {
                    // The tool stays where it is, its coordinates change unit.
                    self.inch = inch;
                    let k = if inch { 1.0 / 25.4 } else { 25.4 };
                    for v in &mut self.at[..3] {
                        *v *= k;
                    }
                }
                Ok(())
            }
            Canon::FeedPerRev(true) => Err(alarm(
                "G95 (feed per revolution): the Н33-2М has no spindle feedback, feeds are mm/min only (A.7)".into(),
            )),
            Canon::FeedPerRev(false) => Ok(()),
            Canon::Skip(_) => Err(alarm(
                "G31 (a skip move): the Н33-2М has no touch-stop (no probe input on the tape control), and a feed to the programmed end would drive the probe through the surface".into(),
            )),
            Canon::SurfaceSpeed(_) | Canon::SpindleClamp(_) | Canon::Thread { .. } => Err(alarm(
                "constant surface speed, a spindle clamp or a thread: the Н33-2М is a milling tape without spindle feedback (A.7)".into(),
            )),
            Canon::FeedRate(f) => {
                self.feed_rate(f, origin);
                Ok(())
            }
            Canon::Reference { number, to, .. } => {
                // No reference return on the tape (§5.2.2, Table 5 has none; §4: the slides go back to machine
                // zero by hand): a move there, when the position is known.
                if let Some(i) = (0..3).find(|&i| to[i].is_nan() && !self.at[i].is_nan()) {
                    return Err(fmsvm_canon::unknown_axis(
                        i,
                        &format!(
                            "{} on the Н33-2М tape (it has no reference return: the move is written as an increment to the reference position, which --offsets [reference] gives)",
                            if number == 1 { "G28".to_string() } else { format!("G30 P{number}") }
                        ),
                    )
                    .into());
                }
                self.canon(&Canon::Rapid(to), origin)
            }
            // No G53 on the tape: the move, as an increment.
            Canon::Machine { to, .. } => self.canon(&Canon::Rapid(to), origin),
            Canon::Rapid(to) => {
                self.check_abc(&to)?;
                let to = self.known_target(&to)?;
                self.flush_spindle(origin)?;
                let q = self.quantise_pose(&to);
                let len = (0..3)
                    .map(|i| ((q[i] - self.q[i]) as f64 / 100.0).powi(2))
                    .sum::<f64>()
                    .sqrt();
                // No G00: G01 F0748; short rapids at the fastest working feed (A.7).
                let f = if len < self.options.rapid_min_length {
                    FASTEST_WORKING
                } else {
                    RAPID
                };
                self.line(q, f, true, origin)?;
                self.at = to;
                Ok(())
            }
            Canon::Feed(to) => {
                self.check_abc(&to)?;
                let to = self.known_target(&to)?;
                self.flush_spindle(origin)?;
                let q = self.quantise_pose(&to);
                if q != self.q {
                    let f = self.cutting_feed(origin)?;
                    self.line(q, f, false, origin)?;
                }
                self.at = to;
                Ok(())
            }
            Canon::Arc(arc) => {
                self.known_target(&arc.to)?;
                self.flush_spindle(origin)?;
                self.arc(&arc, origin)?;
                self.at = arc.to;
                Ok(())
            }
            Canon::Dwell(seconds) => {
                self.flush_spindle(origin)?;
                self.dwell(seconds, origin)
            }
            Canon::Speed(s) => {
                self.warn(origin, format!(
                    "S{s}: the 6Р13Ф3-37 has no S word (§5.2.18); set the spindle by hand to {} rpm (the nearest of its 18 steps, A.2)",
                    nearest_spindle_step(s)
                ));
                Ok(())
            }
            Canon::Tool(t) => {
                self.tool = Some(t);
                self.warn(origin, format!(
                    "T{}: the 6Р13Ф3-37 has no T word (§5.2.18): dropped",
                    t.round() as i64
                ));
                Ok(())
            }
            Canon::MCode(m) => self.mcode(m, origin),
            Canon::AuxCode(letter, code) => {
                self.warn(origin, format!(
                    "{letter}{code}: the Н33-2М tape has no second auxiliary function (no {letter} address for it, §5.1.1): dropped"
                ));
                Ok(())
            }
            // No comments on this tape (A.4): the run is told once when it asked for them.
            Canon::Comment(_) => {
                if self.options.comments {
                    self.lines.leave_out_comment();
                }
                Ok(())
            }
            Canon::Cycle(_) | Canon::CycleEnd | Canon::Corners(_) => Ok(()),
            // The tape's positions are the tool's: it has no work systems or length registers of
            // its own that fmsvm could leave offsets to.
            Canon::WorkSystem(_) | Canon::ToolLength { .. } => Err(fmsvm_block::Alarm::new(
                fmsvm_canon::UNKNOWN_POSITION,
                "the Н33-2М tape has no work systems or length registers: fmsvm applies the offsets itself",
            )
            .into()),
        }
    }

    fn message(&mut self, number: u32, text: &str) -> Result<(), Stop> {
        self.warn(Origin::default(), format!(
            "#3006 message {number} ({text}): an M00 stop, the Н33-2М tape cannot carry its text"
        ));
        self.stop_block(0, Origin::default())
    }

    fn written(&self) -> u64 {
        self.lines.written()
    }

    fn end(&mut self) -> Result<(), Stop> {
        if !self.ended {
            self.flush_spindle(Origin::default())?;
            self.warn(
                Origin::default(),
                "the program ends without M02/M30: M02 added (A.4)".into(),
            );
            self.finish_program(Origin::default())?;
        }
        self.render_gathered()?;
        if self.tapes > 1 {
            self.warn(Origin::default(), format!(
                "the program takes {} tapes of at most 999 blocks (§5.2.1): each ends after a rapid with M02, and the next starts where it left the tool, saying the plane and the spindle again; load it without moving the machine",
                self.tapes
            ));
        }
        if self.options.tape {
            self.lines
                .buf
                .extend(std::iter::repeat_n(0u8, self.options.trailer));
            self.lines.end_line()?;
        }
        self.lines.finish()
    }
}
