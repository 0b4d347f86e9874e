//! The path of motion from the kernel to the emitter: the contour stage (corner words `,R` `,C`,
//! NCT's arc intersections), which holds a move until the next one decides it, then cutter
//! compensation, then the emitter; non-motion operations wait behind a held move.

use super::*;

impl<E: Emitter> Kernel<E> {
    /// Step 10: the contour stage's corner word for this block's move.
    #[inline(always)]
    pub(super) fn corner_words(&mut self, w: &Words, origin: Origin) -> Result<(), Stop> {
        self.follow_frame(origin)?;
        let factor = self.transform.radius_factor(self.plane()).unwrap_or(1.0);
        self.stage = Stage {
            corner: match (w.get(Letter::CommaR), w.get(Letter::CommaC)) {
                (Some(r), _) => Some(Corner::Round(r * factor)),
                (None, Some(c)) => Some(Corner::Chamfer(c * factor)),
                _ => None,
            },
            ..Stage::default()
        };
        Ok(())
    }

    /// Sends one canonical operation (motion through cutter compensation when it is on).
    pub(super) fn canon(&mut self, op: Canon<'_>, origin: Origin) -> Result<(), Stop> {
        if !E::CANON {
            return Ok(());
        }
        if self.settings.lathe.is_some() && !self.feed_known {
            self.lathe_feed_known(&op)?;
        }
        let origin = Origin {
            fixed: origin.fixed & !self.warned_axes,
            ..origin
        };
        let motion = match &op {
            Canon::Rapid(p) | Canon::Feed(p) | Canon::Skip(p) => Some((*p, None)),
            Canon::Arc(a) => Some((a.to, Some(a.plane))),
            _ => None,
        };
        if let Some((to, arc_plane)) = motion {
            self.follow_frame(origin)?;
            // No move leaves a known axis for an unknown place, and no arc starts or ends where
            // its plane's axes are unknown.
            if let Some(i) = (0..6).find(|&i| to[i].is_nan() && !self.path_from[i].is_nan()) {
                return Err(unknown_axis(i, "this move").into());
            }
            if let Some(plane) = arc_plane {
                let (a, b, _) = plane.axes();
                for i in [a, b] {
                    if to[i].is_nan() || self.path_from[i].is_nan() {
                        return Err(unknown_axis(
                            i,
                            "an arc (its centre and radius are from its start)",
                        )
                        .into());
                    }
                }
            }
        }
        let m = match op {
            Canon::Rapid(to) => crate::comp::Move::Line { to, rapid: true },
            Canon::Feed(to) => crate::comp::Move::Line { to, rapid: false },
            Canon::Arc(a) => crate::comp::Move::Arc(a),
            // Non-motion operations wait behind a move the contour stage or compensation holds.
            other => {
                if self.comp.is_active() || self.pending.is_some() {
                    self.held.push((Held::of(&other), origin));
                    return Ok(());
                }
                return self.emitter.canon(&other, origin);
            }
        };
        let stage = std::mem::take(&mut self.stage);
        self.contour(m, stage, origin)
    }

    /// The contour stage: corner words and arc intersections need the next move, so a move that has
    /// either waits for it; everything else goes on to compensation at once.
    pub(super) fn contour(&mut self, m: Move, stage: Stage, origin: Origin) -> Result<(), Stop> {
        // Under compensation a straight move that rounds to nothing at the least increment (under
        // half of it on every axis) is no move: it must make no corner (the gear teeth of textbook
        // 32/33), and an R arc after it starts where the tool is.
        if let Move::Line { to, .. } = m
            && stage.corner.is_none()
            && self.comp.is_active()
            && rounds_to_nothing(&to, &self.path_from)
        {
            return Ok(());
        }
        let mut cur = Pending {
            from: self.path_from,
            m,
            corner: stage.corner,
            circle: stage.circle,
            open: stage.open,
            origin,
        };
        match self.pending.take() {
            Some(prev) => self.join(prev, &mut cur)?,
            None if cur.circle.is_some() => self.lone_intersection(&mut cur)?,
            None => {}
        }
        if !cur.open {
            self.path_from = cur.m.to();
        }
        let hold = cur.corner.is_some()
            || cur.open
            || (self.settings.arc_intersections && matches!(cur.m, Move::Arc(_)));
        if hold {
            self.pending = Some(cur);
            return Ok(());
        }
        self.compensate(cur.m, cur.origin)?;
        self.release_held()
    }

    /// Lets a held move go as it stands (before compensation changes, and at the end).
    pub(super) fn settle(&mut self) -> Result<(), Stop> {
        let Some(p) = self.pending.take() else {
            return Ok(());
        };
        if p.open {
            return Err(Alarm::new(
                crate::contour::NO_INTERSECTION,
                format!(
                    "the arc of line {} has no end point, and no arc intersection block (G2/G3 I J R) follows it",
                    p.origin.line
                ),
            )
            .into());
        }
        if let Some(c) = p.corner {
            let value = match c {
                Corner::Round(v) | Corner::Chamfer(v) => v,
            };
            if value != 0.0 {
                return Err(Alarm::new(
                    crate::contour::NO_CORNER,
                    format!(
                        "the corner word of line {} has no move after it to make the corner with",
                        p.origin.line
                    ),
                )
                .into());
            }
        }
        self.compensate(p.m, p.origin)?;
        self.release_held()
    }

    /// An arc intersection block with no arc before it: an arc about its centre from where the tool
    /// is, if its end lies on the circle.
    pub(super) fn lone_intersection(&mut self, cur: &mut Pending) -> Result<(), Stop> {
        let Some(c) = cur.circle else { return Ok(()) };
        let plane = self.plane();
        let [fx, fy] = plane.project(&cur.from);
        if cur.open
            || ((fx - c.centre[0]).hypot(fy - c.centre[1]) - c.radius).abs()
                > self.settings.arc_tolerance
        {
            return Err(Alarm::new(
                crate::contour::NO_INTERSECTION,
                format!(
                    "the arc intersection block of line {} (I J R) has no arc before it to meet",
                    cur.origin.line
                ),
            )
            .into());
        }
        cur.m = self.circle_arc(cur.from, cur.m.to(), c)?;
        cur.circle = None;
        Ok(())
    }

    /// The arc about circle `c` from `from` to `to`; its end must lie on the circle (alarm 0020).
    pub(super) fn circle_arc(&self, from: Pose, to: Pose, c: Circle) -> Result<Move, Alarm> {
        let plane = self.plane();
        let [ex, ey] = plane.project(&to);
        let r1 = (ex - c.centre[0]).hypot(ey - c.centre[1]);
        if (r1 - c.radius).abs() > self.settings.arc_tolerance {
            return Err(Alarm::new(
                arcs::RADIUS_TOLERANCE,
                format!(
                    "over tolerance of radius: the end point is {r1:.4} from the centre I J, R is {:.4}",
                    c.radius
                ),
            ));
        }
        let _ = from;
        Ok(Move::Arc(fmsvm_canon::Arc {
            to,
            centre: c.centre,
            plane,
            clockwise: c.clockwise,
            turns: 0,
        }))
    }

    /// Joins the held move `prev` to `cur`: `cur`'s circle decides where `prev` ends, `prev`'s corner
    /// word inserts its rounding or chamfer; `prev` (and what was inserted) goes on.
    pub(super) fn join(&mut self, mut prev: Pending, cur: &mut Pending) -> Result<(), Stop> {
        let plane = self.plane();
        let (a, b, _) = plane.axes();
        if let Some(cb) = cur.circle {
            let (ca, ra, cwa) = match (prev.circle, prev.m) {
                (Some(c), _) => (c.centre, c.radius, c.clockwise),
                (None, Move::Arc(arc)) => {
                    let [fx, fy] = plane.project(&prev.from);
                    (
                        arc.centre,
                        (fx - arc.centre[0]).hypot(fy - arc.centre[1]),
                        arc.clockwise,
                    )
                }
                _ => {
                    return Err(Alarm::new(
                        crate::contour::NO_INTERSECTION,
                        format!(
                            "the arc intersection block of line {} (I J R) follows a straight move: it meets arcs only",
                            cur.origin.line
                        ),
                    )
                    .into());
                }
            };
            let p = crate::contour::arc_intersection(
                ca,
                ra,
                cwa,
                cb.centre,
                cb.radius,
                cb.clockwise,
                cb.q,
            )?;
            let mut end = if prev.open { prev.from } else { prev.m.to() };
            end[a] = p[0];
            end[b] = p[1];
            prev.m = Move::Arc(fmsvm_canon::Arc {
                to: end,
                centre: ca,
                plane,
                clockwise: cwa,
                turns: 0,
            });
            prev.open = false;
            prev.circle = None;
            cur.from = end;
            if cur.open {
                cur.m = Move::Arc(fmsvm_canon::Arc {
                    to: end,
                    centre: cb.centre,
                    plane,
                    clockwise: cb.clockwise,
                    turns: 0,
                });
            } else {
                cur.m = self.circle_arc(end, cur.m.to(), cb)?;
                cur.circle = None;
            }
        } else if prev.open {
            return Err(Alarm::new(
                crate::contour::NO_INTERSECTION,
                format!(
                    "the arc of line {} has no end point, and the next block is no arc intersection (G2/G3 I J R)",
                    prev.origin.line
                ),
            )
            .into());
        }
        if let Some(corner) = prev.corner {
            let ea = element(plane, &prev.from, &prev.m);
            let eb = element(plane, &cur.from, &cur.m);
            let (a2, ins, b2) = crate::contour::corner(&ea, &eb, corner)?;
            let corner_pose = prev.m.to();
            prev.m = lift(plane, &a2, &prev.m);
            self.compensate(prev.m, prev.origin)?;
            let feed = Move::Line {
                to: corner_pose,
                rapid: false,
            };
            if !ins.is_marker() {
                self.compensate(lift(plane, &ins, &feed), prev.origin)?;
            } else if matches!(corner, Corner::Round(_))
                && self.comp.is_active()
                && self.settings.comp_style == CompStyle::Fanuc
            {
                // `,R0` under Fanuc's compensation: the convex corner goes round on the tool radius
                // (exercise 10).
                self.comp.round_next_corner();
            }
            let mut start = cur.from;
            let [sx, sy] = b2.from();
            start[a] = sx;
            start[b] = sy;
            cur.from = start;
            cur.m = lift(plane, &b2, &cur.m);
        } else {
            self.compensate(prev.m, prev.origin)?;
        }
        Ok(())
    }

    /// A final move of the programmed path to cutter compensation (when it is on) and the emitter.
    pub(super) fn compensate(&mut self, m: Move, origin: Origin) -> Result<(), Stop> {
        let lin = self.settings.linearize;
        if self.comp.is_active() {
            let mut from = self.comp_from;
            if let Some(d) = self.comp_start_along.take() {
                // The start-up element is the line of direction I J that ends at this move's end.
                let (a, b, _) = self.plane().axes();
                let to = m.to();
                let len = d[0].hypot(d[1]);
                from[a] = to[a] - d[0] / len * 1000.0;
                from[b] = to[b] - d[1] / len * 1000.0;
            }
            // A move that rounds to nothing is no move: it would make a corner of nothing (pieces of
            // a corner the contour stage made, too).
            if let Move::Line { to, .. } = m
                && rounds_to_nothing(&to, &from)
            {
                return Ok(());
            }
            let emitter = &mut self.emitter;
            let out = &mut self.out_position;
            // LinuxCNC's queue keeps the blocks' other operations (an F, an M8) in order: what
            // came with this move goes out after the moves held from before it, and before the
            // corner's arc, which is this block's (it moves at this block's F).
            let mut before = self.comp.held_moves();
            let held = &mut self.held;
            self.comp.push(from, m, &mut |m| {
                if before == Some(0) {
                    for (h, o) in std::mem::take(held) {
                        match &h {
                            Held::Op(op) => emitter.canon(op, o)?,
                            Held::Comment(t) => emitter.canon(&Canon::Comment(t), o)?,
                        }
                    }
                }
                before = before.and_then(|n| n.checked_sub(1));
                emit_move(emitter, out, lin, m, origin)
            })?;
            self.comp_from = m.to();
            Ok(())
        } else {
            emit_move(&mut self.emitter, &mut self.out_position, lin, m, origin)
        }
    }

    /// Whether a G2/G3 block is NCT's arc intersection: I J (the absolute centre) with R.
    pub(super) fn is_intersection(&self, w: &Words) -> bool {
        let (a, b, _) = self.plane().axes();
        let offsets = [Letter::I, Letter::J, Letter::K];
        self.settings.arc_intersections
            && w.has(Letter::R)
            && w.has(offsets[a])
            && w.has(offsets[b])
    }

    /// An arc intersection block to the contour stage: its circle (I J absolute, R), Q, and its end
    /// point if it has one (else the next such block decides it).
    pub(super) fn intersection_arc(
        &mut self,
        to: &Pose,
        clockwise: bool,
        w: &Words,
        origin: Origin,
    ) -> Result<(), Stop> {
        let plane = self.plane();
        let (a, b, _) = plane.axes();
        let offsets = [Letter::I, Letter::J, Letter::K];
        self.transform.check_arc_plane(plane)?;
        let factor = self.transform.radius_factor(plane)?;
        let mut c = self.position;
        c[a] = w.get(offsets[a]).unwrap_or(0.0);
        c[b] = w.get(offsets[b]).unwrap_or(0.0);
        let c = self.out_point(&c);
        let open = !(w.has(AXES[a]) || w.has(AXES[b]));
        self.stage.circle = Some(Circle {
            centre: [c[a], c[b]],
            radius: w.get(Letter::R).unwrap_or(0.0).abs() * factor,
            clockwise: clockwise != self.transform.reverses(plane),
            q: w.get(Letter::Q).unwrap_or(0.0),
        });
        self.stage.open = open;
        let end = self.out_point(to);
        self.canon(
            Canon::Arc(fmsvm_canon::Arc {
                to: end,
                centre: [c[a], c[b]],
                plane,
                clockwise,
                turns: 0,
            }),
            origin,
        )
    }
}

/// A move of the contour stage.
type Move = crate::comp::Move;

/// A circle an arc intersection block gives (output frame, plane coordinates).
#[derive(Clone, Copy, Debug)]
pub(super) struct Circle {
    centre: [f64; 2],
    radius: f64,
    clockwise: bool,
    q: f64,
}

/// What the block in hand adds to its move for the contour stage.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Stage {
    corner: Option<Corner>,
    circle: Option<Circle>,
    /// The block gives no end point: the next block's circle decides it.
    open: bool,
}

/// A move the contour stage holds.
#[derive(Clone, Copy, Debug)]
pub(super) struct Pending {
    from: Pose,
    m: Move,
    corner: Option<Corner>,
    circle: Option<Circle>,
    open: bool,
    origin: Origin,
}

/// A move as a contour element in the plane.
pub(super) fn element(plane: Plane, from: &Pose, m: &Move) -> crate::contour::Element {
    match m {
        Move::Line { to, .. } => crate::contour::Element::Line {
            from: plane.project(from),
            to: plane.project(to),
        },
        Move::Arc(a) => crate::contour::Element::Arc {
            from: plane.project(from),
            to: plane.project(&a.to),
            centre: a.centre,
            clockwise: a.clockwise,
        },
    }
}

/// A contour element back as a move, its other axes (and its rapid flag) from `like`.
pub(super) fn lift(plane: Plane, e: &crate::contour::Element, like: &Move) -> Move {
    let (a, b, _) = plane.axes();
    let mut to = like.to();
    let [x, y] = e.to();
    to[a] = x;
    to[b] = y;
    match *e {
        crate::contour::Element::Line { .. } => Move::Line {
            to,
            rapid: matches!(like, Move::Line { rapid: true, .. }),
        },
        crate::contour::Element::Arc {
            centre, clockwise, ..
        } => Move::Arc(fmsvm_canon::Arc {
            to,
            centre,
            plane,
            clockwise,
            turns: 0,
        }),
    }
}

/// A non-motion operation kept while compensation holds a move (owned: a comment outlives its block).
#[derive(Debug)]
pub(super) enum Held {
    Op(Canon<'static>),
    Comment(String),
}

impl Held {
    pub(super) fn of(op: &Canon<'_>) -> Held {
        match (op.without_text(), op) {
            (Some(op), _) => Held::Op(op),
            (None, Canon::Comment(t)) => Held::Comment(t.to_string()),
            (None, _) => unreachable!("only a comment has text"),
        }
    }
}

/// Writes one final move (after compensation) as canonical operations: arcs as arcs, or as chords.
pub(super) fn emit_move<E: Emitter>(
    emitter: &mut E,
    out: &mut Pose,
    linearize: Option<f64>,
    m: crate::comp::Move,
    origin: Origin,
) -> Result<(), Stop> {
    match m {
        crate::comp::Move::Line { to, rapid } => {
            *out = to;
            emitter.canon(
                &if rapid {
                    Canon::Rapid(to)
                } else {
                    Canon::Feed(to)
                },
                origin,
            )
        }
        crate::comp::Move::Arc(a) => {
            let from = *out;
            *out = a.to;
            match linearize {
                None => emitter.canon(&Canon::Arc(a), origin),
                Some(tol) => arcs::chords(&from, &a, tol, &mut |p| {
                    emitter.canon(&Canon::Feed(p), origin)
                }),
            }
        }
    }
}

/// Whether a straight move from `from` to `to` rounds to nothing at the least increment (under half
/// of 0.001 on every axis).
pub(super) fn rounds_to_nothing(to: &Pose, from: &Pose) -> bool {
    // An axis unknown at both ends (NaN) does not move.
    to.iter()
        .zip(from)
        .all(|(a, b)| (a - b).abs() < 5e-4 || (a.is_nan() && b.is_nan()))
}
