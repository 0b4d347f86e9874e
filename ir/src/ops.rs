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
