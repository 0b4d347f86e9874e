//! The lathe's multiple repetitive cycles as moves (docs/lathe.md, "Multiple repetitive cycles"): a
//! finishing profile read from blocks ns–nf, and what G70 finishing, G71/G72 stock removal (type I),
//! G73 pattern repeating, G74/G75 peck drilling and grooving and G76 multiple threading make of it,
//! each a list of steps from the start point back to it. Coordinates are (X as a radius, Z).

use fmsvm_block::Alarm;
use fmsvm_block::alarms::NO_FANUC_NUMBER;
use fmsvm_canon::geom::{dist, sub, unit};

/// X (radius) and Z.
pub type P2 = [f64; 2];

/// A profile's piece, as its block moves the tool.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Seg {
    /// G0 (`rapid`) or G1 to `to`.
    Line {
        /// The end.
        to: P2,
        /// G0.
        rapid: bool,
    },
    /// G2 (`cw`) or G3 to `to` about `centre`.
    Arc {
        /// The end.
        to: P2,
        /// The centre.
        centre: P2,
        /// G2.
        cw: bool,
    },
}

impl Seg {
    /// Where the piece ends.
    pub fn to(&self) -> P2 {
        match *self {
            Seg::Line { to, .. } | Seg::Arc { to, .. } => to,
        }
    }

    /// The move along the piece at feed `f`: as its block moves (G0 at rapid), or at the feed
    /// whatever its block said (`rapid_as_feed`: a roughing pass along the profile).
    fn step(&self, f: Option<f64>, rapid_as_feed: bool) -> Step {
        match *self {
            Seg::Line { to, rapid: true } if !rapid_as_feed => Step::Rapid(to),
            Seg::Line { to, .. } => Step::Feed(to, f),
            Seg::Arc { to, centre, cw } => Step::Arc { to, centre, cw, f },
        }
    }

    /// The same piece moved by `d`.
    pub fn shifted(&self, d: P2) -> Seg {
        let add = |p: P2| [p[0] + d[0], p[1] + d[1]];
        match *self {
            Seg::Line { to, rapid } => Seg::Line { to: add(to), rapid },
            Seg::Arc { to, centre, cw } => Seg::Arc {
                to: add(to),
                centre: add(centre),
                cw,
            },
        }
    }
}

/// A finishing profile: the blocks ns–nf as they move the tool from the cycle's start point, each
/// with the F S T its block set (they act in G70 only).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Profile {
    /// N of the first block.
    pub ns: u32,
    /// N of the last block.
    pub nf: u32,
    /// The pieces, in order.
    pub segs: Vec<Seg>,
    /// The F S T each piece's block set (G70 runs them).
    pub codes: Vec<BlockCodes>,
    /// The first block names both axes: a type II profile for G71/G72 (pockets allowed).
    pub type_two: bool,
}

/// The F, S and T of a profile block (0i-TD: ignored by G71–G73, in force in G70); a block
/// without a move passes them on to the next one.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BlockCodes {
    /// F: the feed of this move and the next ones (in G70).
    pub f: Option<f64>,
    /// S: the spindle speed (or surface speed under G96) from this move on.
    pub s: Option<f64>,
    /// T: a tool call (and its offset) before this move.
    pub t: Option<f64>,
}

/// An axis word of a profile block: absolute, or an increment (U W, or G91 in system B).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AxisWord {
    /// X (radius) or Z.
    Abs(f64),
    /// U (radius) or W.
    Inc(f64),
}

/// A profile block as written: its motion, its axis words, an arc's R or I K, its F.
#[derive(Clone, Copy, Debug)]
pub struct ProfileBlock {
    /// G0 (0), G1 (1), G2 (2), G3 (3).
    pub motion: u8,
    /// X and Z (None: not named).
    pub axes: [Option<AxisWord>; 2],
    /// An arc's R, or its I K (X radius, Z) from the start.
    pub centre: Option<fmsvm_canon::arcs::CentreWords>,
    /// A chamfer or corner R at its end (`G1 Z-20. R2.`, `,C1.`).
    pub corner: Option<ProfileCorner>,
}

/// A chamfer or a rounding at the end of a profile block, made between it and the next.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProfileCorner {
    /// A tangent arc of radius `amount` (else a chamfer `amount` from the corner on both moves).
    pub round: bool,
    /// The chamfer's legs or the arc's radius.
    pub amount: f64,
    /// A lathe's chamfering and corner R (I K C R): the next move must go along this axis only
    /// (0 X, 1 Z) in the direction of this sign; `,C` `,R` ask nothing of it.
    pub along: Option<(usize, f64)>,
}

/// A profile as its blocks wrote it: the pieces are worked out from where the cycle starts (a
/// first block naming only X keeps the start's Z, as on the control).
#[derive(Clone, Debug, Default)]
pub struct ProfileBlocks {
    /// N of the first block.
    pub ns: u32,
    /// N of the last block.
    pub nf: u32,
    /// The blocks with a move.
    pub blocks: Vec<ProfileBlock>,
    /// The F S T each block set (G70 runs them).
    pub codes: Vec<BlockCodes>,
}

impl ProfileBlocks {
    /// The pieces from start point `a`; an arc's end off its circle by more than `tolerance` is
    /// alarm 0020.
    pub fn resolve(&self, a: P2, tolerance: f64) -> Result<Profile, Alarm> {
        let mut segs = Vec::with_capacity(self.blocks.len());
        let mut codes = Vec::with_capacity(self.blocks.len());
        let mut corners = Vec::with_capacity(self.blocks.len());
        let mut from = a;
        for (b, c) in self.blocks.iter().zip(&self.codes) {
            let mut to = from;
            for k in 0..2 {
                match b.axes[k] {
                    Some(AxisWord::Abs(v)) => to[k] = v,
                    Some(AxisWord::Inc(v)) => to[k] = from[k] + v,
                    None => {}
                }
            }
            let seg = match (b.motion, b.centre) {
                (2 | 3, Some(centre)) => {
                    let pose = |p: P2| -> fmsvm_canon::Pose { [p[0], 0.0, p[1], 0.0, 0.0, 0.0] };
                    let arc = fmsvm_canon::arcs::arc(
                        &pose(from),
                        &pose(to),
                        fmsvm_canon::Plane::ZX,
                        b.motion == 2,
                        centre,
                        tolerance,
                    )?;
                    match arc {
                        Some(arc) => Seg::Arc {
                            to,
                            centre: [arc.centre[1], arc.centre[0]],
                            cw: b.motion == 2,
                        },
                        None => continue,
                    }
                }
                (m, _) => Seg::Line { to, rapid: m == 0 },
            };
            segs.push(seg);
            codes.push(*c);
            corners.push(b.corner);
            from = to;
        }
        let (segs, codes) = make_corners(a, segs, codes, &corners)?;
        Ok(Profile {
            ns: self.ns,
            nf: self.nf,
            segs,
            codes,
            type_two: self
                .blocks
                .first()
                .is_some_and(|b| b.axes.iter().all(Option::is_some)),
        })
    }
}

/// The profile's chamfers and roundings made: each cornered line ends short of its corner, and a
/// chamfer or a tangent arc joins it to the next line, which starts as far after it (0i-TD
/// "Chamfering and corner R": the next block a G1 along the other axis, in the word's sign).
fn make_corners(
    a: P2,
    segs: Vec<Seg>,
    codes: Vec<BlockCodes>,
    corners: &[Option<ProfileCorner>],
) -> Result<(Vec<Seg>, Vec<BlockCodes>), Alarm> {
    if corners.iter().all(Option::is_none) {
        return Ok((segs, codes));
    }
    let mut out: Vec<Seg> = Vec::with_capacity(segs.len() * 2);
    let mut out_codes = Vec::with_capacity(segs.len() * 2);
    // The next piece starts where the corner's piece ends: a piece is its end point.
    let mut from = a;
    for (k, seg) in segs.iter().enumerate() {
        let seg = *seg;
        let corner_from = from;
        from = seg.to();
        let Some(c) = corners[k] else {
            out.push(seg);
            out_codes.push(codes[k]);
            continue;
        };
        let bad = |what: &str| Alarm::new(51, format!("MISSING MOVE AFTER CNR/CHF: {what}"));
        let (
            Seg::Line {
                rapid: false,
                to: p,
            },
            Some(Seg::Line {
                rapid: false,
                to: next,
            }),
        ) = (seg, segs.get(k + 1).copied())
        else {
            return Err(bad(
                "a profile's chamfer or corner R is between two G1 lines (the next block must be one)",
            ));
        };
        let d1 = unit(sub(p, corner_from)).unwrap_or_default();
        let d2 = unit(sub(next, p)).unwrap_or_default();
        let (l1, l2) = (dist(p, corner_from), dist(next, p));
        if let Some((axis, sign)) = c.along {
            let along = next[axis] - p[axis];
            if (next[1 - axis] - p[1 - axis]).abs() > 1e-9 || along * sign <= 0.0 {
                return Err(bad(&format!(
                    "the block after a chamfer or corner R must move along {} only, towards {}",
                    ["X (U)", "Z (W)"][axis],
                    if sign > 0.0 { "+" } else { "-" }
                )));
            }
        }
        // How far before and after the corner the pieces meet it.
        let cos = (d1[0] * d2[0] + d1[1] * d2[1]).clamp(-1.0, 1.0);
        let turn = cos.acos();
        let t = if c.round {
            c.amount * (turn / 2.0).tan()
        } else {
            c.amount
        };
        if !(turn > 1e-9 && turn < std::f64::consts::PI - 1e-9) || t > l1 + 1e-9 || t > l2 + 1e-9 {
            return Err(Alarm::new(
                55,
                format!(
                    "MISSING MOVE VALUE IN CHF/CNR: a corner of {} needs {t:.4} of each move (they are {l1:.4} and {l2:.4} long, and not in line)",
                    c.amount
                ),
            ));
        }
        let before = [p[0] - d1[0] * t, p[1] - d1[1] * t];
        let after = [p[0] + d2[0] * t, p[1] + d2[1] * t];
        out.push(Seg::Line {
            to: before,
            rapid: false,
        });
        out_codes.push(codes[k]);
        if c.round {
            // Turning towards +X from +Z (in Z, X axes) is anticlockwise seen from +Y: G3.
            let cross = d1[1] * d2[0] - d1[0] * d2[1];
            let centre = centre_of_round(before, d1, cross > 0.0, c.amount);
            out.push(Seg::Arc {
                to: after,
                centre,
                cw: cross < 0.0,
            });
        } else {
            out.push(Seg::Line {
                to: after,
                rapid: false,
            });
        }
        // The corner's piece is of the same block: its F, once its S and T are given.
        out_codes.push(BlockCodes {
            f: codes[k].f,
            ..BlockCodes::default()
        });
    }
    Ok((out, out_codes))
}

/// The centre of an arc of radius `r` tangent at `at` to direction `d` (X, Z), turning
/// anticlockwise seen from +Y (`ccw`) or clockwise.
fn centre_of_round(at: P2, d: P2, ccw: bool, r: f64) -> P2 {
    // In the Z X plane (Z first), the left of direction (dz, dx) is (-dx, dz): as (X, Z), (dz, -dx).
    let left = [d[1], -d[0]];
    let n = if ccw { left } else { [-left[0], -left[1]] };
    [at[0] + n[0] * r, at[1] + n[1] * r]
}

/// One move of a cycle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Step {
    /// At rapid traverse.
    Rapid(P2),
    /// At the feed rate `f` (None: the feed in force).
    Feed(P2, Option<f64>),
    /// An arc at the feed rate.
    Arc {
        /// The end.
        to: P2,
        /// The centre.
        centre: P2,
        /// G2.
        cw: bool,
        /// The feed (None: the feed in force).
        f: Option<f64>,
    },
    /// A thread of lead `lead` (per revolution).
    Thread(P2, f64),
    /// A profile block's S and T, before its move (G70).
    Codes {
        /// S.
        s: Option<f64>,
        /// T.
        t: Option<f64>,
    },
    /// The spindle turned this way: 3 (M03) or 4 (M04), a tap reversed and back.
    Spindle(u8),
}

impl Step {
    /// Where the step ends (None: it does not move).
    pub fn to(&self) -> Option<P2> {
        match *self {
            Step::Rapid(p) | Step::Feed(p, _) | Step::Thread(p, _) | Step::Arc { to: p, .. } => {
                Some(p)
            }
            Step::Codes { .. } | Step::Spindle(_) => None,
        }
    }
}

/// G70: the profile from the start point `a` as its blocks say, each at its own F (or `feed`), then
/// back to `a` at rapid traverse (Fanuc 0i-TD, "Finishing cycle (G70)").
pub fn finishing(a: P2, p: &Profile, feed: Option<f64>) -> Vec<Step> {
    let mut steps = Vec::with_capacity(p.segs.len() + 1);
    let mut f = feed;
    for (seg, own) in p.segs.iter().zip(&p.codes) {
        if own.f.is_some() {
            f = own.f;
        }
        if own.s.is_some() || own.t.is_some() {
            steps.push(Step::Codes { s: own.s, t: own.t });
        }
        steps.push(seg.step(f, false));
    }
    steps.push(Step::Rapid(a));
    steps
}

/// The sign of `v` (0 for 0).
pub fn sign(v: f64) -> f64 {
    if v > 0.0 {
        1.0
    } else if v < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// Whether `v` is a number above 0 (NaN is not).
fn positive(v: f64) -> bool {
    v > 0.0
}

/// An alarm about the cycle's data.
fn bad(what: String) -> Alarm {
    Alarm::new(NO_FANUC_NUMBER, what)
}

/// Where a profile's pieces meet the line where axis `k` (0 X, 1 Z) is `level`: the other axis of
/// the first crossing, or None.
fn crossing(start: P2, segs: &[Seg], k: usize, level: f64) -> Option<f64> {
    let o = 1 - k;
    let mut from = start;
    for seg in segs {
        let to = seg.to();
        match *seg {
            Seg::Line { .. } => {
                let (a, b) = (from[k] - level, to[k] - level);
                if a == 0.0 {
                    return Some(from[o]);
                }
                if a * b <= 0.0 && a != b {
                    let t = a / (a - b);
                    return Some(from[o] + (to[o] - from[o]) * t);
                }
            }
            Seg::Arc { centre, .. } => {
                let r = (from[0] - centre[0]).hypot(from[1] - centre[1]);
                let d = level - centre[k];
                if d.abs() <= r {
                    let h = (r * r - d * d).sqrt();
                    // The crossing between the arc's ends on the axis `o` (a monotonic piece).
                    let (lo, hi) = (from[o].min(to[o]), from[o].max(to[o]));
                    for c in [centre[o] + h, centre[o] - h] {
                        if c >= lo - 1e-9
                            && c <= hi + 1e-9
                            && (from[k] - level) * (to[k] - level) <= 1e-12
                        {
                            return Some(c);
                        }
                    }
                }
            }
        }
        from = to;
    }
    None
}

/// Whether every piece of the profile from `start` moves axis `k` only in direction `dir` (or not
/// at all): an arc may not pass an extreme of that axis between its ends.
fn monotonic(start: P2, segs: &[Seg], k: usize, dir: f64) -> bool {
    let mut from = start;
    for seg in segs {
        let to = seg.to();
        if (to[k] - from[k]) * dir < -1e-9 {
            return false;
        }
        if let Seg::Arc { centre, cw, .. } = *seg {
            // The arc's angles (X the second plane axis, Z the first, as G18's Z X): an extreme of
            // axis k lies where the radius is parallel to it.
            let ang = |p: P2| (p[0] - centre[0]).atan2(p[1] - centre[1]);
            let (a0, a1) = (ang(from), ang(to));
            let mut sweep = if cw { a0 - a1 } else { a1 - a0 };
            if sweep <= 0.0 {
                sweep += std::f64::consts::TAU;
            }
            // The extremes of X are at ±90° (atan2 of x over z), those of Z at 0° and 180°.
            let extremes: [f64; 2] = if k == 0 {
                [std::f64::consts::FRAC_PI_2, -std::f64::consts::FRAC_PI_2]
            } else {
                [0.0, std::f64::consts::PI]
            };
            for e in extremes {
                let turned = if cw { a0 - e } else { e - a0 };
                let t = turned.rem_euclid(std::f64::consts::TAU);
                if t > 1e-9 && t < sweep - 1e-9 {
                    return false;
                }
            }
        }
        from = to;
    }
    true
}

/// The data of G71 (turning, `axis` 1: cut along Z) or G72 (facing, `axis` 0: cut along X).
#[derive(Clone, Copy, Debug)]
pub struct StockRemoval {
    /// The depth of cut Δd (radius for G71), > 0.
    pub depth: f64,
    /// The retract e (radius for G71).
    pub retract: f64,
    /// The finishing allowance (X as a radius, Z), signed.
    pub allowance: P2,
    /// The roughing feed (None: the feed in force).
    pub feed: Option<f64>,
}

/// G71 (`cut` = 1: passes along Z at X levels) or G72 (`cut` = 0: passes along X at Z levels),
/// type I, from start point `a` (Fanuc 0i-TD, "Stock removal in turning (G71)" and "in facing
/// (G72)"): passes Δd apart from `a` towards the profile, each cut straight to the profile moved by
/// the allowance, the retract e at 45° away from it, back at rapid; then a pass along the moved
/// profile, and back to `a` at rapid. The profile must be monotonic on both axes (type I). Sources:
/// Robur, "Concise Guide Fanuc" p. 48 (the 45° retract at rapid, the pre-finishing pass along the
/// profile, the rapid return); the infeed as the first block moves it (G0 or G1).
pub fn stock_removal(
    a: P2,
    p: &Profile,
    cut: usize,
    d: &StockRemoval,
    budget: &fmsvm_block::OutputBudget,
) -> Result<Vec<Step>, fmsvm_block::Stop> {
    let name = if cut == 1 { "G71" } else { "G72" };
    let level_axis = 1 - cut;
    let Some(first) = p.segs.first() else {
        return Err(bad(format!(
            "{name}: the profile N{}–N{} has no move",
            p.ns, p.nf
        ))
        .into());
    };
    if !positive(d.depth) {
        return Err(bad(format!("{name}: the depth of cut must be above 0")).into());
    }
    if d.retract < 0.0 {
        return Err(bad(format!(
            "{name}: the retract R{} is negative (it would move into the stock)",
            d.retract
        ))
        .into());
    }
    if let Seg::Arc { .. } = first {
        return Err(bad(format!(
            "{name}: the profile's first block N{} is an arc (G0 or G1 leads into a profile)",
            p.ns
        ))
        .into());
    }
    if p.type_two {
        return crate::pockets::stock_removal(a, p, cut, d, name, budget);
    }
    let TypeOne {
        p0,
        end,
        infeed_rapid,
        out,
        along,
    } = type_one(a, p, cut, name)?;
    let rest = &p.segs[1..];
    let shift = d.allowance;
    let moved: Vec<Seg> = rest.iter().map(|s| s.shifted(shift)).collect();
    let m0 = [p0[0] + shift[0], p0[1] + shift[1]];
    let m_end = [end[0] + shift[0], end[1] + shift[1]];
    // The profile rises monotonically towards the start's side: its end is its extreme there,
    // and the start point may not lie inside it (Fanuc: "finishing shape over the starting
    // point"; the allowance may reach past it, as when the profile ends on the stock's diameter).
    if (a[level_axis] - end[level_axis]) * out < -1e-9 {
        return Err(bad(format!(
            "{name}: the start point {}{} lies inside the profile (which reaches {}{}){}: start the cycle outside the stock",
            ["X", "Z"][level_axis],
            a[level_axis],
            ["X", "Z"][level_axis],
            end[level_axis],
            [" (radius)", ""][level_axis]
        )).into());
    }
    let mut steps = Vec::new();
    let mut k = 1.0;
    loop {
        let level = a[level_axis] - out * k * d.depth;
        if (level - m0[level_axis]) * out <= 1e-9 {
            break;
        }
        // The cut ends on the moved profile, or at its end beyond its last point.
        let stop = if (level - m_end[level_axis]) * out >= 0.0 {
            m_end[cut]
        } else {
            crossing(m0, &moved, level_axis, level).unwrap_or(m_end[cut])
        };
        let at = |lv: f64, c: f64| -> P2 {
            let mut q = [0.0; 2];
            q[level_axis] = lv;
            q[cut] = c;
            q
        };
        // In at the level as the first block moves (G0 or G1), the cut, 45° out at rapid, back.
        steps.push(if infeed_rapid {
            Step::Rapid(at(level, a[cut]))
        } else {
            Step::Feed(at(level, a[cut]), d.feed)
        });
        steps.push(Step::Feed(at(level, stop), d.feed));
        steps.push(Step::Rapid(at(
            level + out * d.retract,
            stop - along * d.retract,
        )));
        steps.push(Step::Rapid(at(level + out * d.retract, a[cut])));
        // A long profile makes each pass's crossing long: the run's clock bounds the passes.
        budget.clock()?;
        k += 1.0;
        if k > 100_000.0 {
            return Err(bad(format!(
                "{name}: more than 100 000 passes (depth of cut {})",
                d.depth
            ))
            .into());
        }
    }
    // The last roughing pass: along the profile moved by the allowance (in as the first block).
    steps.push(if infeed_rapid {
        Step::Rapid(m0)
    } else {
        Step::Feed(m0, d.feed)
    });
    for seg in &moved {
        steps.push(seg.step(d.feed, true));
    }
    steps.push(Step::Rapid(a));
    Ok(steps)
}

/// A type I profile's shape, checked: its first point, its end, whether it is entered at rapid,
/// and which ways the stock lies (`out`, on the level axis) and the cuts go (`along`).
struct TypeOne {
    p0: P2,
    end: P2,
    infeed_rapid: bool,
    out: f64,
    along: f64,
}

/// Checks a type I profile of G71 (`cut` 1) or G72 (`cut` 0) from start point `a`: its first
/// block moves only the level axis, it lies beside the start point and is monotonic on both axes.
fn type_one(a: P2, p: &Profile, cut: usize, name: &str) -> Result<TypeOne, fmsvm_block::Stop> {
    let level_axis = 1 - cut;
    let Some(first) = p.segs.first() else {
        return Err(bad(format!(
            "{name}: the profile N{}–N{} has no move",
            p.ns, p.nf
        ))
        .into());
    };
    // Type I: the first block moves only the level axis (X for G71), from the start point.
    let p0 = first.to();
    if (p0[cut] - a[cut]).abs() > 1e-9 {
        return Err(bad(format!(
            "{name}: the profile's first block N{} moves {} (a type I profile's first block moves only {}; name both axes in it for type II)",
            p.ns,
            ["X", "Z"][cut],
            ["X", "Z"][level_axis]
        )).into());
    }
    let infeed_rapid = match *first {
        Seg::Line { rapid, .. } => rapid,
        Seg::Arc { .. } => {
            return Err(bad(format!(
                "{name}: the profile's first block N{} is an arc (G0 or G1 leads into a profile)",
                p.ns
            ))
            .into());
        }
    };
    let rest = p.segs.get(1..).unwrap_or_default();
    let end = p.segs.last().map_or(p0, Seg::to);
    // Which way the stock lies from the profile on the level axis, and which way the cuts go.
    let out = sign(a[level_axis] - p0[level_axis]);
    let along = sign(end[cut] - p0[cut]);
    if out == 0.0 || along == 0.0 {
        return Err(bad(format!(
            "{name}: the start point must lie outside the profile on {} and the profile must move along {}",
            ["X", "Z"][level_axis],
            ["X", "Z"][cut]
        )).into());
    }
    if !monotonic(p0, rest, level_axis, out) || !monotonic(p0, rest, cut, along) {
        return Err(bad(format!(
            "{name}: the profile N{}–N{} is not monotonic on X and Z (type I needs it)",
            p.ns, p.nf
        ))
        .into());
    }
    Ok(TypeOne {
        p0,
        end,
        infeed_rapid,
        out,
        along,
    })
}

/// The most passes of G73 (a bound on the moves one block makes).
pub const MAX_PATTERN_PASSES: u32 = 10_000;

/// The data of G73.
#[derive(Clone, Copy, Debug)]
pub struct PatternRepeating {
    /// The relief of the first pass beyond the last (X as a radius, Z): Δi, Δk.
    pub relief: P2,
    /// The number of passes d (≥ 1).
    pub passes: u32,
    /// The finishing allowance (X as a radius, Z), signed.
    pub allowance: P2,
    /// The feed (None: the feed in force).
    pub feed: Option<f64>,
}

/// G73 from start point `a`: `passes` copies of the profile, the first moved by relief + allowance,
/// the last by the allowance alone, the relief shrinking evenly; each pass moves as the profile's
/// blocks do (G0 G1 G2 G3) at the cycle's feed, then goes back to `a` at rapid (Fanuc 0i-TD,
/// "Pattern repeating (G73)"; the rapid back to the start point between passes is inferred: a clone
/// control's manual rapids to the next pass's start, which from the same side of the part is the
/// same point moved less).
pub fn pattern_repeating<'p>(
    a: P2,
    p: &'p Profile,
    d: &PatternRepeating,
) -> Result<impl Iterator<Item = Step> + 'p, Alarm> {
    if p.segs.is_empty() {
        return Err(bad(format!(
            "G73: the profile N{}–N{} has no move",
            p.ns, p.nf
        )));
    }
    if d.passes == 0 || d.passes > MAX_PATTERN_PASSES {
        return Err(bad(format!(
            "G73: the number of passes is 1 to 10 000, not {}",
            d.passes
        )));
    }
    // Made pass by pass as they are written, so that the run's limits (blocks, time, bytes) stop
    // a cycle of many passes over a long profile before it is made whole.
    let d = *d;
    Ok((1..=d.passes).flat_map(move |j| {
        let t = if d.passes == 1 {
            0.0
        } else {
            (d.passes - j) as f64 / (d.passes - 1) as f64
        };
        let off = [
            d.relief[0] * t + d.allowance[0],
            d.relief[1] * t + d.allowance[1],
        ];
        p.segs
            .iter()
            .map(move |seg| seg.shifted(off).step(d.feed, false))
            .chain(std::iter::once(Step::Rapid(a)))
    }))
}

/// The most moves one cycle block may make (a bound on memory and time).
const MAX_STEPS: usize = 1_000_000;

/// The data of G74 (pecks along Z, grooves side by side in X) or G75 (pecks along X, grooves along
/// Z).
#[derive(Clone, Copy, Debug)]
pub struct Pecking {
    /// The end point B (X radius, Z).
    pub end: P2,
    /// The depth of each peck Δ (G74 Q, G75 P), > 0.
    pub peck: f64,
    /// The shift between grooves (G74 P, G75 Q), ≥ 0.
    pub shift: f64,
    /// The retract after each peck e.
    pub retract: f64,
    /// The relief at the bottom Δd, ≥ 0 (away from the next groove).
    pub relief: f64,
    /// The feed (None: the feed in force).
    pub feed: Option<f64>,
}

/// G74 (`peck_axis` 1, Z) or G75 (`peck_axis` 0, X) from start point `a` (Fanuc 0i-TD, "End face
/// peck drilling cycle (G74)", "Outer diameter / internal diameter drilling cycle (G75)"): grooves
/// from `a` to the end point `shift` apart (the last one at the end); in each, pecks of `peck` at
/// the feed, each followed by a rapid retract of e, to the end's depth; then the relief Δd at the
/// feed (inferred: the manual's figure does not say the rate), back to the start level at rapid, the
/// shift at rapid; at last back to `a`.
pub fn pecking(a: P2, peck_axis: usize, d: &Pecking) -> Result<Vec<Step>, Alarm> {
    let name = if peck_axis == 1 { "G74" } else { "G75" };
    let k = peck_axis;
    let o = 1 - k;
    if !positive(d.peck) {
        return Err(bad(format!(
            "{name}: the depth of each peck must be above 0"
        )));
    }
    if d.retract < 0.0 {
        return Err(bad(format!(
            "{name}: the retract R{} is negative (it would move into the hole's bottom)",
            d.retract
        )));
    }
    let dir = sign(d.end[k] - a[k]);
    let side = sign(d.end[o] - a[o]);
    if side != 0.0 && !positive(d.shift) {
        return Err(bad(format!(
            "{name}: the grooves go from {} to {}: give the shift between them",
            a[o], d.end[o]
        )));
    }
    let at = |peck: f64, other: f64| -> P2 {
        let mut q = [0.0; 2];
        q[k] = peck;
        q[o] = other;
        q
    };
    let depth = (d.end[k] - a[k]).abs();
    let pecks = (depth / d.peck).ceil().max(1.0);
    let grooves = if side == 0.0 {
        1.0
    } else {
        ((d.end[o] - a[o]).abs() / d.shift).ceil() + 1.0
    };
    if pecks * grooves * 2.0 > MAX_STEPS as f64 {
        return Err(bad(format!(
            "{name}: {pecks} pecks in each of {grooves} grooves: more than {MAX_STEPS} moves"
        )));
    }
    let mut steps = Vec::new();
    let mut g = 0.0;
    loop {
        let pos = if side == 0.0 {
            a[o]
        } else if ((d.end[o] - a[o]).abs()) <= g * d.shift {
            d.end[o]
        } else {
            a[o] + side * g * d.shift
        };
        steps.push(Step::Rapid(at(a[k], pos)));
        let mut reached = 0.0;
        loop {
            reached = (reached + d.peck).min(depth);
            steps.push(Step::Feed(at(a[k] + dir * reached, pos), d.feed));
            if reached >= depth {
                break;
            }
            steps.push(Step::Rapid(at(
                a[k] + dir * (reached - d.retract).max(0.0),
                pos,
            )));
        }
        let off = pos - side * d.relief.abs();
        if d.relief != 0.0 {
            steps.push(Step::Feed(at(d.end[k], off), d.feed));
        }
        steps.push(Step::Rapid(at(a[k], off)));
        if side == 0.0 || pos == d.end[o] {
            break;
        }
        g += 1.0;
    }
    steps.push(Step::Rapid(a));
    Ok(steps)
}

/// The data of G76.
#[derive(Clone, Copy, Debug)]
pub struct Threading {
    /// The end point at full depth (X radius, Z).
    pub end: P2,
    /// The taper i: the thread's radius at the start minus at the end.
    pub taper: f64,
    /// The thread's height k (radius).
    pub height: f64,
    /// The depth of the first pass Δd (radius).
    pub first: f64,
    /// The least depth of a pass Δdmin.
    pub least: f64,
    /// The finishing allowance d.
    pub allowance: f64,
    /// The number of finishing passes m (≥ 1).
    pub finishing: u32,
    /// The tool's angle a, degrees (the infeed runs along its flank).
    pub angle: f64,
    /// The lead L.
    pub lead: f64,
}

/// How far (radius, mm) a thread's start point must lie outside its crest: every pass returns
/// at the start's X, so a start on the crest would run back along the finished thread. fmsvm's
/// stated minimum (the Fanuc manuals draw the start point outside the thread and give no figure),
/// the 0.5 mm a roughing pass retracts by (`cycle_moves::RETRACT`).
pub const THREAD_CLEARANCE: f64 = 0.5;

/// G76 from start point `a` (Fanuc 0i-TD, "Multiple threading cycle (G76)"): passes at depths
/// Δd·√n (n = 1, 2, …, each at least Δdmin deeper than the last) down to k − d, then m finishing
/// passes at k. A pass: the start Z moved along the flank by depth·tan(a/2) towards the cut (single
/// edge infeed; the direction inferred, as LinuxCNC's G76 with a positive Q), rapid there at the
/// start X, rapid in to the depth, the thread to the end Z, rapid out to the start X, rapid back to
/// `a`. No end chamfer (r = 0). Only the thread is at the lead; the rest is rapid.
pub fn threading(a: P2, d: &Threading) -> Result<Vec<Step>, Alarm> {
    let out = sign(a[0] - d.end[0]);
    let along = sign(d.end[1] - a[1]);
    if out == 0.0 || along == 0.0 {
        return Err(bad(
            "G76: the start point must lie off the thread in X and before its end in Z".into(),
        ));
    }
    if !(positive(d.height) && positive(d.first) && positive(d.lead)) {
        return Err(bad(
            "G76: the thread height P, the first depth Q and the lead F must be above 0".into(),
        ));
    }
    if d.least < 0.0 || d.allowance < 0.0 {
        return Err(bad(format!(
            "G76: the least depth Q{} and the finishing allowance R{} of the first block may not be negative",
            d.least, d.allowance
        )));
    }
    if ![0.0, 29.0, 30.0, 55.0, 60.0, 80.0].contains(&d.angle) {
        return Err(bad(format!(
            "G76: the tool angle a = {} (P's last two digits) is one of 80, 60, 55, 30, 29, 00",
            d.angle
        )));
    }
    if d.allowance >= d.height {
        return Err(bad(format!(
            "G76: the finishing allowance R{} is not below the thread height {}",
            d.allowance, d.height
        )));
    }
    // Every pass goes back out to the start's X: the start must lie outside the thread's crest
    // (its root moved out by the height) at both ends by THREAD_CLEARANCE, or the way out runs
    // along (or through) the thread.
    let span_z = d.end[1] - a[1];
    for z in [a[1], d.end[1]] {
        let crest = d.end[0] + d.taper * (d.end[1] - z) / span_z + out * d.height;
        if (a[0] - crest) * out < THREAD_CLEARANCE - 1e-9 {
            return Err(bad(format!(
                "G76: the start point X{} (radius) is not {THREAD_CLEARANCE} mm outside the thread, whose crest is at X{} (radius) at Z{z}: every pass returns at the start's X, so start the cycle at least {THREAD_CLEARANCE} mm (radius) clear of the crest",
                a[0], crest
            )));
        }
    }
    let mut depths = Vec::new();
    let rough = d.height - d.allowance;
    let mut last = 0.0f64;
    let mut n = 1.0f64;
    while last < rough - 1e-12 {
        let mut next = d.first * n.sqrt();
        if next - last < d.least {
            next = last + d.least;
        }
        next = next.min(rough);
        depths.push(next);
        last = next;
        n += 1.0;
        if depths.len() > 10_000 {
            return Err(bad(format!(
                "G76: more than 10 000 passes (first depth {}, least {})",
                d.first, d.least
            )));
        }
    }
    for _ in 0..d.finishing.max(1) {
        depths.push(d.height);
    }
    let tan = (d.angle.to_radians() / 2.0).tan();
    let span = d.end[1] - a[1];
    let mut steps = Vec::with_capacity(depths.len() * 5);
    for depth in depths {
        let zs = a[1] + along * depth * tan;
        // The thread's X at Z `z` at this depth: the taper line, `k − depth` off the root.
        let x_at = |z: f64| d.end[0] + d.taper * (d.end[1] - z) / span + out * (d.height - depth);
        steps.push(Step::Rapid([a[0], zs]));
        steps.push(Step::Rapid([x_at(zs), zs]));
        steps.push(Step::Thread([x_at(d.end[1]), d.end[1]], d.lead));
        steps.push(Step::Rapid([a[0], d.end[1]]));
        steps.push(Step::Rapid(a));
    }
    Ok(steps)
}
