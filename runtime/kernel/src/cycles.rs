//! Canned cycles (G73 G74 G76 G81–G89): one cycle block expanded into the moves it makes.
//!
//! [`expand`] takes one block of a canned-cycle mode and hands out, in order, the steps the control
//! makes for it: rapids, feeds, dwells, spindle changes and program stops, in program coordinates
//! (the kernel transforms each step afterwards). The sticky words of the mode (R, Z, Q, P, the shift
//! and the initial level) live in a [`CycleModal`] the kernel keeps and cancels on G80 and on the
//! motion codes of group 01.
//!
//! # The oracle
//!
//! Where LinuxCNC has the cycle (G73 G74 G81–G86 G88 G89), the steps are those of LinuxCNC's
//! interpreter: `rs274 -g` of 2.9.0~pre1 (git f1270d6ed7), read in `src/emc/rs274ngc/interp_cycles.cc`
//! (`convert_cycle_xy`, `CYCLE_MACRO` in `interp_internal.hh`, `convert_cycle_g73` …). The tests hold
//! the traces of the programs in `runtime/kernel/tests/cycles/*.ngc` (`regenerate.sh` there remakes them).
//! Zero-length moves and zero dwells LinuxCNC makes are kept (a `G90` repeat re-positions on the
//! spot; G84 without P dwells 0 s): the kernel may drop them.
//!
//! The rules, as LinuxCNC has them, for the plane's axes (first, second, normal) = `Plane::axes()`
//! (G17 X Y Z, G18 Z X Y: drilling along Y, G19 Y Z X: drilling along X):
//!
//! * The **initial level** is the normal-axis position at the first drilling block of the mode; it
//!   stays until the mode is cancelled, whatever cycle codes follow.
//! * **G90**: R and Z are levels; the hole is at the block's first/second axis words, the tool's
//!   position where a word is missing. **G91**: R is the distance from the initial level, Z the
//!   distance from R; the plane words are steps, made before each repeat.
//! * **Starting below R**: when the initial level is below R, the tool first rapids along the normal
//!   axis up to R, where it stands, and R is then also the G98 return level.
//! * **Positioning**, before each repeat: on the first repeat of a block whose start is above R, a
//!   rapid in the plane at the start level, then down to R; otherwise a rapid straight to the hole
//!   at the return level (a diagonal when the return level changed, e.g. G99 after G98 or a new R),
//!   then down to R if that level is above R.
//! * **Return level**: R under G99 (`retract_to_r`), the initial level under G98, per block.
//! * **Repeats** K/L: G90 drills the same hole again; G91 steps each time.
//! * R below Z is an alarm (G87 excepted, whose R is the bottom).
//!
//! # Fanuc's rules, where they differ or LinuxCNC has none
//!
//! Sources: Fanuc Series 15i/150i-MA Operator's Manual (Programming), G76 (cncmanuals.com, page 315:
//! shift by Q along a parameter-set direction, Q's sign ignored; or by I J with bit SIJ); the canned
//! cycle format of Fanuc-compatible controls (doc.weihong.com.cn, "Format of canned cycle" and "G87
//! fine back boring cycle": Z R Q P modal until cancelled, P in ms without a decimal point, K not
//! modal, the G87 sequence); hsckontrol.com, "G88: boring cycle" (one of X Y Z R or another axis
//! must be given for the cycle to run; G88's manual retract).
//!
//! * **P** is Fanuc's: milliseconds ([`CycleBlock::p`]; P1000 = 1 s). A LinuxCNC twin of a program
//!   writes seconds. A cycle that dwells and never got a P dwells 0 s (LinuxCNC refuses G82 G86 G88
//!   G89 without P; Fanuc takes P as 0).
//! * **When a block drills**: when it has a plane word, a normal-axis word, R, or a repeat count.
//!   LinuxCNC drills on any axis word and refuses a block whose only cycle word is R or L; Fanuc drills
//!   on R too. A block with none of them (only F, S, M …) stores its words and drills nothing, on both.
//! * **K0 / L0** stores the block's words and drills nothing (Fanuc); LinuxCNC refuses L0.
//! * **Sticky words across cycle codes**: R, Z, P, Q stay when the cycle code changes (Fanuc);
//!   LinuxCNC wants R and Z again (and P, Q) on each change of code. G80 forgets them all (LinuxCNC
//!   keeps its P and Q across G80).
//! * **G84 / G74 retract**: LinuxCNC feeds out of the hole straight to the return level (under G98
//!   the initial level) and dwells P after the reversal; Fanuc dwells at the bottom, feeds to R,
//!   dwells, then rapids to the initial level. LinuxCNC's is kept (it has the cycle). LinuxCNC 2.9
//!   swaps the axes of G84/G74's two feeds in G18 and G19 (`cycle_feed(…, bottom_z, x, y)`, see the
//!   `g84_g19` trace); fmsvm feeds along the normal axis as in G17.
//! * **Positioning when the return level rises** (a G98 hole after a G99 one): LinuxCNC rapids to
//!   the hole at the new return level, the initial level, and then down to R, so at the same XY the
//!   tool goes up to the initial level and back; a Fanuc positions at the level the tool is at and
//!   goes to R from there. LinuxCNC's is kept (its trace is the oracle): a detour upwards, never a
//!   collision, and a dialect with native cycles writes the hole as the control's own block.
//! * **G88**: LinuxCNC stops the program at the bottom and then restarts the spindle, assuming the
//!   operator took the tool out. Fanuc, after the manual retract and cycle start, rapids to the
//!   return level and starts the spindle: fmsvm emits `Stop`, `Rapid` to the return level above the
//!   hole, then the spindle. (LinuxCNC has no such rapid.)
//! * **G76** (fine boring; LinuxCNC's G76 is a lathe threading cycle) and **G87** (back boring,
//!   Fanuc's; LinuxCNC's takes I J K and is another cycle) follow Fanuc: see [`expand`].
//! * Spindle checks (LinuxCNC refuses G84 unless the spindle turns clockwise, G74 unless
//!   counter-clockwise, G86 G87 G88 unless it turns) are the kernel's: [`CycleBlock::spindle_ccw`]
//!   only says which way to restart it.
//! * LinuxCNC checks Q > 0 after the positioning moves of the hole; fmsvm before any move.

use fmsvm_block::alarms::{IMPROPER_G, MINUS_SIGN, NO_FANUC_NUMBER};
use fmsvm_block::{Alarm, Code, Stop};

use fmsvm_canon::{Plane, Pose};

/// Fanuc alarm 045: address Q not found (G73/G83), or Q0.
const Q_NOT_FOUND: u32 = 45;

/// The most pecks of one hole of G73/G83 (Q0.01 down 100 mm); a smaller Q is alarm 045.
pub const MAX_PECKS: u32 = 10_000;

/// The sticky words of a canned-cycle mode: kept from block to block until G80 or a group-01 motion
/// code ([`CycleModal::cancel`]).
#[derive(Clone, Copy, PartialEq, Debug, Default)]
pub struct CycleModal {
    /// Normal-axis position at the first drilling block of the mode (program coordinates).
    initial: Option<f64>,
    /// R as programmed (a level under G90, a distance from the initial level under G91).
    r: Option<f64>,
    /// The normal-axis word as programmed (the bottom under G90, a distance from R under G91).
    depth: Option<f64>,
    /// Q: peck depth (G73 G83) or shift (G76 G87).
    q: Option<f64>,
    /// P, Fanuc milliseconds.
    p: Option<f64>,
    /// Shift words (I J in G17) for G76 G87, plane coordinates.
    shift: [Option<f64>; 2],
}

impl CycleModal {
    /// Forgets every sticky word and the initial level (G80, G0 G1 G2 G3 …, reset).
    pub fn cancel(&mut self) {
        *self = CycleModal::default();
    }

    /// The initial level of the mode (normal axis), once a block has drilled.
    pub fn initial_level(&self) -> Option<f64> {
        self.initial
    }

    /// R as it stands (a level where the blocks gave levels, as a lathe's cycles are handed in).
    pub fn r_word(&self) -> Option<f64> {
        self.r
    }

    /// Q as it stands: the peck depth of the mode.
    pub fn q_word(&self) -> Option<f64> {
        self.q
    }

    /// P as it stands (milliseconds).
    pub fn p_word(&self) -> Option<f64> {
        self.p
    }
}

/// A canned cycle of group 09 (G80, its cancel, is no cycle): decoded once from the G code, so a
/// `CycleBlock` holds only cycles.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub enum Cycle {
    /// Peck drilling, high speed (retract `g73_retract`).
    G73,
    /// Left-hand tapping.
    G74,
    /// Fine boring (oriented stop, shift out).
    G76,
    /// Drilling.
    #[default]
    G81,
    /// Drilling with dwell.
    G82,
    /// Peck drilling (out to R).
    G83,
    /// Tapping.
    G84,
    /// Boring, feed out.
    G85,
    /// Boring, spindle stop, rapid out.
    G86,
    /// Back boring.
    G87,
    /// Boring, dwell, manual out.
    G88,
    /// Boring, dwell, feed out.
    G89,
}

impl Cycle {
    /// Every cycle with its code.
    const ALL: [(Cycle, Code); 12] = [
        (Cycle::G73, Code::G73),
        (Cycle::G74, Code::G74),
        (Cycle::G76, Code::G76),
        (Cycle::G81, Code::G81),
        (Cycle::G82, Code::G82),
        (Cycle::G83, Code::G83),
        (Cycle::G84, Code::G84),
        (Cycle::G85, Code::G85),
        (Cycle::G86, Code::G86),
        (Cycle::G87, Code::G87),
        (Cycle::G88, Code::G88),
        (Cycle::G89, Code::G89),
    ];

    /// The cycle of G code `code`, or alarm 0010 for a code that is not one.
    pub fn of(code: Code) -> Result<Cycle, Alarm> {
        Cycle::ALL
            .iter()
            .find(|(_, c)| *c == code)
            .map(|&(cycle, _)| cycle)
            .ok_or_else(|| {
                Alarm::new(
                    IMPROPER_G,
                    format!("G{code} is not a canned cycle (G73 G74 G76 G81-G89)"),
                )
            })
    }

    /// The cycle's G code.
    pub fn code(self) -> Code {
        Cycle::ALL[self as usize].1
    }
}

/// One block in a canned-cycle mode, as the kernel decoded it.
#[derive(Clone, Copy, PartialEq, Debug, Default)]
pub struct CycleBlock {
    /// The cycle.
    pub cycle: Cycle,
    /// The plane (G17 G18 G19).
    pub plane: Plane,
    /// G91 (incremental) rather than G90.
    pub incremental: bool,
    /// G99 (return to R) rather than G98 (return to the initial level).
    pub retract_to_r: bool,
    /// The plane's first and second axis words of this block (X Y in G17, Z X in G18, Y Z in G19), as
    /// programmed (increments under G91).
    pub at: [Option<f64>; 2],
    /// The normal-axis word (Z in G17, Y in G18, X in G19): the hole bottom (G87: the top of the back
    /// bore).
    pub depth: Option<f64>,
    /// R: the level the feed starts from (G87: the bottom, below the hole).
    pub r: Option<f64>,
    /// Q: peck depth for G73 G83 (> 0), shift for G76 G87 (sign ignored).
    pub q: Option<f64>,
    /// P: dwell in Fanuc **milliseconds** (P1000 = 1 s), as Fanuc writes it in a cycle.
    pub p: Option<f64>,
    /// K (or L): how many times to drill; not sticky. 0 stores the words and drills nothing.
    pub repeats: Option<f64>,
    /// Shift for G76 G87 in plane coordinates, used instead of Q when either is given (Fanuc's SIJ
    /// option: I J in G17, K I in G18, J K in G19; the kernel maps the letters). Sticky.
    pub shift: [Option<f64>; 2],
    /// The spindle turns counter-clockwise (M4) as the cycle starts: G76 G86 G87 G88 restart it that
    /// way (LinuxCNC restarts "in the direction it was going"; Fanuc always M3).
    pub spindle_ccw: bool,
}

/// What the spindle does in a cycle.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum SpindleAction {
    /// M5.
    Stop,
    /// M3.
    Clockwise,
    /// M4.
    CounterClockwise,
    /// Oriented spindle stop (M19): the spindle stops at its orientation angle.
    Orient,
}

/// One thing a cycle does.
#[derive(Clone, Copy, PartialEq, Debug)]
pub enum Step {
    /// Straight move at rapid traverse to the point (program coordinates, all six axes).
    Rapid(Pose),
    /// Straight move at the feed rate.
    Feed(Pose),
    /// Dwell, seconds.
    Dwell(f64),
    /// A spindle change.
    Spindle(SpindleAction),
    /// Program stop (M0): G88's manual retract.
    Stop,
}

/// Which way G76 and G87 shift the tool off the bore wall when the shift is given by Q (Fanuc
/// 0i parameter 5101 bits RD1 RD2; 15i parameter 6240).
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub enum ShiftDirection {
    /// + first axis of the plane (G17 +X, G18 +Z, G19 +Y): RD2 RD1 = 0 0, the default.
    #[default]
    PlusFirst,
    /// − first axis (G17 −X, G18 −Z, G19 −Y): RD2 RD1 = 0 1.
    MinusFirst,
    /// + second axis (G17 +Y, G18 +X, G19 +Z): RD2 RD1 = 1 0.
    PlusSecond,
    /// − second axis (G17 −Y, G18 −X, G19 −Z): RD2 RD1 = 1 1.
    MinusSecond,
}

/// Machine parameters of the cycles.
#[derive(Clone, Copy, PartialEq, Debug)]
pub struct CycleParams {
    /// G73 back-off after each peck, **mm** (Fanuc parameter 5114); converted for inch programs.
    pub g73_retract: f64,
    /// G83 clearance above the previous peck when rapiding back in, **mm** (Fanuc parameter 5115).
    pub g83_clearance: f64,
    /// Direction of the G76 / G87 shift given by Q.
    pub shift_direction: ShiftDirection,
    /// The retract of a Haas one-block G71/G72 (Haas Setting 73, NGC 287), program units; None:
    /// not known, and such a cycle is refused.
    pub stock_retract: Option<f64>,
    /// A Haas one-block G76's finish allowance (Setting 86), program units; None: not known.
    pub thread_allowance: Option<f64>,
    /// Its least cut (Setting 99), program units; None: not known.
    pub thread_least: Option<f64>,
    /// Its end chamfer (Setting 95), in threads, 0 none; None: not known.
    pub thread_chamfer: Option<f64>,
}

impl Default for CycleParams {
    /// LinuxCNC's: 0.010 inch (0.254 mm) for both, the shift along + first axis.
    fn default() -> Self {
        CycleParams {
            g73_retract: 0.254,
            g83_clearance: 0.254,
            shift_direction: ShiftDirection::PlusFirst,
            stock_retract: None,
            thread_allowance: None,
            thread_least: None,
            thread_chamfer: None,
        }
    }
}

/// A word, or none if it is missing or vacant (a vacant `#` variable is an omitted word).
fn word(v: Option<f64>) -> Option<f64> {
    v.filter(|x| !x.is_nan())
}

fn alarm(number: u32, message: String) -> Stop {
    Stop::Alarm(Alarm::new(number, message))
}

/// The repeat count of a block: 1 when omitted.
fn repeat_count(k: Option<f64>) -> Result<u32, Stop> {
    match k {
        None => Ok(1),
        Some(k) if (0.0..=9999.0).contains(&k) && k.fract() == 0.0 => Ok(k as u32),
        Some(k) => Err(alarm(
            NO_FANUC_NUMBER,
            format!("canned cycle repeat count K{k}: it must be a whole number from 0 to 9999"),
        )),
    }
}

/// Expands one block of a canned-cycle mode: updates the sticky words in `modal`, then, if the block
/// drills (see the module doc), hands each step to `out` and returns where the tool ends (the hole, at
/// the return level). A block that drills nothing returns `start` and makes no step.
///
/// `start` is where the tool is (program coordinates; A B C are carried unchanged into every step).
/// `inch` scales the mm parameters of `params`.
///
/// Per hole, after the positioning of the module doc (R = the R level, Z = the bottom, P = the dwell,
/// "out" = the return level):
///
/// * G81: feed to Z, rapid out. G82: feed to Z, dwell, rapid out.
/// * G73: feeds of Q from R, each followed by a rapid back-off of `g73_retract`; feed to Z; rapid out.
/// * G83: feeds of Q from R, each followed by a rapid to R and a rapid back in to `g83_clearance`
///   above the last depth; feed to Z; rapid out.
/// * G84 (G74): feed to Z, spindle stop, counter-clockwise (G74 clockwise), dwell, feed out, spindle
///   stop, clockwise (G74 counter-clockwise).
/// * G85: feed to Z, feed to R, rapid out. G89: feed to Z, dwell, feed out to the return level (the
///   initial level under G98: LinuxCNC's `g89_g98` trace; a Fanuc or FMS-3000 G89 block feeds only
///   to R, so such a hole is written as its moves, `native_cycle_op`).
/// * G86: feed to Z, dwell, spindle stop, rapid out, spindle restart.
/// * G88: feed to Z, dwell, spindle stop, program stop (the operator retracts the tool), rapid out,
///   spindle restart (Fanuc; see the module doc).
/// * G76 (Fanuc fine boring): feed to Z, dwell, oriented stop, rapid shift off the wall, rapid out,
///   rapid shift back, spindle restart.
/// * G87 (Fanuc back boring; R is below the hole, Z is the top of the back bore, the return is always
///   the initial level, G99 or not): rapid over the hole at the start level, oriented stop, rapid
///   shift, rapid down to R, rapid shift back, spindle restart, feed up to Z, dwell, oriented stop,
///   rapid shift, rapid up to the initial level, rapid shift back, spindle restart.
///
/// The G76/G87 shift is I J ([`CycleBlock::shift`]) if given, else |Q| along
/// [`CycleParams::shift_direction`], else none.
///
/// Alarms: a code that is not a cycle (010); Q missing or not > 0 in G73/G83 (045); negative P (006);
/// no R or no Z in the mode, R below Z (G87: above), a repeat count that is not 0–9999 (0). Errors of
/// `out` come back as they are.
pub fn expand(
    modal: &mut CycleModal,
    b: &CycleBlock,
    start: Pose,
    inch: bool,
    params: &CycleParams,
    out: &mut dyn FnMut(Step) -> Result<(), Stop>,
) -> Result<Pose, Stop> {
    let at = [word(b.at[0]), word(b.at[1])];
    let repeats = word(b.repeats);
    // Sticky words first: a block that drills nothing still sets them (Fanuc K0).
    set_sticky_words(modal, b)?;
    let count = repeat_count(repeats)?;
    let drills = at.iter().any(Option::is_some)
        || word(b.depth).is_some()
        || word(b.r).is_some()
        || repeats.is_some();
    if !drills || count == 0 {
        return Ok(start);
    }
    let (a1, a2, n) = b.plane.axes();
    let lv = levels(modal, b, start[n])?;
    let hole = Hole {
        cycle: b.cycle,
        lv,
        dwell: modal.p.unwrap_or(0.0) / 1000.0,
        restart: if b.spindle_ccw {
            SpindleAction::CounterClockwise
        } else {
            SpindleAction::Clockwise
        },
        shift: bore_shift(modal, params.shift_direction),
        back_off: match b.cycle {
            Cycle::G73 => params.g73_retract,
            _ => params.g83_clearance,
        } * if inch { 1.0 / 25.4 } else { 1.0 },
    };
    // The hole: G90 at the words (the tool's position where one is missing), G91 stepped each repeat.
    let (mut h1, mut h2) = if b.incremental {
        (start[a1], start[a2])
    } else {
        (at[0].unwrap_or(start[a1]), at[1].unwrap_or(start[a2]))
    };
    let step = if b.incremental {
        [at[0].unwrap_or(0.0), at[1].unwrap_or(0.0)]
    } else {
        [0.0, 0.0]
    };
    let point = |p1: f64, p2: f64, level: f64| {
        let mut p = start;
        p[a1] = p1;
        p[a2] = p2;
        p[n] = level;
        p
    };
    // G87 starts over the hole at the start level and always returns to the initial level. The
    // others, from LinuxCNC: from below R, first straight up to R, which is then the G98 level too.
    let mut current = start[n];
    let mut old = lv.initial;
    if b.cycle != Cycle::G87 && old < lv.r {
        out(Step::Rapid(point(start[a1], start[a2], lv.r)))?;
        old = lv.r;
        current = lv.r;
    }
    let clear = match b.cycle {
        Cycle::G87 => lv.initial,
        _ if b.retract_to_r => lv.r,
        _ => old,
    };
    for i in 0..count {
        h1 += step[0];
        h2 += step[1];
        let at = |level: f64| point(h1, h2, level);
        let off = |level: f64| point(h1 + hole.shift[0], h2 + hole.shift[1], level);
        if b.cycle == Cycle::G87 {
            let level = if i == 0 { current } else { lv.initial };
            back_bore(&hole, level, &at, &off, out)?;
            continue;
        }
        if i == 0 && current > lv.r {
            out(Step::Rapid(at(current)))?;
            out(Step::Rapid(at(lv.r)))?;
        } else {
            out(Step::Rapid(at(clear)))?;
            if clear > lv.r {
                out(Step::Rapid(at(lv.r)))?;
            }
        }
        drill(&hole, clear, &at, &off, out)?;
    }
    Ok(point(h1, h2, clear))
}

/// A cycle block's sticky words into the mode: P (a negative dwell is alarm 0006), Q, R, the depth
/// and the G76/G87 shift.
fn set_sticky_words(modal: &mut CycleModal, b: &CycleBlock) -> Result<(), Stop> {
    if let Some(p) = word(b.p) {
        if p < 0.0 {
            return Err(alarm(
                MINUS_SIGN,
                format!("illegal use of minus sign: dwell P{p} in a canned cycle"),
            ));
        }
        modal.p = Some(p);
    }
    if let Some(q) = word(b.q) {
        modal.q = Some(q);
    }
    if let Some(r) = word(b.r) {
        modal.r = Some(r);
    }
    if let Some(d) = word(b.depth) {
        modal.depth = Some(d);
    }
    for (m, s) in modal.shift.iter_mut().zip(b.shift) {
        if let Some(s) = word(s) {
            *m = Some(s);
        }
    }
    Ok(())
}

/// The levels of a block that drills, in program coordinates of the normal axis.
#[derive(Clone, Copy)]
struct Levels {
    /// The initial level (G98's return), kept from the first block of the mode.
    initial: f64,
    /// The R level (G87: the bottom the tool rapids down to, below the hole).
    r: f64,
    /// The bottom of the hole (G87: the top of the back bore).
    bottom: f64,
    /// The peck depth of G73/G83 (0 for the others).
    peck: f64,
}

/// The levels of a block that drills, checked before anything moves: R and the depth given in the
/// mode, R above the bottom (G87: below the top), G73/G83's Q greater than 0 and at most
/// [`MAX_PECKS`] pecks.
fn levels(modal: &mut CycleModal, b: &CycleBlock, start_level: f64) -> Result<Levels, Stop> {
    let g = b.cycle.code();
    let axis = fmsvm_canon::AXES[b.plane.axes().2].as_str();
    let r_programmed = modal.r.ok_or_else(|| {
        alarm(
            NO_FANUC_NUMBER,
            format!("G{g}: no R level given in the canned cycle mode"),
        )
    })?;
    let depth_programmed = modal.depth.ok_or_else(|| {
        alarm(
            NO_FANUC_NUMBER,
            format!("G{g}: no {axis} depth given in the canned cycle mode"),
        )
    })?;
    let peck = if matches!(b.cycle, Cycle::G73 | Cycle::G83) {
        match modal.q {
            Some(q) if q > 0.0 => q,
            Some(q) => {
                return Err(alarm(
                    Q_NOT_FOUND,
                    format!("G{g}: the peck depth Q{q} must be greater than 0"),
                ));
            }
            None => {
                return Err(alarm(
                    Q_NOT_FOUND,
                    format!("G{g}: address Q (the peck depth) not found"),
                ));
            }
        }
    } else {
        0.0
    };
    let initial = *modal.initial.get_or_insert(start_level);
    let (r, bottom) = if b.incremental {
        let r = initial + r_programmed;
        (r, r + depth_programmed)
    } else {
        (r_programmed, depth_programmed)
    };
    if b.cycle == Cycle::G87 {
        if r > bottom {
            return Err(alarm(
                NO_FANUC_NUMBER,
                format!("G87: R {r} is above the top of the back bore {axis}{bottom}"),
            ));
        }
    } else if r < bottom {
        return Err(alarm(
            NO_FANUC_NUMBER,
            format!("G{g}: R {r} is below the bottom {axis}{bottom}"),
        ));
    }
    // A peck is a move of its own: bounded, so that one block cannot expand for ever (Q0.0000001
    // down 100 mm would be a billion pecks). No control documents a limit; this one is ours.
    if peck > 0.0 && (r - bottom) / peck > MAX_PECKS as f64 {
        return Err(alarm(
            Q_NOT_FOUND,
            format!(
                "G{g}: the peck depth Q{peck} makes {:.0} pecks from R {r} to {axis}{bottom} (at most {MAX_PECKS}): give a larger Q",
                ((r - bottom) / peck).ceil()
            ),
        ));
    }
    Ok(Levels {
        initial,
        r,
        bottom,
        peck,
    })
}

/// What every hole of a block shares.
struct Hole {
    cycle: Cycle,
    lv: Levels,
    /// P, seconds.
    dwell: f64,
    /// The spindle direction the block runs in, restored after a stop.
    restart: SpindleAction,
    /// G76/G87's shift off the hole's axis, plane coordinates.
    shift: [f64; 2],
    /// G73's back-off or G83's clearance, program units.
    back_off: f64,
}

/// One hole's steps from the R level to the return level `clear` (every cycle but G87); `at` and
/// `off` give a point on the hole's axis and shifted off it.
fn drill(
    h: &Hole,
    clear: f64,
    at: &dyn Fn(f64) -> Pose,
    off: &dyn Fn(f64) -> Pose,
    out: &mut dyn FnMut(Step) -> Result<(), Stop>,
) -> Result<(), Stop> {
    let Levels {
        r, bottom, peck, ..
    } = h.lv;
    let (dwell, restart) = (h.dwell, h.restart);
    let steps: &[Step] = match h.cycle {
        Cycle::G81 => &[Step::Feed(at(bottom)), Step::Rapid(at(clear))],
        Cycle::G82 => &[
            Step::Feed(at(bottom)),
            Step::Dwell(dwell),
            Step::Rapid(at(clear)),
        ],
        Cycle::G73 | Cycle::G83 => {
            // LinuxCNC's loop, to the bit: depths r − q, r − 2q … by repeated subtraction.
            let mut d = r - peck;
            while d > bottom {
                out(Step::Feed(at(d)))?;
                if h.cycle == Cycle::G83 {
                    out(Step::Rapid(at(r)))?;
                }
                out(Step::Rapid(at(d + h.back_off)))?;
                d -= peck;
            }
            &[Step::Feed(at(bottom)), Step::Rapid(at(clear))]
        }
        Cycle::G84 => &[
            Step::Feed(at(bottom)),
            Step::Spindle(SpindleAction::Stop),
            Step::Spindle(SpindleAction::CounterClockwise),
            Step::Dwell(dwell),
            Step::Feed(at(clear)),
            Step::Spindle(SpindleAction::Stop),
            Step::Spindle(SpindleAction::Clockwise),
        ],
        Cycle::G74 => &[
            Step::Feed(at(bottom)),
            Step::Spindle(SpindleAction::Stop),
            Step::Spindle(SpindleAction::Clockwise),
            Step::Dwell(dwell),
            Step::Feed(at(clear)),
            Step::Spindle(SpindleAction::Stop),
            Step::Spindle(SpindleAction::CounterClockwise),
        ],
        Cycle::G85 => &[
            Step::Feed(at(bottom)),
            Step::Feed(at(r)),
            Step::Rapid(at(clear)),
        ],
        Cycle::G86 => &[
            Step::Feed(at(bottom)),
            Step::Dwell(dwell),
            Step::Spindle(SpindleAction::Stop),
            Step::Rapid(at(clear)),
            Step::Spindle(restart),
        ],
        Cycle::G88 => &[
            Step::Feed(at(bottom)),
            Step::Dwell(dwell),
            Step::Spindle(SpindleAction::Stop),
            Step::Stop,
            Step::Rapid(at(clear)),
            Step::Spindle(restart),
        ],
        Cycle::G89 => &[
            Step::Feed(at(bottom)),
            Step::Dwell(dwell),
            Step::Feed(at(clear)),
        ],
        Cycle::G76 => &[
            Step::Feed(at(bottom)),
            Step::Dwell(dwell),
            Step::Spindle(SpindleAction::Orient),
            Step::Rapid(off(bottom)),
            Step::Rapid(off(clear)),
            Step::Rapid(at(clear)),
            Step::Spindle(restart),
        ],
        // The back bore goes down beside the hole and bores upwards: `back_bore`.
        Cycle::G87 => return back_bore(h, clear, at, off, out),
    };
    steps.iter().try_for_each(|s| out(*s))
}

/// Fanuc's G87 back boring at one hole, from `level` over it (the weihong.com.cn G87 page; Fanuc
/// 0i/15i describe the same sequence): the oriented tool goes down through the hole shifted off its
/// axis to R, boring upwards from R to Z, and back up shifted to the initial level.
fn back_bore(
    h: &Hole,
    level: f64,
    at: &dyn Fn(f64) -> Pose,
    off: &dyn Fn(f64) -> Pose,
    out: &mut dyn FnMut(Step) -> Result<(), Stop>,
) -> Result<(), Stop> {
    let Levels {
        initial,
        r,
        bottom: top,
        ..
    } = h.lv;
    [
        Step::Rapid(at(level)),
        Step::Spindle(SpindleAction::Orient),
        Step::Rapid(off(level)),
        Step::Rapid(off(r)),
        Step::Rapid(at(r)),
        Step::Spindle(h.restart),
        Step::Feed(at(top)),
        Step::Dwell(h.dwell),
        Step::Spindle(SpindleAction::Orient),
        Step::Rapid(off(top)),
        Step::Rapid(off(initial)),
        Step::Rapid(at(initial)),
        Step::Spindle(h.restart),
    ]
    .into_iter()
    .try_for_each(&mut *out)
}

/// The G76 / G87 shift in plane coordinates: the shift words if any, else |Q| along `direction`.
fn bore_shift(modal: &CycleModal, direction: ShiftDirection) -> [f64; 2] {
    if modal.shift.iter().any(Option::is_some) {
        return [modal.shift[0].unwrap_or(0.0), modal.shift[1].unwrap_or(0.0)];
    }
    let q = modal.q.map_or(0.0, f64::abs);
    match direction {
        ShiftDirection::PlusFirst => [q, 0.0],
        ShiftDirection::MinusFirst => [-q, 0.0],
        ShiftDirection::PlusSecond => [0.0, q],
        ShiftDirection::MinusSecond => [0.0, -q],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A G81 block with nothing in it, G90 G98 G17, spindle clockwise: the tests fill it in.
    const NONE: CycleBlock = CycleBlock {
        cycle: Cycle::G81,
        plane: Plane::XY,
        incremental: false,
        retract_to_r: false,
        at: [None, None],
        depth: None,
        r: None,
        q: None,
        p: None,
        repeats: None,
        shift: [None, None],
        spindle_ccw: false,
    };

    fn pose(v: &[f64]) -> Pose {
        let mut p = [0.0; 6];
        p.copy_from_slice(v);
        p
    }

    /// The steps of canonical calls as `rs274 -g` prints them (rs274's line counter and N field cut
    /// off, as `runtime/kernel/tests/cycles/regenerate.sh` writes them); `//` lines are comments.
    fn parse(trace: &str) -> Vec<Step> {
        let mut steps = Vec::new();
        for line in trace.lines().map(str::trim) {
            if line.is_empty() || line.starts_with("//") {
                continue;
            }
            let (name, args) = line.split_once('(').expect("a call");
            let args: Vec<f64> = args
                .trim_end_matches(')')
                .split(',')
                .filter(|a| !a.trim().is_empty())
                .map(|a| a.trim().parse().expect("a number"))
                .collect();
            steps.push(match name {
                "STRAIGHT_TRAVERSE" => Step::Rapid(pose(&args)),
                "STRAIGHT_FEED" => Step::Feed(pose(&args)),
                "DWELL" => Step::Dwell(args[0]),
                "STOP_SPINDLE_TURNING" => Step::Spindle(SpindleAction::Stop),
                "START_SPINDLE_CLOCKWISE" => Step::Spindle(SpindleAction::Clockwise),
                "START_SPINDLE_COUNTERCLOCKWISE" => Step::Spindle(SpindleAction::CounterClockwise),
                "ORIENT_SPINDLE" => Step::Spindle(SpindleAction::Orient),
                "PROGRAM_STOP" => Step::Stop,
                _ => panic!("unknown canonical call {line}"),
            });
        }
        steps
    }

    /// Expands `blocks` one after the other from `start` (the kernel's part: the tool ends where
    /// each block leaves it), with LinuxCNC's parameters.
    fn run(start: Pose, inch: bool, blocks: &[CycleBlock]) -> Result<(Vec<Step>, Pose), Stop> {
        run_with(start, inch, &CycleParams::default(), blocks)
    }

    fn run_with(
        start: Pose,
        inch: bool,
        params: &CycleParams,
        blocks: &[CycleBlock],
    ) -> Result<(Vec<Step>, Pose), Stop> {
        let mut modal = CycleModal::default();
        let mut steps = Vec::new();
        let mut at = start;
        for b in blocks {
            at = expand(&mut modal, b, at, inch, params, &mut |s| {
                steps.push(s);
                Ok(())
            })?;
        }
        Ok((steps, at))
    }

    fn close(a: &Pose, b: &Pose) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-4)
    }

    fn same(a: &Step, b: &Step) -> bool {
        match (a, b) {
            (Step::Rapid(p), Step::Rapid(q)) | (Step::Feed(p), Step::Feed(q)) => close(p, q),
            (Step::Dwell(s), Step::Dwell(t)) => (s - t).abs() < 1e-4,
            _ => a == b,
        }
    }

    /// Runs `blocks` and compares the steps with `trace` and the end with `end`, to 1e-4.
    #[track_caller]
    fn check(start: Pose, inch: bool, blocks: &[CycleBlock], trace: &str, end: Pose) {
        let (steps, at) = run(start, inch, blocks).expect("no alarm");
        let want = parse(trace);
        let ok = steps.len() == want.len() && steps.iter().zip(&want).all(|(a, b)| same(a, b));
        assert!(ok, "steps differ\n got: {steps:#?}\nwant: {want:#?}",);
        assert!(close(&at, &end), "ends at {at:?}, want {end:?}");
    }

    #[track_caller]
    fn alarm_of(r: Result<(Vec<Step>, Pose), Stop>) -> (u32, String) {
        match r {
            Err(Stop::Alarm(a)) => (a.number, a.message.into_owned()),
            Err(other) => panic!("not an alarm: {other}"),
            Ok((steps, _)) => panic!("no alarm; steps {steps:?}"),
        }
    }

    const XYZ10: Pose = [0.0, 0.0, 10.0, 0.0, 0.0, 0.0];

    // In each test below taken from LinuxCNC, the expected steps are the lines of
    // runtime/kernel/tests/cycles/NAME.trace (rs274 -g NAME.ngc) from the cycle's first move to the last
    // step before the program end (M2 stops the spindle); NAME is the test's. The program's text is
    // quoted in the comment, one block a `/`. A Fanuc P in ms is written in seconds in the .ngc.

    #[test]
    fn g81_g98() {
        // G21 G17 G90 G94 F100 S1000 M3 / G0 X0 Y0 Z10 / G98 G81 X1 Y2 Z-5 R2 / X3 / Y4 Z-3 / G80
        let first = CycleBlock {
            cycle: Cycle::G81,
            at: [Some(1.0), Some(2.0)],
            depth: Some(-5.0),
            r: Some(2.0),
            ..NONE
        };
        let x3 = CycleBlock {
            cycle: Cycle::G81,
            at: [Some(3.0), None],
            ..NONE
        };
        let y4 = CycleBlock {
            cycle: Cycle::G81,
            at: [None, Some(4.0)],
            depth: Some(-3.0),
            ..NONE
        };
        check(
            XYZ10,
            false,
            &[first, x3, y4],
            "
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(3.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(3.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(3.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(3.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(3.0000, 4.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(3.0000, 4.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(3.0000, 4.0000, -3.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(3.0000, 4.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        ",
            [3.0, 4.0, 10.0, 0.0, 0.0, 0.0],
        );
    }

    #[test]
    fn g81_g99_then_r_raised_then_g98_g99_per_block() {
        // G99 G81 X1 Y2 Z-5 R2 / X3 R3 / G98 X5 / G99 X6 (from X0 Y0 Z10). A new R under G99 and the
        // G98 block after G99 position diagonally to the return level (LinuxCNC's CYCLE_MACRO).
        let g99 = CycleBlock {
            cycle: Cycle::G81,
            retract_to_r: true,
            ..NONE
        };
        let blocks = [
            CycleBlock {
                at: [Some(1.0), Some(2.0)],
                depth: Some(-5.0),
                r: Some(2.0),
                ..g99
            },
            CycleBlock {
                at: [Some(3.0), None],
                r: Some(3.0),
                ..g99
            },
            CycleBlock {
                cycle: Cycle::G81,
                at: [Some(5.0), None],
                ..NONE
            },
            CycleBlock {
                at: [Some(6.0), None],
                ..g99
            },
        ];
        check(
            XYZ10,
            false,
            &blocks,
            "
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(3.0000, 2.0000, 3.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(3.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(3.0000, 2.0000, 3.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(5.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(5.0000, 2.0000, 3.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(5.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(5.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(6.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(6.0000, 2.0000, 3.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(6.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(6.0000, 2.0000, 3.0000, 0.0000, 0.0000, 0.0000)
        ",
            [6.0, 2.0, 3.0, 0.0, 0.0, 0.0],
        );
    }

    #[test]
    fn g81_starting_below_r() {
        // G0 X0 Y0 Z0 / G98 G81 X1 Y2 Z-5 R2 / X3: up to R first; R is then the G98 level too (and
        // LinuxCNC repeats the move up to R, of length 0, in the second block).
        let blocks = [
            CycleBlock {
                cycle: Cycle::G81,
                at: [Some(1.0), Some(2.0)],
                depth: Some(-5.0),
                r: Some(2.0),
                ..NONE
            },
            CycleBlock {
                cycle: Cycle::G81,
                at: [Some(3.0), None],
                ..NONE
            },
        ];
        check(
            [0.0; 6],
            false,
            &blocks,
            "
            STRAIGHT_TRAVERSE(0.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(3.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(3.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(3.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        ",
            [3.0, 2.0, 2.0, 0.0, 0.0, 0.0],
        );
    }

    #[test]
    fn g81_g91_g98_repeats_step() {
        // G91 G98 G81 X10 Y5 Z-7 R-8 L3 / X-5 L2 (from X0 Y0 Z10): R = 10 - 8 = 2, bottom = 2 - 7 = -5.
        let blocks = [
            CycleBlock {
                cycle: Cycle::G81,
                incremental: true,
                at: [Some(10.0), Some(5.0)],
                depth: Some(-7.0),
                r: Some(-8.0),
                repeats: Some(3.0),
                ..NONE
            },
            CycleBlock {
                cycle: Cycle::G81,
                incremental: true,
                at: [Some(-5.0), None],
                repeats: Some(2.0),
                ..NONE
            },
        ];
        check(
            XYZ10,
            false,
            &blocks,
            "
            STRAIGHT_TRAVERSE(10.0000, 5.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(10.0000, 5.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(10.0000, 5.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(10.0000, 5.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(20.0000, 10.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(20.0000, 10.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(20.0000, 10.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(20.0000, 10.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(30.0000, 15.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(30.0000, 15.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(30.0000, 15.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(30.0000, 15.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(25.0000, 15.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(25.0000, 15.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(25.0000, 15.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(25.0000, 15.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(20.0000, 15.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(20.0000, 15.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(20.0000, 15.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(20.0000, 15.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        ",
            [20.0, 15.0, 10.0, 0.0, 0.0, 0.0],
        );
    }

    #[test]
    fn g81_g91_g99_r_from_the_initial_level() {
        // G91 G99 G81 X10 Z-7 R-8 L2 / Y5 R-6 (from X0 Y0 Z10): the new R is 10 - 6 = 4, from the
        // initial level, not from where the tool is (R2).
        let blocks = [
            CycleBlock {
                cycle: Cycle::G81,
                incremental: true,
                retract_to_r: true,
                at: [Some(10.0), None],
                depth: Some(-7.0),
                r: Some(-8.0),
                repeats: Some(2.0),
                ..NONE
            },
            CycleBlock {
                cycle: Cycle::G81,
                incremental: true,
                retract_to_r: true,
                at: [None, Some(5.0)],
                r: Some(-6.0),
                ..NONE
            },
        ];
        check(
            XYZ10,
            false,
            &blocks,
            "
            STRAIGHT_TRAVERSE(10.0000, 0.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(10.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(10.0000, 0.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(10.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(20.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(20.0000, 0.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(20.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(20.0000, 5.0000, 4.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(20.0000, 5.0000, -3.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(20.0000, 5.0000, 4.0000, 0.0000, 0.0000, 0.0000)
        ",
            [20.0, 5.0, 4.0, 0.0, 0.0, 0.0],
        );
    }

    #[test]
    fn g81_g90_repeats_the_same_hole() {
        // G99 G81 X1 Y2 Z-5 R2 L3 (from X0 Y0 Z10)
        let b = CycleBlock {
            cycle: Cycle::G81,
            retract_to_r: true,
            at: [Some(1.0), Some(2.0)],
            depth: Some(-5.0),
            r: Some(2.0),
            repeats: Some(3.0),
            ..NONE
        };
        check(
            XYZ10,
            false,
            &[b],
            "
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        ",
            [1.0, 2.0, 2.0, 0.0, 0.0, 0.0],
        );
    }

    #[test]
    fn g81_g18_drills_along_y() {
        // G18 / G0 X0 Y10 Z0 / G98 G81 Z1 X2 Y-5 R2 / Z3: the plane words are (Z, X), the depth is Y.
        let g18 = CycleBlock {
            cycle: Cycle::G81,
            plane: Plane::ZX,
            ..NONE
        };
        let blocks = [
            CycleBlock {
                at: [Some(1.0), Some(2.0)],
                depth: Some(-5.0),
                r: Some(2.0),
                ..g18
            },
            CycleBlock {
                at: [Some(3.0), None],
                ..g18
            },
        ];
        let start = [0.0, 10.0, 0.0, 0.0, 0.0, 0.0];
        check(
            start,
            false,
            &blocks,
            "
            STRAIGHT_TRAVERSE(2.0000, 10.0000, 1.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(2.0000, 2.0000, 1.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(2.0000, -5.0000, 1.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(2.0000, 10.0000, 1.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(2.0000, 10.0000, 3.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(2.0000, 2.0000, 3.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(2.0000, -5.0000, 3.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(2.0000, 10.0000, 3.0000, 0.0000, 0.0000, 0.0000)
        ",
            [2.0, 10.0, 3.0, 0.0, 0.0, 0.0],
        );
    }

    #[test]
    fn g81_g19_drills_along_x() {
        // G19 / G0 X10 Y0 Z0 / G99 G81 Y1 Z2 X-5 R2 / Y3: the plane words are (Y, Z), the depth is X.
        let g19 = CycleBlock {
            cycle: Cycle::G81,
            plane: Plane::YZ,
            retract_to_r: true,
            ..NONE
        };
        let blocks = [
            CycleBlock {
                at: [Some(1.0), Some(2.0)],
                depth: Some(-5.0),
                r: Some(2.0),
                ..g19
            },
            CycleBlock {
                at: [Some(3.0), None],
                ..g19
            },
        ];
        let start = [10.0, 0.0, 0.0, 0.0, 0.0, 0.0];
        check(
            start,
            false,
            &blocks,
            "
            STRAIGHT_TRAVERSE(10.0000, 1.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(2.0000, 1.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(-5.0000, 1.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(2.0000, 1.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(2.0000, 3.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(-5.0000, 3.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(2.0000, 3.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        ",
            [2.0, 3.0, 2.0, 0.0, 0.0, 0.0],
        );
    }

    #[test]
    fn g81_g19_g91_repeats() {
        // G19 / G0 X10 Y0 Z0 / G91 G98 G81 Y1 Z2 X-6 R-7 L2: R = 10 - 7 = 3, bottom = 3 - 6 = -3.
        let b = CycleBlock {
            cycle: Cycle::G81,
            plane: Plane::YZ,
            incremental: true,
            at: [Some(1.0), Some(2.0)],
            depth: Some(-6.0),
            r: Some(-7.0),
            repeats: Some(2.0),
            ..NONE
        };
        let start = [10.0, 0.0, 0.0, 0.0, 0.0, 0.0];
        check(
            start,
            false,
            &[b],
            "
            STRAIGHT_TRAVERSE(10.0000, 1.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(3.0000, 1.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(-3.0000, 1.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(10.0000, 1.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(10.0000, 2.0000, 4.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(3.0000, 2.0000, 4.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(-3.0000, 2.0000, 4.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(10.0000, 2.0000, 4.0000, 0.0000, 0.0000, 0.0000)
        ",
            [10.0, 2.0, 4.0, 0.0, 0.0, 0.0],
        );
    }

    #[test]
    fn g81_keeps_a_b_c() {
        // G0 X0 Y0 Z10 A15 B-5 C30 / G98 G81 X1 Y2 Z-5 R2
        let b = CycleBlock {
            cycle: Cycle::G81,
            at: [Some(1.0), Some(2.0)],
            depth: Some(-5.0),
            r: Some(2.0),
            ..NONE
        };
        let start = [0.0, 0.0, 10.0, 15.0, -5.0, 30.0];
        check(
            start,
            false,
            &[b],
            "
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 15.0000, -5.0000, 30.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 15.0000, -5.0000, 30.0000)
            STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 15.0000, -5.0000, 30.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 15.0000, -5.0000, 30.0000)
        ",
            [1.0, 2.0, 10.0, 15.0, -5.0, 30.0],
        );
    }

    #[test]
    fn a_block_without_position_drills_nothing() {
        // G98 G81 X1 Y2 Z-5 R2 / F50: the F block makes no move (LinuxCNC and Fanuc).
        let blocks = [
            CycleBlock {
                cycle: Cycle::G81,
                at: [Some(1.0), Some(2.0)],
                depth: Some(-5.0),
                r: Some(2.0),
                ..NONE
            },
            CycleBlock {
                cycle: Cycle::G81,
                ..NONE
            },
        ];
        check(
            XYZ10,
            false,
            &blocks,
            "
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        ",
            [1.0, 2.0, 10.0, 0.0, 0.0, 0.0],
        );
    }

    #[test]
    fn g73_mm() {
        // G98 G73 X1 Y2 Z-5 R2 Q1.5: pecks to 0.5 -1 -2.5 -4, each backed off 0.254 mm.
        let b = CycleBlock {
            cycle: Cycle::G73,
            at: [Some(1.0), Some(2.0)],
            depth: Some(-5.0),
            r: Some(2.0),
            q: Some(1.5),
            ..NONE
        };
        check(
            XYZ10,
            false,
            &[b],
            "
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(1.0000, 2.0000, 0.5000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 0.7540, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(1.0000, 2.0000, -1.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, -0.7460, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(1.0000, 2.0000, -2.5000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, -2.2460, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(1.0000, 2.0000, -4.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, -3.7460, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        ",
            [1.0, 2.0, 10.0, 0.0, 0.0, 0.0],
        );
    }

    #[test]
    fn g73_inch() {
        // G20 / G0 X0 Y0 Z1 / G99 G73 X0.1 Y0.2 Z-0.3 R0.1 Q0.12: backed off 0.010 inch.
        let b = CycleBlock {
            cycle: Cycle::G73,
            retract_to_r: true,
            at: [Some(0.1), Some(0.2)],
            depth: Some(-0.3),
            r: Some(0.1),
            q: Some(0.12),
            ..NONE
        };
        let start = [0.0, 0.0, 1.0, 0.0, 0.0, 0.0];
        check(
            start,
            true,
            &[b],
            "
            STRAIGHT_TRAVERSE(0.1000, 0.2000, 1.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(0.1000, 0.2000, 0.1000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(0.1000, 0.2000, -0.0200, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(0.1000, 0.2000, -0.0100, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(0.1000, 0.2000, -0.1400, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(0.1000, 0.2000, -0.1300, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(0.1000, 0.2000, -0.2600, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(0.1000, 0.2000, -0.2500, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(0.1000, 0.2000, -0.3000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(0.1000, 0.2000, 0.1000, 0.0000, 0.0000, 0.0000)
        ",
            [0.1, 0.2, 0.1, 0.0, 0.0, 0.0],
        );
    }

    #[test]
    fn g83_mm_q_sticky() {
        // G99 G83 X1 Y2 Z-5 R2 Q2 / X4: out to R after each peck, back in to 0.254 above it.
        let blocks = [
            CycleBlock {
                cycle: Cycle::G83,
                retract_to_r: true,
                at: [Some(1.0), Some(2.0)],
                depth: Some(-5.0),
                r: Some(2.0),
                q: Some(2.0),
                ..NONE
            },
            CycleBlock {
                cycle: Cycle::G83,
                retract_to_r: true,
                at: [Some(4.0), None],
                ..NONE
            },
        ];
        check(
            XYZ10,
            false,
            &blocks,
            "
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(1.0000, 2.0000, 0.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 0.2540, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(1.0000, 2.0000, -2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, -1.7460, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(1.0000, 2.0000, -4.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, -3.7460, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(4.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(4.0000, 2.0000, 0.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(4.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(4.0000, 2.0000, 0.2540, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(4.0000, 2.0000, -2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(4.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(4.0000, 2.0000, -1.7460, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(4.0000, 2.0000, -4.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(4.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(4.0000, 2.0000, -3.7460, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(4.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(4.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        ",
            [4.0, 2.0, 2.0, 0.0, 0.0, 0.0],
        );
    }

    #[test]
    fn g83_inch() {
        // G20 / G0 X0 Y0 Z1 / G98 G83 X0.1 Y0.2 Z-0.3 R0.1 Q0.12: clearance 0.010 inch.
        let b = CycleBlock {
            cycle: Cycle::G83,
            at: [Some(0.1), Some(0.2)],
            depth: Some(-0.3),
            r: Some(0.1),
            q: Some(0.12),
            ..NONE
        };
        let start = [0.0, 0.0, 1.0, 0.0, 0.0, 0.0];
        check(
            start,
            true,
            &[b],
            "
            STRAIGHT_TRAVERSE(0.1000, 0.2000, 1.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(0.1000, 0.2000, 0.1000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(0.1000, 0.2000, -0.0200, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(0.1000, 0.2000, 0.1000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(0.1000, 0.2000, -0.0100, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(0.1000, 0.2000, -0.1400, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(0.1000, 0.2000, 0.1000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(0.1000, 0.2000, -0.1300, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(0.1000, 0.2000, -0.2600, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(0.1000, 0.2000, 0.1000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(0.1000, 0.2000, -0.2500, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(0.1000, 0.2000, -0.3000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(0.1000, 0.2000, 1.0000, 0.0000, 0.0000, 0.0000)
        ",
            [0.1, 0.2, 1.0, 0.0, 0.0, 0.0],
        );
    }

    #[test]
    fn g83_g91_repeats() {
        // G91 G99 G83 X5 Z-4 R-8 Q1.5 L2 (from X0 Y0 Z10): R 2, bottom -2.
        let b = CycleBlock {
            cycle: Cycle::G83,
            incremental: true,
            retract_to_r: true,
            at: [Some(5.0), None],
            depth: Some(-4.0),
            r: Some(-8.0),
            q: Some(1.5),
            repeats: Some(2.0),
            ..NONE
        };
        check(
            XYZ10,
            false,
            &[b],
            "
            STRAIGHT_TRAVERSE(5.0000, 0.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(5.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(5.0000, 0.0000, 0.5000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(5.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(5.0000, 0.0000, 0.7540, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(5.0000, 0.0000, -1.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(5.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(5.0000, 0.0000, -0.7460, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(5.0000, 0.0000, -2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(5.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(10.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(10.0000, 0.0000, 0.5000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(10.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(10.0000, 0.0000, 0.7540, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(10.0000, 0.0000, -1.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(10.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(10.0000, 0.0000, -0.7460, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(10.0000, 0.0000, -2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(10.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        ",
            [10.0, 0.0, 2.0, 0.0, 0.0, 0.0],
        );
    }

    #[test]
    fn g83_g18_pecks_along_y() {
        // G18 / G0 X0 Y10 Z0 / G98 G83 Z1 X2 Y-3 R2 Q2
        let b = CycleBlock {
            cycle: Cycle::G83,
            plane: Plane::ZX,
            at: [Some(1.0), Some(2.0)],
            depth: Some(-3.0),
            r: Some(2.0),
            q: Some(2.0),
            ..NONE
        };
        let start = [0.0, 10.0, 0.0, 0.0, 0.0, 0.0];
        check(
            start,
            false,
            &[b],
            "
            STRAIGHT_TRAVERSE(2.0000, 10.0000, 1.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(2.0000, 2.0000, 1.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(2.0000, 0.0000, 1.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(2.0000, 2.0000, 1.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(2.0000, 0.2540, 1.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(2.0000, -2.0000, 1.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(2.0000, 2.0000, 1.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(2.0000, -1.7460, 1.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(2.0000, -3.0000, 1.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(2.0000, 10.0000, 1.0000, 0.0000, 0.0000, 0.0000)
        ",
            [2.0, 10.0, 1.0, 0.0, 0.0, 0.0],
        );
    }

    #[test]
    fn g82_dwell_p_in_milliseconds_sticky() {
        // Fanuc G98 G82 X1 Y2 Z-5 R2 P1500 / X3 = LinuxCNC P1.5 (seconds).
        let blocks = [
            CycleBlock {
                cycle: Cycle::G82,
                at: [Some(1.0), Some(2.0)],
                depth: Some(-5.0),
                r: Some(2.0),
                p: Some(1500.0),
                ..NONE
            },
            CycleBlock {
                cycle: Cycle::G82,
                at: [Some(3.0), None],
                ..NONE
            },
        ];
        check(
            XYZ10,
            false,
            &blocks,
            "
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            DWELL(1.5000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(3.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(3.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(3.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            DWELL(1.5000)
            STRAIGHT_TRAVERSE(3.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        ",
            [3.0, 2.0, 10.0, 0.0, 0.0, 0.0],
        );
    }

    #[test]
    fn g89_dwell_feed_out() {
        // Fanuc G99 G89 X1 Y2 Z-5 R2 P250 / X3 = LinuxCNC P0.25.
        let blocks = [
            CycleBlock {
                cycle: Cycle::G89,
                retract_to_r: true,
                at: [Some(1.0), Some(2.0)],
                depth: Some(-5.0),
                r: Some(2.0),
                p: Some(250.0),
                ..NONE
            },
            CycleBlock {
                cycle: Cycle::G89,
                retract_to_r: true,
                at: [Some(3.0), None],
                ..NONE
            },
        ];
        check(
            XYZ10,
            false,
            &blocks,
            "
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            DWELL(0.2500)
            STRAIGHT_FEED(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(3.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(3.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            DWELL(0.2500)
            STRAIGHT_FEED(3.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        ",
            [3.0, 2.0, 2.0, 0.0, 0.0, 0.0],
        );
    }

    #[test]
    fn g89_under_g98_feeds_out_to_the_initial_level() {
        // G98 G89 X1 Y2 Z-5 R2 P250 / G99 X3 (g89_g98.trace): unlike G85, LinuxCNC's G89 feeds
        // all the way out to the return level, the initial level under G98.
        let blocks = [
            CycleBlock {
                cycle: Cycle::G89,
                retract_to_r: false,
                at: [Some(1.0), Some(2.0)],
                depth: Some(-5.0),
                r: Some(2.0),
                p: Some(250.0),
                ..NONE
            },
            CycleBlock {
                cycle: Cycle::G89,
                retract_to_r: true,
                at: [Some(3.0), None],
                ..NONE
            },
        ];
        check(
            XYZ10,
            false,
            &blocks,
            "
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            DWELL(0.2500)
            STRAIGHT_FEED(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(3.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(3.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(3.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            DWELL(0.2500)
            STRAIGHT_FEED(3.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        ",
            [3.0, 2.0, 2.0, 0.0, 0.0, 0.0],
        );
    }

    #[test]
    fn g85_feed_out_to_r_then_rapid() {
        // G98 G85 X1 Y2 Z-5 R2 / G99 X3
        let blocks = [
            CycleBlock {
                cycle: Cycle::G85,
                at: [Some(1.0), Some(2.0)],
                depth: Some(-5.0),
                r: Some(2.0),
                ..NONE
            },
            CycleBlock {
                cycle: Cycle::G85,
                retract_to_r: true,
                at: [Some(3.0), None],
                ..NONE
            },
        ];
        check(
            XYZ10,
            false,
            &blocks,
            "
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(3.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(3.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(3.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(3.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(3.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
        ",
            [3.0, 2.0, 2.0, 0.0, 0.0, 0.0],
        );
    }

    #[test]
    fn g84_tapping() {
        // M3 / G98 G84 X1 Y2 Z-5 R2 P500 / G99 X3 (LinuxCNC P0.5): under G98 the feed out goes to
        // the initial level.
        let blocks = [
            CycleBlock {
                cycle: Cycle::G84,
                at: [Some(1.0), Some(2.0)],
                depth: Some(-5.0),
                r: Some(2.0),
                p: Some(500.0),
                ..NONE
            },
            CycleBlock {
                cycle: Cycle::G84,
                retract_to_r: true,
                at: [Some(3.0), None],
                ..NONE
            },
        ];
        check(
            XYZ10,
            false,
            &blocks,
            "
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STOP_SPINDLE_TURNING(0)
            START_SPINDLE_COUNTERCLOCKWISE(0)
            DWELL(0.5000)
            STRAIGHT_FEED(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STOP_SPINDLE_TURNING(0)
            START_SPINDLE_CLOCKWISE(0)
            STRAIGHT_TRAVERSE(3.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(3.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(3.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STOP_SPINDLE_TURNING(0)
            START_SPINDLE_COUNTERCLOCKWISE(0)
            DWELL(0.5000)
            STRAIGHT_FEED(3.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STOP_SPINDLE_TURNING(0)
            START_SPINDLE_CLOCKWISE(0)
        ",
            [3.0, 2.0, 2.0, 0.0, 0.0, 0.0],
        );
    }

    #[test]
    fn g74_counter_tapping() {
        // M4 / G99 G74 X1 Y2 Z-5 R2: no P, LinuxCNC dwells 0.
        let b = CycleBlock {
            cycle: Cycle::G74,
            retract_to_r: true,
            at: [Some(1.0), Some(2.0)],
            depth: Some(-5.0),
            r: Some(2.0),
            spindle_ccw: true,
            ..NONE
        };
        check(
            XYZ10,
            false,
            &[b],
            "
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STOP_SPINDLE_TURNING(0)
            START_SPINDLE_CLOCKWISE(0)
            DWELL(0.0000)
            STRAIGHT_FEED(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STOP_SPINDLE_TURNING(0)
            START_SPINDLE_COUNTERCLOCKWISE(0)
        ",
            [1.0, 2.0, 2.0, 0.0, 0.0, 0.0],
        );
    }

    #[test]
    fn g84_g19_feeds_along_x() {
        // G19 / G0 X10 Y0 Z0 / G98 G84 Y1 Z2 X-5 R2. The positioning is rs274's; its two feeds are
        // STRAIGHT_FEED(2, -5, 1) and STRAIGHT_FEED(2, 10, 1) (g84_g19.trace), the axes swapped by
        // LinuxCNC 2.9's convert_cycle_g74_g84. fmsvm feeds along X at Y1 Z2, as G81 does in G19.
        let b = CycleBlock {
            cycle: Cycle::G84,
            plane: Plane::YZ,
            at: [Some(1.0), Some(2.0)],
            depth: Some(-5.0),
            r: Some(2.0),
            ..NONE
        };
        let trace = "
            STRAIGHT_TRAVERSE(10.0000, 1.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(2.0000, 1.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            // fmsvm, not LinuxCNC:
            STRAIGHT_FEED(-5.0000, 1.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STOP_SPINDLE_TURNING(0)
            START_SPINDLE_COUNTERCLOCKWISE(0)
            DWELL(0.0000)
            // fmsvm, not LinuxCNC:
            STRAIGHT_FEED(10.0000, 1.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STOP_SPINDLE_TURNING(0)
            START_SPINDLE_CLOCKWISE(0)
        ";
        let start = [10.0, 0.0, 0.0, 0.0, 0.0, 0.0];
        check(start, false, &[b], trace, [10.0, 1.0, 2.0, 0.0, 0.0, 0.0]);
    }

    #[test]
    fn g86_spindle_stop_rapid_out() {
        // M3 / G99 G86 X1 Y2 Z-5 R2 P500 (LinuxCNC P0.5)
        let b = CycleBlock {
            cycle: Cycle::G86,
            retract_to_r: true,
            at: [Some(1.0), Some(2.0)],
            depth: Some(-5.0),
            r: Some(2.0),
            p: Some(500.0),
            ..NONE
        };
        check(
            XYZ10,
            false,
            &[b],
            "
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            DWELL(0.5000)
            STOP_SPINDLE_TURNING(0)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            START_SPINDLE_CLOCKWISE(0)
        ",
            [1.0, 2.0, 2.0, 0.0, 0.0, 0.0],
        );
    }

    #[test]
    fn g86_restarts_counter_clockwise_after_m4() {
        // M4 / G98 G86 X1 Y2 Z-5 R2 P500
        let b = CycleBlock {
            cycle: Cycle::G86,
            at: [Some(1.0), Some(2.0)],
            depth: Some(-5.0),
            r: Some(2.0),
            p: Some(500.0),
            spindle_ccw: true,
            ..NONE
        };
        check(
            XYZ10,
            false,
            &[b],
            "
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            DWELL(0.5000)
            STOP_SPINDLE_TURNING(0)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            START_SPINDLE_COUNTERCLOCKWISE(0)
        ",
            [1.0, 2.0, 10.0, 0.0, 0.0, 0.0],
        );
    }

    #[test]
    fn g88_stop_then_fanuc_return() {
        // M3 / G98 G88 X1 Y2 Z-5 R2 P500 / X3 (LinuxCNC P0.5). After PROGRAM_STOP fmsvm adds
        // Fanuc's rapid to the return level (here the initial level Z10) before the spindle restarts;
        // the rest is rs274's.
        let blocks = [
            CycleBlock {
                cycle: Cycle::G88,
                at: [Some(1.0), Some(2.0)],
                depth: Some(-5.0),
                r: Some(2.0),
                p: Some(500.0),
                ..NONE
            },
            CycleBlock {
                cycle: Cycle::G88,
                at: [Some(3.0), None],
                ..NONE
            },
        ];
        let trace = "
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            DWELL(0.5000)
            STOP_SPINDLE_TURNING(0)
            PROGRAM_STOP()
            // fmsvm (Fanuc), not LinuxCNC:
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            START_SPINDLE_CLOCKWISE(0)
            STRAIGHT_TRAVERSE(3.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(3.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(3.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            DWELL(0.5000)
            STOP_SPINDLE_TURNING(0)
            PROGRAM_STOP()
            // fmsvm (Fanuc), not LinuxCNC:
            STRAIGHT_TRAVERSE(3.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            START_SPINDLE_CLOCKWISE(0)
        ";
        check(
            XYZ10,
            false,
            &blocks,
            trace,
            [3.0, 2.0, 10.0, 0.0, 0.0, 0.0],
        );
    }

    // Alarms. err_*.ngc hold the LinuxCNC twins; their traces end in rs274's error message.

    /// A peck so small that one block would expand for ever (the fuzzer's find: Q4e-308) is alarm
    /// 045 before any move; the most pecks allowed still expand.
    #[test]
    fn a_peck_too_small_to_be_a_peck_is_alarm_45() {
        for (q, pecks_ok) in [
            (1e-7, false),
            (4e-308, false),
            (0.01, true),
            (0.0099, false),
        ] {
            let b = CycleBlock {
                cycle: Cycle::G83,
                at: [Some(1.0), Some(2.0)],
                depth: Some(-99.0),
                r: Some(1.0),
                q: Some(q),
                ..NONE
            };
            let mut steps = 0u64;
            let r = expand(
                &mut CycleModal::default(),
                &b,
                XYZ10,
                false,
                &CycleParams::default(),
                &mut |_| {
                    steps += 1;
                    Ok(())
                },
            );
            if pecks_ok {
                assert!(r.is_ok(), "Q{q}: {r:?}");
                assert!(steps > 10_000, "Q{q}: {steps} steps");
            } else {
                assert!(
                    matches!(r, Err(Stop::Alarm(ref a)) if a.number == 45 && a.message.contains("pecks")),
                    "Q{q}: {r:?}"
                );
                assert_eq!(steps, 0, "Q{q}");
            }
        }
    }

    #[test]
    fn q_zero_negative_or_missing_is_alarm_45() {
        // err_q0: G98 G83 X1 Y2 Z-5 R2 Q0 -> "Negative or zero q value used" (after rs274's two
        // positioning moves; fmsvm alarms before any move). err_no_q: G98 G73 X1 Y2 Z-5 R2 ->
        // "Q word missing with g73".
        for (cycle, q) in [
            (Cycle::G83, Some(0.0)),
            (Cycle::G73, Some(-1.0)),
            (Cycle::G73, None),
            (Cycle::G83, None),
        ] {
            let b = CycleBlock {
                cycle,
                at: [Some(1.0), Some(2.0)],
                depth: Some(-5.0),
                r: Some(2.0),
                q,
                ..NONE
            };
            let mut steps = 0;
            let r = expand(
                &mut CycleModal::default(),
                &b,
                XYZ10,
                false,
                &CycleParams::default(),
                &mut |_| {
                    steps += 1;
                    Ok(())
                },
            );
            assert!(
                matches!(r, Err(Stop::Alarm(ref a)) if a.number == 45),
                "{cycle:?} {q:?}"
            );
            assert_eq!(steps, 0);
        }
    }

    #[test]
    fn missing_r_or_z_and_r_below_z_are_alarms() {
        // err_no_r: G98 G81 X1 Y2 Z-5 -> "R clearance plane unspecified in cycle";
        // err_no_z: G98 G81 X1 Y2 R2 -> "Z value unspecified in xy plane canned cycle";
        // err_r_below_z: G98 G81 X1 Y2 Z2 R-5 -> "R less than z in cycle in xy plane".
        let b = CycleBlock {
            cycle: Cycle::G81,
            at: [Some(1.0), Some(2.0)],
            ..NONE
        };
        let no_r = CycleBlock {
            depth: Some(-5.0),
            ..b
        };
        let (n, m) = alarm_of(run(XYZ10, false, &[no_r]));
        assert_eq!(
            (n, m.as_str()),
            (0, "G81: no R level given in the canned cycle mode")
        );
        let no_z = CycleBlock { r: Some(2.0), ..b };
        let (n, m) = alarm_of(run(XYZ10, false, &[no_z]));
        assert_eq!(
            (n, m.as_str()),
            (0, "G81: no Z depth given in the canned cycle mode")
        );
        let no_x = CycleBlock {
            plane: Plane::YZ,
            ..no_z
        };
        let (_, m) = alarm_of(run(XYZ10, false, &[no_x]));
        assert_eq!(m, "G81: no X depth given in the canned cycle mode");
        let below = CycleBlock {
            depth: Some(2.0),
            r: Some(-5.0),
            ..b
        };
        let (n, m) = alarm_of(run(XYZ10, false, &[below]));
        assert_eq!((n, m.as_str()), (0, "G81: R -5 is below the bottom Z2"));
    }

    #[test]
    fn cancel_forgets_r_z_and_the_initial_level() {
        let mut modal = CycleModal::default();
        let b = CycleBlock {
            cycle: Cycle::G81,
            at: [Some(1.0), Some(2.0)],
            depth: Some(-5.0),
            r: Some(2.0),
            ..NONE
        };
        let p = CycleParams::default();
        expand(&mut modal, &b, XYZ10, false, &p, &mut |_| Ok(())).expect("drills");
        assert_eq!(modal.initial_level(), Some(10.0));
        modal.cancel();
        assert_eq!(modal, CycleModal::default());
        let again = CycleBlock {
            cycle: Cycle::G81,
            at: [Some(3.0), None],
            ..NONE
        };
        let r = expand(&mut modal, &again, XYZ10, false, &p, &mut |_| Ok(()));
        assert!(matches!(r, Err(Stop::Alarm(a)) if a.number == 0));
    }

    #[test]
    fn fanuc_r_only_block_drills() {
        // err_r_only: G98 G81 X1 Y2 Z-5 R2 / R3: rs274 refuses the R3 block ("R word with no g code
        // that uses it"); Fanuc drills again where the tool is, from the new R. By hand, the second
        // block: initial 10, R 3, start Z10 above R -> rapid at Z10 over the hole (1, 2), down to 3,
        // feed to -5, back to 10.
        let blocks = [
            CycleBlock {
                cycle: Cycle::G81,
                at: [Some(1.0), Some(2.0)],
                depth: Some(-5.0),
                r: Some(2.0),
                ..NONE
            },
            CycleBlock {
                cycle: Cycle::G81,
                r: Some(3.0),
                ..NONE
            },
        ];
        let trace = "
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            // the R3 block (hand-computed):
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 3.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        ";
        check(
            XYZ10,
            false,
            &blocks,
            trace,
            [1.0, 2.0, 10.0, 0.0, 0.0, 0.0],
        );
    }

    #[test]
    fn fanuc_k0_stores_without_drilling() {
        // err_l0: G98 G81 X1 Y2 Z-5 R2 L0 -> rs274: "Cannot do zero repeats of cycle". Fanuc K0
        // stores Z and R; the next block X3 drills with them (hand: as the X3 block of g81_g98,
        // from Z10 at X0 Y0 as the K0 block left the tool).
        let blocks = [
            CycleBlock {
                cycle: Cycle::G81,
                at: [Some(1.0), Some(2.0)],
                depth: Some(-5.0),
                r: Some(2.0),
                repeats: Some(0.0),
                ..NONE
            },
            CycleBlock {
                cycle: Cycle::G81,
                at: [Some(3.0), None],
                ..NONE
            },
        ];
        let trace = "
            STRAIGHT_TRAVERSE(3.0000, 0.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(3.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(3.0000, 0.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(3.0000, 0.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        ";
        check(
            XYZ10,
            false,
            &blocks,
            trace,
            [3.0, 0.0, 10.0, 0.0, 0.0, 0.0],
        );
    }

    #[test]
    fn fanuc_keeps_r_z_across_cycle_codes_and_p_defaults_to_0() {
        // err_code_change: G98 G81 X1 Y2 Z-5 R2 / G82 X3 P1 -> rs274: "R clearance plane
        // unspecified in cycle". err_no_p: G98 G82 X1 Y2 Z-5 R2 -> rs274: "Dwell time p word missing
        // with g82". Fanuc: G82 X3 P1000 drills with R2 Z-5; a G82 with no P dwells 0 s (hand).
        let blocks = [
            CycleBlock {
                cycle: Cycle::G81,
                at: [Some(1.0), Some(2.0)],
                depth: Some(-5.0),
                r: Some(2.0),
                ..NONE
            },
            CycleBlock {
                cycle: Cycle::G82,
                at: [Some(3.0), None],
                p: Some(1000.0),
                ..NONE
            },
        ];
        let trace = "
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(3.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(3.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(3.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            DWELL(1.0000)
            STRAIGHT_TRAVERSE(3.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
        ";
        check(
            XYZ10,
            false,
            &blocks,
            trace,
            [3.0, 2.0, 10.0, 0.0, 0.0, 0.0],
        );
        let no_p = CycleBlock {
            cycle: Cycle::G82,
            at: [Some(1.0), Some(2.0)],
            depth: Some(-5.0),
            r: Some(2.0),
            ..NONE
        };
        let (steps, _) = run(XYZ10, false, &[no_p]).expect("no alarm");
        assert_eq!(steps[3], Step::Dwell(0.0));
    }

    #[test]
    fn bad_words_are_alarms() {
        let b = CycleBlock {
            cycle: Cycle::G81,
            at: [Some(1.0), Some(2.0)],
            depth: Some(-5.0),
            r: Some(2.0),
            ..NONE
        };
        for k in [-1.0, 1.5, 10000.0] {
            let (n, _) = alarm_of(run(
                XYZ10,
                false,
                &[CycleBlock {
                    repeats: Some(k),
                    ..b
                }],
            ));
            assert_eq!(n, 0, "K{k}");
        }
        let (n, _) = alarm_of(run(XYZ10, false, &[CycleBlock { p: Some(-5.0), ..b }]));
        assert_eq!(n, 6);
        // Not a cycle: G0, G1, G80, G81.1, G90, G75 (alarm 0010 where the kernel decodes the code).
        for code in [0, 10, 800, 811, 900, 750].map(Code::from_tenths) {
            let e = Cycle::of(code).expect_err("not a cycle");
            assert_eq!(e.number, 10, "G{code}");
        }
        for (cycle, code) in Cycle::ALL {
            assert_eq!(Cycle::of(code), Ok(cycle));
            assert_eq!(cycle.code(), code);
        }
    }

    #[test]
    fn vacant_words_are_omitted_words() {
        // X#0 in a Fanuc block: the word is as if not given, the hole is at the tool's X.
        let b = CycleBlock {
            cycle: Cycle::G81,
            at: [Some(f64::NAN), Some(2.0)],
            depth: Some(-5.0),
            r: Some(2.0),
            p: Some(f64::NAN),
            ..NONE
        };
        let (steps, end) = run(XYZ10, false, &[b]).expect("no alarm");
        assert_eq!(steps.len(), 4);
        assert!(close(&end, &[0.0, 2.0, 10.0, 0.0, 0.0, 0.0]));
    }

    #[test]
    fn errors_of_out_stop_the_cycle() {
        let b = CycleBlock {
            cycle: Cycle::G83,
            at: [Some(1.0), Some(2.0)],
            depth: Some(-5.0),
            r: Some(2.0),
            q: Some(0.001),
            ..NONE
        };
        let mut n = 0;
        let r = expand(
            &mut CycleModal::default(),
            &b,
            XYZ10,
            false,
            &CycleParams::default(),
            &mut |_| {
                n += 1;
                if n == 10 {
                    Err(Stop::Limit {
                        kind: fmsvm_block::LimitKind::Blocks,
                        limit: 9,
                    })
                } else {
                    Ok(())
                }
            },
        );
        assert!(matches!(r, Err(Stop::Limit { limit: 9, .. })));
        assert_eq!(n, 10);
    }

    // Fanuc-only cycles, hand-computed (LinuxCNC has no Fanuc G76; its G87 is another cycle).

    #[test]
    fn g76_fine_boring_shift_by_q() {
        // G0 X0 Y0 Z10 / G98 G76 X1 Y2 Z-5 R2 Q0.5 P500 (M3): Q is the decoded value in mm,
        // P500 is 0.5 s, shift direction + first axis (+X in G17; Fanuc parameter 5101 RD2 RD1 = 0 0).
        // Positioning as G81: rapid over (1, 2) at Z10, down to R2. Feed to Z-5, dwell 0.5, oriented
        // stop, shift X 1 + 0.5 = 1.5 at Z-5, rapid out to the G98 level Z10 at X1.5, shift back to
        // X1 at Z10, spindle clockwise (M3 was on).
        let b = CycleBlock {
            cycle: Cycle::G76,
            at: [Some(1.0), Some(2.0)],
            depth: Some(-5.0),
            r: Some(2.0),
            q: Some(0.5),
            p: Some(500.0),
            ..NONE
        };
        let trace = "
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            DWELL(0.5000)
            ORIENT_SPINDLE()
            STRAIGHT_TRAVERSE(1.5000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.5000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            START_SPINDLE_CLOCKWISE(0)
        ";
        check(XYZ10, false, &[b], trace, [1.0, 2.0, 10.0, 0.0, 0.0, 0.0]);
        // A negative Q shifts the same way (Fanuc ignores its sign); shift direction − second axis
        // (RD2 RD1 = 1 1, −Y in G17) shifts to Y 2 − 0.5 = 1.5.
        let minus_y = CycleParams {
            shift_direction: ShiftDirection::MinusSecond,
            ..CycleParams::default()
        };
        let (steps, _) =
            run_with(XYZ10, false, &minus_y, &[CycleBlock { q: Some(-0.5), ..b }]).expect("ok");
        assert!(same(
            &steps[5],
            &Step::Rapid([1.0, 1.5, -5.0, 0.0, 0.0, 0.0])
        ));
    }

    #[test]
    fn g76_g18_g99_shift_by_words() {
        // G18 / G0 X0 Y10 Z0 / G99 G76 Z1 X2 Y-5 R2 K0.3 I-0.4 (Fanuc SIJ: K I are the G18 shift,
        // plane order (Z, X)); no P: dwell 0.
        // Positioning: start Y10 above R2: rapid to Z1 X2 at Y10, down to Y2. Feed to Y-5. Shift:
        // Z 1 + 0.3 = 1.3, X 2 - 0.4 = 1.6, at Y-5; out to the G99 level Y2; back to Z1 X2; M3.
        let b = CycleBlock {
            cycle: Cycle::G76,
            plane: Plane::ZX,
            retract_to_r: true,
            at: [Some(1.0), Some(2.0)],
            depth: Some(-5.0),
            r: Some(2.0),
            q: Some(9.0),
            shift: [Some(0.3), Some(-0.4)],
            ..NONE
        };
        let trace = "
            STRAIGHT_TRAVERSE(2.0000, 10.0000, 1.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(2.0000, 2.0000, 1.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_FEED(2.0000, -5.0000, 1.0000, 0.0000, 0.0000, 0.0000)
            DWELL(0.0000)
            ORIENT_SPINDLE()
            STRAIGHT_TRAVERSE(1.6000, -5.0000, 1.3000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.6000, 2.0000, 1.3000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(2.0000, 2.0000, 1.0000, 0.0000, 0.0000, 0.0000)
            START_SPINDLE_CLOCKWISE(0)
        ";
        let start = [0.0, 10.0, 0.0, 0.0, 0.0, 0.0];
        check(start, false, &[b], trace, [2.0, 2.0, 1.0, 0.0, 0.0, 0.0]);
    }

    #[test]
    fn g87_back_boring() {
        // G0 X0 Y0 Z10 / G98 G87 X1 Y2 Z-5 R-20 Q0.5 P1000 (M3): R-20 is below the part, Z-5 the
        // top of the back bore. Over the hole at Z10, oriented stop, shift X 1 + 0.5 = 1.5, rapid
        // down to Z-20, shift back to X1, M3, feed up to Z-5, dwell 1 s, oriented stop, shift to
        // X1.5, rapid up to the initial level Z10, shift back, M3.
        let b = CycleBlock {
            cycle: Cycle::G87,
            at: [Some(1.0), Some(2.0)],
            depth: Some(-5.0),
            r: Some(-20.0),
            q: Some(0.5),
            p: Some(1000.0),
            ..NONE
        };
        let trace = "
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            ORIENT_SPINDLE()
            STRAIGHT_TRAVERSE(1.5000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.5000, 2.0000, -20.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, -20.0000, 0.0000, 0.0000, 0.0000)
            START_SPINDLE_CLOCKWISE(0)
            STRAIGHT_FEED(1.0000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            DWELL(1.0000)
            ORIENT_SPINDLE()
            STRAIGHT_TRAVERSE(1.5000, 2.0000, -5.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.5000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            STRAIGHT_TRAVERSE(1.0000, 2.0000, 10.0000, 0.0000, 0.0000, 0.0000)
            START_SPINDLE_CLOCKWISE(0)
        ";
        check(XYZ10, false, &[b], trace, [1.0, 2.0, 10.0, 0.0, 0.0, 0.0]);
        // R above the top is an alarm for G87.
        let (n, m) = alarm_of(run(XYZ10, false, &[CycleBlock { r: Some(0.0), ..b }]));
        assert_eq!(
            (n, m.as_str()),
            (0, "G87: R 0 is above the top of the back bore Z-5")
        );
    }

    #[test]
    fn g87_g91_repeats_always_back_to_the_initial_level() {
        // G0 X0 Y0 Z10 / G91 G99 G87 X10 Z10 R-30 Q0.5 K2, spindle M4, shift − second axis (−Y):
        // R = 10 - 30 = -20, top = -20 + 10 = -10; G99 is ignored (Fanuc G87 returns to the
        // initial level). Holes at X10 and X20, shifted to Y 0 - 0.5 = -0.5; restarts M4; no P.
        let b = CycleBlock {
            cycle: Cycle::G87,
            incremental: true,
            retract_to_r: true,
            at: [Some(10.0), None],
            depth: Some(10.0),
            r: Some(-30.0),
            q: Some(0.5),
            repeats: Some(2.0),
            spindle_ccw: true,
            ..NONE
        };
        let mut want = String::new();
        for x in ["10.0", "20.0"] {
            want += &format!(
                "STRAIGHT_TRAVERSE({x}, 0, 10, 0, 0, 0)
                ORIENT_SPINDLE()
                STRAIGHT_TRAVERSE({x}, -0.5, 10, 0, 0, 0)
                STRAIGHT_TRAVERSE({x}, -0.5, -20, 0, 0, 0)
                STRAIGHT_TRAVERSE({x}, 0, -20, 0, 0, 0)
                START_SPINDLE_COUNTERCLOCKWISE(0)
                STRAIGHT_FEED({x}, 0, -10, 0, 0, 0)
                DWELL(0)
                ORIENT_SPINDLE()
                STRAIGHT_TRAVERSE({x}, -0.5, -10, 0, 0, 0)
                STRAIGHT_TRAVERSE({x}, -0.5, 10, 0, 0, 0)
                STRAIGHT_TRAVERSE({x}, 0, 10, 0, 0, 0)
                START_SPINDLE_COUNTERCLOCKWISE(0)
                "
            );
        }
        let params = CycleParams {
            shift_direction: ShiftDirection::MinusSecond,
            ..CycleParams::default()
        };
        let (steps, end) = run_with(XYZ10, false, &params, &[b]).expect("no alarm");
        let want = parse(&want);
        assert!(
            steps.len() == want.len() && steps.iter().zip(&want).all(|(a, b)| same(a, b)),
            "got {steps:#?}"
        );
        assert!(close(&end, &[20.0, 0.0, 10.0, 0.0, 0.0, 0.0]));
    }
}
