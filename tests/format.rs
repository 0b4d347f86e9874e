//! The number formatter (`runtime/emit/src/format.rs`) against a reference that is obviously right:
//! the exact decimal of the integer written by `format!`, then cut and padded by the `NumberFormat`
//! rules as strings. Proptest over every value class and format, exhaustive tests over the rounding
//! boundaries of `Dialect::least_increments` (the values the emitters hand the formatter).

use fmsvm_emit::dialect::{Dialect, NumberFormat, Point};
use fmsvm_emit::format::{push_fixed, push_formatted, push_gcode, push_padded, push_u64};
use proptest::prelude::*;

/// `q × 10^-digits` as `f` says, by string surgery on the exact decimal of `q`.
///
/// - the sign: `-` below zero, else `+` when `f.plus` (zero included); `-0` cannot happen (`q` is an
///   integer);
/// - `Point::Never`: the magnitude in increments, zero-padded to `f.width` digits;
/// - the fraction: the last `digits` digits of the magnitude, trailing zeros cut unless
///   `f.trailing_zeros` (then all `digits` of them);
/// - the point: with `Point::Always`, or when a fraction is written (a non-zero fraction, or the
///   fraction's zeros kept by `trailing_zeros`);
/// - the integer part: leading zeros cut (at least `0`), zero-padded to `f.width`; left out only for
///   a value below one with a fraction written after the point, without `leading_zero` and without a
///   width (`-.5`).
fn reference(q: i64, digits: u32, f: &NumberFormat) -> String {
    let sign = if q < 0 {
        "-"
    } else if f.plus {
        "+"
    } else {
        ""
    };
    let magnitude = (q as i128).abs().to_string();
    let width = f.width as usize;
    if f.point == Point::Never {
        return format!("{sign}{magnitude:0>width$}");
    }
    let d = digits as usize;
    // At least one digit before the fraction's.
    let all = format!("{magnitude:0>n$}", n = d + 1);
    let (int, frac) = all.split_at(all.len() - d);
    let int = int.trim_start_matches('0');
    let int = if int.is_empty() { "0" } else { int };
    let frac = if f.trailing_zeros {
        frac
    } else {
        frac.trim_end_matches('0')
    };
    let point = f.point == Point::Always || !frac.is_empty();
    let below_one = int == "0" && frac.bytes().any(|b| b != b'0');
    let int = if below_one && !f.leading_zero && width == 0 {
        String::new()
    } else {
        format!("{int:0>width$}")
    };
    if point {
        format!("{sign}{int}.{frac}")
    } else {
        format!("{sign}{int}")
    }
}

fn formatted(q: i64, digits: u32, f: &NumberFormat) -> String {
    // Something before, so that a formatter writing at the wrong place or too much shows.
    let mut b = b"X".to_vec();
    push_formatted(&mut b, q, digits, f);
    String::from_utf8(b).unwrap()[1..].to_string()
}

fn fixed(q: i64, digits: u32) -> String {
    let mut b = b"X".to_vec();
    push_fixed(&mut b, q, digits);
    String::from_utf8(b).unwrap()[1..].to_string()
}

fn padded(v: u64, pad: u8) -> String {
    let mut b = b"X".to_vec();
    push_padded(&mut b, v, pad);
    String::from_utf8(b).unwrap()[1..].to_string()
}

fn u64_text(v: u64) -> String {
    let mut b = b"X".to_vec();
    push_u64(&mut b, v);
    String::from_utf8(b).unwrap()[1..].to_string()
}

/// Every combination of the format's rules with widths 0–9 (the profiles' range) and a few beyond.
fn all_formats() -> Vec<NumberFormat> {
    let mut v = Vec::new();
    for point in [Point::Always, Point::WhenFractional, Point::Never] {
        for bits in 0..8u8 {
            for width in (0..=9).chain([12, 17, 20, 25]) {
                v.push(NumberFormat {
                    point,
                    trailing_zeros: bits & 1 != 0,
                    leading_zero: bits & 2 != 0,
                    plus: bits & 4 != 0,
                    width,
                });
            }
        }
    }
    v
}

fn format_strategy() -> impl Strategy<Value = NumberFormat> {
    (
        0..3u8,
        any::<[bool; 3]>(),
        prop_oneof![0..=9u8, any::<u8>()],
    )
        .prop_map(
            |(p, [trailing_zeros, leading_zero, plus], width)| NumberFormat {
                point: [Point::Always, Point::WhenFractional, Point::Never][p as usize],
                trailing_zeros,
                leading_zero,
                plus,
                width,
            },
        )
}

/// Powers of ten and their neighbours up to i64's range.
fn near_powers() -> impl Strategy<Value = i64> {
    (0..19u32, -3..=3i64, any::<bool>()).prop_map(|(e, off, neg)| {
        let p = 10i64.pow(e);
        let v = p.saturating_add(off).max(0);
        if neg { -v } else { v }
    })
}

/// Every class of value a caller can hand the formatter: zero and ±1, below one increment, small,
/// exact multiples of powers of ten, the max-digits edges, near powers of ten, i64's extremes, any.
fn value_strategy() -> impl Strategy<Value = i64> {
    prop_oneof![
        Just(0i64),
        Just(1),
        Just(-1),
        Just(i64::MIN),
        Just(i64::MAX),
        Just(i64::MIN + 1),
        -1_000i64..=1_000,
        -100_000_000i64..=100_000_000,
        (-100_000i64..=100_000, 0..7u32).prop_map(|(k, e)| k * 10i64.pow(e)),
        (1..=9u32, -2..=2i64, any::<bool>()).prop_map(|(m, off, neg)| {
            let v = 10i64.pow(m) - 1 + off;
            if neg { -v } else { v }
        }),
        near_powers(),
        any::<i64>(),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 20_000, .. ProptestConfig::default() })]

    #[test]
    fn formatted_is_the_reference(q in value_strategy(), digits in 0..=9u32, f in format_strategy()) {
        prop_assert_eq!(formatted(q, digits, &f), reference(q, digits, &f), "q {} digits {} {:?}", q, digits, f);
    }

    #[test]
    fn fixed_is_fanucs_reference(q in value_strategy(), digits in 0..=12u32) {
        prop_assert_eq!(fixed(q, digits), reference(q, digits, &NumberFormat::FANUC), "q {} digits {}", q, digits);
    }

    #[test]
    fn padded_and_u64(v in prop_oneof![0..1_000u64, any::<u64>(), near_powers().prop_map(i64::unsigned_abs)], pad in prop_oneof![0..=9u8, any::<u8>()]) {
        prop_assert_eq!(padded(v, pad), format!("{v:0>w$}", w = pad as usize));
        prop_assert_eq!(u64_text(v), v.to_string());
    }
}

#[test]
fn every_format_on_every_digit_count_and_edge() {
    let mut values = vec![
        0i64,
        1,
        -1,
        5,
        -5,
        9,
        10,
        11,
        99,
        100,
        101,
        i64::MIN,
        i64::MAX,
    ];
    for e in 0..19 {
        let p = 10i64.pow(e);
        values.extend([p - 1, p, p + 1, -(p - 1), -p, -(p + 1), 5 * p, -5 * p]);
    }
    for f in all_formats() {
        for digits in 0..=9 {
            for &q in &values {
                assert_eq!(
                    formatted(q, digits, &f),
                    reference(q, digits, &f),
                    "q {q} digits {digits} {f:?}"
                );
            }
        }
    }
}

#[test]
fn every_value_to_a_million_in_the_builtin_formats() {
    // Every value of |q| < 10^6 at 0–6 decimals in Fanuc's, FMS-3000's and the tape's formats.
    let formats = [
        NumberFormat::FANUC,
        NumberFormat {
            point: Point::WhenFractional,
            ..NumberFormat::FANUC
        },
        NumberFormat {
            point: Point::Never,
            plus: true,
            width: 6,
            ..NumberFormat::FANUC
        },
        NumberFormat {
            trailing_zeros: true,
            leading_zero: false,
            width: 2,
            ..NumberFormat::FANUC
        },
    ];
    for digits in 0..=6 {
        for q in (-1_000_000i64..=1_000_000).step_by(if digits == 3 { 1 } else { 7 }) {
            for f in &formats {
                assert_eq!(
                    formatted(q, digits, f),
                    reference(q, digits, f),
                    "q {q} digits {digits} {f:?}"
                );
            }
        }
    }
}

#[test]
fn the_reference_says_what_the_rules_say() {
    let when = NumberFormat {
        point: Point::WhenFractional,
        ..NumberFormat::FANUC
    };
    let bare = NumberFormat {
        leading_zero: false,
        ..NumberFormat::FANUC
    };
    let full = NumberFormat {
        trailing_zeros: true,
        ..NumberFormat::FANUC
    };
    let tape = NumberFormat {
        point: Point::Never,
        plus: true,
        width: 6,
        ..NumberFormat::FANUC
    };
    let cases: [(i64, u32, NumberFormat, &str); 14] = [
        (10_000, 3, NumberFormat::FANUC, "10."),
        (-1_500, 3, NumberFormat::FANUC, "-1.5"),
        (0, 3, NumberFormat::FANUC, "0."),
        (5, 3, NumberFormat::FANUC, "0.005"),
        (10_000, 3, when, "10"),
        (5, 3, when, "0.005"),
        (-500, 3, bare, "-.5"),
        (0, 3, bare, "0."),
        (10_500, 3, full, "10.500"),
        (0, 3, full, "0.000"),
        (5, 0, full, "5."),
        (8_000, 2, tape, "+008000"),
        (-21_759, 2, tape, "-021759"),
        (i64::MIN, 3, NumberFormat::FANUC, "-9223372036854775.808"),
    ];
    for (q, d, f, want) in cases {
        assert_eq!(reference(q, d, &f), want, "{q} {d} {f:?}");
        assert_eq!(formatted(q, d, &f), want, "{q} {d} {f:?}");
    }
}

#[test]
fn codes() {
    for code in 0..=9999u16 {
        let mut b = Vec::new();
        push_gcode(&mut b, code);
        let want = if code % 10 == 0 {
            (code / 10).to_string()
        } else {
            format!("{}.{}", code / 10, code % 10)
        };
        assert_eq!(String::from_utf8(b).unwrap(), want);
    }
}

// --- least_increments: the values the formatter is handed --------------------------------------

/// The reference rounding: the product rounded half away from zero by the standard library, refused
/// when not a number or when it does not fit `max_digits` digits.
fn reference_increments(value: f64, digits: u32, max_digits: u32) -> Option<i64> {
    let q = value * 10f64.powi(digits as i32);
    if q.is_nan() || q.abs() >= 10f64.powi(max_digits as i32) - 0.5 {
        return None;
    }
    Some(q.round() as i64)
}

fn dialect(digits: u32, max_digits: u32) -> Dialect {
    Dialect {
        mm_digits: digits,
        max_digits,
        ..Dialect::fanuc()
    }
}

/// The increments that are interesting at `max_digits`: around zero, around each power of ten, and at
/// the edge.
fn boundary_ks(max_digits: u32) -> Vec<i64> {
    let top = 10i64.pow(max_digits);
    let mut ks: Vec<i64> = (-2_000..=2_000).collect();
    for e in 1..=max_digits {
        let p = 10i64.pow(e);
        ks.extend(p - 20..=p + 20);
    }
    ks.extend(top - 200..=top + 5);
    ks.retain(|&k| k.abs() <= top + 5);
    let neg: Vec<i64> = ks.iter().map(|k| -k).collect();
    ks.extend(neg);
    ks.sort_unstable();
    ks.dedup();
    ks
}

#[test]
fn increments_at_every_rounding_boundary() {
    for max_digits in 1..=9u32 {
        for digits in 0..=6u32.min(max_digits) {
            let d = dialect(digits, max_digits);
            let scale = 10f64.powi(digits as i32);
            let top = 10i64.pow(max_digits);
            for k in boundary_ks(max_digits) {
                let exact = k as f64 / scale;
                let half = (k as f64 + 0.5) / scale;
                for v in [
                    exact,
                    exact.next_up(),
                    exact.next_down(),
                    half,
                    half.next_up(),
                    half.next_down(),
                    -half,
                ] {
                    let got = d.least_increments(v, digits);
                    assert_eq!(
                        got,
                        reference_increments(v, digits, max_digits),
                        "{v:e} at {digits} decimals, {max_digits} digits"
                    );
                    // Whatever the float product, the increment is within one of the value, and the
                    // formatter writes it as the reference does.
                    if let Some(q) = got {
                        assert!((q as f64 - v * scale).abs() <= 0.5 + 1e-6, "{v:e} -> {q}");
                        assert!(q.abs() < top, "{v:e} -> {q}: more than {max_digits} digits");
                        assert_eq!(
                            formatted(q, digits, &NumberFormat::FANUC),
                            reference(q, digits, &NumberFormat::FANUC)
                        );
                    }
                }
                // An exact multiple of the increment (and one ulp either side) is that increment.
                if k.abs() < top {
                    for v in [exact, exact.next_up(), exact.next_down()] {
                        assert_eq!(d.least_increments(v, digits), Some(k), "{v:e}");
                    }
                } else {
                    assert_eq!(d.least_increments(exact, digits), None, "{exact:e}");
                }
            }
        }
    }
}

#[test]
fn half_increments_round_away_from_zero_when_exact() {
    // Half-way values whose product is exact in binary (k + 0.5 at 0 decimals, or k/2 increments of
    // 0.5 at 1 decimal): away from zero, both signs.
    for max_digits in 1..=9u32 {
        let top = 10i64.pow(max_digits);
        let d = dialect(0, max_digits);
        for k in boundary_ks(max_digits) {
            let v = k as f64 + if k < 0 { -0.5 } else { 0.5 };
            let want = if k < 0 { k - 1 } else { k + 1 };
            let want = (want.abs() < top).then_some(want);
            assert_eq!(d.least_increments(v, 0), want, "{v} at {max_digits} digits");
        }
    }
}

#[test]
fn the_edges_of_the_increments() {
    let d = Dialect::fanuc();
    // -0.0 is zero, written without a sign.
    assert_eq!(d.least_increments(-0.0, 3), Some(0));
    assert_eq!(formatted(0, 3, &NumberFormat::FANUC), "0.");
    // Below half an increment rounds to zero, at half an increment away from it.
    assert_eq!(d.least_increments(0.000_499_9, 3), Some(0));
    assert_eq!(d.least_increments(-0.000_499_9, 3), Some(0));
    assert_eq!(d.least_increments(0.000_5, 3), Some(1));
    assert_eq!(d.least_increments(-0.000_5, 3), Some(-1));
    assert_eq!(d.least_increments(f64::MIN_POSITIVE, 3), Some(0));
    // Fanuc's 8 digits: ±99999.999 and no further.
    assert_eq!(d.least_increments(99_999.999, 3), Some(99_999_999));
    assert_eq!(d.least_increments(-99_999.999, 3), Some(-99_999_999));
    assert_eq!(d.least_increments(99_999.999_4, 3), Some(99_999_999));
    assert_eq!(d.least_increments(99_999.999_5, 3), None);
    assert_eq!(d.least_increments(100_000.0, 3), None);
    // Not a number and the infinities are refused.
    for v in [
        f64::NAN,
        -f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::MAX,
        f64::MIN,
    ] {
        assert_eq!(d.least_increments(v, 3), None, "{v}");
    }
}
