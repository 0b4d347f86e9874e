//! Estimated machining time (feed moves at their F, rapids at the rapid rate, dwells), which drives the
//! timers #3001 (ms) and #3002 (hours) so that a macro's timing logic is deterministic (S2), and the
//! fixed clock #3011/#3012.

use fmsvm_block::{Block, Letter};

use fmsvm_canon::modal::{Code, Group, ModalState};

/// The time model of a run.
#[derive(Clone, Debug)]
pub struct Timing {
    /// Rapid traverse rate, mm/min (or inch/min under G20).
    pub rapid: f64,
    /// Machining time since the start, seconds.
    pub total_seconds: f64,
    /// #3001 reads `total − base_ms` (writing #3001 moves the base).
    base_ms: f64,
    /// #3002 likewise, in hours.
    base_hours: f64,
    /// #3011 YYYYMMDD.
    pub date: u32,
    /// #3012 HHMMSS.
    pub time: u32,
    /// Whether motion is timed at all (off when nothing reads the timers: it costs a square root and a
    /// division per block).
    pub enabled: bool,
}

impl Default for Timing {
    fn default() -> Self {
        Timing {
            rapid: 10_000.0,
            total_seconds: 0.0,
            base_ms: 0.0,
            base_hours: 0.0,
            date: 20_000_101,
            time: 0,
            enabled: true,
        }
    }
}

impl Timing {
    /// #3001: milliseconds since it was last set.
    pub fn millis(&self) -> f64 {
        (self.total_seconds * 1000.0 - self.base_ms).round()
    }

    /// Sets #3001.
    pub fn set_millis(&mut self, v: f64) {
        self.base_ms = self.total_seconds * 1000.0 - v;
    }

    /// #3002: hours since it was last set.
    pub fn hours(&self) -> f64 {
        self.total_seconds / 3600.0 - self.base_hours
    }

    /// Sets #3002.
    pub fn set_hours(&mut self, v: f64) {
        self.base_hours = self.total_seconds / 3600.0 - v;
    }

    /// Adds a motion from `start` to `end` (X Y Z A B C) programmed by `block`. Inlined so that a
    /// run that keeps no time (most) pays one test a move, not a call with both poses.
    #[inline(always)]
    pub fn motion(
        &mut self,
        modal: &ModalState,
        start: &[f64; 6],
        end: &[f64; 6],
        block: &Block<'_>,
        last: &[f64],
    ) {
        if self.enabled {
            self.add_motion(modal, start, end, block, last);
        }
    }

    fn add_motion(
        &mut self,
        modal: &ModalState,
        start: &[f64; 6],
        end: &[f64; 6],
        block: &Block<'_>,
        last: &[f64],
    ) {
        // An axis whose start or end is unknown adds nothing (`canon::travel`).
        let d: [f64; 3] = std::array::from_fn(|i| fmsvm_canon::travel(start[i], end[i]));
        let motion = modal.get(Group::Motion);
        let linear = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let length = match motion {
            Code::G2 | Code::G3 if modal.get(Group::Plane) == Code::G17 => {
                arc_length(*start, *end, motion == Code::G2, block)
                    .filter(|l| l.is_finite())
                    .unwrap_or(linear)
            }
            _ => linear,
        };
        let rate = if motion == Code::G0 {
            self.rapid
        } else {
            let f = last[Letter::F.index()];
            if f.is_nan() || f <= 0.0 {
                self.rapid
            } else {
                f
            }
        };
        self.total_seconds += length / rate * 60.0;
    }

    /// Adds a G04 dwell: P in ms, or X in seconds.
    pub fn dwell(&mut self, block: &Block<'_>) {
        if !self.enabled {
            return;
        }
        if let Some(p) = block.get(Letter::P) {
            self.total_seconds += p / 1000.0;
        } else if let Some(x) = block.get(Letter::X) {
            self.total_seconds += x;
        }
    }
}

/// Length of an XY arc given by I J (centre relative to the start) or R, with a helical Z.
fn arc_length(start: [f64; 6], end: [f64; 6], clockwise: bool, block: &Block<'_>) -> Option<f64> {
    let t = |i: usize| fmsvm_canon::travel(start[i], end[i]);
    let (dx, dy, dz) = (t(0), t(1), t(2));
    let chord = (dx * dx + dy * dy).sqrt();
    let (r, sweep) = if let Some(r) = block.get(Letter::R) {
        let r_abs = r.abs();
        if chord == 0.0 || r_abs * 2.0 < chord - 1e-9 {
            return None;
        }
        let half = (chord / (2.0 * r_abs)).min(1.0).asin() * 2.0;
        (
            r_abs,
            if r < 0.0 {
                std::f64::consts::TAU - half
            } else {
                half
            },
        )
    } else {
        let i = block.get(Letter::I).unwrap_or(0.0);
        let j = block.get(Letter::J).unwrap_or(0.0);
        let centre = [start[0] + i, start[1] + j];
        let r = (i * i + j * j).sqrt();
        let sweep = fmsvm_canon::geom::sweep(
            [start[0], start[1]],
            [end[0], end[1]],
            centre,
            !clockwise,
            0,
        );
        (r, sweep)
    };
    let arc = r * sweep;
    Some((arc * arc + dz * dz).sqrt())
}
