//! The IR's operators and functions: what the `Bin`, `Cmp`, `Func1` and `Func2` ops compute. The
//! syntax tree uses the same enums (re-exported from `ast`); the engines read them from here.

/// Binary arithmetic and logic operators (macro-b-rules E7, E13).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum BinOp {
    /// `+`
    Add,
    /// `-`
    Sub,
    /// `*`
    Mul,
    /// `/`
    Div,
    /// `MOD`
    Mod,
    /// `AND` (bitwise on the integer part; logical between comparisons)
    And,
    /// `OR`
    Or,
    /// `XOR`
    Xor,
}

/// Relational operators (macro-b-rules E2, V7).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum CmpOp {
    /// `EQ`
    Eq,
    /// `NE`
    Ne,
    /// `GT`
    Gt,
    /// `GE`
    Ge,
    /// `LT`
    Lt,
    /// `LE`
    Le,
}

/// Functions (macro-b-rules E4, E5, E10–E13).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Func {
    /// `SIN` (degrees)
    Sin,
    /// `COS`
    Cos,
    /// `TAN`
    Tan,
    /// `ASIN`
    Asin,
    /// `ACOS`
    Acos,
    /// one-argument `ATAN`
    Atan,
    /// `ATAN[a]/[b]`, `ATAN[a,b]`
    Atan2,
    /// `SQRT`
    Sqrt,
    /// `ABS`
    Abs,
    /// `ROUND`
    Round,
    /// `FIX` (truncate)
    Fix,
    /// `FUP` (away from zero)
    Fup,
    /// `LN`
    Ln,
    /// `EXP`
    Exp,
    /// `POW[a,b]`
    Pow,
    /// `ADP`
    Adp,
    /// `BIN` (BCD → binary)
    Bin,
    /// `BCD` (binary → BCD)
    Bcd,
}

impl Func {
    /// What the function does, as a programmer reads it (docs/semantics.md, rows E4, E5, E10–E13).
    pub fn describe(self) -> &'static str {
        match self {
            Func::Sin => "SIN[a]: the sine of a degrees",
            Func::Cos => "COS[a]: the cosine of a degrees",
            Func::Tan => "TAN[a]: the tangent of a degrees; alarm 0112 where COS[a] is 0",
            Func::Asin => {
                "ASIN[x]: the angle, degrees, whose sine is x: 270 to 90 (-90 to 90 with NAT); alarm 0119 outside -1 to 1"
            }
            Func::Acos => {
                "ACOS[x]: the angle, degrees, whose cosine is x: 0 to 180; alarm 0119 outside -1 to 1"
            }
            Func::Atan => {
                "ATAN[x]: the angle, degrees, whose tangent is x: 270 to 90 (-90 to 90 with NAT)"
            }
            Func::Atan2 => {
                "ATAN[a]/[b] or ATAN[a,b]: the angle, degrees, of the point X=b Y=a: 0 to 360 (-180 to 180 with NAT)"
            }
            Func::Sqrt => "SQRT[x]: the square root of x; alarm 0119 below 0",
            Func::Abs => "ABS[x]: the absolute value of x",
            Func::Round => "ROUND[x]: x rounded to the nearest whole number, halves away from zero",
            Func::Fix => "FIX[x]: x with its fraction dropped (toward zero)",
            Func::Fup => "FUP[x]: x raised to the next whole number away from zero",
            Func::Ln => "LN[x]: the natural logarithm of x; alarm 0119 at or below 0",
            Func::Exp => "EXP[x]: e to the power x",
            Func::Pow => "POW[a,b]: a to the power b",
            Func::Adp => "ADP[x]: x as a value with a decimal point (ADP[1] = 1.)",
            Func::Bin => "BIN[x]: the binary value of BCD code x",
            Func::Bcd => "BCD[x]: the BCD code of binary value x",
        }
    }
}

impl BinOp {
    /// Every operator, in declaration order (the JIT's codes and the fuzz targets use this list).
    pub const ALL: [BinOp; 8] = [
        BinOp::Add,
        BinOp::Sub,
        BinOp::Mul,
        BinOp::Div,
        BinOp::Mod,
        BinOp::And,
        BinOp::Or,
        BinOp::Xor,
    ];
}

impl CmpOp {
    /// Every comparison, in declaration order.
    pub const ALL: [CmpOp; 6] = [
        CmpOp::Eq,
        CmpOp::Ne,
        CmpOp::Gt,
        CmpOp::Ge,
        CmpOp::Lt,
        CmpOp::Le,
    ];
}

impl Func {
    /// Every function, in declaration order.
    pub const ALL: [Func; 18] = [
        Func::Sin,
        Func::Cos,
        Func::Tan,
        Func::Asin,
        Func::Acos,
        Func::Atan,
        Func::Atan2,
        Func::Sqrt,
        Func::Abs,
        Func::Round,
        Func::Fix,
        Func::Fup,
        Func::Ln,
        Func::Exp,
        Func::Pow,
        Func::Adp,
        Func::Bin,
        Func::Bcd,
    ];

    /// The name as written.
    pub fn name(self) -> &'static str {
        match self {
            Func::Sin => "SIN",
            Func::Cos => "COS",
            Func::Tan => "TAN",
            Func::Asin => "ASIN",
            Func::Acos => "ACOS",
            Func::Atan => "ATAN",
            Func::Atan2 => "ATAN2",
            Func::Sqrt => "SQRT",
            Func::Abs => "ABS",
            Func::Round => "ROUND",
            Func::Fix => "FIX",
            Func::Fup => "FUP",
            Func::Ln => "LN",
            Func::Exp => "EXP",
            Func::Pow => "POW",
            Func::Adp => "ADP",
            Func::Bin => "BIN",
            Func::Bcd => "BCD",
        }
    }
}
