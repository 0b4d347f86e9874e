//! A lathe's stock as its half-section: the plane through the spindle's axis, Z along it and X the
//! radius, divided into square cells, each solid or cut. The tool is its nose, a circle of the nose
//! radius, with the insert's body behind it (away from the cutting side its tip direction names,
//! Fanuc's imaginary tool nose 1–8): a cell is cut when its centre comes within the nose radius of
//! the nose centre's path, or behind it. Exact at the cell centres: for each cell the distance over
//! the move is a piecewise quadratic, minimised in closed form.

/// A turning tool as the stock sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Nose {
    /// The nose radius.
    pub radius: f64,
    /// The controlled point (the imaginary tip) less the nose centre, X and Z: the kernel's table
    /// of tip directions.
    pub tip: [f64; 2],
    /// Where the insert's body extends from the nose, X and Z: +1, −1 or 0 each (none for a tip of
    /// 0 or 9, the nose alone).
    pub body: [f64; 2],
}

impl Nose {
    /// A nose of `radius` with tip direction `tip` (0–9), its centre offset `offset` (controlled
    /// point less centre, X Z).
    pub fn new(radius: f64, tip: u8, offset: [f64; 2]) -> Nose {
        // The body lies away from the cutting side: opposite the direction from centre to tip.
        let away = |v: f64| {
            if v > 0.0 {
                -1.0
            } else if v < 0.0 {
                1.0
            } else {
                0.0
            }
        };
        let body = if matches!(tip, 1..=8) {
            [away(offset[0]), away(offset[1])]
        } else {
            [0.0, 0.0]
        };
        Nose {
            radius,
            tip: offset,
            body,
        }
    }
}

/// What one move did to the bar.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Cut {
    /// The half-section's area removed.
    pub area: f64,
    /// The volume removed (each cell's area turned about the axis).
    pub removed: f64,
}

/// The bar: solid cells over Z × X (radius).
#[derive(Clone, Debug)]
pub struct HalfSection {
    z0: f64,
    x0: f64,
    cell: f64,
    nz: usize,
    nx: usize,
    solid: Vec<bool>,
}

impl HalfSection {
    /// The bar from `z` minimum to maximum and `x` (radius) minimum (a bore, or 0) to maximum, in
    /// cells of side `cell`, at most `max_cells`.
    pub fn new(z: [f64; 2], x: [f64; 2], cell: f64, max_cells: u64) -> Result<HalfSection, String> {
        if !(cell > 0.0 && cell.is_finite()) {
            return Err(format!(
                "the stock's cell must be a positive length, not {cell}"
            ));
        }
        let above = |a: f64, b: f64| a.partial_cmp(&b) == Some(std::cmp::Ordering::Greater);
        if !(above(z[1], z[0]) && above(x[1], x[0]) && x[0] >= 0.0) {
            return Err(
                "the bar is empty: give Z and X (a radius from 0) minimum below maximum".into(),
            );
        }
        let (fz, fx) = (((z[1] - z[0]) / cell).ceil(), ((x[1] - x[0]) / cell).ceil());
        if fz * fx > max_cells as f64 {
            return Err(format!(
                "the bar {:.3} long and {:.3} deep in cells of {cell} is {:.3e} cells, more than the {max_cells:.3e} the simulation may take: give a larger cell",
                z[1] - z[0],
                x[1] - x[0],
                fz * fx
            ));
        }
        let (nz, nx) = (fz as usize, fx as usize);
        Ok(HalfSection {
            z0: z[0],
            x0: x[0],
            cell,
            nz,
            nx,
            solid: vec![true; nz * nx],
        })
    }

    /// The centre of cell (i along Z, j along X): its Z and radius.
    pub fn centre(&self, i: usize, j: usize) -> [f64; 2] {
        [
            self.z0 + (i as f64 + 0.5) * self.cell,
            self.x0 + (j as f64 + 0.5) * self.cell,
        ]
    }

    /// The grid's size (Z, X) and the side of a cell.
    pub fn grid(&self) -> (usize, usize, f64) {
        (self.nz, self.nx, self.cell)
    }

    /// Whether cell (i, j) is still solid.
    pub fn is_solid(&self, i: usize, j: usize) -> bool {
        self.solid[j * self.nz + i]
    }

    /// The bar's volume: each solid cell's area turned about the axis.
    pub fn volume(&self) -> f64 {
        self.solid
            .iter()
            .enumerate()
            .filter(|(_, s)| **s)
            .map(|(k, _)| self.turned(k))
            .sum()
    }

    /// Cell `k`'s area turned about the axis at its centre's radius.
    fn turned(&self, k: usize) -> f64 {
        let r = self.x0 + ((k / self.nz) as f64 + 0.5) * self.cell;
        self.cell * self.cell * std::f64::consts::TAU * r
    }

    /// The half-section's solid area.
    pub fn area(&self) -> f64 {
        self.solid.iter().filter(|&&s| s).count() as f64 * self.cell * self.cell
    }

    /// Moves the tool's controlled point from `from` to `to` (X radius, Z), removing what the nose
    /// and the body behind it pass through.
    pub fn cut(&mut self, from: [f64; 2], to: [f64; 2], nose: &Nose) -> Cut {
        let mut cut = Cut::default();
        let cells = self.cells_hit(from, to, nose);
        for k in cells {
            self.solid[k] = false;
            cut.area += self.cell * self.cell;
            cut.removed += self.turned(k);
        }
        cut
    }

    /// The solid cells the move passes through, the bar left as it is.
    pub fn cells_hit(&self, from: [f64; 2], to: [f64; 2], nose: &Nose) -> Vec<usize> {
        // The nose centre's path (X, Z).
        let c0 = [from[0] - nose.tip[0], from[1] - nose.tip[1]];
        let c1 = [to[0] - nose.tip[0], to[1] - nose.tip[1]];
        let r = nose.radius;
        // The cells the nose and its body can reach: the path's box grown by the radius, and up
        // to the bar's edge on the body's side.
        let span = |a: f64, b: f64, body: f64, origin: f64, n: usize| {
            let lo = if body < 0.0 {
                f64::NEG_INFINITY
            } else {
                a.min(b) - r
            };
            let hi = if body > 0.0 {
                f64::INFINITY
            } else {
                a.max(b) + r
            };
            let first = ((lo - origin) / self.cell - 0.5).ceil().max(0.0);
            let last = ((hi - origin) / self.cell - 0.5)
                .floor()
                .min(n as f64 - 1.0);
            if last < first {
                0..0
            } else {
                first as usize..last as usize + 1
            }
        };
        let xs = span(c0[0], c1[0], nose.body[0], self.x0, self.nx);
        let zs = span(c0[1], c1[1], nose.body[1], self.z0, self.nz);
        let mut hit = Vec::new();
        for j in xs {
            for i in zs.clone() {
                let k = j * self.nz + i;
                if !self.solid[k] {
                    continue;
                }
                let [z, x] = self.centre(i, j);
                if reach([x, z], c0, c1, nose.body) <= r * r {
                    hit.push(k);
                }
            }
        }
        hit
    }
}

/// The least squared distance over the move from point `p` (X, Z) to the nose centre's path
/// `c0`→`c1` with the body's cone `body` behind it: along each axis the body takes away the part of
/// the offset that points its way.
fn reach(p: [f64; 2], c0: [f64; 2], c1: [f64; 2], body: [f64; 2]) -> f64 {
    // u(t) = p − c(t) = u0 − t·d, per axis.
    let u0 = [p[0] - c0[0], p[1] - c0[1]];
    let d = [c1[0] - c0[0], c1[1] - c0[1]];
    // The residual of an axis at t: its offset, less what the body covers (none, or all of a part
    // of one sign).
    let residual = |axis: usize, t: f64| {
        let u = u0[axis] - t * d[axis];
        match body[axis] {
            b if b > 0.0 => u.min(0.0),
            b if b < 0.0 => u.max(0.0),
            _ => u,
        }
    };
    // The residuals change form where an offset crosses zero: at most two breakpoints.
    let mut cuts = vec![0.0, 1.0];
    for axis in 0..2 {
        if d[axis] != 0.0 {
            let t = u0[axis] / d[axis];
            if t > 0.0 && t < 1.0 {
                cuts.push(t);
            }
        }
    }
    cuts.sort_by(f64::total_cmp);
    let g = |t: f64| {
        let (a, b) = (residual(0, t), residual(1, t));
        a * a + b * b
    };
    let mut best = f64::INFINITY;
    for w in cuts.windows(2) {
        let (lo, hi) = (w[0], w[1]);
        best = best.min(g(lo)).min(g(hi));
        // Within a piece each residual is 0 or linear: g is a quadratic; its vertex from three values.
        let mid = (lo + hi) / 2.0;
        let (g0, gm, g1) = (g(lo), g(mid), g(hi));
        let h = hi - lo;
        // g = α t² + β t + γ: the second difference over h/2 is α h²/2, the slope at mid (g1 − g0)/h.
        let alpha = 2.0 * (g0 - 2.0 * gm + g1) / (h * h);
        if alpha > 0.0 {
            let t = (mid - (g1 - g0) / h / (2.0 * alpha)).clamp(lo, hi);
            best = best.min(g(t));
        }
    }
    best
}
