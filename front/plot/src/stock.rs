//! `fmsvm plot --stock`: the part as the program leaves it. A mill's height field seen from above,
//! each pixel the cell under it, its colour the depth ramp (deep dark, the top light) lit from the
//! upper left by the surface's slope; a lathe's half-section, Z to the right and the radius up, solid
//! grey. The rapids that went into material are drawn over it in red.

use fmsvm_stock::{Report, Stock};

use crate::{PlotError, check_size, ramp};

/// The colour of uncut material seen from the side, of air, and of a rapid into material.
const SOLID: [u8; 3] = [150, 150, 150];
const AIR: [u8; 3] = [255, 255, 255];
const HIT: [u8; 3] = [220, 0, 0];

/// The picture of `stock` (with `report`'s rapids into material) as RGB pixels of `size`.
pub fn pixels(stock: &Stock, report: &Report, size: (u32, u32)) -> Result<Vec<u8>, PlotError> {
    check_size(size)?;
    let (w, h) = size;
    let mut px = vec![255u8; w as usize * h as usize * 3];
    // The model's extent (X Y for a mill, Z X for a lathe), fitted into the picture with a margin.
    let (extent, cell) = match stock {
        Stock::Mill(m) => {
            let (nx, ny, c) = m.grid();
            let o = m.centre(0, 0);
            (
                [o[0] - c / 2.0, o[1] - c / 2.0, nx as f64 * c, ny as f64 * c],
                c,
            )
        }
        Stock::Lathe(l) => {
            let (nz, nx, c) = l.grid();
            let o = l.centre(0, 0);
            (
                [o[0] - c / 2.0, o[1] - c / 2.0, nz as f64 * c, nx as f64 * c],
                c,
            )
        }
    };
    let margin = 16.0;
    let scale = ((f64::from(w) - 2.0 * margin) / extent[2])
        .min((f64::from(h) - 2.0 * margin) / extent[3])
        .max(1e-9);
    // The depth ramp spans the heights the part has: its deepest cut to the stock's top.
    let span = match stock {
        Stock::Mill(m) => {
            let (nx, ny, _) = m.grid();
            let low = (0..ny)
                .flat_map(|j| (0..nx).map(move |i| (i, j)))
                .map(|(i, j)| m.height(i, j))
                .fold(f64::INFINITY, f64::min);
            (low, m.bounds().1)
        }
        Stock::Lathe(_) => (0.0, 1.0),
    };
    let to_pixel = |a: f64, b: f64| {
        (
            margin + (a - extent[0]) * scale,
            f64::from(h) - margin - (b - extent[1]) * scale,
        )
    };
    for y in 0..h {
        for x in 0..w {
            // The cell under the pixel's centre.
            let a = extent[0] + (f64::from(x) + 0.5 - margin) / scale;
            let b = extent[1] + (f64::from(h) - margin - f64::from(y) - 0.5) / scale;
            let i = ((a - extent[0]) / cell).floor();
            let j = ((b - extent[1]) / cell).floor();
            let colour = match stock {
                Stock::Mill(m) => {
                    let (nx, ny, _) = m.grid();
                    if i < 0.0 || j < 0.0 || i >= nx as f64 || j >= ny as f64 {
                        continue;
                    }
                    shade(m, i as usize, j as usize, span)
                }
                Stock::Lathe(l) => {
                    let (nz, nx, _) = l.grid();
                    if i < 0.0 || j < 0.0 || i >= nz as f64 || j >= nx as f64 {
                        continue;
                    }
                    if l.is_solid(i as usize, j as usize) {
                        SOLID
                    } else {
                        AIR
                    }
                }
            };
            let k = (y as usize * w as usize + x as usize) * 3;
            px[k..k + 3].copy_from_slice(&colour);
        }
    }
    for [from, to] in &report.hits {
        let (a, b) = match stock {
            Stock::Mill(_) => ((from[0], from[1]), (to[0], to[1])),
            // The lathe's picture: Z right, the radius (X) up.
            Stock::Lathe(_) => ((from[2], from[0]), (to[2], to[0])),
        };
        let (pa, pb) = (to_pixel(a.0, a.1), to_pixel(b.0, b.1));
        line(&mut px, size, pa, pb);
        // A ring where it ends, so that a plunge straight down shows too.
        for k in 0..48 {
            let (s0, s1) = (
                k as f64 / 48.0 * std::f64::consts::TAU,
                (k + 1) as f64 / 48.0 * std::f64::consts::TAU,
            );
            let ring = |s: f64| (pb.0 + 9.0 * s.cos(), pb.1 + 9.0 * s.sin());
            line(&mut px, size, ring(s0), ring(s1));
        }
    }
    Ok(px)
}

/// A mill's cell as seen from above: the depth ramp, lit from the upper left by its slope.
fn shade(m: &fmsvm_stock::HeightField, i: usize, j: usize, (low, top): (f64, f64)) -> [u8; 3] {
    let (nx, ny, c) = m.grid();
    let z = m.height(i, j);
    let depth = if top > low {
        ((z - low) / (top - low)).clamp(0.0, 1.0)
    } else {
        1.0
    };
    // The slope by central differences (one-sided at the edges).
    let at = |i: usize, j: usize| m.height(i.min(nx - 1), j.min(ny - 1));
    let dzdx = (at(i + 1, j) - at(i.saturating_sub(1), j)) / (2.0 * c);
    let dzdy = (at(i, j + 1) - at(i, j.saturating_sub(1))) / (2.0 * c);
    // Light from the upper left, 45° up: the surface's normal (−dz/dx, −dz/dy, 1) against it.
    let n = (dzdx * dzdx + dzdy * dzdy + 1.0).sqrt();
    let light = ((dzdx * 0.5 - dzdy * 0.5 + std::f64::consts::FRAC_1_SQRT_2) / n).clamp(0.0, 1.0);
    // The path picture's depth ramp.
    let base = ramp(depth);
    let k = 0.35 + 0.65 * light;
    [base.0, base.1, base.2].map(|v| (f64::from(v) * k).round() as u8)
}

/// A line three pixels wide in red.
fn line(px: &mut [u8], (w, h): (u32, u32), a: (f64, f64), b: (f64, f64)) {
    let steps = ((b.0 - a.0).abs().max((b.1 - a.1).abs()).ceil() as usize).clamp(1, 1 << 16);
    for s in 0..=steps {
        let t = s as f64 / steps as f64;
        let (x, y) = (a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t);
        for (dx, dy) in [(0, 0), (1, 0), (-1, 0), (0, 1), (0, -1)] {
            let (x, y) = (x.round() as i64 + dx, y.round() as i64 + dy);
            if x >= 0 && y >= 0 && x < i64::from(w) && y < i64::from(h) {
                let k = (y as usize * w as usize + x as usize) * 3;
                px[k..k + 3].copy_from_slice(&HIT);
            }
        }
    }
}
