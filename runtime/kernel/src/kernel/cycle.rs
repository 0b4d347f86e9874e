//! A canned-cycle block in the kernel: the hole positions through the transforms, the cycle's steps
//! (`crate::cycles`) as moves, or one native cycle block where the dialect writes the cycle itself.

use super::*;
use fmsvm_block::alarms::NO_FANUC_NUMBER;

impl<E: Emitter> Kernel<E> {
    /// A canned-cycle block: its moves through the transforms to the output; the tool ends where the
    /// cycle leaves it. Returns whether it moved.
    pub(super) fn canned_cycle(
        &mut self,
        code: Code,
        w: &Words,
        origin: Origin,
    ) -> Result<bool, Stop> {
        if self.settings.lathe.is_some() {
            return self.lathe_drilling(code, w, origin);
        }
        let plane = self.plane();
        let (a, b, n) = plane.axes();
        let polar = self.modal.get(Group::Polar) == Code::G16;
        let mut cb = cycles::CycleBlock {
            cycle: cycles::Cycle::of(code)?,
            plane,
            incremental: self.modal.incremental(),
            retract_to_r: self.modal.get(Group::ReturnLevel) == Code::G99,
            at: [w.get(AXES[a]), w.get(AXES[b])],
            depth: w.get(AXES[n]),
            r: w.get(Letter::R),
            q: w.get(Letter::Q),
            p: w.get(Letter::P),
            repeats: w.get(Letter::K).or(w.get(Letter::L)),
            shift: [w.get(Letter::I), w.get(Letter::J)],
            spindle_ccw: self.spindle_ccw,
        };
        if polar && cb.incremental && (cb.at[0].is_some() || cb.at[1].is_some()) {
            return Err(Alarm::new(
                NO_FANUC_NUMBER,
                "polar coordinates (G16) under G91 are not supported: program them in G90",
            )
            .into());
        }
        let holes = cb.repeats.map_or(1.0, f64::round);
        let stepped = self.hole_step != [0.0; 2] && holes > 1.0;
        if !stepped && !polar {
            return self.one_cycle(&cb, origin);
        }
        if stepped && !E::CANON {
            return Err(Alarm::new(
                NO_FANUC_NUMBER,
                "a canned cycle repeated by L with NCT's incremental operator has no Fanuc literal form: run with --resolve",
            )
            .into());
        }
        // Hole by hole: the first at the block's words, each repeat adding what the incremental
        // words say (in radius and angle under G16).
        let first = cb.at;
        let count = if stepped { holes as u64 } else { 1 };
        let mut moved = false;
        for k in 0..count {
            let words: [Option<f64>; 2] =
                std::array::from_fn(|i| first[i].map(|v| v + k as f64 * self.hole_step[i]));
            cb.at = if polar && (words[0].is_some() || words[1].is_some()) {
                let r = words[0].unwrap_or(self.polar[0]);
                let ang = words[1].unwrap_or(self.polar[1]);
                if E::CANON && (r.is_nan() || ang.is_nan()) {
                    return Err(Alarm::new(
                        UNKNOWN_POSITION,
                        "G16: a cycle's polar radius or angle is not known (no earlier G16 block gave it)",
                    )
                    .into());
                }
                self.polar = [r, ang];
                let [x, y] = polar_point(r, ang);
                [Some(x), Some(y)]
            } else {
                words
            };
            if stepped {
                cb.repeats = Some(1.0);
            }
            moved |= self.one_cycle(&cb, origin)?;
        }
        Ok(moved)
    }

    /// The native form of one hole, when the control's own cycle says exactly what the steps do: the
    /// XY plane, no rotation, scaling or mirror, a plain hole (G81 G82 G85 G89: position, rapid to R,
    /// feed to the bottom, maybe a dwell, out), R not above the initial level.
    pub(super) fn native_cycle_op(
        &self,
        cb: &cycles::CycleBlock,
        start: &Pose,
        steps: &[cycles::Step],
    ) -> Option<fmsvm_canon::CycleOp> {
        if cb.plane != Plane::XY
            || !self.transform.is_identity()
            || !matches!(
                cb.cycle,
                cycles::Cycle::G81 | cycles::Cycle::G82 | cycles::Cycle::G85 | cycles::Cycle::G89
            )
        {
            return None;
        }
        // K/L repeats drill the hole several times: one native block would drill it once.
        if cb.repeats.is_some_and(|k| k.round() != 1.0) {
            return None;
        }
        // One pass over the steps, in the output frame: the first and last point, the level
        // before the first feed (R), the deepest level, the dwells.
        let from = self.out_point(start);
        let (mut first, mut last) = (None::<Pose>, None::<Pose>);
        let (mut r, mut level, mut bottom, mut dwell) = (None, from[2], f64::INFINITY, 0.0);
        for s in steps {
            let (p, feed) = match *s {
                cycles::Step::Rapid(p) => (p, false),
                cycles::Step::Feed(p) => (p, true),
                cycles::Step::Dwell(t) => {
                    dwell += t;
                    continue;
                }
                _ => return None,
            };
            let q = self.out_point(&p);
            // Every step on the hole's axis line.
            if let Some(f) = first
                && ((q[0] - f[0]).abs() > 1e-9
                    || (q[1] - f[1]).abs() > 1e-9
                    || !same_pose(
                        &[q[3], q[4], q[5], 0.0, 0.0, 0.0],
                        &[f[3], f[4], f[5], 0.0, 0.0, 0.0],
                    ))
            {
                return None;
            }
            if feed && r.is_none() {
                r = Some(level);
            }
            first.get_or_insert(q);
            level = q[2];
            bottom = bottom.min(q[2]);
            last = Some(q);
        }
        let (first, last, r) = (first?, last?, r?);
        // The positioning keeps the level the tool is at (a cycle block positions first, then
        // moves along the cycle axis); a diagonal rise to the initial level has no cycle block.
        if ((first[0] - from[0]).abs() > 1e-9 || (first[1] - from[1]).abs() > 1e-9)
            && (first[2] - from[2]).abs() > 1e-9
        {
            return None;
        }
        let mut hole = last;
        hole[2] = from[2];
        // A hole on an axis the program has not positioned has no cycle block: its moves.
        if hole[..2].iter().any(|v| v.is_nan()) {
            return None;
        }
        let initial = {
            let mut p = *start;
            p[2] = self.cycle.initial_level()?;
            self.out_point(&p)[2]
        };
        let end = last[2];
        let to_r = (end - r).abs() < 1e-9;
        let to_initial = (end - initial).abs() < 1e-9;
        if r > hole[2] + 1e-9 || r > initial + 1e-9 || bottom >= r || !(to_r || to_initial) {
            return None;
        }
        // G89 feeds out of the hole to the return level (LinuxCNC's trace of `G98 G89`, the
        // kernel's steps); a control's own G89 block (Fanuc: "almost the same as G85", feed to R
        // then rapid; the FMS-3000's G82 with H: feed to U, rapid to I) feeds only to R. Above R
        // the two differ: that hole is written as its moves.
        if cb.cycle == cycles::Cycle::G89 && !to_r {
            return None;
        }
        Some(fmsvm_canon::CycleOp {
            code: cb.cycle.code(),
            hole,
            r,
            bottom,
            end,
            initial,
            dwell,
        })
    }

    /// One canned-cycle block with its plane words worked out: its moves through the transforms to
    /// the output; the tool ends where the cycle leaves it.
    pub(super) fn one_cycle(
        &mut self,
        cb: &cycles::CycleBlock,
        origin: Origin,
    ) -> Result<bool, Stop> {
        if E::CANON && self.comp.is_active() {
            return Err(Alarm::new(
                44,
                "a canned cycle under cutter compensation (G41/G42): cancel it with G40 first",
            )
            .into());
        }
        let start = self.position;
        if E::CANON {
            let (a, b, n) = cb.plane.axes();
            for (k, i) in [a, b].into_iter().enumerate() {
                if cb.at[k].is_some() && cb.incremental && start[i].is_nan() {
                    return Err(unknown_axis(
                        i,
                        &format!("the incremental {} word of a canned cycle", AXES[i]),
                    )
                    .into());
                }
            }
            if start[n].is_nan() {
                return Err(unknown_axis(
                    n,
                    "a canned cycle (its initial level is where the tool stands)",
                )
                .into());
            }
        }
        let params = self.settings.cycles;
        let inch = self.modal.inch();
        // The steps wait in a buffer the kernel keeps (no allocation per cycle block): the cycle
        // borrows its modal words while it runs, the output needs the whole kernel.
        let mut steps = std::mem::take(&mut self.steps);
        steps.clear();
        let end = cycles::expand(&mut self.cycle, cb, start, inch, &params, &mut |s| {
            if E::CANON {
                steps.push(s);
            }
            Ok(())
        })?;
        // A lathe's drilling cycles are handed in as the mill's: never written as the mill's codes.
        let native = if E::CANON
            && self.settings.lathe.is_none()
            && self.emitter.native_cycle(cb.cycle.code())
        {
            self.native_cycle_op(cb, &start, &steps)
        } else {
            None
        };
        if let Some(op) = native {
            self.canon(Canon::Cycle(op), origin)?;
        }
        for &s in &steps {
            let op = match s {
                cycles::Step::Rapid(p) => Canon::Rapid(self.out_point(&p)),
                cycles::Step::Feed(p) => Canon::Feed(self.out_point(&p)),
                cycles::Step::Dwell(t) => Canon::Dwell(t),
                cycles::Step::Spindle(sa) => Canon::MCode(match sa {
                    cycles::SpindleAction::Stop => 5.0,
                    cycles::SpindleAction::Clockwise => 3.0,
                    cycles::SpindleAction::CounterClockwise => 4.0,
                    cycles::SpindleAction::Orient => 19.0,
                }),
                cycles::Step::Stop => Canon::MCode(0.0),
            };
            self.canon(op, origin)?;
        }
        if native.is_some() {
            self.canon(Canon::CycleEnd, origin)?;
        }
        self.steps = steps;
        let moved = !same_pose(&end, &start);
        self.position = end;
        Ok(moved)
    }
}
