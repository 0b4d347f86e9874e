//! How a control spells a flat program: which addresses are codes, integers, lengths or angles, their
//! digits and ranges, how numbers, blocks, comments, arcs, helices and dwells are written, and the
//! program's envelope. A dialect is data (a table per letter and a few enums), never a branch on a
//! dialect name; the CLI reads the built-in profiles and users' `--dialect-file`s into one.

use fmsvm_block::alarms::TOO_MANY_DIGITS;
use fmsvm_block::{AddressClass, Alarm, Letter};

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

/// Where a number has a decimal point.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Point {
    /// Always (`X10.`): on a Fanuc without calculator-type input `X10` is 10 µm.
    Always,
    /// Only when the value has a fraction (`X10`, `X10.5`): controls that read `X10` as 10 mm.
    WhenFractional,
    /// Never: the value in least increments, the decimals implied (`X10000` for 10 mm at 0.001).
    Never,
}

/// How the numbers of one address are written.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct NumberFormat {
    /// The decimal point.
    pub point: Point,
    /// Keep every decimal (`X10.500`) instead of trimming trailing zeros (`X10.5`).
    pub trailing_zeros: bool,
    /// A zero before the point of a value below one (`0.5`, or `.5` without it).
    pub leading_zero: bool,
    /// `+` before positive values (and zero).
    pub plus: bool,
    /// The integer part zero-padded to at least this many digits (0: no padding).
    pub width: u8,
}

impl NumberFormat {
    /// Fanuc's: `X10.`, `X-0.5`, no padding.
    pub const FANUC: NumberFormat = NumberFormat {
        point: Point::Always,
        trailing_zeros: false,
        leading_zero: true,
        plus: false,
        width: 0,
    };
}

/// How comments are written.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum CommentStyle {
    /// `(text)`.
    Paren,
    /// `; text` to the end of the block.
    Semicolon,
    /// The control has none: comments are left out.
    None,
}

/// How arcs are written.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum ArcForm {
    /// G2/G3 with the centre as I J K from the start point.
    Ijk,
    /// G2/G3 with a signed radius R (negative over 180°); full circles in two halves.
    Radius,
    /// As straight moves within the arc tolerance.
    Linearize,
}

/// How a helix (an arc whose normal axis moves) is written.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum HelixForm {
    /// G2/G3 with the normal axis word (Fanuc, ISO, LinuxCNC).
    Axis,
    /// G2/G3 G10 with the normal axis word and its pitch per revolution under the centre letter of
    /// that axis (I for X, J for Y, K for Z), signed like the linear move (FMS-3000 §2.5).
    Pitch,
    /// As straight moves within the arc tolerance.
    Linearize,
}

/// How a dwell is written.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum DwellForm {
    /// `G4 P<milliseconds>` (Fanuc, P without a point).
    Milliseconds,
    /// `G4 P<seconds>` (LinuxCNC).
    PSeconds,
    /// `G4 X<seconds>` (ISO 6983, Fanuc's other form).
    XSeconds,
    /// `G4 F<seconds>` (Sinumerik: the F of a G4 block is not the feed).
    FSeconds,
    /// `G04 E<tenths of a second>`, 1–65535, longer dwells split (FMS-3000 §2.12).
    ETenths,
    /// `G04 K<hundredths of a second>`, 1–9999, longer dwells split (FAGOR 8055 T / 8037 T, as
    /// Autodesk's FAGOR Turning post writes it: "centiseconds for G4 K", K "range 1-9999").
    KHundredths,
}

impl DwellForm {
    /// The dwell's address.
    pub fn letter(self) -> Letter {
        match self {
            DwellForm::Milliseconds | DwellForm::PSeconds => Letter::P,
            DwellForm::XSeconds => Letter::X,
            DwellForm::FSeconds => Letter::F,
            DwellForm::ETenths => Letter::E,
            DwellForm::KHundredths => Letter::K,
        }
    }

    /// The units a second the word resolves: milliseconds (a seconds word has three decimals) or
    /// tenths; a dwell of s seconds is round(s × units) of them.
    pub fn units_per_second(self) -> f64 {
        match self {
            DwellForm::ETenths => 10.0,
            DwellForm::KHundredths => 100.0,
            _ => 1000.0,
        }
    }

    /// The word is in whole units (milliseconds, tenths), not seconds with decimals.
    pub fn whole_units(self) -> bool {
        matches!(
            self,
            DwellForm::Milliseconds | DwellForm::ETenths | DwellForm::KHundredths
        )
    }

    /// The seconds a dwell word's value says (its units read back).
    pub fn seconds(self, value: f64) -> f64 {
        if self.whole_units() {
            value / self.units_per_second()
        } else {
            value
        }
    }

    /// The most units one block holds (FMS-3000 §2.12: E is 1–65535 tenths); None: no limit.
    pub fn most_a_block(self) -> Option<u64> {
        match self {
            DwellForm::ETenths => Some(65_535),
            DwellForm::KHundredths => Some(9_999),
            _ => None,
        }
    }
}

/// How a native canned cycle block is written.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum CycleForm {
    /// `G98 G81 X Y Z R [P] F` (Fanuc, LinuxCNC: modal until G80).
    Fanuc,
    /// `G00 X Y G81 U<R> Z<bottom> [I<end>] F [E<tenths>]`: other words before the cycle code,
    /// parameters after it (FMS-3000 §4.1); Fanuc G85/G89 are its G82 with the exit feed H.
    Fms3000,
}

/// How the control returns an axis to a reference position (G28, G30).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum ReferenceForm {
    /// `G91 G28 Z0` (G30 P2–P4 likewise), then `G90`: the control moves to its own reference
    /// position with no intermediate point (Fanuc, ISO, LinuxCNC).
    Incremental,
    /// `G28 Z0`: the axis letters only select axes, the control goes to machine zero (the FMS-3000,
    /// §2.9.2); G30 is another thing there, so G30 Pn is written as a move to a known position.
    MachineZero,
    /// No return code: a move to the reference position, written only when it is known.
    None,
}

/// How a lathe control writes constant surface speed.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum CssForm {
    /// The control's own `G96 S` (m/min) and `G97 S` (rpm), the clamp as `ClampForm` says.
    Native,
    /// The control has none: each move under G96 gets the rpm of its end diameter, clamped, as
    /// `S` (docs/lathe.md).
    Rpm,
}

/// How a lathe control writes the spindle's speed limit under constant surface speed.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum ClampForm {
    /// `G50 S` (Fanuc T, G-code system A).
    G50,
    /// `G92 S` (Fanuc T system B, Fagor).
    G92,
    /// `D` on the `G96` block (LinuxCNC's `G96 D2500 S180`).
    D,
    /// `LIMS=` (Sinumerik).
    Lims,
}

/// How a lathe control writes a thread (a straight move synchronised with the spindle).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum ThreadForm {
    /// The thread code (G32 in Fanuc T system A, else G33) with the lead as `F`.
    F,
    /// G33 with the lead as `K`, the lead along Z (LinuxCNC's G33: a thread at 45° or steeper
    /// cannot be written).
    K,
    /// G33 with the lead as `K` (along Z) below 45° from the Z axis and `I` (along X) at 45° and
    /// above (DIN 66025, ISO 6983-1: I J K the lead parallel to X Y Z; SINUMERIK 802D).
    Din,
    /// No thread block is known for the control: a thread is refused (alarm).
    None,
}

/// How a milling control writes a thread in one block (spindle-synchronised feed).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum MillThread {
    /// None known: a thread is refused (alarm 0010, at the kernel).
    None,
    /// `G01 X Y Z G33 F<lead>`: G33 acts on its block alone, the motion is G01's and F the lead
    /// per revolution in that block (FMS-3000 §2.7: `G91 G1 Z-10 G33 F1.6`).
    G1G33F,
}

/// How a control writes a skip move (Fanuc's G31: feed towards the end, stop where the probe
/// touches).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum SkipForm {
    /// None known: a skip move is refused (a plain feed would drive the probe through the surface).
    None,
    /// `G31 X… F…`: one-shot, the block moves straight at F (Fanuc "Skip function (G31)").
    G31,
    /// `G01 G32 X… F…`: one-shot with the block's G01, ends the block on the touch signal
    /// ("КАСАНИЕ") and goes on (FMS-3000 §2.11).
    G01G32,
    /// `G38.3 X… F…`: probe towards the work, stop on contact, no error without one; a motion
    /// code in force until another (LinuxCNC G-code reference, "G38.x Straight Probe").
    G38_3,
}

impl SkipForm {
    /// Its name in a profile (`[motion] skip`).
    pub fn name(self) -> &'static str {
        match self {
            SkipForm::None => "none",
            SkipForm::G31 => "g31",
            SkipForm::G01G32 => "g01-g32",
            SkipForm::G38_3 => "g38.3",
        }
    }
}

/// How a lathe control calls a tool and its offset (Fanuc's `T0101`: tool 01, offset 01).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum ToolForm {
    /// The T word as the program wrote it (`T0101`).
    Fanuc,
    /// LinuxCNC: `T1 M6 G43` (T only prepares a tool; M6 changes it, G43 applies its offsets),
    /// `G43 H2` where the offset is not the tool's number, `G49` for offset 00.
    LinuxCnc,
    /// `T1 D1`: the tool and its cutting edge (Sinumerik, Fagor; *inferred* for Fagor).
    TD,
}

/// How a lathe control spells turning (`[lathe]` of a profile).
#[derive(Clone, Debug, PartialEq)]
pub struct LatheForm {
    /// X words are diameters (else radii).
    pub diameter: bool,
    /// How the control numbers its G codes (the output's codes are written back from their
    /// meanings).
    pub codes: fmsvm_canon::modal::CodeSystem,
    /// The words of the output's first line (`G18`; LinuxCNC `G7 G18 G90`).
    pub frame: String,
    /// Constant surface speed.
    pub css: CssForm,
    /// The spindle clamp.
    pub clamp: ClampForm,
    /// Threads.
    pub thread: ThreadForm,
    /// Tool calls.
    pub tool: ToolForm,
    /// The words that select millimetres (`G21` on a Fanuc, `G71` on a SINUMERIK or a FAGOR and in
    /// ISO 6983-1); empty: none known, nothing is written.
    pub metric: String,
    /// The words that select inches (`G20`, `G70`); empty: none known.
    pub inch: String,
    /// The machine's highest spindle speed (rpm), the clamp of constant surface speed where the
    /// program gives none; None: the program must give it (G50 S).
    pub max_rpm: Option<f64>,
    /// Tapping in elementary moves (G33 in, the spindle reversed, G33 out) is right only with a
    /// floating (compensating) tap holder: the profile declares the machine has one.
    pub floating_tap: bool,
    /// The control's lathes may have a Y axis (a turning centre's: the 0i-TD's Y-axis option,
    /// a Haas ST-…Y): Y is written where a program moves it; without it a Y move is refused.
    pub y_axis: bool,
}

impl LatheForm {
    /// A lathe's tool call `T0101` (tool 01 with offset 01, the lower two digits: Fanuc 0i-TD
    /// "Tool function", parameter 5002#0 LD1 = 0) in the control's words: `T0101` on a Fanuc,
    /// `T1 D1` where T is the tool and D its cutting edge (SINUMERIK 802D, FAGOR 8035 T), LinuxCNC's
    /// `T1 M6 G43`. `loaded` is the tool in the turret, if known: LinuxCNC changes only to another.
    /// The one home of the tool call (`run`'s resolved output and `post`).
    pub fn tool_call(&self, t: f64, loaded: Option<u32>) -> Result<(String, u32), String> {
        let t = t.round();
        if !(0.0..=9999.0).contains(&t) {
            return Err(format!(
                "T{t}: a lathe's tool call is tool and offset, T0000 to T9999"
            ));
        }
        let (tool, offset) = ((t / 100.0).floor() as u32, (t % 100.0) as u32);
        let change = if loaded == Some(tool) {
            String::new()
        } else {
            format!("T{tool} M6 ")
        };
        let text = match self.tool {
            ToolForm::Fanuc => format!("T{:04}", t as u32),
            ToolForm::LinuxCnc if offset == 0 => format!("{change}G49"),
            ToolForm::LinuxCnc if offset == tool => format!("{change}G43"),
            ToolForm::LinuxCnc => format!("{change}G43 H{offset}"),
            ToolForm::TD => format!("T{tool} D{offset}"),
        };
        Ok((text, tool))
    }

    /// The letter of a thread's lead from `from` to `to` (X radius, Z) in the control's thread
    /// block: F on a Fanuc (its lead along the longer axis, 0i-TD "Thread cutting (G32)"); with
    /// `ThreadForm::Din`, K (the lead along Z) below 45° from the Z axis and I (along X) at 45° and
    /// above, as DIN 66025 controls read G33 (SINUMERIK 802D "Thread cutting with constant lead
    /// G33"); with `ThreadForm::K` (LinuxCNC) K, and None at 45° and above. None: no thread block
    /// is known. X here on the radius.
    pub fn thread_letter(&self, from: [f64; 2], to: [f64; 2]) -> Option<Letter> {
        match self.thread {
            ThreadForm::F => Some(Letter::F),
            ThreadForm::K | ThreadForm::Din => {
                let steep = (to[0] - from[0]).abs() >= (to[1] - from[1]).abs();
                match (steep, self.thread) {
                    (false, _) => Some(Letter::K),
                    (true, ThreadForm::Din) => Some(Letter::I),
                    // LinuxCNC's G33 K moves along Z: no lead across.
                    _ => None,
                }
            }
            ThreadForm::None => None,
        }
    }
}

/// Which machines a dialect writes for.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum MachineKind {
    /// Milling only.
    Mill,
    /// Turning only: a run for it is a turning program.
    Lathe,
    /// Both (LinuxCNC): turning when the run says `--machine lathe`.
    Both,
}

/// Line numbers of the output.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum LineNumbers {
    /// Keep the N words the program wrote (and add none).
    Keep,
    /// No N words.
    Off,
    /// Every block numbered from `start` in steps of `step`, wrapping at the dialect's N maximum.
    Renumber {
        /// First number.
        start: u32,
        /// Step.
        step: u32,
    },
}

/// A control's dialect: everything about how a flat program is spelled for it.
#[derive(Clone, Debug, PartialEq)]
pub struct Dialect {
    /// Name (`fanuc`).
    pub name: String,
    /// One line saying what control it is for.
    pub summary: String,
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
    /// How the numbers of each address are written, indexed by `Letter::index`.
    pub numbers: [NumberFormat; Letter::COUNT],
    /// Decimals of one address where it differs from its kind's (`F` with 1), by `Letter::index`.
    pub address_digits: [Option<u8>; Letter::COUNT],
    /// Between two words of a block (`" "`, or `""` for `G1X10.`).
    pub separator: String,
    /// Block end (`"\n"`, `"\r\n"`).
    pub eol: String,
    /// Most bytes of a block, its end included (None: no limit).
    pub max_block: Option<usize>,
    /// Line numbers.
    pub line_numbers: LineNumbers,
    /// Zero-padded digits of a renumbered N word (`N006`: 3).
    pub number_width: u8,
    /// Comments.
    pub comments: CommentStyle,
    /// Comments the control acts on: one whose text begins (spaces left out, any case) with one
    /// of these words is written with a `-` before it, inert (LinuxCNC's `(MSG,…)`, `(LOGOPEN,…)`,
    /// `(PROBEOPEN …)`, `(ABORT,…)`). Upper case.
    pub active_comments: Vec<String>,
    /// `/` is written before a block the program marked block-delete (it ran: the switch was off).
    pub block_delete: bool,
    /// Lines before the first block; `{number}` `{name}` `{source}` `{version}` are replaced.
    pub header: Vec<String>,
    /// Lines after the last block.
    pub footer: Vec<String>,
    /// The program-number line, e.g. `O{number:04}` (`{number:0N}` pads); empty: none.
    pub program_number: String,
    /// A comment line naming fmsvm, its version and the source file after the header.
    pub header_comment: bool,
    /// The control refuses a program that does not end with M2 or M30 (FMS-3000 §7): resolved
    /// output ends with M30 where the program did not say it.
    pub end_required: bool,
    /// Arcs.
    pub arcs: ArcForm,
    /// Helices.
    pub helix: HelixForm,
    /// How a milling program's thread (G33) is written.
    pub mill_thread: MillThread,
    /// How a skip move (G31) is written.
    pub skip: SkipForm,
    /// I J K are the centre itself in the output's coordinates, not its offset from the start
    /// point (FMS-3000 N3021 = 1, §2.4.2; or 2, §2.4.3, the output being G90).
    pub centre_absolute: bool,
    /// A full circle in I J K form is written with its centre alone, no axis words (FMS-3000
    /// §2.4.3), rather than with its end point at its start (Fanuc).
    pub circle_by_centre: bool,
    /// The output leaves work offsets to the control: G54–G59 are written, the positions are in
    /// the selected system (FMS-3000 §2.15.1).
    pub control_work: bool,
    /// The output leaves tool lengths to the control: G43/G44 H and G49 are written, the
    /// positions are the tool tip's (FMS-3000 §3.3).
    pub control_length: bool,
    /// Dwells.
    pub dwell: DwellForm,
    /// The control has inch mode (G20/G21). Without it inch programs are written in mm.
    pub inch: bool,
    /// The control reads Fanuc's language: the literal form (the program's own words) may be written.
    pub literal: bool,
    /// The control is a Haas: its literal output may carry the Haas's own forms as the program
    /// wrote them (the one-block G71–G73 and G76, G154 P), which a Fanuc would misread.
    pub haas: bool,
    /// The canned cycles the control has (`G81`, `CYCLE81`), for the record: resolved output writes
    /// them as motion.
    pub cycles: Vec<String>,
    /// Modal suppression by default (`--compact`).
    pub compact: bool,
    /// The canned cycles resolved output writes as the control's own blocks (G81 G82 G85 G89),
    /// when resolving was not asked for.
    pub native_cycles: Vec<fmsvm_block::Code>,
    /// How they are written.
    pub cycle_form: CycleForm,
    /// The modes the first block of resolved milling output states after `G90 G17`, in the
    /// control's words (`G94 G40 G49 G80 G54`): feed per minute, no compensation, no cycle, the
    /// work system the output is written in. Nothing rests on what an earlier program left.
    pub start_modes: Vec<fmsvm_block::Code>,
    /// How a return to a reference position is written.
    pub reference: ReferenceForm,
    /// The machines the dialect writes for.
    pub machine: MachineKind,
    /// How it writes turning (required unless `machine` is `Mill`).
    pub lathe: Option<LatheForm>,
    /// The output is a turning program (the run's machine is a lathe): `lathe` applies.
    pub turning: bool,
    /// The machine's travel on each axis, mm (A B C degrees; infinite: not declared; `[motion]
    /// travel`): the
    /// span of the output's moves on an axis is held to it ([`crate::travel`]).
    pub travel: [f64; 6],
    /// The control's words for exact stop on one move, exact stop until cancelled, and its
    /// cutting mode (Fanuc's G09, G61, G64; the FMS-3000's G09, G61, G62, §2.13): written where
    /// the program says them. None: the dialect leaves the corners to the control's own mode (a
    /// warning says so).
    pub corners: Option<[fmsvm_block::Code; 3]>,
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
                    max: fmsvm_canon::decode::integer_max(l),
                },
                AddressClass::Linear => AddressKind::Linear,
                AddressClass::Angular => AddressKind::Angular,
                AddressClass::Feed => AddressKind::Feed,
            }
        });
        Dialect {
            name: "fanuc".into(),
            summary: "Fanuc 0i/16i/18i/30i milling (the default)".into(),
            kinds,
            mm_digits: 3,
            inch_digits: 4,
            angle_digits: 3,
            max_digits: 8,
            numbers: [NumberFormat::FANUC; Letter::COUNT],
            address_digits: [None; Letter::COUNT],
            separator: " ".into(),
            eol: "\n".into(),
            max_block: None,
            line_numbers: LineNumbers::Keep,
            number_width: 0,
            comments: CommentStyle::Paren,
            active_comments: Vec::new(),
            block_delete: true,
            header: vec!["%".into()],
            footer: vec!["%".into()],
            program_number: "O{number:04}".into(),
            header_comment: false,
            end_required: false,
            arcs: ArcForm::Ijk,
            helix: HelixForm::Axis,
            circle_by_centre: false,
            centre_absolute: false,
            mill_thread: MillThread::None,
            skip: SkipForm::G31,
            control_work: false,
            control_length: false,
            dwell: DwellForm::Milliseconds,
            inch: true,
            literal: true,
            haas: false,
            cycles: Vec::new(),
            compact: false,
            native_cycles: Vec::new(),
            cycle_form: CycleForm::Fanuc,
            start_modes: [940, 400, 490, 800, 540]
                .into_iter()
                .map(fmsvm_block::Code::from_tenths)
                .collect(),
            reference: ReferenceForm::Incremental,
            machine: MachineKind::Mill,
            lathe: None,
            turning: false,
            travel: [f64::INFINITY; 6],
            corners: None,
        }
    }

    /// How turning is written, when the output is a turning program.
    #[inline]
    pub fn turning(&self) -> Option<&LatheForm> {
        if self.turning {
            self.lathe.as_ref()
        } else {
            None
        }
    }

    /// The kind of `letter`.
    pub fn kind(&self, letter: Letter) -> AddressKind {
        self.kinds[letter.index()]
    }

    /// The largest value of integer address `letter` (0 for other kinds).
    pub fn integer_max(&self, letter: Letter) -> u64 {
        match self.kind(letter) {
            AddressKind::Integer { max } => max,
            _ => 0,
        }
    }

    /// How `letter`'s numbers are written.
    #[inline(always)]
    pub fn format(&self, letter: Letter) -> &NumberFormat {
        &self.numbers[letter.index()]
    }

    /// Decimals of a feed (or a thread's lead) in the feed mode and units: per minute as F's
    /// digits; per revolution two more in inch and one more in mm (Fanuc IS-B: F0.0001 mm/rev,
    /// F0.000001 in/rev against F0.001 mm/min), unless the profile sets F's digits itself.
    pub fn feed_digits(&self, per_rev: bool, inch: bool) -> u32 {
        let d = self.digits(Letter::F, inch);
        if !per_rev || self.address_digits[Letter::F.index()].is_some() {
            return d;
        }
        d + if inch { 2 } else { 1 }
    }

    /// Decimals of `letter` in the given units (0 for integer addresses, 1 for G codes).
    pub fn digits(&self, letter: Letter, inch: bool) -> u32 {
        if let Some(d) = self.address_digits[letter.index()] {
            return d as u32;
        }
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

    /// The header and footer line `template` with its placeholders replaced.
    pub fn expand_template(
        template: &str,
        number: Option<u32>,
        name: &str,
        source: &str,
    ) -> String {
        let mut out = String::with_capacity(template.len() + 16);
        let mut rest = template;
        while let Some(i) = rest.find('{') {
            out.push_str(&rest[..i]);
            let Some(j) = rest[i..].find('}') else {
                out.push_str(&rest[i..]);
                return out;
            };
            let key = &rest[i + 1..i + j];
            let (key, pad) = match key.split_once(':') {
                // At most MAX_TEMPLATE_WIDTH wide (`check_template` refuses a profile wider).
                Some((k, p)) => (
                    k,
                    p.trim_start_matches('0')
                        .parse::<usize>()
                        .unwrap_or(0)
                        .min(MAX_TEMPLATE_WIDTH),
                ),
                None => (key, 0),
            };
            match key {
                "number" => {
                    if let Some(n) = number {
                        out.push_str(&format!("{n:0pad$}"));
                    }
                }
                "name" => out.push_str(name),
                "source" => out.push_str(source),
                "version" => out.push_str(env!("CARGO_PKG_VERSION")),
                _ => out.push_str(&rest[i..i + j + 1]),
            }
            rest = &rest[i + j + 1..];
        }
        out.push_str(rest);
        out
    }

    /// A header, footer or number template as a profile gives it: each `{key:width}` one of
    /// `TEMPLATE_KEYS`, only `{number:0N}` with a width, at most `MAX_TEMPLATE_WIDTH`.
    pub fn check_template(t: &str) -> Result<(), String> {
        let mut rest = t;
        while let Some(i) = rest.find('{') {
            let Some(j) = rest[i..].find('}') else {
                return Ok(());
            };
            let field = &rest[i + 1..i + j];
            let (key, width) = field.split_once(':').unwrap_or((field, ""));
            if TEMPLATE_KEYS.contains(&key) && !width.is_empty() {
                let ok = key == "number"
                    && width.starts_with('0')
                    && width
                        .parse::<usize>()
                        .is_ok_and(|w| w <= MAX_TEMPLATE_WIDTH);
                if !ok {
                    return Err(format!(
                        "[program] {t:?}: `{{{field}}}`: only {{number:0N}} takes a width, N at most {MAX_TEMPLATE_WIDTH}"
                    ));
                }
            }
            rest = &rest[i + j + 1..];
        }
        Ok(())
    }
}

/// The placeholders a header or footer template may hold.
pub const TEMPLATE_KEYS: [&str; 4] = ["number", "name", "source", "version"];

/// The widest `{number:0N}` a template may ask for: program numbers have at most eight digits.
pub const MAX_TEMPLATE_WIDTH: usize = 16;

/// Powers of ten for the digits of an address.
const POW10: [f64; 10] = [1.0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9];

/// Rounds half away from zero without a libm call (|x| < 2^52, which the digit check guarantees).
#[inline(always)]
pub(crate) fn round_away(x: f64) -> i64 {
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
        let q = value * Self::increments_per_unit(digits);
        if q.is_nan() || q.abs() >= self.increments_limit() {
            return None;
        }
        Some(round_away(q))
    }

    /// Least increments per unit at `digits` decimals (what `least_increments` multiplies by).
    #[inline(always)]
    pub(crate) fn increments_per_unit(digits: u32) -> f64 {
        POW10[digits as usize]
    }

    /// The line numbers a program is written with: the run's `--renumber START STEP`, else the
    /// dialect's own renumbering, else none.
    pub fn renumbering(&self, asked: Option<(u32, u32)>) -> Option<(u32, u32)> {
        asked.or(match self.line_numbers {
            LineNumbers::Renumber { start, step } => Some((start, step)),
            _ => None,
        })
    }

    /// The block numbers of renumbered output (`asked`: the option's start and step), if any.
    pub fn block_numbers(&self, asked: Option<(u32, u32)>) -> Option<BlockNumbers> {
        let (start, step) = self.renumbering(asked)?;
        Some(BlockNumbers {
            start,
            step,
            next: start,
            max: self.integer_max(Letter::N),
            width: self.number_width as usize,
            wrapped: None,
        })
    }

    /// Which letters' numbers are in Fanuc's format (the formatter's fast path).
    pub fn fanuc_formats(&self) -> [bool; Letter::COUNT] {
        std::array::from_fn(|i| self.numbers[i] == NumberFormat::FANUC)
    }

    /// The magnitude in least increments that no longer fits the digits (`least_increments`).
    #[inline(always)]
    pub(crate) fn increments_limit(&self) -> f64 {
        POW10[self.max_digits as usize] - 0.5
    }

    /// Alarm 0003 for a resolved `value` of `letter` that does not fit the digits.
    pub fn too_many_digits(&self, letter: Letter, value: f64) -> Alarm {
        too_many_digits(letter, value, self.max_digits)
    }

    /// The positions the dialect can write, for a consumer that writes none (`stats`, `plot`).
    pub fn reach(&self) -> Reach {
        let largest = |inch: bool| {
            fmsvm_canon::AXES
                .map(|l| self.increments_limit() / Self::increments_per_unit(self.digits(l, inch)))
        };
        Reach {
            largest: [largest(false), largest(true)],
            max_digits: self.max_digits,
        }
    }
}

/// Alarm 0003: a resolved `value` of `letter` does not fit `max_digits`.
fn too_many_digits(letter: Letter, value: f64, max_digits: u32) -> Alarm {
    Alarm::new(
        TOO_MANY_DIGITS,
        format!("too many digits: the resolved {letter}{value} does not fit {max_digits} digits"),
    )
}

/// The positions a dialect can write: each axis's largest magnitude in mm and in inch. The default
/// reaches everywhere.
#[derive(Clone, Copy, Debug)]
pub struct Reach {
    /// `largest[inch][axis]`, exclusive.
    largest: [[f64; 6]; 2],
    /// The dialect's digits, for the alarm's words.
    max_digits: u32,
}

impl Default for Reach {
    fn default() -> Self {
        Reach {
            largest: [[f64::INFINITY; 6]; 2],
            max_digits: 0,
        }
    }
}

impl Reach {
    /// Alarm 0003 when an axis of `to` (in the program's units, `inch` when G20; NaN: not
    /// positioned) does not fit the dialect's digits, as the resolved emitter would refuse it.
    #[inline]
    pub fn check(&self, to: &[f64; 6], inch: bool) -> Result<(), Alarm> {
        let largest = &self.largest[inch as usize];
        for i in 0..6 {
            // An infinite position is refused too; the default's infinite reach holds every
            // finite one.
            if to[i].abs() >= largest[i] && (to[i].is_finite() || largest[i].is_finite()) {
                return Err(too_many_digits(
                    fmsvm_canon::AXES[i],
                    to[i],
                    self.max_digits,
                ));
            }
        }
        Ok(())
    }
}

impl Default for Dialect {
    fn default() -> Self {
        Dialect::fanuc()
    }
}

/// Renumbered output's block numbers: from `start` by `step`; past the dialect's largest N they
/// start again at `start` (numbers then repeat, which a control runs but a search by number finds
/// the first of), said once.
#[derive(Clone, Debug)]
pub struct BlockNumbers {
    start: u32,
    step: u32,
    next: u32,
    max: u64,
    width: usize,
    /// The largest N passed, once it was.
    wrapped: Option<u64>,
}

impl BlockNumbers {
    /// The next block's number.
    #[inline]
    pub fn take(&mut self) -> u32 {
        let n = self.next;
        self.next = self.next.saturating_add(self.step);
        if u64::from(self.next) > self.max {
            self.next = self.start;
            self.wrapped.get_or_insert(self.max);
        }
        n
    }

    /// The warning for a run whose numbers started again (`control`: the dialect's name).
    pub fn warning(&self, control: &str) -> Option<String> {
        self.wrapped.map(|max| {
            format!(
                "block numbers passed N{max}, the {control}'s largest: they start again at N{:0width$}, so numbers repeat (a search by number finds the first)",
                self.start,
                width = self.width
            )
        })
    }
}

#[cfg(test)]
mod tests {
    use super::DwellForm;

    /// A dwell word's value read back as seconds, by each form's definition: P in milliseconds,
    /// P/X/F in seconds, E in tenths (FMS-3000 §2.12), K in hundredths (FAGOR).
    #[test]
    fn a_dwell_words_value_in_seconds() {
        assert_eq!(DwellForm::Milliseconds.seconds(1500.0), 1.5);
        assert_eq!(DwellForm::PSeconds.seconds(1.5), 1.5);
        assert_eq!(DwellForm::XSeconds.seconds(2.0), 2.0);
        assert_eq!(DwellForm::FSeconds.seconds(0.25), 0.25);
        assert_eq!(DwellForm::ETenths.seconds(25.0), 2.5);
        assert_eq!(DwellForm::KHundredths.seconds(250.0), 2.5);
    }
}
