//! The lathe's reading of a block (docs/lathe.md): X a diameter, U and W the incremental X and Z,
//! Y only on a turning centre that declares one; G50 S (G92 S in system B) the spindle clamp, G96/G97 the spindle's mode; G32 threads and
//! the single cycles G90/G92/G94 (system A; G77/G78/G79 in B) as moves.

use fmsvm_block::alarms::{FORMAT, NO_FANUC_NUMBER};
use fmsvm_block::{Alarm, Block, Flow, Letter, Stop};
use fmsvm_canon::decode::Decoded;
use fmsvm_canon::modal::{Code, Group};
use fmsvm_canon::{Canon, Emitter, Origin, Pose, unknown_axis};

use super::{Kernel, Words};
use crate::{cycles, turning};

/// The words of a lathe's single cycle that stay in force from block to block (Fanuc: "X(U), Z(W)
/// and R of a canned cycle are modal"): the end point, absolute, and the taper, radius.
#[derive(Clone, Copy, Debug)]
pub(super) struct SingleCycle {
    /// X (radius) and Z of the cycle's end point.
    pub end: [f64; 2],
    /// R: the taper (G90, G92: X at the cut's start minus X at its end, radius; G94: the same in Z).
    pub taper: f64,
}

/// The words of a lathe's chamfering and corner R (0i-TD, parameter 3405#4 CCR = 0: I K and R,
/// and C as in CCR = 1).
const CORNER_LETTERS: [(Letter, char); 4] = [
    (Letter::I, 'I'),
    (Letter::K, 'K'),
    (Letter::C, 'C'),
    (Letter::R, 'R'),
];

/// What a chamfering or corner R block requires of the next block: a G1 along `axis` (0 X, 2 Z)
/// in the direction of `sign`.
#[derive(Clone, Copy, Debug)]
pub(super) struct CornerNext {
    axis: usize,
    sign: f64,
    word: char,
}

impl<E: Emitter> Kernel<E> {
    /// Step 2b on a lathe: the words as the kernel reads a mill's. X (and U) halve on a diameter
    /// lathe; U and W become incremental X and Z; a dwell's U is its X (seconds). The words of G10
    /// and of the multiple repetitive cycles (G70–G76) are the cycle's data, read there.
    #[cold]
    #[inline(never)]
    pub(super) fn lathe_words(&mut self, w: &mut Words) -> Result<(), Alarm> {
        let Some(lathe) = self.settings.lathe else {
            return Ok(());
        };
        // A turning centre's Y (V its increment, `G28 V0`): a position where the machine has the
        // axis, moved as X and Z are by G0/G1 and the returns; in an arc or a cycle it would be a
        // helix or an offset the cycle does not know.
        for l in [Letter::Y, Letter::V] {
            if !w.has(l) {
                continue;
            }
            if !lathe.y_axis {
                return Err(Alarm::new(
                    FORMAT,
                    format!(
                        "{l}: this lathe has no Y axis (a turning centre's Y, V its increment: declare it with [machine] y_axis = true in --params)"
                    ),
                ));
            }
            let returns = matches!(w.non_modal, Some(Code::G28 | Code::G30 | Code::G53));
            let positions = w.non_modal.is_none()
                && self.modal.get(Group::CannedCycle) == Code::G80
                && matches!(self.modal.get(Group::Motion), Code::G0 | Code::G1);
            if !(returns || positions) {
                return Err(Alarm::new(
                    FORMAT,
                    format!(
                        "{l}: a turning centre's Y moves with G0 or G1 (and G28, G30, G53), not in an arc, a thread or a cycle"
                    ),
                ));
            }
        }
        for l in [Letter::A, Letter::B, Letter::C] {
            // C is also a chamfer (G1) and G10's added nose radius.
            let c_word = l == Letter::C
                && (w.non_modal == Some(Code::G10)
                    || (w.non_modal.is_none() && self.modal.get(Group::Motion) == Code::G1));
            // A Haas G76's A is the tool angle.
            let haas_angle = l == Letter::A
                && self.settings.haas_codes
                && w.non_modal == Some(Code::THREADING_MULTIPLE);
            if w.has(l) && !c_word && !haas_angle {
                return Err(Alarm::new(
                    FORMAT,
                    format!(
                        "{l}: a lathe of X and Z has no {l} axis (a C axis, a chamfer word C: not yet modelled)"
                    ),
                ));
            }
        }
        let motion = self.modal.get(Group::Motion);
        let follows = self.corner_next.take();
        if let Some(next) = follows
            && w.non_modal.is_some()
        {
            return Err(Alarm::new(
                52,
                format!(
                    "CODE IS NOT G01 AFTER CHF/CNR: the block after {} must be a G1 move",
                    next.word
                ),
            ));
        }
        // In a drilling cycle's mode R is the cycle's.
        let moves = w.non_modal.is_none() && self.modal.get(Group::CannedCycle) == Code::G80;
        let corner = moves && motion == Code::G1 && CORNER_LETTERS.iter().any(|&(l, _)| w.has(l));
        if moves && motion == Code::G0 && CORNER_LETTERS.iter().any(|&(l, _)| w.has(l)) {
            return Err(Alarm::new(
                52,
                "chamfering and corner R (I, K, C, R) are of G1 only, not of a rapid",
            ));
        }
        if w.has(Letter::Q) && matches!(motion, Code::G33 | Code::THREADING_CYCLE) {
            return Err(Alarm::new(
                NO_FANUC_NUMBER,
                "Q on a thread (the start angle of a multi-start thread) is not yet resolved: cut each start as a thread of its own",
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
        let x_factor = lathe.radius_per_x_word();
        for (axis, letter, increment, factor) in [
            (0, Letter::X, Letter::U, x_factor),
            (1, Letter::Y, Letter::V, 1.0),
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
                (None, Some(v)) if w.non_modal == Some(Code::G92) => {
                    // G50 U W: the position becomes where the tool stands plus U W.
                    if self.position[axis].is_nan() {
                        return Err(unknown_axis(
                            axis,
                            &format!("G50 {increment} (an increment from where the tool stands)"),
                        ));
                    }
                    w.value[letter.index()] = self.position[axis] + v * factor;
                    w.value[increment.index()] = f64::NAN;
                }
                (None, Some(v)) => {
                    w.value[letter.index()] = v * factor;
                    w.value[increment.index()] = f64::NAN;
                    w.inc |= 1 << axis;
                }
                (None, None) => {}
            }
        }
        if let Some(next) = follows {
            self.corner_follows(w, next)?;
        }
        if corner {
            self.corner_next = Some(self.chamfer_words(w)?);
        }
        Ok(())
    }

    /// A chamfering or corner R block (`G1 Z-20. I2.`, `G1 X40. K-1.`, `C`, `R`): one axis moves to
    /// the corner, the word becomes the contour stage's `,C` or `,R` (the same chamfer and arc
    /// between two perpendicular moves), and the next block must leave the corner along the other
    /// axis in the word's sign. The amounts are radii. 0i-TD "Chamfering and corner R", alarms
    /// PS0051–PS0055.
    fn chamfer_words(&self, w: &mut Words) -> Result<CornerNext, Alarm> {
        let given: Vec<(Letter, char)> = CORNER_LETTERS
            .iter()
            .copied()
            .filter(|&(l, _)| w.has(l))
            .collect();
        if given.len() > 1 {
            return Err(Alarm::new(
                53,
                "TOO MANY ADDRESS COMMANDS: one of I, K, C and R in a chamfering or corner R block",
            ));
        }
        let (letter, name) = given[0];
        let moves = [
            w.has(Letter::X) || w.has(Letter::U),
            w.has(Letter::Z) || w.has(Letter::W),
        ];
        let axis = match moves {
            [true, false] => 0,
            [false, true] => 2,
            _ => {
                return Err(Alarm::new(
                    54,
                    format!(
                        "NO TAPER ALLOWED AFTER CHF/CNR: a block with {name} moves X or Z, not both nor neither"
                    ),
                ));
            }
        };
        let along_x = axis == 0;
        if (letter == Letter::I && along_x) || (letter == Letter::K && !along_x) {
            return Err(Alarm::new(
                53,
                format!(
                    "{name} on a move along {}: I is the chamfer of a move along Z (towards X), K of a move along X (towards Z)",
                    if along_x { "X" } else { "Z" }
                ),
            ));
        }
        let v = w.get(letter).unwrap_or(0.0);
        if v == 0.0 {
            return Err(Alarm::new(
                55,
                format!("MISSING MOVE VALUE IN CHF/CNR: {name}0"),
            ));
        }
        w.value[letter.index()] = f64::NAN;
        let comma = if letter == Letter::R {
            Letter::CommaR
        } else {
            Letter::CommaC
        };
        w.value[comma.index()] = v.abs();
        Ok(CornerNext {
            axis: if along_x { 2 } else { 0 },
            sign: v.signum(),
            word: name,
        })
    }

    /// The block after a chamfering or corner R block: G1 along the other axis only, in the sign
    /// of the chamfer's word.
    fn corner_follows(&self, w: &Words, next: CornerNext) -> Result<(), Alarm> {
        let axis_names = if next.axis == 0 { "X (U)" } else { "Z (W)" };
        if w.non_modal.is_some() || self.modal.get(Group::Motion) != Code::G1 {
            return Err(Alarm::new(
                52,
                format!(
                    "CODE IS NOT G01 AFTER CHF/CNR: the block after {} must be a G1 move along {axis_names}",
                    next.word
                ),
            ));
        }
        let letter = if next.axis == 0 { Letter::X } else { Letter::Z };
        let other = if next.axis == 0 { Letter::Z } else { Letter::X };
        let delta = w.get(letter).map(|v| {
            if w.incremental(next.axis, self.modal.incremental()) {
                v
            } else {
                v - self.position[next.axis]
            }
        });
        match delta {
            Some(d) if !w.has(other) && d * next.sign > 0.0 => Ok(()),
            _ => Err(Alarm::new(
                51,
                format!(
                    "MISSING MOVE AFTER CNR/CHF: the block after {} must move along {axis_names} only, towards {}",
                    next.word,
                    if next.sign > 0.0 { "+" } else { "-" }
                ),
            )),
        }
    }

    /// G41/G42 on a lathe: the nose radius of the tool offset the last T word chose (its lower two
    /// digits, `T0101` offset 01: 0i-TD parameter 5002#0 LD1 = 0) and where its controlled point,
    /// the imaginary tool nose, is from the nose centre.
    pub(super) fn nose_radius(&mut self, origin: Origin) -> Result<(f64, Pose), Stop> {
        let n = self
            .last_value(Letter::T)
            .map_or(0.0, |t| t.round().abs() % 100.0);
        self.register_set('T', Some(n), origin)?;
        if n == 0.0 {
            return Ok((0.0, [0.0; 6]));
        }
        let reg = self.frames.tool(n)?;
        let r = reg.radius();
        if r < 0.0 {
            // A mill's negative radius swaps the side; a nose has no negative radius.
            return Err(Alarm::new(
                NO_FANUC_NUMBER,
                format!("tool offset {n:02}: a nose radius of {r} (geometry and wear): below zero"),
            )
            .into());
        }
        Ok((r, imaginary_tip(reg.tip, r)))
    }

    /// A lathe's drilling cycle block (G83–G85 on the face, along Z at X; G87–G89 on the side,
    /// along X at Z), handed to the mill's cycles with the drilling axis as the plane's normal (G17
    /// for the face, G19 for the side): R is the distance from the initial level to R (signed; a
    /// radius on the side, *inferred*), Z (X) the bottom or W (U) the distance from R to it, Q the
    /// peck (then out to R after each peck, as the mill's G83: parameter 5101#2 RTR = 1), P the
    /// dwell at the bottom, K the repeats. The tool returns to the initial level in G-code system
    /// A, to the level G98/G99 choose in system B (docs/lathe.md, "Drilling cycles").
    pub(super) fn lathe_drilling(
        &mut self,
        code: Code,
        w: &Words,
        origin: Origin,
    ) -> Result<bool, Stop> {
        let face = matches!(
            code,
            Code::FACE_DRILLING | Code::FACE_TAPPING | Code::FACE_BORING
        );
        // The drilling axis n and the positioning axis m (X 0, Z 2).
        let (n, m) = if face { (2, 0) } else { (0, 2) };
        let name = format!("G{}", self.modal.system.written(code));
        let inc = self.modal.incremental();
        let absolute = |i: usize, v: f64| -> Result<f64, Alarm> {
            if w.incremental(i, inc) {
                let from = self.position[i];
                if from.is_nan() {
                    return Err(unknown_axis(i, &format!("the increment of {name}")));
                }
                Ok(from + v)
            } else {
                Ok(v)
            }
        };
        let initial = self.cycle.initial_level().unwrap_or(self.position[n]);
        let r_level = match w.get(Letter::R) {
            Some(r) => Some(initial + r),
            None => self.cycle.r_word(),
        };
        let depth = match w.get(fmsvm_canon::AXES[n]) {
            Some(v) if w.incremental(n, inc) => Some(
                r_level.ok_or_else(|| {
                    Alarm::new(
                        FORMAT,
                        format!(
                            "{name}: an incremental depth needs R (the distance to the R level)"
                        ),
                    )
                })? + v,
            ),
            Some(v) => Some(v),
            None => None,
        };
        let peck = w.get(Letter::Q).or(self.cycle.q_word());
        let dwell = w
            .get(Letter::P)
            .or(self.cycle.p_word())
            .is_some_and(|p| p > 0.0);
        let cycle = match code {
            Code::FACE_DRILLING | Code::SIDE_DRILLING if peck.is_some() => cycles::Cycle::G83,
            Code::FACE_DRILLING | Code::SIDE_DRILLING if dwell => cycles::Cycle::G82,
            Code::FACE_DRILLING | Code::SIDE_DRILLING => cycles::Cycle::G81,
            Code::FACE_TAPPING | Code::SIDE_TAPPING => cycles::Cycle::G84,
            _ if dwell => cycles::Cycle::G89,
            _ => cycles::Cycle::G85,
        };
        let at = match w.get(fmsvm_canon::AXES[m]) {
            Some(v) => Some(absolute(m, v)?),
            None => None,
        };
        if E::CANON
            && self.modal.system == fmsvm_canon::modal::CodeSystem::LatheA
            && !self.warned("returns to its initial level")
        {
            let text = format!(
                "{name} returns to its initial level after each hole (inferred for G-code system A, where G98/G99 are feeds: a control that returns to R moves less)"
            );
            self.warn(origin, text);
        }
        let cb = cycles::CycleBlock {
            cycle,
            plane: if face {
                fmsvm_canon::Plane::XY
            } else {
                fmsvm_canon::Plane::YZ
            },
            incremental: false,
            retract_to_r: self.modal.get(Group::ReturnLevel) == Code::G99,
            // The plane's first and second axes: X Y (face), Y Z (side); Y stays on the centre.
            at: if face { [at, None] } else { [None, at] },
            depth,
            r: r_level,
            q: w.get(Letter::Q),
            p: w.get(Letter::P),
            repeats: w.get(Letter::K),
            shift: [None, None],
            spindle_ccw: self.spindle_ccw,
        };
        self.one_cycle(&cb, origin)
    }

    /// `G10 P X(U) Z(W) R(C) Q` on a lathe: tool offset P's wear (P1–P999) or geometry (P10001–
    /// P10999): X Z (U W added), the nose radius R (C added) and the tip Q (0i-TD "Changing of tool
    /// offset value (programmable data input) (G10)"). Literal output passes the block on to the
    /// control. Resolved output makes the nose radius compensation itself, so R and Q are fmsvm's;
    /// X Z are the control's, which the flat program cannot set: alarm.
    pub(super) fn lathe_offset_setting(&mut self, w: &Words) -> Result<(), Alarm> {
        let p = w.get(Letter::P).unwrap_or(f64::NAN);
        let (geometry, n) = match p {
            p if (1.0..=999.0).contains(&p) && p.fract() == 0.0 => (false, p),
            p if (10_001.0..=10_999.0).contains(&p) && p.fract() == 0.0 => (true, p - 10_000.0),
            _ => {
                return Err(Alarm::new(
                    FORMAT,
                    format!(
                        "G10 P{p}: a lathe's tool offset is P1–P999 (wear) or P10001–P10999 (geometry)"
                    ),
                ));
            }
        };
        let moves_xz = [Letter::X, Letter::U, Letter::Z, Letter::W]
            .iter()
            .any(|&l| w.has(l));
        if E::CANON && moves_xz {
            return Err(Alarm::new(
                115,
                "G10 P X Z: the X and Z of a lathe's tool offset are the control's register, which resolved output cannot set (the control applies them by T): set them on the control, or write the program literally",
            ));
        }
        let inc = self.modal.incremental();
        let reg = self.frames.tool_mut(n)?;
        reg.set = true;
        let xz = if geometry {
            &mut reg.xz_geometry
        } else {
            &mut reg.xz_wear
        };
        for (k, (abs, add)) in [(Letter::X, Letter::U), (Letter::Z, Letter::W)]
            .into_iter()
            .enumerate()
        {
            match (w.get(abs), w.get(add)) {
                (Some(v), _) => xz[k] = if inc { xz[k] + v } else { v },
                (None, Some(v)) => xz[k] += v,
                (None, None) => {}
            }
        }
        let radius = if geometry {
            &mut reg.radius_geometry
        } else {
            &mut reg.radius_wear
        };
        match (w.get(Letter::R), w.get(Letter::C)) {
            (Some(v), _) => *radius = if inc { *radius + v } else { v },
            (None, Some(v)) => *radius += v,
            (None, None) => {}
        }
        if let Some(q) = w.get(Letter::Q) {
            if !(0.0..=9.0).contains(&q) || q.fract() != 0.0 {
                return Err(Alarm::new(
                    FORMAT,
                    format!("G10 Q{q}: the imaginary tool nose direction is 0 to 9"),
                ));
            }
            reg.tip = q as u8;
        }
        Ok(())
    }

    /// Before a lathe's first cutting move: an F must have gone out (Fanuc PS0011: a cutting feed
    /// with no F; the output would say F0).
    #[cold]
    pub(super) fn lathe_feed_known(&mut self, op: &Canon<'_>) -> Result<(), Stop> {
        match op {
            Canon::FeedRate(f) if *f > 0.0 => self.feed_known = true,
            Canon::Feed(_) | Canon::Skip(_) | Canon::Arc(_) => {
                return Err(Alarm::new(11, "feed zero: a cutting move before any F").into());
            }
            _ => {}
        }
        Ok(())
    }

    /// A lathe cycle resolved into moves starts and ends where the tool stands: both axes must be
    /// known. Under tool nose radius compensation only the cycles that run the profile's blocks as
    /// they are (`runs_profile`: G70, G73) may start; their moves are compensated as the blocks
    /// written out would be.
    fn cycle_may_start(&self, name: &str, runs_profile: bool) -> Result<(), Stop> {
        if !E::CANON {
            // Literal output: the control runs the cycle from where it stands.
            return Ok(());
        }
        for (i, what) in [(0, "X"), (2, "Z")] {
            if self.position[i].is_nan() {
                return Err(unknown_axis(
                    i,
                    &format!("{name} (it returns to its start point, {what})"),
                )
                .into());
            }
        }
        if self.comp.is_active() && !runs_profile {
            return Err(Alarm::new(
                NO_FANUC_NUMBER,
                format!("{name} under tool nose radius compensation: fmsvm does not offset a roughing or threading cycle's shape; give it under G40 (a roughing allowance covers the nose) and finish with G70 under G41/G42"),
            )
            .into());
        }
        Ok(())
    }

    /// The spindle words of a lathe block: G50 S (system A; G92 S in B) clamps the spindle, S under
    /// G96 is the surface speed, otherwise rpm. True when the block's S was taken here.
    #[cold]
    #[inline(never)]
    pub(super) fn lathe_spindle(&mut self, w: &Words, origin: Origin) -> Result<bool, Stop> {
        if self.settings.lathe.is_none() {
            return Ok(false);
        }
        let s = w.get(Letter::S);
        if w.non_modal == Some(Code::G92) {
            if let Some(s) = s {
                self.spindle_clamped = true;
                self.canon(Canon::SpindleClamp(s), origin)?;
                return Ok(true);
            }
            return Ok(false);
        }
        match s {
            Some(s) => self.spindle_speed(s, origin)?,
            None if w.names(Group::SurfaceSpeed) => {
                // G96 or G97 alone: the last S in its new meaning (Fanuc keeps S as given; a G50 S
                // is the clamp, not this S).
                let Some(last) = self.spindle_s else {
                    if self.modal.get(Group::SurfaceSpeed) == Code::G96 {
                        return Err(Alarm::new(
                            FORMAT,
                            "G96 without S: the surface speed (m/min) was never given",
                        )
                        .into());
                    }
                    return Ok(true);
                };
                self.spindle_speed(last, origin)?;
            }
            None => {}
        }
        Ok(true)
    }

    /// A lathe's S (outside G50): kept for G96/G97 alone, and a surface speed under G96, else rpm.
    fn spindle_speed(&mut self, s: f64, origin: Origin) -> Result<(), Stop> {
        self.spindle_s = Some(s);
        let css = self.modal.get(Group::SurfaceSpeed) == Code::G96;
        if css && !self.spindle_clamped {
            // Fanuc's lathe manuals (Series 16/18-C lathe, "Clamp of maximum spindle speed"): at
            // power-on the maximum spindle speed is not set and the speed is not clamped, so a cut
            // towards X0 under G96 would run the spindle up to the machine's limit.
            let Some(max) = self.settings.lathe.and_then(|l| l.max_rpm) else {
                return Err(Alarm::new(
                    NO_FANUC_NUMBER,
                    "G96 (constant surface speed) with no spindle clamp: give G50 S (G92 S in G-code system B) before it, or the machine's [machine] max_rpm in the parameters",
                )
                .into());
            };
            self.spindle_clamped = true;
            self.canon(Canon::SpindleClamp(max), origin)?;
        }
        self.canon(
            if css {
                Canon::SurfaceSpeed(s)
            } else {
                Canon::Speed(s)
            },
            origin,
        )
    }

    /// G32 (the lathe's G33): a thread to `to`, its lead F (per revolution); the tool moves with the
    /// spindle, so neither compensation nor a held corner may act on it.
    #[cold]
    #[inline(never)]
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
    #[cold]
    #[inline(never)]
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
        self.cycle_may_start(&format!("G{name}"), false)?;
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

/// A multiple repetitive cycle's code (G70–G76 of system A and B).
pub(super) fn is_repetitive(code: Code) -> bool {
    matches!(
        code,
        Code::FINISHING_CYCLE
            | Code::TURNING_STOCK_REMOVAL
            | Code::FACING_STOCK_REMOVAL
            | Code::PATTERN_REPEATING
            | Code::FACE_PECK_DRILLING
            | Code::GROOVING_CYCLE
            | Code::THREADING_MULTIPLE
    )
}

/// The words the first block of a two-block cycle leaves in force (Fanuc: "modal", until the next
/// first block): G71's and G72's depth of cut and retract, G73's relief and number of passes.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct CycleWords {
    /// G71 U(Δd) R(e).
    pub g71: Option<[f64; 2]>,
    /// G72 W(Δd) R(e).
    pub g72: Option<[f64; 2]>,
    /// G73 U(Δi, radius) W(Δk) R(d).
    pub g73: Option<[f64; 3]>,
    /// G74 R(e), G75 R(e).
    pub g74: Option<f64>,
    /// G75 R(e).
    pub g75: Option<f64>,
    /// G76 P(m r a) Q(Δdmin) R(d): m, r, a, Δdmin, d.
    pub g76: Option<[f64; 5]>,
}

/// A cycle reading its profile from the blocks that follow it.
#[derive(Clone, Debug)]
pub(super) struct Capture {
    /// The cycle's code (a meaning).
    code: Code,
    /// Its block, for messages.
    pub(super) origin: Origin,
    /// What it will do with the profile.
    job: Job,
    /// The start point A (the tool's position at the cycle's block).
    start: Pose,
    /// The profile as read so far.
    pub(super) profile: turning::ProfileBlocks,
    /// N(P) came.
    started: bool,
    /// The profile's own modal state (its G0–G3 are not the program's).
    modal: fmsvm_canon::modal::ModalState,
    /// An F of a block without a move, for the next move.
    pending: Option<turning::BlockCodes>,
}

/// What a cycle does with its profile.
#[derive(Clone, Copy, Debug)]
enum Job {
    Finishing(Option<f64>),
    StockRemoval(usize, turning::StockRemoval),
    PatternRepeating(turning::PatternRepeating),
}

/// What a point-to-point cycle (G74 G75 G76) does: its moves need no profile.
#[derive(Clone, Copy, Debug)]
enum Direct {
    Pecking(usize, turning::Pecking),
    Threading(turning::Threading),
}

/// The warning of a G76 whose passes feed in along the tool's flank (`angle` as the block says it).
fn flank_infeed(name: &str, angle: &str) -> String {
    format!(
        "{name} feeds in along the tool's flank ({angle}): each pass starts depth·tan(angle/2) further along the cut, as LinuxCNC's G76 does (the direction is inferred; an angle of 0 feeds straight in)"
    )
}

/// A Haas one-block cycle in literal output: a Fanuc reads G70–G76 in two blocks, without D.
fn haas_literal(name: &str) -> Alarm {
    Alarm::new(
        FORMAT,
        format!(
            "{name} in Haas's one-block form has no Fanuc literal form (a Fanuc lathe reads the cycle in two blocks, without D): run with --resolve, or write the two-block form"
        ),
    )
}

/// The most blocks a profile may have (a bound on memory; Fanuc's own is far below).
const MAX_PROFILE: usize = 100_000;
/// The most profiles kept for a later G70.
const MAX_PROFILES: usize = 1_000;

impl<E: Emitter> Kernel<E> {
    /// Literal output for a Haas (`haaslathe`): its one-block cycles are written as the program
    /// wrote them, for the control to run; the kernel does not work out their moves.
    fn haas_runs_it(&self) -> bool {
        !E::CANON && self.settings.haas_output
    }

    /// The kernel's X per unit of this lathe's X or U word (½ on a diameter lathe).
    fn radius_per_x_word(&self) -> f64 {
        self.settings
            .lathe
            .map_or(0.5, super::Lathe::radius_per_x_word)
    }

    /// The raw number of address `letter` in `block` (P and Q of a cycle are sequence numbers).
    fn raw(block: &Block<'_>, letter: Letter) -> Option<f64> {
        block
            .words()
            .iter()
            .rev()
            .find(|w| w.letter == letter)
            .map(|w| w.value)
    }

    /// A G70–G73 block (Fanuc 0i-TD, "Multiple repetitive cycles"; docs/lathe.md): a first block
    /// stores its words, a second (with P and Q) reads the profile N(P)–N(Q) — kept from an earlier
    /// cycle, or read from the blocks that follow — and runs the cycle from where the tool stands.
    #[cold]
    #[inline(never)]
    pub(super) fn repetitive_cycle(
        &mut self,
        block: &Block<'_>,
        code: Code,
        w: &Words,
        origin: Origin,
    ) -> Result<(), Stop> {
        let name = format!("G{}", self.modal.system.written(code));
        let x_factor = self.radius_per_x_word();
        if matches!(
            code,
            Code::FACE_PECK_DRILLING | Code::GROOVING_CYCLE | Code::THREADING_MULTIPLE
        ) {
            return self.direct_cycle(block, code, w, origin);
        }
        let (p, q) = (Self::raw(block, Letter::P), Self::raw(block, Letter::Q));
        if code != Code::FINISHING_CYCLE && p.is_none() && q.is_none() {
            // The first block: its words stay in force.
            return self.profile_first_block(code, w, &name);
        }
        let (Some(p), Some(q)) = (p, q) else {
            return Err(Alarm::new(
                FORMAT,
                format!("{name} without P and Q (the profile's first and last sequence numbers)"),
            )
            .into());
        };
        let seq = |v: f64, l: &str| -> Result<u32, Alarm> {
            if v.fract() == 0.0 && (1.0..=99_999.0).contains(&v) {
                Ok(v as u32)
            } else {
                Err(Alarm::new(
                    FORMAT,
                    format!("{name} {l}{v}: a sequence number 1 to 99999"),
                ))
            }
        };
        let (ns, nf) = (seq(p, "P")?, seq(q, "Q")?);
        self.cycle_may_start(
            &name,
            matches!(code, Code::FINISHING_CYCLE | Code::PATTERN_REPEATING),
        )?;
        let feed = w.get(Letter::F);
        let allowance = [
            w.get(Letter::U).unwrap_or(0.0) * x_factor,
            w.get(Letter::W).unwrap_or(0.0),
        ];
        let job = match code {
            Code::FINISHING_CYCLE => Job::Finishing(feed),
            Code::TURNING_STOCK_REMOVAL | Code::FACING_STOCK_REMOVAL => {
                let turning = code == Code::TURNING_STOCK_REMOVAL;
                let first = if let Some(one) = self.haas_stock_removal(block, &name)? {
                    Some(one)
                } else if turning {
                    self.cycle_words.g71
                } else {
                    self.cycle_words.g72
                };
                let Some([depth, retract]) = first else {
                    return Err(Alarm::new(
                        FORMAT,
                        format!("{name} P{ns} Q{nf} without its first block ({name} {}… R…: fmsvm does not know the control's parameters 5132/5133)", if turning { "U" } else { "W" }),
                    )
                    .into());
                };
                Job::StockRemoval(
                    if turning { 1 } else { 0 },
                    turning::StockRemoval {
                        depth,
                        retract,
                        allowance,
                        feed,
                    },
                )
            }
            _ => {
                let Some([di, dk, d]) = self
                    .haas_pattern_repeating(block, &name)?
                    .or(self.cycle_words.g73)
                else {
                    return Err(Alarm::new(
                        FORMAT,
                        format!("{name} P{ns} Q{nf} without its first block ({name} U… W… R…: fmsvm does not know the control's parameters 5135–5137)"),
                    )
                    .into());
                };
                if d.fract() != 0.0 || !(1.0..=f64::from(turning::MAX_PATTERN_PASSES)).contains(&d)
                {
                    return Err(Alarm::new(
                        FORMAT,
                        format!(
                            "{name}: the number of passes ({} here) is a whole number from 1 to {}, not {d}",
                            if self.settings.haas_codes && Self::raw(block, Letter::D).is_some() {
                                "D"
                            } else {
                                "R"
                            },
                            turning::MAX_PATTERN_PASSES
                        ),
                    )
                    .into());
                }
                Job::PatternRepeating(turning::PatternRepeating {
                    relief: [di, dk],
                    passes: d as u32,
                    allowance,
                    feed,
                })
            }
        };
        let start = self.position;
        // G70 finishes a profile read before (by its G71–G73); a roughing cycle reads its profile
        // from the blocks after it (Fanuc skips them then), or, when they are not its profile, uses
        // one read before.
        if code == Code::FINISHING_CYCLE
            && let Some(profile) = self.stored_profile(ns, nf)
        {
            return self.run_repetitive(job, start, &profile, origin);
        }
        self.capture = Some(Box::new(Capture {
            code,
            origin: Origin { fixed: 0, ..origin },
            job,
            start,
            profile: turning::ProfileBlocks {
                ns,
                nf,
                ..turning::ProfileBlocks::default()
            },
            started: false,
            modal: self.modal.clone(),
            pending: None,
        }));
        Ok(())
    }

    /// A Haas lathe's G71/G72 in one block (`G71 P Q U W D F`; the Haas lathe operator's manual,
    /// "G71 O.D./I.D. Stock Removal Cycle", "G72 End Face Stock Removal Cycle"): D the depth of cut
    /// (positive, a radius), the retract Haas Setting 73 (NGC 287), none of the block. None where
    /// the block has no D (the two-block form, which the NGC reads as Fanuc does).
    fn haas_stock_removal(&self, block: &Block<'_>, name: &str) -> Result<Option<[f64; 2]>, Alarm> {
        if !self.settings.haas_codes {
            return Ok(None);
        }
        let Some(depth) = Self::raw(block, Letter::D) else {
            return Ok(None);
        };
        if self.haas_runs_it() {
            // The tool ends where it began: D is only checked.
            return Ok(Some([depth, 0.0]));
        }
        if !E::CANON {
            return Err(haas_literal(name));
        }
        if !(depth.is_finite() && depth > 0.0) {
            return Err(Alarm::new(
                FORMAT,
                format!("{name} D{depth}: the depth of cut is positive (a radius)"),
            ));
        }
        for (letter, what) in [(Letter::I, "X"), (Letter::K, "Z")] {
            if Self::raw(block, letter).is_some() {
                return Err(Alarm::new(
                    FORMAT,
                    format!(
                        "{name} {letter}: Haas's {what} rough-pass allowance; how its passes leave it is not described in the Haas text fmsvm follows, so the cycle is refused rather than guessed (leave it out: U and W give the finishing allowance)"
                    ),
                ));
            }
        }
        let Some(retract) = self.settings.cycles.stock_retract else {
            return Err(Alarm::new(
                FORMAT,
                format!(
                    "{name} in one block (D{depth}): its retract is the control's Setting 73 (Can Cycle Retraction; 287 on the NGC), which fmsvm does not know: give it in --params ([cycles] setting_73 = …, the program's units), or write the two-block form ({name} {}{depth} R…)",
                    if name.ends_with('1') { "U" } else { "W" }
                ),
            ));
        };
        Ok(Some([depth, retract]))
    }

    /// A Haas lathe's G73 in one block (`G73 P Q U W I K D F`; the Haas lathe operator's manual,
    /// "G73 Irregular Path Stock Removal Cycle"): I and K the relief from the first cut to the last
    /// (I a radius), D the number of passes. None without them (the two-block form).
    fn haas_pattern_repeating(
        &self,
        block: &Block<'_>,
        name: &str,
    ) -> Result<Option<[f64; 3]>, Alarm> {
        if !self.settings.haas_codes {
            return Ok(None);
        }
        let (i, k, d) = (
            Self::raw(block, Letter::I),
            Self::raw(block, Letter::K),
            Self::raw(block, Letter::D),
        );
        if i.is_none() && k.is_none() && d.is_none() {
            return Ok(None);
        }
        if !E::CANON && !self.haas_runs_it() {
            return Err(haas_literal(name));
        }
        // A missing one is 0 relief or, for D, no pass (refused as the two-block R is).
        Ok(Some([i.unwrap_or(0.0), k.unwrap_or(0.0), d.unwrap_or(0.0)]))
    }

    /// The profile N`ns`–N`nf` read last, if any.
    fn stored_profile(&self, ns: u32, nf: u32) -> Option<turning::ProfileBlocks> {
        self.profiles
            .iter()
            .rev()
            .find(|p| p.ns == ns && p.nf == nf)
            .cloned()
    }

    /// The first block of G71, G72 or G73: its words, kept until the next first block.
    fn profile_first_block(&mut self, code: Code, w: &Words, name: &str) -> Result<(), Stop> {
        let (u, wv, r) = (w.get(Letter::U), w.get(Letter::W), w.get(Letter::R));
        let need = |v: Option<f64>, what: &str| {
            v.ok_or_else(|| {
                Alarm::new(
                    FORMAT,
                    format!("{name}'s first block without {what} (the control's parameter for it is not known to fmsvm: give it)"),
                )
            })
        };
        match code {
            Code::TURNING_STOCK_REMOVAL => {
                self.cycle_words.g71 = Some([
                    need(u, "U (the depth of cut)")?,
                    need(r, "R (the retract)")?,
                ]);
            }
            Code::FACING_STOCK_REMOVAL => {
                self.cycle_words.g72 = Some([
                    need(wv, "W (the depth of cut)")?,
                    need(r, "R (the retract)")?,
                ]);
            }
            _ => {
                let passes = need(r, "R (the number of passes)")?;
                self.cycle_words.g73 = Some([
                    // Δi is a radius whatever X is (0i-TD: "radius designation").
                    need(u, "U (the relief in X)")?,
                    need(wv, "W (the relief in Z)")?,
                    passes,
                ]);
            }
        }
        Ok(())
    }

    /// A block of a profile being read: its move recorded (not made), in the profile's own modal
    /// state; written as it is by a literal emitter; at N(Q) the cycle runs.
    #[cold]
    #[inline(never)]
    pub(super) fn profile_block(&mut self, block: &Block<'_>) -> Result<Flow, Stop> {
        let Some(mut cap) = self.capture.take() else {
            return Ok(Flow::Continue);
        };
        let name = format!("G{}", self.modal.system.written(cap.code));
        let n = Self::raw(block, Letter::N);
        if !cap.started && n != Some(f64::from(cap.profile.ns)) {
            if let Some(profile) = self.stored_profile(cap.profile.ns, cap.profile.nf) {
                // Not the profile: the one read before, then this block as any other.
                let origin = Origin {
                    block_delete: false,
                    ..cap.origin
                };
                self.run_repetitive(cap.job, cap.start, &profile, origin)?;
                return <Self as fmsvm_block::Machine>::block(self, block);
            }
            return Err(Alarm::new(
                FORMAT,
                format!(
                    "{name} at line {} reads its profile N{}–N{} from the blocks after it: the next block must be N{} (a profile elsewhere in the program is not yet read)",
                    cap.origin.line, cap.profile.ns, cap.profile.nf, cap.profile.ns
                ),
            )
            .into());
        }
        cap.started = true;
        let saved_last = self.last;
        std::mem::swap(&mut self.modal, &mut cap.modal);
        let read = self.profile_words(block, &mut cap);
        std::mem::swap(&mut self.modal, &mut cap.modal);
        // F S T of a profile act only in G70: the program's last values are as before it.
        self.last = saved_last;
        let (ctx, flow) = read?;
        if flow == Flow::End {
            return Err(Alarm::new(
                FORMAT,
                format!(
                    "the program ends inside {name}'s profile N{}–N{}",
                    cap.profile.ns, cap.profile.nf
                ),
            )
            .into());
        }
        if !E::CANON {
            self.emitter
                .block(&Decoded::view(block, &self.decoded), &ctx)?;
        }
        if n == Some(f64::from(cap.profile.nf)) {
            let origin = Origin::of(block, 0);
            let profile = cap.profile.clone();
            // The profile read last replaces one of the same numbers (a loop, a subprogram).
            self.profiles
                .retain(|p| !(p.ns == profile.ns && p.nf == profile.nf));
            if self.profiles.len() >= MAX_PROFILES {
                self.profiles.remove(0);
            }
            self.profiles.push(profile.clone());
            self.run_repetitive(cap.job, cap.start, &profile, origin)?;
        } else {
            self.capture = Some(cap);
        }
        Ok(flow)
    }

    /// One profile block's words read into its piece.
    fn profile_words(
        &mut self,
        block: &Block<'_>,
        cap: &mut Capture,
    ) -> Result<(fmsvm_canon::Context, Flow), Stop> {
        let mut w = Words::empty();
        self.modal_codes(block, &mut w)?;
        let (ctx, flow) = self.decode_words(block, &mut w)?;
        let name = format!("G{}", self.modal.system.written(cap.code));
        // A chamfer or corner R: the profile's (made when it is worked out), with what it asks of
        // the next block; the kernel's own check of the next block is for the program's moves.
        let along = self
            .corner_next
            .take()
            .map(|n| (usize::from(n.axis == 2), n.sign));
        let corner = match (w.get(Letter::CommaR), w.get(Letter::CommaC)) {
            (Some(r), _) => Some(turning::ProfileCorner {
                round: true,
                amount: r.abs(),
                along,
            }),
            (None, Some(c)) => Some(turning::ProfileCorner {
                round: false,
                amount: c.abs(),
                along,
            }),
            _ => None,
        };
        // Tool nose radius compensation in a profile (G42 at N(P), G40 at N(Q), as Haas programs
        // write it): the control's to apply in literal output; how a control roughs along a
        // compensated profile is in none of the manuals fmsvm follows, so resolved output refuses it.
        let comp = 1 << Group::CutterComp as u32;
        if w.named & comp != 0 && E::CANON {
            return Err(Alarm::new(
                FORMAT,
                format!("{name}'s profile N{}–N{}: tool nose radius compensation (G40 G41 G42) in a profile is not resolved (how the control roughs along a compensated profile is in none of the manuals fmsvm follows): write the program literally for its control, or give the profile as the tool's path without G41/G42", cap.profile.ns, cap.profile.nf),
            )
            .into());
        }
        if w.non_modal.is_some()
            || w.m_count > 0
            || w.named & !(1 << Group::Motion as u32 | comp) != 0
        {
            return Err(Alarm::new(
                FORMAT,
                format!("{name}'s profile N{}–N{}: only moves (G0 G1 G2 G3 with X Z U W R I K) and F S T may be in it", cap.profile.ns, cap.profile.nf),
            )
            .into());
        }
        // F S T act in G70: an F for this block's move and those after it, S and T before it; a
        // block without a move passes them on.
        let pending = cap.pending.take().unwrap_or_default();
        let own = turning::BlockCodes {
            f: w.get(Letter::F).or(pending.f),
            s: w.get(Letter::S).or(pending.s),
            t: w.get(Letter::T).or(pending.t),
        };
        if !w.any_axis() {
            cap.pending = Some(own);
            return Ok((ctx, flow));
        }
        if cap.profile.blocks.len() >= MAX_PROFILE {
            return Err(Alarm::new(
                FORMAT,
                format!("{name}'s profile has more than {MAX_PROFILE} blocks"),
            )
            .into());
        }
        let inc = self.modal.incremental();
        let mut axes = [None; 2];
        for (k, i) in [(0usize, 0usize), (1, 2)] {
            if let Some(v) = w.get(AXES_LATHE[k]) {
                axes[k] = Some(if w.incremental(i, inc) {
                    turning::AxisWord::Inc(v)
                } else {
                    turning::AxisWord::Abs(v)
                });
            }
        }
        let motion = self.modal.get(Group::Motion);
        let (code, centre) = match motion {
            Code::G0 => (0, None),
            Code::G1 => (1, None),
            Code::G2 | Code::G3 => (
                if motion == Code::G2 { 2 } else { 3 },
                Some(match w.get(Letter::R) {
                    Some(r) => fmsvm_canon::arcs::CentreWords::Radius(r),
                    None => fmsvm_canon::arcs::CentreWords::Offsets([
                        w.get(Letter::I).unwrap_or(0.0),
                        0.0,
                        w.get(Letter::K).unwrap_or(0.0),
                    ]),
                }),
            ),
            other => {
                return Err(Alarm::new(
                    FORMAT,
                    format!(
                        "{name}'s profile: G{} cannot be in a profile (G0 G1 G2 G3)",
                        self.modal.system.written(other)
                    ),
                )
                .into());
            }
        };
        cap.profile.blocks.push(turning::ProfileBlock {
            motion: code,
            axes,
            centre,
            corner,
        });
        cap.profile.codes.push(own);
        Ok((ctx, flow))
    }

    /// Runs a cycle on its profile from start point `start`: its steps as moves (resolved output),
    /// the tool back at `start` (every cycle ends where it began).
    fn run_repetitive(
        &mut self,
        job: Job,
        start: Pose,
        blocks: &turning::ProfileBlocks,
        origin: Origin,
    ) -> Result<(), Stop> {
        let a = [start[0], start[2]];
        if !E::CANON {
            // Literal output: the control runs it; the tool ends where it began.
            self.position = start;
            return Ok(());
        }
        let profile = &blocks.resolve(a, self.settings.arc_tolerance)?;
        match job {
            Job::Finishing(f) => self.run_steps(start, turning::finishing(a, profile, f), origin),
            Job::StockRemoval(cut, d) => {
                let budget = self.settings.budget.clone();
                let steps = turning::stock_removal(a, profile, cut, &d, &budget)?;
                self.run_steps(start, steps, origin)
            }
            Job::PatternRepeating(d) => {
                let steps = turning::pattern_repeating(a, profile, &d)?;
                self.run_steps(start, steps, origin)
            }
        }
    }

    /// A cycle's steps as moves from `start` (resolved output), the tool back at `start` (every
    /// cycle ends where it began).
    fn run_steps(
        &mut self,
        start: Pose,
        steps: impl IntoIterator<Item = turning::Step>,
        origin: Origin,
    ) -> Result<(), Stop> {
        if E::CANON {
            let feed_before = self.last_value(Letter::F);
            let mut feed_now = feed_before;
            let at = |p: [f64; 2]| -> Pose {
                let mut q = start;
                q[0] = p[0];
                q[2] = p[1];
                q
            };
            for step in steps {
                match step {
                    turning::Step::Rapid(p) => {
                        let out = self.out_point(&at(p));
                        self.canon(Canon::Rapid(out), origin)?;
                    }
                    turning::Step::Feed(p, f) => {
                        self.cycle_feed(f, &mut feed_now, origin)?;
                        let out = self.out_point(&at(p));
                        self.canon(Canon::Feed(out), origin)?;
                    }
                    turning::Step::Arc { to, centre, cw, f } => {
                        self.cycle_feed(f, &mut feed_now, origin)?;
                        let end = self.out_point(&at(to));
                        let c = self.out_point(&at(centre));
                        let arc = fmsvm_canon::Arc {
                            to: end,
                            centre: [c[2], c[0]],
                            plane: fmsvm_canon::Plane::ZX,
                            clockwise: cw,
                            turns: 0,
                        };
                        self.canon(Canon::Arc(arc), origin)?;
                    }
                    turning::Step::Codes { s, t } => self.profile_codes(s, t, origin)?,
                    turning::Step::Spindle(d) => {
                        self.canon(Canon::MCode(f64::from(d)), origin)?;
                    }
                    turning::Step::Thread(p, lead) => {
                        let out = self.out_point(&at(p));
                        self.thread_move(out, lead, origin)?;
                    }
                }
            }
            // The feed in force after the cycle is the program's again.
            if feed_now != feed_before
                && let Some(f) = feed_before
            {
                self.canon(Canon::FeedRate(f), origin)?;
            }
        }
        self.position = start;
        Ok(())
    }

    /// A G70 profile block's S and T, as the block would give them: T calls the tool and its
    /// offset (the nose radius compensation in force keeps its radius), S is a surface speed under
    /// G96, else rpm.
    fn profile_codes(
        &mut self,
        s: Option<f64>,
        t: Option<f64>,
        origin: Origin,
    ) -> Result<(), Stop> {
        if let Some(t) = t {
            self.last[Letter::T.index()] = t;
            self.canon(Canon::Tool(t), origin)?;
        }
        if let Some(s) = s {
            self.spindle_speed(s, origin)?;
        }
        Ok(())
    }

    /// Before a cycle's feed move at `f` (None: the feed in force): F when it changes.
    fn cycle_feed(
        &mut self,
        f: Option<f64>,
        now: &mut Option<f64>,
        origin: Origin,
    ) -> Result<(), Stop> {
        if let Some(f) = f
            && *now != Some(f)
        {
            self.canon(Canon::FeedRate(f), origin)?;
            *now = Some(f);
        }
        if now.is_none() {
            return Err(Alarm::new(11, "a cycle's feed move without a feed rate: give F").into());
        }
        Ok(())
    }
}

/// The letters of a lathe's two axes, X and Z.
const AXES_LATHE: [Letter; 2] = [Letter::X, Letter::Z];

impl<E: Emitter> Kernel<E> {
    /// A whole number of least increments written without a point (G74/G75 P Q, G76 P Q: Fanuc
    /// reads them so), as a length; None when the block has no such word.
    fn increments(
        &self,
        block: &Block<'_>,
        letter: Letter,
        name: &str,
    ) -> Result<Option<f64>, Alarm> {
        let Some(raw) = Self::raw(block, letter) else {
            return Ok(None);
        };
        if raw.fract() != 0.0 || raw < 0.0 {
            return Err(Alarm::new(
                FORMAT,
                format!(
                    "{name} {letter}{raw}: a whole number of least increments without a point ({letter}{} is {} mm)",
                    1500,
                    1500.0 * self.rules.increment(Letter::X, self.modal.inch())
                ),
            ));
        }
        Ok(Some(
            raw * self.rules.increment(Letter::X, self.modal.inch()),
        ))
    }

    /// The end point of a G74/G75/G76 second block: X (a diameter on a diameter lathe) or U, Z or W,
    /// each defaulting to where the tool stands.
    fn cycle_end(&self, w: &Words) -> [f64; 2] {
        let x_factor = self.radius_per_x_word();
        let (x0, z0) = (self.position[0], self.position[2]);
        let x = match (w.get(Letter::X), w.get(Letter::U)) {
            (Some(x), _) => x * x_factor,
            (None, Some(u)) => x0 + u * x_factor,
            _ => x0,
        };
        let z = match (w.get(Letter::Z), w.get(Letter::W)) {
            (Some(z), _) => z,
            (None, Some(dw)) => z0 + dw,
            _ => z0,
        };
        [x, z]
    }

    /// The first block of G74, G75 or G76: its words, kept until the next first block.
    fn direct_first_block(
        &mut self,
        block: &Block<'_>,
        code: Code,
        w: &Words,
        name: &str,
    ) -> Result<(), Stop> {
        match code {
            Code::FACE_PECK_DRILLING | Code::GROOVING_CYCLE => {
                let e = w.get(Letter::R).ok_or_else(|| {
                    Alarm::new(
                        FORMAT,
                        format!("{name}'s first block without R (the retract after each peck)"),
                    )
                })?;
                if code == Code::FACE_PECK_DRILLING {
                    self.cycle_words.g74 = Some(e);
                } else {
                    self.cycle_words.g75 = Some(e);
                }
            }
            _ => {
                let p = Self::raw(block, Letter::P).ok_or_else(|| {
                    Alarm::new(FORMAT, format!("{name}'s first block without P (m r a: finishing passes, chamfer, tool angle)"))
                })?;
                if p.fract() != 0.0 || !(0.0..=999_999.0).contains(&p) {
                    return Err(Alarm::new(
                        FORMAT,
                        format!("{name} P{p}: six digits, m r a (P021060)"),
                    )
                    .into());
                }
                let p = p as u32;
                let (m, r, a) = (p / 10_000, p / 100 % 100, p % 100);
                let least = self.increments(block, Letter::Q, name)?.ok_or_else(|| {
                    Alarm::new(
                        FORMAT,
                        format!("{name}'s first block without Q (the least depth of a pass)"),
                    )
                })?;
                let d = w.get(Letter::R).ok_or_else(|| {
                    Alarm::new(
                        FORMAT,
                        format!("{name}'s first block without R (the finishing allowance)"),
                    )
                })?;
                self.cycle_words.g76 = Some([f64::from(m), f64::from(r), f64::from(a), least, d]);
            }
        }
        Ok(())
    }

    /// G74, G75, G76: a first block stores its words; a second runs the cycle to its end point.
    fn direct_cycle(
        &mut self,
        block: &Block<'_>,
        code: Code,
        w: &Words,
        origin: Origin,
    ) -> Result<(), Stop> {
        let name = format!("G{}", self.modal.system.written(code));
        let second = w.has(Letter::X) || w.has(Letter::U) || w.has(Letter::Z) || w.has(Letter::W);
        if !second {
            return self.direct_first_block(block, code, w, &name);
        }
        self.cycle_may_start(&name, false)?;
        let end = self.cycle_end(w);
        let feed = w.get(Letter::F);
        let job = match code {
            Code::FACE_PECK_DRILLING | Code::GROOVING_CYCLE
                if self.settings.haas_codes
                    && (w.has(Letter::I) || w.has(Letter::K) || w.has(Letter::D)) =>
            {
                if self.haas_runs_it() {
                    // Where it leaves the tool is in no Haas text at hand: X and Z are unknown
                    // until the program gives them.
                    self.position[0] = f64::NAN;
                    self.position[2] = f64::NAN;
                    return Ok(());
                }
                return Err(Alarm::new(
                    FORMAT,
                    format!(
                        "{name} in Haas's one-block form (I K the peck and the step): the units of its words and its retract are not in the Haas manual text fmsvm follows, so it is refused rather than guessed; write the Fanuc two-block form ({name} R… then {name} X Z P Q F)"
                    ),
                )
                .into());
            }
            Code::FACE_PECK_DRILLING | Code::GROOVING_CYCLE => {
                let g74 = code == Code::FACE_PECK_DRILLING;
                let e = if g74 {
                    self.cycle_words.g74
                } else {
                    self.cycle_words.g75
                };
                let Some(e) = e else {
                    return Err(Alarm::new(
                        FORMAT,
                        format!("{name} without its first block ({name} R…: fmsvm does not know the control's parameter 5139)"),
                    )
                    .into());
                };
                // G74: Q the peck along Z, P the shift in X; G75 the other way round.
                let (peck_letter, shift_letter) = if g74 {
                    (Letter::Q, Letter::P)
                } else {
                    (Letter::P, Letter::Q)
                };
                let peck = self.increments(block, peck_letter, &name)?.ok_or_else(|| {
                    Alarm::new(FORMAT, format!("{name} without {peck_letter} (the depth of each peck, in least increments)"))
                })?;
                let shift = self.increments(block, shift_letter, &name)?.unwrap_or(0.0);
                let relief = w.get(Letter::R).unwrap_or(0.0);
                Direct::Pecking(
                    if g74 { 1 } else { 0 },
                    turning::Pecking {
                        end,
                        peck,
                        shift,
                        retract: e,
                        relief,
                        feed,
                    },
                )
            }
            _ if self.settings.haas_codes && Self::raw(block, Letter::K).is_some() => {
                if self.haas_runs_it() {
                    // The tool ends where it began.
                    return Ok(());
                }
                self.haas_threading(block, w, end, &name, origin)?
            }
            _ => {
                let Some([m, r, a, least, d]) = self.cycle_words.g76 else {
                    return Err(Alarm::new(
                        FORMAT,
                        format!("{name} without its first block ({name} P… Q… R…: fmsvm does not know the control's parameters 5140–5143)"),
                    )
                    .into());
                };
                if r != 0.0 {
                    return Err(Alarm::new(
                        NO_FANUC_NUMBER,
                        format!("{name} with an end chamfer (r = {r:02} in P): not yet resolved; write r = 00"),
                    )
                    .into());
                }
                let height = self.increments(block, Letter::P, &name)?.ok_or_else(|| {
                    Alarm::new(
                        FORMAT,
                        format!("{name} without P (the thread height, in least increments)"),
                    )
                })?;
                let first = self.increments(block, Letter::Q, &name)?.ok_or_else(|| {
                    Alarm::new(
                        FORMAT,
                        format!("{name} without Q (the first depth, in least increments)"),
                    )
                })?;
                let lead = self.thread_lead(w)?;
                if a != 0.0 {
                    self.warn(origin, flank_infeed(&name, &format!("a = {a}")));
                }
                Direct::Threading(turning::Threading {
                    end,
                    taper: w.get(Letter::R).unwrap_or(0.0),
                    height,
                    first,
                    least,
                    allowance: d,
                    finishing: m as u32,
                    angle: a,
                    lead,
                })
            }
        };
        let start = self.position;
        let a2 = [start[0], start[2]];
        let steps = match job {
            Direct::Pecking(axis, d) => turning::pecking(a2, axis, &d)?,
            Direct::Threading(d) => turning::threading(a2, &d)?,
        };
        self.run_steps(start, steps, origin)
    }
}

impl<E: Emitter> Kernel<E> {
    /// A Haas lathe's G76 in one block (the Haas lathe operator's manual, "G76 Threading Cycle,
    /// Multiple Pass"): `G76 X(U) Z(W) K D F [A] [I] [P1]`, K the thread height and D the first
    /// depth (radii, with a point), I the taper (a radius, as Fanuc's R), A the tool angle (0–120,
    /// no point), P1 single-edge cutting with a constant amount (Fanuc's depths Δd·√n). What the
    /// control keeps in its settings comes from `--params`: the finish allowance (Setting 86), the
    /// least cut (Setting 99) and the end chamfer (Setting 95, 0: none); one finishing pass
    /// (*inferred*: Setting 86 names one allowance). P2–P4 and a start angle Q are refused.
    fn haas_threading(
        &mut self,
        block: &Block<'_>,
        w: &Words,
        end: [f64; 2],
        name: &str,
        origin: Origin,
    ) -> Result<Direct, Stop> {
        let raw = |l| Self::raw(block, l);
        if !E::CANON {
            return Err(haas_literal(name).into());
        }
        let method = raw(Letter::P).unwrap_or(1.0);
        if method != 1.0 {
            return Err(Alarm::new(
                FORMAT,
                format!("{name} P{method}: only P1 (single edge, constant cutting amount) is resolved; the Haas manual text at hand does not describe P2–P4"),
            )
            .into());
        }
        if raw(Letter::Q).is_some_and(|q| q != 0.0) {
            return Err(Alarm::new(
                FORMAT,
                format!("{name} Q: a thread start angle (a multi-start thread) is not resolved"),
            )
            .into());
        }
        let c = self.settings.cycles;
        let (Some(allowance), Some(least), Some(chamfer)) =
            (c.thread_allowance, c.thread_least, c.thread_chamfer)
        else {
            return Err(Alarm::new(
                FORMAT,
                format!("{name} in one block takes its finish allowance, least cut and end chamfer from the control's Settings 86, 99 and 95, which fmsvm does not know: give them in --params ([cycles] setting_86 = …, setting_99 = …, setting_95 = 0 for no chamfer)"),
            )
            .into());
        };
        if chamfer != 0.0 {
            return Err(Alarm::new(
                NO_FANUC_NUMBER,
                format!("{name} with an end chamfer (Setting 95 = {chamfer}): not yet resolved; give setting_95 = 0 (M24 on the control)"),
            )
            .into());
        }
        let positive = |v: Option<f64>, what: &str| match v {
            Some(v) if v.is_finite() && v > 0.0 => Ok(v),
            _ => Err(Alarm::new(
                FORMAT,
                format!("{name} without {what} (positive, a radius)"),
            )),
        };
        let height = positive(raw(Letter::K), "K (the thread height)")?;
        let first = positive(raw(Letter::D), "D (the first pass's depth)")?;
        let angle = match raw(Letter::A) {
            Some(a) if a.fract() == 0.0 && (0.0..=120.0).contains(&a) => a,
            Some(a) => {
                return Err(Alarm::new(
                    FORMAT,
                    format!("{name} A{a}: the tool angle is 0 to 120 degrees, whole"),
                )
                .into());
            }
            None => {
                self.warn(
                    origin,
                    format!("{name} without A: the tool angle is taken as 0, each pass straight in (the Haas manual text at hand gives no default)"),
                );
                0.0
            }
        };
        if angle != 0.0 {
            self.warn(origin, flank_infeed(name, &format!("A{angle}")));
        }
        let lead = self.thread_lead(w)?;
        Ok(Direct::Threading(turning::Threading {
            end,
            taper: raw(Letter::I).unwrap_or(0.0),
            height,
            first,
            least,
            allowance,
            finishing: 1,
            angle,
            lead,
        }))
    }
}

/// The imaginary tool nose of direction `tip` less the nose centre, for a nose radius `r`: X
/// (radius) and Z. Fanuc's numbering (0i-TD "Imaginary tool nose direction", the figure with +X up
/// and +Z right: 2 6 1 over 7 0 5 over 3 8 4), so that an outside turning tool cutting towards the
/// chuck is 3 and a boring bar 2; 0 and 9 make the nose centre the controlled point. LinuxCNC
/// numbers the same positions mirrored in X (its Q2 is Fanuc's 3: `latheorigin_x` in
/// rs274ngc's interp_queue.cc).
pub fn imaginary_tip(tip: u8, r: f64) -> Pose {
    let (x, z) = match tip {
        1 => (r, r),
        2 => (r, -r),
        3 => (-r, -r),
        4 => (-r, r),
        5 => (0.0, r),
        6 => (r, 0.0),
        7 => (0.0, -r),
        8 => (-r, 0.0),
        _ => (0.0, 0.0),
    };
    [x, 0.0, z, 0.0, 0.0, 0.0]
}
