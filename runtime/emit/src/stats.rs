//! Statistics of a program's motion, read from its canonical operations as they stream past: counts by
//! kind, rapid and feed lengths, the bounding box, estimated machining time and tool changes, in constant
//! memory (no move is kept).
//!
//! Rules of the estimate (what `fmsvm stats` reports):
//! - Lengths are of the X Y Z path: lines by their chord, arcs by their true length (a helix's rise
//!   included). A move of the rotary axes A B C alone has no length.
//! - Feed moves take their length at F (units/min). Under G95 (F per revolution) the rate is F × S; with
//!   no spindle speed (S0 or none yet) the move is left out of the time and counted in `untimed_feeds`,
//!   as is a feed move with no F. A feed move of the rotary axes alone takes its largest rotary travel
//!   (degrees) at F, as a control reads F in degrees/min for such a move.
//! - Rapids take their length at the rapid rate (mm/min, given to [`Stats::finish`]): a straight
//!   interpolated rapid, as the run's #3001 clock has it. Rotary-only rapids take no time.
//! - Under constant surface speed (a lathe's G96 S, m/min or ft/min) the spindle turns at
//!   1000·V/(π·D) rev/min (12·V/(π·D) in inch) at the tool's diameter D = 2·|X|, up to the clamp (G50 S);
//!   a per-revolution feed move takes ∫ ds / (F·n) along its path: exact for a straight move (the
//!   integrand is piecewise linear in the radius), 64 pieces for an arc. A thread (G32) moves its
//!   lead a revolution.
//! - Dwells add their seconds. Tool changes, M codes and the spindle's acceleration add nothing.
//! - A tool change is an M6. A program that has no M6 at all (a lathe's turret, indexed by T alone)
//!   changes tool at every T that selects a tool other than the one before.
//! - The bounding box holds every point of every move, the start of each included: an arc adds the
//!   axis-extreme points it passes, not only its ends.
//! - Everything is measured in mm and reported in the units of the first move (G20 inch or G21 mm);
//!   a program that changes units on the way is converted, not mixed.

use fmsvm_canon::{Arc, Canon, Pose, travel};

/// Millimetres in an inch.
pub const MM_PER_INCH: f64 = 25.4;

/// An axis-aligned box of the six axes.
#[derive(Clone, Copy, PartialEq, Debug)]
pub struct Bounds {
    /// The least value of each axis X Y Z A B C.
    pub min: Pose,
    /// The greatest value of each axis.
    pub max: Pose,
}

impl Default for Bounds {
    fn default() -> Self {
        Bounds::EMPTY
    }
}

impl Bounds {
    /// The box that holds nothing (every minimum +∞, every maximum −∞).
    pub const EMPTY: Bounds = Bounds {
        min: [f64::INFINITY; 6],
        max: [f64::NEG_INFINITY; 6],
    };

    /// Whether nothing was added.
    pub fn is_empty(&self) -> bool {
        (0..6).all(|i| self.min[i] > self.max[i])
    }

    /// Grows the box to hold `p`.
    #[inline]
    pub fn add(&mut self, p: &Pose) {
        for (i, v) in p.iter().enumerate() {
            self.min[i] = self.min[i].min(*v);
            self.max[i] = self.max[i].max(*v);
        }
    }

    /// Grows the box to hold the whole of `arc` from `from`: both ends and each point where the arc
    /// passes an extreme of its plane's axes (0°, 90°, 180°, 270° about the centre). The normal axis and
    /// A B C move linearly, so their ends bound them.
    pub fn add_arc(&mut self, from: &Pose, arc: &Arc) {
        self.add(from);
        self.add(&arc.to);
        let (r, sweep) = arc.sweep(from);
        let (a, b, _) = arc.plane.axes();
        let [ca, cb] = arc.centre;
        let start = (from[b] - cb).atan2(from[a] - ca);
        for k in 0..4 {
            let theta = k as f64 * std::f64::consts::FRAC_PI_2;
            let turned = if arc.clockwise {
                start - theta
            } else {
                theta - start
            };
            if turned.rem_euclid(std::f64::consts::TAU) <= sweep {
                let (s, c) = theta.sin_cos();
                let mut p = *from;
                p[a] = ca + r * c;
                p[b] = cb + r * s;
                // Only the plane's two axes are extended by this point.
                for i in [a, b] {
                    self.min[i] = self.min[i].min(p[i]);
                    self.max[i] = self.max[i].max(p[i]);
                }
            }
        }
    }

    /// The box with X Y Z multiplied by `k` (A B C are degrees and stay).
    pub fn scaled(&self, k: f64) -> Bounds {
        let mut b = *self;
        for i in 0..3 {
            b.min[i] *= k;
            b.max[i] *= k;
        }
        b
    }
}

/// `p` in mm: X Y Z multiplied by 25.4 when `inch`.
#[inline]
pub fn to_mm(p: &Pose, inch: bool) -> Pose {
    let mut q = *p;
    if inch {
        for v in &mut q[..3] {
            *v *= MM_PER_INCH;
        }
    }
    q
}

/// `arc` in mm (its end and centre; the centre's axes are linear axes in every plane).
#[inline]
pub fn arc_to_mm(arc: &Arc, inch: bool) -> Arc {
    let mut a = *arc;
    if inch {
        a.to = to_mm(&arc.to, true);
        a.centre = [arc.centre[0] * MM_PER_INCH, arc.centre[1] * MM_PER_INCH];
    }
    a
}

/// The running statistics of one program (see the module's rules).
#[derive(Clone, Debug)]
pub struct Stats {
    /// Where the tool is, mm.
    at: Pose,
    /// G20 in force.
    inch: bool,
    /// The units of the first move: the report's.
    report_inch: Option<bool>,
    /// F as programmed, in the units in force.
    feed: f64,
    /// G95 in force.
    per_rev: bool,
    /// S, rev/min.
    speed: f64,
    /// Constant surface speed in force (m/min, ft/min under G20).
    css: Option<f64>,
    /// The spindle's speed limit, rev/min.
    clamp: Option<f64>,
    /// A turning program: X in diameter (true) or radius in the report.
    turning: Option<bool>,
    /// The last T.
    tool: Option<f64>,
    rapids: u64,
    feeds: u64,
    arcs: u64,
    dwells: u64,
    m_codes: u64,
    comments: u64,
    m6: u64,
    t_changes: u64,
    untimed_feeds: u64,
    /// mm.
    rapid_length: f64,
    /// mm, lines and arcs.
    feed_length: f64,
    /// mm, arcs alone.
    arc_length: f64,
    /// mm never timed.
    untimed_length: f64,
    feed_seconds: f64,
    dwell_seconds: f64,
    /// mm.
    bounds: Bounds,
    /// The run's limits, a move a block.
    budget: fmsvm_block::OutputBudget,
    /// The positions the output's dialect can write (alarm 0003 past them, as `run --resolve`).
    reach: crate::dialect::Reach,
}

impl Default for Stats {
    fn default() -> Self {
        Stats::new([0.0; 6])
    }
}

/// What [`Stats::finish`] reports. Lengths and the box are in inches when `inch`, else mm; times in
/// seconds.
#[derive(Clone, Copy, PartialEq, Debug)]
pub struct Report {
    /// Lengths are in inches (the program's first move was under G20).
    pub inch: bool,
    /// Rapid moves (G0).
    pub rapids: u64,
    /// Straight feed moves (G1).
    pub feeds: u64,
    /// Arcs and helices (G2, G3).
    pub arcs: u64,
    /// Dwells (G4).
    pub dwells: u64,
    /// Tool changes: M6s, or T changes in a program without M6.
    pub tool_changes: u64,
    /// M codes of every kind (M6 included).
    pub m_codes: u64,
    /// Comments passed on.
    pub comments: u64,
    /// Length at rapid traverse.
    pub rapid_length: f64,
    /// Length at the feed rate: lines and arcs.
    pub feed_length: f64,
    /// The part of `feed_length` on arcs.
    pub arc_length: f64,
    /// The box of all motion; `None` when nothing moved.
    pub bounds: Option<Bounds>,
    /// The rapid rate of the estimate, mm/min.
    pub rapid_rate: f64,
    /// Time at rapid traverse.
    pub rapid_seconds: f64,
    /// Time at the feed rate.
    pub feed_seconds: f64,
    /// Time dwelling.
    pub dwell_seconds: f64,
    /// The estimated machining time: rapids, feeds and dwells.
    pub total_seconds: f64,
    /// Feed moves left out of the time: no F, or G95 without a spindle speed.
    pub untimed_feeds: u64,
    /// Their length.
    pub untimed_length: f64,
    /// A turning program (its X a diameter: true): the box's X is the kernel's, a radius.
    pub turning: Option<bool>,
}

impl Stats {
    /// The same statistics, counting each move against the run's block and time limits, and
    /// refusing a position the dialect cannot write.
    pub fn within(self, budget: fmsvm_block::OutputBudget, reach: crate::dialect::Reach) -> Stats {
        Stats {
            budget,
            reach,
            ..self
        }
    }

    /// Statistics of a program whose tool starts at `start` (mm, or the program's units: the start is
    /// taken as it is).
    pub fn new(start: Pose) -> Stats {
        Stats {
            at: start,
            inch: false,
            report_inch: None,
            feed: 0.0,
            per_rev: false,
            speed: 0.0,
            css: None,
            clamp: None,
            turning: None,
            tool: None,
            rapids: 0,
            feeds: 0,
            arcs: 0,
            dwells: 0,
            m_codes: 0,
            comments: 0,
            m6: 0,
            t_changes: 0,
            untimed_feeds: 0,
            rapid_length: 0.0,
            feed_length: 0.0,
            arc_length: 0.0,
            untimed_length: 0.0,
            feed_seconds: 0.0,
            dwell_seconds: 0.0,
            budget: fmsvm_block::OutputBudget::default(),
            reach: crate::dialect::Reach::default(),
            bounds: Bounds::EMPTY,
        }
    }

    /// The statistics of a turning program, its X a diameter (`diameter`) or a radius.
    pub fn turning(mut self, diameter: bool) -> Stats {
        self.turning = Some(diameter);
        self
    }

    /// Places the tool at `at` (in the units in force) without a move: where the program starts.
    pub fn start(&mut self, at: Pose) {
        self.at = to_mm(&at, self.inch);
    }

    /// Takes one operation.
    pub fn op(&mut self, op: &Canon<'_>) {
        match *op {
            Canon::Start(at) => self.start(at),
            // A return to a reference position is a rapid (of unknown length where the
            // reference position is not known).
            Canon::Rapid(to) | Canon::Reference { to, .. } | Canon::Machine { to, .. } => {
                let to = self.moved(&to);
                self.rapids += 1;
                self.rapid_length += linear(&self.at, &to);
                self.bounds.add(&to);
                self.at = to;
            }
            Canon::Feed(to) | Canon::Skip(to) => {
                let to = self.moved(&to);
                self.feeds += 1;
                let length = linear(&self.at, &to);
                self.feed_length += length;
                let travel = if length > 0.0 {
                    length
                } else {
                    rotary(&self.at, &to)
                };
                if self.css.is_some() && self.per_rev {
                    self.time_css(&[self.at, to], length, self.feed);
                } else {
                    self.time_feed(length, travel);
                }
                self.bounds.add(&to);
                self.at = to;
            }
            Canon::Arc(arc) => {
                self.moved(&arc.to);
                let arc = arc_to_mm(&arc, self.inch);
                self.arcs += 1;
                let length = arc.length(&self.at);
                self.feed_length += length;
                self.arc_length += length;
                if self.css.is_some() && self.per_rev {
                    let points = arc_points(&self.at, &arc, 64);
                    self.time_css(&points, length, self.feed);
                } else {
                    self.time_feed(length, length);
                }
                self.bounds.add_arc(&self.at, &arc);
                self.at = arc.to;
            }
            Canon::Dwell(seconds) => {
                self.dwells += 1;
                if seconds.is_finite() && seconds > 0.0 {
                    self.dwell_seconds += seconds;
                }
            }
            Canon::FeedRate(f) => self.feed = f,
            Canon::FeedPerRev(on) => self.per_rev = on,
            Canon::Units(inch) => self.inch = inch,
            Canon::Speed(s) => {
                self.speed = s.abs();
                self.css = None;
            }
            Canon::SurfaceSpeed(v) => self.css = Some(v.abs()),
            Canon::SpindleClamp(s) => self.clamp = Some(s.abs()),
            Canon::Thread { to, lead } => {
                let to = self.moved(&to);
                self.feeds += 1;
                let length = linear(&self.at, &to);
                self.feed_length += length;
                let (per_rev, feed) = (self.per_rev, self.feed);
                self.per_rev = true;
                if !self.time_css(&[self.at, to], length, lead) {
                    self.feed = lead;
                    self.time_feed(length, length);
                }
                (self.per_rev, self.feed) = (per_rev, feed);
                self.bounds.add(&to);
                self.at = to;
            }
            Canon::Tool(t) => {
                if self.tool != Some(t) {
                    self.t_changes += 1;
                }
                self.tool = Some(t);
            }
            Canon::MCode(m) => {
                self.m_codes += 1;
                if m == 6.0 {
                    self.m6 += 1;
                }
            }
            Canon::Comment(_) => self.comments += 1,
            Canon::AuxCode(..)
            | Canon::Cycle(_)
            | Canon::CycleEnd
            | Canon::Corners(_)
            | Canon::WorkSystem(_)
            | Canon::ToolLength { .. } => {}
        }
    }

    /// Before a move to `to` (the units in force): the move's end in mm, the box opened at the start.
    fn moved(&mut self, to: &Pose) -> Pose {
        if self.report_inch.is_none() {
            self.report_inch = Some(self.inch);
        }
        self.bounds.add(&self.at);
        to_mm(to, self.inch)
    }

    /// Times a feed move of `length` mm, `travel` the distance F applies to (mm, or degrees for a
    /// rotary-only move).
    fn time_feed(&mut self, length: f64, travel: f64) {
        let scale = if self.inch { MM_PER_INCH } else { 1.0 };
        let rate = if self.per_rev {
            self.feed * scale * self.speed
        } else {
            self.feed * scale
        };
        if rate.is_finite() && rate > 0.0 {
            // A rotary-only move's F is degrees/min: no unit conversion.
            let rate = if length > 0.0 { rate } else { rate / scale };
            self.feed_seconds += travel / rate * 60.0;
        } else if travel > 0.0 {
            self.untimed_feeds += 1;
            self.untimed_length += length;
        }
    }

    /// Times a per-revolution feed of `f` along the path through `points` (mm, `length` long in
    /// all) under constant surface speed; false when CSS or per-revolution feed is not in force.
    fn time_css(&mut self, points: &[Pose], length: f64, f: f64) -> bool {
        let (Some(v), true) = (self.css, self.per_rev) else {
            return false;
        };
        let scale = if self.inch { MM_PER_INCH } else { 1.0 };
        // n = k / r with r in mm.
        let k = fmsvm_canon::surface_speed_constant(v, self.inch);
        let floor = self.clamp.map_or(0.0, |c| 1.0 / c);
        // 1/n at radius r: the larger of 1/clamp and r/k.
        let inv = |r: f64| floor.max(r.abs() / k);
        let rate = f * scale;
        if !(rate > 0.0 && k > 0.0) || points.len() < 2 {
            if length > 0.0 {
                self.untimed_feeds += 1;
                self.untimed_length += length;
            }
            return true;
        }
        let total: f64 = points.windows(2).map(|w| linear(&w[0], &w[1])).sum();
        let mut minutes = 0.0;
        for w in points.windows(2) {
            let (x0, x1) = (w[0][0], w[1][0]);
            let piece = linear(&w[0], &w[1]) * if total > 0.0 { length / total } else { 0.0 };
            // Breakpoints of the piecewise-linear integrand: where X crosses 0 and ±k/clamp.
            let mut ts = vec![0.0, 1.0];
            let r_clamp = k * floor;
            for at in [0.0, r_clamp, -r_clamp] {
                if x1 != x0 {
                    let t = (at - x0) / (x1 - x0);
                    if t > 0.0 && t < 1.0 {
                        ts.push(t);
                    }
                }
            }
            ts.sort_by(f64::total_cmp);
            for t in ts.windows(2) {
                let (a, b) = (x0 + (x1 - x0) * t[0], x0 + (x1 - x0) * t[1]);
                minutes += piece * (t[1] - t[0]) * (inv(a) + inv(b)) / 2.0 / rate;
            }
        }
        self.feed_seconds += minutes * 60.0;
        true
    }

    /// The report, with rapids timed at `rapid_rate_mm_min`.
    pub fn finish(&self, rapid_rate_mm_min: f64) -> Report {
        let inch = self.report_inch.unwrap_or(self.inch);
        let k = if inch { 1.0 / MM_PER_INCH } else { 1.0 };
        let rapid_seconds = if rapid_rate_mm_min > 0.0 {
            self.rapid_length / rapid_rate_mm_min * 60.0
        } else {
            0.0
        };
        Report {
            inch,
            rapids: self.rapids,
            feeds: self.feeds,
            arcs: self.arcs,
            dwells: self.dwells,
            tool_changes: if self.m6 > 0 { self.m6 } else { self.t_changes },
            m_codes: self.m_codes,
            comments: self.comments,
            rapid_length: self.rapid_length * k,
            feed_length: self.feed_length * k,
            arc_length: self.arc_length * k,
            bounds: (!self.bounds.is_empty()).then(|| self.bounds.scaled(k)),
            rapid_rate: rapid_rate_mm_min,
            rapid_seconds,
            feed_seconds: self.feed_seconds,
            dwell_seconds: self.dwell_seconds,
            total_seconds: rapid_seconds + self.feed_seconds + self.dwell_seconds,
            untimed_feeds: self.untimed_feeds,
            untimed_length: self.untimed_length * k,
            turning: self.turning,
        }
    }
}

/// The X Y Z distance from `a` to `b`.
#[inline]
fn linear(a: &Pose, b: &Pose) -> f64 {
    let (dx, dy, dz) = (travel(a[0], b[0]), travel(a[1], b[1]), travel(a[2], b[2]));
    (dx * dx + dy * dy + dz * dz).sqrt()
}

/// `n + 1` points along `arc` from `from`, evenly by angle (the normal axis linearly).
fn arc_points(from: &Pose, arc: &Arc, n: usize) -> Vec<Pose> {
    let (a, b, c) = arc.plane.axes();
    let (r, sweep) = arc.sweep(from);
    let [ca, cb] = arc.centre;
    let start = (from[b] - cb).atan2(from[a] - ca);
    let dir = if arc.clockwise { -1.0 } else { 1.0 };
    (0..=n)
        .map(|k| {
            let t = k as f64 / n as f64;
            let mut p = *from;
            let ang = start + dir * sweep * t;
            p[a] = ca + r * ang.cos();
            p[b] = cb + r * ang.sin();
            p[c] = from[c] + (arc.to[c] - from[c]) * t;
            p
        })
        .collect()
}

/// The largest A B C travel from `a` to `b`, degrees.
#[inline]
fn rotary(a: &Pose, b: &Pose) -> f64 {
    (3..6).map(|i| travel(a[i], b[i]).abs()).fold(0.0, f64::max)
}

impl fmsvm_canon::Emitter for Stats {
    const CANON: bool = true;

    fn canon(&mut self, op: &Canon<'_>, _: fmsvm_canon::Origin) -> Result<(), fmsvm_block::Stop> {
        if op.is_block() {
            self.budget.spend_line(0)?;
        }
        if let Some(to) = op.end() {
            self.reach.check(to, self.inch)?;
        }
        self.op(op);
        Ok(())
    }
}

#[cfg(test)]
mod tests;
