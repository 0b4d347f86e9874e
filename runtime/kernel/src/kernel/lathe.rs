//! The lathe's reading of a block (docs/lathe.md): X a diameter, U and W the incremental X and Z,
//! no Y; G50 S (G92 S in system B) the spindle clamp, G96/G97 the spindle's mode; G32 threads and
//! the single cycles G90/G92/G94 (system A; G77/G78/G79 in B) as moves.

use fmsvm_block::{Alarm, Letter, Stop};
use fmsvm_canon::decode::FORMAT;
use fmsvm_canon::modal::{Code, Group};
use fmsvm_canon::{Canon, Emitter, Origin, Pose, unknown_axis};

use super::{Kernel, Words};

/// fmsvm's own refusals (no Fanuc alarm says them).
const NO_FANUC_NUMBER: u32 = 0;

/// The words of a lathe's single cycle that stay in force from block to block (Fanuc: "X(U), Z(W)
/// and R of a canned cycle are modal"): the end point, absolute, and the taper, radius.
#[derive(Clone, Copy, Debug)]
pub(super) struct SingleCycle {
    /// X (radius) and Z of the cycle's end point.
    pub end: [f64; 2],
    /// R: the taper (G90, G92: X at the cut's start minus X at its end, radius; G94: the same in Z).
    pub taper: f64,
}

impl<E: Emitter> Kernel<E> {
    /// Step 2b on a lathe: the words as the kernel reads a mill's. X (and U) halve on a diameter
    /// lathe; U and W become incremental X and Z; a dwell's U is its X (seconds). The words of G10
    /// and of the multiple repetitive cycles (G70–G76) are the cycle's data, read there.
    pub(super) fn lathe_words(&mut self, w: &mut Words) -> Result<(), Alarm> {
        let Some(lathe) = self.settings.lathe else {
            return Ok(());
        };
        if w.has(Letter::Y) {
            return Err(Alarm::new(
                FORMAT,
                "Y: a lathe has no Y axis (a turning program moves X and Z)",
            ));
        }
        match w.non_modal {
            Some(Code::G4) => {
                if let Some(u) = w.get(Letter::U)
                    && !w.has(Letter::X)
                {
                    w.value[Letter::X.index()] = u;
                }
                return Ok(());
            }
            Some(Code::G10) => return Ok(()),
            Some(c) if c.tenths() >= Code::FINISHING_CYCLE.tenths() => return Ok(()),
            _ => {}
        }
        let x_factor = if lathe.diameter { 0.5 } else { 1.0 };
        for (axis, letter, increment, factor) in [
            (0, Letter::X, Letter::U, x_factor),
            (2, Letter::Z, Letter::W, 1.0),
        ] {
            match (w.get(letter), w.get(increment)) {
                (Some(_), Some(_)) => {
                    return Err(Alarm::new(
                        FORMAT,
                        format!(
                            "{letter} and {increment} in one block: give the end point absolute ({letter}) or incremental ({increment}), not both"
                        ),
                    ));
                }
                (Some(v), None) => w.value[letter.index()] = v * factor,
                (None, Some(v)) => {
                    w.value[letter.index()] = v * factor;
                    w.value[increment.index()] = f64::NAN;
                    w.inc |= 1 << axis;
                }
                (None, None) => {}
            }
        }
        Ok(())
    }

    /// The spindle words of a lathe block: G50 S (system A; G92 S in B) clamps the spindle, S under
    /// G96 is the surface speed, otherwise rpm. True when the block's S was taken here.
    pub(super) fn lathe_spindle(&mut self, w: &Words, origin: Origin) -> Result<bool, Stop> {
        if self.settings.lathe.is_none() {
            return Ok(false);
        }
        let s = w.get(Letter::S);
        if w.non_modal == Some(Code::G92) {
            if let Some(s) = s {
                self.canon(Canon::SpindleClamp(s), origin)?;
                return Ok(true);
            }
            return Ok(false);
        }
        let css = self.modal.get(Group::SurfaceSpeed) == Code::G96;
        match s {
            Some(s) if css => self.canon(Canon::SurfaceSpeed(s), origin)?,
            Some(s) => self.canon(Canon::Speed(s), origin)?,
            None if w.names(Group::SurfaceSpeed) => {
                // G96 or G97 alone: the last S in its new meaning (Fanuc keeps S as given).
                let Some(last) = self.last_value(Letter::S) else {
                    if css {
                        return Err(Alarm::new(
                            FORMAT,
                            "G96 without S: the surface speed (m/min) was never given",
                        )
                        .into());
                    }
                    return Ok(true);
                };
                self.canon(
                    if css {
                        Canon::SurfaceSpeed(last)
                    } else {
                        Canon::Speed(last)
                    },
                    origin,
                )?;
            }
            None => {}
        }
        Ok(true)
    }

    /// G32 (the lathe's G33): a thread to `to`, its lead F (per revolution); the tool moves with the
    /// spindle, so neither compensation nor a held corner may act on it.
    pub(super) fn thread(&mut self, to: &Pose, w: &Words, origin: Origin) -> Result<(), Stop> {
        let lead = self.thread_lead(w)?;
        let out = self.out_target(to, w, origin)?;
        self.thread_move(out, lead, origin)
    }

    /// The lead of a thread block: F (or the last F), which must be positive.
    fn thread_lead(&self, w: &Words) -> Result<f64, Alarm> {
        match w.get(Letter::F).or_else(|| self.last_value(Letter::F)) {
            Some(f) if f > 0.0 => Ok(f),
            _ => Err(Alarm::new(
                FORMAT,
                "a thread without its lead: give F (the lead, per revolution)",
            )),
        }
    }

    /// A thread move to output point `out`.
    fn thread_move(&mut self, out: Pose, lead: f64, origin: Origin) -> Result<(), Stop> {
        self.settle()?;
        if self.comp.is_active() {
            return Err(Alarm::new(
                NO_FANUC_NUMBER,
                "a thread under tool nose radius compensation: cancel it with G40 before threading",
            )
            .into());
        }
        self.follow_frame(origin)?;
        if let Some(i) = (0..6).find(|&i| out[i].is_nan() && !self.path_from[i].is_nan()) {
            return Err(unknown_axis(i, "this thread").into());
        }
        self.emitter
            .canon(&Canon::Thread { to: out, lead }, origin)?;
        self.stands_at(out);
        Ok(())
    }

    /// A single cycle (G90 turning, G92 threading, G94 facing; Fanuc 0i-TD manual, "Canned cycle",
    /// figures of the four paths) from where the tool stands to end point `to`: its four moves,
    /// the tool back at the start. `to` holds what the block gives; the rest is the cycle's modal
    /// end point.
    pub(super) fn single_cycle(
        &mut self,
        code: Code,
        to: &Pose,
        w: &Words,
        origin: Origin,
    ) -> Result<(), Stop> {
        let start = self.position;
        let prior = self.single_cycle;
        let end = [
            if w.has(Letter::X) {
                to[0]
            } else {
                prior.map_or(f64::NAN, |c| c.end[0])
            },
            if w.has(Letter::Z) {
                to[2]
            } else {
                prior.map_or(f64::NAN, |c| c.end[1])
            },
        ];
        let taper = w
            .get(Letter::R)
            .or_else(|| prior.map(|c| c.taper))
            .unwrap_or(0.0);
        let name = self.modal.system.written(code);
        if let Some(k) = (0..2).find(|&k| end[k].is_nan()) {
            return Err(Alarm::new(
                FORMAT,
                format!(
                    "G{name} without its {}: the cycle's end point needs both X and Z",
                    ["X", "Z"][k]
                ),
            )
            .into());
        }
        self.single_cycle = Some(SingleCycle { end, taper });
        if !E::CANON {
            return Ok(());
        }
        for (i, what) in [(0, "X"), (2, "Z")] {
            if start[i].is_nan() {
                return Err(unknown_axis(
                    i,
                    &format!("G{name} (it returns to its start point, {what})"),
                )
                .into());
            }
        }
        if self.comp.is_active() {
            return Err(Alarm::new(
                NO_FANUC_NUMBER,
                format!(
                    "G{name} under tool nose radius compensation is not yet resolved: cancel it with G40"
                ),
            )
            .into());
        }
        let at = |x: f64, z: f64| -> Pose {
            let mut p = start;
            p[0] = x;
            p[2] = z;
            p
        };
        let [xe, ze] = end;
        let [xs, zs] = [start[0], start[2]];
        let lead = if code == Code::THREADING_CYCLE {
            Some(self.thread_lead(w)?)
        } else {
            None
        };
        let path: [(Pose, Step); 4] = match code {
            Code::FACING_CYCLE => [
                (at(xs, ze + taper), Step::Rapid),
                (at(xe, ze), Step::Feed),
                (at(xe, zs), Step::Feed),
                (at(xs, zs), Step::Rapid),
            ],
            _ => [
                (at(xe + taper, zs), Step::Rapid),
                (at(xe, ze), lead.map_or(Step::Feed, Step::Thread)),
                (
                    at(xs, ze),
                    if lead.is_some() {
                        Step::Rapid
                    } else {
                        Step::Feed
                    },
                ),
                (at(xs, zs), Step::Rapid),
            ],
        };
        for (p, step) in path {
            let out = self.out_point(&p);
            match step {
                Step::Rapid => self.canon(Canon::Rapid(out), origin)?,
                Step::Feed => self.canon(Canon::Feed(out), origin)?,
                Step::Thread(lead) => self.thread_move(out, lead, origin)?,
            }
        }
        Ok(())
    }
}

/// One move of a single cycle.
#[derive(Clone, Copy)]
enum Step {
    Rapid,
    Feed,
    Thread(f64),
}
