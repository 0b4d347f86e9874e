//! What a block's words mean in the program's language, before any output: the least input increment
//! (IS-B), the decimal-point input rule (V11), the range of each integer address, which G codes exist,
//! vacant stores. The kernel decodes with these once per block; emitters only format.

use fmsvm_block::{AddressClass, Alarm, Block, Code, Letter, MAX_WORDS, Word, WordFlags};

use fmsvm_block::alarms::{IMPROPER_G, MINUS_SIGN, TOO_MANY_DIGITS};

/// How a literal without a decimal point is read (macro-b-rules V11).
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub enum DecimalInput {
    /// `X10` = 10 mm (calculator type, Fanuc parameter; what the textbook programs and LinuxCNC assume).
    #[default]
    Calculator,
    /// `X10` = 10 least increments = 0.010 mm (Fanuc decimal-point input type I).
    Increment,
}

/// The number rules of the program's language (the control it was written for), apart from how the
/// output is spelled: the least input increment of lengths and angles (IS-B: 0.001 mm, 0.0001 inch,
/// 0.001°), the decimal-point input rule, the range of each integer address, the most digits a value
/// may have.
#[derive(Clone, Debug)]
pub struct InputRules {
    /// How literals without a point are read.
    pub decimal: DecimalInput,
    /// Decimals of the least increment of a length in mm (3 = 0.001 mm).
    pub mm_digits: u32,
    /// Decimals of the least increment of a length in inch.
    pub inch_digits: u32,
    /// Decimals of the least increment of an angle.
    pub angle_digits: u32,
    /// Most digits a length or angle may have (8 on Fanuc: ±99999.999 mm).
    pub max_digits: u32,
    /// The second auxiliary function's address when the control has one (B, or where parameter
    /// 3460 moves it): an integer code there, though A, B and C are angles otherwise.
    pub second_aux: Option<Letter>,
}

impl Default for InputRules {
    /// Fanuc 0i/16i/30i milling, IS-B, calculator-type input.
    fn default() -> Self {
        InputRules {
            decimal: DecimalInput::Calculator,
            mm_digits: 3,
            inch_digits: 4,
            angle_digits: 3,
            max_digits: 8,
            second_aux: None,
        }
    }
}

/// The largest value of an integer address (Fanuc ranges).
pub const fn integer_max(letter: Letter) -> u64 {
    match letter {
        Letter::D | Letter::H | Letter::M => 999,
        Letter::L | Letter::O => 9999,
        Letter::N | Letter::S => 99_999,
        _ => 99_999_999,
    }
}

impl InputRules {
    /// What `letter`'s value is here: its class in the language, but an integer code at the second
    /// auxiliary function's address.
    pub fn class(&self, letter: Letter) -> AddressClass {
        if Some(letter) == self.second_aux {
            AddressClass::Integer
        } else {
            letter.class()
        }
    }

    /// The least increment of `letter` (what `ROUND` in an address rounds to, E3).
    pub fn increment(&self, letter: Letter, inch: bool) -> f64 {
        match self.class(letter) {
            AddressClass::GCode | AddressClass::Integer => 1.0,
            AddressClass::Angular => 10f64.powi(-(self.angle_digits as i32)),
            AddressClass::Linear | AddressClass::Feed => 10f64.powi(
                -((if inch {
                    self.inch_digits
                } else {
                    self.mm_digits
                }) as i32),
            ),
        }
    }

    /// The rules as a table per unit system and letter, so that decoding a word costs no power of ten.
    pub fn table(&self) -> DecodeTable {
        let mut t = DecodeTable {
            class: Letter::ALL.map(|l| self.class(l)),
            second_aux: self.second_aux,
            decimal: self.decimal,
            increment: [[1.0; Letter::COUNT]; 2],
            bounds: [[(f64::NEG_INFINITY, f64::INFINITY); Letter::COUNT]; 2],
            max_digits: self.max_digits,
        };
        for (u, inch) in [false, true].into_iter().enumerate() {
            for l in Letter::ALL {
                let inc = self.increment(l, inch);
                t.increment[u][l.index()] = inc;
                t.bounds[u][l.index()] = match self.class(l) {
                    AddressClass::GCode => (f64::NEG_INFINITY, f64::INFINITY),
                    // Rounded half away from zero, −0.5 is −1 (alarm 0006) and max + 0.5 too many.
                    AddressClass::Integer => (-0.5, integer_max(l) as f64 + 0.5),
                    _ => {
                        let limit = 10f64.powi(self.max_digits as i32) * inc - inc / 2.0;
                        (-limit, limit)
                    }
                };
            }
        }
        t
    }
}

/// `InputRules` worked out per unit system (mm, inch) and letter: the least increment and the largest
/// magnitude a value may have.
#[derive(Clone, Debug)]
pub struct DecodeTable {
    /// Each letter's class (`InputRules::class`).
    class: [AddressClass; Letter::COUNT],
    second_aux: Option<Letter>,
    decimal: DecimalInput,
    increment: [[f64; Letter::COUNT]; 2],
    /// The open interval each value must lie in (a NaN lies in none).
    bounds: [[(f64, f64); Letter::COUNT]; 2],
    max_digits: u32,
}

impl DecodeTable {
    /// The second auxiliary function's address (`InputRules::second_aux`): a code, not an axis.
    #[inline(always)]
    pub fn second_aux(&self) -> Option<Letter> {
        self.second_aux
    }

    /// The open interval a value of `letter` must lie in (`fits`).
    pub fn bounds(&self, letter: Letter, inch: bool) -> (f64, f64) {
        self.bounds[inch as usize][letter.index()]
    }

    /// The least increment of `letter`.
    #[inline(always)]
    pub fn increment(&self, letter: Letter, inch: bool) -> f64 {
        self.increment[inch as usize][letter.index()]
    }

    /// The value a word stands for, after the decimal-point input rule.
    #[inline(always)]
    pub fn value(&self, w: &Word, inch: bool) -> f64 {
        if self.decimal == DecimalInput::Increment
            && w.flags.has(WordFlags::NO_POINT)
            && matches!(
                self.class[w.letter.index()],
                AddressClass::Linear | AddressClass::Angular
            )
        {
            return w.value * self.increment(w.letter, inch);
        }
        w.value
    }

    /// Checks a decoded value against the language's limits: integer addresses are whole numbers in
    /// their range after rounding half away from zero (V10), lengths and angles fit the digits.
    #[inline(always)]
    fn check(&self, w: &Word, v: f64, inch: bool) -> Result<(), Alarm> {
        if self.fits(w, v, inch) {
            return Ok(());
        }
        self.refuse(w, v)
    }

    /// Whether `check` passes: two comparisons for the usual word (finite, not negative where that
    /// matters, within range).
    #[inline(always)]
    pub fn fits(&self, w: &Word, v: f64, inch: bool) -> bool {
        let (low, high) = self.bounds[inch as usize][w.letter.index()];
        v > low && v < high
    }

    #[cold]
    fn refuse(&self, w: &Word, v: f64) -> Result<(), Alarm> {
        if !v.is_finite() {
            return Err(Alarm::new(
                111,
                format!("{}: value is not a finite number", w.letter),
            ));
        }
        match self.class[w.letter.index()] {
            AddressClass::GCode => Ok(()),
            AddressClass::Integer => {
                let r = v.round();
                let max = integer_max(w.letter);
                if r < 0.0 {
                    Err(Alarm::new(
                        MINUS_SIGN,
                        format!("illegal use of minus sign: {}{v}", w.letter),
                    ))
                } else if r > max as f64 {
                    Err(Alarm::new(
                        TOO_MANY_DIGITS,
                        format!(
                            "too many digits: {}{v} (at most {}{max})",
                            w.letter, w.letter
                        ),
                    ))
                } else {
                    Ok(())
                }
            }
            AddressClass::Linear | AddressClass::Angular | AddressClass::Feed => Err(Alarm::new(
                TOO_MANY_DIGITS,
                format!(
                    "too many digits: {}{v} does not fit {} digit{}",
                    w.letter,
                    self.max_digits,
                    if self.max_digits == 1 { "" } else { "s" }
                ),
            )),
        }
    }
}

/// A block with the value of each word decoded once (decimal-point rule applied, ranges checked):
/// what the literal emitter writes and the kernel executes.
pub struct Decoded<'b, 'p> {
    /// The block as the VM built it.
    pub block: &'b Block<'p>,
    /// The decoded value of each word, in the block's order (those past the block's words are not
    /// its values).
    values: &'b [f64; MAX_WORDS],
    /// Some word carries NCT's incremental operator.
    incremental: bool,
}

impl<'b, 'p> Decoded<'b, 'p> {
    /// Decodes every word of `block` under `rules` in the given units, into `buf` (the caller's, reused
    /// block after block: decoding neither clears nor copies a block-sized array).
    #[inline]
    pub fn new(
        block: &'b Block<'p>,
        rules: &DecodeTable,
        inch: bool,
        buf: &'b mut [f64; MAX_WORDS],
    ) -> Result<Self, Alarm> {
        for (slot, w) in buf.iter_mut().zip(block.words()) {
            let v = rules.value(w, inch);
            rules.check(w, v, inch)?;
            *slot = v;
        }
        Ok(Decoded {
            block,
            values: buf,
            incremental: block.any_flags().has(WordFlags::INCREMENTAL),
        })
    }

    /// A view of `block` with values already decoded into `values` (by `new`, then perhaps rewritten
    /// by the kernel: NCT's incremental words become absolute; or by the kernel's plain move, with
    /// `DecodeTable::value` and `fits`, as `new` does).
    pub fn view(block: &'b Block<'p>, values: &'b [f64; MAX_WORDS]) -> Self {
        Decoded {
            block,
            values,
            // The kernel has made every incremental word absolute by now.
            incremental: false,
        }
    }

    /// Whether some word carries NCT's incremental operator (`XI10`).
    #[inline(always)]
    pub fn has_incremental(&self) -> bool {
        self.incremental
    }

    /// The decoded values, one for each of the block's words, in programmed order.
    #[inline(always)]
    pub fn values(&self) -> &'b [f64] {
        &self.values[..self.block.words().len()]
    }

    /// The whole buffer the values are in, the block's first (the pipelined emitter copies them in
    /// fixed-size pieces).
    #[inline(always)]
    pub fn value_buffer(&self) -> &'b [f64; MAX_WORDS] {
        self.values
    }

    /// The words with their decoded values, in programmed order.
    #[inline(always)]
    pub fn words(&self) -> impl Iterator<Item = (&'b Word, f64)> + '_ {
        self.block.words().iter().zip(self.values().iter().copied())
    }
}

/// Rounds a G-code value to its ×10 code and checks it exists.
#[inline(always)]
pub fn gcode(value: f64) -> Result<Code, Alarm> {
    match Code::of(value) {
        Some(c) if c.is_exact(value) && crate::modal::group(c).is_some() => Ok(c),
        _ => Err(Alarm::new(IMPROPER_G, format!("improper G-code: G{value}"))),
    }
}

/// Vacant written to a numeric store counts as 0.
pub fn vacant_as_zero(v: f64) -> f64 {
    if fmsvm_block::is_vacant(v) { 0.0 } else { v }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn word(letter: Letter, value: f64, no_point: bool) -> Word {
        Word {
            letter,
            flags: WordFlags(if no_point { WordFlags::NO_POINT } else { 0 }),
            value,
        }
    }

    #[test]
    fn decimal_point_input_type_one() {
        let r = InputRules {
            decimal: DecimalInput::Increment,
            ..InputRules::default()
        }
        .table();
        // V11: X10 is 10 µm, X10. is 10 mm, F and integer addresses are never scaled.
        assert!((r.value(&word(Letter::X, 10.0, true), false) - 0.010).abs() < 1e-12);
        assert_eq!(r.value(&word(Letter::X, 10.0, false), false), 10.0);
        assert_eq!(r.value(&word(Letter::F, 100.0, true), false), 100.0);
        assert_eq!(r.value(&word(Letter::S, 100.0, true), false), 100.0);
        assert!((r.value(&word(Letter::X, 10.0, true), true) - 0.001).abs() < 1e-12);
    }

    #[test]
    fn ranges_and_digits() {
        let r = InputRules::default().table();
        assert_eq!(
            r.check(&word(Letter::M, -1.0, false), -1.0, false)
                .unwrap_err()
                .number,
            6
        );
        assert_eq!(
            r.check(&word(Letter::M, 1000.0, false), 1000.0, false)
                .unwrap_err()
                .number,
            3
        );
        assert!(
            r.check(&word(Letter::X, 99_999.999, false), 99_999.999, false)
                .is_ok()
        );
        assert_eq!(
            r.check(&word(Letter::X, 100_000.0, false), 100_000.0, false)
                .unwrap_err()
                .number,
            3
        );
    }
}
