//! G and M codes as integers ×10 (`G54.1` = 541, `M98` = 980, `G1` = 10): the one convention every
//! crate compares codes in, and a named constant for every code the compiler, the VM or the kernel
//! treats. What a code *does* lives with its reader (the kernel's modal groups, the VM's calls); its
//! number lives here.

use std::fmt;

/// A G or M code ×10, so that codes are never compared as floats and `G54.1` has a number.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Debug, Default)]
pub struct Code(u32);

impl Code {
    /// The code of `tenths` (541 is `54.1`).
    pub const fn from_tenths(tenths: u32) -> Code {
        Code(tenths)
    }

    /// The code's number ×10 (a table index).
    pub const fn tenths(self) -> u32 {
        self.0
    }

    /// The whole part of the code's number (`G54.1` → 54).
    pub const fn whole(self) -> u32 {
        self.0 / 10
    }

    /// The code of a G word's value: the value ×10 rounded half away from zero; None when it is
    /// negative, not a number or above 9999.9 (the largest code a parameter can bind, G9999).
    #[inline(always)]
    pub fn of(value: f64) -> Option<Code> {
        let scaled = value * 10.0;
        if (0.0..=99999.0).contains(&scaled) {
            // Half away from zero for a non-negative value, without a libm call.
            let t = scaled as u32;
            Some(Code(if scaled - f64::from(t) >= 0.5 {
                t + 1
            } else {
                t
            }))
        } else {
            None
        }
    }

    /// The code of an M word's value as the kernel executes it: an M address takes an integer, so
    /// the value is rounded half away from zero first (`M[3.5]` is M4), as every integer address is.
    #[inline]
    pub fn of_integer(value: f64) -> Option<Code> {
        Code::of(value.round())
    }

    /// True when `value` is exactly this code (`G1.05` is not G1.1: a G code has at most one
    /// decimal).
    #[inline]
    pub fn is_exact(self, value: f64) -> bool {
        (value * 10.0 - f64::from(self.0)).abs() < 1e-6
    }
}

/// `54.1`, `28`: the code's number as a program writes it.
impl fmt::Display for Code {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.0.is_multiple_of(10) {
            write!(f, "{}", self.0 / 10)
        } else {
            write!(f, "{}.{}", self.0 / 10, self.0 % 10)
        }
    }
}

/// The one-block codes whose axis words are data, not a move: the dwell, data setting, the G52 and
/// G92 shifts and the G92.1 preset, a macro call's arguments. The kernel moves no axis for them;
/// a reader of the flat text (DNC's resume) takes no position from them as a move.
pub const AXES_ARE_DATA: [Code; 6] = [
    Code::G4,
    Code::G10,
    Code::G52,
    Code::G92,
    Code::G92_1,
    Code::G65,
];

/// Declares each code once: its name is the code as a program writes it, its doc what it is.
macro_rules! codes {
    ($($(#[$doc:meta])* $name:ident = $tenths:literal;)*) => {
        impl Code {
            $($(#[$doc])* pub const $name: Code = Code($tenths);)*
        }
    };
}

codes! {
    /// Rapid positioning.
    G0 = 0;
    /// Linear interpolation at the feed rate.
    G1 = 10;
    /// Circular interpolation clockwise.
    G2 = 20;
    /// Circular interpolation counterclockwise.
    G3 = 30;
    /// Dwell.
    G4 = 40;
    /// High-speed cycle machining / AI contour control (one block).
    G5 = 50;
    /// AI contour control (G5.1).
    G5_1 = 51;
    /// Cylindrical interpolation (G7.1).
    G7_1 = 71;
    /// Diameter mode (LinuxCNC's G7: a lathe's X words are diameters), on a turning program's first line.
    G7 = 70;
    /// Exact stop (one block).
    G9 = 90;
    /// Programmable data input (offsets, parameters); on the FMS-3000 a helix pitch.
    G10 = 100;
    /// Programmable data input cancel.
    G11 = 110;
    /// Polar coordinates cancel.
    G15 = 150;
    /// Polar coordinates.
    G16 = 160;
    /// XY plane.
    G17 = 170;
    /// ZX plane.
    G18 = 180;
    /// YZ plane.
    G19 = 190;
    /// Input in inch.
    G20 = 200;
    /// Input in mm.
    G21 = 210;
    /// Stored stroke check on.
    G22 = 220;
    /// Stored stroke check off.
    G23 = 230;
    /// Spindle speed fluctuation detection off.
    G25 = 250;
    /// Spindle speed fluctuation detection on.
    G26 = 260;
    /// Reference position return check.
    G27 = 270;
    /// Return to the reference position.
    G28 = 280;
    /// Return from the reference position.
    G29 = 290;
    /// Return to the 2nd, 3rd or 4th reference position.
    G30 = 300;
    /// Skip function (probing move).
    G31 = 310;
    /// Thread cutting on a lathe (the mill's G33).
    G32 = 320;
    /// Thread cutting.
    G33 = 330;
    /// Automatic tool length measurement.
    G37 = 370;
    /// Tool nose radius compensation / corner circular interpolation.
    G39 = 390;
    /// Cutter compensation cancel.
    G40 = 400;
    /// Normal direction control cancel.
    G40_1 = 401;
    /// Cutter compensation left.
    G41 = 410;
    /// Normal direction control left.
    G41_1 = 411;
    /// Cutter compensation right.
    G42 = 420;
    /// Normal direction control right.
    G42_1 = 421;
    /// Tool length compensation +.
    G43 = 430;
    /// Tool length compensation −.
    G44 = 440;
    /// Tool offset increase.
    G45 = 450;
    /// Tool offset decrease.
    G46 = 460;
    /// Tool offset double increase.
    G47 = 470;
    /// Tool offset double decrease.
    G48 = 480;
    /// Tool length compensation cancel.
    G49 = 490;
    /// Scaling cancel.
    G50 = 500;
    /// Programmable mirror image cancel.
    G50_1 = 501;
    /// Scaling.
    G51 = 510;
    /// Programmable mirror image.
    G51_1 = 511;
    /// Local coordinate system setting.
    G52 = 520;
    /// Machine coordinate system selection (one block).
    G53 = 530;
    /// Work coordinate system 1.
    G54 = 540;
    /// Additional work coordinate systems (with P1–P48).
    G54_1 = 541;
    /// Work coordinate system 2.
    G55 = 550;
    /// Work coordinate system 3.
    G56 = 560;
    /// Work coordinate system 4.
    G57 = 570;
    /// Work coordinate system 5.
    G58 = 580;
    /// Work coordinate system 6.
    G59 = 590;
    /// Single direction positioning.
    G60 = 600;
    /// Exact stop mode.
    G61 = 610;
    /// Automatic corner override.
    G62 = 620;
    /// Tapping mode.
    G63 = 630;
    /// Cutting mode.
    G64 = 640;
    /// Macro call (one block).
    G65 = 650;
    /// Macro modal call after each move block.
    G66 = 660;
    /// Macro modal call at every block.
    G66_1 = 661;
    /// Macro modal call cancel.
    G67 = 670;
    /// Coordinate system rotation.
    G68 = 680;
    /// Coordinate system rotation cancel.
    G69 = 690;
    /// Finishing cycle (lathe).
    G70 = 700;
    /// Stock removal in turning (lathe).
    G71 = 710;
    /// Stock removal in facing (lathe).
    G72 = 720;
    /// Peck drilling cycle (high speed).
    G73 = 730;
    /// Left-hand tapping cycle.
    G74 = 740;
    /// Grooving cycle (lathe).
    G75 = 750;
    /// Fine boring cycle.
    G76 = 760;
    /// Outer diameter cutting cycle (lathe, G-code system B).
    G77 = 770;
    /// Thread cutting cycle (lathe, G-code system B).
    G78 = 780;
    /// End face turning cycle (lathe, G-code system B).
    G79 = 790;
    /// Canned cycle cancel.
    G80 = 800;
    /// Drilling cycle, spot drilling.
    G81 = 810;
    /// Drilling cycle with dwell, counter boring.
    G82 = 820;
    /// Peck drilling cycle.
    G83 = 830;
    /// Tapping cycle.
    G84 = 840;
    /// Boring cycle (feed out).
    G85 = 850;
    /// Boring cycle (spindle stop, rapid out).
    G86 = 860;
    /// Back boring cycle.
    G87 = 870;
    /// Boring cycle (dwell, manual out).
    G88 = 880;
    /// Boring cycle (dwell, feed out).
    G89 = 890;
    /// Absolute programming.
    G90 = 900;
    /// Incremental programming.
    G91 = 910;
    /// Work coordinate system setting (shift).
    G92 = 920;
    /// Work coordinate system preset.
    G92_1 = 921;
    /// Inverse time feed.
    G93 = 930;
    /// Feed per minute.
    G94 = 940;
    /// Feed per revolution.
    G95 = 950;
    /// Constant surface speed.
    G96 = 960;
    /// Constant surface speed cancel.
    G97 = 970;
    /// Canned cycle return to the initial level.
    G98 = 980;
    /// Canned cycle return to the R level.
    G99 = 990;

    // What a lathe's codes mean where the mill has no code for it (Fanuc T series; docs/lathe.md).
    // The numbers lie above any code a program can write (`Code::of` stops at G9999.9), so they
    // are never read from a program: `modal::CodeSystem` gives the code each is written as.
    /// Finishing cycle (lathe G70).
    FINISHING_CYCLE = 100_700;
    /// Stock removal in turning (lathe G71).
    TURNING_STOCK_REMOVAL = 100_710;
    /// Stock removal in facing (lathe G72).
    FACING_STOCK_REMOVAL = 100_720;
    /// Pattern repeating (lathe G73).
    PATTERN_REPEATING = 100_730;
    /// End face peck drilling (lathe G74).
    FACE_PECK_DRILLING = 100_740;
    /// Outer / inner diameter grooving (lathe G75).
    GROOVING_CYCLE = 100_750;
    /// Multiple threading cycle (lathe G76).
    THREADING_MULTIPLE = 100_760;
    /// Face drilling cycle (lathe G83).
    FACE_DRILLING = 100_830;
    /// Face tapping cycle (lathe G84).
    FACE_TAPPING = 100_840;
    /// Face boring cycle (lathe G85).
    FACE_BORING = 100_850;
    /// Side drilling cycle (lathe G87).
    SIDE_DRILLING = 100_870;
    /// Side tapping cycle (lathe G88).
    SIDE_TAPPING = 100_880;
    /// Side boring cycle (lathe G89).
    SIDE_BORING = 100_890;
    /// Outer / inner diameter cutting cycle (lathe G90 in system A, G77 in B).
    TURNING_CYCLE = 100_900;
    /// Thread cutting cycle (lathe G92 in system A, G78 in B).
    THREADING_CYCLE = 100_920;
    /// End face turning cycle (lathe G94 in system A, G79 in B).
    FACING_CYCLE = 100_940;
    /// Mirror image for double turrets on (lathe G68, system A).
    TURRET_MIRROR = 100_680;
    /// Mirror image for double turrets off (lathe G69, system A).
    TURRET_MIRROR_CANCEL = 100_690;

    /// Program stop.
    M0 = 0;
    /// Optional stop.
    M1 = 10;
    /// End of program.
    M2 = 20;
    /// Spindle on clockwise.
    M3 = 30;
    /// Spindle on counterclockwise.
    M4 = 40;
    /// Spindle stop.
    M5 = 50;
    /// Tool change.
    M6 = 60;
    /// Mist coolant on.
    M7 = 70;
    /// Flood coolant on.
    M8 = 80;
    /// Coolant off.
    M9 = 90;
    /// End of program and rewind.
    M30 = 300;
    /// Local subprogram call (Haas).
    M97 = 970;
    /// Subprogram call.
    M98 = 980;
    /// End of subprogram (return).
    M99 = 990;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_become_codes() {
        for (v, c) in [
            (1.0, 10),
            (54.1, 541),
            (98.0, 980),
            (0.0, 0),
            (9999.0, 99990),
        ] {
            assert_eq!(Code::of(v), Some(Code(c)), "{v}");
            assert!(Code(c).is_exact(v), "{v}");
        }
        assert_eq!(Code::of(1.05), Some(Code(11)));
        assert!(!Code(11).is_exact(1.05));
        assert_eq!(Code::of(0.04), Some(Code(0)));
        for v in [-0.1, 10000.0, f64::NAN, f64::INFINITY] {
            assert_eq!(Code::of(v), None, "{v}");
        }
        assert_eq!(Code::of_integer(3.5), Some(Code::M4));
        assert_eq!(Code::of_integer(30.0), Some(Code::M30));
    }

    #[test]
    fn codes_print_as_written() {
        assert_eq!(Code::G54_1.to_string(), "54.1");
        assert_eq!(Code::G28.to_string(), "28");
        assert_eq!(Code::M30.whole(), 30);
    }
}
