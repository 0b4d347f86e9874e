//! Contour geometry of the comma words and of NCT's "automatic geometric calculation between arcs":
//! corner rounding `,R`, chamfer `,C` and the intersection of two circles chosen by Q. Pure
//! geometry in one plane, in the plane's 2-D coordinates `[first, second]` (`Plane::axes()`); the
//! kernel projects its poses, calls these functions and lifts the results back.
//!
//! # Rules (the textbook corpus, `corpus/textbook/README.md`, "How the explicit twins were made")
//!
//! - **`,R` rounding** ([`corner`] with [`Corner::Round`]): an arc of the given radius tangent to
//!   both elements (line–line, line–arc, arc–line, arc–arc) replaces the corner; the first element
//!   ends at its tangent point, the second starts at its own. The arc turns the way the contour
//!   turns: G3 (counter-clockwise) where the contour turns left, G2 where it turns right. Its
//!   centre is the intersection, nearest the corner, of the two elements offset by R towards the
//!   inside of the turn: a line moves parallel by R, an arc of radius ρ becomes the concentric
//!   circle ρ − R when the inside of the turn is the arc's own inside (a G3 arc at a left turn, a
//!   G2 arc at a right turn), ρ + R otherwise. That is the README's construction for 28–30
//!   ("inside both … at R − 14 from both centres", "outside both … at 31 + 5"), and for two lines
//!   the book's "ends R before the corner" at a right angle (R·tan(θ/2) in general, θ the turn).
//! - **`,C` chamfer** ([`Corner::Chamfer`]): a straight line joins the point C before the corner on
//!   the first element to the point C after it on the second. The book only chamfers between two
//!   lines (13, 14), where "C along the line" is unambiguous. **Chosen here for arcs** (the book
//!   never does it): C is the *chord*, the straight distance from the corner, so the chamfer's ends
//!   are where the circle of radius C about the corner meets the element (on a line that is the
//!   same as the distance along it; on an arc of radius ρ the arc length is 2ρ·asin(C/2ρ), a little
//!   more than C).
//! - **`,R0` and `,C0`**: no rounding, no chamfer; [`corner`] returns both elements unchanged and,
//!   as the inserted element, a *marker* of zero size at the corner point P ([`Element::is_marker`]):
//!   `Arc { from: P, to: P, centre: P, clockwise }` for `,R0` (clockwise = the contour turns
//!   right, so the marker says which way the corner turns) and `Line { from: P, to: P }` for `,C0`.
//!   The marker is never a move (as an arc it would read as a full circle of radius 0: the kernel
//!   must drop it or act on it, not emit it). Its use is Fanuc-style compensation (NCT, exercise
//!   10: `,R0` "an arc of radius zero", the tool goes round the corner on an arc of the tool radius
//!   while the contour keeps its sharp corner): a zero-radius arc about P offset by the tool radius
//!   r is the arc of radius r about P from the offset of the first element's end to the offset of
//!   the second's start, i.e. exactly the LinuxCNC-style convex corner. So under Fanuc-style
//!   compensation the kernel makes that arc at a convex corner instead of the intersection/extra
//!   straight moves; at a concave corner (the turn towards the tool side) the intersection as
//!   always; without compensation, or with LinuxCNC-style compensation (which rounds convex corners
//!   anyway), it drops the marker. The corner is still checked: `,R0` on tangent elements alarms
//!   like any `,R`.
//! - **Arc intersections, Q** ([`circle_intersection`]): q < 0 takes the intersection to the
//!   *left* of the line from the first centre to the second, q > 0 (Q1) the one to the right — the
//!   README's rule, which fits all nine corners of 28, 29 and 30 (all G3 arcs). The README also
//!   says "for two G3 arcs that is also: Q-1 where the contour turns left". **Inferred** (the book
//!   has no G2 intersections): Q-1 means "the contour turns left" for every pair of directions
//!   ([`arc_intersection`]). Worked out below, that is the same left-of-the-centre-line point for
//!   G3–G3 *and* G2–G2 pairs, and the other point (right of the centre line) when the two arcs turn
//!   opposite ways (G3 then G2, G2 then G3). Only the sign of q counts; Q0 with two intersections
//!   alarms.
//!
//!   Why: put the first centre at (0, 0), the second at (L, 0), the intersection left of the line
//!   at P = (a, h), h > 0. The direction of travel on a circle at P is the radius vector turned
//!   +90° for G3, −90° for G2: G3 on circle 1 t₁ = (−h, a), on circle 2 t₂ = (−h, a − L); the turn
//!   t₁ × t₂ = (−h)(a − L) − a(−h) = hL > 0: left. G2 on both: t₁ = (h, −a), t₂ = (h, L − a),
//!   t₁ × t₂ = h(L − a) + ah = hL > 0: left again. G3 then G2: t₁ = (−h, a), t₂ = (h, L − a),
//!   t₁ × t₂ = −h(L − a) − ah = −hL: right.
//! - **What exercise 30 N240 needs**: `N230 G3 X-11 Y-20 R31 ,R5` / `N240 G3 X-20 Y11 I-20 J-20 R31
//!   Q1`. N230 is an ordinary R arc: its circle (centre X20 Y-20) comes from its start X20 Y11, its
//!   programmed end and R31 (`arcs::arc`); N240's circle is I J (absolute) and R; N240 keeps its
//!   own end point X-20 Y11 (on its circle: the kernel's end-point check, alarm 0020); N230 ends at
//!   `circle_intersection([20, -20], 31, [-20, -20], 31, 1)` = X0 Y3.685, then `,R5` rounds that
//!   corner with [`corner`] (arc–arc). So it needs the circle–circle intersection only; every
//!   over-determined block of the book follows an arc (28 N200 "XI-505 YI505 R505" is the R arc
//!   through a point, also `arcs::arc`), none follows a line, so no line–circle intersection is
//!   provided.
//!
//! # Alarms (numbers from the Fanuc 0i/16i program-error list)
//!
//! - [`NO_CORNER`] 0051 MISSING MOVE AFTER CNR/CHF: the elements have no corner to round or
//!   chamfer (tangent, or collinear lines), or one of them has no length, or the second does not
//!   start where the first ends.
//! - [`DOES_NOT_FIT`] 0055 MISSING MOVE VALUE IN CHF/CNR: the rounding or chamfer does not fit its
//!   elements (an element is shorter than what the corner takes from it, R larger than an arc it
//!   must lie inside, a reversal of direction), or a negative or non-finite value.
//! - [`NO_INTERSECTION`] 0057 NO SOLUTION OF BLOCK END (Fanuc's alarm for an end point that direct
//!   drawing dimension programming cannot compute): the two circles do not meet, are concentric,
//!   have a radius ≤ 0, or Q0 leaves two intersections to choose from.

use std::f64::consts::TAU;

use fmsvm_block::Alarm;

use fmsvm_canon::geom::{
    EPS, V2, add, circle_circle, cross, dist, dot, left, line_circle, line_line, norm, rotate,
    scale, sub, turned, unit,
};

/// 0051 MISSING MOVE AFTER CNR/CHF: no corner between the two elements.
pub const NO_CORNER: u32 = 51;
/// 0055 MISSING MOVE VALUE IN CHF/CNR: the rounding or chamfer does not fit.
pub const DOES_NOT_FIT: u32 = 55;
/// 0057 NO SOLUTION OF BLOCK END: two circles without the intersection asked for.
pub const NO_INTERSECTION: u32 = 57;

// Lengths within `geom::EPS` (mm or inch) are equal: what a corner may overrun an element by, how
// far apart two circles may be and still touch, how far the second element may start from the
// first one's end.
/// Two unit tangents whose cross product is within this (radians) are tangent: no corner.
const TANGENT: f64 = 1e-6;

/// One element of a contour in the plane's coordinates.
#[derive(Clone, Copy, PartialEq, Debug)]
pub enum Element {
    /// A straight line.
    Line {
        /// Start point.
        from: [f64; 2],
        /// End point.
        to: [f64; 2],
    },
    /// An arc of at most one turn (end = start: a full circle).
    Arc {
        /// Start point.
        from: [f64; 2],
        /// End point.
        to: [f64; 2],
        /// Centre.
        centre: [f64; 2],
        /// G2 rather than G3.
        clockwise: bool,
    },
}

/// What replaces a corner.
#[derive(Clone, Copy, PartialEq, Debug)]
pub enum Corner {
    /// `,R`: a tangent arc of this radius (0: no rounding, a marker).
    Round(f64),
    /// `,C`: a straight line from this distance before the corner to this distance after it (0: no
    /// chamfer, a marker).
    Chamfer(f64),
}

impl Element {
    /// The start point.
    pub fn from(&self) -> [f64; 2] {
        match *self {
            Element::Line { from, .. } | Element::Arc { from, .. } => from,
        }
    }

    /// The end point.
    pub fn to(&self) -> [f64; 2] {
        match *self {
            Element::Line { to, .. } | Element::Arc { to, .. } => to,
        }
    }

    /// The marker of `,R0` / `,C0` (see the module documentation): a line of zero length, or an
    /// arc whose start, end and centre are the same point. Not a move.
    pub fn is_marker(&self) -> bool {
        match *self {
            Element::Line { from, to } => from == to,
            Element::Arc {
                from, to, centre, ..
            } => from == to && centre == from,
        }
    }

    /// The same element with another start point.
    fn with_from(self, p: [f64; 2]) -> Element {
        match self {
            Element::Line { to, .. } => Element::Line { from: p, to },
            Element::Arc {
                to,
                centre,
                clockwise,
                ..
            } => Element::Arc {
                from: p,
                to,
                centre,
                clockwise,
            },
        }
    }

    /// The same element with another end point.
    fn with_to(self, p: [f64; 2]) -> Element {
        match self {
            Element::Line { from, .. } => Element::Line { from, to: p },
            Element::Arc {
                from,
                centre,
                clockwise,
                ..
            } => Element::Arc {
                from,
                to: p,
                centre,
                clockwise,
            },
        }
    }

    /// The unit direction of travel at `p` (a point of the element), or None when it has none (a
    /// line of no length, an arc of no radius).
    fn tangent_at(&self, p: [f64; 2]) -> Option<[f64; 2]> {
        match *self {
            Element::Line { from, to } => unit(sub(to, from)),
            Element::Arc {
                centre, clockwise, ..
            } => {
                let r = unit(sub(p, centre))?;
                Some(if clockwise { [r[1], -r[0]] } else { left(r) })
            }
        }
    }

    /// Length (a line) or radius (an arc), for the messages and tolerances.
    fn size(&self) -> f64 {
        match *self {
            Element::Line { from, to } => dist(from, to),
            Element::Arc { from, centre, .. } => dist(from, centre),
        }
    }

    /// How far along the element `p` (a point on it) lies from its start: the distance along a
    /// line (negative before the start), the swept angle on an arc (in [0, 2π), a point within
    /// `EPS` before the start counted as 0).
    fn along(&self, p: [f64; 2]) -> f64 {
        match *self {
            Element::Line { from, to } => match unit(sub(to, from)) {
                Some(d) => dot(sub(p, from), d),
                None => 0.0,
            },
            Element::Arc {
                from,
                centre,
                clockwise,
                ..
            } => {
                let r = dist(from, centre);
                let phi = turned(from, p, centre, !clockwise);
                if phi > TAU - EPS / r { 0.0 } else { phi }
            }
        }
    }

    /// The whole extent in the units of [`Element::along`]: a line's length, an arc's sweep
    /// (0, 2π] (end = start: a full circle).
    fn extent(&self) -> f64 {
        match *self {
            Element::Line { from, to } => dist(from, to),
            Element::Arc {
                from,
                to,
                centre,
                clockwise,
            } => {
                let d = turned(from, to, centre, !clockwise);
                if d <= 1e-12 { TAU } else { d }
            }
        }
    }

    /// The tolerance `EPS` in the units of [`Element::along`].
    fn eps(&self) -> f64 {
        match self {
            Element::Line { .. } => EPS,
            Element::Arc { .. } => EPS / self.size().max(EPS),
        }
    }
}

/// Replace the corner between `a` (ending at the corner) and `b` (starting there) by a rounding or
/// a chamfer: returns `a` ending where the corner begins, the inserted element (an arc tangent to
/// both for [`Corner::Round`], G3 where the contour turns left and G2 where it turns right; a line
/// for [`Corner::Chamfer`]; a marker for a value of 0) and `b` starting where the corner ends.
/// See the module documentation for the rules and the alarms (0051 no corner, 0055 does not fit).
pub fn corner(a: &Element, b: &Element, c: Corner) -> Result<(Element, Element, Element), Alarm> {
    let (word, value) = match c {
        Corner::Round(r) => (",R", r),
        Corner::Chamfer(c) => (",C", c),
    };
    if !value.is_finite() || value < 0.0 {
        return Err(Alarm::new(
            DOES_NOT_FIT,
            format!("{word}{value}: the corner value must be a length of 0 or more"),
        ));
    }
    let p = a.to();
    if dist(p, b.from()) > EPS {
        return Err(Alarm::new(
            NO_CORNER,
            format!(
                "{word}{value}: the next element starts at {} but the block ends at {}",
                pt(b.from()),
                pt(p)
            ),
        ));
    }
    let (Some(t1), Some(t2)) = (a.tangent_at(p), b.tangent_at(p)) else {
        return Err(Alarm::new(
            NO_CORNER,
            format!(
                "{word}{value} at {}: an element of the corner has no length",
                pt(p)
            ),
        ));
    };
    // The turn: t₁ × t₂ = sin θ (> 0 left), t₁ · t₂ = cos θ.
    let turn = cross(t1, t2);
    if turn.abs() <= TANGENT {
        if dot(t1, t2) > 0.0 {
            return Err(Alarm::new(
                NO_CORNER,
                format!(
                    "{word}{value} at {}: the two elements are tangent there, there is no corner",
                    pt(p)
                ),
            ));
        }
        return Err(Alarm::new(
            DOES_NOT_FIT,
            format!(
                "{word}{value} at {}: the contour reverses its direction there",
                pt(p)
            ),
        ));
    }
    let s = turn.signum(); // +1 left turn, −1 right turn
    if value == 0.0 {
        let marker = match c {
            Corner::Round(_) => Element::Arc {
                from: p,
                to: p,
                centre: p,
                clockwise: s < 0.0,
            },
            Corner::Chamfer(_) => Element::Line { from: p, to: p },
        };
        return Ok((*a, marker, *b));
    }
    let (ta, tb, inserted) = match c {
        Corner::Round(r) => {
            let f = fillet_centre(a, b, p, r, s)?;
            let ta = foot(a, f, r, s);
            let tb = foot(b, f, r, s);
            let arc = Element::Arc {
                from: ta,
                to: tb,
                centre: f,
                clockwise: s < 0.0,
            };
            // The rounding must continue each element, not run against it.
            let ok = |e: &Element, q: [f64; 2]| match (e.tangent_at(q), arc.tangent_at(q)) {
                (Some(u), Some(v)) => dot(u, v) > 0.0,
                _ => false,
            };
            if !ok(a, ta) || !ok(b, tb) {
                return Err(Alarm::new(
                    DOES_NOT_FIT,
                    format!("{word}{r} at {}: no rounding of that radius fits", pt(p)),
                ));
            }
            (ta, tb, arc)
        }
        Corner::Chamfer(c) => {
            let ta = chord_point(a, p, c, false)?;
            let tb = chord_point(b, p, c, true)?;
            (ta, tb, Element::Line { from: ta, to: tb })
        }
    };
    // The first element keeps [start, ta], the second [tb, end].
    let ea = a.along(ta);
    if ea < -a.eps() || ea > a.extent() + a.eps() {
        return Err(Alarm::new(
            DOES_NOT_FIT,
            format!(
                "{word}{value} at {}: the corner would begin at {}, before the start {} of the block ({})",
                pt(p),
                pt(ta),
                pt(a.from()),
                describe(a)
            ),
        ));
    }
    let eb = b.along(tb);
    if eb < -b.eps() || eb > b.extent() + b.eps() {
        return Err(Alarm::new(
            DOES_NOT_FIT,
            format!(
                "{word}{value} at {}: the corner would end at {}, past the end {} of the next block ({})",
                pt(p),
                pt(tb),
                pt(b.to()),
                describe(b)
            ),
        ));
    }
    Ok((a.with_to(ta), inserted, b.with_from(tb)))
}

/// An element offset by `r` to side `s` (+1 left of the direction of travel, −1 right).
enum Offset {
    /// The line through the point with the unit direction.
    Line([f64; 2], [f64; 2]),
    /// The circle: centre, radius.
    Circle([f64; 2], f64),
}

fn offset(e: &Element, p: [f64; 2], r: f64, s: f64) -> Result<Offset, Alarm> {
    match *e {
        Element::Line { from, to } => {
            let d = unit(sub(to, from)).unwrap_or([1.0, 0.0]);
            Ok(Offset::Line(add(from, scale(left(d), s * r)), d))
        }
        Element::Arc {
            from,
            centre,
            clockwise,
            ..
        } => {
            // The left of travel is the arc's inside on a G3 arc (k = +1), its outside on a G2 arc
            // (k = −1): the offset to side s is the circle ρ − s·k·r.
            let rho = dist(from, centre);
            let k = if clockwise { -1.0 } else { 1.0 };
            let rho2 = rho - s * k * r;
            if rho2 <= EPS {
                return Err(Alarm::new(
                    DOES_NOT_FIT,
                    format!(
                        ",R{r} at {}: a rounding of that radius cannot lie inside the arc of radius {rho:.4} about {}",
                        pt(p),
                        pt(centre)
                    ),
                ));
            }
            Ok(Offset::Circle(centre, rho2))
        }
    }
}

/// The centre of the rounding of radius `r` at corner `p` turning to side `s`: the intersection of
/// the two offsets nearest the corner.
fn fillet_centre(a: &Element, b: &Element, p: [f64; 2], r: f64, s: f64) -> Result<[f64; 2], Alarm> {
    let oa = offset(a, p, r, s)?;
    let ob = offset(b, p, r, s)?;
    let candidates: Option<[[f64; 2]; 2]> = match (&oa, &ob) {
        (Offset::Line(p1, d1), Offset::Line(p2, d2)) => {
            line_line(*p1, *d1, *p2, *d2).map(|x| [x, x])
        }
        (Offset::Line(q, d), Offset::Circle(c, rho))
        | (Offset::Circle(c, rho), Offset::Line(q, d)) => line_circle_points(*q, *d, *c, *rho),
        (Offset::Circle(c1, r1), Offset::Circle(c2, r2)) => circle_circle(*c1, *r1, *c2, *r2),
    };
    let Some([x, y]) = candidates else {
        return Err(Alarm::new(
            DOES_NOT_FIT,
            format!(
                ",R{r} at {}: no arc of that radius is tangent to both elements",
                pt(p)
            ),
        ));
    };
    Ok(if dist(x, p) <= dist(y, p) { x } else { y })
}

/// Where the rounding about `f` (radius `r`, on side `s`) touches element `e`.
fn foot(e: &Element, f: [f64; 2], r: f64, s: f64) -> [f64; 2] {
    match *e {
        Element::Line { from, to } => {
            let d = unit(sub(to, from)).unwrap_or([1.0, 0.0]);
            sub(f, scale(left(d), s * r))
        }
        Element::Arc { from, centre, .. } => {
            // On the ray from the arc's centre through f: c + (f − c)·ρ/|f − c|.
            let rho = dist(from, centre);
            let v = sub(f, centre);
            add(centre, scale(v, rho / norm(v)))
        }
    }
}

/// The point of `e` at straight distance `c` from its end `p` (`after` false: the first element,
/// going back from its end) or from its start `p` (`after` true: the second element, going on).
fn chord_point(e: &Element, p: [f64; 2], c: f64, after: bool) -> Result<[f64; 2], Alarm> {
    match *e {
        Element::Line { from, to } => {
            let d = unit(sub(to, from)).unwrap_or([1.0, 0.0]);
            Ok(add(p, scale(d, if after { c } else { -c })))
        }
        Element::Arc {
            from,
            centre,
            clockwise,
            ..
        } => {
            // A chord c of a circle ρ spans the angle δ = 2·asin(c / 2ρ).
            let rho = dist(from, centre);
            if c > 2.0 * rho + EPS {
                return Err(Alarm::new(
                    DOES_NOT_FIT,
                    format!(
                        ",C{c} at {}: the chamfer is longer than the diameter of the arc of radius {rho:.4}",
                        pt(p)
                    ),
                ));
            }
            let delta = 2.0 * (c / (2.0 * rho)).min(1.0).asin();
            // Forward along a G3 arc is +δ, along a G2 arc −δ; back is the opposite.
            let dir = if clockwise { -1.0 } else { 1.0 } * if after { 1.0 } else { -1.0 };
            Ok(add(centre, rotate(sub(p, centre), dir * delta)))
        }
    }
}

/// The intersection of the circle about `c1` of radius `r1` with the circle about `c2` of radius
/// `r2`, chosen by the sign of `q`: q < 0 the one to the left of the line from `c1` to `c2`,
/// q > 0 (Q1) the one to the right (the README's rule, for the G3 arcs of exercises 28–30; for
/// arcs of other directions see [`arc_intersection`]). Circles that touch have one intersection,
/// whatever q. Alarm 0057 when the circles do not meet, are concentric, a radius is not positive,
/// or q is 0 (or NaN) with two intersections.
pub fn circle_intersection(
    c1: [f64; 2],
    r1: f64,
    c2: [f64; 2],
    r2: f64,
    q: f64,
) -> Result<[f64; 2], Alarm> {
    let circle = |c: [f64; 2], r: f64| format!("the circle R{r} about {}", pt(c));
    if !(r1 > 0.0 && r2 > 0.0) {
        return Err(Alarm::new(
            NO_INTERSECTION,
            format!(
                "arc intersection: {} and {}: a radius must be positive",
                circle(c1, r1),
                circle(c2, r2)
            ),
        ));
    }
    let l = dist(c1, c2);
    if l <= EPS {
        return Err(Alarm::new(
            NO_INTERSECTION,
            format!(
                "arc intersection: {} and {} are concentric",
                circle(c1, r1),
                circle(c2, r2)
            ),
        ));
    }
    let Some([left_point, right_point]) = circle_circle(c1, r1, c2, r2) else {
        let why = if l > r1 + r2 {
            format!(
                "their centres are {l:.4} apart, more than R1 + R2 = {:.4}",
                r1 + r2
            )
        } else {
            format!(
                "their centres are {l:.4} apart, less than |R1 - R2| = {:.4}: one lies inside the other",
                (r1 - r2).abs()
            )
        };
        return Err(Alarm::new(
            NO_INTERSECTION,
            format!(
                "arc intersection: {} and {} do not meet: {why}",
                circle(c1, r1),
                circle(c2, r2)
            ),
        ));
    };
    if dist(left_point, right_point) <= EPS {
        return Ok(left_point);
    }
    if q < 0.0 {
        Ok(left_point)
    } else if q > 0.0 {
        Ok(right_point)
    } else {
        Err(Alarm::new(
            NO_INTERSECTION,
            format!(
                "arc intersection: {} and {} meet twice, at {} and {}: Q{q} does not choose (Q-1 or Q1)",
                circle(c1, r1),
                circle(c2, r2),
                pt(left_point),
                pt(right_point)
            ),
        ))
    }
}

/// The corner of two arcs (the first G2 when `cw1`, the second G2 when `cw2`), chosen by Q as
/// "Q-1 where the contour turns left, Q1 where it turns right" — **inferred** from the README for
/// G2 arcs (module documentation): for arcs of the same direction that is [`circle_intersection`]
/// with the same q, for arcs of opposite directions with −q.
pub fn arc_intersection(
    c1: [f64; 2],
    r1: f64,
    cw1: bool,
    c2: [f64; 2],
    r2: f64,
    cw2: bool,
    q: f64,
) -> Result<[f64; 2], Alarm> {
    circle_intersection(c1, r1, c2, r2, if cw1 == cw2 { q } else { -q })
}

/// The two points where the line through `q` with unit direction `d` meets the circle about `c` of
/// radius `rho`, or None.
fn line_circle_points(q: V2, d: V2, c: V2, rho: f64) -> Option<[V2; 2]> {
    let (t1, t2) = line_circle(q, d, c, rho)?;
    Some([add(q, scale(d, t2)), add(q, scale(d, t1))])
}

fn describe(e: &Element) -> String {
    match *e {
        Element::Line { from, to } => format!("a line of length {:.4}", dist(from, to)),
        Element::Arc {
            centre, clockwise, ..
        } => format!(
            "a {} arc of radius {:.4} about {} sweeping {:.4}°",
            if clockwise { "G2" } else { "G3" },
            e.size(),
            pt(centre),
            e.extent().to_degrees()
        ),
    }
}

fn pt(p: [f64; 2]) -> String {
    format!("({:.4}, {:.4})", p[0], p[1])
}

#[cfg(test)]
mod tests;
