//! Canonical operations: what the tool does, after every frame, transform, cycle and compensation is
//! applied (as rs274ngc's canon). The kernel produces them; resolved emitters, `stats` and `plot`
//! consume them.

use fmsvm_block::Code;

use fmsvm_block::{Alarm, Letter};

use crate::geom;

/// Axes tracked for position variables (#5001–#5006 → X Y Z A B C).
pub const AXES: [Letter; 6] = [
    Letter::X,
    Letter::Y,
    Letter::Z,
    Letter::A,
    Letter::B,
    Letter::C,
];

/// Alarm for a position the program needs and fmsvm does not know (Fanuc PS0224, "reference position
/// return not finished": a control refuses to move an axis it has not established either).
pub const UNKNOWN_POSITION: u32 = 224;

/// Alarm 0224 for axis `i`: `what` needs it, and nothing has made it known.
pub fn unknown_axis(i: usize, what: &str) -> Alarm {
    let l = AXES[i.min(5)];
    Alarm::new(
        UNKNOWN_POSITION,
        format!(
            "{what} needs the position of {l}, which is not known: the program has not positioned {l} (an absolute {l} word, a return to a reference position --offsets gives, or --start-point makes it known)"
        ),
    )
}

/// `letter`'s place in `AXES`, unless it is the second auxiliary function's address (a code there).
pub fn axis_index(letter: Letter, second_aux: Option<Letter>) -> Option<usize> {
    AXES.iter()
        .position(|&a| a == letter)
        .filter(|_| Some(letter) != second_aux)
}

/// A point of the six axes X Y Z A B C.
pub type Pose = [f64; 6];

/// How far an axis moves from `from` to `to`; 0 where either end is unknown (NaN: the program had
/// not positioned the axis, so the length of its first positioning is not known).
#[inline]
pub fn travel(from: f64, to: f64) -> f64 {
    let d = to - from;
    if d.is_nan() { 0.0 } else { d }
}

/// The plane of arcs, cycles and cutter compensation (G17, G18, G19).
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub enum Plane {
    /// G17: X Y, tool axis Z.
    #[default]
    XY,
    /// G18: Z X, tool axis Y.
    ZX,
    /// G19: Y Z, tool axis X.
    YZ,
}

impl Plane {
    /// The indices (into a `Pose`) of the plane's first axis, its second axis and the axis normal to it,
    /// in the order that makes them right-handed: G17 (X, Y, Z), G18 (Z, X, Y), G19 (Y, Z, X).
    pub const fn axes(self) -> (usize, usize, usize) {
        match self {
            Plane::XY => (0, 1, 2),
            Plane::ZX => (2, 0, 1),
            Plane::YZ => (1, 2, 0),
        }
    }

    /// The G code ×10 that selects the plane.
    pub const fn code(self) -> Code {
        match self {
            Plane::XY => Code::G17,
            Plane::ZX => Code::G18,
            Plane::YZ => Code::G19,
        }
    }

    /// The plane of G17, G18 or G19 (any other code is XY).
    pub fn from_code(code: Code) -> Plane {
        match code {
            Code::G18 => Plane::ZX,
            Code::G19 => Plane::YZ,
            _ => Plane::XY,
        }
    }

    /// The plane coordinates (first, second) of `p`.
    #[inline(always)]
    pub fn project(self, p: &Pose) -> [f64; 2] {
        let (a, b, _) = self.axes();
        [p[a], p[b]]
    }
}

/// A circular (or helical) move in a plane.
#[derive(Clone, Copy, PartialEq, Debug)]
pub struct Arc {
    /// End point (all six axes; the normal axis and A B C move linearly: a helix).
    pub to: Pose,
    /// Centre in the plane's coordinates (first, second axis).
    pub centre: [f64; 2],
    /// The plane.
    pub plane: Plane,
    /// G2 (clockwise seen from the positive normal axis) rather than G3.
    pub clockwise: bool,
    /// Whole extra turns before the end (0 for an arc of at most one revolution).
    pub turns: u32,
}

/// One canonical operation. Coordinates are in the output frame (the frame the flat program is
/// written in: G54 as it stands, or machine coordinates), in the program's units.
#[derive(Clone, Copy, PartialEq, Debug)]
pub enum Canon<'a> {
    /// Where the tool is (no motion): the first op of every run, and again when the output frame moves
    /// under the tool (G10 L2 P1, #5221…, the external offset).
    Start(Pose),
    /// Straight move at rapid traverse.
    Rapid(Pose),
    /// Straight move at the feed rate.
    Feed(Pose),
    /// How the control takes the corners from here (Fanuc's G09, G61, G64): written only to an
    /// emitter that says it can ([`crate::Emitter::corners`]).
    Corners(Corners),
    /// A skip move (Fanuc's G31): straight at the feed rate towards the programmed end, stopped
    /// where the probe touches. The kernel follows it with a `Start` where its probe model says the
    /// probe stopped, if it touched.
    Skip(Pose),
    /// Arc at the feed rate.
    Arc(Arc),
    /// A return to reference position `number` (1: G28, 2–4: G30 P2–P4) on the axes of `axes`
    /// (bit 0 X … bit 5 C), at rapid traverse and with no intermediate point (the kernel sends that
    /// as a rapid first). `to` is where the tool is afterwards: NaN on a returned axis whose
    /// reference position is not known, and on an axis that was unknown before.
    Reference {
        /// 1 for G28, 2–4 for G30 P2–P4.
        number: u8,
        /// The axes returned, bit 0 X to bit 5 C.
        axes: u8,
        /// The tool's position afterwards (output frame; NaN: unknown).
        to: Pose,
    },
    /// G53: a rapid to machine coordinates `machine` (NaN on the axes the block does not name),
    /// for the dialect to write as its own G53 where it has one. `to` is the same point in the
    /// output frame, as the kernel's frames say.
    Machine {
        /// The axes moved, bit 0 X to bit 5 C.
        axes: u8,
        /// Their machine coordinates.
        machine: Pose,
        /// The tool's position afterwards (output frame; NaN: unknown).
        to: Pose,
    },
    /// Dwell, seconds.
    Dwell(f64),
    /// The feed rate changes (F, in the program's units per minute, or per revolution under G95).
    FeedRate(f64),
    /// Feed per minute (false) or per revolution (G95, true).
    FeedPerRev(bool),
    /// Length units of what follows: inch (G20, true) or mm (G21).
    Units(bool),
    /// Spindle speed (S), rpm; ends constant surface speed.
    Speed(f64),
    /// Constant surface speed (a lathe's G96 S, `surface_speed_constant` gives the rpm): metres (feet) a minute at the tool's X, the
    /// spindle's rpm following the diameter up to the clamp.
    SurfaceSpeed(f64),
    /// The spindle's speed limit, rpm (a lathe's G50 S; LinuxCNC's G96 D).
    SpindleClamp(f64),
    /// A straight move synchronised with the spindle (thread cutting: a lathe's G32, the mill's
    /// G33), `lead` along Z per revolution.
    Thread {
        /// The end of the thread.
        to: Pose,
        /// The lead, length per revolution.
        lead: f64,
    },
    /// Tool selection (T).
    Tool(f64),
    /// An M code, as written (M3, M6, M8, M30 …). Program end codes come last in their block.
    MCode(f64),
    /// A second auxiliary function code (`B12`, or at the address the control moves it to), as
    /// written: a code for the machine, not motion.
    AuxCode(fmsvm_block::Letter, f64),
    /// A comment of the program (only when comments are kept).
    Comment(&'a str),
    /// The control's own work system is selected (1–6: G54–G59), where the output leaves work
    /// offsets to the control (`[motion] work_offsets = "control"`): the positions that
    /// follow are in it. A `Start` follows with where the tool is in it (NaN: not known).
    WorkSystem(u8),
    /// The control's own tool length offset is put in force (G43 or G44 with the register) or
    /// cancelled (G49, register 0), where the output leaves lengths to the control (`[motion]
    /// tool_length = "control"`): the positions are the tool tip's, the control adds the length.
    ToolLength {
        /// G43, G44 or G49.
        code: Code,
        /// The H register (0 with G49).
        register: u16,
    },
    /// A canned cycle the emitter asked to write as the control's own (`Emitter::native_cycle`):
    /// the cycle's moves follow as usual, up to [`Canon::CycleEnd`].
    Cycle(CycleOp),
    /// The end of a native cycle's moves.
    CycleEnd,
}

impl Canon<'_> {
    /// The operation as one that outlives its block, or None for a comment (its text is the
    /// block's): what a stage that holds operations back keeps.
    pub fn without_text(&self) -> Option<Canon<'static>> {
        Some(match *self {
            Canon::Comment(_) => return None,
            Canon::Start(p) => Canon::Start(p),
            Canon::Rapid(p) => Canon::Rapid(p),
            Canon::Feed(p) => Canon::Feed(p),
            Canon::Skip(p) => Canon::Skip(p),
            Canon::Arc(a) => Canon::Arc(a),
            Canon::Reference { number, axes, to } => Canon::Reference { number, axes, to },
            Canon::Machine { axes, machine, to } => Canon::Machine { axes, machine, to },
            Canon::Dwell(t) => Canon::Dwell(t),
            Canon::FeedRate(f) => Canon::FeedRate(f),
            Canon::FeedPerRev(b) => Canon::FeedPerRev(b),
            Canon::Units(b) => Canon::Units(b),
            Canon::Speed(v) => Canon::Speed(v),
            Canon::SurfaceSpeed(v) => Canon::SurfaceSpeed(v),
            Canon::SpindleClamp(v) => Canon::SpindleClamp(v),
            Canon::Thread { to, lead } => Canon::Thread { to, lead },
            Canon::Tool(v) => Canon::Tool(v),
            Canon::MCode(v) => Canon::MCode(v),
            Canon::AuxCode(l, v) => Canon::AuxCode(l, v),
            Canon::WorkSystem(n) => Canon::WorkSystem(n),
            Canon::ToolLength { code, register } => Canon::ToolLength { code, register },
            Canon::Cycle(c) => Canon::Cycle(c),
            Canon::CycleEnd => Canon::CycleEnd,
            Canon::Corners(c) => Canon::Corners(c),
        })
    }
}

impl Canon<'_> {
    /// Whether the operation moves the tool (a straight move, an arc, a thread, a return to a
    /// reference position, a move to machine coordinates).
    pub fn is_motion(&self) -> bool {
        matches!(
            self,
            Canon::Rapid(_)
                | Canon::Feed(_)
                | Canon::Skip(_)
                | Canon::Arc(_)
                | Canon::Thread { .. }
                | Canon::Reference { .. }
                | Canon::Machine { .. }
        )
    }

    /// Whether the operation is a move or a dwell: a block of the flat program, for the block limit
    /// of a consumer that writes no text (`stats`, `plot`).
    pub fn is_block(&self) -> bool {
        self.is_motion() || matches!(self, Canon::Dwell(_))
    }

    /// Where a move ends (None for what is not a move).
    pub fn end(&self) -> Option<&Pose> {
        match self {
            Canon::Rapid(to)
            | Canon::Feed(to)
            | Canon::Skip(to)
            | Canon::Thread { to, .. }
            | Canon::Reference { to, .. }
            | Canon::Machine { to, .. } => Some(to),
            Canon::Arc(arc) => Some(&arc.to),
            _ => None,
        }
    }
}

/// One hole of a canned cycle in the output frame (G17: the cycle axis is Z).
#[derive(Clone, Copy, PartialEq, Debug)]
pub struct CycleOp {
    /// The cycle: G81, G82, G85 or G89.
    pub code: Code,
    /// The hole: X Y (and A B C) of the hole, Z the level the tool is at when the cycle starts.
    pub hole: Pose,
    /// The R level, where the feed starts.
    pub r: f64,
    /// The hole bottom.
    pub bottom: f64,
    /// The level the tool is left at (the initial level under G98, R under G99).
    pub end: f64,
    /// The initial level of the cycle mode (where G98 returns).
    pub initial: f64,
    /// Dwell at the bottom, seconds (0: none).
    pub dwell: f64,
}

/// How the control takes the corners between moves: the meanings of Fanuc's G09, G61 and G64
/// (the FMS-3000's G09, G61 and G62, §2.13).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Corners {
    /// Decelerate to a stop and check the position at the end of the next move only (G09).
    ExactStopOnce,
    /// The same at the end of every move until cancelled (G61).
    ExactStop,
    /// The control's own cutting mode: no stop at the block ends (G64).
    Cutting,
}

/// Where an operation came from, for the emitter: source file, line and column, and block delete.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct Origin {
    /// Source line (1-based; 0: no source block).
    pub line: u32,
    /// Source file (its id in the run's source map; 0 the program's own file).
    pub file: u16,
    /// Column (1-based) of the block's first word.
    pub column: u16,
    /// The block was marked `/` (and ran).
    pub block_delete: bool,
    /// The output axes (bit 0 X … bit 5 C) the block's moves must leave where they are: those it
    /// neither names nor couples (a rotation, compensation, a cycle, an arc's plane, a corner)
    /// nor was warned about. `--verify` holds the output to it; 0 checks nothing.
    pub fixed: u8,
}

impl Origin {
    /// The origin of `block`'s operations, holding the axes `fixed` to where they are.
    pub fn of(block: &fmsvm_block::Block<'_>, fixed: u8) -> Origin {
        Origin {
            line: block.line,
            file: block.file,
            column: block.column,
            block_delete: block.block_delete,
            fixed,
        }
    }
}

/// Something the run should be told about the output, at the source block it comes from.
#[derive(Clone, PartialEq, Eq, Debug)]
pub struct Warning {
    /// The block (`line` 0: the program as a whole).
    pub at: Origin,
    /// What to say, without the place.
    pub text: String,
}

impl Warning {
    /// A warning at `at`.
    pub fn at(at: Origin, text: impl Into<String>) -> Warning {
        Warning {
            at,
            text: text.into(),
        }
    }

    /// A warning about the program as a whole.
    pub fn program(text: impl Into<String>) -> Warning {
        Warning::at(Origin::default(), text)
    }
}

impl Arc {
    /// The start radius and the swept angle (radians, positive) from `from`.
    pub fn sweep(&self, from: &Pose) -> (f64, f64) {
        let s = self.plane.project(from);
        let e = self.plane.project(&self.to);
        (
            geom::dist(s, self.centre),
            geom::sweep(s, e, self.centre, !self.clockwise, self.turns),
        )
    }

    /// Length of the path from `from` (the helix included).
    pub fn length(&self, from: &Pose) -> f64 {
        let (r, sweep) = self.sweep(from);
        let (_, _, n) = self.plane.axes();
        (r * sweep).hypot(travel(from[n], self.to[n]))
    }
}

/// A point for a message: `X1.0000 Y? Z5.0000` (`?`: not known).
pub fn describe_pose(p: &Pose) -> String {
    let mut t = String::new();
    for (i, l) in AXES[..3].iter().enumerate() {
        if i > 0 {
            t.push(' ');
        }
        if p[i].is_nan() {
            t.push_str(&format!("{l}?"));
        } else {
            t.push_str(&format!("{l}{:.4}", p[i]));
        }
    }
    t
}

/// Constant surface speed `v` (m/min, or ft/min when `inch`) as the spindle's rev/min times the
/// tool's radius in mm: the spindle turns at this over the radius, 1000·V/(π·D) (12·V/(π·D) in
/// inch), before the clamp.
pub fn surface_speed_constant(v: f64, inch: bool) -> f64 {
    let per_unit = if inch { 12.0 * 25.4 } else { 1000.0 };
    per_unit * v / std::f64::consts::TAU
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arc_sweep_and_length() {
        // Quarter circle R10 about the origin, X10 Y0 → X0 Y10, counter-clockwise.
        let from = [10.0, 0.0, 0.0, 0.0, 0.0, 0.0];
        let a = Arc {
            to: [0.0, 10.0, 0.0, 0.0, 0.0, 0.0],
            centre: [0.0, 0.0],
            plane: Plane::XY,
            clockwise: false,
            turns: 0,
        };
        let (r, s) = a.sweep(&from);
        assert!((r - 10.0).abs() < 1e-12 && (s - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        // Clockwise the other way round: three quarters.
        let cw = Arc {
            clockwise: true,
            ..a
        };
        assert!((cw.sweep(&from).1 - 3.0 * std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        // A full circle (end = start) is one turn, not zero.
        let full = Arc { to: from, ..a };
        assert!((full.sweep(&from).1 - std::f64::consts::TAU).abs() < 1e-12);
        // G18: the plane is Z X; a helix rises along Y.
        let g18 = Arc {
            to: [0.0, 5.0, 10.0, 0.0, 0.0, 0.0],
            centre: [0.0, 0.0],
            plane: Plane::ZX,
            // From Z0 X10 (90° in the Z X plane) to Z10 X0 (0°): a quarter clockwise seen from +Y.
            clockwise: true,
            turns: 0,
        };
        let l = g18.length(&from);
        assert!((l - (10.0 * std::f64::consts::FRAC_PI_2).hypot(5.0)).abs() < 1e-9);
    }
}
