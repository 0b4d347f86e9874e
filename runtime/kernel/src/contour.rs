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
mod tests {
    use super::*;

    fn line(from: [f64; 2], to: [f64; 2]) -> Element {
        Element::Line { from, to }
    }
    fn arc(from: [f64; 2], to: [f64; 2], centre: [f64; 2], clockwise: bool) -> Element {
        Element::Arc {
            from,
            to,
            centre,
            clockwise,
        }
    }
    fn near(a: [f64; 2], b: [f64; 2], tol: f64) -> bool {
        dist(a, b) <= tol
    }
    #[track_caller]
    fn assert_near(a: [f64; 2], b: [f64; 2], tol: f64) {
        assert!(near(a, b, tol), "{a:?} is not {b:?} (within {tol})");
    }
    #[track_caller]
    fn fillet(e: &Element) -> ([f64; 2], [f64; 2], [f64; 2], bool) {
        match *e {
            Element::Arc {
                from,
                to,
                centre,
                clockwise,
            } => (from, to, centre, clockwise),
            Element::Line { .. } => panic!("not an arc: {e:?}"),
        }
    }

    /// Rounds the corner and checks what every rounding must be: the first element keeps its start
    /// and ends where the rounding starts, the second starts where it ends and keeps its end; the
    /// rounding has radius r at both ends, its ends lie on the elements' curves, its centre is r
    /// from each line and ρ ± r from each arc's centre, and the direction of travel does not break
    /// at either joint (tangency). Returns the rounding.
    #[track_caller]
    fn round(a: &Element, b: &Element, r: f64) -> Element {
        let (na, f, nb) = corner(a, b, Corner::Round(r)).unwrap();
        let (fa, fb, fc, _) = fillet(&f);
        assert_eq!(na.from(), a.from());
        assert_eq!(nb.to(), b.to());
        assert_eq!(na.to(), fa);
        assert_eq!(nb.from(), fb);
        assert!((dist(fa, fc) - r).abs() < 1e-9 && (dist(fb, fc) - r).abs() < 1e-9);
        for (e, t) in [(a, fa), (b, fb)] {
            match *e {
                Element::Line { from, to } => {
                    let d = unit(sub(to, from)).unwrap();
                    // On the line, and the centre r from it.
                    assert!(cross(d, sub(t, from)).abs() < 1e-9);
                    assert!((cross(d, sub(fc, from)).abs() - r).abs() < 1e-9);
                }
                Element::Arc { from, centre, .. } => {
                    let rho = dist(from, centre);
                    assert!((dist(t, centre) - rho).abs() < 1e-9);
                    let k = dist(fc, centre);
                    assert!(
                        (k - (rho - r)).abs() < 1e-9 || (k - (rho + r)).abs() < 1e-9,
                        "centre {k} from the arc's centre, not {rho} ± {r}"
                    );
                }
            }
            let u = e.tangent_at(t).unwrap();
            let v = f.tangent_at(t).unwrap();
            assert!(near(u, v, 1e-9), "not tangent at {t:?}: {u:?} / {v:?}");
        }
        f
    }

    #[test]
    fn line_line_rounding_at_right_angles() {
        // 11, corner X100 Y-50: X- → X+ then Y+, a left turn of 90°. The tangent points are
        // R·tan(45°) = R = 10 from the corner: X90 Y-50 and X100 Y-40; the centre X90 Y-40; G3.
        let a = line([-100.0, -50.0], [100.0, -50.0]);
        let b = line([100.0, -50.0], [100.0, 50.0]);
        let f = round(&a, &b, 10.0);
        assert_eq!(
            corner(&a, &b, Corner::Round(10.0)).unwrap(),
            (
                line([-100.0, -50.0], [90.0, -50.0]),
                arc([90.0, -50.0], [100.0, -40.0], [90.0, -40.0], false),
                line([100.0, -40.0], [100.0, 50.0]),
            )
        );
        assert_eq!(f, arc([90.0, -50.0], [100.0, -40.0], [90.0, -40.0], false));
        // 13 N240/N250, corner X0 Y100: X- then Y-, left: X20 Y100 → X0 Y80 about X20 Y80, G3.
        let f = round(
            &line([150.0, 100.0], [0.0, 100.0]),
            &line([0.0, 100.0], [0.0, 0.0]),
            20.0,
        );
        assert_eq!(f, arc([20.0, 100.0], [0.0, 80.0], [20.0, 80.0], false));
        // 30 N190/N200 ,R9, corner X11 Y-11: Y+ then X+, a right turn: X11 Y-20 → X20 Y-11 about
        // X20 Y-20, G2 (the twin's "G2 X20 Y-11 I9 J0").
        let f = round(
            &line([11.0, -35.0], [11.0, -11.0]),
            &line([11.0, -11.0], [120.0, -11.0]),
            9.0,
        );
        assert_eq!(f, arc([11.0, -20.0], [20.0, -11.0], [20.0, -20.0], true));
        // 30 N270/N280, corner X-11 Y-11: X+ then Y-, right: X-20 Y-11 → X-11 Y-20 about X-20 Y-20.
        let f = round(
            &line([-120.0, -11.0], [-11.0, -11.0]),
            &line([-11.0, -11.0], [-11.0, -35.0]),
            9.0,
        );
        let (fa, fb, fc, cw) = fillet(&f);
        assert_near(fa, [-20.0, -11.0], 1e-12);
        assert_near(fb, [-11.0, -20.0], 1e-12);
        assert_near(fc, [-20.0, -20.0], 1e-12);
        assert!(cw);
    }

    #[test]
    fn line_line_rounding_at_135_degrees() {
        // 13 N230/N240 with ,R10: X200 Y50 → X150 Y100 (d₁ = (−1, 1)/√2), then X0 Y100 (d₂ = (−1, 0)).
        // d₁ × d₂ = 0·(−1/√2) − (1/√2)(−1) = 1/√2 > 0: left, G3, a turn θ = 45° (an inner angle of 135°).
        // The tangent points are R·tan(θ/2) = 10·(√2 − 1) = 4.142136 from the corner:
        // on the first line X150 + 4.142136/√2 = X152.928932, Y100 − 2.928932 = Y97.071068;
        // on the second X145.857864 Y100; the centre R to the left of d₂ (left(d₂) = (0, −1)):
        // X145.857864 Y90. Check: its distance from the first line, d₁ × (F − P) =
        // (−1/√2)(−10) − (1/√2)(−4.142136) = 14.142136/√2 = 10.
        let t = 10.0 * (2f64.sqrt() - 1.0);
        let f = round(
            &line([200.0, 50.0], [150.0, 100.0]),
            &line([150.0, 100.0], [0.0, 100.0]),
            10.0,
        );
        let (fa, fb, fc, cw) = fillet(&f);
        assert_near(fa, [150.0 + t / 2f64.sqrt(), 100.0 - t / 2f64.sqrt()], 1e-9);
        assert_near(fa, [152.928932, 97.071068], 1e-6);
        assert_near(fb, [145.857864, 100.0], 1e-6);
        assert_near(fc, [145.857864, 90.0], 1e-6);
        assert!(!cw);
    }

    #[test]
    fn chamfers_between_lines() {
        // 13 N210/N220 ,C10, corner X200 Y0 (X+ then Y+): X190 Y0 → X200 Y10, as the twin.
        let (a, c, b) = corner(
            &line([100.0, 0.0], [200.0, 0.0]),
            &line([200.0, 0.0], [200.0, 50.0]),
            Corner::Chamfer(10.0),
        )
        .unwrap();
        assert_eq!(a, line([100.0, 0.0], [190.0, 0.0]));
        assert_eq!(c, line([190.0, 0.0], [200.0, 10.0]));
        assert_eq!(b, line([200.0, 10.0], [200.0, 50.0]));
        // ,C10 at the 135° corner X150 Y100: 10 back along d₁ = (−1, 1)/√2 is X150 + 10/√2 =
        // X157.071068, Y100 − 7.071068 = Y92.928932; 10 on along X−: X140 Y100.
        let (a, c, b) = corner(
            &line([200.0, 50.0], [150.0, 100.0]),
            &line([150.0, 100.0], [0.0, 100.0]),
            Corner::Chamfer(10.0),
        )
        .unwrap();
        assert_near(a.to(), [157.071068, 92.928932], 1e-6);
        assert_eq!(c.from(), a.to());
        assert_near(c.to(), [140.0, 100.0], 1e-9);
        assert_eq!(b, line(c.to(), [0.0, 100.0]));
    }

    #[test]
    fn chamfer_on_an_arc_is_measured_as_the_chord() {
        // X0 Y0 → X10 Y0, then G2 about X20 Y0 (R10) over the top to X30 Y0: at X10 Y0 the arc
        // heads Y+, a left turn of 90°. ,C5: X5 Y0 on the line; on the arc the chord 5 spans
        // δ = 2·asin(5/20), cos δ = 1 − 2·(1/4)² = 0.875, sin δ = 2·(1/4)·√(1 − 1/16) = 0.484123,
        // and the radius vector (−10, 0) turned clockwise by δ is (−10 cos δ, 10 sin δ):
        // X20 − 8.75 = X11.25, Y4.841229; its distance from X10 Y0 is √(1.25² + 4.841229²) = 5.
        let a = line([0.0, 0.0], [10.0, 0.0]);
        let b = arc([10.0, 0.0], [30.0, 0.0], [20.0, 0.0], true);
        let (na, c, nb) = corner(&a, &b, Corner::Chamfer(5.0)).unwrap();
        assert_near(na.to(), [5.0, 0.0], 1e-12);
        assert_near(c.to(), [11.25, 4.841229], 1e-6);
        assert!((dist(c.to(), [10.0, 0.0]) - 5.0).abs() < 1e-9);
        assert_eq!(nb, arc(c.to(), [30.0, 0.0], [20.0, 0.0], true));
        // Longer than the diameter: 0055.
        assert_eq!(
            corner(&a, &b, Corner::Chamfer(21.0)).unwrap_err().number,
            DOES_NOT_FIT
        );
    }

    #[test]
    fn line_arc_and_arc_line_rounding() {
        // The same corner: X0 Y0 → X10 Y0 (X+), then G2 about X20 Y0, R10, heading Y+ at X10 Y0: a
        // left turn, so the rounding R2 lies left of both, G3. The line's offset is Y2; left of a
        // G2 arc is its outside: the circle R10 + 2 = 12 about X20 Y0. They meet at
        // X20 − √(12² − 2²) = 20 − √140 = X8.167840 Y2 (the one nearer the corner). Tangent points:
        // X8.167840 Y0 on the line; on the arc X20 Y0 + (F − C)·10/12 =
        // (20 − 11.832160·10/12, 2·10/12) = X10.139867 Y1.666667.
        let a = line([0.0, 0.0], [10.0, 0.0]);
        let b = arc([10.0, 0.0], [30.0, 0.0], [20.0, 0.0], true);
        let f = round(&a, &b, 2.0);
        let (fa, fb, fc, cw) = fillet(&f);
        let x = 20.0 - 140f64.sqrt();
        assert_near(fc, [x, 2.0], 1e-12);
        assert_near(fc, [8.167840, 2.0], 1e-6);
        assert_near(fa, [8.167840, 0.0], 1e-6);
        assert_near(fb, [10.139867, 1.666667], 1e-6);
        assert!(!cw);
        // Backwards: G3 about X20 Y0 from X30 Y0 over the top to X10 Y0 (heading Y− there), then
        // X0 Y0 (X−): (0, −1) × (−1, 0) = −1, a right turn; the same circle, now G2 from the arc.
        let a = arc([30.0, 0.0], [10.0, 0.0], [20.0, 0.0], false);
        let b = line([10.0, 0.0], [0.0, 0.0]);
        let f = round(&a, &b, 2.0);
        let (fa, fb, fc, cw) = fillet(&f);
        assert_near(fc, [x, 2.0], 1e-12);
        assert_near(fa, [10.139867, 1.666667], 1e-6);
        assert_near(fb, [8.167840, 0.0], 1e-6);
        assert!(cw);
        // A rounding inside a G3 arc: X0 Y-10 → X0 Y0 (Y+), then G3 about X-10 Y0 (R10) from X0 Y0
        // (heading Y+: tangent, no corner) is not a corner; take G3 about X0 Y10 instead, which at
        // X0 Y0 heads X+: a right turn, the rounding right of both, i.e. outside that G3 arc
        // (R10 + 3 = 13 about X0 Y10) and at X3 from the line: X3, Y10 − √(169 − 9) = Y-2.649111.
        let a = line([0.0, -10.0], [0.0, 0.0]);
        let b = arc([0.0, 0.0], [0.0, 20.0], [0.0, 10.0], false);
        let f = round(&a, &b, 3.0);
        let (_, _, fc, cw) = fillet(&f);
        assert_near(fc, [3.0, 10.0 - 160f64.sqrt()], 1e-12);
        assert!(cw);
    }

    /// The four circles of 28 (R505 about X∓467.5, R185 about Y∓135) or 29 (R460 about X∓420, R200
    /// about Y∓100), chained as the book's N200–N240 from the start X37.5 / X40 Y0.
    fn chain(big: (f64, f64), small: (f64, f64), start: [f64; 2]) -> Vec<Element> {
        let centres = [
            ([-big.0, 0.0], big.1),
            ([0.0, -small.0], small.1),
            ([big.0, 0.0], big.1),
            ([0.0, small.0], small.1),
            ([-big.0, 0.0], big.1),
        ];
        let mut points = vec![start];
        for w in centres.windows(2) {
            points.push(circle_intersection(w[0].0, w[0].1, w[1].0, w[1].1, -1.0).unwrap());
        }
        points.push(start);
        (0..5)
            .map(|i| arc(points[i], points[i + 1], centres[i].0, false))
            .collect()
    }

    #[test]
    fn the_nine_corners_of_the_q_table() {
        // README table: both arcs G3, Q-1 left of the line from the first centre to the second,
        // Q1 right of it. E.g. 28 N200/N210: d = (467.5, −135), L = 486.601, a = (505² − 185² +
        // L²)/2L = 454.345, h = √(505² − a²) = 220.445; left(d)/L = (0.27743, 0.96075):
        // X−467.5 + 454.345·0.96075 + 220.445·0.27743 = X35.346,
        // Y0 − 454.345·0.27743 + 220.445·0.96075 = Y46.592.
        // (first centre, R, second centre, R, Q, corner taken)
        type Row = ([f64; 2], f64, [f64; 2], f64, f64, [f64; 2]);
        let rows: [Row; 9] = [
            (
                [-467.5, 0.0],
                505.0,
                [0.0, -135.0],
                185.0,
                -1.0,
                [35.346, 46.592],
            ),
            (
                [0.0, -135.0],
                185.0,
                [467.5, 0.0],
                505.0,
                -1.0,
                [-35.346, 46.592],
            ),
            (
                [467.5, 0.0],
                505.0,
                [0.0, 135.0],
                185.0,
                -1.0,
                [-35.346, -46.592],
            ),
            (
                [0.0, 135.0],
                185.0,
                [-467.5, 0.0],
                505.0,
                -1.0,
                [35.346, -46.592],
            ),
            (
                [-420.0, 0.0],
                460.0,
                [0.0, -100.0],
                200.0,
                -1.0,
                [29.480, 97.815],
            ),
            (
                [0.0, -100.0],
                200.0,
                [420.0, 0.0],
                460.0,
                -1.0,
                [-29.480, 97.815],
            ),
            (
                [420.0, 0.0],
                460.0,
                [0.0, 100.0],
                200.0,
                -1.0,
                [-29.480, -97.815],
            ),
            (
                [0.0, 100.0],
                200.0,
                [-420.0, 0.0],
                460.0,
                -1.0,
                [29.480, -97.815],
            ),
            // 30 N230/N240: x = 0 by symmetry, y = −20 ± √(31² − 20²) = −20 ± 23.685; right of
            // the line X20 → X−20 (heading X−) is Y+: Y3.685.
            ([20.0, -20.0], 31.0, [-20.0, -20.0], 31.0, 1.0, [0.0, 3.685]),
        ];
        for (c1, r1, c2, r2, q, want) in rows {
            let p = circle_intersection(c1, r1, c2, r2, q).unwrap();
            assert_near(p, want, 0.001);
            // All G3: the turn rule gives the same point, and the point is on both circles.
            assert_eq!(
                arc_intersection(c1, r1, false, c2, r2, false, q).unwrap(),
                p
            );
            assert!((dist(p, c1) - r1).abs() < 1e-9 && (dist(p, c2) - r2).abs() < 1e-9);
            // The other Q takes the other point, mirrored in the line of centres.
            let o = circle_intersection(c1, r1, c2, r2, -q).unwrap();
            assert!(dist(o, p) > 1.0);
            // Q counts by its sign only.
            assert_eq!(circle_intersection(c1, r1, c2, r2, q * 7.0).unwrap(), p);
        }
        assert_near(
            circle_intersection([20.0, -20.0], 31.0, [-20.0, -20.0], 31.0, 1.0).unwrap(),
            [0.0, -20.0 + 561f64.sqrt()],
            1e-12,
        );
    }

    #[test]
    fn q_for_g2_arcs_is_the_turn_rule() {
        // Inferred: Q-1 where the contour turns left. G2–G2 takes the same (left) point as G3–G3;
        // G3–G2 and G2–G3 the other one. Checked by the turn at the point itself.
        let (c1, c2, r) = ([20.0, -20.0], [-20.0, -20.0], 31.0);
        let left_point = circle_intersection(c1, r, c2, r, -1.0).unwrap();
        assert_near(left_point, [0.0, -43.685], 0.001);
        for (cw1, cw2) in [(false, false), (true, true), (false, true), (true, false)] {
            for q in [-1.0, 1.0] {
                let p = arc_intersection(c1, r, cw1, c2, r, cw2, q).unwrap();
                let a = arc([20.0, 11.0], p, c1, cw1);
                let b = arc(p, [-20.0, 11.0], c2, cw2);
                let turn = cross(a.tangent_at(p).unwrap(), b.tangent_at(p).unwrap());
                assert_eq!(turn > 0.0, q < 0.0, "{cw1} {cw2} Q{q}: turn {turn}");
                assert_eq!(near(p, left_point, 1e-9), (cw1 == cw2) == (q < 0.0));
            }
        }
    }

    #[test]
    fn roundings_between_the_arcs_of_28_29_30() {
        // 28: ,R14 at each corner, G3 arcs turning left: inside both circles, the centre at
        // 505 − 14 = 491 and 185 − 14 = 171 from the two centres, on the Q side:
        // README X±22.2835 Y±34.5419.
        let want = [
            [22.2835, 34.5419],
            [-22.2835, 34.5419],
            [-22.2835, -34.5419],
            [22.2835, -34.5419],
        ];
        let arcs = chain((467.5, 505.0), (135.0, 185.0), [37.5, 0.0]);
        for (i, w) in want.iter().enumerate() {
            let f = round(&arcs[i], &arcs[i + 1], 14.0);
            let (_, _, fc, cw) = fillet(&f);
            assert_near(fc, *w, 0.0001);
            assert!(!cw);
            assert!(
                (dist(fc, [-467.5, 0.0]) - 491.0).abs() < 1e-9
                    || (dist(fc, [467.5, 0.0]) - 491.0).abs() < 1e-9
            );
        }
        // 29: ,R18, inside both (460 − 18, 200 − 18): X±14.4349 Y±81.4267.
        let want = [
            [14.4349, 81.4267],
            [-14.4349, 81.4267],
            [-14.4349, -81.4267],
            [14.4349, -81.4267],
        ];
        let arcs = chain((420.0, 460.0), (100.0, 200.0), [40.0, 0.0]);
        for (i, w) in want.iter().enumerate() {
            let (_, _, fc, cw) = fillet(&round(&arcs[i], &arcs[i + 1], 18.0));
            assert_near(fc, *w, 0.0001);
            assert!(!cw);
        }
        // The rounded chain of 29 is still one contour: each element starts where the last ended.
        let mut prev = arcs[0].from();
        let mut rest = arcs[0];
        for b in &arcs[1..] {
            let (a, f, nb) = corner(&rest, b, Corner::Round(18.0)).unwrap();
            assert_eq!(a.from(), prev);
            assert_eq!(f.from(), a.to());
            assert_eq!(nb.from(), f.to());
            prev = f.to();
            rest = nb;
        }
        assert_eq!(rest.to(), [40.0, 0.0]);
        // 30 N230/N240 ,R5: both G3, turning right (Q1): outside both circles, 31 + 5 = 36 from
        // X±20 Y-20: x = 0, y = −20 + √(36² − 20²) = −20 + √896 = Y9.9333; G2.
        let p = circle_intersection([20.0, -20.0], 31.0, [-20.0, -20.0], 31.0, 1.0).unwrap();
        let a = arc([20.0, 11.0], p, [20.0, -20.0], false);
        let b = arc(p, [-20.0, 11.0], [-20.0, -20.0], false);
        let f = round(&a, &b, 5.0);
        let (fa, fb, fc, cw) = fillet(&f);
        assert_near(fc, [0.0, -20.0 + 896f64.sqrt()], 1e-9);
        assert_near(fc, [0.0, 9.9333], 0.0001);
        assert!(cw);
        // Tangent points on the lines from each centre through the rounding's centre, 31/36 of
        // the way: X20 − 20·31/36 = X2.7778, Y−20 + 29.9333·31/36 = Y5.7759 (and mirrored).
        assert_near(fa, [2.7778, 5.7759], 0.0001);
        assert_near(fb, [-2.7778, 5.7759], 0.0001);
    }

    #[test]
    fn zero_values_are_markers() {
        // ,R0 (exercise 10): the elements unchanged, a zero-radius arc at the corner that says the
        // turn (X+ then Y+: left, G3); ,C0 a zero-length line.
        let a = line([-100.0, -50.0], [100.0, -50.0]);
        let b = line([100.0, -50.0], [100.0, 50.0]);
        let (na, m, nb) = corner(&a, &b, Corner::Round(0.0)).unwrap();
        assert_eq!((na, nb), (a, b));
        assert_eq!(
            m,
            arc([100.0, -50.0], [100.0, -50.0], [100.0, -50.0], false)
        );
        assert!(m.is_marker());
        let (_, m, _) =
            corner(&b, &line([100.0, 50.0], [200.0, 50.0]), Corner::Round(0.0)).unwrap();
        assert!(
            m.is_marker()
                && matches!(
                    m,
                    Element::Arc {
                        clockwise: true,
                        ..
                    }
                )
        );
        let (na, m, nb) = corner(&a, &b, Corner::Chamfer(0.0)).unwrap();
        assert_eq!((na, nb), (a, b));
        assert_eq!(m, line([100.0, -50.0], [100.0, -50.0]));
        assert!(m.is_marker());
        // Real elements are not markers, a full circle included.
        assert!(!a.is_marker());
        assert!(!arc([10.0, 0.0], [10.0, 0.0], [0.0, 0.0], false).is_marker());
    }

    #[test]
    fn corners_that_do_not_fit() {
        let a = line([0.0, 0.0], [100.0, 0.0]);
        let b = line([100.0, 0.0], [100.0, 5.0]);
        // At 90° R10 takes 10 from each line; the second is 5 long: 0055.
        let e = corner(&a, &b, Corner::Round(10.0)).unwrap_err();
        assert_eq!(e.number, DOES_NOT_FIT);
        assert!(e.message.contains("past the end"), "{}", e.message);
        let e = corner(
            &b.with_from([100.0, 0.0]),
            &line([100.0, 5.0], [0.0, 5.0]),
            Corner::Chamfer(6.0),
        );
        assert_eq!(e.unwrap_err().number, DOES_NOT_FIT);
        // Exactly the length of the first element: fits, the first element keeps no length.
        let (na, _, _) = corner(
            &line([95.0, 0.0], [100.0, 0.0]),
            &line([100.0, 0.0], [100.0, 50.0]),
            Corner::Round(5.0),
        )
        .unwrap();
        assert!(dist(na.from(), na.to()) < 1e-12);
        // A rounding R12 inside a G3 arc of R10 (the arc turning left, the turn left): 0055.
        let a = line([10.0, -20.0], [10.0, 0.0]);
        let b = arc([10.0, 0.0], [-10.0, 0.0], [0.0, 0.0], false);
        // At X10 Y0 the G3 arc about X0 Y0 heads Y+: tangent to the line — no corner, 0051.
        assert_eq!(
            corner(&a, &b, Corner::Round(2.0)).unwrap_err().number,
            NO_CORNER
        );
        let a = line([0.0, -20.0], [10.0, 0.0]);
        let e = corner(&a, &b, Corner::Round(12.0)).unwrap_err();
        assert_eq!(e.number, DOES_NOT_FIT);
        // A rounding larger than a short arc allows: 28's arcs with R150: 0055.
        let arcs = chain((467.5, 505.0), (135.0, 185.0), [37.5, 0.0]);
        assert_eq!(
            corner(&arcs[0], &arcs[1], Corner::Round(150.0))
                .unwrap_err()
                .number,
            DOES_NOT_FIT
        );
        // Negative or NaN values: 0055.
        let b = line([10.0, 0.0], [10.0, 10.0]);
        let a = line([0.0, 0.0], [10.0, 0.0]);
        assert_eq!(
            corner(&a, &b, Corner::Round(-1.0)).unwrap_err().number,
            DOES_NOT_FIT
        );
        assert_eq!(
            corner(&a, &b, Corner::Chamfer(f64::NAN))
                .unwrap_err()
                .number,
            DOES_NOT_FIT
        );
        // A reversal: 0055.
        let back = line([10.0, 0.0], [0.0, 0.0]);
        assert_eq!(
            corner(&a, &back, Corner::Round(1.0)).unwrap_err().number,
            DOES_NOT_FIT
        );
    }

    #[test]
    fn no_corner() {
        // Collinear lines: 0051, for ,R0 too.
        let a = line([0.0, 0.0], [10.0, 0.0]);
        let b = line([10.0, 0.0], [20.0, 0.0]);
        for c in [Corner::Round(1.0), Corner::Round(0.0), Corner::Chamfer(1.0)] {
            let e = corner(&a, &b, c).unwrap_err();
            assert_eq!(e.number, NO_CORNER);
            assert!(e.message.contains("tangent"), "{}", e.message);
        }
        // 13 N180/N190: Y+ into the G2 R25 about X75 Y30, which heads Y+ at X50 Y30: tangent.
        let a = line([50.0, 0.0], [50.0, 30.0]);
        let b = arc([50.0, 30.0], [100.0, 30.0], [75.0, 30.0], true);
        assert_eq!(
            corner(&a, &b, Corner::Round(5.0)).unwrap_err().number,
            NO_CORNER
        );
        // 29 N240/N260: the G3 R460 about X-420 Y0 ends at X40 Y0 heading Y+, the line goes Y+.
        let a = arc([29.48, -97.815], [40.0, 0.0], [-420.0, 0.0], false);
        let b = line([40.0, 0.0], [40.0, 50.0]);
        assert_eq!(
            corner(&a, &b, Corner::Round(18.0)).unwrap_err().number,
            NO_CORNER
        );
        // An element without length, or a gap between the elements: 0051.
        let z = line([10.0, 0.0], [10.0, 0.0]);
        assert_eq!(
            corner(&a.with_to([10.0, 0.0]), &z, Corner::Round(1.0))
                .unwrap_err()
                .number,
            NO_CORNER
        );
        let gap = line([11.0, 0.0], [11.0, 10.0]);
        assert_eq!(
            corner(&line([0.0, 0.0], [10.0, 0.0]), &gap, Corner::Round(1.0))
                .unwrap_err()
                .number,
            NO_CORNER
        );
    }

    #[test]
    fn messages_name_the_numbers() {
        // 28 N200/N210 with ,R150: the offsets 505 − 150 and 185 − 150 do not meet; with ,R60 the
        // rounding would start before N200's start X37.5 Y0 (N200 sweeps only 5.29°).
        let arcs = chain((467.5, 505.0), (135.0, 185.0), [37.5, 0.0]);
        let msg = |a: &Element, b: &Element, c| corner(a, b, c).unwrap_err().to_string();
        assert_eq!(
            msg(&arcs[0], &arcs[1], Corner::Round(150.0)),
            "alarm 0055: ,R150 at (35.3461, 46.5920): no arc of that radius is tangent to both elements"
        );
        assert_eq!(
            msg(&arcs[0], &arcs[1], Corner::Round(60.0)),
            "alarm 0055: ,R60 at (35.3461, 46.5920): the corner would begin at (37.3142, -13.6994), \
             before the start (37.5000, 0.0000) of the block (a G3 arc of radius 505.0000 about \
             (-467.5000, 0.0000) sweeping 5.2937°)"
        );
        assert_eq!(
            msg(
                &line([0.0, -20.0], [10.0, 0.0]),
                &arc([10.0, 0.0], [-10.0, 0.0], [0.0, 0.0], false),
                Corner::Round(12.0)
            ),
            "alarm 0055: ,R12 at (10.0000, 0.0000): a rounding of that radius cannot lie inside the \
             arc of radius 10.0000 about (0.0000, 0.0000)"
        );
        assert_eq!(
            circle_intersection([0.0, 0.0], 30.0, [100.0, 0.0], 40.0, -1.0)
                .unwrap_err()
                .to_string(),
            "alarm 0057: arc intersection: the circle R30 about (0.0000, 0.0000) and the circle R40 \
             about (100.0000, 0.0000) do not meet: their centres are 100.0000 apart, more than \
             R1 + R2 = 70.0000"
        );
    }

    #[test]
    fn circles_that_do_not_meet() {
        // Centres 100 apart, radii 30 + 40 < 100: 0057.
        let e = circle_intersection([0.0, 0.0], 30.0, [100.0, 0.0], 40.0, -1.0).unwrap_err();
        assert_eq!(e.number, NO_INTERSECTION);
        assert!(e.message.contains("do not meet"), "{}", e.message);
        // One inside the other: 10 apart, |50 − 30| = 20 > 10.
        let e = circle_intersection([0.0, 0.0], 50.0, [10.0, 0.0], 30.0, 1.0).unwrap_err();
        assert!(
            e.number == NO_INTERSECTION && e.message.contains("inside"),
            "{}",
            e.message
        );
        // Concentric, a radius of 0, Q0 with two points: 0057.
        let e = circle_intersection([5.0, 5.0], 10.0, [5.0, 5.0], 10.0, 1.0).unwrap_err();
        assert!(e.number == NO_INTERSECTION && e.message.contains("concentric"));
        assert_eq!(
            circle_intersection([0.0, 0.0], 0.0, [1.0, 0.0], 1.0, 1.0)
                .unwrap_err()
                .number,
            NO_INTERSECTION
        );
        let e = circle_intersection([20.0, -20.0], 31.0, [-20.0, -20.0], 31.0, 0.0).unwrap_err();
        assert!(
            e.number == NO_INTERSECTION && e.message.contains("Q0"),
            "{}",
            e.message
        );
        // Touching circles (30 + 70 = 100): the one point, whatever Q (Q0 included).
        for q in [-1.0, 0.0, 1.0] {
            let p = circle_intersection([0.0, 0.0], 30.0, [100.0, 0.0], 70.0, q).unwrap();
            assert_near(p, [30.0, 0.0], 1e-9);
        }
    }
}
