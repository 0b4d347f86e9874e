//! Cutter radius compensation (G40, G41, G42) over a stream of moves, in two styles.
//!
//! The kernel hands every programmed move to a [`Compensator`] ([`Compensator::push`]) with the
//! programmed point it starts from; the compensator writes tool-centre moves to a callback, holding
//! back only what the next corner can still change (one plane element and the moves without motion
//! in the plane that follow it). Everything is computed in the plane of [`Plane::axes`] (first,
//! second axis; "left" and "right" are seen from the positive normal axis, as G2/G3 are). Axes out
//! of the plane (the normal axis, A B C) are never offset: each output move takes them from its
//! programmed end point. A negative radius swaps the side (G41 ↔ G42), as on both controls
//! (Fanuc: [16/18-C MC operator's manual p. 302](http://www.cncmanuals.com/fanuc/fanuc-series-16-18-160-180-model-c-machining-center-operators-manual.html/302);
//! LinuxCNC: `convert_cutter_compensation_on`). A radius of 0 is no compensation (given while
//! compensation is on, it cancels, as `D0` does on Fanuc).
//!
//! Words used below: the *offset element* of a line is the parallel line at distance r on the
//! compensation side; of an arc, the concentric arc of radius R + r (tool outside the arc: G41 on
//! G2, G42 on G3) or R − r (tool inside: G41 on G3, G42 on G2). `A` is the offset of a corner point
//! P perpendicular to the element ending there (P + r·n₁), `B` the one perpendicular to the element
//! starting there (P + r·n₂); t₁, t₂ are the unit tangents at P. The *turn* at P is the angle from
//! t₁ to t₂; a corner is *inner* (concave) when the path turns towards the tool side, *outer*
//! (convex) when it turns away. Fanuc measures α, the angle on the workpiece side: inner is
//! α ≥ 180°, outer obtuse 180° > α ≥ 90°, outer acute α < 90°.
//!
//! # `Style::LinuxCnc`: LinuxCNC's rs274ngc interpreter
//!
//! As `src/emc/rs274ngc/interp_convert.cc` (`convert_straight_comp1/2`, `convert_arc_comp1/2`,
//! `convert_cutter_compensation_off`) and `interp_queue.cc` (`move_endpoint_and_flush`) do it, read
//! at LinuxCNC commit 5c41560e (the comp code is unchanged since 2.9.0~pre1, the installed `rs274`),
//! and checked against `rs274` traces (tests below). The corner tolerance is 0.05 rad.
//!
//! 1. **Start-up** (the first move with motion in the plane after G41/G42). A line ends at its
//!    programmed end point offset by r perpendicular to the line from where the tool is; it must be
//!    longer than r. An arc ends at its end point offset by r along the radius, on a new centre that
//!    keeps it circular from where the tool is. The next element then treats the start-up line as
//!    the *parallel* offset of the programmed start-up line, so at an inner corner the tool goes
//!    straight from where it is to the intersection of that parallel with the next offset element.
//! 2. **Inner corners** (turn towards the tool by more than 0.05 rad, or a reversal beyond 180° −
//!    0.05): the previous element (and any held move without plane motion after it) is cut back to
//!    the intersection of the two offset elements. Line/arc: the intersection with the offset line
//!    of the line, the later one along the line when the tool is inside the arc, the earlier one
//!    otherwise; arc/arc: the one given by the tool being inside the previous arc and the direction
//!    of the next. A tangent reversal onto an arc with the tool outside it (the top of an "m" or
//!    "h") is an inner corner too. The cut-back previous element must not turn backwards (a line
//!    against its programmed direction, an arc sweeping more than before by over 0.0254 rad).
//! 3. **Outer corners** (turn away from the tool by more than 0.05 rad): the previous element keeps
//!    its perpendicular end; an arc of radius r about the programmed corner (G2 for G41, G3 for G42)
//!    joins it to the start of the next offset element. Under G0 the joint is a straight rapid
//!    instead. The joint is made at the normal-axis position before the next move (a Z plunge
//!    happens before the arc), with the next move's A B C.
//! 4. **Tangent** (within 0.05 rad): the next element starts where the tool is.
//! 5. **Moves without motion in the plane** (a Z plunge) are held after the element before them and
//!    made at its final end point, so they never break the corner between the elements around them.
//! 6. **Cancel** (the move after G40): the last element ends at its end point's perpendicular offset
//!    and the cancel move goes straight from there to its programmed point; it must be a line.
//! 7. **A block's other operations** (its F, an M8) go out with its moves in program order, as
//!    rs274's queue keeps them: after the moves held from before it and before the arc round a
//!    convex corner, which is the new block's and moves at its F ([`Compensator::held_moves`]).
//!
//! Deliberate differences from rs274ngc (which refuses these): a move without plane motion right
//! after G41/G42 passes through and the start-up waits for the first plane move; G41/G42 while on
//! ends the contour (as [`Compensator::flush`]) and the next move starts up again.
//!
//! # `Style::Fanuc`: Fanuc cutter compensation C (and the NCT control of the textbook corpus)
//!
//! Sources: Fanuc 15i-MA operator's manual B-63324EN
//! [p. 402](http://www.cncmanuals.com/fanuc/fanuc-series-15i-150i-ma-programming-operators-manual.html/402)
//! (cancel mode, arcs refused with alarm 034, offset change at a block's end) and
//! [p. 419](http://www.cncmanuals.com/fanuc/fanuc-series-15i-150i-ma-programming-operators-manual.html/419)
//! (offset mode: intersection of two read-ahead moves); 16/18-C MC manual
//! [p. 293](http://www.cncmanuals.com/fanuc/fanuc-series-16-18-160-180-model-c-machining-center-operators-manual.html/293)
//! (start-up in G00/G01 only); NCT 99M manual
//! [p. 88](http://personalcare.manualsonline.com/manuals/mfg/nct_group/99m.html?p=88)
//! (outer corners: obtuse 90° ≤ α ≤ 180°, acute α < 90°); the 30i manual B-63944EN-1
//! [p. 238](http://www.cncmanuals.com/fanuc/740/30i-300i-300is-model-a-31i-310i-310is-model-a-and-a5-32i-320i-320is-model-a-users-manual/page/238)
//! and 16i-LB [p. 208](http://www.cncmanuals.com/fanuc/665/16i-160i-lb-operators-manual/page/208)
//! (interference: a compensated path running against the programmed one, an inside corner radius
//! below the tool radius, alarm and stop); the corpus README (NCT rules, exercises 9/10/14);
//! [cnc.wiki](https://cnc.wiki/en/g40-g41-g42-tool-nose-cutter-radius-compensation) (parameter
//! No. 5003 SUP/SUV selects the start-up/cancel type); alarm numbers and texts from a public
//! Fanuc alarm list. B-64304EN itself was not among the stored pages, and the stored excerpts lack
//! the manuals' figures: the construction for each corner type follows Fanuc's usual figures
//! (start-up, offset mode, cancel; inner, obtuse, acute; line and arc), and what no stored text
//! states is marked *(inferred)*.
//!
//! 1. **Start-up** (the first move with motion in the plane after G41/G42; G02/G03 there is alarm
//!    0034). Inner corner with the next element: the start-up line goes from where the tool is to
//!    the intersection of the programmed start-up line's parallel offset with the next offset
//!    element (both types; the corpus README calls this the usual intersection start-up). Outer
//!    corner, **type A** (the default, parameter No. 5003#0 SUP = 0): it ends at `B`, the offset
//!    perpendicular to the next element at its start. **Type B** (SUP = 1,
//!    [`Compensator::set_type_b`]): as an outer corner in offset mode, the start-up line playing the
//!    previous element *(inferred)*.
//! 2. **Inner corners** (α ≥ 180°): the two offset elements are cut at their intersection (the one
//!    nearest behind the previous element's perpendicular end); none is alarm 0033.
//! 3. **Outer obtuse corners** (180° > α ≥ 90°): the two offset elements are extended to their
//!    intersection (the one nearest ahead of the previous element's perpendicular end, within 4r;
//!    an arc is extended along its circle). If there is none the acute construction is used
//!    *(inferred)*.
//! 4. **Outer acute corners** (α < 90°): each offset element is extended by r past the corner along
//!    its tangent and the two ends are joined: a line ends at `A + r·t₁` (an arc ends at `A` and a
//!    straight move goes to `A + r·t₁`), a straight move goes to `B − r·t₂`, and the next element
//!    starts there (a line) or after a straight move to `B` (an arc) *(arc cases inferred)*.
//! 5. **Tangent** (|turn| ≤ 1e-9 rad, or an inner corner within 0.01 rad whose elements have no
//!    intersection through rounding): the previous element ends at `A`, the next starts at `B`.
//! 6. **Moves without motion in the plane** are held after the element before them and made where
//!    that element finally ends (before any straight corner moves, which take the mode G0/G1 of the
//!    next element and the axes out of the plane of the previous one) *(inferred: Fanuc reads ahead
//!    past such blocks, 15i p. 419)*.
//! 7. **Cancel** (the move after G40, a line; G02/G03 is alarm 0034): where the last element and the
//!    cancel line make an inner corner, the last element ends at the intersection of its offset
//!    element with the cancel line's parallel offset (the corpus README's NCT rule (4)); at an outer
//!    corner, type A: at its end point's perpendicular offset `A`; type B: as an outer corner in
//!    offset mode *(inferred)*. The cancel move then goes straight to its programmed point. A cancel
//!    move without plane motion ends the last element at `A`.
//! 8. **Interference** (alarm 0041): a compensated line running against its programmed direction, a
//!    compensated arc whose sweep differs from the programmed one by more than 180°, an inside arc
//!    whose radius is not larger than r.
//! 9. **Changes in offset mode** *(inferred)*: G41/G42 while on, or a new radius, applies from the
//!    next element; the corner before it uses the previous radius (15i p. 402: the new value counts
//!    from the end point of the block that gives it) and each element's own side; a change of side
//!    joins the two offset elements at their intersection if its distances to the two
//!    perpendicular ends add up to at most 4r, otherwise `A` to `B` by a straight move.
//!
//! # Both styles
//!
//! Alarms: 0033 no intersection of offset elements, 0034 an arc as start-up (Fanuc) or cancel move,
//! 0037 an arc or G41/G42 in another plane than compensation's, 0038 an arc whose start or end
//! point is its centre, 0041 interference (gouging, the tool does not fit an inside arc, a
//! LinuxCNC start-up not longer than the radius). Numbers and names as Fanuc's alarm list (PS0033
//! NO SOLUTION AT CRC, PS0034 NO CIRC ALLOWED IN ST-UP/EXT BLK, PS0037, PS0038 INTERFERENCE IN
//! CIRCULAR BLOCK, PS0041 INTERFERENCE IN CRC). [`Compensator::flush`] writes the held moves as if
//! the contour ended (perpendicular end point); a later element starts with a straight move from
//! where the tool is to its own perpendicular start offset (no corner can be computed any more, so
//! an inner corner is overcut, as Fanuc warns for blocks it cannot read ahead, 15i p. 419; in the
//! LinuxCNC style an outer corner still gets its arc, which needs nothing held); the caller should
//! flush only when it must. A move whose in-plane displacement is at most 1e-9 has
//! no motion in the plane; the caller drops moves below the least increment before pushing.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use fmsvm_block::{Alarm, Stop};

use fmsvm_canon::geom::{
    V2, add, angle, circle_circle, cross, dir, dist, dot, left, line_circle, line_line, scale, sub,
    sweep, turned, unit,
};
use fmsvm_canon::{Arc, Plane, Pose};

/// The side of the programmed path the tool keeps to.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Side {
    /// G41: the tool on the left, seen along the motion from the positive normal axis.
    Left,
    /// G42: the tool on the right.
    Right,
}

/// Whose rules resolve the corners (see the module documentation).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Style {
    /// Fanuc cutter compensation C (intersections, extra moves at acute corners).
    Fanuc,
    /// LinuxCNC's rs274ngc interpreter (arcs around convex corners).
    LinuxCnc,
}

/// A move in output-frame coordinates; arcs are in their own plane (compensated only in the
/// compensation plane).
#[derive(Clone, Copy, PartialEq, Debug)]
pub enum Move {
    /// A straight move, at rapid traverse (G0) or the feed rate (G1).
    Line {
        /// End point.
        to: Pose,
        /// G0 rather than G1.
        rapid: bool,
    },
    /// A circular or helical move at the feed rate.
    Arc(Arc),
}

impl Move {
    /// The end point.
    pub fn to(&self) -> Pose {
        match self {
            Move::Line { to, .. } => *to,
            Move::Arc(a) => a.to,
        }
    }

    fn with_to(self, to: Pose) -> Move {
        match self {
            Move::Line { rapid, .. } => Move::Line { to, rapid },
            Move::Arc(a) => Move::Arc(Arc { to, ..a }),
        }
    }
}

/// 0033: the offset elements have no intersection.
const NO_INTERSECTION: u32 = 33;
/// 0034: an arc as start-up or cancel move.
const NO_CIRC_START_CANCEL: u32 = 34;
/// 0037: the plane changed under compensation.
const PLANE_CHANGE: u32 = 37;
/// 0038: an arc's start or end point is its centre.
const ARC_AT_CENTRE: u32 = 38;
/// 0041: interference (the compensated path gouges or runs backwards).
const INTERFERENCE: u32 = 41;

/// LinuxCNC's TOLERANCE_CONCAVE_CORNER (radians).
const LC_SMALL: f64 = 0.05;
/// LinuxCNC's allowance for an arc's sweep growing when its end is moved (mm units).
const LC_SWEEP_GROWTH: f64 = 0.0254;
/// In-plane displacement that is no motion in the plane.
const NO_MOTION: f64 = 1e-9;
/// Fanuc style: a turn this small is a tangent joint.
const TANGENT: f64 = 1e-9;
/// Fanuc style: an inner corner this small whose intersection is lost to rounding is tangent.
const NEAR_TANGENT: f64 = 0.01;

fn put(plane: Plane, mut p: Pose, q: V2) -> Pose {
    let (a, b, _) = plane.axes();
    p[a] = q[0];
    p[b] = q[1];
    p
}

/// The angle (0 ≤ a < 2π) travelled from `s` to `e` about `c` in the arc's direction; within 1e-9 of
/// a whole turn is none.
fn travel(s: V2, e: V2, c: V2, ccw: bool) -> f64 {
    let d = turned(s, e, c, ccw);
    if d > TAU - 1e-9 { 0.0 } else { d }
}

/// Where a compensated arc that should sweep `prog` (radians) from `start` ends: a full circle whose
/// compensated end meets its start within rounding ends exactly there (a whole turn, not none).
fn fit_arc_end(start: V2, end: V2, prog: f64) -> V2 {
    if dist(start, end) < 1e-9 && prog > PI {
        start
    } else {
        end
    }
}

// ---------------------------------------------------------------------------------------------
// The compensator
// ---------------------------------------------------------------------------------------------

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum State {
    /// No compensation: moves pass through.
    Off,
    /// G41/G42 given, waiting for the start-up move.
    Starting,
    /// Compensating.
    On,
    /// G41/G42 again while on (LinuxCNC style) or after G40 without a move: end the contour at the
    /// next move, then start up.
    Restart,
    /// G40 given: the next move is the cancel move.
    Cancelling,
}

/// What LinuxCNC checks when a held move's end point is moved.
#[derive(Clone, Copy, Debug)]
enum Check {
    /// Nothing (start-up moves, moves without plane motion).
    None,
    /// A line must not run against its programmed direction.
    Line(V2),
    /// An arc must not sweep more than its programmed `l1` (+ 0.0254).
    Arc(f64),
}

#[derive(Clone, Copy, Debug)]
struct Held {
    mv: Move,
    /// The move has motion in the plane (only the first held move can).
    plane: bool,
    check: Check,
    /// The programmed sweep, for arcs (full-circle fitting).
    prog_sweep: f64,
}

/// LinuxCNC style: the interpreter's queue and its current point.
#[derive(Debug, Default)]
struct Lc {
    queue: Vec<Held>,
    /// Start of the held plane move (rs274ngc's `endpoint`, None = not valid).
    endpoint: Option<V2>,
    /// Compensated end of the last move queued (rs274ngc's `current`).
    cur: Pose,
}

/// The programmed plane geometry of an element.
#[derive(Clone, Copy, Debug)]
enum Geom {
    Line { a: V2, b: V2 },
    Arc { a: V2, b: V2, c: V2, ccw: bool },
}

impl Geom {
    fn start(&self) -> V2 {
        match *self {
            Geom::Line { a, .. } | Geom::Arc { a, .. } => a,
        }
    }
    fn end(&self) -> V2 {
        match *self {
            Geom::Line { b, .. } | Geom::Arc { b, .. } => b,
        }
    }
    fn tangent_at(&self, q: V2) -> V2 {
        match *self {
            Geom::Line { a, b } => unit(sub(b, a)).unwrap_or_default(),
            Geom::Arc { c, ccw, .. } => {
                let t = left(unit(sub(q, c)).unwrap_or_default());
                if ccw { t } else { scale(t, -1.0) }
            }
        }
    }
    fn t_start(&self) -> V2 {
        self.tangent_at(self.start())
    }
    fn t_end(&self) -> V2 {
        self.tangent_at(self.end())
    }
}

/// An offset element, extended: a line or a circle.
#[derive(Clone, Copy, Debug)]
enum Curve {
    Line { p: V2, d: V2 },
    Circle { c: V2, rho: f64, ccw: bool },
}

fn intersections(x: Curve, y: Curve) -> Vec<V2> {
    match (x, y) {
        (Curve::Line { p, d }, Curve::Line { p: q, d: e }) => {
            line_line(p, d, q, e).into_iter().collect()
        }
        (Curve::Line { p, d }, Curve::Circle { c, rho, .. })
        | (Curve::Circle { c, rho, .. }, Curve::Line { p, d }) => match line_circle(p, d, c, rho) {
            Some((t1, t2)) => vec![add(p, scale(d, t1)), add(p, scale(d, t2))],
            None => Vec::new(),
        },
        (
            Curve::Circle { c, rho, .. },
            Curve::Circle {
                c: c2, rho: rho2, ..
            },
        ) => circle_circle(c, rho, c2, rho2).map_or_else(Vec::new, |p| p.to_vec()),
    }
}

/// Fanuc style: the held element.
#[derive(Clone, Debug)]
struct FElem {
    geom: Geom,
    /// Programmed end point (the axes out of the plane come from it).
    end: Pose,
    rapid: bool,
    turns: u32,
    /// Compensated start (where its output begins).
    start: V2,
    /// The start-up line (output from where the tool was; its offset element is the parallel).
    startup: bool,
    /// Side (+1 left, −1 right) and radius in effect for it.
    s: f64,
    r: f64,
    /// Moves without plane motion after it.
    zs: Vec<(Pose, bool)>,
}

/// The end of one element and the start of the next at a Fanuc corner.
struct Corner {
    a_end: V2,
    extra: Vec<V2>,
    b_start: V2,
}

/// Cutter radius compensation over a stream of moves (see the module documentation).
#[derive(Debug)]
pub struct Compensator {
    style: Style,
    type_b: bool,
    state: State,
    side: Side,
    radius: f64,
    plane: Plane,
    /// An alarm raised by `start` (which cannot fail), reported by the next `push` or `flush`.
    pending_alarm: Option<Alarm>,
    /// G40 with I J (NCT): the direction the cancel corner is taken with.
    cancel_dir: Option<V2>,
    /// `,R0` (NCT, Fanuc style): the next corner, if convex, goes round on an arc of the tool radius.
    round_next: bool,
    /// The tool centre after the last move given out.
    tool: Option<Pose>,
    /// A lathe tool's controlled point (its imaginary tip) less its nose centre: added to every
    /// compensated move written (zero for a milling cutter, tip 0 or 9).
    tip: Pose,
    lc: Lc,
    fa: Option<FElem>,
}

type Out<'a> = &'a mut dyn FnMut(Move) -> Result<(), Stop>;

impl Compensator {
    /// A compensator, off.
    pub fn new(style: Style) -> Self {
        Compensator {
            style,
            type_b: false,
            state: State::Off,
            side: Side::Left,
            radius: 0.0,
            plane: Plane::XY,
            pending_alarm: None,
            cancel_dir: None,
            round_next: false,
            tool: None,
            tip: [0.0; 6],
            lc: Lc::default(),
            fa: None,
        }
    }

    /// Fanuc style: start-up and cancel of type B (parameter No. 5003#0 SUP = 1) instead of type A
    /// (the default). No effect on the LinuxCNC style. No parameter selects it yet: only the tests.
    #[cfg_attr(not(test), allow(dead_code))]
    pub fn set_type_b(&mut self, type_b: bool) {
        self.type_b = type_b;
    }

    /// Compensation is on, or moves are still held.
    pub fn is_active(&self) -> bool {
        self.state != State::Off || !self.lc.queue.is_empty() || self.fa.is_some()
    }

    /// G41/G42 with radius r (already resolved from D, may be negative = other side); the next move
    /// is the start-up.
    pub fn start(&mut self, side: Side, radius: f64, plane: Plane) {
        let side = if radius < 0.0 {
            match side {
                Side::Left => Side::Right,
                Side::Right => Side::Left,
            }
        } else {
            side
        };
        let radius = radius.abs();
        if radius == 0.0 {
            match self.state {
                State::Off | State::Starting => self.state = State::Off,
                _ => self.cancel(),
            }
            return;
        }
        match self.state {
            State::Off | State::Starting => self.state = State::Starting,
            State::On if self.style == Style::Fanuc => {
                if plane != self.plane && self.pending_alarm.is_none() {
                    self.pending_alarm = Some(Alarm::new(
                        PLANE_CHANGE,
                        "CAN NOT CHANGE PLANE IN CRC: G41/G42 in another plane while compensation is on",
                    ));
                }
                self.side = side;
                self.radius = radius;
                return;
            }
            State::On | State::Restart | State::Cancelling => self.state = State::Restart,
        }
        self.side = side;
        self.radius = radius;
        self.plane = plane;
    }

    /// A lathe tool: its controlled point is `tip` (X, Z) from the centre of its nose, which the
    /// compensation steers; every compensated move is written `tip` away from the centre path (as
    /// LinuxCNC's `latheorigin_x`/`latheorigin_z` and Fanuc's imaginary tool nose do). Set with
    /// `start`; the start-up move is aimed from the controlled point, the cancel move ends on the
    /// programmed point.
    pub fn set_tip(&mut self, tip: Pose) {
        self.tip = tip;
    }

    /// G40: the next move is the cancel move.
    /// G40 with I J (NCT, textbook exercise 14): the last element ends at its intersection with the
    /// line of direction `dir` from its programmed end, both offset by the radius (always the
    /// intersection, in both styles); then the cancel move goes to its programmed point.
    pub fn cancel_along(&mut self, dir: [f64; 2]) {
        self.cancel();
        if self.state == State::Cancelling && dist(dir, [0.0, 0.0]) > 0.0 {
            self.cancel_dir = Some(unit(dir).unwrap_or_default());
        }
    }

    /// `,R0` (NCT, exercise 10): under the Fanuc style the corner between the held element and the
    /// next one, if convex, is an arc of the tool radius about the programmed corner (the contour's
    /// corner stays sharp); the LinuxCNC style rounds convex corners so anyway.
    pub fn round_next_corner(&mut self) {
        self.round_next = true;
    }

    /// G40: the next move is the cancel move.
    pub fn cancel(&mut self) {
        self.state = match self.state {
            State::Off | State::Starting => State::Off,
            State::On | State::Restart | State::Cancelling => State::Cancelling,
        };
    }

    /// LinuxCNC style: how many moves it holds from earlier pushes (the next push gives them out
    /// first, then the corner's joint). None in the Fanuc style, whose corner moves are the held
    /// element's.
    pub fn held_moves(&self) -> Option<usize> {
        match self.style {
            Style::LinuxCnc if self.state != State::Off => Some(self.lc.queue.len()),
            _ => None,
        }
    }

    /// Where the tool centre is now (after the last move given to `out`).
    #[cfg(test)]
    pub fn tool_position(&self) -> Option<Pose> {
        self.tool
    }

    /// The next programmed move from `from` (the programmed, uncompensated previous end point).
    /// Compensated moves that are now final go to `out`, in order; at most what the next corner needs
    /// is held back.
    pub fn push(&mut self, from: Pose, m: Move, out: Out<'_>) -> Result<(), Stop> {
        if let Some(a) = self.pending_alarm.take() {
            return Err(a.into());
        }
        if self.state == State::Restart {
            self.end_contour(out)?;
            self.state = State::Starting;
        }
        match self.state {
            State::Off | State::Restart => self.emit(m, out),
            State::Starting => {
                if !self.plane_motion(&from, &m) {
                    return self.emit(m, out);
                }
                self.check_plane(&m)?;
                self.state = State::On;
                match self.style {
                    Style::LinuxCnc => self.lc_start(from, m, out),
                    Style::Fanuc => self.fa_start(from, m),
                }
            }
            State::On => {
                if self.plane_motion(&from, &m) {
                    self.check_plane(&m)?;
                }
                match self.style {
                    Style::LinuxCnc => match m {
                        Move::Line { to, rapid } => self.lc_line(from, to, rapid, out),
                        Move::Arc(a) => self.lc_arc(from, a, out),
                    },
                    Style::Fanuc => self.fa_push(from, m, out),
                }
            }
            State::Cancelling => {
                let Move::Line { to, rapid } = m else {
                    return Err(Alarm::new(
                        NO_CIRC_START_CANCEL,
                        "NO CIRC ALLOWED IN ST-UP/EXT BLK: the move that cancels compensation (G40) must be straight",
                    )
                    .into());
                };
                let along = self.cancel_dir.take();
                match (self.style, along) {
                    (Style::LinuxCnc, Some(d)) => {
                        // The compensated last line (its start to the current point) meets the
                        // offset of the line from the programmed end along `d`.
                        let c = self.plane.project(&self.lc.cur);
                        let x = match (self.lc_front(), self.lc.endpoint) {
                            (Some(Move::Line { .. }), Some(s)) if dist(s, c) > NO_MOTION => {
                                let t1 = unit(sub(c, s)).unwrap_or_default();
                                let n = if self.left() {
                                    left(d)
                                } else {
                                    scale(left(d), -1.0)
                                };
                                let q = add(self.plane.project(&from), scale(n, self.radius));
                                let den = cross(t1, d);
                                if den.abs() < 1e-12 {
                                    c
                                } else {
                                    add(c, scale(t1, cross(sub(q, c), d) / den))
                                }
                            }
                            _ => c,
                        };
                        self.lc_flush_at(x, out)?;
                        self.lc_dequeue(out)?;
                    }
                    (Style::LinuxCnc, None) => {
                        let c = self.plane.project(&self.lc.cur);
                        self.lc_flush_at(c, out)?;
                        self.lc_dequeue(out)?;
                    }
                    (Style::Fanuc, Some(d)) => {
                        let mut virt = from;
                        let (a, b, _) = self.plane.axes();
                        virt[a] += d[0];
                        virt[b] += d[1];
                        self.fa_cancel(from, virt, rapid, out)?;
                    }
                    (Style::Fanuc, None) => self.fa_cancel(from, to, rapid, out)?,
                }
                self.state = State::Off;
                self.emit(Move::Line { to, rapid }, out)
            }
        }
    }

    /// End of program, or anything that forces the held moves out: writes them as if the contour
    /// ended there (compensation stays on; a later element starts from where the tool is).
    pub fn flush(&mut self, out: Out<'_>) -> Result<(), Stop> {
        if let Some(a) = self.pending_alarm.take() {
            return Err(a.into());
        }
        self.end_contour(out)
    }

    // -- shared --------------------------------------------------------------------------------

    fn end_contour(&mut self, out: Out<'_>) -> Result<(), Stop> {
        match self.style {
            Style::LinuxCnc => {
                if !self.lc.queue.is_empty() {
                    let c = self.plane.project(&self.lc.cur);
                    self.lc_flush_at(c, out)?;
                    self.lc_dequeue(out)?;
                }
                Ok(())
            }
            Style::Fanuc => {
                if let Some(a) = self.fa.take() {
                    let end = self.fa_perp_end(&a);
                    self.fa_emit(a, end, &[], false, out)?;
                }
                Ok(())
            }
        }
    }

    fn emit(&mut self, m: Move, out: Out<'_>) -> Result<(), Stop> {
        if let (Move::Line { to, .. }, Some(t)) = (m, self.tool)
            && to.iter().zip(t.iter()).all(|(a, b)| (a - b).abs() <= 1e-12)
        {
            return Ok(());
        }
        if matches!(self.state, State::Off | State::Starting) || self.tip == [0.0; 6] {
            out(m)?;
        } else {
            out(self.at_tip(m))?;
        }
        self.tool = Some(m.to());
        Ok(())
    }

    /// A move of the nose centre as its controlled point makes it.
    fn at_tip(&self, m: Move) -> Move {
        let mut to = m.to();
        for (v, d) in to.iter_mut().zip(self.tip) {
            *v += d;
        }
        match m {
            Move::Line { rapid, .. } => Move::Line { to, rapid },
            Move::Arc(a) => {
                let (i, j, _) = a.plane.axes();
                Move::Arc(Arc {
                    to,
                    centre: [a.centre[0] + self.tip[i], a.centre[1] + self.tip[j]],
                    ..a
                })
            }
        }
    }

    fn plane_motion(&self, from: &Pose, m: &Move) -> bool {
        match m {
            Move::Arc(_) => true,
            Move::Line { to, .. } => {
                dist(self.plane.project(from), self.plane.project(to)) > NO_MOTION
            }
        }
    }

    fn check_plane(&self, m: &Move) -> Result<(), Alarm> {
        if let Move::Arc(a) = m
            && a.plane != self.plane
        {
            return Err(Alarm::new(
                PLANE_CHANGE,
                "CAN NOT CHANGE PLANE IN CRC: an arc in another plane than cutter compensation's",
            ));
        }
        Ok(())
    }

    fn left(&self) -> bool {
        self.side == Side::Left
    }

    /// An arc's programmed geometry, checked for a zero radius.
    fn arc_geom(&self, from: &Pose, a: &Arc) -> Result<Geom, Alarm> {
        let s = self.plane.project(from);
        let e = self.plane.project(&a.to);
        if dist(s, a.centre) < 1e-9 || dist(e, a.centre) < 1e-9 {
            return Err(Alarm::new(
                ARC_AT_CENTRE,
                format!(
                    "INTERFERENCE IN CIRCULAR BLOCK: the arc's start or end point is its centre {:.4} {:.4}",
                    a.centre[0], a.centre[1]
                ),
            ));
        }
        Ok(Geom::Arc {
            a: s,
            b: e,
            c: a.centre,
            ccw: !a.clockwise,
        })
    }

    /// A corner move's pose: plane point `q`, the normal axis where the tool is, A B C of `to`.
    fn corner_pose(&self, to: &Pose, at: &Pose, q: V2) -> Pose {
        let (_, _, n) = self.plane.axes();
        let mut p = put(self.plane, *to, q);
        p[n] = at[n];
        p
    }

    // -- LinuxCNC ------------------------------------------------------------------------------

    fn lc_start(&mut self, from: Pose, m: Move, out: Out<'_>) -> Result<(), Stop> {
        let pl = self.plane;
        let r = self.radius;
        let c = pl.project(&from);
        self.lc.cur = from;
        match m {
            Move::Line { to, rapid } => {
                let p = pl.project(&to);
                if dist(p, c) <= r {
                    return Err(Alarm::new(
                        INTERFERENCE,
                        format!(
                            "INTERFERENCE IN CRC: the start-up move ({:.4}) is not longer than the tool radius {r}",
                            dist(p, c)
                        ),
                    )
                    .into());
                }
                let alpha = angle(sub(p, c)) + if self.left() { FRAC_PI_2 } else { -FRAC_PI_2 };
                let end = put(pl, to, add(p, scale(dir(alpha), r)));
                self.lc_dequeue(out)?;
                self.lc.endpoint = Some(c);
                self.lc.queue.push(Held {
                    mv: Move::Line { to: end, rapid },
                    plane: true,
                    check: Check::None,
                    prog_sweep: 0.0,
                });
                self.lc.cur = end;
            }
            Move::Arc(a) => {
                let g = self.arc_geom(&from, &a)?;
                let p = pl.project(&a.to);
                let cen = a.centre;
                if dist(p, c) <= r {
                    return Err(Alarm::new(
                        INTERFERENCE,
                        "INTERFERENCE IN CRC: the start-up arc's end is not farther than the tool radius from the start",
                    )
                    .into());
                }
                let inside = self.left() != a.clockwise;
                if inside && dist(cen, c) <= r {
                    return Err(too_small(dist(cen, c), r).into());
                }
                let gamma = if inside {
                    angle(sub(cen, p))
                } else {
                    angle(sub(p, cen))
                };
                let new_end = add(p, scale(dir(gamma), r));
                let b_len = dist(c, new_end) / 2.0;
                let ab = angle(sub(cen, new_end));
                let a_ang = angle(sub(c, new_end)) - ab;
                if a_ang.cos().abs() < 1e-6 {
                    return Err(too_small(dist(cen, p), r).into());
                }
                let new_cen = add(new_end, scale(dir(ab), b_len / a_ang.cos()));
                let to = put(pl, a.to, new_end);
                let ccw = !a.clockwise;
                let prog = sweep(g.start(), g.end(), cen, ccw, a.turns);
                self.lc_dequeue(out)?;
                if self.tip != [0.0; 6] {
                    // A lathe tool: its controlled point goes first from where it stands to where
                    // it is as the nose centre starts the arc (rs274ngc's `convert_arc_comp1`),
                    // or the arc would not be one.
                    out(self.at_tip(Move::Line {
                        to: from,
                        rapid: false,
                    }))?;
                    self.tool = Some(from);
                }
                self.lc.endpoint = None;
                self.lc.queue.push(Held {
                    mv: Move::Arc(Arc {
                        to,
                        centre: new_cen,
                        ..a
                    }),
                    plane: true,
                    check: Check::None,
                    prog_sweep: prog,
                });
                self.lc.cur = to;
            }
        }
        Ok(())
    }

    /// The held plane move, if the queue starts with one.
    fn lc_front(&self) -> Option<Move> {
        self.lc.queue.first().filter(|h| h.plane).map(|h| h.mv)
    }

    /// A move without plane motion: held after the plane move, or made now if none is held.
    fn lc_no_plane(&mut self, to: Pose, rapid: bool, out: Out<'_>) -> Result<(), Stop> {
        let c = self.plane.project(&self.lc.cur);
        let pose = put(self.plane, to, c);
        self.lc.cur = pose;
        let mv = Move::Line { to: pose, rapid };
        if self.lc_front().is_some() {
            self.lc.queue.push(Held {
                mv,
                plane: false,
                check: Check::None,
                prog_sweep: 0.0,
            });
            Ok(())
        } else {
            self.emit(mv, out)
        }
    }

    /// rs274ngc's `move_endpoint_and_flush`: every held move ends at `x` (checked), then all go out.
    fn lc_flush_at(&mut self, x: V2, out: Out<'_>) -> Result<(), Stop> {
        if self.lc.queue.is_empty() {
            return Ok(());
        }
        let pl = self.plane;
        let queue = std::mem::take(&mut self.lc.queue);
        let mut moved = Vec::with_capacity(queue.len());
        for h in &queue {
            match (h.check, self.lc.endpoint, h.mv) {
                (Check::Line(d), Some(e), _) if dot(d, sub(x, e)) < 0.0 => {
                    return Err(Alarm::new(
                        INTERFERENCE,
                        format!(
                            "INTERFERENCE IN CRC: straight move in a concave corner cannot be reached by the tool without gouging (corner {:.4} {:.4})",
                            x[0], x[1]
                        ),
                    )
                    .into());
                }
                (Check::Arc(l1), Some(e), Move::Arc(a)) => {
                    let l2 = sweep(e, x, a.centre, !a.clockwise, a.turns);
                    if l1 != 0.0 && l2 > l1 + LC_SWEEP_GROWTH {
                        return Err(Alarm::new(
                            INTERFERENCE,
                            format!(
                                "INTERFERENCE IN CRC: arc in a concave corner cannot be reached by the tool without gouging (corner {:.4} {:.4})",
                                x[0], x[1]
                            ),
                        )
                        .into());
                    }
                }
                _ => {}
            }
            let mut q = x;
            if let (Move::Arc(_), Some(t)) = (h.mv, self.tool)
                && h.plane
            {
                q = fit_arc_end(pl.project(&t), x, h.prog_sweep);
            }
            moved.push(h.mv.with_to(put(pl, h.mv.to(), q)));
        }
        for m in moved {
            self.emit(m, out)?;
        }
        self.lc.endpoint = Some(x);
        Ok(())
    }

    /// rs274ngc's `dequeue_canons`: the held moves go out as they are.
    fn lc_dequeue(&mut self, out: Out<'_>) -> Result<(), Stop> {
        let pl = self.plane;
        for h in std::mem::take(&mut self.lc.queue) {
            let mut m = h.mv;
            if let (Move::Arc(a), Some(t)) = (m, self.tool)
                && h.plane
            {
                let q = fit_arc_end(pl.project(&t), pl.project(&a.to), h.prog_sweep);
                m = m.with_to(put(pl, a.to, q));
            }
            self.emit(m, out)?;
        }
        self.lc.endpoint = None;
        Ok(())
    }

    fn lc_line(&mut self, from: Pose, to: Pose, rapid: bool, out: Out<'_>) -> Result<(), Stop> {
        let pl = self.plane;
        let p0 = pl.project(&from);
        let p = pl.project(&to);
        if dist(p0, p) <= NO_MOTION {
            return self.lc_no_plane(to, rapid, out);
        }
        let r = self.radius;
        let left = self.left();
        let c = pl.project(&self.lc.cur);
        let mut theta = angle(sub(c, p0));
        let mut alpha = angle(sub(p, p0));
        let beta = if left {
            if theta < alpha {
                theta += TAU;
            }
            theta - alpha - FRAC_PI_2
        } else {
            if alpha < theta {
                alpha += TAU;
            }
            alpha - theta - FRAC_PI_2
        };
        let gamma = if left { FRAC_PI_2 } else { -FRAC_PI_2 };
        let n = dir(alpha + gamma);
        let end = add(p, scale(n, r));
        let mid = add(p0, scale(n, r));
        let front = self.lc_front();
        let h_shape = matches!(front, Some(Move::Arc(a)) if a.clockwise == left);
        let convex_range = -LC_SMALL..=PI + LC_SMALL;
        let concave = !convex_range.contains(&beta) || (beta > PI - LC_SMALL && h_shape);
        let cur = self.lc.cur;
        if !concave && beta > LC_SMALL {
            // Convex: an arc about the programmed corner (a straight rapid under G0).
            self.lc_flush_at(c, out)?;
            let q = self.corner_pose(&to, &cur, mid);
            let m = if rapid {
                Move::Line { to: q, rapid: true }
            } else {
                Move::Arc(Arc {
                    to: q,
                    centre: p0,
                    plane: pl,
                    clockwise: left,
                    turns: 0,
                })
            };
            self.emit(m, out)?;
            self.lc.endpoint = Some(mid);
        } else if concave {
            match front {
                Some(Move::Line { .. }) => {
                    let half = (beta + PI) / 2.0;
                    if half == 0.0 {
                        return Err(Alarm::new(
                            INTERFERENCE,
                            "INTERFERENCE IN CRC: zero degree inside corner",
                        )
                        .into());
                    }
                    let x = add(c, scale(dir(theta + gamma), r / half.tan()));
                    self.lc_flush_at(x, out)?;
                }
                Some(Move::Arc(a)) => {
                    let rho = dist(pl.project(&a.to), a.centre);
                    let u = dir(alpha);
                    let inside_prev = left != a.clockwise;
                    let (t1, t2) =
                        line_circle(mid, u, a.centre, rho).ok_or_else(|| no_intersection(p0))?;
                    let x = add(mid, scale(u, if inside_prev { t1 } else { t2 }));
                    self.lc_flush_at(x, out)?;
                }
                None => {
                    let q = self.corner_pose(&to, &cur, mid);
                    self.emit(Move::Line { to: q, rapid }, out)?;
                    self.lc.endpoint = Some(mid);
                }
            }
        } else {
            self.lc_dequeue(out)?;
            self.lc.endpoint = Some(c);
        }
        let end = put(pl, to, end);
        self.lc.queue.push(Held {
            mv: Move::Line { to: end, rapid },
            plane: true,
            check: Check::Line(sub(p, p0)),
            prog_sweep: 0.0,
        });
        self.lc.cur = end;
        Ok(())
    }

    fn lc_arc(&mut self, from: Pose, a: Arc, out: Out<'_>) -> Result<(), Stop> {
        let pl = self.plane;
        let g = self.arc_geom(&from, &a)?;
        let p0 = g.start();
        let p = g.end();
        let cen = a.centre;
        let ccw = !a.clockwise;
        let r = self.radius;
        let left = self.left();
        let c = pl.project(&self.lc.cur);
        let arc_radius = dist(cen, p);
        let theta = angle(sub(c, p0)) + if left { -FRAC_PI_2 } else { FRAC_PI_2 };
        let mut delta = angle(sub(cen, p0));
        let alpha = if ccw {
            delta - FRAC_PI_2
        } else {
            delta + FRAC_PI_2
        };
        let mut beta = if left { theta - alpha } else { alpha - theta };
        if beta > 1.5 * PI {
            beta -= TAU;
        } else if beta < -FRAC_PI_2 {
            beta += TAU;
        }
        let inside = left == ccw;
        let gamma = if inside {
            if arc_radius <= r {
                return Err(too_small(arc_radius, r).into());
            }
            angle(sub(cen, p))
        } else {
            delta += PI;
            angle(sub(p, cen))
        };
        let new_end = add(p, scale(dir(gamma), r));
        let convex_range = -LC_SMALL..=PI + LC_SMALL;
        let concave = !convex_range.contains(&beta) || ((beta - PI).abs() < LC_SMALL && !inside);
        let cur = self.lc.cur;
        let mid = add(p0, scale(dir(delta), r));
        if concave {
            let new_rad = if inside {
                arc_radius - r
            } else {
                arc_radius + r
            };
            match self.lc_front() {
                Some(Move::Arc(pa)) => {
                    let old_rad = dist(pl.project(&pa.to), pa.centre);
                    let cc = dist(cen, pa.centre);
                    if old_rad == 0.0 || cc == 0.0 {
                        return Err(Alarm::new(
                            NO_INTERSECTION,
                            "NO SOLUTION AT CRC: arc to arc motion with the same centre",
                        )
                        .into());
                    }
                    let k =
                        (old_rad * old_rad + cc * cc - new_rad * new_rad) / (2.0 * old_rad * cc);
                    if !(-1.0..=1.0).contains(&k) {
                        return Err(no_intersection(p0).into());
                    }
                    let pull = k.acos();
                    let cc_dir = angle(sub(cen, pa.centre));
                    let inside_prev = left != pa.clockwise;
                    let sign = if inside_prev == ccw { 1.0 } else { -1.0 };
                    let x = add(pa.centre, scale(dir(cc_dir + sign * pull), old_rad));
                    self.lc_flush_at(x, out)?;
                }
                Some(Move::Line { .. }) => {
                    let u = dir(theta);
                    let (t1, t2) =
                        line_circle(c, u, cen, new_rad).ok_or_else(|| no_intersection(p0))?;
                    let x = add(c, scale(u, if inside { t2 } else { t1 }));
                    self.lc_flush_at(x, out)?;
                }
                None => {
                    let q = self.corner_pose(&a.to, &cur, mid);
                    self.emit(
                        Move::Line {
                            to: q,
                            rapid: false,
                        },
                        out,
                    )?;
                    self.lc.endpoint = Some(mid);
                }
            }
        } else if beta > LC_SMALL {
            self.lc_dequeue(out)?;
            let q = self.corner_pose(&a.to, &cur, mid);
            self.emit(
                Move::Arc(Arc {
                    to: q,
                    centre: p0,
                    plane: pl,
                    clockwise: left,
                    turns: 0,
                }),
                out,
            )?;
            self.lc.endpoint = Some(mid);
        } else {
            self.lc_dequeue(out)?;
            self.lc.endpoint = Some(c);
        }
        let prog = sweep(p0, p, cen, ccw, a.turns);
        let to = put(pl, a.to, new_end);
        self.lc.queue.push(Held {
            mv: Move::Arc(Arc { to, ..a }),
            plane: true,
            check: Check::Arc(prog),
            prog_sweep: prog,
        });
        self.lc.cur = to;
        Ok(())
    }

    // -- Fanuc ---------------------------------------------------------------------------------

    fn side_sign(&self) -> f64 {
        if self.left() { 1.0 } else { -1.0 }
    }

    fn fa_geom(&self, from: &Pose, m: &Move) -> Result<(Geom, Pose, bool, u32), Alarm> {
        Ok(match m {
            Move::Line { to, rapid } => (
                Geom::Line {
                    a: self.plane.project(from),
                    b: self.plane.project(to),
                },
                *to,
                *rapid,
                0,
            ),
            Move::Arc(a) => (self.arc_geom(from, a)?, a.to, false, a.turns),
        })
    }

    fn fa_start(&mut self, from: Pose, m: Move) -> Result<(), Stop> {
        let Move::Line { to, rapid } = m else {
            return Err(Alarm::new(
                NO_CIRC_START_CANCEL,
                "NO CIRC ALLOWED IN ST-UP/EXT BLK: the start-up move of compensation (G41/G42) must be straight",
            )
            .into());
        };
        let start = match self.tool {
            Some(t) => self.plane.project(&t),
            None => self.plane.project(&from),
        };
        self.fa = Some(FElem {
            geom: Geom::Line {
                a: self.plane.project(&from),
                b: self.plane.project(&to),
            },
            end: to,
            rapid,
            turns: 0,
            start,
            startup: true,
            s: self.side_sign(),
            r: self.radius,
            zs: Vec::new(),
        });
        Ok(())
    }

    /// The offset element of `g` for side `s`, radius `r`, at the point `q` of it.
    fn fa_curve(g: &Geom, s: f64, r: f64, q: V2) -> Result<Curve, Alarm> {
        let t = g.tangent_at(q);
        let n = scale(left(t), s);
        Ok(match *g {
            Geom::Line { .. } => Curve::Line {
                p: add(q, scale(n, r)),
                d: t,
            },
            Geom::Arc { c, ccw, .. } => {
                let radial = unit(sub(q, c)).unwrap_or_default();
                let rr = dist(q, c);
                let rho = rr + r * dot(n, radial);
                if rho <= 1e-9 {
                    return Err(too_small(rr, r));
                }
                Curve::Circle { c, rho, ccw }
            }
        })
    }

    /// `A`: the perpendicular offset of an element's end point.
    fn fa_perp_end(&self, a: &FElem) -> V2 {
        let p = a.geom.end();
        add(p, scale(left(a.geom.t_end()), a.s * a.r))
    }

    fn fa_push(&mut self, from: Pose, m: Move, out: Out<'_>) -> Result<(), Stop> {
        if !self.plane_motion(&from, &m) {
            let to = m.to();
            let rapid = matches!(m, Move::Line { rapid: true, .. });
            if let Some(a) = self.fa.as_mut() {
                a.zs.push((to, rapid));
                return Ok(());
            }
            let q = match self.tool {
                Some(t) => self.plane.project(&t),
                None => self.plane.project(&from),
            };
            return self.emit(
                Move::Line {
                    to: put(self.plane, to, q),
                    rapid,
                },
                out,
            );
        }
        let (geom, end, rapid, turns) = self.fa_geom(&from, &m)?;
        let s = self.side_sign();
        let r = self.radius;
        // A check that the element can be offset at all (an inside arc not larger than r).
        Self::fa_curve(&geom, s, r, geom.end())?;
        let round = std::mem::take(&mut self.round_next);
        let b_start = match self.fa.take() {
            Some(a) if round && a.s == s && cross(a.geom.t_end(), geom.t_start()) * s < 0.0 => {
                // A convex corner under `,R0`: round it on the tool radius about the corner.
                let p = a.geom.end();
                let pa = add(p, scale(left(a.geom.t_end()), s * r));
                let pb = add(p, scale(left(geom.t_start()), s * r));
                let at = a.end;
                self.fa_emit(a, pa, &[], rapid, out)?;
                self.emit(
                    Move::Arc(Arc {
                        to: put(self.plane, at, pb),
                        centre: p,
                        plane: self.plane,
                        clockwise: s > 0.0,
                        turns: 0,
                    }),
                    out,
                )?;
                pb
            }
            Some(a) => {
                let corner = self.fa_corner(&a, &geom, s, false)?;
                let bs = corner.b_start;
                self.fa_emit(a, corner.a_end, &corner.extra, rapid, out)?;
                bs
            }
            None => {
                // Nothing held (after a flush): straight from where the tool is to the start offset.
                let p = geom.start();
                let bs = add(p, scale(left(geom.t_start()), s * r));
                let at = self.tool.unwrap_or(from);
                let q = self.corner_pose(&at, &at, bs);
                self.emit(Move::Line { to: q, rapid }, out)?;
                bs
            }
        };
        self.fa = Some(FElem {
            geom,
            end,
            rapid,
            turns,
            start: b_start,
            startup: false,
            s,
            r,
            zs: Vec::new(),
        });
        Ok(())
    }

    fn fa_cancel(&mut self, from: Pose, to: Pose, rapid: bool, out: Out<'_>) -> Result<(), Stop> {
        let Some(a) = self.fa.take() else {
            return Ok(());
        };
        let p = self.plane.project(&from);
        let e = self.plane.project(&to);
        if dist(p, e) <= NO_MOTION {
            let end = self.fa_perp_end(&a);
            return self.fa_emit(a, end, &[], false, out);
        }
        let g = Geom::Line { a: p, b: e };
        let corner = self.fa_corner(&a, &g, a.s, true)?;
        self.fa_emit(a, corner.a_end, &corner.extra, rapid, out)
    }

    /// The Fanuc corner between the held element `a` and the next element `g` (side `sb`); `cancel`:
    /// `g` is the cancel move.
    fn fa_corner(&self, a: &FElem, g: &Geom, sb: f64, cancel: bool) -> Result<Corner, Alarm> {
        let r = a.r;
        let p = a.geom.end();
        let t1 = a.geom.t_end();
        let t2 = g.t_start();
        let pa = add(p, scale(left(t1), a.s * r));
        let pb = add(p, scale(left(t2), sb * r));
        let ca = Self::fa_curve(&a.geom, a.s, r, p)?;
        let cb = Self::fa_curve(g, sb, r, p)?;
        let simple = |a_end: V2, b_start: V2| {
            let extra = if dist(a_end, b_start) > 1e-9 {
                vec![b_start]
            } else {
                Vec::new()
            };
            Corner {
                a_end,
                extra,
                b_start,
            }
        };
        if a.s != sb {
            // Change of side: the intersection near both perpendicular ends, else A to B.
            let best = intersections(ca, cb)
                .into_iter()
                .map(|x| (dist(x, pa) + dist(x, pb), x))
                .filter(|(d, _)| *d <= 4.0 * r)
                .min_by(|x, y| x.0.total_cmp(&y.0));
            return Ok(match best {
                Some((_, x)) => simple(x, x),
                None => simple(pa, pb),
            });
        }
        let turn = cross(t1, t2).atan2(dot(t1, t2));
        let kappa = -a.s * turn; // > 0: outer corner
        if kappa.abs() <= TANGENT {
            return Ok(simple(pa, pb));
        }
        // Along the (extended) offset element of `a`: how far behind / ahead of `pa` a point is.
        let behind = |x: V2| match ca {
            Curve::Line { d, .. } => dot(sub(pa, x), d),
            Curve::Circle { c, rho, ccw } => travel(x, pa, c, ccw) * rho,
        };
        let ahead = |x: V2| match ca {
            Curve::Line { d, .. } => dot(sub(x, pa), d),
            Curve::Circle { c, rho, ccw } => travel(pa, x, c, ccw) * rho,
        };
        if kappa < 0.0 {
            let best = intersections(ca, cb)
                .into_iter()
                .map(|x| (behind(x), x))
                .filter(|(b, _)| *b >= -1e-9)
                .min_by(|x, y| x.0.total_cmp(&y.0));
            return match best {
                Some((_, x)) => Ok(simple(x, x)),
                None if -kappa < NEAR_TANGENT => Ok(simple(pa, pb)),
                None => Err(no_intersection(p)),
            };
        }
        // Outer corner.
        if !self.type_b {
            if cancel {
                return Ok(Corner {
                    a_end: pa,
                    extra: Vec::new(),
                    b_start: pa,
                });
            }
            if a.startup {
                return Ok(Corner {
                    a_end: pb,
                    extra: Vec::new(),
                    b_start: pb,
                });
            }
        }
        if kappa <= FRAC_PI_2 + 1e-12 {
            let best = intersections(ca, cb)
                .into_iter()
                .map(|x| (ahead(x), x))
                .filter(|(e, _)| *e >= -1e-9 && *e <= 4.0 * r)
                .min_by(|x, y| x.0.total_cmp(&y.0));
            if let Some((_, x)) = best {
                return Ok(simple(x, x));
            }
        }
        // Acute (or no intersection): each offset element extended by r, then joined.
        let a2 = add(pa, scale(t1, r));
        let b2 = sub(pb, scale(t2, r));
        let mut extra = Vec::new();
        let a_end = match a.geom {
            Geom::Line { .. } => a2,
            Geom::Arc { .. } => {
                extra.push(a2);
                pa
            }
        };
        extra.push(b2);
        let b_start = match g {
            Geom::Arc { .. } => {
                extra.push(pb);
                pb
            }
            Geom::Line { .. } => b2,
        };
        Ok(Corner {
            a_end,
            extra,
            b_start,
        })
    }

    /// Writes the held element ending at `a_end`, its moves without plane motion, then the straight
    /// corner moves to `extra` (mode `rapid` of the next element).
    fn fa_emit(
        &mut self,
        a: FElem,
        a_end: V2,
        extra: &[V2],
        rapid: bool,
        out: Out<'_>,
    ) -> Result<(), Stop> {
        let pl = self.plane;
        match a.geom {
            Geom::Line { a: s, b: e } => {
                if !a.startup && dot(sub(a_end, a.start), sub(e, s)) < 0.0 {
                    return Err(interference(e).into());
                }
                self.emit(
                    Move::Line {
                        to: put(pl, a.end, a_end),
                        rapid: a.rapid,
                    },
                    out,
                )?;
            }
            Geom::Arc { a: s, b: e, c, ccw } => {
                let prog = sweep(s, e, c, ccw, a.turns);
                let end = fit_arc_end(a.start, a_end, prog);
                let comp = sweep(a.start, end, c, ccw, a.turns);
                if (comp - prog).abs() > PI {
                    return Err(interference(e).into());
                }
                self.emit(
                    Move::Arc(Arc {
                        to: put(pl, a.end, end),
                        centre: c,
                        plane: pl,
                        clockwise: !ccw,
                        turns: a.turns,
                    }),
                    out,
                )?;
            }
        }
        let mut last = put(pl, a.end, a_end);
        for (z, zr) in a.zs {
            last = put(pl, z, a_end);
            self.emit(
                Move::Line {
                    to: last,
                    rapid: zr,
                },
                out,
            )?;
        }
        for &q in extra {
            self.emit(
                Move::Line {
                    to: put(pl, last, q),
                    rapid,
                },
                out,
            )?;
        }
        Ok(())
    }
}

fn too_small(arc_radius: f64, r: f64) -> Alarm {
    Alarm::new(
        INTERFERENCE,
        format!(
            "INTERFERENCE IN CRC: the tool radius {r} is not smaller than the inside arc's radius {arc_radius:.4}"
        ),
    )
}

fn no_intersection(p: V2) -> Alarm {
    Alarm::new(
        NO_INTERSECTION,
        format!(
            "NO SOLUTION AT CRC: the offset elements at the corner {:.4} {:.4} do not intersect",
            p[0], p[1]
        ),
    )
}

fn interference(p: V2) -> Alarm {
    Alarm::new(
        INTERFERENCE,
        format!(
            "INTERFERENCE IN CRC: the compensated path runs against the programmed one in the element ending at {:.4} {:.4}",
            p[0], p[1]
        ),
    )
}

#[cfg(test)]
mod tests;
