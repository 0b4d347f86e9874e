//! A cycle record in elementary moves (docs/postprocessor.md, "Elementary moves"): the kernel's
//! turning cycles (G71/G72 stock removal, G73 pattern repeating, G74 pecking, G76 threading) run
//! with the record's parameters by the roles the control's catalogue gives them, from the cycle's
//! start point back to it. Coordinates are (X as a radius, Z); the neutral language's X is a
//! diameter.

use fmsvm_canon::arcs::CentreWords;
use fmsvm_kernel::turning::{
    self, AxisWord, BlockCodes, P2, Pecking, Profile, ProfileBlock, ProfileBlocks, Seg, Step,
    StockRemoval, sign,
};

use fmsvm_driver::catalogue::{MachineCycle, Scheme};
use fmsvm_driver::neutral::{Cycle, Plain};

/// One elementary move (X as a radius): the kernel's turning step (a profile block's S and T,
/// `Step::Codes`, are not part of a cycle's path and never come out of here).
pub type Move = Step;

/// The retract after each roughing pass or peck when the record gives none: fmsvm's choice, 0.5 mm
/// (the value shops commonly set in Fanuc's parameters 5133 and 5139, which have no factory value).
pub const RETRACT: f64 = 0.5;

/// A thread's first depth of cut when the record gives none: the height over √8, so that the
/// Δd·√n rule reaches the full height in about eight passes. fmsvm's choice.
const THREAD_PASSES: f64 = 8.0;

/// A thread's least depth of cut when the record gives none (mm), fmsvm's choice.
const THREAD_LEAST: f64 = 0.05;

/// How far the library's numbers (two decimals) may miss each other: an arc's end off its circle,
/// a figure's corner off the start's line.
const TOLERANCE: f64 = 0.01;

/// The path of cycle `c` (the control's `m`) from `start` back to it; `spindle` is the direction
/// the spindle turns (3 or 4) if it turns.
pub fn path(
    c: &Cycle,
    m: &MachineCycle,
    start: P2,
    spindle: Option<u8>,
) -> Result<Vec<Move>, String> {
    let Some(scheme) = m.moves else {
        return Err(format!(
            "CYCLE {}: the catalogue does not say how to write it in elementary moves (moves = …)",
            c.number
        ));
    };
    let r = Record { c, m };
    let moves = match scheme {
        Scheme::Turning => r.stock_removal(start, 1)?,
        Scheme::Facing => r.stock_removal(start, 0)?,
        Scheme::Pattern => r.pattern(start)?,
        Scheme::Drilling => r.drilling(start)?,
        Scheme::Threading => r.threading(start)?,
        Scheme::Tapping => r.tapping(start, spindle)?,
    };
    // The continuity rule of the library: a cycle ends where it started.
    let end = moves.iter().rev().find_map(Move::to).unwrap_or(start);
    if (end[0] - start[0]).abs() > 1e-6 || (end[1] - start[1]).abs() > 1e-6 {
        return Err(format!(
            "CYCLE {}: its path ends at X{} Z{}, not at its start X{} Z{} (a defect of fmsvm: please report it)",
            c.number,
            end[0] * 2.0,
            end[1],
            start[0] * 2.0,
            start[1]
        ));
    }
    Ok(moves)
}

/// The side of the stock from the profile, `[x, z]` each +1 or -1 (a bore: X -1), for a turning
/// cycle whose figure fmsvm can build.
pub fn stock_side(c: &Cycle, m: &MachineCycle, start: P2) -> Option<[f64; 2]> {
    let level = match m.moves? {
        Scheme::Turning | Scheme::Pattern => 0,
        Scheme::Facing => 1,
        _ => return None,
    };
    let r = Record { c, m };
    let p = r.profile(start, level).ok()?;
    Some(sides(start, &p, level))
}

/// Which way the stock lies from the profile (each +1 or -1): on the level axis (X for turning)
/// from the figure's begin towards the start (Fanuc's G71: the passes go from the start towards
/// the profile's first point), on the other from the profile's end towards the start.
fn sides(start: P2, p: &Profile, level: usize) -> P2 {
    let begin = p.segs.first().map_or(start, Seg::to);
    let end = p.segs.last().map_or(start, Seg::to);
    let mut s = [1.0; 2];
    s[level] = if start[level] < begin[level] {
        -1.0
    } else {
        1.0
    };
    let cut = 1 - level;
    s[cut] = if start[cut] < end[cut] { -1.0 } else { 1.0 };
    s
}

/// Whether a stock-removal record's profile has pockets (Fanuc's type II): the level axis (X for
/// turning, Z for facing) goes back on itself along the profile from the figure's begin. Such a
/// profile's first block names both axes (0i-TD G71/G72: "type II … the first block specifies
/// both X(U) and Z(W)"), in fmsvm's model and in the control's block alike. Judged by the blocks'
/// end points.
pub fn type_two(c: &Cycle, m: &MachineCycle) -> bool {
    let (letter, begin) = match m.moves {
        Some(Scheme::Turning) => ('X', "_Xbegin"),
        Some(Scheme::Facing) => ('Z', "_Zbegin"),
        _ => return false,
    };
    let Some(begin) = c.param(begin) else {
        return false;
    };
    let mut at = begin.value;
    let mut way = 0.0;
    for v in c.profile.iter().filter_map(|b| b.get(letter)) {
        let d = v - at;
        if d.abs() > TOLERANCE {
            if way != 0.0 && d.signum() != way {
                return true;
            }
            way = d.signum();
            at = v;
        }
    }
    false
}

/// A record read through its catalogue entry.
struct Record<'a> {
    c: &'a Cycle,
    m: &'a MachineCycle,
}

impl Record<'_> {
    /// The value of the parameter with `role`: the record's, or the catalogue's default.
    fn role(&self, role: &str) -> Option<f64> {
        let p = self
            .m
            .parameters
            .iter()
            .find(|p| p.role.as_deref() == Some(role))?;
        match self.c.param(&p.name) {
            Some(v) => Some(v.value),
            None => p.default.as_ref()?.trim().parse().ok(),
        }
    }

    /// The value of the parameter with `role`, which must be above 0 (or at least 0: `zero`).
    fn positive(&self, role: &str, zero: bool) -> Result<Option<f64>, String> {
        match self.role(role) {
            Some(v) if v > 0.0 || (zero && v == 0.0) => Ok(Some(v)),
            Some(v) => Err(self.bad(format!(
                "{} = {v}: {}",
                self.named(role),
                if zero { "not negative" } else { "above 0" }
            ))),
            None => Ok(None),
        }
    }

    /// The designation of the parameter with `role`, for messages.
    fn named(&self, role: &str) -> String {
        self.m
            .parameters
            .iter()
            .find(|p| p.role.as_deref() == Some(role))
            .map_or_else(|| format!("(the {role})"), |p| p.name.clone())
    }

    /// An environment variable the library must give (`_Xend`).
    fn env(&self, name: &str) -> Result<f64, String> {
        self.c.param(name).map(|p| p.value).ok_or_else(|| {
            format!(
                "CYCLE {}: the record has no {name}, which its elementary moves need",
                self.c.number
            )
        })
    }

    /// A count (passes, starts) from a parameter's value.
    fn count(&self, role: &str, v: f64) -> Result<u32, String> {
        // A thread's finishing passes are two digits on the controls that take them (the 0i-TD's
        // m, 01–99); passes of a roughing cycle up to 10 000.
        let most = if role == "finish_passes" {
            99.0
        } else {
            10_000.0
        };
        if v.fract() != 0.0 || !(1.0..=most).contains(&v) {
            return Err(format!(
                "CYCLE {}: {} = {v}: a whole number from 1 to {}",
                self.c.number,
                self.named(role),
                if most == 99.0 { "99" } else { "10 000" }
            ));
        }
        Ok(v as u32)
    }

    fn bad(&self, what: String) -> String {
        format!("CYCLE {}: {what}", self.c.number)
    }

    /// The profile from `start`: a rapid infeed along the level axis to the figure's begin
    /// (`_Xbegin`, `_Zbegin`), then the profile blocks.
    fn profile(&self, start: P2, level: usize) -> Result<Profile, String> {
        let begin = [self.env("_Xbegin")? / 2.0, self.env("_Zbegin")?];
        let cut = 1 - level;
        if (begin[cut] - start[cut]).abs() > TOLERANCE {
            let (name, v, s) = if cut == 1 {
                ("_Zbegin", begin[1], start[1])
            } else {
                ("_Xbegin", begin[0] * 2.0, start[0] * 2.0)
            };
            return Err(self.bad(format!(
                "the figure starts at {name}={v}, off the cycle's start ({s}): the passes run from the start point along the figure"
            )));
        }
        let mut axes = [None, None];
        axes[level] = Some(AxisWord::Abs(begin[level]));
        // The library's profile starts at the figure's begin; one that moves there itself (a
        // first block on the level axis alone, at the begin) needs no infeed before it.
        let letter = if level == 0 { 'X' } else { 'Z' };
        let scale = if level == 0 { 0.5 } else { 1.0 };
        let has_infeed = self.c.profile.first().is_some_and(|b| {
            b.get(letter)
                .is_some_and(|v| (v * scale - begin[level]).abs() < TOLERANCE)
                && b.get(if level == 0 { 'Z' } else { 'X' }).is_none()
        });
        // A profile with pockets: its first block names both axes (type II).
        let pockets = type_two(self.c, self.m);
        if pockets {
            axes[cut] = Some(AxisWord::Abs(begin[cut]));
        }
        let mut blocks = Vec::new();
        if !has_infeed {
            blocks.push(ProfileBlock {
                motion: 0,
                axes,
                centre: None,
                corner: None,
            });
        }
        let mut motion = 1u8;
        for b in &self.c.profile {
            if let Some(g) = b.words.iter().find(|w| w.letter == 'G' && w.value <= 3.0) {
                motion = g.value as u8;
            }
            if let Some(mut block) = profile_block(b, motion) {
                if pockets && blocks.is_empty() {
                    block.axes[cut] = Some(AxisWord::Abs(begin[cut]));
                }
                if block.motion >= 2 && block.centre.is_none() {
                    return Err(format!(
                        "line {}: an arc (G0{}) in the profile without I K or R",
                        b.line, block.motion
                    ));
                }
                blocks.push(block);
            }
        }
        let n = blocks.len();
        let mut numbers = self.c.profile.iter().filter_map(|b| b.n);
        ProfileBlocks {
            ns: numbers.clone().next().or(self.c.n).unwrap_or(0),
            nf: numbers.next_back().or(self.c.n).unwrap_or(0),
            blocks,
            codes: vec![BlockCodes::default(); n],
        }
        .resolve(start, TOLERANCE)
        .map_err(|a| self.bad(a.message.to_string()))
    }

    /// The finishing allowance (X radius, Z), signed towards the start (the stock's side).
    fn allowance(&self, start: P2, p: &Profile, level: usize) -> Result<P2, String> {
        let s = sides(start, p, level);
        let side = |k: usize| s[k];
        Ok([
            self.positive("allowance_x", true)?.unwrap_or(0.0) / 2.0 * side(0),
            self.positive("allowance_z", true)?.unwrap_or(0.0) * side(1),
        ])
    }

    /// The cutting feed (role `feed`), above 0, or the feed in force.
    fn feed(&self) -> Result<Option<f64>, String> {
        self.positive("feed", false)
    }

    /// Turning (`cut` 1) or facing (`cut` 0): Fanuc's G71/G72 type I passes, then the finishing
    /// passes that take the allowance off.
    fn stock_removal(&self, start: P2, cut: usize) -> Result<Vec<Move>, String> {
        let level = 1 - cut;
        let p = self.profile(start, level)?;
        self.plan_angle(start, &p, cut)?;
        let stock = (start[level] - p.segs[0].to()[level]).abs();
        let depth = match (self.positive("depth", false)?, self.role("passes")) {
            (Some(d), _) => d,
            (_, Some(n)) => stock / f64::from(self.count("passes", n)?),
            (None, None) => {
                return Err(self.bad(format!(
                    "give the depth of cut {} or the number of passes {}",
                    self.named("depth"),
                    self.named("passes")
                )));
            }
        };
        let allowance = self.allowance(start, &p, level)?;
        let feed = self.feed()?;
        let data = StockRemoval {
            depth,
            retract: self.positive("retract", true)?.unwrap_or(RETRACT),
            allowance,
            feed,
        };
        let mut steps =
            turning::stock_removal(start, &p, cut, &data, &fmsvm_block::OutputBudget::default())
                .map_err(|s| match s {
                    fmsvm_block::Stop::Alarm(a) => self.bad(a.message.to_string()),
                    other => self.bad(other.to_string()),
                })?;
        self.finishing(start, &p, allowance, feed, &mut steps)?;
        Ok(steps
            .iter()
            .filter(|s| !matches!(s, Step::Codes { .. }))
            .copied()
            .collect())
    }

    /// The finishing passes (role `finish_passes`), each along the profile moved by what is left
    /// of the allowance, the last on the profile itself.
    fn finishing(
        &self,
        start: P2,
        p: &Profile,
        allowance: P2,
        feed: Option<f64>,
        steps: &mut Vec<Step>,
    ) -> Result<(), String> {
        let Some(n) = self.role("finish_passes") else {
            return Ok(());
        };
        if n == 0.0 || allowance == [0.0, 0.0] {
            return Ok(());
        }
        let n = self.count("finish_passes", n)?;
        for j in 1..=n {
            let left = f64::from(n - j) / f64::from(n);
            let moved = Profile {
                segs: p
                    .segs
                    .iter()
                    .map(|s| s.shifted([allowance[0] * left, allowance[1] * left]))
                    .collect(),
                ..p.clone()
            };
            steps.extend(turning::finishing(start, &moved, feed));
        }
        Ok(())
    }

    /// The tool's main angle in plan (role `plan_angle`): a wall of the profile that rises towards
    /// the stock's side steeper than it, measured from the feed's direction, cannot be cut by the
    /// tool's main edge (B.3's "the tool's plan angle respected"). Lines and both ends of each arc.
    fn plan_angle(&self, start: P2, p: &Profile, cut: usize) -> Result<(), String> {
        let Some(kappa) = self.role("plan_angle") else {
            return Ok(());
        };
        let level = 1 - cut;
        let Some(first) = p.segs.first() else {
            return Ok(());
        };
        let end = p.segs.last().map_or(start, Seg::to);
        let feed_dir = sign(end[cut] - first.to()[cut]);
        let stock_dir = sign(start[level] - first.to()[level]);
        let mut from = first.to();
        for (k, seg) in p.segs.iter().enumerate().skip(1) {
            let to = seg.to();
            let tangents: Vec<P2> = match *seg {
                Seg::Line { .. } => vec![[to[0] - from[0], to[1] - from[1]]],
                Seg::Arc { centre, .. } => {
                    let chord = [to[0] - from[0], to[1] - from[1]];
                    [from, to]
                        .iter()
                        .map(|q| {
                            let t = [-(q[1] - centre[1]), q[0] - centre[0]];
                            if t[0] * chord[0] + t[1] * chord[1] < 0.0 {
                                [-t[0], -t[1]]
                            } else {
                                t
                            }
                        })
                        .collect()
                }
            };
            for t in tangents {
                let rise = t[level] * stock_dir;
                if rise <= 1e-9 {
                    continue;
                }
                let angle = rise.atan2(t[cut] * feed_dir).to_degrees();
                if angle > kappa + 0.01 {
                    return Err(self.bad(format!(
                        "the profile's move {k} rises {angle:.1}° from the feed's direction, steeper than the tool's plan angle {} = {kappa}°: the tool cannot cut it",
                        self.named("plan_angle")
                    )));
                }
            }
            from = to;
        }
        Ok(())
    }

    /// Pattern repeating: Fanuc's G73.
    fn pattern(&self, start: P2) -> Result<Vec<Move>, String> {
        let p = self.profile(start, 0)?;
        let passes = match self.role("passes") {
            Some(n) => self.count("passes", n)?,
            None => {
                return Err(self.bad(format!(
                    "give the number of passes {}",
                    self.named("passes")
                )));
            }
        };
        let allowance = self.allowance(start, &p, 0)?;
        let relief = [
            self.positive("relief_x", true)?.unwrap_or(0.0) * sign_or_one(allowance[0]),
            self.positive("relief_z", true)?.unwrap_or(0.0) * sign_or_one(allowance[1]),
        ];
        let feed = self.feed()?;
        let data = turning::PatternRepeating {
            relief,
            passes,
            allowance,
            feed,
        };
        // Made as they are taken: past the output's most blocks it is refused before it is whole.
        let mut steps: Vec<Step> = turning::pattern_repeating(start, &p, &data)
            .map_err(|a| self.bad(a.message.to_string()))?
            .take(crate::MAX_BLOCKS + 1)
            .collect();
        if steps.len() > crate::MAX_BLOCKS {
            return Err(self.bad(format!(
                "{passes} passes of the profile make more than {} blocks, the most one output takes",
                crate::MAX_BLOCKS
            )));
        }
        self.finishing(start, &p, allowance, feed, &mut steps)?;
        Ok(steps
            .iter()
            .filter(|s| !matches!(s, Step::Codes { .. }))
            .copied()
            .collect())
    }

    /// The hole's start at feed (`_Zbegin`, else the start) and end (`_Zend`), on the axis.
    fn hole(&self, start: P2) -> Result<(f64, f64), String> {
        if start[0].abs() > 1e-6 {
            return Err(self.bad(format!(
                "a hole on the spindle's axis is drilled or tapped from X0, and the cycle starts at X{}",
                start[0] * 2.0
            )));
        }
        let zb = self.c.param("_Zbegin").map_or(start[1], |p| p.value);
        let ze = self.env("_Zend")?;
        if (ze - zb).abs() < 1e-9 {
            return Err(self.bad("_Zend is _Zbegin: the hole has no depth".into()));
        }
        // The approach from the start to `_Zbegin` runs the way the hole does, never back from it.
        if (zb - start[1]).abs() > 1e-9 && sign(ze - zb) != sign(zb - start[1]) {
            return Err(self.bad(format!(
                "the cycle starts at Z{} beyond the hole's start _Zbegin={zb}, on the side of its end",
                start[1]
            )));
        }
        Ok((zb, ze))
    }

    /// Drilling: Fanuc's G74 pecks on the axis from `_Zbegin` to `_Zend`.
    fn drilling(&self, start: P2) -> Result<Vec<Move>, String> {
        let (zb, ze) = self.hole(start)?;
        let depth = (ze - zb).abs();
        if let Some(d) = self.c.param("_D")
            && d.value <= 0.0
        {
            return Err(self.bad(format!("_D={}: the drill's diameter is above 0", d.text)));
        }
        let data = Pecking {
            end: [0.0, ze],
            peck: self.positive("peck", false)?.unwrap_or(depth),
            shift: 0.0,
            retract: self.positive("retract", true)?.unwrap_or(RETRACT),
            relief: 0.0,
            feed: self.feed()?,
        };
        let mut moves = vec![Move::Rapid([0.0, zb])];
        let steps =
            turning::pecking([0.0, zb], 1, &data).map_err(|a| self.bad(a.message.to_string()))?;
        moves.extend(
            steps
                .iter()
                .filter(|s| !matches!(s, Step::Codes { .. }))
                .copied(),
        );
        moves.push(Move::Rapid(start));
        Ok(moves)
    }

    /// The number of starts (`_NTHREADS`): one, as the kernel threads.
    fn single_start(&self) -> Result<(), String> {
        match self.c.param("_NTHREADS") {
            Some(p) if p.value != 1.0 => Err(self.bad(format!(
                "_NTHREADS={}: a thread of several starts is not yet written in elementary moves",
                p.text
            ))),
            _ => Ok(()),
        }
    }

    /// Threading: Fanuc's G76 passes from the start to the root (`_Xend`, `_Zend`) of a thread
    /// `_DEPTH` high with lead `_FEED`.
    fn threading(&self, start: P2) -> Result<Vec<Move>, String> {
        self.single_start()?;
        let lead = self.env("_FEED")?;
        let height = self.env("_DEPTH")?;
        let end = [self.env("_Xend")? / 2.0, self.env("_Zend")?];
        let begin_x = self.c.param("_Xbegin").map_or(end[0], |p| p.value / 2.0);
        let data = turning::Threading {
            end,
            taper: begin_x - end[0],
            height,
            first: self
                .positive("first_depth", false)?
                .unwrap_or(height / THREAD_PASSES.sqrt()),
            least: self.positive("least_depth", true)?.unwrap_or(THREAD_LEAST),
            allowance: self.positive("thread_allowance", true)?.unwrap_or(0.0),
            finishing: match self.role("finish_passes") {
                Some(n) => self.count("finish_passes", n)?,
                None => 1,
            },
            angle: self.role("tool_angle").unwrap_or(0.0),
            lead,
        };
        let steps =
            turning::threading(start, &data).map_err(|a| self.bad(a.message.to_string()))?;
        Ok(steps
            .iter()
            .filter(|s| !matches!(s, Step::Codes { .. }))
            .copied()
            .collect())
    }

    /// Tapping (or a die): in along the axis at the lead, the spindle reversed, out again, the
    /// spindle turned back.
    fn tapping(&self, start: P2, spindle: Option<u8>) -> Result<Vec<Move>, String> {
        self.single_start()?;
        let lead = self.env("_FEED")?;
        let (zb, ze) = self.hole(start)?;
        let Some(turn) = spindle else {
            return Err(
                self.bad("the spindle must turn (M03 or M04) before a tap or a die goes in".into())
            );
        };
        let back = if turn == 3 { 4 } else { 3 };
        Ok(vec![
            Move::Rapid([0.0, zb]),
            Move::Thread([0.0, ze], lead),
            Move::Spindle(back),
            Move::Thread([0.0, zb], lead),
            Move::Spindle(turn),
            Move::Rapid(start),
        ])
    }
}

/// A neutral profile block as the kernel's profile block (X a diameter there, a radius here); None
/// for a block that does not move.
fn profile_block(b: &Plain, motion: u8) -> Option<ProfileBlock> {
    let x = b.get('X').map(|v| AxisWord::Abs(v / 2.0));
    let z = b.get('Z').map(AxisWord::Abs);
    if x.is_none() && z.is_none() {
        return None;
    }
    let centre = match (b.get('R'), b.get('I'), b.get('K')) {
        (Some(r), _, _) => Some(CentreWords::Radius(r)),
        (None, None, None) => None,
        (None, i, k) => Some(CentreWords::Offsets([
            i.unwrap_or(0.0),
            0.0,
            k.unwrap_or(0.0),
        ])),
    };
    Some(ProfileBlock {
        motion,
        axes: [x, z],
        centre: if motion >= 2 { centre } else { None },
        corner: None,
    })
}

fn sign_or_one(v: f64) -> f64 {
    if v < 0.0 { -1.0 } else { 1.0 }
}
