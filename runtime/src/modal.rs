//! G codes as integers ×10 (G54.1 = 541), the table of their modal groups (Fanuc M series), and the
//! modal state a block updates; #4001–#4022 read from it (macro-b-rules S3, S8).

/// A G code ×10 (`G1` = 10, `G54.1` = 541), so codes are never compared as floats.
pub type GCode = u16;

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
const TABLE: &[(GCode, Group)] = &[
    (0, Group::Motion),
    (10, Group::Motion),
    (20, Group::Motion),
    (30, Group::Motion),
    (40, Group::NonModal),
    (50, Group::NonModal),
    (51, Group::NonModal),
    (71, Group::NonModal),
    (90, Group::NonModal),
    (100, Group::NonModal),
    (110, Group::NonModal),
    (150, Group::Polar),
    (160, Group::Polar),
    (170, Group::Plane),
    (180, Group::Plane),
    (190, Group::Plane),
    (200, Group::Units),
    (210, Group::Units),
    (220, Group::StrokeCheck),
    (230, Group::StrokeCheck),
    (250, Group::SpindleFluctuation),
    (260, Group::SpindleFluctuation),
    (270, Group::NonModal),
    (280, Group::NonModal),
    (290, Group::NonModal),
    (300, Group::NonModal),
    (310, Group::NonModal),
    (330, Group::Motion),
    (370, Group::NonModal),
    (390, Group::NonModal),
    (400, Group::CutterComp),
    (401, Group::NormalDirection),
    (410, Group::CutterComp),
    (411, Group::NormalDirection),
    (420, Group::CutterComp),
    (421, Group::NormalDirection),
    (430, Group::LengthComp),
    (440, Group::LengthComp),
    (450, Group::NonModal),
    (460, Group::NonModal),
    (470, Group::NonModal),
    (480, Group::NonModal),
    (490, Group::LengthComp),
    (500, Group::Scaling),
    (501, Group::Mirror),
    (510, Group::Scaling),
    (511, Group::Mirror),
    (520, Group::NonModal),
    (530, Group::NonModal),
    (540, Group::WorkOffset),
    (541, Group::WorkOffset),
    (550, Group::WorkOffset),
    (560, Group::WorkOffset),
    (570, Group::WorkOffset),
    (580, Group::WorkOffset),
    (590, Group::WorkOffset),
    (600, Group::NonModal),
    (610, Group::CuttingMode),
    (620, Group::CuttingMode),
    (630, Group::CuttingMode),
    (640, Group::CuttingMode),
    (650, Group::NonModal),
    (660, Group::MacroCall),
    (661, Group::MacroCall),
    (670, Group::MacroCall),
    (680, Group::Rotation),
    (690, Group::Rotation),
    (730, Group::CannedCycle),
    (740, Group::CannedCycle),
    (760, Group::CannedCycle),
    (800, Group::CannedCycle),
    (810, Group::CannedCycle),
    (820, Group::CannedCycle),
    (830, Group::CannedCycle),
    (840, Group::CannedCycle),
    (850, Group::CannedCycle),
    (860, Group::CannedCycle),
    (870, Group::CannedCycle),
    (880, Group::CannedCycle),
    (890, Group::CannedCycle),
    (900, Group::Distance),
    (910, Group::Distance),
    (920, Group::NonModal),
    (921, Group::NonModal),
    (930, Group::FeedMode),
    (940, Group::FeedMode),
    (950, Group::FeedMode),
    (960, Group::SurfaceSpeed),
    (970, Group::SurfaceSpeed),
    (980, Group::ReturnLevel),
    (990, Group::ReturnLevel),
];

/// The modal group of G code `code`, or None when the code does not exist (alarm 0010).
#[inline]
pub fn group(code: GCode) -> Option<Group> {
    match GROUP_OF.get(code as usize) {
        Some(&Some(g)) => Some(g),
        _ => None,
    }
}

/// `TABLE` as a direct index (codes below G100), built at compile time: no search per word.
static GROUP_OF: [Option<Group>; 1000] = {
    let mut t = [None; 1000];
    let mut i = 0;
    while i < TABLE.len() {
        t[TABLE[i].0 as usize] = Some(TABLE[i].1);
        i += 1;
    }
    t
};

/// The G codes in effect at power-on (Fanuc M-series defaults, parameter-independent choice).
const POWER_ON: &[(Group, GCode)] = &[
    (Group::Motion, 0),
    (Group::Plane, 170),
    (Group::Distance, 900),
    (Group::StrokeCheck, 220),
    (Group::FeedMode, 940),
    (Group::Units, 210),
    (Group::CutterComp, 400),
    (Group::LengthComp, 490),
    (Group::CannedCycle, 800),
    (Group::ReturnLevel, 980),
    (Group::Scaling, 500),
    (Group::MacroCall, 670),
    (Group::SurfaceSpeed, 970),
    (Group::WorkOffset, 540),
    (Group::CuttingMode, 640),
    (Group::Rotation, 690),
    (Group::Polar, 150),
    (Group::NormalDirection, 401),
    (Group::SpindleFluctuation, 250),
    (Group::Mirror, 501),
];

/// The active G code of every group.
#[derive(Clone, Debug)]
pub struct ModalState {
    /// Active code per group (index = group number); 0 for groups without one.
    pub groups: [GCode; GROUPS],
}

impl Default for ModalState {
    fn default() -> Self {
        let mut groups = [0; GROUPS];
        for &(g, c) in POWER_ON {
            groups[g as usize] = c;
        }
        ModalState { groups }
    }
}

impl ModalState {
    /// Makes `code` active in its group (non-modal codes change nothing).
    pub fn set(&mut self, code: GCode) {
        if let Some(g) = group(code)
            && g != Group::NonModal
        {
            self.groups[g as usize] = code;
        }
    }

    /// The active code of `group`.
    pub fn get(&self, group: Group) -> GCode {
        self.groups[group as usize]
    }

    /// The active code of Fanuc group number `n` (#40nn); 0 for a number without a group.
    pub fn get_number(&self, n: u8) -> GCode {
        Group::from_number(n).map_or(0, |g| self.get(g))
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
            let code = fmsvm_block::code10(value)
                .filter(|&c| fmsvm_block::is_exact_code(value, c))
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
                ) if ![400, 490, 690, 500, 501, 670].contains(&code) => {
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
        self.get(Group::Units) == 200
    }

    /// Incremental positioning (G91) is active.
    pub fn incremental(&self) -> bool {
        self.get(Group::Distance) == 910
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
        assert_eq!(group(10), Some(Group::Motion));
        assert_eq!(group(541), Some(Group::WorkOffset));
        assert_eq!(group(15), None);
        assert_eq!(Group::from_number(14), Some(Group::WorkOffset));
        assert_eq!(Group::from_number(20), None);
        assert_eq!(Group::from_number(0), None);
    }

    #[test]
    fn power_on_state() {
        let m = ModalState::default();
        assert_eq!(m.get(Group::Motion), 0);
        assert_eq!(m.get(Group::Distance), 900);
        assert_eq!(m.get_number(17), 150);
        assert_eq!(m.get_number(21), 0);
        assert!(!m.inch());
    }
}
