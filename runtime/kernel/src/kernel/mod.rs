//! The kernel: one NC block at a time, the control's interpretation of it — modal state, frames,
//! transforms, arcs, canned cycles, compensation — ending in the literal emitter (the decoded block) or
//! in canonical operations (resolved output, stats, plot).

use fmsvm_block::alarms::{FORMAT, IMPROPER_G, NO_FANUC_NUMBER};
use fmsvm_block::{Alarm, Block, Flow, Letter, Machine, Stop, Word, WordFlags};

use crate::contour::Corner;
use crate::frames::{Frames, WorkOffset};
use crate::transform::{Rotation, Transform};
use crate::{cycles, probe, sysvars, timing};
use fmsvm_canon::arcs::{self, CentreWords};
use fmsvm_canon::decode::{DecodeTable, Decoded, InputRules};
use fmsvm_canon::modal::{Code, Group, ModalState};
pub use fmsvm_canon::{AXES, UNKNOWN_POSITION};
use fmsvm_canon::{Canon, Origin, Plane, Pose, Warning, axis_index, unknown_axis};
use fmsvm_canon::{Context, Emitter};

mod cycle;
pub(crate) mod lathe;
mod path;
mod plain;
use path::{Held, Pending, Stage, emit_move};
use plain::PLAIN_LETTERS;

/// The frame resolved output is written in.
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub enum OutputFrame {
    /// G54 as it stands (with the external offset): what `ncmotion` and LinuxCNC's trace compare.
    #[default]
    G54,
    /// Machine coordinates.
    Machine,
}

/// The cutter compensation style.
pub use crate::comp::Style as CompStyle;

/// How the kernel resolves, beyond the program itself.
#[derive(Clone, Debug)]
pub struct Settings {
    /// How far an arc's end may lie off its circle before alarm 0020 (Fanuc parameter 3410).
    pub arc_tolerance: f64,
    /// Write arcs as chords within this tolerance.
    pub linearize: Option<f64>,
    /// The frame of resolved output.
    pub frame: OutputFrame,
    /// The cutter compensation rules.
    pub comp_style: CompStyle,
    /// The canned-cycle parameters.
    pub cycles: cycles::CycleParams,
    /// The modal state at power-on.
    pub power_on: ModalState,
    /// NCT's automatic geometry between arcs: a G2/G3 block with I J (the absolute centre) and R ends
    /// the arc before it where the two circles meet (Q chooses), with or without its own end point.
    pub arc_intersections: bool,
    /// The plain-move shortcut (`Kernel::plain_move`); off, every block takes the general path (the
    /// tests compare the two).
    pub plain_moves: bool,
    /// Where the tool stands when the program starts, in the work coordinates of the power-on work
    /// offset (`--start-point`); NaN on an axis nobody declared: it is unknown until the program
    /// positions it.
    pub start_point: Pose,
    /// An output move of an axis its block does not name (outside a rotation that couples it), and
    /// a compensation or length register nobody set, are errors rather than warnings
    /// (`--strict-axes`).
    pub strict_axes: bool,
    /// The program is a turning program (`--machine lathe`): the lathe's words (X a diameter, U
    /// and W the incremental X and Z), codes (`power_on.system`) and cycles.
    pub lathe: Option<Lathe>,
    /// The variables the control's parameters declare beyond those fmsvm models.
    pub variables: crate::ControlVariables,
    /// How I J K give an arc's centre (FMS-3000 parameter N3021).
    pub arc_centre: ArcCentre,
    /// A milling program's G33 thread is applied (the output can write it: FMS-3000 §2.7), not
    /// refused.
    pub mill_threads: bool,
    /// The offsets the output leaves to the control's own registers (the profile's `[motion]
    /// work_offsets` and `tool_length`).
    pub control_offsets: ControlOffsets,
    /// The positions are the tool tip's: the tool length offset in force is taken off (`plot`).
    pub tool_tip: bool,
    /// G51's least increment of magnification, for P I J K written without a point (Fanuc 0.001
    /// or 0.00001 by parameter 5400#7 SCR); 0: the word is the factor itself (the NCT textbook).
    pub scaling_unit: f64,
    /// The Haas's own codes and forms are read (the Haas macro dialect: `--control haas`,
    /// `haas-lathe`, `--macro-dialect haas`): G103 P (not written), G154 P (as G54.1 P), a G28
    /// without axes (every axis home), and on a lathe the one-block G71–G73 and G76 (with A the
    /// tool angle) and the refusal of the one-block G74/G75 (kernel/lathe.rs).
    pub haas_codes: bool,
    /// Literal output is for a Haas (the `haaslathe` dialect): the Haas's own forms (one-block
    /// G71–G73 and G76, G154 P) are written as the program wrote them, not refused.
    pub haas_output: bool,
    /// The run's output budget, whose clock bounds a cycle's work before its first line.
    pub budget: fmsvm_block::OutputBudget,
}

/// Which offsets the flat program leaves to the control's own registers rather than applying them
/// itself (docs/kernel.md, "The control's own offsets").
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub struct ControlOffsets {
    /// G54–G59 are written (`G55`), the positions in the selected system.
    pub work: bool,
    /// G43/G44 H and G49 are written, the positions the tool tip's.
    pub length: bool,
}

/// How an arc block's I J K give its centre: FMS-3000 parameter N3021 (§2.4.1–§2.4.3).
#[derive(Clone, Copy, PartialEq, Eq, Debug, Default)]
pub enum ArcCentre {
    /// From the start point, whatever G90/G91 (Fanuc; N3021 = 0).
    #[default]
    Incremental,
    /// The centre itself in the work coordinates, whatever G90/G91 (N3021 = 1).
    Absolute,
    /// As the distance mode: the centre itself under G90, from the start point under G91
    /// (N3021 = 2).
    Modal,
}

/// How a lathe reads its X words (docs/lathe.md).
#[derive(Clone, Copy, PartialEq, Debug)]
pub struct Lathe {
    /// X (and U) are diameters (Fanuc parameter 1006#3 DIAx = 1, the lathe's habit), else radii.
    pub diameter: bool,
    /// The machine's highest spindle speed (Fanuc parameter 3772), the clamp of constant surface
    /// speed where the program gives no G50 S; None: G96 needs a G50 S first.
    pub max_rpm: Option<f64>,
    /// A turning centre with a Y axis (`[machine] y_axis`: a Haas ST-…Y, a 0i-TF with the Y-axis
    /// option): Y is a linear position (V its increment, as U and W are X's and Z's), written by
    /// the dialects whose lathes have one. Without it a lathe is X and Z, Y0 the spindle's plane.
    pub y_axis: bool,
}

impl Lathe {
    /// The kernel's X (a radius) per unit of an X or U word: ½ on a diameter lathe.
    pub fn radius_per_x_word(self) -> f64 {
        if self.diameter { 0.5 } else { 1.0 }
    }
}

impl Settings {
    /// The settings of a lathe numbering its codes by `system` (`CodeSystem::LatheA` or `LatheB`).
    pub fn lathe(system: fmsvm_canon::modal::CodeSystem, diameter: bool) -> Settings {
        Settings {
            power_on: ModalState::power_on(system),
            lathe: Some(Lathe {
                diameter,
                max_rpm: None,
                y_axis: false,
            }),
            ..Settings::default()
        }
    }
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            arc_tolerance: 0.005,
            linearize: None,
            frame: OutputFrame::G54,
            comp_style: CompStyle::Fanuc,
            cycles: cycles::CycleParams::default(),
            power_on: ModalState::default(),
            arc_intersections: false,
            plain_moves: true,
            start_point: [f64::NAN; 6],
            strict_axes: false,
            lathe: None,
            variables: crate::ControlVariables::default(),
            arc_centre: ArcCentre::Incremental,
            mill_threads: false,
            control_offsets: ControlOffsets::default(),
            tool_tip: false,
            scaling_unit: 0.001,
            haas_codes: false,
            haas_output: false,
            budget: fmsvm_block::OutputBudget::default(),
        }
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn unresolved_table_is_sorted_and_known() {
        assert!(super::UNRESOLVED.windows(2).all(|w| w[0].0 < w[1].0));
        assert!(
            super::UNRESOLVED
                .iter()
                .all(|(c, _)| fmsvm_canon::modal::group(*c).is_some())
        );
    }
}

/// Haas's G154 P1–P99, its additional work offsets (the Haas operator's manuals, "G154 Select
/// Work Coordinates P1-P99"): Fanuc's G54.1 P by meaning, the same registers for P1–P48 (the
/// kernel keeps 48). Literal output would hand a Fanuc a code it does not have: refused there,
/// unless it is for a Haas (`haas_output`).
fn haas_work_offsets<E: Emitter>(haas_output: bool) -> Result<Code, Alarm> {
    if E::CANON || haas_output {
        Ok(Code::G54_1)
    } else {
        Err(Alarm::new(
            IMPROPER_G,
            "G154 (Haas: additional work offsets) has no Fanuc literal form (Fanuc's is G54.1 P): run with --resolve".to_string(),
        ))
    }
}

/// Haas NGC's G103 P0–P15 (the operator's manual, "G103 Limit Block Buffering"): how many blocks
/// the control reads ahead, for macro reads of positions and inputs; P0 (or no P) no limit. It
/// moves nothing and is no code of the output's controls: the block is consumed (true) when it
/// is G103 with P and a sequence number only, refused when it carries anything else.
fn look_ahead_limit(block: &Block<'_>) -> Result<bool, Alarm> {
    let words = block.words();
    if !words
        .iter()
        .any(|w| w.letter == Letter::G && w.value == 103.0)
    {
        return Ok(false);
    }
    for w in words {
        let ok = match w.letter {
            Letter::G => w.value == 103.0,
            Letter::P => w.value.fract() == 0.0 && (0.0..=15.0).contains(&w.value),
            Letter::N => true,
            _ => false,
        };
        if !ok {
            return Err(Alarm::new(
                FORMAT,
                format!(
                    "G103 (Haas: limit block look-ahead) takes P0–P15 in a block of its own, not {}{}",
                    w.letter, w.value
                ),
            ));
        }
    }
    Ok(true)
}

/// What resolved output does with a G code that is neither applied by the kernel nor written.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Unresolved {
    /// It changes nothing a flat program of straight moves and arcs can show (path control,
    /// stroke check, spindle fluctuation detection): left out.
    Dropped,
    /// fmsvm cannot write it as flat motion: resolving stops with this reason.
    Refused(&'static str),
}

/// The G codes resolved output leaves out or refuses; every other code is applied (docs/kernel.md has
/// the whole table).
const UNRESOLVED: &[(Code, Unresolved)] = &[
    (
        Code::G5,
        Unresolved::Refused("G5 high-speed cycle machining"),
    ),
    (Code::G5_1, Unresolved::Dropped),
    (
        Code::G7_1,
        Unresolved::Refused("G7.1 cylindrical interpolation"),
    ),
    (Code::G9, Unresolved::Dropped),
    (
        Code::G11,
        Unresolved::Refused("G11 data setting mode cancel without G10 L"),
    ),
    (Code::G22, Unresolved::Dropped),
    (Code::G23, Unresolved::Dropped),
    (Code::G25, Unresolved::Dropped),
    (Code::G26, Unresolved::Dropped),
    (
        Code::G27,
        Unresolved::Refused("G27 reference position check"),
    ),
    (
        Code::G29,
        Unresolved::Refused("G29 return from the reference position"),
    ),
    (
        Code::G33,
        Unresolved::Refused("G33 thread cutting (spindle-synchronised feed)"),
    ),
    (
        Code::G37,
        Unresolved::Refused("G37 automatic tool length measurement"),
    ),
    (
        Code::G39,
        Unresolved::Refused("G39 corner offset circular interpolation"),
    ),
    (Code::G40_1, Unresolved::Dropped),
    (
        Code::G41_1,
        Unresolved::Refused("G41.1 normal direction control"),
    ),
    (
        Code::G42_1,
        Unresolved::Refused("G42.1 normal direction control"),
    ),
    (Code::G45, Unresolved::Refused("G45 tool offset increase")),
    (Code::G46, Unresolved::Refused("G46 tool offset decrease")),
    (
        Code::G47,
        Unresolved::Refused("G47 tool offset double increase"),
    ),
    (
        Code::G48,
        Unresolved::Refused("G48 tool offset double decrease"),
    ),
    (
        Code::G60,
        Unresolved::Refused("G60 single-direction positioning"),
    ),
    (Code::G61, Unresolved::Dropped),
    (Code::G62, Unresolved::Dropped),
    (Code::G63, Unresolved::Dropped),
    (Code::G64, Unresolved::Dropped),
    (Code::G93, Unresolved::Refused("G93 inverse time feed")),
    (
        Code::G96,
        Unresolved::Refused(
            "G96 constant surface speed on a mill (it is a lathe's: --machine lathe)",
        ),
    ),
    (Code::G97, Unresolved::Dropped),
    (
        Code::TURRET_MIRROR,
        Unresolved::Refused("G68 mirror image for double turrets"),
    ),
    (Code::TURRET_MIRROR_CANCEL, Unresolved::Dropped),
];

/// How resolved output treats G code `code` (a meaning) on a control numbering its codes by
/// `system` (None: applied). A lathe applies its thread cutting and constant surface speed.
#[inline(always)]
fn unresolved(code: Code, system: fmsvm_canon::modal::CodeSystem) -> Option<Unresolved> {
    if system.lathe() {
        return lathe_unresolved(code);
    }
    mill_unresolved(code)
}

/// `unresolved` on a mill: the table.
#[inline(always)]
fn mill_unresolved(code: Code) -> Option<Unresolved> {
    UNRESOLVED
        .binary_search_by_key(&code, |e| e.0)
        .ok()
        .map(|i| UNRESOLVED[i].1)
}

/// `unresolved` on a lathe: it applies its threads and constant surface speed.
#[cold]
#[inline(never)]
fn lathe_unresolved(code: Code) -> Option<Unresolved> {
    match code {
        Code::G33 | Code::G96 => None,
        _ => mill_unresolved(code),
    }
}

/// The words of one block by letter (the last of each wins), its M codes and its G codes by kind.
struct Words {
    value: [f64; Letter::COUNT],
    m: [f64; 4],
    m_count: usize,
    /// The one-block G code (group 00), if any.
    non_modal: Option<Code>,
    /// Which modal groups the block names.
    named: u32,
    /// The second auxiliary function's code (`InputRules::second_aux`), if the block has one.
    aux: Option<f64>,
    /// The axes (bit 0 X … bit 5 C) whose word is an increment whatever G90/G91 say: a lathe's U
    /// and W, read into X and Z.
    inc: u8,
    /// Which of P I J K were written without a decimal point (bits 0–3): G51's magnification is
    /// then in its least increment (`Settings::scaling_unit`).
    no_point: u8,
}

impl Words {
    /// A block with no words yet.
    #[inline(always)]
    fn empty() -> Words {
        Words {
            value: [f64::NAN; Letter::COUNT],
            m: [0.0; 4],
            m_count: 0,
            non_modal: None,
            named: 0,
            aux: None,
            inc: 0,
            no_point: 0,
        }
    }

    #[inline(always)]
    fn get(&self, l: Letter) -> Option<f64> {
        let v = self.value[l.index()];
        (!v.is_nan()).then_some(v)
    }

    #[inline(always)]
    fn has(&self, l: Letter) -> bool {
        !self.value[l.index()].is_nan()
    }

    fn names(&self, g: Group) -> bool {
        self.named & (1 << g as u32) != 0
    }

    fn any_axis(&self) -> bool {
        AXES.iter().any(|&l| self.has(l))
    }

    /// Whether axis `i`'s word is an increment (`modal_incremental`: G91 in force).
    fn incremental(&self, i: usize, modal_incremental: bool) -> bool {
        modal_incremental || self.inc & (1 << i) != 0
    }

    /// The block's axis words for a message (`X10. Y5.`).
    fn named_axes_text(&self) -> String {
        let mut t = String::new();
        for &l in &AXES {
            if let Some(v) = self.get(l) {
                if !t.is_empty() {
                    t.push(' ');
                }
                t.push_str(&format!("{l}{v}"));
            }
        }
        if t.is_empty() {
            t.push_str("the block");
        }
        t
    }
}

/// The kernel: modal state, frames and positions in front of an emitter.
pub struct Kernel<E: Emitter> {
    emitter: E,
    /// The program's number rules, worked out per letter.
    rules: DecodeTable,
    /// The decoded values of the block in hand (reused).
    decoded: [f64; fmsvm_block::MAX_WORDS],
    pub(crate) settings: Settings,
    /// The letters that send a block off the plain-move path (`PLAIN_LETTERS`' complement, and the
    /// second auxiliary function's address).
    not_plain: u32,
    pub(crate) modal: ModalState,
    /// Programmed end point of the last block, in the current work coordinates (#5001–#5006).
    pub(crate) position: Pose,
    /// Last value of each address (#4102–#4130 read from it).
    pub(crate) last: [f64; Letter::COUNT],
    pub(crate) frames: Frames,
    transform: Transform,
    cycle: cycles::CycleModal,
    comp: crate::comp::Compensator,
    /// Output position of the last canonical move (output frame), for arcs and compensation.
    out_position: Pose,
    /// The programmed (uncompensated) output point of the last move given to compensation.
    comp_from: Pose,
    /// G16: the last polar radius and angle (degrees), the plane's first and second axis words.
    polar: [f64; 2],
    /// What each repeat of the block's canned cycle adds to the plane's two words (NCT's incremental
    /// operator with L: `G81 XI10 … L9`); zero when it adds nothing.
    hole_step: [f64; 2],
    /// G41/G42 with I J (NCT): the start-up move comes along this direction, not from the tool.
    comp_start_along: Option<[f64; 2]>,
    /// The end of the programmed path as it reached the contour stage (output frame).
    path_from: Pose,
    /// A move the contour stage holds until the next one: for its corner word, or for an arc
    /// intersection the next block may decide.
    pending: Option<Pending>,
    /// What the block in hand adds to its move for the contour stage.
    stage: Stage,
    /// The steps of the canned-cycle block in hand (reused).
    steps: Vec<cycles::Step>,
    /// A lathe's single cycle in force (G90/G92/G94): its modal end point and taper.
    single_cycle: Option<lathe::SingleCycle>,
    /// The move a lathe's chamfering or corner R block requires of the next block.
    corner_next: Option<lathe::CornerNext>,
    /// A multiple repetitive cycle reading its profile from the blocks that follow.
    capture: Option<Box<lathe::Capture>>,
    /// Profiles read (for a later G70 P Q).
    profiles: Vec<crate::turning::ProfileBlocks>,
    /// The first blocks' words of G71 G72 G73.
    cycle_words: lathe::CycleWords,
    /// A lathe's spindle speed as programmed (S outside G50), for G96/G97 alone.
    spindle_s: Option<f64>,
    /// A lathe's spindle clamp was given (G50 S, or the machine's `max_rpm` written).
    spindle_clamped: bool,
    /// A feed rate went out (a lathe's feed move without one is alarm 0011).
    feed_known: bool,
    /// The origin of the output frame when the tool's output position was last worked out.
    frame_origin: Pose,
    /// Non-motion operations that came while compensation held a move back: they go out after it.
    held: Vec<(Held, Origin)>,
    /// The spindle was last started counter-clockwise (M4): cycles that stop it restart it so.
    spindle_ccw: bool,
    pub(crate) program_number: Option<u32>,
    /// Estimated machining time, and the clock the program reads.
    pub(crate) timing: timing::Timing,
    /// #3003, #3004 as last written (S7).
    pub(crate) flags_3003_3004: [f64; 2],
    /// The values of the variables the parameters declare (`Settings::variables`).
    pub(crate) declared: std::collections::BTreeMap<u32, f64>,
    /// `#3006` messages shown so far: (number, text).
    messages: Vec<(u32, String)>,
    /// What stops a G31 skip move.
    probe: probe::ProbeModel,
    /// Skip position of the last G31 (#5061–#5066).
    pub(crate) skip: Pose,
    /// Things the user should know that are not errors (G31 without a model…).
    warnings: Vec<Warning>,
    /// The warning that a rotation moves axes a block does not name was given for the rotation in
    /// force (reset when the transforms change).
    coupling_warned: bool,
    /// The output axes the block in hand moves without naming them, each with its warning: free
    /// for `--verify` (`Origin::fixed`).
    warned_axes: u8,
}

impl<E: Emitter> Kernel<E> {
    /// A kernel at power-on state writing to `emitter`, reading numbers by `rules`.
    pub fn new(emitter: E, rules: InputRules) -> Self {
        Self::with_settings(emitter, rules, Settings::default())
    }

    /// A kernel with explicit settings.
    pub fn with_settings(emitter: E, rules: InputRules, settings: Settings) -> Self {
        let comp = crate::comp::Compensator::new(settings.comp_style);
        let declared = settings.variables.values.clone();
        Kernel {
            emitter,
            rules: rules.table(),
            decoded: [0.0; fmsvm_block::MAX_WORDS],
            modal: settings.power_on.clone(),
            not_plain: !PLAIN_LETTERS | rules.second_aux.map_or(0, |l| 1 << l as u32),
            position: {
                // A lathe without a Y axis: its tool is on the spindle's centre plane, Y0, from
                // the start (never written: no block moves it). A turning centre's Y is where the
                // start point says (unknown unless it says).
                let mut p = settings.start_point;
                if settings.lathe.is_some_and(|l| !l.y_axis) {
                    p[1] = 0.0;
                }
                p
            },
            settings,
            last: [fmsvm_block::VACANT; Letter::COUNT],
            frames: Frames::default(),
            transform: Transform::default(),
            cycle: cycles::CycleModal::default(),
            comp,
            out_position: [0.0; 6],
            comp_from: [0.0; 6],
            held: Vec::new(),
            frame_origin: [0.0; 6],
            steps: Vec::new(),
            single_cycle: None,
            corner_next: None,
            capture: None,
            profiles: Vec::new(),
            cycle_words: lathe::CycleWords::default(),
            spindle_s: None,
            spindle_clamped: false,
            feed_known: false,
            path_from: [0.0; 6],
            comp_start_along: None,
            pending: None,
            stage: Stage::default(),
            polar: [f64::NAN; 2],
            hole_step: [0.0; 2],
            spindle_ccw: false,
            program_number: None,
            timing: timing::Timing::default(),
            flags_3003_3004: [0.0; 2],
            declared,
            messages: Vec::new(),
            probe: probe::ProbeModel::None,
            skip: [0.0; 6],
            warnings: Vec::new(),
            coupling_warned: false,
            warned_axes: 0,
        }
    }

    /// The frames and registers (work offsets, tools), to load from `--offsets` before the run.
    pub fn frames_mut(&mut self) -> &mut Frames {
        &mut self.frames
    }

    /// The frames and registers.
    pub fn frames(&self) -> &Frames {
        &self.frames
    }

    /// Sets the probe model for G31.
    pub fn set_probe(&mut self, model: probe::ProbeModel) {
        self.probe = model;
    }

    /// Warnings of the run so far.
    pub fn warnings(&self) -> &[Warning] {
        &self.warnings
    }

    /// Says `text` about the block at `at`, once for that block.
    fn warn(&mut self, at: Origin, text: String) {
        let said = |w: &Warning| w.at.line == at.line && w.at.file == at.file && w.text == text;
        if !self.warnings.iter().any(said) {
            self.warnings.push(Warning::at(at, text));
        }
    }

    /// Whether a warning saying `what` was given.
    fn warned(&self, what: &str) -> bool {
        self.warnings.iter().any(|w| w.text.contains(what))
    }

    /// Sets the date and time #3011/#3012 read (YYYYMMDD, HHMMSS): fixed for the run, so output is
    /// reproducible.
    pub fn set_clock(&mut self, date: u32, time: u32) {
        self.timing.date = date;
        self.timing.time = time;
    }

    /// Sets the rapid traverse rate (mm/min) used to estimate machining time.
    pub fn set_rapid_rate(&mut self, mm_per_min: f64) {
        self.timing.rapid = mm_per_min;
    }

    /// Times motion for #3001/#3002 and `machining_seconds` (on by default; off saves time per block
    /// when nothing reads them).
    pub fn set_timing(&mut self, on: bool) {
        self.timing.enabled = on;
    }

    /// Estimated machining time so far, seconds (feed moves at F, rapids at the rapid rate, dwells).
    pub fn machining_seconds(&self) -> f64 {
        self.timing.total_seconds
    }

    /// The `#3006` messages of the run.
    pub fn messages(&self) -> &[(u32, String)] {
        &self.messages
    }

    /// #3003 and #3004 as the program left them (non-zero at the end deserves a warning, S7).
    pub fn flags_3003_3004(&self) -> [f64; 2] {
        self.flags_3003_3004
    }

    /// Starts the output of program `number`.
    pub fn begin(&mut self, number: Option<u32>, title: &str) -> Result<(), Stop> {
        self.program_number = number;
        self.emitter.begin(number, title)?;
        if E::CANON {
            self.frame_origin = self.output_origin();
            self.out_position = self.out_point(&self.position);
            self.path_from = self.out_position;
            self.emitter
                .canon(&Canon::Start(self.out_position), Origin::default())?;
            if self.settings.control_offsets.work {
                // The system the program starts in is said, not left to the control's power-on
                // choice (FMS-3000 parameter N3008, §2.15.1).
                if let crate::frames::WorkOffset::Standard(n) = self.frames.active {
                    self.emitter
                        .canon(&Canon::WorkSystem(n), Origin::default())?;
                }
            } else if self.settings.frame == OutputFrame::Machine {
                self.guessed_work_offset(Origin::default())?;
            }
            self.emitter
                .canon(&Canon::Units(self.modal.inch()), Origin::default())?;
            if self.settings.lathe.is_some() {
                // A lathe starts in feed per revolution (G99): the output must say which.
                self.emitter.canon(
                    &Canon::FeedPerRev(self.modal.get(Group::FeedMode) == Code::G95),
                    Origin::default(),
                )?;
            }
        }
        Ok(())
    }

    /// Ends the output: compensation still holding moves lets them go, the emitter flushes.
    pub fn end(&mut self) -> Result<(), Stop> {
        if let Some(cap) = &self.capture {
            return Err(Alarm::new(
                FORMAT,
                format!(
                    "the program ends inside the profile N{}–N{} of the cycle at line {}: N{} never came",
                    cap.profile.ns, cap.profile.nf, cap.origin.line, cap.profile.nf
                ),
            )
            .into());
        }
        if E::CANON {
            self.settle()?;
        }
        if E::CANON && self.comp.is_active() {
            let emitter = &mut self.emitter;
            let out = &mut self.out_position;
            let lin = self.settings.linearize;
            self.comp
                .flush(&mut |m| emit_move(emitter, out, lin, m, Origin::default()))?;
        }
        if E::CANON {
            self.release_held()?;
        }
        self.emitter.end()
    }

    /// A `/` block in resolved output keeps its slash, for the control's block-delete switch. Under
    /// cutter compensation (or by a corner word) its moves depend on the blocks around it and go
    /// out with the next block's: the control could not skip them alone. Refused.
    #[cold]
    fn block_delete_may_stay(&self, w: &Words) -> Result<(), Stop> {
        let compensated = self.comp.is_active()
            || matches!(self.modal.get(Group::CutterComp), Code::G41 | Code::G42);
        if compensated || self.pending.is_some() || w.has(Letter::CommaR) || w.has(Letter::CommaC) {
            return Err(Alarm::new(
                NO_FANUC_NUMBER,
                "a block-delete block (/) under cutter compensation or a corner: its moves depend on the blocks around it, so resolved output cannot leave it to the control's switch; expand with --block-delete (the switch on) or take the / off",
            )
            .into());
        }
        Ok(())
    }

    /// Sends the non-motion operations held behind compensation, once it holds no move.
    fn release_held(&mut self) -> Result<(), Stop> {
        if self.held.is_empty() {
            return Ok(());
        }
        for (h, origin) in std::mem::take(&mut self.held) {
            match &h {
                Held::Op(op) => self.emitter.canon(op, origin)?,
                Held::Comment(t) => self.emitter.canon(&Canon::Comment(t), origin)?,
            }
        }
        Ok(())
    }

    /// Lets the emitter finish what it has taken after a stop (`Emitter::settle`): the output error
    /// it met on the way, which then is the run's stop.
    pub fn settle_output(&mut self) -> Result<(), Stop> {
        self.emitter.settle()
    }

    /// The emitter back.
    pub fn into_emitter(self) -> E {
        self.emitter
    }

    /// The emitter.
    pub fn emitter(&self) -> &E {
        &self.emitter
    }

    /// The modal state.
    pub fn modal(&self) -> &ModalState {
        &self.modal
    }

    /// Programmed position (work coordinates) of X Y Z A B C.
    pub fn position(&self) -> Pose {
        self.position
    }

    /// The plane of arcs, cycles and compensation.
    fn plane(&self) -> Plane {
        Plane::from_code(self.modal.get(Group::Plane))
    }

    /// Where programmed point `p` (current work coordinates) is in machine coordinates.
    pub(crate) fn machine_point(&self, p: &Pose) -> Pose {
        let q = if self.transform.is_identity() {
            *p
        } else {
            self.transform.apply(p)
        };
        let o = self.frames.origin();
        let mut m: Pose = std::array::from_fn(|i| q[i] + o[i]);
        m[2] += self.frames.length;
        m
    }

    /// Where programmed point `p` is in the output frame.
    fn out_point(&self, p: &Pose) -> Pose {
        self.out_machine(&self.machine_point(p))
    }

    /// The programmed point (current work coordinates) of machine point `m`, without transforms.
    fn program_point(&self, m: &Pose) -> Pose {
        let o = self.frames.origin();
        let mut p: Pose = std::array::from_fn(|i| m[i] - o[i]);
        p[2] -= self.frames.length;
        p
    }

    /// The programmed point (current work coordinates) of machine point `m` through the transforms
    /// in force: the inverse of `machine_point`.
    fn program_point_seen(&self, m: &Pose) -> Pose {
        let p = self.program_point(m);
        if self.transform.is_identity() {
            p
        } else {
            self.transform.invert(&p)
        }
    }

    /// The origin of the output frame, machine coordinates.
    fn output_origin(&self) -> Pose {
        if self.settings.control_offsets.work {
            return self.frames.work_origin();
        }
        match self.settings.frame {
            OutputFrame::Machine => [0.0; 6],
            OutputFrame::G54 => self.frames.g54_origin(),
        }
    }

    /// When the output frame itself moved (G10 L2 P1, #5221…, the external offset), the tool is now
    /// elsewhere in it: say so to the emitter before the next move.
    fn follow_frame(&mut self, origin: Origin) -> Result<(), Stop> {
        let now = self.output_origin();
        if now == self.frame_origin {
            return Ok(());
        }
        let d: Pose = std::array::from_fn(|i| now[i] - self.frame_origin[i]);
        self.frame_origin = now;
        // The flat program's control keeps its own G54: the coordinates written from here on are
        // in the new one, and a move that spells an axis again moves it by the change.
        let text = if self.settings.control_offsets.work {
            format!(
                "the program changed the work offset in force ({}, or the external offset) by {}: the output leaves work offsets to the control, which a flat program cannot set, so set the control's the same way",
                self.frames.active_name(),
                fmsvm_canon::describe_pose(&d)
            )
        } else {
            format!(
                "the work offset the output is written in (G54 or the external offset) changed by {}: the output's coordinates from here are in the changed frame, so the control's G54 must change the same way (or use --frame machine)",
                fmsvm_canon::describe_pose(&d)
            )
        };
        if self.settings.strict_axes {
            return Err(Alarm::new(UNKNOWN_POSITION, format!("{text}; --strict-axes")).into());
        }
        self.warn(origin, text);
        for (i, d) in d.iter().enumerate() {
            self.out_position[i] -= d;
            self.comp_from[i] -= d;
            self.path_from[i] -= d;
        }
        self.emitter.canon(&Canon::Start(self.out_position), origin)
    }
}

/// Alarm 0115: the program sets a register the output leaves to the control, which a flat program
/// cannot set (as a lathe's X Z tool offsets).
pub(crate) fn control_register(what: &str, registers: &str) -> Alarm {
    Alarm::new(
        115,
        format!(
            "{what}: the output leaves {registers} to the control (the profile's [motion] work_offsets, tool_length = \"control\"), and a flat program cannot set the control's registers: set them on the control (and for fmsvm in --offsets), or let fmsvm apply them (\"resolved\")"
        ),
    )
}

/// Alarm 0224: a plane other than G17 while the control's own length offset is in force, which on
/// the FMS-3000 acts on the plane's third axis (§3.3: Y under G18, X under G19) where Fanuc keeps Z.
fn plane_under_control_length(plane: Plane) -> Alarm {
    Alarm::new(
        UNKNOWN_POSITION,
        format!(
            "G{} under G43/G44: the output leaves lengths to the control, which applies the length to the plane's third axis (FMS-3000 §3.3), not Z: cancel it with G49 first, or let fmsvm apply lengths (the profile's [motion] tool_length = \"resolved\")",
            plane.code()
        ),
    )
}

/// How an arc block gives its centre: R (without I J K), else I J K from the start `from`
/// (programmed), or, where they are the centre itself (`absolute`: FMS-3000 N3021 = 1, or 2 under
/// G90), their offset from it; there both centre words of the plane must be given.
fn centre_words(
    w: &Words,
    from: &Pose,
    plane: fmsvm_canon::Plane,
    absolute: bool,
) -> Result<CentreWords, Alarm> {
    if let Some(r) = w.get(Letter::R)
        && !(w.has(Letter::I) || w.has(Letter::J) || w.has(Letter::K))
    {
        return Ok(CentreWords::Radius(r));
    }
    let letters = [Letter::I, Letter::J, Letter::K];
    let mut o = [
        w.get(Letter::I).unwrap_or(0.0),
        w.get(Letter::J).unwrap_or(0.0),
        w.get(Letter::K).unwrap_or(0.0),
    ];
    if absolute {
        let (a, b, _) = plane.axes();
        for k in [a, b] {
            if !w.has(letters[k]) {
                return Err(Alarm::new(
                    ARC_CENTRE_WORD,
                    format!(
                        "the arc's centre words are its centre itself here (N3021 = 1, or 2 under G90): give {} and {}",
                        letters[a], letters[b]
                    ),
                ));
            }
            o[k] -= from[k];
        }
    }
    Ok(CentreWords::Offsets(o))
}

/// 0021: an arc's centre words do not fit its plane or mode.
const ARC_CENTRE_WORD: u32 = 21;

/// Whether two points are the same, an axis unknown in both (NaN) counting as the same.
fn same_pose(a: &Pose, b: &Pose) -> bool {
    a.iter()
        .zip(b)
        .all(|(x, y)| x == y || (x.is_nan() && y.is_nan()))
}

/// The plane point of polar radius `r` at `degrees` about the local zero.
fn polar_point(r: f64, degrees: f64) -> [f64; 2] {
    let (sin, cos) = degrees.to_radians().sin_cos();
    [r * cos, r * sin]
}

/// A lathe's single cycle (G90/G92/G94 in system A).
fn is_single_cycle(code: Code) -> bool {
    matches!(
        code,
        Code::TURNING_CYCLE | Code::THREADING_CYCLE | Code::FACING_CYCLE
    )
}

/// M codes that act before the block's motion (spindle and coolant on, tool change); the others act
/// after it (as LinuxCNC orders them).
fn before_motion(m: f64) -> bool {
    matches!(
        Code::of_integer(m),
        Some(Code::M3 | Code::M4 | Code::M6 | Code::M7 | Code::M8)
    )
}

impl<E: Emitter> Kernel<E> {
    /// Moves the program's zero by `delta` (machine coordinates) while the tool stays: the programmed
    /// position changes by −delta.
    pub(crate) fn shift_origin(&mut self, old: Pose) {
        let new = self.frames.origin();
        if self.transform.is_identity() {
            for i in 0..6 {
                self.position[i] -= new[i] - old[i];
            }
            return;
        }
        // Under a transform the tool's machine point is seen through it again (the tool stays).
        let q = self.transform.apply(&self.position);
        let mut m: Pose = std::array::from_fn(|i| q[i] + old[i]);
        m[2] += self.frames.length;
        self.position = self.program_point_seen(&m);
    }

    /// NCT's incremental operator (`XI10`): each such word becomes the absolute value it stands for,
    /// in place in the decoded block, so that the kernel and the literal output (Fanuc form) see
    /// plain words. From the block's start point for an axis; from the local shift in `G52 XI`; from
    /// the rotation in force in `G68 RI`; from the last polar radius or angle under G16. Under G91
    /// every word is incremental already. What a canned cycle's repeats add is kept in `hole_step`.
    fn absolutize(&mut self, block: &Block<'_>, w: &Words) -> Result<(), Alarm> {
        if self.modal.incremental() {
            return Ok(());
        }
        let polar = self.modal.get(Group::Polar) == Code::G16;
        let (pa, pb, pn) = self.plane().axes();
        for (i, word) in block.words().iter().enumerate() {
            if !word.flags.has(WordFlags::INCREMENTAL) {
                continue;
            }
            let v = self.decoded[i];
            let axis = axis_index(word.letter, self.rules.second_aux());
            self.decoded[i] = match axis {
                Some(a) if w.non_modal == Some(Code::G52) => self.frames.local[a] + v,
                Some(a) if polar && (a == pa || a == pb) => {
                    let k = usize::from(a == pb);
                    self.hole_step[k] = v;
                    if self.polar[k].is_nan() {
                        return Err(Alarm::new(
                            UNKNOWN_POSITION,
                            format!(
                                "`{}I` under G16: no polar radius or angle was given before it",
                                word.letter
                            ),
                        ));
                    }
                    self.polar[k] + v
                }
                Some(a) => {
                    if a == pa || a == pb {
                        self.hole_step[usize::from(a == pb)] = v;
                    }
                    if self.position[a].is_nan() {
                        return Err(unknown_axis(a, &format!("`{}I`", word.letter)));
                    }
                    self.position[a] + v
                }
                None if word.letter == Letter::R && w.names(Group::Rotation) => {
                    self.transform.rotation.map_or(0.0, |r| r.degrees) + v
                }
                // `RI` in a canned cycle: R from the block's start level.
                None if word.letter == Letter::R => {
                    if self.position[pn].is_nan() {
                        return Err(unknown_axis(pn, "`RI` (R from the start level)"));
                    }
                    self.position[pn] + v
                }
                None => {
                    return Err(Alarm::new(
                        FORMAT,
                        format!(
                            "`{}I{v}`: the incremental operator is for axes and R",
                            word.letter
                        ),
                    ));
                }
            };
        }
        Ok(())
    }

    /// The end point of a motion block: under G16 the plane's words are a radius and an angle
    /// (degrees from the first axis) about the local zero, an omitted one keeping its last value;
    /// otherwise `target`.
    fn end_point(&mut self, w: &Words) -> Result<Pose, Alarm> {
        let mut to = self.target(w);
        if self.modal.get(Group::Polar) == Code::G16 {
            let (pa, pb, _) = self.plane().axes();
            if w.has(AXES[pa]) || w.has(AXES[pb]) {
                if self.modal.incremental() {
                    return Err(Alarm::new(
                        NO_FANUC_NUMBER,
                        "polar coordinates (G16) under G91 are not supported: program them in G90",
                    ));
                }
                let r = w.get(AXES[pa]).unwrap_or(self.polar[0]);
                let a = w.get(AXES[pb]).unwrap_or(self.polar[1]);
                if E::CANON && (r.is_nan() || a.is_nan()) {
                    return Err(Alarm::new(
                        UNKNOWN_POSITION,
                        format!(
                            "G16: the polar {} is not known (no earlier G16 block gave it): give both {} and {} in the first polar move",
                            if r.is_nan() { "radius" } else { "angle" },
                            AXES[pa],
                            AXES[pb]
                        ),
                    ));
                }
                self.polar = [r, a];
                let [x, y] = polar_point(r, a);
                to[pa] = x;
                to[pb] = y;
            }
        }
        Ok(to)
    }

    /// The axis words of a block as an end point: absolute, or added to the position under G91.
    fn target(&self, w: &Words) -> Pose {
        let inc = self.modal.incremental();
        std::array::from_fn(|i| match w.get(AXES[i]) {
            Some(v) if w.incremental(i, inc) => self.position[i] + v,
            Some(v) => v,
            None => self.position[i],
        })
    }

    /// A length (H) or radius (D) register the block puts in force that nothing set (not the
    /// program, nor `--offsets`): a warning naming it and the line, an error under `--strict-axes`.
    fn register_set(&mut self, letter: char, n: Option<f64>, origin: Origin) -> Result<(), Stop> {
        let n = n.unwrap_or(0.0).round();
        let what = match letter {
            'H' => "tool length",
            'T' => "tool nose radius",
            _ => "cutter radius",
        };
        let unset = n == 0.0 || self.frames.tool(n).is_ok_and(|t| !t.set);
        if !unset || (n == 0.0 && letter == 'H') {
            return Ok(());
        }
        let text = if n == 0.0 && letter == 'T' {
            "tool nose radius compensation with no tool offset (T0101 selects offset 01): the nose radius is 0".to_string()
        } else if n == 0.0 {
            format!(
                "cutter compensation with no D: the {what} is 0 (give D and its register in --offsets)"
            )
        } else if letter == 'T' {
            format!(
                "tool offset {n:02}: the {what} register {n} was never set by the program or --offsets: it is 0"
            )
        } else {
            format!(
                "{letter}{n}: the {what} register {n} was never set by the program or --offsets: it is 0"
            )
        };
        if self.settings.strict_axes {
            return Err(Alarm::new(UNKNOWN_POSITION, format!("{text}; --strict-axes")).into());
        }
        self.warn(origin, text);
        Ok(())
    }

    /// G28 / G30 Pn: through the intermediate point (the block's words; under G91 a zero word is
    /// where the tool stands, known or not) to reference position `n` on the axes the block names.
    /// The axes are known afterwards only where the reference position is (`--offsets`); the output
    /// gets one `Canon::Reference`, for the dialect to write as its own return or refuse.
    fn reference_return(
        &mut self,
        n: u8,
        reference: &Pose,
        w: &Words,
        origin: Origin,
    ) -> Result<(), Stop> {
        let modal_inc = self.modal.incremental();
        let mut mid = self.position;
        let mut axes = 0u8;
        let mut through = false;
        for (i, &a) in AXES.iter().enumerate() {
            let Some(v) = w.get(a) else { continue };
            let inc = w.incremental(i, modal_inc);
            axes |= 1 << i;
            if inc && v == 0.0 {
                continue;
            }
            let p = if inc { self.position[i] + v } else { v };
            if E::CANON && p.is_nan() {
                return Err(unknown_axis(i, "G28/G30's intermediate point").into());
            }
            through |= p != self.position[i];
            mid[i] = p;
        }
        // A Haas G28 without axis words returns every axis (the Haas operator's manuals: "returns
        // all axes … simultaneously to the machine zero position when no axis is specified"): the
        // machine's linear axes, and a rotary one the program has positioned.
        if axes == 0 && self.settings.haas_codes && n == 1 {
            axes = match self.settings.lathe {
                Some(l) if !l.y_axis => 0b101,
                _ => 0b111,
            };
            for i in 3..6 {
                if !self.position[i].is_nan() {
                    axes |= 1 << i;
                }
            }
        }
        if E::CANON {
            self.ready_to_position("a return to a reference position")?;
            if through {
                // Axes it returns with a zero increment stay where the tool is, known or not.
                let mut to = self.out_point(&mid);
                for (i, (v, &at)) in to.iter_mut().zip(&self.path_from).enumerate() {
                    if v.is_nan() {
                        if w.has(AXES[i])
                            && !(w.incremental(i, modal_inc) && w.get(AXES[i]) == Some(0.0))
                        {
                            return Err(unknown_axis(i, "G28/G30's intermediate point").into());
                        }
                        *v = at;
                    }
                }
                self.canon(Canon::Rapid(to), origin)?;
                self.settle()?;
            }
        }
        self.position = mid;
        let mut m = self.machine_point(&self.position);
        for i in 0..6 {
            if axes & (1 << i) != 0 {
                m[i] = reference[i];
            }
        }
        // Straight to the reference point, untransformed.
        self.position = self.program_point_seen(&m);
        if E::CANON {
            let to = self.positioned(axes, &m, origin)?;
            self.emitter.canon(
                &Canon::Reference {
                    number: n,
                    axes,
                    to,
                },
                origin,
            )?;
            self.stands_at(to);
        }
        Ok(())
    }

    /// Before a one-block positioning the dialect writes as its own (`what`: G28/G30, G53): the
    /// contour stage lets its held move go; under cutter compensation it is refused.
    fn ready_to_position(&mut self, what: &str) -> Result<(), Stop> {
        self.settle()?;
        if self.comp.is_active() {
            return Err(Alarm::new(
                UNKNOWN_POSITION,
                format!("{what} under cutter compensation (G41/G42): cancel it with G40 first"),
            )
            .into());
        }
        Ok(())
    }

    /// Where a one-block positioning to machine point `m` on the axes of `axes` leaves the tool,
    /// in the output frame: the axes it does not name stay where the tool is.
    fn positioned(&mut self, axes: u8, m: &Pose, origin: Origin) -> Result<Pose, Stop> {
        self.follow_frame(origin)?;
        let mut to = self.out_machine(m);
        for (i, (v, &at)) in to.iter_mut().zip(&self.path_from).enumerate() {
            if axes & (1 << i) == 0 {
                *v = at;
            }
        }
        // Where the output leaves offsets to the control, a machine position is known in the
        // control's system only through offsets fmsvm knows.
        let control = self.settings.control_offsets;
        // In the control's system, the selected work offset; in fmsvm's G54 frame, G54's: a
        // machine position lies where it does in the output only through an offset someone set
        // (the program or --offsets: G54 = 0 is a declaration, never a default).
        let work_unknown = if control.work {
            !self.frames.work_set[self.frames.active_slot()]
        } else {
            self.settings.frame == OutputFrame::G54 && !self.frames.work_set[1]
        };
        let length_unknown = control.length
            && self.modal.get(Group::LengthComp) != Code::G49
            && self
                .last_value(Letter::H)
                .is_some_and(|h| self.frames.tool(h).is_ok_and(|t| !t.set));
        let moved = (0..6).filter(|i| axes & (1 << i) != 0);
        if work_unknown && !control.work && moved.clone().any(|i| !m[i].is_nan()) {
            let text = "G54's work offset was never set by the program or --offsets ([work.G54]; declare X = 0 … where the part's zero is machine zero): where this machine position lies in the output's G54 frame is not known, and the axes it moves are unknown after it".to_string();
            // docs/offsets.md: an offset a move is computed through must be known; a warning,
            // an error with --strict-axes.
            if self.settings.strict_axes {
                return Err(Alarm::new(UNKNOWN_POSITION, format!("{text}; --strict-axes")).into());
            }
            self.warn(origin, text);
        }
        for i in moved {
            if work_unknown || (i == 2 && length_unknown) {
                to[i] = f64::NAN;
                self.position[i] = f64::NAN;
            }
        }
        Ok(to)
    }

    /// The tool stands at `to` (output frame) after a move the kernel sent past the contour stage
    /// and compensation.
    fn stands_at(&mut self, to: Pose) {
        self.out_position = to;
        self.path_from = to;
        self.comp_from = to;
    }

    /// The output axes a block's moves must leave where they are (`Origin::fixed`): all but those
    /// it names and those something in force couples to them — a rotation (the plane's axes), cutter
    /// compensation, a corner word or a held move (the plane), an arc (its plane), polar
    /// coordinates (the plane), a canned cycle or a lathe's single cycle (X Y Z).
    fn fixed_axes(&self, w: &Words) -> u8 {
        let mut free = 0u8;
        for (i, &a) in AXES.iter().enumerate() {
            if w.has(a) {
                free |= 1 << i;
            }
        }
        let (a, b, _) = self.plane().axes();
        let plane = (1u8 << a) | (1 << b);
        let rotation = self.transform.rotation.is_some() || w.names(Group::Rotation);
        if (rotation && free & plane != 0)
            || self.comp.is_active()
            || w.names(Group::CutterComp)
            || w.has(Letter::CommaR)
            || w.has(Letter::CommaC)
            || self.pending.is_some()
            || matches!(self.modal.get(Group::Motion), Code::G2 | Code::G3)
            || self.modal.get(Group::Polar) == Code::G16
        {
            free |= plane;
        }
        // A canned cycle moves X Y Z; compensation lets its moves go one block late (a held move
        // goes out with the next block's origin).
        if self.modal.get(Group::CannedCycle) != Code::G80
            || w.names(Group::CannedCycle)
            || (self.single_cycle.is_some() && is_single_cycle(self.modal.get(Group::Motion)))
            || w.non_modal.is_some_and(lathe::is_repetitive)
            || self.comp.is_active()
            || w.names(Group::CutterComp)
        {
            free |= 0b111;
        }
        !free & 0b11_1111
    }

    /// The output point of programmed end point `to` of a block with words `w`. An axis whose
    /// output is unknown stays where the tool is when the block neither names it nor couples it
    /// (a rotation in its plane) to one it names; otherwise the block needs it, and that is alarm
    /// 0224. An output axis the block does not name that moves anyway is a warning (an error under
    /// `--strict-axes`), once per rotation when a rotation couples it.
    fn out_target(&mut self, to: &Pose, w: &Words, origin: Origin) -> Result<Pose, Stop> {
        let mut out = self.out_point(to);
        let coupled = |k: &Self, i: usize| -> Option<usize> {
            let r = k.transform.rotation.as_ref()?;
            let (a, b, _) = r.plane.axes();
            if i == a && w.has(AXES[b]) {
                Some(b)
            } else if i == b && w.has(AXES[a]) {
                Some(a)
            } else {
                None
            }
        };
        for i in 0..6 {
            if !out[i].is_nan() {
                continue;
            }
            if w.has(AXES[i]) && to[i].is_nan() {
                let what = if self.modal.incremental() {
                    format!("the incremental {} word", AXES[i])
                } else {
                    format!("the {} word", AXES[i])
                };
                return Err(unknown_axis(i, &what).into());
            }
            if w.has(AXES[i]) || coupled(self, i).is_some() {
                let j = (0..6).find(|&j| j != i && to[j].is_nan()).unwrap_or(i);
                return Err(unknown_axis(
                    j,
                    &format!(
                        "{} under the G68 rotation (it moves both axes of the plane)",
                        w.named_axes_text()
                    ),
                )
                .into());
            }
            out[i] = self.path_from[i];
        }
        // Axes the block does not name that move anyway.
        for i in 0..6 {
            if w.has(AXES[i]) || self.path_from[i].is_nan() {
                continue;
            }
            let d = out[i] - self.path_from[i];
            if d.abs() < 5e-4 {
                continue;
            }
            self.warned_axes |= 1 << i;
            if coupled(self, i).is_some() {
                if !self.coupling_warned {
                    self.coupling_warned = true;
                    let text = format!(
                        "{} also moves {} by {:.3}: the G68 rotation couples the axes of its plane (said once per rotation)",
                        w.named_axes_text(),
                        AXES[i],
                        d
                    );
                    self.warn(origin, text);
                }
                continue;
            }
            let text = format!(
                "{} also moves {} by {:.3}, which the block does not name (a tool length offset or a shift that changed since the last move)",
                w.named_axes_text(),
                AXES[i],
                d
            );
            if self.settings.strict_axes {
                return Err(Alarm::new(UNKNOWN_POSITION, format!("{text}; --strict-axes")).into());
            }
            self.warn(origin, text);
        }
        Ok(out)
    }

    /// G10: data setting (work offsets L2/L20, tool registers L10–L13; a lathe's tool offsets).
    fn data_setting(&mut self, w: &Words) -> Result<(), Alarm> {
        let l = w.get(Letter::L).map(|l| l.round() as u32);
        let inc = self.modal.incremental();
        if self.settings.lathe.is_some() {
            return match l {
                None => self.lathe_offset_setting(w),
                Some(10..=13) => Err(Alarm::new(
                    FORMAT,
                    "G10 L10–L13 set a mill's tool registers: a lathe's offsets are G10 P X Z R Q",
                )),
                _ => self.mill_data_setting(w, l, inc),
            };
        }
        self.mill_data_setting(w, l, inc)
    }

    /// G10 L2/L20 (work offsets) and L10–L13 (a mill's tool registers).
    fn mill_data_setting(&mut self, w: &Words, l: Option<u32>, inc: bool) -> Result<(), Alarm> {
        let control = self.settings.control_offsets;
        let controls = match l {
            Some(2 | 20) => control.work.then_some("work offsets"),
            Some(10 | 11) => control.length.then_some("tool lengths"),
            _ => None,
        };
        if let (true, Some(what)) = (E::CANON, controls) {
            return Err(control_register(&format!("G10 L{}", l.unwrap_or(2)), what));
        }
        match l {
            Some(2 | 20) => {
                let p = w.get(Letter::P).unwrap_or(0.0);
                let old = self.frames.origin();
                let reg = self.frames.register_mut(l.unwrap_or(2), p)?;
                for (i, &a) in AXES.iter().enumerate() {
                    if let Some(v) = w.get(a) {
                        reg[i] = if inc { reg[i] + v } else { v };
                    }
                }
                self.shift_origin(old);
                Ok(())
            }
            Some(n @ 10..=13) => {
                let p = w.get(Letter::P).ok_or_else(|| {
                    Alarm::new(FORMAT, format!("G10 L{n} needs P (the offset number)"))
                })?;
                let r = w.get(Letter::R).unwrap_or(0.0);
                let reg = self.frames.tool_mut(p)?;
                let field = match n {
                    10 => &mut reg.length_geometry,
                    11 => &mut reg.length_wear,
                    12 => &mut reg.radius_geometry,
                    _ => &mut reg.radius_wear,
                };
                *field = if inc { *field + r } else { r };
                Ok(())
            }
            _ => Err(Alarm::new(
                FORMAT,
                format!(
                    "G10 L{}: fmsvm sets work offsets (L2, L20) and tool registers (L10-L13)",
                    w.get(Letter::L).map_or("?".to_string(), |l| l.to_string())
                ),
            )),
        }
    }

    /// The length offset G43/G44/G49 asks for, with H (or the last H).
    fn length_offset(&self, h: Option<f64>) -> Result<f64, Alarm> {
        let sign = match self.modal.get(Group::LengthComp) {
            Code::G43 => 1.0,
            Code::G44 => -1.0,
            _ => return Ok(0.0),
        };
        match h {
            None => Ok(0.0),
            Some(h) if h.round() == 0.0 => Ok(0.0),
            Some(h) => Ok(sign * self.frames.tool(h)?.length()),
        }
    }

    /// Updates the transforms a block names (G68/G69, G51/G50, G51.1/G50.1). Returns whether the
    /// block's axis words were taken as the transform's centre (they are then no move).
    fn transforms(&mut self, w: &Words) -> Result<bool, Alarm> {
        let mut consumed = false;
        let plane = self.plane();
        if w.names(Group::Mirror) {
            match self.modal.get(Group::Mirror) {
                Code::G51_1 => {
                    for (m, &a) in self.transform.mirror.iter_mut().zip(&AXES) {
                        if let Some(v) = w.get(a) {
                            *m = Some(v);
                        }
                    }
                }
                _ => {
                    let all = !AXES[..3].iter().any(|&a| w.has(a));
                    for (m, &a) in self.transform.mirror.iter_mut().zip(&AXES) {
                        if all || w.has(a) {
                            *m = None;
                        }
                    }
                }
            }
            consumed = true;
        }
        if w.names(Group::Scaling) {
            match self.modal.get(Group::Scaling) {
                Code::G51 => {
                    let centre: [f64; 3] =
                        std::array::from_fn(|i| w.get(AXES[i]).unwrap_or(self.position[i]));
                    let named = (0..3).any(|i| w.has(AXES[i]));
                    // A magnification written without a point is in the control's least
                    // increment of magnification (Fanuc "Scaling": 0.001 or 0.00001, parameter
                    // 5400#7 SCR): `G51 P2000` is ×2. The NCT textbook writes the factor itself
                    // (`G51 X0 Y0 P2`: ×2), `scaling_unit` 0.
                    let unit = self.settings.scaling_unit;
                    let factor = |bit: u8, v: f64| {
                        if unit > 0.0 && w.no_point & bit != 0 {
                            v * unit
                        } else {
                            v
                        }
                    };
                    let factors: [f64; 3] = if let Some(p) = w.get(Letter::P) {
                        let p = factor(1, p);
                        // P scales the axes whose centre the block gives (all three when it gives
                        // none): the textbook's G51 X0 Y0 P2 leaves Z alone.
                        std::array::from_fn(|i| if !named || w.has(AXES[i]) { p } else { 1.0 })
                    } else {
                        let ijk = [Letter::I, Letter::J, Letter::K];
                        std::array::from_fn(|i| w.get(ijk[i]).map_or(1.0, |v| factor(2 << i, v)))
                    };
                    if factors.contains(&0.0) {
                        return Err(Alarm::new(142, "scaling factor 0 (G51)"));
                    }
                    // An axis it scales needs its centre: the block's word, or where the tool is.
                    if let Some(i) =
                        (0..3).find(|&i| E::CANON && factors[i] != 1.0 && centre[i].is_nan())
                    {
                        return Err(unknown_axis(
                            i,
                            "G51 without its centre (the tool's position)",
                        ));
                    }
                    self.transform.scale = Some((centre, factors));
                    consumed = true;
                }
                // G50's axis words are a move (the NCT manual's own `G50 G0 X0 Y0`).
                _ => self.transform.scale = None,
            }
        }
        if w.names(Group::Rotation) {
            match self.modal.get(Group::Rotation) {
                Code::G68 => {
                    let (a, b, _) = plane.axes();
                    let centre = [
                        w.get(AXES[a]).unwrap_or(self.position[a]),
                        w.get(AXES[b]).unwrap_or(self.position[b]),
                    ];
                    if let Some(i) = [a, b].into_iter().find(|&i| {
                        E::CANON && w.get(AXES[i]).is_none() && self.position[i].is_nan()
                    }) {
                        return Err(unknown_axis(
                            i,
                            "G68 without its centre (the tool's position)",
                        ));
                    }
                    let r = w.get(Letter::R).unwrap_or(0.0);
                    let degrees = match &self.transform.rotation {
                        Some(old) if self.modal.incremental() => old.degrees + r,
                        _ => r,
                    };
                    self.transform.rotation = Some(Rotation::new(plane, centre, degrees));
                    consumed = true;
                }
                _ => self.transform.rotation = None,
            }
        }
        Ok(consumed)
    }

    /// I J of a G40/G41/G42 straight block in the output frame's plane: the direction compensation
    /// starts or ends along (NCT; only the direction counts).
    fn start_direction(&self, w: &Words) -> Option<[f64; 2]> {
        if matches!(self.modal.get(Group::Motion), Code::G2 | Code::G3) {
            return None;
        }
        let (a, b, _) = self.plane().axes();
        let offsets = [Letter::I, Letter::J, Letter::K];
        let d = [
            w.get(offsets[a]).unwrap_or(0.0),
            w.get(offsets[b]).unwrap_or(0.0),
        ];
        if d == [0.0, 0.0] {
            return None;
        }
        // The direction turns with the transforms (a rotation; a mirror flips it).
        let o = self.out_point(&[0.0; 6]);
        let mut p = [0.0; 6];
        p[a] = d[0];
        p[b] = d[1];
        let q = self.out_point(&p);
        Some([q[a] - o[a], q[b] - o[b]])
    }

    /// Whether this block's I J K are the centre itself (FMS-3000 N3021 = 1, or 2 under G90).
    fn centre_absolute(&self) -> bool {
        match self.settings.arc_centre {
            ArcCentre::Incremental => false,
            ArcCentre::Absolute => true,
            ArcCentre::Modal => !self.modal.incremental(),
        }
    }

    /// An arc's canonical form from programmed `from` to programmed `to`, in the output frame.
    fn arc_op(
        &self,
        from: &Pose,
        to: &Pose,
        clockwise: bool,
        w: &Words,
    ) -> Result<Option<Canon<'static>>, Alarm> {
        let plane = self.plane();
        // Everything an arc is worked out from must be known: its end, its start on the plane
        // (centre and radius come from it), and the start of a helix's rise.
        let (a, b, n) = plane.axes();
        if let Some(i) = (0..6).find(|&i| w.has(AXES[i]) && to[i].is_nan()) {
            return Err(unknown_axis(
                i,
                &format!("the incremental {} word", AXES[i]),
            ));
        }
        if let Some(i) = [a, b].into_iter().find(|&i| self.path_from[i].is_nan()) {
            return Err(unknown_axis(
                i,
                "an arc (its centre and radius are from its start)",
            ));
        }
        if w.has(AXES[n]) && self.path_from[n].is_nan() {
            return Err(unknown_axis(n, "a helix (its rise is from its start)"));
        }
        let centre = centre_words(w, from, plane, self.centre_absolute())?;
        if let CentreWords::Radius(r) = centre {
            // An R arc is worked out where the control works it out: from where the tool stands to
            // the end point, both through the transforms (a centre given by R moves with its end
            // points, so a move too small to make is not allowed to move it: textbook 32/33).
            self.transform.check_arc_plane(plane)?;
            let factor = self.transform.radius_factor(plane)?;
            let tool = self.path_from;
            return Ok(arcs::arc(
                &tool,
                &self.out_point(to),
                plane,
                clockwise != self.transform.reverses(plane),
                CentreWords::Radius(r * factor),
                self.settings.arc_tolerance,
            )?
            .map(Canon::Arc));
        }
        let Some(arc) = arcs::arc(
            from,
            to,
            plane,
            clockwise,
            centre,
            self.settings.arc_tolerance,
        )?
        else {
            return Ok(None);
        };
        if self.transform.is_identity()
            && self.settings.frame == OutputFrame::G54
            && self.frames.origin() == self.frames.g54_origin()
            && self.frames.length == 0.0
        {
            return Ok(Some(Canon::Arc(arc)));
        }
        self.transform.check_arc_plane(plane)?;
        self.transform.radius_factor(plane)?;
        let (a, b, _) = plane.axes();
        let mut c = *from;
        c[a] = arc.centre[0];
        c[b] = arc.centre[1];
        let c = self.out_point(&c);
        // After a transform changed, the tool may not stand at the arc's programmed start seen
        // through it: the arc starts where the tool is, and must still be an arc about its centre.
        let tool = self.path_from;
        let end = self.out_point(to);
        let r0 = (tool[a] - c[a]).hypot(tool[b] - c[b]);
        let r1 = (end[a] - c[a]).hypot(end[b] - c[b]);
        if r0 < 1e-9 || (r0 - r1).abs() > self.settings.arc_tolerance {
            return Err(Alarm::new(
                arcs::RADIUS_TOLERANCE,
                format!(
                    "over tolerance of radius: the tool stands {r0:.4} from the arc's centre, its end is {r1:.4} away (a transform changed since the last move: position the tool first)"
                ),
            ));
        }
        Ok(Some(Canon::Arc(fmsvm_canon::Arc {
            to: self.out_point(to),
            centre: [c[a], c[b]],
            plane,
            clockwise: clockwise != self.transform.reverses(plane),
            turns: 0,
        })))
    }
}

impl<E: Emitter> Kernel<E> {
    /// Whether a block's F is per revolution: the feed mode (G95, a lathe's G99), or a thread's
    /// lead whatever the mode (G32/G33, a lathe's G92 and G76).
    fn f_per_rev(&self, non_modal: Option<Code>) -> bool {
        self.modal.get(Group::FeedMode) == Code::G95
            || matches!(
                self.modal.get(Group::Motion),
                Code::G33 | Code::THREADING_CYCLE
            )
            || non_modal == Some(Code::THREADING_MULTIPLE)
    }

    /// Step 1: the block's G codes by modal group (a later code of the same group wins, as on
    /// Fanuc), G0–G3 ending a canned cycle, and a change of units converting where the tool is.
    /// True when the units changed.
    #[inline(always)]
    fn modal_codes(&mut self, block: &Block<'_>, w: &mut Words) -> Result<bool, Stop> {
        let was_inch = self.modal.inch();
        let system = self.modal.system;
        for word in block.words() {
            if word.letter == Letter::G {
                let code = if self.settings.haas_codes && word.value == 154.0 {
                    haas_work_offsets::<E>(self.settings.haas_output)?
                } else if system.lathe() {
                    self.modal.read(word.value)?
                } else {
                    fmsvm_canon::decode::gcode(word.value)?
                };
                if E::CANON
                    && !(code == Code::G33 && self.settings.mill_threads)
                    && let Some(Unresolved::Refused(what)) = unresolved(code, system)
                {
                    return Err(Alarm::new(
                        IMPROPER_G,
                        format!("{what} cannot be resolved into flat motion; run without --resolve to pass it through"),
                    )
                    .into());
                }
                // Exact stop and the cutting modes are left out of resolved output: the corners
                // are then the control's own mode's. Said once a code.
                let written =
                    self.emitter.corners() && matches!(code, Code::G9 | Code::G61 | Code::G64);
                if E::CANON
                    && !written
                    && matches!(
                        code,
                        Code::G9 | Code::G61 | Code::G62 | Code::G63 | Code::G64
                    )
                {
                    let said = format!("G{code} (exact stop or cutting mode)");
                    if !self.warned(&said) {
                        let text = format!(
                            "{said} is not written in resolved output: corners follow the control's own mode (said at its first block)"
                        );
                        self.warn(Origin::of(block, 0), text);
                    }
                }
                match fmsvm_canon::modal::group(code) {
                    Some(Group::NonModal) => w.non_modal = Some(code),
                    Some(g) => w.named |= 1 << g as u32,
                    None => {}
                }
                self.modal.set(code);
            }
        }
        // G0–G3 end a canned cycle (Fanuc: group 01 cancels group 09).
        if w.names(Group::Motion) && !w.names(Group::CannedCycle) {
            self.modal.set(Code::G80);
        }
        let inch = self.modal.inch();
        if inch != was_inch {
            // G20/G21 moves nothing: where the tool is reads in the new unit (LinuxCNC and Fanuc
            // keep the tool where it is).
            let k = if inch { 1.0 / 25.4 } else { 25.4 };
            for p in [
                &mut self.position,
                &mut self.out_position,
                &mut self.path_from,
                &mut self.comp_from,
            ] {
                for v in &mut p[..3] {
                    *v *= k;
                }
            }
            // The feed rate stays the same speed: its number changes unit too.
            self.last[Letter::F.index()] *= k;
        }
        Ok(inch != was_inch)
    }

    /// Step 2: every word decoded once (incremental words made absolute), into `w` by letter and
    /// into the modal values (`last`); the M codes, and whether the block ends the program.
    #[inline(always)]
    fn decode_words(&mut self, block: &Block<'_>, w: &mut Words) -> Result<(Context, Flow), Stop> {
        let inch = self.modal.inch();
        let incremental =
            Decoded::new(block, &self.rules, inch, &mut self.decoded)?.has_incremental();
        if self.hole_step != [0.0; 2] {
            self.hole_step = [0.0; 2];
        }
        if incremental {
            self.absolutize(block, w)?;
        }
        let decoded = Decoded::view(block, &self.decoded);
        let ctx = Context {
            inch,
            absolute: !self.modal.incremental(),
            motion: match self.modal.get(Group::CannedCycle) {
                Code::G80 => self.modal.get(Group::Motion),
                cycle => cycle,
            },
            // A lathe's G10 P Q: the offset number and the tip are whole numbers.
            pq_integers: self.settings.lathe.is_some() && w.non_modal == Some(Code::G10),
            per_rev: self.f_per_rev(w.non_modal),
        };
        let mut flow = Flow::Continue;
        for (word, v) in decoded.words() {
            self.last[word.letter.index()] = v;
            match word.letter {
                Letter::G => {}
                Letter::M => {
                    let code = Code::of_integer(v);
                    match code {
                        Some(Code::M3) => self.spindle_ccw = false,
                        Some(Code::M4) => self.spindle_ccw = true,
                        _ => {}
                    }
                    if w.m_count < w.m.len() {
                        w.m[w.m_count] = v;
                        w.m_count += 1;
                    }
                    // M02, M30 end the program (M98/M99 are the VM's: they never reach here).
                    if matches!(code, Some(Code::M2 | Code::M30)) {
                        flow = Flow::End;
                    }
                }
                l if Some(l) == self.rules.second_aux() => w.aux = Some(v),
                l => {
                    w.value[l.index()] = v;
                    let bit = match l {
                        Letter::P => 1,
                        Letter::I => 2,
                        Letter::J => 4,
                        Letter::K => 8,
                        _ => 0,
                    };
                    if word.flags.has(WordFlags::NO_POINT) {
                        w.no_point |= bit;
                    } else {
                        w.no_point &= !bit;
                    }
                }
            }
        }
        // No rule of the kernel reads E (a thread's lead is F): resolved output would drop it
        // without a word. A Fanuc has no exponents either: `Z-1e300` is Z-1 and E300 to it.
        if E::CANON && block.get(Letter::E).is_some() {
            return Err(Alarm::new(
                FORMAT,
                format!(
                    "E{}: no rule gives the address E a meaning here (a thread's lead is F), and flat motion would drop it; a number written with an exponent (1e300) reads as a number and an E word",
                    block.get(Letter::E).unwrap_or(0.0)
                ),
            )
            .into());
        }
        if self.settings.lathe.is_some() {
            self.lathe_words(w)?;
        }
        Ok((ctx, flow))
    }

    /// Exact stop and the cutting mode, for an emitter that writes them: G09 for this block's
    /// move, G61/G64 from here on (the modal group's code in force once the block named it).
    fn corners(&mut self, block: &Block<'_>, w: &Words, origin: Origin) -> Result<(), Stop> {
        let g9 = block
            .words()
            .iter()
            .any(|x| x.letter == Letter::G && x.value == 9.0);
        if g9 {
            self.canon(Canon::Corners(fmsvm_canon::Corners::ExactStopOnce), origin)?;
        }
        if w.names(Group::CuttingMode) {
            let mode = match self.modal.get(Group::CuttingMode) {
                Code::G61 => fmsvm_canon::Corners::ExactStop,
                Code::G64 => fmsvm_canon::Corners::Cutting,
                // G62 (corner override) and G63 (tapping mode) have no word here: said once.
                _ => return Ok(()),
            };
            self.canon(Canon::Corners(mode), origin)?;
        }
        Ok(())
    }

    /// Step 3: what acts before motion, as canonical operations: the comment, units, feed mode,
    /// F, S, T, the second auxiliary function and the M codes that act first.
    #[inline(never)]
    fn before_motion(
        &mut self,
        block: &Block<'_>,
        w: &Words,
        units_changed: bool,
        origin: Origin,
    ) -> Result<(), Stop> {
        if !block.comment.is_empty() {
            self.canon(Canon::Comment(block.comment), origin)?;
        }
        if self.emitter.corners() {
            self.corners(block, w, origin)?;
        }
        if w.names(Group::Units) {
            self.canon(Canon::Units(self.modal.inch()), origin)?;
            if units_changed
                && !w.has(Letter::F)
                && let Some(f) = self.last_value(Letter::F)
            {
                self.canon(Canon::FeedRate(f), origin)?;
            }
        }
        if w.names(Group::FeedMode) {
            self.canon(
                Canon::FeedPerRev(self.modal.get(Group::FeedMode) == Code::G95),
                origin,
            )?;
        }
        if let Some(f) = w.get(Letter::F) {
            self.canon(Canon::FeedRate(f), origin)?;
        }
        let lathe_s = self.settings.lathe.is_some() && self.lathe_spindle(w, origin)?;
        if !lathe_s && let Some(s) = w.get(Letter::S) {
            self.canon(Canon::Speed(s), origin)?;
        }
        if let Some(t) = w.get(Letter::T) {
            self.canon(Canon::Tool(t), origin)?;
        }
        if let (Some(letter), Some(code)) = (self.rules.second_aux(), w.aux) {
            self.canon(Canon::AuxCode(letter, code), origin)?;
        }
        for &m in &w.m[..w.m_count] {
            if before_motion(m) {
                self.canon(Canon::MCode(m), origin)?;
            }
        }
        Ok(())
    }

    /// Step 4: G4's dwell (P in ms, else X in seconds).
    #[inline(never)]
    fn dwell(&mut self, block: &Block<'_>, w: &Words, origin: Origin) -> Result<(), Stop> {
        let seconds = match (w.get(Letter::P), w.get(Letter::X)) {
            (Some(p), _) => p / 1000.0,
            (None, Some(x)) => x,
            _ => 0.0,
        };
        self.canon(Canon::Dwell(seconds), origin)?;
        self.timing.dwell(block);
        Ok(())
    }

    /// Step 5: tool length compensation (group 08) with H.
    #[inline(never)]
    fn length_compensation(&mut self, w: &Words, origin: Origin) -> Result<(), Stop> {
        let control = self.settings.control_offsets.length;
        let active = matches!(self.modal.get(Group::LengthComp), Code::G43 | Code::G44);
        if control && active && w.names(Group::Plane) && self.plane() != Plane::XY {
            return Err(plane_under_control_length(self.plane()).into());
        }
        if w.names(Group::LengthComp) || w.has(Letter::H) {
            self.frames.length = self.length_offset(self.last_value(Letter::H))?;
            if control {
                return self.control_length(w, origin);
            }
            // Only where fmsvm computes with the register: literal output leaves H to the control.
            if active && E::CANON {
                self.register_set('H', self.last_value(Letter::H), origin)?;
            }
        }
        Ok(())
    }

    /// The output leaves lengths to the control: the block says `G43 H1` (or G44, G49), the
    /// positions stay the tool tip's, and the control takes the length on at the next block that
    /// moves Z, which the output makes spell Z (FMS-3000 §3.3).
    fn control_length(&mut self, w: &Words, origin: Origin) -> Result<(), Stop> {
        let code = self.modal.get(Group::LengthComp);
        let h = self.last_value(Letter::H).unwrap_or(0.0).round();
        let register = if code == Code::G49 { 0 } else { h as u16 };
        if code != Code::G49 && self.plane() != Plane::XY {
            return Err(plane_under_control_length(self.plane()).into());
        }
        if E::CANON {
            if code != Code::G49 && !w.has(Letter::Z) {
                let text = format!(
                    "G{} H{register} without Z: the control takes the length on at the next block that moves Z, so the output spells Z in the next move",
                    code
                );
                self.warn(origin, text);
            }
            self.canon(Canon::ToolLength { code, register }, origin)?;
        }
        Ok(())
    }

    /// Step 6: cutter compensation (group 07) with D: its start or cancel.
    #[inline(never)]
    fn cutter_compensation(&mut self, w: &Words, origin: Origin) -> Result<(), Stop> {
        // The contour stage lets its held move go under the compensation it was programmed in.
        self.settle()?;
        match self.modal.get(Group::CutterComp) {
            Code::G40 => {
                if self.comp.is_active() {
                    match self.start_direction(w) {
                        Some(d) => self.comp.cancel_along(d),
                        None => self.comp.cancel(),
                    }
                }
            }
            code => {
                let (radius, tip) = if self.settings.lathe.is_some() {
                    self.nose_radius(origin)?
                } else {
                    if E::CANON {
                        self.register_set('D', self.last_value(Letter::D), origin)?;
                    }
                    let d = self.last_value(Letter::D).unwrap_or(0.0);
                    let radius = if d.round() == 0.0 {
                        0.0
                    } else {
                        self.frames.tool(d)?.radius()
                    };
                    (radius, [0.0; 6])
                };
                let left = (code == Code::G41) != self.transform.reverses(self.plane());
                // The start-up move's offset vector comes from where the tool stands.
                let (a, b, _) = self.plane().axes();
                for i in [a, b] {
                    if self.out_position[i].is_nan() {
                        return Err(unknown_axis(i, "starting cutter compensation").into());
                    }
                }
                self.comp_from = self.out_position;
                self.comp_start_along = self.start_direction(w);
                self.comp.start(
                    if left {
                        crate::comp::Side::Left
                    } else {
                        crate::comp::Side::Right
                    },
                    radius,
                    self.plane(),
                );
                self.comp.set_tip(tip);
            }
        }
        Ok(())
    }

    /// Step 7: work offset selection (group 14); the tool stays where it is.
    #[inline(never)]
    fn select_work_offset(&mut self, w: &Words, origin: Origin) -> Result<(), Stop> {
        let old = self.frames.origin();
        let old_slot = self.frames.active_slot();
        self.frames.active = match self.modal.get(Group::WorkOffset) {
            Code::G54_1 => {
                let p = w.get(Letter::P).unwrap_or(1.0).round();
                if !(1.0..=crate::frames::EXTENDED as f64).contains(&p) {
                    let text = if self.settings.haas_codes {
                        format!(
                            "G154 P{p}: fmsvm keeps the first 48 additional work offsets (P1 to P48) of the Haas's 99"
                        )
                    } else {
                        format!("G54.1 P{p}: the additional work offsets are P1 to P48")
                    };
                    return Err(Alarm::new(33, text).into());
                }
                WorkOffset::Extended(p as u8)
            }
            c => WorkOffset::Standard((c.whole() - 53) as u8),
        };
        self.shift_origin(old);
        if self.settings.control_offsets.work {
            return self.control_work_system(old_slot, origin);
        }
        let slot = self.frames.active_slot();
        if slot != old_slot {
            self.guessed_work_offset(origin)?;
        }
        Ok(())
    }

    /// The output leaves work offsets to the control: the block says the system (`G55`), and the
    /// tool's position in it is known only where fmsvm knows both systems' offsets (`--offsets`,
    /// or the program set them); elsewhere the next block must position each axis.
    fn control_work_system(&mut self, old_slot: usize, origin: Origin) -> Result<(), Stop> {
        let slot = self.frames.active_slot();
        let crate::frames::WorkOffset::Standard(n) = self.frames.active else {
            return Err(Alarm::new(
                33,
                format!(
                    "{}: the output leaves work offsets to the control (the profile's [motion] work_offsets = \"control\"), whose systems are G54 to G59",
                    self.frames.active_name()
                ),
            )
            .into());
        };
        if slot == old_slot || !E::CANON {
            return Ok(());
        }
        self.ready_to_position(&self.frames.active_name())?;
        if !(self.frames.work_set[slot] && self.frames.work_set[old_slot]) {
            self.position = [f64::NAN; 6];
        }
        self.frame_origin = self.output_origin();
        let to = self.out_point(&self.position);
        self.canon(Canon::WorkSystem(n), origin)?;
        self.canon(Canon::Start(to), origin)?;
        self.stands_at(to);
        Ok(())
    }

    /// Resolved output in the G54 frame (or machine coordinates) of a program that selects a work
    /// offset nobody set: where it lies from G54 (from machine zero) is a guess, 0. A warning naming
    /// the line, an error under `--strict-axes`.
    fn guessed_work_offset(&mut self, origin: Origin) -> Result<(), Stop> {
        if !E::CANON {
            return Ok(());
        }
        let slot = self.frames.active_slot();
        let name = self.frames.active_name();
        let text = match self.settings.frame {
            OutputFrame::G54
                if slot != 1 && !(self.frames.work_set[slot] && self.frames.work_set[1]) =>
            {
                format!(
                    "{name}: its work offset and G54's (the frame the output is written in) were not both set by the program or --offsets: the output takes {name} to lie where G54 does"
                )
            }
            OutputFrame::Machine if !self.frames.work_set[slot] => format!(
                "{name}: its work offset was never set by the program or --offsets: the output in machine coordinates takes it as 0"
            ),
            _ => return Ok(()),
        };
        if self.settings.strict_axes {
            return Err(Alarm::new(UNKNOWN_POSITION, format!("{text}; --strict-axes")).into());
        }
        self.warn(origin, text);
        Ok(())
    }

    /// Step 8: the one-block codes that set frames or move on their own (G10, G52, G92, G92.1,
    /// G28/G30, G53).
    #[inline(never)]
    fn one_block_code(&mut self, w: &Words, origin: Origin) -> Result<(), Stop> {
        match w.non_modal {
            Some(Code::G10) => self.data_setting(w)?,
            Some(Code::G52) => {
                let old = self.frames.origin();
                for (i, &a) in AXES.iter().enumerate() {
                    if let Some(v) = w.get(a) {
                        self.frames.local[i] = v;
                    }
                }
                self.shift_origin(old);
            }
            Some(Code::G92) => {
                // G92 sets the shift so that the tool reads the words, and cancels the G52 local
                // shift of the axes it names (Fanuc; the NCT manual 9.2.4 says the same).
                let old = self.frames.origin();
                for (i, &a) in AXES.iter().enumerate() {
                    if let Some(v) = w.get(a) {
                        if E::CANON && self.position[i].is_nan() {
                            return Err(unknown_axis(
                                i,
                                "G92 (the shift it sets is where the tool stands)",
                            )
                            .into());
                        }
                        self.frames.shift[i] += self.frames.local[i] + self.position[i] - v;
                        self.frames.local[i] = 0.0;
                    }
                }
                self.shift_origin(old);
            }
            Some(Code::G92_1) => {
                // G92.1 IP0: the axes it names go back to their work offset; without words, all.
                let old = self.frames.origin();
                let all = !w.any_axis();
                for (i, &a) in AXES.iter().enumerate() {
                    if all || w.has(a) {
                        self.frames.shift[i] = 0.0;
                    }
                }
                self.shift_origin(old);
            }
            Some(code @ (Code::G28 | Code::G30)) => {
                let n = if code == Code::G28 {
                    1
                } else {
                    w.get(Letter::P).map_or(2.0, f64::round) as usize
                };
                let Some(reference) = self.frames.reference.get(n.wrapping_sub(1)).copied() else {
                    return Err(Alarm::new(
                        46,
                        format!("G30 P{n}: the reference positions are P2 to P4"),
                    )
                    .into());
                };
                // Fanuc's G28 without axes moves nothing; a Haas's returns every axis.
                if w.any_axis() || (self.settings.haas_codes && n == 1) {
                    self.reference_return(n as u8, &reference, w, origin)?;
                }
            }
            Some(Code::G53) if w.any_axis() && !self.modal.incremental() => {
                // Machine coordinates of the spindle: the length offset does not apply to the axes
                // G53 names (Fanuc cancels the length vector for them; LinuxCNC agrees); always at
                // rapid traverse (Fanuc).
                let mut m = self.machine_point(&self.position);
                let mut machine = [f64::NAN; 6];
                let mut axes = 0u8;
                for (i, &a) in AXES.iter().enumerate() {
                    if let Some(v) = w.get(a) {
                        m[i] = v;
                        machine[i] = v;
                        axes |= 1 << i;
                    }
                }
                self.position = self.program_point_seen(&m);
                if E::CANON {
                    self.ready_to_position("G53")?;
                    let to = self.positioned(axes, &m, origin)?;
                    self.emitter
                        .canon(&Canon::Machine { axes, machine, to }, origin)?;
                    self.stands_at(to);
                }
            }
            _ => {}
        }
        Ok(())
    }

    /// Step 9: G50.1/G51.1 mirror, G50/G51 scaling, G68/G69 rotation. A transform that changes
    /// moves nothing: the tool stays, and the programmed position becomes where it stands seen
    /// through the new transform, so a block that names only Z after G50.1/G69/G50 leaves X Y where
    /// they are (docs/kernel.md, "A block moves only what it names"). True when the block's axis
    /// words were the transform's (a centre), not a move.
    #[inline(never)]
    fn change_transforms(&mut self, w: &Words) -> Result<bool, Stop> {
        let tool = self.machine_point(&self.position);
        let before = self.transform.clone();
        let took_axes = self.transforms(w)?;
        if self.transform != before {
            self.coupling_warned = false;
            self.position = self.program_point_seen(&tool);
        }
        Ok(took_axes)
    }

    /// Step 11: the motion of the group 01 code in force (G0 G1 G2 G3, G31 with it), to the words'
    /// end point. True when the block moved.
    #[inline(never)]
    fn programmed_motion(
        &mut self,
        block: &Block<'_>,
        w: &Words,
        start: Pose,
        origin: Origin,
    ) -> Result<bool, Stop> {
        if w.names(Group::CannedCycle) {
            self.cycle.cancel();
        }
        let motion = self.modal.get(Group::Motion);
        if self.single_cycle.is_some() && (w.names(Group::Motion) || !is_single_cycle(motion)) {
            self.single_cycle = None;
        }
        let arc_words =
            w.has(Letter::I) || w.has(Letter::J) || w.has(Letter::K) || w.has(Letter::R);
        let full_circle = matches!(motion, Code::G2 | Code::G3) && arc_words;
        if !(w.any_axis() || full_circle) {
            return Ok(false);
        }
        let to = self.end_point(w)?;
        if w.non_modal == Some(Code::G31) {
            let target = if E::CANON {
                // A skip block stands alone: not under cutter compensation (Fanuc's G31 alarm;
                // FMS-3000 §7, "G32 при введённой коррекции на радиус").
                self.ready_to_position("a skip move (G31)")?;
                Some(self.out_target(&to, w, origin)?)
            } else {
                None
            };
            self.position = to;
            let touched = self.skip_move(start, block);
            // The control's skip block to the programmed end (it stops at the real surface);
            // then where the probe model says the probe stopped, if it touched.
            if let Some(target) = target {
                self.canon(Canon::Skip(target), origin)?;
                self.stands_at(target);
                if touched {
                    let at = self.out_point(&self.position);
                    self.canon(Canon::Start(at), origin)?;
                    self.stands_at(at);
                }
            }
            return Ok(true);
        }
        match motion {
            Code::TURNING_CYCLE | Code::THREADING_CYCLE | Code::FACING_CYCLE => {
                self.single_cycle(motion, &to, w, origin)?;
                return Ok(true);
            }
            Code::G33 if E::CANON => self.thread(&to, w, origin)?,
            Code::G2 | Code::G3 if self.is_intersection(w) => {
                if !E::CANON {
                    return Err(Alarm::new(
                        NO_FANUC_NUMBER,
                        "an arc intersection (G2/G3 with I J R) has no Fanuc literal form: its end and the previous block's end are computed; run with --resolve",
                    )
                    .into());
                }
                self.intersection_arc(&to, motion == Code::G2, w, origin)?;
            }
            Code::G2 | Code::G3 => {
                if E::CANON {
                    if let Some(op) = self.arc_op(&start, &to, motion == Code::G2, w)? {
                        self.canon(op, origin)?;
                    }
                } else {
                    // Literal output copies I J K as written: right only for a control that reads
                    // them as the program's did.
                    if self.settings.arc_centre != ArcCentre::Incremental
                        && (w.has(Letter::I) || w.has(Letter::J) || w.has(Letter::K))
                    {
                        return Err(Alarm::new(
                            ARC_CENTRE_WORD,
                            "the program's I J K are read as N3021 sets them (centre itself), and literal output would copy them as written: expand it with --resolve",
                        )
                        .into());
                    }
                    // Literal output checks the arc as the control would (alarm 0020) before the
                    // block is written, where its start is known.
                    let (a, b, _) = self.plane().axes();
                    if [start[a], start[b], to[a], to[b]]
                        .iter()
                        .all(|v| !v.is_nan())
                    {
                        arcs::arc(
                            &start,
                            &to,
                            self.plane(),
                            motion == Code::G2,
                            centre_words(w, &start, self.plane(), self.centre_absolute())?,
                            self.settings.arc_tolerance,
                        )?;
                    }
                }
            }
            Code::G0 if E::CANON => {
                let out = self.out_target(&to, w, origin)?;
                self.canon(Canon::Rapid(out), origin)?
            }
            _ if E::CANON => {
                let out = self.out_target(&to, w, origin)?;
                self.canon(Canon::Feed(out), origin)?
            }
            _ => {}
        }
        self.position = to;
        Ok(true)
    }

    /// Step 12: the M codes that act after motion.
    #[inline(never)]
    fn after_motion(&mut self, w: &Words, origin: Origin) -> Result<(), Stop> {
        for &m in &w.m[..w.m_count] {
            if !before_motion(m) {
                self.canon(Canon::MCode(m), origin)?;
            }
        }
        Ok(())
    }
}

impl<E: Emitter> Machine for Kernel<E> {
    /// One block, in the order of execution of rs274ngc's `execute_block` and the Fanuc manuals
    /// (docs/kernel.md, "Order of work in one block"): G codes by group, the words decoded, what
    /// acts before motion (F S T, the early M codes), G4, length and cutter compensation, the work
    /// offset, the one-block codes, transforms, motion (a canned cycle, or G0–G3/G31), the late M
    /// codes; the literal emitter gets the block last, once nothing in it raised an alarm. The
    /// plain move (`plain_move`) takes a raster's blocks by a shorter way to the same state.
    ///
    /// Inlining, measured (docs/performance.md, "Current figures"): `modal_codes` and `decode_words`
    /// are inlined into this function, the other phases are calls of their own; inlining them all
    /// runs the same instructions and 2–7 % slower on the canonical paths (resolved output, stats).
    fn block(&mut self, block: &Block<'_>) -> Result<Flow, Stop> {
        if let Some(flow) = self.plain_move(block) {
            return flow;
        }
        if self.settings.haas_codes && look_ahead_limit(block)? {
            return Ok(Flow::Continue);
        }
        if self.capture.is_some() {
            return self.profile_block(block);
        }
        let mut w = Words::empty();
        let units_changed = self.modal_codes(block, &mut w)?;
        let (ctx, mut flow) = self.decode_words(block, &mut w)?;
        self.warned_axes = 0;
        let origin = Origin::of(block, if E::CANON { self.fixed_axes(&w) } else { 0 });
        if E::CANON && block.block_delete {
            self.block_delete_may_stay(&w)?;
        }
        if E::CANON {
            self.before_motion(block, &w, units_changed, origin)?;
        }
        if let Some(code) = w.non_modal.filter(|&c| lathe::is_repetitive(c)) {
            // A lathe's multiple repetitive cycle: its profile and passes (kernel/lathe.rs).
            self.repetitive_cycle(block, code, &w, origin)?;
            if E::CANON {
                self.after_motion(&w, origin)?;
            } else {
                let ctx = Context {
                    pq_integers: true,
                    ..ctx
                };
                self.emitter
                    .block(&Decoded::view(block, &self.decoded), &ctx)?;
            }
            return Ok(flow);
        }
        let start = self.position;
        if w.non_modal == Some(Code::G4) {
            self.dwell(block, &w, origin)?;
        }
        self.length_compensation(&w, origin)?;
        if E::CANON && w.names(Group::CutterComp) {
            self.cutter_compensation(&w, origin)?;
        }
        if w.names(Group::WorkOffset) {
            self.select_work_offset(&w, origin)?;
        }
        let mut moves_by_words = !matches!(w.non_modal, Some(c) if fmsvm_block::AXES_ARE_DATA.contains(&c) || matches!(c, Code::G28 | Code::G30 | Code::G53));
        self.one_block_code(&w, origin)?;
        if moves_by_words
            && (w.names(Group::Mirror) || w.names(Group::Scaling) || w.names(Group::Rotation))
            && self.change_transforms(&w)?
        {
            moves_by_words = false;
        }
        if E::CANON {
            self.corner_words(&w, origin)?;
        }
        let cycle = self.modal.get(Group::CannedCycle);
        let moved = if moves_by_words && cycle != Code::G80 {
            (w.any_axis()
                || w.names(Group::CannedCycle)
                    && (w.has(Letter::R) || w.has(Letter::K) || w.has(Letter::L)))
                && self.canned_cycle(cycle, &w, origin)?
        } else if moves_by_words {
            self.programmed_motion(block, &w, start, origin)?
        } else {
            matches!(w.non_modal, Some(Code::G28 | Code::G30 | Code::G53)) && w.any_axis()
        };
        if E::CANON {
            self.after_motion(&w, origin)?;
        }
        if moved {
            self.timing
                .motion(&self.modal, &start, &self.position, block, &self.last);
            if flow == Flow::Continue {
                flow = Flow::Moved;
            }
        }
        // The literal emitter writes the block once the kernel has decided it whole: a block that
        // raises an alarm is never written (docs/kernel.md, "Order of work in one block").
        if !E::CANON {
            self.emitter
                .block(&Decoded::view(block, &self.decoded), &ctx)?;
        }
        Ok(flow)
    }

    fn argument(&self, word: &Word) -> f64 {
        self.rules.value(word, self.modal.inch())
    }

    fn message(&mut self, number: u32, text: &str) -> Result<(), Stop> {
        self.messages.push((number, text.to_string()));
        self.emitter.message(number, text)
    }

    fn read_system(&mut self, number: u32) -> Result<f64, Stop> {
        sysvars::read(self, number).map_err(Stop::from)
    }

    fn write_system(&mut self, number: u32, value: f64) -> Result<(), Stop> {
        sysvars::write(self, number, value).map_err(Stop::from)
    }

    fn increment(&self, letter: Letter) -> f64 {
        self.rules.increment(letter, self.modal.inch())
    }
}

impl<E: Emitter> Kernel<E> {
    /// The last value of address `l` (this block's, or an earlier one's), if it was ever given.
    fn last_value(&self, l: Letter) -> Option<f64> {
        let v = self.last[l.index()];
        (!v.is_nan()).then_some(v)
    }

    /// Machine point `m` in the output frame.
    fn out_machine(&self, m: &Pose) -> Pose {
        let o = self.output_origin();
        let mut p: Pose = std::array::from_fn(|i| m[i] - o[i]);
        if self.settings.control_offsets.length || self.settings.tool_tip {
            // The control adds the length itself (or a picture shows the tip): the tool tip's.
            p[2] -= self.frames.length;
        }
        p
    }

    /// G31: the probe stops where the model says; the tool is there afterwards (S4, S9).
    fn skip_move(&mut self, start: Pose, block: &Block<'_>) -> bool {
        let end = [self.position[0], self.position[1], self.position[2]];
        let (at, touched) = probe::skip(&mut self.probe, [start[0], start[1], start[2]], end);
        if matches!(self.probe, probe::ProbeModel::None)
            && !self.warned("G31 without a probe model")
        {
            self.warn(
                Origin::of(block, 0),
                "G31 without a probe model: the skip position #5061-#5066 is the programmed end point (give --stock or --probe-points)".into(),
            );
        } else if !touched && !matches!(self.probe, probe::ProbeModel::None) {
            self.warn(
                Origin::of(block, 0),
                "G31: the probe touched nothing on its way".into(),
            );
        }
        self.position[..3].copy_from_slice(&at);
        self.skip = self.position;
        touched
    }
}
