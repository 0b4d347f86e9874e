//! The machine's travels: the span each axis of the output moves over, against the travel the
//! machine declares (a dialect profile's `[motion] travel`, the Н33-2М's table, `--travel`).
//!
//! Where the part is clamped is the operator's choice, so no written coordinate is beyond a
//! travel by itself; a program whose moves on one axis span more than the machine's travel cannot
//! run wherever the part is. That is what is checked: from the first known position on, every
//! position the tool reaches (an arc's extremes too), in mm, with a frame change under the tool
//! (G92, a new work offset) taken out so that the span is the machine's motion.

use fmsvm_block::Alarm;
use fmsvm_canon::{AXES, Arc, Pose};

/// Fanuc's alarm for a move beyond the stored stroke limit (OT0500/OT0501, "overtravel"): here the
/// span of the program's moves beyond the machine's travel.
pub const OVERTRAVEL: u32 = 500;

/// Millimetres per output unit of axis `i`: `mm` for X Y Z, 1 for A B C (degrees whatever the units).
fn unit(i: usize, mm: f64) -> f64 {
    if i < 3 { mm } else { 1.0 }
}

/// The spans seen so far, against the machine's travels (X Y Z in mm, A B C in degrees).
#[derive(Clone, Debug)]
pub struct Travel {
    /// The machine's travel on each axis, mm (infinite: not declared).
    travel: [f64; 6],
    /// The lowest and highest machine-frame positions reached, mm (NaN: none yet).
    low: [f64; 6],
    high: [f64; 6],
    /// What the output's coordinates were shifted by (frame changes under the tool), mm.
    shift: [f64; 6],
}

impl Travel {
    /// A check against `travel` (mm per axis; infinite: none).
    pub fn new(travel: [f64; 6]) -> Travel {
        Travel {
            travel,
            low: [f64::NAN; 6],
            high: [f64::NAN; 6],
            shift: [0.0; 6],
        }
    }

    /// Whether any axis has a travel.
    pub fn limited(&self) -> bool {
        self.travel.iter().any(|t| t.is_finite())
    }

    /// The coordinates changed under a tool that did not move (from `was` to `now`, output units of
    /// `mm` mm each).
    pub fn reframe(&mut self, was: &Pose, now: &Pose, mm: f64) {
        for i in 0..6 {
            if was[i].is_finite() && now[i].is_finite() {
                self.shift[i] += (now[i] - was[i]) * unit(i, mm);
            }
        }
    }

    /// The tool reaches `p` (output units of `mm` mm each; NaN: not known).
    pub fn reach(&mut self, p: &Pose, mm: f64) -> Result<(), Alarm> {
        for (i, &v) in p.iter().enumerate() {
            if v.is_finite() {
                self.axis(i, v * unit(i, mm) - self.shift[i])?;
            }
        }
        Ok(())
    }

    /// The tool moves along `arc` from `from`: its end, and the extremes of its plane's axes it
    /// passes (the circle's points at 0°, 90°, 180°, 270° within the sweep).
    pub fn reach_arc(&mut self, from: &Pose, arc: &Arc, mm: f64) -> Result<(), Alarm> {
        if !self.limited() {
            return Ok(());
        }
        self.reach(&arc.to, mm)?;
        let (a, b, _) = arc.plane.axes();
        if !(from[a].is_finite() && from[b].is_finite()) {
            return Ok(());
        }
        let (r, sweep) = arc.sweep(from);
        let [ca, cb] = arc.centre;
        let start = (from[b] - cb).atan2(from[a] - ca);
        let turn = std::f64::consts::TAU;
        for k in 0..4 {
            let angle = f64::from(k) * turn / 4.0;
            // How far round from the start, in the arc's direction, the extreme lies.
            let along = if arc.clockwise {
                start - angle
            } else {
                angle - start
            }
            .rem_euclid(turn);
            if along <= sweep {
                self.axis(a, (ca + r * angle.cos()) * unit(a, mm) - self.shift[a])?;
                self.axis(b, (cb + r * angle.sin()) * unit(b, mm) - self.shift[b])?;
            }
        }
        Ok(())
    }

    fn axis(&mut self, i: usize, v: f64) -> Result<(), Alarm> {
        let (low, high) = if self.low[i].is_nan() {
            (v, v)
        } else {
            (self.low[i].min(v), self.high[i].max(v))
        };
        (self.low[i], self.high[i]) = (low, high);
        // A thousandth of a millimetre for the rounding of the written numbers.
        if high - low > self.travel[i] + 1e-3 {
            let (l, h) = (low + self.shift[i], high + self.shift[i]);
            return Err(Alarm::new(
                OVERTRAVEL,
                format!(
                    "{} moves over {:.3} {u} (from {l:.3} to {h:.3} {u}), more than the machine's {} {u} travel: the program cannot run wherever the part is clamped (--travel)",
                    AXES[i],
                    high - low,
                    self.travel[i],
                    u = if i < 3 { "mm" } else { "degrees" }
                ),
            ));
        }
        Ok(())
    }
}

/// Travels from a points text: `X1000 Y400 Z150` (mm; A B C in degrees), or `none`.
pub fn parse(text: &str) -> Result<[f64; 6], String> {
    let mut travel = [f64::INFINITY; 6];
    if text.trim().eq_ignore_ascii_case("none") {
        return Ok(travel);
    }
    for word in text.split_whitespace() {
        let mut chars = word.chars();
        let letter = chars.next().map(|c| c.to_ascii_uppercase());
        let Some(i) = letter.and_then(|l| AXES.iter().position(|a| a.to_string().starts_with(l)))
        else {
            return Err(format!(
                "`{word}`: a travel is an axis (X Y Z A B C) and mm, as X1000"
            ));
        };
        match chars.as_str().parse::<f64>() {
            Ok(v) if v.is_finite() && v > 0.0 => travel[i] = v,
            _ => {
                return Err(format!(
                    "`{word}`: a travel is a positive number of mm after its axis, as X1000"
                ));
            }
        }
    }
    Ok(travel)
}

/// The travels as [`parse`] reads them (`none` when no axis has one).
pub fn text(travel: &[f64; 6]) -> String {
    let words: Vec<String> = (0..6)
        .filter(|&i| travel[i].is_finite())
        .map(|i| format!("{}{}", AXES[i], travel[i]))
        .collect();
    if words.is_empty() {
        "none".into()
    } else {
        words.join(" ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fmsvm_canon::Plane;

    fn p(x: f64, y: f64, z: f64) -> Pose {
        [x, y, z, 0.0, 0.0, 0.0]
    }

    #[test]
    fn a_span_beyond_the_travel_is_an_overtravel() {
        let mut t = Travel::new(parse("X100 Z50").unwrap());
        assert!(t.reach(&p(-40.0, 500.0, 0.0), 1.0).is_ok());
        assert!(t.reach(&p(60.0, -500.0, -50.0), 1.0).is_ok());
        let e = t.reach(&p(60.5, 0.0, 0.0), 1.0).unwrap_err();
        assert_eq!(e.number, OVERTRAVEL);
        assert!(
            e.message.contains("X moves over 100.500 mm"),
            "{}",
            e.message
        );
        // Inch output: 2 in = 50.8 mm of Z.
        let mut t = Travel::new(parse("Z50").unwrap());
        assert!(t.reach(&p(0.0, 0.0, 0.0), 25.4).is_ok());
        assert!(t.reach(&p(0.0, 0.0, 2.0), 25.4).is_err());
    }

    #[test]
    fn an_arcs_extremes_count_and_a_reframe_is_no_motion() {
        // A half circle of radius 30 about X30 from X0 clockwise through Y+30: X spans 60, Y 30.
        let arc = Arc {
            plane: Plane::XY,
            to: p(60.0, 0.0, 0.0),
            centre: [30.0, 0.0],
            clockwise: true,
            turns: 0,
        };
        let mut t = Travel::new(parse("X100 Y29").unwrap());
        t.reach(&p(0.0, 0.0, 0.0), 1.0).unwrap();
        let e = t.reach_arc(&p(0.0, 0.0, 0.0), &arc, 1.0).unwrap_err();
        assert!(e.message.contains("Y moves over 30.000"), "{}", e.message);
        // From Y40 down: clockwise the half stays within Y0..30, counter-clockwise it goes
        // through Y-30.
        let mut t = Travel::new(parse("Y69").unwrap());
        t.reach(&p(0.0, 40.0, 0.0), 1.0).unwrap();
        t.reach_arc(&p(0.0, 0.0, 0.0), &arc, 1.0).unwrap();
        let ccw = Arc {
            clockwise: false,
            ..arc
        };
        let e = t.reach_arc(&p(0.0, 0.0, 0.0), &ccw, 1.0).unwrap_err();
        assert!(e.message.contains("Y moves over 70.000"), "{}", e.message);
        // G92 X0 where the tool stands at X90: the coordinates change, the machine does not move.
        let mut t = Travel::new(parse("X100").unwrap());
        t.reach(&p(0.0, 0.0, 0.0), 1.0).unwrap();
        t.reach(&p(90.0, 0.0, 0.0), 1.0).unwrap();
        t.reframe(&p(90.0, 0.0, 0.0), &p(0.0, 0.0, 0.0), 1.0);
        assert!(t.reach(&p(5.0, 0.0, 0.0), 1.0).is_ok());
        assert!(t.reach(&p(10.5, 0.0, 0.0), 1.0).is_err());
    }

    /// A rotary axis's travel is in degrees whatever the units: inch output does not scale it.
    #[test]
    fn a_rotary_axis_is_in_degrees() {
        let mut t = Travel::new(parse("A90").unwrap());
        let mut a = p(0.0, 0.0, 0.0);
        t.reach(&a, 25.4).unwrap();
        a[3] = 90.0;
        assert!(t.reach(&a, 25.4).is_ok());
        a[3] = 90.5;
        let e = t.reach(&a, 25.4).unwrap_err();
        assert!(
            e.message.contains("A moves over 90.500 degrees"),
            "{}",
            e.message
        );
    }

    #[test]
    fn travels_are_read_or_refused() {
        assert_eq!(parse("none").unwrap(), [f64::INFINITY; 6]);
        assert_eq!(
            parse("x1000 Y400 Z150").unwrap()[..3],
            [1000.0, 400.0, 150.0]
        );
        assert!(parse("Q5").is_err());
        assert!(parse("X-5").is_err());
        assert!(parse("Xabc").is_err());
        assert_eq!(text(&parse("Z150 X1000.5").unwrap()), "X1000.5 Z150");
        assert_eq!(text(&parse("none").unwrap()), "none");
    }
}
