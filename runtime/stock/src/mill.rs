//! A mill's stock as a height field (a Z-map): the stock box divided into square cells, each with
//! the height of the material at its centre, lowered by the cutter's swept surface as it passes.
//! Exact at the cell centres for straight 3-axis moves: for each cell the lowest point of the
//! cutting surface over the move is found where its distance to the cell's vertical is within the
//! radius (a convex function of the move's parameter, minimised to 1e-10 of the move).
//!
//! A move visits only the cells where its lowest point can lie within it. Because that height is
//! a convex function of the move's parameter, a cell where it rises from the move's start (behind
//! the cutter) was left by the move before at least as low, and a cell where it still falls at the
//! move's end (ahead of the cutter) is lowest at a later point of the path: a chain of feed moves
//! leaves those for the next move, which cuts them (where they are behind it) or leaves them on
//! again. What a chain leaves is cut by `flush` before anything else reads the stock.
//!
//! The cells are visited line by line (rows or columns of the grid). Most moves are swept across
//! their lines (`sweep_across`): the band between the two ends' sides crosses few of them, and
//! each other line's chord lies wholly on one side. A ball's move along X or Y that rises or
//! falls is swept along them (`sweep_along`): across them its sides' bounds curve over every line
//! under the ball, but along them each is one point a line, `k w` from the disc's centre.

use crate::cutter::{Cutter, Shape};

/// What one move did to the stock.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Cut {
    /// Volume removed.
    pub removed: f64,
    /// How far the cutter went below the material's top, at the cell where most.
    pub deepest: f64,
    /// How far it went below the stock's floor (into the fixture), where it did.
    pub below_floor: f64,
    /// The cutter met material: somewhere its surface went more than 10⁻⁹ below the material's
    /// top, among the cells a chain left ahead of the move too (their material is counted on the
    /// move that cuts them).
    pub touched: bool,
}

/// The stock: heights over a grid of cells.
#[derive(Clone, Debug)]
pub struct HeightField {
    /// The lower corner of the grid (the stock box's X Y minimum).
    x0: f64,
    y0: f64,
    /// The side of a cell.
    cell: f64,
    nx: usize,
    ny: usize,
    /// The stock box's bottom: nothing is below it but the fixture.
    floor: f64,
    /// Its top, where every cell starts.
    top: f64,
    /// The material's height at each cell's centre, row by row (Y), X along a row.
    z: Vec<f64>,
    /// What the moves so far left for the next (a chain of moves).
    chain: Box<Chain>,
}

/// A chain of moves: where the last left the cutter and what it left for the next.
#[derive(Clone, Debug, Default)]
struct Chain {
    /// Where the last move left the cutter, when every cell under it is at most as high as its
    /// surface there but those it left for the next move.
    trail: Option<Trail>,
    /// The cells the last move left, on lines of `left_lines`.
    left: LeftLines,
    left_lines: Lines,
    /// What the move under way leaves.
    leaving: LeftLines,
}

/// What a move left for the next on the lines it swept (`from..end`): on the lines below its band
/// (`band[0]..band[1]`, those solved one by one) the same on each (its end disc's chord, or
/// nothing, or a span along it for a move along its lines); above it the same; the band's lines
/// one by one.
#[derive(Clone, Debug, Default)]
struct LeftLines {
    from: usize,
    end: usize,
    band: [usize; 2],
    below: Left,
    above: Left,
    rows: Vec<Left>,
}

impl LeftLines {
    /// What it left on line `j`.
    #[inline]
    fn get(&self, j: usize) -> Left {
        if j < self.from || j >= self.end {
            Left::Nothing
        } else if j < self.band[0] {
            self.below
        } else if j < self.band[1] {
            self.rows[j - self.band[0]]
        } else {
            self.above
        }
    }

    /// Whether it left anything on lines `lines`.
    fn any(&self, lines: std::ops::Range<usize>) -> bool {
        let (lo, hi) = (lines.start.max(self.from), lines.end.min(self.end));
        lo < hi
            && ((!matches!(self.below, Left::Nothing) && lo < self.band[0])
                || (!matches!(self.above, Left::Nothing) && hi > self.band[1])
                || (lo.max(self.band[0])..hi.min(self.band[1]))
                    .any(|j| !matches!(self.rows[j - self.band[0]], Left::Nothing)))
    }

    /// Nothing left.
    fn clear(&mut self) {
        *self = LeftLines {
            rows: std::mem::take(&mut self.rows),
            ..LeftLines::default()
        };
        self.rows.clear();
    }
}

/// Where the last move left the cutter.
#[derive(Clone, Copy, Debug)]
struct Trail {
    at: [f64; 3],
    cutter: Cutter,
    /// The move's direction, when it left the cells ahead of it for the next move.
    left: Option<[f64; 3]>,
}

impl HeightField {
    /// The stock box `[min, max]` (X Y Z) in cells of side `cell`, at most `max_cells` of them.
    pub fn new(stock: [[f64; 3]; 2], cell: f64, max_cells: u64) -> Result<HeightField, String> {
        let [lo, hi] = stock;
        if !(cell > 0.0 && cell.is_finite()) {
            return Err(format!(
                "the stock's cell must be a positive length, not {cell}"
            ));
        }
        // NaN bounds are refused with the rest: only a real span passes.
        if (0..3).any(|i| hi[i].partial_cmp(&lo[i]) != Some(std::cmp::Ordering::Greater)) {
            return Err("the stock box is empty: each maximum must be above its minimum".into());
        }
        let count = |len: f64| (len / cell).ceil();
        let (fx, fy) = (count(hi[0] - lo[0]), count(hi[1] - lo[1]));
        let cells = fx * fy;
        if cells > max_cells as f64 {
            return Err(format!(
                "the stock box {:.3} × {:.3} in cells of {cell} is {cells:.3e} cells, more than the {max_cells:.3e} the simulation may take ({} bytes each): give a larger cell",
                hi[0] - lo[0],
                hi[1] - lo[1],
                std::mem::size_of::<f64>()
            ));
        }
        let (nx, ny) = (fx as usize, fy as usize);
        Ok(HeightField {
            x0: lo[0],
            y0: lo[1],
            cell,
            nx,
            ny,
            floor: lo[2],
            top: hi[2],
            z: vec![hi[2]; nx * ny],
            chain: Box::default(),
        })
    }

    /// The stock is a cylinder standing on Z, its axis at `centre` (X Y) and of `radius`: the cells
    /// whose centres lie outside it hold no material.
    pub fn round(mut self, centre: [f64; 2], radius: f64) -> HeightField {
        let r = radius;
        for j in 0..self.ny {
            for i in 0..self.nx {
                let c = self.centre(i, j);
                if (c[0] - centre[0]).hypot(c[1] - centre[1]) > r {
                    self.z[j * self.nx + i] = self.floor;
                }
            }
        }
        self
    }

    /// The cells `i0..i1` × `j0..j1` as a field of their own, with no move before it.
    pub fn part(&self, [i0, i1]: [usize; 2], [j0, j1]: [usize; 2]) -> HeightField {
        let mut z = Vec::with_capacity((i1 - i0) * (j1 - j0));
        for j in j0..j1 {
            z.extend_from_slice(&self.z[j * self.nx + i0..j * self.nx + i1]);
        }
        HeightField {
            x0: self.x0 + i0 as f64 * self.cell,
            y0: self.y0 + j0 as f64 * self.cell,
            nx: i1 - i0,
            ny: j1 - j0,
            z,
            chain: Box::default(),
            ..*self
        }
    }

    /// Lets go of the cells (its parts hold them), or takes room for them again.
    pub(crate) fn hold_cells(&mut self, hold: bool) {
        self.z = if hold {
            vec![self.floor; self.nx * self.ny]
        } else {
            Vec::new()
        };
    }

    /// Puts `part`'s cells back where they came from (cell `i0`, `j0`).
    pub fn put(&mut self, part: &HeightField, i0: usize, j0: usize) {
        for j in 0..part.ny {
            let row = (j0 + j) * self.nx + i0;
            self.z[row..row + part.nx].copy_from_slice(&part.z[j * part.nx..(j + 1) * part.nx]);
        }
    }

    /// Whether a move of a cutter of `radius` from `from` to `to` passes over any cell.
    pub fn reaches(&self, from: [f64; 3], to: [f64; 3], radius: f64) -> bool {
        let (w, h) = (self.nx as f64 * self.cell, self.ny as f64 * self.cell);
        from[0].max(to[0]) + radius >= self.x0
            && from[0].min(to[0]) - radius <= self.x0 + w
            && from[1].max(to[1]) + radius >= self.y0
            && from[1].min(to[1]) - radius <= self.y0 + h
    }

    /// The grid's size in cells (X, Y) and the side of a cell.
    pub fn grid(&self) -> (usize, usize, f64) {
        (self.nx, self.ny, self.cell)
    }

    /// The material's height at cell (i, j).
    pub fn height(&self, i: usize, j: usize) -> f64 {
        self.z[j * self.nx + i]
    }

    /// The centre of cell (i, j).
    pub fn centre(&self, i: usize, j: usize) -> [f64; 2] {
        [
            self.x0 + (i as f64 + 0.5) * self.cell,
            self.y0 + (j as f64 + 0.5) * self.cell,
        ]
    }

    /// The stock box's bottom and top.
    pub fn bounds(&self) -> (f64, f64) {
        (self.floor, self.top)
    }

    /// The volume of material left.
    pub fn volume(&self) -> f64 {
        let area = self.cell * self.cell;
        self.z
            .iter()
            .map(|z| (z - self.floor).max(0.0) * area)
            .sum()
    }

    /// Moves `cutter`'s tip straight from `from` to `to` (X Y Z), removing what it passes through
    /// (with what a chain of moves before it left, when one did).
    pub fn cut(&mut self, from: [f64; 3], to: [f64; 3], cutter: &Cutter) -> Cut {
        let (before, now) = self.advance(from, to, cutter, false);
        before.and(now)
    }

    /// Moves `cutter`'s tip straight from `from` to `to`; with `chain`, the cells ahead of it (where
    /// its surface still falls at the end) are left for the next move or `flush`. Returns what the
    /// last move left and this one cut (that move's), and what this move removed.
    pub fn advance(
        &mut self,
        from: [f64; 3],
        to: [f64; 3],
        cutter: &Cutter,
        chain: bool,
    ) -> (Cut, Cut) {
        let cutter = &trimmed(cutter);
        let v = [to[0] - from[0], to[1] - from[1], to[2] - from[2]];
        let follows = self
            .chain
            .trail
            .is_some_and(|t| t.at == from && t.cutter == *cutter);
        if follows && v == [0.0; 3] {
            return (Cut::default(), Cut::default());
        }
        // A ball's move along X or Y that rises or falls is swept along its lines (each crosses
        // what it cuts once, where across them its sides' bounds curve over many); any other
        // across its main direction (its band crosses few of them; where a move is level, or
        // the cutter a flat end or a bull-nose, the bounds are straight across, and the lines
        // beyond them are passed over whole).
        let along = cutter.shape == Shape::Ball && v[2] != 0.0 && (v[0] == 0.0) != (v[1] == 0.0);
        let lines = if along {
            if v[1] == 0.0 {
                Lines::Rows
            } else {
                Lines::Columns
            }
        } else if v[0].abs() > v[1].abs() {
            Lines::Columns
        } else if v[1].abs() > v[0].abs() {
            Lines::Rows
        } else {
            self.chain.left_lines
        };
        // A move that leaves nothing (a rapid) first has the last move's left cells cut: what it
        // meets is then what the moves before it left.
        let mut before = if follows && chain && lines == self.chain.left_lines {
            Sweep::default()
        } else {
            Sweep { cut: self.flush() }
        };
        // What the last move left, and its direction.
        let last = if follows {
            self.chain.trail.and_then(|t| t.left)
        } else {
            None
        };
        // Nothing is left where the cutter goes below the floor: the cells there hold the floor,
        // not the cutter's surface, so what is behind the next move is not known to be cut.
        let leave = chain && v != [0.0; 3] && from[2].min(to[2]) >= self.floor;
        let mut now = Sweep::default();
        self.sweep_lines(
            lines,
            [from, to, v],
            cutter,
            [follows, leave],
            last,
            &mut before,
            &mut now,
        );
        self.chain.trail = (to[2] >= self.floor).then_some(Trail {
            at: to,
            cutter: *cutter,
            left: leave.then_some(v),
        });
        (before.cut, now.cut)
    }

    /// The move's sweep line by line, in the frame of `lines` (for columns, X and Y swapped):
    /// what it cuts into `now`, what the last move left and it cuts into `before`, what it
    /// leaves into `self.chain.leaving`, then `self.chain.left`.
    #[allow(clippy::too_many_arguments)]
    fn sweep_lines(
        &mut self,
        lines: Lines,
        [from_xy, to_xy, v_xy]: [[f64; 3]; 3],
        cutter: &Cutter,
        [follows, leave]: [bool; 2],
        last: Option<[f64; 3]>,
        before: &mut Sweep,
        now: &mut Sweep,
    ) {
        let (from, to, v) = (lines.frame(from_xy), lines.frame(to_xy), lines.frame(v_xy));
        let last = last.map(|u| lines.frame(u));
        let r = cutter.radius;
        let ys = self.lines_over(lines, from[1], to[1], r);
        let path = Path::new(from_xy, to_xy, cutter);
        // The cutter where the last move ended: what that move left is its to cut.
        let ended = Path::new(from_xy, from_xy, cutter);
        let mut leaving = std::mem::take(&mut self.chain.leaving);
        leaving.clear();
        leaving.from = ys.start;
        leaving.end = ys.end;
        let sweep = Sweeping {
            lines,
            ys: ys.clone(),
            moves: [from, to, v],
            cutter,
            sides: [follows, leave],
            paths: [&ended, &path],
        };
        if v[1] == 0.0 && v[0] != 0.0 {
            self.sweep_along(&sweep, last.is_some(), &mut leaving, [before, now]);
        } else {
            self.sweep_across(&sweep, last, &mut leaving, before, now);
        }
        // Whether the move met material where it cut nothing of its own: the cells it left ahead
        // with material above its end's surface (nearest the tip first: in material the first
        // look finds it).
        if leave && !now.cut.touched && !ys.is_empty() {
            let end = Path::new(to_xy, to_xy, cutter);
            let tip = (((to[1] - self.line_at(lines, 0)) / self.cell)
                .round()
                .max(0.0) as usize)
                .clamp(ys.start, ys.end.saturating_sub(1));
            let n = ys.len();
            let order = (0..2 * n).map(|k| {
                // tip, tip + 1, tip − 1, tip + 2, …
                let d = k.div_ceil(2);
                let t = tip - ys.start;
                if k % 2 == 1 { t + d } else { t.wrapping_sub(d) }
            });
            now.cut.touched = order.filter(|&m| m < n).take(n).any(|m| {
                let y = self.line_at(lines, ys.start + m);
                let spans = leaving.get(ys.start + m).spans(chord(y, to, r), to[0]);
                self.meets(lines, ys.start + m, &spans, &end, to[0])
            });
        }
        self.chain.leaving = std::mem::replace(&mut self.chain.left, leaving);
        self.chain.left_lines = lines;
    }

    /// A move across its lines: the rows where a side's bound crosses the cutter's disc (the
    /// band) solved one by one, and those below and above it as zones.
    fn sweep_across(
        &mut self,
        sweep: &Sweeping,
        last: Option<[f64; 3]>,
        leaving: &mut LeftLines,
        before: &mut Sweep,
        now: &mut Sweep,
    ) {
        let Sweeping {
            lines,
            ref ys,
            moves: [from, to, v],
            cutter,
            sides: [follows, leave],
            paths: [ended, path],
        } = *sweep;
        let r = cutter.radius;
        let capsule = Capsule::new([from[0], from[1]], [to[0], to[1]], r);
        let behind_rule = if follows {
            SideRule::new(cutter, v, Side::Behind)
        } else {
            SideRule::Nothing
        };
        let ahead_rule = if leave {
            SideRule::new(cutter, v, Side::Ahead)
        } else {
            SideRule::Nothing
        };
        // The rows where a side's bound crosses the cutter's disc, or the capsule's straight
        // sides run: there the sides are solved row by row. Elsewhere each disc's chord lies
        // wholly on one side, which its middle shows.
        let mut band = capsule.sides;
        if follows {
            band = hull(band, bound_rows(cutter, from, v, Side::Behind));
        }
        if leave {
            band = hull(band, bound_rows(cutter, to, v, Side::Ahead));
        }
        if let Some(u) = last {
            band = hull(band, bound_rows(cutter, from, u, Side::Ahead));
        }
        let band = band.map(|[lo, hi]| [lo - ROWS_MARGIN, hi + ROWS_MARGIN]);
        // Outside the band each disc's chord is wholly on one side, the same for every row on
        // the same side of the band: one look at a row of each (its middle) tells.
        let zone = |y: f64| {
            let look = |p: [f64; 3], u: [f64; 3], side: Side| {
                chord(y.clamp(p[1] - r, p[1] + r), p, r)
                    .is_some_and(|(dy, w)| leaves_at(cutter, dy, w, u, side))
            };
            Zone {
                behind: follows && look(from, v, Side::Behind),
                ahead: leave && look(to, v, Side::Ahead),
            }
        };
        let (below, above) = match band {
            Some([lo, hi]) => (zone(lo - ROWS_MARGIN), zone(hi + ROWS_MARGIN)),
            None => (zone(from[1]), zone(from[1])),
        };
        // A move along Y: its discs' chords nest (the nearer centre's is the wider).
        let along_y = from[0] == to[0];
        // Whether a zone's rows have nothing to cut (unless the last move left something there):
        // both chords left; or one, and the other nests in it (the zone on that one's side).
        let idle = |z: Zone, near_from: bool| match (z.behind, z.ahead) {
            (true, true) => true,
            (true, false) => along_y && near_from,
            (false, true) => along_y && !near_from,
            (false, false) => false,
        };
        let (idle_below, idle_above) =
            (idle(below, from[1] <= to[1]), idle(above, from[1] >= to[1]));
        // The band's lines, solved one by one; below and above them the zones' (those a zone has
        // nothing to cut on are passed over whole).
        let [b0, b1] = match band {
            Some([lo, hi]) => [
                self.first_line_past(lines, lo, false, ys.clone()),
                self.first_line_past(lines, hi, true, ys.clone()),
            ],
            None => [ys.start; 2],
        };
        leaving.band = [b0, b1];
        let chord_if = |left: bool| if left { Left::Chord } else { Left::Nothing };
        leaving.below = chord_if(below.ahead);
        leaving.above = chord_if(above.ahead);
        let left_of = |chain: &Chain, j: usize| match last {
            Some(_) => chain.left.get(j),
            None => Left::Nothing,
        };
        // A zone whose lines have nothing to cut, where the last move left nothing either, is
        // passed over whole.
        let passed = |zone: std::ops::Range<usize>, z: Zone, idle: bool| {
            idle && (!z.behind || last.is_none() || !self.chain.left.any(zone))
        };
        let below_lines = if passed(ys.start..b0, below, idle_below) {
            b0..b0
        } else {
            ys.start..b0
        };
        let above_lines = if passed(b1..ys.end, above, idle_above) {
            b1..b1
        } else {
            b1..ys.end
        };
        for j in below_lines.chain(b0..b1).chain(above_lines) {
            let y = self.line_at(lines, j);
            let left = left_of(&self.chain, j);
            if (b0..b1).contains(&j) {
                let (c0, c1) = (chord(y, from, r), chord(y, to, r));
                let Some((lo, hi)) = capsule.row_with(y, c0, c1) else {
                    leaving.rows.push(Left::Nothing);
                    continue;
                };
                // Behind: lowest at the start, where the last move left the surface at most as
                // high.
                let behind = behind_rule.spans(c0, from[0]);
                let ahead = ahead_rule.spans(c1, to[0]);
                leaving.rows.push(Left::of(&ahead));
                // What the last move left and this one does not leave again is first cut as low
                // as where that one ended: that is the last move's.
                let mine = Spans::gaps(lo, hi, &behind, &ahead);
                if matches!(left, Left::Nothing) {
                    self.lower_line(lines, j, &mine, path, now);
                } else {
                    let theirs = left.spans(c0, from[0]).less(&ahead);
                    let both = [&theirs, &mine];
                    self.lower_line_after(lines, j, both, [ended, path], before, now);
                }
                continue;
            }
            let (z, idle) = if j < b0 {
                (below, idle_below)
            } else {
                (above, idle_above)
            };
            if idle && (matches!(left, Left::Nothing) || !z.behind) {
                continue;
            }
            let (near0, near1) = ((y - from[1]).abs(), (y - to[1]).abs());
            let (in0, in1) = (near0 <= r, near1 <= r);
            let nothing = match (z.behind, z.ahead) {
                (true, true) => true,
                (true, false) => !in1 || (along_y && near1 >= near0),
                (false, true) => !in0 || (along_y && near0 >= near1),
                (false, false) => false,
            };
            let theirs = z.behind && in0 && !matches!(left, Left::Nothing);
            if nothing && !theirs {
                continue;
            }
            let (c0, c1) = (chord(y, from, r), chord(y, to, r));
            let (s0, s1) = (chord_span(c0, from[0]), chord_span(c1, to[0]));
            let theirs = if matches!(left, Left::Nothing) {
                Spans::EMPTY
            } else {
                let a = if z.ahead { s1 } else { Spans::EMPTY };
                left.spans(c0, from[0]).less(&a)
            };
            if nothing {
                self.lower_line(lines, j, &theirs, ended, before);
                continue;
            }
            let mut whole = s0;
            if let Some(&[lo, hi]) = s1.iter().next() {
                whole = whole.join(lo, hi);
            }
            let (b, a) = (
                if z.behind { s0 } else { Spans::EMPTY },
                if z.ahead { s1 } else { Spans::EMPTY },
            );
            let mut mine = Spans::EMPTY;
            for &[lo, hi] in whole.iter() {
                for &[g0, g1] in Spans::gaps(lo, hi, &b, &a).iter() {
                    mine.push(g0, g1);
                }
            }
            if theirs.n == 0 {
                self.lower_line(lines, j, &mine, path, now);
            } else {
                let both = [&theirs, &mine];
                self.lower_line_after(lines, j, both, [ended, path], before, now);
            }
        }
    }

    /// A ball's move along its lines (in their frame it has no Y): on each line within the radius,
    /// where the disc's chord is `w` half-wide, what it leaves behind (lowest at its start) and
    /// ahead (lowest at its end or later) is one span from the rim to a bound `k w` along the move
    /// from the disc's centre (`along_bound`), and what it cuts the one span between: the cells it
    /// cuts are found from a few products a line. (Only a ball's moves are swept along; a path of
    /// another shape would be taken through `Path::lowest`.)
    fn sweep_along(
        &mut self,
        sweep: &Sweeping,
        after: bool,
        leaving: &mut LeftLines,
        sweeps: [&mut Sweep; 2],
    ) {
        match sweep.paths {
            [Path::Ball(e), Path::Ball(b)] => self.along_on_lines(
                sweep,
                after,
                leaving,
                sweeps,
                (|c, h| e.below(c, h), |c, h| b.below(c, h)),
            ),
            [e, p] => self.along_on_lines(
                sweep,
                after,
                leaving,
                sweeps,
                (|c, h| e.lowest(c, h), |c, h| p.lowest(c, h)),
            ),
        }
    }

    /// `along_lines` on the move's lines, rows or columns.
    #[inline(always)]
    fn along_on_lines<T, M>(
        &mut self,
        sweep: &Sweeping,
        after: bool,
        leaving: &mut LeftLines,
        sweeps: [&mut Sweep; 2],
        paths: (T, M),
    ) where
        T: Fn([f64; 2], f64) -> Option<f64>,
        M: Fn([f64; 2], f64) -> Option<f64>,
    {
        match sweep.lines {
            Lines::Rows => self.along_lines::<false, _, _>(sweep, after, leaving, sweeps, paths),
            Lines::Columns => self.along_lines::<true, _, _>(sweep, after, leaving, sweeps, paths),
        }
    }

    /// `sweep_along` over lines that are columns with `COLUMNS` (else rows), `ended` and
    /// `path_lowest` the lowest points of the cutter where the last move ended and of this move.
    #[inline(always)]
    fn along_lines<const COLUMNS: bool, T, M>(
        &mut self,
        sweep: &Sweeping,
        after: bool,
        leaving: &mut LeftLines,
        [before, now]: [&mut Sweep; 2],
        (ended, path_lowest): (T, M),
    ) where
        T: Fn([f64; 2], f64) -> Option<f64>,
        M: Fn([f64; 2], f64) -> Option<f64>,
    {
        let Sweeping {
            ref ys,
            moves: [from, to, v],
            cutter,
            sides: [follows, leave],
            ..
        } = *sweep;
        let r = cutter.radius;
        let k = along_bound(v);
        let (behind, ahead) = (follows.then_some(k), leave.then_some(k));
        let sigma = v[0].signum();
        // Least and greatest X of two points along the move.
        let sorted = |[a, b]: [f64; 2]| if sigma > 0.0 { [a, b] } else { [b, a] };
        // What the last move left: where it went along the lines the same way, ahead of a bound
        // (found on each line as this move's are); else as it left it.
        let left = &self.chain.left;
        let last_ahead = match (left.band, left.above) {
            (b, Left::Ahead { sigma: s, k }) if after && b[1] == left.from && s == sigma => Some(k),
            _ => None,
        };
        let (floor, cell, per_cell) = (self.floor, self.cell, 1.0 / self.cell);
        let (mut bt, mut mt) = (Tally::of(before), Tally::of(now));
        // Every line the same: what is ahead of the bound.
        leaving.band = [ys.start; 2];
        leaving.above = match ahead {
            Some(k) => Left::Ahead { sigma, k },
            None => Left::Nothing,
        };
        // A chain along the lines the same way, leaving behind and ahead: four bounds a line.
        if let (Some(kb), Some(ka), Some(kp)) = (behind, ahead, last_ahead) {
            let chain = (ys.clone(), [from, to], r, [kb, ka, kp]);
            let tallies = [&mut bt, &mut mt];
            if sigma > 0.0 {
                self.along_chain::<COLUMNS, true, _, _>(chain, (&ended, &path_lowest), tallies);
            } else {
                self.along_chain::<COLUMNS, false, _, _>(chain, (&ended, &path_lowest), tallies);
            }
            bt.into(before, cell);
            mt.into(now, cell);
            return;
        }
        for j in ys.clone() {
            let (line, origin, n, stride, base) = self.line_cells(COLUMNS, j);
            let Some((dy, w)) = chord(line, from, r) else {
                continue;
            };
            // Ahead from `k w` past the end's centre, behind to `k w` past the start's (each taken
            // in); the move's own the rest of the capsule (a sliver at the rim behind left out: it
            // is behind).
            let start = match behind {
                Some(k) => behind_to(from[0], sigma, k, w),
                None => from[0] - sigma * w,
            };
            // Where what it leaves ahead begins (as `ahead_along` has it), else the rim.
            let end = match ahead {
                Some(k) => ahead_from(to[0], sigma, k, w),
                None => to[0] + sigma * w,
            };
            let [m0, m1] = sorted([start, end]);
            // What the last move left, less what this one leaves again (at most two pieces).
            let mut theirs = [[f64::INFINITY, f64::NEG_INFINITY]; 2];
            match last_ahead {
                // Ahead of the last move's bound to the rim (`ahead_along`), and not past this
                // one's: both ahead along the same way.
                Some(k) => {
                    let (bound, rim) = (
                        ahead_from(from[0], sigma, k, w),
                        rim_ahead(from[0], sigma, w),
                    );
                    let rim = if (end - rim) * sigma < 0.0 { end } else { rim };
                    theirs[0] = sorted([bound, rim]);
                }
                None if after => {
                    let a = ahead.and_then(|k| ahead_along(to[0], sigma, k, w));
                    let a = a.map_or(Spans::EMPTY, |[lo, hi]| Spans::one(lo, hi));
                    let spans = left.get(j).spans(Some((dy, w)), from[0]).less(&a);
                    for (t, s) in spans.iter().take(2).enumerate() {
                        theirs[t] = *s;
                    }
                    if spans.n > 2 {
                        theirs[1][1] = spans.s[spans.n - 1][1];
                    }
                }
                None => {}
            }
            let least = |a: f64, b: f64| if b < a { b } else { a };
            let most = |a: f64, b: f64| if b > a { b } else { a };
            let lo = least(least(m0, theirs[0][0]), theirs[1][0]);
            let hi = most(most(m1, theirs[0][1]), theirs[1][1]);
            let Some((first, last)) = along(lo, hi, origin, per_cell, n) else {
                continue;
            };
            let z = &mut self.z;
            let mut at = origin + (first as i64 as f64 + 0.5) * cell;
            for i in first..last + 1 {
                let k = base + i * stride;
                let c = if COLUMNS { [line, at] } else { [at, line] };
                let theirs = || {
                    (theirs[0][0] <= at && at <= theirs[0][1])
                        || (theirs[1][0] <= at && at <= theirs[1][1])
                };
                let mine = m0 <= at && at <= m1;
                let paths = (&ended, &path_lowest);
                if let Some(h) = cut_cell(z[k], c, mine, theirs, paths, [&mut bt, &mut mt], floor) {
                    z[k] = h;
                }
                at += cell;
            }
        }
        bt.into(before, cell);
        mt.into(now, cell);
    }

    /// `along_lines` where the last move went along the same lines the same way (`FORWARD`: to
    /// greater X), and this one leaves what is behind and ahead: on each line its own cells lie
    /// from its start's bound (`kb`) to its end's (`ka`), and the last move's from that one's end
    /// bound (`kp`) to the rim or this move's end bound, whichever comes first.
    #[inline(always)]
    fn along_chain<const COLUMNS: bool, const FORWARD: bool, T, M>(
        &mut self,
        (ys, [from, to], r, [kb, ka, kp]): (std::ops::Range<usize>, [[f64; 3]; 2], f64, [f64; 3]),
        (ended, path_lowest): (&T, &M),
        [bt, mt]: [&mut Tally; 2],
    ) where
        T: Fn([f64; 2], f64) -> Option<f64>,
        M: Fn([f64; 2], f64) -> Option<f64>,
    {
        let sigma = if FORWARD { 1.0 } else { -1.0 };
        let (floor, cell, per_cell) = (self.floor, self.cell, 1.0 / self.cell);
        // Whether `a` comes no later than `b` along the move.
        let by = |a: f64, b: f64| if FORWARD { a <= b } else { b <= a };
        let (_, origin, n, stride, _) = self.line_cells(COLUMNS, 0);
        // Line j's centre across them is this + (j + 0.5) cells, as `line_cells` has it.
        let across0 = if COLUMNS { self.x0 } else { self.y0 };
        let nf = n as f64;
        let (rr, y) = (r * r, from[1]);
        // The four bounds on a line whose chord is `w` half-wide, as `along_lines` and
        // `ahead_along` find them.
        let bounds = |w: f64| {
            let start = behind_to(from[0], sigma, kb, w);
            let end = ahead_from(to[0], sigma, ka, w);
            let bound = ahead_from(from[0], sigma, kp, w);
            let rim = rim_ahead(from[0], sigma, w);
            (start, end, bound, if by(end, rim) { end } else { rim })
        };
        // A block of lines at a time: first each line's chord and its cells' first and last
        // (as `along` finds them: whole numbers in f64), then the cells of those that have some.
        for j0 in ys.clone().step_by(BLOCK) {
            let m = BLOCK.min(ys.end - j0);
            let (mut w, mut first, mut last) = ([0.0; BLOCK], [0; BLOCK], [0; BLOCK]);
            let j0f = j0 as i64 as f64;
            for l in 0..m {
                let line = across0 + ((j0f + COUNT[l]) + 0.5) * cell;
                let dy = line - y;
                // NaN beyond the radius: no cells.
                w[l] = (rr - dy * dy).sqrt();
                let (start, end, bound, _) = bounds(w[l]);
                let early = if by(start, bound) { start } else { bound };
                let (lo, hi) = if FORWARD { (early, end) } else { (end, early) };
                let held = |x: f64| {
                    let x = if x < nf { x } else { nf };
                    if x > -1.0 { x } else { -1.0 }
                };
                let (a, b) = (
                    held((lo - origin) * per_cell - 0.5),
                    held((hi - origin) * per_cell - 0.5),
                );
                let (ta, tb) = ((a + WHOLE) - WHOLE, (b + WHOLE) - WHOLE);
                let (fa, lb) = (
                    if ta < a { ta + 1.0 } else { ta },
                    if tb > b { tb - 1.0 } else { tb },
                );
                let (fa, lb) = (
                    if fa > 0.0 { fa } else { 0.0 },
                    if lb < nf - 1.0 { lb } else { nf - 1.0 },
                );
                first[l] = (fa + WHOLE).to_bits() as i64 - WHOLE.to_bits() as i64;
                last[l] = (lb + WHOLE).to_bits() as i64 - WHOLE.to_bits() as i64;
            }
            // The lines that have cells, listed without a branch (about half of them, in no
            // order a predictor learns). None beyond the radius: there `w` is NaN, and so the
            // first n.
            let (mut with, mut count) = ([0u8; BLOCK], 0);
            for l in 0..m {
                with[count] = l as u8;
                count += usize::from(first[l] <= last[l]);
            }
            for &l in &with[..count] {
                let l = usize::from(l);
                let j = j0 + l;
                let (line, _, _, _, base) = self.line_cells(COLUMNS, j);
                let (start, _, bound, rim) = bounds(w[l]);
                let (first, last) = (first[l] as usize, last[l] as usize);
                let z = &mut self.z;
                let mut at = origin + (first as i64 as f64 + 0.5) * cell;
                for i in first..last + 1 {
                    let k = base + i * stride;
                    let c = if COLUMNS { [line, at] } else { [at, line] };
                    let theirs = || by(bound, at) && by(at, rim);
                    let (paths, tallies) = ((ended, path_lowest), [&mut *bt, &mut *mt]);
                    if let Some(h) = cut_cell(z[k], c, by(start, at), theirs, paths, tallies, floor)
                    {
                        z[k] = h;
                    }
                    at += cell;
                }
            }
        }
    }

    /// Whether `path`'s surface goes below the material at a cell of line `j` whose centre lies in
    /// `spans`, looking outward from the one nearest `tip` along the line.
    fn meets(&self, lines: Lines, j: usize, spans: &Spans, path: &Path, tip: f64) -> bool {
        let (line, origin, n, stride, base) = self.line_cells(lines == Lines::Columns, j);
        spans.iter().any(|&[lo, hi]| {
            along(lo, hi, origin, 1.0 / self.cell, n).is_some_and(|(first, last)| {
                // Outward from the cell under the tip: in material the first looks find it.
                let mid = (((tip - origin) / self.cell).max(0.0) as usize).clamp(first, last);
                let meets = |i: usize| {
                    let at = origin + (i as i64 as f64 + 0.5) * self.cell;
                    let c = match lines {
                        Lines::Columns => [line, at],
                        Lines::Rows => [at, line],
                    };
                    path.goes_below(c, self.z[base + i * stride] - TOUCH)
                };
                (0..=(mid - first).max(last - mid)).any(|d| {
                    (mid + d <= last && meets(mid + d))
                        || (d > 0 && d <= mid - first && meets(mid - d))
                })
            })
        })
    }

    /// Cuts what the last move left for the next one (the cells ahead of it, lowest where it
    /// ended): what that move removed there.
    pub fn flush(&mut self) -> Cut {
        let mut s = Sweep::default();
        let Some(Trail {
            at,
            cutter,
            left: Some(_),
        }) = self.chain.trail
        else {
            return s.cut;
        };
        let path = Path::new(at, at, &cutter);
        let lines = self.chain.left_lines;
        let framed = lines.frame(at);
        for j in self.chain.left.from..self.chain.left.end {
            let y = self.line_at(lines, j);
            let left = self
                .chain
                .left
                .get(j)
                .spans(chord(y, framed, cutter.radius), framed[0]);
            self.lower_line(lines, j, &left, &path, &mut s);
        }
        self.chain.left.clear();
        if let Some(t) = &mut self.chain.trail {
            t.left = None;
        }
        s.cut
    }

    /// The rows within `radius` of the Y span of a move.
    fn rows(&self, ya: f64, yb: f64, radius: f64) -> std::ops::Range<usize> {
        self.lines_over(Lines::Rows, ya, yb, radius)
    }

    /// The lines within `radius` of a move's span across them (`a`, `b` in the lines' frame).
    fn lines_over(&self, lines: Lines, a: f64, b: f64, radius: f64) -> std::ops::Range<usize> {
        let (origin, n) = match lines {
            Lines::Rows => (self.y0, self.ny),
            Lines::Columns => (self.x0, self.nx),
        };
        let lo = ((a.min(b) - radius - origin) / self.cell - 0.5)
            .ceil()
            .max(0.0);
        let hi = ((a.max(b) + radius - origin) / self.cell - 0.5).floor();
        if hi < 0.0 || lo >= n as f64 {
            return 0..0;
        }
        // Clamped before the cast: a coordinate far outside (a macro's) is no index.
        lo as usize..(hi.min(n as f64 - 1.0) as usize + 1)
    }

    /// The first of `range`'s lines whose centre lies beyond `y` (at or beyond unless `strictly`).
    fn first_line_past(
        &self,
        lines: Lines,
        y: f64,
        strictly: bool,
        range: std::ops::Range<usize>,
    ) -> usize {
        let past = |j: usize| {
            let at = self.line_at(lines, j);
            if strictly { at > y } else { at >= y }
        };
        let origin = self.line_at(lines, 0) - 0.5 * self.cell;
        // The nearest line by division, then by the same test as the lines are taken.
        let guess = ((y - origin) / self.cell - 0.5).max(range.start as f64 - 1.0);
        let mut j = (guess.min(range.end as f64) as usize).clamp(range.start, range.end);
        while j > range.start && past(j - 1) {
            j -= 1;
        }
        while j < range.end && !past(j) {
            j += 1;
        }
        j
    }

    /// The centre's coordinate of line `j` across the lines.
    fn line_at(&self, lines: Lines, j: usize) -> f64 {
        self.line_cells(lines == Lines::Columns, j).0
    }

    /// Line `j` (a column with `columns`, else a row) in the grid: its centre across the lines,
    /// where its cells start along it, how many it has, the step between them in the heights and
    /// its first's index.
    #[inline(always)]
    fn line_cells(&self, columns: bool, j: usize) -> (f64, f64, usize, usize, usize) {
        let across = |origin: f64| origin + (j as i64 as f64 + 0.5) * self.cell;
        if columns {
            (across(self.x0), self.y0, self.ny, self.nx, j)
        } else {
            (across(self.y0), self.x0, self.nx, 1, j * self.nx)
        }
    }

    /// Lowers the cells of line `j` (a row or a column) whose centres lie in `spans` to the lowest
    /// point of `path` over them, counting it in `s`.
    fn lower_line(&mut self, lines: Lines, j: usize, spans: &Spans, path: &Path, s: &mut Sweep) {
        if spans.n == 0 {
            return;
        }
        let no = None::<(&Spans, &mut Sweep, fn([f64; 2], f64) -> Option<f64>)>;
        match (path, lines) {
            (Path::Ball(b), Lines::Rows) => {
                self.lower_cells::<false, _, _>(j, no, (spans, s, |c, h| b.below(c, h)))
            }
            (Path::Ball(b), Lines::Columns) => {
                self.lower_cells::<true, _, _>(j, no, (spans, s, |c, h| b.below(c, h)))
            }
            (Path::Any { from, to, cutter }, Lines::Rows) => self.lower_cells::<false, _, _>(
                j,
                no,
                (spans, s, |c, h| lowest(c, *from, *to, cutter, h)),
            ),
            (Path::Any { from, to, cutter }, Lines::Columns) => self.lower_cells::<true, _, _>(
                j,
                no,
                (spans, s, |c, h| lowest(c, *from, *to, cutter, h)),
            ),
        }
    }

    /// Lowers the cells of line `j` in `theirs` (what the last move left) to the lowest point of
    /// `ended` (the cutter where that move ended) over them, counted in `before`, then those in
    /// `mine` to the lowest of `path` (which starts there), counted in `now`: one look at a cell
    /// in both. Called where the last move left something (`lower_line` elsewhere: taking that
    /// case here too was measured at 3.6 % more instructions a move, the optimiser inlining less).
    #[allow(clippy::too_many_arguments)]
    fn lower_line_after(
        &mut self,
        lines: Lines,
        j: usize,
        [theirs, mine]: [&Spans; 2],
        [ended, path]: [&Path; 2],
        before: &mut Sweep,
        now: &mut Sweep,
    ) {
        match (ended, path, lines) {
            (Path::Ball(e), Path::Ball(b), Lines::Rows) => self.lower_cells::<false, _, _>(
                j,
                Some((theirs, before, |c, h| e.below(c, h))),
                (mine, now, |c, h| b.below(c, h)),
            ),
            (Path::Ball(e), Path::Ball(b), Lines::Columns) => self.lower_cells::<true, _, _>(
                j,
                Some((theirs, before, |c, h| e.below(c, h))),
                (mine, now, |c, h| b.below(c, h)),
            ),
            _ => {
                self.lower_line(lines, j, theirs, ended, before);
                self.lower_line(lines, j, mine, path, now);
            }
        }
    }

    /// Lowers the cells of line `j` (a row, or with `COLUMNS` a column) whose centres lie in
    /// `theirs`' spans (along it) to its `lowest` of each, counting it in its sweep, then those in
    /// `mine`'s likewise; a cell in both has `mine`'s lowest found first, and `theirs`' only when
    /// that is below the material (theirs is the start of mine: never lower).
    #[inline(always)]
    fn lower_cells<const COLUMNS: bool, T, M>(
        &mut self,
        j: usize,
        theirs: Option<(&Spans, &mut Sweep, T)>,
        (mine, now, path_lowest): (&Spans, &mut Sweep, M),
    ) where
        T: Fn([f64; 2], f64) -> Option<f64>,
        M: Fn([f64; 2], f64) -> Option<f64>,
    {
        let (line, origin, n, stride, base) = self.line_cells(COLUMNS, j);
        let (floor, cell, per_cell) = (self.floor, self.cell, 1.0 / self.cell);
        let z = &mut self.z;
        // Each span's cells, as index ranges.
        let cells = |spans: &Spans| spans.cells(origin, per_cell, n);
        let centre = |at: f64| if COLUMNS { [line, at] } else { [at, line] };
        let (mine, m) = cells(mine);
        let mut mt = Tally::of(now);
        match theirs {
            None => {
                for &(first, last) in &mine[..m] {
                    let mut at = origin + (first as i64 as f64 + 0.5) * cell;
                    for i in first..last + 1 {
                        let k = base + i * stride;
                        let height = z[k];
                        if let Some(low) = path_lowest(centre(at), height) {
                            z[k] = mt.lower(height, low, floor);
                        }
                        at += cell;
                    }
                }
            }
            Some((theirs, before, ended_lowest)) => {
                let (theirs, t) = cells(theirs);
                let mut bt = Tally::of(before);
                // The last move's alone: its ranges less this move's.
                let (alone, a) = less_cells(&theirs[..t], &mine[..m]);
                for &(first, end) in &alone[..a] {
                    for i in first..end {
                        let k = base + i * stride;
                        let at = origin + (i as i64 as f64 + 0.5) * cell;
                        let paths = (&ended_lowest, &path_lowest);
                        let tallies = [&mut bt, &mut mt];
                        if let Some(h) =
                            cut_cell(z[k], centre(at), false, || true, paths, tallies, floor)
                        {
                            z[k] = h;
                        }
                    }
                }
                // This move's, where the last left it too.
                for &(first, last) in &mine[..m] {
                    let mut at = origin + (first as i64 as f64 + 0.5) * cell;
                    let mut cur = 0;
                    for i in first..last + 1 {
                        let k = base + i * stride;
                        let theirs = || within(&theirs[..t], &mut cur, i);
                        let paths = (&ended_lowest, &path_lowest);
                        let tallies = [&mut bt, &mut mt];
                        if let Some(h) =
                            cut_cell(z[k], centre(at), true, theirs, paths, tallies, floor)
                        {
                            z[k] = h;
                        }
                        at += cell;
                    }
                }
                bt.into(before, cell);
            }
        }
        mt.into(now, cell);
    }

    /// The move cut the plain way, every cell under it: what `advance` must equal.
    #[cfg(test)]
    pub(crate) fn cut_everywhere(&mut self, from: [f64; 3], to: [f64; 3], cutter: &Cutter) -> Cut {
        let cutter = &trimmed(cutter);
        let mut s = Sweep::default();
        let mut t = Tally::of(&s);
        let mut lowered = Vec::new();
        self.each_cell(from, to, cutter.radius, |field, k, c| {
            if let Some(low) = lowest(c, from, to, cutter, field.z[k]) {
                lowered.push((k, t.lower(field.z[k], low, field.floor)));
            }
        });
        for (k, z) in lowered {
            self.z[k] = z;
        }
        t.into(&mut s, self.cell);
        s.cut
    }

    /// What the move would remove, the stock left as it is (the shank's rub).
    pub fn touch(&self, from: [f64; 3], to: [f64; 3], cutter: &Cutter) -> Cut {
        let cutter = &trimmed(cutter);
        let mut s = Sweep::default();
        let mut t = Tally::of(&s);
        self.each_cell(from, to, cutter.radius, |field, k, c| {
            if let Some(low) = lowest(c, from, to, cutter, field.z[k]) {
                t.lower(field.z[k], low, field.floor);
            }
        });
        t.into(&mut s, self.cell);
        s.cut
    }

    /// Calls `f` with each cell within `radius` of the move's bounding box in X Y: its index and
    /// centre.
    fn each_cell(
        &self,
        from: [f64; 3],
        to: [f64; 3],
        radius: f64,
        mut f: impl FnMut(&HeightField, usize, [f64; 2]),
    ) {
        let ys = self.rows(from[1], to[1], radius);
        let capsule = Capsule::new([from[0], from[1]], [to[0], to[1]], radius);
        for j in ys {
            // Only the cells of the row the cutter's path can reach: where the row's line crosses
            // the capsule the cutter's disc sweeps.
            let y = self.y0 + (j as f64 + 0.5) * self.cell;
            let Some((lo, hi)) = capsule.row(y) else {
                continue;
            };
            let Some((first, last)) = along(lo, hi, self.x0, 1.0 / self.cell, self.nx) else {
                continue;
            };
            for i in first..last + 1 {
                let c = self.centre(i, j);
                f(self, j * self.nx + i, c);
            }
        }
    }
}

/// A move as its sweep over lines sees it.
struct Sweeping<'a> {
    lines: Lines,
    /// The lines within the radius of it.
    ys: std::ops::Range<usize>,
    /// Its start, end and direction, in the lines' frame.
    moves: [[f64; 3]; 3],
    cutter: &'a Cutter,
    /// Whether it follows the last move (what is behind it is cut), and leaves what is ahead.
    sides: [bool; 2],
    /// The cutter where the last move ended, and this move.
    paths: [&'a Path; 2],
}

/// Where a ball moving along its lines (in their frame, `v` has no Y) leaves what is behind and
/// what is ahead, on a line where its disc's chord is `w` half-wide: `k w` along the move from
/// the disc's centre (behind the start's, ahead the end's), where the ball's normal is square to
/// the move (`SideRule` on such a line, solved once: the normal's part along the move and its Z
/// scale alike with w, so k is the move's slope's sine).
fn along_bound(v: [f64; 3]) -> f64 {
    v[2] / norm(v[0], v[2])
}

/// The capsule a disc of radius `r` sweeps from `a` to `b` (X Y): the convex hull of its two end
/// discs.
struct Capsule {
    a: [f64; 2],
    b: [f64; 2],
    r: f64,
    /// The offset from the path to its straight sides (r across the move), when it moves.
    across: Option<[f64; 2]>,
    /// The rows its straight sides run over.
    sides: Option<[f64; 2]>,
}

impl Capsule {
    fn new(a: [f64; 2], b: [f64; 2], r: f64) -> Capsule {
        let d = [b[0] - a[0], b[1] - a[1]];
        let len = norm(d[0], d[1]);
        let across = (len > 0.0).then(|| [-d[1] / len * r, d[0] / len * r]);
        let sides = across.map(|n| {
            let h = n[1].abs();
            [a[1].min(b[1]) - h, a[1].max(b[1]) + h]
        });
        Capsule {
            a,
            b,
            r,
            across,
            sides,
        }
    }

    /// Where the line at height `y` crosses it: the least and greatest X of its boundary's
    /// crossings (the discs' and the two sides').
    fn row(&self, y: f64) -> Option<(f64, f64)> {
        let chord = |p: [f64; 2]| {
            let dy = y - p[1];
            (dy.abs() <= self.r).then(|| (dy, (self.r * self.r - dy * dy).sqrt()))
        };
        self.row_with(y, chord(self.a), chord(self.b))
    }

    /// `row`, given the row's chords of the two discs.
    fn row_with(&self, y: f64, a: Option<(f64, f64)>, b: Option<(f64, f64)>) -> Option<(f64, f64)> {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for (p, c) in [(self.a, a), (self.b, b)] {
            if let Some((_, w)) = c {
                lo = lo.min(p[0] - w);
                hi = hi.max(p[0] + w);
            }
        }
        if let Some(n) = self.across {
            for s in [-1.0, 1.0] {
                let (p, q) = (
                    [self.a[0] + s * n[0], self.a[1] + s * n[1]],
                    [self.b[0] + s * n[0], self.b[1] + s * n[1]],
                );
                if (p[1] - y) * (q[1] - y) <= 0.0 && p[1] != q[1] {
                    let x = p[0] + (y - p[1]) / (q[1] - p[1]) * (q[0] - p[0]);
                    lo = lo.min(x);
                    hi = hi.max(x);
                }
            }
        }
        (lo <= hi).then_some((lo, hi))
    }
}

/// How far beyond the rows a side's bound or the capsule's sides reach the rows solved one by one
/// are taken (rounding).
const ROWS_MARGIN: f64 = 1e-6;

/// √(a² + b²): a length in the stock's units (no overflow to guard against, as `hypot` does at
/// some cost).
#[inline]
fn norm(a: f64, b: f64) -> f64 {
    (a * a + b * b).sqrt()
}

/// Both row ranges' hull.
fn hull(a: Option<[f64; 2]>, b: Option<[f64; 2]>) -> Option<[f64; 2]> {
    match (a, b) {
        (Some(a), Some(b)) => Some([a[0].min(b[0]), a[1].max(b[1])]),
        (a, None) => a,
        (None, b) => b,
    }
}

/// Row `y`'s place in the disc of radius `r` round `p`: its distance from the centre's row and the
/// chord's half-width, when it crosses it.
fn chord(y: f64, p: [f64; 3], r: f64) -> Option<(f64, f64)> {
    let dy = y - p[1];
    let w2 = r * r - dy * dy;
    (w2 >= 0.0).then(|| (dy, w2.sqrt()))
}

/// The rows over which the bound of what a move of direction `v` leaves on `side` of the cutter's
/// disc at `p` runs inside the disc (None: what it leaves there is all the disc or nothing).
fn bound_rows(cutter: &Cutter, p: [f64; 3], v: [f64; 3], side: Side) -> Option<[f64; 2]> {
    let r = cutter.radius;
    let len = norm(v[0], v[1]);
    if len == 0.0 {
        return None;
    }
    // The horizontal across the move (its Y part); the bound's ends lie on it, r from the axis.
    let across_y = v[0] / len;
    match cutter.shape {
        Shape::Flat => None,
        // The half-disc's diameter across the move.
        Shape::Bull(_) => side
            .tip_leaves(v)
            .then(|| [p[1] - r * across_y.abs(), p[1] + r * across_y.abs()]),
        // Where the ball's normal is square to the move: the half-ellipse p + r (cos φ q̂ +
        // sin θ sin φ û), φ in [0, π], q̂ across the move, û along it, θ its slope (the same rows
        // for the move back). Its Y is p.y + r (A cos φ + B sin φ).
        Shape::Ball => {
            let full = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            let a = across_y;
            let b = v[2] / full * (v[1] / len);
            let reach = norm(a, b);
            let lo = if b < 0.0 { -reach } else { -a.abs() };
            let hi = if b > 0.0 { reach } else { a.abs() };
            Some([p[1] + r * lo, p[1] + r * hi])
        }
    }
}

/// `side` at the middle of a disc's chord, `dy` from its centre's row and `w` half-wide: all the
/// chord's cells are on one side when the row is outside `bound_rows`.
fn leaves_at(cutter: &Cutter, dy: f64, w: f64, v: [f64; 3], side: Side) -> bool {
    let (tip, u) = (side.tip_leaves(v), side.facing(v));
    match cutter.shape {
        Shape::Ball => dy * u[1] <= u[2] * w,
        Shape::Flat => tip,
        Shape::Bull(_) => tip && dy * u[1] <= 0.0,
    }
}

/// What a move left on one row for the next.
#[derive(Clone, Copy, Debug, Default)]
enum Left {
    #[default]
    Nothing,
    /// All the row's chord of the cutter's disc where the move ended.
    Chord,
    /// One or two spans (a side of the ball's disc is at most two).
    Spans(u8, [[f64; 2]; 2]),
    /// A move along the rows (direction `sigma`, ±1) left what is ahead of `k w` from the disc's
    /// centre along it, where the row's chord is `w` half-wide (`along_bound`).
    Ahead { sigma: f64, k: f64 },
}

impl Left {
    fn of(s: &Spans) -> Left {
        match s.n {
            0 => Left::Nothing,
            n => Left::Spans(n.min(2) as u8, [s.s[0], s.s[1]]),
        }
    }

    /// Its spans on a row whose chord of the disc where the move ended is `chord`, round `px`.
    #[inline(always)]
    fn spans(&self, chord: Option<(f64, f64)>, px: f64) -> Spans {
        match self {
            Left::Nothing => Spans::EMPTY,
            Left::Chord => chord_span(chord, px),
            Left::Spans(n, s) => {
                let mut out = Spans::EMPTY;
                for span in &s[..*n as usize] {
                    out.push(span[0], span[1]);
                }
                out
            }
            Left::Ahead { sigma, k } => {
                match chord.and_then(|(_, w)| ahead_along(px, *sigma, *k, w)) {
                    Some([lo, hi]) => Spans::one(lo, hi),
                    None => Spans::EMPTY,
                }
            }
        }
    }
}

/// Where a ball moving along its lines in direction `sigma` (±1) begins to leave what is ahead of
/// its end at `px`, on a line where its disc's chord is `w` half-wide: `k w` past the centre along
/// the move (`along_bound`), taken `INSIDE` further on. The one expression for it: the move that
/// leaves the cells and the move that cuts them must find it bit for bit alike, or a cell between
/// would be neither's.
#[inline(always)]
fn ahead_from(px: f64, sigma: f64, k: f64, w: f64) -> f64 {
    px + sigma * (k * w + INSIDE)
}

/// Where what such a move leaves behind its start at `px` ends: `k w` past the centre, taken
/// `INSIDE` back.
#[inline(always)]
fn behind_to(px: f64, sigma: f64, k: f64, w: f64) -> f64 {
    px + sigma * (k * w - INSIDE)
}

/// The rim of such a move's disc at `px` ahead of it, taken `INSIDE` in.
#[inline(always)]
fn rim_ahead(px: f64, sigma: f64, w: f64) -> f64 {
    px + sigma * (w - INSIDE)
}

/// What a move along the rows in direction `sigma` (±1) leaves ahead of its end at X `px` on a row
/// where its disc's chord is `w` half-wide: from `k w` along the move from the centre to the rim,
/// taken `INSIDE` in, as X from least to greatest.
#[inline(always)]
fn ahead_along(px: f64, sigma: f64, k: f64, w: f64) -> Option<[f64; 2]> {
    let (a, b) = (ahead_from(px, sigma, k, w), rim_ahead(px, sigma, w));
    let (lo, hi) = if sigma > 0.0 { (a, b) } else { (b, a) };
    (lo <= hi).then_some([lo, hi])
}

/// Whether the chords of the start's and the end's discs are left, on rows outside the band.
#[derive(Clone, Copy)]
struct Zone {
    behind: bool,
    ahead: bool,
}

/// Which cells under a cutter at one end of a move the move leaves as they are there.
#[derive(Clone, Copy)]
enum Side {
    /// At its start: where the surface rises as the move begins, so is lowest there.
    Behind,
    /// At its end: where the surface still falls as the move ends, so is lowest there or later.
    Ahead,
}

impl Side {
    /// Whether a flat end's disc, or a bull-nose's half of it, is left on this side by a move of
    /// direction `v`: behind as the tip rises (or stays level), ahead as it falls.
    fn tip_leaves(self, v: [f64; 3]) -> bool {
        match self {
            Side::Behind => v[2] >= 0.0,
            Side::Ahead => v[2] < 0.0,
        }
    }

    /// The move as this side sees it: the move itself behind, the move back ahead.
    fn facing(self, v: [f64; 3]) -> [f64; 3] {
        match self {
            Side::Behind => v,
            Side::Ahead => [-v[0], -v[1], -v[2]],
        }
    }
}

/// How far inside their bounds the cells a move leaves are taken (the roots' rounding): a cell this
/// near a bound is cut rather than left, which is always right.
const INSIDE: f64 = 1e-6;

/// What a move of direction `v` leaves on `side` of a cutter's disc there: a part of where the
/// cutter's height over the cell, a convex function of the move's parameter, has its least at
/// that end. Set up once a move, for row after row.
#[derive(Clone, Copy, Debug)]
enum SideRule {
    Nothing,
    /// All the disc.
    Disc,
    /// Where the normal n of the ball's surface over the cell has n · v ≤ 0: with u = x − p.x and
    /// L(u) = (c − p)·v in X Y, L(u) ≤ v.z √(w² − u²) (a bull-nose's half-disc has v.z = 0).
    Normal {
        v: [f64; 3],
        /// 1 / v.x; v.x² + v.z² and its inverse; v.z².
        inv_vx: f64,
        a: f64,
        inv_a: f64,
        vz2: f64,
    },
}

impl SideRule {
    fn new(cutter: &Cutter, v: [f64; 3], side: Side) -> SideRule {
        let u = side.facing(v);
        match cutter.shape {
            // The ball: exactly, where its surface's normal at the cell faces away from the move
            // (behind) or into it (ahead).
            Shape::Ball => SideRule::normal(u),
            // A flat end is as high as its tip everywhere: all of it, as the tip rises or falls.
            Shape::Flat if side.tip_leaves(v) => SideRule::Disc,
            // A bull-nose's surface never falls away from its axis: the half behind the move's
            // horizontal direction as it rises, the half ahead as it falls.
            Shape::Bull(_) if side.tip_leaves(v) => SideRule::normal([u[0], u[1], 0.0]),
            _ => SideRule::Nothing,
        }
    }

    fn normal(v: [f64; 3]) -> SideRule {
        let a = v[0] * v[0] + v[2] * v[2];
        SideRule::Normal {
            v,
            inv_vx: 1.0 / v[0],
            a,
            inv_a: 1.0 / a,
            vz2: v[2] * v[2],
        }
    }

    /// The spans of a row whose chord of the disc round X `px` is `chord` (its distance from the
    /// centre's row, its half-width), taken `INSIDE` in from their ends.
    #[inline(always)]
    fn spans(&self, chord: Option<(f64, f64)>, px: f64) -> Spans {
        let Some((dy, w)) = chord else {
            return Spans::EMPTY;
        };
        // At most two spans, in order, about the disc's centre; each placed at `px` as it is
        // found (one taken in to nothing is none).
        let mut out = Spans::EMPTY;
        let mut put = |lo: f64, hi: f64| {
            let (lo, hi) = (lo + px + INSIDE, hi + px - INSIDE);
            if lo <= hi {
                out.s[out.n] = [lo, hi];
                out.n += 1;
            }
        };
        match *self {
            SideRule::Nothing => {}
            SideRule::Disc => put(-w, w),
            SideRule::Normal {
                v,
                inv_vx,
                a,
                inv_a,
                vz2,
            } => {
                let (vx, vz, b0) = (v[0], v[2], dy * v[1]);
                // L(u) = vx u + b0 ≤ 0: the half [h0, h1], none where h0 > h1.
                let (h0, h1) = if vx > 0.0 {
                    (-w, (-b0 * inv_vx).min(w))
                } else if vx < 0.0 {
                    ((-b0 * inv_vx).max(-w), w)
                } else if b0 <= 0.0 {
                    (-w, w)
                } else {
                    (1.0, 0.0)
                };
                // Q(u) = L² − vz² (w² − u²) = a u² + 2 b u + c, zero where L = ±vz √(w² − u²).
                let roots = (vz != 0.0)
                    .then(|| {
                        let b = vx * b0;
                        let c = b0 * b0 - vz2 * w * w;
                        let disc = b * b - a * c;
                        (disc >= 0.0).then(|| {
                            let s = disc.sqrt();
                            ((-b - s) * inv_a, (-b + s) * inv_a)
                        })
                    })
                    .flatten();
                match roots {
                    // L ≤ vz √(…) with vz > 0: where L ≤ 0, and where L > 0 but
                    // L² ≤ vz² (w² − u²): the half and [q1, q2] within the chord.
                    Some((q1, q2)) if vz > 0.0 => {
                        let (lo, hi) = (q1.max(-w), q2.min(w));
                        if lo > hi {
                            if h0 <= h1 {
                                put(h0, h1);
                            }
                        } else if h0 > h1 {
                            put(lo, hi);
                        } else if h1 < lo {
                            put(h0, h1);
                            put(lo, hi);
                        } else if hi < h0 {
                            put(lo, hi);
                            put(h0, h1);
                        } else {
                            put(h0.min(lo), h1.max(hi));
                        }
                    }
                    // With vz < 0: where L ≤ 0 and L² ≥ vz² (w² − u²): the half less
                    // [q1, q2] (its ends kept).
                    Some((q1, q2)) => {
                        if h0 <= h1 {
                            if q2 < h0 || q1 > h1 {
                                put(h0, h1);
                            } else {
                                if h0 < q1 {
                                    put(h0, q1);
                                }
                                if q2 < h1 {
                                    put(q2, h1);
                                }
                            }
                        }
                    }
                    None => {
                        if h0 <= h1 {
                            put(h0, h1);
                        }
                    }
                }
            }
        }
        out
    }
}

/// The chord a row's `chord` (its distance from the centre's row and half-width) cuts from the disc
/// round X `px`.
#[inline]
fn chord_span(chord: Option<(f64, f64)>, px: f64) -> Spans {
    match chord {
        Some((_, w)) => Spans::one(px - w, px + w),
        None => Spans::EMPTY,
    }
}

/// Spans a row's set of cells has room for (a side is at most two, and two less two at most four;
/// a move's own, the row less two sides, could be five, and the fourth then widens over the fifth:
/// the cells between are behind the move, where its lowest is its start's, or ahead, where it is
/// its end's, so cutting them too changes nothing the move would not; a side is never widened).
const SPANS: usize = 4;

/// A few disjoint closed spans of X along a row, in order.
#[derive(Clone, Copy, Debug)]
struct Spans {
    n: usize,
    s: [[f64; 2]; SPANS],
}

impl Spans {
    const EMPTY: Spans = Spans {
        n: 0,
        s: [[0.0; 2]; SPANS],
    };

    fn one(lo: f64, hi: f64) -> Spans {
        let mut s = Spans::EMPTY;
        s.push(lo, hi);
        s
    }

    fn iter(&self) -> impl Iterator<Item = &[f64; 2]> {
        self.s[..self.n].iter()
    }

    /// Adds `[lo, hi]` after the last span (nothing when empty). Were there ever more than room
    /// for, the last would widen: right for the spans a move cuts (more cells cut), not for those
    /// it leaves, which are at most two.
    fn push(&mut self, lo: f64, hi: f64) {
        if lo > hi {
            return;
        }
        if self.n == SPANS {
            self.s[SPANS - 1][1] = self.s[SPANS - 1][1].max(hi);
            return;
        }
        self.s[self.n] = [lo, hi];
        self.n += 1;
    }

    /// These spans less `other`'s (their ends kept; both in order).
    #[inline(always)]
    fn less(&self, other: &Spans) -> Spans {
        if other.n == 0 {
            return *self;
        }
        let mut out = Spans::EMPTY;
        for &[lo, hi] in self.iter() {
            // What is left of [lo, hi] runs from `from`: each of `other`'s spans over it, in
            // order, ends a piece and moves `from` past itself.
            let mut from = lo;
            let mut whole = true;
            for &[a0, a1] in other.iter() {
                if a1 < from || a0 > hi {
                    continue;
                }
                whole = false;
                if from < a0 {
                    out.push(from, a0);
                }
                from = a1;
                if from >= hi {
                    break;
                }
            }
            if whole {
                out.push(lo, hi);
            } else if from < hi {
                out.push(from, hi);
            }
        }
        out
    }

    /// What of `[lo, hi]` neither `a`'s spans nor `b`'s cover (their ends kept).
    fn gaps(lo: f64, hi: f64, a: &Spans, b: &Spans) -> Spans {
        let mut out = Spans::EMPTY;
        let (mut i, mut k) = (0, 0);
        let mut from = lo;
        loop {
            // The next span of either, by its start.
            let next = match (a.s[..a.n].get(i), b.s[..b.n].get(k)) {
                (Some(x), Some(y)) if x[0] <= y[0] => {
                    i += 1;
                    *x
                }
                (Some(_), Some(y)) | (None, Some(y)) => {
                    k += 1;
                    *y
                }
                (Some(x), None) => {
                    i += 1;
                    *x
                }
                (None, None) => break,
            };
            if next[0] > from {
                out.push(from, next[0].min(hi));
            }
            from = from.max(next[1]);
            if from >= hi {
                return out;
            }
        }
        out.push(from, hi);
        out
    }

    /// This span (at most one) and `[lo, hi]`.
    fn join(&self, lo: f64, hi: f64) -> Spans {
        if lo > hi {
            return *self;
        }
        match self.iter().next() {
            None => Spans::one(lo, hi),
            Some(&[a0, a1]) if a1 < lo => {
                let mut s = Spans::one(a0, a1);
                s.push(lo, hi);
                s
            }
            Some(&[a0, a1]) if hi < a0 => {
                let mut s = Spans::one(lo, hi);
                s.push(a0, a1);
                s
            }
            Some(&[a0, a1]) => Spans::one(a0.min(lo), a1.max(hi)),
        }
    }

    /// Each span's cells along a line (`along`), as index ranges, and how many.
    #[inline(always)]
    fn cells(&self, origin: f64, per_cell: f64, n: usize) -> ([(usize, usize); SPANS], usize) {
        let mut out = [(0, 0); SPANS];
        let mut m = 0;
        for &[lo, hi] in self.iter() {
            if let Some(r) = along(lo, hi, origin, per_cell, n) {
                out[m] = r;
                m += 1;
            }
        }
        (out, m)
    }
}

/// How far a cutter must go below the material's top to meet it (the rounding of one way of
/// computing its surface against another's is some 10⁻¹⁵).
const TOUCH: f64 = 1e-9;

/// How much of its radius a cutter is taken to reach, as a part of it.
const REACH: f64 = 1.0 - 1e-10;

/// `cutter` reaching a ten-billionth of its radius less far. At its very edge a cutter's surface
/// is its side, where the height jumps from its rim to none: a cell whose centre lies exactly one
/// radius from the path (as on a raster whose step and cells are both round numbers) would be
/// reached or not by the rounding of each way of computing it. Short of the radius by far more than
/// the rounding (3·10⁻¹⁰ mm on a 6 mm cutter), no cell of such a grid lies on the edge.
fn trimmed(cutter: &Cutter) -> Cutter {
    Cutter {
        radius: cutter.radius * REACH,
        ..*cutter
    }
}

/// What a sweep found, cell by cell.
#[derive(Default)]
struct Sweep {
    cut: Cut,
}

/// A sweep's figures over its cells (one line's, or a whole move's), the volume as depths until
/// the end: the one rule for what lowering a cell counts.
struct Tally {
    depth: f64,
    deepest: f64,
    below: f64,
    touched: bool,
}

impl Tally {
    fn of(s: &Sweep) -> Tally {
        Tally {
            depth: 0.0,
            deepest: s.cut.deepest,
            below: s.cut.below_floor,
            touched: false,
        }
    }

    /// A cell of `height` the cutter takes down to `low` (not below `floor`): its new height.
    #[inline(always)]
    fn lower(&mut self, height: f64, low: f64, floor: f64) -> f64 {
        self.touched |= height - low > TOUCH;
        self.depth += (height - low.max(floor)).max(0.0);
        self.deepest = self.deepest.max(height - low);
        if low < floor {
            self.below = self.below.max(floor - low);
        }
        low.max(floor)
    }

    /// Into the sweep's figures, for cells of side `cell`.
    fn into(self, s: &mut Sweep, cell: f64) {
        s.cut.removed += self.depth * cell * cell;
        s.cut.deepest = self.deepest;
        s.cut.below_floor = self.below;
        s.cut.touched |= self.touched;
    }
}

impl Cut {
    /// What two parts of one move did.
    pub fn and(self, other: Cut) -> Cut {
        Cut {
            removed: self.removed + other.removed,
            deepest: self.deepest.max(other.deepest),
            below_floor: self.below_floor.max(other.below_floor),
            touched: self.touched || other.touched,
        }
    }
}

/// One cell of `height` over `c` that this move takes (`mine`), or that only the last move left
/// (`theirs`): this move's lowest, and where the cell is the last move's too, first as low as that
/// move's end reached (this move's start: never lower), each counted on its own move's tally (the
/// last move's, this one's); the cell's new height, where it is lowered.
#[inline(always)]
fn cut_cell<T, M>(
    height: f64,
    c: [f64; 2],
    mine: bool,
    theirs: impl FnOnce() -> bool,
    (ended, path_lowest): (&T, &M),
    [bt, mt]: [&mut Tally; 2],
    floor: f64,
) -> Option<f64>
where
    T: Fn([f64; 2], f64) -> Option<f64>,
    M: Fn([f64; 2], f64) -> Option<f64>,
{
    if mine {
        let low = path_lowest(c, height)?;
        let mut height = height;
        if theirs()
            && let Some(was) = ended(c, height)
        {
            height = bt.lower(height, was, floor);
        }
        if low < height {
            height = mt.lower(height, low, floor);
        }
        Some(height)
    } else if theirs() {
        ended(c, height).map(|low| bt.lower(height, low, floor))
    } else {
        None
    }
}

/// The cells of `ranges` (`first..=last` each, in order) not in `less`'s, as `first..end` ranges
/// (no more than both together hold; were there more, the last would widen over cells of `less`).
#[inline(always)]
fn less_cells(
    ranges: &[(usize, usize)],
    less: &[(usize, usize)],
) -> ([(usize, usize); 2 * SPANS], usize) {
    let mut out = [(0, 0); 2 * SPANS];
    let mut a = 0;
    let mut put = |first: usize, end: usize| {
        if a < out.len() {
            out[a] = (first, end);
            a += 1;
        } else {
            out[a - 1].1 = out[a - 1].1.max(end);
        }
    };
    for &(first, last) in ranges {
        let mut from = first;
        for &(m0, m1) in less {
            if m1 >= from && m0 <= last {
                if from < m0 {
                    put(from, m0);
                }
                from = m1 + 1;
            }
        }
        if from <= last {
            put(from, last + 1);
        }
    }
    (out, a)
}

/// Whether cell `i` is in `ranges` (cells taken in order, `cur` the range reached so far).
#[inline(always)]
fn within(ranges: &[(usize, usize)], cur: &mut usize, i: usize) -> bool {
    while *cur < ranges.len() && ranges[*cur].1 < i {
        *cur += 1;
    }
    *cur < ranges.len() && ranges[*cur].0 <= i
}

/// The cells `first..=last` along a line whose centres lie in `[lo, hi]` (`per_cell` cells to the
/// unit from `origin`, `n` of them).
#[inline(always)]
fn along(lo: f64, hi: f64, origin: f64, per_cell: f64, n: usize) -> Option<(usize, usize)> {
    // In cells from the first centre, held within [−1, n] (beyond them the answer is the same,
    // and NaN is no cell): there `nearest` is exact.
    let held = |x: f64| x.max(-1.0).min(n as f64);
    let (a, b) = (
        held((lo - origin) * per_cell - 0.5),
        held((hi - origin) * per_cell - 0.5),
    );
    let (ta, tb) = (nearest(a), nearest(b));
    // ⌈a⌉, no less than the first cell; ⌊b⌋, no more than the last.
    let first = (ta + i64::from((ta as f64) < a)).max(0);
    let last = (tb - i64::from((tb as f64) > b)).min(n as i64 - 1);
    (first <= last).then_some((first as usize, last as usize))
}

/// Lines a move along them takes at a time (its lines' bounds first, then their cells).
const BLOCK: usize = 64;

/// 0, 1, 2, … as f64: the lines of a block.
const COUNT: [f64; BLOCK] = {
    let mut c = [0.0; BLOCK];
    let mut i = 0;
    while i < BLOCK {
        c[i] = i as f64;
        i += 1;
    }
    c
};

/// 1.5 · 2⁵²: a number below 2⁵¹ in size added to it is rounded to a whole one (to the nearest,
/// ties to even), which the sum's bits then hold in their low part.
const WHOLE: f64 = 6_755_399_441_055_744.0;

/// The whole number nearest `x` (|x| < 2⁵¹), without a saturating cast's checks.
#[inline(always)]
fn nearest(x: f64) -> i64 {
    (x + WHOLE).to_bits() as i64 - WHOLE.to_bits() as i64
}

/// Which lines of cells a move is swept along: rows (along X) or columns (along Y).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
enum Lines {
    #[default]
    Rows,
    Columns,
}

impl Lines {
    /// A point or direction in the lines' frame: the lines run along its first coordinate.
    fn frame(self, p: [f64; 3]) -> [f64; 3] {
        match self {
            Lines::Rows => p,
            Lines::Columns => [p[1], p[0], p[2]],
        }
    }
}

/// A straight move of a cutter, ready to give its lowest point over cell after cell.
enum Path {
    Ball(BallPath),
    Any {
        from: [f64; 3],
        to: [f64; 3],
        cutter: Cutter,
    },
}

impl Path {
    /// Whether the surface goes below `height` over `c` (`lowest` is some): for a ball standing
    /// still, without its square root.
    #[inline]
    fn goes_below(&self, c: [f64; 2], height: f64) -> bool {
        match self {
            Path::Ball(b) if b.axis.is_none() => {
                let e = if b.to[2] < b.from[2] { b.to } else { b.from };
                let (d2, r2) = ((c[0] - e[0]).powi(2) + (c[1] - e[1]).powi(2), b.r * b.r);
                // e.z + r − √(r² − d²) < height, with k = height − e.z: √(r² − d²) > r − k.
                let k = height - e[2];
                d2 <= r2 && k > 0.0 && (k > b.r || r2 - d2 > (b.r - k) * (b.r - k))
            }
            _ => self.lowest(c, height).is_some(),
        }
    }

    /// The lowest point over `c`, when below `height`.
    fn lowest(&self, c: [f64; 2], height: f64) -> Option<f64> {
        match self {
            Path::Ball(b) => b.below(c, height),
            Path::Any { from, to, cutter } => lowest(c, *from, *to, cutter, height),
        }
    }

    fn new(from: [f64; 3], to: [f64; 3], cutter: &Cutter) -> Path {
        match cutter.shape {
            Shape::Ball => Path::Ball(BallPath::new(from, to, cutter.radius)),
            _ => Path::Any {
                from,
                to,
                cutter: *cutter,
            },
        }
    }
}

/// A ball's move: the capsule its centre sweeps, whose lowest point over a cell is on the cylinder
/// between the end spheres where that point's foot on the axis lies within the move, else on the
/// end sphere on the foot's side (its height along the move is convex: the least of the whole
/// cylinder's lies before the start only when the cell is under the start's sphere, and so at the
/// end).
struct BallPath {
    from: [f64; 3],
    to: [f64; 3],
    r: f64,
    /// The tip's lowest: the surface is nowhere below it.
    tip_low: f64,
    /// The axis's unit direction, 1 / its length, 1 / (2 (1 − u.z²)); None when it goes nowhere
    /// or straight up or down (the lowest is then the lower end's sphere).
    axis: Option<([f64; 3], f64, f64)>,
    /// 2 (1 − u.z²).
    two_a: f64,
}

impl BallPath {
    fn new(from: [f64; 3], to: [f64; 3], r: f64) -> BallPath {
        let v = [to[0] - from[0], to[1] - from[1], to[2] - from[2]];
        let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        let axis = (len > 0.0).then(|| v.map(|c| c / len)).and_then(|u| {
            let a = 1.0 - u[2] * u[2];
            (a > 1e-12).then(|| (u, 1.0 / len, 0.5 / a))
        });
        BallPath {
            from,
            to,
            r,
            tip_low: from[2].min(to[2]),
            axis,
            two_a: axis.map_or(0.0, |(_, _, inv_2a)| 1.0 / inv_2a),
        }
    }

    /// The sphere's lowest point over `c` with its tip at `e` (infinite beyond its radius).
    #[inline]
    fn sphere(&self, c: [f64; 2], e: [f64; 3]) -> f64 {
        let d2 = (c[0] - e[0]) * (c[0] - e[0]) + (c[1] - e[1]) * (c[1] - e[1]);
        let r2 = self.r * self.r;
        if d2 <= r2 {
            e[2] + self.r - (r2 - d2).sqrt()
        } else {
            f64::INFINITY
        }
    }

    /// The capsule's lowest point over `c`, when below `height`.
    #[inline(always)]
    fn below(&self, c: [f64; 2], height: f64) -> Option<f64> {
        if self.tip_low >= height {
            return None;
        }
        let low = self.lowest(c);
        (low < height).then_some(low)
    }

    /// The capsule's lowest point over `c` (infinite where it does not pass over it).
    #[inline(always)]
    fn lowest(&self, c: [f64; 2]) -> f64 {
        let Some((u, inv_len, inv_2a)) = self.axis else {
            let lower = if self.to[2] < self.from[2] {
                self.to
            } else {
                self.from
            };
            return self.sphere(c, lower);
        };
        // The point (c, from.z + r + q): its distance² to the axis line is a q² + b q + cc, with
        // a = 1 − u.z²; the lower root is the cylinder's lowest point over c.
        let (px, py) = (c[0] - self.from[0], c[1] - self.from[1]);
        let a0 = px * u[0] + py * u[1];
        let b = -2.0 * a0 * u[2];
        let cc = px * px + py * py - a0 * a0 - self.r * self.r;
        let disc = b * b - 2.0 * cc * self.two_a;
        if disc < 0.0 {
            return f64::INFINITY;
        }
        let q = (-b - disc.sqrt()) * inv_2a;
        let foot = (a0 + q * u[2]) * inv_len;
        if foot < 0.0 {
            self.sphere(c, self.from)
        } else if foot > 1.0 {
            self.sphere(c, self.to)
        } else {
            self.from[2] + self.r + q
        }
    }
}

/// The lowest point of `cutter`'s surface over the vertical of `c` as its tip moves from `from` to
/// `to`, when it is below `height` (else None: the move leaves the cell as it is).
#[inline]
fn lowest(c: [f64; 2], from: [f64; 3], to: [f64; 3], cutter: &Cutter, height: f64) -> Option<f64> {
    let r = cutter.radius;
    let (dx, dy, dz) = (to[0] - from[0], to[1] - from[1], to[2] - from[2]);
    let (px, py) = (c[0] - from[0], c[1] - from[1]);
    // d(t)² = a t² − 2 b t + cc: the horizontal distance from the cell to the axis at t.
    let a = dx * dx + dy * dy;
    let b = px * dx + py * dy;
    let cc = px * px + py * py;
    let z = |t: f64| from[2] + t * dz;
    // The cutter's surface is nowhere below its tip.
    if from[2].min(to[2]) >= height {
        return None;
    }
    if a < 1e-18 {
        let d = cc.sqrt();
        let low = from[2].min(to[2]) + cutter.lift(d)?;
        return (low < height).then_some(low);
    }
    // Quick rejects over the whole move, before the interval's square root: the closest approach
    // beyond the radius, or the cutter's rise there at least the material's height above the tip's
    // lowest.
    let t0 = (b / a).clamp(0.0, 1.0);
    let dmin2 = (a * t0 * t0 - 2.0 * b * t0 + cc).max(0.0);
    if dmin2 > r * r || cutter.rises_at_least(dmin2, height - from[2].min(to[2])) {
        return None;
    }
    // Where the cell is within the radius: a t² − 2 b t + cc − r² ≤ 0.
    let disc = b * b - a * (cc - r * r);
    if disc < 0.0 {
        return None;
    }
    let root = disc.sqrt();
    let (t1, t2) = (((b - root) / a).max(0.0), ((b + root) / a).min(1.0));
    if t1 > t2 {
        return None;
    }
    let d = |t: f64| (a * t * t - 2.0 * b * t + cc).max(0.0).sqrt().min(r);
    let f = |t: f64| z(t) + cutter.lift(d(t)).unwrap_or(0.0);
    // A bound from below: the lowest tip height with the closest approach.
    let closest = (b / a).clamp(t1, t2);
    let d2 = (a * closest * closest - 2.0 * b * closest + cc).max(0.0);
    if cutter.rises_at_least(d2, height - z(t1).min(z(t2))) {
        return None;
    }
    let low = match cutter.shape {
        crate::cutter::Shape::Flat => z(t1).min(z(t2)),
        _ if dz == 0.0 => f(closest),
        crate::cutter::Shape::Ball => BallPath::new(from, to, r).lowest(c),
        // f is convex in t (a convex non-decreasing lift of a convex distance, plus a line):
        // golden-section search.
        _ => golden(f, t1, t2),
    };
    (low < height).then_some(low)
}

/// The minimum of convex `f` on `[lo, hi]`.
fn golden(f: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    const K: f64 = 0.618_033_988_749_894_8;
    let mut x1 = hi - K * (hi - lo);
    let mut x2 = lo + K * (hi - lo);
    let (mut f1, mut f2) = (f(x1), f(x2));
    while hi - lo > 1e-10 {
        if f1 <= f2 {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - K * (hi - lo);
            f1 = f(x1);
        } else {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + K * (hi - lo);
            f2 = f(x2);
        }
    }
    f1.min(f2).min(f(lo)).min(f(hi))
}
