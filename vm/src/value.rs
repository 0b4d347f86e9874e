//! Every operator and function rule of Macro B on `f64` values with NaN as vacant: vacancy (V5, V7),
//! FIX/FUP/ROUND (E4, E12), degrees (E5, E10), bitwise logic (E13), and the alarms of E11 and A3.
//!
//! These functions are the single definition of the semantics; the interpreter calls them and the JIT
//! will call the same functions (or inline code proven equal by the differential tests).

use fmsvm_block::alarms::FORMAT;
use fmsvm_block::{Alarm, is_vacant};
use fmsvm_ir::{BinOp, CmpOp, Func};

/// 0112 ZERO DIVIDE.
pub const ZERO_DIVIDE: u32 = 112;
/// 0110 OVERFLOW: INTEGER.
pub const INTEGER_OVERFLOW: u32 = 110;
/// 0111 OVERFLOW: FLOATING.
pub const FLOAT_OVERFLOW: u32 = 111;
/// 0119 ARGUMENT VALUE OUT OF RANGE.
pub const ARGUMENT_RANGE: u32 = 119;

/// Where controls differ in the arithmetic itself (each a named option, macro-b-rules E10, E13).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Semantics {
    /// Fanuc parameter NAT (6004#0): ATAN gives −180…180 and ASIN −90…90 instead of 0…360 and
    /// 270…90 (E10).
    pub nat: bool,
    /// MOD rounds both operands to integers first (the rule stated for the 30i series, E13); off, MOD is
    /// the remainder of the values as they are.
    pub mod_integers: bool,
}

/// A vacant value acts as 0 in arithmetic (V5).
#[inline(always)]
pub fn num(x: f64) -> f64 {
    if is_vacant(x) { 0.0 } else { x }
}

#[inline(always)]
fn finite(r: f64, what: &'static str) -> Result<f64, Alarm> {
    if r.is_finite() {
        Ok(r)
    } else {
        Err(Alarm::new(
            FLOAT_OVERFLOW,
            format!("floating overflow in {what}"),
        ))
    }
}

/// The integer part of `x` as a 32-bit integer, for AND/OR/XOR/BIN/BCD (E13).
fn int32(x: f64, what: &'static str) -> Result<i64, Alarm> {
    let t = num(x).trunc();
    if (-2_147_483_648.0..=4_294_967_295.0).contains(&t) {
        Ok(t as i64)
    } else {
        Err(Alarm::new(
            INTEGER_OVERFLOW,
            format!(
                "integer overflow: {what} of {} does not fit in 32 bits",
                num(x)
            ),
        ))
    }
}

/// A binary operator.
#[inline]
pub fn binary(op: BinOp, a: f64, b: f64, sem: Semantics) -> Result<f64, Alarm> {
    let (x, y) = (num(a), num(b));
    match op {
        BinOp::Add => finite(x + y, "+"),
        BinOp::Sub => finite(x - y, "-"),
        BinOp::Mul => finite(x * y, "*"),
        BinOp::Div => {
            if y == 0.0 {
                Err(Alarm::new(
                    ZERO_DIVIDE,
                    format!(
                        "zero divide: {x} / {}",
                        if is_vacant(b) { "#0 (vacant)" } else { "0" }
                    ),
                ))
            } else {
                finite(x / y, "/")
            }
        }
        // E13: remainder with the sign of the dividend (the 30i integer rule is unverified).
        BinOp::Mod => {
            let (x, y) = if sem.mod_integers {
                (x.round(), y.round())
            } else {
                (x, y)
            };
            if y == 0.0 {
                Err(Alarm::new(ZERO_DIVIDE, format!("zero divide: {x} MOD 0")))
            } else {
                finite(x % y, "MOD")
            }
        }
        BinOp::And => Ok((int32(a, "AND")? & int32(b, "AND")?) as f64),
        BinOp::Or => Ok((int32(a, "OR")? | int32(b, "OR")?) as f64),
        BinOp::Xor => Ok((int32(a, "XOR")? ^ int32(b, "XOR")?) as f64),
    }
}

/// A comparison: EQ/NE tell vacant from 0, the others treat vacant as 0 (V7).
#[inline]
pub fn compare(op: CmpOp, a: f64, b: f64) -> bool {
    match op {
        CmpOp::Eq | CmpOp::Ne => {
            let eq = match (is_vacant(a), is_vacant(b)) {
                (true, true) => true,
                (false, false) => a == b,
                _ => false,
            };
            eq == (op == CmpOp::Eq)
        }
        CmpOp::Gt => num(a) > num(b),
        CmpOp::Ge => num(a) >= num(b),
        CmpOp::Lt => num(a) < num(b),
        CmpOp::Le => num(a) <= num(b),
    }
}

/// Sine and cosine of an angle in degrees, exact at multiples of 90° and at ±30° offsets (so that
/// `SIN[180]` is 0, not 1.2e-16, and `SIN[30]` is 0.5).
fn sin_cos_deg(deg: f64) -> (f64, f64) {
    let r = deg.rem_euclid(360.0);
    let q = (r / 90.0).round();
    let d = r - 90.0 * q;
    let (s, c) = if d == 0.0 {
        (0.0, 1.0)
    } else if d == 30.0 {
        (0.5, (d.to_radians()).cos())
    } else if d == -30.0 {
        (-0.5, (d.to_radians()).cos())
    } else {
        d.to_radians().sin_cos()
    };
    match q as i64 % 4 {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

/// An angle in degrees brought into 0 ≤ θ < 360 (E10, NAT off).
fn positive_degrees(rad: f64) -> f64 {
    let d = rad.to_degrees();
    let d = if d < 0.0 { d + 360.0 } else { d };
    if d >= 360.0 { d - 360.0 } else { d }
}

fn bcd_to_bin(x: i64) -> Result<f64, Alarm> {
    if x < 0 {
        return Err(Alarm::new(ARGUMENT_RANGE, format!("BIN of negative {x}")));
    }
    let (mut v, mut out, mut scale) = (x, 0i64, 1i64);
    while v > 0 {
        let digit = v & 0xF;
        if digit > 9 {
            return Err(Alarm::new(
                ARGUMENT_RANGE,
                format!("BIN[{x}]: {x:#x} is not BCD"),
            ));
        }
        out += digit * scale;
        scale *= 10;
        v >>= 4;
    }
    Ok(out as f64)
}

fn bin_to_bcd(x: i64) -> Result<f64, Alarm> {
    if !(0..=99_999_999).contains(&x) {
        return Err(Alarm::new(
            INTEGER_OVERFLOW,
            format!("BCD[{x}] does not fit 8 digits"),
        ));
    }
    let (mut v, mut out, mut shift) = (x, 0i64, 0);
    while v > 0 {
        out |= (v % 10) << shift;
        shift += 4;
        v /= 10;
    }
    Ok(out as f64)
}

fn range_alarm(f: Func, x: f64) -> Alarm {
    Alarm::new(
        ARGUMENT_RANGE,
        format!("argument value out of range: {}[{x}]", f.name()),
    )
}

/// A one-argument function.
pub fn func1(f: Func, a: f64, sem: Semantics) -> Result<f64, Alarm> {
    let angle = |rad: f64| {
        if sem.nat {
            rad.to_degrees()
        } else {
            positive_degrees(rad)
        }
    };
    let x = num(a);
    match f {
        Func::Sin => Ok(sin_cos_deg(x).0),
        Func::Cos => Ok(sin_cos_deg(x).1),
        Func::Tan => {
            // V9: TAN performs SIN/COS.
            let (s, c) = sin_cos_deg(x);
            if c == 0.0 {
                Err(Alarm::new(
                    ZERO_DIVIDE,
                    format!("zero divide: TAN[{x}] (COS is 0)"),
                ))
            } else {
                finite(s / c, "TAN")
            }
        }
        Func::Asin => {
            if !(-1.0..=1.0).contains(&x) {
                return Err(range_alarm(f, x));
            }
            // E10: 270…90, i.e. negative results as 360 + asin (NAT: −90…90).
            Ok(angle(x.asin()))
        }
        Func::Acos => {
            if !(-1.0..=1.0).contains(&x) {
                return Err(range_alarm(f, x));
            }
            Ok(x.acos().to_degrees())
        }
        Func::Atan => Ok(angle(x.atan())),
        Func::Sqrt => {
            if x < 0.0 {
                Err(range_alarm(f, x))
            } else {
                Ok(x.sqrt())
            }
        }
        Func::Abs => Ok(x.abs()),
        // E12: half away from zero.
        Func::Round => Ok(x.round()),
        // E4: FIX truncates, FUP rounds away from zero.
        Func::Fix => Ok(x.trunc()),
        Func::Fup => Ok(if x >= 0.0 { x.ceil() } else { x.floor() }),
        Func::Ln => {
            if x <= 0.0 {
                Err(range_alarm(f, x))
            } else {
                Ok(x.ln())
            }
        }
        Func::Exp => finite(x.exp(), "EXP"),
        // E13: ADP[1] = 1. (zappettini); other semantics unverified: the value is unchanged.
        Func::Adp => Ok(x),
        Func::Bin => bcd_to_bin(int32(a, "BIN")?),
        Func::Bcd => bin_to_bcd(int32(a, "BCD")?),
        Func::Atan2 | Func::Pow => Err(Alarm::new(
            FORMAT,
            format!("{} takes two arguments", f.name()),
        )),
    }
}

/// A two-argument function: `ATAN[a]/[b]` (angle of the point x = b, y = a, E10) and `POW[a,b]`.
pub fn func2(f: Func, a: f64, b: f64, sem: Semantics) -> Result<f64, Alarm> {
    let (x, y) = (num(a), num(b));
    match f {
        Func::Atan2 if sem.nat => Ok(x.atan2(y).to_degrees()),
        Func::Atan2 => Ok(positive_degrees(x.atan2(y))),
        Func::Pow => {
            let r = x.powf(y);
            if r.is_nan() {
                Err(Alarm::new(
                    ARGUMENT_RANGE,
                    format!("argument value out of range: POW[{x},{y}]"),
                ))
            } else {
                finite(r, "POW")
            }
        }
        _ => func1(f, a, sem),
    }
}

/// `ROUND` inside an address: to the address's least increment (E3).
pub fn round_to(a: f64, increment: f64) -> f64 {
    let x = num(a);
    if increment >= 1.0 {
        x.round()
    } else {
        let scale = (1.0 / increment).round();
        (x * scale).round() / scale
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fmsvm_block::VACANT;

    #[test]
    fn trig_is_exact_where_it_should_be() {
        assert_eq!(func1(Func::Sin, 180.0, Semantics::default()), Ok(0.0));
        assert_eq!(func1(Func::Sin, 30.0, Semantics::default()), Ok(0.5));
        assert_eq!(func1(Func::Cos, 60.0, Semantics::default()), Ok(0.5));
        assert_eq!(func1(Func::Cos, 90.0, Semantics::default()), Ok(0.0));
        assert_eq!(func1(Func::Sin, -90.0, Semantics::default()), Ok(-1.0));
        assert_eq!(func1(Func::Sin, 390.0, Semantics::default()), Ok(0.5));
        assert!(
            (func1(Func::Sin, 45.0, Semantics::default()).unwrap() - 0.5f64.sqrt()).abs() < 1e-15
        );
        assert_eq!(
            func1(Func::Tan, 90.0, Semantics::default())
                .unwrap_err()
                .number,
            112
        );
    }

    #[test]
    fn vacant_in_arithmetic_is_zero() {
        assert_eq!(
            binary(BinOp::Add, VACANT, 1.0, Semantics::default()),
            Ok(1.0)
        );
        assert_eq!(
            binary(BinOp::Mul, VACANT, 10.0, Semantics::default()),
            Ok(0.0)
        );
        assert_eq!(
            binary(BinOp::Add, VACANT, VACANT, Semantics::default()),
            Ok(0.0)
        );
    }
}
