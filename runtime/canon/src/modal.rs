//! The table of the G codes' modal groups (Fanuc M series; codes are `fmsvm_block::Code`, ×10) and
//! the modal state a block updates; #4001–#4022 read from it (macro-b-rules S3, S8).

pub use fmsvm_block::Code;

/// Number of modal groups tracked (#4001–#4022 → groups 1–22).
pub const GROUPS: usize = 23;

/// A Fanuc modal group (M series), by name; the discriminant is the Fanuc group number that
/// #4001–#4022 read (group 1 is #4001).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
#[repr(u8)]
pub enum Group {
    /// Group 00: one-block codes (G4, G10, G28, G52, G53, G65, G92 …).
    NonModal = 0,
    /// 01: G0 G1 G2 G3 G33.
    Motion = 1,
    /// 02: G17 G18 G19.
    Plane = 2,
    /// 03: G90 G91.
    Distance = 3,
    /// 04: G22 G23 (stroke check).
    StrokeCheck = 4,
    /// 05: G93 G94 G95.
    FeedMode = 5,
    /// 06: G20 G21.
    Units = 6,
    /// 07: G40 G41 G42.
    CutterComp = 7,
    /// 08: G43 G44 G49.
    LengthComp = 8,
    /// 09: G73 G74 G76 G80–G89.
    CannedCycle = 9,
    /// 10: G98 G99.
    ReturnLevel = 10,
    /// 11: G50 G51.
    Scaling = 11,
    /// 12: G66 G66.1 G67.
    MacroCall = 12,
    /// 13: G96 G97.
    SurfaceSpeed = 13,
    /// 14: G54–G59, G54.1.
    WorkOffset = 14,
    /// 15: G61–G64.
    CuttingMode = 15,
    /// 16: G68 G69.
    Rotation = 16,
    /// 17: G15 G16.
    Polar = 17,
    /// 18: G40.1 G41.1 G42.1.
    NormalDirection = 18,
    /// 19: G25 G26.
    SpindleFluctuation = 19,
    /// 22: G50.1 G51.1.
    Mirror = 22,
}

impl Group {
    /// Every group with modal state (not `NonModal`).
    pub const MODAL: [Group; 20] = [
        Group::Motion,
        Group::Plane,
        Group::Distance,
        Group::StrokeCheck,
        Group::FeedMode,
        Group::Units,
        Group::CutterComp,
        Group::LengthComp,
        Group::CannedCycle,
        Group::ReturnLevel,
        Group::Scaling,
        Group::MacroCall,
        Group::SurfaceSpeed,
        Group::WorkOffset,
        Group::CuttingMode,
        Group::Rotation,
        Group::Polar,
        Group::NormalDirection,
        Group::SpindleFluctuation,
        Group::Mirror,
    ];

    /// The group of Fanuc number `n` (#40nn).
    pub fn from_number(n: u8) -> Option<Group> {
        Group::MODAL.iter().copied().find(|g| *g as u8 == n)
    }
}

/// Every G code the Fanuc M-series (milling) knows, with its group. Group numbers follow the Fanuc
/// 0i/16i/30i tables: 01 motion, 02 plane, 03 absolute/incremental, 04 stroke check, 05 feed mode,
/// 06 units, 07 cutter compensation, 08 tool length offset, 09 canned cycles, 10 return level,
/// 11 scaling, 12 macro modal call, 13 constant surface speed, 14 work coordinate system, 15 exact
/// stop/cutting mode, 16 rotation, 17 polar coordinates, 18 normal direction, 19 spindle speed
/// fluctuation, 22 mirror image.
const TABLE: &[(Code, Group)] = &[
    (Code::G0, Group::Motion),
    (Code::G1, Group::Motion),
    (Code::G2, Group::Motion),
    (Code::G3, Group::Motion),
    (Code::G4, Group::NonModal),
    (Code::G5, Group::NonModal),
    (Code::G5_1, Group::NonModal),
    (Code::G7_1, Group::NonModal),
    (Code::G9, Group::NonModal),
    (Code::G10, Group::NonModal),
    (Code::G11, Group::NonModal),
    (Code::G15, Group::Polar),
    (Code::G16, Group::Polar),
    (Code::G17, Group::Plane),
    (Code::G18, Group::Plane),
    (Code::G19, Group::Plane),
    (Code::G20, Group::Units),
    (Code::G21, Group::Units),
    (Code::G22, Group::StrokeCheck),
    (Code::G23, Group::StrokeCheck),
    (Code::G25, Group::SpindleFluctuation),
    (Code::G26, Group::SpindleFluctuation),
    (Code::G27, Group::NonModal),
    (Code::G28, Group::NonModal),
    (Code::G29, Group::NonModal),
    (Code::G30, Group::NonModal),
    (Code::G31, Group::NonModal),
    (Code::G33, Group::Motion),
    (Code::G37, Group::NonModal),
    (Code::G39, Group::NonModal),
    (Code::G40, Group::CutterComp),
    (Code::G40_1, Group::NormalDirection),
    (Code::G41, Group::CutterComp),
    (Code::G41_1, Group::NormalDirection),
    (Code::G42, Group::CutterComp),
    (Code::G42_1, Group::NormalDirection),
    (Code::G43, Group::LengthComp),
    (Code::G44, Group::LengthComp),
    (Code::G45, Group::NonModal),
    (Code::G46, Group::NonModal),
    (Code::G47, Group::NonModal),
    (Code::G48, Group::NonModal),
    (Code::G49, Group::LengthComp),
    (Code::G50, Group::Scaling),
    (Code::G50_1, Group::Mirror),
    (Code::G51, Group::Scaling),
    (Code::G51_1, Group::Mirror),
    (Code::G52, Group::NonModal),
    (Code::G53, Group::NonModal),
    (Code::G54, Group::WorkOffset),
    (Code::G54_1, Group::WorkOffset),
    (Code::G55, Group::WorkOffset),
    (Code::G56, Group::WorkOffset),
    (Code::G57, Group::WorkOffset),
    (Code::G58, Group::WorkOffset),
    (Code::G59, Group::WorkOffset),
    (Code::G60, Group::NonModal),
    (Code::G61, Group::CuttingMode),
    (Code::G62, Group::CuttingMode),
    (Code::G63, Group::CuttingMode),
    (Code::G64, Group::CuttingMode),
    (Code::G65, Group::NonModal),
    (Code::G66, Group::MacroCall),
    (Code::G66_1, Group::MacroCall),
    (Code::G67, Group::MacroCall),
    (Code::G68, Group::Rotation),
    (Code::G69, Group::Rotation),
    (Code::G73, Group::CannedCycle),
    (Code::G74, Group::CannedCycle),
    (Code::G76, Group::CannedCycle),
    (Code::G80, Group::CannedCycle),
    (Code::G81, Group::CannedCycle),
    (Code::G82, Group::CannedCycle),
    (Code::G83, Group::CannedCycle),
    (Code::G84, Group::CannedCycle),
    (Code::G85, Group::CannedCycle),
    (Code::G86, Group::CannedCycle),
    (Code::G87, Group::CannedCycle),
    (Code::G88, Group::CannedCycle),
    (Code::G89, Group::CannedCycle),
    (Code::G90, Group::Distance),
    (Code::G91, Group::Distance),
    (Code::G92, Group::NonModal),
    (Code::G92_1, Group::NonModal),
    (Code::G93, Group::FeedMode),
    (Code::G94, Group::FeedMode),
    (Code::G95, Group::FeedMode),
    (Code::G96, Group::SurfaceSpeed),
    (Code::G97, Group::SurfaceSpeed),
    (Code::G98, Group::ReturnLevel),
    (Code::G99, Group::ReturnLevel),
];

/// The modal group of G code `code`, or None when the code does not exist (alarm 0010).
#[inline]
pub fn group(code: Code) -> Option<Group> {
    match GROUP_OF.get(code.tenths() as usize) {
        Some(&Some(g)) => Some(g),
        _ => None,
    }
}

/// `TABLE` as a direct index (codes below G100), built at compile time: no search per word.
static GROUP_OF: [Option<Group>; 1000] = {
    let mut t = [None; 1000];
    let mut i = 0;
    while i < TABLE.len() {
        t[TABLE[i].0.tenths() as usize] = Some(TABLE[i].1);
        i += 1;
    }
    t
};

/// The G codes in effect at power-on (Fanuc M-series defaults, parameter-independent choice).
const POWER_ON: &[(Group, Code)] = &[
    (Group::Motion, Code::G0),
    (Group::Plane, Code::G17),
    (Group::Distance, Code::G90),
    (Group::StrokeCheck, Code::G22),
    (Group::FeedMode, Code::G94),
    (Group::Units, Code::G21),
    (Group::CutterComp, Code::G40),
    (Group::LengthComp, Code::G49),
    (Group::CannedCycle, Code::G80),
    (Group::ReturnLevel, Code::G98),
    (Group::Scaling, Code::G50),
    (Group::MacroCall, Code::G67),
    (Group::SurfaceSpeed, Code::G97),
    (Group::WorkOffset, Code::G54),
    (Group::CuttingMode, Code::G64),
    (Group::Rotation, Code::G69),
    (Group::Polar, Code::G15),
    (Group::NormalDirection, Code::G40_1),
    (Group::SpindleFluctuation, Code::G25),
    (Group::Mirror, Code::G50_1),
];

/// The active G code of every group.
#[derive(Clone, Debug)]
pub struct ModalState {
    /// Active code per group (index = group number); G0 (code 0) for groups without one.
    pub groups: [Code; GROUPS],
}

impl Default for ModalState {
    fn default() -> Self {
        let mut groups = [Code::G0; GROUPS];
        for &(g, c) in POWER_ON {
            groups[g as usize] = c;
        }
        ModalState { groups }
    }
}

impl ModalState {
    /// Makes `code` active in its group (non-modal codes change nothing).
    pub fn set(&mut self, code: Code) {
        if let Some(g) = group(code)
            && g != Group::NonModal
        {
            self.groups[g as usize] = code;
        }
    }

    /// The active code of `group`.
    pub fn get(&self, group: Group) -> Code {
        self.groups[group as usize]
    }

    /// The active code of Fanuc group number `n` (#40nn); code 0 for a number without a group.
    pub fn get_number(&self, n: u8) -> Code {
        Group::from_number(n).map_or(Code::G0, |g| self.get(g))
    }

    /// The power-on state with `codes` (`"G17 G90 G94 G21 G40 G49 G80 G98 G0"`) made active; every
    /// code must be a modal G code.
    pub fn parse(codes: &str) -> Result<ModalState, String> {
        let mut m = ModalState::default();
        for word in codes.split(|c: char| c.is_whitespace() || c == ',') {
            if word.is_empty() {
                continue;
            }
            let value = word
                .strip_prefix(['G', 'g'])
                .and_then(|v| v.parse::<f64>().ok())
                .ok_or_else(|| format!("`{word}` is not a G code"))?;
            let code = Code::of(value)
                .filter(|c| c.is_exact(value))
                .ok_or_else(|| format!("`{word}` is not a G code"))?;
            match group(code) {
                None => return Err(format!("{word} does not exist on a Fanuc M-series control")),
                Some(Group::NonModal) => {
                    return Err(format!(
                        "{word} acts for one block only; it has no power-on state"
                    ));
                }
                Some(
                    Group::CutterComp
                    | Group::LengthComp
                    | Group::Rotation
                    | Group::Scaling
                    | Group::Mirror
                    | Group::MacroCall,
                ) if ![
                    Code::G40,
                    Code::G49,
                    Code::G69,
                    Code::G50,
                    Code::G50_1,
                    Code::G67,
                ]
                .contains(&code) =>
                {
                    return Err(format!(
                        "{word} needs words of its own block; it cannot be a power-on state"
                    ));
                }
                Some(_) => m.set(code),
            }
        }
        Ok(m)
    }

    /// Inch units (G20) are active.
    pub fn inch(&self) -> bool {
        self.get(Group::Units) == Code::G20
    }

    /// Incremental positioning (G91) is active.
    pub fn incremental(&self) -> bool {
        self.get(Group::Distance) == Code::G91
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_is_sorted_for_binary_search() {
        assert!(
            TABLE.windows(2).all(|w| w[0].0 < w[1].0),
            "table must be sorted"
        );
        assert_eq!(group(Code::G1), Some(Group::Motion));
        assert_eq!(group(Code::G54_1), Some(Group::WorkOffset));
        assert_eq!(group(Code::from_tenths(15)), None);
        assert_eq!(Group::from_number(14), Some(Group::WorkOffset));
        assert_eq!(Group::from_number(20), None);
        assert_eq!(Group::from_number(0), None);
    }

    #[test]
    fn power_on_state() {
        let m = ModalState::default();
        assert_eq!(m.get(Group::Motion), Code::G0);
        assert_eq!(m.get(Group::Distance), Code::G90);
        assert_eq!(m.get_number(17), Code::G15);
        assert_eq!(m.get_number(21), Code::G0);
        assert!(!m.inch());
    }
}
