//! The table of the G codes' modal groups (Fanuc M series; codes are `fmsvm_block::Code`, ×10), the
//! lathe's G-code systems as a reading of their codes into those meanings, and the modal state a
//! block updates; #4001–#4030 read from it (macro-b-rules S3, S8).

use fmsvm_block::alarms::IMPROPER_G;

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

    /// What the group's codes do, as Fanuc's G code table names it.
    pub fn title(self) -> &'static str {
        match self {
            Group::NonModal => "one-block codes",
            Group::Motion => "motion",
            Group::Plane => "plane selection",
            Group::Distance => "absolute or incremental",
            Group::StrokeCheck => "stroke check",
            Group::FeedMode => "feed mode",
            Group::Units => "inch or metric input",
            Group::CutterComp => "cutter compensation",
            Group::LengthComp => "tool length offset",
            Group::CannedCycle => "canned cycles",
            Group::ReturnLevel => "canned cycle return level",
            Group::Scaling => "scaling",
            Group::MacroCall => "macro modal call",
            Group::SurfaceSpeed => "constant surface speed",
            Group::WorkOffset => "work coordinate system",
            Group::CuttingMode => "exact stop and cutting mode",
            Group::Rotation => "coordinate system rotation",
            Group::Polar => "polar coordinates",
            Group::NormalDirection => "normal direction control",
            Group::SpindleFluctuation => "spindle speed fluctuation detection",
            Group::Mirror => "programmable mirror image",
        }
    }

    /// The mill's G codes of the group, in the table's order.
    pub fn codes(self) -> impl Iterator<Item = Code> {
        TABLE
            .iter()
            .filter(move |(_, g)| *g == self)
            .map(|(c, _)| *c)
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

/// The modal group of G code `code` (a mill code, or a lathe meaning of `Code`'s lathe range), or
/// None when the code does not exist (alarm 0010).
#[inline]
pub fn group(code: Code) -> Option<Group> {
    match GROUP_OF.get(code.tenths() as usize) {
        Some(&Some(g)) => Some(g),
        Some(None) => None,
        None => LATHE_MEANINGS.iter().find(|m| m.0 == code).map(|m| m.1),
    }
}

/// The lathe's own meanings in group `g` (the codes a mill does not have).
pub fn lathe_meanings_of(g: Group) -> impl Iterator<Item = Code> {
    LATHE_MEANINGS.iter().filter(move |m| m.1 == g).map(|m| m.0)
}

/// What a lathe's code means, in words, where the mill's group title does not say it (Fanuc 0i-TD
/// G-code list): the lathe's own meanings, and G50 (system A; G92 in B) of a lathe.
pub fn lathe_title(meaning: Code) -> Option<&'static str> {
    if meaning == Code::G92 {
        return Some("coordinate system setting, or with S the spindle speed clamp");
    }
    LATHE_MEANINGS.iter().find(|m| m.0 == meaning).map(|m| m.2)
}

/// The group of each lathe meaning that has no mill code (Fanuc T series: G32 and the cycles G90 G92
/// G94 are group 01, G70–G76 group 00, the drilling cycles group 10, G68/G69 of a double turret
/// group 04 — here the group of the same kind). G32 means the mill's G33.
const LATHE_MEANINGS: &[(Code, Group, &str)] = &[
    (
        Code::TURRET_MIRROR,
        Group::Rotation,
        "mirror image for double turrets on",
    ),
    (
        Code::TURRET_MIRROR_CANCEL,
        Group::Rotation,
        "mirror image for double turrets off",
    ),
    (Code::FINISHING_CYCLE, Group::NonModal, "finishing cycle"),
    (
        Code::TURNING_STOCK_REMOVAL,
        Group::NonModal,
        "stock removal in turning",
    ),
    (
        Code::FACING_STOCK_REMOVAL,
        Group::NonModal,
        "stock removal in facing",
    ),
    (
        Code::PATTERN_REPEATING,
        Group::NonModal,
        "pattern repeating",
    ),
    (
        Code::FACE_PECK_DRILLING,
        Group::NonModal,
        "end face peck drilling",
    ),
    (
        Code::GROOVING_CYCLE,
        Group::NonModal,
        "outer or inner diameter grooving",
    ),
    (
        Code::THREADING_MULTIPLE,
        Group::NonModal,
        "multiple threading cycle",
    ),
    (
        Code::FACE_DRILLING,
        Group::CannedCycle,
        "cycle for face drilling",
    ),
    (
        Code::FACE_TAPPING,
        Group::CannedCycle,
        "cycle for face tapping",
    ),
    (
        Code::FACE_BORING,
        Group::CannedCycle,
        "cycle for face boring",
    ),
    (
        Code::SIDE_DRILLING,
        Group::CannedCycle,
        "cycle for side drilling",
    ),
    (
        Code::SIDE_TAPPING,
        Group::CannedCycle,
        "cycle for side tapping",
    ),
    (
        Code::SIDE_BORING,
        Group::CannedCycle,
        "cycle for side boring",
    ),
    (
        Code::TURNING_CYCLE,
        Group::Motion,
        "outer or inner diameter cutting cycle",
    ),
    (Code::THREADING_CYCLE, Group::Motion, "threading cycle"),
    (Code::FACING_CYCLE, Group::Motion, "end face turning cycle"),
];

/// How a control numbers its G codes: the mill's (Fanuc M series), or a lathe's G-code system
/// (Fanuc T series, parameter 3401#6 GSB and #7 GSC). A lathe's codes are read into the kernel's
/// meanings (the mill code of the same function, or a lathe meaning of `Code`), and written back
/// from them for #40nn and messages.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub enum CodeSystem {
    /// The machining centre's codes.
    #[default]
    Mill,
    /// Lathe G-code system A (Fanuc's default for lathes): G90/G92/G94 are the single cycles, G50
    /// sets the coordinate system and clamps the spindle, G98/G99 are feed per minute/revolution,
    /// no G90/G91 (U and W are the incremental X and Z).
    LatheA,
    /// Lathe G-code system B: G90/G91 absolute/incremental, G92 coordinate setting, G94/G95 feed
    /// per minute/revolution, G98/G99 the drilling cycles' return level, G77/G78/G79 the single
    /// cycles.
    LatheB,
}

/// A lathe code and its meaning, where they differ or exist only on the lathe; any other code of
/// the lathe's list means what it does on the mill (`LATHE_SAME`).
type Reading = (Code, Code);

/// System A's codes that mean something else than on the mill, or exist only on the lathe (Fanuc
/// 0i-TD G-code list; docs/lathe.md).
const LATHE_A: &[Reading] = &[
    (Code::G32, Code::G33),
    (Code::G50, Code::G92),
    (Code::G68, Code::TURRET_MIRROR),
    (Code::G69, Code::TURRET_MIRROR_CANCEL),
    (Code::G70, Code::FINISHING_CYCLE),
    (Code::G71, Code::TURNING_STOCK_REMOVAL),
    (Code::G72, Code::FACING_STOCK_REMOVAL),
    (Code::G73, Code::PATTERN_REPEATING),
    (Code::G74, Code::FACE_PECK_DRILLING),
    (Code::G75, Code::GROOVING_CYCLE),
    (Code::G76, Code::THREADING_MULTIPLE),
    (Code::G83, Code::FACE_DRILLING),
    (Code::G84, Code::FACE_TAPPING),
    (Code::G85, Code::FACE_BORING),
    (Code::G87, Code::SIDE_DRILLING),
    (Code::G88, Code::SIDE_TAPPING),
    (Code::G89, Code::SIDE_BORING),
    (Code::G90, Code::TURNING_CYCLE),
    (Code::G92, Code::THREADING_CYCLE),
    (Code::G94, Code::FACING_CYCLE),
    (Code::G98, Code::G94),
    (Code::G99, Code::G95),
];

/// System B's (the same list, with G77–G79 for the single cycles and the mill's G90–G99).
const LATHE_B: &[Reading] = &[
    (Code::G32, Code::G33),
    (Code::G70, Code::FINISHING_CYCLE),
    (Code::G71, Code::TURNING_STOCK_REMOVAL),
    (Code::G72, Code::FACING_STOCK_REMOVAL),
    (Code::G73, Code::PATTERN_REPEATING),
    (Code::G74, Code::FACE_PECK_DRILLING),
    (Code::G75, Code::GROOVING_CYCLE),
    (Code::G76, Code::THREADING_MULTIPLE),
    (Code::G77, Code::TURNING_CYCLE),
    (Code::G78, Code::THREADING_CYCLE),
    (Code::G79, Code::FACING_CYCLE),
    (Code::G83, Code::FACE_DRILLING),
    (Code::G84, Code::FACE_TAPPING),
    (Code::G85, Code::FACE_BORING),
    (Code::G87, Code::SIDE_DRILLING),
    (Code::G88, Code::SIDE_TAPPING),
    (Code::G89, Code::SIDE_BORING),
];

/// The lathe's codes that mean what the mill's do (the rest of the 0i-TD list): every other mill
/// code does not exist on the lathe (alarm 0010). System B adds G90 G91 G92 G94 G95 G98 G99.
const LATHE_SAME: &[Code] = &[
    Code::G0,
    Code::G1,
    Code::G2,
    Code::G3,
    Code::G4,
    Code::G7_1,
    Code::G9,
    Code::G10,
    Code::G11,
    Code::G18,
    Code::G20,
    Code::G21,
    Code::G22,
    Code::G23,
    Code::G25,
    Code::G26,
    Code::G27,
    Code::G28,
    Code::G29,
    Code::G30,
    Code::G31,
    Code::G40,
    Code::G41,
    Code::G42,
    Code::G52,
    Code::G53,
    Code::G54,
    Code::G55,
    Code::G56,
    Code::G57,
    Code::G58,
    Code::G59,
    Code::G65,
    Code::G66,
    Code::G67,
    Code::G80,
    Code::G96,
    Code::G97,
];

/// System B's codes beyond `LATHE_SAME` that mean what the mill's do.
const LATHE_B_SAME: &[Code] = &[
    Code::G90,
    Code::G91,
    Code::G92,
    Code::G94,
    Code::G95,
    Code::G98,
    Code::G99,
];

/// A lathe's group numbers (#40nn) for the kernel's groups (Fanuc 0i-TD G-code list: 01 motion,
/// 02 constant surface speed, 03 absolute/incremental (system B), 04 double-turret mirror,
/// 05 feed mode, 06 units, 07 nose radius compensation, 08 spindle speed fluctuation, 09 stroke
/// check, 10 drilling cycles, 11 return level (system B), 12 macro modal call, 14 work
/// coordinates, 16 plane).
const LATHE_GROUP_NUMBERS: &[(Group, u8)] = &[
    (Group::Motion, 1),
    (Group::SurfaceSpeed, 2),
    (Group::Distance, 3),
    (Group::Rotation, 4),
    (Group::FeedMode, 5),
    (Group::Units, 6),
    (Group::CutterComp, 7),
    (Group::SpindleFluctuation, 8),
    (Group::StrokeCheck, 9),
    (Group::CannedCycle, 10),
    (Group::ReturnLevel, 11),
    (Group::MacroCall, 12),
    (Group::WorkOffset, 14),
    (Group::Plane, 16),
];

impl CodeSystem {
    /// The system's codes that differ from the mill's.
    fn readings(self) -> &'static [Reading] {
        match self {
            CodeSystem::Mill => &[],
            CodeSystem::LatheA => LATHE_A,
            CodeSystem::LatheB => LATHE_B,
        }
    }

    /// True for a lathe's system.
    pub fn lathe(self) -> bool {
        self != CodeSystem::Mill
    }

    /// What written code `code` means (a code `group` knows), or None when the control has no
    /// such code.
    pub fn meaning(self, code: Code) -> Option<Code> {
        if self == CodeSystem::Mill {
            return group(code).map(|_| code);
        }
        if let Some(r) = self.readings().iter().find(|r| r.0 == code) {
            return Some(r.1);
        }
        let same = LATHE_SAME.contains(&code)
            || (self == CodeSystem::LatheB && LATHE_B_SAME.contains(&code));
        same.then_some(code)
    }

    /// The code the system writes meaning `meaning` as (the meaning itself where it is the same).
    pub fn written(self, meaning: Code) -> Code {
        self.readings()
            .iter()
            .find(|r| r.1 == meaning)
            .map_or(meaning, |r| r.0)
    }

    /// The number #40nn reads group `g` at.
    pub fn group_number(self, g: Group) -> Option<u8> {
        match self {
            CodeSystem::Mill => Some(g as u8),
            _ => LATHE_GROUP_NUMBERS.iter().find(|e| e.0 == g).map(|e| e.1),
        }
    }

    /// The group #40nn (`n`) reads.
    pub fn group_of_number(self, n: u8) -> Option<Group> {
        match self {
            CodeSystem::Mill => Group::from_number(n),
            _ => LATHE_GROUP_NUMBERS.iter().find(|e| e.1 == n).map(|e| e.0),
        }
    }

    /// The system's name in messages.
    pub fn name(self) -> &'static str {
        match self {
            CodeSystem::Mill => "a Fanuc M-series control",
            CodeSystem::LatheA => "a lathe (G-code system A)",
            CodeSystem::LatheB => "a lathe (G-code system B)",
        }
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

/// What a lathe's power-on state changes from the mill's (Fanuc T series: G18 the plane; G99 feed per
/// revolution, parameter 3402#4 FPM = 0; the rest as the mill).
const LATHE_POWER_ON: &[(Group, Code)] = &[(Group::Plane, Code::G18), (Group::FeedMode, Code::G95)];

/// The active G code of every group, as meanings (`CodeSystem::meaning`), and the code system the
/// program is written in.
#[derive(Clone, Debug)]
pub struct ModalState {
    /// Active code per group (index = group number); G0 (code 0) for groups without one.
    pub groups: [Code; GROUPS],
    /// How the program's codes are numbered.
    pub system: CodeSystem,
}

impl Default for ModalState {
    fn default() -> Self {
        ModalState::power_on(CodeSystem::Mill)
    }
}

impl ModalState {
    /// The power-on state of a control numbering its codes by `system`.
    pub fn power_on(system: CodeSystem) -> ModalState {
        let mut groups = [Code::G0; GROUPS];
        for &(g, c) in POWER_ON {
            groups[g as usize] = c;
        }
        if system.lathe() {
            for &(g, c) in LATHE_POWER_ON {
                groups[g as usize] = c;
            }
        }
        ModalState { groups, system }
    }

    /// The meaning of the G word of value `value` on this control, or alarm 0010.
    #[inline(always)]
    pub fn read(&self, value: f64) -> Result<Code, fmsvm_block::Alarm> {
        if self.system == CodeSystem::Mill {
            return crate::decode::gcode(value);
        }
        self.read_lathe(value)
    }

    /// `read` on a lathe: its code system's meaning.
    #[cold]
    #[inline(never)]
    fn read_lathe(&self, value: f64) -> Result<Code, fmsvm_block::Alarm> {
        Code::of(value)
            .filter(|c| c.is_exact(value))
            .and_then(|c| self.system.meaning(c))
            .ok_or_else(|| {
                // A turning centre's C-axis milling: codes the 0i-TD has as an option (its
                // "Polar coordinate interpolation" G112/G113; G12.1/G13.1 in system B and on
                // other controls), which fmsvm's lathes (X and Z) cannot resolve.
                let polar = [112.0, 113.0, 12.1, 13.1].contains(&value);
                let text = if polar {
                    format!(
                        "G{value}: polar coordinate interpolation (milling with the C axis on a turning centre) is not modelled: fmsvm's lathes move X and Z, and no lathe output dialect has a C axis"
                    )
                } else {
                    format!(
                        "improper G-code: G{value} does not exist on {}",
                        self.system.name()
                    )
                };
                fmsvm_block::Alarm::new(IMPROPER_G, text)
            })
    }

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

    /// The active code of Fanuc group number `n` (#40nn) as the program writes it; code 0 for a
    /// number without a group.
    pub fn get_number(&self, n: u8) -> Code {
        self.system
            .group_of_number(n)
            .map_or(Code::G0, |g| self.system.written(self.get(g)))
    }

    /// The power-on state with `codes` (`"G17 G90 G94 G21 G40 G49 G80 G98 G0"`) made active; every
    /// code must be a modal G code.
    pub fn parse(codes: &str) -> Result<ModalState, String> {
        ModalState::parse_in(CodeSystem::Mill, codes)
    }

    /// The power-on state of a control numbering its codes by `system`, with `codes` (in that
    /// numbering) made active; as `parse`.
    pub fn parse_in(system: CodeSystem, codes: &str) -> Result<ModalState, String> {
        let mut m = ModalState::power_on(system);
        for word in codes.split(|c: char| c.is_whitespace() || c == ',') {
            if word.is_empty() {
                continue;
            }
            let value = word
                .strip_prefix(['G', 'g'])
                .and_then(|v| v.parse::<f64>().ok())
                .ok_or_else(|| format!("`{word}` is not a G code"))?;
            let written = Code::of(value)
                .filter(|c| c.is_exact(value))
                .ok_or_else(|| format!("`{word}` is not a G code"))?;
            let code = system.meaning(written).unwrap_or(written);
            match system.meaning(written).and_then(group) {
                None => return Err(format!("{word} does not exist on {}", system.name())),
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
