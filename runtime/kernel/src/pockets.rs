//! G71/G72 type II: stock removal of a profile with pockets (docs/lathe.md, "Type II profiles").
//!
//! The profile, moved by the finishing allowance, is cut in levels Δd apart as in type I, but a
//! level may meet it several times: each stretch of a level that lies in the stock is a *region*
//! (the one reached from the start point, and the pockets). Regions are cut one at a time, each
//! down to its bottom before the next (the pocket beyond a shoulder after the stock before it), in
//! the order of the cut. A pass: in along the wall of its pocket (following the profile down from
//! where the level above left it), along the level to the far wall, up that wall along the profile
//! to the level above (or to the wall's top), out by the retract e along the level axis. Sources:
//! the Haas lathe manual ("G71 O.D./I.D. stock removal", "Type 2 details": type II when the first
//! block names both axes; Z monotonic, X free; each pass follows the profile and retracts parallel
//! to the other axis) and the Allen-Bradley 8520 lathe manual (a pocket is left along the contour
//! for the next); the order and the travel between regions are *inferred*.

use fmsvm_block::Alarm;
use fmsvm_block::alarms::NO_FANUC_NUMBER;
use fmsvm_canon::geom::dist;

use crate::turning::{P2, Profile, Seg, Step, StockRemoval};

/// Below this, a length is none.
const TINY: f64 = 1e-9;
/// The most passes a cycle may make.
const MAX_PASSES: usize = 100_000;

/// A piece of the moved profile, monotonic on both axes (arcs split at their extremes).
#[derive(Clone, Copy, Debug)]
struct Piece {
    from: P2,
    seg: Seg,
}

impl Piece {
    fn to(&self) -> P2 {
        self.seg.to()
    }
}

/// The geometry of one cycle: the pieces, its axes and directions.
struct Shape {
    pieces: Vec<Piece>,
    /// The level axis (0 X for G71) and the cut axis.
    lv: usize,
    ct: usize,
    /// Which way the stock lies from the profile on the level axis.
    out: f64,
}

/// A point on the profile: the piece it is on and where.
#[derive(Clone, Copy, Debug)]
struct Mark {
    k: usize,
    p: P2,
}

/// A stretch of one level in the stock: from `c_in` (None: from the start point's side) to
/// `c_out` (None: past the profile's end).
#[derive(Clone, Copy, Debug)]
struct Region {
    level: usize,
    c_in: Option<Mark>,
    c_out: Option<Mark>,
}

impl Shape {
    /// How far `p` is out of level `l`: above 0 where the profile stands above the level (no stock
    /// to cut there), below 0 where the level runs in the stock.
    fn depth(&self, p: P2, l: f64) -> f64 {
        (p[self.lv] - l) * self.out
    }

    /// Where a mark lies along the profile: its piece's index and the fraction of the piece.
    fn order(&self, m: &Mark) -> f64 {
        let piece = &self.pieces[m.k];
        let len = dist(piece.from, piece.to());
        m.k as f64
            + if len > TINY {
                (dist(piece.from, m.p) / len).min(1.0)
            } else {
                1.0
            }
    }

    /// Where `piece` meets level `l`, if it crosses it.
    fn crossing(&self, piece: &Piece, l: f64) -> Option<P2> {
        let (a, b) = (piece.from, piece.to());
        let (da, db) = (self.depth(a, l), self.depth(b, l));
        if (da < -TINY) == (db < -TINY) {
            return None;
        }
        self.at_level(piece, l)
    }

    /// The point of `piece` on level `l` (a piece is monotonic: at most one).
    fn at_level(&self, piece: &Piece, l: f64) -> Option<P2> {
        let (a, b) = (piece.from, piece.to());
        let mut q = [0.0; 2];
        q[self.lv] = l;
        match piece.seg {
            Seg::Line { .. } => {
                let span = b[self.lv] - a[self.lv];
                if span.abs() < TINY {
                    return None;
                }
                let t = ((l - a[self.lv]) / span).clamp(0.0, 1.0);
                q[self.ct] = a[self.ct] + (b[self.ct] - a[self.ct]) * t;
            }
            Seg::Arc { centre, .. } => {
                let r = dist(a, centre);
                let dl = l - centre[self.lv];
                let h = (r * r - dl * dl).max(0.0).sqrt();
                let (lo, hi) = (a[self.ct].min(b[self.ct]), a[self.ct].max(b[self.ct]));
                q[self.ct] = [centre[self.ct] + h, centre[self.ct] - h]
                    .into_iter()
                    .find(|c| *c >= lo - 1e-7 && *c <= hi + 1e-7)?
                    .clamp(lo, hi);
            }
        }
        Some(q)
    }

    /// The stretches of level `l` in the stock, in the cut's order.
    fn regions(&self, level: usize, l: f64) -> Vec<Region> {
        let mut out = Vec::new();
        let first = self.pieces[0].from;
        let mut open = (self.depth(first, l) < -TINY).then_some(None);
        for (k, piece) in self.pieces.iter().enumerate() {
            if let Some(p) = self.crossing(piece, l) {
                let m = Mark { k, p };
                match open.take() {
                    Some(c_in) => out.push(Region {
                        level,
                        c_in,
                        c_out: Some(m),
                    }),
                    None => open = Some(Some(m)),
                }
            }
        }
        if let Some(c_in) = open {
            out.push(Region {
                level,
                c_in,
                c_out: None,
            });
        }
        // A level that only touches the stock between two crossings at one point cuts nothing.
        out.retain(|r| match (r.c_in, r.c_out) {
            (Some(a), Some(b)) => dist(a.p, b.p) > TINY,
            _ => true,
        });
        out
    }

    /// The moves along the profile from `m` forwards while it climbs out of the stock, until it
    /// reaches level `top` or stops climbing (a wall's top) or ends. Returns the point reached.
    fn climb(&self, m: Mark, top: f64, feed: Option<f64>, steps: &mut Vec<Step>) -> P2 {
        let mut at = m.p;
        for piece in &self.pieces[m.k..] {
            let end = piece.to();
            if self.depth(end, top) <= self.depth(at, top) + TINY {
                return at;
            }
            if self.depth(end, top) >= -TINY {
                let stop = self.at_level(piece, top).unwrap_or(end);
                steps.push(step_along(piece, stop, feed));
                return stop;
            }
            steps.push(step_along(piece, end, feed));
            at = end;
        }
        at
    }

    /// The top of the wall that falls to `m` from level `top` (or from a bump lower than it):
    /// where a pass down that wall starts.
    fn wall_top(&self, m: Mark, top: f64) -> Mark {
        let mut at = m;
        for k in (0..=m.k).rev() {
            let piece = &self.pieces[k];
            let start = piece.from;
            // Backwards, the wall rises while the piece's start stands higher.
            if self.depth(start, top) <= self.depth(at.p, top) + TINY {
                return at;
            }
            if self.depth(start, top) >= -TINY {
                return Mark {
                    k,
                    p: self.at_level(piece, top).unwrap_or(start),
                };
            }
            at = Mark { k, p: start };
        }
        at
    }

    /// The moves along the profile from mark `from` forwards to mark `to`.
    fn follow(&self, from: Mark, to: Mark, feed: Option<f64>, steps: &mut Vec<Step>) {
        for k in from.k..=to.k {
            let piece = &self.pieces[k];
            let end = if k == to.k { to.p } else { piece.to() };
            let start = if k == from.k { from.p } else { piece.from };
            if dist(start, end) > TINY {
                steps.push(step_along(piece, end, feed));
            }
        }
    }
}

/// The move along `piece` to its point `to`, at the feed.
fn step_along(piece: &Piece, to: P2, f: Option<f64>) -> Step {
    match piece.seg {
        Seg::Line { .. } => Step::Feed(to, f),
        Seg::Arc { centre, cw, .. } => Step::Arc { to, centre, cw, f },
    }
}

/// The pieces of `segs` from `start`, each monotonic on both axes: arcs split where the level axis
/// has an extreme (a type II profile is monotonic on the cut axis, checked before).
fn pieces(start: P2, segs: &[Seg], lv: usize, ct: usize) -> Vec<Piece> {
    let mut out = Vec::with_capacity(segs.len() * 2);
    let mut from = start;
    for seg in segs {
        let to = seg.to();
        if let Seg::Arc { centre, cw, .. } = *seg {
            let r = (from[0] - centre[0]).hypot(from[1] - centre[1]);
            let c = centre[ct];
            let (lo, hi) = (from[ct].min(to[ct]), from[ct].max(to[ct]));
            if c > lo + 1e-7 && c < hi - 1e-7 {
                // The extreme of the level axis: on the side of the arc's ends.
                let side = (from[lv] - centre[lv]) + (to[lv] - centre[lv]);
                let mut mid = [0.0; 2];
                mid[ct] = c;
                mid[lv] = centre[lv] + r.copysign(side);
                out.push(Piece {
                    from,
                    seg: Seg::Arc {
                        to: mid,
                        centre,
                        cw,
                    },
                });
                out.push(Piece {
                    from: mid,
                    seg: Seg::Arc { to, centre, cw },
                });
                from = to;
                continue;
            }
        }
        if (to[0] - from[0]).hypot(to[1] - from[1]) > TINY {
            out.push(Piece { from, seg: *seg });
        }
        from = to;
    }
    out
}

/// G71 (`cut` = 1) or G72 (`cut` = 0), type II, from start point `a`: the regions' passes, then
/// the pass along the moved profile, then back to `a` (see the module documentation).
pub(crate) fn stock_removal(
    a: P2,
    p: &Profile,
    cut: usize,
    d: &StockRemoval,
    name: &str,
    budget: &fmsvm_block::OutputBudget,
) -> Result<Vec<Step>, fmsvm_block::Stop> {
    let bad = |what: String| -> fmsvm_block::Stop {
        Alarm::new(NO_FANUC_NUMBER, format!("{name} (type II): {what}")).into()
    };
    let (shape, m0, moved) = shape_of(a, p, cut, d).map_err(bad)?;
    let (lv, ct) = (shape.lv, shape.ct);
    // The deepest point of the profile: the last level is above it.
    let deepest = shape
        .pieces
        .iter()
        .map(|q| shape.depth(q.to(), a[lv]).min(shape.depth(q.from, a[lv])))
        .fold(0.0_f64, f64::min);
    let levels = ((-deepest) / d.depth).ceil() as usize;
    let too_many = || {
        bad(format!(
            "more than {MAX_PASSES} passes (depth of cut {})",
            d.depth
        ))
    };
    if levels > MAX_PASSES {
        return Err(too_many());
    }
    let mut r = Roughing {
        shape: &shape,
        a,
        d,
        infeed_rapid: matches!(p.segs.first(), Some(Seg::Line { rapid: true, .. })),
        end: moved.last().map_or(m0, Seg::to),
        steps: Vec::new(),
        at_top: true,
    };
    // Depth-first: a region, then the regions under it in the cut's order.
    let mut stack: Vec<(Region, bool)> = shape
        .regions(1, r.level(1))
        .into_iter()
        .rev()
        .map(|g| (g, true))
        .collect();
    let mut passes = 0usize;
    while let Some((g, first)) = stack.pop() {
        if g.level > levels {
            continue;
        }
        passes += 1;
        if passes > MAX_PASSES {
            return Err(too_many());
        }
        // Each pass looks the profile through: the run's clock bounds the passes.
        budget.clock()?;
        r.pass(&g, first);
        // The regions of the next level under this one.
        let next = g.level + 1;
        if next <= levels {
            let children: Vec<Region> = shape
                .regions(next, r.level(next))
                .into_iter()
                .filter(|c| contains(&shape, &g, c))
                .collect();
            for (i, c) in children.into_iter().enumerate().rev() {
                // The first stays this region's (its wall was just left); the others are new.
                stack.push((c, i > 0 || g.c_in.is_none() && c.c_in.is_some()));
            }
        }
    }
    // Out of the last pocket, then the pass along the moved profile, and back to the start.
    let mut steps = r.steps;
    if !r.at_top {
        steps.push(Step::Rapid(point_of(
            a[lv],
            last_point(&steps, a)[ct],
            lv,
            ct,
        )));
        steps.push(Step::Rapid(a));
    }
    steps.push(if r.infeed_rapid {
        Step::Rapid(m0)
    } else {
        Step::Feed(m0, d.feed)
    });
    for seg in &moved {
        steps.push(match *seg {
            Seg::Line { to, .. } => Step::Feed(to, d.feed),
            Seg::Arc { to, centre, cw } => Step::Arc {
                to,
                centre,
                cw,
                f: d.feed,
            },
        });
    }
    steps.push(Step::Rapid(a));
    // Travel that arrives where the tool already is is no move.
    let mut last = a;
    steps.retain(|s| {
        let Some(to) = s.to() else {
            return true;
        };
        let keep = dist(to, last) > TINY;
        last = to;
        keep
    });
    Ok(steps)
}

/// The moved profile's shape, its first point and its pieces after the first block, checked: the
/// start point outside it, and every piece going the cut's way.
fn shape_of(
    a: P2,
    p: &Profile,
    cut: usize,
    d: &StockRemoval,
) -> Result<(Shape, P2, Vec<Seg>), String> {
    let (lv, ct) = (1 - cut, cut);
    let p0 = p.segs.first().map(Seg::to).unwrap_or(a);
    let shift = d.allowance;
    let moved: Vec<Seg> = p.segs[1..].iter().map(|s| s.shifted(shift)).collect();
    let m0 = [p0[0] + shift[0], p0[1] + shift[1]];
    let end = moved.last().map_or(m0, Seg::to);
    let along = (end[ct] - m0[ct]).signum();
    let out = (a[lv] - m0[lv]).signum();
    if moved.is_empty() || along == 0.0 || out == 0.0 || (a[lv] - m0[lv]).abs() < TINY {
        return Err(format!(
            "the start point must lie outside the profile on {} and the profile must move along {}",
            ["X", "Z"][lv],
            ["X", "Z"][ct]
        ));
    }
    let shape = Shape {
        pieces: pieces(m0, &moved, lv, ct),
        lv,
        ct,
        out,
    };
    // Every piece goes the cut's way (Z for G71): type II frees only the level axis.
    let mut from = m0;
    for piece in &shape.pieces {
        if (piece.to()[ct] - from[ct]) * along < -1e-9 {
            return Err(format!(
                "the profile N{}–N{} turns back along {} (type II frees only {})",
                p.ns,
                p.nf,
                ["X", "Z"][ct],
                ["X", "Z"][lv]
            ));
        }
        from = piece.to();
    }
    // The profile may not stand above the start point (its allowance may: as when the profile
    // ends on the stock's diameter, type I's rule).
    if p.segs[1..]
        .iter()
        .any(|q| shape.depth(q.to(), a[lv]) > TINY)
    {
        return Err(format!(
            "the start point {}{}{} lies inside the profile: start the cycle outside the stock",
            ["X", "Z"][lv],
            a[lv],
            [" (radius)", ""][lv]
        ));
    }
    Ok((shape, m0, moved))
}

/// The roughing passes as they are made.
struct Roughing<'a> {
    shape: &'a Shape,
    a: P2,
    d: &'a StockRemoval,
    /// The first block is a rapid: the passes go in at rapid.
    infeed_rapid: bool,
    /// The moved profile's end.
    end: P2,
    steps: Vec<Step>,
    /// No pass made yet: the tool is at the start point.
    at_top: bool,
}

impl Roughing<'_> {
    /// Level `k` on the level axis (0: the start point's).
    fn level(&self, k: usize) -> f64 {
        self.a[self.shape.lv] - self.shape.out * k as f64 * self.d.depth
    }

    /// The point at `l` on the level axis and `c` on the cut axis.
    fn point(&self, l: f64, c: f64) -> P2 {
        point_of(l, c, self.shape.lv, self.shape.ct)
    }

    /// One region's pass (`first`: the first of a pocket): in, along the level, up the far wall,
    /// out by e.
    fn pass(&mut self, r: &Region, first: bool) {
        let (shape, d, a) = (self.shape, self.d, self.a);
        let (lv, ct, out) = (shape.lv, shape.ct, shape.out);
        let l = self.level(r.level);
        let up = self.level(r.level - 1);
        match r.c_in {
            None => {
                // From the start point's side at the level, as the first block moves (the tool
                // stands where the last pass came back to: type I's way).
                let to = self.point(l, a[ct]);
                self.steps.push(if self.infeed_rapid {
                    Step::Rapid(to)
                } else {
                    Step::Feed(to, d.feed)
                });
            }
            Some(c_in) => {
                let top = shape.wall_top(c_in, up);
                if first || self.at_top {
                    // To a new pocket: out to the start point's level, across, down.
                    if !self.at_top {
                        let c = last_point(&self.steps, a)[ct];
                        self.steps.push(Step::Rapid(self.point(a[lv], c)));
                    }
                    self.steps.push(Step::Rapid(self.point(a[lv], top.p[ct])));
                } else {
                    // The next pass of the same pocket: across at the height the last pass left
                    // it at (above the stretch it cut and the wall it climbed), then down.
                    let height = last_point(&self.steps, a)[lv];
                    self.steps.push(Step::Rapid(self.point(height, top.p[ct])));
                }
                let clear = self.point(top.p[lv] + out * d.retract, top.p[ct]);
                self.steps.push(Step::Rapid(clear));
                // Down the wall along the profile to the level.
                self.steps.push(Step::Feed(top.p, d.feed));
                shape.follow(top, c_in, d.feed, &mut self.steps);
            }
        }
        // Along the level, then up the far wall to the level above, then out by e.
        let reached = match r.c_out {
            Some(c_out) => {
                self.steps.push(Step::Feed(c_out.p, d.feed));
                shape.climb(c_out, up, d.feed, &mut self.steps)
            }
            None => {
                let q = self.point(l, self.end[ct]);
                self.steps.push(Step::Feed(q, d.feed));
                q
            }
        };
        let out_by_e = reached[lv] + out * d.retract;
        self.steps
            .push(Step::Rapid(self.point(out_by_e, reached[ct])));
        self.at_top = false;
        if r.c_in.is_none() {
            // Back to the start point's side at that height (the stretch behind is cut).
            self.steps.push(Step::Rapid(self.point(out_by_e, a[ct])));
        }
    }
}

/// Whether region `c` (a level deeper) lies under region `r`.
fn contains(shape: &Shape, r: &Region, c: &Region) -> bool {
    let after_start = match (r.c_in, c.c_in) {
        (None, _) => true,
        (Some(_), None) => false,
        (Some(a), Some(b)) => shape.order(&b) >= shape.order(&a) - TINY,
    };
    let before_end = match (r.c_out, c.c_out) {
        (None, _) => true,
        (Some(_), None) => false,
        (Some(a), Some(b)) => shape.order(&b) <= shape.order(&a) + TINY,
    };
    after_start && before_end
}

/// The last point the steps reached (the start point if none).
fn last_point(steps: &[Step], a: P2) -> P2 {
    steps.iter().rev().find_map(Step::to).unwrap_or(a)
}

fn point_of(l: f64, c: f64, lv: usize, ct: usize) -> P2 {
    let mut q = [0.0; 2];
    q[lv] = l;
    q[ct] = c;
    q
}
