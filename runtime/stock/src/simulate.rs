//! The stock beside any consumer of canonical operations: every move cuts the stock with the
//! tool in the spindle, and what must not happen is said at its block — a rapid into material,
//! a cut below the stock's floor, a shank that rubs, a plunge with a tool that cannot plunge.
//! With `strict` the first of them stops the run there.

use std::collections::{BTreeMap, BTreeSet, VecDeque};

use fmsvm_block::alarms::NO_FANUC_NUMBER;
use fmsvm_block::{Alarm, Code, Stop};
use fmsvm_canon::decode::Decoded;
use fmsvm_canon::{Canon, Context, Emitter, Origin, Pose, Warning};

use crate::cutter::Cutter;
use crate::lathe::{HalfSection, Nose};
use crate::mill::{Cut, HeightField};
use crate::quarters::{Quarters, Step};

/// The stock being cut.
#[derive(Clone, Debug)]
pub enum Stock {
    /// A mill's box as a height field.
    Mill(HeightField),
    /// A lathe's bar as its half-section.
    Lathe(HalfSection),
}

/// A tool as the stock sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Tool {
    Mill(Cutter),
    Lathe(Nose),
}

/// Findings kept at most (each class is counted beyond it).
const KEPT: usize = 50;

/// What the moves of one tool did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ToolTotals {
    /// Volume removed.
    pub removed: f64,
    /// Feed moves' length through material, and through air.
    pub cutting_length: f64,
    pub air_length: f64,
    /// Their time, where the feed is per minute.
    pub cutting_seconds: f64,
    pub air_seconds: f64,
    /// Rapids into material.
    pub rapids_into_material: u32,
}

/// The stock's report at the end of a run.
#[derive(Clone, Debug, Default)]
pub struct Report {
    /// Per tool number (T as written).
    pub tools: BTreeMap<u32, ToolTotals>,
    /// The stock's volume before and after.
    pub before: f64,
    pub after: f64,
    /// Findings of each kind (all, not only those kept).
    pub rapids_into_material: u32,
    pub below_floor: u32,
    pub shank_rubs: u32,
    pub plunges: u32,
    /// The rapids into material (X Y Z from, to), the first of them.
    pub hits: Vec<[[f64; 3]; 2]>,
}

/// `inner` with the stock cut beside it.
pub struct Simulated<E> {
    inner: E,
    stock: Held,
    tools: BTreeMap<u32, Tool>,
    tool: Option<u32>,
    at: Pose,
    /// Feed per minute (None: per revolution, or not yet given).
    feed: Option<f64>,
    feed_value: f64,
    per_rev: bool,
    strict: bool,
    /// Chords of arcs within this of the arc.
    tolerance: f64,
    findings: Vec<Warning>,
    report: Report,
    unknown_tools: BTreeSet<u32>,
    untooled_said: bool,
    /// A feed move whose cut a chain has not finished.
    open: Option<Move>,
    /// Moves of a mill's cutter waiting to be cut as a batch, and what each is.
    queue: Vec<Step>,
    queued: Vec<Move>,
    /// The batches being cut while the run goes on, oldest first.
    flights: VecDeque<Vec<Move>>,
    /// Batches' room, landed and empty, for the next.
    spare: Vec<Vec<Move>>,
}

/// The stock as a run holds it.
enum Held {
    Mill(Box<Quarters>),
    Lathe(HalfSection),
}

/// Moves cut in one batch at most.
const BATCH: usize = 4096;

/// Batches being cut at once at most (while the run makes the next): one worker may run ahead of
/// the other by as many.
const FLIGHTS: usize = 8;

impl<E> Simulated<E> {
    /// `inner`, with `stock` cut by the `tools` (by T number as the program writes it); `strict`
    /// stops the run at the first finding.
    pub fn new(inner: E, stock: Stock, tools: BTreeMap<u32, Tool>, strict: bool) -> Self {
        let cell = match &stock {
            Stock::Mill(m) => m.grid().2,
            Stock::Lathe(l) => l.grid().2,
        };
        let before = volume(&stock);
        let stock = match stock {
            Stock::Mill(m) => Held::Mill(Box::new(Quarters::new(m))),
            Stock::Lathe(l) => Held::Lathe(l),
        };
        Simulated {
            inner,
            stock,
            tools,
            tool: None,
            at: [f64::NAN; 6],
            feed: None,
            feed_value: 0.0,
            per_rev: false,
            strict,
            tolerance: (cell / 10.0).min(0.001),
            findings: Vec::new(),
            report: Report {
                before,
                ..Report::default()
            },
            unknown_tools: BTreeSet::new(),
            untooled_said: false,
            open: None,
            queue: Vec::new(),
            queued: Vec::new(),
            flights: VecDeque::new(),
            spare: Vec::new(),
        }
    }

    /// The emitter inside.
    pub fn inner(&self) -> &E {
        &self.inner
    }

    /// What the stock has to say about the run, each at its block.
    pub fn warnings(&self) -> &[Warning] {
        &self.findings
    }

    /// Finishes a run that stopped before its end: what the last feed move left is cut and what
    /// it did said (a run that reached its end did so there).
    pub fn stopped(&mut self) {
        // A move is open only when the run is not strict: closing it says, and cannot stop.
        let _ = self.close_all();
    }

    /// The emitter, the stock and its report.
    pub fn finish(mut self) -> (E, Stock, Report) {
        self.stopped();
        let stock = match self.stock {
            Held::Mill(q) => Stock::Mill(q.join()),
            Held::Lathe(l) => Stock::Lathe(l),
        };
        let mut report = self.report;
        report.after = volume(&stock);
        (self.inner, stock, report)
    }

    /// Says `text` at `origin`, or stops there when strict.
    fn find(&mut self, origin: Origin, text: String) -> Result<(), Stop> {
        if self.strict {
            return Err(Stop::Alarm(Alarm::new(NO_FANUC_NUMBER, text)));
        }
        if self.findings.len() < KEPT {
            self.findings.push(Warning::at(origin, text));
        }
        Ok(())
    }

    /// The tool in the spindle, when the stock knows its shape.
    fn cutting_tool(&mut self, origin: Origin) -> Option<(u32, Tool)> {
        let Some(n) = self.tool else {
            if !self.untooled_said {
                self.untooled_said = true;
                self.findings.push(Warning::at(
                    origin,
                    "the stock: no tool is selected (T) before this move: moves without one are not simulated",
                ));
            }
            return None;
        };
        // A lathe's tool shapes are its offsets', the T word's last two digits (T0101: 1).
        let key = match self.stock {
            Held::Lathe(_) => n % 100,
            Held::Mill(_) => n,
        };
        match self.tools.get(&key) {
            Some(t) => Some((n, *t)),
            None => {
                if self.unknown_tools.insert(n) {
                    self.findings.push(Warning::at(
                        origin,
                        format!("the stock: T{n} has no shape in --offsets ([tool.N] diameter and type, or a lathe tool's radius): its moves are not simulated"),
                    ));
                }
                None
            }
        }
    }

    /// One straight move of the tool from where it is to `to`.
    fn travel(&mut self, to: Pose, rapid: bool, origin: Origin) -> Result<(), Stop> {
        let from = self.at;
        self.at = to;
        // A move that goes nowhere cuts nothing the move that brought the tool there did not.
        if from[..3].iter().chain(&to[..3]).any(|v| v.is_nan()) || from[..3] == to[..3] {
            return Ok(());
        }
        let Some((n, tool)) = self.cutting_tool(origin) else {
            return Ok(());
        };
        let length =
            ((to[0] - from[0]).powi(2) + (to[1] - from[1]).powi(2) + (to[2] - from[2]).powi(2))
                .sqrt();
        let mut done = Move {
            tool: n,
            origin,
            rapid,
            path: [[from[0], from[1], from[2]], [to[0], to[1], to[2]]],
            length,
            seconds: self.feed.map(|f| length / f * 60.0),
            cut: Cut::default(),
            plunge: false,
            chain: false,
        };
        match (&mut self.stock, tool) {
            (Held::Mill(_), Tool::Mill(cutter)) => {
                let (a, b) = ([from[0], from[1], from[2]], [to[0], to[1], to[2]]);
                return self.mill_move(cutter, a, b, done);
            }
            (Held::Lathe(bar), Tool::Lathe(nose)) => {
                // The half-section's X is the radius: the kernel's terms.
                let cut = bar.cut([from[0], from[2]], [to[0], to[2]], &nose);
                done.cut = Cut {
                    removed: cut.removed,
                    deepest: cut.area,
                    below_floor: 0.0,
                    touched: cut.removed > 0.0,
                };
            }
            _ => return Ok(()),
        }
        self.conclude(done)
    }

    /// Finishes the move a chain left open with what it had left, cut now.
    fn close(&mut self, left: Cut) -> Result<(), Stop> {
        match self.open.take() {
            Some(mut m) => {
                m.cut = m.cut.and(left);
                self.conclude(m)
            }
            None => Ok(()),
        }
    }

    /// A move of a mill's cutter from `a` to `b`: queued for the next batch, or cut at once where
    /// its findings must come at its block (a strict run) or the shank must see the stock as the
    /// moves before it left it.
    fn mill_move(
        &mut self,
        cutter: Cutter,
        a: [f64; 3],
        b: [f64; 3],
        mut done: Move,
    ) -> Result<(), Stop> {
        let rapid = done.rapid;
        done.plunge = !rapid
            && !cutter.plunges
            && b[2] < a[2]
            && (b[0] - a[0]).hypot(b[1] - a[1]) < cutter.radius;
        let shank = cutter.shank().filter(|_| !rapid);
        // A feed move leaves the cells ahead of it to the next (see `HeightField`), but not
        // where a strict run must stop at its own block, nor where a shank's check must see them
        // cut.
        let chain = !rapid && !self.strict && shank.is_none();
        let step = Step {
            from: a,
            to: b,
            cutter,
            chain,
        };
        if chain || (rapid && !self.strict) {
            done.chain = chain;
            self.queue.push(step);
            self.queued.push(done);
            return if self.queue.len() >= BATCH {
                self.send_queue()
            } else {
                Ok(())
            };
        }
        self.run_queue()?;
        let Held::Mill(q) = &mut self.stock else {
            return Ok(());
        };
        // The shank first: what stands above the flutes' reach before they cut.
        let (flushed, rub) = match shank {
            Some((radius, above)) => {
                let flushed = q.flush();
                let shank = Cutter::new(crate::cutter::Shape::Flat, radius);
                let lift = |p: [f64; 3]| [p[0], p[1], p[2] + above];
                (flushed, q.touch(lift(a), lift(b), &shank).deepest)
            }
            None => (Cut::default(), 0.0),
        };
        let (left, cut) = q.run(&[step])[0];
        self.close(flushed.and(left))?;
        done.cut = cut;
        if rub > 1e-9 {
            self.report.shank_rubs += 1;
            let (n, above) = (done.tool, cutter.flute_length.unwrap_or(0.0));
            self.find(
                done.origin,
                format!(
                    "T{n}'s shank above its {above} of flutes rubs the material, {rub:.3} deep"
                ),
            )?;
        }
        self.conclude(done)
    }

    /// Cuts the queued moves and finishes each in order (those sent before them first).
    fn run_queue(&mut self) -> Result<(), Stop> {
        self.send_queue()?;
        while !self.flights.is_empty() {
            self.land()?;
        }
        Ok(())
    }

    /// Sends the queued moves to be cut while the run goes on (the oldest batch away finished
    /// first where as many as `FLIGHTS` are).
    fn send_queue(&mut self) -> Result<(), Stop> {
        if self.queue.is_empty() {
            return Ok(());
        }
        if self.flights.len() >= FLIGHTS {
            self.land()?;
        }
        let Held::Mill(q) = &mut self.stock else {
            return Ok(());
        };
        q.send(self.queue.as_slice().into());
        self.queue.clear();
        let next = self.spare.pop().unwrap_or_default();
        self.flights
            .push_back(std::mem::replace(&mut self.queued, next));
        Ok(())
    }

    /// Finishes each move of the oldest batch sent, in order, once it is cut.
    fn land(&mut self) -> Result<(), Stop> {
        let (Some(mut flight), Held::Mill(q)) = (self.flights.pop_front(), &mut self.stock) else {
            return Ok(());
        };
        let cuts = q.receive();
        let mut result = Ok(());
        for (mut done, (left, cut)) in flight.drain(..).zip(cuts) {
            if result.is_err() {
                continue;
            }
            result = self.close(left).and_then(|()| {
                done.cut = cut;
                if done.chain {
                    self.open = Some(done);
                    Ok(())
                } else {
                    self.conclude(done)
                }
            });
        }
        self.spare.push(flight);
        result
    }

    /// Cuts the queued moves and what the last move left, and finishes it.
    fn close_all(&mut self) -> Result<(), Stop> {
        self.run_queue()?;
        let left = match &mut self.stock {
            Held::Mill(q) => q.flush(),
            Held::Lathe(_) => Cut::default(),
        };
        self.close(left)
    }

    /// Says what a finished move did wrong and counts it in its tool's totals.
    fn conclude(&mut self, m: Move) -> Result<(), Stop> {
        let (n, origin, cut) = (m.tool, m.origin, m.cut);
        if !m.rapid && cut.below_floor > 1e-9 {
            self.report.below_floor += 1;
            self.find(
                origin,
                format!(
                    "the cut goes {:.3} below the stock's floor, into the fixture",
                    cut.below_floor
                ),
            )?;
        }
        if m.plunge && cut.touched {
            self.report.plunges += 1;
            self.find(origin, format!("T{n} does not cut at its centre (plunge = false) and goes {:.3} straight down into material", m.path[0][2] - m.path[1][2]))?;
        }
        let totals = self.report.tools.entry(n).or_default();
        totals.removed += cut.removed;
        if m.rapid {
            if cut.deepest > 1e-9 {
                let into = cut.deepest;
                totals.rapids_into_material += 1;
                self.report.rapids_into_material += 1;
                if self.report.hits.len() < KEPT {
                    self.report.hits.push(m.path);
                }
                let what = match self.stock {
                    Held::Mill(_) => format!("the cutter goes {into:.3} below the material's top"),
                    Held::Lathe(_) => format!(
                        "the tool passes through {into:.3} of the bar's half-section (area)"
                    ),
                };
                return self.find(origin, format!("a rapid (G0) into the stock: {what}"));
            }
            return Ok(());
        }
        if cut.touched {
            totals.cutting_length += m.length;
            totals.cutting_seconds += m.seconds.unwrap_or(0.0);
        } else {
            totals.air_length += m.length;
            totals.air_seconds += m.seconds.unwrap_or(0.0);
        }
        Ok(())
    }
}

/// A move of a tool with a shape, until what it did is known.
#[derive(Clone, Copy, Debug)]
struct Move {
    tool: u32,
    origin: Origin,
    rapid: bool,
    path: [[f64; 3]; 2],
    length: f64,
    /// Its time, where the feed is per minute.
    seconds: Option<f64>,
    /// What it removed (for a lathe, `deepest` is the area it passed through).
    cut: Cut,
    /// It goes straight down with a tool that cannot (a mill's).
    plunge: bool,
    /// It may leave what is ahead of it to the next move (a mill's feed in a chain).
    chain: bool,
}

/// The stock's volume.
fn volume(stock: &Stock) -> f64 {
    match stock {
        Stock::Mill(m) => m.volume(),
        Stock::Lathe(l) => l.volume(),
    }
}

impl<E: Emitter> Emitter for Simulated<E> {
    const CANON: bool = true;

    fn begin(&mut self, number: Option<u32>, title: &str) -> Result<(), Stop> {
        self.inner.begin(number, title)
    }
    fn block(&mut self, block: &Decoded<'_, '_>, ctx: &Context) -> Result<(), Stop> {
        self.inner.block(block, ctx)
    }
    fn canon(&mut self, op: &Canon<'_>, origin: Origin) -> Result<(), Stop> {
        match *op {
            Canon::Start(p) => self.at = p,
            Canon::Rapid(p) => self.travel(p, true, origin)?,
            Canon::Feed(p) => self.travel(p, false, origin)?,
            Canon::Thread { to, .. } => self.travel(to, false, origin)?,
            // The probe stops where it touches: it cuts nothing.
            Canon::Skip(p) => self.at = p,
            Canon::Reference { to, .. } | Canon::Machine { to, .. } => {
                self.travel(to, true, origin)?
            }
            Canon::Arc(arc) => {
                let from = self.at;
                let mut at = from;
                let mut result = Ok(());
                fmsvm_canon::arcs::chords(&from, &arc, self.tolerance, &mut |p| {
                    self.at = at;
                    let r = self.travel(p, false, origin);
                    at = p;
                    if r.is_err() {
                        result = r;
                        return Err(());
                    }
                    Ok(())
                })
                .ok();
                result?;
                self.at = arc.to;
            }
            Canon::Tool(v) => self.tool = (v >= 0.0 && v.fract() == 0.0).then_some(v as u32),
            Canon::FeedRate(f) => {
                self.feed_value = f;
                self.feed = (!self.per_rev && f > 0.0).then_some(f);
            }
            Canon::FeedPerRev(on) => {
                self.per_rev = on;
                self.feed = (!on && self.feed_value > 0.0).then_some(self.feed_value);
            }
            _ => {}
        }
        self.inner.canon(op, origin)
    }
    fn native_cycle(&self, code: Code) -> bool {
        self.inner.native_cycle(code)
    }
    fn corners(&self) -> bool {
        self.inner.corners()
    }
    fn written(&self) -> u64 {
        self.inner.written()
    }
    fn end(&mut self) -> Result<(), Stop> {
        self.close_all()?;
        self.inner.end()
    }
    fn settle(&mut self) -> Result<(), Stop> {
        self.inner.settle()
    }
    fn message(&mut self, number: u32, text: &str) -> Result<(), Stop> {
        self.inner.message(number, text)
    }
}
