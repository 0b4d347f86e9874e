//! How a control spells numbers: which addresses are codes, integers, lengths or angles, their digits
//! and ranges. A dialect is data (a table per letter), never a branch on a dialect name.

use fmsvm_block::{AddressClass, Letter};

/// What kind of value an address carries.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum AddressKind {
    /// A G code: a number with at most one decimal (G54.1), checked against the G-code table.
    GCode,
    /// A whole number from 0 to `max` (M S T D H N O L P): rounded half away from zero (V10), no point.
    Integer {
        /// The largest value the address takes.
        max: u64,
    },
    /// A length (X Y Z I J K R Q U V W E, `,C` `,R`): least increment 0.001 mm / 0.0001 inch.
    Linear,
    /// An angle (A B C, `,A`): least increment 0.001 degree in either unit system.
    Angular,
    /// A feed (F): written like a length.
    Feed,
}

/// A control's number format.
#[derive(Clone, Debug)]
pub struct Dialect {
    /// Name (`fanuc`).
    pub name: &'static str,
    /// Kind of each address, indexed by `Letter::index`.
    pub kinds: [AddressKind; Letter::COUNT],
    /// Decimals of a length in mm (3 = 0.001 mm).
    pub mm_digits: u32,
    /// Decimals of a length in inch (4 = 0.0001 inch).
    pub inch_digits: u32,
    /// Decimals of an angle.
    pub angle_digits: u32,
    /// Most digits a dimension word may have (8 on Fanuc: ±99999.999 mm).
    pub max_digits: u32,
}

impl Dialect {
    /// Fanuc 0i/16i/18i/30i milling, metric 1 µm system (IS-B).
    pub fn fanuc() -> Dialect {
        // The class of each address is the language's (Letter::class); the range of each integer
        // address is Fanuc's, the same table the input is checked against (decode::integer_max).
        let kinds = std::array::from_fn(|i| {
            let l = Letter::ALL[i];
            match l.class() {
                AddressClass::GCode => AddressKind::GCode,
                AddressClass::Integer => AddressKind::Integer {
                    max: crate::decode::integer_max(l),
                },
                AddressClass::Linear => AddressKind::Linear,
                AddressClass::Angular => AddressKind::Angular,
                AddressClass::Feed => AddressKind::Feed,
            }
        });
        Dialect {
            name: "fanuc",
            kinds,
            mm_digits: 3,
            inch_digits: 4,
            angle_digits: 3,
            max_digits: 8,
        }
    }

    /// The kind of `letter`.
    pub fn kind(&self, letter: Letter) -> AddressKind {
        self.kinds[letter.index()]
    }

    /// Decimals of `letter` in the given units (0 for integer addresses, 1 for G codes).
    pub fn digits(&self, letter: Letter, inch: bool) -> u32 {
        match self.kind(letter) {
            AddressKind::GCode => 1,
            AddressKind::Integer { .. } => 0,
            AddressKind::Angular => self.angle_digits,
            AddressKind::Linear | AddressKind::Feed => {
                if inch {
                    self.inch_digits
                } else {
                    self.mm_digits
                }
            }
        }
    }
}

/// Powers of ten for the digits of an address.
const POW10: [f64; 10] = [1.0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9];

/// Rounds half away from zero without a libm call (|x| < 2^52, which the digit check guarantees).
#[inline(always)]
fn round_away(x: f64) -> i64 {
    let t = x as i64;
    let f = x - t as f64;
    if f >= 0.5 {
        t + 1
    } else if f <= -0.5 {
        t - 1
    } else {
        t
    }
}

impl Dialect {
    /// `value` of a length, angle or feed address with `digits` decimals (`digits(letter, inch)`, which
    /// the caller has at hand) in the output's least increments (rounded half away from zero), or
    /// None when it does not fit the dialect's digits (alarm 0003 for the caller).
    #[inline(always)]
    pub fn least_increments(&self, value: f64, digits: u32) -> Option<i64> {
        let q = value * POW10[digits as usize];
        if q.is_nan() || q.abs() >= POW10[self.max_digits as usize] - 0.5 {
            return None;
        }
        Some(round_away(q))
    }
}

impl Default for Dialect {
    fn default() -> Self {
        Dialect::fanuc()
    }
}
