//! G codes as integers ×10 (G54.1 = 541), the table of their modal groups (Fanuc M series), and the
//! modal state a block updates; #4001–#4022 read from it (macro-b-rules S3, S8).

/// A G code ×10 (`G1` = 10, `G54.1` = 541), so codes are never compared as floats.
pub type GCode = u16;

/// Number of modal groups tracked (#4001–#4022 → groups 1–22).
pub const GROUPS: usize = 23;

/// Modal group 0: non-modal codes (one block only).
pub const NON_MODAL: u8 = 0;

/// Every G code the Fanuc M-series (milling) knows, with its group. Group numbers follow the Fanuc
/// 0i/16i/30i tables: 01 motion, 02 plane, 03 absolute/incremental, 04 stroke check, 05 feed mode,
/// 06 units, 07 cutter compensation, 08 tool length offset, 09 canned cycles, 10 return level,
/// 11 scaling, 12 macro modal call, 13 constant surface speed, 14 work coordinate system, 15 exact
/// stop/cutting mode, 16 rotation, 17 polar coordinates, 18 normal direction, 19 spindle speed
/// fluctuation, 22 mirror image.
const TABLE: &[(GCode, u8)] = &[
    (0, 1),
    (10, 1),
    (20, 1),
    (30, 1),
    (40, NON_MODAL),
    (50, NON_MODAL),
    (51, NON_MODAL),
    (71, NON_MODAL),
    (90, NON_MODAL),
    (100, NON_MODAL),
    (110, NON_MODAL),
    (150, 17),
    (160, 17),
    (170, 2),
    (180, 2),
    (190, 2),
    (200, 6),
    (210, 6),
    (220, 4),
    (230, 4),
    (250, 19),
    (260, 19),
    (270, NON_MODAL),
    (280, NON_MODAL),
    (290, NON_MODAL),
    (300, NON_MODAL),
    (310, NON_MODAL),
    (330, 1),
    (370, NON_MODAL),
    (390, NON_MODAL),
    (400, 7),
    (401, 18),
    (410, 7),
    (411, 18),
    (420, 7),
    (421, 18),
    (430, 8),
    (440, 8),
    (450, NON_MODAL),
    (460, NON_MODAL),
    (470, NON_MODAL),
    (480, NON_MODAL),
    (490, 8),
    (500, 11),
    (501, 22),
    (510, 11),
    (511, 22),
    (520, NON_MODAL),
    (530, NON_MODAL),
    (540, 14),
    (541, 14),
    (550, 14),
    (560, 14),
    (570, 14),
    (580, 14),
    (590, 14),
    (600, NON_MODAL),
    (610, 15),
    (620, 15),
    (630, 15),
    (640, 15),
    (650, NON_MODAL),
    (660, 12),
    (661, 12),
    (670, 12),
    (680, 16),
    (690, 16),
    (730, 9),
    (740, 9),
    (760, 9),
    (800, 9),
    (810, 9),
    (820, 9),
    (830, 9),
    (840, 9),
    (850, 9),
    (860, 9),
    (870, 9),
    (880, 9),
    (890, 9),
    (900, 3),
    (910, 3),
    (920, NON_MODAL),
    (930, 5),
    (940, 5),
    (950, 5),
    (960, 13),
    (970, 13),
    (980, 10),
    (990, 10),
];

/// The modal group of G code `code`, or None when the code does not exist (alarm 0010).
#[inline]
pub fn group(code: GCode) -> Option<u8> {
    match GROUP_OF.get(code as usize) {
        Some(&g) if g != NO_GROUP => Some(g),
        _ => None,
    }
}

/// Marks a code that does not exist in `GROUP_OF`.
const NO_GROUP: u8 = u8::MAX;

/// `TABLE` as a direct index (codes below G100), built at compile time: no search per word.
static GROUP_OF: [u8; 1000] = {
    let mut t = [NO_GROUP; 1000];
    let mut i = 0;
    while i < TABLE.len() {
        t[TABLE[i].0 as usize] = TABLE[i].1;
        i += 1;
    }
    t
};

/// The G codes in effect at power-on (Fanuc M-series defaults, parameter-independent choice).
const POWER_ON: &[(u8, GCode)] = &[
    (1, 0),
    (2, 170),
    (3, 900),
    (4, 220),
    (5, 940),
    (6, 210),
    (7, 400),
    (8, 490),
    (9, 800),
    (10, 980),
    (11, 500),
    (12, 670),
    (13, 970),
    (14, 540),
    (15, 640),
    (16, 690),
    (17, 150),
    (18, 401),
    (19, 250),
    (22, 501),
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
            && g != NON_MODAL
        {
            self.groups[g as usize] = code;
        }
    }

    /// The active code of `group`.
    pub fn get(&self, group: u8) -> GCode {
        self.groups.get(group as usize).copied().unwrap_or(0)
    }

    /// Inch units (G20) are active.
    pub fn inch(&self) -> bool {
        self.get(6) == 200
    }

    /// Incremental positioning (G91) is active.
    pub fn incremental(&self) -> bool {
        self.get(3) == 910
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
        assert_eq!(group(10), Some(1));
        assert_eq!(group(541), Some(14));
        assert_eq!(group(15), None);
    }

    #[test]
    fn power_on_state() {
        let m = ModalState::default();
        assert_eq!(m.get(1), 0);
        assert_eq!(m.get(3), 900);
        assert!(!m.inch());
    }
}
