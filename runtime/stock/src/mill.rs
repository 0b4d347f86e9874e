//! A mill's stock as a height field (a Z-map): the stock box divided into square cells, each with
//! the height of the material at its centre, lowered by the cutter's swept surface as it passes.
//! Exact at the cell centres for straight 3-axis moves: for each cell the lowest point of the
//! cutting surface over the move is found where its distance to the cell's vertical is within the
//! radius (a convex function of the move's parameter, minimised to 1e-10 of the move).

use crate::cutter::Cutter;

/// What one move did to the stock.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Cut {
    /// Volume removed.
    pub removed: f64,
    /// How far the cutter went below the material's top, at the cell where most.
    pub deepest: f64,
    /// How far it went below the stock's floor (into the fixture), where it did.
    pub below_floor: f64,
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

    /// Moves `cutter`'s tip straight from `from` to `to` (X Y Z), removing what it passes through.
    pub fn cut(&mut self, from: [f64; 3], to: [f64; 3], cutter: &Cutter) -> Cut {
        let mut s = Sweep::default();
        let mut lowered = Vec::new();
        self.each_cell(from, to, cutter.radius, |field, k, c| {
            if let Some(low) = lowest(c, from, to, cutter, field.z[k]) {
                s.add(field, k, low);
                lowered.push((k, low.max(field.floor)));
            }
        });
        for (k, z) in lowered {
            self.z[k] = z;
        }
        s.cut
    }

    /// What the move would remove, the stock left as it is (the shank's rub).
    pub fn touch(&self, from: [f64; 3], to: [f64; 3], cutter: &Cutter) -> Cut {
        let mut s = Sweep::default();
        self.each_cell(from, to, cutter.radius, |field, k, c| {
            if let Some(low) = lowest(c, from, to, cutter, field.z[k]) {
                s.add(field, k, low);
            }
        });
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
        let range = |a: f64, b: f64, origin: f64, n: usize| {
            let lo = ((a.min(b) - radius - origin) / self.cell - 0.5)
                .ceil()
                .max(0.0);
            let hi = ((a.max(b) + radius - origin) / self.cell - 0.5).floor();
            if hi < 0.0 || lo >= n as f64 {
                return 0..0;
            }
            lo as usize..(hi as usize + 1).min(n)
        };
        let ys = range(from[1], to[1], self.y0, self.ny);
        let (a, b) = ([from[0], from[1]], [to[0], to[1]]);
        for j in ys {
            // Only the cells of the row the cutter's path can reach: where the row's line crosses
            // the capsule the cutter's disc sweeps.
            let y = self.y0 + (j as f64 + 0.5) * self.cell;
            let Some((lo, hi)) = row_span(y, a, b, radius) else {
                continue;
            };
            let first = ((lo - self.x0) / self.cell - 0.5).ceil().max(0.0);
            let last = ((hi - self.x0) / self.cell - 0.5).floor();
            if last < first || first >= self.nx as f64 {
                continue;
            }
            let (first, last) = (first as usize, (last as usize).min(self.nx - 1));
            for i in first..=last {
                let c = self.centre(i, j);
                f(self, j * self.nx + i, c);
            }
        }
    }
}

/// Where the line at height `y` crosses the capsule a disc of `radius` sweeps from `a` to `b` (X Y):
/// the convex hull of the two end discs, so the least and greatest X of its boundary's crossings
/// (the discs' and the two sides').
fn row_span(y: f64, a: [f64; 2], b: [f64; 2], radius: f64) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in [a, b] {
        let dy = y - p[1];
        if dy.abs() <= radius {
            let w = (radius * radius - dy * dy).sqrt();
            lo = lo.min(p[0] - w);
            hi = hi.max(p[0] + w);
        }
    }
    let d = [b[0] - a[0], b[1] - a[1]];
    let len = d[0].hypot(d[1]);
    if len > 0.0 {
        let n = [-d[1] / len * radius, d[0] / len * radius];
        for s in [-1.0, 1.0] {
            let (p, q) = (
                [a[0] + s * n[0], a[1] + s * n[1]],
                [b[0] + s * n[0], b[1] + s * n[1]],
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

/// What a sweep found, cell by cell.
#[derive(Default)]
struct Sweep {
    cut: Cut,
}

impl Sweep {
    fn add(&mut self, field: &HeightField, k: usize, low: f64) {
        let z = field.z[k];
        let area = field.cell * field.cell;
        self.cut.removed += (z - low.max(field.floor)).max(0.0) * area;
        self.cut.deepest = self.cut.deepest.max(z - low);
        if low < field.floor {
            self.cut.below_floor = self.cut.below_floor.max(field.floor - low);
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
        crate::cutter::Shape::Ball => ball_lowest(c, from, to, r),
        // f is convex in t (a convex non-decreasing lift of a convex distance, plus a line):
        // golden-section search.
        _ => golden(f, t1, t2),
    };
    (low < height).then_some(low)
}

/// The lowest point over `c` of a ball of radius `r` whose tip moves from `from` to `to`: the lowest
/// point of the capsule its centre sweeps on the cell's vertical, from the two end spheres and the
/// cylinder between them (where the foot of the point on the axis falls within the move).
fn ball_lowest(c: [f64; 2], from: [f64; 3], to: [f64; 3], r: f64) -> f64 {
    let mut low = f64::INFINITY;
    for e in [from, to] {
        let d2 = (c[0] - e[0]).powi(2) + (c[1] - e[1]).powi(2);
        if d2 <= r * r {
            low = low.min(e[2] + r - (r * r - d2).sqrt());
        }
    }
    let axis = [to[0] - from[0], to[1] - from[1], to[2] - from[2]];
    let len = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
    if len > 0.0 {
        let u = axis.map(|v| v / len);
        // The point (c, C0z + q): its distance² to the axis line is A q² + B q + C.
        let (px, py) = (c[0] - from[0], c[1] - from[1]);
        let a0 = px * u[0] + py * u[1];
        let a = 1.0 - u[2] * u[2];
        let b = -2.0 * a0 * u[2];
        let cc = px * px + py * py - a0 * a0 - r * r;
        let disc = b * b - 4.0 * a * cc;
        if a > 1e-12 && disc >= 0.0 {
            let q = (-b - disc.sqrt()) / (2.0 * a);
            let foot = (a0 + q * u[2]) / len;
            if (0.0..=1.0).contains(&foot) {
                low = low.min(from[2] + r + q);
            }
        }
    }
    low
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
