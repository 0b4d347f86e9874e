//! The stock against hand-computed removal: a flat end mill's slot, a ball end mill's scallop
//! (the textbook's h = r − √(r² − (s/2)²)), a bull-nose's corner, a ball on a ramp (the capsule's
//! lowest point), a lathe's facing and turning passes; and the findings a move must raise.

use super::*;
use fmsvm_canon::{Canon, Emitter, Origin, Pose};

const CELL: f64 = 0.1;

fn field() -> HeightField {
    // X 0–20, Y 0–10, Z −10–0 in 0.1 cells: centres at 0.05, 0.15, …
    HeightField::new([[0.0, 0.0, -10.0], [20.0, 10.0, 0.0]], CELL, MAX_CELLS).expect("a field")
}

/// The cell whose centre is at (x, y).
fn at(f: &HeightField, x: f64, y: f64) -> f64 {
    let i = (x / CELL - 0.5).round() as usize;
    let j = (y / CELL - 0.5).round() as usize;
    let c = f.centre(i, j);
    assert!((c[0] - x).abs() < 1e-9 && (c[1] - y).abs() < 1e-9, "{c:?}");
    f.height(i, j)
}

#[test]
fn a_flat_end_mill_cuts_a_slot_of_its_diameter_to_its_depth() {
    let mut f = field();
    let d6 = Cutter::new(Shape::Flat, 3.0);
    let cut = f.cut([-5.0, 5.0, -2.0], [25.0, 5.0, -2.0], &d6);
    // Every cell centre within 3 of Y5 (Y 2.05 … 7.95: 60 rows, 6.0 wide) goes to Z−2, all 200
    // columns: 20 × 6 × 2 = 240 removed.
    assert!((cut.removed - 240.0).abs() < 1e-9, "{cut:?}");
    assert!((cut.deepest - 2.0).abs() < 1e-12);
    assert_eq!(cut.below_floor, 0.0);
    for x in [0.05, 10.05, 19.95] {
        assert_eq!(at(&f, x, 2.05), -2.0);
        assert_eq!(at(&f, x, 7.95), -2.0);
        assert_eq!(at(&f, x, 1.95), 0.0);
        assert_eq!(at(&f, x, 8.05), 0.0);
    }
    assert!((f.volume() - (20.0 * 10.0 * 10.0 - 240.0)).abs() < 1e-6);
}

#[test]
fn a_ball_end_mill_raster_leaves_the_textbook_scallop() {
    let mut f = field();
    let r = 5.0;
    let ball = Cutter::new(Shape::Ball, r);
    let step = 2.0;
    for y in [2.05, 4.05, 6.05] {
        f.cut([-6.0, y, -1.0], [26.0, y, -1.0], &ball);
    }
    // Under a pass the tip's depth; midway between two the scallop h = r − √(r² − (s/2)²).
    let h = r - (r * r - (step / 2.0_f64).powi(2)).sqrt();
    assert!((h - 0.101_020_514_4).abs() < 1e-9);
    for x in [0.05, 7.35, 19.95] {
        assert!((at(&f, x, 4.05) + 1.0).abs() < 1e-12);
        assert!(
            (at(&f, x, 3.05) - (-1.0 + h)).abs() < 1e-9,
            "{}",
            at(&f, x, 3.05)
        );
        assert!((at(&f, x, 5.05) - (-1.0 + h)).abs() < 1e-9);
    }
}

#[test]
fn a_bull_nose_rounds_the_edge_of_its_flat_by_its_corner() {
    let mut f = field();
    let bull = Cutter::new(Shape::Bull(1.0), 5.0);
    f.cut([10.05, 5.05, 1.0], [10.05, 5.05, -2.0], &bull);
    // Flat to 4 from the axis, then the corner: at 4.5, 1 − √(1 − 0.5²) above the tip.
    assert_eq!(at(&f, 14.05, 5.05), -2.0);
    let lift = 1.0 - (1.0_f64 - 0.25).sqrt();
    // Within 1e-9, not the rounding alone: the stock takes every cutter a ten-billionth of its
    // radius smaller (5·10⁻¹⁰ here), so that no cell lies on its edge (see `mill::trimmed`).
    assert!((at(&f, 14.55, 5.05) - (-2.0 + lift)).abs() < 1e-9);
    assert_eq!(at(&f, 15.15, 5.05), 0.0);
}

#[test]
fn a_ball_on_a_ramp_cuts_to_the_lowest_point_of_its_swept_sphere() {
    let mut f = field();
    let r = 5.0;
    let ball = Cutter::new(Shape::Ball, r);
    // Down 2 over 20 along X at Y5.05: the sphere's centre on a line of slope m = 0.1. Under it, the
    // lowest point on a cell's vertical is the centre's height less r·√(1 + m²).
    f.cut([0.0, 5.05, 0.0], [20.0, 5.05, -2.0], &ball);
    let m: f64 = 0.1;
    let x = 10.05;
    let tip = -2.0 * x / 20.0;
    let expected = tip + r - r * (1.0 + m * m).sqrt();
    assert!(
        (at(&f, x, 5.05) - expected).abs() < 1e-9,
        "{} {expected}",
        at(&f, x, 5.05)
    );
}

#[test]
fn a_box_of_a_thousand_million_cells_is_refused_with_the_figure() {
    let e = HeightField::new([[0.0, 0.0, 0.0], [1000.0, 1000.0, 10.0]], 0.03, MAX_CELLS)
        .expect_err("refused");
    assert!(e.contains("1.111e9 cells"), "{e}");
    assert!(e.contains("5.000e7"), "{e}");
}

/// A bar of radius 20 from Z−30 to Z2 in 0.05 cells, and a tool of nose radius 0.8 with Fanuc's
/// tip 3 (controlled point less centre X−0.8 Z−0.8: the kernel's table), its body towards +X +Z.
fn bar() -> (HalfSection, Nose) {
    let bar = HalfSection::new([-30.0, 2.0], [0.0, 20.0], 0.05, MAX_CELLS).expect("a bar");
    (bar, Nose::new(0.8, 3, [-0.8, -0.8]))
}

#[test]
fn a_facing_pass_removes_the_bar_beyond_the_face() {
    let (mut bar, nose) = bar();
    let before = bar.area();
    // Across the end at Z0, from outside the bar past the centre.
    let cut = bar.cut([21.0, 0.0], [-1.0, 0.0], &nose);
    // Z 0–2 of radius 0–20: 40 of half-section, π·20²·2 of volume.
    assert!((cut.area - 40.0).abs() < 1e-9, "{cut:?}");
    let volume = std::f64::consts::PI * 400.0 * 2.0;
    assert!(
        (cut.removed - volume).abs() < 1e-6,
        "{} {volume}",
        cut.removed
    );
    assert!((before - bar.area() - 40.0).abs() < 1e-9);
}

#[test]
fn a_turning_pass_removes_down_to_its_diameter_and_leaves_the_nose_radius_in_the_corner() {
    let (mut bar, nose) = bar();
    bar.cut([21.0, 0.0], [-1.0, 0.0], &nose);
    let cut = bar.cut([18.0, 1.0], [18.0, -20.0], &nose);
    // Radius 18–20 over Z −20…0 (40), less the corner the nose leaves at Z−20: a square of the
    // nose radius less its quarter circle, r²(1 − π/4) = 0.1373; the cells see it to within
    // their size along the quarter circle (1.26 long × 0.05).
    let corner = 0.64 * (1.0 - std::f64::consts::FRAC_PI_4);
    assert!((cut.area - (40.0 - corner)).abs() < 0.07, "{cut:?}");
    // Exactly at cell centres: beyond the radius cut, within it not; the fillet's middle kept.
    let cell = |z: f64, x: f64| {
        let (nz, nx, c) = bar.grid();
        let i = ((z + 30.0) / c - 0.5).round() as usize;
        let j = (x / c - 0.5).round() as usize;
        assert!(i < nz && j < nx);
        bar.is_solid(i, j)
    };
    assert!(!cell(-10.025, 18.025));
    assert!(cell(-10.025, 17.975));
    assert!(!cell(-19.175, 19.975));
    // 0.05 inside the corner's diagonal: farther than 0.8 from the nose centre (X18.8 Z−19.2).
    assert!(cell(-19.975, 18.025));
    assert!(cell(-20.025, 19.975));
}

/// An emitter that takes everything and writes nothing.
struct Nothing;

impl Emitter for Nothing {
    const CANON: bool = true;
}

fn p(x: f64, y: f64, z: f64) -> Pose {
    [x, y, z, 0.0, 0.0, 0.0]
}

fn origin(line: u32) -> Origin {
    Origin {
        line,
        ..Origin::default()
    }
}

fn milled(ops: &[Canon<'_>], cutter: Cutter) -> Simulated<Nothing> {
    let stock = Stock::Mill(field());
    let tools = [(1, Tool::Mill(cutter))].into_iter().collect();
    let mut s = Simulated::new(Nothing, stock, tools, false);
    for (k, op) in ops.iter().enumerate() {
        s.canon(op, origin(k as u32 + 1)).expect("runs");
    }
    s.end().expect("ends");
    s
}

#[test]
fn a_rapid_into_the_stock_is_said_at_its_block_with_its_depth() {
    let d6 = Cutter::new(Shape::Flat, 3.0);
    let s = milled(
        &[
            Canon::Tool(1.0),
            Canon::Start(p(10.0, 5.0, 50.0)),
            Canon::Rapid(p(10.0, 5.0, 2.0)),
            Canon::Rapid(p(10.0, 5.0, -1.0)),
        ],
        d6,
    );
    let w = s.warnings();
    assert_eq!(w.len(), 1, "{w:?}");
    assert_eq!(w[0].at.line, 4);
    assert!(
        w[0].text
            .contains("a rapid (G0) into the stock: the cutter goes 1.000 below"),
        "{}",
        w[0].text
    );
}

#[test]
fn a_rapid_across_a_pocket_wall_is_said_and_one_above_the_stock_not() {
    let d6 = Cutter::new(Shape::Flat, 3.0);
    let s = milled(
        &[
            Canon::Tool(1.0),
            Canon::Start(p(10.0, 5.0, 5.0)),
            Canon::Feed(p(10.0, 5.0, -5.0)),
            // Out of the hole at Z−5, sideways (a G28 through an intermediate point left low).
            Canon::Rapid(p(30.0, 5.0, -5.0)),
            Canon::Rapid(p(30.0, 5.0, 10.0)),
            Canon::Rapid(p(-10.0, 5.0, 10.0)),
        ],
        d6,
    );
    let w = s.warnings();
    assert_eq!(w.len(), 1, "{w:?}");
    assert_eq!(w[0].at.line, 4);
    assert!(w[0].text.contains("5.000 below"), "{}", w[0].text);
}

#[test]
fn a_shank_above_short_flutes_rubs_a_deep_wall_and_a_cut_below_the_floor_is_said() {
    let mut d6 = Cutter::new(Shape::Flat, 3.0);
    d6.flute_length = Some(4.0);
    let s = milled(
        &[
            Canon::Tool(1.0),
            Canon::Start(p(-5.0, 5.0, 5.0)),
            Canon::Feed(p(-5.0, 5.0, -6.0)),
            // A slot 6 deep with 4 of flutes: the shank rubs the 2 above them.
            Canon::Feed(p(25.0, 5.0, -6.0)),
            Canon::Feed(p(25.0, 5.0, -12.0)),
            Canon::Feed(p(15.0, 5.0, -12.0)),
        ],
        d6,
    );
    let w = s.warnings();
    assert!(
        w.iter().any(|w| w.at.line == 4
            && w.text
                .contains("shank above its 4 of flutes rubs the material, 2.000 deep")),
        "{w:?}"
    );
    assert!(
        w.iter()
            .any(|w| w.at.line == 6 && w.text.contains("2.000 below the stock's floor")),
        "{w:?}"
    );
}

#[test]
fn a_tool_that_cannot_plunge_going_straight_down_into_material_is_said() {
    let mut d6 = Cutter::new(Shape::Flat, 3.0);
    d6.plunges = false;
    let s = milled(
        &[
            Canon::Tool(1.0),
            Canon::Start(p(10.0, 5.0, 5.0)),
            Canon::Feed(p(10.0, 5.0, -2.0)),
        ],
        d6,
    );
    assert!(
        s.warnings()
            .iter()
            .any(|w| w.text.contains("does not cut at its centre")),
        "{:?}",
        s.warnings()
    );
    // A ramp over more than the radius is how such a tool goes down.
    let s = milled(
        &[
            Canon::Tool(1.0),
            Canon::Start(p(0.0, 5.0, 0.5)),
            Canon::Feed(p(10.0, 5.0, -1.0)),
        ],
        d6,
    );
    assert!(s.warnings().is_empty(), "{:?}", s.warnings());
}

#[test]
fn strict_stops_at_the_first_finding() {
    let d6 = Cutter::new(Shape::Flat, 3.0);
    let tools = [(1, Tool::Mill(d6))].into_iter().collect();
    let mut s = Simulated::new(Nothing, Stock::Mill(field()), tools, true);
    s.canon(&Canon::Tool(1.0), origin(1)).expect("runs");
    s.canon(&Canon::Start(p(10.0, 5.0, 5.0)), origin(2))
        .expect("runs");
    let stop = s.canon(&Canon::Rapid(p(10.0, 5.0, -1.0)), origin(3));
    assert!(matches!(stop, Err(fmsvm_block::Stop::Alarm(_))), "{stop:?}");
}

#[test]
fn a_lathe_rapid_into_the_bar_is_said() {
    let (bar, nose) = bar();
    // A lathe's tools are its offsets: T0101 is offset 1.
    let tools = [(1, Tool::Lathe(nose))].into_iter().collect();
    let mut s = Simulated::new(Nothing, Stock::Lathe(bar), tools, false);
    // X is the radius (the kernel's terms): from outside, a rapid along Z at radius 15 through the bar.
    for (k, op) in [
        Canon::Tool(101.0),
        Canon::Start(p(25.0, 0.0, 5.0)),
        Canon::Rapid(p(15.0, 0.0, 5.0)),
        Canon::Rapid(p(15.0, 0.0, -5.0)),
    ]
    .iter()
    .enumerate()
    {
        s.canon(op, origin(k as u32 + 1)).expect("runs");
    }
    let w = s.warnings();
    assert_eq!(w.len(), 1, "{w:?}");
    assert_eq!(w[0].at.line, 4);
    assert!(
        w[0].text
            .contains("into the stock: the tool passes through"),
        "{}",
        w[0].text
    );
}

/// A reproducible sequence of numbers in [0, 1) (a linear congruential generator).
struct Numbers(u64);

impl Numbers {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// `moves` moves from `start` made by `step` (given the numbers and where the last move ended: a
/// move's start, end, and whether it is a rapid), cut chained on one field and cut over every cell on another:
/// every `every` moves and at the end (what the chain left flushed) every cell is the same, and the
/// volume removed is, and the moves cut some.
fn chained_as_every_cell(
    seed: u64,
    cutter: Cutter,
    start: [f64; 3],
    [moves, every]: [usize; 2],
    mut step: impl FnMut(&mut Numbers, [f64; 3]) -> ([f64; 3], [f64; 3], bool),
) {
    let mut rng = Numbers(seed);
    let (mut chained, mut plain) = (field(), field());
    let (mut removed, mut reference) = (0.0, 0.0);
    let mut at = start;
    for n in 0..moves {
        let (from, to, rapid) = step(&mut rng, at);
        let (before, now) = chained.advance(from, to, &cutter, !rapid);
        removed += before.removed + now.removed;
        reference += plain.cut_everywhere(from, to, &cutter).removed;
        at = to;
        if n % every == every - 1 {
            removed += chained.flush().removed;
            compare(&chained, &plain, seed, n);
        }
    }
    removed += chained.flush().removed;
    compare(&chained, &plain, seed, moves);
    assert!(
        (removed - reference).abs() < 1e-6 * reference.max(1.0),
        "seed {seed}: {removed} against {reference}"
    );
    assert!(
        reference > 10.0,
        "seed {seed}: the moves cut little ({reference})"
    );
}

/// Moves that follow each other as a raster does (short steps, rising and falling, turning a
/// little, now and then a sharp turn, a plunge, a step that goes nowhere, a rapid, a jump that does
/// not start where the last ended), chained, leave every cell where cutting each move over every
/// cell under it does, and remove as much.
#[test]
fn a_chain_of_moves_leaves_what_cutting_every_cell_of_each_leaves() {
    for (seed, cutter) in [
        (1, Cutter::new(Shape::Ball, 3.0)),
        (2, Cutter::new(Shape::Ball, 1.0)),
        (3, Cutter::new(Shape::Flat, 2.0)),
        (4, Cutter::new(Shape::Bull(1.0), 2.5)),
        (5, Cutter::new(Shape::Ball, 2.0)),
    ] {
        let mut heading: f64 = 0.3;
        chained_as_every_cell(seed, cutter, [10.0, 5.0, 1.0], [3000, 500], |rng, at| {
            let pick = rng.next();
            let step = 0.02 + 0.3 * rng.next();
            heading += (rng.next() - 0.5) * if pick < 0.05 { 3.0 } else { 0.2 };
            let mut to = [
                (at[0] + step * heading.cos()).clamp(-2.0, 22.0),
                (at[1] + step * heading.sin()).clamp(-2.0, 12.0),
                (at[2] + (rng.next() - 0.55) * 0.4).clamp(-4.0, 2.0),
            ];
            if pick > 0.97 {
                to = at;
            } else if pick > 0.95 {
                to = [at[0], at[1], at[2] - 0.5];
            }
            let rapid = pick > 0.93 && pick <= 0.95;
            let from = if pick > 0.90 && pick <= 0.91 {
                [at[0] + 0.5, at[1], at[2]]
            } else {
                at
            };
            (from, to, rapid)
        });
    }
}

/// A ball's moves along X or Y (swept along the grid's lines), rising, falling and level, now and
/// then turning to the other axis, going back the way they came, a plunge, a rapid, a jump that
/// does not start where the last ended, steps shorter and longer than a cell, over and into a
/// dome: chained, they leave every cell where cutting each move over every cell under it does, and
/// remove as much.
#[test]
fn a_ball_s_moves_along_x_and_y_chained_leave_what_cutting_every_cell_leaves() {
    for (seed, radius) in [(11, 1.5), (12, 0.7), (13, 2.2)] {
        let (mut axis, mut sign) = (0, 1.0);
        let cutter = Cutter::new(Shape::Ball, radius);
        chained_as_every_cell(seed, cutter, [10.0, 5.0, 0.5], [4000, 800], |rng, at| {
            let pick = rng.next();
            if pick < 0.04 {
                axis = 1 - axis;
            } else if pick < 0.07 {
                sign = -sign;
            }
            let step = if rng.next() < 0.6 {
                0.05
            } else {
                0.02 + 0.5 * rng.next()
            };
            let mut to = at;
            to[axis] = (at[axis] + sign * step).clamp(0.5, if axis == 0 { 19.5 } else { 9.5 });
            if to[axis] == at[axis] {
                sign = -sign;
            }
            // Level a third of the time; else rising or falling, over the dome or into it.
            let dz = rng.next();
            if dz > 0.33 {
                to[2] = (at[2] + (dz - 0.7) * 0.6).clamp(-3.0, 1.0);
            }
            if (0.3..0.35).contains(&pick) {
                let (x, y) = (to[0], to[1]);
                to[2] = dome(x, y);
            }
            if pick > 0.98 {
                to = [at[0], at[1], at[2] - 0.3];
            }
            let rapid = pick > 0.96 && pick <= 0.98;
            let from = if pick > 0.94 && pick <= 0.95 {
                [at[0] + 0.3, at[1], at[2]]
            } else {
                at
            };
            (from, to, rapid)
        });
    }
}

/// Rasters along Y and along X over a dome, in steps shorter and longer than a cell, zigzag and
/// one-way (a rapid back), chained, leave what cutting every cell of each move leaves.
#[test]
fn rasters_along_each_axis_chained_leave_what_cutting_every_cell_leaves() {
    for cutter in [
        Cutter::new(Shape::Ball, 1.5),
        Cutter::new(Shape::Flat, 1.0),
        Cutter::new(Shape::Bull(0.5), 1.5),
    ] {
        for (along_y, step, zigzag) in [
            (true, 0.05, true),
            (false, 0.13, true),
            (true, 0.3, false),
            (false, 0.05, false),
        ] {
            let (mut chained, mut plain) = (field(), field());
            let mut at = [0.0, 0.0, 2.0];
            let mut pass = 0;
            let mut across = 0.5;
            while across < if along_y { 19.5 } else { 9.5 } {
                let forward = !zigzag || pass % 2 == 0;
                let (lo, hi) = if along_y { (0.0, 10.0) } else { (0.0, 20.0) };
                let mut t = if forward { lo } else { hi };
                let mut first = true;
                while (lo..=hi).contains(&t) {
                    let (x, y) = if along_y { (across, t) } else { (t, across) };
                    let to = [x, y, dome(x, y)];
                    let rapid = first && !zigzag;
                    let from = if rapid { [to[0], to[1], 2.0] } else { at };
                    chained.advance(from, to, &cutter, !rapid);
                    plain.cut_everywhere(from, to, &cutter);
                    at = to;
                    first = false;
                    t += if forward { step } else { -step };
                }
                across += 0.7;
                pass += 1;
            }
            chained.flush();
            compare(&chained, &plain, pass, 0);
        }
    }
}

/// A dome of radius 4 on the field's middle, its top 0.5 below the stock's, on a floor 0.5 down.
fn dome(x: f64, y: f64) -> f64 {
    let d2 = (x - 10.0).powi(2) + (y - 5.0).powi(2);
    if d2 < 16.0 {
        (16.0 - d2).sqrt() - 4.5
    } else {
        -0.5
    }
}

fn compare(a: &HeightField, b: &HeightField, seed: u64, n: usize) {
    let (nx, ny, _) = a.grid();
    for j in 0..ny {
        for i in 0..nx {
            let (x, y) = (a.height(i, j), b.height(i, j));
            assert!(
                (x - y).abs() < 1e-9,
                "seed {seed}, move {n}, cell {i} {j}: {x} against {y}"
            );
        }
    }
}

/// The field in quarters on two threads, a batch at a time, leaves every cell as one field cutting
/// the moves in order does, and each move's removal (its own and what the next cut of what it left)
/// is the same.
#[test]
fn quarters_on_two_threads_cut_what_one_field_cuts_move_by_move() {
    use crate::quarters::{Quarters, Step};
    use std::collections::VecDeque;
    let ball = Cutter::new(Shape::Ball, 1.5);
    let mut steps = Vec::new();
    let mut at = [0.0, 0.0, 2.0];
    for (pass, x) in (0..30).map(|k| (k, 0.3 + 0.65 * k as f64)) {
        for k in 0..=100 {
            let y = if pass % 2 == 0 {
                0.1 * k as f64
            } else {
                10.0 - 0.1 * k as f64
            };
            let to = [x, y, dome(x, y)];
            steps.push(Step {
                from: at,
                to,
                cutter: ball,
                chain: k > 0,
            });
            at = to;
        }
    }
    let mut one = field();
    let mut serial = vec![[0.0; 2]; steps.len() + 1];
    for (k, s) in steps.iter().enumerate() {
        let (before, now) = one.advance(s.from, s.to, &s.cutter, s.chain);
        serial[k.saturating_sub(1)][1] += before.removed;
        serial[k][0] += now.removed;
    }
    serial[steps.len() - 1][1] += one.flush().removed;
    let mut quarters = Quarters::new(field());
    let mut split = vec![[0.0; 2]; steps.len() + 1];
    // Batches big and small (cut by the workers or here), up to three away at once, a small one
    // sent while big ones are away, one cut alone between, the stock's volume asked for between.
    let sizes = [700, 40, 300, 5, 1000, 256, 255, 900];
    let (mut at, mut away, mut received) = (0, VecDeque::new(), 0);
    let mut land = |quarters: &mut Quarters, away: &mut VecDeque<usize>, received: &mut usize| {
        let n = away.pop_front().unwrap_or(0);
        let cuts = quarters.receive();
        assert_eq!(cuts.len(), n);
        for (m, (before, now)) in cuts.into_iter().enumerate() {
            let k = *received + m;
            split[k.saturating_sub(1)][1] += before.removed;
            split[k][0] += now.removed;
        }
        *received += n;
    };
    for (b, size) in sizes.iter().cycle().enumerate() {
        let size = (*size).min(steps.len() - at);
        if size == 0 {
            break;
        }
        if b % 5 == 4 {
            while !away.is_empty() {
                land(&mut quarters, &mut away, &mut received);
            }
            assert!(quarters.volume() > 0.0);
        }
        quarters.send(steps[at..at + size].into());
        away.push_back(size);
        at += size;
        if away.len() == 3 {
            land(&mut quarters, &mut away, &mut received);
        }
    }
    while !away.is_empty() {
        land(&mut quarters, &mut away, &mut received);
    }
    assert_eq!(received, steps.len());
    split[steps.len() - 1][1] += quarters.flush().removed;
    let joined = quarters.join();
    compare(&joined, &one, 0, steps.len());
    for (k, (a, b)) in serial.iter().zip(&split).enumerate() {
        let (a, b) = (a[0] + a[1], b[0] + b[1]);
        assert!(
            (a - b).abs() < 1e-9 * a.abs().max(1.0),
            "move {k}: {a} against {b}"
        );
    }
    assert!(serial.iter().map(|r| r[0] + r[1]).sum::<f64>() > 50.0);
}

/// Each move's own account (feed in material or in air, a plunge, a rapid into material) is what
/// cutting each move whole at once gives (a tool with a shank to check is cut so: the reference),
/// though a chain leaves the cells ahead of each move to the next: short steps through material,
/// plunges one after another with a tool that cannot, rapids after feeds, moves in the air.
#[test]
fn each_move_s_account_in_a_chain_is_that_of_cutting_it_whole() {
    for (seed, shape) in [(7, Shape::Ball), (8, Shape::Flat), (9, Shape::Bull(0.5))] {
        let mut cutter = Cutter::new(shape, 1.5);
        cutter.plunges = false;
        let mut whole = cutter;
        // Flutes longer than the stock is high: the shank never rubs, each move is cut whole.
        whole.flute_length = Some(1000.0);
        let mut rng = Numbers(seed);
        let mut ops = vec![
            Canon::Tool(1.0),
            Canon::Start(p(10.0, 5.0, 2.0)),
            Canon::FeedRate(600.0),
        ];
        let mut at = [10.0, 5.0, 2.0];
        let mut heading: f64 = 0.0;
        for _ in 0..1500 {
            let pick = rng.next();
            heading += (rng.next() - 0.5) * 0.3;
            let step = if pick < 0.5 {
                0.02
            } else {
                0.02 + 0.4 * rng.next()
            };
            let mut to = [
                (at[0] + step * heading.cos()).clamp(-1.0, 21.0),
                (at[1] + step * heading.sin()).clamp(-1.0, 11.0),
                (at[2] + (rng.next() - 0.6) * 0.3).clamp(-3.0, 2.0),
            ];
            if pick > 0.96 {
                to = [at[0], at[1], at[2] - 0.4];
            }
            ops.push(if pick > 0.93 && pick <= 0.96 {
                Canon::Rapid(p(to[0], to[1], to[2]))
            } else {
                Canon::Feed(p(to[0], to[1], to[2]))
            });
            at = to;
        }
        let chained = milled(&ops, cutter).finish().2;
        let reference = milled(&ops, whole).finish().2;
        let (a, b) = (chained.tools[&1], reference.tools[&1]);
        assert!(
            b.air_length > 1.0 && b.cutting_length > 1.0,
            "seed {seed}: {b:?}"
        );
        assert!(
            (a.cutting_length - b.cutting_length).abs() < 1e-9,
            "seed {seed}: {a:?} against {b:?}"
        );
        assert!(
            (a.air_length - b.air_length).abs() < 1e-9,
            "seed {seed}: {a:?} against {b:?}"
        );
        assert!(
            (a.removed - b.removed).abs() < 1e-6 * b.removed,
            "seed {seed}: {a:?} against {b:?}"
        );
        assert_eq!(chained.plunges, reference.plunges, "seed {seed}");
        assert!(reference.plunges > 0, "seed {seed}");
        assert_eq!(
            chained.rapids_into_material, reference.rapids_into_material,
            "seed {seed}"
        );
        assert_eq!(chained.below_floor, reference.below_floor, "seed {seed}");
    }
}
