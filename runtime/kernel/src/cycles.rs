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
mod tests;
